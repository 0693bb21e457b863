"""Batch functions against the scalar ones and Pinocchio, per state, in the same run.

Usage:  python benchmarks/batch_speed.py [ROBOT ...]      (default: puma560 ur5 iiwa14 panda)

For each robot: generates double-precision C with ``--batch``, and times over 10,000 distinct
random states (median of 7 passes, ns per state):
- the scalar function called once per state (``NAME_f(q + k*N, ...)``),
- the batch function over all 10,000 states (``NAME_f_batch(10000, ...)``),
each compiled three ways: gcc -O3 -march=native -fno-tree-slp-vectorize (vector width 8 on
AVX-512; see COMPILERS), gcc -O2 (baseline
x86-64: SSE2, width 2) and clang -O3 -march=native; then Pinocchio's C++ (rnea, crba,
computeGeneralizedGravity, nonLinearEffects, aba) on the same model, built by
benchmarks/c_speed.py's helper.  Before timing, every batch result is compared with the scalar
results byte for byte (the harness exits non-zero on a difference).
"""

import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import symdyn  # noqa: E402
from symdyn.check.pinocchio_model import build_model  # noqa: E402
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
#define S 10000
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec * 1e9 + t.tv_nsec; }
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
#: compares batch and scalar results bit for bit, so that build turns it off
COMPILERS = [("gcc -O3 -march=native -fno-tree-slp-vectorize", ["gcc", "-O3", "-march=native", "-fno-tree-slp-vectorize"]),
             ("gcc -O2", ["gcc", "-O2"]),
             ("clang -O3 -march=native", ["clang", "-O3", "-march=native"])]


def harness(name, dof):
    body = ""
    for f, inputs, size, _ in FUNCTIONS:
        body += BODY % {"n": name, "f": f, "size": size, "scalar_args": ", ".join(f"{a} + (size_t)k * N" for a in inputs),
                        "batch_args": ", ".join(inputs)}
    return HARNESS % {"n": name, "dof": dof, "body": body}


def main(argv=None):
    from c_speed import pinocchio_bench_binary
    names = (argv if argv is not None else sys.argv[1:]) or ["puma560", "ur5", "iiwa14", "panda"]
    compilers = [(label, cmd) for label, cmd in COMPILERS if shutil.which(cmd[0])]
    with tempfile.TemporaryDirectory() as workdir:
        print("building Pinocchio benchmark (C++, takes a minute)...", file=sys.stderr)
        pinbench = pinocchio_bench_binary(workdir)
        print("| robot | function | compiler | scalar (ns/state) | batch (ns/state) | batch / scalar | "
              "Pinocchio (ns) | Pinocchio / batch |")
        print("|---|---|---|---:|---:|---:|---:|---:|")
        for name in names:
            robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{name}.yaml"))
            eqs = symdyn.derive(robot)
            for fname, text in generate_c(eqs, [f for f, *_ in FUNCTIONS], batch=True).items():
                with open(os.path.join(workdir, fname), "w") as handle:
                    handle.write(text)
            with open(os.path.join(workdir, "batch.c"), "w") as handle:
                handle.write(harness(name, robot.dof))
            model, _ = build_model(robot)
            model_file = os.path.join(workdir, f"{name}.txt")
            model.saveToText(model_file)
            theirs = parse(subprocess.run([pinbench, model_file], capture_output=True, text=True, check=True).stdout)
            for label, cmd in compilers:
                exe = os.path.join(workdir, f"batch_{name}")
                subprocess.run([*cmd, "-std=c99", os.path.join(workdir, "batch.c"),
                                os.path.join(workdir, f"{name}_dynamics.c"), "-o", exe, "-lm"], check=True)
                run = subprocess.run([exe], capture_output=True, text=True)
                if run.returncode != 0:
                    sys.exit(f"{name} ({label}): batch results differ from the scalar ones: {run.stdout.strip()}")
                mine = parse(run.stdout)
                for f, _, _, pin_name in FUNCTIONS:
                    scalar, batch = mine[f"{f}_scalar"], mine[f"{f}_batch"]
                    print(f"| {name} | {f} | {label} | {scalar:.1f} | {batch:.1f} | {batch / scalar:.2f} | "
                          f"{theirs[pin_name]:.0f} ({pin_name}) | {theirs[pin_name] / batch:.1f}x |", flush=True)


if __name__ == "__main__":
    main()
