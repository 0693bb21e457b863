"""Shared symbolic set-up of a chain for the derivations: joint symbols, per-joint sin/cos
symbols, and the link transforms written with them.

For each revolute joint i the program starts with ``_c{i} = cos(theta_i + q_i)`` and
``_s{i} = sin(theta_i + q_i)``, so each joint's trigonometric functions are computed once.  With
an offset theta_i != 0 they are computed as ``cos(theta_i) cos(q_i) - sin(theta_i) sin(q_i)``
(and likewise for the sine), so that the sum theta_i + q_i is never rounded: for |q| ~ 1e4
rad that rounding alone would cost ~1e-12 in double and ~5e-4 in float.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model.geometry import JointGeometry, joint_geometry, joint_motion
from .kinematics import joint_symbols
from .program import ProgramBuilder
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

    @property
    def n(self) -> int:
        return self.robot.dof

    @property
    def parents(self) -> tuple[int, ...]:
        """Per joint, its parent joint (-1: the base); ``(-1, 0, 1, ...)`` for a serial chain."""
        return self.robot.parent_indices

    def children(self, i: int) -> tuple[int, ...]:
        """The joints whose links hang on link ``i`` (-1: on the base), in order."""
        return self.robot.children(i)

    @property
    def gravity(self) -> sp.Matrix:
        return sp.Matrix(self.robot.base_gravity)  # base frame (the world rotated by base)


def make_chain(robot: Robot, prefix: str = "_") -> Chain:
    q, qd, qdd, tau = joint_symbols(robot.dof)
    builder = ProgramBuilder(prefix)
    geometry, transforms, motions, trig, joint_trig = [], [], [], {}, []
    for i, link in enumerate(robot.links):
        geo = joint_geometry(link, robot.convention)
        cos_sin = None
        if link.is_revolute:
            angle = link.theta + q[i]
            if link.theta == 0:
                c = builder.define(f"c{i + 1}", sp.cos(angle), force=True)
                s = builder.define(f"s{i + 1}", sp.sin(angle), force=True)
            else:
                # cos(theta + q) = cos(theta) cos(q) - sin(theta) sin(q): the sum theta + q is
                # never rounded, so large |q| (1e4 rad) loses no accuracy in float or double
                cq = builder.define(f"cq{i + 1}", sp.cos(q[i]), force=True)
                sq = builder.define(f"sq{i + 1}", sp.sin(q[i]), force=True)
                c = builder.define(f"c{i + 1}", sp.cos(link.theta) * cq - sp.sin(link.theta) * sq, force=True)
                s = builder.define(f"s{i + 1}", sp.sin(link.theta) * cq + sp.cos(link.theta) * sq, force=True)
            trig[c], trig[s] = sp.cos(angle), sp.sin(angle)
            cos_sin = (c, s)
        joint_trig.append(cos_sin or ())
        geometry.append(geo)
        motions.append(joint_motion(link, q[i], cos_sin))
        transforms.append(sp.Matrix(geo.pre) * motions[-1] * sp.Matrix(geo.post))
    return Chain(robot, q, qd, qdd, tau, builder, geometry, transforms, motions, trig, tuple(joint_trig))
