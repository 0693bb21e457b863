"""Mass matrix by the composite-rigid-body method, symbolic (Walker-Orin / Featherstone's CRBA).

D(q) is the kinetic-energy matrix: ``D_ij = S_i . (Ic_j S_j)`` for i <= j, where ``S_j`` is the
unit motion of joint j and ``Ic_j`` the inertia of links j..n taken as one rigid body (the
*composite* body of joint j).  Instead of n unit-acceleration Newton-Euler passes this needs
one backward sweep to accumulate the composite inertias and, per column, one sweep that carries
the composite body's force back towards the base.

Frames.  Every quantity of joint j is written in its *joint frame* ``J_j = frame_{j-1} Pre_j
Joint_j(q_j)`` (see :mod:`symdyn.derive.kinematics`): the joint axis is its z axis and passes through
its origin, so ``S_j`` is (omega = e_z, v = 0) for a revolute joint and (0, e_z) for a
prismatic one, and link j's own inertia in ``J_j`` is a constant (frame j is ``J_j Post_j``).
The pose of ``J_{j+1}`` in ``J_j`` is ``Post_j Pre_{j+1} Joint_{j+1}(q_{j+1})``: one constant
transform (structural zeros and ones of the DH table fold away) after a rotation about z or a
translation along z.

A rigid body's inertia about a frame's origin is kept as (m, h, J): mass (kg), first moment
``h = m c`` (kg m, c the centre of mass) and the 3x3 rotational inertia about the origin
(kg m^2).  For unit motion (omega, v) of the origin the body's momentum is
``f = m v + omega x h`` (N s) and ``n = h x v + J omega`` (N m s) about the origin.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .chain import Chain
from .program import ProgramBuilder
from .spatial import named_symmetric, skew


@dataclass(frozen=True)
class BodyInertia:
    """Inertia of a rigid body about the origin of some frame, components in that frame."""

    mass: sp.Expr
    first_moment: sp.Matrix  # 3 x 1, m c
    rotational: sp.Matrix  # 3 x 3 symmetric, about the origin


def _cross_matrix_terms(p: sp.Matrix, h: sp.Matrix, m: sp.Expr) -> sp.Matrix:
    """``m (|p|^2 I - p p^T) + 2 (p.h) I - p h^T - h p^T``: the change of a rotational inertia
    when the reference point moves by -p (body frame origin placed at p)."""
    ph = (p.T * h)[0]
    pp = (p.T * p)[0]
    return m * (pp * sp.eye(3) - p * p.T) + 2 * ph * sp.eye(3) - p * h.T - h * p.T


def _single_axis(R: sp.Matrix):
    """``(k, a, b, c, s)`` when R is a rotation about coordinate axis k (R[k, :] and R[:, k]
    are e_k, and the (a, b) block is [[c, -s], [s, c]], a < b the other two axes), else None."""
    for k in range(3):
        unit = [sp.S.One if r == k else sp.S.Zero for r in range(3)]
        if list(R[k, :]) != unit or list(R[:, k]) != unit:
            continue
        a, b = (r for r in range(3) if r != k)
        c, s = R[a, a], R[b, a]
        if sp.expand(R[b, b] - c) == 0 and sp.expand(R[a, b] + s) == 0:
            return k, a, b, c, s
    return None


def _rotate_about_axis(b: ProgramBuilder, J: sp.Matrix, axis, hint: str) -> sp.Matrix:
    """``R J R^T`` for a symmetric J and a rotation about one coordinate axis (see
    :func:`_single_axis`), by the half-angle identities: with ``D = J_aa - J_bb``,
    ``J'_aa = J_aa - s^2 D - 2 c s J_ab``, ``J'_bb = J_bb + s^2 D + 2 c s J_ab``,
    ``J'_ab = (c^2 - s^2) J_ab + c s D``, ``J'_ka = c J_ka - s J_kb``, ``J'_kb = s J_ka + c J_kb``:
    about 11 multiplications (8 for a constant rotation) instead of 18-22 for the product."""
    k, a, bb, c_, s_ = axis
    ss = b.define(f"{hint}ss", sp.expand(s_ * s_))
    cs = b.define(f"{hint}cs", sp.expand(c_ * s_))
    cc_ss = sp.expand(1 - 2 * ss) if ss.is_Symbol else sp.expand(c_ * c_ - s_ * s_)
    D = b.define(f"{hint}D", sp.expand(J[a, a] - J[bb, bb]))
    t1 = b.define(f"{hint}t1", sp.expand(ss * D))
    t2 = b.define(f"{hint}t2", sp.expand(2 * cs * J[a, bb]))
    out = sp.zeros(3, 3)
    entries = {(k, k): J[k, k],
               (a, a): J[a, a] - t1 - t2,
               (bb, bb): J[bb, bb] + t1 + t2,
               (a, bb): cc_ss * J[a, bb] + cs * D,
               (k, a): c_ * J[k, a] - s_ * J[k, bb],
               (k, bb): s_ * J[k, a] + c_ * J[k, bb]}
    for (r, col), e in entries.items():
        lo, hi = min(r, col), max(r, col)
        out[lo, hi] = out[hi, lo] = b.define(f"{hint}R_{lo}{hi}", sp.expand(e))
    return out


def transform_inertia(b: ProgramBuilder, body: BodyInertia, pose: sp.Matrix, hint: str) -> BodyInertia:
    """The inertia of ``body`` (given in frame B) expressed in frame A, where ``pose`` (4x4) is
    the pose of B in A."""
    R, p = pose[:3, :3], pose[:3, 3]
    m = body.mass
    h_rot = b.vector(f"{hint}h", (R * body.first_moment).applyfunc(sp.expand))
    if R == sp.eye(3):
        J_rot = body.rotational
    elif (axis := _single_axis(R)) is not None:
        J_rot = _rotate_about_axis(b, body.rotational, axis, hint)
    else:
        half = sp.Matrix(3, 3, lambda r, c: b.define(f"{hint}A_{r}{c}", sp.expand((R[r, :] * body.rotational[:, c])[0])))
        J_rot = named_symmetric(b, f"{hint}R", half * R.T)
    if p.is_zero_matrix:
        return BodyInertia(m, h_rot, J_rot)
    J = named_symmetric(b, f"{hint}J", J_rot + _cross_matrix_terms(p, h_rot, m))
    h = b.vector(f"{hint}m", (h_rot + m * p).applyfunc(sp.expand))
    return BodyInertia(m, h, J)


def add_inertia(b: ProgramBuilder, a: BodyInertia, c: BodyInertia, hint: str) -> BodyInertia:
    return BodyInertia(sp.expand(a.mass + c.mass),
                       b.vector(f"{hint}h", (a.first_moment + c.first_moment).applyfunc(sp.expand)),
                       named_symmetric(b, f"{hint}J", a.rotational + c.rotational))


def transform_force(b: ProgramBuilder, force: tuple[sp.Matrix, sp.Matrix], pose: sp.Matrix, hint: str):
    """A force/moment pair (f, n about B's origin, components in B) expressed in frame A."""
    f, n = force
    R, p = pose[:3, :3], pose[:3, 3]
    f_a = b.vector(f"{hint}f", (R * f).applyfunc(sp.expand))
    n_a = R * n
    if not p.is_zero_matrix:
        n_a = n_a + p.cross(f_a)
    return f_a, b.vector(f"{hint}n", n_a.applyfunc(sp.expand))


def _cancel(expr):
    """``expr`` with symbolic divisions cancelled where they cancel (rational function normal
    form); expressions without a symbolic denominator are returned unchanged."""
    expr = sp.sympify(expr)
    has_division = any(p.exp.is_negative and p.base.free_symbols for p in expr.atoms(sp.Pow))
    return sp.cancel(expr) if has_division else expr


def _about_origin(body) -> BodyInertia:
    """A link's (or a floating base's) inertia about the origin of the frame its centre of mass
    and inertia are given in (``body``: ``mass``, ``com``, ``inertia_matrix``)."""
    m = body.mass
    s = sp.Matrix(body.com)
    J = sp.Matrix(body.inertia_matrix) + m * ((s.T * s)[0] * sp.eye(3) - s * s.T)
    # m s and the inertia about the origin are polynomial in the parameters even when the COM
    # is not (a merged runtime payload has c = (m1 c1 + m2 c2) / (m1 + m2)): cancel the division
    return BodyInertia(m, (m * s).applyfunc(_cancel), J.applyfunc(_cancel))


def _link_inertia(chain: Chain, i: int) -> BodyInertia:
    """Link i's inertia about the origin of its joint frame (constant)."""
    body = _about_origin(chain.robot.links[i])
    m = body.mass
    post = sp.Matrix(chain.geometry[i].post)
    R, p = post[:3, :3], post[:3, 3]
    h = R * body.first_moment
    J = R * body.rotational * R.T + _cross_matrix_terms(p, h, m)
    return BodyInertia(m, (h + m * p).applyfunc(sp.expand), J.applyfunc(sp.expand))


def composite_inertias(chain: Chain) -> list[BodyInertia]:
    """Ic_j for j = 1..n: link j and every link that hangs on it (links j..n of a chain) as one
    body, about the origin of joint frame J_j."""
    b = chain.builder
    n = chain.n
    composite: list[BodyInertia | None] = [None] * n
    for j in reversed(range(n)):
        own = _link_inertia(chain, j)
        children = chain.children(j)
        if not children:
            composite[j] = BodyInertia(own.mass, b.vector(f"Ic{j + 1}h", own.first_moment),
                                       named_symmetric(b, f"Ic{j + 1}J", own.rotational))
            continue
        composite[j] = _with_children(chain, own, composite, children, f"Ic{j + 1}")
    return composite


def _with_children(chain: Chain, own: BodyInertia, composite: list, children, hint: str) -> BodyInertia:
    """``own`` plus the composite inertias of ``children`` (each moved into the parent's joint
    frame by its motion and its constant placement), named ``{hint}`` (``{hint}_{c}`` on the
    way)."""
    b, total = chain.builder, own
    for c in children:
        child = transform_inertia(b, composite[c], chain.motions[c], f"Iq{c + 1}")
        child = transform_inertia(b, child, _between(chain, c), f"Ib{c + 1}")
        total = add_inertia(b, total, child, hint if c == children[-1] else f"{hint}_{c + 1}")
    return total


def _between(chain: Chain, c: int) -> sp.Matrix:
    """The constant pose of joint c's pre-motion frame in its parent's joint frame: ``Post_p Pre_c``
    (``Pre_c`` for a joint on the base)."""
    parent = chain.parents[c]
    pre = sp.Matrix(chain.geometry[c].pre)
    return pre if parent < 0 else sp.Matrix(chain.geometry[parent].post) * pre


def unit_momentum(body: BodyInertia, revolute: bool) -> tuple[sp.Matrix, sp.Matrix]:
    """(f, n): momentum of ``body`` for a unit motion of the joint whose axis is the z axis of
    the frame the body's inertia is given in (f in N s per unit rate, n about the origin)."""
    ez = sp.Matrix([0, 0, 1])
    if revolute:
        return -body.first_moment.cross(ez), body.rotational * ez
    return body.mass * ez, body.first_moment.cross(ez)


def whole_robot_inertia(chain: Chain, composite: list[BodyInertia]) -> BodyInertia:
    """Every link, and a floating base's body, as one rigid body about the base origin (base
    frame), from the composite inertias of the joints on the base."""
    return _with_children(chain, _about_origin(chain.robot.base_inertia), composite, chain.children(-1), "Ic0")


def _with_floating_base(chain: Chain, composite: list[BodyInertia], D: sp.Matrix, to_base: list) -> sp.Matrix:
    """The mass matrix of a floating-base robot, (6 + n) x (6 + n), from the joints' block ``D``:
    the whole robot's composite inertia (m, h, J) about the base origin in the base frame gives
    the base block ``[[m 1, -[h x]], [[h x], J]]`` (linear velocity first, as Pinocchio's
    free-flyer), and each joint's column of it is its composite body's unit momentum in the base
    frame (``to_base``: force, then moment about the base origin)."""
    total = whole_robot_inertia(chain, composite)
    n = D.shape[0]
    out = sp.zeros(6 + n, 6 + n)
    hx = skew(total.first_moment)
    out[:3, :3] = total.mass * sp.eye(3)
    out[:3, 3:6] = -hx
    out[3:6, :3] = hx
    out[3:6, 3:6] = total.rotational
    out[6:, 6:] = D
    for j, (f, moment) in enumerate(to_base):
        for r in range(3):
            out[r, 6 + j] = out[6 + j, r] = f[r]
            out[3 + r, 6 + j] = out[6 + j, 3 + r] = moment[r]
    return out


#: Chains with at least this many joints get D by the projected form (see :func:`mass_matrix`):
#: on generic chains (benchmarks/long_chains.py) the propagated form is faster at 12 joints
#: (645 against 722 ns, gcc -O2), the projected one from about 16 (18: 1364 against 1454 ns;
#: 24: 1919 against 2456 ns).
PROJECTED_FROM_DOF = 16


def mass_matrix(chain: Chain, projected: bool | None = None) -> sp.Matrix:
    """D(q) (see :func:`mass_matrix_factored`)."""
    return mass_matrix_factored(chain, projected)[0]


def mass_matrix_factored(chain: Chain, projected: bool | None = None) -> tuple[sp.Matrix, tuple]:
    """D(q) (n x n, kg m^2 / kg m / kg by joint types) by the composite-rigid-body method.

    Two ways to form the off-diagonal entries ``D_ij = S_i . F_j`` (i < j), where
    ``F_j = Ic_j S_j`` is the momentum of composite body j for a unit rate of joint j:

    - *propagated* (default below :data:`PROJECTED_FROM_DOF` joints): F_j is carried from J_j
      to J_i through the joint frames between them, one force transform per pair (i, j); the
      structural zeros of each DH step fold away, which wins on short arms.
    - *projected* (``projected=True``, default from :data:`PROJECTED_FROM_DOF` joints): every
      S_i and F_j is written once in joint frame J_1 (its axis is z and q_1 drops out), so each
      pair costs one 6-vector dot product; O(n) transforms plus 11 operations per pair
      instead of ~30, as in Pinocchio's world-frame ``crba``.

    Returns ``(D, factors)``.  ``factors`` is ``()`` for the propagated form; for the projected
    form it is ``(S, F)``: ``S[i]`` (i = 0..n-2) is joint i+1's unit motion (omega; v) and
    ``F[j - 1]`` (j = 1..n-1) composite body j+1's momentum (moment; force), 6 expressions each,
    both in J_1, with ``D[i, j] = S[i] . F[j - 1]`` for every i < j (an emitter may compute the
    off-diagonal entries as that loop of dot products instead of n(n-1)/2 expressions).
    """
    b = chain.builder
    n = chain.n
    links = chain.robot.links
    if projected is None:
        projected = n >= PROJECTED_FROM_DOF and not chain.robot.is_tree
    if projected and chain.robot.is_tree:
        raise ValueError("the projected form of the mass matrix is written for serial chains")
    composite = composite_inertias(chain)
    between = [_between(chain, j + 1) for j in range(n - 1)] if projected else []
    D = sp.zeros(n, n)
    if projected:
        # one forward sweep: the pose of J_k in J_1, then S_k and F_k right away, so that no
        # pose stays needed (live in the generated code) after its own joint
        motion = []  # S_i in J_1: (omega, v of the point at J_1's origin)
        momenta = []
        pose = sp.eye(4)
        for k in range(n):
            if k > 0:
                # (pose of J_k-1) * (constant step) named first: the product with the joint's
                # rotation about z then costs 4 multiplications per row instead of 11
                step = pose * between[k - 1]
                fixed = b.matrix(f"R1_{k + 1}b", step[:3, :3].applyfunc(sp.expand))
                step = fixed.row_join(step[:3, 3]).col_join(sp.Matrix([[0, 0, 0, 1]]))
                moved = step * chain.motions[k]
                rot = b.matrix(f"R1_{k + 1}", moved[:3, :3].applyfunc(sp.expand))
                pos = b.vector(f"p1_{k + 1}", moved[:3, 3].applyfunc(sp.expand))
                pose = rot.row_join(pos).col_join(sp.Matrix([[0, 0, 0, 1]]))
            axis, point = pose[:3, 2], pose[:3, 3]
            if links[k].is_revolute:
                motion.append((axis, b.vector(f"S{k + 1}v", point.cross(axis).applyfunc(sp.expand))))
            else:
                motion.append((sp.zeros(3, 1), axis))
            local = unit_momentum(composite[k], links[k].is_revolute)
            D[k, k] = (local[1] if links[k].is_revolute else local[0])[2]
            if k == 0:
                continue
            f, moment = transform_force(b, local, pose, f"F{k + 1}p")
            momenta.append(tuple(moment) + tuple(f))
            for i in range(k):
                omega, v = motion[i]
                D[i, k] = D[k, i] = sp.expand((omega.T * moment)[0] + (v.T * f)[0])
        factors = (tuple(tuple(omega) + tuple(v) for omega, v in motion[:-1]), tuple(momenta))
        return D, factors
    to_base: list = []  # per joint, its composite body's unit momentum in the floating base's frame
    for j in range(n):
        force = unit_momentum(composite[j], links[j].is_revolute)
        D[j, j] = (force[1] if links[j].is_revolute else force[0])[2]
        # carried towards the base through each ancestor i of j (joint k is the next one on the
        # way to j); entries of joints on different branches stay exact zeros, never computed
        k = j
        for i in chain.robot.ancestors(j):
            force = transform_force(b, force, chain.motions[k], f"F{j + 1}q{k + 1}")
            force = transform_force(b, force, _between(chain, k), f"F{j + 1}b{k + 1}")
            D[i, j] = D[j, i] = (force[1] if links[i].is_revolute else force[0])[2]
            k = i
        if chain.robot.floating:  # on to the base frame: the base's rows (force, then moment)
            force = transform_force(b, force, chain.motions[k], f"F{j + 1}q{k + 1}")
            force = transform_force(b, force, _between(chain, k), f"F{j + 1}b0")
            to_base.append(force)
    if chain.robot.floating:
        return _with_floating_base(chain, composite, D, to_base), ()
    return D, ()
