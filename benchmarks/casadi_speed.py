"""symdyn's CasADi functions beside symdyn's own C, timed by benchmarks/harness.py.

Usage:  python benchmarks/casadi_speed.py [ROBOT ...] [--functions LIST] [--no-vm] [harness options]
        (default: puma560 ur5 iiwa14, the six dynamics functions and the tool kinematics;
        harness options: --processes, --passes, --states, --flags, --seed, --smoke, --no-peer)

For each robot and function, with the harness's method (distinct random states read by every
side, thread CPU time, interleaved passes, several processes from fresh copies of the binary,
the same gcc flags on every side), ns per call of:

- symdyn C: the generated NAME_dynamics.c;
- CasADi C: CasADi's own generated C of symdyn's ``casadi.Function`` of the same output
  (``symdyn generate --target casadi-c``), called with its arg/res/work-vector convention;
- the Pinocchio -> CasADi peer and Pinocchio itself where Pinocchio has the function (a function
  it lacks, e.g. ``inverse_dynamics_dq``, is timed on symdyn's two sides only);

and, outside the harness (Python), the same ``casadi.Function`` evaluated by CasADi's SX
virtual machine (one call of ``f.map(M, "serial")`` over M = 20000 states, divided by M, so
Python's per-call overhead is not counted; median of 7) and one plain ``f(q, qd, qdd)`` call from
numpy, which is what a Python user sees.  Ratios > 1: symdyn's C is faster.
"""

import argparse
import os
import statistics
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)

import harness  # noqa: E402

FUNCTIONS = ("inverse_dynamics", "mass_matrix", "gravity", "coriolis", "coriolis_matrix", "forward_dynamics",
             "forward_kinematics", "jacobian", "jacobian_dot_qd")


def vm_time(function, dof, states=20000, repeats=7):
    """ns per evaluation by CasADi's SX virtual machine (serial map, one Python call)."""
    mapped = function.map(states, "serial")
    rng = np.random.default_rng(1)
    args = [rng.uniform(-1, 1, (function.size1_in(k), states)) for k in range(function.n_in())]
    runs = []
    for _ in range(repeats):
        start = time.perf_counter()
        mapped(*args)
        runs.append((time.perf_counter() - start) / states * 1e9)
    return statistics.median(runs)


def python_call_time(function, calls=2000):
    """ns of one plain call of ``function`` from numpy arrays (median of 5 runs)."""
    args = [np.linspace(-1, 1, function.size1_in(k)) for k in range(function.n_in())]
    runs = []
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(calls):
            function(*args)
        runs.append((time.perf_counter() - start) / calls * 1e9)
    return statistics.median(runs)


def python_times(robot_name: str, functions, smoke: bool) -> dict:
    """{function: (SX VM ns, Python call ns)} of symdyn's casadi.Function of each output."""
    import symdyn
    from symdyn.emit.casadi_backend import casadi_function
    with tempfile.TemporaryDirectory() as folder:
        robot = symdyn.load(harness.robot_file(robot_name, folder))
    eqs = symdyn.derive(robot, outputs=functions)
    found = {}
    for name in functions:
        function = casadi_function(eqs, name)
        found[name] = (vm_time(function, robot.dof, 200 if smoke else 20000, 1 if smoke else 7),
                       python_call_time(function, 20 if smoke else 2000))
    return found


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="*", default=["puma560", "ur5", "iiwa14"])
    parser.add_argument("--functions", default=",".join(FUNCTIONS),
                        help="comma-separated outputs of symdyn, one casadi.Function each (default: the dynamics "
                             "and the tool kinematics), e.g. the single derivatives inverse_dynamics_dq,"
                             "inverse_dynamics_dqd,forward_dynamics_dq,forward_dynamics_dqd,mass_matrix_inverse,"
                             "gravity_derivative")
    parser.add_argument("--no-vm", action="store_true", help="leave out the SX virtual machine and Python columns")
    harness.add_arguments(parser)
    args = parser.parse_args(argv)
    kwargs = harness.options(args)
    functions = [f.strip() for f in args.functions.split(",") if f.strip()]
    rows = harness.run(args.robots, functions, sides=("casadi",), **kwargs)
    python = {} if args.no_vm else {name: python_times(name, functions, args.smoke) for name in args.robots}
    cases = list({id(r.case): r.case for r in rows}.values())  # in the order of the robots asked
    spec_of = {id(case): spec for case, spec in zip(cases, args.robots)}
    for flag_set in harness.flag_set_sections(kwargs):
        print("| robot | function | symdyn C ns | CasADi C ns | CasADi C / symdyn C | peer ns | peer / symdyn C | "
              "Pinocchio / symdyn C | SX VM ns | SX VM / symdyn C | Python call of f (us) |")
        print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for row in (r for r in rows if r.flag_set == flag_set):
            casadi_side, peer = row.side("casadi"), row.side("peer")
            mine = statistics.median(row.times["symdyn"])
            vm, call = python[spec_of[id(row.case)]][row.function] if python else (None, None)
            print(f"| {row.case.label} | {row.function} | {harness.summary(row.times['symdyn'])} | "
                  f"{harness.summary(casadi_side[1])} | {harness.summary(row.ratio('casadi'), 2)} | "
                  f"{harness.summary(peer[1]) if peer else '-'} | "
                  f"{harness.summary(row.ratio('peer'), 2) if peer else '-'} | "
                  f"{harness.summary(row.ratio('pinocchio'), 2) if row.side('pinocchio') else '-'} | "
                  f"{f'{vm:.0f}' if vm else '-'} | {f'{vm / mine:.1f}x' if vm else '-'} | "
                  f"{f'{call / 1000:.1f}' if call else '-'} |", flush=True)


if __name__ == "__main__":
    main()
