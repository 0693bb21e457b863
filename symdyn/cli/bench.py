"""``symdyn bench``: speed against error of every way of generating the dynamics."""

from __future__ import annotations

import os
import sys
import tempfile

from ..model.files import output_directory, write_files
from ..model.errors import SymdynError
from dataclasses import dataclass
from typing import Callable

from ..emit.pipeline import PLATFORM, SERIAL, kind_of, parse_platform_functions, scene_choices
from .common import add_fd_method_option, add_size_options, check_size, load_robot, parse_functions

HELP = "time each generation variant and measure its error against a 50-digit reference"


def add_parser(sub) -> None:
    from ..check.bench import DEFAULT_FUNCTIONS, VARIANTS
    from ..check.platform_bench import PLATFORM_VARIANTS
    from ..model.outputs import PLATFORM_REGISTRY as PLATFORM_FUNCTIONS
    p = sub.add_parser("bench", help=HELP, description=HELP + ": symdyn C (Newton-Euler double and "
                       "float, Lagrange-Euler, expanded closed form), CasADi SX and CasADi C, and "
                       "Pinocchio. Writes a Markdown table, the data as CSV and (with matplotlib) a PNG plot of time against error. "
                       "A platform robot (kind: parallel): symdyn C (natural orthogonal complement, noc-double and "
                       "noc-float), CasADi SX and C, and Pinocchio's closed-loop equivalents, the error against "
                       "Pinocchio's closed-loop model.")
    p.add_argument("robots", nargs="+", metavar="ROBOT", help="robot file(s) (.yaml: arms or platforms), URDF(s), MuJoCo MJCF(s) or scene(s), without free parameters")
    p.add_argument("--out", metavar="DIR", help="write bench.md, bench.csv and bench.png to DIR (default: print the table only)")
    p.add_argument("--functions", metavar="LIST", default=None,
                   help=f"comma-separated functions to measure (default: a scene's functions, else "
                        f"{','.join(DEFAULT_FUNCTIONS)}; a platform robot's from: {', '.join(PLATFORM_FUNCTIONS)})")
    p.add_argument("--variants", metavar="LIST", default=None,
                   help=f"comma-separated subset of: {', '.join(VARIANTS)}; for platform robots: "
                        f"{', '.join(PLATFORM_VARIANTS)} (default: all that apply; for a scene with "
                        "a precision, the symdyn C variants of that precision and the others)")
    p.add_argument("--states", type=int, default=20, metavar="N", help="states for the error (default 20)")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    add_fd_method_option(p)
    add_size_options(p)
    p.set_defaults(run=run)


def run(args) -> int:
    from ..check import bench
    from ..check.platform_bench import PLATFORM_VARIANTS
    functions = args.functions or None  # parsed for each robot (serial and platform robots have their own)
    variants = None
    if args.variants is not None:
        known = bench.VARIANTS + tuple(v for v in PLATFORM_VARIANTS if v not in bench.VARIANTS)
        variants = [v.strip() for v in args.variants.split(",") if v.strip()]
        unknown = [v for v in variants if v not in known]
        if unknown or not variants:
            raise SymdynError(f"unknown variant '{unknown[0] if unknown else ''}' in --variants (known: {', '.join(known)})")
    if args.states < 1:
        raise SymdynError("--states must be at least 1")
    loaded = [load_robot(path, args, parallel=True) for path in args.robots]  # every file is checked before any work
    robots = []
    for path, (robot, scene) in zip(args.robots, loaded):
        check_size(robot, args, path)
        robots.append((robot, BY_KIND[kind_of(robot).name](bench, scene, functions, variants, robot, path, args)))
    if not args.out:
        _bench(args, robots, functions, variants)
        return 0
    from ..model.scene import input_files
    protect = [p for path in args.robots for p in input_files(path)]
    plotting = bench.can_plot()  # known before the long measurements, said once
    if not plotting:
        print("symdyn bench: warning: matplotlib is not installed: bench.md and bench.csv are written without "
              "bench.png (pip install 'symdyn[plot]' for the plot)", file=sys.stderr, flush=True)
    with output_directory(args.out):  # checked (and created) before the long measurements
        results = _bench(args, robots, functions, variants)
        files = _report_files(args, bench, results, plotting,
                              [robot.name for robot, plan in robots if plan.closed_loop])
        write_files(args.out, files, protect=protect)  # every file of the report lands together
    _progress(args, "wrote " + ", ".join(os.path.join(args.out, name) for name in files))
    return 0


def _report_files(args, bench, results, plotting: bool, platforms=()) -> dict[str, bytes]:
    """bench.md, bench.csv and (with matplotlib) bench.png; a plot that fails costs only the
    plot, with a one-line warning (``platforms``: the names of the platform robots, whose
    measurement the report describes)."""
    options = "".join(f" --{name} {value}" for name, value in (("functions", args.functions), ("variants", args.variants))
                      if value) + f" --states {args.states}"
    header = (f"# symdyn bench\n\nMachine: {bench.machine()}.\n\nReproduce: `symdyn bench "
              f"{' '.join(os.path.basename(p) for p in args.robots)}{options}`\n\n"
              "Pinocchio is timed through its Python bindings (each call pays the binding "
              "overhead); its C++ timings are in benchmarks/c_speed.py. The numbers are also in bench.csv.\n\n")
    if platforms:
        from ..check.platform_bench import REPORT_NOTE
        header += REPORT_NOTE + "\n\n"
    image = None
    if plotting:
        with tempfile.TemporaryDirectory() as tmp:
            png = os.path.join(tmp, "bench.png")
            try:
                if platforms:  # their panels say what the errors are measured against
                    bench.plot(results, png, platforms)
                else:
                    bench.plot(results, png)
                with open(png, "rb") as handle:
                    image = handle.read()
            except Exception as exc:  # noqa: BLE001 - a broken plotting setup must not lose the measurements
                print(f"symdyn bench: warning: the plot failed ({type(exc).__name__}: {exc}); writing the "
                      "table and data without it", file=sys.stderr, flush=True)
    if image is not None:
        header += "![time against error](bench.png)\n\n"
    files = {"bench.md": (header + bench.markdown_table(results)).encode(), "bench.csv": bench.csv_table(results).encode()}
    if image is not None:
        files["bench.png"] = image
    return files


def _progress(args, text: str) -> None:
    if not args.quiet:
        print(f"symdyn bench: {text}", file=sys.stderr, flush=True)


@dataclass(frozen=True)
class BenchPlan:
    """What is measured for one robot: its functions and variants, how (``measure(robot,
    functions, variants, states, progress, args)``: the results), and whether its errors are
    against Pinocchio's closed loop (the report says so) rather than the 50-digit reference."""

    functions: tuple
    variants: tuple
    measure: Callable
    closed_loop: bool = False


def _platform_plan(bench, scene, functions, variants, robot, path="", args=None) -> BenchPlan:
    """A platform robot's plan: its functions (default the bench's), the platform variants."""
    from ..check.platform_bench import PLATFORM_VARIANTS, bench_platform
    from ..derive.parallel import check_derivable
    if args is not None and args.fd_method:
        raise SymdynError(f"{path}: --fd-method does not apply to a platform robot (kind: parallel)")
    check_derivable(robot)  # before any work
    chosen = [v for v in (variants or PLATFORM_VARIANTS) if v in PLATFORM_VARIANTS]
    if not chosen:
        raise SymdynError(f"{path}: no variant in --variants applies to a platform robot (its variants: "
                          f"{', '.join(PLATFORM_VARIANTS)})")

    def measure(robot, functions, variants, states, progress, args):
        return bench_platform(robot, functions, variants, states, progress)
    return BenchPlan(tuple(parse_platform_functions(functions) or bench.DEFAULT_FUNCTIONS), tuple(chosen), measure,
                     closed_loop=True)


def _serial_plan(bench, scene, functions, variants, robot=None, path="", args=None) -> BenchPlan:
    """A serial robot's plan: the options when given (``functions`` the text of --functions),
    else what a scene asks for (its functions; its precision picks the symdyn C variants), else
    the defaults; only the serial variants."""
    functions, variants = _serial_choices(bench, scene, functions, variants, path)

    def measure(robot, functions, variants, states, progress, args):
        return bench.bench_robot(robot, functions, variants, states, progress, fd_method=args.fd_method or "ldlt")
    return BenchPlan(functions, variants, measure)


def _serial_choices(bench, scene, functions, variants, path="") -> tuple[tuple, tuple]:
    """(functions, variants) of a serial robot from the options, the scene or the defaults."""
    functions = parse_functions(functions) if functions else None
    if variants is not None:
        variants = [v for v in variants if v in bench.VARIANTS]
        if not variants:
            raise SymdynError(f"{path}: no variant in --variants applies to a serial robot (its variants: "
                              f"{', '.join(bench.VARIANTS)})")
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
    """Measure every robot by its plan and print the Markdown table; returns the results."""
    from ..check import bench
    results = []
    for k, (robot, plan) in enumerate(robots):
        _progress(args, f"[{k + 1}/{len(robots)}] {robot.name}")
        results.extend(plan.measure(robot, plan.functions, plan.variants, args.states,
                                    lambda text: _progress(args, text), args))
    sys.stdout.write(bench.markdown_table(results))
    return results


#: how each kind of robot (symdyn.emit.pipeline.KINDS) is benchmarked: its :class:`BenchPlan`
BY_KIND = {SERIAL.name: _serial_plan, PLATFORM.name: _platform_plan}
