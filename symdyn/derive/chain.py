"""Shared symbolic set-up of a chain for the derivations: joint symbols, per-joint sin/cos
symbols, and the link transforms written with them.

For each revolute joint i the program starts with ``_c{i} = cos(theta_i + q_i)`` and
``_s{i} = sin(theta_i + q_i)``, so each joint's trigonometric functions are computed once.  With
an offset theta_i != 0 they are computed as ``cos(theta_i) cos(q_i) - sin(theta_i) sin(q_i)``
(and likewise for the sine), so that the sum theta_i + q_i is never rounded: for |q| ~ 1e4
rad that rounding alone would cost ~1e-12 in double and ~5e-4 in float.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import sympy as sp

from ..model.geometry import JointGeometry, joint_geometry, joint_motion
from .kinematics import joint_symbols
from .program import ProgramBuilder
from .spatial import quaternion_rotation
from ..model.expr import expanded_terms_bound, tree_size
from ..model.robot import Robot


@dataclass
class Chain:
    """Working state of one derivation (not part of any result)."""

    robot: Robot
    q: tuple[sp.Symbol, ...]
    qd: tuple[sp.Symbol, ...]
    qdd: tuple[sp.Symbol, ...]
    tau: tuple[sp.Symbol, ...]
    builder: ProgramBuilder
    geometry: list[JointGeometry]
    transforms: list[sp.Matrix]  # ^{i-1}T_i written with the sin/cos symbols
    motions: list[sp.Matrix]  # Joint_i(q_i) (4x4) written with the sin/cos symbols
    trig: dict[sp.Symbol, sp.Expr]  # trig symbol -> cos/sin(theta + q)
    #: per joint, its (cos, sin) symbols (revolute), or () (prismatic)
    joint_trig: tuple = ()
    #: the inputs ``(q, qd, qdd, tau)``: symbols, one per coordinate (NQ, NV, NV, NV).  They are
    #: ``q, qd, qdd, tau`` themselves unless the robot has mimic joints; then ``qd``, ``qdd`` and
    #: ``tau`` above are per link (a floating base's 6 first), a mimic's entries its leader's
    #: times the multiplier (tau: 0), and the joint positions per link are :attr:`joint_q`
    coordinates: tuple = ()
    #: per link, its joint's position (the coordinate's symbol, or a mimic's law)
    link_q: tuple = ()

    @property
    def n(self) -> int:
        """The links (a mimic joint's among them)."""
        return len(self.robot.links)

    @property
    def parents(self) -> tuple[int, ...]:
        """Per joint, its parent joint (-1: the base); ``(-1, 0, 1, ...)`` for a serial chain."""
        return self.robot.parent_indices

    def children(self, i: int) -> tuple[int, ...]:
        """The joints whose links hang on link ``i`` (-1: on the base), in order."""
        return self.robot.children(i)

    #: a floating base's rotation (3x3, base frame in the world) from its quaternion, normalized
    base_rotation: sp.Matrix | None = None

    @property
    def gravity(self) -> sp.Matrix:
        """Gravity (m/s^2) in the base frame: the world's rotated by the base placement, or by
        the floating base's orientation (``R^T g``, in terms of the quaternion's symbols)."""
        if self.base_rotation is not None:
            return (self.base_rotation.T * sp.Matrix(self.robot.gravity)).applyfunc(sp.expand)
        return sp.Matrix(self.robot.base_gravity)  # base frame (the world rotated by base)

    @property
    def joint_q(self) -> tuple[sp.Expr, ...]:
        """Each link's joint position (q after a floating base's 7; a mimic's law of its leader's)."""
        return self.link_q

    @property
    def coordinate_q(self) -> tuple[sp.Symbol, ...]:
        """The joints' coordinates, symbols (q after a floating base's 7; mimics have none)."""
        q = self.coordinates[0]
        return q[7:] if self.robot.floating else q

    def expand(self, values) -> list:
        """An NV-vector of rates (coordinates) as the links' rates (:func:`_link_rates`)."""
        return list(_link_rates(self.robot, values))

    def project(self, forces) -> sp.Matrix:
        """The links' joint forces (rows per link, a floating base's 6 first; a vector or a
        matrix) as the coordinates' generalized forces: each mimic's row added to its leader's,
        times its multiplier (G^T f)."""
        if not self.robot.mimics:
            return forces
        forces = sp.Matrix(forces)
        base = 6 if self.robot.floating else 0
        out = sp.zeros(base + self.robot.dof, forces.cols)
        out[:base, :] = forces[:base, :]
        for i, (k, m) in enumerate(self.robot.link_coordinates):
            out[base + k, :] += m * forces[base + i, :]
        return out

    def project_columns(self, matrix) -> sp.Matrix:
        """``matrix`` G: columns per link rate (a floating base's 6 first) as columns per
        coordinate (a mimic's column added to its leader's, times its multiplier)."""
        if not self.robot.mimics:
            return matrix
        return self.project(sp.Matrix(matrix).T).T

    def joint_part(self, values) -> list:
        """The joints' entries of an nv-vector (after a floating base's 6)."""
        return list(values[6:] if self.robot.floating else values)

    def base_part(self, values) -> list:
        """A floating base's 6 entries of an nv-vector (linear, then angular), else []."""
        return list(values[:6]) if self.robot.floating else []


#: a link field (length, mass, centre of mass, inertia) whose expression in the runtime
#: parameters is larger than this (nodes written out, or terms expanded) is named once, as an
#: intermediate computed from them, and the derivation works with the name: a field written as
#: a polynomial of 45 terms in two parameters took 29 s when the products of the dynamics
#: expanded it (4 links), 2.7 s named
LARGE_FIELD_NODES, LARGE_FIELD_TERMS = 40, 8


def _named_fields(robot: Robot, builder: ProgramBuilder) -> Robot:
    """``robot`` with each large expression of its links' lengths and inertial fields replaced
    by an intermediate symbol defined in ``builder`` (the same expression, one symbol)."""
    named: dict[sp.Expr, sp.Expr] = {}

    def name(value):
        value = sp.sympify(value)
        if not value.free_symbols or value.is_Symbol:
            return value
        if value not in named:
            large = (tree_size(value, LARGE_FIELD_NODES) > LARGE_FIELD_NODES
                     or expanded_terms_bound(value) > LARGE_FIELD_TERMS)
            named[value] = builder.define(f"pf{len(named) + 1}", value, force=True) if large else value
        return named[value]

    links = [replace(link, a=name(link.a), d=name(link.d), mass=name(link.mass),
                     com=tuple(name(c) for c in link.com), inertia=tuple(name(c) for c in link.inertia))
             for link in robot.links]
    if all(new == old for new, old in zip(links, robot.links)):
        return robot
    return replace(robot, links=tuple(links))


def _link_rates(robot: Robot, values) -> tuple:
    """An NV-vector of rates (coordinates) as the links' rates: a mimic's is its leader's times
    its multiplier (G v; a floating base's 6 first, unchanged); ``values`` without mimic joints."""
    if not robot.mimics:
        return tuple(values)
    base = 6 if robot.floating else 0
    return tuple(values[:base]) + tuple(m * values[base + k] for k, m in robot.link_coordinates)


def _link_motion(robot: Robot, q, qd, qdd, tau) -> tuple:
    """``(joint_q, qd, qdd, tau)`` per link from the coordinates' symbols (mimics by their law)."""
    joint_q = q[7:] if robot.floating else q
    if not robot.mimics:
        return joint_q, qd, qdd, tau
    base = 6 if robot.floating else 0
    laws = robot.link_coordinates
    link_q = tuple(joint_q[k] if link.mimic is None else link.mimic.multiplier * joint_q[k] + link.mimic.offset
                   for link, (k, _) in zip(robot.links, laws))
    torques = tuple(tau[:base]) + tuple(tau[base + k] if link.mimic is None else sp.S.Zero
                                        for link, (k, _) in zip(robot.links, laws))
    return link_q, _link_rates(robot, qd), _link_rates(robot, qdd), torques


def make_chain(robot: Robot, prefix: str = "_") -> Chain:
    coordinates = joint_symbols(robot.nq, robot.nv)
    q = coordinates[0]
    joint_q, qd, qdd, tau = _link_motion(robot, *coordinates)
    builder = ProgramBuilder(prefix)
    robot = _named_fields(robot, builder)
    base_rotation = quaternion_rotation(builder, *q[3:7]) if robot.floating else None
    geometry, transforms, motions, trig, joint_trig = [], [], [], {}, []
    for i, link in enumerate(robot.links):
        geo = joint_geometry(link, robot.convention)
        cos_sin = None
        if link.is_revolute:
            angle = link.theta + joint_q[i]
            if link.theta == 0:
                c = builder.define(f"c{i + 1}", sp.cos(angle), force=True)
                s = builder.define(f"s{i + 1}", sp.sin(angle), force=True)
            else:
                # cos(theta + q) = cos(theta) cos(q) - sin(theta) sin(q): the sum theta + q is
                # never rounded, so large |q| (1e4 rad) loses no accuracy in float or double
                cq = builder.define(f"cq{i + 1}", sp.cos(joint_q[i]), force=True)
                sq = builder.define(f"sq{i + 1}", sp.sin(joint_q[i]), force=True)
                c = builder.define(f"c{i + 1}", sp.cos(link.theta) * cq - sp.sin(link.theta) * sq, force=True)
                s = builder.define(f"s{i + 1}", sp.sin(link.theta) * cq + sp.cos(link.theta) * sq, force=True)
            trig[c], trig[s] = sp.cos(angle), sp.sin(angle)
            cos_sin = (c, s)
        joint_trig.append(cos_sin or ())
        geometry.append(geo)
        motions.append(joint_motion(link, joint_q[i], cos_sin))
        transforms.append(sp.Matrix(geo.pre) * motions[-1] * sp.Matrix(geo.post))
    return Chain(robot, q, qd, qdd, tau, builder, geometry, transforms, motions, trig, tuple(joint_trig),
                 tuple(coordinates), tuple(joint_q), base_rotation)
