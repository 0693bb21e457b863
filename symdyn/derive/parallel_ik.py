"""Closed-form inverse kinematics of a platform robot's leg (the parallel-manipulator notes' legs: S-X-U).

A leg whose first three joints are revolute with axes meeting at one point (a spherical pair S
at the base), whose fourth joint is revolute or prismatic (X, the actuated one in the parallel-manipulator notes), and
whose last two joints are revolute with axes meeting at one point (a universal joint U at the
platform) has its joint values in closed form from the pose of its frame 6 (fixed to the
platform), in the manner of a wrist-partitioned arm:

1. the U centre is a point of frame 6; its distance from the S centre depends on joint 4 only:
   a quadratic (prismatic) or ``A cos + B sin = K`` (revolute), two branches;
2. the direction of the leg, seen from frame 4 and from frame 6, fixes the universal joint's two
   angles (Paden-Kahan subproblem 2: two rotations about intersecting axes taking one vector to
   another), two branches;
3. the spherical pair's rotation is then known, and its three angles follow (subproblem 2 for
   the first two, the third read off the remaining rotation), two branches.

Every step uses only arithmetic and square roots, so the same code runs on numbers (numpy, to
check it) and on SymPy expressions (to derive the generated code): joint angles come out as
``(cos, sin)`` pairs of ``theta_i + q_i`` (what the recursions use), the prismatic joint as its
value.  ``branches`` picks the sign of each square root: (joint 4, universal, spherical), +1 or
-1; :meth:`LegIK.branches_of` finds those of a known configuration.

Frames follow :mod:`symdyn.model.geometry`: link i's transform is ``pre_i * motion_i * post_i``,
the motion a rotation about, or a translation along, the z axis of ``frame_{i-1} * pre_i``.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import sympy as sp

from ..model.geometry import JointGeometry, joint_geometry, numeric_pose
from ..model.robot import Robot
from .spatial import cross3, dot3


class LegStructureError(ValueError):
    """The leg is not of the S-X-U kind this closed form solves."""


def leg_error(err: LegStructureError, leg) -> str:
    """The message of ``err`` without the leg chain's own name in front (callers name the leg)."""
    text = str(err)
    prefix = f"{leg.chain.name}: "
    return text[len(prefix):] if text.startswith(prefix) else text


def _add(a, b):
    return [x + y for x, y in zip(a, b)]


def _sub(a, b):
    return [x - y for x, y in zip(a, b)]


def _scale(k, a):
    return [k * x for x in a]


def _matvec(R, v):
    return [R[r][0] * v[0] + R[r][1] * v[1] + R[r][2] * v[2] for r in range(3)]


def _transpose(R):
    return [[R[c][r] for c in range(3)] for r in range(3)]


def _matmul(A, B):
    return [[sum(A[r][k] * B[k][c] for k in range(3)) for c in range(3)] for r in range(3)]


def _rz(c, s):
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def _keep(hint, value):
    return value


def _ignore(kind, value, scale=None):
    return None


def _rotation_to(omega, p, q, name=_keep, check=_ignore):
    """``(cos, sin)`` of the rotation about the unit axis ``omega`` taking p to q (Paden-Kahan
    subproblem 1; p and q have the same component along omega and the same length)."""
    pp = [name("pp", x) for x in _sub(p, _scale(dot3(omega, p), omega))]
    qq = _sub(q, _scale(dot3(omega, q), omega))
    n2 = name("den", dot3(pp, pp))
    check("den", n2, dot3(p, p))  # p along the axis: the angle is not defined (a singular configuration)
    inverse = name("inv", 1 / n2)
    return name("c", dot3(pp, qq) * inverse), name("s", dot3(omega, cross3(pp, qq)) * inverse)


def _two_rotations(omega1, omega2, p, q, sign, sqrt, name=_keep, check=_ignore):
    """``((cos1, sin1), (cos2, sin2))`` with ``Rot(omega1, t1) Rot(omega2, t2) p = q`` (Paden-Kahan
    subproblem 2; unit axes through the origin, not parallel); ``sign`` picks the solution."""
    w12 = dot3(omega1, omega2)
    denom = w12 * w12 - 1
    alpha = (w12 * dot3(omega2, p) - dot3(omega1, q)) / denom
    beta = (w12 * dot3(omega1, q) - dot3(omega2, p)) / denom
    normal = cross3(omega1, omega2)
    alpha, beta = name("alpha", alpha), name("beta", beta)
    gamma2 = name("rad", (dot3(p, p) - alpha * alpha - beta * beta - 2 * alpha * beta * w12) / dot3(normal, normal))
    check("rad", gamma2)
    z = [name("z", x) for x in _add(_add(_scale(alpha, omega1), _scale(beta, omega2)),
                                     _scale(sign * name("root", sqrt(gamma2)), normal))]
    return _rotation_to(omega1, z, q, name, check), _rotation_to(omega2, p, z, name, check)


def _rot(m):
    return [[m[r, c] for c in range(3)] for r in range(3)]


def _vec(m):
    return [m[r, 3] for r in range(3)]


def _meet(p1, d1, p2, d2, what: str):
    """The point where two lines (point, direction; exact) meet, else LegStructureError."""
    n = cross3(d1, d2)
    nn = sp.nsimplify(dot3(n, n))
    if nn == 0:
        raise LegStructureError(f"{what}: parallel axes")
    gap = _sub(p2, p1)
    if abs(float(dot3(gap, n))) > 1e-9 * max(1.0, float(sp.sqrt(nn))):
        raise LegStructureError(f"{what}: the axes do not meet")
    t = dot3(cross3(gap, d2), n) / nn
    return [sp.nsimplify(x) if x.is_number else x for x in _add(p1, _scale(t, d1))]


@dataclass(frozen=True)
class LegIK:
    """The constant geometry of an S-X-U leg (exact, from its table) and its closed form.

    ``centre_s``: the S centre in frame 0; ``s_in_3``: the same point in frame 3; ``u_in_4`` and
    ``u_in_6``: the U centre in frames 4 and 6; ``geometry``: the six links' pre/post parts.
    """

    leg: Robot
    centre_s: tuple
    s_in_3: tuple
    u_in_4: tuple
    u_in_6: tuple
    geometry: tuple

    @classmethod
    def of(cls, leg: Robot) -> "LegIK":
        """Check the structure (three revolute joints meeting at a point, any fourth joint, two
        revolute joints meeting at a point) and precompute the constants."""
        if len(leg.links) != 6:
            raise LegStructureError(f"{leg.name}: {len(leg.links)} joints, not 6")
        kinds = [link.is_revolute for link in leg.links]
        if not (kinds[0] and kinds[1] and kinds[2] and kinds[4] and kinds[5]):
            raise LegStructureError(f"{leg.name}: joints 1-3 and 5-6 must be revolute (a spherical pair and "
                                    "a universal joint)")
        geometry = tuple(joint_geometry(link, leg.convention) for link in leg.links)
        zero = [sp.Matrix(g.pre) * sp.Matrix(g.post) for g in geometry]  # each link at q = 0 (no theta)
        frames = [sp.eye(4)]
        for k in range(6):
            frames.append(frames[-1] * zero[k])
        axes = [frames[k] * sp.Matrix(geometry[k].pre) for k in range(6)]  # joint frames at q = 0
        point = [_vec(a) for a in axes]
        direction = [[a[r, 2] for r in range(3)] for a in axes]
        s = _meet(point[0], direction[0], point[1], direction[1], f"{leg.name}: joints 1 and 2")
        s2 = _meet(point[1], direction[1], point[2], direction[2], f"{leg.name}: joints 2 and 3")
        if any(abs(float(a - b)) > 1e-9 for a, b in zip(s, s2)):
            raise LegStructureError(f"{leg.name}: the axes of joints 1-3 do not meet at one point")
        u = _meet(point[4], direction[4], point[5], direction[5], f"{leg.name}: joints 5 and 6")

        def local(frame, p):
            inv = frame.inv()
            return tuple(sp.nsimplify(sp.expand(x)) if sp.sympify(x).is_number else sp.expand(x)
                         for x in _vec(inv * sp.Matrix([[1, 0, 0, p[0]], [0, 1, 0, p[1]], [0, 0, 1, p[2]], [0, 0, 0, 1]])))
        return cls(leg, tuple(s), local(frames[3], s), local(frames[4], u), local(frames[6], u), geometry)

    def with_floats(self) -> "LegIK":
        """The same leg with its constants as floats (numpy arrays): :meth:`solve` on numbers."""
        import numpy as np
        geometry = tuple(JointGeometry(np.array(g.pre, dtype=float), np.array(g.post, dtype=float), g.revolute)
                         for g in self.geometry)
        return replace(self, centre_s=tuple(float(x) for x in self.centre_s),
                       s_in_3=tuple(float(x) for x in self.s_in_3), u_in_4=tuple(float(x) for x in self.u_in_4),
                       u_in_6=tuple(float(x) for x in self.u_in_6), geometry=geometry)

    def branches_of(self, joints) -> tuple[int, int, int]:
        """The branches ``(joint 4, universal, spherical)`` that give back the configuration
        ``joints`` (six joint variables q, as in the robot file: revolute offsets theta are added)
        from its own frame-6 pose.  Raises LegStructureError when none does (a singular one)."""
        import itertools

        import numpy as np
        numeric = self.with_floats()
        pose = numeric_pose(self.leg, joints)
        values = [(np.cos(float(link.theta + q)), np.sin(float(link.theta + q))) if link.is_revolute else float(q)
                  for link, q in zip(self.leg.links, joints)]
        for branches in itertools.product((1, -1), repeat=3):
            with np.errstate(invalid="ignore", divide="ignore"):
                found = numeric.solve(pose[:3, :3].tolist(), pose[:3, 3].tolist(), branches, np.sqrt)
            if all(np.allclose(np.array(a, dtype=float), np.array(b, dtype=float), atol=1e-9)
                   for a, b in zip(found, values)):
                return branches
        raise LegStructureError(f"{self.leg.name}: no branch of the closed form gives back the configuration "
                                f"{list(joints)} (a singular configuration?)")

    def solve(self, rotation, position, branches=(1, 1, 1), sqrt=sp.sqrt, name=_keep, check=_ignore):
        """Joint values for frame 6 at ``rotation`` (3x3 nested lists) and ``position`` (3) in
        frame 0: six entries, ``(cos, sin)`` of ``theta_i + q_i`` for a revolute joint and the value
        of a prismatic one (numbers or expressions, as the inputs are).

        ``name(hint, value) -> value`` sees each intermediate quantity as it is computed (default:
        returned as is): a derivation names them (intermediate symbols).  ``check(kind, value,
        scale)`` sees each radicand (kind ``"rad"``: negative when the pose is out of reach) and
        each denominator (``"den"``: a sum of squares, zero at a singular configuration, where
        the angle it gives is not defined; ``scale`` is the square of the length it is relative to)
        before it is used."""
        g = self.geometry
        R06, p06 = rotation, position
        u = _add(p06, _matvec(R06, list(self.u_in_6)))
        u = [name("u", x) for x in u]
        e = [name("e", x) for x in _sub(u, list(self.centre_s))]
        e2 = name("e2", dot3(e, e))
        c4_local = list(self.u_in_4)
        pre4, post4 = g[3].pre, g[3].post
        w = _add(_matvec(_rot(post4), c4_local), _vec(post4))  # U centre in joint 4's moved frame
        s3 = list(self.s_in_3)
        if g[3].revolute:
            gap = _matvec(_transpose(_rot(pre4)), _sub(_vec(pre4), s3))
            A = gap[0] * w[0] + gap[1] * w[1]
            B = gap[1] * w[0] - gap[0] * w[1]
            K = (e2 - dot3(w, w) - dot3(gap, gap)) / 2 - gap[2] * w[2]
            A, B, K = name("A", A), name("B", B), name("K", K)
            r2 = name("den", A * A + B * B)
            check("den", r2, (gap[0] * gap[0] + gap[1] * gap[1]) * (w[0] * w[0] + w[1] * w[1]))
            radicand = name("rad", r2 - K * K)
            check("rad", radicand)
            root = branches[0] * name("root", sqrt(radicand))
            inverse = name("inv", 1 / r2)
            joint4 = (name("c", (A * K - B * root) * inverse), name("s", (B * K + A * root) * inverse))
            motion4 = _rz(*joint4)
            moved = _matvec(motion4, w)
        else:
            a = _sub(_add(_matvec(_rot(pre4), w), _vec(pre4)), s3)
            b = [pre4[r, 2] for r in range(3)]
            ab = name("ab", dot3(a, b))
            radicand = name("rad", ab * ab - dot3(a, a) + e2)
            check("rad", radicand)
            joint4 = name("d", -ab + branches[0] * sqrt(radicand))
            motion4 = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
            moved = _add(w, [0, 0, joint4])
        d = [name("leg", x) for x in _sub(_add(_matvec(_rot(pre4), moved), _vec(pre4)), s3)]  # in frame 3
        R34 = [[name("R34", x) for x in row] for row in _matmul(_matmul(_rot(pre4), motion4), _rot(post4))]
        # universal joint: R46 y = x, R46 = A5 Rz(q5) B56 Rz(q6) C6
        x = [name("x", v) for v in _matvec(_transpose(R34), d)]
        y = [name("y", v) for v in _matvec(_transpose(R06), e)]
        A5, B56, C6 = _rot(g[4].pre), _matmul(_rot(g[4].post), _rot(g[5].pre)), _rot(g[5].post)
        p_vec = _matvec(B56, _matvec(C6, y))
        q_vec = _matvec(_transpose(A5), x)
        omega2 = [B56[r][2] for r in range(3)]
        joint5, joint6 = _two_rotations([0, 0, 1], omega2, p_vec, q_vec, branches[1], sqrt, name, check)
        R46 = [[name("R46", v) for v in row]
               for row in _matmul(_matmul(_matmul(_matmul(A5, _rz(*joint5)), B56), _rz(*joint6)), C6)]
        R03 = [[name("R03", v) for v in row] for row in _matmul(_matmul(R06, _transpose(R46)), _transpose(R34))]
        # spherical pair: R03 = A1 Rz(q1) B12 Rz(q2) B23 Rz(q3) C3
        A1, B12 = _rot(g[0].pre), _matmul(_rot(g[0].post), _rot(g[1].pre))
        B23, C3 = _matmul(_rot(g[1].post), _rot(g[2].pre)), _rot(g[2].post)
        G = [[name("G", v) for v in row] for row in _matmul(_matmul(_transpose(A1), R03), _transpose(C3))]
        axis2 = [B12[r][2] for r in range(3)]
        start = _matvec(B12, [B23[r][2] for r in range(3)])
        goal = [G[r][2] for r in range(3)]
        joint1, joint2 = _two_rotations([0, 0, 1], axis2, start, goal, branches[2], sqrt, name, check)
        rest = _matmul(_matmul(_matmul(_matmul(_transpose(B23), _transpose(_rz(*joint2))), _transpose(B12)),
                               _transpose(_rz(*joint1))), G)
        joint3 = (name("c", rest[0][0]), name("s", rest[1][0]))
        return [joint1, joint2, joint3, joint4, joint5, joint6]
