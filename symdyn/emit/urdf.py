"""Writing a robot as URDF text (:func:`robot_to_urdf`), for viewers, simulators and Pinocchio.

The URDF has a root link ``world`` (the world frame of the robot file), a fixed joint to a link
``base`` when the robot has a ``base`` placement, one joint per link named after it moving a
URDF link ``<name>_link``, and a fixed joint to a link ``tool`` (the robot's tool frame: the last
link frame when the file gives no ``tool``).  Joint coordinates are symdyn's: a revolute joint's
angle offset (DH ``theta``) is part of its ``<origin>``, so q = 0 is the same pose in both.

- Denavit-Hartenberg links (``T_k = Pre_k * Joint(q_k) * Post_k``, :mod:`symdyn.model.geometry`):
  joint k's origin is ``Post_{k-1} * Pre_k`` (times ``Rz(theta_k)`` for a revolute joint), its
  axis z, and the URDF link frame is the joint frame; link k's COM and inertia (given in DH frame
  k = joint frame * ``Post_k``) go into ``<inertial>`` with ``Post_k`` as its origin.
- General links (``origin``/``axis``) are written as they are: origin, axis, COM and inertia.

URDF has no place for some of symdyn's data: gravity (simulators assume (0, 0, -9.81); a
different one draws a warning and a comment), armature and passive joints (a warning and a comment per joint);
revolute and prismatic joints need a ``<limit>``, so the robot's limits are written with
:data:`DEFAULT_LIMITS` for what it does not give.  Numbers are ``repr(float)``; the output is
deterministic (the same robot gives the same bytes).
"""

from __future__ import annotations

import math
import os

import sympy as sp

from .._version import __version__
from ..model.errors import SymdynError, display_path, one_line, warn
from ..model.geometry import joint_geometry, rot_z
from ..model.robot import Robot
from ..model.urdf import matrix_rpy

#: limits written where the robot gives none (URDF requires ``<limit>`` on revolute and
#: prismatic joints; symdyn does not use limits): one turn (rad) or one metre either way, and
#: effort and velocity 0, meaning "not given" -- set real values before a controller or
#: simulator relies on them
DEFAULT_LIMITS = {"revolute": {"lower": -math.pi, "upper": math.pi, "effort": 0.0, "velocity": 0.0},
                  "prismatic": {"lower": -1.0, "upper": 1.0, "effort": 0.0, "velocity": 0.0}}
#: the gravity simulators assume when a URDF is loaded (m/s^2)
URDF_GRAVITY = (0, 0, sp.Rational(-981, 100))


def _float(value, what: str) -> float:
    number = float(sp.N(sp.sympify(value), 30))
    if not math.isfinite(number):
        raise SymdynError(f"URDF needs finite numbers: {what} is {number}")
    return number + 0.0  # no negative zero


def _number(value, what: str) -> str:
    return repr(_float(value, what))


def _triple(values, what: str) -> str:
    return " ".join(_number(v, what) for v in values)


def _comment(text: str) -> str:
    """``text`` as the body of an XML comment: one line, no ``--``, not ending with ``-``."""
    text = one_line(text)
    while "--" in text:
        text = text.replace("--", "- -")
    return f"<!-- {text} -->"


def _origin(matrix, what: str) -> str:
    """``<origin xyz rpy>`` of a 4x4 transform."""
    M = sp.Matrix(matrix)
    rpy = [float(a) + 0.0 for a in matrix_rpy(M[:3, :3])]
    return f'<origin xyz="{_triple(M[:3, 3], what)}" rpy="{" ".join(repr(a) for a in rpy)}"/>'


def _unique(name: str, taken: set) -> str:
    while name in taken:
        name += "_"
    return name


def _inertial(body, frame, what: str) -> list[str]:
    """The ``<inertial>`` lines of a link's (or the base body's) mass, centre of mass and inertia
    given in the frame placed at ``frame`` (4x4) in the URDF link's frame; none for no mass."""
    if body.mass == 0 and all(v == 0 for v in body.inertia):
        return []
    place = sp.Matrix(frame)
    place[:3, 3] = frame[:3, :3] * sp.Matrix(body.com) + frame[:3, 3]
    xx, yy, zz, xy, xz, yz = (_number(v, f"{what} inertia") for v in body.inertia)
    return ["    <inertial>", f"      {_origin(place, what)}", f'      <mass value="{_number(body.mass, what)}"/>',
            f'      <inertia ixx="{xx}" ixy="{xy}" ixz="{xz}" iyy="{yy}" iyz="{yz}" izz="{zz}"/>',
            "    </inertial>"]


def robot_to_urdf(robot: Robot) -> str:
    """The URDF text of ``robot`` (any convention).  Runtime parameters take their nominal
    values; a parameter without one raises :class:`SymdynError`.  Armature (not expressible in
    URDF) and a gravity other than (0, 0, -9.81) give a warning and a comment."""
    robot = robot.with_nominal_values()
    if robot.parameters:
        names = [s.name for s in robot.parameters]
        shown = ", ".join(names[:5]) + (f" and {len(names) - 5} more" if len(names) > 5 else "")
        raise SymdynError(f"URDF needs numbers: parameter{'s' if len(names) > 1 else ''} {shown} "
                          f"{'have' if len(names) > 1 else 'has'} no value; give "
                          f"{'them values' if len(names) > 1 else 'it a value'} or use a scene")
    source = display_path(os.path.basename(robot.source))
    lines = ['<?xml version="1.0"?>',
             _comment(f"Generated by symdyn {__version__} from {source}"
                      + (f" (sha256 {robot.source_hash})" if robot.source_hash else "")
                      + ". Do not edit: change the robot file and convert it again (symdyn convert)."),
             _comment(f"Joint coordinates are symdyn's (q = 0 is the same pose); revolute joints "
                      f"without limits in the robot file get [{-math.pi!r}, {math.pi!r}] rad, prismatic "
                      "ones [-1, 1] m, and effort and velocity 0 (not given).")]
    gravity = [_float(g, "gravity") for g in robot.gravity]
    lines.append(_comment(f"Gravity: {gravity} m/s^2 in the world link's frame (URDF carries none)."))
    if tuple(sp.sympify(g) for g in robot.gravity) != URDF_GRAVITY:
        warn(f"{source}: gravity {gravity} m/s^2 is not the (0, 0, -9.81) simulators assume for a URDF, "
             "which has no place for it: set it where the URDF is loaded (Pinocchio: model.gravity)")
    for note in robot.notes:
        lines.append(_comment(f"Note: {note}"))
    lines.append(f'<robot name="{robot.name}">')
    joint_names = {link.name for link in robot.links}
    parent = "world"
    if robot.floating:  # the root link is the floating base: URDF cannot say it floats
        lines.append("  " + _comment("The base floats (base: floating): read this file on a free-flyer joint (symdyn's "
                                     "floating-base option; Pinocchio: buildModelFromUrdf(path, JointModelFreeFlyer()))."))
        lines.append('  <link name="base">')
        lines += _inertial(robot.base_inertia, sp.eye(4), "base_body")
        lines.append("  </link>")
        parent = "base"
    else:
        lines.append('  <link name="world"/>')
    if robot.base is not None:
        name = _unique("base_joint", joint_names)
        lines += [f'  <joint name="{name}" type="fixed">',
                  f"    {_origin(robot.base_matrix(), 'base')}",
                  '    <parent link="world"/>', '    <child link="base"/>', "  </joint>",
                  '  <link name="base"/>']
        parent = "base"
    root, post = parent, sp.eye(4)  # the parent link's frame in its URDF link frame
    armature, passive, placed = [], [], []  # placed: each link's (URDF link, post)
    for k, link in enumerate(robot.links):
        what = f"link {k + 1} ('{link.name}')"
        up = robot.parent_indices[k]
        parent, post = (root, sp.eye(4)) if up < 0 else placed[up]
        link_lines, child, body = _link_lines(robot, link, what, parent, post, armature, passive)
        lines += link_lines
        placed.append((child, body))
    if not robot.is_tree:
        parent, post = placed[-1]
        name = _unique("tool_joint", joint_names)
        lines += [f'  <joint name="{name}" type="fixed">',
                  f"    {_origin(post * sp.Matrix(robot.tool_matrix()), 'tool')}",
                  f'    <parent link="{parent}"/>', '    <child link="tool"/>', "  </joint>", '  <link name="tool"/>']
    link_names = {"world", "base", "tool"} | {child for child, _ in placed}
    for frame in robot.frames:  # each a link on a fixed joint (read back with --frames NAME)
        parent, post = (root, sp.eye(4)) if frame.link < 0 else placed[frame.link]
        name = _unique(frame.name, link_names)
        link_names.add(name)
        lines += [f'  <joint name="{_unique(f"{name}_joint", joint_names)}" type="fixed">',
                  f"    {_origin(post * frame.matrix(), f'frame {frame.name}')}",
                  f'    <parent link="{parent}"/>', f'    <child link="{name}"/>', "  </joint>",
                  "  " + _comment(f"frame {frame.name} of the frame functions (read it back with --frames {name})"),
                  f'  <link name="{name}"/>']
    lines += _contact_lines(robot, source) + ["</robot>", ""]
    if armature:
        warn(f"{source}: armature of {', '.join(armature[:6])}{' ...' if len(armature) > 6 else ''} is left "
             "out of the URDF (URDF has no rotor inertia; the values are in comments)")
    if passive:
        warn(f"{source}: {', '.join(passive[:6])}{' ...' if len(passive) > 6 else ''} "
             f"{'is a passive joint' if len(passive) == 1 else 'are passive joints'} (actuated: false), which "
             "URDF cannot say: written as ordinary joints, with a comment")
    return "\n".join(lines)


def _contact_lines(robot: Robot, source: str) -> list[str]:
    """A comment naming the robot's contact set (URDF has no place for one), and a warning."""
    if not robot.contacts:
        return []
    held = ",".join(f"{robot.frames[c.frame].name}:{c.kind}" for c in robot.contacts)
    corrected = [robot.frames[c.frame].name for c in robot.contacts if c.corrected]
    gains = (f"; the Baumgarte correction of {', '.join(corrected)} is lost (give it in a scene's contacts:)"
             if corrected else "")
    warn(f"{source}: the contact set ({held}) is left out of the URDF (URDF has no place for one; read it back "
         f"with --contacts {held}{gains})")
    return ["  " + _comment(f"contact set of the contact dynamics: {held} (read it back with --contacts {held})")]


def _link_lines(robot: Robot, link, what: str, parent: str, post, armature: list, passive: list):
    """``(lines, child, body)``: the URDF joint and link of ``link`` on the URDF link ``parent``
    (whose frame is ``post`` in it), the child link's name and the link frame in it; the link's
    name is added to ``armature``/``passive`` where URDF cannot hold what it has."""
    fixed = sp.eye(4) if link.fixed is None else sp.Matrix(4, 4, list(link.fixed))
    if robot.convention == "general":
        origin = post * fixed * sp.Matrix(link.origin.matrix())
        axis = _triple(link.axis, f"{what} axis")
        body = sp.eye(4)
    else:
        geometry = joint_geometry(link, robot.convention)  # includes the fixed transform
        origin = post * sp.Matrix(geometry.pre) * (rot_z(link.theta) if link.is_revolute else sp.eye(4))
        axis = "0.0 0.0 1.0"
        body = sp.Matrix(geometry.post)
    kind = "revolute" if link.is_revolute else "prismatic"
    child = f"{link.name}_link"
    out = [f'  <joint name="{link.name}" type="{kind}">', f"    {_origin(origin, what)}",
           f'    <parent link="{parent}"/>', f'    <child link="{child}"/>', f'    <axis xyz="{axis}"/>']
    limits = dict(DEFAULT_LIMITS[kind])
    if link.limits is not None:
        for key in limits:
            if getattr(link.limits, key) is not None:
                limits[key] = _float(getattr(link.limits, key), f"{what} limit {key}")
    out.append(f'    <limit lower="{limits["lower"]!r}" upper="{limits["upper"]!r}" '
               f'effort="{limits["effort"]!r}" velocity="{limits["velocity"]!r}"/>')
    if link.damping != 0 or link.coulomb != 0:
        out.append(f'    <dynamics damping="{_number(link.damping, what)}" '
                   f'friction="{_number(link.coulomb, what)}"/>')
    if link.mimic is not None:
        out.append(f'    <mimic joint="{robot.links[link.mimic.leader].name}" '
                   f'multiplier="{_number(link.mimic.multiplier, what)}" offset="{_number(link.mimic.offset, what)}"/>')
    if link.armature != 0:
        armature.append(link.name)
        unit = "kg m^2" if link.is_revolute else "kg"
        out.append("    " + _comment(f"armature {_number(link.armature, what)} {unit}: URDF has no rotor "
                                        "inertia, left out"))
    if not link.actuated:
        passive.append(link.name)
        out.append("    " + _comment("passive joint (actuated: false, tau = 0): URDF has no such "
                                        "attribute"))
    out.append("  </joint>")
    out.append(f'  <link name="{child}">')
    out += _inertial(link, body, what)
    out.append("  </link>")
    return out, child, body
