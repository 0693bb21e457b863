"""Lagrange-Euler equations of motion in the trace form of the notes (the Lagrange-Euler/Newton-Euler tables).

Notation (4x4 homogeneous matrices, base frame 0):

- ``A_i = ^0A_i``: pose of link frame i; ``rbar_i``: COM of link i in frame i, homogeneous.
- ``Q_j``: the derivative operator of joint j (revolute: rotation generator about z, prismatic:
  translation generator along z), applied in the joint's own frame.
- ``U_ij = dA_i/dq_j = A_{j-1} Q_j ^{j-1}A_i`` for j <= i, 0 otherwise.  It is computed as
  ``Delta_j A_i`` with ``Delta_j = G_j Q_j G_j^{-1}``, G_j the joint frame in the base (the same
  matrix: for standard DH G_j = A_{j-1}; for modified DH the joint frame follows the constant
  part of the link transform).
- ``U_ijk = dU_ij/dq_k = Delta_min(j,k) Delta_max(j,k) A_i`` for j, k <= i, 0 otherwise.
- ``J_i``: 4x4 pseudo-inertia of link i in frame i, ``[[Sigma_i, m_i s_i], [m_i s_i^T, m_i]]``
  with ``Sigma_i = (tr(I_i)/2) 1 - I_i + m_i s_i s_i^T`` (I_i the inertia tensor about the COM).

Then::

    D_ik  = sum_{j >= max(i,k)} Tr(U_jk J_j U_ji^T)
    h_ikm = sum_{j >= max(i,k,m)} Tr(U_jkm J_j U_ji^T),   h_i = sum_k sum_m h_ikm qd_k qd_m
    c_i   = sum_{j >= i} -m_j g U_ji rbar_j,   g = (g_x, g_y, g_z, 0)

The Christoffel symbols of the first kind of D are exactly h_ikm, so the Coriolis matrix is
``C_ik = sum_m h_ikm qd_m = sum_j Tr(W_jk J_j U_ji^T)`` with ``W_jk = sum_m U_jkm qd_m``; W is
built incrementally (``S_jk = S_{j-1,k} + Delta_k Delta_j qd_j``) so the cost is O(n^3).
"""

from __future__ import annotations

import sympy as sp

from .chain import Chain
from ..model.geometry import rot_z


def pseudo_inertia(link) -> sp.Matrix:
    """The 4x4 pseudo-inertia J_i of a link about its frame origin (kg m^2 / kg m / kg)."""
    m = link.mass
    s = sp.Matrix(link.com)
    inertia = sp.Matrix(link.inertia_matrix)
    trace_half = (inertia[0, 0] + inertia[1, 1] + inertia[2, 2]) / 2
    sigma = trace_half * sp.eye(3) - inertia + m * s * s.T
    J = sp.zeros(4, 4)
    J[:3, :3] = sigma
    J[:3, 3] = m * s
    J[3, :3] = m * s.T
    J[3, 3] = m
    return J


def q_operator(revolute: bool) -> sp.Matrix:
    Q = sp.zeros(4, 4)
    if revolute:
        Q[0, 1], Q[1, 0] = -1, 1
    else:
        Q[2, 3] = 1
    return Q


def _define_transform(b, hint: str, mat: sp.Matrix, corner: int = 1) -> sp.Matrix:
    """Name the top three rows of a 4x4 matrix whose last row is (0, 0, 0, corner)."""
    out = sp.zeros(4, 4)
    out[3, 3] = corner
    for r in range(3):
        for c in range(4):
            out[r, c] = b.define(f"{hint}_{r}{c}", mat[r, c])
    return out


def _trace_product(X: sp.Matrix, Y: sp.Matrix) -> sp.Expr:
    """Tr(X Y^T) = sum of elementwise products (only the 3 top rows of U are nonzero)."""
    return sp.Add(*[X[r, c] * Y[r, c] for r in range(4) for c in range(4)
                    if X[r, c] != 0 and Y[r, c] != 0])


class LagrangeEuler:
    """Builds the Lagrange-Euler quantities of a chain with intermediate symbols."""

    def __init__(self, chain: Chain):
        self.chain = chain
        b = chain.builder
        n = chain.n
        self.A: list[sp.Matrix] = []        # ^0A_i
        self.Delta: list[sp.Matrix] = []    # Delta_j
        current = sp.eye(4)
        for i, link in enumerate(chain.robot.links):
            geo = chain.geometry[i]
            joint_frame = current * sp.Matrix(geo.pre)
            Q = q_operator(link.is_revolute)
            R, t = joint_frame[:3, :3], joint_frame[:3, 3]
            inv = sp.eye(4)
            inv[:3, :3] = R.T
            inv[:3, 3] = -R.T * t
            delta = (joint_frame * Q * inv).applyfunc(sp.expand)
            self.Delta.append(_define_transform(b, f"Dl{i + 1}", delta, corner=0))
            current = _define_transform(b, f"A{i + 1}", current * chain.transforms[i])
            self.A.append(current)
        self.J = [pseudo_inertia(link) for link in chain.robot.links]
        self._U: dict[tuple[int, int], sp.Matrix] = {}
        self._UJ: dict[tuple[int, int], sp.Matrix] = {}
        self.n = n

    def U(self, i: int, j: int) -> sp.Matrix:
        """U_ij (0-based indices), zero for j > i."""
        if j > i:
            return sp.zeros(4, 4)
        key = (i, j)
        if key not in self._U:
            b = self.chain.builder
            prod = self.Delta[j] * self.A[i]
            self._U[key] = sp.Matrix(4, 4, lambda r, c: b.define(f"U{i + 1}{j + 1}_{r}{c}", prod[r, c]) if r < 3 else 0)
        return self._U[key]

    def UJ(self, j: int, k: int) -> sp.Matrix:
        """U_jk J_j (named)."""
        key = (j, k)
        if key not in self._UJ:
            b = self.chain.builder
            prod = self.U(j, k) * self.J[j]
            self._UJ[key] = sp.Matrix(4, 4, lambda r, c: b.define(f"UJ{j + 1}{k + 1}_{r}{c}", prod[r, c]) if r < 3 else 0)
        return self._UJ[key]

    def mass_matrix(self) -> sp.Matrix:
        b = self.chain.builder
        n = self.n
        D = sp.zeros(n, n)
        for i in range(n):
            for k in range(i, n):
                total = sp.Add(*[_trace_product(self.UJ(j, k), self.U(j, i)) for j in range(max(i, k), n)])
                D[i, k] = D[k, i] = b.define(f"D{i + 1}{k + 1}", total)
        return D

    def coriolis_matrix(self, qd) -> sp.Matrix:
        b = self.chain.builder
        n = self.n
        C = sp.zeros(n, n)
        # S[j][k] = sum_{m <= j} Delta_min(k,m) Delta_max(k,m) qd_m, for j >= k
        omega_prev = sp.zeros(4, 4)  # sum_{m < k} Delta_m qd_m
        WJ: dict[tuple[int, int], sp.Matrix] = {}
        for k in range(n):
            S = omega_prev * self.Delta[k] + self.Delta[k] * self.Delta[k] * qd[k]
            for j in range(k, n):
                if j > k:
                    S = S + self.Delta[k] * self.Delta[j] * qd[j]
                S = _define_transform(b, f"S{j + 1}{k + 1}", S, corner=0)
                W = S * self.A[j]
                W = sp.Matrix(4, 4, lambda r, c: b.define(f"W{j + 1}{k + 1}_{r}{c}", W[r, c]) if r < 3 else 0)
                prod = W * self.J[j]
                WJ[(j, k)] = sp.Matrix(4, 4, lambda r, c: b.define(f"WJ{j + 1}{k + 1}_{r}{c}", prod[r, c]) if r < 3 else 0)
            omega_prev = _define_transform(b, f"Om{k + 1}", omega_prev + self.Delta[k] * qd[k], corner=0)
        for i in range(n):
            for k in range(n):
                total = sp.Add(*[_trace_product(WJ[(j, k)], self.U(j, i)) for j in range(max(i, k), n)])
                C[i, k] = b.define(f"C{i + 1}{k + 1}", total)
        return C

    def gravity(self) -> sp.Matrix:
        b = self.chain.builder
        n = self.n
        g = sp.Matrix([[*self.chain.gravity, 0]])
        c = sp.zeros(n, 1)
        for i in range(n):
            terms = []
            for j in range(i, n):
                link = self.chain.robot.links[j]
                if link.mass == 0:
                    continue
                rbar = sp.Matrix([*link.com, 1])
                terms.append(-link.mass * (g * self.U(j, i) * rbar)[0])
            c[i] = b.define(f"c{i + 1}_grav", sp.Add(*terms))
        return c

