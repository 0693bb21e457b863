"""The differential fuzzer's MJCF renditions: a random URDF tree written as a MuJoCo MJCF of the
same robot, so that symdyn's MJCF reader is checked, on robots nobody chose, against Pinocchio's
reading of the URDF (an independent reader of the same robot).

Each link becomes a body named as the link (the root: the world's, or with a free joint the
floating base), each moving joint its body's ``hinge`` or ``slide`` joint named as the joint
(axis as the URDF writes it, in the body frame), its ``<origin>`` the body's ``pos`` and an
orientation written in one of MJCF's forms (``quat``, ``axisangle``, ``euler`` in the file's
``eulerseq``, ``xyaxes``), angles in degrees or radians as the file's ``<compiler angle>`` says;
each inertial an ``<inertial>`` with the rotated tensor as ``fullinertia`` or its principal
moments as ``diaginertia`` with a ``quat``; limits as ``range``, damping and friction as
``damping`` and ``frictionloss``.  A link's child joints are written in the order of their
names, the order in which Pinocchio's URDF reader numbers them.  Every choice is drawn from its
own random stream ``[case number, 29]``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np


def _rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    def rx(a):
        return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])

    def ry(a):
        return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])

    def rz(a):
        return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    return rz(yaw) @ ry(pitch) @ rx(roll)


def _quaternion(R: np.ndarray) -> np.ndarray:
    """(w, x, y, z) of a rotation matrix (Shepperd's method: the largest of the four first)."""
    trace = np.trace(R)
    candidates = [trace, R[0, 0], R[1, 1], R[2, 2]]
    k = int(np.argmax(candidates))
    if k == 0:
        w = math.sqrt(1 + trace) / 2
        q = [w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)]
    else:
        i, j, m = (k - 1, k % 3, (k + 1) % 3)
        s = math.sqrt(1 + R[i, i] - R[j, j] - R[m, m]) * 2
        q = [0.0] * 4
        q[0] = (R[m, j] - R[j, m]) / s
        q[1 + i] = s / 4
        q[1 + j] = (R[j, i] + R[i, j]) / s
        q[1 + m] = (R[m, i] + R[i, m]) / s
    q = np.array(q)
    return q if q[0] >= 0 else -q


def _numbers(values) -> str:
    return " ".join(repr(float(v)) for v in values)


class _Writer:
    def __init__(self, rng, degrees: bool, eulerseq: str):
        self.rng, self.degrees, self.eulerseq = rng, degrees, eulerseq

    def angle(self, radians: float) -> float:
        return math.degrees(radians) if self.degrees else radians

    def orientation(self, rpy: tuple) -> str:
        """``rpy`` (URDF's roll, pitch, yaw, rad) as one of MJCF's orientation attributes."""
        if not any(rpy) and self.rng.random() < 0.5:
            return ""
        R = _rpy_matrix(*rpy)
        form = str(self.rng.choice(["quat", "axisangle", "euler", "xyaxes"]))
        if form == "euler":
            angles = rpy if self.eulerseq == "XYZ" else rpy[::-1]  # XYZ extrinsic = zyx intrinsic = Rz Ry Rx
            return f' euler="{_numbers(self.angle(a) for a in angles)}"'
        if form == "xyaxes":
            return f' xyaxes="{_numbers(list(R[:, 0]) + list(R[:, 1]))}"'
        q = _quaternion(R)
        if form == "axisangle" and np.linalg.norm(q[1:]) > 1e-6:
            axis = q[1:] / np.linalg.norm(q[1:]) * float(self.rng.uniform(0.5, 3))  # (MJCF normalizes it)
            return f' axisangle="{_numbers(list(axis) + [self.angle(2 * math.atan2(np.linalg.norm(q[1:]), q[0]))])}"'
        return f' quat="{_numbers(q * float(self.rng.uniform(0.5, 2)))}"'  # (MJCF normalizes it)

    def inertial(self, link) -> str:
        element = link.find("inertial")
        if element is None:
            return ""
        origin = element.find("origin")
        xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
        rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
        values = {k: float(element.find("inertia").get(k)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
        tensor = np.array([[values["ixx"], values["ixy"], values["ixz"]], [values["ixy"], values["iyy"], values["iyz"]],
                           [values["ixz"], values["iyz"], values["izz"]]])
        R = _rpy_matrix(*rpy)
        body = R @ tensor @ R.T
        mass = element.find("mass").get("value")
        if self.rng.random() < 0.5:
            full = [body[0, 0], body[1, 1], body[2, 2], body[0, 1], body[0, 2], body[1, 2]]
            return f'<inertial pos="{_numbers(xyz)}" mass="{mass}" fullinertia="{_numbers(full)}"/>'
        moments, axes = np.linalg.eigh(body)
        if np.linalg.det(axes) < 0:
            axes[:, 0] = -axes[:, 0]
        return (f'<inertial pos="{_numbers(xyz)}" quat="{_numbers(_quaternion(axes))}" mass="{mass}" '
                f'diaginertia="{_numbers(moments)}"/>')

    def joint(self, joint) -> str:
        kind = joint.get("type")
        if kind == "fixed":
            return ""
        axis = joint.find("axis")
        text = f'<joint name="{joint.get("name")}" type="{"slide" if kind == "prismatic" else "hinge"}" ' \
               f'axis="{axis.get("xyz") if axis is not None else "1 0 0"}"'
        limit = joint.find("limit")
        if limit is not None and kind != "continuous":
            low, high = float(limit.get("lower")), float(limit.get("upper"))
            if kind == "revolute":
                low, high = self.angle(low), self.angle(high)
            text += f' range="{_numbers([low, high])}"'
        dynamics = joint.find("dynamics")
        if dynamics is not None:
            for attribute, key in (("damping", "damping"), ("friction", "frictionloss")):
                if dynamics.get(attribute) is not None:
                    text += f' {key}="{dynamics.get(attribute)}"'
        return text + "/>"


def mjcf_of_urdf(text: str, number: int, floating: bool) -> str:
    """The MJCF text of the fuzzer's URDF ``text`` (case ``number``; ``floating``: the root link on
    a free joint)."""
    rng = np.random.default_rng([number, 29])
    writer = _Writer(rng, bool(rng.random() < 0.5), str(rng.choice(["XYZ", "zyx"])))
    root = ET.fromstring(text)
    links = {link.get("name"): link for link in root.findall("link")}
    children: dict[str, list] = {}
    for joint in root.findall("joint"):
        children.setdefault(joint.find("parent").get("link"), []).append(joint)
    base = next(name for name in links if all(j.find("child").get("link") != name for j in root.findall("joint")))
    lines = [f'<mujoco model="{root.get("name")}">',
             f'  <compiler angle="{"degree" if writer.degrees else "radian"}" eulerseq="{writer.eulerseq}"/>',
             "  <worldbody>"]

    def body(link: str, indent: str) -> None:
        for joint in sorted(children.get(link, []), key=lambda j: j.get("name")):
            child = joint.find("child").get("link")
            origin = joint.find("origin")
            xyz = [float(v) for v in origin.get("xyz", "0 0 0").split()]
            rpy = tuple(float(v) for v in origin.get("rpy", "0 0 0").split())
            lines.append(f'{indent}<body name="{child}" pos="{_numbers(xyz)}"{writer.orientation(rpy)}>')
            for item in (writer.joint(joint), writer.inertial(links[child])):
                if item:
                    lines.append(f"{indent}  {item}")
            body(child, indent + "  ")
            lines.append(f"{indent}</body>")

    if floating:
        lines.append(f'    <body name="{base}">')
        lines.append("      <freejoint/>")
        inertial = writer.inertial(links[base])
        if inertial:
            lines.append(f"      {inertial}")
        body(base, "      ")
        lines.append("    </body>")
    else:
        body(base, "    ")
    return "\n".join(lines + ["  </worldbody>", "</mujoco>", ""])
