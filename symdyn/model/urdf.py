"""Reading URDF files: a serial chain of a URDF tree as a robot document (the format's general
form, ``convention: general``), which :func:`symdyn.model.robot.from_document` then reads.

XML is parsed with the standard library's expat binding (:mod:`xml.parsers.expat`, the parser
behind :mod:`xml.etree.ElementTree`, kept up to date with Python) building an ElementTree through
:class:`xml.etree.ElementTree.TreeBuilder`.  The expat parser is driven directly because the C
``ElementTree.XMLParser`` does not expose it: its ``StartDoctypeDeclHandler`` and
``EntityDeclHandler`` refuse any DOCTYPE or entity declaration before it is read, so no entity is
ever defined or expanded (no "billion laughs", no external files).  A URDF needs neither.

What is read (see ``docs/urdf.md``), matching Pinocchio's ``buildModelFromUrdf`` for the chain
from the root link to the tip link:

- ``revolute`` and ``continuous`` joints become ``revolute`` (one coordinate: the angle),
  ``prismatic`` stays; ``fixed`` joints are merged; any other joint type or a ``<mimic>`` on the
  chain is refused.  A missing ``<axis>`` is (1, 0, 0), as in the URDF specification and
  Pinocchio; a zero axis is refused.
- A fixed joint's child link is merged into the moving link above it (its inertia moved by the
  fixed transforms, combined by the parallel-axis theorem); the fixed transforms compose into the
  next moving joint's ``origin``, or into the ``tool`` frame after the last moving joint.  Links
  before the first moving joint are fixed to the ground: their inertia is left out.
- Subtrees off the chain are merged into the link they hang from with every joint in them at
  position 0 (moving joints so locked draw a warning), as Pinocchio's ``buildReducedModel`` at
  the neutral configuration does.
- An rpy angle within 1e-9 rad of a multiple of pi/2 is taken as that multiple (URDFs write
  1.57079632679 for pi/2), so that zeros fold exactly.

Numbers are carried exactly: the file's decimal text when a value is used as written, exact
rationals (:class:`fractions.Fraction`, read from the decimal text) when transforms compose with
quarter-turn rotations, and 50-digit floating point (mpmath, written as ``repr(float)``) when
other rotations are involved.
"""

from __future__ import annotations

import difflib
import math
import os
import re
import xml.parsers.expat as expat
from dataclasses import dataclass
from fractions import Fraction
from xml.etree.ElementTree import TreeBuilder

import mpmath
import sympy as sp

from .errors import RobotFileError, describe, display_path, one_line, warn
from .expr import MAX_LITERAL, ExpressionError, number_to_rational
from .robot import FORMAT_VERSION, MAX_ANGLE, MAX_MAGNITUDE, MAX_NAME

#: joint types of the URDF specification
JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
#: the most links (and joints) a URDF may have
MAX_LINKS = 2000
#: an rpy angle this close to a multiple of pi/2 (rad) is taken as that multiple
QUARTER_TOLERANCE = 1e-9
#: digits of the floating-point arithmetic used where rotations are not quarter turns
DIGITS = 50
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")
_NAMES_SHOWN = 6


# ---------------------------------------------------------------------------------------------
# XML


class _Refused(Exception):
    """Raised inside the expat handlers for a construct the reader does not accept."""


def parse_xml(text: str, path: str, kind: str = "a URDF"):
    """The root element of the XML ``text`` (the content of ``path``, ``kind`` of file: a URDF,
    an MJCF); DOCTYPE and entity declarations are refused, and every problem is one
    :class:`RobotFileError` line."""
    builder = TreeBuilder()
    parser = expat.ParserCreate()

    def refuse(what):
        def handler(*_):
            raise _Refused(what)
        return handler
    parser.StartDoctypeDeclHandler = refuse("a DOCTYPE declaration")
    parser.EntityDeclHandler = refuse("an entity declaration")
    parser.UnparsedEntityDeclHandler = refuse("an entity declaration")
    parser.ExternalEntityRefHandler = refuse("an external entity")
    parser.StartElementHandler = builder.start
    parser.EndElementHandler = builder.end
    parser.CharacterDataHandler = builder.data
    parser.buffer_text = True
    try:
        parser.Parse(text, True)
        return builder.close()
    except _Refused as exc:
        raise RobotFileError(path, f"not accepted: the file has {exc} (line {parser.CurrentLineNumber}); "
                                   f"{kind} needs none, and they are refused so that no entity is ever "
                                   "expanded") from None
    except expat.ExpatError as exc:
        raise RobotFileError(path, f"not valid XML (line {exc.lineno}, column {exc.offset + 1}): "
                                   f"{expat.ErrorString(exc.code)}") from None
    except RecursionError:
        raise RobotFileError(path, "not accepted: elements nested too deeply") from None


# ---------------------------------------------------------------------------------------------
# Numbers and frames


def quarter_text(k: int) -> str:
    """``k * pi/2`` as an expression the robot format reads: 0, pi/2, -pi, 3*pi/2 ..."""
    if k == 0:
        return "0"
    if k % 2 == 0:
        half = k // 2
        return "pi" if half == 1 else "-pi" if half == -1 else f"{half}*pi"
    return "pi/2" if k == 1 else "-pi/2" if k == -1 else f"{k}*pi/2"


@dataclass(frozen=True)
class Quarter:
    """The angle ``k * pi/2`` (exact)."""

    k: int

    def __float__(self) -> float:
        return self.k * math.pi / 2


_MP = mpmath.MPContext()  # a private context: the module never changes mpmath's global precision
_MP.dps = DIGITS
_SNAP = _MP.mpf("1e-30")


def _mp(value):
    """``value`` (int, Fraction, Quarter, 50-digit float or SymPy number) as a 50-digit float."""
    if isinstance(value, Quarter):
        return value.k * _MP.pi / 2
    if isinstance(value, Fraction):
        return _MP.mpf(value.numerator) / value.denominator
    if isinstance(value, (int, _MP.mpf)):
        return _MP.mpf(value)
    return _MP.mpf(str(sp.sympify(value).evalf(DIGITS + 10)))


def number_text(value) -> str:
    """A number as robot-file text: a :class:`Quarter` or a multiple of pi/2 by
    :func:`quarter_text`; an exact rational (int, Fraction, SymPy Rational) as its exact text (an
    integer, a terminating decimal or ``p/q``) when that is no longer than the shortest decimal
    that reads back to the same double, else as that decimal (``repr(float)``: a merged link's
    mass ``94812479387383249/8067700000000000000`` is written ``0.011752...``); anything else as
    ``repr(float)`` (0 below 1e-40)."""
    if isinstance(value, Quarter):
        return quarter_text(value.k)
    if isinstance(value, sp.Basic):
        value = sp.sympify(value)
        ratio = value / (sp.pi / 2)
        if value != 0 and ratio.is_Rational and ratio.q == 1:
            return quarter_text(int(ratio))
        if value.is_Rational:
            value = Fraction(int(value.p), int(value.q))
    number = float(_mp(value))
    shortest = "0" if abs(number) < 1e-40 else repr(number)
    if isinstance(value, (int, Fraction)):
        exact = _exact_text(Fraction(value))
        if exact is not None and len(exact) <= max(len(shortest), 3):
            return exact
    return shortest


def _exact_text(value: Fraction) -> str | None:
    """An integer, a terminating decimal or ``p/q``, exactly; None beyond MAX_LITERAL digits."""
    p, q = value.numerator, value.denominator
    if q == 1:
        return str(p) if len(str(p)) <= MAX_LITERAL else None
    rest, twos, fives = q, 0, 0
    while rest % 2 == 0:
        rest, twos = rest // 2, twos + 1
    while rest % 5 == 0:
        rest, fives = rest // 5, fives + 1
    if rest == 1:
        places = max(twos, fives)
        digits = str(abs(p) * 10 ** places // q).rjust(places + 1, "0")
        text = f"{'-' if p < 0 else ''}{digits[:-places]}.{digits[-places:]}"
        if len(text) <= MAX_LITERAL:
            return text
    if len(str(abs(p))) <= MAX_LITERAL and len(str(q)) <= MAX_LITERAL:
        return f"{p}/{q}"
    return None


_ZERO, _ONE = Fraction(0), Fraction(1)
_I3 = ((_ONE, _ZERO, _ZERO), (_ZERO, _ONE, _ZERO), (_ZERO, _ZERO, _ONE))
_Z3 = ((_ZERO,) * 3,) * 3


def _cos_sin(angle) -> tuple:
    """Exact cos and sin of a multiple of pi/2 (a :class:`Quarter` or 0), else 50-digit values."""
    if isinstance(angle, Quarter):
        return ((_ONE, _ZERO), (_ZERO, _ONE), (-_ONE, _ZERO), (_ZERO, -_ONE))[angle.k % 4]
    if angle == 0:
        return _ONE, _ZERO
    value = _mp(angle)
    return _MP.cos(value), _MP.sin(value)


def _times(a, b):
    """``a * b``, skipping the work for exact 0 and +-1 (most rotation entries)."""
    for x, y in ((a, b), (b, a)):
        if type(x) is Fraction and x.denominator == 1 and -1 <= x <= 1:
            return x if x == 0 else y if x == 1 else -y
    return a * b


def _dot(row, column):
    total = _ZERO
    for x, y in zip(row, column):
        term = _times(x, y)
        if not (type(term) is Fraction and term == 0):
            total = term if (type(total) is Fraction and total == 0) else total + term
    return total


def _mul(A, B):
    """Product of two 3x3 matrices (tuples of rows)."""
    columns = tuple(zip(*B))
    return tuple(tuple(_dot(row, column) for column in columns) for row in A)


def _apply(A, v):
    return tuple(_dot(row, v) for row in A)


def _transpose(A):
    return tuple(zip(*A))


def rpy_rotation(rpy) -> tuple:
    """``Rz(yaw) Ry(pitch) Rx(roll)`` as a 3x3 tuple of rows; angles are Fractions (rad) or
    :class:`Quarter` s, and the entries exact (Fractions) for quarter turns, else 50-digit."""
    (cr, sr), (cp, spt), (cy, sy) = (_cos_sin(a) for a in rpy)
    rx = ((_ONE, _ZERO, _ZERO), (_ZERO, cr, -sr), (_ZERO, sr, cr))
    ry = ((cp, _ZERO, spt), (_ZERO, _ONE, _ZERO), (-spt, _ZERO, cp))
    rz = ((cy, -sy, _ZERO), (sy, cy, _ZERO), (_ZERO, _ZERO, _ONE))
    return _mul(rz, _mul(ry, rx))


@dataclass(frozen=True)
class Frame:
    """A rigid transform: rotation ``R`` (3x3 tuple of rows) and translation ``t`` (3-tuple) of
    exact Fractions, or 50-digit floats where rotations are not quarter turns."""

    R: tuple = _I3
    t: tuple = (_ZERO, _ZERO, _ZERO)

    @staticmethod
    def of(xyz, rpy) -> "Frame":
        """The frame of a URDF ``<origin xyz rpy>`` (Fractions; angles may be Quarters)."""
        return Frame(rpy_rotation(rpy), tuple(xyz))

    def __mul__(self, other: "Frame") -> "Frame":
        moved = _apply(self.R, other.t)
        return Frame(_mul(self.R, other.R), tuple(a + b for a, b in zip(moved, self.t)))

    @property
    def is_identity(self) -> bool:
        return all(self.R[i][j] == (1 if i == j else 0) for i in range(3) for j in range(3)) and \
            all(v == 0 for v in self.t)

    def texts(self) -> dict:
        """``{xyz: [...], rpy: [...]}`` (robot-file texts) of this frame."""
        return {"xyz": [number_text(v) for v in self.t], "rpy": [number_text(a) for a in matrix_rpy(self.R)]}


def _snap(angle):
    """``angle`` (50-digit) as a :class:`Quarter` when it is one to 30 digits, else as is."""
    k = round(float(angle) / (math.pi / 2))
    return Quarter(k) if abs(angle - k * _MP.pi / 2) < _SNAP else angle


def matrix_rpy(rotation) -> tuple:
    """Roll, pitch, yaw of a 3x3 rotation (rows, or a SymPy matrix) with
    ``R = Rz(yaw) Ry(pitch) Rx(roll)``: each a :class:`Quarter` when it is a multiple of pi/2 (to
    30 digits), else a 50-digit mpmath float.  At pitch = +-pi/2 (gimbal lock) yaw is 0 and roll
    carries the turn about z."""
    if hasattr(rotation, "shape"):
        rotation = [[rotation[i, j] for j in range(3)] for i in range(3)]
    R = [[_mp(e) for e in row] for row in rotation]
    if abs(R[2][0]) >= 1 - _SNAP:
        if R[2][0] < 0:  # pitch = pi/2: R[0][1] = sin(roll - yaw), R[1][1] = cos(roll - yaw)
            return _snap(_MP.atan2(R[0][1], R[1][1])), Quarter(1), Quarter(0)
        return _snap(_MP.atan2(-R[0][1], R[1][1])), Quarter(-1), Quarter(0)  # roll + yaw
    pitch = _MP.atan2(-R[2][0], _MP.sqrt(R[0][0] ** 2 + R[1][0] ** 2))
    return _snap(_MP.atan2(R[2][1], R[2][2])), _snap(pitch), _snap(_MP.atan2(R[1][0], R[0][0]))


@dataclass
class _Origin:
    """A URDF ``<origin>``: exact values, the texts to write when it is used as it stands, and
    its frame."""

    xyz: tuple
    rpy: tuple
    texts: dict
    frame: Frame

    @property
    def is_identity(self) -> bool:
        return all(v == 0 for v in (*self.xyz, *self.rpy))


@dataclass
class _Body:
    """Mass, COM (3-tuple) and inertia about the COM (3x3 rows) in one frame; ``texts`` holds
    the file's own texts (mass, com, inertia) while the values are as read."""

    mass: Fraction
    com: tuple
    inertia: tuple
    texts: tuple | None = None

    @property
    def is_empty(self) -> bool:
        return self.mass == 0 and all(e == 0 for row in self.inertia for e in row)

    def moved(self, frame: Frame) -> "_Body":
        """The body seen from a frame in which its own frame sits at ``frame``."""
        if frame.is_identity or self.is_empty:
            return self
        com = tuple(a + b for a, b in zip(_apply(frame.R, self.com), frame.t))
        return _Body(self.mass, com, _mul(frame.R, _mul(self.inertia, _transpose(frame.R))))

    def plus(self, other: "_Body") -> "_Body":
        """Both bodies as one rigid body (parallel-axis theorem)."""
        if other.is_empty:
            return self
        if self.is_empty:
            return other
        mass = self.mass + other.mass
        if mass == 0:
            return _Body(mass, (_ZERO,) * 3, tuple(tuple(a + b for a, b in zip(r1, r2))
                                                   for r1, r2 in zip(self.inertia, other.inertia)))
        com = tuple((self.mass * a + other.mass * b) / mass for a, b in zip(self.com, other.com))
        inertia = [[_ZERO] * 3 for _ in range(3)]
        for body in (self, other):
            d = [c + -m for c, m in zip(body.com, com)]  # (Fraction - mpf is not defined)
            square = d[0] ** 2 + d[1] ** 2 + d[2] ** 2
            for i in range(3):
                for j in range(3):
                    inertia[i][j] += body.inertia[i][j] + body.mass * ((square if i == j else 0) + -(d[i] * d[j]))
        return _Body(mass, com, tuple(tuple(row) for row in inertia))

    def fields(self) -> dict:
        if self.texts is not None:
            mass, com, inertia = self.texts
            return {"mass": mass, "com": list(com), "inertia": list(inertia)}
        I = self.inertia
        return {"mass": number_text(self.mass), "com": [number_text(c) for c in self.com],
                "inertia": [number_text(I[i][j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))]}


_EMPTY = _Body(_ZERO, (_ZERO,) * 3, _Z3, ("0", ("0", "0", "0"), ("0",) * 6))


# ---------------------------------------------------------------------------------------------
# The URDF tree


@dataclass
class _Joint:
    name: str
    type: str
    parent: str
    child: str
    origin: _Origin
    element: object
    index: int


def _hint(name: str, known) -> str:
    """``; did you mean 'x'?`` for the known name closest to ``name`` (names of at most 200
    characters are compared, so that the work stays small), or nothing."""
    if len(name) > 200:
        return ""
    close = difflib.get_close_matches(name, [k for k in known if len(k) <= 200], n=1, cutoff=0.6)
    return f"; did you mean {describe(close[0])}?" if close else ""


def _names(names, limit: int = _NAMES_SHOWN) -> str:
    """A bounded list of quoted names for messages."""
    names = list(names)
    shown = ", ".join(describe(n, 60) for n in names[:limit])
    return shown + (f" and {len(names) - limit} more" if len(names) > limit else "")


class _Reader:
    """One URDF file's links and joints, and the chain from its root to a tip."""

    def __init__(self, text: str, path: str, exact_angles: bool = False, file_order: bool = False,
                 joint_fields: dict | None = None, quarter_tolerance: float = QUARTER_TOLERANCE,
                 source: str = "URDF"):
        self.path = path
        self.source = source  # the format the file was written from (a URDF made from an MJCF: "MJCF")
        self.exact_angles = exact_angles
        self.quarter_tolerance = quarter_tolerance
        self.file_order = file_order  # a link's joints in the file's order (else by name, as Pinocchio's URDF reader)
        self.joint_fields = joint_fields or {}  # moving joint -> more fields of its link (armature)
        self.snapped: list[str] = []  # the rpy texts taken as exact quarter turns
        root = parse_xml(text, path)
        if root.tag != "robot":
            self.fail(f"the top element is <{one_line(root.tag, 40)}>, not <robot>: not a URDF file")
        name = root.get("name")
        if name is None:
            self.fail("the <robot> element has no name attribute")
        self.robot_name = name
        self.link_of_joint: dict[str, str] = {}  # moving joint -> its link's name in the robot document
        self.renamed: list[tuple[str, str]] = []  # (URDF joint name, the link's name): said once, listed in full
        self.unfollowed: list[str] = []  # mimic joints whose leader is not in the file: read free, said once
        self.links: dict[str, object] = {}
        self.joints: dict[str, _Joint] = {}
        self.bodies: dict[str, _Body] = {}
        for element in root:
            if element.tag == "link":
                link = self.name_of(element, "link")
                if link in self.links:
                    self.fail(f"two links are named {describe(link)}", f"link {describe(link)}")
                self.links[link] = element
            elif element.tag == "joint":
                joint = self.read_joint(element, len(self.joints))
                if joint.name in self.joints:
                    self.fail(f"two joints are named {describe(joint.name)}", f"joint {describe(joint.name)}")
                self.joints[joint.name] = joint
            if len(self.links) > MAX_LINKS or len(self.joints) > MAX_LINKS:
                self.fail(f"more than {MAX_LINKS} links or joints: not accepted")
        if not self.links:
            self.fail("the file has no <link>")
        self.parent_joint: dict[str, _Joint] = {}
        self.child_joints: dict[str, list[_Joint]] = {name: [] for name in self.links}
        self.tip_note = ""  # how the tip was found when the file does not say
        for joint in self.joints.values():
            for role in ("parent", "child"):
                link = getattr(joint, role)
                if link not in self.links:
                    self.fail(f"{role} link {describe(link)} is not a link of the file{_hint(link, self.links)}",
                              self.where(joint), role)
            if joint.child in self.parent_joint:
                self.fail(f"link {describe(joint.child)} is the child of two joints "
                          f"({describe(self.parent_joint[joint.child].name)} and {describe(joint.name)}): "
                          "a URDF is a tree", self.where(joint), "child")
            self.parent_joint[joint.child] = joint
            self.child_joints[joint.parent].append(joint)
        roots = [name for name in self.links if name not in self.parent_joint]
        if not roots:
            self.fail("every link is the child of a joint: the joints form a cycle (a URDF is a tree "
                      "with one root link)")
        if len(roots) > 1:
            self.fail(f"{len(roots)} root links ({_names(roots)}): a URDF is one tree, with one link "
                      "that is no joint's child")
        self.root = roots[0]
        reached, stack = {self.root}, [self.root]
        while stack:
            for joint in self.child_joints[stack.pop()]:
                if joint.child not in reached:
                    reached.add(joint.child)
                    stack.append(joint.child)
        lost = [name for name in self.links if name not in reached]
        if lost:
            self.fail(f"links {_names(lost)} are not connected to the root link {describe(self.root)}: "
                      "their joints form a cycle")

    # -- messages

    def fail(self, reason: str, where: str | None = None, attribute: str | None = None):
        raise RobotFileError(self.path, reason, link=where, field=attribute)

    def warn(self, reason: str, where: str | None = None, attribute: str | None = None) -> None:
        parts = [one_line(self.path, 200)] + ([one_line(where, 120)] if where else []) + \
            ([f"field '{one_line(attribute, 80)}'"] if attribute else [])
        warn(f"{': '.join(parts)}: {reason}")

    @staticmethod
    def where(joint: _Joint) -> str:
        return f"joint {describe(joint.name)}"

    # -- elements

    def name_of(self, element, kind: str) -> str:
        name = element.get("name")
        if not name:
            self.fail(f"<{kind}> number {len(self.links if kind == 'link' else self.joints) + 1} of the file "
                      "has no name")
        return name

    def number(self, text: str, where: str, attribute: str) -> tuple[Fraction, str]:
        """The exact value and the text of one number of an attribute."""
        if not _NUMBER.match(text):
            self.fail(f"{describe(text)} is not a decimal number", where, attribute)
        try:
            value = number_to_rational(text)  # checks the literal's length and exponent
        except ExpressionError as exc:
            self.fail(str(exc), where, attribute)
        if abs(value) > int(MAX_MAGNITUDE):
            self.fail(f"{describe(text)} is too large (more than 1e100 in magnitude): check the units",
                      where, attribute)
        return Fraction(int(value.p), int(value.q)), text.lstrip("+")

    def numbers(self, element, attribute: str, count: int, default: str | None, where: str,
                label: str) -> list[tuple[Fraction, str]]:
        """The ``count`` numbers of ``element``'s ``attribute`` (``default`` when absent)."""
        text = element.get(attribute) if element is not None else None
        if text is None:
            if default is None:
                self.fail("missing attribute", where, label)
            text = default
        parts = text.split()
        if len(parts) != count:
            self.fail(f"expected {count} number{'s' if count > 1 else ''}, got {describe(one_line(text, 60))}",
                      where, label)
        return [self.number(part, where, label) for part in parts]

    def origin(self, element, where: str, label: str) -> _Origin:
        """An ``<origin xyz rpy>`` (absent: identity), angles near quarter turns made exact."""
        xyz = self.numbers(element, "xyz", 3, "0 0 0", where, f"{label} xyz")
        rpy = []
        for value, text in self.numbers(element, "rpy", 3, "0 0 0", where, f"{label} rpy"):
            if abs(value) > MAX_ANGLE:
                self.fail(f"angle {describe(text)} is larger than {MAX_ANGLE:g} rad", where, f"{label} rpy")
            k = round(float(value) / (math.pi / 2))
            if not self.exact_angles and abs(float(value) - k * math.pi / 2) <= self.quarter_tolerance:
                rpy.append((Quarter(k) if k else _ZERO, quarter_text(k)))
                if float(value) != k * math.pi / 2 and text not in self.snapped:
                    self.snapped.append(text)
            else:
                rpy.append((value, text))
        values = tuple(v for v, _ in xyz), tuple(v for v, _ in rpy)
        return _Origin(*values, {"xyz": [t for _, t in xyz], "rpy": [t for _, t in rpy]}, Frame.of(*values))

    def read_joint(self, element, index: int) -> _Joint:
        name = self.name_of(element, "joint")
        where = f"joint {describe(name)}"
        kind = element.get("type")
        if kind not in JOINT_TYPES:
            self.fail(f"unknown joint type {describe(kind)} (URDF has {', '.join(JOINT_TYPES)})", where, "type")
        links = {}
        for role in ("parent", "child"):
            item = element.find(role)
            if item is None or not item.get("link"):
                self.fail(f"missing <{role} link=...>", where, role)
            links[role] = item.get("link")
        if links["parent"] == links["child"]:
            self.fail(f"the joint connects link {describe(links['parent'])} to itself", where, "child")
        origin = self.origin(element.find("origin"), where, "origin")
        return _Joint(name, kind, links["parent"], links["child"], origin, element, index)

    def body(self, link: str) -> _Body:
        """A link's ``<inertial>`` in the link frame (none: no mass)."""
        if link in self.bodies:
            return self.bodies[link]
        inertial = self.links[link].find("inertial")
        where = f"link {describe(link)}"
        if inertial is None:
            body = _EMPTY
        else:
            mass_element = inertial.find("mass")
            if mass_element is None:
                self.fail("<inertial> without <mass value=...>", where, "inertial mass")
            (mass, mass_text), = self.numbers(mass_element, "value", 1, None, where, "inertial mass value")
            if mass < 0:
                self.fail(f"mass must not be negative, got {describe(mass_text)}", where, "inertial mass value")
            inertia_element = inertial.find("inertia")
            if inertia_element is None:
                self.fail("<inertial> without <inertia ixx=... iyy=... izz=... ixy=... ixz=... iyz=...>",
                          where, "inertial inertia")
            values = [self.numbers(inertia_element, key, 1, None, where, f"inertial inertia {key}")[0]
                      for key in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")]
            xx, yy, zz, xy, xz, yz = (v for v, _ in values)
            frame = self.origin(inertial.find("origin"), where, "inertial origin")
            inertia = ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz))
            if all(a == 0 for a in frame.rpy):
                body = _Body(mass, frame.xyz, inertia, (mass_text, tuple(frame.texts["xyz"]),
                                                        tuple(t for _, t in values)))
            else:
                body = _Body(mass, (_ZERO,) * 3, inertia).moved(Frame(frame.frame.R))
                body = _Body(mass, frame.xyz, body.inertia)
        self.bodies[link] = body
        return body

    # -- the chain

    def tip(self, tip: str | None) -> str:
        if tip is not None:
            if tip not in self.links:
                self.fail(f"tip link {describe(tip)} is not a link of the file{_hint(tip, self.links)}")
            return tip
        leaves = [name for name in self.links if not self.child_joints[name]]
        if len(leaves) == 1:
            return leaves[0]
        end = self.moving_chain_end()
        if end is not None:
            others = [leaf for leaf in leaves if leaf != end]
            self.tip_note = (f"tip: {one_line(end, 60)}, the link of the last moving joint (the moving joints form one "
                             f"chain; {_names(others)} hang{'s' if len(others) == 1 else ''} on fixed joints only and "
                             f"{'is' if len(others) == 1 else 'are'} merged; --tool LINK makes one the tool frame)")
            return end
        self.fail(f"the tree has {len(leaves)} leaf links ({_names(leaves)}) and moving joints on more than one "
                  "branch: choose one with --tip LINK (or `tip:` in a scene) to say where the chain ends")

    def moving_chain_end(self) -> str | None:
        """The child link of the last moving (non-fixed) joint when the moving joints all lie on
        one path from the root (every other branch holds fixed joints only), else None."""
        moves: dict[str, bool] = {}  # whether a link's subtree holds a moving joint
        stack = [(self.root, False)]  # iterative post-order: deep trees do not recurse
        while stack:
            name, done = stack.pop()
            if done:
                moves[name] = any(j.type != "fixed" or moves[j.child] for j in self.child_joints[name])
            elif name not in moves:
                stack.append((name, True))
                stack.extend((j.child, False) for j in self.child_joints[name])
        link, end = self.root, None
        while True:
            onward = [j for j in self.child_joints[link] if j.type != "fixed" or moves[j.child]]
            if not onward:
                return end
            if len(onward) > 1:
                return None
            if onward[0].type != "fixed":
                end = onward[0].child
            link = onward[0].child

    def chain(self, tip: str) -> list[_Joint]:
        """The joints from the root to ``tip``."""
        joints, link = [], tip
        while link in self.parent_joint:
            joints.append(self.parent_joint[link])
            link = joints[-1].parent
        return joints[::-1]


# ---------------------------------------------------------------------------------------------
# Names


def _renamed_note(urdf: "_Reader", notes: list) -> None:
    """One warning for every joint whose name was changed, and a note (the generated header lists
    the notes) with each full URDF name beside the name used."""
    if not urdf.renamed:
        return
    urdf.warn(f"{len(urdf.renamed)} joint name{'s' if len(urdf.renamed) > 1 else ''} changed (link names: letters, "
              f"digits and '_', at most {MAX_NAME} characters, distinct): "
              + ", ".join(f"{describe(full)} -> '{short}'" for full, short in urdf.renamed[:3])
              + (", ..." if len(urdf.renamed) > 3 else ""))
    notes.append("joints renamed (URDF name -> name here): "
                 + "; ".join(f"{one_line(full, 200)} -> {short}" for full, short in urdf.renamed))


def valid_link_name(name: str, taken: set) -> str:
    """A valid link name (a C identifier of at most 31 characters) for ``name``, not in ``taken``."""
    return _link_name(name, taken)


def _link_name(name: str, taken: set) -> str:
    """A valid, unused link name for the URDF joint ``name``."""
    out = re.sub(r"[^A-Za-z0-9_]", "_", name) or "_"
    if out[0].isdigit():
        out = "_" + out
    out = out[:MAX_NAME]
    candidate, k = out, 2
    while candidate in taken:
        suffix = f"_{k}"
        candidate, k = out[:MAX_NAME - len(suffix)] + suffix, k + 1
    return candidate


def _robot_name(name: str) -> str:
    out = re.sub(r"[^a-z0-9_]", "_", name.lower())
    if not out or not ("a" <= out[0] <= "z"):
        out = "robot_" + out if out else "robot"
    return out[:MAX_NAME]


# ---------------------------------------------------------------------------------------------
# The document


def reads_as_tree(text: str, path: str) -> bool:
    """Whether :func:`read_urdf` without a tip reads this URDF as its whole tree (its moving
    joints branch)."""
    return _branches(_Reader(text, path, False))


def default_tip(text: str, path: str) -> str:
    """The link a URDF's chain ends at when no tip is given: the only leaf, or the link of the
    last moving joint when the moving joints form one chain and the other leaves hang on fixed
    joints only (a :class:`RobotFileError` otherwise)."""
    return _Reader(text, path, False).tip(None)


def read_urdf(text: str, path: str, tip: str | None = None, tool: str | None = None,
              exact_angles: bool = False, floating_base: bool = False,
              frames: list[str] | None = None, whole_tree: bool = False, file_order: bool = False,
              joint_fields: dict | None = None, quarter_tolerance: float = QUARTER_TOLERANCE,
              source: str = "URDF") -> tuple[dict, list[str]]:
    """:func:`read_chain_or_tree`, with ``frames`` (URDF link names, in order) as the
    document's ``frames:``: each link's frame on the moving link it is rigidly attached to (a
    link merged by fixed joints, such as a foot; or the child link of a moving joint, whose own
    frame it is), or on the base.  For a URDF made from another format
    (:mod:`symdyn.model.mjcf`): ``whole_tree`` reads the tree even when it is a chain,
    ``file_order`` numbers each link's joints as the file orders them, and ``joint_fields``
    adds fields (armature) to the links of the moving joints it names; ``quarter_tolerance``
    (rad): how near a multiple of pi/2 an rpy angle is taken as one (0: only the double nearest
    it, which is what a URDF made from exact rotations writes); ``source``: the format the URDF
    was made from (only a URDF's fixed root with branches draws the --floating-base hint)."""
    urdf = _Reader(text, path, exact_angles, file_order, joint_fields, quarter_tolerance, source)
    doc, notes = read_chain_or_tree(urdf, tip, tool, floating_base, whole_tree)
    if frames:
        doc["frames"] = _frame_entries(urdf, frames, {link["name"] for link in doc["links"]})
    return doc, notes


def _frame_entries(urdf: _Reader, names, link_names: set) -> list:
    """The ``frames:`` entries of URDF links ``names``: the link's frame in the frame of the
    moving link it hangs on through fixed joints (a moving joint off a chain read with a tip
    counts at position 0, as it is locked there), or of the base (the root link)."""
    entries, seen = [], set()
    for name in names:
        if name not in urdf.links:
            urdf.fail(f"frame {describe(name)}: no link of that name in the file{_hint(name, urdf.links)}")
        frame, link, owner = Frame(), name, "base"
        while (joint := urdf.parent_joint.get(link)) is not None:
            if joint.type != "fixed" and joint.name in urdf.link_of_joint:
                owner = urdf.link_of_joint[joint.name]
                break
            frame = joint.origin.frame * frame
            link = joint.parent
        shown = _link_name(name, set())
        if shown in link_names and not (shown == owner and frame.is_identity):
            shown = _link_name(f"{shown}_frame", link_names)  # not to hide a link's own frame
        if shown in seen:
            urdf.fail(f"frame {describe(name)} is asked for twice")
        seen.add(shown)
        if shown == owner and frame.is_identity:
            entries.append(shown)
        else:
            entries.append({"name": shown, "link": owner, **frame.texts()})
    return entries


def read_chain_or_tree(urdf: "_Reader", tip: str | None = None, tool: str | None = None,
                       floating_base: bool = False, whole_tree: bool = False) -> tuple[dict, list[str]]:
    """The robot document (``convention: general``, see ``docs/urdf.md``) of the chain of a URDF
    from its root link to ``tip`` (default: the only leaf), and notes saying what was merged,
    locked or left out.  ``tool``: a link rigidly attached to the last moving link whose frame is
    the tool frame (default: the tip's frame when fixed joints lead to it).  ``urdf`` is the
    file as read (its path names it in messages; made with ``exact_angles``: keep every rpy
    angle as written, else angles within :data:`QUARTER_TOLERANCE` of a multiple of pi/2 are
    taken as that multiple, so that zeros fold).  Problems raise :class:`RobotFileError` (one
    line); doubtful readings give a :func:`~symdyn.model.errors.warn` line.  ``floating_base``:
    the whole tree on a free-floating root link (:func:`read_tree`; no tip or tool then);
    ``whole_tree``: the tree even when it is one chain."""
    path = urdf.path
    name = _robot_name(urdf.robot_name)
    if name != urdf.robot_name:
        urdf.warn(f"{describe(urdf.robot_name)} renamed '{name}' (robot names: a-z, 0-9 and '_', at most "
                  f"{MAX_NAME} characters)", None, "robot name")
    if whole_tree:
        return read_tree(urdf, name, floating=floating_base)
    if floating_base:
        if tip is not None or tool is not None:
            urdf.fail("--floating-base reads the whole tree on its free root link: --tip and --tool do not apply")
        return read_tree(urdf, name, floating=True)  # (no moving joint: one free body, a drone)
    if tip is None and _branches(urdf):
        if tool is not None:
            urdf.fail("--tool needs a chain: this file's moving joints branch (give --tip LINK to choose one chain)")
        return read_tree(urdf, name)
    tip, chain, on_chain, moving = _moving_chain(urdf, tip)

    notes = [f"read from URDF {display_path(os.path.basename(path))}: chain {one_line(urdf.root, 60)} -> "
             f"{one_line(tip, 60)}, "
             f"{len(moving)} moving joint{'s' if len(moving) != 1 else ''}"] + ([urdf.tip_note] if urdf.tip_note else [])
    links: list[dict] = []
    bodies: list[_Body] = []  # of each moving link, in its frame
    ground = {"body": _EMPTY, "links": []}
    locked: dict[int, list] = {}  # target (-1: ground) -> [joint names, mass]
    rigid: dict[int, list] = {}  # target -> off-chain links merged through fixed joints only
    fixed_merged: list[str] = []
    taken: set = set()
    pending = Frame()  # current link in the frame of the last moving link (or the root)
    pending_joints: list[_Joint] = []

    def absorb(link: str, frame: Frame) -> None:
        """Merge ``link`` (at ``frame``) and every subtree off the chain hanging from it into
        the current moving link (or the ground)."""
        target = len(bodies) - 1
        body = urdf.body(link).moved(frame)
        for joint in urdf.child_joints[link]:
            if joint.name in on_chain:
                continue
            stack, names, mass = [(joint, frame)], [], _ZERO
            while stack:
                j, above = stack.pop()
                if j.type != "fixed":
                    names.append(j.name)
                at = above * j.origin.frame  # a moving joint at position 0
                part = urdf.body(j.child)
                mass += part.mass
                body = body.plus(part.moved(at))
                stack.extend((c, at) for c in reversed(urdf.child_joints[j.child]))
            if names:
                entry = locked.setdefault(target, [[], _ZERO])
                entry[0].extend(sorted(names, key=lambda n: urdf.joints[n].index))
                entry[1] += mass
            else:
                rigid.setdefault(target, []).append(joint.child)
        if target < 0:
            ground["body"] = ground["body"].plus(body)
            ground["links"].append(link)
        else:
            bodies[target] = bodies[target].plus(body)

    absorb(urdf.root, pending)
    dynamics = False
    for joint in chain:
        if joint.type == "fixed":
            pending = pending * joint.origin.frame
            pending_joints.append(joint)
            if bodies and not urdf.body(joint.child).is_empty:
                fixed_merged.append(joint.name)
            absorb(joint.child, pending)
            continue
        entry, extra = _joint_entry(urdf, joint, pending, pending_joints, taken)
        dynamics = dynamics or any(key in extra for key in ("damping", "coulomb"))
        links.append((entry, extra))
        bodies.append(_EMPTY)
        pending, pending_joints = Frame(), []
        absorb(joint.child, pending)

    mimics = _resolve_mimics(urdf, links, f"off the chain to {describe(tip)}")
    _mimic_note(mimics, notes, urdf.unfollowed)
    last = moving[-1]
    doc = {"format": FORMAT_VERSION, "name": name, "convention": "general", "gravity": [0, 0, "-9.81"]}
    _tool_field(urdf, doc, tool, last, pending, pending_joints, tip, notes)
    doc["links"] = []
    for (entry, extra), body in zip(links, bodies):
        doc["links"].append({**entry, **body.fields(), **extra})

    _merge_notes(urdf, tip, chain, moving, links, ground, rigid, locked, fixed_merged, dynamics, notes)
    return doc, notes


def _tool_field(urdf: "_Reader", doc: dict, tool: str | None, last, pending: "Frame", pending_joints: list, tip: str,
                notes: list) -> None:
    """Set ``doc['tool']``: the frame of link ``tool`` on the last moving joint's link, or, without
    one, the fixed joints after it to the tip (a note appended to ``notes``)."""
    if tool is not None:
        tool_frame = _tool_frame(urdf, tool, last)
        if tool_frame is not None:
            doc["tool"] = tool_frame
        notes.append(f"tool frame: link {one_line(tool, 60)}")
    elif pending_joints and not pending.is_identity:
        if len(pending_joints) == 1:
            doc["tool"] = {"xyz": list(pending_joints[0].origin.texts["xyz"]),
                           "rpy": list(pending_joints[0].origin.texts["rpy"])}
        else:
            doc["tool"] = pending.texts()
        notes.append(f"tool frame: tip link {one_line(tip, 60)}")


def _merge_notes(urdf: "_Reader", tip: str, chain, moving, links, ground, rigid, locked, fixed_merged, dynamics: bool,
                 notes: list) -> None:
    """Append to ``notes`` (and warn about) what reading the chain merged, locked, composed or
    left out (:func:`read_chain_or_tree`'s bookkeeping)."""
    continuous = [j.name for j in moving if j.type == "continuous"]
    if continuous:
        notes.append(f"continuous joints read as revolute (the angle is the coordinate): {_plain(continuous)}")
    if fixed_merged:
        notes.append(f"fixed joints merged (child inertia added to the moving link above): {_plain(fixed_merged)}")
    before = [j.name for j in chain[:chain.index(moving[0])]]
    if before:
        notes.append(f"fixed joints before the first moving joint composed into its origin: {_plain(before)}")
    ground_mass = ground["body"].mass
    if ground_mass != 0 or rigid.get(-1) or locked.get(-1):
        notes.append(f"fixed to the ground, inertia left out ({_kg(ground_mass)} kg): links "
                     f"{_plain(ground['links'] + rigid.get(-1, []))}")
    for target, names in sorted(rigid.items()):
        if target >= 0:
            notes.append(f"off the chain, merged rigidly into {links[target][0]['name']}: links {_plain(names)}")
    for target, (names, mass) in sorted(locked.items()):
        into = "left out with the fixed base" if target < 0 else \
            f"carried rigidly by link {target + 1} ('{links[target][0]['name']}')"
        urdf.warn(f"joints {_names(names)} are off the chain to {describe(tip)}: locked at 0, their links "
                  f"({_kg(mass)} kg) {into}")
        notes.append(f"off the chain, locked at 0 and {into}: joints {_plain(names)}")
    if dynamics:
        notes.append("<dynamics damping friction> read as viscous damping and Coulomb friction (coulomb)")
    _renamed_note(urdf, notes)
    if urdf.snapped:
        notes.append(f"rpy angles within {QUARTER_TOLERANCE:g} rad of a multiple of pi/2 taken as that multiple "
                     f"(--exact-angles keeps them as written): {_plain(urdf.snapped)}")
def _moving_chain(urdf: "_Reader", tip: str | None):
    """``(tip, chain, on_chain, moving)``: the tip link, the joints from the root to it, their
    names, and the moving ones among them (at least one, each checked)."""
    tip = urdf.tip(tip)
    chain = urdf.chain(tip)
    on_chain = {j.name for j in chain}
    for joint in chain:
        _check_moving(urdf, joint, f"on the chain from {describe(urdf.root)} to {describe(tip)}")
    moving = [j for j in chain if j.type != "fixed"]
    if not moving:
        urdf.fail(f"no moving joint (revolute, continuous or prismatic) on the chain from {describe(urdf.root)} "
                  f"to {describe(tip)}")
    return tip, chain, on_chain, moving


def _joint_entry(urdf: _Reader, joint: _Joint, pending: Frame, pending_joints: list, taken: set) -> tuple[dict, dict]:
    """The robot-file link of a moving URDF joint: ``(entry, extra)``, the name, joint type,
    origin (after the fixed joints ``pending_joints`` that lead to it from the moving link
    above, whose composed frame is ``pending``) and axis; then damping, Coulomb friction and
    limits where the file gives them.  The link name is made valid and distinct (``taken``)."""
    where = urdf.where(joint)
    if all(j.origin.is_identity for j in pending_joints):
        origin = {"xyz": list(joint.origin.texts["xyz"]), "rpy": list(joint.origin.texts["rpy"])}
    else:
        origin = (pending * joint.origin.frame).texts()
    axis = urdf.numbers(joint.element.find("axis"), "xyz", 3, "1 0 0", where, "axis xyz")
    if all(v == 0 for v, _ in axis):
        urdf.fail("the axis is zero: give a direction such as \"0 0 1\"", where, "axis xyz")
    link_name = _link_name(joint.name, taken)
    taken.add(link_name)
    urdf.link_of_joint[joint.name] = link_name
    if link_name != joint.name:
        urdf.renamed.append((joint.name, link_name))
    entry = {"name": link_name, "joint": "prismatic" if joint.type == "prismatic" else "revolute",
             "origin": origin, "axis": [t for _, t in axis]}
    extra = {}
    element = joint.element.find("dynamics")
    if element is not None:
        for attribute, key in (("damping", "damping"), ("friction", "coulomb")):
            if element.get(attribute) is not None:
                extra[key] = urdf.numbers(element, attribute, 1, None, where, f"dynamics {attribute}")[0][1]
    element = joint.element.find("limit")
    limits = {}
    if element is not None:
        for key in ("lower", "upper", "velocity", "effort"):
            if element.get(key) is not None and not (joint.type == "continuous" and key in ("lower", "upper")):
                limits[key] = urdf.numbers(element, key, 1, None, where, f"limit {key}")[0][1]
    if limits:
        extra["limits"] = limits
    mimic = _mimic_entry(urdf, joint)
    if mimic is not None:
        extra["mimic"] = mimic
    extra.update(urdf.joint_fields.get(joint.name, {}))
    return entry, extra


def _check_moving(urdf: _Reader, joint: _Joint, what: str) -> None:
    """Refuse a floating or planar joint where the dynamics need it (``what``: where it is, for
    the message)."""
    if joint.type in ("floating", "planar"):
        hint = " (choose a chain without it with --tip LINK)" if what == "in the tree" else ""
        urdf.fail(f"a {joint.type} joint is {what}: only revolute, continuous, prismatic and fixed joints can be{hint}",
                  urdf.where(joint), "type")


def _mimic_entry(urdf: _Reader, joint: _Joint) -> dict | None:
    """A moving joint's ``<mimic joint multiplier offset>`` as read (the URDF joint name it
    follows, the numbers' text), or None."""
    element = joint.element.find("mimic")
    if element is None:
        return None
    where = urdf.where(joint)
    leader = element.get("joint")
    if not leader:
        urdf.fail("<mimic> names no joint (joint=\"...\")", where, "mimic joint")
    if leader not in urdf.joints:  # (a typo in the file: Pinocchio reads it only without mimic joints)
        close = _hint(leader, urdf.joints).removeprefix("; did you mean ").removesuffix("?")
        urdf.unfollowed.append(f"{one_line(joint.name, 60)} follows {describe(leader)}" + (f" (perhaps {close})" if close else ""))
        return None
    multiplier = urdf.numbers(element, "multiplier", 1, "1", where, "mimic multiplier")[0]
    offset = urdf.numbers(element, "offset", 1, "0", where, "mimic offset")[0]
    if multiplier[0] == 0:
        urdf.fail("<mimic multiplier=\"0\"> holds the joint at its offset: make it a fixed joint", where,
                  "mimic multiplier")
    return {"joint": leader, "multiplier": multiplier, "offset": offset}


def _resolve_mimics(urdf: _Reader, entries: list, what: str) -> list[str]:
    """Give each mimic entry (``extra['mimic']`` of ``entries``, as :func:`_mimic_entry` read it)
    the link name of the joint it follows, through mimics of mimics (the laws composed), in the
    robot document's form; a leader that is not read (fixed, or off the chain: ``what``) is
    refused.  Returns the notes' lines, one per mimic joint: its law."""
    if urdf.unfollowed:
        urdf.warn(f"{len(urdf.unfollowed)} <mimic> element{'s follow joints' if len(urdf.unfollowed) > 1 else ' follows a joint'} "
                  f"that the file does not have ({'; '.join(urdf.unfollowed[:3])}{'; ...' if len(urdf.unfollowed) > 3 else ''}): "
                  "those joints are read with coordinates of their own, as Pinocchio reads the file without mimic joints")
    laws = {}
    for entry, extra in entries:
        if "mimic" in extra:
            laws[entry["name"]] = extra["mimic"]
    lines = []
    for entry, extra in entries:
        law = extra.get("mimic")
        if law is None:
            continue
        multiplier, offset = Fraction(law["multiplier"][0]), Fraction(law["offset"][0])
        leader, seen = law["joint"], {entry["name"]}
        while True:
            joint = urdf.joints[leader]
            if joint.type == "fixed" or leader not in urdf.link_of_joint:
                urdf.fail(f"<mimic> follows {describe(leader)}, which is {'a fixed joint' if joint.type == 'fixed' else what}:"
                          " a mimic joint needs a moving leader that is read with it", f"joint {describe(entry['name'])}",
                          "mimic joint")
            link = urdf.link_of_joint[leader]
            if link in seen:
                urdf.fail("mimic joints follow each other in a circle", f"joint {describe(entry['name'])}", "mimic joint")
            seen.add(link)
            if link not in laws:
                break
            step = laws[link]  # q_leader = m2 q_next + o2: q = m (m2 q_next + o2) + o
            offset += multiplier * Fraction(step["offset"][0])
            multiplier *= Fraction(step["multiplier"][0])
            leader = step["joint"]
        extra["mimic"] = {"joint": link, "multiplier": _fraction_text(multiplier, law["multiplier"][1]),
                          "offset": _fraction_text(offset, law["offset"][1])}
        lines.append(f"{entry['name']} = {extra['mimic']['multiplier']} * {link} + {extra['mimic']['offset']}")
    return lines


def _mimic_note(lines: list[str], notes: list, unfollowed=()) -> None:
    if unfollowed:
        notes.append("<mimic> elements that follow no joint of the file, those joints read with their own coordinates: "
                     + "; ".join(unfollowed))
    if lines:
        notes.append(f"mimic joints (<mimic>: no coordinate of their own, q = multiplier * q_leader + offset; their "
                     f"joint force acts on the leader's coordinate times the multiplier): {'; '.join(lines)}")


def _fraction_text(value: Fraction, text: str) -> str:
    """The text of a number: as written when it was not composed, else exact."""
    if Fraction(text) == value:
        return text
    return f"{value.numerator}/{value.denominator}" if value.denominator != 1 else str(value.numerator)


def _branches(urdf: _Reader) -> bool:
    """Whether the moving joints lie on more than one branch (a tree the chain reading refuses
    without a tip)."""
    leaves = [name for name in urdf.links if not urdf.child_joints[name]]
    return (len(leaves) > 1 and urdf.moving_chain_end() is None
            and any(j.type != "fixed" for j in urdf.joints.values()))


def read_tree(urdf: _Reader, name: str, floating: bool = False) -> tuple[dict, list[str]]:
    """The robot document of a URDF's whole tree: one link per moving joint, numbered as
    Pinocchio's URDF reader numbers them (depth first from the root link, the joints of each
    link in the order of their names), each with ``parent:`` the link of the moving joint above
    it; links on fixed joints are merged into the moving link above them (or left out with the
    ground; with ``floating``, they make the free-floating base: ``base: floating`` and its
    ``base_body``)."""
    entries: list[tuple[dict, dict]] = []
    bodies: list[_Body] = []
    parents: list[int] = []
    ground, ground_links, merged = _EMPTY, [], []
    taken: set = set()

    def visit(link: str, owner: int, frame: Frame, fixed_path: list) -> list:
        """Merge ``link`` (at ``frame`` in the owner's frame) into its owner; its joints to visit next."""
        nonlocal ground
        body = urdf.body(link).moved(frame)
        if owner < 0:
            ground = ground.plus(body)
            ground_links.append(link)
        else:
            bodies[owner] = bodies[owner].plus(body)
        order = (lambda j: j.index) if urdf.file_order else (lambda j: j.name)
        return [(j, owner, frame, fixed_path) for j in sorted(urdf.child_joints[link], key=order)]

    pending = visit(urdf.root, -1, Frame(), [])[::-1]
    while pending:  # iterative depth-first walk: deep trees do not recurse
        joint, owner, frame, fixed_path = pending.pop()
        if joint.type == "fixed":
            if owner >= 0 and not urdf.body(joint.child).is_empty:
                merged.append(joint.name)
            pending.extend(visit(joint.child, owner, frame * joint.origin.frame, fixed_path + [joint])[::-1])
            continue
        _check_moving(urdf, joint, "in the tree")
        entries.append(_joint_entry(urdf, joint, frame, fixed_path, taken))
        bodies.append(_EMPTY)
        parents.append(owner)
        pending.extend(visit(joint.child, len(entries) - 1, Frame(), [])[::-1])

    mimics = _resolve_mimics(urdf, entries, "not in the tree")
    doc = {"format": FORMAT_VERSION, "name": name, "convention": "general", "gravity": [0, 0, "-9.81"]}
    if floating:
        doc["base"] = "floating"
        doc["base_body"] = ground.fields()
    doc["links"] = []
    for k, ((entry, extra), body, parent) in enumerate(zip(entries, bodies, parents)):
        up = {} if parent == k - 1 else {"parent": "base" if parent < 0 else entries[parent][0]["name"]}
        doc["links"].append({"name": entry["name"], **up, **{key: v for key, v in entry.items() if key != "name"},
                             **body.fields(), **extra})
    on_base = sum(1 for p in parents if p < 0)
    notes = [f"read from URDF {display_path(os.path.basename(urdf.path))}: the whole tree from "
             f"{one_line(urdf.root, 60)}, {len(entries)} moving joints, {on_base} on the root link; joints numbered as "
             "Pinocchio's URDF reader numbers them (depth first, each link's joints in the order of their names)"]
    moving = [j for j in urdf.joints.values() if j.type != "fixed"]
    continuous = [j.name for j in moving if j.type == "continuous"]
    if continuous:
        notes.append(f"continuous joints read as revolute (the angle is the coordinate): {_plain(continuous)}")
    if merged:
        notes.append(f"fixed joints merged (child inertia added to the moving link above): {_plain(merged)}")
    if floating:
        notes.append(f"floating base (a free-flyer joint on {one_line(urdf.root, 60)}, Pinocchio's conventions), "
                     f"{_kg(ground.mass)} kg: links {_plain(ground_links)}")
    elif ground.mass != 0:
        notes.append(f"fixed to the ground, inertia left out ({_kg(ground.mass)} kg): links {_plain(ground_links)}")
        if on_base > 1 and urdf.source == "URDF":  # branches on a heavy root: a legged or mobile robot, most likely
            urdf.warn(f"the root link {describe(urdf.root)} ({_kg(ground.mass)} kg) is fixed to the ground and its "
                      f"inertia left out, with {on_base} branches of joints on it: give --floating-base if the robot "
                      "moves freely (a legged or mobile robot)")
    if any(key in extra for _, extra in entries for key in ("damping", "coulomb")):
        notes.append("<dynamics damping friction> read as viscous damping and Coulomb friction (coulomb)")
    _mimic_note(mimics, notes, urdf.unfollowed)
    _renamed_note(urdf, notes)
    if urdf.snapped:
        notes.append(f"rpy angles within {QUARTER_TOLERANCE:g} rad of a multiple of pi/2 taken as that multiple "
                     f"(--exact-angles keeps them as written): {_plain(urdf.snapped)}")
    return doc, notes


def _kg(mass) -> str:
    return f"{float(_mp(mass)):.6g}"


def _plain(names, limit: int = _NAMES_SHOWN) -> str:
    names = [one_line(n, 60) for n in names]
    return ", ".join(names[:limit]) + (f" and {len(names) - limit} more" if len(names) > limit else "")


def _tool_frame(urdf: _Reader, tool: str, last: _Joint) -> dict | None:
    """The frame of link ``tool`` in the last moving link's frame (None: the same frame); the
    link must hang from it through fixed joints only."""
    if tool not in urdf.links:
        urdf.fail(f"tool link {describe(tool)} is not a link of the file{_hint(tool, urdf.links)}")
    joints, link = [], tool
    while link != last.child:
        joint = urdf.parent_joint.get(link)
        if joint is None or joint.type != "fixed":
            urdf.fail(f"tool link {describe(tool)} is not rigidly attached to link {describe(last.child)} (the "
                      f"child of the last moving joint {describe(last.name)}): the tool must hang from it "
                      "through fixed joints only")
        joints.append(joint)
        link = joint.parent
    joints.reverse()
    if all(joint.origin.is_identity for joint in joints):
        return None
    if len(joints) == 1:
        return {"xyz": list(joints[0].origin.texts["xyz"]), "rpy": list(joints[0].origin.texts["rpy"])}
    frame = Frame()
    for joint in joints:
        frame = frame * joint.origin.frame
    return None if frame.is_identity else frame.texts()
