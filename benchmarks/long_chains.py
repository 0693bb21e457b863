"""Long generic chains: where straight-line code stops paying, measured against Pinocchio.

Usage:  python benchmarks/long_chains.py [N ...] [--functions LIST] [--fd-method ldlt|aba]
            [--processes 5] [--passes 15] [--states 10000] [--flags O2,O3native] [--no-peer] [--smoke]
        (default N: 6 12 24 48; functions: inverse_dynamics,mass_matrix,gravity,forward_dynamics;
        forward dynamics: symdyn's own choice, as ``symdyn generate`` makes it, unless --fd-method)

Each chain is generic: revolute joints with standard DH parameters drawn at random (seeded; a, d
in [0.05, 0.4] m, twists anywhere in (-pi, pi), no zeros or quarter turns to exploit), masses in
[0.5, 5] kg, full inertia tensors (random principal moments satisfying the triangle inequality,
rotated by a random rotation) and COM offsets in all three axes.  Timing: benchmarks/harness.py
(its docstring gives the method): symdyn's C, Pinocchio's C++ and the Pinocchio -> CasADi peer,
same GCC and flags, interleaved passes over the same random states, several processes.  Prints
the harness's tables, then per N and function: the time symdyn took to derive and emit the C
(``symdyn generate --no-cache``), its operation counts, the C file's size and gcc -O2's compile
time and peak memory on it (the file a user compiles).
"""

import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import harness  # noqa: E402


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


def chain_table(rows) -> str:
    """Per N and function: generation time, operation counts, file size, gcc -O2 compile cost."""
    lines = ["| N | function | derive + emit, no cache (s) | symdyn forward dynamics | mul | add | C file (kB) | "
             "gcc -O2 compile (s) | gcc -O2 peak (MB) |", "|---:|---|---:|---|---:|---:|---:|---:|---:|"]
    seen = set()
    for row in rows:
        case = row.case
        if (id(case), row.function) in seen:
            continue
        seen.add((id(case), row.function))
        ops = case.costs().get(row.function, {"mul": "-", "add": "-"})
        compile_s, peak = case.compile_costs.get(("O2", "symdyn"), ("-", "-"))
        compile_cells = f"{compile_s:.1f} | {peak:.0f}" if compile_s != "-" else "- | -"
        lines.append(f"| {case.dof} | {row.function} | {case.generate_seconds:.1f} | {case.fd_method} | {ops['mul']} | "
                     f"{ops['add']} | {case.sizes['symdyn'] / 1000:.0f} | {compile_cells} |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sizes", nargs="*", type=int, default=[6, 12, 24, 48])
    parser.add_argument("--functions", default="inverse_dynamics,mass_matrix,gravity,forward_dynamics")
    parser.add_argument("--fd-method", default=None, choices=("ldlt", "aba"))
    harness.add_arguments(parser)
    args = parser.parse_args(argv)
    kwargs = harness.options(args)
    generate_options = {"use_cache": False, **({"fd_method": args.fd_method} if args.fd_method else {})}
    rows = harness.run([str(n) for n in args.sizes], args.functions.split(","), generate_options=generate_options,
                       **kwargs)
    harness.print_tables(rows, kwargs)
    print("\n### Generated code per chain\n")
    print(chain_table(rows))


if __name__ == "__main__":
    main()
