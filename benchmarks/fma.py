"""Fused multiply-add: accuracy and speed of the generated C with and without contraction.

Usage:  python benchmarks/fma.py [ROBOT ...]      (default: puma560 iiwa14 panda chain12)

With -std=c99 GCC does not contract a*b + c into fused multiply-adds (-ffp-contract=off), even with
-march=native on FMA hardware; -ffp-contract=fast lets it.  For each robot this compiles the same
generated double-precision C both ways (gcc -O3 -march=native -std=c99, with and without
-ffp-contract=fast), measures the error of inverse dynamics, the mass matrix, the Coriolis matrix
and forward dynamics against the 50-digit reference (symdyn.check.reference; 20 seeded states,
error normalized per joint), and times them (ns per call, median of 7 x 20000 calls over 10,000
distinct states).  Prints a Markdown table.
"""

import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

import symdyn  # noqa: E402
from symdyn.check.bench import INPUTS, _states  # noqa: E402
from symdyn.check.cbuild import CompiledDynamics, compile_shared, find_compiler  # noqa: E402
from symdyn.check.pinocchio_model import normalized_error  # noqa: E402
from symdyn.check.reference import MpReference  # noqa: E402
from symdyn.check.timing import parse, symdyn_harness  # noqa: E402
from symdyn.emit.cgen import generate_c  # noqa: E402

FUNCTIONS = ("inverse_dynamics", "mass_matrix", "coriolis_matrix", "forward_dynamics")
MODES = {"off": ["-O3", "-march=native", "-std=c99"],
         "fast": ["-O3", "-march=native", "-std=c99", "-ffp-contract=fast"]}


def main(argv=None):
    names = (argv if argv is not None else sys.argv[1:]) or ["puma560", "iiwa14", "panda", "chain12"]
    print("| robot | function | error, contraction off | error, -ffp-contract=fast | ns, off | ns, fast | "
          "fast / off time |")
    print("|---|---|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as workdir:
        for name in names:
            robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{name}.yaml")).with_nominal_values()
            eqs = symdyn.derive(robot)
            files = generate_c(eqs, list(FUNCTIONS))
            for fname, text in files.items():
                with open(os.path.join(workdir, fname), "w") as handle:
                    handle.write(text)
            reference = MpReference(robot)
            states = _states(robot.dof, 20)
            refs = {f: [getattr(reference, f)(*[s[k] for k in INPUTS[f]]) for s in states] for f in FUNCTIONS}
            errors, times = {}, {}
            for mode, flags in MODES.items():
                folder = os.path.join(workdir, mode)
                os.makedirs(folder, exist_ok=True)
                lib = CompiledDynamics(compile_shared(os.path.join(workdir, f"{name}_dynamics.c"), folder,
                                                      extra_flags=flags[:2] + flags[3:]), name, robot.dof, 0)
                for f in FUNCTIONS:
                    mine = [np.asarray(getattr(lib, f)(*[s[k] for k in INPUTS[f]]), dtype=float) for s in states]
                    errors[mode, f] = normalized_error(mine, refs[f])
                harness = os.path.join(folder, "time.c")
                with open(harness, "w") as handle:
                    handle.write(symdyn_harness(name, robot.dof, FUNCTIONS))
                exe = os.path.join(folder, "time")
                subprocess.run([find_compiler(), *flags, "-w", f"-I{workdir}", harness,
                                os.path.join(workdir, f"{name}_dynamics.c"), "-o", exe, "-lm"], check=True)
                for f, ns in parse(subprocess.run([exe], capture_output=True, text=True, check=True).stdout).items():
                    times[mode, f] = ns
            for f in FUNCTIONS:
                print(f"| {name} | {f} | {errors['off', f]:.1e} | {errors['fast', f]:.1e} | {times['off', f]:.0f} | "
                      f"{times['fast', f]:.0f} | {times['fast', f] / times['off', f]:.2f} |", flush=True)


if __name__ == "__main__":
    main()
