"""Timing generated C in a C loop: the harness shared by ``symdyn bench`` and ``benchmarks/``."""

import os
import re
import subprocess

from ..model.outputs import COMBINED, REGISTRY, Dimensions, function_inputs

#: C prelude: includes, a monotonic clock, S seeded random states of N joints (q, qd, qdd) and
#: TIME(label, call): median of 7 repeats of 20000 calls, printed as "label ns".  The includes
#: of the code under test go in %(includes)s (which may #define REAL, the scalar type of the
#: state arrays, default double, and OUT_SIZE, the size of the output buffer, default
#: N * N + 6 N + 16); N is %(dof)d, NQ (the entries of q) %(nq)d.  Follow it with the body of main
#: and "return 0; }".
PRELUDE = r"""#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
%(includes)s
#ifndef REAL
#define REAL double
#endif
#ifndef OUT_SIZE
#define OUT_SIZE (N * N + 6 * N + 16)
#endif
#define N %(dof)d
#define NQ %(nq)d
#define S 10000 /* distinct random states, cycled */
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec * 1e9 + t.tv_nsec; }
static int cmp(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return (x > y) - (x < y); }
static REAL q[S][NQ], qd[S][N], qdd[S][N], out[OUT_SIZE];
static volatile double sink;
#define TIME(label, call) do { double runs[7]; int r, i; for (r = 0; r < 7; ++r) { double t0 = now(); \
    for (i = 0; i < 20000; ++i) { int k = i %% S; call; sink += out[0]; } runs[r] = (now() - t0) / 20000; } \
    qsort(runs, 7, sizeof(double), cmp); printf("%%s %%.1f\n", label, runs[3]); } while (0)
int main(void) {
    int k, j;
    srand(1);
    for (k = 0; k < S; ++k) for (j = 0; j < NQ; ++j) {
        q[k][j] = (REAL)(6.0 * rand() / RAND_MAX - 3);
        if (j < N) { qd[k][j] = (REAL)(2.0 * rand() / RAND_MAX - 1); qdd[k][j] = (REAL)(2.0 * rand() / RAND_MAX - 1); } }
"""


def parse(text):
    """{label: ns} from the harness's output."""
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"^(\w+) ([\d.]+)$", text, re.M)}


def call_arguments(function: str, dims: Dimensions) -> tuple[str, list[str], int]:
    """The harness's arguments of ``NAME_<function>`` before ``p`` and its output arrays: the
    inputs (state k; tau is read from the qdd array, integrate's v from qd, difference's q1 is
    the next state's q), then every output argument at its own
    offset in ``out`` (the first at ``out``); and the numbers the outputs take (``dims``: the
    robot's, :meth:`Dimensions.of`)."""
    parts = COMBINED.get(function, (function,))
    source = {"tau": "qdd[k]", "v": "qd[k]", "q1": "q[(k + 1) % S]", "f": "fext", "restitution": "erest"}
    inputs = ", ".join(source.get(g, f"{g}[k]") for g in function_inputs(function))
    sizes = [rows * cols for part in parts for _, (rows, cols) in REGISTRY[part].argument_shapes(dims)]
    offsets = [sum(sizes[:k]) for k in range(len(sizes))]
    return inputs, [("out" if offset == 0 else f"out + {offset}") for offset in offsets], sum(sizes)


def symdyn_harness(prefix: str, dims: Dimensions, functions, precision: str = "double", parameters=()) -> str:
    """A C program timing symdyn's generated ``prefix_<function>`` (``dims``: the robot's sizes,
    :meth:`Dimensions.of`; ``parameters``: the values of its runtime parameters, passed as ``p``)."""
    real = "double" if precision == "double" else "float"
    includes = f'#define REAL {real}\n#include "{prefix}_dynamics.h"'
    extra = ""
    if parameters:
        includes += f"\nstatic const REAL p[{len(parameters)}] = {{{', '.join(repr(float(v)) for v in parameters)}}};"
        extra = ", p"
    if dims.contacts:  # external forces at the contacts (the functions *_ext): constant, of tens of newtons
        includes += f"\nstatic const REAL fext[{dims.contacts}] = {{{', '.join(str(10.0 + k) for k in range(dims.contacts))}}};"
        includes += "\nstatic const REAL erest[1] = {0.5};"
    body, out_size = "", 1
    for f in functions:
        inputs, outputs, size = call_arguments(f, dims)
        out_size = max(out_size, size)
        body += f'    TIME("{f}", {prefix}_{f}({inputs}{extra}, {", ".join(outputs)}));\n'
    includes += f"\n#define OUT_SIZE {out_size}"
    return PRELUDE.replace("%(includes)s", includes) % {"dof": dims.dof, "nq": dims.nq} + body + "    return 0;\n}\n"


def time_generated(files: dict[str, str], prefix: str, dims: Dimensions, functions, precision: str, workdir: str,
                   parameters=()) -> dict[str, float]:
    """Write symdyn's generated ``files`` to ``workdir``, compile them with the timing harness
    (-O3 -march=native) and return ``{function: ns per call}``."""
    from .cbuild import c_sources, find_compiler
    for name, text in files.items():
        with open(os.path.join(workdir, name), "w") as handle:
            handle.write(text)
    harness = os.path.join(workdir, "bench.c")
    with open(harness, "w") as handle:
        handle.write(symdyn_harness(prefix, dims, functions, precision, parameters))
    exe = os.path.join(workdir, "bench")
    subprocess.run([find_compiler(), "-O3", "-march=native", "-std=c99", "-w", harness,
                    *(os.path.join(workdir, name) for name in c_sources(files, prefix)), "-o", exe, "-lm"], check=True)
    return parse(subprocess.run([exe], capture_output=True, text=True, check=True).stdout)
