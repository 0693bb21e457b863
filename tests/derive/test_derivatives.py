"""Derivatives of the dynamics (first: gravity_derivative, dc/dq) against Pinocchio's
computeGeneralizedGravityDerivatives and against central differences of symdyn's own compiled
gravity (a check that cannot agree by construction)."""

from __future__ import annotations

import numpy as np
import pytest

import symdyn
from helpers import REPO, ROBOTS, TOL, parameter_values, random_states, robot_path
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import PinocchioReference, UrdfReference, compare
from symdyn.emit.cgen import generate_c
from symdyn.model.errors import SymdynError


@pytest.mark.parametrize("name", ROBOTS)
def test_gravity_derivative_agrees_with_pinocchio(name):
    """Every bundled robot (chain12: 12 joints; the symbolic ones with their nominal values), at
    50 states."""
    robot = symdyn.load(robot_path(name))
    values = parameter_values(robot)
    eqs = symdyn.derive(robot, outputs=["gravity_derivative"])
    p = [values[s] for s in eqs.parameters]
    reference = PinocchioReference(robot, values)
    states = random_states(robot.dof, 50, seed=31)
    scale = max(np.max(np.abs(reference.gravity_derivative(q))) for q, _, _, _ in states)
    if scale < 1e-12:  # a SCARA's vertical axes: dc/dq is zero (Pinocchio's rounding noise, 1e-33)
        assert all(np.max(np.abs(eqs.numeric.gravity_derivative(q, p or None))) <= 1e-12 for q, _, _, _ in states)
        return
    errors = compare(eqs.numeric, reference, states, ["gravity_derivative"], p)
    assert errors["gravity_derivative"] <= TOL, errors


def test_gravity_derivative_of_a_urdf_arm_and_a_tree():
    """A URDF arm against Pinocchio's own reading of the file, and the hand-written tree."""
    from test_trees import example_robot_data
    path = example_robot_data("ur_description/urdf/ur5_robot.urdf")
    robot = symdyn.load(path, tip="tool0")
    eqs = symdyn.derive(robot, outputs=["gravity_derivative"])
    errors = compare(eqs.numeric, UrdfReference(path, "tool0"), random_states(robot.dof, 50, seed=32),
                     ["gravity_derivative"])
    assert errors["gravity_derivative"] <= TOL, errors
    tree = symdyn.load(str(REPO / "examples" / "trees" / "torso_two_arms.yaml"))
    eqs = symdyn.derive(tree, outputs=["gravity_derivative"])
    errors = compare(eqs.numeric, PinocchioReference(tree), random_states(tree.dof, 50, seed=33), ["gravity_derivative"])
    assert errors["gravity_derivative"] <= TOL, errors


def test_gravity_derivative_against_central_differences_of_the_compiled_gravity(tmp_path):
    """The compiled dc/dq against central differences of the compiled c (step 1e-6 rad) on
    puma560: within 1e-6 relative; a floating base is refused in one line."""
    robot = symdyn.load(robot_path("puma560"))
    eqs = symdyn.derive(robot, outputs=["gravity", "gravity_derivative"])
    lib = build_and_load(generate_c(eqs, ["gravity", "gravity_derivative"]), robot.name, robot.dof, 0,
                         workdir=str(tmp_path))
    step = 1e-6
    for q, _, _, _ in random_states(robot.dof, 10, seed=34):
        exact = lib.gravity_derivative(q)
        numeric = np.column_stack([(lib.gravity(q + step * e) - lib.gravity(q - step * e)) / (2 * step)
                                   for e in np.eye(robot.dof)])
        assert np.max(np.abs(exact - numeric)) <= 1e-6 * max(1.0, np.max(np.abs(exact))), (exact, numeric)
    floating = symdyn.load(str(REPO / "examples" / "trees" / "space_robot.yaml"))
    with pytest.raises(SymdynError, match="fixed bases") as caught:
        symdyn.derive(floating, outputs=["gravity_derivative"])
    assert "\n" not in str(caught.value)
