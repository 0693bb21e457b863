"""Mimic joints: a joint that follows another (q = multiplier * q_leader + offset) has no
coordinate; the dynamics are the full tree's projected on the coordinates.

Checked three ways: every function of a tree against the full Pinocchio model projected by G
(symdyn.check.pinocchio_model.MimicReduction) on robots written for it (a mimic on a sibling, one
on a later link of its own chain with a multiplier and an offset, one across branches that no tree
factorization follows, on fixed and floating bases); the mass matrix and inverse dynamics of the
Panda (with its hand) and Baxter against Pinocchio's own mimic joints (``mimic=True``), an
independent reading of the laws; and ``symdyn verify`` end to end.
"""

from __future__ import annotations

import numpy as np
import pytest
import yaml

import symdyn
from symdyn.check.pinocchio_model import MimicReduction, PinocchioReference, compare, mirror_upper
from symdyn.check.states import random_state
from symdyn.cli import main
from symdyn.derive.equations import coordinate_parents, derive
from symdyn.model.errors import RobotFileError
from symdyn.model.outputs import REGISTRY, TREE_AVAILABLE, DERIVATIVE_OUTPUTS

from helpers import error_line, example_robot_data

pin = pytest.importorskip("pinocchio")


def _link(name, parent, joint="revolute", xyz=(0, 0, 0.3), axis=(0, 0, 1), mass=1.0, **extra):
    return {"name": name, "parent": parent, "joint": joint, "origin": {"xyz": list(xyz), "rpy": [0.1, -0.2, 0.3]},
            "axis": list(axis), "mass": mass, "com": [0.02, -0.01, 0.1], "inertia": [0.03, 0.02, 0.01, 0.001, 0, 0.002],
            **extra}


def gripper(floating: bool = False, across: bool = False) -> dict:
    """A wrist with two fingers (the second mimics the first, mirrored with an offset), an arm whose
    last joint follows its first at twice its angle plus 0.3 rad, and (``across``) a joint on the
    branch beside the arm following a joint of the arm (listed after that branch): G^T D G then
    couples that joint with both branches, and the coordinates' order gives no tree whose L^T D L
    follows M's zeros."""
    links = [_link("shoulder", "base"), _link("elbow", "shoulder", axis=(0, 1, 0), damping=0.2, armature=0.05),
             _link("wrist", "elbow", axis=(1, 0, 0), coulomb=0.3),
             _link("finger_a", "wrist", joint="prismatic", axis=(0, 1, 0), mass=0.1, damping=0.5),
             _link("finger_b", "wrist", joint="prismatic", axis=(0, -1, 0), mass=0.12, armature=0.01,
                   mimic={"joint": "finger_a", "multiplier": -1, "offset": 0.01}),
             _link("tail", "elbow", axis=(0, 0, 1), mass=0.4, mimic={"joint": "shoulder", "multiplier": 2, "offset": 0.3}),
             _link("other", "base", axis=(0, 1, 0), mass=0.7)]
    if across:
        links += [_link("side", "shoulder", axis=(0, 1, 0), mass=0.2),
                  _link("follower", "other", axis=(1, 0, 0), mass=0.3, damping=0.1,
                        mimic={"joint": "side", "multiplier": -0.5})]
    doc = {"format": 1, "name": "gripper", "convention": "general", "gravity": [0, 0, -9.81], "links": links,
           "frames": ["finger_b", "tail"]}
    if floating:
        doc["base"] = "floating"
        doc["base_body"] = {"mass": 2.0, "com": [0, 0, 0.05], "inertia": [0.1, 0.2, 0.15, 0, 0, 0]}
    return doc


def load(doc) -> symdyn.Robot:
    return symdyn.loads(yaml.safe_dump(doc), "gripper.yaml")


@pytest.mark.parametrize("floating,across", [(False, False), pytest.param(False, True, marks=pytest.mark.slow),
                                             pytest.param(True, False, marks=pytest.mark.slow)])
def test_every_function_is_the_full_tree_projected(floating, across):
    robot = load(gripper(floating, across))
    assert robot.dof == len(robot.links) - (3 if across else 2)
    assert (coordinate_parents(robot) is None) == across  # across branches: M is factorized dense
    wanted = [f for f in TREE_AVAILABLE if not (floating and f in DERIVATIVE_OUTPUTS and f != "mass_matrix_inverse")
              and REGISTRY[f].family != "contact"]  # (the gripper holds nothing: the fuzzer crosses mimics with contacts)
    eqs = derive(robot, outputs=wanted)
    reference = MimicReduction(PinocchioReference(robot), robot)
    rng = np.random.default_rng(7)
    states = [random_state(robot, rng) for _ in range(6)]
    errors = compare(eqs.numeric, reference, states, wanted)
    assert max(errors.values()) < 1e-11, {k: v for k, v in errors.items() if v >= 1e-11}


def test_pinocchio_mimic_joints_agree_on_the_panda_hand_and_baxter():
    """Pinocchio's own mimic joints (its crba and rnea support them) against symdyn's reading:
    the laws, the joint order and the projection, read independently."""
    for relative in ("panda_description/urdf/panda.urdf", "baxter_description/urdf/baxter.urdf"):
        path = example_robot_data(relative)
        robot = symdyn.load(path)
        assert robot.mimics
        eqs = derive(robot, outputs=["mass_matrix", "inverse_dynamics"])
        model = pin.buildModelFromUrdf(str(path), mimic=True)
        data = model.createData()
        assert model.nv == robot.nv
        rng = np.random.default_rng(3)
        for _ in range(5):
            q, qd, qdd, _ = random_state(robot, rng)
            friction = np.array([float(symdyn_link.damping) for symdyn_link in robot.links])
            M = mirror_upper(pin.crba(model, data, q))
            # (rtol 1e-8: symdyn reads Baxter's rpy angles within 1e-9 rad of a quarter turn as
            # that quarter turn, Pinocchio as written; verify makes them exact for Pinocchio too)
            np.testing.assert_allclose(eqs.numeric.mass_matrix(q), M, rtol=1e-8, atol=1e-10)
            tau = pin.rnea(model, data, q, qd, qdd)
            # Pinocchio's rnea has no joint friction: symdyn's damping, projected (G^T diag G qd)
            mine = eqs.numeric.inverse_dynamics(q, qd, qdd)
            G = MimicReduction(PinocchioReference(robot), robot).G
            np.testing.assert_allclose(mine - G.T @ (friction * (G @ qd)), tau, rtol=1e-8, atol=1e-8)


def test_verify_checks_the_panda_with_its_hand(capsys):
    path = example_robot_data("panda_description/urdf/panda.urdf")
    assert main(["verify", str(path), "--states", "20"]) == 0
    out = capsys.readouterr().out
    assert "the mimic joint projected on its leader" in out and "forward_dynamics" in out


def test_generated_header_lists_the_mimics(tmp_path):
    path = tmp_path / "gripper.yaml"
    path.write_text(yaml.safe_dump(gripper()))
    assert main(["generate", str(path), "--out", str(tmp_path / "out"), "--functions", "mass_matrix"]) == 0
    header = (tmp_path / "out" / "gripper_dynamics.h").read_text()
    assert "#define GRIPPER_DOF 5" in header
    assert "finger_b = -1.0 * finger_a + 0.01" in header and "tail = 2.0 * shoulder + 0.3" in header
    assert "mimic joints that follow it: finger_b" in header


@pytest.mark.parametrize("change,words", [
    ({"mimic": {"joint": "nope"}}, ["link 5 ('finger_b')", "field 'mimic.joint'", "no link named 'nope'"]),
    ({"mimic": {"joint": "finger_b"}}, ["field 'mimic.joint'", "cannot follow itself"]),
    ({"mimic": {"joint": "finger_a", "multiplier": 0}}, ["field 'mimic.multiplier'", "fixed joint"]),
    ({"mimic": {"joint": "finger_a", "offset": "k"}}, ["field 'mimic.offset'"]),
    ({"mimic": {"joint": "finger_a", "gain": 2}}, ["field 'mimic.gain'", "unknown key 'gain'"]),
    ({"mimic": [1, 2]}, ["field 'mimic'", "expected a mapping"]),
    ({"actuated": False}, ["field 'mimic'", "must be actuated"]),
])
def test_bad_mimic_fields_are_one_line(change, words):
    doc = gripper()
    doc["links"][4].update(change)
    with pytest.raises(RobotFileError) as caught:
        load(doc)
    message = str(caught.value)
    assert "\n" not in message and all(w in message for w in words), message


def test_a_mimic_of_a_mimic_is_refused_with_the_way_out():
    doc = gripper()
    doc["links"][5]["mimic"] = {"joint": "finger_b"}
    with pytest.raises(RobotFileError, match="is a mimic joint itself: name the joint it follows"):
        load(doc)


def test_what_mimic_robots_do_not_have_is_refused_in_one_line(tmp_path, capsys):
    path = tmp_path / "gripper.yaml"
    path.write_text(yaml.safe_dump(gripper()))
    assert main(["generate", str(path), "--out", str(tmp_path / "out"), "--functions", "jacobian"]) == 1
    assert "not available for a robot with mimic joints" in error_line(capsys)
    assert main(["generate", str(path), "--out", str(tmp_path / "out"), "--method", "lagrange-euler"]) == 1
    assert "has mimic joints" in error_line(capsys)


def test_convert_keeps_the_mimics_both_ways(tmp_path):
    """A robot file with mimic joints written as URDF (``<mimic>``) and read back: the same laws and
    the same mass matrix and inverse dynamics (joints matched by name: the URDF reader numbers
    them depth first; URDF has no armature: the robot here has none)."""
    from symdyn.emit.urdf import robot_to_urdf
    import warnings
    doc = gripper()
    for link in doc["links"]:
        link.pop("armature", None)
    robot = load(doc)
    path = tmp_path / "gripper.urdf"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        path.write_text(robot_to_urdf(robot))
        again = symdyn.load(str(path))
    names = [robot.links[j].name for j in robot.coordinate_links]
    order = [[again.links[j].name for j in again.coordinate_links].index(n) for n in names]
    laws = {link.name: (robot.links[link.mimic.leader].name, float(link.mimic.multiplier), float(link.mimic.offset))
            for link in robot.links if link.mimic is not None}
    assert {link.name: (again.links[link.mimic.leader].name, float(link.mimic.multiplier), float(link.mimic.offset))
            for link in again.links if link.mimic is not None} == laws
    first = derive(robot, outputs=["mass_matrix", "inverse_dynamics"])
    second = derive(again, outputs=["mass_matrix", "inverse_dynamics"])
    rng = np.random.default_rng(4)
    for _ in range(3):
        q, qd, qdd, _ = random_state(robot, rng)
        back = np.empty_like(q)
        back[order] = q
        vd, ad = np.empty_like(qd), np.empty_like(qdd)
        vd[order], ad[order] = qd, qdd
        M = second.numeric.mass_matrix(back)[np.ix_(order, order)]
        np.testing.assert_allclose(first.numeric.mass_matrix(q), M, rtol=1e-10, atol=1e-12)
        tau = second.numeric.inverse_dynamics(back, vd, ad)[order]
        np.testing.assert_allclose(first.numeric.inverse_dynamics(q, qd, qdd), tau, rtol=1e-10, atol=1e-10)
