"""The dynamics of a platform robot by the natural orthogonal complement, numerically (natural orthogonal complement notes).

A numeric reference for the parallel-robot derivation (issue: parallel platforms): each leg's
serial quantities come from symdyn's serial equations evaluated with numpy (the leg's Jacobian,
its J-dot qd, its inverse dynamics and mass matrix); the platform and the loop closure are the
notes' formulas, written here with 6x6 linear solves.

State.  The platform pose is the position ``p`` (m, world frame W) of the platform frame P's
origin and the rotation ``R`` (3x3, P's axes in W); its twist is the notes'
``t_M = [omega; c_dot]`` (rad/s, m/s, W axes): the angular velocity and the velocity of the
platform's mass centre C_M; ``t_dot = [omega_dot; c_ddot]`` (classical derivatives, W axes).

Per leg J (k its actuated joint):

- inverse kinematics: the leg's joint positions theta_J that put its frame 6 at the platform's
  attachment (Newton iterations on the leg's own forward kinematics, from a starting guess);
- twist-shape relation: the twist of frame 6's origin U_J is ``S_J t_M`` with
  ``S_J = [[-[r]x ... ]]`` the shift from C_M to U_J (r = U_J - C_M), so the leg's rates are
  ``theta_dot_J = J_J^-1 S_J t_M`` (J_J: the leg's 6x6 Jacobian at U_J in W axes) and
  ``q_dot_J = e_k^T J_J^-1 S_J t_M``: the rows ``e_k^T J_J^-1 S_J`` make the 6x6 matrix
  ``K`` with ``q_dot = K t_M``, i.e. ``T = K^-1`` of the notes (``t_M = T q_dot``) and
  ``L_J = J_J^-1 S_J T``;
- the leg's own inverse dynamics tau_J^leg (gravity included, no load at its end).

Inverse dynamics (power balance, equivalent to the notes' ``phi = Lambda^-1 [M q_ddot + N q_dot
- tau^W]``): ``phi = K^-T (w_M + sum_J S_J^T J_J^-T tau_J^leg)`` with
``w_M = M_M t_dot + W_M M_M t_M - w_gravity`` the wrench the platform's motion needs.
Forward dynamics: the same relation is linear in ``t_dot``: ``A t_dot + b = K^T phi``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..derive.spatial import skew_numeric
from ..model.parallel import ParallelRobot


@dataclass
class LegState:
    """One leg at a platform state: joint positions, rates and accelerations (6 each), the
    point U_J (W), its Jacobian J_J (6x6: linear rows first, W axes), the shift S_J and
    ``rates = J_J^-1 S_J`` (6x6: the leg's joint rates per unit platform twist)."""

    theta: np.ndarray
    theta_dot: np.ndarray
    theta_ddot: np.ndarray | None
    point: np.ndarray
    jacobian: np.ndarray
    shift: np.ndarray
    rates: np.ndarray


class ParallelReference:
    """Numeric dynamics of a :class:`ParallelRobot` (numbers only: runtime parameters are not
    supported here).  ``home`` (6 legs x 6 joint positions; default: the file's ``home``) starts
    the inverse kinematics."""

    def __init__(self, robot: ParallelRobot, home=None):
        from ..derive.equations import derive
        if robot.parameters:
            raise ValueError("the numeric reference needs numbers for every parameter")
        if home is None:
            if any(leg.home is None for leg in robot.legs):
                raise ValueError(f"{robot.source}: no home configuration in the file: give home= to start the "
                                 "inverse kinematics from")
            home = [leg.home for leg in robot.legs]
        self.robot = robot
        self.home = [np.asarray([float(v) for v in h], dtype=float) for h in home]
        outputs = ["forward_kinematics", "jacobian", "jacobian_dot_qd", "inverse_dynamics", "mass_matrix"]
        self.legs = [derive(leg.chain, outputs=outputs).numeric for leg in robot.legs]
        self.attachments = [np.array(leg.attachment.matrix(), dtype=float) for leg in robot.legs]
        plat = robot.platform
        self.mass = float(plat.mass)
        self.com = np.array([float(c) for c in plat.com])
        self.inertia = np.array(plat.inertia_matrix, dtype=float)
        self.gravity = np.array([float(g) for g in robot.gravity])
        self.actuated = [leg.actuated for leg in robot.legs]

    # kinematics ------------------------------------------------------------------------------
    def leg_positions(self, p, R, guess=None) -> list[np.ndarray]:
        """Each leg's joint positions that close its loop at platform pose (p, R)."""
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = R, p
        out = []
        for k, numeric in enumerate(self.legs):
            target = pose @ self.attachments[k]
            theta = np.array(self.home[k] if guess is None else guess[k], dtype=float)
            for _ in range(50):
                T = np.asarray(numeric.forward_kinematics(theta, []), dtype=float).reshape(4, 4)
                err_p = target[:3, 3] - T[:3, 3]
                Re = target[:3, :3] @ T[:3, :3].T
                err_w = 0.5 * np.array([Re[2, 1] - Re[1, 2], Re[0, 2] - Re[2, 0], Re[1, 0] - Re[0, 1]])
                if max(np.abs(err_p).max(), np.abs(err_w).max()) < 1e-14:
                    break
                J = np.asarray(numeric.jacobian(theta, []), dtype=float).reshape(6, 6)
                theta = theta + np.linalg.solve(J, np.concatenate([err_p, err_w]))
            else:
                raise ValueError(f"leg {k + 1}: inverse kinematics did not converge")
            out.append(theta)
        return out

    def leg_states(self, p, R, twist, twist_rate=None, guess=None) -> list[LegState]:
        thetas = self.leg_positions(p, R, guess)
        omega, c_dot = np.asarray(twist[:3], float), np.asarray(twist[3:], float)
        c = p + R @ self.com
        states = []
        for k, numeric in enumerate(self.legs):
            theta = thetas[k]
            T = np.asarray(numeric.forward_kinematics(theta, []), dtype=float).reshape(4, 4)
            u = T[:3, 3]
            r = u - c
            # [v_U; omega] = S t_M with t_M = [omega; c_dot]
            S = np.zeros((6, 6))
            S[:3, :3] = -skew_numeric(r)
            S[:3, 3:] = np.eye(3)
            S[3:, :3] = np.eye(3)
            J = np.asarray(numeric.jacobian(theta, []), dtype=float).reshape(6, 6)
            rates = np.linalg.solve(J, S)
            theta_dot = rates @ np.concatenate([omega, c_dot])
            theta_ddot = None
            if twist_rate is not None:
                omega_dot, c_ddot = np.asarray(twist_rate[:3], float), np.asarray(twist_rate[3:], float)
                a_u = c_ddot + np.cross(omega_dot, r) + np.cross(omega, np.cross(omega, r))
                jdqd = np.asarray(numeric.jacobian_dot_qd(theta, theta_dot, []), dtype=float).reshape(6)
                theta_ddot = np.linalg.solve(J, np.concatenate([a_u, omega_dot]) - jdqd)
            states.append(LegState(theta, theta_dot, theta_ddot, u, J, S, rates))
        return states

    def twist_map(self, states) -> np.ndarray:
        """K (6x6): ``q_dot = K t_M``; the notes' T is its inverse."""
        return np.array([st.rates[self.actuated[k]] for k, st in enumerate(states)])

    # dynamics -----------------------------------------------------------------------------------
    def _platform_wrench_terms(self, R, twist):
        """(M_M (6x6), bias (6)): the wrench on the platform at C_M, [moment; force], is
        ``M_M t_dot + bias`` (bias: gyroscopic moment and minus gravity)."""
        I_world = R @ self.inertia @ R.T
        M = np.zeros((6, 6))
        M[:3, :3] = I_world
        M[3:, 3:] = self.mass * np.eye(3)
        omega = np.asarray(twist[:3], float)
        bias = np.concatenate([np.cross(omega, I_world @ omega), -self.mass * self.gravity])
        return M, bias

    def inverse_dynamics(self, p, R, twist, twist_rate, guess=None) -> np.ndarray:
        """phi (6): the actuator forces (N) or torques (N m) that give the platform the twist
        rate ``twist_rate`` at state (p, R, twist)."""
        states = self.leg_states(p, R, twist, twist_rate, guess)
        M, bias = self._platform_wrench_terms(R, twist)
        wrench = M @ np.asarray(twist_rate, float) + bias
        for k, st in enumerate(states):
            tau = np.asarray(self.legs[k].inverse_dynamics(st.theta, st.theta_dot, st.theta_ddot, []),
                             dtype=float).reshape(6)
            wrench = wrench + st.rates.T @ tau  # S_J^T J_J^-T tau
        K = self.twist_map(states)
        return np.linalg.solve(K.T, wrench)

    def forward_dynamics(self, p, R, twist, phi, guess=None) -> np.ndarray:
        """t_dot (6): the platform's twist rate [omega_dot; c_ddot] under actuator forces phi."""
        states = self.leg_states(p, R, twist, None, guess)
        M, bias = self._platform_wrench_terms(R, twist)
        A, b = M.copy(), bias.copy()
        omega = np.asarray(twist[:3], float)
        c = p + R @ self.com
        for k, st in enumerate(states):
            r = st.point - c
            numeric = self.legs[k]
            D = np.asarray(numeric.mass_matrix(st.theta, []), dtype=float).reshape(6, 6)
            h = np.asarray(numeric.inverse_dynamics(st.theta, st.theta_dot, np.zeros(6), []), dtype=float).reshape(6)
            jdqd = np.asarray(numeric.jacobian_dot_qd(st.theta, st.theta_dot, []), dtype=float).reshape(6)
            # theta_ddot = J^-1 (S t_dot + centripetal of U - J-dot theta_dot)
            centripetal = np.concatenate([np.cross(omega, np.cross(omega, r)), np.zeros(3)])
            offset = np.linalg.solve(st.jacobian, centripetal - jdqd)
            A += st.rates.T @ D @ st.rates  # S_J^T J_J^-T D_J J_J^-1 S_J
            b += st.rates.T @ (D @ offset + h)
        K = self.twist_map(states)
        return np.linalg.solve(A, K.T @ np.asarray(phi, float) - b)

    def seed_matrices(self, p, R, twist=None) -> dict:
        """The notes' matrices at platform pose (p, R): ``T`` (6x6, ``t_M = T q_dot``), ``L``
        (each leg's 6x6 ``L_J = J_J^-1 T``, with J_J taken at the platform's mass centre),
        ``Lambda`` (6x6: column J is ``L_J^T e_k``, k leg J's actuated joint; the identity, since
        ``q_J`` is itself joint k of leg J) and ``M`` (6x6, the mass matrix in actuated coordinates:
        ``T^T M_M T + sum L_J^T I_J L_J``)."""
        states = self.leg_states(p, R, np.zeros(6) if twist is None else twist)
        T = np.linalg.inv(self.twist_map(states))
        L = [st.rates @ T for st in states]
        Lambda = np.column_stack([L_J[k, :] for L_J, k in zip(L, self.actuated)])
        M_platform, _ = self._platform_wrench_terms(R, np.zeros(6))
        M = T.T @ M_platform @ T
        for k, (st, L_J) in enumerate(zip(states, L)):
            D = np.asarray(self.legs[k].mass_matrix(st.theta, []), dtype=float).reshape(6, 6)
            M = M + L_J.T @ D @ L_J
        return {"T": T, "L": L, "Lambda": Lambda, "M": M}
