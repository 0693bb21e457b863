"""``symdyn generate``: robot file(s) in, C (header and source) or CasADi functions out.

A thin layer over :mod:`symdyn.emit.pipeline`: the arguments become one
:class:`~symdyn.emit.pipeline.GenerateOptions`, each input one resolved configuration, and the
files of all inputs are written in one transaction."""

from __future__ import annotations

import os

from ..check.cbuild import c_sources
from ..check.firmware import FLAGS as FIRMWARE_FLAGS
from ..emit.cgen import PRECISION_CHOICES
from ..emit.pipeline import (PLATFORM, TARGETS, GenerateOptions, check_inputs, check_options, configure,
                              generate, provenance)
from ..model.errors import SymdynError, warn
from ..model.files import output_directory, write_files
from ..model.outputs import functions_help
from ..model.scene import input_files
from .common import add_fd_method_option, add_method_option, add_size_options, check_size, load_robot, progress_printer

HELP = "generate C code (NAME_dynamics.h/.c) or CasADi functions for robot files"


def add_parser(sub) -> None:
    p = sub.add_parser("generate", help=HELP, description=HELP + ". The files of a run are written "
                       "as one unit (temporaries, then renames, under a lock on the output directory); "
                       "on any error existing files are left untouched. Only regular files are "
                       "replaced, never an input file, nor (without --force) a file generated from "
                       "another input or not by symdyn.")
    p.add_argument("robots", nargs="+", metavar="ROBOT", help="robot file(s) (.yaml: an arm, docs/robot-format.md, "
                   "or a platform, docs/parallel-format.md), URDF file(s) (.urdf), MuJoCo MJCF file(s) (.xml, .mjcf; "
                   "docs/mjcf.md) or scene file(s) "
                   "(docs/scene-format.md: locked joints, payload, runtime parameters)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created if missing)")
    p.add_argument("--name", metavar="NAME", default=None,
                   help="the C prefix and file names (NAME_dynamics.h/.c, NAME_forward_dynamics, ...; "
                        "CasADi: NAME_*.casadi) instead of the robot's name, e.g. one per leg of a URDF "
                        "(--tip LF_FOOT --name lf_leg); lower-case letters, digits and '_', one input only")
    p.add_argument("--force", action="store_true",
                   help="replace files in --out that were generated from another input (or not by "
                        "symdyn); without it such a file stops the run before anything is written")
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
                        f"{', '.join(PLATFORM.functions)} (default all)")
    p.add_argument("--header-only", action="store_true",
                   help="write one header of static inline functions instead of .h + .c; c target only")
    p.add_argument("--parameters", default="standard", choices=("standard", "base"),
                   help="base: inverse dynamics written in the robot's base parameters (the regrouped "
                        "inertial parameters zero and folded away; fewer operations on some arms, "
                        "docs/benchmarks.md); needs a numeric link geometry. Default standard")
    p.add_argument("--size-report", action="store_true",
                   help=f"compile the C for a Cortex-M4 with arm-none-eabi-gcc ({' '.join(FIRMWARE_FLAGS)} "
                        "-fstack-usage) and document each function's code size and stack use, and those "
                        "flags, in the header; c target, .h + .c only")
    p.add_argument("--batch", action="store_true",
                   help="also write NAME_<function>_batch(count, ...) over arrays of states: several "
                        "states at once in GCC/Clang vector types in double precision (identical results), "
                        "a loop over the scalar function otherwise; c target only")
    p.add_argument("--c-file-mb", type=float, default=None, metavar="MB",
                   help="C of more than MB megabytes (default 3) is written as several files of whole "
                        "functions, NAME_dynamics.c, NAME_dynamics_2.c, ..., each compiling within about "
                        "400 MB of compiler memory at gcc -O2 (the header lists them); 0: always one file")
    add_method_option(p)
    add_fd_method_option(p)
    add_size_options(p)
    p.add_argument("--no-cache", action="store_true", help="do not read or write the derivation cache")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    p.set_defaults(run=run)


def options_of(args) -> GenerateOptions:
    """The generation options the arguments ask for (``--size-report``: measured by
    :func:`symdyn.check.firmware.measure`)."""
    size_report = None
    if args.size_report:
        from ..check.firmware import measure
        size_report = measure
    return GenerateOptions(functions=args.functions, precision=args.precision, target=args.target,
                           method=args.method, fd_method=args.fd_method, parameters=args.parameters,
                           header_only=args.header_only, batch=args.batch, size_report=size_report,
                           use_cache=not args.no_cache, name=args.name, c_file_mb=args.c_file_mb)


def run(args) -> int:
    """Check the options, load and resolve every input, check the output directory, then derive
    and emit everything, and write all files of all robots in one transaction
    (:func:`symdyn.model.files.write_files`; unless ``--force``, a file there that another input
    generated, or that symdyn did not write, stops it before anything is written)."""
    options = options_of(args)
    check_options(options)
    check_inputs(args.robots, options)
    if args.size_report:
        from ..check.firmware import COMPILER, available
        if not available():
            raise SymdynError(f"--size-report needs {COMPILER} (Debian/Ubuntu: apt install gcc-arm-none-eabi "
                              "libnewlib-arm-none-eabi)")
    configs = []
    for path in args.robots:  # every file is loaded and checked first
        config = configure(path, options, loaded=load_robot(path, args, parallel=True))
        check_size(config.robot, args, path)
        configs.append(config)
    protect = [p for path in args.robots for p in input_files(path)]
    # the directory is checked (and created) before deriving, and removed again if the run fails
    with output_directory(args.out):
        rendered, owners = {}, {}
        for config in configs:
            files = generate(config, progress=progress_printer(args))
            for name, text in files.items():
                if name in rendered:
                    raise SymdynError(f"two robot files produce {name}: give each robot a distinct name")
                rendered[name] = text
            owners.update(provenance(config, files))
        written = write_files(args.out, rendered, protect=protect, owners=None if args.force else owners)
    if not args.quiet:
        for target in written:
            print(f"wrote {target}")
    _warn_stale_parts(args.out, rendered)
    return 0


def _warn_stale_parts(directory: str, rendered) -> None:
    """One warning per ``NAME_dynamics_K.c`` in ``directory`` that this run did not write while
    it wrote ``NAME_dynamics.h`` (an earlier run's C in more files: compiled with the new files it
    would bring back old functions)."""
    present = os.listdir(directory)
    for prefix in (name[:-len("_dynamics.h")] for name in rendered if name.endswith("_dynamics.h")):
        written = [name for name in c_sources(rendered, prefix) if name in rendered]
        for name in c_sources(present, prefix)[1:]:
            if name not in rendered:
                warn(f"{os.path.join(directory, name)} is from an earlier run (this run wrote {len(written)} C "
                     f"file(s) for {prefix}): delete it before compiling the folder")
