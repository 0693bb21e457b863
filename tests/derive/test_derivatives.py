"""Derivatives of the dynamics (inverse_dynamics_dq, inverse_dynamics_dqd and their combined
inverse_dynamics_derivatives; gravity_derivative) against Pinocchio's computeRNEADerivatives and
computeGeneralizedGravityDerivatives, and against central differences of symdyn's own compiled
functions (a check that cannot agree by construction)."""

from __future__ import annotations

import numpy as np
import pytest

import symdyn
from helpers import REPO, ROBOTS, TOL, parameter_values, random_states, robot_path
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import PinocchioReference, UrdfReference, compare
from symdyn.emit.cgen import generate_c
from symdyn.model.errors import SymdynError


DERIVATIVES = ("inverse_dynamics_dq", "inverse_dynamics_dqd", "gravity_derivative")


@pytest.mark.parametrize("name", ROBOTS)
def test_derivatives_agree_with_pinocchio(name):
    """Every bundled robot (chain12: 12 joints; the symbolic ones with their nominal values), at
    50 states: dtau/dq and dtau/dqd (viscous damping on its diagonal), and dc/dq."""
    robot = symdyn.load(robot_path(name))
    values = parameter_values(robot)
    eqs = symdyn.derive(robot, outputs=DERIVATIVES)
    p = [values[s] for s in eqs.parameters]
    states = random_states(robot.dof, 50, seed=30)
    reference = PinocchioReference(robot, values)
    errors = compare(eqs.numeric, reference, states, DERIVATIVES[:2], p)
    assert all(e <= TOL for e in errors.values()), errors
    scale = max(np.max(np.abs(reference.gravity_derivative(q))) for q, _, _, _ in states)
    if scale < 1e-12:  # a SCARA's vertical axes: dc/dq is zero (Pinocchio's rounding noise, 1e-33)
        assert all(np.max(np.abs(eqs.numeric.gravity_derivative(q, p or None))) <= 1e-12 for q, _, _, _ in states)
        return
    errors = compare(eqs.numeric, reference, states, ["gravity_derivative"], p)
    assert errors["gravity_derivative"] <= TOL, errors


def test_derivatives_of_a_urdf_arm_and_a_tree():
    """A URDF arm against Pinocchio's own reading of the file, and the hand-written tree."""
    from test_trees import example_robot_data
    path = example_robot_data("ur_description/urdf/ur5_robot.urdf")
    robot = symdyn.load(path, tip="tool0")
    eqs = symdyn.derive(robot, outputs=DERIVATIVES)
    errors = compare(eqs.numeric, UrdfReference(path, "tool0"), random_states(robot.dof, 50, seed=32), DERIVATIVES)
    assert all(e <= TOL for e in errors.values()), errors
    tree = symdyn.load(str(REPO / "examples" / "trees" / "torso_two_arms.yaml"))
    eqs = symdyn.derive(tree, outputs=DERIVATIVES)
    errors = compare(eqs.numeric, PinocchioReference(tree), random_states(tree.dof, 50, seed=33), DERIVATIVES)
    assert all(e <= TOL for e in errors.values()), errors


def test_derivatives_against_central_differences_of_the_compiled_functions(tmp_path):
    """The compiled derivatives against central differences (step 1e-6) of the compiled inverse
    dynamics and gravity on the Stanford arm (a prismatic joint; its friction too, away from qd =
    0): within 1e-6 relative; the combined function gives the single ones' numbers; a floating
    base is refused in one line."""
    robot = symdyn.load(robot_path("stanford"))
    functions = ("inverse_dynamics", "gravity") + DERIVATIVES
    eqs = symdyn.derive(robot, outputs=functions)
    lib = build_and_load(generate_c(eqs, functions + ("inverse_dynamics_derivatives",)), robot.name, robot.dof, 0,
                         workdir=str(tmp_path))
    step = 1e-6

    def central(f, x):
        return np.column_stack([(f(x + step * e) - f(x - step * e)) / (2 * step) for e in np.eye(robot.dof)])
    for q, qd, qdd, _ in random_states(robot.dof, 10, seed=34):
        qd = np.where(np.abs(qd) < 1e-3, 0.5, qd)  # Coulomb friction's sign stays put
        for exact, numeric in ((lib.inverse_dynamics_dq(q, qd, qdd), central(lambda x: lib.inverse_dynamics(x, qd, qdd), q)),
                               (lib.inverse_dynamics_dqd(q, qd, qdd), central(lambda x: lib.inverse_dynamics(q, x, qdd), qd)),
                               (lib.gravity_derivative(q), central(lib.gravity, q))):
            assert np.max(np.abs(exact - numeric)) <= 1e-6 * max(1.0, np.max(np.abs(exact))), (exact, numeric)
        together = lib.inverse_dynamics_derivatives(q, qd, qdd)
        np.testing.assert_allclose(together[0], lib.inverse_dynamics_dq(q, qd, qdd), rtol=0, atol=1e-12)
        np.testing.assert_allclose(together[1], lib.inverse_dynamics_dqd(q, qd, qdd), rtol=0, atol=1e-12)
    floating = symdyn.load(str(REPO / "examples" / "trees" / "space_robot.yaml"))
    with pytest.raises(SymdynError, match="fixed bases") as caught:
        symdyn.derive(floating, outputs=["gravity_derivative"])
    assert "\n" not in str(caught.value)
