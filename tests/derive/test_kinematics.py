"""The general joint placement (convention: general), base and tool frames, and the tool's
kinematics (pose, Jacobian, J-dot qd): against Pinocchio, the 50-digit reference, and their own
definitions (finite differences)."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import yaml

import symdyn
from helpers import (REPO, ROBOTS, TOL, PinocchioReference, parameter_values, random_states,
                     robot_path)
from symdyn.check.cbuild import CompiledDynamics, compile_shared
from symdyn.check.pinocchio_model import compare
from symdyn.check.reference import MpReference
from symdyn.cli import main
from symdyn.model.robot import from_document

KINEMATICS = ("forward_kinematics", "jacobian", "jacobian_dot_qd")
GENERAL = str(REPO / "tests" / "data" / "general_arm.yaml")


def _numeric_parameters(robot):
    values = parameter_values(robot)
    return values, ([values[s] for s in robot.parameters] if robot.parameters else None)


@pytest.mark.parametrize("name", ROBOTS)
def test_kinematics_agree_with_pinocchio(derived, name):
    """Pose (framesForwardKinematics), Jacobian (getFrameJacobian, LOCAL_WORLD_ALIGNED) and
    J-dot qd (getFrameClassicalAcceleration at qdd = 0) of the tool, every bundled robot."""
    eqs = derived(name)
    values, p = _numeric_parameters(eqs.robot)
    ref = PinocchioReference(eqs.robot, values)
    errors = compare(eqs.numeric, ref, random_states(eqs.n, 20, seed=3), KINEMATICS, p)
    assert all(e <= TOL for e in errors.values()), errors


@pytest.fixture(scope="module")
def general():
    return symdyn.derive(symdyn.load(GENERAL))


def test_general_placements_agree_with_pinocchio_and_the_reference(general):
    """Unaligned axes ([0.6, 0, 0.8], [1, 1, 1], -y), rpy origins, a prismatic joint, a base
    placement and a tool frame: every output, against Pinocchio's unaligned joints and the
    independent 50-digit Newton-Euler (Rodrigues rotations, no shared code)."""
    states = random_states(general.n, 15, seed=8)
    pin_errors = compare(general.numeric, PinocchioReference(general.robot), states, symdyn.OUTPUTS)
    assert all(e <= TOL for e in pin_errors.values()), pin_errors
    mp_errors = compare(general.numeric, MpReference(general.robot), states[:4],
                        ("inverse_dynamics", "mass_matrix", "gravity") + KINEMATICS)
    assert all(e <= TOL for e in mp_errors.values()), mp_errors


def test_jacobian_and_jacobian_dot_are_the_derivatives_of_the_pose(general):
    """J's linear rows are dp/dq, its angular rows give dR/dt = [omega]x R, and J-dot qd is
    d(J)/dt qd: central differences along q + t qd."""
    num = general.numeric
    rng = np.random.default_rng(2)
    h = 1e-6
    for _ in range(5):
        q, qd = rng.uniform(-2, 2, general.n), rng.uniform(-1, 1, general.n)
        J = num.jacobian(q)
        T_plus, T_minus = num.forward_kinematics(q + h * qd), num.forward_kinematics(q - h * qd)
        velocity = (T_plus[:3, 3] - T_minus[:3, 3]) / (2 * h)
        assert np.allclose(J[:3] @ qd, velocity, rtol=1e-6, atol=1e-8)
        R = num.forward_kinematics(q)[:3, :3]
        dR = (T_plus[:3, :3] - T_minus[:3, :3]) / (2 * h)
        wx = dR @ R.T
        assert np.allclose(J[3:] @ qd, [wx[2, 1], wx[0, 2], wx[1, 0]], rtol=1e-6, atol=1e-8)
        Jdot = (num.jacobian(q + h * qd) - num.jacobian(q - h * qd)) / (2 * h)
        assert np.allclose(num.jacobian_dot_qd(q, qd), Jdot @ qd, rtol=1e-6, atol=1e-7)


def _puma_document():
    with open(robot_path("puma560"), encoding="utf-8") as handle:
        return yaml.safe_load(handle)


def test_base_rotates_gravity_and_places_the_tool():
    """A base rotated by 90 degrees about x turns world gravity -z into base-frame -y
    (= the same arm with gravity [0, -9.81, 0]), and the pose is base * chain * tool."""
    doc = _puma_document()
    placed = copy.deepcopy(doc)
    placed["base"] = {"xyz": [0.5, 0, 1], "rpy": ["pi/2", 0, 0]}
    placed["tool"] = {"xyz": [0, 0, 0.2], "rpy": [0, 0, 0]}
    rotated = copy.deepcopy(doc)
    rotated["gravity"] = [0, "-9.81", 0]
    eqs_placed = symdyn.derive(from_document(placed, "placed"), outputs=["gravity", "forward_kinematics"])
    eqs_rotated = symdyn.derive(from_document(rotated, "rotated"), outputs=["gravity", "forward_kinematics"])
    for q, *_ in random_states(6, 5, seed=4):
        assert np.allclose(eqs_placed.numeric.gravity(q), eqs_rotated.numeric.gravity(q), rtol=1e-12, atol=1e-12)
        base = np.array([[1, 0, 0, 0.5], [0, 0, -1, 0], [0, 1, 0, 1], [0, 0, 0, 1.0]])
        tool = np.eye(4)
        tool[2, 3] = 0.2
        expected = base @ eqs_rotated.numeric.forward_kinematics(q) @ tool
        assert np.allclose(eqs_placed.numeric.forward_kinematics(q), expected, rtol=1e-12, atol=1e-12)
    ref = PinocchioReference(eqs_placed.robot)
    errors = compare(eqs_placed.numeric, ref, random_states(6, 10, seed=5), ("gravity", "forward_kinematics"))
    assert all(e <= TOL for e in errors.values()), errors


def test_locking_the_last_joints_keeps_the_tool(tmp_path):
    """A scene locking the wrist: the tool rides on the last free link, at the locked angles."""
    scene = tmp_path / "locked.yaml"
    scene.write_text(f"scene: 1\nrobot: {GENERAL}\nlock: {{4: 0.3, 5: -0.7}}\nname: locked_arm\n")
    locked = symdyn.derive(symdyn.load(scene), outputs=list(KINEMATICS))
    full = symdyn.derive(symdyn.load(GENERAL), outputs=list(KINEMATICS))
    rng = np.random.default_rng(6)
    for _ in range(5):
        q, qd = rng.uniform(-2, 2, 3), rng.uniform(-1, 1, 3)
        q_full, qd_full = np.concatenate([q, [0.3, -0.7]]), np.concatenate([qd, [0, 0]])
        assert np.allclose(locked.numeric.forward_kinematics(q), full.numeric.forward_kinematics(q_full), atol=1e-13)
        assert np.allclose(locked.numeric.jacobian(q), full.numeric.jacobian(q_full)[:, :3], atol=1e-13)
        assert np.allclose(locked.numeric.jacobian_dot_qd(q, qd), full.numeric.jacobian_dot_qd(q_full, qd_full), atol=1e-12)


@pytest.mark.parametrize("edit, message", [
    (lambda d: d["links"][0].update(origin={"xyz": [0, 0, 1]}), "'origin' needs convention: general"),
    (lambda d: d["links"][0].update(axis=[1, 0, 0]), "'axis' needs convention: general"),
    (lambda d: d.update(base={"xyz": [0, 0]}), "field 'base.xyz': expected a list of 3 numbers"),
    (lambda d: d.update(tool={"xyz": [0, 0, 0], "rot": [0, 0, 0]}), "unknown key 'rot' (allowed: xyz, rpy)"),
    (lambda d: d["links"][0].update(limits={"lower": 1, "upper": -1}), "lower limit above upper limit"),
    (lambda d: d["links"][0].update(limits={"effort": -3}), "effort limit must not be negative"),
])
def test_dh_file_rejections(edit, message):
    doc = _puma_document()
    edit(doc)
    with pytest.raises(symdyn.RobotFileError) as info:
        from_document(doc, "arm.yaml")
    assert message in str(info.value)


def _general_document():
    with open(GENERAL, encoding="utf-8") as handle:
        return yaml.safe_load(handle)


@pytest.mark.parametrize("edit, message", [
    (lambda d: d["links"][1].update(a=0.1), "'a' is a Denavit-Hartenberg field"),
    (lambda d: d["links"][1].update(axis=[0, 0, 0]), "the axis is zero"),
    (lambda d: d["links"][1].update(axis=[0, "k", 1]), "unknown name 'k'"),
    (lambda d: d["links"][1].update(origin={"xyz": [0, 0, 0], "rpy": [0, 0, 0], "scale": 2}), "unknown key 'scale'"),
    (lambda d: d["links"][1].update(origin=[0, 0, 0]), "expected a mapping {xyz"),
])
def test_general_file_rejections(edit, message):
    doc = _general_document()
    edit(doc)
    with pytest.raises(symdyn.RobotFileError) as info:
        from_document(doc, "general.yaml")
    assert message in str(info.value)
    assert "general.yaml" in str(info.value)


def test_degrees_apply_to_rpy_and_big_rpy_warns():
    doc = _general_document()
    doc["angles"] = "degrees"
    doc["base"]["rpy"] = [0, 0, 90]
    doc["tool"]["rpy"] = [90, 0, 0]
    for link in doc["links"]:
        if "origin" in link and "rpy" in link["origin"]:
            link["origin"]["rpy"] = [f"({v})*180/pi" for v in link["origin"]["rpy"]]
    robot = from_document(doc, "deg.yaml")
    reference = symdyn.load(GENERAL)
    for mine, theirs in zip(robot.links, reference.links):
        assert all(float(a - b) == 0 for a, b in zip(mine.origin.rpy, theirs.origin.rpy))
    doc = _general_document()
    doc["links"][1]["origin"]["rpy"] = [90, 0, 0]
    with pytest.warns(symdyn.SymdynWarning, match="looks like degrees"):
        from_document(doc, "general.yaml")


def test_generated_c_for_general_robot_compiles_and_agrees(tmp_path, capsys, general):
    """The CLI end to end on the general robot: generate, then verify (compiled C against
    Pinocchio, every function) in double and float; the combined NAME_kinematics gives the
    same pose and Jacobian as the two single functions."""
    assert main(["generate", GENERAL, "--out", str(tmp_path), "--quiet"]) == 0
    header = (tmp_path / "general_arm_dynamics.h").read_text()
    assert "void general_arm_jacobian(const general_arm_real *q, general_arm_real *J);" in header
    assert "void general_arm_kinematics(const general_arm_real *q, general_arm_real *T, general_arm_real *J);" in header
    assert "base.xyz = [0.1, -0.2, 0.5]; base.rpy = [0.1, -0.2, pi/2 = 1.5707963267948966]" in header
    lib = CompiledDynamics(compile_shared(str(tmp_path / "general_arm_dynamics.c"), str(tmp_path)),
                           "general_arm", general.dimensions, 0)
    for q, *_ in random_states(general.n, 5, seed=9):
        T, J = lib.kinematics(q)
        assert np.allclose(T, lib.forward_kinematics(q), rtol=1e-14, atol=1e-15)
        assert np.allclose(J, lib.jacobian(q), rtol=1e-14, atol=1e-15)
        assert np.allclose(T, general.numeric.forward_kinematics(q), rtol=1e-12, atol=1e-13)
    assert main(["verify", GENERAL]) == 0  # float: every bundled robot in tests/emit/test_cgen.py
    out = capsys.readouterr().out
    rows = [line.split() for line in out.splitlines()]
    checked = {row[0]: row[-1] for row in rows if len(row) == 3 and row[0] in symdyn.ALL_OUTPUTS}
    assert checked == {name: "ok" for name in symdyn.OUTPUTS}, out
