"""Build and run examples/ilqr/ilqr_solo12.c: iLQR of Solo-12 on its floating base (a squat in
the air) with symdyn's generated C, and, when Pinocchio's wheel (pin) is installed, the same
solver linked against Pinocchio (ilqr_solo12_pinocchio.cpp); both at the same gcc flags.

    python examples/ilqr/solo12_ddp.py [--flags="-O3 -march=native"] [--out build/solo12_ddp] [--runs 7]
    python examples/ilqr/solo12_ddp.py --on-feet      # the squat standing on four feet (symdyn's C only)

Prints each program's iterations, then the median of each time per iteration over 7 runs of
each program (--runs), interleaved (one solve is a few ms: a single run swings by half), and the ratios;
exits 0 when both converge to the same cost (within 1e-6 of it).
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
FUNCTIONS = "forward_dynamics,forward_dynamics_derivatives,integrate,integrate_jacobians,difference"
#: standing on four feet: the contact dynamics, their derivatives and contact inverse dynamics
ON_FEET = "contact_forward_dynamics,contact_forward_dynamics_derivatives,contact_inverse_dynamics,integrate," \
          "integrate_jacobians,difference,frame_poses"
FEET = "FL_FOOT:3d,FR_FOOT:3d,HL_FOOT:3d,HR_FOOT:3d"


def solo12_urdf() -> str:
    """Solo-12's URDF from example-robot-data (shipped in the pin wheel's cmeel prefix)."""
    import sysconfig
    path = Path(sysconfig.get_paths()["purelib"]) / "cmeel.prefix" / "share" / "example-robot-data" / "robots" / \
        "solo_description" / "robots" / "solo12.urdf"
    if not path.exists():
        sys.exit("solo12.urdf not found: install example-robot-data (pip install pin)")
    return str(path)


RUNS = 7


def run(program: str, model: str = "", quiet: bool = False) -> tuple[str, float, dict]:
    """The program's output, its final cost and its times per iteration (ms: ``total``,
    ``linearization``, ``backward``, ``forward``); ``model``: the saved Pinocchio model the
    Pinocchio build reads."""
    done = subprocess.run([program], capture_output=True, text=True, timeout=600, env={**os.environ, "SOLO12_MODEL": model})
    if not quiet:
        print(done.stdout, end="")
    if done.returncode != 0:
        sys.exit(f"{program}: exit {done.returncode}: {done.stderr.strip()}")
    cost = float(re.search(r"final: cost (\S+)", done.stdout).group(1))
    found = re.search(r"time per iteration: (\S+) ms \(linearization (\S+) ms, backward pass (\S+) ms, "
                      r"forward passes (\S+) ms\)", done.stdout)
    times = dict(zip(("total", "linearization", "backward", "forward"), map(float, found.groups())))
    return done.stdout, cost, times


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--flags", default="-O2", help="gcc/g++ optimization flags of both builds (default -O2)")
    parser.add_argument("--out", default=str(REPO / "build" / "solo12_ddp"))
    parser.add_argument("--runs", type=int, default=RUNS,
                        help=f"runs of each build timed, interleaved (default {RUNS}; 1: the comparison only)")
    parser.add_argument("--on-feet", action="store_true",
                        help="the squat standing on four feet (contact dynamics; symdyn's build only)")
    args = parser.parse_args(argv)
    out = Path(args.out + ("_on_feet" if args.on_feet else ""))
    out.mkdir(parents=True, exist_ok=True)
    urdf = solo12_urdf()
    from symdyn.cli import main as symdyn
    request = ["--functions", ON_FEET, "--contacts", FEET] if args.on_feet else ["--functions", FUNCTIONS]
    if symdyn(["generate", urdf, "--floating-base", *request, "--out", str(out), "--quiet"]) != 0:
        return 1
    flags = args.flags.split() + ["-ffp-contract=off"]
    sources = sorted(str(p) for p in out.glob("solo_dynamics*.c"))
    mine = str(out / "ilqr_symdyn")
    subprocess.run(["gcc", *flags, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", f"-I{out}",
                    *(["-DON_FEET"] if args.on_feet else []), str(HERE / "ilqr_solo12.c"), *sources, "-lm", "-o", mine],
                   check=True)
    print(f"== symdyn's generated C ({' '.join(flags)}){' on four feet' if args.on_feet else ''}")
    _, cost, ms = run(mine)
    if args.on_feet:
        return 0
    try:
        import pinocchio as pin
    except ImportError:
        print("(pin not installed: no comparison with Pinocchio)")
        return 0
    sys.path.insert(0, str(REPO / "benchmarks"))
    from harness import link_pinocchio, pinocchio_compile_flags
    solver, backend = str(out / "ilqr_solo12.o"), str(out / "ilqr_solo12_pinocchio.o")
    subprocess.run(["gcc", *flags, "-std=c99", f"-I{out}", "-c", str(HERE / "ilqr_solo12.c"), "-o", solver], check=True)
    subprocess.run(["g++", *flags, *pinocchio_compile_flags([str(out)]), "-c", str(HERE / "ilqr_solo12_pinocchio.cpp"),
                    "-o", backend], check=True)
    theirs = link_pinocchio([solver, backend], str(out / "ilqr_pinocchio"), flags)
    model = str(out / "solo12_model.txt")
    pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer()).saveToText(model)
    print(f"== the same solver on Pinocchio ({' '.join(flags)})")
    _, their_cost, their_ms = run(theirs, model)
    same = abs(cost - their_cost) <= 1e-6 * abs(cost)
    runs, timed = [(ms, their_ms)], max(args.runs, 1)
    for _ in range(timed - 1):
        runs.append((run(mine, quiet=True)[2], run(theirs, model, quiet=True)[2]))
    ms = {part: statistics.median(r[0][part] for r in runs) for part in ms}
    their_ms = {part: statistics.median(r[1][part] for r in runs) for part in their_ms}
    print(f"median of {timed} runs of each, interleaved:")
    for part, what in (("total", "time per iteration"), ("linearization", "linearization (the dynamics' derivatives)"),
                       ("forward", "forward passes (the dynamics, integrate, difference)"),
                       ("backward", "backward pass (the solver's own, the same code)")):
        print(f"{what}: symdyn {ms[part]:.3f} ms, Pinocchio {their_ms[part]:.3f} ms: "
              f"{their_ms[part] / ms[part]:.2f}x")
    print(f"final costs {cost:.9g} and {their_cost:.9g}: {'the same' if same else 'DIFFERENT'}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
