"""Platform robots: the natural-orthogonal-complement dynamics (numeric reference of seed 002)
against Pinocchio's closed-loop model (issue: parallel platforms).

Pinocchio's model is built independently (symdyn.check.pinocchio_model.build_closed_loop_model:
a free-flying platform, six leg chains, a 6D loop closure per leg); its quantities check:
- the legs' joint positions, rates and accelerations the reference computes close every loop
  (frames, velocities and accelerations of both sides of each closure coincide);
- inverse dynamics: rnea of the open tree and the constraint Jacobian give the actuator forces
  (tau = Jc^T lambda + S phi, 42 equations for 36 + 6 unknowns);
- forward dynamics: the constrained system M a + nle = S phi + Jc^T lambda, Jc a + gamma = 0;
- for the flight simulator also constraintDynamics itself (its solver needs a positive definite
  mass matrix, which the legs' massless spherical and universal crosses leave singular: a 1e-9
  armature on the legs' joints, which moves the accelerations by about 5e-12).
"""

import dataclasses

import numpy as np
import pytest

from closed_loop import (PLATFORMS, actuation_matrix, closure_accelerations, closure_mismatch, energy_balance, pinocchio_state,
                         states)
from helpers import REPO
from symdyn.model import parallel

pin = pytest.importorskip("pinocchio")

@pytest.fixture(scope="module", params=sorted(PLATFORMS))
def platform(request):
    from symdyn.check.parallel_reference import ParallelReference
    from symdyn.check.pinocchio_model import build_closed_loop_model
    robot = parallel.load(REPO / "robots" / "parallel" / f"{request.param}.yaml")
    model, constraints, info = build_closed_loop_model(robot)
    models, datas = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    for cm in constraints:
        models.append(cm)
        datas.append(cm.createData())
    return robot, ParallelReference(robot), model, models, datas, info  # IK from the file's home


def test_leg_states_close_the_loops(platform):
    """The reference's leg inverse kinematics, rates and accelerations satisfy Pinocchio's six
    loop closures at random platform states."""
    robot, ref, model, models, datas, info = platform
    data = model.createData()
    for p, R, twist, twist_rate in states(robot.name, 5, seed=1):
        legs = ref.leg_states(p, R, twist, twist_rate)
        q, v, a = pinocchio_state(model, info, ref, p, R, twist, twist_rate, legs)
        placement, velocity, acceleration = closure_mismatch(model, data, models, q, v, a)
        assert placement < 1e-10 and velocity < 1e-10 and acceleration < 1e-9, (placement, velocity, acceleration)


def test_inverse_dynamics_agrees_with_pinocchio(platform):
    """phi from the natural orthogonal complement equals the actuator forces Pinocchio's rnea of
    the open tree and the constraint Jacobian give (rnea = Jc^T lambda + S phi), <= 1e-8 of the
    largest force."""
    robot, ref, model, models, datas, info = platform
    data = model.createData()
    S = actuation_matrix(model, info)
    for p, R, twist, twist_rate in states(robot.name, 10, seed=2):
        phi = ref.inverse_dynamics(p, R, twist, twist_rate)
        legs = ref.leg_states(p, R, twist, twist_rate)
        q, v, a = pinocchio_state(model, info, ref, p, R, twist, twist_rate, legs)
        tau_tree = pin.rnea(model, data, q, v, a)
        pin.computeJointJacobians(model, data, q)
        Jc = pin.getConstraintsJacobian(model, data, models, datas)
        theirs = np.linalg.solve(np.hstack([Jc.T, S]), tau_tree)[-6:]
        assert np.abs(phi - theirs).max() <= 1e-8 * np.abs(theirs).max(), (phi, theirs)


def test_forward_dynamics_agrees_with_pinocchio(platform):
    """The platform's twist rate under actuator forces phi: the reference's forward dynamics
    against Pinocchio's constrained equations (M a + nle = S phi + Jc^T lambda, Jc a = -gamma,
    gamma the closures' acceleration at a = 0), and against its own inverse dynamics."""
    robot, ref, model, models, datas, info = platform
    data = model.createData()
    S = actuation_matrix(model, info)
    nv, nc = model.nv, 6 * len(models)
    for p, R, twist, twist_rate in states(robot.name, 10, seed=3):
        phi = ref.inverse_dynamics(p, R, twist, twist_rate) * 1.1  # not the forces of that motion
        rate = ref.forward_dynamics(p, R, twist, phi)
        legs = ref.leg_states(p, R, twist)
        q, v, _ = pinocchio_state(model, info, ref, p, R, twist, None, legs)
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        nle = pin.nonLinearEffects(model, data, q, v)
        # the closures' relative spatial acceleration is affine in a: gamma at a = 0, and the
        # columns of Jc from unit accelerations (exact; Jc a + gamma = 0 on the constraint)
        gamma = closure_accelerations(model, data, models, q, v, np.zeros(nv))
        Jc = np.column_stack([closure_accelerations(model, data, models, q, v, unit) - gamma
                              for unit in np.eye(nv)])
        kkt = np.block([[M, -Jc.T], [Jc, np.zeros((nc, nc))]])
        a = np.linalg.solve(kkt, np.concatenate([S @ phi - nle, -gamma]))[:nv]
        _, _, ours = pinocchio_state(model, info, ref, p, R, twist, rate,
                                      [dataclasses.replace(leg, theta_ddot=None) for leg in legs])
        assert np.abs(ours[:6] - a[:6]).max() <= 1e-8 * (1.0 + np.abs(a[:6]).max()), (ours[:6], a[:6])
        back = ref.inverse_dynamics(p, R, twist, rate)
        assert np.abs(back - phi).max() <= 1e-8 * np.abs(phi).max()


def test_constraint_dynamics_gives_back_the_twist_rate():
    """Pinocchio's constraintDynamics (flight simulator, with a 1e-9 armature on the legs' joints,
    see the module docstring) under phi from the reference returns the platform's twist rate."""
    from symdyn.check.parallel_reference import ParallelReference
    from symdyn.check.pinocchio_model import build_closed_loop_model
    robot = parallel.load(REPO / "robots" / "parallel" / "flight_simulator.yaml")
    ref = ParallelReference(robot)
    model, constraints, info = build_closed_loop_model(robot, armature=1e-9)
    models, datas = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    for cm in constraints:
        models.append(cm)
        datas.append(cm.createData())
    data = model.createData()
    pin.initConstraintDynamics(model, data, models, datas)
    S = actuation_matrix(model, info)
    for p, R, twist, twist_rate in states("flight_simulator", 5, seed=4):
        phi = ref.inverse_dynamics(p, R, twist, twist_rate)
        legs = ref.leg_states(p, R, twist, twist_rate)
        q, v, expected = pinocchio_state(model, info, ref, p, R, twist, twist_rate, legs)
        a = pin.constraintDynamics(model, data, q, v, S @ phi, models, datas, pin.ProximalSettings(1e-13, 1e-12, 50))
        assert np.abs(a[:6] - expected[:6]).max() <= 1e-8 * (1.0 + np.abs(expected[:6]).max())


def test_power_balance_along_a_trajectory(platform):
    """Simulated with the reference's forward dynamics: the work of the actuator forces equals
    the change of the mechanism's energy to the integration's accuracy (energy_balance)."""
    robot, ref, model, models, datas, info = platform
    change, work = energy_balance(robot, ref, model, info, ref.forward_dynamics)
    assert abs(change - work) <= 1e-6 * max(abs(work), abs(change)), (change, work)


def test_seed_matrices(platform):
    """The seed's T, L_J, Lambda and M(q): Lambda is the identity (q_J is joint k of leg J),
    M is symmetric positive definite, L_J maps actuated rates to leg J's joint rates, and inverse
    dynamics is affine in the actuated accelerations with slope M (two twist rates at one state)."""
    robot, ref, model, models, datas, info = platform
    for p, R, twist, twist_rate in states(robot.name, 5, seed=6):
        seed = ref.seed_matrices(p, R, twist)
        assert np.abs(seed["Lambda"] - np.eye(6)).max() <= 1e-12
        M = seed["M"]
        assert np.abs(M - M.T).max() <= 1e-12 * np.abs(M).max() and np.linalg.eigvalsh(M).min() > 0
        K = np.linalg.inv(seed["T"])
        q_dot = K @ twist
        for L_J, leg in zip(seed["L"], ref.leg_states(p, R, twist)):
            assert np.abs(L_J @ q_dot - leg.theta_dot).max() <= 1e-10 * (1 + np.abs(leg.theta_dot).max())
        other = twist_rate + np.linspace(-1, 1, 6)
        difference = ref.inverse_dynamics(p, R, twist, other) - ref.inverse_dynamics(p, R, twist, twist_rate)
        expected = M @ K @ (other - twist_rate)
        assert np.abs(difference - expected).max() <= 1e-9 * np.abs(expected).max()
