"""Code size and stack use of the float C on a Cortex-M4 (single-precision FPU).

Usage:  python benchmarks/firmware_size.py [ROBOT ...]   (default: puma560 ur5 iiwa14 chain12 pendulum_leg)

Generates ``--precision float`` C for each robot (every function; forward dynamics by the
default for float, the articulated-body algorithm), compiles it with ``arm-none-eabi-gcc
-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -O2 -fstack-usage``
(:mod:`symdyn.check.firmware`, the same measurement as ``symdyn generate --size-report``) and
prints, per function, its text size and stack use in bytes, and whether any double-precision
routine (``__aeabi_d*``, double sin/cos/sqrt) is referenced.
"""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

import symdyn  # noqa: E402
from symdyn.check.firmware import measure  # noqa: E402
from symdyn.emit.pipeline import GenerateOptions, configure, generate  # noqa: E402


def main(argv=None):
    names = (argv if argv is not None else sys.argv[1:]) or ["puma560", "ur5", "iiwa14", "chain12", "pendulum_leg"]
    print("| robot | function | text (bytes) | stack (bytes) |")
    print("|---|---|---:|---:|")
    doubles, toolchain = {}, ""
    for name in names:
        path = os.path.join(HERE, "..", "robots", f"{name}.yaml")
        files = {k: v.decode() for k, v in generate(configure(path, GenerateOptions(precision="float"))).items()}
        report = measure(files, symdyn.load(path).name)
        toolchain = report.toolchain
        doubles[name] = report.doubles
        for function in sorted(report.sizes):
            text, stack = report.sizes[function]
            print(f"| {name} | {function} | {text} | {stack} |")
    for name, routines in doubles.items():
        print(f"- {name}: double-precision routines referenced: {', '.join(routines) or 'none'}")
    print(f"\nMeasured with {toolchain}.")


if __name__ == "__main__":
    main()
