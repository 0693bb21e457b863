"""Call time of symdyn's CasADi functions beside symdyn's own C, in the same run.

Usage:  python benchmarks/casadi_speed.py [ROBOT ...] [--functions LIST]   (default: puma560 ur5 iiwa14, the
        standard outputs)

For each robot and function, ns per call of:
- symdyn C: the generated NAME_dynamics.c, -O3 -march=native, timed in a C loop;
- CasADi C: CasADi's own generated C of the same casadi.Function (symdyn generate --target
  casadi-c), same flags, same loop, called with its arg/res/work-vector convention;
- SX VM: the casadi.Function evaluated by CasADi's SX virtual machine, timed as one call of
  ``f.map(M, "serial")`` over M = 20000 states divided by M (so Python's per-call overhead is
  not counted), median of 7.
Also the Python overhead of one plain ``f(q, qd, qdd)`` call from numpy, which is what a Python
user sees.  Ratios > 1 mean symdyn's C is faster.
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

import casadi as ca  # noqa: E402

import symdyn  # noqa: E402
from symdyn.check.timing import PRELUDE, parse  # noqa: E402
from symdyn.emit.casadi_backend import casadi_files, casadi_function  # noqa: E402
from symdyn.emit.cgen import generate_c  # noqa: E402
from symdyn.derive.equations import OUTPUT_INPUTS, OUTPUTS  # noqa: E402

DECLARATIONS = r"""#include "%(n)s_dynamics.h"
#include "%(n)s_casadi.h"
static double w[100000];
static casadi_int iw[1000];
#define CASADI(fn, a0, a1, a2) do { const double *arg[3]; double *res[1]; \
    arg[0] = a0; arg[1] = a1; arg[2] = a2; res[0] = out; fn(arg, res, iw, w, 0); } while (0)"""

HARNESS = PRELUDE.replace("%(includes)s", DECLARATIONS) + "%(cases)s    return 0;\n}\n"


def harness_cases(name: str, functions) -> str:
    """The TIME lines of symdyn's C and CasADi's C of each function (tau read from the qdd array)."""
    arrays = {"q": "q[k]", "qd": "qd[k]", "qdd": "qdd[k]", "tau": "qdd[k]"}
    lines = []
    for function in functions:
        args = [arrays[group] for group in OUTPUT_INPUTS[function]]
        padded = (args + ["0", "0"])[:3]
        lines.append(f'    TIME("c_{function}", {name}_{function}({", ".join(args)}, out));\n')
        lines.append(f'    TIME("casadi_c_{function}", CASADI({name}_casadi_{function}, {", ".join(padded)}));\n')
    return "".join(lines)


def vm_time(function, dof, states=20000, repeats=7):
    """ns per evaluation by CasADi's SX virtual machine (serial map, one Python call)."""
    mapped = function.map(states, "serial")
    rng = np.random.default_rng(1)
    args = [rng.uniform(-1, 1, (dof, states)) for _ in range(function.n_in())]
    runs = []
    for _ in range(repeats):
        start = time.perf_counter()
        mapped(*args)
        runs.append((time.perf_counter() - start) / states * 1e9)
    return statistics.median(runs)


def python_call_time(function, dof, calls=2000):
    args = [np.linspace(-1, 1, dof) for _ in range(function.n_in())]
    runs = []
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(calls):
            function(*args)
        runs.append((time.perf_counter() - start) / calls * 1e9)
    return statistics.median(runs)


def main(argv=None):
    import argparse
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="*", default=["puma560", "ur5", "iiwa14"])
    parser.add_argument("--functions", default=",".join(OUTPUTS),
                        help="comma-separated outputs to time (default: the standard ones), e.g. the derivatives "
                             "inverse_dynamics_dq,inverse_dynamics_dqd,forward_dynamics_dq,forward_dynamics_dqd,"
                             "mass_matrix_inverse,gravity_derivative")
    args = parser.parse_args(argv)
    names, functions = args.robots, [f.strip() for f in args.functions.split(",") if f.strip()]
    print(f"CasADi {ca.__version__}")
    print("| robot | function | symdyn C (ns) | CasADi C (ns) | SX VM (ns) | CasADi C / symdyn C | SX VM / symdyn C | Python call of f (us) |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as workdir:
        for name in names:
            robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{name}.yaml"))
            if robot.parameters:
                raise SystemExit(f"{name} has runtime parameters; this benchmark times robots without them")
            eqs = symdyn.derive(robot, outputs=functions)
            for fname in functions:  # the harness's work arrays: w[100000], iw[1000]
                function = casadi_function(eqs, fname)
                if function.sz_w() > 100000 or function.sz_iw() > 1000:
                    raise SystemExit(f"{name} {fname}: CasADi's work vectors exceed the harness's")
            files = {k: v.encode() for k, v in generate_c(eqs).items()}
            files.update(casadi_files(eqs, casadi_c=True))
            for fname, data in files.items():
                with open(os.path.join(workdir, fname), "wb") as handle:
                    handle.write(data)
            with open(os.path.join(workdir, "bench.c"), "w") as handle:
                handle.write(HARNESS % {"n": name, "dof": robot.dof, "cases": harness_cases(name, functions)})
            exe = os.path.join(workdir, f"bench_{name}")
            subprocess.run(["gcc", "-O3", "-march=native", "-std=c99", "-w", os.path.join(workdir, "bench.c"),
                            os.path.join(workdir, f"{name}_dynamics.c"), os.path.join(workdir, f"{name}_casadi.c"),
                            "-o", exe, "-lm"], check=True)
            timings = parse(subprocess.run([exe], capture_output=True, text=True, check=True).stdout)
            for fname in functions:
                function = casadi_function(eqs, fname)
                assert function.n_in() == len(OUTPUT_INPUTS[fname])
                vm = vm_time(function, robot.dof)
                call = python_call_time(function, robot.dof)
                mine, theirs = timings[f"c_{fname}"], timings[f"casadi_c_{fname}"]
                print(f"| {name} | {fname} | {mine:.0f} | {theirs:.0f} | {vm:.0f} | {theirs / mine:.1f}x | "
                      f"{vm / mine:.1f}x | {call / 1000:.1f} |", flush=True)


if __name__ == "__main__":
    main()
