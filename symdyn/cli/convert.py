"""``symdyn convert``: a URDF or MJCF to a robot file (YAML), or a robot file (or scene) to URDF.

``--to yaml`` reads a URDF (:mod:`symdyn.model.urdf`: the chain from its root to ``--tip``) or
an MJCF (:mod:`symdyn.model.mjcf`: its whole tree) and
writes the robot file in the format's general form, with the source, the symdyn version and the
reading's notes as comments; ``--to urdf`` writes :func:`symdyn.emit.urdf.robot_to_urdf` of a
robot file, a scene or a URDF (the latter normalized: fixed joints merged, one chain).  A robot
file is not converted to YAML again (it is one already).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import sys
from dataclasses import replace
from fractions import Fraction

import yaml

from .._version import __version__
from ..emit.urdf import robot_to_urdf
from ..model.errors import SymdynError, display_path, one_line
from ..model.files import write_atomic
from ..model.robot import from_document, parse_contacts
from ..model.scene import is_robot_xml, load_input, read_robot_document
from .common import add_urdf_options
from ..model.scene import input_files

HELP = "convert a URDF or MuJoCo MJCF to a robot file (YAML), or a robot file, scene or MJCF to URDF"
FORMATS = ("urdf", "yaml")


def add_parser(sub) -> None:
    p = sub.add_parser("convert", help=HELP, description=HELP + ". A URDF gives the chain from its root "
                       "link to --tip (fixed joints merged, branches off the chain locked at 0 and merged; "
                       "docs/urdf.md); the YAML is a robot file with convention: general. A robot file's "
                       "runtime parameters take their values; one without a value cannot be written as URDF. "
                       "With --out the file is replaced atomically (never an input file).")
    p.add_argument("robot", metavar="ROBOT", help="a robot file (.yaml), a scene, a URDF (.urdf, any case) or a MuJoCo MJCF "
                   "(.xml with a <mujoco> element, or .mjcf)")
    p.add_argument("--to", required=True, choices=FORMATS, help="urdf: a URDF file; yaml: a robot file "
                   "(from a URDF)")
    p.add_argument("--out", metavar="FILE", default=None, help="write to FILE (default: standard output)")
    add_urdf_options(p)
    p.add_argument("--strict", action="store_true",
                   help="treat every warning (joints locked off the chain, renamed joints, armature or "
                        "gravity that URDF cannot hold, ...) as an error")
    p.add_argument("--quiet", action="store_true", help="print nothing on success (with --out)")
    p.set_defaults(run=run)


def run(args) -> int:
    path = args.robot
    contacts = None
    if args.contacts is not None:
        if not is_robot_xml(path) or args.to != "yaml":
            raise SymdynError(f"{display_path(path)}: --contacts applies to a URDF converted --to yaml (a robot file "
                              "says 'contacts:'; a URDF has no place for them)")
        contacts = parse_contacts(args.contacts, lambda message, at="": _refuse(path, f"--contacts{at}: {message}"))
        args.frames = list(args.frames or []) + [c.name for c in contacts if c.name not in (args.frames or [])]
    if is_robot_xml(path):
        doc, raw, notes = read_robot_document(path, args.tip, args.tool, exact_angles=args.exact_angles,
                                              floating_base=args.floating_base, frames=args.frames)
        if contacts:
            doc["contacts"] = [f"{c.name}:{c.kind}" for c in contacts]
        robot = from_document(doc, path, hashlib.sha256(raw).hexdigest())  # the document must read back
        if args.to == "yaml":
            text = document_to_yaml(doc, _yaml_header(path, raw, args, notes))
        else:
            text = robot_to_urdf(replace(robot, notes=tuple(notes)))
    else:
        if args.tip is not None or args.tool is not None or args.exact_angles or args.floating_base:
            raise SymdynError(f"{display_path(path)}: --tip, --tool, --exact-angles and --floating-base apply to URDF "
                              "input only (a robot file names its tool with 'tool:' and says 'base: floating')")
        if args.to == "yaml":
            raise SymdynError(f"{display_path(path)} is a robot file already: --to yaml converts a URDF "
                              "(.urdf); use --to urdf to write this robot as URDF")
        robot, scene = load_input(path)
        if scene is not None:
            robot = replace(robot, notes=scene.notes)
        text = robot_to_urdf(robot)
    data = text.encode("utf-8")
    if args.out is None:
        sys.stdout.write(text)
        sys.stdout.flush()
        return 0
    write_atomic(args.out, data, protect=input_files(path))
    if not args.quiet:
        print(f"wrote {args.out}")
    return 0


def _refuse(path: str, message: str):
    raise SymdynError(f"{display_path(path)}: {message}")


def _yaml_header(path: str, raw: bytes, args, notes) -> list[str]:
    options = "".join(f" --{name} {one_line(value, 60)}" for name, value in (("tip", args.tip), ("tool", args.tool))
                      if value is not None) + (" --exact-angles" if args.exact_angles else "") \
        + (" --floating-base" if args.floating_base else "") \
        + (f" --frames {one_line(','.join(args.frames), 200)}" if args.frames else "") \
        + (f" --contacts {one_line(str(args.contacts), 200)}" if args.contacts else "")
    lines = [f"Converted by symdyn {__version__} from {display_path(os.path.basename(path))} "
             f"(sha256 {hashlib.sha256(raw).hexdigest()})",
             f"with: symdyn convert {display_path(os.path.basename(path))} --to yaml{options}",
             "A robot file (docs/robot-format.md) with general joint placements (docs/urdf.md)."]
    if notes:
        lines.append("Notes:")
        lines += [f"  - {note}" for note in notes]
    return lines


# ---------------------------------------------------------------------------------------------
# YAML text of a robot document

_PLAIN = re.compile(r"[A-Za-z0-9_.+/-][A-Za-z0-9_.+*/-]*\Z")
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")


def _scalar(value) -> str:
    """A scalar as YAML that reads back as the same value: a number's text plain when YAML reads
    it as that very number (or as the same text), else double-quoted."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    text = str(value)
    if _PLAIN.match(text):
        try:
            loaded = yaml.safe_load(text)
        except yaml.YAMLError:
            loaded = None
        if isinstance(loaded, str) and loaded == text:
            return text
        if _DECIMAL.match(text) and isinstance(loaded, (int, float)) and not isinstance(loaded, bool):
            # the robot reader takes a YAML float by its repr: plain only when that is exact
            exact = Fraction(loaded) if isinstance(loaded, int) else Fraction(repr(loaded))
            if exact == Fraction(text):
                return text
    return json.dumps(text)


def _flow(value) -> str:
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_scalar(k)}: {_flow(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_flow(v) for v in value) + "]"
    return _scalar(value)


def document_to_yaml(doc: dict, comments=()) -> str:
    """The YAML text of a robot document (keys in the document's order, one link per block,
    each field on one line), after ``comments`` as ``#`` lines."""
    lines = [f"# {one_line(c)}".rstrip() for c in comments]
    for key, value in doc.items():
        if key == "links":
            lines.append("links:")
            for link in value:
                for k, (field, item) in enumerate(link.items()):
                    lines.append(f"{'  - ' if k == 0 else '    '}{_scalar(field)}: {_flow(item)}")
        else:
            lines.append(f"{_scalar(key)}: {_flow(value)}")
    return "\n".join(lines) + "\n"
