"""Reading MuJoCo MJCF files: a robot as MuJoCo's compiler makes it, turned into a URDF of the
same kinematics and inertia that :mod:`symdyn.model.urdf` then reads (its whole tree, joints in
the MJCF's order).

MuJoCo defines the format; where Pinocchio's MJCF reader differs, this reader follows MuJoCo
(``docs/mjcf.md`` lists the differences).  What is read:

- ``<body>`` trees under ``<worldbody>`` (every top-level body, not just the first), ``<frame>``
  (its pose and ``childclass`` compose into what it holds), body ``pos`` and every orientation
  form (``quat``, ``axisangle``, ``euler`` with ``<compiler eulerseq>``, ``xyaxes``, ``zaxis``);
- ``<joint>`` of type ``hinge`` and ``slide`` (several in one body compose in order, each at its
  ``pos`` with its ``axis`` in the body frame as moved by the joints before it, as MuJoCo's
  kinematics do; ``ref`` is the coordinate at which the body sits as written); ``<freejoint>``
  or ``<joint type="free">`` on a body of the world: the floating base, with Pinocchio's
  conventions for q and v; ``armature``, ``damping`` and ``frictionloss`` (as Coulomb friction);
- ``<inertial>`` (``diaginertia`` or ``fullinertia``) and, as ``<compiler inertiafromgeom>``
  says, the inertia of the geoms (sphere, capsule, cylinder, ellipsoid, box; ``mass`` or
  ``density``, ``fromto``, ``shellinertia`` for sphere, capsule and cylinder; the geoms whose
  ``group`` is in ``inertiagrouprange``), then ``boundmass``, ``boundinertia``,
  ``balanceinertia`` and ``settotalmass`` as MuJoCo applies them;
- ``<default>`` classes (nested, inherited) and ``childclass``; ``<compiler angle>``;
- ``<option gravity>`` and ``<flag gravity="disable">``;
- ``<include file>`` of files inside the model's folder;
- ``<site>`` s: the robot's frames.

The file is untrusted input: no DOCTYPE or entity is accepted (:func:`symdyn.model.urdf.parse_xml`),
included files must lie under the model's folder and are bounded in number, depth and size, no
other file (mesh, texture) is ever opened, and the bodies, elements and numbers are bounded.
What MJCF says that the equations of motion do not hold (actuators, tendons, equality
constraints, springs, limits, contacts' parameters) is listed in one warning line.
"""

from __future__ import annotations

import difflib
import os
import re
from dataclasses import dataclass, field
from xml.sax.saxutils import quoteattr

import mpmath
import numpy as np

from .errors import RobotFileError, describe, display_path, one_line, warn
from .expr import ExpressionError, number_to_rational
from .inputs import decode_text, read_input
from .robot import MAX_MAGNITUDE
from .urdf import MAX_LINKS, Frame, matrix_rpy, number_text, parse_xml, read_urdf, valid_link_name

#: the most elements an MJCF (with its includes) may have
MAX_ELEMENTS = 200_000
#: the most files an MJCF may include, and how deeply includes may nest
MAX_INCLUDES = 64
MAX_INCLUDE_DEPTH = 8
MAX_INCLUDED_BYTES = 16 * 1024 * 1024
#: MuJoCo's smallest mass or volume that counts (mjMINVAL and the geom tests)
_MIN_MASS = 1e-14

_MP = mpmath.MPContext()
_MP.dps = 50
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")
_ORIENTATIONS = ("quat", "axisangle", "euler", "xyaxes", "zaxis")
_REFUSED = {"composite": "composite objects", "flexcomp": "flexible objects", "replicate": "<replicate>",
            "attach": "<attach> (models from other files)", "plugin": "plugins"}
_IGNORED_IN_BODY = {"camera", "light"}
_GEOM_TYPES = ("plane", "hfield", "sphere", "capsule", "ellipsoid", "cylinder", "box", "mesh", "sdf")
_ZERO = _MP.mpf(0)
_I3 = ((_MP.mpf(1), _ZERO, _ZERO), (_ZERO, _MP.mpf(1), _ZERO), (_ZERO, _ZERO, _MP.mpf(1)))


def xml_top_element(text: str) -> str | None:
    """The name of an XML text's top element (a look at its start, not a parse: the XML
    declaration, comments and a DOCTYPE before it are passed over); None when the text does not
    start as XML does."""
    head = re.sub(r"<\?.*?\?>|<!--.*?-->|<!DOCTYPE[^\[>]*(?:\[.*?\])?\s*>", "", text[:65536], flags=re.S)
    match = re.match(r"<([A-Za-z_][A-Za-z0-9_.:-]*)", head.lstrip(" \t\r\n\ufeff"))
    return match.group(1) if match else None


def is_mjcf_text(text: str) -> bool:
    """Whether an XML text's top element is ``<mujoco>``."""
    return xml_top_element(text) == "mujoco"


# ---------------------------------------------------------------------------------------------
# Small 3D algebra on 50-digit numbers


def _mul(A, B):
    return tuple(tuple(sum((A[i][k] * B[k][j] for k in range(3)), _ZERO) for j in range(3)) for i in range(3))


def _apply(A, v):
    return tuple(sum((A[i][k] * v[k] for k in range(3)), _ZERO) for i in range(3))


def _transpose(A):
    return tuple(zip(*A))


def _norm(v):
    return _MP.sqrt(sum((x * x for x in v), _ZERO))


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _quat_matrix(w, x, y, z):
    return ((1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
            (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
            (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)))


def _rotated(R, inertia):
    """``R inertia R^T``: an inertia tensor (3x3 rows) turned by the rotation ``R``."""
    return _mul(R, _mul(inertia, _transpose(R)))


def _axis_angle(axis, angle):
    """The rotation by ``angle`` (rad) about the unit vector ``axis``."""
    c, s = _MP.cos(angle / 2), _MP.sin(angle / 2)
    return _quat_matrix(c, s * axis[0], s * axis[1], s * axis[2])


@dataclass
class _Inertia:
    """Mass, COM and inertia about the COM (3x3 rows), in a body's frame."""

    mass: object = _ZERO
    com: tuple = (_ZERO,) * 3
    inertia: tuple = ((_ZERO,) * 3,) * 3

    def plus(self, other: "_Inertia") -> "_Inertia":
        mass = self.mass + other.mass
        if mass == 0:
            return self
        com = tuple((self.mass * a + other.mass * b) / mass for a, b in zip(self.com, other.com))
        total = [[_ZERO] * 3 for _ in range(3)]
        for part in (self, other):
            d = [a - b for a, b in zip(part.com, com)]
            square = sum((x * x for x in d), _ZERO)
            for i in range(3):
                for j in range(3):
                    total[i][j] += part.inertia[i][j] + part.mass * ((square if i == j else 0) - d[i] * d[j])
        return _Inertia(mass, com, tuple(tuple(row) for row in total))


@dataclass
class _JointSpec:
    name: str
    type: str  # hinge, slide, free
    pos: tuple
    axis: tuple
    ref: object
    fields: dict  # armature, damping, frictionloss as texts
    limits: tuple | None  # (lower, upper) in rad or m


@dataclass
class _BodySpec:
    name: str
    parent: int  # -1: the world
    frame: Frame  # in the parent body's frame
    joints: list = field(default_factory=list)
    inertia: _Inertia = field(default_factory=_Inertia)
    sites: list = field(default_factory=list)  # (name, Frame in the body frame)
    #: no inertia source (no <inertial>, no geom with mass): MuJoCo then puts a bounded mass at the
    #: numbers of the body's own pos, turned by its own orientation (its compiler's reading)
    sourceless: bool = False
    own_pose: Frame = field(default_factory=Frame)
    static: bool = False  # welded to the world: no joint in it or above it
    unknown_mass: bool = False  # a static body's mesh geoms: left out, so never needed but by settotalmass


class _NeedsMesh(Exception):
    """A geom whose inertia needs its mesh (refused on a moving body)."""


# ---------------------------------------------------------------------------------------------
# The reader


class _Reader:
    """One MJCF file (its includes expanded): compiler settings, default classes and the bodies."""

    def __init__(self, text: str, path: str):
        self.path = path
        self.folder = os.path.realpath(os.path.dirname(os.path.abspath(path)))
        self.included: list[str] = []
        self.included_bytes = 0
        self.large_angles: list[float] = []
        self.unmodelled: dict[str, int] = {}
        root = parse_xml(text, path, "an MJCF")
        if root.tag != "mujoco":
            self.fail(f"the top element is <{one_line(root.tag, 40)}>, not <mujoco>: not an MJCF file")
        self.model_name = root.get("model") or os.path.splitext(os.path.basename(path))[0]
        self.root = self.expand_includes(root, 0, {os.path.realpath(path)})
        if sum(1 for _ in self.root.iter("body")) > MAX_LINKS:
            self.fail(f"more than {MAX_LINKS} bodies: not accepted")
        if sum(1 for _ in self.root.iter()) > MAX_ELEMENTS:
            self.fail(f"more than {MAX_ELEMENTS} elements: not accepted")
        self.read_compiler()
        self.classes = self.read_defaults()
        self.gravity = self.read_gravity()

    # -- messages

    def fail(self, reason: str, where: str | None = None, attribute: str | None = None):
        raise RobotFileError(self.path, reason, link=where, field=attribute)

    def note_unmodelled(self, what: str, count: int = 1) -> None:
        self.unmodelled[what] = self.unmodelled.get(what, 0) + count

    # -- includes

    def expand_includes(self, root, depth: int, open_files: set):
        """``root`` with each ``<include file>`` replaced by the included file's elements (a walk
        without recursion: elements may nest deeply)."""
        stack = [root]
        while stack:
            element = stack.pop()
            children = list(element)
            if any(child.tag == "include" for child in children):
                for child in children:
                    element.remove(child)
                for child in children:
                    for part in (self.included_elements(child, depth, open_files) if child.tag == "include"
                                 else [child]):
                        element.append(part)
            stack.extend(child for child in element if child.tag != "include")
        return root

    def included_elements(self, include, depth: int, open_files: set) -> list:
        name = include.get("file")
        where = f"<include file={describe(name)}>"
        if not name:
            self.fail("<include> without a file attribute", "<include>")
        if depth >= MAX_INCLUDE_DEPTH:
            self.fail(f"includes nest more than {MAX_INCLUDE_DEPTH} deep", where)
        if len(self.included) >= MAX_INCLUDES:
            self.fail(f"more than {MAX_INCLUDES} included files", where)
        if os.path.isabs(name) or re.match(r"[A-Za-z][A-Za-z0-9+.-]*:", name) or "\\" in name:
            self.fail("an included file must be named relative to the model's folder", where, "file")
        target = os.path.realpath(os.path.join(self.folder, name))
        if os.path.commonpath([target, self.folder]) != self.folder:
            self.fail("the included file is outside the model's folder: not opened", where, "file")
        if target in open_files:
            self.fail("the file includes itself (an include cycle)", where, "file")
        try:
            raw = read_input(target)
        except RobotFileError as exc:
            self.fail(f"the included file: {exc.reason}", where, "file")
        self.included_bytes += len(raw)
        if self.included_bytes > MAX_INCLUDED_BYTES:
            self.fail(f"the included files hold more than {MAX_INCLUDED_BYTES} bytes", where, "file")
        text = decode_text(raw, target)
        self.included.append(target)
        root = parse_xml(text, target, "an MJCF")
        if root.tag != "mujoco":
            raise RobotFileError(target, f"an included file's top element must be <mujoco>, not "
                                         f"<{one_line(root.tag, 40)}>")
        self.expand_includes(root, depth + 1, open_files | {target})
        return list(root)

    # -- numbers

    def values(self, text: str, count: int | None, where: str, attribute: str) -> list:
        """The numbers of an attribute's ``text`` (``count`` of them, or any number when None)."""
        parts = text.split()
        if count is not None and len(parts) != count:
            self.fail(f"expected {count} number{'s' if count > 1 else ''}, got {describe(one_line(text, 60))}",
                      where, attribute)
        out = []
        for part in parts[:64]:
            if not _NUMBER.match(part):
                self.fail(f"{describe(part)} is not a decimal number", where, attribute)
            try:
                value = number_to_rational(part)
            except ExpressionError as exc:
                self.fail(str(exc), where, attribute)
            if abs(value) > MAX_MAGNITUDE:
                self.fail(f"{describe(part)} is too large (more than 1e100 in magnitude): check the units",
                          where, attribute)
            out.append(_MP.mpf(int(value.p)) / int(value.q))
        return out

    def angle(self, value):
        """An angle of the file in radians (``<compiler angle>``); one beyond 2 pi in radians is
        noted (degrees by mistake?)."""
        if not self.degrees and abs(value) > 2 * _MP.pi + 1e-9 and float(value) not in self.large_angles:
            self.large_angles.append(float(value))
        return value * _MP.pi / 180 if self.degrees else value

    # -- compiler, options, defaults

    def read_compiler(self) -> None:
        settings = {}
        for element in self.root.iter("compiler"):
            settings.update(element.attrib)
        where = "<compiler>"
        angle = settings.get("angle", "degree")
        if angle not in ("degree", "radian"):
            self.fail(f"angle {describe(angle)} is neither 'degree' nor 'radian'", where, "angle")
        self.degrees = angle == "degree"
        self.eulerseq = settings.get("eulerseq", "xyz")
        if len(self.eulerseq) != 3 or any(c not in "xyzXYZ" for c in self.eulerseq):
            self.fail(f"eulerseq {describe(self.eulerseq)} is not three of x, y, z, X, Y, Z", where, "eulerseq")
        self.inertia_from_geom = settings.get("inertiafromgeom", "auto")
        if self.inertia_from_geom not in ("true", "false", "auto"):
            self.fail(f"inertiafromgeom {describe(self.inertia_from_geom)} is not true, false or auto", where,
                      "inertiafromgeom")
        self.group_range = [int(v) for v in self.values(settings.get("inertiagrouprange", "0 5"), 2, where,
                                                           "inertiagrouprange")]
        self.bound_mass, = self.values(settings.get("boundmass", "0"), 1, where, "boundmass")
        self.bound_inertia, = self.values(settings.get("boundinertia", "0"), 1, where, "boundinertia")
        self.balance = self.flag(settings.get("balanceinertia", "false"), where, "balanceinertia")
        self.total_mass, = self.values(settings.get("settotalmass", "-1"), 1, where, "settotalmass")
        self.autolimits = self.flag(settings.get("autolimits", "true"), where, "autolimits")
        if settings.get("coordinate", "local") != "local":
            self.fail("coordinate=\"global\" is no longer supported by MuJoCo (give local coordinates)", where,
                      "coordinate")
        self.align_free = self.flag(settings.get("alignfree", "false"), where, "alignfree")

    def flag(self, text: str, where: str, attribute: str) -> bool:
        if text not in ("true", "false"):
            self.fail(f"{describe(text)} is neither 'true' nor 'false'", where, attribute)
        return text == "true"

    def read_gravity(self) -> list:
        gravity = [_ZERO, _ZERO, _MP.mpf("-9.81")]
        for option in self.root.iter("option"):
            if option.get("gravity") is not None:
                gravity = self.values(option.get("gravity"), 3, "<option>", "gravity")
            for flag in option.iter("flag"):
                if flag.get("gravity") == "disable":
                    gravity = [_ZERO] * 3
        return gravity

    def read_defaults(self) -> dict:
        """``{class name: {tag: {attribute: text}}}``, each class holding what it inherits."""
        classes: dict[str, dict] = {"main": {}}
        stack = []
        for top in [e for e in self.root if e.tag == "default"]:
            name = top.get("class", "main")
            if name != "main":
                self.fail(f"the top-level default class must be 'main', not {describe(name)}", "<default>", "class")
            stack.append((top, "main"))
        while stack:
            element, name = stack.pop()
            own = classes[name]
            for child in element:
                if child.tag == "default":
                    sub = child.get("class")
                    if not sub:
                        self.fail("a nested <default> needs a class name", "<default>", "class")
                    if sub in classes:
                        self.fail(f"two default classes are named {describe(sub)}", "<default>", "class")
                    classes[sub] = {tag: dict(values) for tag, values in own.items()}
                    stack.append((child, sub))
                else:
                    merged = own.setdefault(child.tag, {})
                    attributes = dict(child.attrib)
                    if any(key in attributes for key in _ORIENTATIONS):
                        for key in _ORIENTATIONS:
                            merged.pop(key, None)
                    merged.update(attributes)
        return classes

    def attributes(self, element, childclass: str) -> dict:
        """``element``'s attributes with its class's defaults (its ``class``, else the
        enclosing ``childclass``) under them."""
        name = element.get("class", childclass)
        if name not in self.classes:
            self.fail(f"unknown default class {describe(name)}", f"<{element.tag}>", "class")
        own = dict(element.attrib)
        merged = dict(self.classes[name].get(element.tag, {}))
        if any(key in own for key in _ORIENTATIONS) or "fromto" in own:
            for key in _ORIENTATIONS + ("fromto",):
                merged.pop(key, None)
        merged.update(own)
        return merged

    # -- poses

    def rotation(self, attributes: dict, where: str):
        """The rotation an element's orientation attributes give (identity: none)."""
        given = [key for key in _ORIENTATIONS if key in attributes]
        if len(given) > 1:
            self.fail(f"several orientations ({', '.join(given)}): give one", where, given[1])
        if not given:
            return _I3
        key = given[0]
        if key == "quat":
            q = self.values(attributes[key], 4, where, key)
            norm = _norm(q)
            if norm < 1e-14:
                self.fail("the quaternion is zero", where, key)
            return _quat_matrix(*(v / norm for v in q))
        if key == "axisangle":
            *axis, angle = self.values(attributes[key], 4, where, key)
            return _axis_angle(self.unit(axis, where, key), self.angle(angle))
        if key == "euler":
            R = _I3
            for axis_name, angle in zip(self.eulerseq, self.values(attributes[key], 3, where, key)):
                axis = tuple(_MP.mpf(1) if "xyz"[k] == axis_name.lower() else _ZERO for k in range(3))
                step = _axis_angle(axis, self.angle(angle))
                R = _mul(R, step) if axis_name.islower() else _mul(step, R)
            return R
        if key == "xyaxes":
            values = self.values(attributes[key], 6, where, key)
            x = self.unit(values[:3], where, key)
            y = values[3:]
            dot = sum((a * b for a, b in zip(x, y)), _ZERO)
            y = self.unit([b - dot * a for a, b in zip(x, y)], where, key)
            z = _cross(x, y)
            return tuple(tuple(column[i] for column in (x, y, z)) for i in range(3))
        return _z_rotation(self.unit(self.values(attributes[key], 3, where, key), where, key))

    def unit(self, vector, where: str, attribute: str) -> tuple:
        norm = _norm(vector)
        if norm < 1e-14:
            self.fail("the direction is zero", where, attribute)
        return tuple(v / norm for v in vector)

    def pose(self, attributes: dict, where: str) -> Frame:
        position = self.values(attributes.get("pos", "0 0 0"), 3, where, "pos")
        return Frame(self.rotation(attributes, where), tuple(position))


def _z_rotation(v) -> tuple:
    """MuJoCo's ``zaxis``: the smallest rotation taking +z to the unit vector ``v`` (a half turn
    about x for -z)."""
    z = (_ZERO, _ZERO, _MP.mpf(1))
    axis = _cross(z, v)
    sine = _norm(axis)
    if sine < 1e-10:
        axis, sine = (_MP.mpf(1), _ZERO, _ZERO), _ZERO
    else:
        axis = tuple(a / sine for a in axis)
    return _axis_angle(axis, _MP.atan2(sine, v[2]))


# ---------------------------------------------------------------------------------------------
# MuJoCo's schema, for what the bodies hold (an unknown name there is most likely a typo)

_ORIENTED = ("pos",) + _ORIENTATIONS
_SCHEMA = {
    "body": {"name", "childclass", "mocap", "gravcomp", "user", *_ORIENTED},
    "frame": {"name", "childclass", *_ORIENTED},
    "joint": {"name", "class", "type", "group", "pos", "axis", "springdamper", "limited", "actuatorfrclimited",
              "range", "actuatorfrcrange", "actuatorgravcomp", "margin", "ref", "springref", "armature", "damping",
              "frictionloss", "stiffness", "solreflimit", "solimplimit", "solreffriction", "solimpfriction", "user"},
    "freejoint": {"name", "group", "align"},
    "geom": {"name", "class", "type", "contype", "conaffinity", "condim", "group", "priority", "size", "material",
             "friction", "mass", "density", "shellinertia", "solmix", "solref", "solimp", "margin", "gap", "fromto",
             "hfield", "mesh", "fitscale", "rgba", "fluidshape", "fluidcoef", "user", *_ORIENTED},
    "site": {"name", "class", "type", "group", "size", "material", "rgba", "fromto", "user", *_ORIENTED},
    "inertial": {"mass", "diaginertia", "fullinertia", *_ORIENTED},
}
_IN_BODY = {"inertial", "joint", "freejoint", "geom", "site", "camera", "light", "body", "frame", "plugin",
            "composite", "flexcomp", "replicate", "attach"}


def _warn_unknown(reader: "_Reader") -> None:
    """One warning line naming the elements and attributes in the bodies that MuJoCo's schema does
    not have (MuJoCo refuses the file; symdyn reads on without them)."""
    unknown: list[str] = []
    for world in reader.root.iter("worldbody"):
        stack = [(world, "<worldbody>")]
        while stack:
            element, where = stack.pop()
            for child in element:
                if element.tag in ("worldbody", "body", "frame") and child.tag not in _IN_BODY:
                    unknown.append(f"element <{one_line(child.tag, 30)}> in {where}")
                    continue
                extra = sorted(set(child.attrib) - _SCHEMA.get(child.tag, set(child.attrib)))
                unknown.extend(f"attribute {describe(key, 30)} of <{child.tag}> in {where}" for key in extra)
                inner = f"body {describe(child.get('name'), 40)}" if child.tag == "body" and child.get("name") else where
                stack.append((child, inner))
    if unknown:
        more = f" and {len(unknown) - 6} more" if len(unknown) > 6 else ""
        warn(f"{one_line(reader.path, 200)}: not in MuJoCo's schema (a typo?), ignored: {', '.join(unknown[:6])}{more}")


# ---------------------------------------------------------------------------------------------
# Bodies, joints, geoms and sites


def _body_items(reader: _Reader, body, childclass: str):
    """A body's elements in document order, ``<frame>`` s opened: ``(element, pose of the
    enclosing frames in the body frame, childclass)``."""
    stack = [(child, Frame(), childclass) for child in reversed(list(body))]
    while stack:
        element, frame, cls = stack.pop()
        if element.tag == "frame":
            attributes = reader.attributes(element, cls) if "class" in element.attrib else dict(element.attrib)
            inner = frame * reader.pose(attributes, "<frame>")
            inner_class = element.get("childclass", cls)
            stack.extend((child, inner, inner_class) for child in reversed(list(element)))
        else:
            yield element, frame, cls


class _Bodies:
    """The bodies of an MJCF in MuJoCo's order (depth first, as written), with their joints,
    inertia and sites."""

    def __init__(self, reader: _Reader):
        self.reader = reader
        self.bodies: list[_BodySpec] = []
        self.names: set[str] = {"world"}
        self.joint_names: set[str] = set()
        self.world_sites: list = []
        self.free: int | None = None  # the body on a free joint
        worlds = [e for e in reader.root if e.tag == "worldbody"]
        stack = []
        for world in reversed(worlds):
            for element, frame, cls in reversed(list(_body_items(reader, world, world.get("childclass", "main")))):
                stack.append((element, -1, frame, cls))
        while stack:
            element, parent, frame, cls = stack.pop()
            children = self.read_element(element, parent, frame, cls)
            stack.extend(reversed(children))
        if not self.bodies:
            reader.fail("the <worldbody> has no <body>: nothing moves")

    def read_element(self, element, parent: int, frame: Frame, cls: str) -> list:
        tag = element.tag
        where = f"body {describe(self.bodies[parent].name)}" if parent >= 0 else "<worldbody>"
        if tag in _REFUSED:
            self.reader.fail(f"{_REFUSED[tag]} are not supported", where, f"<{tag}>")
        if tag == "body":
            return self.read_body(element, parent, frame, cls)
        if tag == "site":
            attributes = self.reader.attributes(element, cls)
            site = (attributes.get("name"), frame * self.site_pose(attributes, where))
            (self.bodies[parent].sites if parent >= 0 else self.world_sites).append(site)
        elif parent < 0 and tag in ("joint", "freejoint", "inertial"):
            self.reader.fail(f"<{tag}> on the world body: the world does not move", where)
        return []

    def read_body(self, element, parent: int, frame: Frame, cls: str) -> list:
        reader = self.reader
        if len(self.bodies) >= MAX_LINKS:
            reader.fail(f"more than {MAX_LINKS} bodies: not accepted")
        name = element.get("name") or f"body{len(self.bodies) + 1}"
        where = f"body {describe(name)}"
        if name in self.names:
            reader.fail(f"two bodies are named {describe(name)}", where, "name")
        self.names.add(name)
        if element.get("gravcomp") not in (None, "0"):
            reader.note_unmodelled("bod|ies with gravity compensation (gravcomp)")
        own_pose = reader.pose(dict(element.attrib), where)
        pose = frame * own_pose
        childclass = element.get("childclass", cls)
        if childclass not in reader.classes:
            reader.fail(f"unknown default class {describe(childclass)}", where, "childclass")
        index = len(self.bodies)
        body = _BodySpec(name, parent, pose, own_pose=own_pose)
        self.bodies.append(body)
        geoms, inertial, children = [], None, []
        for item, inner, item_class in _body_items(reader, element, childclass):
            if item.tag in ("joint", "freejoint"):
                self.read_joint(body, index, item, inner, item_class)
            elif item.tag == "geom":
                geoms.append((item, inner, item_class))
            elif item.tag == "inertial":
                if inertial is not None:
                    reader.fail("two <inertial> elements", where, "<inertial>")
                inertial = (item, inner)
            elif item.tag in _IGNORED_IN_BODY:
                continue
            else:
                children.append((item, index, inner, item_class))
        body.static = not body.joints and (parent < 0 or self.bodies[parent].static)
        try:
            body.inertia = self.body_inertia(body, geoms, inertial)
        except _NeedsMesh as need:
            if not body.static:
                reader.fail(need.args[0], need.args[1], "type")
            body.unknown_mass = True  # (left out with the ground)
        return children

    def read_joint(self, body: _BodySpec, index: int, element, frame: Frame, cls: str) -> None:
        reader = self.reader
        where = f"body {describe(body.name)}"
        attributes = {"type": "free", **{k: v for k, v in element.attrib.items() if k in ("name", "align")}} \
            if element.tag == "freejoint" else reader.attributes(element, cls)
        kind = attributes.get("type", "hinge")
        name = attributes.get("name") or f"{body.name}_joint{len(body.joints) + 1}"
        where = f"joint {describe(name)}"
        if name in self.joint_names:
            reader.fail(f"two joints are named {describe(name)}", where, "name")
        self.joint_names.add(name)
        if kind == "ball":
            reader.fail("ball joints are not supported yet (hinge, slide and free are): write three hinges "
                        "or lock it", where, "type")
        if kind not in ("hinge", "slide", "free"):
            reader.fail(f"unknown joint type {describe(kind)} (MJCF has hinge, slide, ball and free)", where, "type")
        if kind == "free":
            if self.free is not None:
                reader.fail(f"a second free joint (body {describe(self.bodies[self.free].name)} has one): symdyn reads "
                            "one floating base", where, "type")
            if body.parent >= 0 or body.joints:
                reader.fail("a free joint must be the only joint of a body of the world", where, "type")
            if attributes.get("align") == "true" or (attributes.get("align", "auto") == "auto" and reader.align_free):
                reader.fail("align=\"true\" moves the body frame onto its inertial frame: not supported (the base "
                            "frame is the body frame as written)", where, "align")
            self.free = index
            body.joints.append(_JointSpec(name, kind, (_ZERO,) * 3, (_ZERO, _ZERO, _MP.mpf(1)), _ZERO, {}, None))
            return
        if body.joints and body.joints[0].type == "free":
            reader.fail("a free joint must be the only joint of a body of the world", where, "type")
        if len(body.joints) >= 6:
            reader.fail("more than 6 degrees of freedom in one body", where)
        pos = frame.t if "pos" not in attributes else \
            tuple(a + b for a, b in zip(_apply(frame.R, reader.values(attributes["pos"], 3, where, "pos")), frame.t))
        axis = _apply(frame.R, reader.unit(reader.values(attributes.get("axis", "0 0 1"), 3, where, "axis"),
                                           where, "axis"))
        ref, = reader.values(attributes.get("ref", "0"), 1, where, "ref")
        ref = reader.angle(ref) if kind == "hinge" else ref
        fields = {}
        for key in ("armature", "damping", "frictionloss"):
            value, = reader.values(attributes.get(key, "0"), 1, where, key)
            if value < 0:
                reader.fail(f"{key} must not be negative", where, key)
            if value != 0:
                fields[key] = number_text(value)
        for key, what in (("stiffness", "joint spring|s (stiffness)"),):
            if reader.values(attributes.get(key, "0"), 1, where, key)[0] != 0:
                reader.note_unmodelled(what)
        if any(v != 0 for v in reader.values(attributes.get("springdamper", "0 0"), 2, where, "springdamper")):
            reader.note_unmodelled("joint spring-damper|s (springdamper: its stiffness and damping too)")
        body.joints.append(_JointSpec(name, kind, pos if kind == "hinge" else (_ZERO,) * 3, axis, ref, fields,
                                      self.limits(attributes, kind, where)))

    def limits(self, attributes: dict, kind: str, where: str):
        reader = self.reader
        limited = attributes.get("limited", "auto")
        if limited not in ("auto", "true", "false"):
            reader.fail(f"limited {describe(limited)} is not true, false or auto", where, "limited")
        if "range" not in attributes:
            return None
        low, high = reader.values(attributes["range"], 2, where, "range")
        if limited == "auto" and not reader.autolimits:
            reader.fail("a range without limited=\"true\" or \"false\" (the model says autolimits=\"false\")",
                        where, "limited")
        if limited == "false" or low >= high:
            if limited == "true":
                reader.fail("the range's lower end is not below its upper end", where, "range")
            return None
        return (reader.angle(low), reader.angle(high)) if kind == "hinge" else (low, high)

    def site_pose(self, attributes: dict, where: str) -> Frame:
        if "fromto" not in attributes:
            return self.reader.pose(attributes, where)
        if attributes.get("type", "sphere") not in ("capsule", "cylinder", "box", "ellipsoid"):
            self.reader.fail("fromto applies to capsules, cylinders, boxes and ellipsoids", where, "fromto")
        values = self.reader.values(attributes["fromto"], 6, where, "fromto")
        start, end = values[:3], values[3:]
        direction = [a - b for a, b in zip(start, end)]
        return Frame(_z_rotation(self.reader.unit(direction, where, "fromto")),
                     tuple((a + b) / 2 for a, b in zip(start, end)))

    # -- inertia

    def body_inertia(self, body: _BodySpec, geoms: list, inertial) -> _Inertia:
        """The body's inertia as MuJoCo's compiler sets it: the ``<inertial>``, or the geoms'
        (``inertiafromgeom``)."""
        reader = self.reader
        mode = reader.inertia_from_geom
        if inertial is not None and mode != "true":
            return self.explicit_inertia(body, *inertial)
        total, counted = _Inertia(), False
        for index, (element, frame, cls) in enumerate(geoms if mode != "false" else ()):
            part = self.geom_inertia_of(body, index, element, frame, cls)
            if part is not None:
                total, counted = total.plus(part), True
        body.sourceless = not counted
        return total

    def explicit_inertia(self, body: _BodySpec, element, frame: Frame) -> _Inertia:
        reader = self.reader
        where = f"body {describe(body.name)} <inertial>"
        attributes = dict(element.attrib)
        for key in ("pos", "mass"):
            if key not in attributes:
                reader.fail("missing attribute", where, key)
        pose = frame * reader.pose(attributes, where)
        mass, = reader.values(attributes["mass"], 1, where, "mass")
        if mass < 0:
            reader.fail("mass must not be negative", where, "mass")
        if ("diaginertia" in attributes) == ("fullinertia" in attributes):
            reader.fail("give diaginertia or fullinertia (one of them)", where, "diaginertia")
        if "diaginertia" in attributes:
            values = reader.values(attributes["diaginertia"], 3, where, "diaginertia")
            local = tuple(tuple(values[i] if i == j else _ZERO for j in range(3)) for i in range(3))
        else:
            if any(key in attributes for key in _ORIENTATIONS):
                reader.fail("fullinertia takes no orientation (it is in the body frame)", where, "fullinertia")
            xx, yy, zz, xy, xz, yz = reader.values(attributes["fullinertia"], 6, where, "fullinertia")
            local = ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz))
        if any(local[i][i] < 0 for i in range(3)):
            reader.fail("the moments of inertia must not be negative", where, "diaginertia")
        return _Inertia(mass, pose.t, _rotated(pose.R, local))

    def geom_inertia_of(self, body: _BodySpec, index: int, element, frame: Frame, cls: str) -> _Inertia | None:
        """A geom's mass and inertia in the body frame (None: it does not count)."""
        reader = self.reader
        attributes = reader.attributes(element, cls)
        where = f"body {describe(body.name)} geom {describe(attributes.get('name') or index + 1)}"
        group, = reader.values(attributes.get("group", "0"), 1, where, "group")
        if not reader.group_range[0] <= group <= reader.group_range[1]:
            return None
        kind = attributes.get("type", "sphere")
        if kind not in _GEOM_TYPES:
            reader.fail(f"unknown geom type {describe(kind)}", where, "type")
        if kind == "plane":
            return None
        if kind in ("mesh", "hfield", "sdf") or attributes.get("mesh") is not None:
            weightless = reader.values(attributes["mass"], 1, where, "mass")[0] == 0 if "mass" in attributes else \
                reader.values(attributes.get("density", "1000"), 1, where, "density")[0] == 0
            if weightless:
                return None
            raise _NeedsMesh(f"a {kind} geom's volume and inertia come from its {kind}, which symdyn does not read: "
                             "give the body an <inertial> (with inertiafromgeom=\"auto\"), the geom mass=\"0\", or "
                             "put it in a group outside inertiagrouprange", where)
        shape, pose = self.geom_shape(kind, attributes, where)
        shell = reader.flag(attributes.get("shellinertia", "false"), where, "shellinertia")
        if shell and kind in ("ellipsoid", "box"):
            reader.fail(f"shellinertia of a {kind} is not supported (sphere, capsule and cylinder are)", where,
                        "shellinertia")
        volume, unit = _geom_volume(kind, shape, shell)
        if "mass" in attributes:
            mass, = reader.values(attributes["mass"], 1, where, "mass")
            if mass < 0:
                reader.fail("mass must not be negative", where, "mass")
        else:
            density, = reader.values(attributes.get("density", "1000"), 1, where, "density")
            if density < 0:
                reader.fail("density must not be negative", where, "density")
            mass = density * volume
        if mass <= _MIN_MASS or volume <= _MIN_MASS:
            return None
        moments = unit(mass)
        local = tuple(tuple(moments[i] if i == j else _ZERO for j in range(3)) for i in range(3))
        pose = frame * pose
        return _Inertia(mass, pose.t, _rotated(pose.R, local))

    def geom_shape(self, kind: str, attributes: dict, where: str) -> tuple:
        """The geom's sizes (radius, half-length / half-sizes) and pose in its body."""
        reader = self.reader
        needed = {"sphere": 1, "capsule": 2, "cylinder": 2, "ellipsoid": 3, "box": 3}[kind]
        if "size" not in attributes:
            reader.fail(f"missing attribute: a {kind} needs its size ({needed} number{'s' if needed > 1 else ''}"
                        + (", or a radius with fromto" if needed > 1 else "") + ")", where, "size")
        sizes = reader.values(attributes["size"], None, where, "size")
        if "fromto" in attributes:
            if kind == "sphere":
                reader.fail("fromto applies to capsules, cylinders, boxes and ellipsoids", where, "fromto")
            values = reader.values(attributes["fromto"], 6, where, "fromto")
            start, end = values[:3], values[3:]
            half = _norm([a - b for a, b in zip(start, end)]) / 2
            if half < 1e-14 / 2:
                reader.fail("the two points of fromto are the same", where, "fromto")
            if not sizes:
                reader.fail("missing attribute (the radius)", where, "size")
            sizes = [sizes[0], half] if kind in ("capsule", "cylinder") else [sizes[0], sizes[0], half]
            pose = self.site_pose(attributes, where)
        else:
            pose = reader.pose(attributes, where)
        if len(sizes) < needed:
            reader.fail(f"a {kind} needs {needed} size{'s' if needed > 1 else ''}, got {len(sizes)}", where, "size")
        sizes = sizes[:needed]
        if any(s <= 0 for s in sizes):
            reader.fail(f"the sizes of a {kind} must be positive", where, "size")
        return (kind, sizes), pose


def _geom_volume(kind: str, shape: tuple, shell: bool):
    """``(volume or area, moments(mass))``: MuJoCo's volume (area with ``shell``) of a geom and
    its principal moments of inertia for a mass, about its centre in its frame."""
    _, s = shape
    pi = _MP.pi
    if kind == "sphere":
        r = s[0]
        if shell:
            return 4 * pi * r ** 2, lambda m: (2 * m * r ** 2 / 3,) * 3
        return 4 * pi * r ** 3 / 3, lambda m: (2 * m * r ** 2 / 5,) * 3
    if kind == "capsule":
        r, h = s[0], 2 * s[1]
        if shell:
            sphere, side = 4 * pi * r ** 2, 2 * pi * r * h

            def shell_capsule(m):
                ms = m * sphere / (sphere + side)
                mc = m - ms
                xx = mc * (6 * r ** 2 + h ** 2) / 12 + 2 * ms * r ** 2 / 3 + ms * ((h / 2 + r / 2) ** 2 - (r / 2) ** 2)
                return xx, xx, mc * r ** 2 + 2 * ms * r ** 2 / 3
            return sphere + side, shell_capsule

        def capsule(m):
            ms = m * 4 * r / (4 * r + 3 * h)
            mc = m - ms
            xx = mc * (3 * r ** 2 + h ** 2) / 12 + 2 * ms * r ** 2 / 5 + ms * h * (3 * r + 2 * h) / 8
            return xx, xx, mc * r ** 2 / 2 + 2 * ms * r ** 2 / 5
        return pi * r ** 2 * h + 4 * pi * r ** 3 / 3, capsule
    if kind == "cylinder":
        r, h = s[0], 2 * s[1]
        if shell:
            area = 2 * pi * r ** 2 + 2 * pi * r * h

            def shell_cylinder(m):
                md = m * pi * r ** 2 / area
                mc = m - 2 * md
                xx = mc * (6 * r ** 2 + h ** 2) / 12 + 2 * (md * r ** 2 / 4 + md * (h / 2) ** 2)
                return xx, xx, mc * r ** 2 + md * r ** 2
            return area, shell_cylinder
        return pi * r ** 2 * h, lambda m: (m * (3 * r ** 2 + h ** 2) / 12,) * 2 + (m * r ** 2 / 2,)
    a, b, c = s
    if kind == "ellipsoid":
        return 4 * pi * a * b * c / 3, lambda m: (m * (b * b + c * c) / 5, m * (a * a + c * c) / 5,
                                                   m * (a * a + b * b) / 5)
    return 8 * a * b * c, lambda m: (m * (b * b + c * c) / 3, m * (a * a + c * c) / 3, m * (a * a + b * b) / 3)


def _compiler_bounds(reader: _Reader, bodies: list) -> None:
    """``boundmass``, ``boundinertia``, ``balanceinertia`` (on each body's principal moments)
    and ``settotalmass``, in MuJoCo's order."""
    if reader.bound_mass > 0 or reader.bound_inertia > 0 or reader.balance:
        for body in bodies:
            inertia = body.inertia
            if body.sourceless:  # MuJoCo's compiler: no inertia, its frame the body's own pos and orientation
                com = body.own_pose.t
                moments, axes = np.zeros(3), np.array([[float(e) for e in row] for row in body.own_pose.R])
                changed = np.full(3, float(reader.bound_inertia))
            else:
                com = inertia.com
                moments, axes = np.linalg.eigh(np.array([[float(e) for e in row] for row in inertia.inertia]))
                changed = np.maximum(moments, float(reader.bound_inertia))
                a, b, c = changed
                if reader.balance and (a + b < c or a + c < b or b + c < a):
                    changed = np.full(3, changed.mean())
            mass = max(inertia.mass, reader.bound_mass)
            if mass != inertia.mass or not np.array_equal(changed, moments):
                rebuilt = axes @ np.diag(changed) @ axes.T
                body.inertia = _Inertia(mass, com, tuple(tuple(_MP.mpf(float(v)) for v in row) for row in rebuilt))
    if reader.total_mass > 0:
        unknown = [body.name for body in bodies if body.unknown_mass]
        if unknown:
            reader.fail(f"settotalmass needs the mass of body {describe(unknown[0])}, which its mesh geoms hold: "
                        "give it an <inertial>", "<compiler>", "settotalmass")
        total = sum((body.inertia.mass for body in bodies), _ZERO)
        scale = max(_MP.mpf("1e-15"), reader.total_mass / max(_MP.mpf("1e-15"), total))
        for body in bodies:
            inertia = body.inertia
            body.inertia = _Inertia(inertia.mass * scale, inertia.com,
                                    tuple(tuple(e * scale for e in row) for row in inertia.inertia))


# ---------------------------------------------------------------------------------------------
# The URDF of the same robot


def _texts(values) -> str:
    return " ".join(number_text(v) for v in values)


def _origin(frame: Frame) -> str:
    """A URDF ``<origin>`` of ``frame``: decimal texts (quarter turns as the doubles nearest to
    them, which the URDF reader takes as exact quarter turns)."""
    rpy = " ".join(repr(float(a)) if float(a) else "0" for a in matrix_rpy(frame.R))
    return f'<origin xyz="{_texts(frame.t)}" rpy="{rpy}"/>'


class _Urdf:
    """The URDF text of the bodies: one link per body, a chain of massless links for a body's
    joints after the first, a link per site."""

    def __init__(self, reader: _Reader, tree: _Bodies):
        self.reader, self.tree = reader, tree
        self.links: set[str] = set()
        self.lines: list[str] = []
        self.joint_fields: dict[str, dict] = {}
        self.site_links: dict[str, str] = {}  # site name -> its link
        self.body_links: dict[int, str] = {}
        self.dropped: list[str] = []
        self.renamed_sites: list[tuple[str, str]] = []
        self.joint_names = set(tree.joint_names)
        #: the robot's links, named after the joints (a site's frame must not take one's name)
        self.joint_links = {valid_link_name(name, set()) for name in tree.joint_names}

    def link_name(self, wanted: str) -> str:
        name, k = wanted, 1
        while name in self.links:
            k += 1
            name = f"{wanted}_{k}"
        self.links.add(name)
        return name

    def link(self, name: str, inertia: _Inertia | None = None) -> None:
        if inertia is None or (inertia.mass == 0 and all(e == 0 for row in inertia.inertia for e in row)):
            self.lines.append(f"  <link name={quoteattr(name)}/>")
            return
        I = inertia.inertia
        values = [number_text(I[i][j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))]
        self.lines.append(f"  <link name={quoteattr(name)}><inertial><origin xyz=\"{_texts(inertia.com)}\"/>"
                          f"<mass value=\"{number_text(inertia.mass)}\"/><inertia ixx=\"{values[0]}\" "
                          f"ixy=\"{values[1]}\" ixz=\"{values[2]}\" iyy=\"{values[3]}\" iyz=\"{values[4]}\" "
                          f"izz=\"{values[5]}\"/></inertial></link>")

    def joint(self, name: str, kind: str, parent: str, child: str, frame: Frame, extra: str = "") -> None:
        if kind == "fixed":
            wanted, k = name, 1
            while name in self.joint_names:
                k += 1
                name = f"{wanted}_{k}"
            self.joint_names.add(name)
        self.lines.append(f"  <joint name={quoteattr(name)} type=\"{kind}\"><parent link={quoteattr(parent)}/>"
                          f"<child link={quoteattr(child)}/>{_origin(frame)}{extra}</joint>")

    def text(self) -> str:
        tree = self.tree
        floating = tree.free is not None
        root = self.link_name(tree.bodies[tree.free].name if floating else "world")
        if not floating:
            self.link(root)
            self.attach_sites(root, tree.world_sites)
        elif tree.world_sites:
            self.dropped.append(f"{len(tree.world_sites)} site{'s' if len(tree.world_sites) > 1 else ''} "
                                "on the world body (not on the robot)")
        root_of: list[int] = []  # each body's body of the world (the bodies come parents first)
        for index, body in enumerate(tree.bodies):
            root_of.append(index if body.parent < 0 else root_of[body.parent])
        for index, body in enumerate(tree.bodies):
            if floating and root_of[index] != tree.free:
                if index == root_of[index]:
                    if any(b.joints for k, b in enumerate(tree.bodies) if root_of[k] == index):
                        self.reader.fail(f"body {describe(body.name)} has joints but is not on the floating base: "
                                         "symdyn reads one moving tree (a free body, or bodies on the world)")
                    self.dropped.append(f"body {one_line(body.name, 60)} (fixed to the world)")
                continue
            parent = root if body.parent < 0 else self.body_links[body.parent]
            self.add_body(index, body, parent, root if index == tree.free else None)
        header = f"<robot name={quoteattr(self.reader.model_name)}>"
        return "\n".join([header] + self.lines + ["</robot>", ""])

    def add_body(self, index: int, body: _BodySpec, parent: str, root: str | None) -> None:
        """The links and joints of one body; ``root``: the body is the floating base, that link."""
        if root is not None:
            self.body_links[index] = root
            self.link(root, body.inertia)
            self.attach_sites(root, body.sites)
            return
        offset = body.frame
        joints = [j for j in body.joints if j.type != "free"]
        for k, joint in enumerate(joints):
            kind = "revolute" if joint.type == "hinge" else "prismatic"
            if kind == "revolute":
                move = Frame(_axis_angle(joint.axis, -joint.ref), joint.pos)
            else:
                move = Frame(_I3, tuple(-a * joint.ref for a in joint.axis))
            last = k == len(joints) - 1 and all(p == 0 for p in joint.pos)
            child = self.link_name(body.name if last else f"{body.name}_{joint.name}")
            self.link(child, body.inertia if last else None)
            self.joint(joint.name, kind, parent, child, offset * move, self.joint_extra(joint))
            parent, offset = child, Frame(_I3, tuple(-p for p in joint.pos))
            if last:
                self.body_links[index] = child
        if index not in self.body_links:
            link = self.link_name(body.name)
            self.link(link, body.inertia)
            self.joint(f"{body.name}_fixed", "fixed", parent, link, offset)
            self.body_links[index] = link
        self.attach_sites(self.body_links[index], body.sites)

    def joint_extra(self, joint: _JointSpec) -> str:
        extra = f"<axis xyz=\"{_texts(joint.axis)}\"/>"
        damping, friction = joint.fields.get("damping"), joint.fields.get("frictionloss")
        if damping or friction:
            extra += "<dynamics" + (f" damping=\"{damping}\"" if damping else "") + \
                (f" friction=\"{friction}\"" if friction else "") + "/>"
        if joint.limits is not None:
            extra += f"<limit lower=\"{number_text(joint.limits[0])}\" upper=\"{number_text(joint.limits[1])}\"/>"
        if "armature" in joint.fields:
            self.joint_fields[joint.name] = {"armature": joint.fields["armature"]}
        return extra

    def attach_sites(self, link: str, sites: list) -> None:
        """A link on a fixed joint per site, named as the site where that name is a valid frame
        name that no body or other site has (else made one: the renames noted)."""
        for k, (name, frame) in enumerate(sites):
            shown = name or f"{link}_site{k + 1}"
            wanted = shown if shown not in self.tree.names else f"{shown}_site"
            child = valid_link_name(wanted, self.links | self.tree.names | self.joint_links)
            self.links.add(child)
            if name:
                self.site_links[name] = child
                if child != name:
                    self.renamed_sites.append((name, child))
            self.link(child)
            self.joint(f"{child}_fixed", "fixed", link, child, frame)


# ---------------------------------------------------------------------------------------------
# Entry point


def read_mjcf(text: str, path: str, frames: list[str] | None = None,
              exact_angles: bool = False) -> tuple[dict, list[str]]:
    """The robot document (``convention: general``) of an MJCF file and the notes of its reading.

    Joints are numbered as MuJoCo numbers them (bodies depth first as written, each body's
    joints in order); a free joint is the floating base (``base: floating``, Pinocchio's
    free-flyer conventions).  Every named ``<site>`` is a frame (``frames:``); ``frames`` adds
    the frames of bodies or sites by name.  Problems raise one-line
    :class:`~symdyn.model.errors.RobotFileError` s; what the equations do not model is one
    warning line."""
    reader = _Reader(text, path)
    _warn_unknown(reader)
    tree = _Bodies(reader)
    if not any(body.joints for body in tree.bodies):
        reader.fail("no body has a joint: nothing moves (give the moving bodies <joint>s, or the robot's root body "
                    "a <freejoint/>)")
    _compiler_bounds(reader, tree.bodies)
    urdf = _Urdf(reader, tree)
    urdf_text = urdf.text()
    wanted = list(urdf.site_links.values())
    body_links = {tree.bodies[k].name: link for k, link in urdf.body_links.items()}
    for name in frames or []:  # a frame's name (a site's, renamed or not), else a site's or a body's in the file
        link = name if name in wanted else urdf.site_links.get(name) or body_links.get(name)
        if link is None:
            known = wanted + list(urdf.site_links) + list(body_links)
            close = difflib.get_close_matches(name, known, n=1)
            reader.fail(f"frame {describe(name)}: no frame (a site) or body of that name in the file"
                        + (f" (did you mean {describe(close[0])}?)" if close else ""))
        if link not in wanted:
            wanted.append(link)
    floating = tree.free is not None
    doc, notes = read_urdf(urdf_text, path, exact_angles=exact_angles, floating_base=floating,
                           frames=wanted or None, whole_tree=True, file_order=True, joint_fields=urdf.joint_fields,
                           quarter_tolerance=0.0, source="MJCF")
    doc["gravity"] = [number_text(g) for g in reader.gravity]
    notes = _notes(reader, tree, urdf, notes)
    _warn_unmodelled(reader)
    return doc, notes


def _notes(reader: _Reader, tree: _Bodies, urdf: _Urdf, notes: list[str]) -> list[str]:
    out = [f"read from MJCF {display_path(os.path.basename(reader.path))}"
           + (f" (with {len(reader.included)} included file{'s' if len(reader.included) > 1 else ''})"
              if reader.included else "")
           + f": {len(tree.bodies)} bod{'y' if len(tree.bodies) == 1 else 'ies'}, joints numbered as MuJoCo numbers "
             "them (bodies depth first as written, each body's joints in order)"
           + ("; a body's joints after its first are joined by massless links"
              if any(len(b.joints) > 1 for b in tree.bodies) else "")]
    if tree.free is not None:
        out.append("the free joint is the floating base with Pinocchio's free-flyer conventions, not MuJoCo's: q = "
                   "(position, quaternion x y z w), v = (linear, angular velocity) in the body frame")
    if any(j.ref != 0 for b in tree.bodies for j in b.joints):
        out.append("joints with ref: q is MuJoCo's qpos (the body sits as written at q = ref)")
    if reader.total_mass > 0:
        out.append(f"settotalmass {float(reader.total_mass):g} kg applied (masses and inertias scaled)")
    out.extend(f"left out: {item}" for item in urdf.dropped)
    if urdf.renamed_sites:
        shown = ", ".join(f"{one_line(a, 40)} -> {b}" for a, b in urdf.renamed_sites[:8])
        more = len(urdf.renamed_sites) - 8
        out.append(f"sites renamed as frames (C identifiers, distinct from the bodies' names): {shown}"
                   + (f" and {more} more" if more > 0 else ""))
    for note in notes[1:]:
        if note.startswith("<dynamics damping friction>"):
            note = "damping and frictionloss read as viscous damping and Coulomb friction (coulomb)"
        elif note.startswith("fixed joints merged"):
            note = "bodies without joints merged into the moving body above them (their inertia added)"
        out.append(note)
    return out


def _plural(what: str, count: int) -> str:
    """``what`` (``"spring|s (stiffness)"``, ``"bod|ies"``) for ``count`` things."""
    stem, _, rest = what.partition("|")
    ending, space, tail = rest.partition(" ")
    singular = "y" if ending == "ies" else ""
    return stem + (ending if count != 1 else singular) + space + tail


def _warn_unmodelled(reader: _Reader) -> None:
    for tag, what in (("actuator", "actuator|s (symdyn's tau is the generalized force: transmissions, gear, gains "
                                   "and limits are the user's)"),
                      ("tendon", "tendon|s"), ("equality", "equality constraint|s"),
                      ("deformable", "deformable object|s (flex, skin)")):
        for section in reader.root.iter(tag):
            count = sum(1 for _ in section)
            if count:
                reader.note_unmodelled(what, count)
    armatures = [e for e in reader.root.iter() if e.tag in ("spatial", "fixed", "general", "motor", "position")
                 and e.get("armature") not in (None, "0")]
    if armatures:
        reader.note_unmodelled("tendon or actuator armature| (MuJoCo adds it to the mass matrix)", len(armatures))
    if reader.large_angles:
        shown = ", ".join(f"{a:g}" for a in reader.large_angles[:4])
        warn(f"{one_line(reader.path, 200)}: angles beyond 2 pi rad ({shown}) where <compiler angle=\"radian\"> says "
             "radians: degrees by mistake? (MuJoCo's default unit is the degree)")
    if reader.unmodelled:
        items = ", ".join(f"{count} {_plural(what, count)}" for what, count in reader.unmodelled.items())
        warn(f"{one_line(reader.path, 200)}: not in the equations of motion: {items}")
