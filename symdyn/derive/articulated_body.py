"""Forward dynamics by the articulated-body algorithm (the force-to-torque articulated-body note, Algorithm 1), symbolic.

Spatial vectors are 6 x 1 with the angular part first: motion ``[omega; v]`` (v: velocity of the
frame origin) and force ``[n; f]`` (n: moment about the origin).  Every quantity of joint j is
written in its *joint frame* ``J_j`` (as in :mod:`symdyn.derive.composite`): the joint axis is
its z axis through its origin, so the motion subspace is ``S_j = [e_z; 0]`` (revolute) or
``[0; e_z]`` (prismatic) and ``U_j = I^A_j S_j`` is a column of ``I^A_j``.  ``X_j`` maps motion
vectors from ``J_{j-1}`` (the base frame for j = 1) to ``J_j``; forces go back with ``X_j^T``.

Three sweeps, the notes' notation::

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

from dataclasses import dataclass

import sympy as sp

from .chain import Chain
from .spatial import (Placement, apply_force_back, apply_inertia_back, apply_motion, cross_force, cross_motion,
                      named_symmetric, spatial_inertia)


@dataclass(frozen=True)
class JointTransform:
    """``X_j = X(motion) X(constant)``: the motion transform into joint frame j as two
    :class:`~symdyn.derive.spatial.Placement` s, the constant one (the previous link's fixed
    placement and this joint's: numbers and parameters only) and the joint's own motion (a
    rotation about z by q_j, or a translation along z).  Applied stage by stage, each stage
    named, a transform costs what its structure needs."""

    constant: Placement
    moving: Placement

    def matrix(self) -> sp.Matrix:
        return self.moving.matrix() * self.constant.matrix()


def _named(b, hint, exprs) -> sp.Matrix:
    return sp.Matrix(b.vector(hint, [sp.expand(e) for e in exprs]))


def _namer(b):
    return lambda hint, exprs: list(b.vector(hint, exprs))


def transform_motion(b, T: JointTransform, v, hint: str) -> sp.Matrix:
    """``X v`` for a motion vector ``v`` (6 x 1) of the parent frame (stages named ``hint...``;
    the result itself is returned unnamed)."""
    inner = apply_motion(T.constant, v, _namer(b), f"{hint}c")
    return apply_motion(T.moving, inner, _namer(b), f"{hint}m")


def transform_force_back(b, T: JointTransform, f, hint: str) -> sp.Matrix:
    """``X^T f`` for a force ``f`` (6 x 1) of the joint frame, into the parent frame."""
    inner = _named(b, f"{hint}m", apply_force_back(T.moving, f, _namer(b), f"{hint}m"))
    return apply_force_back(T.constant, inner, _namer(b), f"{hint}c")


def transform_inertia_back(b, T: JointTransform, M, hint: str) -> sp.Matrix:
    """``X^T M X`` for a symmetric 6 x 6 inertia ``M`` of the joint frame, into the parent frame."""
    inner = named_symmetric(b, f"{hint}m", apply_inertia_back(T.moving, M, _namer(b), f"{hint}m"))
    return apply_inertia_back(T.constant, inner, _namer(b), f"{hint}c")


def joint_frames(chain: Chain):
    """Yield, base to tip, ``(j, X_j, v_j, S_j qd_j, post_j)`` for each joint (0-based j): the
    motion transform ``^jX_{j-1}`` into joint frame j, the body's spatial velocity there, the
    joint's own velocity and the constant pose of link frame j in joint frame j; ``X_j`` and
    ``v_j`` are named in the chain's program as they are made (a consumer's own definitions
    for joint j come after them, before joint j + 1's).  :func:`joint_transforms` gives the
    same transforms split for staged products."""
    b = chain.builder
    velocity = sp.zeros(6, 1)
    for j, (T, post) in enumerate(joint_transforms(chain)):
        k = j + 1
        link = chain.robot.links[j]
        Xj = T.matrix().applyfunc(lambda e: b.define(f"X{k}", sp.expand(e)))
        S_qd = sp.zeros(6, 1)
        S_qd[2 if link.is_revolute else 5] = chain.qd[j]
        velocity = _named(b, f"sv{k}", transform_motion(b, T, velocity, f"svc{k}") + S_qd)
        yield j, Xj, velocity, S_qd, post


def link_inertia(link, post: sp.Matrix) -> sp.Matrix:
    """The spatial inertia (6 x 6) of ``link`` in its joint frame, ``post`` the constant pose of
    the link frame in the joint frame (4 x 4)."""
    R, t = post[:3, :3], post[:3, 3]
    com = R * sp.Matrix(link.com) + t
    return spatial_inertia(link.mass, com, R * sp.Matrix(link.inertia_matrix) * R.T)


def joint_transforms(chain: Chain) -> list[tuple[JointTransform, sp.Matrix]]:
    """Per joint, base to tip: its :class:`JointTransform` and the constant pose of link frame j
    in joint frame j (4 x 4)."""
    out = []
    previous_post = sp.eye(4)
    for j in range(chain.n):
        geo = chain.geometry[j]
        out.append((JointTransform(Placement(previous_post * sp.Matrix(geo.pre)), Placement(chain.motions[j])),
                    sp.Matrix(geo.post)))
        previous_post = sp.Matrix(geo.post)
    return out


@dataclass(frozen=True)
class Sweeps:
    """The first two sweeps of Algorithm 1 for one robot (0-based lists, joint j+1 at index j).

    ``X``: motion transforms ``^jX_{j-1}``; ``axis``: the index of ``S_j``'s unit entry;
    ``v``, ``c``: velocities and velocity-product accelerations; ``I``: the links' spatial
    inertias; ``pA0``: the first sweep's bias forces ``v x* I v``; ``IA``, ``pA``: the
    articulated inertias and bias forces after the backward sweep; ``U``, ``d``, ``u``, ``inv``
    (``1/d``), ``Ia``, ``pa`` (``I^a``, ``p^a``, index 0 unused)."""

    X: tuple
    axis: tuple
    v: tuple
    c: tuple
    I: tuple
    pA0: tuple
    IA: tuple
    pA: tuple
    U: tuple
    d: tuple
    u: tuple
    inv: tuple
    Ia: tuple
    pa: tuple
    transforms: tuple = ()


def sweeps(chain: Chain, tau, friction) -> Sweeps:
    """Sweeps 1 and 2 of Algorithm 1 (forward: ``v``, ``c``, ``I^A = I``, ``p^A``; backward:
    ``U``, ``d``, ``u``, ``I^a``, ``p^a`` and their accumulation into the parent), every entry
    named in the chain's program.  ``tau``: joint forces (n); ``friction``: the damping and
    Coulomb terms to subtract from them (n, no qdd)."""
    b = chain.builder
    robot = chain.robot
    n = chain.n
    axis = tuple(2 if link.is_revolute else 5 for link in robot.links)  # S_j = unit vector e_axis

    def vec(hint, v):
        return sp.Matrix(b.vector(hint, [sp.expand(e) for e in v]))

    def sym6(hint, M):
        return named_symmetric(b, hint, M)

    transforms = [T for T, _ in joint_transforms(chain)]
    X, v, c, I, IA = [], [], [], [], []
    for j, Xj, velocity, S_qd, post in joint_frames(chain):
        k = j + 1
        link = robot.links[j]
        X.append(Xj)
        v.append(velocity)
        c.append(vec(f"sc{k}", cross_motion(velocity, S_qd)))
        I.append(sym6(f"IA{k}", link_inertia(link, post)))
        IA.append(I[j])

    def bias(j):
        """``p^A_j = v_j x* I_j v_j``, made where the backward sweep first needs it (so that it
        is not live through the whole forward sweep: faster register allocation for the
        compiler on long chains)."""
        momentum = vec(f"Iv{j + 1}", I[j] * v[j])  # named first: v x* (I v) stays bilinear, not expanded
        return vec(f"pA{j + 1}", cross_force(v[j], momentum))

    pA0 = [None] * n
    pA = [None] * n
    U, d, u, inv, Ia, pa = [None] * n, [None] * n, [None] * n, [None] * n, [None] * n, [None] * n
    pA[n - 1] = pA0[n - 1] = bias(n - 1)
    for j in reversed(range(n)):
        k = j + 1
        link = robot.links[j]
        U[j] = IA[j][:, axis[j]]
        d[j] = b.define(f"aba_d{k}", sp.expand(U[j][axis[j]] + link.armature))
        u[j] = b.define(f"aba_u{k}", sp.expand(tau[j] - friction[j] - pA[j][axis[j]]))
        inv[j] = b.define(f"aba_inv{k}", 1 / d[j])
        if j == 0:
            break
        scaled = vec(f"aba_b{k}", U[j] * inv[j])  # U / d, once: I^a below takes 21 products, not 42
        projected = IA[j] - scaled * U[j].T
        if link.armature == 0:
            # I^a S = U - U (S^T U) / d = 0 exactly when d = S^T U: the joint's row and column
            # vanish (Featherstone, section 7.3), and every product with them folds away
            projected[axis[j], :] = sp.zeros(1, 6)
            projected[:, axis[j]] = sp.zeros(6, 1)
        Ia[j] = sym6(f"Ia{k}", projected)
        pa[j] = vec(f"pa{k}", pA[j] + Ia[j] * c[j] + U[j] * b.define(f"aba_ud{k}", u[j] * inv[j]))
        IA[j - 1] = sym6(f"IA{k - 1}s", IA[j - 1] + transform_inertia_back(b, transforms[j], Ia[j], f"IAm{k}"))
        pA0[j - 1] = bias(j - 1)
        pA[j - 1] = vec(f"pA{k - 1}s", pA0[j - 1] + transform_force_back(b, transforms[j], pa[j], f"pAm{k}"))
    return Sweeps(X=tuple(X), axis=axis, v=tuple(v), c=tuple(c), I=tuple(I), pA0=tuple(pA0), IA=tuple(IA),
                  pA=tuple(pA), U=tuple(U), d=tuple(d), u=tuple(u), inv=tuple(inv), Ia=tuple(Ia),
                  pa=tuple(pa), transforms=tuple(transforms))


def accelerations(chain: Chain, sw: Sweeps):
    """Sweep 3 of Algorithm 1: ``(a', qdd, a)`` per joint (lists, base to tip), ``a_0 = [0; -g]``."""
    b = chain.builder
    accel = sp.Matrix([0, 0, 0, *[-g for g in chain.gravity]])
    a_prime, qdd, a = [], [], []
    for j in range(chain.n):
        k = j + 1
        ap = _named(b, f"ap{k}", transform_motion(b, sw.transforms[j], accel, f"apc{k}") + sw.c[j])
        qdd_j = b.define(f"qdd{k}_aba", sp.expand((sw.u[j] - (sw.U[j].T * ap)[0]) * sw.inv[j]))
        accel = ap.copy()
        accel[sw.axis[j]] += qdd_j
        a_prime.append(ap)
        qdd.append(qdd_j)
        a.append(accel)
    return a_prime, qdd, a


def forward_dynamics(chain: Chain, tau, friction) -> tuple[sp.Matrix, tuple[tuple[sp.Expr, sp.Expr], ...]]:
    """qdd (n x 1) by the articulated-body algorithm, and the pivots ``(d_j, d_j)`` it divides
    by (each must be positive).  ``tau``: joint forces; ``friction``: the damping and Coulomb
    terms to subtract (n x 1, no qdd in them)."""
    sw = sweeps(chain, tau, friction)
    _, qdd, _ = accelerations(chain, sw)
    return sp.Matrix(qdd), tuple((sw.d[j], sw.d[j]) for j in range(chain.n))


@dataclass(frozen=True)
class ReactionMap:
    """The force-to-torque map of the force-to-torque articulated-body note (sections 2-4) for one robot, 0-based lists.

    ``b[j] = U_j / d_j`` (eq. 3), ``A[j] = 1 - b_j S_j^T`` (eq. 4), :attr:`k_force` ``[j]`` the bias force
    ``p^A_j`` at tau = 0 (the notes' ``k_{j+1}``, eq. 5), ``k1`` the acceleration of body 1 at
    tau = 0 without its bias force (eq. 7), ``k0`` the base wrench at tau = 0 (eqs. 9-10),
    ``columns`` the base wrench per unit torque of each actuated joint (eq. 14:
    ``X_1^T A_1 ... X_{j-1}^T A_{j-1} X_j^T b_j``), ``actuated`` their joint indices."""

    sweeps: Sweeps
    b: tuple
    A: tuple
    k1: sp.Matrix
    k0: sp.Matrix
    columns: tuple
    actuated: tuple
    #: ``(j, i, W)``: the partial products ``W_{j,i} = A_i X_{i+1}^T ... X_j^T b_j`` (0-based j, i)
    partials: tuple = ()

    @property
    def k_force(self) -> tuple:
        """The bias forces ``p^A_j`` at tau = 0 (the notes' ``k_{j+1}``): the sweeps' own."""
        return self.sweeps.pA

    @property
    def matrix(self) -> sp.Matrix:
        """``[k0 | D]``, 6 x (1 + number of actuated joints)."""
        return sp.Matrix.hstack(self.k0, *self.columns)


def reaction_map(chain: Chain, friction) -> ReactionMap:
    """The wrench ``[n; f]`` that the base exerts on body 1 through joint 1, in the base frame
    (moment about the base origin first), as ``k0 + D tau_H`` with ``tau_H`` the actuated joints'
    forces and the passive joints' forces zero (the force-to-torque articulated-body note, eqs. 5-14), derived from the
    articulated-body recursion: ``k0`` from Algorithm 1 at tau = 0, each column of D as the
    notes' product ``X_1^T A_1 X_2^T A_2 ... X_j^T b_j``.  ``friction``: damping and Coulomb
    terms (n, no qdd); they stay in k0."""
    b = chain.builder
    n = chain.n
    sw = sweeps(chain, [sp.S.Zero] * n, friction)
    ax = sw.axis
    bvec, A = [], []
    for j in range(n):
        bj = sp.Matrix(b.vector(f"rb{j + 1}", [sp.expand(e * sw.inv[j]) for e in sw.U[j]]))
        bvec.append(bj)
        Aj = sp.eye(6)
        Aj[:, ax[j]] -= bj
        A.append(Aj)
    # eq. (7): a_1 = k_1 + S (tau_1 - S^T p^A_1) / d_1 with k_1 = (1 - S S^T I^A_1 / d_1)(X_1 a_0 + c_1)
    a0 = sp.Matrix([0, 0, 0, *[-g for g in chain.gravity]])
    base_accel = sw.X[0] * a0 + sw.c[0]
    k1 = base_accel.copy()
    k1[ax[0]] -= (sw.U[0].T * base_accel)[0] * sw.inv[0]
    k1 = sp.Matrix(b.vector("rk1", [sp.expand(e) for e in k1]))
    # eqs. (8)-(9) at tau = 0, friction included: f_1 = I^A_1 k_1 + A_1 p^A_1 - b_1 friction_1
    f1 = sw.IA[0] * k1 + A[0] * sw.pA[0] - bvec[0] * friction[0]
    k0 = sp.Matrix(b.vector("rk0", [sp.expand(e) for e in sw.X[0].T * f1]))
    columns, partials, actuated = [], [], chain.robot.actuated_joints
    for j in actuated:
        w = bvec[j]
        for i in reversed(range(j)):
            y = sw.X[i + 1].T * w
            w = sp.Matrix(b.vector(f"rw{j + 1}_{i + 1}", [sp.expand(e) for e in A[i] * y]))
            partials.append((j, i, w))
        columns.append(sp.Matrix(b.vector(f"rD{j + 1}", [sp.expand(e) for e in sw.X[0].T * w])))
    return ReactionMap(sweeps=sw, b=tuple(bvec), A=tuple(A), k1=k1, k0=k0,
                       columns=tuple(columns), actuated=actuated, partials=tuple(partials))
