"""Whole robots as people have them: a massless subtree is named, joint by joint, and verify
checks everything else; a legged robot on a fixed base says so (tests/model/test_urdf_robots.py)."""

from __future__ import annotations

import pytest

from helpers import REPO, example_robot_data  # noqa: F401
from symdyn.cli import main
from test_hostile import robot_text, run_cli, workspace  # noqa: F401 (the fixture)

ARM = ("{name: arm, joint: revolute, a: 0.4, alpha: 0, d: 0, theta: 0, mass: 2, com: [0.2, 0, 0], "
       "inertia: [0.01, 0.02, 0.02, 0, 0, 0]}")


def _finger(name: str, parent: str = "") -> str:
    up = f"parent: {parent}, " if parent else ""
    return (f"{{name: {name}, {up}joint: revolute, a: 0.05, alpha: 0.3, d: 0, theta: 0, mass: 0, com: [0, 0, 0], "
            "inertia: 0}")


def test_a_massless_chain_names_every_massless_joint_and_verify_checks_the_rest(workspace, capsys):
    (workspace / "hand.yaml").write_text(robot_text("hand", [ARM, _finger("thumb1"), _finger("thumb2")]))
    (line,), _ = run_cli(["generate", workspace / "hand.yaml", "--out", workspace / "out", "--no-cache",
                          "--functions", "forward_dynamics"], capsys, 1)
    assert "hand.yaml" in line and "2 ('thumb1')" in line and "3 ('thumb2')" in line, line
    assert main(["verify", str(workspace / "hand.yaml"), "--states", "4"]) == 0
    out = capsys.readouterr().out
    assert "skipped forward_dynamics: " in out and "'thumb1'" in out
    assert "inverse_dynamics" in out and "mass_matrix" in out and "FAIL" not in out


def test_a_massless_subtree_of_a_tree_is_named(workspace, capsys):
    """A tree (two fingers hanging on the arm, each massless): the factorization's zero pivot
    names both fingers' joints, not an index; verify skips forward dynamics and the inverse mass
    matrix (asked with --all) and checks the rest."""
    links = [ARM, _finger("index", "arm"), _finger("ring", "arm")]
    (workspace / "tree.yaml").write_text(robot_text("tree", links))
    (line,), _ = run_cli(["generate", workspace / "tree.yaml", "--out", workspace / "out", "--no-cache",
                          "--functions", "forward_dynamics"], capsys, 1)
    assert "tree.yaml" in line and "'index'" in line and "'ring'" in line, line
    assert main(["verify", str(workspace / "tree.yaml"), "--states", "4", "--all"]) == 0
    out = capsys.readouterr().out
    assert "skipped " in out and "forward_dynamics" in out.split("skipped ")[1].split(":")[0]
    assert "mass_matrix_inverse" in out.split("skipped ")[1].split(":")[0]
    assert "FAIL" not in out


MIMIC_ROBOTS = [  # (example-robot-data file, a mobile robot: on a floating base)
    ("baxter_description/urdf/baxter.urdf", False),
    ("talos_data/robots/talos_full_v2.urdf", True),
    ("romeo_description/urdf/romeo.urdf", True),
]


@pytest.mark.slow
@pytest.mark.parametrize("relative,floating", MIMIC_ROBOTS, ids=[r.split("/")[-1] for r, _ in MIMIC_ROBOTS])
def test_robots_with_mimic_joints_generate_and_verify_as_they_are(relative, floating, capsys):
    """The robots of example-robot-data that have mimic joints, read as they are (the Panda with its
    hand is in test_mimic, in the quick suite): their default functions derived, compiled and
    compared with Pinocchio's reading of the file, the mimics projected on their leaders; Romeo's
    massless hands leave its forward dynamics out, which verify says."""
    path = example_robot_data(relative)
    assert main(["verify", path, "--states", "20", *(["--floating-base"] if floating else [])]) == 0
    out = capsys.readouterr().out
    assert "mimic joints projected on their leaders" in out
    rows = [line.split() for line in out.splitlines() if line.endswith(" ok") or line.endswith(" FAIL")]
    assert {row[0] for row in rows} >= {"inverse_dynamics", "mass_matrix", "coriolis", "gravity"}
    assert all(row[-1] == "ok" for row in rows)


def test_generate_leaves_out_what_a_singular_mass_matrix_stops_when_defaulted(workspace, capsys):
    """Default functions of a robot whose mass matrix is singular for every q (a massless finger,
    as Romeo's hands): the others are generated, one warning and a header note (without the
    file's path: the same input gives the same bytes anywhere) say which were left out and why;
    asked for by name, forward dynamics is refused in one line (the tests above)."""
    (workspace / "hand.yaml").write_text(robot_text("hand", [ARM, _finger("thumb1")]))
    assert main(["generate", str(workspace / "hand.yaml"), "--out", str(workspace / "out"), "--no-cache"]) == 0
    err = capsys.readouterr().err
    assert "forward_dynamics left out" in err and "('thumb1')" in err, err
    header = (workspace / "out" / "hand_dynamics.h").read_text()
    assert "left out, the mass matrix being singular for every q: forward_dynamics" in header
    assert "hand_forward_dynamics(" not in header and "hand_inverse_dynamics(" in header
    assert str(workspace) not in header


def test_a_free_body_without_joints_is_a_floating_base_alone(workspace, capsys):
    """A drone (example-robot-data's Iris: one rigid body, no moving joint) on --floating-base, and
    a robot file with 'base: floating' and no links: the Newton-Euler equations of one free body
    (NV = 6), generated and checked against Pinocchio's free-flyer."""
    assert main(["verify", example_robot_data("iris_description/robots/iris_simple.urdf"), "--floating-base",
                 "--states", "5"]) == 0
    assert "0 joints on a floating base" in capsys.readouterr().out
    (workspace / "body.yaml").write_text(
        "format: 1\nname: body\nconvention: general\nbase: floating\n"
        "base_body: {mass: 1.5, com: [0.01, 0, 0.02], inertia: [0.03, 0.04, 0.05, 0.001, 0, 0]}\nlinks: []\n")
    assert main(["verify", str(workspace / "body.yaml"), "--states", "5"]) == 0
    out = capsys.readouterr().out
    assert out.count(" ok") == 6 and "FAIL" not in out
    (workspace / "fixed.yaml").write_text("format: 1\nname: fixed\nconvention: general\nlinks: []\n")
    (line,), _ = run_cli(["generate", workspace / "fixed.yaml", "--out", workspace / "out"], capsys, 1)
    assert "the chain is empty" in line and "base: floating" in line
