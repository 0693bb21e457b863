"""Symbolic kinematics of a DH chain: joint symbols, link transforms, base-to-link transforms,
Jacobians.

Each link transform is ``T_i = Pre_i * Joint_i(q_i) * Post_i`` with the constant parts taken from
the description (:mod:`symdyn.model.geometry`).  All matrices are 4x4 homogeneous transforms,
lengths in m, angles in rad.
"""

from __future__ import annotations

import sympy as sp

from ..model.geometry import joint_geometry, joint_motion, rot_z
from ..model.robot import Robot


def joint_symbols(n: int, nv: int | None = None) -> tuple[tuple[sp.Symbol, ...], ...]:
    """Real symbols (q, qd, qdd, tau), each a tuple q1..qn (rad or m, per s, per s^2, N m or N);
    ``nv``: qd, qdd and tau have that many instead (a floating base: n = nq = nv + 1)."""
    make = lambda base, count: tuple(sp.Symbol(f"{base}{k + 1}", real=True) for k in range(count))
    nv = n if nv is None else nv
    return make("q", n), make("qd", nv), make("qdd", nv), make("tau", nv)


def configuration_symbols(nq: int, nv: int) -> tuple[tuple[sp.Symbol, ...], tuple[sp.Symbol, ...]]:
    """Real symbols (v, q1) of the configuration-space functions: a tangent vector v (nv entries)
    and a second configuration q1 (nq).  Their names (``v.1``, ``q1.1``) are not identifiers, so
    no parameter of a robot file can take them."""
    return (tuple(sp.Symbol(f"v.{k + 1}", real=True) for k in range(nv)),
            tuple(sp.Symbol(f"q1.{k + 1}", real=True) for k in range(nq)))


def contact_force_symbols(count: int) -> tuple[sp.Symbol, ...]:
    """Real symbols of the external forces at the contacts (``count`` entries, laid out as the
    contact forces); named ``f.1``, ... (not identifiers: no parameter can take them)."""
    return tuple(sp.Symbol(f"f.{k + 1}", real=True) for k in range(count))


#: the restitution of an impact (the impulse dynamics' one input beside q and qd)
RESTITUTION = (sp.Symbol("restitution.1", real=True),)


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
