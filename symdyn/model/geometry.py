"""Geometry of a link as the robot file describes it: the constant parts of each link transform
around the joint's motion, ``T_i = Pre_i * Joint_i(q_i) * Post_i``.

- standard:  ``A_i = Rz(theta_i + q_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``
  -> ``Pre = I``, ``Post = Rz(theta) Tz(d) Tx(a) Rx(alpha)`` (joint i moves about z_{i-1});
- modified:  ``T_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i + q_i) Tz(d_i)``
  -> ``Pre = Rx(alpha) Tx(a) Rz(theta) Tz(d)``, ``Post = I`` (joint i moves about z_i);
- general (``origin`` O and unit ``axis`` a, as URDF): ``T_i = O_i Rot(a_i, q_i)`` (revolute) or
  ``O_i Trans(a_i q_i)`` (prismatic) -> ``Pre = O R_a``, ``Post = R_a^T`` with R_a a constant
  rotation taking z to a (the identity for a = z, a signed permutation for +-x, +-y, -z), so the
  joint again moves about (or along) z between Pre and Post, and zeros fold as in the DH case.

(Rz and Tz commute with each other, which is why the joint's offset can move into Pre/Post.)
All matrices are 4x4 homogeneous SymPy transforms, lengths in m, angles in rad.  This is part of
the description (scenes use it to merge locked links); the derivations build on it in
:mod:`symdyn.derive.kinematics`.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .robot import Link


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


def axis_rotation(axis) -> sp.Matrix:
    """A constant 4x4 rotation taking z to the unit vector ``axis`` (exact): the identity for
    +z, ``Rx(pi)`` for -z, else the rotation about ``z x axis`` (Rodrigues' formula)."""
    x, y, z = (sp.sympify(v) for v in axis)
    out = sp.eye(4)
    if x == 0 and y == 0:
        if z.is_number and z < 0:
            out[1, 1] = out[2, 2] = -1
        return out
    k = 1 / (1 + z)
    out[:3, :3] = sp.Matrix([[sp.radsimp(1 - x * x * k), sp.radsimp(-x * y * k), x],
                             [sp.radsimp(-x * y * k), sp.radsimp(1 - y * y * k), y],
                             [-x, -y, z]])
    return out


def joint_geometry(link: Link, convention: str) -> JointGeometry:
    """Split a link's DH transform into constant ``pre``/``post`` around the joint motion.

    For a revolute joint the constant offset theta goes with the joint's rotation only through
    ``sin/cos(theta + q)`` (see :func:`link_transform`), so it is left out of pre/post here.
    """
    if convention == "general":
        turn = axis_rotation(link.axis)
        pre = sp.Matrix(link.origin.matrix()) * turn
        post = turn.T
    elif convention == "standard":
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


def numeric_pose(robot, values):
    """The pose (4x4 numpy array) of the robot's last link frame in its frame 0 (its ``base``
    placement not included) at joint variables ``values`` (numbers; revolute offsets theta are
    added): for checks on numeric models, where no derivation is wanted."""
    import numpy as np
    pose = np.eye(4)
    for link, value in zip(robot.links, values):
        geometry = joint_geometry(link, robot.convention)
        motion = np.eye(4)
        if link.is_revolute:
            angle = float(link.theta + value)
            motion[:2, :2] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
        else:
            motion[2, 3] = float(value)
        pose = pose @ np.array(geometry.pre, dtype=float) @ motion @ np.array(geometry.post, dtype=float)
    return pose

