"""Time a platform robot's generated inverse and forward dynamics against Pinocchio's C++
closed-loop computation, in the same run, with the method of benchmarks/harness.py (issue:
parallel platforms).

Usage:  python benchmarks/parallel_speed.py [PLATFORM ...] [--keep DIR] [harness options]
        (default: flight_simulator; harness options: --processes 5, --passes 15, --states 10000,
        --flags O2,O3native, --seed, --smoke: 20 states, 1 process, 2 passes, -O2)

For each platform (robots/parallel/NAME.yaml): generates double-precision C, builds Pinocchio's
closed-loop model (symdyn.check.pinocchio_model.build_closed_loop_model: a free-flying platform,
six leg chains, a 6D loop closure per leg; for forward dynamics with a 1e-9 armature on the legs'
joints, which Pinocchio's constraint solvers need, and which moves the accelerations by about
1e-9 of themselves: the accuracy column shows it), draws N distinct random platform states about
the home pose, and gets each leg's joint positions, rates and accelerations from Pinocchio's
closed-loop model (symdyn.check.closed_loop, the reference of symdyn verify and bench:
Pinocchio's side is handed them, it has no inverse kinematics of closed loops).
benchmarks/pinocchio_platform_bench.cpp (g++ against the pin wheel's Pinocchio) linked with the
generated C (gcc -std=c99), every side with the same flags of one flag set, times

- inverse dynamics: symdyn's NAME_inverse_dynamics(pose, twist, twist_rate) against Pinocchio's
  rnea + computeJointJacobians + getConstraintsJacobian + a block solve of [Jc^T S] (one 6 x 6 LU
  per leg, then one for the platform);
- forward dynamics: symdyn's NAME_forward_dynamics(pose, twist, phi) against Pinocchio's
  constraintDynamics (proximal accuracy 1e-12, mu 1e-12, 10 iterations) and lcaba
  (loop-constrained ABA; accuracy 1e-12, mu 1e-6, up to 50 iterations);

ns per call: thread CPU time of passes over every state, the sides of one function taking turns
pass after pass; per process the median pass; several processes, each from a fresh copy of the
binary; reported the median over processes (min-max) and the ratio Pinocchio / symdyn per
process.  The first process of each flag set also writes every state's results: the largest
normalized differences are the last column.
"""

import argparse
import multiprocessing
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

sys.path.insert(0, HERE)
import harness  # noqa: E402

#: platform -> (home height of P (m), range of positions (m) and angles (rad) about the home pose)
PLATFORMS = {"flight_simulator": (2.0, 0.2, 0.17), "sru_platform": (0.55, 0.03, 0.08)}
ARMATURE = 1e-9


def _robot(name):
    from symdyn.model import parallel
    return parallel.load(os.path.join(HERE, "..", "robots", "parallel", f"{name}.yaml"))


def _leg_chunk(args):
    """Pinocchio's q, v, a for a chunk of platform states (worker process): the legs solved on
    Pinocchio's closed-loop model (symdyn.check.closed_loop, as symdyn verify and bench do), each
    state's from the previous one's."""
    from symdyn.check.closed_loop import ClosedLoopReference, pose_vector
    name, chunk = args
    ref = ClosedLoopReference(_robot(name))
    out = []
    guess = None
    for p, R, twist, rate in chunk:
        pose = pose_vector(p, R)
        guess = ref.kinematics(pose, guess).q
        q, v, a = ref.tree_state(pose, twist, rate)
        out.append(np.concatenate([pose, twist, rate, q, v, a]))
    return out


def _states(name, count, seed=2026):
    from symdyn.check.closed_loop import platform_states
    height, reach, tilt = PLATFORMS[name]
    return list(platform_states(np.array([0.0, 0.0, height]), reach, tilt, count, seed))


def run(name, kwargs, workdir):
    """Generate, sample, build per flag set and time ``kwargs['processes']`` processes:
    ({flag set: {(function, side): [ns, one per process]}}, {flag set: errors}, generated files)."""
    from symdyn.check.cbuild import build_platform
    from symdyn.check.pinocchio_model import build_closed_loop_model
    from symdyn.derive.parallel import derive_parallel
    from symdyn.emit.parallel_c import generate_parallel_c
    count, processes, passes, flag_sets = kwargs["states"], kwargs["processes"], kwargs["passes"], kwargs["flag_sets"]
    robot = _robot(name)
    eqs = derive_parallel(robot, ["inverse_dynamics", "forward_dynamics"])
    files = generate_parallel_c(eqs)
    lib = build_platform(files, name, workdir=workdir)
    model, constraints, info = build_closed_loop_model(robot, ARMATURE)
    model.saveToText(os.path.join(workdir, "model.txt"))
    build_closed_loop_model(robot, 0.0)[0].saveToText(os.path.join(workdir, "model_no_armature.txt"))
    with open(os.path.join(workdir, "closures.txt"), "w") as handle:
        handle.write(f"{len(constraints)}\n")
        for cm in constraints:
            numbers = [cm.joint1_id, cm.joint2_id]
            for placement in (cm.joint1_placement, cm.joint2_placement):
                numbers += list(placement.rotation.ravel()) + list(placement.translation)
            handle.write(" ".join(repr(float(x)) if isinstance(x, float) else str(x) for x in numbers) + "\n")
        handle.write(" ".join(str(leg["actuated_v"]) for leg in info["legs"]) + "\n")
    print(f"{name}: leg states of {count} platform states (Pinocchio's closed loop)...", file=sys.stderr)
    sampled = _states(name, count, kwargs["seed"])
    chunks = [(name, sampled[k::2]) for k in range(2)]
    with multiprocessing.Pool(2) as pool:
        parts = pool.map(_leg_chunk, chunks)
    rows = [None] * count
    for k, part in enumerate(parts):
        rows[k::2] = part
    records = []
    for row in rows:
        status, phi = lib.inverse_dynamics(row[:7], row[7:13], row[13:19])
        assert status == 0
        phi = phi * 1.1  # forward dynamics under forces that are not those of the sampled motion
        records.append(np.concatenate([row[:19], phi, row[19:]]))
    np.asarray(records, dtype=np.float64).tofile(os.path.join(workdir, "states.bin"))
    arguments = [os.path.join(workdir, "model.txt"), os.path.join(workdir, "closures.txt"),
                 os.path.join(workdir, "states.bin")]
    times, errors = {}, {}
    for flag_set in flag_sets:  # every side built with the same flags
        flags = harness.FLAG_SETS[flag_set]
        subprocess.run(["gcc", "-std=c99", *flags, "-c", os.path.join(workdir, f"{name}_dynamics.c"),
                        "-o", os.path.join(workdir, f"{name}-{flag_set}.o")], check=True)
        bench = harness.pinocchio_object("pinocchio_platform_bench.cpp", "pinocchio-platform", flags)
        exe = harness.link_pinocchio(
            [bench, os.path.join(workdir, f"{name}-{flag_set}.o")], os.path.join(workdir, f"bench_{name}_{flag_set}"),
            flags, [f"-Wl,--defsym,platform_inverse_dynamics={name}_inverse_dynamics",
                    f"-Wl,--defsym,platform_forward_dynamics={name}_forward_dynamics"])
        runs = []
        for index in range(processes):
            print(f"process {index + 1}/{processes}: {name} {flag_set}", file=sys.stderr, flush=True)
            results_file = os.path.join(workdir, "results.bin") if index == 0 else "-"
            runs.append(harness.run_copy(exe, [*arguments, results_file, os.path.join(workdir, "model_no_armature.txt"),
                                               str(passes)], workdir, index))
            if index == 0:
                errors[flag_set] = accuracy(robot, model.nv, records, os.path.join(workdir, "results.bin"))
        times[flag_set] = {key: [statistics.median(r["time"][key]) for r in runs] for key in runs[0]["time"]}
    return times, errors, files


def accuracy(robot, nv: int, records, path: str) -> dict:
    """The largest normalized differences between symdyn's results and Pinocchio's over every
    state (the timing program's results file): phi (inverse dynamics) and the platform's twist rate
    against constraintDynamics and lcaba; stops when a generated function returned nonzero."""
    import pinocchio as pin

    from symdyn.check.pinocchio_model import free_flyer_twist_rate
    width = 6 + 2 * nv + 6 + 12 + 2
    results = np.fromfile(path).reshape(len(records), width)
    errors = {"inverse": 0.0, "constraintDynamics": 0.0, "lcaba": 0.0}
    com = np.array([float(c) for c in robot.platform.com])
    for row, res in zip(records, results):
        pin_phi, pin_a, lc_a = res[:6], res[6:6 + nv], res[6 + nv:6 + 2 * nv]
        ours_phi, ours_rate = res[6 + 2 * nv:12 + 2 * nv], res[12 + 2 * nv:18 + 2 * nv]
        if res[-2] != 0 or res[-1] != 0:
            raise SystemExit(f"{robot.name}: a generated function returned {res[-2]:.0f}, {res[-1]:.0f} "
                             "at a sampled state")
        errors["inverse"] = max(errors["inverse"], np.abs(ours_phi - pin_phi).max() / np.abs(pin_phi).max())
        R = pin.Quaternion(row[3:7]).toRotationMatrix()
        for key, acc in (("constraintDynamics", pin_a), ("lcaba", lc_a)):
            theirs = free_flyer_twist_rate(R, com, row[7:13], acc)
            errors[key] = max(errors[key], np.abs(ours_rate - theirs).max() / (1 + np.abs(theirs).max()))
    return errors


#: (function, Pinocchio's side, the row's label)
ROWS = [("inverse_dynamics", "pinocchio", "inverse dynamics (rnea + Jc + block solve)", "inverse"),
        ("forward_dynamics", "pinocchio_constraintDynamics", "forward dynamics (constraintDynamics)",
         "constraintDynamics"),
        ("forward_dynamics", "pinocchio_lcaba", "forward dynamics (lcaba)", "lcaba")]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("platforms", nargs="*", default=["flight_simulator"])
    parser.add_argument("--keep", help="build and run in this directory and keep it (debugging)")
    harness.add_arguments(parser, peer=False)
    args = parser.parse_args(argv)
    kwargs = harness.options(args)
    if args.smoke and args.states is None:
        kwargs["states"] = 20
    results = {}
    for name in args.platforms:
        if args.keep:
            os.makedirs(args.keep, exist_ok=True)
            results[name] = run(name, kwargs, args.keep)
        else:
            with tempfile.TemporaryDirectory() as workdir:
                results[name] = run(name, kwargs, workdir)
    for flag_set in harness.flag_set_sections(kwargs):
        print("| platform | function | symdyn ns | Pinocchio ns | Pinocchio / symdyn | max difference (normalized) |")
        print("|---|---|---:|---:|---:|---:|")
        for name, (times, errors, _) in results.items():
            for function, side, label, error in ROWS:
                ours, theirs = times[flag_set][function, "symdyn"], times[flag_set][function, side]
                print(f"| {name} | {label} | {harness.summary(ours)} | {harness.summary(theirs)} | "
                      f"{harness.summary([t / o for t, o in zip(theirs, ours)], 1)} | {errors[flag_set][error]:.1e} |")
    for name, (_, _, files) in results.items():
        header = files[f"{name}_dynamics.h"]
        costs = [line.strip(" *") for line in header.splitlines() if line.startswith(" * Cost:")]
        print(f"\n{name}: operation counts (header): inverse dynamics {costs[0]}; forward dynamics {costs[1]}")


if __name__ == "__main__":
    main()
