"""Poses along a kinematic tree, symbolic: each joint frame and link frame in the base frame, and
the base frame in the world (a floating base's from q, a fixed base's placement).  Shared by the
centre-of-mass, centroidal and frame functions."""

from __future__ import annotations

import sympy as sp

from .chain import Chain
from .spatial import named_pose


def tree_poses(chain: Chain, hints: tuple[str, str, str] = ("Tp", "Tj", "Tb")) -> tuple[list[sp.Matrix], list[sp.Matrix]]:
    """``(joint_frames, link_frames)``: each joint frame J_i (its axis z, after its motion) and
    each link frame in the base frame, 4x4, named as they are composed along the tree (parents
    first): the parent's link frame times the constant placement ``Pre_i`` (named: the product
    with the joint's rotation about z then costs 4 multiplications a row), the joint's motion,
    then ``Post_i``; ``hints`` name the three stages (``{hint}{i}_{r}{c}``)."""
    placed_hint, joint_hint, link_hint = hints
    b = chain.builder
    joints: list[sp.Matrix] = []
    links: list[sp.Matrix] = []
    for i in range(chain.n):
        parent = chain.parents[i]
        geo = chain.geometry[i]
        placed = (sp.Matrix(geo.pre) if parent < 0
                  else named_pose(b, f"{placed_hint}{i + 1}", links[parent] * sp.Matrix(geo.pre)))
        joint = named_pose(b, f"{joint_hint}{i + 1}", placed * chain.motions[i])
        post = sp.Matrix(geo.post)
        joints.append(joint)
        links.append(joint if post == sp.eye(4) else named_pose(b, f"{link_hint}{i + 1}", joint * post))
    return joints, links


def world_placement(chain: Chain) -> tuple[sp.Matrix, sp.Matrix]:
    """(R, p): the base frame's orientation and origin in the world (the floating base's pose
    from q, its quaternion normalized; the fixed base's placement)."""
    if chain.robot.floating:
        b = chain.builder
        R = sp.Matrix(3, 3, lambda r, c: b.define(f"Rw_{r}{c}", sp.expand(chain.base_rotation[r, c])))
        return R, sp.Matrix(chain.q[:3])
    base = sp.Matrix(chain.robot.base_matrix())
    return base[:3, :3], base[:3, 3]
