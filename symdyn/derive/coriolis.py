"""The Coriolis matrix C(q, qd) by an O(n^2) recursion in one inertial frame.

The Christoffel-consistent Coriolis matrix (the one of Pinocchio's ``computeCoriolisMatrix``;
``dD/dt - 2C`` skew-symmetric, ``C qd = h``) is, with every spatial quantity in one inertial
frame about its origin (Featherstone's ``[omega; v]`` motion and ``[n; f]`` force vectors),

    C = sum_b J_b^T (I_b dJ_b/dt + B_b J_b),   B_b = 1/2 (dI_b/dt + (I_b v_b) x-bar)

(Echeandia and Wensing, "Numerical methods to compute the Coriolis matrix and Christoffel
symbols for rigid-body systems", 2021), where J_b (6 x n) is body b's Jacobian, whose column j
is joint j's motion subspace ``S_j`` for every joint j on the way to b, v_b the body's
velocity, ``dI_b/dt = v_b x* I_b - I_b v_b x`` and ``(f x-bar) u = u x* f``.  ``dI/dt`` is
symmetric and ``f x-bar`` skew, so B's two halves are what ``dD/dt - 2C`` needs to be skew.

The entries are dot products, the same in any inertial frame: the one used is the frame of
joint 1 turned by q_1 at this instant (fixed in space), where joint 1's axis and link 1's pose
are constants and q_1, on which nothing depends, never enters.

In a chain (and in any tree) the bodies seen by both joints i and k are the subtree of the later
one, so with the composite quantities of joint i's subtree (inertia ``Ic_i``, its rate
``dIc_i``, momentum ``hc_i``; sums over the subtree)::

    dS_i = v_i x S_i                                  (rate of joint i's axis, 6)
    F_i  = Ic_i dS_i + 1/2 dIc_i S_i + 1/2 S_i x* hc_i  (6)
    g_i  = Ic_i S_i,  e_i = 1/2 dIc_i S_i - 1/2 S_i x* hc_i   (6 each)

    C[i, k] = S_i . F_k                 for i <= k (joint i on the way to body k)
    C[i, k] = g_i . dS_k + e_i . S_k    for k < i

The composites are sums of 10 (inertia), 9 (its rate: ``dh = m dc``, the rotational part) and 6
(momentum) numbers per body: no 6 x 6 matrix is formed, and the n^2 entries cost 6 or 12
multiplications each.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .chain import Chain
from .poses import tree_poses
from .spatial import cross, cross_force, cross_motion, named_pose, named_symmetric, skew


@dataclass(frozen=True)
class CoriolisFactors:
    """Per joint (in joint order) the 6-vectors (in the recursion's inertial frame, moments about
    its reference point) whose dot products are C's entries:
    ``C[i, k] = S[i] . F[k]`` (i <= k), ``g[i] . dS[k] + e[i] . S[k]`` (k < i); each a tuple of
    n 6 x 1 SymPy matrices in the program's symbols."""

    S: tuple
    dS: tuple
    F: tuple
    g: tuple
    e: tuple

    def as_tuple(self) -> tuple:
        """``(S, dS, F, g, e)``, each a tuple of n tuples of 6 expressions (what
        :attr:`symdyn.derive.equations.Equations.coriolis_factors` holds)."""
        return tuple(tuple(tuple(v) for v in vectors) for vectors in (self.S, self.dS, self.F, self.g, self.e))

    def entry(self, i: int, k: int) -> sp.Expr:
        """C[i, k] (0-based) as a sum of products."""
        if i <= k:
            return _dot(self.S[i], self.F[k])
        return _dot(self.g[i], self.dS[k]) + _dot(self.e[i], self.S[k])


def _dot(a, b) -> sp.Expr:
    return sp.Add(*[x * y for x, y in zip(a, b) if x != 0 and y != 0])


@dataclass
class _Body:
    """One body's inertia in the recursion's frame (mass, first moment h = m c, rotational
    inertia about the reference point, 3 x 3), its rate (dh, dI) and its momentum (6)."""

    mass: sp.Expr
    h: sp.Matrix
    inertia: sp.Matrix
    dh: sp.Matrix
    dinertia: sp.Matrix
    momentum: sp.Matrix

    def __add__(self, other: "_Body") -> "_Body":
        return _Body(self.mass + other.mass, self.h + other.h, self.inertia + other.inertia,
                     self.dh + other.dh, self.dinertia + other.dinertia, self.momentum + other.momentum)

    def times(self, motion: sp.Matrix) -> sp.Matrix:
        """``I m`` for a motion vector ``m = [w; x]``: ``[I_O w + h x x; m x - h x w]``."""
        w, x = motion[:3, 0], motion[3:, 0]
        return sp.Matrix.vstack(self.inertia * w + cross(self.h, x), self.mass * x - cross(self.h, w))

    def rate_times(self, motion: sp.Matrix) -> sp.Matrix:
        """``dI/dt m``: ``[dI_O w + dh x x; -dh x w]`` (the mass does not change)."""
        w, x = motion[:3, 0], motion[3:, 0]
        return sp.Matrix.vstack(self.dinertia * w + cross(self.dh, x), -cross(self.dh, w))


def _frames(chain: Chain) -> list[tuple[list, list, sp.Matrix]]:
    """Per joint: its axis (3), its point (3) and its link's pose (4 x 4, named) in the frame of
    joint 1 turned by q_1, where joint 1's axis and link 1's pose are constants."""
    b = chain.builder
    current = sp.eye(4)
    frames = []
    for i, geometry in enumerate(chain.geometry):
        j = i + 1
        if i == 0:
            joint_frame = sp.eye(4)
        elif sp.Matrix(geometry.pre) != sp.eye(4):
            joint_frame = named_pose(b, f"cP{j}", current * sp.Matrix(geometry.pre))
        else:
            joint_frame = current
        moved = named_pose(b, f"cM{j}", joint_frame * (chain.motions[i] if i else sp.eye(4)))
        current = named_pose(b, f"cA0{j}", moved * sp.Matrix(geometry.post))
        frames.append(([sp.expand(e) for e in joint_frame[:3, 2]], [sp.expand(e) for e in joint_frame[:3, 3]], current))
    return frames


def coriolis_factors(chain: Chain) -> CoriolisFactors:
    """The vectors of the recursion (see the module docstring), named in ``chain``'s program.

    Positions are taken from the last joint's point (the reference point of every moment): a
    small distal body's rows of C are then not the difference of large moments about a far
    origin (in float, the Puma's wrist rows lost 3 digits that way).  Each product is staged
    so that it costs what its structure allows: the link pose as (joint frame) x (joint motion)
    x (constant rest), a link's rotated inertia as ``R (I R^T)``, and the halves of ``B_i S_i``
    from ``S_i / 2``, shared by F and e."""
    b, robot = chain.builder, chain.robot
    n = chain.n
    frames = _frames(chain)
    reference = sp.Matrix(frames[-1][1])
    velocity = sp.zeros(6, 1)
    S, dS, bodies = [], [], []
    for i, (link, (axis, point, pose)) in enumerate(zip(robot.links, frames)):
        j = i + 1
        if link.is_revolute:
            lever = b.vector(f"cp{j}", (sp.Matrix(point) - reference).applyfunc(sp.expand))
            subspace = axis + list(cross(lever, axis))
        else:
            subspace = [0, 0, 0] + axis
        S.append(b.vector(f"cS{j}", [sp.expand(e) for e in subspace]))
        velocity = b.vector(f"cv{j}", velocity + S[i] * chain.qd[i])
        dS.append(b.vector(f"cdS{j}", cross_motion(velocity, S[i]).applyfunc(sp.expand)))
        origin = b.vector(f"co{j}", (pose[:3, 3] - reference).applyfunc(sp.expand))
        bodies.append((link, pose[:3, :3], origin, velocity))
    F, g, e = [None] * n, [None] * n, [None] * n
    composite = None
    for i in reversed(range(n)):
        j = i + 1
        # each body's quantities are made where they are summed (the tip first): few values
        # stay live from the forward pass to the backward one, which keeps the compiler's
        # register allocation fast on long chains
        body = _body(b, j, *bodies[i])
        composite = body if composite is None else _named_body(b, f"cC{j}", body + composite)
        F[i], g[i], e[i] = _joint_factors(b, S[i], dS[i], composite, str(j))
    return CoriolisFactors(tuple(S), tuple(dS), tuple(F), tuple(g), tuple(e))


def _joint_factors(b, S: sp.Matrix, dS: sp.Matrix, composite: "_Body", hint: str):
    """``(F, g, e)`` of one joint (see the module docstring) from its axis ``S``, the axis's rate
    ``dS`` and the composite of the bodies it moves; named ``cF{hint}``, ``cg{hint}``,
    ``ce{hint}`` (the halves of ``B S``, from ``S / 2``, shared by F and e)."""
    half = b.vector(f"cSh{hint}", (S / 2).applyfunc(sp.expand))
    half_rate = b.vector(f"cBr{hint}", composite.rate_times(half).applyfunc(sp.expand))
    half_cross = b.vector(f"cBx{hint}", cross_force(half, composite.momentum).applyfunc(sp.expand))
    return (b.vector(f"cF{hint}", (composite.times(dS) + half_rate + half_cross).applyfunc(sp.expand)),
            b.vector(f"cg{hint}", composite.times(S).applyfunc(sp.expand)),
            b.vector(f"ce{hint}", (half_rate - half_cross).applyfunc(sp.expand)))


def _body(b, j: int, link, R: sp.Matrix, origin: sp.Matrix, velocity: sp.Matrix) -> _Body:
    """Link j's inertia, inertia rate and momentum about the reference point (``R``, ``origin``:
    the link frame's axes and origin, named; ``velocity``: its spatial velocity)."""
    mass = sp.sympify(link.mass)
    com = b.vector(f"cc{j}", (origin + R * sp.Matrix(link.com)).applyfunc(sp.expand))
    half = b.matrix(f"cIh{j}", (sp.Matrix(link.inertia_matrix) * R.T).applyfunc(sp.expand))
    rotated = named_symmetric(b, f"cIr{j}", R * half)
    cx = skew(com)
    h = b.vector(f"ch{j}", mass * com)
    hx = skew(h)  # products with h = m c cost one multiplication where m c c costs two
    inertia = named_symmetric(b, f"cIo{j}", rotated - hx * cx)
    w, x = velocity[:3, 0], velocity[3:, 0]
    com_velocity = b.vector(f"ccd{j}", (x + cross(w, com)).applyfunc(sp.expand))
    dh = b.vector(f"cdh{j}", mass * com_velocity)
    wx, cdx = skew(w), skew(com_velocity)
    spin = b.matrix(f"cW{j}", (wx * rotated).applyfunc(sp.expand))  # R_dot I R^T: the rate is spin + spin^T
    dinertia = named_symmetric(b, f"cdI{j}", spin + spin.T - (cdx * hx + hx * cdx))
    # momentum I v = [I_r w + c x m c_dot; m c_dot]: the linear part is dh itself
    angular = b.vector(f"cm{j}", (rotated * w + cross(com, dh)).applyfunc(sp.expand))
    return _Body(mass, h, inertia, dh, dinertia, sp.Matrix.vstack(angular, dh))


def _named_body(b, hint: str, body: _Body) -> _Body:
    return _Body(b.define(f"{hint}m", sp.expand(body.mass)), b.vector(f"{hint}h", body.h.applyfunc(sp.expand)),
                 named_symmetric(b, f"{hint}I", body.inertia), b.vector(f"{hint}dh", body.dh.applyfunc(sp.expand)),
                 named_symmetric(b, f"{hint}dI", body.dinertia),
                 b.vector(f"{hint}p", body.momentum.applyfunc(sp.expand)))


def coriolis_matrix(chain: Chain) -> tuple[sp.Matrix, CoriolisFactors]:
    """C (n x n, each entry named ``C{i}_{k}``) and the factors it is made of."""
    factors = coriolis_factors(chain)
    n = chain.n
    b = chain.builder
    # each entry is a sum of products of named factor entries: already expanded (no sp.expand,
    # which took 5 s of a 64-joint chain's derivation to return it unchanged)
    C = sp.Matrix(n, n, lambda i, k: b.define(f"C{i + 1}_{k + 1}", factors.entry(i, k)))
    return C, factors


def tree_coriolis_matrix(chain: Chain) -> sp.Matrix:
    """C (nv x nv) of a kinematic tree or a floating base by the same sums as
    :func:`coriolis_factors`, in the base frame at this instant (an inertial frame; moments about
    the base origin): the bodies joints i and k both move are the subtree of the later one, so
    ``C[i, k] = S_i . F_k`` when i is k or on the way to it, ``g_i . dS_k + e_i . S_k`` when k is
    on the way to i, and 0 for joints on different branches (not computed).  A floating base is
    a 6-column joint under every other one, its columns ``[0; e_a]`` (linear velocity) and
    ``[e_a; 0]`` (angular), fixed in the base body (``dS = v_base x S``); within its block every
    entry is ``S_a . F_b`` (one body, one composite)."""
    b, robot = chain.builder, chain.robot
    n, parents = chain.n, chain.parents
    base = 6 if robot.floating else 0
    velocities = []
    S, dS = [], []
    base_velocity = sp.zeros(6, 1)
    if robot.floating:
        for a in range(6):  # Pinocchio's free-flyer: linear velocity first, then angular
            column = sp.zeros(6, 1)
            column[3 + a if a < 3 else a - 3] = 1
            S.append(column)
        base_velocity = b.vector("cv0", sum((S[a] * chain.qd[a] for a in range(6)), sp.zeros(6, 1)))
        dS = [b.vector(f"cdS0_{a + 1}", cross_motion(base_velocity, S[a]).applyfunc(sp.expand)) for a in range(6)]
    # each joint frame (its motion about or along its own z leaves the axis and, for a
    # revolute joint, its point as they were) and link frame in the base frame
    joints, poses = tree_poses(chain, ("cP", "cM", "cA0"))
    for i in range(n):
        j = i + 1
        axis, point = sp.Matrix(joints[i][:3, 2]).applyfunc(sp.expand), sp.Matrix(joints[i][:3, 3])
        if robot.links[i].is_revolute:
            subspace = list(axis) + list(cross(point, axis))
        else:
            subspace = [0, 0, 0] + list(axis)
        S.append(b.vector(f"cS{j}", [sp.expand(e) for e in subspace]))
        above = base_velocity if parents[i] < 0 else velocities[parents[i]]
        velocities.append(b.vector(f"cv{j}", above + S[base + i] * chain.qd[base + i]))
        dS.append(b.vector(f"cdS{j}", cross_motion(velocities[i], S[base + i]).applyfunc(sp.expand)))
    composite: list = [None] * n
    F, g, e = [None] * (base + n), [None] * (base + n), [None] * (base + n)

    for i in reversed(range(n)):
        j = i + 1
        body = _body(b, j, robot.links[i], poses[i][:3, :3], poses[i][:3, 3], velocities[i])
        for c in chain.children(i):
            body = body + composite[c]
        composite[i] = _named_body(b, f"cC{j}", body) if chain.children(i) else body
        F[base + i], g[base + i], e[base + i] = _joint_factors(b, S[base + i], dS[base + i], composite[i], str(j))
    if robot.floating:
        body = _body(b, 0, robot.base_inertia, sp.eye(3), sp.zeros(3, 1), base_velocity)
        for c in chain.children(-1):
            body = body + composite[c]
        whole = _named_body(b, "cC0", body)
        for a in range(6):
            F[a], g[a], e[a] = _joint_factors(b, S[a], dS[a], whole, f"0_{a + 1}")
    ancestors = [set() for _ in range(base + n)]
    for i in range(n):
        ancestors[base + i] = {base + p for p in chain.robot.ancestors(i)} | set(range(base))
    C = sp.zeros(base + n, base + n)
    for i in range(base + n):
        for k in range(base + n):
            if i == k or i in ancestors[k] or (i < base and k < base):
                entry = _dot(S[i], F[k])
            elif k in ancestors[i]:
                entry = _dot(g[i], dS[k]) + _dot(e[i], S[k])
            else:
                continue  # joints on different branches: exactly zero
            C[i, k] = b.define(f"C{i + 1}_{k + 1}", sp.expand(entry))
    return C
