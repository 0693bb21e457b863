"""Speed against error: each way of generating the dynamics, timed and checked against the
50-digit reference (:mod:`symdyn.check.reference`).

Variants (each where it applies):

=================  ==========================================================================
``ne-double``      symdyn C, Newton-Euler with intermediate symbols (the default), double
``ne-float``       the same in float (inputs rounded to float; the reference sees them rounded)
``le-double``      symdyn C from the Lagrange-Euler derivation, double
``jne-double``     symdyn C from the Jacobian-projected Newton-Euler derivation, double
``closed-double``  symdyn C from the fully expanded closed form (trig-simplified when small);
                   up to 3 joints, where it derives in reasonable time; no forward dynamics
``casadi-sx``      the CasADi Function on CasADi's SX virtual machine
``casadi-c``       CasADi's own generated C of the same Function, compiled
``pinocchio``      Pinocchio through its Python bindings (its time includes Python's call
                   overhead; benchmarks/c_speed.py times its C++ directly)
=================  ==========================================================================

Time: ns per call, median of 7 x 20000 calls in a C loop (-O3 -march=native); CasADi SX: one
call of ``f.map(M, "serial")`` over M states divided by M.  Error: the largest error over the
states, normalized per joint by the RMS of that joint's reference value.
"""

from __future__ import annotations

import dataclasses
import os
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Callable

import numpy as np
import sympy as sp

from ..derive.cache import derive_cached
from .cbuild import build_and_load, find_compiler
from ..model.outputs import with_requirements
from .states import state_arguments
from ..model.errors import SymdynError
from .pinocchio_model import normalized_error
from ..derive.program import Program
from .reference import MpReference
from ..model.robot import Robot
from .timing import parse, time_generated

VARIANTS = ("ne-double", "ne-float", "le-double", "jne-double", "closed-double", "casadi-sx", "casadi-c", "pinocchio")
#: every variant of serial and platform robots (symdyn.check.platform_bench), in the order of the
#: table, and the plot's marker of each
ORDER = ("ne-double", "ne-float", "noc-double", "noc-float", "le-double", "jne-double", "closed-double",
         "casadi-sx", "casadi-c", "pinocchio")
MARKERS = dict(zip(ORDER, "os<>^vDPXd"))
#: the derivation method of each symdyn C variant
VARIANT_METHODS = {"ne-double": "newton-euler", "ne-float": "newton-euler", "le-double": "lagrange-euler",
                   "jne-double": "jacobian-newton-euler", "closed-double": "newton-euler"}
DEFAULT_FUNCTIONS = ("inverse_dynamics", "mass_matrix", "forward_dynamics")
CLOSED_FORM_MAX_DOF = 3


@dataclasses.dataclass(frozen=True)
class Result:
    robot: str
    variant: str
    function: str
    ns: float | None  # time per call
    ops: int | None  # arithmetic operations (C: mul + add + div + trig; CasADi: instructions)
    error: float  # normalized error against the reference (NaN: not measured)
    label: str = ""  # shown instead of the variant's name (e.g. which Pinocchio algorithm)


def _states(n: int, count: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    return [[rng.uniform(-np.pi, np.pi, n), rng.uniform(-2, 2, n), rng.uniform(-5, 5, n),
             rng.uniform(-20, 20, n)] for _ in range(count)]


def _simplify_closed(e):
    e = sp.expand(e)
    if sp.count_ops(e) <= 300 and not e.has(sp.Float):
        e = sp.trigsimp(e)
    return e


def _closed_form(eqs, functions):
    """The equations with every intermediate substituted (closed form), simplified when small."""
    outputs = []
    for name, matrix in eqs.outputs:
        if name not in functions or name == "forward_dynamics":
            continue
        expanded = eqs.program.expand(sp.Matrix(matrix))
        outputs.append((name, sp.ImmutableMatrix(expanded.applyfunc(_simplify_closed))))
    return dataclasses.replace(eqs, program=Program(()), outputs=tuple(outputs), mass_factors=(), fd_system=(), fd_loops=())


def _c_ops(eqs, name, precision):
    from ..emit.cgen import build_function
    ops = build_function(eqs, name, precision, eqs.robot.name).ops
    return int(ops["mul"] + ops["add"] + ops["div"] + ops["trig"] + ops["sqrt"] + ops["other"])


def bench_robot(robot: Robot, functions=DEFAULT_FUNCTIONS, variants=VARIANTS, count: int = 20,
                progress: Callable[[str], None] = lambda text: None, workdir: str | None = None,
                fd_method: str = "ldlt") -> list[Result]:
    """Measure every variant of ``robot`` (numbers only: no runtime parameters left);
    ``fd_method`` solves the symdyn variants' forward dynamics (``'ldlt'`` or ``'aba'``)."""
    from ..emit.cgen import generate_c

    robot = robot.with_nominal_values()
    if robot.parameters:
        names = [s.name for s in robot.parameters]
        raise SymdynError(f"{robot.source}: bench needs numbers, but {', '.join(names)} "
                          f"{'has' if len(names) == 1 else 'have'} no value (give "
                          f"{'it a value' if len(names) == 1 else 'them values'} under 'parameters:')")
    if robot.floating:
        raise SymdynError(f"{robot.source}: symdyn bench's 50-digit reference is written for fixed bases; time a floating "
                          "base with benchmarks/harness.py (against Pinocchio's C++) and check it with symdyn verify")
    n = robot.dof
    name = robot.name
    if robot.is_tree:  # Lagrange-Euler and the Jacobian form are written for serial chains
        skipped = [v for v in variants if VARIANT_METHODS.get(v, "newton-euler") != "newton-euler"]
        variants = [v for v in variants if v not in skipped]
        if skipped:
            progress(f"{name}: a kinematic tree: {', '.join(skipped)} skipped (serial chains only)")
    progress(f"{name}: 50-digit reference at {count} states")
    reference = MpReference(robot)
    states = _states(n, count)
    rounded = [[x.astype(np.float32).astype(float) for x in s] for s in states]
    refs = {f: [getattr(reference, f)(*state_arguments(f, s)) for s in states] for f in functions}
    refs_float = None
    results: list[Result] = []
    wanted = with_requirements(functions)
    workdir = workdir or tempfile.mkdtemp(prefix="symdyn-bench-")

    def error_of(call, f, float_inputs=False):
        nonlocal refs_float
        if float_inputs and refs_float is None:
            refs_float = {g: [getattr(reference, g)(*state_arguments(g, s)) for s in rounded] for g in functions}
        source = rounded if float_inputs else states
        mine = [np.asarray(call(*state_arguments(f, s)), dtype=float) for s in source]
        if not all(np.all(np.isfinite(m)) for m in mine):
            return float("inf")
        return normalized_error(mine, (refs_float if float_inputs else refs)[f])

    methods = {"ne": derive_cached(robot, "newton-euler", wanted, fd_method=fd_method)}
    for variant in variants:
        if variant in VARIANT_METHODS:
            method = VARIANT_METHODS[variant]
            precision = "float" if variant.endswith("float") else "double"
            if method not in methods:
                progress(f"{name}: deriving by {method}")
                methods[method] = derive_cached(robot, method, wanted, fd_method=fd_method)
            eqs = methods[method]
            fns = functions
            if variant == "closed-double":
                if n > CLOSED_FORM_MAX_DOF:
                    progress(f"{name}: closed form skipped ({n} joints > {CLOSED_FORM_MAX_DOF})")
                    continue
                progress(f"{name}: expanding the closed form")
                eqs = _closed_form(methods["ne"], functions)
                fns = [f for f in functions if f != "forward_dynamics"]
            progress(f"{name}: {variant}: generating, compiling, timing")
            files = generate_c(eqs, fns, precision)
            folder = os.path.join(workdir, f"{name}-{variant}")
            os.makedirs(folder, exist_ok=True)
            lib = build_and_load(files, name, eqs.dimensions, 0, precision, folder)
            timings = time_generated(files, name, eqs.dimensions, fns, precision, folder)
            for f in fns:
                results.append(Result(name, variant, f, timings[f], _c_ops(eqs, f, precision),
                                      error_of(getattr(lib, f), f, precision == "float")))
        elif variant in ("casadi-sx", "casadi-c"):
            progress(f"{name}: {variant}")
            results.extend(_casadi_results(methods["ne"], functions, variant, error_of, os.path.join(workdir, f"{name}-{variant}")))
        elif variant == "pinocchio":
            try:
                from .pinocchio_model import PinocchioReference, reduced
                pin = reduced(PinocchioReference(robot), robot)  # (mimic joints: projected in numpy)
            except ImportError:
                progress(f"{name}: pinocchio not installed, skipped")
                continue
            progress(f"{name}: pinocchio")
            for f in functions:
                call = getattr(pin, f)
                args = state_arguments(f, states[0])
                results.append(Result(name, variant, f, python_time(lambda: call(*args)), None, error_of(call, f)))
    return results


def python_time(call, repeats=5, calls=2000):
    """ns per call of ``call()`` from Python: the median of ``repeats`` runs of ``calls`` calls."""
    runs = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            call()
        runs.append((time.perf_counter() - start) / calls * 1e9)
    return statistics.median(runs)


def _casadi_results(eqs, functions, variant, error_of, folder):
    import casadi as ca

    from ..emit.casadi_backend import casadi_function
    os.makedirs(folder, exist_ok=True)
    n = eqs.n
    out = []
    rng = np.random.default_rng(1)
    for f in functions:
        function = casadi_function(eqs, f, f"{eqs.robot.name}_{f}")
        if variant == "casadi-sx":
            states = 20000
            mapped = function.map(states, "serial")
            args = [rng.uniform(-1, 1, (n, states)) for _ in range(function.n_in())]
            runs = []
            for _ in range(7):
                start = time.perf_counter()
                mapped(*args)
                runs.append((time.perf_counter() - start) / states * 1e9)
            ns = statistics.median(runs)
            call = function
        else:
            source = os.path.join(folder, f"{function.name()}.c")
            library = os.path.join(folder, f"{function.name()}.so")
            generator = ca.CodeGenerator(f"{function.name()}.c")
            generator.add(function)
            generator.generate(folder + os.sep)
            subprocess.run([find_compiler(), "-O3", "-march=native", "-shared", "-fPIC", "-w", source,
                            "-o", library, "-lm"], check=True)
            call = ca.external(function.name(), library)
            ns = _casadi_c_time(n, folder, function.name(), source)
        out.append(Result(eqs.robot.name, variant, f, ns, int(function.n_instructions()),
                          error_of(_dense(call), f)))
    return out


def _dense(function):
    """``function`` returning numpy arrays: vectors as (n,), matrices as (n, n)."""
    def call(*args):
        value = np.array(function(*args))
        return value.reshape(-1) if value.shape[1] == 1 else value
    return call


def _casadi_c_time(n, folder, name, source):
    """Time CasADi's generated C in the same C loop as symdyn's."""
    from .timing import PRELUDE
    includes = (f"typedef long long int casadi_int;\nint {name}(const double** arg, double** res, casadi_int* iw, double* w, int mem);\n"
                "static double w[200000];\nstatic casadi_int iw[1000];")
    body = (f"    {{ const double *arg[3]; double *res[1];\n"
            f"    TIME(\"{name}\", (arg[0] = q[k], arg[1] = qd[k], arg[2] = qdd[k], res[0] = out, "
            f"{name}(arg, res, iw, w, 0)));\n    }}\n    return 0;\n}}\n")
    harness = os.path.join(folder, "bench.c")
    with open(harness, "w") as handle:
        handle.write(PRELUDE.replace("%(includes)s", includes) % {"dof": n, "nq": n} + body)
    exe = os.path.join(folder, "bench")
    subprocess.run([find_compiler(), "-O3", "-march=native", "-std=c99", "-w", harness, source, "-o", exe, "-lm"],
                   check=True)
    return parse(subprocess.run([exe], capture_output=True, text=True, check=True).stdout)[name]


def markdown_table(results: list[Result]) -> str:
    lines = ["| robot | function | variant | time (ns) | operations | normalized error |",
             "|---|---|---|---:|---:|---:|"]
    for r in sorted(results, key=lambda r: (r.robot, r.function, ORDER.index(r.variant))):
        ns = f"{r.ns:.0f}" if r.ns is not None else "-"
        ops = str(r.ops) if r.ops is not None else "-"
        variant = r.label or ("pinocchio (Python bindings)" if r.variant == "pinocchio" else r.variant)
        error = "-" if np.isnan(r.error) else f"{r.error:.1e}"
        lines.append(f"| {r.robot} | {r.function} | {variant} | {ns} | {ops} | {error} |")
    return "\n".join(lines) + "\n"


def csv_table(results: list[Result]) -> str:
    """The results as CSV (one row per robot, function and variant; empty cells where a
    variant has no time or no operation count), in the Markdown table's order."""
    lines = ["robot,function,variant,ns_per_call,operations,normalized_error"]
    for r in sorted(results, key=lambda r: (r.robot, r.function, ORDER.index(r.variant))):
        ns = f"{r.ns:.1f}" if r.ns is not None else ""
        ops = str(r.ops) if r.ops is not None else ""
        error = "" if np.isnan(r.error) else f"{r.error:.3e}"  # NaN: not measured (no equivalent)
        lines.append(f"{r.robot},{r.function},{r.label or r.variant},{ns},{ops},{error}")
    return "\n".join(lines) + "\n"


def can_plot() -> bool:
    """Whether matplotlib can be imported (the plot is optional; the table and data are not)."""
    import importlib.util
    return importlib.util.find_spec("matplotlib") is not None


def plot(results: list[Result], path: str, platforms=()) -> None:
    """Time against error, one panel per robot (log-log), PNG (``platforms``: the names of the
    platform robots, whose errors are against Pinocchio's closed loop)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    robots = sorted({r.robot for r in results})
    functions = sorted({r.function for r in results})
    markers = MARKERS
    colors = {f: f"C{k % 10}" for k, f in enumerate(functions)}
    fig, axes = plt.subplots(1, len(robots), figsize=(5.5 * len(robots), 4.6), squeeze=False)
    for ax, robot in zip(axes[0], robots):
        for r in results:
            if r.robot != robot or r.ns is None or np.isnan(r.error):
                continue
            ax.scatter(r.ns, max(r.error, 1e-17), marker=markers[r.variant], color=colors[r.function], s=40)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(robot)
        ax.set_xlabel("time per call (ns)")
        ax.set_ylabel("normalized error vs " + ("Pinocchio's closed loop" if robot in platforms else "50-digit reference"))
        ax.grid(True, which="both", alpha=0.3)
    handles = [plt.Line2D([], [], marker=markers[v], linestyle="", color="gray", label=v) for v in ORDER
               if any(r.variant == v for r in results)]
    handles += [plt.Line2D([], [], marker="s", linestyle="", color=colors[f], label=f) for f in functions]
    # a legend that fits the figure's width: about three entries per 5.5-inch panel per row
    columns = max(1, min(len(handles), 3 * len(robots)))
    rows = -(-len(handles) // columns)
    fig.legend(handles=handles, loc="lower center", ncol=columns, fontsize=8)
    fig.tight_layout(rect=(0, 0.05 + 0.05 * rows, 1, 1))
    fig.savefig(path, dpi=110, bbox_inches="tight")  # nothing cut at the edges
    plt.close(fig)


def machine() -> str:
    import platform
    return (f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
            f"SymPy {sp.__version__}, {sys.platform}")
