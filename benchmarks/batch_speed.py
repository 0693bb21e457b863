"""Batch functions against the scalar ones and Pinocchio, per state, in the same run.

Usage:  python benchmarks/batch_speed.py [ROBOT ...] [--functions LIST] [--states 10000] [--smoke]
            [--processes 5] [--passes 15]      (default: puma560 ur5 iiwa14 panda)

For each robot: generates double-precision C with ``--batch``, and times over 10,000 distinct
random states (median of 7 passes, thread CPU time, ns per state):
- the scalar function called once per state (``NAME_f(q + k*N, ...)``),
- the batch function over all 10,000 states (``NAME_f_batch(10000, ...)``),
each compiled three ways: gcc -O3 -march=native -fno-tree-slp-vectorize (vector width 8 on
AVX-512; see COMPILERS), gcc -O2 (baseline
x86-64: SSE2, width 2) and clang -O3 -march=native; then Pinocchio's C++ (rnea, crba,
computeGeneralizedGravity, nonLinearEffects, aba; the faster convention of crba and aba) on the
same model, timed by benchmarks/harness.py (g++ -O3 -march=native for the -O3 rows, -O2 for the
-O2 row; ns per call, median over processes).  Before timing, every batch result is compared with
the scalar results byte for byte (the harness exits non-zero on a difference).  --smoke: gcc -O2
only, 200 states, one harness process.
"""

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import harness  # noqa: E402
import symdyn  # noqa: E402
from symdyn.check.timing import parse  # noqa: E402
from symdyn.emit.cgen import generate_c  # noqa: E402

#: (symdyn function, its input arrays, its output size in units of N or N*N, Pinocchio's function)
FUNCTIONS = [("inverse_dynamics", ("q", "qd", "qdd"), "N", "rnea"),
             ("mass_matrix", ("q",), "N*N", "crba"),
             ("gravity", ("q",), "N", "computeGeneralizedGravity"),
             ("coriolis", ("q", "qd"), "N", "nonLinearEffects"),
             ("forward_dynamics", ("q", "qd", "qdd"), "N", "aba")]

HARNESS = r"""#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "%(n)s_dynamics.h"
#define N %(dof)d
#define S %(states)d
static double now(void) { struct timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t); return t.tv_sec * 1e9 + t.tv_nsec; }
static int cmp(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return (x > y) - (x < y); }
static double q[S * N], qd[S * N], qdd[S * N], out1[S * N * N], out2[S * N * N];
#define MEDIAN(label, stmt) do { double runs[7]; int r; for (r = 0; r < 7; ++r) { double t0 = now(); stmt; \
    runs[r] = (now() - t0) / S; } qsort(runs, 7, sizeof(double), cmp); printf("%%s %%.2f\n", label, runs[3]); } while (0)
int main(void) {
    int k;
    srand(1);
    for (k = 0; k < S * N; ++k) { q[k] = 6.0 * rand() / RAND_MAX - 3; qd[k] = 2.0 * rand() / RAND_MAX - 1;
        qdd[k] = 2.0 * rand() / RAND_MAX - 1; }
%(body)s
    return 0;
}
"""

BODY = r"""    for (k = 0; k < S; ++k) %(n)s_%(f)s(%(scalar_args)s, out1 + (size_t)k * %(size)s);
    %(n)s_%(f)s_batch(S, %(batch_args)s, out2);
    if (memcmp(out1, out2, sizeof(double) * S * %(size)s) != 0) { printf("MISMATCH %(f)s\n"); return 1; }
    MEDIAN("%(f)s_scalar", for (k = 0; k < S; ++k) %(n)s_%(f)s(%(scalar_args)s, out1 + (size_t)k * %(size)s));
    MEDIAN("%(f)s_batch", %(n)s_%(f)s_batch(S, %(batch_args)s, out2));
"""

#: GCC at -O3 on FMA hardware fuses a*b - c, a*b + c pairs in the scalar code despite
#: -ffp-contract=off unless its SLP vectorizer is off (see the generated header); the harness
#: compares batch and scalar results bit for bit, so that build turns it off.  Last: the flag set
#: of benchmarks/harness.py that Pinocchio's column of the row is built with.
COMPILERS = [("gcc -O3 -march=native -fno-tree-slp-vectorize",
              ["gcc", "-O3", "-march=native", "-fno-tree-slp-vectorize"], "O3native"),
             ("gcc -O2", ["gcc", "-O2"], "O2"),
             ("clang -O3 -march=native", ["clang", "-O3", "-march=native"], "O3native")]


def batch_harness(name, dof, functions, states):
    body = ""
    for f, inputs, size, _ in FUNCTIONS:
        if f in functions:
            body += BODY % {"n": name, "f": f, "size": size, "batch_args": ", ".join(inputs),
                            "scalar_args": ", ".join(f"{a} + (size_t)k * N" for a in inputs)}
    return HARNESS % {"n": name, "dof": dof, "body": body, "states": states}


def pinocchio_times(names, functions, flag_sets, args) -> dict:
    """{(robot, flag set, function): (Pinocchio's ns, its name)} from benchmarks/harness.py."""
    kwargs = {**harness.options(args), "flag_sets": tuple(flag_sets), "peer": False}
    found = {}
    for row in harness.run(names, functions, **kwargs):
        convention, times = row.side("pinocchio")
        pin_name = [p for f, _, _, p in FUNCTIONS if f == row.function][0]
        found[row.case.prefix, row.flag_set, row.function] = (statistics.median(times),
                                                              f"{pin_name} {convention}".strip())
    return found


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=["puma560", "ur5", "iiwa14", "panda"])
    parser.add_argument("--functions", default=",".join(f for f, *_ in FUNCTIONS))
    harness.add_arguments(parser, peer=False)
    args = parser.parse_args(argv)
    functions = [f for f, *_ in FUNCTIONS if f in args.functions.split(",")]
    states = args.states or (200 if args.smoke else 10000)
    compilers = [c for c in COMPILERS if shutil.which(c[1][0]) and (not args.smoke or c[0] == "gcc -O2")]
    theirs = pinocchio_times(args.robots, functions, sorted({c[2] for c in compilers}), args)
    with tempfile.TemporaryDirectory() as workdir:
        print("| robot | function | compiler | scalar (ns/state) | batch (ns/state) | batch / scalar | "
              "Pinocchio (ns, same optimization) | Pinocchio / batch |")
        print("|---|---|---|---:|---:|---:|---:|---:|")
        for name in args.robots:
            robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{name}.yaml"))
            eqs = symdyn.derive(robot, outputs=functions)
            for fname, text in generate_c(eqs, functions, batch=True).items():
                with open(os.path.join(workdir, fname), "w") as handle:
                    handle.write(text)
            with open(os.path.join(workdir, "batch.c"), "w") as handle:
                handle.write(batch_harness(robot.name, robot.dof, functions, states))
            for label, cmd, flag_set in compilers:
                exe = os.path.join(workdir, f"batch_{name}")
                subprocess.run([*cmd, "-std=c99", os.path.join(workdir, "batch.c"),
                                os.path.join(workdir, f"{robot.name}_dynamics.c"), "-o", exe, "-lm"], check=True)
                run = subprocess.run([exe], capture_output=True, text=True)
                if run.returncode != 0:
                    sys.exit(f"{name} ({label}): batch results differ from the scalar ones: {run.stdout.strip()}")
                mine = parse(run.stdout)
                for f in functions:
                    scalar, batch = mine[f"{f}_scalar"], mine[f"{f}_batch"]
                    pin, pin_name = theirs[robot.name, flag_set, f]
                    print(f"| {name} | {f} | {label} | {scalar:.1f} | {batch:.1f} | {batch / scalar:.2f} | "
                          f"{pin:.0f} ({pin_name}, {' '.join(harness.FLAG_SETS[flag_set])}) | {pin / batch:.1f}x |",
                          flush=True)


if __name__ == "__main__":
    main()
