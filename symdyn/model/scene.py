"""Scenes: model only what an application needs (format in docs/scene-format.md).

A scene names a robot file and specializes it: the functions wanted, joints locked at given
values (removed from q, their links merged into the parent), a payload on the last link (numbers
or runtime parameters), which named parameters stay runtime inputs (all others folded to their
values) and the precision.  :func:`load_scene` returns a plain :class:`~symdyn.model.robot.Robot`, so
every derivation and emitter works on it unchanged.
"""

from __future__ import annotations

import difflib
import hashlib
import math
import os
import re
import warnings
from dataclasses import dataclass, replace

import sympy as sp

from .errors import RobotFileError, SymdynError, SymdynWarning, describe, display_path, one_line, warn
from .geometry import joint_geometry, joint_motion
from .outputs import ALL_OUTPUTS
from .inputs import decode_text, load_yaml, read_input
from .mjcf import xml_top_element
from .robot import MAX_NAME, ROBOT_NAME_PATTERN, Link, Robot, from_document, parse_contacts, resolve_contacts, task_rows

SCENE_VERSION = 1
SCENE_KEYS = ("scene", "robot", "tip", "tool", "task", "exact_angles", "floating_base", "frames", "contacts", "name", "functions", "precision", "lock", "payload",
              "runtime", "values")
PAYLOAD_KEYS = ("mass", "com", "inertia")
NAME_TOKEN = re.compile(r"(?<![0-9.])\b[A-Za-z_][A-Za-z0-9_]*")
#: the largest magnitude of a lock value (rad or m)
MAX_LOCK_VALUE = 1e6


@dataclass(frozen=True)
class Scene:
    """A specialized robot and what to emit for it."""

    robot: Robot
    functions: tuple[str, ...] | None
    precision: str | None
    notes: tuple[str, ...]  # what the scene did, for the generated header
    source: str
    source_hash: str
    #: the joints the scene locked: ``(joint index from 1, link name, value in rad or m)`` in the
    #: numbering of the robot file it reads (for the generated header's list of constants)
    locked: tuple[tuple[int, str, sp.Expr], ...] = ()


def is_urdf(path) -> bool:
    """Whether ``path`` names a URDF file (by its extension, ``.urdf`` in any case)."""
    return os.fspath(path).lower().endswith(".urdf")


def _top_element(path) -> str | None:
    """The top element of an ``.xml`` or ``.mjcf`` file (best effort: None when it cannot be
    read; reading it reports the problem)."""
    try:
        return xml_top_element(decode_text(read_input(os.fspath(path)), os.fspath(path)))
    except (SymdynError, OSError):
        return None


def is_mjcf(path) -> bool:
    """Whether ``path`` names a MuJoCo MJCF file: extension ``.mjcf``, or ``.xml`` with a
    ``<mujoco>`` top element."""
    name = os.fspath(path).lower()
    return name.endswith(".mjcf") or (name.endswith(".xml") and _top_element(path) == "mujoco")


def is_robot_xml(path) -> bool:
    """Whether ``path`` is read as XML (a URDF, ``.urdf`` or ``.xml`` with a ``<robot>`` top
    element, or an MJCF), not as a YAML robot file or scene."""
    name = os.fspath(path).lower()
    return is_urdf(path) or name.endswith(".mjcf") or (name.endswith(".xml") and _top_element(path) is not None)


def read_robot_document(path: str, tip: str | None = None, tool: str | None = None,
                        option: str = "--tip/--tool", exact_angles: bool = False, floating_base: bool = False,
                        frames: list[str] | None = None):
    """``(document, raw bytes, notes)`` of a robot file: a YAML/JSON robot file (or scene) as
    parsed, or a URDF turned into the format's general form (:mod:`symdyn.model.urdf`;
    ``tip``/``tool`` name its tip and tool links, ``exact_angles`` keeps near-quarter-turn rpy
    angles as written).  ``frames``: the frames of the frame functions, by name (a URDF's
    links; a robot file's links or the frames its ``frames:`` defines), in place of the file's."""
    raw = read_input(path)
    text = decode_text(raw, path)
    top = None if is_urdf(path) else xml_top_element(text)
    if top not in (None, "mujoco", "robot") or (top is None and path.lower().endswith((".mjcf", ".xml"))):
        raise RobotFileError(path, f"an XML file whose top element is {describe('<' + top + '>') if top else 'not found'}: "
                                   "symdyn reads URDF (<robot>) and MuJoCo MJCF (<mujoco>) files")
    if top == "mujoco":
        if floating_base:
            raise RobotFileError(path, "an MJCF says itself whether its base floats (a <freejoint> on a body of the "
                                       "world): --floating-base applies to URDF files")
        if tip is not None or tool is not None:
            raise RobotFileError(path, f"{option} apply to URDF files (an MJCF is read whole; its sites are frames)")
        from .mjcf import read_mjcf
        doc, notes = read_mjcf(text, path, frames=frames, exact_angles=exact_angles)
        return doc, raw, tuple(notes)
    if is_urdf(path) or top == "robot":
        from .urdf import read_urdf
        doc, notes = read_urdf(text, path, tip=tip, tool=tool, exact_angles=exact_angles, floating_base=floating_base,
                               frames=frames)
        return doc, raw, tuple(notes)
    if floating_base:
        raise RobotFileError(path, "--floating-base applies to URDF files only (a robot file says 'base: floating')")
    if tip is not None or tool is not None:
        raise RobotFileError(path, f"{option} apply to URDF files only (a robot file names its tool with 'tool:')")
    if exact_angles:
        raise RobotFileError(path, "exact angles apply to URDF files only (a scene of a URDF says 'exact_angles: true')")
    doc = load_yaml(text, path)
    if frames and isinstance(doc, dict) and "scene" not in doc:
        defined = {item.get("name"): item for item in doc.get("frames") or [] if isinstance(item, dict)}
        doc["frames"] = [defined.get(name, name) for name in frames]  # links by name; the file checks them
    return doc, raw, ()


def load_input(path: str, tip: str | None = None, tool: str | None = None, exact_angles: bool = False,
               parallel: bool = False, floating_base: bool = False, frames: list[str] | None = None,
               contacts=None):
    """A robot file, a URDF or a scene (told apart by a top-level ``scene`` key), read once:
    returns ``(robot, scene or None)``.  ``tip``/``tool``/``exact_angles``: how to read a URDF
    (:func:`symdyn.model.urdf.read_urdf`).  ``parallel``: a platform robot file (``kind:
    parallel``) gives its :class:`symdyn.model.parallel.ParallelRobot` (else it is refused).
    ``contacts``: the contact set (``FRAME:3d,FRAME:6d``, :func:`symdyn.model.robot.parse_contacts`)
    in place of the file's or scene's; a URDF's contact frames are read as its frames are."""
    path = os.fspath(path)
    wanted = None
    if contacts is not None:
        wanted = parse_contacts(contacts, lambda message, at="": _fail(path, f"--contacts{at}: {message}"))
        if is_robot_xml(path):
            frames = list(frames or []) + [c.name for c in wanted if c.name not in (frames or [])]
    doc, raw, notes = read_robot_document(path, tip, tool, exact_angles=exact_angles, floating_base=floating_base,
                                          frames=frames)
    if parallel:
        from .parallel import from_document as parallel_document, is_parallel_document
        if is_parallel_document(doc):
            if wanted:
                _fail(path, "a platform robot has no contact set (its legs' closures are its constraints)", "contacts")
            return parallel_document(doc, path, hashlib.sha256(raw).hexdigest()), None
    if isinstance(doc, dict) and "scene" in doc:
        scene = _build_scene(path, raw, doc, frames, wanted)
        return scene.robot, scene
    robot = from_document(doc, path, hashlib.sha256(raw).hexdigest())
    if wanted is not None:
        robot = _with_contacts(path, robot, wanted, "--contacts")
    return (replace(robot, notes=notes) if notes else robot), None


def _with_contacts(path: str, robot: Robot, wanted, where: str) -> Robot:
    """``robot`` with the contact set ``wanted`` (:class:`~symdyn.model.robot.WantedContact` s) in place of its own."""
    frames, contacts = resolve_contacts(robot.frames, robot.links, wanted,
                                        lambda message, at="": _fail(path, f"{where}{at}: {message}"))
    return replace(robot, frames=frames, contacts=contacts)


def input_files(path: str) -> list[str]:
    """The files reading ``path`` involves: ``path`` itself and, for a scene, the robot file it
    names (resolved against the scene's directory).  Best effort: a file that cannot be read or
    parsed just adds nothing (loading it reports the problem)."""
    paths = [os.fspath(path)]
    try:
        doc = load_yaml(decode_text(read_input(paths[0]), paths[0]), paths[0])
    except (SymdynError, OSError, ValueError):
        return paths
    if isinstance(doc, dict) and "scene" in doc and isinstance(doc.get("robot"), str):
        paths.append(os.path.join(os.path.dirname(os.path.abspath(paths[0])), doc["robot"]))
    return paths


def load(path, tip: str | None = None, tool: str | None = None, exact_angles: bool = False,
         floating_base: bool = False, frames: list[str] | None = None) -> Robot:
    """The robot of a robot file, a URDF (``tip``/``tool``: its tip and tool links;
    ``exact_angles``: rpy angles as written; ``floating_base``: the whole tree on a free root
    link; see :func:`symdyn.model.urdf.read_urdf`) or a scene (``symdyn.load``): a scene's
    specialized robot.  ``frames``: the frames of the frame functions by name (URDF links, a
    robot file's links or the frames its ``frames:`` defines), in place of the file's."""
    return load_input(os.fspath(path), tip, tool, exact_angles, floating_base=floating_base, frames=frames)[0]


def _payload_names(payload) -> set[str]:
    """The names the payload's fields use (best effort: the robot reader checks them again)."""
    if not isinstance(payload, dict):
        return set()
    texts = []
    for value in payload.values():
        items = value.values() if isinstance(value, dict) else value if isinstance(value, list) else [value]
        texts.extend(v for v in items if isinstance(v, str))
    return {name for text in texts for name in NAME_TOKEN.findall(text)} - {"pi"}


def _fail(path, reason, fld=None):
    raise RobotFileError(path, reason, field=fld)


def _transform(robot: Robot, link: Link, value) -> sp.Matrix:
    """The constant 4x4 transform of a link with its joint at ``value``."""
    geo = joint_geometry(link, robot.convention)
    return sp.Matrix(geo.pre) * joint_motion(link, value) * sp.Matrix(geo.post)


def merge_bodies(m1, c1, I1, m2, c2, I2):
    """Mass, COM and inertia about the COM of two rigid bodies given in one frame."""
    m = sp.expand(m1 + m2)
    if m == 0:
        return m, sp.zeros(3, 1), I1 + I2
    c = (m1 * c1 + m2 * c2) / m
    eye = sp.eye(3)

    def shifted(mk, ck, Ik):
        d = ck - c
        return Ik + mk * ((d.T * d)[0] * eye - d * d.T)
    return m, c, shifted(m1, c1, I1) + shifted(m2, c2, I2)


def _with_body(link: Link, m, c, inertia) -> Link:
    def simplify(e):
        e = sp.sympify(e)
        return e if e.is_number else sp.simplify(e)
    I = inertia
    return replace(link, mass=sp.simplify(m), com=tuple(simplify(x) for x in c),
                   inertia=tuple(simplify(x) for x in (I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2])))


def _tidy(e):
    """Simplify a symbolic entry; an exact number is left as it is (simplifying products of
    cos/sin of non-special angles is slow and gains nothing: emitters fold them)."""
    e = sp.sympify(e)
    return e if e.is_number else sp.simplify(e)


def _body(link: Link):
    return link.mass, sp.Matrix(link.com), sp.Matrix(link.inertia_matrix)


def lock_joints(robot: Robot, locked: dict[int, sp.Expr]) -> Robot:
    """The robot with the joints ``locked`` (0-based index -> value) removed: each locked link is
    merged into its nearest moving ancestor (or into a floating base's body, or the ground), and
    the links that hang on it hang on that ancestor, the constant transforms carried to them.
    On a serial chain the ancestor is the moving link before it."""
    parents = robot.parent_indices
    kept: list[Link] = []
    kept_parents: list[int] = []
    new_index: dict[int, int] = {}  # kept link (old index) -> its index in ``kept``
    # locked link -> (the index in ``kept`` of its nearest moving ancestor, -1 the base; the
    # transform from that ancestor's frame to the locked link's frame)
    carried: dict[int, tuple[int, sp.Matrix]] = {}
    base_body = robot.base_body
    for i, link in enumerate(robot.links):
        p = parents[i]
        anchor, before = carried[p] if p in carried else (new_index.get(p, -1), sp.eye(4))
        if i in locked:
            pending = before * _transform(robot, link, locked[i])
            carried[i] = (anchor, pending)
            R, t = pending[:3, :3], pending[:3, 3]
            m2, c2, I2 = _body(link)
            if anchor >= 0:
                m, c, inertia = merge_bodies(*_body(kept[anchor]), m2, R * c2 + t, R * I2 * R.T)
                kept[anchor] = _with_body(kept[anchor], m, c, inertia)
            elif robot.floating:  # into the free base's own body
                body = robot.base_inertia
                m, c, inertia = merge_bodies(body.mass, sp.Matrix(body.com), sp.Matrix(body.inertia_matrix),
                                             m2, R * c2 + t, R * I2 * R.T)
                base_body = _with_body(body, m, c, inertia)
            continue
        fixed = before * (sp.Matrix(4, 4, list(link.fixed)) if link.fixed is not None else sp.eye(4))
        fixed = fixed.applyfunc(_tidy)
        new_index[i] = len(kept)
        kept.append(replace(link, fixed=None if fixed == sp.eye(4) else tuple(fixed)))
        kept_parents.append(anchor)
    if not kept:
        raise SymdynError("a scene must leave at least one joint free")
    tool_fixed = robot.tool_fixed
    last = len(robot.links) - 1
    if last in carried and carried[last][1] != sp.eye(4):  # the last joint is locked: the tool rides on its moving ancestor
        anchor, pending = carried[last]
        chain = not robot.floating and all(p == k - 1 for k, p in enumerate(kept_parents))
        if anchor != len(kept) - 1 and chain and (robot.tool is not None or tool_fixed is not None):
            raise SymdynError(f"{robot.source}: locking link {last + 1} ({robot.links[last].name}) leaves the tool, "
                              "given in the last link's frame, on a link that is not the last free one; lock "
                              "fewer joints or drop the tool from the robot file")
        previous = sp.eye(4) if tool_fixed is None else sp.Matrix(4, 4, list(tool_fixed))
        tool_fixed = tuple((pending * previous).applyfunc(_tidy))
    tree = robot.floating or any(p != k - 1 for k, p in enumerate(kept_parents))
    frames = []  # a frame on a locked link rides on that link's moving ancestor
    for frame in robot.frames:
        if frame.link in carried:
            anchor, pending = carried[frame.link]
            frames.append(replace(frame, link=anchor, pose=tuple((pending * frame.matrix()).applyfunc(_tidy))))
        else:
            frames.append(replace(frame, link=new_index.get(frame.link, -1)))
    return _drop_unused(replace(robot, links=tuple(kept), tool_fixed=tool_fixed,
                                parents=tuple(kept_parents) if tree else (), base_body=base_body,
                                frames=tuple(frames)))


def _drop_unused(robot: Robot) -> Robot:
    used = set().union(*(e.free_symbols for link in robot.links for e in link.expressions()),
                       *(sp.sympify(e).free_symbols for e in robot.base_inertia.expressions()),
                       *(sp.sympify(g).free_symbols for g in (*robot.gravity, *robot.base_matrix(),
                                                             *robot.tool_matrix())),
                       *(sp.sympify(e).free_symbols for contact in robot.contacts for e in contact.expressions()))
    keep = [(s, v) for s, v in zip(robot.parameters, robot.nominal) if s in used]
    return replace(robot, parameters=tuple(s for s, _ in keep), nominal=tuple(v for _, v in keep),
                   runtime_names=tuple(n for n in robot.runtime_names if any(s.name == n for s, _ in keep)))


def load_scene(path: str) -> Scene:
    """Read a scene file and build its specialized robot."""
    path = os.fspath(path)
    raw = read_input(path)
    return _build_scene(path, raw, load_yaml(decode_text(raw, path), path, "scene file"))


def _build_scene(path: str, raw: bytes, doc, frames: list[str] | None = None, contacts=None) -> Scene:
    """The scene of a parsed scene document (``raw``: the file's bytes, for its hash);
    ``frames`` and ``contacts`` (the command line's, parsed) in place of the scene's ``frames:``
    and ``contacts:``."""
    if contacts is None and isinstance(doc, dict) and "contacts" in doc:
        contacts = parse_contacts(doc["contacts"], lambda message, at="": _fail(path, message, "contacts" + at))
    robot_path, robot_doc, robot_raw, robot_notes = _scene_robot_document(path, doc, frames,
                                                                          [c.name for c in contacts or ()])
    runtime, values, functions, precision = _scene_choices(path, doc)
    params, payload_names = _scene_parameter_names(path, doc, robot_doc, runtime, values)
    notes = [f"scene: {display_path(os.path.basename(path))} (sha256 {hashlib.sha256(raw).hexdigest()})",
             f"robot: {display_path(doc['robot'])} (sha256 {hashlib.sha256(robot_raw).hexdigest()})",
             *robot_notes]
    params, folded = _folded_parameters(path, params, payload_names, runtime, values)
    robot = _robot_with_payload(path, doc, robot_doc, robot_path, params, notes)
    degrees = robot_doc.get("angles") == "degrees"
    locked = _scene_locks(path, doc, robot, degrees)
    if locked and robot.mimics:
        _fail(path, f"'{robot.name}' has mimic joints: a scene cannot lock its joints yet (a locked leader would "
                    "hold its mimics too); lock none, or remove the mimics in a copy of the robot file", "lock")
    locked_joints = tuple((k + 1, robot.links[k].name, v) for k, v in sorted(locked.items()))
    if locked and len(locked) == robot.dof:
        _fail(path, f"the scene locks every joint of '{robot.name}' ({robot.dof}): leave at least one joint free",
              "lock")
    if locked:
        notes.append("locked: " + ", ".join(f"joint {k + 1} ({robot.links[k].name}) at {float(v):g}"
                                            for k, v in sorted(locked.items())))
        robot = lock_joints(robot, locked)
    robot = _drop_unused(robot)
    if folded:
        notes.append("folded parameters: " + ", ".join(folded))
    if robot.parameters:
        notes.append("runtime parameters: " + ", ".join(s.name for s in robot.parameters))
    name = doc.get("name", robot.name)
    if not isinstance(name, str) or not ROBOT_NAME_PATTERN.match(name) or len(name) > MAX_NAME:
        _fail(path, f"{describe(name)} is not a valid name: use lower-case letters, digits and '_', "
                    f"starting with a letter, at most {MAX_NAME} characters", "name")
    if "task" in doc:  # the task of the task-space functions (replaces the robot file's)
        task = task_rows(doc["task"], lambda message: _fail(path, message, "task"))
        robot = replace(robot, task=task)
        notes.append("task: Jacobian rows " + ", ".join(str(r) for r in task))
    if contacts is not None:
        robot = _with_contacts(path, robot, contacts, "contacts")
        notes.append("contacts: " + ", ".join(str(c) for c in contacts))
    robot = replace(robot, name=name, source=path, source_hash=hashlib.sha256(raw + robot_raw).hexdigest())
    return Scene(robot=robot, functions=functions, precision=precision, notes=tuple(notes),
                 source=path, source_hash=robot.source_hash, locked=locked_joints)


def _scene_robot_document(path: str, doc, frames, contact_frames=()):
    """Check the scene's own keys and read its robot file: ``(robot_path, robot_doc, robot_raw,
    robot_notes)``, the robot file checked as it is before the scene changes anything (a URDF
    read with the contacts' frames among its frames)."""
    if not isinstance(doc, dict):
        _fail(path, "expected a mapping")
    for key in doc:
        if key not in SCENE_KEYS:
            _fail(path, f"unknown key {describe(key)} (allowed: {', '.join(SCENE_KEYS)})", one_line(str(key), 40))
    if doc.get("scene") != SCENE_VERSION or isinstance(doc.get("scene"), bool):
        _fail(path, f"unsupported scene version {describe(doc.get('scene'))}; this symdyn reads scene {SCENE_VERSION}", "scene")
    if not isinstance(doc.get("robot"), str) or not doc["robot"].strip():
        _fail(path, "missing or invalid robot file path", "robot")
    robot_path = os.path.join(os.path.dirname(os.path.abspath(path)), doc["robot"])
    tip, tool = doc.get("tip"), doc.get("tool")
    for fld, value in (("tip", tip), ("tool", tool)):
        if value is not None and not isinstance(value, str):
            _fail(path, f"expected a link name of the URDF, not {describe(value)}", fld)
    scene_frames = doc.get("frames")
    if scene_frames is not None and (not isinstance(scene_frames, list) or not scene_frames
                                     or not all(isinstance(n, str) for n in scene_frames)):
        _fail(path, "expected a list of frame names (the robot's links, or the frames its file defines)", "frames")
    exact_angles, floating_base = doc.get("exact_angles", False), doc.get("floating_base", False)
    for fld, value in (("exact_angles", exact_angles), ("floating_base", floating_base)):
        if not isinstance(value, bool):
            _fail(path, "expected true or false", fld)
    frames = frames or scene_frames
    if contact_frames and is_robot_xml(robot_path):
        frames = list(frames or []) + [n for n in contact_frames if n not in (frames or [])]
    try:
        robot_doc, robot_raw, robot_notes = read_robot_document(robot_path, tip, tool, "tip: and tool:", exact_angles,
                                                                floating_base, frames)
    except RobotFileError as exc:
        raise RobotFileError(path, f"robot file {display_path(doc['robot'])}: {exc.reason}", field="robot") from None
    # The robot file must be valid as it is before the scene changes anything in it (its own
    # errors name the robot file); the scene's edits below then work on checked data.
    try:
        from_document(robot_doc, robot_path)
    except RobotFileError as exc:
        raise RobotFileError(path, f"in robot {display_path(doc['robot'])}: {exc.reason}", link=exc.link,
                             field=exc.field) from None
    return robot_path, robot_doc, robot_raw, robot_notes


def _scene_choices(path: str, doc):
    """``(runtime, values, functions, precision)`` of a scene, checked."""
    runtime = doc.get("runtime", [])
    if not isinstance(runtime, list) or not all(isinstance(n, str) for n in runtime):
        _fail(path, "expected a list of parameter names", "runtime")
    values = doc.get("values", {}) or {}
    if not isinstance(values, dict) or not all(isinstance(k, str) for k in values) \
            or not all(isinstance(v, (int, float, str)) and not isinstance(v, bool) for v in values.values()):
        _fail(path, "expected a mapping of parameter names to numbers", "values")
    functions = doc.get("functions")
    if functions is not None:
        if not isinstance(functions, list) or not functions:
            _fail(path, "expected a non-empty list of functions", "functions")
        for f in functions:
            if not isinstance(f, str) or f not in ALL_OUTPUTS:
                _fail(path, f"unknown function {describe(f)} (known: {', '.join(ALL_OUTPUTS)})", "functions")
        functions = tuple(f for f in ALL_OUTPUTS if f in functions)
    precision = doc.get("precision")
    if precision is not None and precision not in ("double", "float", "mixed"):
        _fail(path, f"precision must be double, float or mixed, not {describe(precision)}", "precision")
    return runtime, values, functions, precision


def _scene_parameter_names(path: str, doc, robot_doc, runtime, values):
    """``(params, payload_names)``: the robot file's parameters, and the names the payload uses,
    each name of runtime: and values: checked against them."""
    # Parameters: the scene decides which stay runtime inputs; the rest fold to their values.
    params = dict(robot_doc.get("parameters") or {})
    payload_names = _payload_names(doc.get("payload"))
    for name in sorted(payload_names - set(params)):
        if name not in runtime and name not in values:
            _fail(path, f"the payload uses '{name}', which is not a parameter of robot {display_path(doc['robot'])}: "
                        "list it under runtime: (an input of the code) or give it under values:", "payload")
    for fld, names in (("runtime", runtime), ("values", list(values))):
        for name in names:
            if name not in params and name not in payload_names:
                candidates = list(params) + sorted(payload_names)
                close = difflib.get_close_matches(name, candidates, n=1, cutoff=0.6)
                hint = f"; did you mean '{close[0]}'?" if close else ""
                known = f" (it has: {', '.join(params)})" if params else " (it has none)"
                _fail(path, f"robot {display_path(doc['robot'])} has no parameter {describe(name)}{known}, and "
                            f"the payload does not use it{hint}", f"{fld}")
    return params, payload_names


def _folded_parameters(path: str, params: dict, payload_names, runtime, values):
    """``(params, folded)``: the parameters as the scene leaves them (runtime ones as inputs, the
    others folded to their values; the payload's own names added) and the folded ``name=value``."""
    params = dict(params)
    folded = []
    for name in sorted(payload_names - set(params), key=lambda n: (n not in runtime, runtime.index(n) if n in runtime else 0, n)):
        params[name] = {"runtime": True} if name in runtime else values[name]
    for name, spec in list(params.items()):
        value = spec.get("value") if isinstance(spec, dict) else spec
        if name in values:
            value = values[name]
        if name in runtime:
            params[name] = {"value": value, "runtime": True} if value is not None else {"runtime": True}
        elif value is None:
            _fail(path, f"parameter '{name}' of the robot has no value: give one under values: or list it "
                        "under runtime:", "values")
        else:
            params[name] = value
            folded.append(f"{name}={value}")
    return params, folded


def _robot_with_payload(path: str, doc, robot_doc, robot_path: str, params: dict, notes: list):
    """The scene's robot before locking: the robot file with the scene's parameters and its
    payload merged into the last link (a note appended to ``notes``)."""
    robot_doc = dict(robot_doc)
    if params:
        robot_doc["parameters"] = params
    links = list(robot_doc["links"])
    payload = doc.get("payload")
    if payload is not None:
        if not isinstance(payload, dict):
            _fail(path, "expected a mapping with mass, com and inertia", "payload")
        for key in payload:
            if key not in PAYLOAD_KEYS:
                _fail(path, f"unknown key {describe(key)} (allowed: {', '.join(PAYLOAD_KEYS)})", f"payload.{one_line(str(key), 40)}")
        # read the payload with the robot's own (safe) number parser, as one more link's fields
        taken = {link.get("name") for link in links if isinstance(link, dict)}
        carrier_name = next(n for n in (f"payload{k}" if k else "payload" for k in range(len(links) + 1)) if n not in taken)
        carrier = {"name": carrier_name, "joint": "revolute", "mass": payload.get("mass", 0),
                   "com": payload.get("com", [0, 0, 0]), "inertia": payload.get("inertia", [0, 0, 0, 0, 0, 0])}
        if robot_doc.get("convention") != "general":
            carrier.update(a=0, alpha=0, d=0, theta=0)
        links.append(carrier)
    robot_doc["links"] = links
    try:
        with warnings.catch_warnings():  # the robot file's warnings were given by the check above
            warnings.simplefilter("ignore", SymdynWarning)
            robot = from_document(robot_doc, robot_path)
    except RobotFileError as exc:
        raise RobotFileError(path, f"in robot {display_path(doc['robot'])}: {exc.reason}", link=exc.link, field=exc.field) from None
    if payload is not None:
        carrier, last = robot.links[-1], robot.links[-2]
        m, c, inertia = merge_bodies(*_body(last), *_body(carrier))
        robot = replace(robot, links=robot.links[:-2] + (_with_body(last, m, c, inertia),),
                        parents=robot.parents[:-1] if robot.is_tree else ())
        notes.append(f"payload: mass {carrier.mass}, com ({', '.join(map(str, carrier.com))}) in the frame of "
                     f"link {robot.dof} ({last.name}), merged into that link")
    return robot


def _scene_locks(path: str, doc, robot, degrees: bool) -> dict:
    """The joints the scene locks: ``{index: value}`` (radians or metres), checked."""
    lock = doc.get("lock", {}) or {}
    if not isinstance(lock, dict):
        _fail(path, "expected a mapping of joint (1-based index or link name) to value", "lock")
    locked: dict[int, sp.Expr] = {}
    keys: dict[int, object] = {}  # the key that locked each joint
    names = {link.name: k for k, link in enumerate(robot.links)}
    for key, value in lock.items():
        index = names.get(key) if isinstance(key, str) else (key - 1 if isinstance(key, int) and not isinstance(key, bool) else None)
        where = f"lock.{one_line(str(key), 40)}"
        if index is None or not 0 <= index < robot.dof:
            _fail(path, f"no joint {describe(key)} in {robot.name} (give a 1-based index or a link name)", where)
        if index in keys:
            _fail(path, f"joint {index + 1} ({robot.links[index].name}) is locked twice, as "
                        f"{describe(keys[index])} and as {describe(key)}: give it once", where)
        keys[index] = key
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            _fail(path, f"expected a number (rad or m), not {describe(value)}", where)
        if not math.isfinite(value) or abs(value) > MAX_LOCK_VALUE:
            _fail(path, f"expected a finite number of magnitude at most {MAX_LOCK_VALUE:g} (rad or m), not {describe(value)}", where)
        locked[index] = sp.nsimplify(value, rational=True)
        if robot.links[index].is_revolute:  # an angle: in the robot file's unit
            if degrees:
                locked[index] = locked[index] * sp.pi / 180
            elif abs(value) > 2 * math.pi:
                warn(f"{one_line(path, 200)}: field '{where}': {value:g} rad looks like degrees (more than "
                     "2 pi); lock values of revolute joints are in the robot file's angle unit "
                     "('angles: degrees' there makes them degrees)")
    return locked
