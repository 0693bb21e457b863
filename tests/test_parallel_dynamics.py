"""Platform robots: the natural-orthogonal-complement dynamics (numeric reference of seed 002)
against Pinocchio's closed-loop dynamics (issue: parallel platforms)."""

import numpy as np
import pytest

from helpers import REPO
from symdyn.model import parallel

pin = pytest.importorskip("pinocchio")

FLIGHT_SIMULATOR = REPO / "robots" / "parallel" / "flight_simulator.yaml"
HOME_LENGTH = 3.153800684  # m, the legs' home length (see the robot file)
HOME = [[0, 0, 0, HOME_LENGTH, 0, 0]] * 6


def _rotation(roll, pitch, yaw):
    return pin.rpy.rpyToMatrix(roll, pitch, yaw)


def _states(count, seed):
    """Platform states around the home pose (p = (0, 0, 2) m, level): positions within 0.2 m,
    angles within 10 degrees, twists and twist rates of order 1."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        p = np.array([0.0, 0.0, 2.0]) + rng.uniform(-0.2, 0.2, 3)
        R = _rotation(*rng.uniform(-0.17, 0.17, 3))
        yield p, R, rng.uniform(-0.5, 0.5, 6), rng.uniform(-1.0, 1.0, 6)


@pytest.fixture(scope="module")
def flight_simulator():
    from symdyn.check.parallel_reference import ParallelReference
    from symdyn.check.pinocchio_model import build_closed_loop_model
    robot = parallel.load(FLIGHT_SIMULATOR)
    # a 1e-9 armature on the legs' joints: Pinocchio's constraint solver needs a positive definite
    # mass matrix, which the legs' massless spherical and universal crosses leave singular (it
    # moves the platform's accelerations by about 5e-12)
    return robot, ParallelReference(robot, HOME), build_closed_loop_model(robot, armature=1e-9)


def _pinocchio_state(model, info, ref, p, R, twist, thetas, theta_dots):
    """Pinocchio's q, v for the platform state and the legs' joint positions and rates."""
    q = np.zeros(model.nq)
    v = np.zeros(model.nv)
    q[:3] = p
    q[3:7] = pin.Quaternion(R).coeffs()
    c = R @ ref.com
    omega, c_dot = twist[:3], twist[3:]
    v[:3] = R.T @ (c_dot - np.cross(omega, c))
    v[3:6] = R.T @ omega
    for leg, theta, theta_dot in zip(info["legs"], thetas, theta_dots):
        q[leg["q"]] = theta
        v[leg["v"]] = theta_dot
    return q, v


def _platform_acceleration(R, ref, twist, twist_rate):
    """The free flyer's acceleration (Pinocchio: spatial, LOCAL) for the platform's classical
    twist rate [omega_dot; c_ddot] (world) at twist [omega; c_dot]."""
    omega, c_dot = twist[:3], twist[3:]
    omega_dot, c_ddot = twist_rate[:3], twist_rate[3:]
    c = R @ ref.com
    v_origin = c_dot - np.cross(omega, c)
    a_origin = c_ddot - np.cross(omega_dot, c) - np.cross(omega, np.cross(omega, c))
    omega_b, v_b = R.T @ omega, R.T @ v_origin
    return np.concatenate([R.T @ a_origin - np.cross(omega_b, v_b), R.T @ omega_dot])


def test_legs_close_their_loops_in_pinocchio(flight_simulator):
    """The reference's leg inverse kinematics and rates satisfy Pinocchio's six loop closures
    (positions and velocities) at random platform states."""
    robot, ref, (model, constraints, info) = flight_simulator
    data = model.createData()
    for p, R, twist, _ in _states(5, seed=1):
        states = ref.leg_states(p, R, twist)
        q, v = _pinocchio_state(model, info, ref, p, R, twist, [s.theta for s in states],
                                [s.theta_dot for s in states])
        pin.forwardKinematics(model, data, q, v)
        for cm in constraints:
            oM1 = data.oMi[cm.joint1_id] * cm.joint1_placement
            oM2 = data.oMi[cm.joint2_id] * cm.joint2_placement
            assert np.abs(oM1.homogeneous - oM2.homogeneous).max() < 1e-10
            v1 = cm.joint1_placement.actInv(data.v[cm.joint1_id])
            v2 = (oM1.inverse() * oM2).act(cm.joint2_placement.actInv(data.v[cm.joint2_id]))
            assert np.abs(v1.vector - v2.vector).max() < 1e-10


def test_inverse_dynamics_agrees_with_constraint_dynamics(flight_simulator):
    """phi from the natural orthogonal complement, applied at the actuated joints of Pinocchio's
    closed-loop model, gives back the platform's twist rate (constraintDynamics), and forward
    dynamics inverts inverse dynamics: error <= 1e-8 relative to the twist rates' size."""
    robot, ref, (model, constraints, info) = flight_simulator
    data = model.createData()
    models = pin.StdVec_RigidConstraintModel()
    datas = pin.StdVec_RigidConstraintData()
    for cm in constraints:
        models.append(cm)
        datas.append(cm.createData())
    pin.initConstraintDynamics(model, data, models, datas)
    prox = pin.ProximalSettings(1e-13, 1e-12, 50)
    for p, R, twist, twist_rate in _states(10, seed=2):
        phi = ref.inverse_dynamics(p, R, twist, twist_rate)
        states = ref.leg_states(p, R, twist)
        q, v = _pinocchio_state(model, info, ref, p, R, twist, [s.theta for s in states],
                                [s.theta_dot for s in states])
        tau = np.zeros(model.nv)
        for leg, force in zip(info["legs"], phi):
            tau[leg["actuated_v"]] = force
        a = pin.constraintDynamics(model, data, q, v, tau, models, datas, prox)
        expected = _platform_acceleration(R, ref, twist, twist_rate)
        scale = 1.0 + np.abs(expected).max()
        assert np.abs(a[:6] - expected).max() <= 1e-8 * scale, (a[:6], expected)
        back = ref.forward_dynamics(p, R, twist, phi)
        assert np.abs(back - twist_rate).max() <= 1e-8 * (1.0 + np.abs(twist_rate).max())
