"""Identification: derivation time and size of the regressor and base parameters, and inverse
dynamics written in the base parameters against the standard form and Pinocchio's rnea.

Usage:  python benchmarks/identification.py [ROBOT ...] [--processes 5] [--passes 15] [--states 10000]
            [--flags O3native] [--smoke]      (default: puma560 stanford iiwa14 panda chain12)

For each robot: the time to derive the regressor and the base regressor (no cache), SymPy's
count_ops of the regressor's program, the number of base parameters; then inverse dynamics
generated both ways (``--parameters standard|base``), its multiplications/additions and its time
beside Pinocchio's C++ rnea, each form in its own run of benchmarks/harness.py (same GCC and
flags, interleaved passes over the same states; ns per call, median over processes).
"""

import argparse
import os
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))

import harness  # noqa: E402
import symdyn  # noqa: E402


def inverse_dynamics_times(name, form, kwargs):
    """{flag set: (symdyn ns, Pinocchio rnea ns, ops)} of inverse dynamics in ``form``."""
    rows = harness.run([name], ["inverse_dynamics"], **{**kwargs, "peer": False},
                       generate_options={"parameters": form})
    return {row.flag_set: (statistics.median(row.times["symdyn"]), statistics.median(row.side("pinocchio")[1]),
                           row.case.costs()["inverse_dynamics"]) for row in rows}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=["puma560", "stanford", "iiwa14", "panda", "chain12"])
    harness.add_arguments(parser, peer=False)
    args = parser.parse_args(argv)
    if args.flags is None and not args.smoke:
        args.flags = "O3native"
    kwargs = harness.options(args)
    print("| robot | flags | derive Y (s) | derive Y + base (s) | count_ops Y | base parameters | "
          "ID standard mul/add, ns | ID base mul/add, ns | Pinocchio rnea ns (standard run; base run) |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for name in args.robots:
        robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{name}.yaml"))
        start = time.perf_counter()
        full = symdyn.derive(robot, outputs=["regressor"])
        derive_y = time.perf_counter() - start
        start = time.perf_counter()
        base = symdyn.derive(robot, outputs=["regressor", "base_regressor"])
        derive_base = time.perf_counter() - start
        forms = {form: inverse_dynamics_times(name, form, kwargs) for form in ("standard", "base")}
        for flag_set in kwargs["flag_sets"]:
            cells = [f"{ops['mul']}/{ops['add']}, {ns:.0f}" for ns, _, ops in (forms[f][flag_set] for f in forms)]
            pins = " ; ".join(f"{forms[f][flag_set][1]:.0f}" for f in forms)
            print(f"| {name} | {' '.join(harness.FLAG_SETS[flag_set])} | {derive_y:.2f} | {derive_base:.2f} | "
                  f"{full.count_ops(['regressor'])} | {len(base.base_parameters)} of {13 * robot.dof} | {cells[0]} | "
                  f"{cells[1]} | {pins} |", flush=True)


if __name__ == "__main__":
    main()
