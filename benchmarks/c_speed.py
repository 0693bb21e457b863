"""symdyn's generated C against Pinocchio's C++ and the Pinocchio -> CasADi code-generation peer,
timed by benchmarks/harness.py (its docstring gives the method).

Usage:  python benchmarks/c_speed.py [ROBOT ...] [--functions LIST] [--processes 5] [--passes 15]
            [--states 10000] [--flags O2,O3native] [--no-peer] [--smoke]
        (default robots: puma560 ur5 iiwa14; functions: all six)

Prints the harness's tables (per flag set: ns per call of each side, median over processes and
min-max, Pinocchio's faster convention for crba and aba, the ratios Pinocchio / symdyn and
peer / symdyn: > 1 means symdyn is faster; every side built by the same GCC with the same flags),
symdyn's operation counts per function, and each generated file's size and gcc compile time and
peak memory.
"""

import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import harness  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=["puma560", "ur5", "iiwa14"])
    parser.add_argument("--functions", default=",".join(harness.FUNCTIONS))
    harness.add_arguments(parser)
    args = parser.parse_args(argv)
    kwargs = harness.options(args)
    rows = harness.run(args.robots, args.functions.split(","), **kwargs)
    harness.print_tables(rows, kwargs)
    print("\n### symdyn's operation counts\n")
    print(harness.operations_table(rows))


if __name__ == "__main__":
    main()
