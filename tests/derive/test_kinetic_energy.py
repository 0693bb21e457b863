"""The kinetic energy (kinetic_energy: 1/2 qd^T (D + diag(armature)) qd, bodies and rotors)
against Pinocchio's computeKineticEnergy and the 50-digit reference's sum over the bodies: a DH
arm with armature (every method), a kinematic tree, Solo-12 on its floating base read by
Pinocchio's URDF parser; numpy, compiled C (double and float) and CasADi; and its identities
(the quadratic form of the mass matrix, exactly, and homogeneous of degree 2 in qd)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import symdyn
from helpers import TOL, example_robot_data, robot_path
from symdyn.check.agreement import compile_equations
from symdyn.check.pinocchio_model import PinocchioReference, UrdfReference, compare
from symdyn.check.reference import MpReference
from symdyn.check.states import random_state
from symdyn.derive.equations import armature_matrix
from symdyn.emit.casadi_backend import casadi_function
from test_trees import HAND_TREE, SOLO

OUTPUT = ("kinetic_energy",)


def _states(robot, count=30, seed=11):
    rng = np.random.default_rng(seed)
    return [random_state(robot, rng) for _ in range(count)]


@pytest.mark.parametrize("method", ["newton-euler", "lagrange-euler", "jacobian-newton-euler"])
def test_arm_agrees_with_pinocchio_and_the_reference(method, tmp_path):
    """puma560 (armature on every joint): numpy by each method, and the C in double, against
    computeKineticEnergy and the 50-digit reference."""
    robot = symdyn.load(robot_path("puma560"))
    eqs = symdyn.derive(robot, method=method, outputs=OUTPUT)
    states = _states(robot)
    for reference in (PinocchioReference(robot), MpReference(robot)):
        errors = compare(eqs.numeric, reference, states, OUTPUT)
        assert errors["kinetic_energy"] <= TOL, (method, type(reference).__name__, errors)
    if method == "newton-euler":
        lib = compile_equations(eqs, OUTPUT, "double", str(tmp_path))
        assert compare(lib, PinocchioReference(robot), states, OUTPUT)["kinetic_energy"] <= TOL
        single = tmp_path / "float"
        single.mkdir()
        lib = compile_equations(eqs, OUTPUT, "float", str(single))
        rounded = [[np.asarray(x, dtype=np.float32).astype(float) for x in s] for s in states]
        assert compare(lib, PinocchioReference(robot), rounded, OUTPUT)["kinetic_energy"] <= 1e-5


def test_tree_and_floating_base_agree_with_pinocchio(tmp_path):
    """The hand-written tree, and Solo-12 on Pinocchio's free-flyer (the base's own motion in
    qd): numpy, C and CasADi."""
    tree = symdyn.load(HAND_TREE)
    eqs = symdyn.derive(tree, outputs=OUTPUT)
    assert compare(eqs.numeric, PinocchioReference(tree), _states(tree), OUTPUT)["kinetic_energy"] <= TOL
    path = example_robot_data(SOLO)
    solo = symdyn.load(path, floating_base=True)
    eqs = symdyn.derive(solo, outputs=OUTPUT)
    reference, states = UrdfReference(path, floating_base=True), _states(solo)
    assert compare(eqs.numeric, reference, states, OUTPUT)["kinetic_energy"] <= TOL
    assert compare(compile_equations(eqs, OUTPUT, "double", str(tmp_path)), reference, states,
                   OUTPUT)["kinetic_energy"] <= TOL
    function = casadi_function(eqs, "kinetic_energy")
    for q, qd, _, _ in states[:5]:
        expected = reference.kinetic_energy(q, qd)
        np.testing.assert_allclose(np.array(function(q, qd)).reshape(1), expected, rtol=1e-12, atol=1e-12)


def test_is_the_quadratic_form_of_the_mass_matrix():
    """Symbolically, for a 2-joint arm with every inertial parameter and armature a symbol:
    Ek - 1/2 qd^T (D + diag(armature)) qd is identically zero; and numerically, for a 7-joint
    arm, Ek(q, s qd) = s^2 Ek(q, qd) and Ek > 0 for qd != 0 (D + diag(armature) is positive definite)."""
    robot = symdyn.load(robot_path("planar2r"))
    eqs = symdyn.derive(robot, outputs=("kinetic_energy", "mass_matrix"))
    qd = sp.Matrix(eqs.qd)
    M = eqs.expanded("mass_matrix") + armature_matrix(robot)
    difference = eqs.expanded("kinetic_energy")[0] - (qd.T * M * qd)[0] / 2
    assert sp.simplify(sp.expand(difference)) == 0
    panda = symdyn.load(robot_path("panda"))
    energy = symdyn.derive(panda, outputs=OUTPUT).numeric.kinetic_energy
    for q, qd, _, _ in _states(panda, 10):
        value = float(energy(q, qd)[0])
        assert value > 0
        assert float(energy(q, 2.5 * qd)[0]) == pytest.approx(6.25 * value, rel=1e-12)
