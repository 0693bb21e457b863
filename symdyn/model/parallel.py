"""Parallel (platform) robots: a moving platform coupled to a fixed base by six serial legs.

The model of the notes on the dynamics of parallel manipulators (after Angeles): a moving platform M
and six legs, each a six-joint serial chain from the base to the platform with exactly one
actuated joint, so that the six actuated joint variables ``q`` are as many as the platform's
degrees of freedom.  The file format (``kind: parallel``) is specified in
``docs/parallel-format.md``; this module reads it into an immutable :class:`ParallelRobot`.

Frames.  The world frame W is the base's; the platform frame P is fixed to the platform (its
pose in W is the robot's configuration).  Leg J is a serial robot whose frame 0 is placed in W
by the leg's ``base`` placement and whose last link frame (frame 6) is fixed to the platform:
the leg's ``platform`` placement is the pose of that frame in P.  Each leg is read with the
serial reader (:mod:`symdyn.model.robot`), so its table, units, parameters and checks are those
of a serial robot file.
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import sympy as sp

from .errors import describe, one_line
from .geometry import numeric_pose
from .inputs import decode_text, load_yaml, read_input
from .robot import DEFAULT_GRAVITY, MAX_NAME, ROBOT_NAME_PATTERN, Body, Placement, Robot, RobotFileReader

#: the value of the top-level ``kind`` field of a parallel robot file
KIND = "parallel"
TOP_KEYS = ("format", "kind", "name", "angles", "parameters", "gravity", "platform", "leg", "legs")
PLATFORM_KEYS = ("mass", "com", "inertia")
SHARED_LEG_KEYS = ("convention", "actuated", "links", "home")
LEG_KEYS = ("name", "base", "platform", *SHARED_LEG_KEYS)
#: how far (m, and rad times 1 m) the platform poses the legs' home configurations give may be
#: apart (the files' numbers have about ten digits)
HOME_TOLERANCE = 1e-6
#: legs of a platform robot, and joints of each leg (the natural orthogonal complement of the
#: parallel-manipulator notes needs one actuated joint per leg and as many legs as the platform's degrees of freedom)
LEG_COUNT = 6
LEG_JOINTS = 6


@dataclass(frozen=True)
class Platform(Body):
    """The moving platform's inertial data: mass (kg), centre of mass (m, in the platform frame
    P) and inertia about the centre of mass in P's axes (kg m^2; ``xx, yy, zz, xy, xz, yz``)."""


@dataclass(frozen=True)
class Leg:
    """One leg: a six-joint serial chain from the base to the platform.

    ``chain`` is the leg as a serial :class:`Robot` (its ``base`` is the leg's frame 0 in the
    world frame, its links the leg's table, its gravity the parallel robot's); ``attachment`` is
    the pose of the leg's last link frame (frame 6, fixed to the platform) in the platform
    frame P; ``actuated`` is the index (from 0) of the leg's one actuated joint.
    """

    name: str
    chain: Robot
    attachment: Placement
    actuated: int
    #: the leg's joint variables (rad or m) in the robot's home pose, or None: they pick the
    #: branches of the closed-form inverse kinematics (symdyn.derive.parallel_ik)
    home: tuple[sp.Expr, ...] | None = None

    @property
    def actuated_link(self):
        return self.chain.links[self.actuated]


@dataclass(frozen=True)
class ParallelRobot:
    """A platform robot (see the module docstring): immutable, every value a SymPy expression.

    ``parameters`` are the runtime parameters the model uses (in order of declaration), with
    their ``nominal`` values (None when the file gives none); ``q`` of the generated functions is
    the six actuated joint variables, leg by leg.
    """

    name: str
    gravity: tuple[sp.Expr, sp.Expr, sp.Expr]
    platform: Platform
    legs: tuple[Leg, ...]
    parameters: tuple[sp.Symbol, ...] = ()
    nominal: tuple[sp.Expr | None, ...] = ()
    source: str = ""
    source_hash: str = ""

    @property
    def dof(self) -> int:
        """The platform's degrees of freedom (= actuated joints)."""
        return len(self.legs)

    @property
    def actuated_joints(self) -> tuple[str, ...]:
        """``leg.joint`` names of the actuated joints, in the order of ``q``."""
        return tuple(f"{leg.name}.{leg.actuated_link.name}" for leg in self.legs)


class _ParallelReader(RobotFileReader):
    """The serial reader, plus the platform and the legs."""

    def platform(self, raw: Any) -> Platform:
        self.check_mapping(raw, PLATFORM_KEYS, None, "platform", "expected a mapping {mass, com, inertia}")
        if "mass" not in raw:
            self.fail("missing required field", None, "platform.mass")
        mass = self.number(raw["mass"], None, "platform.mass")
        if mass.is_number and mass < 0:
            self.fail(f"mass must not be negative, got {float(mass):g}", None, "platform.mass")
        if mass.is_number and mass == 0:
            self.warn("a massless platform: its six degrees of freedom get their inertia from the legs "
                      "only (computed as given)", None, "platform.mass")
        com = self.vector(raw.get("com", [0, 0, 0]), 3, None, "platform.com")
        if "inertia" not in raw and mass != 0:
            self.warn("a mass but no inertia: a point mass is assumed (write 'inertia: 0' to say so)",
                      None, "platform.inertia")
        inertia = self.read_inertia(raw.get("inertia", 0), "platform")
        return Platform(mass, com, inertia)

    def leg_table(self, raw: dict, shared: dict, label: str) -> tuple[str, int, list]:
        """``(convention, actuated index, raw links)`` of a leg: its own fields, else the shared
        ``leg:`` table's."""
        source = raw if "links" in raw else shared
        where = label if "links" in raw else "leg"
        if "links" not in source:
            self.fail("missing required field: give the leg's links, or a shared table under the "
                      "top-level 'leg:'", label, "links")
        for key in ("convention", "actuated"):
            if key in raw and "links" not in raw:
                self.fail(f"'{key}' of a leg goes with its own 'links' (the shared table's is under "
                          "the top-level 'leg:')", label, key)
        convention = self.convention_of(source.get("convention"), where)
        actuated = source.get("actuated")
        if actuated is None:
            self.fail(f"missing required field: the number (1 to {LEG_JOINTS}) of the leg's actuated joint",
                      where, "actuated")
        if isinstance(actuated, bool) or not isinstance(actuated, int) or not 1 <= actuated <= LEG_JOINTS:
            self.fail(f"expected the number (1 to {LEG_JOINTS}) of the leg's one actuated joint, got "
                      f"{describe(actuated)}", where, "actuated")
        links = source["links"]
        if not isinstance(links, list):
            self.fail("expected a list of links", where, "links")
        if len(links) != LEG_JOINTS:
            self.fail(f"a leg has {LEG_JOINTS} joints (a platform robot's leg joins the base to the "
                      f"platform's six degrees of freedom), this table has {len(links)}", where, "links")
        for k, link in enumerate(links):
            if isinstance(link, dict) and "actuated" in link:
                self.fail("a leg marks its one actuated joint with the leg's 'actuated: K', not per link",
                          f"{where}, link {k + 1}", "actuated")
        return convention, actuated - 1, links

    def leg(self, index: int, raw: Any, shared: dict, robot_name: str, gravity, names: set) -> Leg:
        label = f"leg {index + 1}"
        if not isinstance(raw, dict):
            self.fail("expected a mapping {name, base, platform} (and the leg's own table, if it has one)",
                      label, None)
        for key in raw:
            if key not in LEG_KEYS:
                self.fail(f"unknown key {describe(key)} (allowed: {', '.join(LEG_KEYS)})", label,
                          one_line(str(key), 40))
        name = raw.get("name", f"leg{index + 1}")
        if not isinstance(name, str) or not ROBOT_NAME_PATTERN.match(name) or \
                len(robot_name) + 1 + len(name) > MAX_NAME:
            self.fail(f"{describe(name)} is not a valid leg name: lower-case letters, digits and '_', "
                      f"starting with a letter, and at most {MAX_NAME} characters together with the robot's "
                      "name and '_'", label, "name")
        if name in names:
            self.fail(f"duplicate leg name '{name}'", label, "name")
        names.add(name)
        label = f"leg {index + 1} ('{name}')"
        for key in ("base", "platform"):
            if key not in raw:
                self.fail("missing required field (a placement {xyz: [x, y, z], rpy: [roll, pitch, yaw]})",
                          label, key)
        base = self.placement(raw["base"], label, "base")
        attachment = self.placement(raw["platform"], label, "platform")
        convention, actuated, links_raw = self.leg_table(raw, shared, label)
        self.convention = convention
        seen: set = set()
        prefix = f"{label}, " if "links" in raw else "leg, "  # the shared table's errors name 'leg:'
        links = tuple(self.read_link(k, link, seen, prefix=prefix) for k, link in enumerate(links_raw))
        chain = Robot(name=f"{robot_name}_{name}", convention=convention, gravity=gravity, links=links,
                      source=self.path, base=None if base.is_identity else base)
        home = None
        home_raw = raw["home"] if "home" in raw else shared.get("home") if "links" not in raw else None
        if home_raw is not None:
            where = label if "home" in raw else "leg"
            values = self.vector(home_raw, LEG_JOINTS, where, "home")
            home = tuple(self.angle(v, where, f"home[{k}]") if link.is_revolute else v
                         for k, (v, link) in enumerate(zip(values, links)))
        return Leg(name=name, chain=chain, attachment=attachment, actuated=actuated, home=home)

    def check_home(self, legs: tuple[Leg, ...]) -> None:
        """Every leg has a home configuration or none does; numeric ones must hold the platform
        at one pose (each leg's frame 6, moved back by its attachment, gives the platform frame)."""
        given = [leg.home is not None for leg in legs]
        if not any(given):
            return
        if not all(given):
            missing = given.index(False)
            self.fail("give the home configuration of every leg (under the shared 'leg:' or each leg), or "
                      "of none", f"leg {missing + 1} ('{legs[missing].name}')", "home")
        poses = []
        for leg in legs:
            exprs = [*leg.home, *leg.chain.base_matrix(), *(e for link in leg.chain.links for e in link.expressions()),
                     *leg.attachment.expressions()]
            if any(sp.sympify(e).free_symbols for e in exprs):
                return  # runtime parameters: checked when they get values
            base = np.array(leg.chain.base_matrix(), dtype=float)
            poses.append(base @ numeric_pose(leg.chain, leg.home)
                         @ np.linalg.inv(np.array(leg.attachment.matrix(), dtype=float)))
        for k, pose in enumerate(poses[1:], start=1):
            offset = float(np.abs(pose[:3, 3] - poses[0][:3, 3]).max())
            turn = float(np.abs(pose[:3, :3] - poses[0][:3, :3]).max())
            if max(offset, turn) > HOME_TOLERANCE:
                self.fail(f"the legs' home configurations do not hold the platform at one pose: this leg "
                          f"puts the platform frame {offset:.3g} m and {np.degrees(turn):.3g} deg away from where "
                          f"leg 1 puts it", f"leg {k + 1} ('{legs[k].name}')", "home")


def is_parallel_document(doc: Any) -> bool:
    """Whether a parsed robot file is a parallel robot (top-level ``kind: parallel``)."""
    return isinstance(doc, dict) and doc.get("kind") == KIND


def from_document(doc: Any, path: str, source_hash: str = "") -> ParallelRobot:
    """The parallel robot of a parsed ``kind: parallel`` file; ``path`` names the file in errors."""
    reader = _ParallelReader(path)
    if not isinstance(doc, dict):
        reader.fail("expected a mapping with format, kind, name, platform and legs")
    for key in doc:
        if key not in TOP_KEYS:
            reader.fail(f"unknown key {describe(key)} (allowed in a parallel robot file: {', '.join(TOP_KEYS)})",
                        None, one_line(str(key), 40))
    reader.check_format(doc)
    if doc.get("kind") != KIND:
        reader.fail(f"expected kind: {KIND}", None, "kind")
    name = reader.robot_name(doc)
    reader.read_angles(doc)
    reader.read_parameters(doc.get("parameters"))
    gravity = tuple(sp.sympify(g) for g in (reader.vector(doc["gravity"], 3, None, "gravity")
                                            if "gravity" in doc else DEFAULT_GRAVITY))
    if "platform" not in doc:
        reader.fail("missing required field", None, "platform")
    platform = reader.platform(doc["platform"])
    shared = doc.get("leg", {})
    if not isinstance(shared, dict):
        reader.fail("expected a mapping {convention, actuated, links}: the table every leg shares", None, "leg")
    for key in shared:
        if key not in SHARED_LEG_KEYS:
            reader.fail(f"unknown key {describe(key)} (allowed: {', '.join(SHARED_LEG_KEYS)})", "leg",
                        one_line(str(key), 40))
    legs_raw = doc.get("legs")
    if legs_raw is None:
        reader.fail("missing required field", None, "legs")
    if not isinstance(legs_raw, list) or len(legs_raw) != LEG_COUNT:
        count = len(legs_raw) if isinstance(legs_raw, list) else describe(legs_raw)
        reader.fail(f"expected a list of {LEG_COUNT} legs (one actuated joint each, as many as the "
                    f"platform's degrees of freedom), got {count}", None, "legs")
    names: set = set()
    legs = tuple(reader.leg(k, raw, shared, name, gravity, names) for k, raw in enumerate(legs_raw))
    reader.check_home(legs)
    used = set().union(*(sp.sympify(e).free_symbols for e in (*gravity, *platform.expressions())),
                       *(e.free_symbols for leg in legs for link in leg.chain.links for e in link.expressions()),
                       *(sp.sympify(e).free_symbols for leg in legs
                         for e in (*leg.attachment.expressions(),
                                   *(leg.chain.base.expressions() if leg.chain.base else ()))))
    keep = [(s, reader.runtime_nominal[s.name]) for s in reader.runtime.values() if s in used]
    legs = tuple(replace(leg, chain=_with_parameters(leg.chain, keep, source_hash)) for leg in legs)
    return ParallelRobot(name=name, gravity=gravity, platform=platform, legs=legs,
                         parameters=tuple(s for s, _ in keep), nominal=tuple(v for _, v in keep),
                         source=path, source_hash=source_hash)


def _with_parameters(chain: Robot, keep, source_hash: str) -> Robot:
    """The leg's chain with the runtime parameters it uses (in the file's order)."""
    exprs = [e for link in chain.links for e in link.expressions()] + list(chain.gravity)
    if chain.base is not None:
        exprs += list(chain.base.expressions())
    used = set().union(*(sp.sympify(e).free_symbols for e in exprs))
    own = [(s, v) for s, v in keep if s in used]
    return replace(chain, parameters=tuple(s for s, _ in own), nominal=tuple(v for _, v in own),
                   runtime_names=tuple(s.name for s, _ in own), source_hash=source_hash)


def loads(text: str, path: str = "<string>") -> ParallelRobot:
    """Read a parallel robot from the text of a ``kind: parallel`` file (YAML or JSON)."""
    doc = load_yaml(text, path, "YAML")
    return from_document(doc, path, hashlib.sha256(text.encode("utf-8")).hexdigest())


def load(path: str | os.PathLike) -> ParallelRobot:
    """Read a ``kind: parallel`` robot file; errors name the file, the leg, the link and the field
    (:class:`symdyn.model.errors.RobotFileError`)."""
    path = os.fspath(path)
    return loads(decode_text(read_input(path), path), path)


__all__ = ["ParallelRobot", "Platform", "Leg", "load", "loads", "from_document", "is_parallel_document",
           "LEG_COUNT", "LEG_JOINTS"]
