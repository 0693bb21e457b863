"""Batch functions against the scalar ones and Pinocchio, per state, timed by benchmarks/harness.py.

Usage:  python benchmarks/batch_speed.py [ROBOT ...] [--functions LIST] [harness options]
        (default: puma560 ur5 iiwa14 panda, inverse_dynamics, mass_matrix, gravity, coriolis,
        forward_dynamics; harness options: --processes, --passes, --states, --flags, --seed,
        --smoke, --no-peer)

For each robot: symdyn's double-precision C generated with ``--batch``, timed with the harness's
method (distinct random states read by every side, thread CPU time, interleaved passes, several
processes from fresh copies of the binary, the same gcc flags on every side; -O2 is baseline
x86-64, 2 doubles per SSE2 vector; -O3 -march=native uses the machine's widest vectors), in ns
per state:

- the scalar function called once per state,
- the batch function ``NAME_f_batch(S, ...)`` called once over all S states (its time / S),
- Pinocchio (the faster convention of crba and aba) and the Pinocchio -> CasADi peer, per call.

Before timing, the batch function's results on the first states are compared with the scalar
function's (the run stops beyond 1e-6 relative; bit-for-bit equality under the flags the
generated header names is the test suite's, tests/emit/test_batch.py).
"""

import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import harness  # noqa: E402

FUNCTIONS = ("inverse_dynamics", "mass_matrix", "gravity", "coriolis", "forward_dynamics")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=["puma560", "ur5", "iiwa14", "panda"])
    parser.add_argument("--functions", default=",".join(FUNCTIONS))
    harness.add_arguments(parser)
    args = parser.parse_args(argv)
    kwargs = harness.options(args)
    functions = [f.strip() for f in args.functions.split(",") if f.strip()]
    rows = harness.run(args.robots, functions, sides=("batch",), **kwargs)
    for flag_set in harness.flag_set_sections(kwargs):
        print(harness.sides_table(rows, flag_set))
        print(f"\nThe same run, symdyn's scalar function against Pinocchio and the peer:\n")
        print(harness.markdown(rows, flag_set))


if __name__ == "__main__":
    main()
