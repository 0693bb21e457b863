"""Whole robots as people have them: a massless subtree is named, joint by joint, and verify
checks everything else; a legged robot on a fixed base says so (tests/model/test_urdf_robots.py)."""

from __future__ import annotations

from helpers import REPO  # noqa: F401
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
    (line,), _ = run_cli(["generate", workspace / "hand.yaml", "--out", workspace / "out", "--no-cache"], capsys, 1)
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
    (line,), _ = run_cli(["generate", workspace / "tree.yaml", "--out", workspace / "out", "--no-cache"], capsys, 1)
    assert "tree.yaml" in line and "'index'" in line and "'ring'" in line, line
    assert main(["verify", str(workspace / "tree.yaml"), "--states", "4", "--all"]) == 0
    out = capsys.readouterr().out
    assert "skipped " in out and "forward_dynamics" in out.split("skipped ")[1].split(":")[0]
    assert "mass_matrix_inverse" in out.split("skipped ")[1].split(":")[0]
    assert "FAIL" not in out
