"""What specialization buys: operation counts and time per call of each scene in
robots/scenes/ (and float versions) against the full model's same function.

Usage:  python benchmarks/scenes.py [--smoke]
Prints a Markdown table (ns per call: median of 7 x 20000 calls, -O3 -march=native; the loop of
symdyn.check.timing: no Pinocchio here).  --smoke: the first two cases only.
"""

import argparse
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

import symdyn  # noqa: E402
from symdyn.emit.cgen import build_function, generate_c  # noqa: E402
from symdyn.model.scene import load_scene  # noqa: E402
from symdyn.check.timing import time_generated  # noqa: E402

ROBOTS = os.path.join(HERE, "..", "robots")
CASES = [  # (label, scene file or robot, functions, precision)
    ("puma560 full", "puma560.yaml", ["gravity", "inverse_dynamics", "mass_matrix", "forward_dynamics"], "double"),
    ("puma560 gravity only, float (scene)", "scenes/puma560_gravity.yaml", ["gravity"], "float"),
    ("puma560 wrist locked (scene, 3 joints)", "scenes/puma560_wrist_locked.yaml",
     ["gravity", "inverse_dynamics", "mass_matrix", "forward_dynamics"], "double"),
    ("puma560 wrist locked, float", "scenes/puma560_wrist_locked.yaml",
     ["gravity", "inverse_dynamics", "mass_matrix", "forward_dynamics"], "float"),
    ("ur5 full", "ur5.yaml", ["gravity", "inverse_dynamics", "mass_matrix", "forward_dynamics"], "double"),
    ("ur5 runtime payload (scene)", "scenes/ur5_payload.yaml",
     ["gravity", "inverse_dynamics", "mass_matrix", "forward_dynamics"], "double"),
    ("ur5 runtime payload, float", "scenes/ur5_payload.yaml",
     ["gravity", "inverse_dynamics", "mass_matrix", "forward_dynamics"], "float"),
]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="the first two cases only")
    args = parser.parse_args(argv)
    print("| model | function | precision | ns | mul | add | div | sin/cos |")
    print("|---|---|---|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as workdir:
        for label, file, functions, precision in CASES[:2] if args.smoke else CASES:
            path = os.path.join(ROBOTS, file)
            robot = load_scene(path).robot if file.startswith("scenes/") else symdyn.load(path)
            eqs = symdyn.derive(robot)
            files = generate_c(eqs, functions, precision)
            folder = os.path.join(workdir, label.replace(" ", "_").replace(",", "").replace("(", "").replace(")", ""))
            os.makedirs(folder)
            nominal = [float(v) for v in robot.nominal]
            timings = time_generated(files, robot.name, robot.dof, functions, precision, folder, nominal)
            for f in functions:
                ops = build_function(eqs, f, precision, robot.name).ops
                print(f"| {label} | {f} | {precision} | {timings[f]:.0f} | {ops['mul']} | {ops['add']} | "
                      f"{ops['div']} | {ops['trig']} |", flush=True)


if __name__ == "__main__":
    main()
