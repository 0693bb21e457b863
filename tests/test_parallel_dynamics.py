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

from helpers import REPO
from symdyn.model import parallel

pin = pytest.importorskip("pinocchio")

#: bundled platform -> (home height of P (m), range of the positions (m) and angles (rad) of the
#: random states about the home pose)
PLATFORMS = {"flight_simulator": (2.0, 0.2, 0.17), "sru_platform": (0.55, 0.03, 0.08)}


def _states(name, count, seed):
    """Platform states about the home pose (level, P at the home height), twists and twist rates
    of order 1."""
    height, reach, tilt = PLATFORMS[name]
    rng = np.random.default_rng(seed)
    for _ in range(count):
        p = np.array([0.0, 0.0, height]) + rng.uniform(-reach, reach, 3)
        R = pin.rpy.rpyToMatrix(*rng.uniform(-tilt, tilt, 3))
        yield p, R, rng.uniform(-0.5, 0.5, 6), rng.uniform(-1.0, 1.0, 6)


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


def _pinocchio_state(model, info, ref, p, R, twist, twist_rate, legs):
    """Pinocchio's q, v, a for the platform state and the legs' joint positions, rates and
    accelerations.  The free flyer's v and a are LOCAL and spatial: the platform's classical
    [omega_dot; c_ddot] (world, at the mass centre) is converted."""
    q, v, a = np.zeros(model.nq), np.zeros(model.nv), np.zeros(model.nv)
    q[:3] = p
    q[3:7] = pin.Quaternion(R).coeffs()
    c = R @ ref.com
    omega, c_dot = twist[:3], twist[3:]
    v_origin = c_dot - np.cross(omega, c)
    v[:3], v[3:6] = R.T @ v_origin, R.T @ omega
    if twist_rate is not None:
        omega_dot, c_ddot = twist_rate[:3], twist_rate[3:]
        a_origin = c_ddot - np.cross(omega_dot, c) - np.cross(omega, np.cross(omega, c))
        a[:3] = R.T @ a_origin - np.cross(v[3:6], v[:3])
        a[3:6] = R.T @ omega_dot
    for leg, state in zip(info["legs"], legs):
        q[leg["q"]] = state.theta
        v[leg["v"]] = state.theta_dot
        if state.theta_ddot is not None:
            a[leg["v"]] = state.theta_ddot
    return q, v, a


def _closure_mismatch(model, data, models, q, v, a):
    """The largest difference between the two sides of the loop closures: placements, and the
    spatial velocities and accelerations in the closure frame."""
    pin.forwardKinematics(model, data, q, v, a)
    worst = [0.0, 0.0, 0.0]
    for cm in models:
        oM1 = data.oMi[cm.joint1_id] * cm.joint1_placement
        oM2 = data.oMi[cm.joint2_id] * cm.joint2_placement
        relative = oM1.inverse() * oM2
        worst[0] = max(worst[0], np.abs(oM1.homogeneous - oM2.homogeneous).max())
        for k, motion in ((1, data.v), (2, data.a)):
            side1 = cm.joint1_placement.actInv(motion[cm.joint1_id])
            side2 = relative.act(cm.joint2_placement.actInv(motion[cm.joint2_id]))
            worst[k] = max(worst[k], np.abs(side1.vector - side2.vector).max())
    return worst


def _closure_accelerations(model, data, models, q, v, a):
    """The closures' relative spatial accelerations (side 1 minus side 2, in the closure frame),
    stacked: zero for accelerations that keep the loops closed."""
    pin.forwardKinematics(model, data, q, v, a)
    out = []
    for cm in models:
        relative = (data.oMi[cm.joint1_id] * cm.joint1_placement).inverse() * \
            (data.oMi[cm.joint2_id] * cm.joint2_placement)
        side1 = cm.joint1_placement.actInv(data.a[cm.joint1_id])
        side2 = relative.act(cm.joint2_placement.actInv(data.a[cm.joint2_id]))
        out.append((side1 - side2).vector)
    return np.concatenate(out)


def _actuation(model, info):
    S = np.zeros((model.nv, 6))
    for k, leg in enumerate(info["legs"]):
        S[leg["actuated_v"], k] = 1.0
    return S


def test_leg_states_close_the_loops(platform):
    """The reference's leg inverse kinematics, rates and accelerations satisfy Pinocchio's six
    loop closures at random platform states."""
    robot, ref, model, models, datas, info = platform
    data = model.createData()
    for p, R, twist, twist_rate in _states(robot.name, 5, seed=1):
        legs = ref.leg_states(p, R, twist, twist_rate)
        q, v, a = _pinocchio_state(model, info, ref, p, R, twist, twist_rate, legs)
        placement, velocity, acceleration = _closure_mismatch(model, data, models, q, v, a)
        assert placement < 1e-10 and velocity < 1e-10 and acceleration < 1e-9, (placement, velocity, acceleration)


def test_inverse_dynamics_agrees_with_pinocchio(platform):
    """phi from the natural orthogonal complement equals the actuator forces Pinocchio's rnea of
    the open tree and the constraint Jacobian give (rnea = Jc^T lambda + S phi), <= 1e-8 of the
    largest force."""
    robot, ref, model, models, datas, info = platform
    data = model.createData()
    S = _actuation(model, info)
    for p, R, twist, twist_rate in _states(robot.name, 10, seed=2):
        phi = ref.inverse_dynamics(p, R, twist, twist_rate)
        legs = ref.leg_states(p, R, twist, twist_rate)
        q, v, a = _pinocchio_state(model, info, ref, p, R, twist, twist_rate, legs)
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
    S = _actuation(model, info)
    nv, nc = model.nv, 6 * len(models)
    for p, R, twist, twist_rate in _states(robot.name, 10, seed=3):
        phi = ref.inverse_dynamics(p, R, twist, twist_rate) * 1.1  # not the forces of that motion
        rate = ref.forward_dynamics(p, R, twist, phi)
        legs = ref.leg_states(p, R, twist)
        q, v, _ = _pinocchio_state(model, info, ref, p, R, twist, None, legs)
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        nle = pin.nonLinearEffects(model, data, q, v)
        # the closures' relative spatial acceleration is affine in a: gamma at a = 0, and the
        # columns of Jc from unit accelerations (exact; Jc a + gamma = 0 on the constraint)
        gamma = _closure_accelerations(model, data, models, q, v, np.zeros(nv))
        Jc = np.column_stack([_closure_accelerations(model, data, models, q, v, unit) - gamma
                              for unit in np.eye(nv)])
        kkt = np.block([[M, -Jc.T], [Jc, np.zeros((nc, nc))]])
        a = np.linalg.solve(kkt, np.concatenate([S @ phi - nle, -gamma]))[:nv]
        _, _, ours = _pinocchio_state(model, info, ref, p, R, twist, rate,
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
    S = _actuation(model, info)
    for p, R, twist, twist_rate in _states("flight_simulator", 5, seed=4):
        phi = ref.inverse_dynamics(p, R, twist, twist_rate)
        legs = ref.leg_states(p, R, twist, twist_rate)
        q, v, expected = _pinocchio_state(model, info, ref, p, R, twist, twist_rate, legs)
        a = pin.constraintDynamics(model, data, q, v, S @ phi, models, datas, pin.ProximalSettings(1e-13, 1e-12, 50))
        assert np.abs(a[:6] - expected[:6]).max() <= 1e-8 * (1.0 + np.abs(expected[:6]).max())


def _skew(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def test_power_balance_along_a_trajectory(platform):
    """Simulated from rest at the home pose under actuator forces that vary about those holding
    it there (the reference's forward dynamics, RK4): the work of phi (Simpson over phi . q_dot)
    equals the change of the whole mechanism's kinetic plus potential energy, which Pinocchio
    computes from the legs' and the platform's states, to the integration's accuracy."""
    robot, ref, model, models, datas, info = platform
    data = model.createData()
    height = PLATFORMS[robot.name][0]
    hold = ref.inverse_dynamics(np.array([0, 0, height]), np.eye(3), np.zeros(6), np.zeros(6))

    def forces(t):
        return hold * (1.0 + 0.05 * np.sin(2 * np.pi * t / 0.4 + np.arange(6)))

    def derivative(t, p, R, twist):
        rate = ref.forward_dynamics(p, R, twist, forces(t))
        return twist[3:] - np.cross(twist[:3], R @ ref.com), _skew(twist[:3]) @ R, rate

    def energy_and_power(t, p, R, twist):
        legs = ref.leg_states(p, R, twist)
        q, v, _ = _pinocchio_state(model, info, ref, p, R, twist, None, legs)
        energy = pin.computeKineticEnergy(model, data, q, v) + pin.computePotentialEnergy(model, data, q)
        q_dot = np.array([leg.theta_dot[a] for leg, a in zip(legs, ref.actuated)])
        return energy, forces(t) @ q_dot

    step, steps = 0.002, 150
    p, R, twist = np.array([0, 0, height], dtype=float), np.eye(3), np.zeros(6)
    energies, powers = [], []
    for k in range(steps + 1):
        t = k * step
        energy, power = energy_and_power(t, p, R, twist)
        energies.append(energy)
        powers.append(power)
        if k == steps:
            break
        k1 = derivative(t, p, R, twist)
        k2 = derivative(t + step / 2, *(x + step / 2 * dx for x, dx in zip((p, R, twist), k1)))
        k3 = derivative(t + step / 2, *(x + step / 2 * dx for x, dx in zip((p, R, twist), k2)))
        k4 = derivative(t + step, *(x + step * dx for x, dx in zip((p, R, twist), k3)))
        p, R, twist = (x + step / 6 * (a + 2 * b + 2 * c + d) for x, a, b, c, d in zip((p, R, twist), k1, k2, k3, k4))
        u, _, vt = np.linalg.svd(R)
        R = u @ vt  # back onto the rotations
    work = step / 3 * (powers[0] + powers[-1] + 4 * sum(powers[1:-1:2]) + 2 * sum(powers[2:-1:2]))
    change = energies[-1] - energies[0]
    assert abs(work) > 1e-3 * abs(energies[0]) * 1e-3, "the platform hardly moved"
    assert abs(change - work) <= 1e-6 * max(abs(work), abs(change)), (change, work)


def test_seed_matrices(platform):
    """The seed's T, L_J, Lambda and M(q): Lambda is the identity (q_J is joint k of leg J),
    M is symmetric positive definite, L_J maps actuated rates to leg J's joint rates, and inverse
    dynamics is affine in the actuated accelerations with slope M (two twist rates at one state)."""
    robot, ref, model, models, datas, info = platform
    for p, R, twist, twist_rate in _states(robot.name, 5, seed=6):
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
