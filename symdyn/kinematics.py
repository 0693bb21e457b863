"""Symbolic kinematics of a DH chain: link transforms, base-to-link transforms, Jacobians.

Both conventions are written as ``T_i = Pre_i * Joint_i(q_i) * Post_i`` with constant
``Pre``/``Post`` and ``Joint`` a rotation about z (revolute) or a translation along z (prismatic):

- standard:  ``A_i = Rz(theta_i + q_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``
  -> ``Pre = I``, ``Post = Rz(theta) Tz(d) Tx(a) Rx(alpha)`` (joint i moves about z_{i-1});
- modified:  ``T_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i + q_i) Tz(d_i)``
  -> ``Pre = Rx(alpha) Tx(a) Rz(theta) Tz(d)``, ``Post = I`` (joint i moves about z_i).

(Rz and Tz commute with each other, which is why the joint's offset can move into Pre/Post.)
All matrices are 4x4 homogeneous transforms, lengths in m, angles in rad.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .robot import Link, Robot


def joint_symbols(n: int) -> tuple[tuple[sp.Symbol, ...], ...]:
    """Real symbols (q, qd, qdd, tau), each a tuple q1..qn (rad or m, per s, per s^2, N m or N)."""
    make = lambda base: tuple(sp.Symbol(f"{base}{k + 1}", real=True) for k in range(n))
    return make("q"), make("qd"), make("qdd"), make("tau")


def rot_x(angle) -> sp.Matrix:
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.Matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def rot_z_cs(c, s) -> sp.Matrix:
    return sp.Matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def rot_z(angle) -> sp.Matrix:
    return rot_z_cs(sp.cos(angle), sp.sin(angle))


def trans(x=0, y=0, z=0) -> sp.Matrix:
    return sp.Matrix([[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]])


@dataclass(frozen=True)
class JointGeometry:
    """Constant parts of ``T_i = pre * joint(q_i) * post`` for one link."""

    pre: sp.ImmutableMatrix
    post: sp.ImmutableMatrix
    revolute: bool


def joint_geometry(link: Link, convention: str) -> JointGeometry:
    """Split a link's DH transform into constant ``pre``/``post`` around the joint motion.

    For a revolute joint the constant offset theta goes with the joint's rotation only through
    ``sin/cos(theta + q)`` (see :func:`link_transform`), so it is left out of pre/post here.
    """
    if convention == "standard":
        pre = sp.eye(4)
        post = trans(z=link.d) * trans(x=link.a) * rot_x(link.alpha)
        if not link.is_revolute:
            post = rot_z(link.theta) * post
    else:
        pre = rot_x(link.alpha) * trans(x=link.a)
        if not link.is_revolute:
            pre = pre * rot_z(link.theta)
        pre = pre * trans(z=link.d)
        post = sp.eye(4)
    if link.fixed is not None:  # a constant transform before the DH transform (locked joints)
        pre = sp.Matrix(4, 4, list(link.fixed)) * pre
    return JointGeometry(sp.ImmutableMatrix(pre), sp.ImmutableMatrix(post), link.is_revolute)


def joint_motion(link: Link, q: sp.Expr, cos_sin: tuple[sp.Expr, sp.Expr] | None = None) -> sp.Matrix:
    """The moving part of a link transform.

    Revolute: ``Rz(theta + q)`` (``cos_sin`` may give symbols standing for cos/sin(theta + q)).
    Prismatic: ``Tz(q)``.
    """
    if link.is_revolute:
        c, s = cos_sin if cos_sin is not None else (sp.cos(link.theta + q), sp.sin(link.theta + q))
        return rot_z_cs(c, s)
    return trans(z=q)


def link_transform(robot: Robot, i: int, q: sp.Expr, cos_sin=None) -> sp.Matrix:
    """``^{i-1}A_i`` (standard) or ``^{i-1}T_i`` (modified) of link ``i`` (0-based), 4x4."""
    link = robot.links[i]
    geo = joint_geometry(link, robot.convention)
    return sp.Matrix(geo.pre) * joint_motion(link, q, cos_sin) * sp.Matrix(geo.post)


def base_transforms(robot: Robot, q=None, simplify: bool = False) -> list[sp.Matrix]:
    """``^0A_i`` for i = 1..n: pose of each link frame in the base frame (4x4 each)."""
    if q is None:
        q = joint_symbols(robot.dof)[0]
    out, current = [], sp.eye(4)
    for i in range(robot.dof):
        current = current * link_transform(robot, i, q[i])
        if simplify:
            current = sp.simplify(current)
        out.append(current)
    return out


def link_jacobians(robot: Robot, q=None) -> list[sp.Matrix]:
    """Geometric Jacobian (6 x n, rows: linear then angular velocity, base-frame coordinates)
    of the origin of each link frame i, for i = 1..n. Column j is zero for joints beyond i."""
    n = robot.dof
    if q is None:
        q = joint_symbols(n)[0]
    frames = base_transforms(robot, q)
    axes, points = [], []
    previous = sp.eye(4)
    for j, link in enumerate(robot.links):
        geo = joint_geometry(link, robot.convention)
        joint_frame = previous * sp.Matrix(geo.pre)
        if link.is_revolute:
            joint_frame = joint_frame * rot_z(link.theta + q[j])
        axes.append(joint_frame[:3, 2])
        points.append(joint_frame[:3, 3])
        previous = frames[j]
    jacobians = []
    for i in range(n):
        origin = frames[i][:3, 3]
        jac = sp.zeros(6, n)
        for j in range(i + 1):
            if robot.links[j].is_revolute:
                jac[:3, j] = axes[j].cross(origin - points[j])
                jac[3:, j] = axes[j]
            else:
                jac[:3, j] = axes[j]
        jacobians.append(jac)
    return jacobians
