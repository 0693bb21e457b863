"""``symdyn bench``: speed against error of every way of generating the dynamics."""

from __future__ import annotations

import os
import sys
import tempfile

from ..model.files import output_directory, write_files
from ..model.errors import SymdynError
from ..emit.pipeline import scene_choices
from .common import add_fd_method_option, add_size_options, check_size, load_robot, parse_functions

HELP = "time each generation variant and measure its error against a 50-digit reference"


def add_parser(sub) -> None:
    from ..check.bench import DEFAULT_FUNCTIONS, VARIANTS
    p = sub.add_parser("bench", help=HELP, description=HELP + ": symdyn C (Newton-Euler double and "
                       "float, Lagrange-Euler, expanded closed form), CasADi SX and CasADi C, and "
                       "Pinocchio. Writes a Markdown table and a PNG plot of time against error.")
    p.add_argument("robots", nargs="+", metavar="ROBOT.yaml", help="robot file(s) without free parameters")
    p.add_argument("--out", metavar="DIR", help="write bench.md and bench.png to DIR (default: print the table only)")
    p.add_argument("--functions", metavar="LIST", default=None,
                   help=f"comma-separated functions to measure (default: a scene's functions, else "
                        f"{','.join(DEFAULT_FUNCTIONS)})")
    p.add_argument("--variants", metavar="LIST", default=None,
                   help=f"comma-separated subset of: {', '.join(VARIANTS)} (default: all; for a scene with "
                        "a precision, the symdyn C variants of that precision and the others)")
    p.add_argument("--states", type=int, default=20, metavar="N", help="states for the error (default 20)")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    add_fd_method_option(p)
    add_size_options(p)
    p.set_defaults(run=run)


def run(args) -> int:
    from ..check import bench
    functions = parse_functions(args.functions) if args.functions else None
    variants = None
    if args.variants is not None:
        variants = [v.strip() for v in args.variants.split(",") if v.strip()]
        unknown = [v for v in variants if v not in bench.VARIANTS]
        if unknown or not variants:
            raise SymdynError(f"unknown variant '{unknown[0] if unknown else ''}' in --variants (known: {', '.join(bench.VARIANTS)})")
    if args.states < 1:
        raise SymdynError("--states must be at least 1")
    loaded = [load_robot(path, args) for path in args.robots]  # every file is checked before any work
    robots = []
    for path, (robot, scene) in zip(args.robots, loaded):
        check_size(robot, args, path)
        robots.append((robot, _plan(bench, scene, functions, variants)))
    if not args.out:
        _bench(args, robots, functions, variants)
        return 0
    from ..model.scene import input_files
    protect = [p for path in args.robots for p in input_files(path)]
    with output_directory(args.out):  # checked (and created) before the long measurements
        results = _bench(args, robots, functions, variants)
        table = bench.markdown_table(results)
        options = "".join(f" --{name} {value}" for name, value in (("functions", args.functions), ("variants", args.variants))
                          if value) + f" --states {args.states}"
        header = (f"# symdyn bench\n\nMachine: {bench.machine()}.\n\nReproduce: `symdyn bench "
                  f"{' '.join(os.path.basename(p) for p in args.robots)}{options}`\n\n"
                  "Pinocchio is timed through its Python bindings (each call pays the binding "
                  "overhead); its C++ timings are in benchmarks/c_speed.py.\n\n"
                  "![time against error](bench.png)\n\n")
        with tempfile.TemporaryDirectory() as tmp:
            png = os.path.join(tmp, "bench.png")
            try:
                bench.plot(results, png)
            except ImportError:
                raise SymdynError("the plot needs matplotlib: pip install 'symdyn[plot]'") from None
            with open(png, "rb") as handle:
                image = handle.read()
        # bench.md and bench.png land together (one transaction)
        write_files(args.out, {"bench.md": (header + table).encode(), "bench.png": image}, protect=protect)
    _progress(args, f"wrote {os.path.join(args.out, 'bench.md')} and {os.path.join(args.out, 'bench.png')}")
    return 0


def _progress(args, text: str) -> None:
    if not args.quiet:
        print(f"symdyn bench: {text}", file=sys.stderr, flush=True)


def _plan(bench, scene, functions, variants):
    """(functions, variants) for one input: the options when given, else what a scene asks
    for (its functions; its precision picks the symdyn C variants), else the defaults."""
    if functions is None:
        functions, _, _ = scene_choices(None, scene, None, None, bench.DEFAULT_FUNCTIONS)
    if variants is None:
        variants = list(bench.VARIANTS)
        precision = scene.precision if scene is not None else None
        if precision == "float":
            variants = [v for v in variants if not v.endswith("-double")]
        elif precision == "double":
            variants = [v for v in variants if v != "ne-float"]
    return tuple(functions), tuple(variants)


def _bench(args, robots, functions, variants) -> list:
    """Measure every robot and print the Markdown table; returns the results."""
    from ..check import bench
    results = []
    for k, robot in enumerate(robots):
        robot, (functions, variants) = robot
        _progress(args, f"[{k + 1}/{len(robots)}] {robot.name}")
        results.extend(bench.bench_robot(robot, functions, variants, args.states,
                                         lambda text: _progress(args, text), fd_method=args.fd_method or "ldlt"))
    sys.stdout.write(bench.markdown_table(results))
    return results
