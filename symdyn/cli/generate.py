"""``symdyn generate``: robot file(s) in, C (header and source) or CasADi functions out."""

from __future__ import annotations

import os

from ..derive.cache import derive_cached
from ..model.files import write_atomic
from ..emit.cgen import generate_c
from ..emit.cprinter import PRECISIONS
from ..model.errors import SymdynError
from ..derive.equations import OUTPUTS
from ..model.scene import load_input
from .common import add_method_option, parse_functions

HELP = "generate C code (NAME_dynamics.h/.c) or CasADi functions for robot files"
TARGETS = ("c", "casadi", "casadi-c")


def add_parser(sub) -> None:
    p = sub.add_parser("generate", help=HELP, description=HELP + ". Output files are written "
                       "atomically; on any error existing files are left untouched.")
    p.add_argument("robots", nargs="+", metavar="ROBOT.yaml", help="robot file(s) (format version 1) or "
                   "scene file(s) (docs/scene-format.md: locked joints, payload, runtime parameters)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created if missing)")
    p.add_argument("--target", default="c", choices=TARGETS,
                   help="c (default): NAME_dynamics.h/.c; casadi: NAME_dynamics.casadi and one "
                        "NAME_<function>.casadi per function (casadi.Function.save format) with "
                        "NAME_casadi.txt describing them; casadi-c: as casadi, plus CasADi's own "
                        "generated C (NAME_casadi.c/.h) for comparison")
    p.add_argument("--precision", default=None, choices=PRECISIONS,
                   help="scalar type of the generated C (float gives sinf/cosf and float literals); c target "
                        "only; default: the scene's precision, else double")
    p.add_argument("--functions", metavar="LIST",
                   help="comma-separated subset of: inverse_dynamics, mass_matrix, coriolis, "
                        "coriolis_matrix, gravity, forward_dynamics (default: the scene's functions, else all)")
    p.add_argument("--header-only", action="store_true",
                   help="write one header of static inline functions instead of .h + .c; c target only")
    add_method_option(p)
    p.add_argument("--no-cache", action="store_true", help="do not read or write the derivation cache")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(run=run)


def generate_files(path: str, functions, precision, header_only: bool, method: str,
                   use_cache: bool = True, target: str = "c") -> dict[str, bytes]:
    """Load (robot or scene), derive (cached) and emit; returns {file name: content} without
    writing anything.  ``functions``/``precision`` None: the scene's, else all / double."""
    robot, scene = load_input(path)
    notes: tuple[str, ...] = ()
    source_hash = robot.source_hash
    if scene is not None:
        functions = functions or scene.functions
        precision = precision or scene.precision
        notes = scene.notes
    functions = functions or OUTPUTS
    precision = precision or "double"
    wanted = set(functions)
    if "forward_dynamics" in wanted:
        wanted |= {"mass_matrix"}
    eqs = derive_cached(robot, method, tuple(wanted), use_cache=use_cache)
    source = os.path.basename(path)
    if target == "c":
        files = generate_c(eqs, functions, precision, header_only, source_name=source,
                           source_hash=source_hash, notes=notes)
        return {name: text.encode("utf-8") for name, text in files.items()}
    from ..emit.casadi_backend import casadi_files
    return casadi_files(eqs, functions, casadi_c=target == "casadi-c", source_name=source,
                        source_hash=source_hash)


def run(args) -> int:
    functions = parse_functions(args.functions) if args.functions else None
    if args.target != "c" and (args.precision not in (None, "double") or args.header_only):
        raise SymdynError(f"--precision and --header-only apply to the c target only, not {args.target}")
    rendered = {}
    for path in args.robots:
        for name, text in generate_files(path, functions, args.precision, args.header_only,
                                         args.method, not args.no_cache, args.target).items():
            if name in rendered:
                raise SymdynError(f"two robot files produce {name}: give each robot a distinct name")
            rendered[name] = text
    try:
        os.makedirs(args.out, exist_ok=True)
    except OSError as exc:
        raise SymdynError(f"cannot create output directory {args.out}: {exc.strerror or exc}") from None
    if not os.access(args.out, os.W_OK):
        raise SymdynError(f"output directory {args.out} is not writable")
    for name, text in rendered.items():
        target = os.path.join(args.out, name)
        try:
            write_atomic(target, text)
        except OSError as exc:
            raise SymdynError(f"cannot write {target}: {exc.strerror or exc}") from None
        if not args.quiet:
            print(f"wrote {target}")
    return 0
