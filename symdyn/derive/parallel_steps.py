"""The natural-orthogonal-complement derivation of a platform robot, step by step, in the
notation and order of the parallel-manipulator notes, evaluated at one platform state (for ``symdyn derive``).

The quantities of the notes are 6x6 matrices whose closed forms in the pose are far too long to
print; a derivation shows each one's definition and its value at a given state (default: the
robot file's home pose at rest), so that a reader can follow the notes with numbers, or check a
paper's.  Everything is computed here from the legs' serial equations (numerically) and the
closed-form leg inverse kinematics, independently of the generated functions' programs.

Notation (natural orthogonal complement notes): the twist of the platform M at its mass centre C_M is
``t_M = [omega_M; c_dot_M]``; leg J's Jacobian ``J_J`` maps its joint rates to t_M
(``J_J theta_dot_J = t_M``), its columns ``[e_i; e_i x r_i]`` with ``e_i`` the unit axis of joint
i (a prismatic joint: ``[0; e_i]``) and ``r_i`` the vector from a point O_i of that axis to C_M
(r_1 = r_2 = r_3: the spherical pair's centre; r_5 = r_6: the universal joint's).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.errors import SymdynError
from ..model.parallel import ParallelRobot
from .parallel import home_pose
from .parallel_ik import LegIK, LegStructureError, leg_error
from .spatial import skew_numeric
from ..model.tolerances import SINGULAR_CONDITION

ROMAN = ("I", "II", "III", "IV", "V", "VI")


@dataclass(frozen=True)
class Step:
    """One step of the notes: a title, its defining formula (``formula``: plain text in the
    notes' notation), and the values it takes: ``(label, numpy array or number)`` pairs."""

    title: str
    formula: str
    values: tuple


@dataclass(frozen=True)
class ParallelDerivation:
    """The steps in the notes' order, and the state they are evaluated at."""

    robot: ParallelRobot
    pose: np.ndarray  # p (3) and quaternion (x, y, z, w)
    twist: np.ndarray
    accelerations: np.ndarray  # q_ddot
    steps: tuple


def _rotation(quaternion) -> np.ndarray:
    scale = sum(abs(float(c)) for c in quaternion)  # scaled: tiny or huge components stay representable
    if not 0 < scale < float("inf"):
        raise SymdynError("the pose's quaternion is zero" if scale == 0 else "the pose's quaternion is not finite")
    x, y, z, w = (float(c) / scale for c in quaternion)
    n = x * x + y * y + z * z + w * w
    s = 2.0 / n
    return np.array([[1 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w)],
                     [s * (x * y + z * w), 1 - s * (x * x + z * z), s * (y * z - x * w)],
                     [s * (x * z - y * w), s * (y * z + x * w), 1 - s * (x * x + y * y)]])


class _Leg:
    """Leg J's numeric serial equations and closed-form inverse kinematics."""

    def __init__(self, leg, where: str):
        from .equations import derive
        self.leg = leg
        self.where = f"{where}: leg {leg.name}"
        self.eqs = derive(leg.chain, outputs=["forward_kinematics", "jacobian", "jacobian_dot_qd",
                                                     "inverse_dynamics", "mass_matrix"]).numeric
        try:
            structure = LegIK.of(leg.chain)
            self.branches = structure.branches_of(leg.home)
        except LegStructureError as err:
            raise SymdynError(f"{self.where}: {leg_error(err, leg)}") from None
        self.ik = structure.with_floats()
        self.centre = np.array([float(x) for x in structure.centre_s])
        self.base = np.array(leg.chain.base_matrix(), dtype=float)
        self.attachment = np.array(leg.attachment.matrix(), dtype=float)

    def joints(self, p, R) -> np.ndarray:
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = R, p
        target = np.linalg.inv(self.base) @ pose @ self.attachment
        with np.errstate(invalid="ignore", divide="ignore"):
            values = self.ik.solve(target[:3, :3].tolist(), target[:3, 3].tolist(), self.branches, np.sqrt)
        out = []
        for link, value in zip(self.leg.chain.links, values):
            out.append(np.arctan2(value[1], value[0]) - float(link.theta) if link.is_revolute else float(value))
        theta = np.array(out, dtype=float)
        if not np.all(np.isfinite(theta)):
            raise SymdynError(f"{self.where}: the pose is out of the leg's reach, or the leg is at a singular "
                              "configuration there")
        return theta


def _twist_shape_steps(robot: ParallelRobot, legs: list, p, R, c, steps: list) -> tuple:
    """Steps 1-3 of the natural orthogonal complement at the platform pose (p, R) with the
    platform's centre of mass at ``c``: each leg's Jacobian at C_M, the A_J that eliminate the
    spherical pair's rates and the scalar twist-shape relations; appended to ``steps``.
    Returns ``(thetas, jacobians, zetas, ys)``."""
    # 1. leg Jacobians at C_M
    thetas, jacobians, axes, r1s = [], [], [], []
    for J, leg in enumerate(legs):
        theta = leg.joints(p, R)
        frame6 = np.asarray(leg.eqs.forward_kinematics(theta, []), dtype=float).reshape(4, 4)
        j6 = np.asarray(leg.eqs.jacobian(theta, []), dtype=float).reshape(6, 6)  # [linear; angular] at frame 6
        e = j6[3:, :]
        lin = j6[:3, :] + np.cross(e.T, c - frame6[:3, 3]).T  # e_i x r_i: velocity of C_M per joint rate
        jacobian = np.vstack([e, lin])
        thetas.append(theta)
        jacobians.append(jacobian)
        axes.append(e)
        r1s.append(c - (leg.base[:3, :3] @ leg.centre + leg.base[:3, 3]))
    steps.append(Step("Leg Jacobians", "J_J theta_dot_J = t_M,  J_J = [e_1 ... e_6; e_1 x r_1 ... e_6 x r_6]  "
                      "(r_i: from a point O_i of axis i to C_M; a prismatic joint's column is [0; e_i])",
                      tuple(v for J in range(6) for v in ((f"theta_{ROMAN[J]}", thetas[J]),
                                                          (f"J_{ROMAN[J]}", jacobians[J])))))
    # 2. A_J eliminates the spherical pair's rates
    eliminated = []
    values = []
    for J in range(6):
        A = np.hstack([skew_numeric(r1s[J]), np.eye(3)])
        AJ = A @ jacobians[J]
        eliminated.append(AJ)
        values += [(f"r_{ROMAN[J]}1", r1s[J]), (f"A_{ROMAN[J]}", A), (f"A_{ROMAN[J]} J_{ROMAN[J]}", AJ)]
    steps.append(Step("A_J", "A_J = [R_J1 1] (R_J1 = CPM(r_J1));  A_J J_J = [0 0 0 e_4 x (r_4 - r_1) "
                      "e_5 x (r_5 - r_1) e_6 x (r_5 - r_1)]", tuple(values)))
    # 3. scalar twist-shape relations
    us, zetas, ys, values = [], [], [], []
    for J in range(6):
        k = robot.legs[J].actuated
        passive = [i for i in (3, 4, 5) if i != k]
        u = np.cross(eliminated[J][:, passive[0]], eliminated[J][:, passive[1]])
        zeta = float(u @ eliminated[J][:, k])
        y = np.concatenate([-np.cross(r1s[J], u), u])
        us.append(u)
        zetas.append(zeta)
        ys.append(y)
        values += [(f"u_{ROMAN[J]}", u), (f"zeta_{ROMAN[J]}", zeta), (f"y_{ROMAN[J]}", y)]
    steps.append(Step("Scalar twist-shape relations",
                      "zeta_J q_dot_J = y_J^T t_M,  u_J = [e_5 x (r_5 - r_1)] x [e_6 x (r_5 - r_1)],  "
                      "zeta_J = u_J . e_k x (r_k - r_1),  y_J = [-r_1 x u_J; u_J]  (k: the actuated joint; "
                      "u_J from the other two of joints 4-6)", tuple(values)))
    return thetas, jacobians, zetas, ys


def parallel_steps(robot: ParallelRobot, pose=None, twist=None, accelerations=None) -> ParallelDerivation:
    """The notes' quantities at platform state (``pose``: p and quaternion (x, y, z, w), default
    the home pose; ``twist`` t_M, default 0; ``accelerations`` q_ddot, default 0)."""
    where = robot.source or robot.name
    if robot.parameters:
        raise SymdynError(f"{where}: runtime parameters ({', '.join(s.name for s in robot.parameters)}) are not "
                          "supported for platform robots yet: give numbers")
    legs = [_Leg(leg, where) for leg in robot.legs]
    pose = np.asarray(home_pose(robot) if pose is None else pose, dtype=float)
    twist = np.zeros(6) if twist is None else np.asarray(twist, dtype=float)
    qdd = np.zeros(6) if accelerations is None else np.asarray(accelerations, dtype=float)
    p, R = pose[:3], _rotation(pose[3:7])
    plat = robot.platform
    mass = float(plat.mass)
    c = p + R @ np.array([float(x) for x in plat.com])
    inertia = R @ np.array(plat.inertia_matrix, dtype=float) @ R.T
    MM = np.zeros((6, 6))
    MM[:3, :3], MM[3:, 3:] = inertia, mass * np.eye(3)
    gravity = np.array([float(g) for g in robot.gravity])
    steps = []

    thetas, jacobians, zetas, ys = _twist_shape_steps(robot, legs, p, R, c, steps)
    Y = np.array(ys)
    Z = np.diag(zetas)
    for J in range(6):
        if not np.linalg.cond(jacobians[J]) < SINGULAR_CONDITION:
            raise SymdynError(f"{legs[J].where}: the leg is at a singular configuration at this pose (J_J has "
                              f"condition number {np.linalg.cond(jacobians[J]):.1e}): give another --pose")
    if not np.linalg.cond(Y) < SINGULAR_CONDITION or not min(abs(z) for z in zetas) > 0:
        raise SymdynError(f"{where}: the platform is at a parallel singularity at this pose (Y has condition number "
                          f"{np.linalg.cond(Y):.1e}; T = Y^-1 Z is not defined): give another --pose")
    steps.append(Step("Y", "Y = [y_I^T; y_II^T; ...; y_VI^T]", (("Y", Y),)))
    steps.append(Step("Z", "Z = diag(zeta_I, ..., zeta_VI)", (("Z", Z),)))
    try:
        T = np.linalg.solve(Y, Z)
        L = [np.linalg.solve(jacobians[J], T) for J in range(6)]
    except np.linalg.LinAlgError:
        raise SymdynError("the pose is singular (Y or a leg's Jacobian is singular)") from None
    steps.append(Step("T", "T = Y^-1 Z  (t_M = T q_dot)", (("T", T),)))
    steps.append(Step("L_J", "L_J = J_J^-1 T  (theta_dot_J = L_J q_dot)",
                      tuple((f"L_{ROMAN[J]}", L[J]) for J in range(6))))
    # leg inertia matrices (armature included) and the mass matrix
    masses = []
    for J, leg in enumerate(legs):
        D = np.asarray(leg.eqs.mass_matrix(thetas[J], []), dtype=float).reshape(6, 6)
        masses.append(D + np.diag([float(link.armature) for link in leg.leg.chain.links]))
    M = T.T @ MM @ T + sum(L[J].T @ masses[J] @ L[J] for J in range(6))
    steps.append(Step("M", "M(q) = T^T M_M T + sum_J L_J^T I_J L_J  (M_M = diag(I_M, m_M 1), world axes)",
                      (("M_M", MM), ("M(q)", M))))
    # N q_dot and tau^W from the legs' and the platform's inverse dynamics (power balance)
    qd = np.linalg.solve(T, twist)
    generalized = _generalized_forces(legs, thetas, jacobians, T, MM, inertia, mass, gravity, c, twist)
    n_qd, tau_w = generalized["N q_dot"], generalized["tau^W"]
    steps.append(Step("N", "N(q, q_dot) q_dot = T^T (M_M T_dot + W_M M_M T) q_dot + sum_J L_J^T (I_J L_dot_J + "
                      "C_J L_J) q_dot  (at this state)", (("q_dot", qd), ("N q_dot", n_qd))))
    Lam = np.column_stack([L[J][robot.legs[J].actuated, :] for J in range(6)])
    steps.append(Step("Lambda", "Lambda = [L_I^T e_Ik ... L_VI^T e_VIk]  (= 1: q_J is joint k of leg J)",
                      (("Lambda", Lam),)))
    phi = np.linalg.solve(Lam, M @ qdd + n_qd - tau_w)
    steps.append(Step("phi", "phi = Lambda^-1 [M(q) q_ddot + N(q, q_dot) q_dot - tau^W]  (tau^W: the weights of "
                      "the platform and the legs as generalized forces)",
                      (("tau^W", tau_w), ("q_ddot", qdd), ("phi", phi))))
    return ParallelDerivation(robot, pose, twist, qdd, tuple(steps))


def _rates_and_bias(leg, theta, jac, twist, c):
    """Leg ``leg``'s joint rates ``J^-1 t`` and the acceleration [alpha; a] of C_M (a point of its
    last link) at theta_ddot = 0, from its J-dot theta_dot at frame 6's origin."""
    omega = twist[:3]
    theta_dot = np.linalg.solve(jac, twist)
    frame6 = np.asarray(leg.eqs.forward_kinematics(theta, []), dtype=float).reshape(4, 4)
    rho = c - frame6[:3, 3]
    jdqd = np.asarray(leg.eqs.jacobian_dot_qd(theta, theta_dot, []), dtype=float).reshape(6)
    alpha0 = jdqd[3:]
    a0 = jdqd[:3] + np.cross(alpha0, rho) + np.cross(omega, np.cross(omega, rho))
    return theta_dot, np.concatenate([alpha0, a0])


def _generalized_forces(legs, thetas, jacobians, T, MM, inertia, mass, gravity, c, twist):
    """``N q_dot`` and ``tau^W`` at the state: the actuator forces at q_ddot = 0 minus those at
    rest (power balance of the legs' and the platform's Newton-Euler equations)."""
    def forces(tw, rate, with_gravity):
        omega = tw[:3]
        wrench = MM @ rate + np.concatenate([np.cross(omega, inertia @ omega),
                                             -mass * gravity if with_gravity else np.zeros(3)])
        total = wrench.copy()
        for J, leg in enumerate(legs):
            theta, jac = thetas[J], jacobians[J]  # jac: [angular; linear at C_M]
            theta_dot, bias = _rates_and_bias(leg, theta, jac, tw, c)
            theta_ddot = np.linalg.solve(jac, rate - bias)
            tau = np.asarray(leg.eqs.inverse_dynamics(theta, theta_dot, theta_ddot, []), dtype=float).reshape(6)
            if not with_gravity:
                tau = tau - np.asarray(leg.eqs.inverse_dynamics(theta, np.zeros(6), np.zeros(6), []),
                                       dtype=float).reshape(6)
            total = total + np.linalg.solve(jac.T, tau)
        return T.T @ total  # generalized forces on q (Lambda = 1)
    # the twist rate with q_ddot = 0 (t_dot = T_dot q_dot)
    rate0 = _twist_rate_at_zero_qdd(legs, thetas, jacobians, twist, c)
    n_qd = forces(twist, rate0, False)
    tau_w = -forces(np.zeros(6), np.zeros(6), True)
    return {"N q_dot": n_qd, "tau^W": tau_w}


def _twist_rate_at_zero_qdd(legs, thetas, jacobians, twist, c):
    """t_dot with the actuated joints' accelerations zero: K t_dot + (K_dot t) = 0 with
    q_dot = K t; each leg's row of K_dot t from its own J-dot: e_k^T J^-1 (t_dot - J_dot theta_dot)
    = q_ddot_J = 0, i.e. e_k^T J^-1 t_dot = e_k^T J^-1 b_J (b_J: the acceleration of C_M at
    theta_ddot = 0)."""
    rows, rhs = [], []
    for J, leg in enumerate(legs):
        _, bias = _rates_and_bias(leg, thetas[J], jacobians[J], twist, c)
        row = np.linalg.solve(jacobians[J].T, np.eye(6)[leg.leg.actuated])  # e_k^T J^-1 as a vector
        rows.append(row)
        rhs.append(row @ bias)
    return np.linalg.solve(np.array(rows), np.array(rhs))
