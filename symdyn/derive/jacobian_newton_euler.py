"""Jacobian-projected Newton-Euler equations (the lecture "MB Dynamics NE"), symbolic.

Every vector is in the base frame ("world" of the notes).  For link i: ``k_i`` the joint axis,
``r_i`` the centre of mass, ``d_i = r_i - p_i`` from the joint point p_i to the centre of mass,
``h_i = p_i - r_{i-1}`` from the previous centre of mass to the joint (``r_0`` the base origin),
``M_i = diag(m_i 1, I_i)`` with ``I_i`` the inertia about the centre of mass in world axes.

- Link Jacobians ``J_ci`` (6 x n, rows: centre-of-mass velocity, angular velocity), column
  j <= i: ``[k_j x (r_i - p_j); k_j]`` (revolute) or ``[k_j; 0]`` (prismatic).
- Mass matrix, the sum of the projected link mass matrices: ``H = sum_i J_ci^T M_i J_ci``.
- Forward recursion (i = 1..n), revolute::

      omega_i    = omega_{i-1} + k_i qd_i
      omegadot_i = omegadot_{i-1} + omega_{i-1} x k_i qd_i + k_i qdd_i
      v_i        = v_{i-1} + omega_{i-1} x (r_i - r_{i-1}) + (k_i x d_i) qd_i
      vdot_i     = vdot_{i-1} + omegadot_{i-1} x (r_i - r_{i-1}) + omega_{i-1} x (v_i - v_{i-1})
                   + omega_i x (k_i x d_i) qd_i + (k_i x d_i) qdd_i

  prismatic::

      omega_i = omega_{i-1};  omegadot_i = omegadot_{i-1}
      v_i     = v_{i-1} + omega_{i-1} x (r_i - r_{i-1}) + k_i qd_i
      vdot_i  = vdot_{i-1} + omegadot_{i-1} x (r_i - r_{i-1})
                + omega_{i-1} x (v_i - v_{i-1} + k_i qd_i) + k_i qdd_i

  with ``vdot_0 = -g`` (gravity as an upward acceleration of the base, as in Table 3.2); at
  ``qdd = 0`` and ``g = 0`` the accelerations are ``gamma = Jdot_c qd``.
- Backward recursion (i = n..1), forces and torques through joint i, about the joint point::

      f_ec,i = m_i vdot_i;   t_ec,i = I_i omegadot_i + omega_i x I_i omega_i   (u_n)
      f_Ji = f_ec,i + f_J(i+1)
      t_Ji = t_ec,i + t_J(i+1) + d_i x f_ec,i + (d_i + h_(i+1)) x f_J(i+1)
      tau_i = k_i . t_Ji (revolute),   k_i . f_Ji (prismatic)

  which is ``J_c^T (M nudot + u_n)`` without forming ``J_c^T``: with ``qdd = 0`` it gives
  ``c = J_c^T (M gamma + u_n)`` (plus gravity when ``g`` is given).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import sympy as sp

from .chain import Chain
from .spatial import cross_nonzero as _cross
from .spatial import named_pose


@dataclass
class LinkMotion:
    """World-frame motion of one link's centre of mass for one forward recursion."""

    omega: sp.Matrix
    omegadot: sp.Matrix
    v: sp.Matrix
    vdot: sp.Matrix
    f_ec: sp.Matrix | None = None
    t_ec: sp.Matrix | None = None
    f_J: sp.Matrix | None = None
    t_J: sp.Matrix | None = None
    tau: sp.Expr | None = None


class JacobianNewtonEuler:
    """The world-frame quantities of one chain (``k_i``, ``p_i``, ``r_i``, ``d_i``, ``h_i``,
    ``I_i``), named in the chain's program as they are built."""

    def __init__(self, chain: Chain):
        self.chain = chain
        b = chain.builder
        robot = chain.robot
        current = sp.eye(4)
        self.k, self.p, self.r, self.d, self.h, self.inertia = [], [], [], [], [], []
        previous_com = sp.zeros(3, 1)
        for i, link in enumerate(robot.links):
            n = i + 1
            geo = chain.geometry[i]
            joint_frame = current * sp.Matrix(geo.pre)
            self.k.append(b.vector(f"k{n}", [sp.expand(e) for e in joint_frame[:3, 2]]))
            self.p.append(b.vector(f"pj{n}", [sp.expand(e) for e in joint_frame[:3, 3]]))
            current = named_pose(b, f"A0{n}", current * chain.transforms[i])
            R = current[:3, :3]
            self.r.append(b.vector(f"r{n}", [sp.expand(e) for e in current[:3, 3] + R * sp.Matrix(link.com)]))
            self.d.append(b.vector(f"d{n}", self.r[i] - self.p[i]))
            self.h.append(b.vector(f"h{n}", self.p[i] - previous_com))
            world = R * sp.Matrix(link.inertia_matrix) * R.T
            self.inertia.append(sp.Matrix(3, 3, lambda a, c: b.define(f"I{n}w_{min(a, c)}{max(a, c)}",
                                                                     sp.expand(world[a, c]))))
            previous_com = self.r[i]

    @property
    def n(self) -> int:
        return self.chain.n

    def link_jacobian(self, i: int) -> sp.Matrix:
        """``J_ci`` (6 x n): velocity of link i's centre of mass (rows 0-2) and its angular
        velocity (rows 3-5) per joint rate, world axes."""
        b = self.chain.builder
        J = sp.zeros(6, self.n)
        for j in range(i + 1):
            if self.chain.robot.links[j].is_revolute:
                J[:3, j] = b.vector(f"Jc{i + 1}_{j + 1}", _cross(self.k[j], self.r[i] - self.p[j]))
                J[3:, j] = self.k[j]
            else:
                J[:3, j] = self.k[j]
        return J

    def mass_matrix(self) -> sp.Matrix:
        """``H = sum_i J_ci^T M_i J_ci`` (n x n, symmetric), each entry named."""
        b = self.chain.builder
        n = self.n
        jacobians = [self.link_jacobian(i) for i in range(n)]
        H = sp.zeros(n, n)
        for row in range(n):
            for col in range(row, n):
                total = sp.S.Zero
                for i in range(max(row, col), n):
                    link = self.chain.robot.links[i]
                    Jv, Jw = jacobians[i][:3, :], jacobians[i][3:, :]
                    total += link.mass * (Jv[:, row].T * Jv[:, col])[0]
                    total += (Jw[:, row].T * self.inertia[i] * Jw[:, col])[0]
                H[row, col] = H[col, row] = b.define(f"H{row + 1}{col + 1}", sp.expand(total))
        return H

    def forward(self, qd: Sequence[sp.Expr], qdd: Sequence[sp.Expr], gravity: sp.Matrix, tag: str) -> list[LinkMotion]:
        """The forward recursion of the notes for the given rates and accelerations."""
        b = self.chain.builder
        omega = sp.zeros(3, 1)
        omegadot = sp.zeros(3, 1)
        v = sp.zeros(3, 1)
        vdot = -sp.Matrix(gravity)
        previous_com = sp.zeros(3, 1)
        motions = []
        for i, link in enumerate(self.chain.robot.links):
            n = i + 1
            k, d = self.k[i], self.d[i]
            lever = self.r[i] - previous_com
            if link.is_revolute:
                kd = b.vector(f"kd{n}", _cross(k, d))
                omega_i = b.vector(f"om{n}{tag}", omega + k * qd[i])
                omegadot_i = b.vector(f"omd{n}{tag}", omegadot + _cross(omega, k * qd[i]) + k * qdd[i])
                v_i = b.vector(f"v{n}{tag}", v + _cross(omega, lever) + kd * qd[i])
                vdot_i = b.vector(f"vdt{n}{tag}", vdot + _cross(omegadot, lever) + _cross(omega, v_i - v)
                                  + _cross(omega_i, kd) * qd[i] + kd * qdd[i])
            else:
                omega_i, omegadot_i = omega, omegadot
                v_i = b.vector(f"v{n}{tag}", v + _cross(omega, lever) + k * qd[i])
                vdot_i = b.vector(f"vdt{n}{tag}", vdot + _cross(omegadot, lever)
                                  + _cross(omega, v_i - v + k * qd[i]) + k * qdd[i])
            motions.append(LinkMotion(omega_i, omegadot_i, v_i, vdot_i))
            omega, omegadot, v, vdot, previous_com = omega_i, omegadot_i, v_i, vdot_i, self.r[i]
        return motions

    def backward(self, motions: list[LinkMotion], tag: str) -> sp.Matrix:
        """The backward recursion: joint forces (n x 1) ``J_c^T (M nudot + u_n)``."""
        b = self.chain.builder
        f_next, t_next = sp.zeros(3, 1), sp.zeros(3, 1)
        taus = [sp.S.Zero] * self.n
        for i in reversed(range(self.n)):
            n = i + 1
            link = self.chain.robot.links[i]
            m = motions[i]
            I = self.inertia[i]
            m.f_ec = b.vector(f"fec{n}{tag}", link.mass * m.vdot)
            m.t_ec = b.vector(f"tec{n}{tag}", I * m.omegadot + _cross(m.omega, I * m.omega))
            m.f_J = b.vector(f"fJ{n}{tag}", m.f_ec + f_next)
            arm_next = self.d[i] + self.h[i + 1] if i + 1 < self.n else sp.zeros(3, 1)
            m.t_J = b.vector(f"tJ{n}{tag}", m.t_ec + t_next + _cross(self.d[i], m.f_ec) + _cross(arm_next, f_next))
            m.tau = b.define(f"tauJ{n}{tag}", sp.expand((self.k[i].T * (m.t_J if link.is_revolute else m.f_J))[0]))
            taus[i] = m.tau
            f_next, t_next = m.f_J, m.t_J
        return sp.Matrix(taus)

    def joint_forces(self, qd, qdd, gravity, tag: str) -> sp.Matrix:
        return self.backward(self.forward(qd, qdd, gravity, tag), tag)
