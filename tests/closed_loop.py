"""Platform robots in Pinocchio (shared by the platform tests): random states about the home
pose, the closed-loop model's q, v, a for a platform state, and its loop closures' accelerations.
"""

import numpy as np
import pinocchio as pin

#: bundled platform -> (home height of P (m), range of the positions (m) and angles (rad) of the
#: random states about the home pose)
PLATFORMS = {"flight_simulator": (2.0, 0.2, 0.17), "sru_platform": (0.55, 0.03, 0.08)}


def states(name, count, seed):
    """Platform states about the home pose (level, P at the home height), twists and twist rates
    of order 1."""
    height, reach, tilt = PLATFORMS[name]
    rng = np.random.default_rng(seed)
    for _ in range(count):
        p = np.array([0.0, 0.0, height]) + rng.uniform(-reach, reach, 3)
        R = pin.rpy.rpyToMatrix(*rng.uniform(-tilt, tilt, 3))
        yield p, R, rng.uniform(-0.5, 0.5, 6), rng.uniform(-1.0, 1.0, 6)


def pinocchio_state(model, info, ref, p, R, twist, twist_rate, legs):
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


def closure_mismatch(model, data, models, q, v, a):
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


def closure_accelerations(model, data, models, q, v, a):
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


def actuation_matrix(model, info):
    S = np.zeros((model.nv, 6))
    for k, leg in enumerate(info["legs"]):
        S[leg["actuated_v"], k] = 1.0
    return S


def pinocchio_inverse_dynamics(model, data, models, datas, info, q, v, a):
    """Actuator forces from rnea of the open tree and the constraint Jacobian
    (rnea = Jc^T lambda + S phi: 42 equations, 36 + 6 unknowns)."""
    tau_tree = pin.rnea(model, data, q, v, a)
    pin.computeJointJacobians(model, data, q)
    Jc = pin.getConstraintsJacobian(model, data, models, datas)
    return np.linalg.solve(np.hstack([Jc.T, actuation_matrix(model, info)]), tau_tree)[-6:]


def pinocchio_forward_dynamics(model, data, models, info, q, v, phi):
    """The tree's accelerations a under actuator forces phi from the constrained equations
    M a + nle = S phi + Jc^T lambda, Jc a + gamma = 0 (gamma: the closures' acceleration at
    a = 0, Jc's columns from unit accelerations: exact)."""
    nv, nc = model.nv, 6 * len(models)
    M = pin.crba(model, data, q)
    M = np.triu(M) + np.triu(M, 1).T
    nle = pin.nonLinearEffects(model, data, q, v)
    gamma = closure_accelerations(model, data, models, q, v, np.zeros(nv))
    Jc = np.column_stack([closure_accelerations(model, data, models, q, v, unit) - gamma for unit in np.eye(nv)])
    kkt = np.block([[M, -Jc.T], [Jc, np.zeros((nc, nc))]])
    return np.linalg.solve(kkt, np.concatenate([actuation_matrix(model, info) @ phi - nle, -gamma]))[:nv]


def free_flyer_twist_rate(R, com, twist, a):
    """The platform's classical [omega_dot; c_ddot] (world, at the mass centre) from the free
    flyer's LOCAL spatial acceleration a[:6] (inverse of the conversion in pinocchio_state)."""
    omega, c_dot = twist[:3], twist[3:]
    c = R @ com
    v_origin = c_dot - np.cross(omega, c)
    v_local, w_local = R.T @ v_origin, R.T @ omega
    omega_dot = R @ a[3:6]
    a_origin = R @ (a[:3] + np.cross(w_local, v_local))
    c_ddot = a_origin + np.cross(omega_dot, c) + np.cross(omega, np.cross(omega, c))
    return np.concatenate([omega_dot, c_ddot])
