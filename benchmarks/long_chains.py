"""Long generic chains: where straight-line code stops paying, measured against Pinocchio.

Usage:  python benchmarks/long_chains.py [N ...] [--functions LIST] [--fd-method ldlt|aba|auto]
        (default N: 6 12 24 48; functions: inverse_dynamics,mass_matrix,gravity,forward_dynamics)

Each chain is generic: revolute joints with standard DH parameters drawn at random (seeded; a, d
in [0.05, 0.4] m, twists anywhere in (-pi, pi), no zeros or quarter turns to exploit), masses in
[0.5, 5] kg, full inertia tensors (random principal moments satisfying the triangle inequality,
rotated by a random rotation) and COM offsets in all three axes.  For each N: derive time, C
operation counts, C file size, gcc -O2 compile time of the file (the size a user compiles), and
ns per call (gcc -O2 and gcc -O3 -march=native, median of 7 x 20000 calls over 10,000 distinct
states) beside Pinocchio's C++ (rnea, crba, computeGeneralizedGravity, aba) timed in the same run.
Prints a Markdown table.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import symdyn  # noqa: E402
from symdyn.check.pinocchio_model import build_model  # noqa: E402
from symdyn.check.timing import parse, symdyn_harness  # noqa: E402
from symdyn.emit.cgen import build_function, generate_c  # noqa: E402

PINOCCHIO = {"inverse_dynamics": "rnea", "mass_matrix": "crba", "gravity": "computeGeneralizedGravity",
             "coriolis": "nonLinearEffects", "coriolis_matrix": "computeCoriolisMatrix", "forward_dynamics": "aba"}


def generic_chain(n: int, seed: int = 0) -> str:
    """A robot file (YAML text) of a generic n-joint revolute chain (see the module docstring)."""
    rng = np.random.default_rng(seed + n)
    lines = ["format: 1", f"name: generic{n}", "convention: standard", "gravity: [0, 0, -9.81]", "links:"]
    for _ in range(n):
        a, d = rng.uniform(0.05, 0.4, 2)
        alpha = rng.uniform(-3.0, 3.0)
        mass = rng.uniform(0.5, 5.0)
        com = rng.uniform(-0.1, 0.1, 3)
        principal = rng.uniform(0.01, 0.05, 3)
        principal[2] = rng.uniform(abs(principal[0] - principal[1]) + 0.002, principal[0] + principal[1] - 0.002)
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        inertia = q @ np.diag(principal) @ q.T
        tensor = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2]]
        lines.append(f"  - {{joint: revolute, a: {a:.4f}, alpha: {alpha:.4f}, d: {d:.4f}, theta: 0, mass: {mass:.3f}, "
                     f"com: [{', '.join(f'{c:.4f}' for c in com)}], inertia: [{', '.join(f'{c:.6f}' for c in tensor)}]}}")
    return "\n".join(lines) + "\n"


def main(argv=None):
    from c_speed import pinocchio_bench_binary
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sizes", nargs="*", type=int, default=[6, 12, 24, 48])
    parser.add_argument("--functions", default="inverse_dynamics,mass_matrix,gravity,forward_dynamics")
    parser.add_argument("--fd-method", default=None, choices=("ldlt", "aba"))
    args = parser.parse_args(argv)
    functions = args.functions.split(",")
    with tempfile.TemporaryDirectory() as workdir:
        print("building Pinocchio benchmark (C++, takes a minute)...", file=sys.stderr)
        pinbench = pinocchio_bench_binary(workdir)
        print("| N | function | derive (s) | emit (s) | mul | add | C file (kB) | gcc -O2 compile (s) | "
              "-O2 ns | -O3 native ns | Pinocchio ns | Pinocchio / -O2 | Pinocchio / -O3 native |")
        print("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for n in args.sizes:
            path = os.path.join(workdir, f"generic{n}.yaml")
            with open(path, "w") as handle:
                handle.write(generic_chain(n))
            robot = symdyn.load(path)
            start = time.perf_counter()
            kwargs = {"fd_method": args.fd_method} if args.fd_method else {}
            eqs = symdyn.derive(robot, outputs=functions, **kwargs)
            derive_time = time.perf_counter() - start
            start = time.perf_counter()
            files = generate_c(eqs, functions)
            emit_time = time.perf_counter() - start
            for fname, text in files.items():
                with open(os.path.join(workdir, fname), "w") as handle:
                    handle.write(text)
            source = os.path.join(workdir, f"generic{n}_dynamics.c")
            start = time.perf_counter()
            subprocess.run(["gcc", "-O2", "-std=c99", "-c", source, "-o", os.path.join(workdir, "o2.o")], check=True)
            compile_time = time.perf_counter() - start
            harness = os.path.join(workdir, "time.c")
            with open(harness, "w") as handle:
                handle.write(symdyn_harness(f"generic{n}", n, functions))
            ns = {}
            for label, flags in (("O2", ["-O2"]), ("O3", ["-O3", "-march=native"])):
                exe = os.path.join(workdir, f"time_{label}")
                subprocess.run(["gcc", *flags, "-std=c99", "-w", harness, source, "-o", exe, "-lm"], check=True)
                ns[label] = parse(subprocess.run([exe], capture_output=True, text=True, check=True).stdout)
            model, _ = build_model(robot)
            model_file = os.path.join(workdir, f"generic{n}.txt")
            model.saveToText(model_file)
            theirs = parse(subprocess.run([pinbench, model_file], capture_output=True, text=True, check=True).stdout)
            size = os.path.getsize(source) / 1000
            for f in functions:
                ops = build_function(eqs, f, "double", robot.name).ops
                pin = theirs[PINOCCHIO[f]]
                print(f"| {n} | {f} | {derive_time:.1f} | {emit_time:.1f} | {ops['mul']} | {ops['add']} | {size:.0f} | "
                      f"{compile_time:.1f} | {ns['O2'][f]:.0f} | {ns['O3'][f]:.0f} | {pin:.0f} | "
                      f"{pin / ns['O2'][f]:.1f}x | {pin / ns['O3'][f]:.1f}x |", flush=True)


if __name__ == "__main__":
    main()
