"""Time a platform robot's generated inverse and forward dynamics against Pinocchio's C++
closed-loop computation, in the same run (issue: parallel platforms).

Usage:  python benchmarks/parallel_speed.py [PLATFORM ...] [--states N] [--symdyn-flags "-O2"] [--smoke]
        (default: flight_simulator, 10000 states, the generated C at -O3 -march=native; --smoke:
        20 states)

For each platform (robots/parallel/NAME.yaml): generates double-precision C, builds Pinocchio's
closed-loop model (symdyn.check.pinocchio_model.build_closed_loop_model: a free-flying platform,
six leg chains, a 6D loop closure per leg; for forward dynamics with a 1e-9 armature on the legs'
joints, which Pinocchio's constraint solvers need, and which moves the accelerations by about
1e-9 of themselves: the accuracy column shows it), draws N distinct random platform states about the home pose, and gets
each leg's joint positions, rates and accelerations from Pinocchio's closed-loop model
(symdyn.check.closed_loop, the reference of symdyn verify and bench: Pinocchio's side is handed
them, it has no inverse kinematics of closed loops).  benchmarks/pinocchio_platform_bench.cpp, compiled with g++ -O3 -march=native against the
pin wheel's Pinocchio (-ffp-contract=off, as -std=c99 implies for the C; once, cached by
benchmarks/harness.py) and linked with the generated C (gcc, same flags), times

- inverse dynamics: symdyn's NAME_inverse_dynamics(pose, twist, twist_rate) against Pinocchio's
  rnea + computeJointJacobians + getConstraintsJacobian + LU solve of [Jc^T S] (42 x 42);
- forward dynamics: symdyn's NAME_forward_dynamics(pose, twist, phi) against Pinocchio's
  constraintDynamics (proximal accuracy 1e-12, mu 1e-12, 10 iterations) and lcaba
  (loop-constrained ABA; accuracy 1e-12, mu 1e-6, up to 50 iterations);

ns per call (thread CPU time), median of 7 repeats of 20000 calls (2 N when fewer) cycling over
the states, and checks every state's results against each other.  Prints a Markdown table (ratio = Pinocchio's time / symdyn's).
"""

import multiprocessing
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

sys.path.insert(0, HERE)
import harness  # noqa: E402
from symdyn.check.timing import parse  # noqa: E402

#: platform -> (home height of P (m), range of positions (m) and angles (rad) about the home pose)
PLATFORMS = {"flight_simulator": (2.0, 0.2, 0.17), "sru_platform": (0.55, 0.03, 0.08)}
ARMATURE = 1e-9
#: gcc flags of the generated C (--symdyn-flags "-O2" for a baseline x86-64 build); Pinocchio's
#: side is always built with g++ -O3 -march=native -ffp-contract=off
SYMDYN_FLAGS = ["-O3", "-march=native"]


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


def run(name, count, workdir):
    import pinocchio as pin

    from symdyn.check.cbuild import build_platform
    from symdyn.check.pinocchio_model import build_closed_loop_model, free_flyer_twist_rate
    from symdyn.derive.parallel import derive_parallel
    from symdyn.emit.parallel_c import generate_parallel_c
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
    sampled = _states(name, count)
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

    subprocess.run(["gcc", "-std=c99", *SYMDYN_FLAGS, "-c", os.path.join(workdir, f"{name}_dynamics.c"),
                    "-o", os.path.join(workdir, f"{name}.o")], check=True)
    flags = ("-O3", "-march=native", "-ffp-contract=off")  # as gcc -std=c99 on the generated C
    bench = harness.pinocchio_object("pinocchio_platform_bench.cpp", "pinocchio-platform", flags)
    exe = harness.link_pinocchio([bench, os.path.join(workdir, f"{name}.o")], os.path.join(workdir, f"bench_{name}"),
                                 flags, [f"-Wl,--defsym,platform_inverse_dynamics={name}_inverse_dynamics",
                                         f"-Wl,--defsym,platform_forward_dynamics={name}_forward_dynamics"])
    output = subprocess.run([exe, os.path.join(workdir, "model.txt"), os.path.join(workdir, "closures.txt"),
                             os.path.join(workdir, "states.bin"), os.path.join(workdir, "results.bin"),
                             os.path.join(workdir, "model_no_armature.txt"), str(min(20000, 2 * count))],
                            capture_output=True, text=True, check=True).stdout
    times = parse(output)
    nv = model.nv
    width = 6 + 2 * nv + 6 + 12 + 2
    results = np.fromfile(os.path.join(workdir, "results.bin")).reshape(count, width)
    errors = {"inverse": 0.0, "constraintDynamics": 0.0, "lcaba": 0.0}
    for row, res in zip(records, results):
        pin_phi, pin_a, lc_a = res[:6], res[6:6 + nv], res[6 + nv:6 + 2 * nv]
        ours_phi, ours_rate = res[6 + 2 * nv:12 + 2 * nv], res[12 + 2 * nv:18 + 2 * nv]
        assert res[-2] == 0 and res[-1] == 0
        errors["inverse"] = max(errors["inverse"], np.abs(ours_phi - pin_phi).max() / np.abs(pin_phi).max())
        R = pin.Quaternion(row[3:7]).toRotationMatrix()
        com = np.array([float(c) for c in robot.platform.com])
        for key, acc in (("constraintDynamics", pin_a), ("lcaba", lc_a)):
            theirs = free_flyer_twist_rate(R, com, row[7:13], acc)
            errors[key] = max(errors[key], np.abs(ours_rate - theirs).max() / (1 + np.abs(theirs).max()))
    return times, errors, files


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    count = 10000
    if "--smoke" in argv:
        argv.remove("--smoke")
        count = 20
    if "--states" in argv:
        k = argv.index("--states")
        count = int(argv[k + 1])
        del argv[k:k + 2]
    keep = None
    if "--keep" in argv:  # keep the build and data in this directory (debugging)
        k = argv.index("--keep")
        keep = argv[k + 1]
        del argv[k:k + 2]
    if "--symdyn-flags" in argv:
        k = argv.index("--symdyn-flags")
        SYMDYN_FLAGS[:] = argv[k + 1].split()
        del argv[k:k + 2]
    names = argv or ["flight_simulator"]
    print("| platform | function | symdyn (ns) | Pinocchio (ns) | ratio | max difference (normalized) |")
    print("|---|---|---|---|---|---|")
    for name in names:
        if keep:
            os.makedirs(keep, exist_ok=True)
            times, errors, files = run(name, count, keep)
        else:
            with tempfile.TemporaryDirectory() as workdir:
                times, errors, files = run(name, count, workdir)
        ours_id, theirs_id = times["symdyn_inverse_dynamics"], times["pinocchio_inverse_dynamics"]
        ours_fd = times["symdyn_forward_dynamics"]
        print(f"| {name} | inverse dynamics (rnea + Jc + block solve) | {ours_id:.0f} | {theirs_id:.0f} | "
              f"{theirs_id / ours_id:.1f}x | {errors['inverse']:.1e} |")
        for key in ("constraintDynamics", "lcaba"):
            theirs = times[f"pinocchio_{key}"]
            print(f"| {name} | forward dynamics ({key}) | {ours_fd:.0f} | {theirs:.0f} | {theirs / ours_fd:.1f}x | "
                  f"{errors[key]:.1e} |")
        header = files[f"{name}_dynamics.h"]
        costs = [line.strip(" *") for line in header.splitlines() if line.startswith(" * Cost:")]
        print(f"\n{name}: op counts (header): inverse dynamics {costs[0]}; forward dynamics {costs[1]}", file=sys.stderr)
    print(f"\n({count} distinct states; symdyn: gcc {' '.join(SYMDYN_FLAGS)}; Pinocchio {__import__('pinocchio').__version__}: "
          "g++ -O3 -march=native -ffp-contract=off)")


if __name__ == "__main__":
    main()
