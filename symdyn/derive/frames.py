"""Kinematics of named frames (the robot's ``frames:``) on a chain, a tree or a floating base,
symbolic: each frame's pose in the world, its geometric Jacobian and J-dot v, world axes at the
frame's origin (Pinocchio's LOCAL_WORLD_ALIGNED; rows linear then angular).

- ``frame_poses``: K x 4 x 4, ``W * T_link * F`` (W the base frame in the world, T_link the
  frame's link in the base frame, F the frame in its link), composed once along the tree;
- ``frame_jacobians``: K x 6 x nv; joint j on the frame's path from the base has column
  ``[k_j x (o - p_j); k_j]`` (revolute) or ``[k_j; 0]`` (prismatic), k_j its axis and p_j a point
  on it, o the frame's origin; a floating base's six columns are ``[R, -[(o - p_b) x] R; 0, R]``
  (its linear and angular velocity are in its own frame); the other joints' columns are zero;
- ``frame_jacobian_dot_v``: K x 6, the frame origin's classical acceleration and the angular
  acceleration at zero accelerations, from the Newton-Euler forward recursion at zero gravity
  (the quantities the Coriolis vector uses, shared when both are derived).
"""

from __future__ import annotations

import sympy as sp

from ..model.errors import SymdynError
from ..model.outputs import FRAME_OUTPUTS  # noqa: F401 (the outputs this module derives)
from .chain import Chain
from .newton_euler import recursion
from .poses import tree_poses, world_placement
from .spatial import named_pose, named_vector, skew


def frame_kinematics(chain: Chain, wanted) -> dict[str, sp.Matrix]:
    """The requested frame outputs of ``chain``'s robot, its frames in their order."""
    robot, b = chain.robot, chain.builder
    if not robot.frames:
        raise SymdynError(f"{robot.source or robot.name}: the frame functions need frames: list them under "
                          "'frames:' in the robot file (link names, or {name, link, xyz, rpy})")
    joints, links = tree_poses(chain)
    R_w, p_w = world_placement(chain)
    world = R_w.row_join(p_w).col_join(sp.Matrix([[0, 0, 0, 1]]))
    poses, origins = [], []
    for k, frame in enumerate(robot.frames):
        in_base = (links[frame.link] if frame.link >= 0 else sp.eye(4)) * frame.matrix()
        pose = named_pose(b, f"Tf{k + 1}", world * in_base)
        poses.append(pose)
        origins.append(pose[:3, 3])
    result: dict[str, sp.Matrix] = {}
    if "frame_poses" in wanted:
        result["frame_poses"] = sp.Matrix.vstack(*poses)
    if "frame_jacobians" in wanted:
        result["frame_jacobians"] = sp.Matrix.vstack(*[_jacobian(chain, joints, R_w, p_w, frame.link, origin)
                                                       for frame, origin in zip(robot.frames, origins)])
    if "frame_jacobian_dot_v" in wanted:
        result["frame_jacobian_dot_v"] = _bias(chain, links, R_w)
    return result


def _jacobian(chain: Chain, joints, R_w: sp.Matrix, p_w: sp.Matrix, link: int, origin: sp.Matrix) -> sp.Matrix:
    """One frame's 6 x nv Jacobian (world axes at its origin ``origin``), on link ``link``."""
    robot, b = chain.robot, chain.builder
    base = 6 if robot.floating else 0
    J = sp.zeros(6, len(chain.qd))  # per link rate (mimic joints too: projected by the caller)
    if robot.floating:
        J[:3, :3] = R_w
        J[3:, 3:6] = R_w
        J[:3, 3:6] = (-skew(origin - p_w) * R_w).applyfunc(sp.expand)
    path = ((link,) + robot.ancestors(link)) if link >= 0 else ()
    for j in path:
        axis = named_vector(b, f"kw{j + 1}", R_w * joints[j][:3, 2])
        if robot.links[j].is_revolute:
            point = named_vector(b, f"pw{j + 1}", R_w * joints[j][:3, 3] + p_w)
            J[:3, base + j] = axis.cross(origin - point).applyfunc(sp.expand)
            J[3:, base + j] = axis
        else:
            J[:3, base + j] = axis
    return J


def _bias(chain: Chain, links, R_w: sp.Matrix) -> sp.Matrix:
    """Each frame's J-dot v (classical acceleration at zero accelerations), stacked, world axes."""
    robot, b = chain.robot, chain.builder
    motion: list = []
    states = recursion(chain, chain.qd, [sp.S.Zero] * len(chain.qd), sp.zeros(3, 1), "h", joint_frames=False,
                       base_motion=motion)
    rows = []
    for k, frame in enumerate(robot.frames):
        r = frame.matrix()[:3, 3]
        if frame.link >= 0:
            st = states[frame.link]
            omega, omegad, vd, R = st.omega, st.omegad, st.vd, links[frame.link][:3, :3]
        elif robot.floating:
            (omega, omegad, vd), R = motion, sp.eye(3)
        else:  # fixed to a fixed base
            rows += [sp.S.Zero] * 6
            continue
        linear = vd + omegad.cross(r) + omega.cross(omega.cross(r))
        rotation = R_w * R
        rows += list(named_vector(b, f"af{k + 1}", rotation * linear)) + list(named_vector(b, f"alf{k + 1}", rotation * omegad))
    return sp.Matrix(rows)
