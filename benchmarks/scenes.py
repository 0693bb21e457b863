"""What specialization buys: each scene of robots/scenes/ (and float versions) against the full
model's same functions, timed by benchmarks/harness.py, with operation counts.

Usage:  python benchmarks/scenes.py [--smoke] [harness options]
        (harness options: --processes, --passes, --states, --flags, --seed, --no-peer;
        --smoke: the float gravity scene and the float runtime-payload scene, the harness's
        tiny run)

Every case is one harness run (distinct random states read by every side, thread CPU time,
interleaved passes, several processes from fresh copies of the binary, the same gcc flags on
every side): symdyn's C of the scene (a scene's runtime parameters passed at the values in its
file), Pinocchio's model of the same reduced robot (with those values), and the Pinocchio ->
CasADi peer.  Float rows time symdyn's float C against Pinocchio and the peer in double.
Operation counts from the generated header.
"""

import argparse
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import harness  # noqa: E402

ROBOTS = os.path.join(HERE, "..", "robots")
FOUR = ["gravity", "inverse_dynamics", "mass_matrix", "forward_dynamics"]
CASES = [  # (label, scene or robot file under robots/, functions, precision)
    ("puma560 full", "puma560.yaml", FOUR, "double"),
    ("puma560 gravity only, float (scene)", "scenes/puma560_gravity.yaml", ["gravity"], "float"),
    ("puma560 wrist locked (scene, 3 joints)", "scenes/puma560_wrist_locked.yaml", FOUR, "double"),
    ("puma560 wrist locked, float", "scenes/puma560_wrist_locked.yaml", FOUR, "float"),
    ("ur5 full", "ur5.yaml", FOUR, "double"),
    ("ur5 runtime payload (scene)", "scenes/ur5_payload.yaml", FOUR, "double"),
    ("ur5 runtime payload, float", "scenes/ur5_payload.yaml", FOUR, "float"),
]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    harness.add_arguments(parser)
    args = parser.parse_args(argv)
    kwargs = harness.options(args)
    results = []
    for label, file, functions, precision in [CASES[1], CASES[-1]] if args.smoke else CASES:
        rows = harness.run([os.path.join(ROBOTS, file)], functions, generate_options={"precision": precision},
                           **kwargs)
        results.append((label, precision, rows))
    for flag_set in harness.flag_set_sections(kwargs):
        print("| model | function | precision | symdyn ns | Pinocchio ns | Pinocchio / symdyn | peer / symdyn | "
              "mul | add | div | sin/cos |")
        print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
        for label, precision, rows in results:
            for row in (r for r in rows if r.flag_set == flag_set):
                ops = row.case.costs()[row.function]
                pinocchio, peer = row.side("pinocchio"), row.side("peer")
                print(f"| {label} | {row.function} | {precision} | {harness.summary(row.times['symdyn'])} | "
                      f"{statistics.median(pinocchio[1]):.0f} | {harness.summary(row.ratio('pinocchio'), 1)} | "
                      f"{harness.summary(row.ratio('peer'), 2) if peer else '-'} | {ops['mul']} | {ops['add']} | "
                      f"{ops['div']} | {ops['trig']} |")


if __name__ == "__main__":
    main()
