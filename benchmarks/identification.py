"""Identification: derivation time and size of the regressor and base parameters, and inverse
dynamics written in the base parameters against the standard form and Pinocchio's rnea.

Usage:  python benchmarks/identification.py [ROBOT ...]   (default: puma560 stanford iiwa14 panda chain12)

For each robot: the time to derive the regressor and the base regressor (no cache), SymPy's
count_ops of the regressor's program, the number of base parameters; then inverse dynamics
generated both ways (``--parameters standard|base``), its multiplications/additions and its time
(-O3 -march=native, 10,000 distinct states, symdyn.check.timing) beside Pinocchio's C++ rnea in
the same run (benchmarks/pinocchio_bench.cpp).
"""

import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))

import symdyn  # noqa: E402
from c_speed import pinocchio_bench_binary  # noqa: E402
from symdyn.check.pinocchio_model import build_model  # noqa: E402
from symdyn.check.timing import parse, time_generated  # noqa: E402
from symdyn.emit.cgen import build_function, generate_c  # noqa: E402


def main(argv=None):
    names = (argv if argv is not None else sys.argv[1:]) or ["puma560", "stanford", "iiwa14", "panda", "chain12"]
    with tempfile.TemporaryDirectory() as workdir:
        print("building Pinocchio benchmark (C++, takes a minute)...", file=sys.stderr)
        pinbench = pinocchio_bench_binary(workdir)
        print("| robot | derive Y (s) | derive Y + base (s) | count_ops Y | base parameters | "
              "ID standard mul/add, ns | ID base mul/add, ns | Pinocchio rnea ns |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        for name in names:
            robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{name}.yaml"))
            start = time.perf_counter()
            full = symdyn.derive(robot, outputs=["regressor"])
            derive_y = time.perf_counter() - start
            start = time.perf_counter()
            base = symdyn.derive(robot, outputs=["regressor", "base_regressor"])
            derive_base = time.perf_counter() - start
            cells = []
            for form in ("standard", "base"):
                eqs = symdyn.derive(robot, outputs=["inverse_dynamics"], parameters=form)
                folder = os.path.join(workdir, f"{name}-{form}")
                os.makedirs(folder)
                ns = time_generated(generate_c(eqs, ["inverse_dynamics"]), name, robot.dof, ["inverse_dynamics"],
                                    "double", folder)["inverse_dynamics"]
                ops = build_function(eqs, "inverse_dynamics", "double", name).ops
                cells.append(f"{ops['mul']}/{ops['add']}, {ns:.0f}")
            model, _ = build_model(robot)
            model_file = os.path.join(workdir, f"{name}.txt")
            model.saveToText(model_file)
            rnea = parse(subprocess.run([pinbench, model_file], capture_output=True, text=True, check=True).stdout)["rnea"]
            print(f"| {name} | {derive_y:.2f} | {derive_base:.2f} | {full.count_ops(['regressor'])} | "
                  f"{len(base.base_parameters)} of {13 * robot.dof} | {cells[0]} | {cells[1]} | {rnea:.0f} |", flush=True)


if __name__ == "__main__":
    main()
