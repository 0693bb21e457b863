"""Kinematics of the tool frame: its pose, its geometric Jacobian and J-dot times qd, symbolic.

All three are in world axes (Pinocchio's LOCAL_WORLD_ALIGNED): the world is the robot's base
placement times the chain, and the tool is the robot's tool frame in the last link's frame.

- ``forward_kinematics``: ``T = Base * T_1(q_1) * ... * T_n(q_n) * Tool``, 4 x 4 (m, unitless
  rotation); each link's world pose is named as it is composed, so the chain costs one 3x3
  rotation product and one translation per link.
- ``jacobian``: 6 x n; column j is ``[z_j x (p - p_j); z_j]`` for a revolute joint and
  ``[z_j; 0]`` for a prismatic one, with z_j the joint axis and p_j a point on it (world), p the
  tool origin.  Rows 0-2 give the tool origin's linear velocity (m/s), rows 3-5 the angular
  velocity (rad/s).
- ``jacobian_dot_qd``: 6 x 1, ``J-dot qd``: the classical acceleration of the tool origin and
  the angular acceleration at ``qdd = 0``.  It comes from the Newton-Euler forward recursion
  (link frames, zero gravity, zero qdd; the same intermediate quantities as the Coriolis
  vector's, shared when both are derived), carried from the last link's origin to the tool
  origin and rotated into world axes.
"""

from __future__ import annotations

import sympy as sp

from ..model.outputs import KINEMATIC_OUTPUTS  # noqa: F401 (the outputs this module derives)
from .chain import Chain
from .newton_euler import recursion


def _compose(b, hint: str, left: sp.Matrix, right: sp.Matrix) -> sp.Matrix:
    """``left * right`` of 4x4 transforms, the rotation and translation entries named."""
    product = left * right
    out = sp.eye(4)
    for r in range(3):
        for c in range(4):
            out[r, c] = b.define(f"{hint}_{r}{c}", sp.expand(product[r, c]))
    return out


def tool_kinematics(chain: Chain, wanted) -> dict[str, sp.Matrix]:
    """The requested kinematic outputs (names from :data:`KINEMATIC_OUTPUTS`) of ``chain``."""
    robot = chain.robot
    b = chain.builder
    n = chain.n
    current = sp.Matrix(robot.base_matrix())
    axes, points = [], []
    for i in range(n):
        geo = chain.geometry[i]
        joint_frame = current * sp.Matrix(geo.pre)
        axes.append(b.vector(f"z{i + 1}", [sp.expand(e) for e in joint_frame[:3, 2]]))
        points.append(b.vector(f"o{i + 1}", [sp.expand(e) for e in joint_frame[:3, 3]]))
        current = _compose(b, f"T0{i + 1}", current, sp.Matrix(geo.pre) * chain.motions[i] * sp.Matrix(geo.post))
    tool_local = sp.Matrix(robot.tool_matrix())
    tool = current * tool_local
    tool = sp.Matrix(4, 4, lambda r, c: sp.expand(tool[r, c]))
    result: dict[str, sp.Matrix] = {}
    if "forward_kinematics" in wanted:
        result["forward_kinematics"] = tool
    if "jacobian" in wanted:
        p = b.vector("ptool", tool[:3, 3])
        J = sp.zeros(6, n)
        for j, link in enumerate(robot.links):
            z = axes[j]
            if link.is_revolute:
                J[:3, j] = z.cross(p - points[j])
                J[3:, j] = z
            else:
                J[:3, j] = z
        result["jacobian"] = J.applyfunc(sp.expand)
    if "jacobian_dot_qd" in wanted:
        zero = [sp.S.Zero] * n
        last = recursion(chain, chain.qd, zero, sp.zeros(3, 1), "h", joint_frames=False)[-1]
        r = tool_local[:3, 3]
        linear = last.vd
        if not r.is_zero_matrix:
            linear = linear + last.omegad.cross(r) + last.omega.cross(last.omega.cross(r))
        rotation = current[:3, :3]
        result["jacobian_dot_qd"] = sp.Matrix.vstack(rotation * linear, rotation * last.omegad).applyfunc(sp.expand)
    return result
