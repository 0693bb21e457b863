"""Robot descriptions: the immutable model read from a robot file (format version 1).

The file format is specified in ``docs/robot-format.md`` (a copy of the project contract).
A :class:`Robot` is a *description*: every field is a SymPy expression, numbers are exact
rationals, and names that stay inputs of the generated code (runtime parameters and free
symbols) are real SymPy symbols listed in :attr:`Robot.parameters`.  Robots are frozen; every
function that changes one returns a new value.
"""

from __future__ import annotations

import difflib
import hashlib
import os
import re
from dataclasses import dataclass, field, replace
from typing import Any, Iterable, Mapping

import numpy as np
import sympy as sp
from .errors import RobotFileError, SymdynError, describe, one_line, warn
from .expr import NAME_PATTERN, ExpressionError, number_to_rational, parse_expression
from .inputs import decode_text, load_yaml, read_input

FORMAT_VERSION = 1
CONVENTIONS = ("standard", "modified", "general")
JOINT_TYPES = ("revolute", "prismatic")
ROBOT_NAME_PATTERN = re.compile(r"[a-z][a-z0-9_]*\Z")
#: link names: C-identifier-like, so that they can appear in generated text unescaped
LINK_NAME_PATTERN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
#: the longest robot, link or parameter name (C99 guarantees 31 significant characters)
MAX_NAME = 31
#: the largest magnitude of a numeric field (products of three such stay finite in double)
MAX_MAGNITUDE = sp.Integer(10) ** 100
#: the largest angle read, in every format (rad): cos and sin of 1e6 rad carry an error of about
#: 1e-10 in double (the angle's own rounding, 1e-10 rad); of 1e100 rad, of order 1
MAX_ANGLE = 1e6
# Names the derivation itself uses for joint variables; a parameter may not shadow them.
#: names that print like symdyn's own symbols (joint variables and their rates in code and
#: printouts, the sin/cos shorthand c1, s1 of the printouts, the C emitter's temporaries cse0, ...)
_RESERVED_NAME = re.compile(r"(q|qd|qdd|qdot|qddot|tau|p|cse)[0-9]*\Z|(c|s)[0-9]+\Z")
_RESERVED_WORDS = frozenset({"pi", "e", "E", "I", "sin", "cos", "sqrt"})
_RESERVED_FOLDED = frozenset({"nan", "inf", "infinity", "oo", "zoo"})  # in any case

TOP_KEYS = ("format", "name", "convention", "gravity", "angles", "base", "base_body", "tool", "task", "parameters",
            "frames", "contacts", "links")
#: the kinds of contact: a point held (its linear velocity zero), a body held (its whole
#: velocity zero) and a point held in a coordinate plane (its velocity's two entries in that plane
#: zero: a planar robot's foot), each with its rows of the frame's Jacobian (world-aligned axes at
#: the frame's origin, linear 0-2 then angular 3-5)
CONTACT_AXES = {"3d": (0, 1, 2), "6d": (0, 1, 2, 3, 4, 5), "xz": (0, 2), "xy": (0, 1), "yz": (1, 2)}
CONTACT_ROWS = {kind: len(axes) for kind, axes in CONTACT_AXES.items()}
#: the kinds as a message lists them
CONTACT_KINDS_TEXT = ("3d (a point held), 6d (a sole held) or xz, xy, yz (a point held in that plane: a planar "
                      "robot's foot)")
#: the fields of a ``contacts:`` entry written as a mapping (``kp``, ``kd``, ``reference``: its
#: Baumgarte correction, :class:`Contact`)
CONTACT_KEYS = ("frame", "kind", "kp", "kd", "reference")
#: the fields of a frame fixed in a link (``frames:`` entries written as mappings)
FRAME_KEYS = ("name", "link", "xyz", "rpy")
#: the fields of ``base_body:`` (the free-floating base's own inertia)
BODY_KEYS = ("mass", "com", "inertia")
#: the free-flyer's coordinates, before the joints' (Pinocchio's): position, quaternion (x, y, z, w)
FREE_FLYER_Q = ("x", "y", "z", "qx", "qy", "qz", "qw")
#: and its velocities: the base's linear velocity and angular velocity, both in the base frame
FREE_FLYER_V = ("vx", "vy", "vz", "wx", "wy", "wz")
#: the named tasks of ``task:`` (rows of the tool Jacobian: 0-2 linear x, y, z, 3-5 angular)
TASKS = {"pose": (0, 1, 2, 3, 4, 5), "position": (0, 1, 2), "orientation": (3, 4, 5)}
#: the name of each row of the tool Jacobian (world axes at the tool origin)
JACOBIAN_ROWS = ("linear x", "linear y", "linear z", "angular x", "angular y", "angular z")
ANGLE_UNITS = ("radians", "degrees")
LINK_KEYS = ("name", "parent", "joint", "a", "alpha", "d", "theta", "origin", "axis", "mass", "com", "inertia",
             "armature", "damping", "coulomb", "limits", "actuated", "mimic")
#: the fields of a link's ``mimic:`` (its joint follows another: q = multiplier * q_joint + offset)
MIMIC_KEYS = ("joint", "multiplier", "offset")
DH_KEYS = ("a", "alpha", "d", "theta")
GENERAL_KEYS = ("origin", "axis")
PLACEMENT_KEYS = ("xyz", "rpy")
LIMIT_KEYS = ("lower", "upper", "velocity", "effort")
INERTIA_KEYS = ("xx", "yy", "zz", "xy", "xz", "yz")
DEFAULT_GRAVITY = (0, 0, number_to_rational("-9.81"))


def _rpy_matrix(roll, pitch, yaw) -> sp.Matrix:
    """``Rz(yaw) Ry(pitch) Rx(roll)`` (rotations about the fixed x, y, z axes, as in URDF), 3x3."""
    cr, sr, cp, spt, cy, sy = (sp.cos(roll), sp.sin(roll), sp.cos(pitch), sp.sin(pitch),
                               sp.cos(yaw), sp.sin(yaw))
    rx = sp.Matrix([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = sp.Matrix([[cp, 0, spt], [0, 1, 0], [-spt, 0, cp]])
    rz = sp.Matrix([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz * ry * rx


@dataclass(frozen=True)
class Placement:
    """A constant frame placement ``{xyz, rpy}``: translation (m), then rotation by roll, pitch,
    yaw (rad) about the fixed x, y, z axes, as URDF's ``<origin>``."""

    xyz: tuple[sp.Expr, sp.Expr, sp.Expr]
    rpy: tuple[sp.Expr, sp.Expr, sp.Expr]

    def matrix(self) -> sp.ImmutableMatrix:
        """The 4x4 homogeneous transform (exact)."""
        out = sp.eye(4)
        out[:3, :3] = _rpy_matrix(*self.rpy)
        out[:3, 3] = sp.Matrix(self.xyz)
        return sp.ImmutableMatrix(out)

    @property
    def is_identity(self) -> bool:
        return all(sp.sympify(v) == 0 for v in (*self.xyz, *self.rpy))

    def expressions(self) -> tuple[sp.Expr, ...]:
        return (*self.xyz, *self.rpy)

    def subs(self, mapping) -> "Placement":
        return Placement(tuple(sp.sympify(v).xreplace(mapping) for v in self.xyz),
                         tuple(sp.sympify(v).xreplace(mapping) for v in self.rpy))


@dataclass(frozen=True)
class Limits:
    """Joint limits (informative: the dynamics do not use them; headers and URDF output list
    them). Each is an expression or None: position (rad or m), velocity (rad/s or m/s), effort
    (N m or N)."""

    lower: sp.Expr | None = None
    upper: sp.Expr | None = None
    velocity: sp.Expr | None = None
    effort: sp.Expr | None = None

    def expressions(self) -> tuple[sp.Expr, ...]:
        return tuple(v for v in (self.lower, self.upper, self.velocity, self.effort) if v is not None)

    def subs(self, mapping) -> "Limits":
        return Limits(*(None if v is None else sp.sympify(v).xreplace(mapping)
                        for v in (self.lower, self.upper, self.velocity, self.effort)))


@dataclass(frozen=True)
class Mimic:
    """A mimic joint's law: its position is ``multiplier * q_leader + offset`` (rad or m), its rate
    and acceleration ``multiplier`` times the leader's; it has no coordinate of its own, and its
    joint force reaches the leader's coordinate times ``multiplier`` (URDF's ``<mimic>``,
    Pinocchio's mimic joints).  ``leader`` is the index (0-based) of the link whose joint it follows."""

    leader: int
    multiplier: sp.Expr
    offset: sp.Expr = sp.S.Zero


@dataclass(frozen=True)
class Link:
    """One joint and the link it moves, as in one row of the DH table.

    Lengths in m, angles in rad, mass in kg, inertia in kg m^2 about the centre of mass with
    link-frame axes (tensor entries: ``xy`` is the (x, y) entry of the inertia matrix), COM in
    m in link frame i.  ``a`` and ``alpha`` hold a_i/alpha_i (standard) or a_{i-1}/alpha_{i-1}
    (modified).  ``armature`` is in kg m^2 (kg for prismatic joints), ``damping`` in N m s/rad
    (N s/m), ``coulomb`` in N m (N).  ``actuated`` is False for a passive joint (tau_i = 0 by
    construction; see the reaction map, :mod:`symdyn.derive.articulated_body`).
    """

    name: str
    joint: str
    a: sp.Expr
    alpha: sp.Expr
    d: sp.Expr
    theta: sp.Expr
    mass: sp.Expr
    com: tuple[sp.Expr, sp.Expr, sp.Expr]
    inertia: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr, sp.Expr, sp.Expr]  # xx yy zz xy xz yz
    armature: sp.Expr = sp.S.Zero
    damping: sp.Expr = sp.S.Zero
    coulomb: sp.Expr = sp.S.Zero
    #: constant 4x4 transform (16 entries, row-major) applied before the link's DH transform, or
    #: None; not part of the file format: scenes set it when they lock joints (symdyn.model.scene)
    fixed: tuple[sp.Expr, ...] | None = None
    #: general convention only: the joint frame in the previous link's frame, and the joint axis
    #: in it (unit, exact); the link frame is the joint frame moved by the joint
    origin: Placement | None = None
    axis: tuple[sp.Expr, sp.Expr, sp.Expr] | None = None
    limits: Limits | None = None
    actuated: bool = True
    #: the law of a mimic joint (no coordinate of its own), or None
    mimic: Mimic | None = None

    @property
    def is_revolute(self) -> bool:
        return self.joint == "revolute"

    @property
    def inertia_matrix(self) -> sp.ImmutableMatrix:
        """3x3 inertia tensor about the COM, in link-frame axes (kg m^2)."""
        xx, yy, zz, xy, xz, yz = self.inertia
        return sp.ImmutableMatrix([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])

    def expressions(self) -> tuple[sp.Expr, ...]:
        return (self.a, self.alpha, self.d, self.theta, self.mass, *self.com, *self.inertia,
                self.armature, self.damping, self.coulomb, *(self.fixed or ()),
                *(self.origin.expressions() if self.origin else ()), *(self.axis or ()),
                *(self.limits.expressions() if self.limits else ()))

    def subs(self, mapping: Mapping[sp.Symbol, sp.Expr]) -> "Link":
        def s(e):
            return sp.sympify(e).xreplace(mapping)
        return replace(
            self, a=s(self.a), alpha=s(self.alpha), d=s(self.d), theta=s(self.theta),
            mass=s(self.mass), com=tuple(s(c) for c in self.com),
            inertia=tuple(s(c) for c in self.inertia), armature=s(self.armature),
            damping=s(self.damping), coulomb=s(self.coulomb),
            fixed=None if self.fixed is None else tuple(s(c) for c in self.fixed),
            origin=None if self.origin is None else self.origin.subs(mapping),
            axis=None if self.axis is None else tuple(s(c) for c in self.axis),
            limits=None if self.limits is None else self.limits.subs(mapping))


@dataclass(frozen=True)
class Body:
    """A rigid body's inertia: mass (kg), centre of mass (m) and inertia about it (kg m^2, xx yy zz
    xy xz yz), in the body's frame: the free-floating base's (``base_body:``), a platform's."""

    mass: sp.Expr
    com: tuple[sp.Expr, sp.Expr, sp.Expr]
    inertia: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr, sp.Expr, sp.Expr]

    @property
    def inertia_matrix(self) -> sp.ImmutableMatrix:
        """3x3 inertia tensor about the COM, in the body's axes (kg m^2)."""
        xx, yy, zz, xy, xz, yz = self.inertia
        return sp.ImmutableMatrix([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])

    def expressions(self) -> tuple[sp.Expr, ...]:
        return (self.mass, *self.com, *self.inertia)

    def subs(self, mapping) -> "Body":
        return type(self)(*(tuple(sp.sympify(e).xreplace(mapping) for e in part) if isinstance(part, tuple)
                      else sp.sympify(part).xreplace(mapping) for part in (self.mass, self.com, self.inertia)))


ZERO_BODY = Body(sp.S.Zero, (sp.S.Zero,) * 3, (sp.S.Zero,) * 6)


@dataclass(frozen=True)
class NamedFrame:
    """A frame fixed in a link (or in the base) whose pose, Jacobian and J-dot v the frame
    functions give: ``link`` the link's index (0-based, -1 the base), ``pose`` the frame in that
    link's frame (16 numbers, row-major 4x4), or None for the link's own frame."""

    name: str
    link: int
    pose: tuple[sp.Expr, ...] | None = None

    def matrix(self) -> sp.Matrix:
        return sp.eye(4) if self.pose is None else sp.Matrix(4, 4, list(self.pose))


@dataclass(frozen=True)
class Contact:
    """A contact of the contact dynamics: the frame ``frame`` (an index into the robot's
    ``frames``) held, ``kind`` ``"3d"`` (its origin's linear velocity zero: a point foot),
    ``"6d"`` (its whole velocity zero: a sole, a gripped tool) or ``"xz"``, ``"xy"``, ``"yz"``
    (its origin's velocity zero along those two world axes: a planar robot's foot).

    A contact may be held with a Baumgarte correction (Pinocchio's ``corrector`` with the same
    gain on every axis): a point's constraint becomes ``a + kd v + kp (p - reference) = 0`` (a,
    v, p the frame origin's classical acceleration, velocity and position, world axes; on the
    kind's axes: a planar contact's two), a sole's ``a + kd v - kp X log6(M^-1 M_ref) = 0`` (a its
    spatial acceleration, v its velocity, world-aligned; M its placement, M_ref the reference's,
    X = diag(R, R) with R its rotation); ``kp`` (1/s^2) and ``kd`` (1/s) at least 0,
    ``reference`` the point held (3 entries, m, world) or the placement (6: x, y, z in m, then
    roll, pitch, yaw in rad about the fixed axes); each an expression of numbers and runtime
    parameters (a reference that changes at run time is runtime parameters)."""

    frame: int
    kind: str
    kp: sp.Expr = sp.S.Zero
    kd: sp.Expr = sp.S.Zero
    reference: tuple[sp.Expr, ...] | None = None

    @property
    def rows(self) -> int:
        """Constraint rows: 3, 6 or 2."""
        return CONTACT_ROWS[self.kind]

    @property
    def axes(self) -> tuple[int, ...]:
        """The rows of the frame's Jacobian (0-2 linear, 3-5 angular, world axes) it holds."""
        return CONTACT_AXES[self.kind]

    @property
    def corrected(self) -> bool:
        """True when the contact has a Baumgarte correction (a gain not identically zero)."""
        return self.kp != 0 or self.kd != 0

    def reference_placement(self) -> tuple[sp.Matrix, sp.Matrix]:
        """``(R, p)``: a sole's reference rotation (3 x 3) and origin (3 x 1), world."""
        return _rpy_matrix(*self.reference[3:6]), sp.Matrix(self.reference[:3])

    def expressions(self) -> tuple[sp.Expr, ...]:
        """The correction's gains and reference (what may name runtime parameters)."""
        return (self.kp, self.kd, *(self.reference or ()))

    def subs(self, mapping) -> "Contact":
        return replace(self, kp=sp.sympify(self.kp).xreplace(mapping), kd=sp.sympify(self.kd).xreplace(mapping),
                       reference=None if self.reference is None else
                       tuple(sp.sympify(e).xreplace(mapping) for e in self.reference))


@dataclass(frozen=True)
class Robot:
    """A serial chain described by its DH table and inertial parameters.

    Attributes
    ----------
    name : C identifier prefix of generated code.
    convention : ``'standard'`` or ``'modified'`` DH, or ``'general'`` (origin and axis per link).
    gravity : gravity acceleration (m/s^2) in the world frame, 3 expressions (the base frame
        when ``base`` is None); :attr:`base_gravity` is it in the base frame.
    base : placement of the chain's base frame in the world, or None (identity).
    tool : the tool frame in the last link's frame, or None (the last link frame).
    links : the links, base to tip.
    parameters : symbols that stay inputs (runtime parameters first, in file order, then free
        symbols in order of first appearance); this is the order of the ``p`` array in C.
    nominal : the value given for each runtime parameter (``None`` for free symbols).
    source : the path the robot was read from (``'<memory>'`` if built in code).
    source_hash : SHA-256 of the file's bytes (empty if built in code).
    """

    name: str
    convention: str
    gravity: tuple[sp.Expr, sp.Expr, sp.Expr]
    links: tuple[Link, ...]
    parameters: tuple[sp.Symbol, ...] = ()
    nominal: tuple[sp.Expr | None, ...] = ()
    source: str = "<memory>"
    source_hash: str = ""
    runtime_names: tuple[str, ...] = field(default=())  # parameters marked runtime: true
    base: Placement | None = None
    tool: Placement | None = None
    notes: tuple[str, ...] = ()  # what reading the file did (URDF merges), for headers
    #: constant 4x4 transform (16 entries) from the last link's frame to the frame ``tool`` is
    #: given in, or None; not part of the file format: set by scenes that lock the last joints
    tool_fixed: tuple[sp.Expr, ...] | None = None
    #: the task of the task-space functions, as rows of the tool Jacobian (0-2 linear x, y, z,
    #: 3-5 angular), or None when the file names none (they then use the whole pose)
    task: tuple[int, ...] | None = None
    #: per link, the index (0-based) of the link it hangs on, -1 for the base; empty for a serial
    #: chain (each link on the one before it), which every chain keeps so that its description,
    #: and everything derived from it, is unchanged
    parents: tuple[int, ...] = ()
    #: True for a free-floating base (``base: floating``): a free-flyer joint before the links,
    #: with Pinocchio's conventions (q: position, quaternion x y z w, then the joints; v: the
    #: base's linear and angular velocity in the base frame, then the joint rates)
    floating: bool = False
    #: the floating base's own inertia in the base frame (``base_body:``; zero when not given)
    base_body: Body | None = None
    #: the frames of the frame functions (``frames:``), in their order
    frames: tuple[NamedFrame, ...] = ()
    #: the contacts of the contact dynamics (``contacts:``), in their order (the forces' order)
    contacts: tuple[Contact, ...] = ()

    @property
    def contact_rows(self) -> int:
        """Rows of the contact constraints (3 per point contact, 6 per sole): the forces' entries."""
        return sum(c.rows for c in self.contacts)

    @property
    def nv(self) -> int:
        """Velocity coordinates: the joints, and 6 for a floating base (entries of qd, qdd, tau)."""
        return self.dof + (6 if self.floating else 0)

    @property
    def nq(self) -> int:
        """Configuration coordinates: the joints, and 7 for a floating base (its quaternion has 4)."""
        return self.dof + (7 if self.floating else 0)

    @property
    def base_inertia(self) -> Body:
        """The floating base's inertia (zero when none was given)."""
        return self.base_body or ZERO_BODY

    @property
    def parent_indices(self) -> tuple[int, ...]:
        """Per link, the index of its parent link (-1: the base): ``(-1, 0, 1, ...)`` for a chain."""
        return self.parents or tuple(range(-1, len(self.links) - 1))

    @property
    def is_tree(self) -> bool:
        """Whether some link hangs on another than the one before it (a kinematic tree), the
        base floats, or a joint mimics another (the functions of a tree then apply)."""
        return self.floating or any(p != k - 1 for k, p in enumerate(self.parents)) or bool(self.mimics)

    def children(self, index: int) -> tuple[int, ...]:
        """The links that hang on link ``index`` (-1: on the base), in file order."""
        return tuple(k for k, p in enumerate(self.parent_indices) if p == index)

    def ancestors(self, index: int) -> tuple[int, ...]:
        """The links between link ``index`` and the base, nearest first (not ``index`` itself)."""
        out, parents = [], self.parent_indices
        k = parents[index]
        while k >= 0:
            out.append(k)
            k = parents[k]
        return tuple(out)

    def subtree(self, index: int) -> tuple[int, ...]:
        """Link ``index`` and every link that hangs on it, directly or not, in file order."""
        return tuple(k for k in range(index, len(self.links)) if k == index or index in self.ancestors(k))

    @property
    def task_rows(self) -> tuple[int, ...]:
        """The rows of the tool Jacobian the task-space functions use (the pose by default)."""
        return TASKS["pose"] if self.task is None else self.task

    @property
    def base_gravity(self) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
        """Gravity (m/s^2) in the base frame: ``R_base^T g`` (the dynamics are computed there)."""
        if self.base is None:
            return self.gravity
        rotation = sp.Matrix(self.base.matrix())[:3, :3]
        g = rotation.T * sp.Matrix(self.gravity)
        return tuple(sp.expand(e) for e in g)

    def base_matrix(self) -> sp.ImmutableMatrix:
        return sp.ImmutableMatrix(sp.eye(4)) if self.base is None else self.base.matrix()

    def tool_matrix(self) -> sp.ImmutableMatrix:
        """The tool frame in the last link's frame, 4x4."""
        tool = sp.eye(4) if self.tool is None else sp.Matrix(self.tool.matrix())
        if self.tool_fixed is not None:
            tool = sp.Matrix(4, 4, list(self.tool_fixed)) * tool
        return sp.ImmutableMatrix(tool)

    @property
    def dof(self) -> int:
        """Joint coordinates: one per link, except mimic joints (which follow another's)."""
        return len(self.coordinate_links)

    @property
    def coordinate_links(self) -> tuple[int, ...]:
        """The links whose joints have a coordinate of their own (not mimics), in order: joint
        coordinate k moves link ``coordinate_links[k]`` (and the mimics that follow it)."""
        return tuple(k for k, link in enumerate(self.links) if link.mimic is None)

    @property
    def mimics(self) -> tuple[int, ...]:
        """The indices of the mimic joints' links."""
        return tuple(k for k, link in enumerate(self.links) if link.mimic is not None)

    @property
    def link_coordinates(self) -> tuple[tuple[int, sp.Expr], ...]:
        """Per link, ``(k, m)``: its joint rate is ``m`` times joint coordinate k's rate (m = 1 but
        for a mimic joint, whose k is its leader's): the rows of G, the links' rates per coordinate."""
        index = {j: k for k, j in enumerate(self.coordinate_links)}
        return tuple((index[k], sp.S.One) if link.mimic is None else (index[link.mimic.leader], link.mimic.multiplier)
                     for k, link in enumerate(self.links))

    def coordinate_of(self, link: int) -> tuple[int, sp.Expr]:
        """``(k, m)`` of one link (:attr:`link_coordinates`)."""
        return self.link_coordinates[link]

    def per_coordinate(self, values) -> tuple:
        """Per-link coefficients of a joint's rate (armature, damping, an inertia it moves) as per-
        coordinate ones: each link's times the square of its multiplier, summed on its coordinate
        (the diagonal of G^T diag(values) G); ``values`` themselves without mimic joints."""
        if not self.mimics:
            return tuple(values)
        out = [0] * self.dof
        for (k, m), value in zip(self.link_coordinates, values):
            out[k] += m * m * value
        return tuple(out)

    @property
    def actuated_joints(self) -> tuple[int, ...]:
        """0-based indices of the actuated joint coordinates (``actuated: true``, the default), base to tip."""
        return tuple(k for k, j in enumerate(self.coordinate_links) if self.links[j].actuated)

    @property
    def passive_joints(self) -> tuple[int, ...]:
        """0-based indices of the passive joint coordinates (``actuated: false``: tau_i = 0)."""
        return tuple(k for k, j in enumerate(self.coordinate_links) if not self.links[j].actuated)

    @property
    def is_numeric(self) -> bool:
        """True when no parameter remains symbolic."""
        return not self.parameters

    def nominal_values(self) -> dict[sp.Symbol, sp.Expr]:
        """Nominal values of the runtime parameters that have one."""
        return {s: v for s, v in zip(self.parameters, self.nominal) if v is not None}

    def substitute(self, values: Mapping[sp.Symbol | str, Any]) -> "Robot":
        """A new robot with the given parameters replaced by numbers (or expressions).

        Keys are symbols or their names; unknown names raise ``KeyError``.
        """
        by_name = {s.name: s for s in self.parameters}
        mapping: dict[sp.Symbol, sp.Expr] = {}
        for key, value in values.items():
            sym = by_name[key] if isinstance(key, str) else key
            if sym not in self.parameters:
                raise KeyError(f"{sym} is not a parameter of robot {self.name}")
            mapping[sym] = _to_exact(value)
        keep = [(s, v) for s, v in zip(self.parameters, self.nominal) if s not in mapping]
        return replace(
            self,
            gravity=tuple(sp.sympify(g).xreplace(mapping) for g in self.gravity),
            links=tuple(link.subs(mapping) for link in self.links),
            base=None if self.base is None else self.base.subs(mapping),
            base_body=None if self.base_body is None else self.base_body.subs(mapping),
            tool=None if self.tool is None else self.tool.subs(mapping),
            tool_fixed=None if self.tool_fixed is None else tuple(sp.sympify(c).xreplace(mapping)
                                                                    for c in self.tool_fixed),
            contacts=tuple(contact.subs(mapping) for contact in self.contacts),
            parameters=tuple(s for s, _ in keep),
            nominal=tuple(v for _, v in keep),
            runtime_names=tuple(n for n in self.runtime_names if by_name.get(n) not in mapping),
        )

    def with_nominal_values(self) -> "Robot":
        """Fold every runtime parameter that has a nominal value into the robot."""
        return self.substitute(self.nominal_values())


def _to_exact(value: Any) -> sp.Expr:
    if isinstance(value, sp.Basic):
        return value
    if isinstance(value, bool):
        raise TypeError("a boolean is not a number")
    if isinstance(value, (int, np.integer)):
        return sp.Integer(int(value))
    if isinstance(value, (float, np.floating)):
        return number_to_rational(repr(float(value)))
    raise TypeError(f"cannot use {value!r} as a number")


def parameter_symbol(name: str) -> sp.Symbol:
    """The SymPy symbol used for a parameter or free symbol named ``name`` (real)."""
    return sp.Symbol(name, real=True)


# ---------------------------------------------------------------------------------------------
# Loading


class RobotFileReader:
    """Turns the parsed YAML document into a Robot, tracking names in order of appearance."""

    def __init__(self, path: str):
        self.path = path
        self.constants: dict[str, sp.Expr] = {}
        self.runtime: dict[str, sp.Symbol] = {}
        self.runtime_nominal: dict[str, sp.Expr | None] = {}
        self.degrees = False  # angles: degrees
        self.convention = "standard"

    def fail(self, reason: str, link: str | None = None, fld: str | None = None):
        raise RobotFileError(self.path, reason, link=link, field=fld)

    def check_name(self, name: str, link, fld, what="name"):
        if (not NAME_PATTERN.match(name) or len(name) > MAX_NAME or name in _RESERVED_WORDS
                or name.lower() in _RESERVED_FOLDED or _RESERVED_NAME.match(name)):
            self.fail(f"{describe(name)} cannot be used as a {what}: names are letters, digits and '_', "
                      f"start with a letter, have at most {MAX_NAME} characters, and may not be pi, e, E, "
                      "I, sin, cos, sqrt, nan, inf, oo, zoo, a joint variable name (q1, qd1, qdot1, qdd1, "
                      "qddot1, tau1, p...) or a name symdyn uses itself (c1, s1, cse0, ...)", link, fld)

    def warn(self, reason: str, link: str | None = None, fld: str | None = None):
        """A one-line :class:`SymdynWarning` naming the file, link and field."""
        where = [one_line(self.path, 200)] + ([one_line(link, 120)] if link else []) + \
            ([f"field '{one_line(fld, 80)}'"] if fld else [])
        warn(f"{': '.join(where)}: {reason}")

    def resolver(self, link, fld, earlier=False):
        """Names resolve to the parameters declared under ``parameters:`` (``earlier``: inside
        ``parameters:``, only those declared before); any other name is an error."""
        def resolve(name: str) -> sp.Expr:
            if name in self.constants:
                return self.constants[name]
            if name in self.runtime:
                return self.runtime[name]
            known = list(self.constants) + list(self.runtime)
            close = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            where = "earlier under parameters" if earlier else "under parameters: (name: {runtime: true} for a symbol)"
            raise ExpressionError(f"unknown name '{name}': declare it {where}{hint}")
        return resolve

    def number(self, value: Any, link: str | None, fld: str, earlier: bool = False) -> sp.Expr:
        """The exact value of a numeric field: a finite number of magnitude at most
        :data:`MAX_MAGNITUDE` (after folding named constants), or an expression of names."""
        if isinstance(value, bool) or value is None:
            self.fail(f"expected a number or an expression, got {describe(value)}", link, fld)
        if isinstance(value, int):
            result = sp.Integer(value) if abs(value) <= 10**101 else None
        elif isinstance(value, float):
            if not np.isfinite(value):
                self.fail(f"expected a finite number, got {value}", link, fld)
            result = number_to_rational(repr(value))
        elif isinstance(value, str):
            try:
                result = parse_expression(value, self.resolver(link, fld, earlier))
            except ExpressionError as exc:
                self.fail(f"bad expression: {exc}", link, fld)
        else:
            self.fail(f"expected a number or an expression, got {describe(value)}", link, fld)
        if result is None or (result.is_number and abs(result) > MAX_MAGNITUDE):
            self.fail("the value is too large (more than 1e100 in magnitude): check the units", link, fld)
        return result

    def vector(self, value: Any, size: int, link, fld) -> tuple[sp.Expr, ...]:
        if not isinstance(value, (list, tuple)) or len(value) != size:
            self.fail(f"expected a list of {size} numbers", link, fld)
        return tuple(self.number(v, link, f"{fld}[{k}]") for k, v in enumerate(value))

    def read_parameters(self, params: Any):
        if params is None:
            return
        if not isinstance(params, dict):
            self.fail("expected a mapping of names to values", None, "parameters")
        for name, spec in params.items():
            fld = f"parameters.{name}"
            if not isinstance(name, str):
                self.fail(f"parameter names must be text, got {describe(name)}", None, "parameters")
            self.check_name(name, None, fld, "parameter name")
            runtime = False
            if isinstance(spec, dict):
                unknown = sorted(set(map(str, spec)) - {"value", "runtime"})
                if unknown:
                    self.fail(f"unknown key {describe(unknown[0])} (allowed: value, runtime)", None, fld)
                runtime = spec.get("runtime", False)
                if not isinstance(runtime, bool):
                    self.fail("'runtime' must be true or false", None, f"{fld}.runtime")
                if "value" not in spec and not runtime:
                    self.fail("a parameter needs a value (or runtime: true)", None, f"{fld}.value")
                raw = spec.get("value")
            else:
                raw = spec
            value = None if raw is None else self.number(raw, None, fld if not isinstance(spec, dict) else f"{fld}.value", earlier=True)
            if value is None and not runtime:
                self.fail("a parameter needs a value (or runtime: true)", None, fld)
            if runtime:
                if value is not None and value.free_symbols:
                    self.fail("the value of a runtime parameter must be a number", None, f"{fld}.value")
                self.runtime[name] = parameter_symbol(name)
                self.runtime_nominal[name] = value
            else:
                self.constants[name] = value

    def check_format(self, doc: dict) -> None:
        """The top-level ``format`` field: present and the version this symdyn reads."""
        if "format" not in doc:
            self.fail("missing required field", None, "format")
        if doc["format"] != FORMAT_VERSION or isinstance(doc["format"], bool):
            self.fail(f"unsupported format {describe(doc['format'])}; this symdyn reads format {FORMAT_VERSION}",
                      None, "format")

    def robot_name(self, doc: dict) -> str:
        """The top-level ``name``: a lower-case C identifier of at most :data:`MAX_NAME` characters."""
        name = doc.get("name")
        if name is None:
            self.fail("missing required field", None, "name")
        if not isinstance(name, str) or not ROBOT_NAME_PATTERN.match(name) or len(name) > MAX_NAME:
            self.fail(f"{describe(name)} is not a valid name: use lower-case letters, digits and '_', "
                      f"starting with a letter, at most {MAX_NAME} characters", None, "name")
        return name

    def convention_of(self, convention: Any, label: str | None) -> str:
        """A table's ``convention`` field (required)."""
        if convention is None:
            self.fail("missing required field (standard, modified or general)", label, "convention")
        if convention not in CONVENTIONS:
            self.fail(f"unknown convention {describe(convention)} (expected standard, modified or general)",
                      label, "convention")
        return convention

    def read_angles(self, doc: dict) -> None:
        """The top-level ``angles`` unit (radians by default)."""
        angles = doc.get("angles", "radians")
        if angles not in ANGLE_UNITS:
            self.fail(f"unknown angle unit {describe(angles)} (expected radians or degrees)", None, "angles")
        self.degrees = angles == "degrees"

    def read_link(self, index: int, raw: Any, names_seen: set, prefix: str = "") -> Link:
        """Link ``index`` (from 0) of a table; ``prefix`` starts its label in errors (a parallel
        robot's ``leg 2, ``)."""
        label = f"{prefix}link {index + 1}"
        if not isinstance(raw, dict):
            self.fail("expected a mapping with the link's fields", label, None)
        name = raw.get("name", f"j{index + 1}")
        if not isinstance(name, str) or not LINK_NAME_PATTERN.match(name) or len(name) > MAX_NAME:
            self.fail(f"{describe(name)} is not a valid link name: use letters, digits and '_' "
                      f"(not starting with a digit), at most {MAX_NAME} characters", label, "name")
        label = f"{prefix}link {index + 1} ('{name}')"
        if name in names_seen:
            self.fail(f"duplicate link name '{name}'", label, "name")
        names_seen.add(name)
        for key in raw:
            if key not in LINK_KEYS:
                self.fail(f"unknown key {describe(key)} (allowed: {', '.join(LINK_KEYS)})", label, one_line(str(key), 40))
        joint = raw.get("joint")
        if joint is None:
            self.fail("missing required field", label, "joint")
        if joint not in JOINT_TYPES:
            self.fail(f"unknown joint type {describe(joint)} (expected revolute or prismatic)", label, "joint")
        geometry = {}
        if self.convention == "general":
            for key in DH_KEYS:
                if key in raw:
                    self.fail(f"'{key}' is a Denavit-Hartenberg field; under convention: general a link gives "
                              "origin: {xyz, rpy} and axis", label, key)
            geometry = {key: sp.S.Zero for key in DH_KEYS}
            geometry["origin"] = self.placement(raw.get("origin", {}), label, "origin")
            geometry["axis"] = self.axis(raw.get("axis", [0, 0, 1]), label)
        else:
            for key in GENERAL_KEYS:
                if key in raw:
                    self.fail(f"'{key}' needs convention: general (this file uses {self.convention} "
                              "Denavit-Hartenberg parameters)", label, key)
            for key in DH_KEYS:
                if key not in raw:
                    self.fail("missing required field", label, key)
                geometry[key] = self.number(raw[key], label, key)
                if key in ("alpha", "theta"):
                    geometry[key] = self.angle(geometry[key], label, key)
        mass = self.number(raw.get("mass", 0), label, "mass")
        if mass.is_number and mass < 0:
            self.fail(f"mass must not be negative, got {float(mass):g}", label, "mass")
        com = self.vector(raw.get("com", [0, 0, 0]), 3, label, "com")
        if "inertia" not in raw and mass != 0:
            self.warn("a mass but no inertia: a point mass is assumed (write 'inertia: 0' to say so)",
                      label, "inertia")
        inertia = self.read_inertia(raw.get("inertia", 0), label)
        extras = {key: self.number(raw.get(key, 0), label, key) for key in ("armature", "damping", "coulomb")}
        for key, value in extras.items():
            if value.is_number and value < 0:
                self.fail(f"{key} must not be negative, got {float(value):g}", label, key)
        limits = self.limits(raw["limits"], label) if "limits" in raw else None
        actuated = raw.get("actuated", True)
        if not isinstance(actuated, bool):
            self.fail(f"expected true or false, got {describe(actuated)}", label, "actuated")
        return Link(name=name, joint=joint, mass=mass, com=com, inertia=inertia, limits=limits,
                    actuated=actuated, **geometry, **extras)

    def body(self, raw: Any) -> Body:
        """``base_body: {mass, com, inertia}``: the floating base's inertia in the base frame."""
        label, fld = None, "base_body"
        self.check_mapping(raw, BODY_KEYS, label, fld, "expected a mapping {mass, com, inertia}")
        mass = self.number(raw.get("mass", 0), label, f"{fld}.mass")
        if mass.is_number and mass < 0:
            self.fail(f"mass must not be negative, got {float(mass):g}", label, f"{fld}.mass")
        com = self.vector(raw.get("com", [0, 0, 0]), 3, label, f"{fld}.com")
        if "inertia" not in raw and mass != 0:
            self.warn("a mass but no inertia: a point mass is assumed (write 'inertia: 0' to say so)", label,
                      f"{fld}.inertia")
        return Body(mass, com, self.read_inertia(raw.get("inertia", 0), "base_body"))

    def check_mapping(self, raw: Any, allowed: tuple[str, ...], label: str | None, fld: str, expected: str) -> None:
        """``raw`` is a mapping whose keys are all in ``allowed`` (``expected``: the error when it
        is not a mapping)."""
        if not isinstance(raw, dict):
            self.fail(expected, label, fld)
        for key in raw:
            if key not in allowed:
                self.fail(f"unknown key {describe(key)} (allowed: {', '.join(allowed)})", label,
                          f"{fld}.{one_line(str(key), 40)}")

    def placement(self, raw: Any, label: str | None, fld: str) -> Placement:
        """``{xyz: [3 m], rpy: [3 angles]}`` (both optional, default zero)."""
        self.check_mapping(raw, PLACEMENT_KEYS, label, fld, "expected a mapping {xyz: [x, y, z], rpy: [roll, pitch, yaw]}")
        xyz = self.vector(raw.get("xyz", [0, 0, 0]), 3, label, f"{fld}.xyz")
        rpy = self.vector(raw.get("rpy", [0, 0, 0]), 3, label, f"{fld}.rpy")
        rpy = tuple(self.angle(v, label, f"{fld}.rpy[{k}]") for k, v in enumerate(rpy))
        return Placement(xyz, rpy)

    def axis(self, raw: Any, label: str) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
        """A joint axis: three numbers, not all zero, of a length whose square is a normal double
        (:data:`AXIS_LENGTH_RANGE`), normalized exactly."""
        values = self.vector(raw, 3, label, "axis")
        if any(v.free_symbols for v in values):
            self.fail("the axis must be numbers (no parameter names)", label, "axis")
        norm2 = sum(v * v for v in values)
        if norm2 == 0:
            self.fail("the axis is zero: give a direction such as [0, 0, 1]", label, "axis")
        low, high = AXIS_LENGTH_RANGE
        if not low ** 2 <= norm2 <= high ** 2:
            self.fail(f"the axis has length {float(sp.sqrt(norm2)):.3g}: not a direction double precision can "
                      f"normalize (its squared length under- or overflows; other readers, Pinocchio's among them, "
                      f"keep it as written): give a direction of length between {low:g} and {high:g}, such as "
                      "[0, 0, 1]", label, "axis")
        if norm2 == 1:
            return values
        norm = sp.sqrt(norm2)
        return tuple(sp.radsimp(v / norm) for v in values)

    def limits(self, raw: Any, label: str) -> Limits:
        self.check_mapping(raw, LIMIT_KEYS, label, "limits", "expected a mapping {lower, upper, velocity, effort}")
        values = {key: self.number(raw[key], label, f"limits.{key}") for key in LIMIT_KEYS if key in raw}
        for key in ("velocity", "effort"):
            if key in values and values[key].is_number and values[key] < 0:
                self.fail(f"{key} limit must not be negative", label, f"limits.{key}")
        lower, upper = values.get("lower"), values.get("upper")
        if lower is not None and upper is not None and (upper - lower).is_number and upper < lower:
            self.fail("lower limit above upper limit", label, "limits")
        return Limits(**values)

    def angle(self, value: sp.Expr, label: str, fld: str) -> sp.Expr:
        """An angle field in rad: converted from degrees under ``angles: degrees``; a magnitude
        above 2 pi under radians, and pi in an angle under degrees, draw a warning; one above
        :data:`MAX_ANGLE` rad (in every format) is refused."""
        if self.degrees:
            if value.has(sp.pi):
                self.warn(f"'{value}' contains pi but the file says 'angles: degrees', so it is read as "
                          f"{float(value):g} degrees; write it in degrees ({value * 180 / sp.pi} if "
                          f"'{value}' is in radians), or write 'angles: radians'", label, fld)
            value = value * sp.pi / 180
        if value.is_number and abs(value) > MAX_ANGLE:
            self.fail(f"the angle {float(value):.3g} rad is larger than {MAX_ANGLE:g} rad: its sine and cosine "
                      "cannot be computed to the promised accuracy in double (did you mean degrees, or a smaller "
                      "value?)", label, fld)
        if self.degrees:
            return value
        if value.is_number and abs(value) > 2 * sp.pi:
            self.warn(f"{float(value):g} rad looks like degrees (more than 2 pi); write 'angles: degrees' "
                      "at the top of the file if the angles are in degrees", label, fld)
        return value

    def read_inertia(self, raw: Any, label: str) -> tuple[sp.Expr, ...]:
        if isinstance(raw, int) and not isinstance(raw, bool) and raw == 0:
            return (sp.S.Zero,) * 6  # 'inertia: 0': a point mass, said explicitly
        if isinstance(raw, dict):
            for key in raw:
                if key not in INERTIA_KEYS:
                    self.fail(f"unknown inertia component {describe(key)} (allowed: {', '.join(INERTIA_KEYS)})", label, f"inertia.{one_line(str(key), 40)}")
            values = tuple(self.number(raw.get(k, 0), label, f"inertia.{k}") for k in INERTIA_KEYS)
        elif isinstance(raw, (list, tuple)):
            if len(raw) != 6:
                self.fail("expected 6 values [xx, yy, zz, xy, xz, yz] or a mapping", label, "inertia")
            values = tuple(self.number(v, label, f"inertia.{k}") for k, v in zip(INERTIA_KEYS, raw))
        else:
            self.fail("expected a mapping {xx, yy, zz, xy, xz, yz} or a list of 6 values", label, "inertia")
        if all(v.is_number for v in values):
            problem = inertia_problem([float(v) for v in values])
            if problem and "negative" in problem:  # computable (Pinocchio reads it too): said, not refused
                self.warn(problem + " (computed as given: the mass matrix may then be indefinite, and forward "
                          "dynamics return status 1 (singular) wherever a pivot is not positive)", label, "inertia")
            elif problem:
                self.warn(problem + " (computed as given)", label, "inertia")
        return values


def inertia_problem(values: Iterable[float]) -> str | None:
    """Why a numeric inertia (xx, yy, zz, xy, xz, yz) about the COM is not physical, or None."""
    xx, yy, zz, xy, xz, yz = values
    matrix = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]], dtype=float)
    scale = max(1.0, float(np.max(np.abs(matrix))))
    tol = 1e-12 * scale
    eig = np.linalg.eigvalsh(matrix)
    if eig[0] < -tol:
        return f"inertia has a negative principal moment ({eig[0]:.6g}): not positive semi-definite"
    for k in range(3):
        others = eig.sum() - eig[k]
        if eig[k] > others + tol:
            return (f"principal moments {', '.join(f'{e:.6g}' for e in eig)} break the triangle "
                    "inequality (each must be at most the sum of the other two)")
    return None


def loads(text: str, path: str = "<string>") -> Robot:
    """Read a robot from the text of a robot file (YAML or JSON). ``path`` is used in errors."""
    doc = load_yaml(text, path, "YAML")
    return from_document(doc, path, hashlib.sha256(text.encode("utf-8")).hexdigest())


def from_document(doc: Any, path: str, source_hash: str = "") -> Robot:
    """The robot of a parsed robot file (plain data as YAML gives it); ``path`` names the file
    in errors, ``source_hash`` is recorded as the robot's :attr:`Robot.source_hash`."""
    reader = RobotFileReader(path)
    if not isinstance(doc, dict):
        reader.fail("expected a mapping with format, name, convention and links")
    if doc.get("kind") == "parallel":
        reader.fail("a platform robot file (kind: parallel): this command does not take it ('symdyn generate' "
                    "and 'symdyn derive' do; a scene cannot specialize one)", None, "kind")
    if "kind" in doc:
        reader.fail(f"unknown kind {describe(doc['kind'])} (the one kind is 'parallel', for a platform robot; "
                    "a serial robot file has no kind)", None, "kind")
    if "legs" in doc or "platform" in doc:
        reader.fail("'platform' and 'legs' describe a platform robot: add 'kind: parallel' "
                    "(docs/parallel-format.md)", None, "platform" if "platform" in doc else "legs")
    for key in doc:
        if key not in TOP_KEYS:
            reader.fail(f"unknown key {describe(key)} (allowed: {', '.join(TOP_KEYS)})", None, one_line(str(key), 40))
    reader.check_format(doc)
    name = reader.robot_name(doc)
    convention = reader.convention_of(doc.get("convention"), None)
    reader.read_angles(doc)
    reader.convention = convention
    reader.read_parameters(doc.get("parameters"))
    floating = doc.get("base") == "floating"
    if isinstance(doc.get("base"), str) and not floating:
        reader.fail(f"expected 'floating' or a placement {{xyz, rpy}}, got {describe(doc['base'])}", None, "base")
    base = reader.placement(doc["base"], None, "base") if "base" in doc and not floating else None
    base_body = reader.body(doc["base_body"]) if "base_body" in doc else None
    if base_body is not None and not floating:
        reader.fail("a base body needs 'base: floating' (a fixed base's inertia does not move)", None, "base_body")
    tool = reader.placement(doc["tool"], None, "tool") if "tool" in doc else None
    task = task_rows(doc["task"], lambda message: reader.fail(message, None, "task")) if "task" in doc else None
    gravity = (reader.vector(doc["gravity"], 3, None, "gravity") if "gravity" in doc
               else DEFAULT_GRAVITY)
    links_raw = doc.get("links")
    if links_raw is None:
        reader.fail("missing required field", None, "links")
    if not isinstance(links_raw, list):
        reader.fail("expected a list of links", None, "links")
    if not links_raw and doc.get("base") != "floating":
        reader.fail("the chain is empty: give at least one link (or 'base: floating' for one free body)", None, "links")
    names_seen: set = set()
    links = tuple(reader.read_link(k, raw, names_seen) for k, raw in enumerate(links_raw))
    parents = read_parents(reader, links_raw, links)
    links = read_mimics(reader, links_raw, links)
    frames = read_frames(reader, doc["frames"], links) if "frames" in doc else ()
    contacts = ()
    if "contacts" in doc:
        wanted = parse_contacts(doc["contacts"], lambda message, at="": reader.fail(message, None, "contacts" + at),
                                lambda value, at: reader.number(value, None, "contacts" + at),
                                lambda value, at: reader.angle(value, None, "contacts" + at))
        frames, contacts = resolve_contacts(frames, links, wanted,
                                            lambda message, at="": reader.fail(message, None, "contacts" + at))
    runtime_syms = list(reader.runtime.values())
    placements = [e for p in (base, tool, base_body) if p is not None for e in p.expressions()]
    used = set().union(*(e.free_symbols for link in links for e in link.expressions()),
                       *(sp.sympify(g).free_symbols for g in (*gravity, *placements)),
                       *(sp.sympify(e).free_symbols for contact in contacts for e in contact.expressions()))
    parameters = tuple(runtime_syms)
    nominal = tuple(reader.runtime_nominal[s.name] for s in runtime_syms)
    # Drop runtime parameters that nothing uses: they cannot affect any output.
    keep = [(s, v) for s, v in zip(parameters, nominal) if s in used]
    return Robot(
        name=name, convention=convention, gravity=tuple(sp.sympify(g) for g in gravity),
        links=links, parameters=tuple(s for s, _ in keep), nominal=tuple(v for _, v in keep),
        source=path, source_hash=source_hash, base=base, tool=tool, task=task,
        runtime_names=tuple(s.name for s in runtime_syms if s in used),
        parents=parents, floating=floating, base_body=base_body, frames=frames, contacts=contacts)


@dataclass(frozen=True)
class WantedContact:
    """A contact as a file or the command line names it (before its frame is found): the
    frame's name, the kind and the Baumgarte correction (:class:`Contact`)."""

    name: str
    kind: str
    kp: sp.Expr = sp.S.Zero
    kd: sp.Expr = sp.S.Zero
    reference: tuple[sp.Expr, ...] | None = None

    def __str__(self) -> str:
        gains = f" (kp {self.kp}, kd {self.kd})" if self.kp != 0 or self.kd != 0 else ""
        return f"{self.name}:{self.kind}{gains}"


def _numbers_only(value: Any, at: str) -> sp.Expr:
    """A plain finite number (where no parameter names can be resolved: a scene's contacts)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or abs(value) > 1e100:
        raise ExpressionError(f"expected a finite number, not {describe(value)} (expressions of runtime parameters "
                              "belong in the robot file's contacts)")
    return _to_exact(value)


def parse_contacts(raw: Any, fail, number=None, angle=None) -> list[WantedContact]:
    """The contact set as :class:`WantedContact` s: a list of ``NAME:3d`` / ``NAME:6d`` strings or
    ``{frame: NAME, kind: 3d, kp, kd, reference}`` mappings, or one comma-separated string of the
    former (the command line's).  ``fail(message, where)`` reports a mistake (``where``:
    ``[k]``); ``number(value, where)`` reads a gain or reference entry (plain numbers when None),
    ``angle(expr, where)`` turns a sole's reference angle into rad (None: taken as rad)."""
    if isinstance(raw, str):
        raw = [item.strip() for item in raw.split(",") if item.strip()]
    if not isinstance(raw, list) or not raw:
        fail("expected a list of contacts, each FRAME:KIND with KIND " + CONTACT_KINDS_TEXT)
    out: list[WantedContact] = []
    for k, item in enumerate(raw):
        at = f"[{k}]"
        gains: dict = {}
        if isinstance(item, dict):
            unknown = sorted(set(map(str, item)) - set(CONTACT_KEYS))
            if unknown:
                fail(f"unknown field {describe(unknown[0])} (a contact has {', '.join(CONTACT_KEYS)})", at)
            name, kind = item.get("frame"), item.get("kind")
            gains = {key: item[key] for key in ("kp", "kd", "reference") if key in item}
        elif isinstance(item, str) and item.count(":") == 1:
            name, kind = (part.strip() for part in item.split(":"))
        else:
            fail(f"expected FRAME:3d, FRAME:6d or FRAME:xz (or {{frame, kind}}), not {describe(item)}", at)
        if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", name):
            fail(f"expected a frame's name (letters, digits and '_'), not {describe(name)}", at)
        kind = kind.lower() if isinstance(kind, str) else kind
        if kind not in CONTACT_ROWS:
            fail(f"contact {name}: kind {describe(kind)} is not {CONTACT_KINDS_TEXT}", at)
        if any(name == seen.name for seen in out):
            fail(f"frame {describe(name)} is in contact twice", at)
        out.append(WantedContact(name, kind, *_correction(name, kind, gains, at, fail, number, angle)))
    return out


def _correction(name: str, kind: str, gains: dict, at: str, fail, number, angle=None) -> tuple:
    """``(kp, kd, reference)`` of a contact's Baumgarte correction from its mapping's fields."""
    if not gains:
        return sp.S.Zero, sp.S.Zero, None

    def read(value, where):
        try:
            return (number or _numbers_only)(value, f"{at}.{where}")
        except ExpressionError as exc:
            fail(f"contact {name}: {where}: {exc}", f"{at}.{where}")
    kp, kd = (read(gains[key], key) if key in gains else sp.S.Zero for key in ("kp", "kd"))
    for key, gain in (("kp", kp), ("kd", kd)):
        if gain.is_number and gain < 0:
            fail(f"contact {name}: {key} is {float(gain):g}: a gain is at least 0 (a negative one drives the "
                 "contact away from where it is held)", f"{at}.{key}")
    reference = None
    size, shape = (6, "[x, y, z, roll, pitch, yaw], the placement held: its origin in world coordinates (m), its "
                   "rotation about the fixed x, y, z axes (rad)") if kind == "6d" else (
                   3, "[x, y, z], the point held in world coordinates (m)")
    if "reference" in gains:
        raw = gains["reference"]
        if not isinstance(raw, list) or len(raw) != size:
            fail(f"contact {name}: reference: expected {shape}", f"{at}.reference")
        reference = tuple(read(value, f"reference[{i}]") for i, value in enumerate(raw))
        if size == 6 and angle is not None:
            reference = reference[:3] + tuple(angle(e, f"{at}.reference[{3 + i}]") for i, e in enumerate(reference[3:]))
    if kp != 0 and reference is None:
        fail(f"contact {name}: kp needs reference: {shape}: the correction pulls the contact back to it", at)
    if kp == 0 and reference is not None:
        fail(f"contact {name}: reference without kp: the reference is where kp pulls the contact to (give kp, or "
             "leave the reference out)", f"{at}.reference")
    return kp, kd, reference


def resolve_contacts(frames: tuple[NamedFrame, ...], links, wanted, fail) -> tuple[tuple[NamedFrame, ...], tuple[Contact, ...]]:
    """``(frames, contacts)``: each contact's frame found among ``frames`` by name, else a link's
    own frame (appended to the frames); ``fail(message, where)`` for a name that is neither."""
    frames = list(frames)
    index = {link.name: k for k, link in enumerate(links)}
    contacts = []
    for k, want in enumerate(wanted):
        name = want.name
        found = next((i for i, frame in enumerate(frames) if frame.name == name), None)
        if found is None:
            if name not in index:
                known = [frame.name for frame in frames] + list(index)
                fail(f"no frame or link named {describe(name)}{_did_you_mean(name, known)} (a contact is held at a "
                     "frame of 'frames:' or at a link's own frame)", f"[{k}]")
            frames.append(NamedFrame(name, index[name]))
            found = len(frames) - 1
        contacts.append(Contact(found, want.kind, want.kp, want.kd, want.reference))
    return tuple(frames), tuple(contacts)


def _did_you_mean(name: Any, names) -> str:
    close = difflib.get_close_matches(name, list(names), n=1, cutoff=0.6) if isinstance(name, str) else []
    return f"; did you mean '{close[0]}'?" if close else ""


def read_frames(reader: RobotFileReader, raw: Any, links: tuple[Link, ...]) -> tuple[NamedFrame, ...]:
    """``frames:``: a list of link names (each link's own frame) and of frames fixed in a link,
    ``{name, link, xyz, rpy}`` (``link``: a link's name or ``base``; the placement in numbers)."""
    if not isinstance(raw, list) or not raw:
        reader.fail("expected a list of link names and {name, link, xyz, rpy} frames", None, "frames")
    index = {link.name: k for k, link in enumerate(links)}
    out: list[NamedFrame] = []
    for k, item in enumerate(raw):
        fld = f"frames[{k}]"
        if isinstance(item, str):
            if item not in index:
                reader.fail(f"no link named {describe(item)}{_did_you_mean(item, index)} (a frame given by name "
                            "is a link's own frame; a frame elsewhere is {name, link, xyz, rpy})", None, fld)
            out.append(NamedFrame(item, index[item]))
            continue
        reader.check_mapping(item, FRAME_KEYS, None, fld, "expected a link name or a mapping {name, link, xyz, rpy}")
        name, link = item.get("name"), item.get("link")
        if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", name):
            reader.fail(f"expected a name of letters, digits and '_' (at most 64), not {describe(name)}", None,
                        f"{fld}.name")
        if name in index:
            reader.fail(f"{describe(name)} is the name of a link (whose own frame it would hide): choose another",
                        None, f"{fld}.name")
        if link != "base" and link not in index:
            reader.fail(f"no link named {describe(link)}{_did_you_mean(link, index)} (or 'base')", None, f"{fld}.link")
        placement = reader.placement({key: item[key] for key in PLACEMENT_KEYS if key in item}, None, fld)
        if any(sp.sympify(v).free_symbols for v in placement.expressions()):
            reader.fail("a frame's placement takes numbers (no parameter names)", None, fld)
        out.append(NamedFrame(name, -1 if link == "base" else index[link], tuple(placement.matrix())))
    names = [frame.name for frame in out]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        reader.fail(f"frame {describe(twice[0])} is listed twice", None, "frames")
    return tuple(out)


def read_mimics(reader: RobotFileReader, links_raw: list, links: tuple[Link, ...]) -> tuple[Link, ...]:
    """The links with their ``mimic: {joint, multiplier, offset}`` fields read: the joint
    follows the named link's joint (q = multiplier * q_joint + offset; numbers only, the offset in
    the file's angle unit for a revolute joint).  The leader must have its own coordinate (not be a
    mimic itself); a mimic joint cannot be passive (``actuated: false``)."""
    index = {link.name: k for k, link in enumerate(links)}
    out = list(links)
    for k, (raw, link) in enumerate(zip(links_raw, links)):
        if "mimic" not in raw:
            continue
        label = f"link {k + 1} ('{link.name}')"
        item = raw["mimic"]
        reader.check_mapping(item, MIMIC_KEYS, label, "mimic", "expected a mapping {joint, multiplier, offset}")
        leader = item.get("joint")
        if leader not in index:
            reader.fail(f"no link named {describe(leader)}{_did_you_mean(leader, index)} (the link whose joint "
                        "this one follows)", label, "mimic.joint")
        if leader == link.name:
            reader.fail("a joint cannot follow itself", label, "mimic.joint")
        if "mimic" in links_raw[index[leader]]:
            reader.fail(f"'{leader}' is a mimic joint itself: name the joint it follows (multiply the "
                        "multipliers, compose the offsets)", label, "mimic.joint")
        values = {}
        for key, default in (("multiplier", 1), ("offset", 0)):
            value = reader.number(item.get(key, default), label, f"mimic.{key}")
            if value.free_symbols:
                reader.fail("a mimic's multiplier and offset take numbers (no parameter names)", label, f"mimic.{key}")
            values[key] = value
        if values["multiplier"] == 0:
            reader.fail("a multiplier of 0 fixes the joint: merge it as a fixed joint instead", label,
                        "mimic.multiplier")
        if link.is_revolute:
            values["offset"] = reader.angle(values["offset"], label, "mimic.offset")
        if not link.actuated or not links[index[leader]].actuated:
            reader.fail("a mimic joint and its leader must be actuated (passive joints with mimics are not "
                        "supported)", label, "mimic")
        out[k] = replace(link, mimic=Mimic(index[leader], values["multiplier"], values["offset"]))
    return tuple(out)


def read_parents(reader: RobotFileReader, links_raw: list, links: tuple[Link, ...]) -> tuple[int, ...]:
    """The links' ``parent:`` fields as indices (-1: ``base``); ``()`` when every link hangs on
    the one before it (a serial chain, the default).  A parent must be ``base`` or the name of
    an earlier link, so that the file lists every link after the one it hangs on."""
    index = {link.name: k for k, link in enumerate(links)}
    parents = []
    for k, (raw, link) in enumerate(zip(links_raw, links)):
        label = f"link {k + 1} ('{link.name}')"
        name = raw.get("parent", links[k - 1].name if k > 0 else "base")
        if name == "base":
            parents.append(-1)
            continue
        if not isinstance(name, str):
            reader.fail(f"expected the name of an earlier link or 'base', got {describe(name)}", label, "parent")
        if name not in index:
            close = difflib.get_close_matches(name, list(index) + ["base"], n=1, cutoff=0.6)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            reader.fail(f"no link named {describe(name)}{hint}", label, "parent")
        if index[name] >= k:
            reader.fail(f"'{name}' comes {'at' if index[name] == k else 'after'} this link in the file: list every "
                        "link after the link it hangs on", label, "parent")
        parents.append(index[name])
    chain = tuple(range(-1, len(links) - 1))
    return () if tuple(parents) == chain else tuple(parents)


def task_rows(raw, fail) -> tuple[int, ...]:
    """The rows of a ``task:`` field: ``pose``, ``position``, ``orientation`` or a list of
    distinct row indices 0-5 of the tool Jacobian (kept in the order given); ``fail(message)``
    raises the caller's error."""
    if isinstance(raw, str):
        if raw not in TASKS:
            fail(f"unknown task {describe(raw)} (allowed: {', '.join(TASKS)}, or a list of Jacobian rows 0-5, "
                 "e.g. [0, 1] for x and y)")
        return TASKS[raw]
    if not isinstance(raw, list) or not raw:
        fail(f"expected {', '.join(TASKS)} or a non-empty list of Jacobian rows 0-5, not {describe(raw)}")
    rows = []
    for value in raw:
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 5:
            fail(f"a task row is an integer 0-5 (0-2: linear x, y, z; 3-5: angular x, y, z), not {describe(value)}")
        if value in rows:
            fail(f"task row {value} is listed twice")
        rows.append(value)
    return tuple(rows)


#: the lengths a joint axis may have (its square a normal double, with margin): it is normalized
#: exactly, but a reader that normalizes in double (Pinocchio's URDF parser) keeps 1e-300 0 0 as
#: written, and the Jacobian then differs by 1e300
AXIS_LENGTH_RANGE = (1e-150, 1e150)


def serial_robot(robot) -> Robot:
    """``robot`` when it is a serial robot (a chain, a tree or a floating base, which symdyn.derive
    derives); else a SymdynError in one line naming it (a platform robot is derived by
    symdyn.derive.parallel.derive_parallel)."""
    if not isinstance(robot, Robot):
        raise SymdynError(f"{getattr(robot, 'source', '') or getattr(robot, 'name', robot)}: not a serial robot; "
                          "a platform robot (kind: parallel) is derived by symdyn.derive.parallel.derive_parallel")
    return robot


def load(path: str | os.PathLike) -> Robot:
    """Read a robot file (format version 1, YAML or JSON); :func:`symdyn.model.scene.load`
    (``symdyn.load``) reads scenes too.

    Raises :class:`RobotFileError` naming the file, link and field for any problem, including a
    file that cannot be read (see :mod:`symdyn.model.inputs` for the size and type limits).
    """
    path = os.fspath(path)
    return loads(decode_text(read_input(path), path), path)
