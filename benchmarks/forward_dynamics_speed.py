"""Forward dynamics against Pinocchio's C++ ``aba``, in the same run: LDL^T and the
articulated-body algorithm, double and float.

Usage:  python benchmarks/forward_dynamics_speed.py [ROBOT ...]   (default: puma560 ur5 iiwa14 panda)

For each robot generates ``forward_dynamics`` four ways (``--fd-method ldlt|aba`` x
``--precision double|float``), times each with the harness of :mod:`symdyn.check.timing`
(-O3 -march=native, ns per call, median of 7 repeats of 20000 calls cycling over 10,000
distinct random states), times Pinocchio's ``aba`` on the same model (benchmarks/pinocchio_bench.cpp,
also cycling over 10,000 states) and prints a Markdown table with the ratio Pinocchio / symdyn
(> 1: symdyn is faster) and each variant's operation count. ``panda`` has full (non-diagonal)
inertia tensors, as identified by Gaz et al. 2019.
"""

import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, ".."))

import symdyn  # noqa: E402
from c_speed import pinocchio_bench_binary  # noqa: E402
from symdyn.check.pinocchio_model import build_model  # noqa: E402
from symdyn.check.timing import parse, time_generated  # noqa: E402
from symdyn.emit.cgen import build_function, generate_c  # noqa: E402

VARIANTS = (("ldlt", "double"), ("aba", "double"), ("ldlt", "float"), ("aba", "float"))


def main(argv=None):
    names = (argv if argv is not None else sys.argv[1:]) or ["puma560", "ur5", "iiwa14", "panda"]
    with tempfile.TemporaryDirectory() as workdir:
        print("building Pinocchio benchmark (C++, takes a minute)...", file=sys.stderr)
        pinbench = pinocchio_bench_binary(workdir)
        header = " | ".join(f"{m} {p} (ns, ratio)" for m, p in VARIANTS)
        print(f"| robot | Pinocchio aba (ns) | {header} | operations {' / '.join(f'{m} {p}' for m, p in VARIANTS[:2])} |")
        print("|---|---:|" + "---:|" * len(VARIANTS) + "---|")
        for name in names:
            robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{name}.yaml"))
            model, _ = build_model(robot)
            model_file = os.path.join(workdir, f"{name}.txt")
            model.saveToText(model_file)
            theirs = parse(subprocess.run([pinbench, model_file], capture_output=True, text=True, check=True).stdout)["aba"]
            cells, ops = [], []
            for fd_method in ("ldlt", "aba"):
                eqs = symdyn.derive(robot, outputs=["forward_dynamics"], fd_method=fd_method)
                for method, precision in VARIANTS:
                    if method != fd_method:
                        continue
                    folder = os.path.join(workdir, f"{name}-{method}-{precision}")
                    os.makedirs(folder)
                    files = generate_c(eqs, ["forward_dynamics"], precision)
                    mine = time_generated(files, name, robot.dof, ["forward_dynamics"], precision, folder)["forward_dynamics"]
                    cells.append((VARIANTS.index((method, precision)), f"{mine:.0f} ({theirs / mine:.1f}x)"))
                    if precision == "double":
                        o = build_function(eqs, "forward_dynamics", "double", name).ops
                        ops.append((fd_method, f"{o['mul']}/{o['add']}/{o['div']}"))
            row = " | ".join(text for _, text in sorted(cells))
            print(f"| {name} | {theirs:.0f} | {row} | {' ; '.join(f'{m} {t}' for m, t in ops)} |", flush=True)


if __name__ == "__main__":
    main()
