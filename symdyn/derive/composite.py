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


def _symmetric(b: ProgramBuilder, hint: str, mat: sp.Matrix) -> sp.Matrix:
    out = sp.zeros(3, 3)
    for r in range(3):
        for c in range(r, 3):
            out[r, c] = out[c, r] = b.define(f"{hint}_{r}{c}", sp.expand(mat[r, c]))
    return out


def transform_inertia(b: ProgramBuilder, body: BodyInertia, pose: sp.Matrix, hint: str) -> BodyInertia:
    """The inertia of ``body`` (given in frame B) expressed in frame A, where ``pose`` (4x4) is
    the pose of B in A."""
    R, p = pose[:3, :3], pose[:3, 3]
    m = body.mass
    h_rot = b.vector(f"{hint}h", (R * body.first_moment).applyfunc(sp.expand))
    if R == sp.eye(3):
        J_rot = body.rotational
    else:
        half = sp.Matrix(3, 3, lambda r, c: b.define(f"{hint}A_{r}{c}", sp.expand((R[r, :] * body.rotational[:, c])[0])))
        J_rot = _symmetric(b, f"{hint}R", half * R.T)
    if p.is_zero_matrix:
        return BodyInertia(m, h_rot, J_rot)
    J = _symmetric(b, f"{hint}J", J_rot + _cross_matrix_terms(p, h_rot, m))
    h = b.vector(f"{hint}m", (h_rot + m * p).applyfunc(sp.expand))
    return BodyInertia(m, h, J)


def add_inertia(b: ProgramBuilder, a: BodyInertia, c: BodyInertia, hint: str) -> BodyInertia:
    return BodyInertia(sp.expand(a.mass + c.mass),
                       b.vector(f"{hint}h", (a.first_moment + c.first_moment).applyfunc(sp.expand)),
                       _symmetric(b, f"{hint}J", a.rotational + c.rotational))


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


def _link_inertia(chain: Chain, i: int) -> BodyInertia:
    """Link i's inertia about the origin of its joint frame (constant)."""
    link = chain.robot.links[i]
    m = link.mass
    s = sp.Matrix(link.com)
    J = sp.Matrix(link.inertia_matrix) + m * ((s.T * s)[0] * sp.eye(3) - s * s.T)
    # m s and the inertia about the origin are polynomial in the parameters even when the COM
    # is not (a merged runtime payload has c = (m1 c1 + m2 c2) / (m1 + m2)): cancel the division
    body = BodyInertia(m, (m * s).applyfunc(_cancel), J.applyfunc(_cancel))
    post = sp.Matrix(chain.geometry[i].post)
    R, p = post[:3, :3], post[:3, 3]
    h = R * body.first_moment
    J = R * body.rotational * R.T + _cross_matrix_terms(p, h, m)
    return BodyInertia(m, (h + m * p).applyfunc(sp.expand), J.applyfunc(sp.expand))


def mass_matrix(chain: Chain) -> sp.Matrix:
    """D(q) (n x n, kg m^2 / kg m / kg by joint types) by the composite-rigid-body method."""
    b = chain.builder
    n = chain.n
    links = chain.robot.links
    # constant pose of J_{j+1}'s pre-motion frame in J_j: Post_j Pre_{j+1}
    between = [sp.Matrix(chain.geometry[j].post) * sp.Matrix(chain.geometry[j + 1].pre) for j in range(n - 1)]
    joint_pose = chain.motions
    composite: list[BodyInertia | None] = [None] * n
    for j in reversed(range(n)):
        own = _link_inertia(chain, j)
        if j == n - 1:
            composite[j] = BodyInertia(own.mass, b.vector(f"Ic{j + 1}h", own.first_moment),
                                       _symmetric(b, f"Ic{j + 1}J", own.rotational))
            continue
        child = transform_inertia(b, composite[j + 1], joint_pose[j + 1], f"Iq{j + 2}")
        child = transform_inertia(b, child, between[j], f"Ib{j + 2}")
        composite[j] = add_inertia(b, own, child, f"Ic{j + 1}")

    D = sp.zeros(n, n)
    ez = sp.Matrix([0, 0, 1])
    for j in range(n):
        body = composite[j]
        if links[j].is_revolute:
            force = (-body.first_moment.cross(ez), body.rotational * ez)
        else:
            force = (body.mass * ez, body.first_moment.cross(ez))
        D[j, j] = (force[1] if links[j].is_revolute else force[0])[2]
        for i in reversed(range(j)):
            k = i + 1
            force = transform_force(b, force, joint_pose[k], f"F{j + 1}q{k + 1}")
            force = transform_force(b, force, between[i], f"F{j + 1}b{k + 1}")
            D[i, j] = D[j, i] = (force[1] if links[i].is_revolute else force[0])[2]
    return D
