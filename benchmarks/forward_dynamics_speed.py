"""Forward dynamics against Pinocchio's C++ ``aba`` and the Pinocchio -> CasADi peer: LDL^T and the
articulated-body algorithm, double and float, each timed by benchmarks/harness.py.

Usage:  python benchmarks/forward_dynamics_speed.py [ROBOT ...] [--processes 5] [--passes 15]
            [--states 10000] [--flags O2,O3native] [--no-peer] [--smoke]
        (default: puma560 ur5 iiwa14 panda)

For each variant of symdyn's ``forward_dynamics`` (``--fd-method ldlt|aba`` x ``--precision
double|float``) one harness run times it beside Pinocchio's ``aba`` (its faster convention)
in the same processes, over the same states (float C reads float copies of them), same GCC and
flags; the peer's ``aba`` C is timed in the first run.  Prints, per flag set, Pinocchio's time,
the peer's, and per variant symdyn's time and the ratio Pinocchio / symdyn (> 1: symdyn is
faster), each as median over processes (min-max), then each variant's operation count
(mul/add/div).  ``panda`` has full (non-diagonal) inertia tensors, as identified by Gaz et al.
2019.
"""

import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import harness  # noqa: E402

VARIANTS = (("ldlt", "double"), ("aba", "double"), ("ldlt", "float"), ("aba", "float"))


def table(runs, flag_set: str) -> str:
    """runs: {variant: rows of one harness run}."""
    first = runs[VARIANTS[0]]
    lines = ["| robot | Pinocchio aba ns | CasADi peer ns | "
             + " | ".join(f"{m} {p} ns, Pinocchio / symdyn" for m, p in VARIANTS) + " |",
             "|---|---:|---:|" + "---:|" * len(VARIANTS)]
    for index, row in enumerate(r for r in first if r.flag_set == flag_set):
        convention, pinocchio = row.side("pinocchio")
        peer = row.side("peer")
        cells = []
        for variant in VARIANTS:
            other = [r for r in runs[variant] if r.flag_set == flag_set][index]
            cells.append(f"{harness.summary(other.times['symdyn'])}, {harness.summary(other.ratio('pinocchio'), 2)}")
        peer_cell = harness.summary(peer[1]) + (f" {peer[0]}" if peer[0] else "") if peer else "-"
        lines.append(f"| {row.case.label} | {harness.summary(pinocchio)} {convention} | {peer_cell} | "
                     + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=["puma560", "ur5", "iiwa14", "panda"])
    harness.add_arguments(parser)
    args = parser.parse_args(argv)
    kwargs = harness.options(args)
    runs = {}
    for k, (method, precision) in enumerate(VARIANTS):
        print(f"forward dynamics by {method}, {precision}...", file=sys.stderr)
        options = {**kwargs, "peer": kwargs["peer"] and k == 0}  # the peer's aba once
        runs[method, precision] = harness.run(args.robots, ["forward_dynamics"], **options,
                                              generate_options={"fd_method": method, "precision": precision})
    print(harness.environment(kwargs))
    for flag_set in kwargs["flag_sets"]:
        print(f"\n### {' '.join(harness.FLAG_SETS[flag_set])} (every side)\n")
        print(table(runs, flag_set))
    print("\n### Operations (mul/add/div) of symdyn's forward_dynamics\n")
    print("| robot | " + " | ".join(f"{m} {p}" for m, p in VARIANTS) + " |")
    print("|---|" + "---:|" * len(VARIANTS))
    for index, row in enumerate(r for r in runs[VARIANTS[0]] if r.flag_set == kwargs["flag_sets"][0]):
        cells = []
        for variant in VARIANTS:
            case = [r for r in runs[variant] if r.flag_set == kwargs["flag_sets"][0]][index].case
            ops = case.costs()["forward_dynamics"]
            cells.append(f"{ops['mul']}/{ops['add']}/{ops['div']}")
        print(f"| {row.case.label} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
