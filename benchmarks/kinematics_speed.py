"""Tool kinematics of symdyn's generated C against Pinocchio's C++, timed by
benchmarks/harness.py, from URDFs and from DH tables; and the derivation time of a URDF arm
against the same arm from its DH table.

Usage:  python benchmarks/kinematics_speed.py [--smoke] [harness options]
        (harness options: --processes, --passes, --states, --flags, --seed;
        --smoke: the UR5 URDF and the ur5 DH table only, one derivation each, the harness's tiny run)

Robots: the UR5 and Panda URDFs of the example-robot-data wheel (a test extra), read by symdyn
through a scene file that names the URDF and its tip link, and the bundled DH robots ur5, panda
and puma560.  Timing: the harness's method (distinct random states read by every side, thread
CPU time, interleaved passes, several processes from fresh copies of the binary, every side
compiled with the same flags), Pinocchio's model built from symdyn's reading of the same robot
(symdyn.check.pinocchio_model.build_model; ``symdyn verify`` and the test suite also check a
URDF against Pinocchio's own URDF parser, tests/model/test_urdf_robots.py).  Functions and
Pinocchio's counterparts (benchmarks/harness_pinocchio_kin.cpp):

- ``kinematics`` (pose and Jacobian in one call) against ``computeFrameJacobian``, which leaves
  the frame's placement in Data (Pinocchio's leanest path to both results);
- ``forward_kinematics`` against ``forwardKinematics`` + ``updateFramePlacement``;
- ``jacobian`` against ``computeFrameJacobian``;
- ``jacobian_dot_qd`` against ``forwardKinematics(q, v, 0)`` + ``getFrameClassicalAcceleration``.
"""

import argparse
import os
import sys
import sysconfig
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import harness  # noqa: E402

FUNCTIONS = ("forward_kinematics", "jacobian", "jacobian_dot_qd", "kinematics")


def example_robot_data() -> str:
    """The robots folder of the example-robot-data wheel."""
    site = sysconfig.get_paths()["purelib"]
    return os.path.join(site, "cmeel.prefix", "share", "example-robot-data", "robots")


URDFS = [  # (name, path under example-robot-data, tip, bundled DH robot of the same arm)
    ("ur5_urdf", "ur_description/urdf/ur5_robot.urdf", "tool0", "ur5"),
    ("panda_urdf", "panda_description/urdf/panda.urdf", "panda_hand_tcp", "panda"),
]


def scene_file(folder: str, name: str, urdf: str, tip: str) -> str:
    """A scene file naming the URDF and its tip link (the harness reads robot and scene files)."""
    path = os.path.join(folder, f"{name}.yaml")
    with open(path, "w") as handle:
        handle.write(f"scene: 1\nname: {name}\nrobot: {urdf}\ntip: {tip}\n")
    return path


def derivation_seconds(robot, repeats=3):
    """The best of ``repeats`` derivations of every default function (symdyn.derive: no cache)."""
    import symdyn
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        symdyn.derive(robot)
        best = min(best, time.perf_counter() - start)
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    harness.add_arguments(parser)
    args = parser.parse_args(argv)
    kwargs = harness.options(args)
    import symdyn
    robots_dir = example_robot_data()
    urdfs = URDFS[:1] if args.smoke else URDFS
    with tempfile.TemporaryDirectory() as folder:
        specs = [scene_file(folder, name, os.path.join(robots_dir, relative), tip) for name, relative, tip, _ in urdfs]
        specs += ["ur5"] if args.smoke else ["ur5", "panda", "puma560"]
        rows = harness.run(specs, FUNCTIONS, **kwargs)
        derivations = []
        for name, relative, tip, dh_name in urdfs:
            urdf = symdyn.load(os.path.join(robots_dir, relative), tip=tip)
            dh = symdyn.load(os.path.join(HERE, "..", "robots", f"{dh_name}.yaml"))
            repeats = 1 if args.smoke else 3
            derivations.append((name, derivation_seconds(urdf, repeats), dh_name, derivation_seconds(dh, repeats)))
    for flag_set in harness.flag_set_sections(kwargs):
        print(harness.markdown(rows, flag_set))
    print("\n| URDF robot | derivation, all functions (s) | same arm from its DH table | DH (s) | URDF / DH |")
    print("|---|---:|---|---:|---:|")
    for label, urdf_s, dh_name, dh_s in derivations:
        print(f"| {label} | {urdf_s:.2f} | {dh_name}.yaml | {dh_s:.2f} | {urdf_s / dh_s:.2f} |")


if __name__ == "__main__":
    main()
