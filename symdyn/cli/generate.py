"""``symdyn generate``: robot file(s) in, C (header and source) or CasADi functions out."""

from __future__ import annotations

import os

from ..derive.cache import derive_cached
from ..model.files import output_directory, write_files
from ..emit.cgen import generate_c
from ..emit.cgen import PRECISION_CHOICES
from ..model.errors import SymdynError
from ..model.outputs import default_outputs, functions_help, with_requirements
from ..model.inputs import decode_text, load_yaml, read_input
from ..model.parallel import ParallelRobot
from ..derive.parallel import FUNCTIONS as PLATFORM_FUNCTIONS
from ..model.scene import load_input
from .common import add_fd_method_option, add_method_option, add_size_options, check_size, default_fd_method, load_robot, parse_functions, progress_printer

HELP = "generate C code (NAME_dynamics.h/.c) or CasADi functions for robot files"
TARGETS = ("c", "casadi", "casadi-c")


def add_parser(sub) -> None:
    p = sub.add_parser("generate", help=HELP, description=HELP + ". The files of a run are written "
                       "as one unit (temporaries, then renames, under a lock on the output directory); "
                       "on any error existing files are left untouched. Only regular files are "
                       "replaced, never an input file.")
    p.add_argument("robots", nargs="+", metavar="ROBOT.yaml", help="robot file(s) (format version 1) or "
                   "scene file(s) (docs/scene-format.md: locked joints, payload, runtime parameters)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created if missing)")
    p.add_argument("--target", default="c", choices=TARGETS,
                   help="c (default): NAME_dynamics.h/.c; casadi: NAME_dynamics.casadi and one "
                        "NAME_<function>.casadi per function (casadi.Function.save format) with "
                        "NAME_casadi.txt describing them; casadi-c: as casadi, plus CasADi's own "
                        "generated C (NAME_casadi.c/.h) for comparison")
    p.add_argument("--precision", default=None, choices=PRECISION_CHOICES,
                   help="scalar type of the generated C (float gives sinf/cosf and float literals); c target "
                        "only; default: the scene's precision, else double")
    p.add_argument("--functions", metavar="LIST",
                   help=f"{functions_help()}; for a platform robot (kind: parallel): "
                        f"{', '.join(PLATFORM_FUNCTIONS)} (default all)")
    p.add_argument("--header-only", action="store_true",
                   help="write one header of static inline functions instead of .h + .c; c target only")
    p.add_argument("--parameters", default="standard", choices=("standard", "base"),
                   help="base: inverse dynamics written in the robot's base parameters (the regrouped "
                        "inertial parameters zero and folded away; fewer operations on some arms, "
                        "docs/benchmarks.md); needs a numeric link geometry. Default standard")
    p.add_argument("--size-report", action="store_true",
                   help="compile the C for a Cortex-M4 with arm-none-eabi-gcc (-mcpu=cortex-m4 -mthumb "
                        "-mfloat-abi=hard -mfpu=fpv4-sp-d16 -O2) and document each function's code size and "
                        "stack use in the header; c target, .h + .c only")
    p.add_argument("--batch", action="store_true",
                   help="also write NAME_<function>_batch(count, ...) over arrays of states: several "
                        "states at once in GCC/Clang vector types in double precision (identical results), "
                        "a loop over the scalar function otherwise; c target only")
    add_method_option(p)
    add_fd_method_option(p)
    add_size_options(p)
    p.add_argument("--no-cache", action="store_true", help="do not read or write the derivation cache")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(run=run)


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


def generate_files(path: str, functions, precision, header_only: bool, method: str,
                   use_cache: bool = True, target: str = "c", loaded=None, progress=None,
                   fd_method: str | None = None, size_report: bool = False,
                   parameters: str = "standard", batch: bool = False) -> dict[str, bytes]:
    """Load (robot or scene), derive (cached) and emit; returns {file name: content} without
    writing anything.  ``functions``/``precision`` None: the scene's, else all / double.
    ``loaded``: ``load_input(path)`` when the caller already has it; ``progress``: called with a
    short text per derivation part and emitted function."""
    robot, scene = loaded if loaded is not None else load_input(path, parallel=True)
    if isinstance(robot, ParallelRobot):
        return parallel_files(path, robot, functions, precision, target, progress)
    functions = parse_functions(functions) if isinstance(functions, str) else functions
    notes: tuple[str, ...] = robot.notes
    source_hash = robot.source_hash
    if scene is not None:
        functions = functions or scene.functions
        precision = precision or scene.precision
        notes = scene.notes
    functions = functions or default_outputs(robot)
    precision = precision or "double"
    fd_method = fd_method or default_fd_method(precision)
    eqs = derive_cached(robot, method, with_requirements(functions), use_cache=use_cache, progress=progress, fd_method=fd_method,
                        parameters=parameters)
    source = os.path.basename(path)
    if target == "c":
        report = None
        if size_report:
            import functools

            from ..check.firmware import measure
            report = functools.partial(measure, prefix=robot.name)
        files = generate_c(eqs, functions, precision, header_only, source_name=source,
                           source_hash=source_hash, notes=notes, progress=progress, size_report=report,
                           batch=batch)
        return {name: text.encode("utf-8") for name, text in files.items()}
    from ..emit.casadi_backend import casadi_files
    return casadi_files(eqs, functions, casadi_c=target == "casadi-c", source_name=source,
                        source_hash=source_hash)


def parallel_functions(text: str | None) -> tuple[str, ...] | None:
    """The platform functions ``--functions`` names (None: all)."""
    from ..derive.parallel import FUNCTIONS
    if not text:
        return None
    names = [t.strip() for t in text.split(",") if t.strip()]
    unknown = [n for n in names if n not in FUNCTIONS]
    if unknown:
        raise SymdynError(f"unknown function '{unknown[0]}' in --functions for a platform robot (known: "
                          f"{', '.join(FUNCTIONS)})")
    if not names:
        raise SymdynError("--functions lists no function")
    return tuple(n for n in FUNCTIONS if n in names)


def parallel_files(path: str, robot: ParallelRobot, functions, precision, target: str, progress=None) -> dict[str, bytes]:
    """Derive and emit a platform robot (symdyn.derive.parallel): C or CasADi files."""
    from ..derive.parallel import derive_parallel
    functions = parallel_functions(functions) if isinstance(functions, str) or functions is None else functions
    if precision not in (None, "double", "float"):
        raise SymdynError(f"{path}: platform robots are generated in double or float precision, not {precision}")
    if target == "casadi-c":
        raise SymdynError(f"{path}: --target casadi-c is not available for platform robots (use c or casadi)")
    eqs = derive_parallel(robot, functions, progress=progress)
    source = os.path.basename(path)
    if target == "c":
        from ..emit.parallel_c import generate_parallel_c
        files = generate_parallel_c(eqs, functions, precision or "double", source_name=source,
                                    source_hash=robot.source_hash, progress=progress)
        return {name: text.encode("utf-8") for name, text in files.items()}
    from ..emit.parallel_casadi import parallel_casadi_files
    return parallel_casadi_files(eqs, functions, source_name=source, source_hash=robot.source_hash)


def _check_parallel_options(args, path) -> None:
    """Refuse the serial-only options for a platform robot, in one line."""
    refused = [flag for flag, on in (("--header-only", args.header_only), ("--batch", args.batch),
                                     ("--size-report", args.size_report),
                                     ("--parameters base", args.parameters != "standard"),
                                     ("--fd-method", args.fd_method is not None),
                                     ("--method", args.method not in (None, "newton-euler"))) if on]
    if refused:
        raise SymdynError(f"{path}: {refused[0]} does not apply to a platform robot (kind: parallel)")


def run(args) -> int:
    """Load every input, check the output directory, then derive and emit everything, and
    write all files of all robots in one transaction (:func:`symdyn.model.files.write_files`)."""
    if args.target != "c" and (args.precision not in (None, "double") or args.header_only):
        raise SymdynError(f"--precision and --header-only apply to the c target only, not {args.target}")
    if args.batch and args.target != "c":
        raise SymdynError(f"--batch applies to the c target only, not {args.target}")
    if args.size_report and (args.target != "c" or args.header_only):
        raise SymdynError("--size-report applies to the c target with .h + .c files (not --header-only)")
    if args.size_report:
        from ..check.firmware import COMPILER, available
        if not available():
            raise SymdynError(f"--size-report needs {COMPILER} (Debian/Ubuntu: apt install gcc-arm-none-eabi "
                              "libnewlib-arm-none-eabi)")
    loaded = [load_robot(path, args, parallel=True) for path in args.robots]  # every file is checked first
    for path, (robot, _) in zip(args.robots, loaded):
        if isinstance(robot, ParallelRobot):
            _check_parallel_options(args, path)
            parallel_functions(args.functions)
        else:
            parse_functions(args.functions)
            check_size(robot, args, path)
    protect = [p for path in args.robots for p in input_files(path)]
    # the directory is checked (and created) before deriving, and removed again if the run fails
    with output_directory(args.out):
        rendered = {}
        for path, inputs in zip(args.robots, loaded):
            for name, text in generate_files(path, args.functions, args.precision, args.header_only,
                                             args.method, not args.no_cache, args.target,
                                             loaded=inputs, progress=progress_printer(args),
                                             fd_method=args.fd_method, size_report=args.size_report,
                                             parameters=args.parameters, batch=args.batch).items():
                if name in rendered:
                    raise SymdynError(f"two robot files produce {name}: give each robot a distinct name")
                rendered[name] = text
        written = write_files(args.out, rendered, protect=protect)
    if not args.quiet:
        for target in written:
            print(f"wrote {target}")
    return 0
