"""``symdyn bench`` of a platform robot: each way of generating its functions, timed, with its
error against Pinocchio's closed loop (:class:`symdyn.check.closed_loop.ClosedLoopReference`), in
the report of :mod:`symdyn.check.bench` (:class:`~symdyn.check.bench.Result` rows).

Variants (each where it applies):

==============  =================================================================================
``noc-double``  symdyn C (natural orthogonal complement, :mod:`symdyn.emit.parallel_c`), double
``noc-float``   the same in float (inputs rounded to float; the reference sees them rounded)
``casadi-sx``   the CasADi Function (:mod:`symdyn.emit.parallel_casadi`) on CasADi's SX machine
``casadi-c``    CasADi's own generated C of the same Function, compiled
``pinocchio``   Pinocchio's closed-loop equivalent through its Python bindings, given the legs'
                joint values (it has no inverse kinematics of closed loops; symdyn's functions
                compute them from the pose): inverse dynamics ``rnea`` + ``getConstraintsJacobian``
                + LU of ``[Jc^T S]``; forward dynamics ``constraintDynamics`` and ``lcaba`` (the
                model with a 1e-9 armature on the legs' joints, which their solvers need).
                ``mass_matrix``, ``twist_map``, ``leg_rate_maps`` and ``inverse_kinematics`` have
                no equivalent: a row says so
==============  =================================================================================

Time: symdyn C and CasADi C, ns per call, median of 7 x 20000 calls in a C loop (-O3
-march=native) cycling over distinct reachable states (the statuses checked 0); CasADi SX: one
call of ``f.map(M, "serial")`` over M states divided by M; Pinocchio: Python's clock around the
bindings.  Error: the largest error over the states, normalized per output component by the RMS
of the reference's values (:func:`symdyn.check.pinocchio_model.normalized_error`).
"""

from __future__ import annotations

import ctypes
import os
import re
import subprocess
import tempfile
from typing import Callable

import numpy as np

from ..derive.parallel import FUNCTIONS, INPUT_SIZES, derive_parallel
from ..model.errors import SymdynError
from .bench import Result, python_time
from .cbuild import CompiledPlatform, compile_shared, find_compiler
from .closed_loop import ClosedLoopReference, PlatformStatus, pose_vector, rcond
from .pinocchio_model import build_closed_loop_model, closed_loop_friction, free_flyer_twist_rate, normalized_error
from .platform_verify import aligned_reference, flat_outputs, random_states

PLATFORM_VARIANTS = ("noc-double", "noc-float", "casadi-sx", "casadi-c", "pinocchio")
#: C loop of the timings: calls per run (7 runs, the median kept), distinct states cycled
CALLS, TIMING_STATES = 20000, 500
#: Pinocchio's closed-loop equivalents (Python bindings): label of each (function, algorithm)
PINOCCHIO_LABELS = {"inverse_dynamics": ("pinocchio rnea + constraint Jacobian + LU (Python bindings)",),
                    "forward_dynamics": ("pinocchio constraintDynamics (Python bindings)",
                                         "pinocchio lcaba (Python bindings)")}
NO_EQUIVALENT = "pinocchio: no closed-loop equivalent"
#: the 1e-9 armature on the legs' joints of the model Pinocchio's constraint solvers are given
ARMATURE = 1e-9
#: what bench.md says about platform robots
REPORT_NOTE = (
    "Platform robots (kind: parallel): the error is against Pinocchio's closed-loop model "
    "(symdyn.check.closed_loop: a free-flying platform, a 6D loop closure per leg, the legs solved by "
    "Pinocchio, the constrained equations solved directly), at random states about the home pose; "
    "symdyn C (noc-double, noc-float: natural orthogonal complement) and CasADi C are timed in a C loop "
    "over 500 reachable states. Pinocchio's closed-loop equivalents, through its Python bindings and "
    "handed the legs' joint values (it has no inverse kinematics of closed loops; symdyn's functions "
    "compute them from the pose): inverse dynamics rnea + getConstraintsJacobian + LU of [Jc^T S] (the "
    "reference's own computation: its error is 0), forward dynamics constraintDynamics (proximal, "
    "1e-12, 10 iterations) and lcaba (mu 1e-6, 50 iterations), both with a 1e-9 armature on the legs' "
    "joints, which their solvers need. Pinocchio has no equivalent of mass_matrix, twist_map, "
    "leg_rate_maps or inverse_kinematics (rows 'no closed-loop equivalent'). Pinocchio's C++ "
    "closed-loop timings are in benchmarks/parallel_speed.py.")


def bench_platform(robot, functions=("inverse_dynamics", "mass_matrix", "forward_dynamics"),
                   variants=PLATFORM_VARIANTS, count: int = 20,
                   progress: Callable[[str], None] = lambda text: None, workdir: str | None = None) -> list[Result]:
    """Measure every variant of the platform ``robot`` on ``functions``."""
    name = robot.name
    workdir = workdir or tempfile.mkdtemp(prefix="symdyn-bench-")
    progress(f"{name}: deriving")
    eqs = derive_parallel(robot, functions)  # first: it refuses what cannot be measured (runtime parameters)
    progress(f"{name}: Pinocchio's closed loop at {count} states")
    reference = ClosedLoopReference(robot)
    states = [s for s in random_states(reference, count, 0) if _regular(reference, s.pose)]
    if not states:
        raise SymdynError(f"{robot.source or name}: none of the {count} random states about the home pose is "
                          "reachable and regular: nothing to measure")
    timing = _timing_states(reference, states)
    references = {}

    def error_of(call, f, precision="double"):
        if precision not in references:
            ref = reference if precision == "double" else ClosedLoopReference(robot, precision)
            rounded = [s.rounded(precision) for s in states]
            references[precision] = (rounded, {g: [_outputs(g, ref, s) for s in rounded] for g in functions})
        rounded, refs = references[precision]
        mine, outs = [], []
        for s, theirs in zip(rounded, refs[f]):
            if theirs is None:  # the reference refuses the rounded state: not compared
                continue
            status, *outputs = call(*s.arguments(f))
            if status != 0:
                return float("inf")
            outs.append((outputs, theirs))
            mine.append(flat_outputs(outputs))
        return normalized_error(mine, [aligned_reference(f, reference, o, t) for o, t in outs])

    results: list[Result] = []
    for variant in variants:
        folder = os.path.join(workdir, f"{name}-{variant}")
        os.makedirs(folder, exist_ok=True)
        progress(f"{name}: {variant}")
        if variant in ("noc-double", "noc-float"):
            results.extend(_symdyn_c(eqs, functions, variant, timing, error_of, folder))
        elif variant == "casadi-sx":
            results.extend(_casadi_sx(eqs, functions, timing, error_of))
        elif variant == "casadi-c":
            results.extend(_casadi_c(eqs, functions, timing, error_of, folder))
        elif variant == "pinocchio":
            results.extend(_pinocchio(robot, reference, functions, states, error_of))
    return results


def _outputs(function, reference, state):
    status, *outputs = getattr(reference, function)(*state.arguments(function))
    return outputs if status == 0 else None


def _regular(reference, pose) -> bool:
    """Whether every function returns 0 at ``pose`` to the reference (the loops close, no leg
    and not the platform singular)."""
    try:
        return rcond(reference.kinematics(pose).K) >= reference.rtol
    except PlatformStatus:
        return False


def _timing_states(reference, states):
    """Up to TIMING_STATES distinct regular platform states about the home pose (seed 1), forces
    in the range of those of the error states: ``{input name: (states, size) array}``."""
    scale = max([float(np.abs(s.phi).max()) for s in states] + [1.0])
    rng = np.random.default_rng(1)
    rows = {"pose": [], "twist": [], "twist_rate": [], "phi": []}
    for p, R, twist, rate in reference.random_states(TIMING_STATES, 1):
        pose = pose_vector(p, R)
        if _regular(reference, pose):
            for key, value in (("pose", pose), ("twist", twist), ("twist_rate", rate), ("phi", rng.uniform(-scale, scale, 6))):
                rows[key].append(value)
    if not rows["pose"]:  # the error states, then
        rows = {key: [getattr(s, key) for s in states] for key in rows}
    return {key: np.array(value) for key, value in rows.items()}


def _header_ops(header: str, prefix: str, function: str) -> int | None:
    """The operations the header's ``Cost:`` line counts for ``prefix_function``."""
    match = re.search(r"\* Cost: ([^\n]*)\n \*/\nint " + re.escape(f"{prefix}_{function}("), header)
    return sum(int(n) for n in re.findall(r"(\d+) [a-z]", match.group(1))) if match else None


def _c_loop(function: str, call: str, real: str, prelude: str = "") -> str:
    """C of ``double time_<function>(inputs..., count, calls, failures)``: the median ns per
    call of ``call`` (which reads ``in0..`` at state k and writes ``out0..``) over 7 runs."""
    inputs, outputs, _ = FUNCTIONS[function]
    args = ", ".join(f"const {real} *in{j}" for j in range(len(inputs)))
    outs = "".join(f"    {real} out{j}[{rows * cols}];\n" for j, (_, rows, cols) in enumerate(outputs))
    return f"""
double time_{function}({args}, int count, int calls, int *failures)
{{
{outs}    double runs[7];
    volatile double sink = 0;
    int r, i, k;
{prelude}    *failures = 0;
    for (r = 0; r < 7; ++r) {{
        double t0 = bench_now();
        for (i = 0; i < calls; ++i) {{
            k = i % count;
            *failures += ({call}) != 0;
            sink += out0[0];
        }}
        runs[r] = (bench_now() - t0) / calls;
    }}
    qsort(runs, 7, sizeof runs[0], bench_compare);
    (void)sink;
    return runs[3];
}}
"""


HARNESS_TOP = r"""#define _POSIX_C_SOURCE 199309L
#include <stdlib.h>
#include <time.h>
%(include)s
static double bench_now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec * 1e9 + t.tv_nsec; }
static int bench_compare(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return (x > y) - (x < y); }
"""


def _time(library: str, function: str, timing, dtype) -> float:
    """ns per call of ``time_<function>`` in ``library`` over the timing states (an error where
    a call returned a nonzero status: the timing would be of an early return)."""
    inputs = FUNCTIONS[function][0]
    arrays = [np.ascontiguousarray(timing[k], dtype=dtype) for k in inputs]
    fn = getattr(ctypes.CDLL(library), f"time_{function}")
    fn.restype = ctypes.c_double
    failures = ctypes.c_int(0)
    pointer = ctypes.POINTER(ctypes.c_float if dtype == np.float32 else ctypes.c_double)
    ns = fn(*[a.ctypes.data_as(pointer) for a in arrays], len(arrays[0]), CALLS, ctypes.byref(failures))
    if failures.value:
        raise SymdynError(f"{function}: {failures.value} timed calls returned a nonzero status")
    return float(ns)


def _symdyn_c(eqs, functions, variant, timing, error_of, folder) -> list[Result]:
    from ..emit.parallel_c import generate_parallel_c
    precision = "float" if variant.endswith("float") else "double"
    prefix = eqs.robot.name
    files = generate_parallel_c(eqs, functions, precision)
    for file_name, text in files.items():
        with open(os.path.join(folder, file_name), "w", encoding="utf-8") as handle:
            handle.write(text)
    real = f"{prefix}_real"
    loops = []
    for f in functions:
        inputs, outputs, _ = FUNCTIONS[f]
        sizes = [INPUT_SIZES[k] for k in inputs]
        arguments = [f"in{j} + {size} * k" for j, size in enumerate(sizes)] + [f"out{j}" for j in range(len(outputs))]
        loops.append(_c_loop(f, f"{prefix}_{f}({', '.join(arguments)})", real))
    harness = os.path.join(folder, f"{prefix}_bench.c")
    with open(harness, "w", encoding="utf-8") as handle:
        handle.write(HARNESS_TOP % {"include": f'#include "{prefix}_dynamics.c"'} + "".join(loops))
    library = compile_shared(harness, folder, ("-O3", "-march=native"))
    lib = CompiledPlatform(library, prefix, precision)
    header = files[f"{prefix}_dynamics.h"]
    return [Result(prefix, variant, f, _time(library, f, timing, lib.dtype), _header_ops(header, prefix, f),
                   error_of(getattr(lib, f), f, precision)) for f in functions]


def _casadi_functions(eqs, functions):
    from ..emit.parallel_casadi import parallel_casadi_function
    return {f: parallel_casadi_function(eqs, f, f"{eqs.robot.name}_{f}") for f in functions}


def _with_status(function):
    """A CasADi Function called as the compiled C is: numpy in, ``(0, outputs...)`` out."""
    def call(*args):
        out = function(*args)
        out = out if isinstance(out, (list, tuple)) else [out]
        return (0, *[np.array(o).reshape(-1) if np.array(o).shape[1] == 1 else np.array(o) for o in out])
    return call


def _casadi_sx(eqs, functions, timing, error_of) -> list[Result]:
    import statistics
    import time
    out = []
    for f, function in _casadi_functions(eqs, functions).items():
        mapped = function.map(len(timing["pose"]), "serial")
        args = [timing[k].T for k in FUNCTIONS[f][0]]
        runs = []
        for _ in range(7):
            start = time.perf_counter()
            mapped(*args)
            runs.append((time.perf_counter() - start) / len(timing["pose"]) * 1e9)
        out.append(Result(eqs.robot.name, "casadi-sx", f, statistics.median(runs), int(function.n_instructions()),
                          error_of(_with_status(function), f)))
    return out


def _casadi_c(eqs, functions, timing, error_of, folder) -> list[Result]:
    import casadi as ca
    out = []
    for f, function in _casadi_functions(eqs, functions).items():
        name = function.name()
        generator = ca.CodeGenerator(f"{name}.c")
        generator.add(function)
        generator.generate(folder + os.sep)
        declarations = (f"typedef long long int casadi_int;\n"
                        f"int {name}(const double **arg, double **res, casadi_int *iw, double *w, int mem);\n"
                        f"int {name}_work(casadi_int *sz_arg, casadi_int *sz_res, casadi_int *sz_iw, casadi_int *sz_w);")
        inputs, outputs, _ = FUNCTIONS[f]
        prelude = (f"    const double *arg[{len(inputs)}];\n    double *res[{len(outputs)}];\n"
                   f"    casadi_int sizes[4];\n    double *w;\n    casadi_int *iw;\n"
                   f"    {name}_work(sizes, sizes + 1, sizes + 2, sizes + 3);\n"
                   f"    w = malloc(sizeof(double) * (size_t)(sizes[3] + 1));\n"
                   f"    iw = malloc(sizeof(casadi_int) * (size_t)(sizes[2] + 1));\n"
                   + "".join(f"    res[{j}] = out{j};\n" for j in range(len(outputs))))
        sizes = [INPUT_SIZES[k] for k in inputs]
        call = ("(" + ", ".join(f"arg[{j}] = in{j} + {size} * k" for j, size in enumerate(sizes))
                + f", {name}(arg, res, iw, w, 0))")
        loop = _c_loop(f, call, "double", prelude).replace("    return runs[3];", "    free(w);\n    free(iw);\n    return runs[3];")
        harness = os.path.join(folder, f"{name}_bench.c")
        with open(harness, "w", encoding="utf-8") as handle:
            handle.write(HARNESS_TOP % {"include": declarations} + loop)
        library = os.path.join(folder, f"{name}.so")
        subprocess.run([find_compiler(), "-O3", "-march=native", "-shared", "-fPIC", "-w", harness,
                        os.path.join(folder, f"{name}.c"), "-o", library, "-lm"], check=True)
        out.append(Result(eqs.robot.name, "casadi-c", f, _time(library, f, timing, np.float64),
                          int(function.n_instructions()), error_of(_with_status(ca.external(name, library)), f)))
    return out


class _PinocchioCalls:
    """Pinocchio's closed-loop equivalents through its bindings, on the tree's (q, v, a) of a
    platform state (:meth:`ClosedLoopReference.tree_state`)."""

    def __init__(self, robot, reference: ClosedLoopReference):
        import pinocchio as pin
        self.pin, self.reference = pin, reference
        self.model, constraints, info = build_closed_loop_model(robot, ARMATURE)
        self.data, self.data_lc = self.model.createData(), self.model.createData()
        self.models = pin.StdVec_RigidConstraintModel()
        self.datas, self.datas_lc, self.datas_id = (pin.StdVec_RigidConstraintData() for _ in range(3))
        for cm in constraints:
            self.models.append(cm)
            for datas in (self.datas, self.datas_lc, self.datas_id):
                datas.append(cm.createData())
        self.info = info
        pin.initConstraintDynamics(self.model, self.data, self.models, self.datas)
        pin.computeJointMinimalOrdering(self.model, self.data_lc, self.models)
        self.prox = pin.ProximalSettings(1e-12, 1e-12, 10)
        self.prox_lc = pin.ProximalSettings(1e-12, 1e-6, 50)
        self.S = np.zeros((self.model.nv, 6))
        for k, leg in enumerate(info["legs"]):
            self.S[leg["actuated_v"], k] = 1.0
        self.actuated_v = [leg["actuated_v"] for leg in info["legs"]]
        self.ref_model, self.ref_data = reference.model, reference.model.createData()

    def inverse_dynamics(self, q, v, a):
        pin = self.pin
        tau = pin.rnea(self.ref_model, self.ref_data, q, v, a) + closed_loop_friction(self.info, v)
        pin.computeJointJacobians(self.ref_model, self.ref_data, q)
        jc = pin.getConstraintsJacobian(self.ref_model, self.ref_data, self.models, self.datas_id)
        return np.linalg.solve(np.hstack([jc.T, self.S]), tau)[-6:]

    def forward(self, lcaba: bool):
        pin = self.pin

        def call(q, v, phi):
            tau = self.S @ phi - closed_loop_friction(self.info, v)
            if lcaba:
                return pin.lcaba(self.model, self.data_lc, q, v, tau, self.models, self.datas_lc, self.prox_lc)
            return pin.constraintDynamics(self.model, self.data, q, v, tau, self.models, self.datas, self.prox)
        return call

    def platform_call(self, function, algorithm):
        """``algorithm(tree state...)`` as a platform function: ``(0, outputs...)`` from the
        generated function's inputs (the legs solved by the reference first, untimed)."""
        reference = self.reference

        def call(pose, twist, last):
            if function == "inverse_dynamics":
                return 0, algorithm(*reference.tree_state(pose, twist, last))
            q, v, _ = reference.tree_state(pose, twist)
            a = algorithm(q, v, last)
            return 0, free_flyer_twist_rate(reference.kinematics(pose).R, reference.com, twist, a), a[self.actuated_v]
        return call


def _pinocchio(robot, reference, functions, states, error_of) -> list[Result]:
    try:
        calls = _PinocchioCalls(robot, reference)
    except ImportError:
        return []
    out = []
    first = states[0]
    for f in functions:
        if f not in PINOCCHIO_LABELS:
            out.append(Result(robot.name, "pinocchio", f, None, None, float("nan"), NO_EQUIVALENT))
            continue
        algorithms = ([calls.inverse_dynamics] if f == "inverse_dynamics" else [calls.forward(False), calls.forward(True)])
        for label, algorithm in zip(PINOCCHIO_LABELS[f], algorithms):
            q, v, a = reference.tree_state(first.pose, first.twist, first.twist_rate)
            last = a if f == "inverse_dynamics" else first.phi
            ns = python_time(lambda: algorithm(q, v, last), calls=200)
            out.append(Result(robot.name, "pinocchio", f, ns, None,
                              error_of(calls.platform_call(f, algorithm), f), label))
    return out


__all__ = ["PLATFORM_VARIANTS", "REPORT_NOTE", "bench_platform"]
