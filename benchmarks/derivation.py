"""Derivation time and expression size per bundled robot and method.

Usage:  python benchmarks/derivation.py [--repeat N] [ROBOT.yaml ...]

Prints a Markdown table: derivation time of all outputs (best of N runs, seconds) and the SymPy
count_ops of the final assignments (intermediate assignments plus output expressions), in total
and for inverse dynamics alone.
"""

import argparse
import glob
import os
import platform
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
import symdyn  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    here = os.path.dirname(os.path.abspath(__file__))
    paths = args.robots or sorted(glob.glob(os.path.join(here, "..", "robots", "*.yaml")))
    print(f"python {platform.python_version()}, sympy {__import__('sympy').__version__}, "
          f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores\n")
    print("| robot | joints | method | derive all (s) | count_ops all | count_ops inverse dynamics |")
    print("|---|---:|---|---:|---:|---:|")
    for path in paths:
        robot = symdyn.load(path)
        for method in symdyn.METHODS:
            best = float("inf")
            for _ in range(args.repeat):
                start = time.perf_counter()
                eqs = symdyn.derive(robot, method)
                best = min(best, time.perf_counter() - start)
            print(f"| {robot.name} | {robot.dof} | {method} | {best:.2f} | {eqs.count_ops()} | "
                  f"{eqs.count_ops(['inverse_dynamics'])} |", flush=True)


if __name__ == "__main__":
    main()
