"""Hostile input, round three: numbers at the edge of double precision go through every path
or are refused in one line naming the file, and a pivot is called zero only where it is."""

from __future__ import annotations

import numpy as np
import pytest

import symdyn
import symdyn.cli
from helpers import REPO
from symdyn.check.pinocchio_model import PinocchioReference
from test_hostile import robot_text, run_cli, workspace  # noqa: F401 (the fixture)

#: every number of every link 1e100 (round two's A4_huge_all)
HUGE = [("{joint: %s, a: 1e100, alpha: %s, d: %s, theta: 0, mass: 1e100, com: [1e100, 1e100, 1e100], "
         "inertia: [1e100, 1e100, 1e100, 0, 0, 0], damping: 1e100, coulomb: 1e100, armature: 1e100}") % link
        for link in (("revolute", "0", "1e100"), ("revolute", "1.5707963267948966", "1e100"), ("prismatic", "0", "0"))]


def test_huge_numbers_through_the_base_parameters(workspace, capsys):
    """generate --parameters base, derive --base-parameters and plain generate of a robot whose
    every number is 1e100: done (the regressor's norms and the regrouping check scaled, no
    overflow warning), or refused in one line; never a traceback or a numpy warning."""
    (workspace / "huge.yaml").write_text(robot_text("huge", HUGE, "gravity: [0, 0, -1e100]\n"))
    robot = workspace / "huge.yaml"
    for argv in (["generate", robot, "--out", workspace / "out", "--parameters", "base", "--quiet", "--no-cache"],
                 ["derive", robot, "--base-parameters", "--out", workspace / "huge.txt"],
                 ["generate", robot, "--out", workspace / "plain", "--quiet", "--no-cache"]):
        lines, _ = run_cli(argv, capsys, 0)
        assert not any("RuntimeWarning" in line or "overflow" in line for line in lines), lines


def test_a_huge_mass_or_offset_is_not_an_identically_zero_pivot(workspace, capsys):
    """A prismatic joint moving 1e100 kg (its D entry is 1e100), and a revolute joint 1e100 m
    from the base along its own axis (its D entry 0.25 kg m^2): forward dynamics generates (the
    prismatic joint's scale is the mass it moves, not a mass times a length squared; the exact
    check resolves the robot's span of decades), and agrees with Pinocchio."""
    heavy = ["{joint: prismatic, a: 0, alpha: 0, d: 0, theta: 0, mass: 1e100, com: [0, 0, 0], "
             "inertia: [1, 1, 1, 0, 0, 0]}",
             "{joint: revolute, a: 0.3, alpha: 0, d: 1e100, theta: 0, mass: 1, com: [0.1, 0, 0], "
             "inertia: [0.05, 0.05, 0.09, 0, 0, 0]}"]
    (workspace / "heavy.yaml").write_text(robot_text("heavy", heavy))
    lines, _ = run_cli(["generate", workspace / "heavy.yaml", "--out", workspace / "out", "--quiet", "--no-cache"],
                       capsys, 0)
    assert not any("identically" in line for line in lines), lines  # (a nearly-singular warning may come)
    robot = symdyn.load(str(workspace / "heavy.yaml"))
    eqs = symdyn.derive(robot, outputs=["mass_matrix", "forward_dynamics"])
    q, qd, tau = np.array([0.2, 0.7]), np.array([0.1, -0.3]), np.array([1e100, 0.5])
    expected = PinocchioReference(robot).forward_dynamics(q, qd, tau)
    np.testing.assert_allclose(eqs.numeric.forward_dynamics(q, qd, tau), expected, rtol=1e-9)
    np.testing.assert_allclose(eqs.numeric.mass_matrix(q), PinocchioReference(robot).mass_matrix(q), rtol=1e-12)


def _chain(name: str, step: str, count: int, runtime=("a",)) -> str:
    """A robot whose first link's ``a`` is the last of ``count`` parameters, each defined from
    the one before by ``step`` (``{v}`` the previous one)."""
    lines = [f"format: 1\nname: {name}\nconvention: standard\nparameters:\n"]
    lines += [f"  {r}: {{runtime: true}}\n" for r in runtime] + ["  v0: a\n"]
    lines += [f"  v{k}: {step.format(v=f'v{k - 1}')}\n" for k in range(1, count + 1)]
    lines.append(f"links:\n  - {{joint: revolute, a: v{count}, alpha: 0, d: 0, theta: 0, mass: 1, com: [0.1, 0, 0], "
                 "inertia: [0.01, 0.02, 0.02, 0, 0, 0]}\n")
    return "".join(lines)


@pytest.mark.parametrize("step, runtime, refused_at", [
    ("({v} + a)*({v} - a)", ("a",), "v9"),           # products of sums: 10^8 nodes at v24 (257 terms at v9)
    ("{v}*{v} + b*{v} + a", ("a", "b"), "v5"),        # products and sums in two parameters (561 terms)
    ("{v}*{v}*a", ("a",), "v7"),                      # products alone (degree 255)
    ("({v} + a)**2 - {v}", ("a",), "v7"),             # powers of sums (the power's own bound)
    ("{v}*a + {v}*a + {v}/a", ("a",), "v12"),         # each step uses the one before twice: 2^12 copies
    ("{v} + 2*a", ("a",), None),                      # a sum: stays small, generates
])
def test_parameter_chains_refused_in_a_second(workspace, capsys, step, runtime, refused_at):
    """Parameters defined from earlier ones, 24 steps of every operator: refused in one line
    naming the parameter where the expression outgrows the bounds (tree nodes on the shared
    graph, terms of its polynomial), in well under a second of CPU time; a chain that stays
    small generates."""
    (workspace / "chain.yaml").write_text(_chain("chain", step, 24, runtime))
    argv = ["generate", workspace / "chain.yaml", "--out", workspace / "out", "--quiet", "--no-cache",
            "--functions", "gravity"]
    if refused_at is None:
        run_cli(argv, capsys, 0)
        return
    (line,), seconds = run_cli(argv, capsys, 1)
    assert f"parameters.{refused_at}'" in line and "chain.yaml" in line, line
    assert seconds < 5, seconds


def test_an_axis_double_cannot_normalize_is_refused(workspace, capsys):
    """A joint axis of length 1e-300 (URDF and YAML; or 1e200, beyond any number's limit):
    refused naming the file, link and field (Pinocchio keeps 1e-300 0 0 as written and its
    Jacobian is then 1e300 off); 1e-100 and 1e100 are normalized exactly and generate."""
    urdf = (REPO / "tests" / "data" / "urdf" / "handmade.urdf").read_text()
    first = urdf.index("<axis xyz=\"")
    end = urdf.index("\"", first + len("<axis xyz=\""))
    for text, status in (("1e-300 0 0", 1), ("0 0 1e200", 1), ("1e-100 0 0", 0), ("0 1e100 0", 0)):
        (workspace / "axis.urdf").write_text(urdf[:first] + f"<axis xyz=\"{text}" + urdf[end:])
        lines, _ = run_cli(["generate", workspace / "axis.urdf", "--out", workspace / "out", "--quiet", "--no-cache",
                            "--functions", "gravity"], capsys, status)
        if status:
            assert "axis.urdf" in lines[0] and "field 'axis" in lines[0], lines
    general = ("{joint: revolute, origin: {xyz: [0, 0, 0.1], rpy: [0, 0, 0]}, axis: [1e-300, 0, 0], mass: 1, "
               "com: [0.1, 0, 0], inertia: [0.01, 0.02, 0.02, 0, 0, 0]}")
    (workspace / "axis.yaml").write_text(robot_text("axis", [general]).replace("convention: standard",
                                                                              "convention: general"))
    (line,), _ = run_cli(["generate", workspace / "axis.yaml", "--out", workspace / "out"], capsys, 1)
    assert "axis.yaml" in line and "field 'axis'" in line


def test_one_angle_limit_in_every_format(workspace, capsys):
    """alpha: 1e100 (YAML) is refused like an rpy of 1e100 in a URDF, at 1e6 rad, naming the
    file, link and field; 1e5 rad only warns (it looks like degrees); under angles: degrees the
    limit is on the value in radians."""
    link = ("{joint: revolute, a: 0.3, alpha: %s, d: 0, theta: 0, mass: 1, com: [0.1, 0, 0], "
            "inertia: [0.01, 0.02, 0.02, 0, 0, 0]}")
    for value, extra, status in (("1e100", "", 1), ("2e6", "", 1), ("1e5", "", 0), ("1e9", "angles: degrees\n", 1),
                                 ("1e7", "angles: degrees\n", 0)):
        (workspace / "angle.yaml").write_text(robot_text("angle", [link % value], extra))
        lines, _ = run_cli(["generate", workspace / "angle.yaml", "--out", workspace / "out", "--quiet",
                            "--no-cache", "--functions", "gravity"], capsys, status)
        if status:
            assert "angle.yaml" in lines[0] and "field 'alpha'" in lines[0] and "1e+06 rad" in lines[0], lines


def test_long_lists_and_scenes_that_lock_everything_say_what_they_are(workspace, capsys):
    """A plain 100,001-entry list (no alias) is refused as a document with too many values, not
    as an alias expansion; a scene that locks every joint is refused naming the scene file."""
    many = "[" + ", ".join(["0"] * 100001) + "]"
    (workspace / "long.yaml").write_text(robot_text("long", extra=f"task: {many}\n"))
    (line,), _ = run_cli(["generate", workspace / "long.yaml", "--out", workspace / "out"], capsys, 1)
    assert "long.yaml" in line and "more than 100000 values" in line and "expanded" not in line, line
    (workspace / "locked.yaml").write_text(f"scene: 1\nrobot: {REPO / 'robots' / 'puma560.yaml'}\nlock: "
                                           "{waist: 0, shoulder: 0, elbow: 0, wrist_roll: 0, wrist_bend: 0, flange: 0}\n")
    (line,), _ = run_cli(["generate", workspace / "locked.yaml", "--out", workspace / "out"], capsys, 1)
    assert "locked.yaml" in line and "locks every joint" in line, line


def test_verify_judges_outputs_at_the_robot_scale(workspace, capsys, monkeypatch):
    """verify's floor comes from the robot's own torques: the Coriolis forces of coaxial links of
    1e9 and 0.01 kg m^2 (zero but for rounding, 5e-8 by Lagrange-Euler) and of an arm whose DH a
    is a subnormal 4e-320 m pass (they failed at 3e-7 and 2e-4); a real error of 1e-8 of the
    Coriolis forces of the Puma 560 still fails."""
    for name, method in (("coaxial_1e9", "lagrange-euler"), ("subnormal_a", "newton-euler")):
        lines, _ = run_cli(["verify", REPO / "tests" / "data" / f"{name}.yaml", "--states", "10", "--method", method,
                            "--functions", "coriolis,coriolis_matrix,inverse_dynamics"], capsys, 0)
    true_coriolis = PinocchioReference.coriolis
    monkeypatch.setattr(PinocchioReference, "coriolis", lambda self, q, qd: true_coriolis(self, q, qd) * (1 + 1e-8))
    assert symdyn.cli.main(["verify", str(REPO / "robots" / "puma560.yaml"), "--states", "5",
                            "--functions", "coriolis"]) == 1
    assert "FAIL" in capsys.readouterr().out


def test_a_run_stops_at_its_time_budget(workspace, capsys):
    """A robot that takes long (24 generic joints, every default function) with --max-seconds 2
    stops with one line naming the option, after about that much CPU time, and writes nothing;
    the default budget is a run a user can wait for (common.DEFAULT_MAX_SECONDS)."""
    from symdyn.cli.common import DEFAULT_MAX_SECONDS
    assert 0 < DEFAULT_MAX_SECONDS <= 300
    link = ("{joint: revolute, a: 0.%d, alpha: 0.%d, d: 0.1, theta: 0, mass: 1.5, com: [0.05, 0.01, 0.02], "
            "inertia: [0.02, 0.03, 0.025, 0.001, -0.002, 0.0015]}")
    (workspace / "long.yaml").write_text(robot_text("long", [link % (k % 7 + 1, k % 5 + 3) for k in range(24)]))
    (line,), seconds = run_cli(["generate", workspace / "long.yaml", "--out", workspace / "out", "--no-cache",
                                "--max-seconds", "2"], capsys, 1)
    assert "--max-seconds" in line and "long.yaml" in line, line
    assert seconds < 10, seconds
    assert not (workspace / "out").exists()


def test_huge_urdf_mass_and_origin_generate(workspace, capsys):
    """A URDF whose third link weighs 1e100 kg, or whose first joint sits 1e100 m up, generates
    forward dynamics (the second with a nearly-singular warning): neither is 'identically 0'."""
    text = (REPO / "tests" / "data" / "urdf" / "handmade.urdf").read_text()
    masses = [k for k in range(len(text)) if text.startswith('<mass value="', k)]
    start = masses[2] + len('<mass value="')
    heavy = text[:start] + "1e100" + text[text.index('"', start):]
    first = text.index('<origin xyz="', text.index("<joint")) + len('<origin xyz="')
    high = text[:first] + "0 0 1e100" + text[text.index('"', first):]
    for name, urdf in (("heavy", heavy), ("high", high)):
        (workspace / f"{name}.urdf").write_text(urdf)
        lines, _ = run_cli(["generate", workspace / f"{name}.urdf", "--out", workspace / name, "--quiet", "--no-cache"],
                           capsys, 0)
        assert not any("identically" in line for line in lines), lines


@pytest.mark.slow
def test_forty_joints_within_the_default_budgets(workspace, capsys):
    """A generic 40-joint chain with full inertia tensors, every default function, with the
    default budgets: done (about 30 s of CPU time on the reference machine), or stopped at the
    default time budget with one line naming it; never longer."""
    from symdyn.cli.common import DEFAULT_MAX_SECONDS
    rng = np.random.default_rng(40)
    links = [f"{{joint: revolute, a: {rng.uniform(-0.3, 0.3):.4f}, alpha: {rng.uniform(0.4, 1.0):.4f}, "
             f"d: {rng.uniform(-0.3, 0.3):.4f}, theta: 0, mass: {rng.uniform(0.5, 3):.3f}, "
             f"com: [{rng.uniform(-0.1, 0.1):.3f}, {rng.uniform(-0.1, 0.1):.3f}, {rng.uniform(-0.1, 0.1):.3f}], "
             "inertia: [0.02, 0.03, 0.025, 0.001, -0.002, 0.0015]}" for _ in range(40)]
    (workspace / "forty.yaml").write_text(robot_text("forty", links))
    argv = [str(a) for a in ("generate", workspace / "forty.yaml", "--out", workspace / "out", "--quiet", "--no-cache")]
    import time as clock
    start = clock.process_time()
    status = symdyn.cli.main(argv)
    seconds = clock.process_time() - start
    err = capsys.readouterr().err
    assert status == 0 or (status == 1 and "--max-seconds" in err), err
    assert seconds < DEFAULT_MAX_SECONDS + 15, seconds


def test_large_parameter_expressions_are_named_once(workspace, capsys):
    """Every length and inertial field of three links written as a 45-term polynomial in two
    runtime parameters (1 kB): generated in a few seconds (the derivation names each such field
    once instead of expanding its products: 29 s before), and right against Pinocchio."""
    head = "parameters:\n  a: {runtime: true}\n  b: {runtime: true}\n  v0: a\n" + "".join(
        f"  v{k}: v{k - 1}*v{k - 1} + b*v{k - 1} + a\n" for k in range(1, 4))
    links = ["{joint: revolute, a: v3, alpha: 0.%d, d: v2, theta: 0, mass: v3, com: [v3, v2, v1], "
             "inertia: [v3, v3, v3, v2, v1, v2]}" % (k + 3) for k in range(3)]
    (workspace / "poly.yaml").write_text(robot_text("poly", links, head))
    _, seconds = run_cli(["generate", workspace / "poly.yaml", "--out", workspace / "out", "--quiet", "--no-cache"],
                         capsys, 0)
    assert seconds < 10, seconds
    robot = symdyn.load(str(workspace / "poly.yaml"))
    eqs = symdyn.derive(robot, outputs=["inverse_dynamics", "mass_matrix"])
    values = {s: v for s, v in zip(robot.parameters, (0.3, -0.2))}
    reference = PinocchioReference(robot, values)
    rng = np.random.default_rng(9)
    for _ in range(3):
        q, qd, qdd = rng.uniform(-1, 1, (3, 3))
        p = np.array([values[s] for s in robot.parameters])
        np.testing.assert_allclose(eqs.numeric.inverse_dynamics(q, qd, qdd, p), reference.inverse_dynamics(q, qd, qdd),
                                   rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(eqs.numeric.mass_matrix(q, p), reference.mass_matrix(q), rtol=1e-9, atol=1e-9)
