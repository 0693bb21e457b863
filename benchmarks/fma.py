"""Fused multiply-add: accuracy and speed of the generated C with and without contraction.

Usage:  python benchmarks/fma.py [ROBOT ...] [harness options]   (default: puma560 iiwa14 panda chain12;
        harness options: --processes, --passes, --states, --seed; --smoke: the accuracy columns
        only, no timing: the harness's two flag sets would build Pinocchio's objects twice more)

With -std=c99 GCC does not contract a*b + c into fused multiply-adds (-ffp-contract=off), even with
-march=native on FMA hardware; -ffp-contract=fast lets it.  For each robot this compiles the same
generated double-precision C both ways (gcc -O3 -march=native -std=c99, with and without
-ffp-contract=fast) and measures the error of inverse dynamics, the mass matrix, the Coriolis
matrix and forward dynamics against the 50-digit reference (symdyn.check.reference; 20 seeded
states, error normalized per joint); and times both builds with benchmarks/harness.py, flag sets
O3native and O3nativefma (every side, Pinocchio too, with the same flags; distinct random
states, thread CPU time, interleaved passes, processes from fresh binary copies; ns per call,
median over processes).  Prints a Markdown table.
"""

import argparse
import os
import statistics
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import harness  # noqa: E402
import symdyn  # noqa: E402
from symdyn.check.bench import _states  # noqa: E402
from symdyn.check.states import state_arguments  # noqa: E402
from symdyn.check.cbuild import CompiledDynamics, compile_shared  # noqa: E402
from symdyn.check.pinocchio_model import normalized_error  # noqa: E402
from symdyn.check.reference import MpReference  # noqa: E402
from symdyn.emit.cgen import generate_c  # noqa: E402
from symdyn.model.outputs import Dimensions  # noqa: E402

FUNCTIONS = ("inverse_dynamics", "mass_matrix", "coriolis_matrix", "forward_dynamics")
#: the gcc flags of the accuracy builds beyond -O3 (symdyn.check.cbuild) and the harness's flag sets
MODES = {"off": ["-O3", "-march=native"], "fast": ["-O3", "-march=native", "-ffp-contract=fast"]}
FLAG_SETS = {"off": "O3native", "fast": "O3nativefma"}


def accuracy(name: str, workdir: str) -> dict:
    """{(mode, function): normalized error against the 50-digit reference} of one robot."""
    robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{name}.yaml")).with_nominal_values()
    eqs = symdyn.derive(robot)
    for fname, text in generate_c(eqs, list(FUNCTIONS)).items():
        with open(os.path.join(workdir, fname), "w") as handle:
            handle.write(text)
    reference = MpReference(robot)
    states = _states(robot.dof, 20)
    refs = {f: [getattr(reference, f)(*state_arguments(f, s)) for s in states] for f in FUNCTIONS}
    errors = {}
    for mode, flags in MODES.items():
        folder = os.path.join(workdir, mode)
        os.makedirs(folder, exist_ok=True)
        lib = CompiledDynamics(compile_shared(os.path.join(workdir, f"{name}_dynamics.c"), folder,
                                              extra_flags=flags), name, Dimensions.of(robot), 0)
        for f in FUNCTIONS:
            mine = [np.asarray(getattr(lib, f)(*state_arguments(f, s)), dtype=float) for s in states]
            errors[mode, f] = normalized_error(mine, refs[f])
    return errors


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=["puma560", "iiwa14", "panda", "chain12"])
    harness.add_arguments(parser, peer=False)
    args = parser.parse_args(argv)
    kwargs = {**harness.options(args), "flag_sets": tuple(FLAG_SETS.values()), "peer": False}
    rows = {} if args.smoke else {(r.case.prefix, r.flag_set, r.function): r
                                  for r in harness.run(args.robots, FUNCTIONS, **kwargs)}
    if rows:
        print(harness.environment(kwargs))
    print("\n| robot | function | error, contraction off | error, -ffp-contract=fast | ns, off | ns, fast | "
          "fast / off time | Pinocchio / symdyn, off | Pinocchio / symdyn, fast |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as workdir:
        for name in args.robots:
            errors = accuracy(name, workdir)
            for f in FUNCTIONS:
                timing = "- | - | - | - | -"
                if rows:
                    off, fast = rows[name, FLAG_SETS["off"], f], rows[name, FLAG_SETS["fast"], f]
                    ratio = statistics.median(fast.times["symdyn"]) / statistics.median(off.times["symdyn"])
                    timing = (f"{harness.summary(off.times['symdyn'])} | {harness.summary(fast.times['symdyn'])} | "
                              f"{ratio:.2f} | {harness.summary(off.ratio('pinocchio'), 1)} | "
                              f"{harness.summary(fast.ratio('pinocchio'), 1)}")
                print(f"| {name} | {f} | {errors['off', f]:.1e} | {errors['fast', f]:.1e} | {timing} |", flush=True)


if __name__ == "__main__":
    main()
