"""Time symdyn's generated C against Pinocchio's own C++ in the same run.

Usage:  python benchmarks/c_speed.py [ROBOT ...]      (default: puma560 ur5 iiwa14)

For each robot: generates double-precision C, compiles it three ways (gcc -O3 -march=native, the
flags Pinocchio is built with here; gcc -O2 for baseline x86-64; clang -O3 -march=native when
clang is installed) together with a timing loop (ns per call, median of 7 repeats of 20000 calls cycling over 10,000 distinct random states), builds
benchmarks/pinocchio_bench.cpp against the headers and libraries that the pin wheel ships (Eigen
from the casadi wheel), saves the equivalent Pinocchio model as text and times rnea, crba,
computeGeneralizedGravity, computeCoriolisMatrix and aba.  Prints a Markdown table with the
ratios (Pinocchio time / symdyn time, > 1 means symdyn is faster) and the operation counts.
The -O2 ratio compares symdyn's baseline build with Pinocchio's -O3 -march=native one; Pinocchio
is also built at -O2 for the like-for-like -O2 ratio.
"""

import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

import symdyn  # noqa: E402
from symdyn.check.timing import PRELUDE, parse  # noqa: E402
from symdyn.emit.cgen import generate_c  # noqa: E402
from symdyn.check.pinocchio_model import build_model  # noqa: E402

PAIRS = [("inverse_dynamics", "rnea"), ("mass_matrix", "crba"), ("gravity", "computeGeneralizedGravity"),
         ("coriolis", "nonLinearEffects"), ("coriolis_matrix", "computeCoriolisMatrix"), ("forward_dynamics", "aba")]

HARNESS = PRELUDE.replace("%(includes)s", '#include "%(n)s_dynamics.h"') + r"""
    TIME("inverse_dynamics", %(n)s_inverse_dynamics(q[k], qd[k], qdd[k], out));
    TIME("mass_matrix", %(n)s_mass_matrix(q[k], out));
    TIME("gravity", %(n)s_gravity(q[k], out));
    TIME("coriolis", %(n)s_coriolis(q[k], qd[k], out));
    TIME("coriolis_matrix", %(n)s_coriolis_matrix(q[k], qd[k], out));
    TIME("forward_dynamics", %(n)s_forward_dynamics(q[k], qd[k], qdd[k], out));
    return 0;
}
"""


def pinocchio_bench_binary(workdir, source="pinocchio_bench.cpp", name="pinbench", flags=("-O3", "-march=native")):
    """Compile a C++ timing program against the Pinocchio that the pin wheel ships.  The wheel's
    headers do not enable Pinocchio's explicit template instantiation, so the algorithms timed
    are compiled here, with ``flags``."""
    site = sysconfig.get_paths()["purelib"]
    prefix = os.path.join(site, "cmeel.prefix")
    eigen = os.path.join(site, "casadi", "include", "eigen3")
    exe = os.path.join(workdir, name)
    cmd = ["g++", *flags, "-w", "-DNDEBUG", "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS", "-DBOOST_MPL_LIMIT_LIST_SIZE=30",
           "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30", "-DBOOST_FUSION_INVOKE_MAX_ARITY=12",
           "-DBOOST_FUSION_INVOKE_FUNCTION_OBJECT_MAX_ARITY=12", "-DBOOST_FUSION_INVOKE_PROCEDURE_MAX_ARITY=12", "-std=c++17", os.path.join(HERE, source),
           f"-I{prefix}/include", f"-I{eigen}", f"-L{prefix}/lib", "-lpinocchio_default", "-lboost_serialization",
           f"-Wl,-rpath,{prefix}/lib", "-o", exe]
    subprocess.run(cmd, check=True)
    return exe



def main(argv=None):
    names = (argv if argv is not None else sys.argv[1:]) or ["puma560", "ur5", "iiwa14"]
    with tempfile.TemporaryDirectory() as workdir:
        print("building Pinocchio benchmark (C++, takes a minute)...", file=sys.stderr)
        pinbench = pinocchio_bench_binary(workdir)
        pinbench_o2 = pinocchio_bench_binary(workdir, name="pinbench_o2", flags=("-O2",))
        compilers = [("gcc -O3 native", ["gcc", "-O3", "-march=native"]), ("gcc -O2", ["gcc", "-O2"])]
        if shutil.which("clang"):
            compilers.append(("clang -O3 native", ["clang", "-O3", "-march=native"]))
        print("| robot | function | Pinocchio C++ -O3 native (ns) | Pinocchio C++ -O2 (ns) | "
              + " | ".join(f"{label} (ns)" for label, _ in compilers)
              + " | " + " | ".join(f"Pinocchio -O3 native / {label}" for label, _ in compilers)
              + " | Pinocchio -O2 / gcc -O2 | mul | add | div | sin/cos |")
        print("|---|---|" + "---:|" * (3 + 2 * len(compilers) + 4))
        for name in names:
            robot = symdyn.load(os.path.join(HERE, "..", "robots", f"{name}.yaml"))
            eqs = symdyn.derive(robot)
            from symdyn.emit.cgen import build_function
            files = generate_c(eqs)
            for fname, text in files.items():
                open(os.path.join(workdir, fname), "w").write(text)
            open(os.path.join(workdir, "bench.c"), "w").write(HARNESS % {"n": name, "dof": robot.dof})
            mine = []
            for k, (_, command) in enumerate(compilers):
                exe = os.path.join(workdir, f"bench_{name}_{k}")
                subprocess.run([*command, "-std=c99", os.path.join(workdir, "bench.c"),
                                os.path.join(workdir, f"{name}_dynamics.c"), "-o", exe, "-lm"], check=True)
                mine.append(parse(subprocess.run([exe], capture_output=True, text=True, check=True).stdout))
            model, _ = build_model(robot)
            model_file = os.path.join(workdir, f"{name}.txt")
            model.saveToText(model_file)
            theirs = parse(subprocess.run([pinbench, model_file], capture_output=True, text=True, check=True).stdout)
            theirs_o2 = parse(subprocess.run([pinbench_o2, model_file], capture_output=True, text=True,
                                             check=True).stdout)
            for ours, pin_name in PAIRS:
                ops = build_function(eqs, ours, "double", name).ops
                times = " | ".join(f"{m[ours]:.0f}" for m in mine)
                ratios = " | ".join(f"{theirs[pin_name] / m[ours]:.1f}x" for m in mine)
                equal_o2 = f"{theirs_o2[pin_name] / mine[1][ours]:.1f}x"
                print(f"| {name} | {ours} | {theirs[pin_name]:.0f} ({pin_name}) | {theirs_o2[pin_name]:.0f} | {times} | "
                      f"{ratios} | {equal_o2} | {ops['mul']} | {ops['add']} | {ops['div']} | {ops['trig']} |", flush=True)

if __name__ == "__main__":
    main()
