"""Forward dynamics by the articulated-body algorithm (seed 004, Algorithm 1), symbolic.

Spatial vectors are 6 x 1 with the angular part first: motion ``[omega; v]`` (v: velocity of the
frame origin) and force ``[n; f]`` (n: moment about the origin).  Every quantity of joint j is
written in its *joint frame* ``J_j`` (as in :mod:`symdyn.derive.composite`): the joint axis is
its z axis through its origin, so the motion subspace is ``S_j = [e_z; 0]`` (revolute) or
``[0; e_z]`` (prismatic) and ``U_j = I^A_j S_j`` is a column of ``I^A_j``.  ``X_j`` maps motion
vectors from ``J_{j-1}`` (the base frame for j = 1) to ``J_j``; forces go back with ``X_j^T``.

Three sweeps, the seed's notation::

    v_j = X_j v_{j-1} + S_j qd_j,    c_j = v_j x S_j qd_j,
    I^A_j = I_j,                     p^A_j = v_j x* I_j v_j                      (j = 1..n)

    U_j = I^A_j S_j,   d_j = S_j^T U_j + armature_j,   u_j = tau_j - S_j^T p^A_j - friction_j
    I^a = I^A_j - U_j U_j^T / d_j,   p^a = p^A_j + I^a c_j + U_j u_j / d_j
    I^A_{j-1} += X_j^T I^a X_j,      p^A_{j-1} += X_j^T p^a                      (j = n..1)

    a'_j = X_j a_{j-1} + c_j,  qdd_j = (u_j - U_j^T a'_j) / d_j,  a_j = a'_j + S_j qdd_j
                                                                  (j = 1..n, a_0 = [0; -g])

Straight-line code: every entry is named in the chain's program as it is built, zeros fold.
"""

from __future__ import annotations

import sympy as sp

from .chain import Chain


def _skew(p: sp.Matrix) -> sp.Matrix:
    return sp.Matrix([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])


def motion_transform(pose: sp.Matrix) -> sp.Matrix:
    """``X`` (6 x 6) mapping motion vectors of frame A to frame B, ``pose`` = B in A (4x4)."""
    R, p = pose[:3, :3], pose[:3, 3]
    X = sp.zeros(6, 6)
    X[:3, :3] = R.T
    X[3:, 3:] = R.T
    X[3:, :3] = -R.T * _skew(p)
    return X


def spatial_inertia(mass, com: sp.Matrix, inertia_com: sp.Matrix) -> sp.Matrix:
    """The 6 x 6 spatial inertia about a frame's origin of a body with centre of mass ``com``
    and inertia ``inertia_com`` about it (both in that frame)."""
    cx = _skew(com)
    I = sp.zeros(6, 6)
    I[:3, :3] = inertia_com - mass * cx * cx
    I[:3, 3:] = mass * cx
    I[3:, :3] = -mass * cx
    I[3:, 3:] = mass * sp.eye(3)
    return I


def _cross_motion(v: sp.Matrix, m: sp.Matrix) -> sp.Matrix:
    w, u = v[:3, 0], v[3:, 0]
    return sp.Matrix.vstack(w.cross(m[:3, 0]), w.cross(m[3:, 0]) + u.cross(m[:3, 0]))


def _cross_force(v: sp.Matrix, f: sp.Matrix) -> sp.Matrix:
    w, u = v[:3, 0], v[3:, 0]
    return sp.Matrix.vstack(w.cross(f[:3, 0]) + u.cross(f[3:, 0]), w.cross(f[3:, 0]))


def forward_dynamics(chain: Chain, tau, friction) -> tuple[sp.Matrix, tuple[tuple[sp.Expr, sp.Expr], ...]]:
    """qdd (n x 1) by the articulated-body algorithm, and the pivots ``(d_j, d_j)`` it divides
    by (each must be positive).  ``tau``: joint forces; ``friction``: the damping and Coulomb
    terms to subtract (n x 1, no qdd in them)."""
    b = chain.builder
    robot = chain.robot
    n = chain.n
    qd = chain.qd
    axis = [2 if link.is_revolute else 5 for link in robot.links]  # S_j = unit vector e_axis

    def vec(hint, v):
        return sp.Matrix(b.vector(hint, [sp.expand(e) for e in v]))

    def sym6(hint, M):
        out = sp.zeros(6, 6)
        for r in range(6):
            for c in range(r, 6):
                out[r, c] = out[c, r] = b.define(f"{hint}_{r}{c}", sp.expand(M[r, c]))
        return out

    X, v, c, IA, pA = [], [], [], [], []
    previous_post = sp.eye(4)
    velocity = sp.zeros(6, 1)
    for j, link in enumerate(robot.links):
        k = j + 1
        geo = chain.geometry[j]
        pose = previous_post * sp.Matrix(geo.pre) * chain.motions[j]
        Xj = motion_transform(pose).applyfunc(lambda e: b.define(f"X{k}", sp.expand(e)))
        X.append(Xj)
        S_qd = sp.zeros(6, 1)
        S_qd[axis[j]] = qd[j]
        velocity = vec(f"sv{k}", Xj * velocity + S_qd)
        v.append(velocity)
        c.append(vec(f"sc{k}", _cross_motion(velocity, S_qd)))
        post = sp.Matrix(geo.post)
        R, t = post[:3, :3], post[:3, 3]
        com = R * sp.Matrix(link.com) + t
        inertia = spatial_inertia(link.mass, com, R * sp.Matrix(link.inertia_matrix) * R.T)
        IA.append(sym6(f"IA{k}", inertia))
        pA.append(vec(f"pA{k}", _cross_force(velocity, IA[j] * velocity)))
        previous_post = post

    U, d, u, inv = [None] * n, [None] * n, [None] * n, [None] * n
    for j in reversed(range(n)):
        k = j + 1
        link = robot.links[j]
        U[j] = IA[j][:, axis[j]]
        d[j] = b.define(f"aba_d{k}", sp.expand(U[j][axis[j]] + link.armature))
        u[j] = b.define(f"aba_u{k}", sp.expand(tau[j] - friction[j] - pA[j][axis[j]]))
        inv[j] = b.define(f"aba_inv{k}", 1 / d[j])
        if j == 0:
            break
        Ia = sym6(f"Ia{k}", IA[j] - U[j] * U[j].T * inv[j])
        pa = vec(f"pa{k}", pA[j] + Ia * c[j] + U[j] * (u[j] * inv[j]))
        IA[j - 1] = sym6(f"IA{k - 1}s", IA[j - 1] + X[j].T * Ia * X[j])
        pA[j - 1] = vec(f"pA{k - 1}s", pA[j - 1] + X[j].T * pa)

    accel = sp.Matrix([0, 0, 0, *[-g for g in chain.gravity]])
    qdd = []
    for j in range(n):
        k = j + 1
        a_prime = vec(f"ap{k}", X[j] * accel + c[j])
        qdd_j = b.define(f"qdd{k}_aba", sp.expand((u[j] - (U[j].T * a_prime)[0]) * inv[j]))
        qdd.append(qdd_j)
        accel = a_prime.copy()
        accel[axis[j]] += qdd_j
    return sp.Matrix(qdd), tuple((d[j], d[j]) for j in range(n))
