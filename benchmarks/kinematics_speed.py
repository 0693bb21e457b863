"""Tool kinematics of symdyn's generated C against Pinocchio's C++ in the same run, and the
derivation time of a URDF arm against the same arm from its DH table.

Usage:  python benchmarks/kinematics_speed.py [--smoke]
        (--smoke: the UR5 URDF and the ur5 DH table only, one derivation each, 200 states)

Robots: the UR5 and Panda URDFs of the example-robot-data wheel (a test extra), read by
symdyn and, for Pinocchio, by Pinocchio's own URDF parser (``buildModelFromUrdf``, joints off
the chain locked), and the bundled DH robots ur5 and panda.  Timing: ns per call, median of 7
repeats of 20000 calls cycling over 10,000 distinct random states (thread CPU time on
Pinocchio's side, benchmarks/bench_timing.hpp), gcc -O3 -march=native -std=c99 for symdyn's C
and g++ -O3 -march=native -ffp-contract=off for Pinocchio (no FMA contraction on either side, as
-std=c99 implies it; built once and cached by benchmarks/harness.py).  Ratios are Pinocchio / symdyn (> 1: symdyn is faster):

- FK + J: symdyn's ``kinematics`` (pose and Jacobian in one call; the two single functions cost
  about twice as much, each computing the joints' sin/cos) against
  ``computeJointJacobians`` + ``framesForwardKinematics`` + ``getFrameJacobian`` (as the issue
  puts it) and against ``computeFrameJacobian`` (Pinocchio's leanest path to both results);
- FK: ``forward_kinematics`` against ``forwardKinematics`` + ``updateFramePlacement``;
- J-dot qd: ``jacobian_dot_qd`` against ``forwardKinematics(q, v, 0)`` +
  ``getFrameClassicalAcceleration``.
"""

import argparse
import os
import subprocess
import sys
import sysconfig
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import symdyn  # noqa: E402
from symdyn.check.pinocchio_model import PinocchioReference, UrdfReference  # noqa: E402
from symdyn.check.timing import time_generated  # noqa: E402
from symdyn.emit.cgen import generate_c  # noqa: E402

KINEMATICS = ("forward_kinematics", "jacobian", "jacobian_dot_qd")
TIMED = KINEMATICS + ("kinematics",)


def example_robot_data() -> str:
    """The robots folder of the example-robot-data wheel."""
    site = sysconfig.get_paths()["purelib"]
    return os.path.join(site, "cmeel.prefix", "share", "example-robot-data", "robots")


URDFS = [  # (label, path under example-robot-data, tip, tool, bundled DH robot of the same arm)
    ("ur5 (URDF)", "ur_description/urdf/ur5_robot.urdf", "tool0", None, "ur5"),
    ("panda (URDF)", "panda_description/urdf/panda.urdf", "panda_hand_tcp", None, "panda"),
]


def pinocchio_binary(workdir, flags=("-O3", "-march=native", "-ffp-contract=off")):
    import harness
    objects = [harness.pinocchio_object("pinocchio_kinematics_bench.cpp", "pinocchio-kinematics", flags)]
    return harness.link_pinocchio(objects, os.path.join(workdir, "pinkin"), flags)


def pinocchio_times(binary, model, frame, workdir, label, states):
    from symdyn.check.timing import parse
    path = os.path.join(workdir, f"{label.split()[0]}-{len(os.listdir(workdir))}.txt")
    model.saveToText(path)
    return parse(subprocess.run([binary, path, frame, str(states)], capture_output=True, text=True,
                                check=True).stdout)


def symdyn_times(robot, workdir):
    eqs = symdyn.derive(robot, outputs=list(KINEMATICS))
    folder = tempfile.mkdtemp(dir=workdir)
    return eqs, time_generated(generate_c(eqs, KINEMATICS), robot.name, robot.dof, TIMED, "double", folder)


def derivation_seconds(robot, repeats=3):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        symdyn.derive(robot)
        best = min(best, time.perf_counter() - start)
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="UR5 only, one derivation each, 200 states")
    args = parser.parse_args(argv)
    robots_dir = example_robot_data()
    rows, derivations = [], []
    states, repeats = (200, 1) if args.smoke else (10000, 3)
    with tempfile.TemporaryDirectory() as workdir:
        binary = pinocchio_binary(workdir)
        cases = []
        for label, relative, tip, tool, dh_name in URDFS[:1] if args.smoke else URDFS:
            path = os.path.join(robots_dir, relative)
            robot = symdyn.load(path, tip=tip, tool=tool)
            reference = UrdfReference(path, tip, tool)
            cases.append((label, robot, reference.model, tool or tip))
            dh = symdyn.load(os.path.join(HERE, "..", "robots", f"{dh_name}.yaml"))
            derivations.append((label, derivation_seconds(robot, repeats), dh_name, derivation_seconds(dh, repeats)))
        for dh_name in ("ur5",) if args.smoke else ("ur5", "panda", "puma560"):
            robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{dh_name}.yaml"))
            cases.append((f"{dh_name} (DH)", robot, PinocchioReference(robot).model, "tool"))
        for label, robot, model, frame in cases:
            _, mine = symdyn_times(robot, workdir)
            theirs = pinocchio_times(binary, model, frame, workdir, label, states)
            fk_j = mine["kinematics"]
            rows.append((label, fk_j, theirs["computeJointJacobians_framesForwardKinematics"],
                         theirs["computeFrameJacobian"], mine["forward_kinematics"], theirs["updateFramePlacement"],
                         mine["jacobian_dot_qd"], theirs["getFrameClassicalAcceleration"]))
    print("| robot | symdyn FK + J (ns) | Pinocchio jointJacobians + framesFK (ns) | ratio | "
          "Pinocchio computeFrameJacobian (ns) | ratio | symdyn FK (ns) | Pinocchio FK + frame (ns) | ratio | "
          "symdyn J-dot qd (ns) | Pinocchio classical acceleration (ns) | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for label, fk_j, pin_jj, pin_fj, fk, pin_fk, jd, pin_jd in rows:
        print(f"| {label} | {fk_j:.0f} | {pin_jj:.0f} | {pin_jj / fk_j:.1f}x | {pin_fj:.0f} | {pin_fj / fk_j:.1f}x | "
              f"{fk:.0f} | {pin_fk:.0f} | {pin_fk / fk:.1f}x | {jd:.0f} | {pin_jd:.0f} | {pin_jd / jd:.1f}x |")
    print()
    print("| URDF robot | derivation, all functions (s) | same arm from its DH table | DH (s) | URDF / DH |")
    print("|---|---:|---|---:|---:|")
    for label, urdf_s, dh_name, dh_s in derivations:
        print(f"| {label} | {urdf_s:.2f} | {dh_name}.yaml | {dh_s:.2f} | {urdf_s / dh_s:.2f} |")


if __name__ == "__main__":
    main()
