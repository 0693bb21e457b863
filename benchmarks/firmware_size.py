"""Code size and stack use of the float C on a Cortex-M4 (single-precision FPU).

Usage:  python benchmarks/firmware_size.py [ROBOT ...]   (default: puma560 ur5 iiwa14 chain12)

Generates ``--precision float`` C for each robot (every function; forward dynamics by the
default for float, the articulated-body algorithm), compiles it with ``arm-none-eabi-gcc
-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -O2 -fstack-usage`` and prints, per
function, its text size (bytes, from ``arm-none-eabi-nm --size-sort``) and stack use (bytes,
from the .su file), and whether any double-precision routine (``__aeabi_d*``) is referenced.
"""

import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))

from symdyn.cli import main as symdyn_main  # noqa: E402

FLAGS = ["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard", "-mfpu=fpv4-sp-d16", "-O2", "-std=c99", "-fstack-usage"]


def main(argv=None):
    names = (argv if argv is not None else sys.argv[1:]) or ["puma560", "ur5", "iiwa14", "chain12"]
    print("| robot | function | text (bytes) | stack (bytes) |")
    print("|---|---|---:|---:|")
    doubles = {}
    for name in names:
        with tempfile.TemporaryDirectory() as work:
            symdyn_main(["generate", os.path.join(HERE, "..", "robots", f"{name}.yaml"), "--out", work,
                         "--precision", "float", "--quiet"])
            obj = os.path.join(work, f"{name}.o")
            subprocess.run(["arm-none-eabi-gcc", *FLAGS, "-c", f"{name}_dynamics.c", "-o", obj], check=True, cwd=work)
            sizes = {}
            for line in subprocess.run(["arm-none-eabi-nm", "--size-sort", "-S", obj], capture_output=True,
                                       text=True, check=True).stdout.splitlines():
                parts = line.split()
                if len(parts) == 4 and parts[2] in "Tt":
                    sizes[parts[3]] = int(parts[1], 16)
            stacks = {}
            with open(os.path.join(work, f"{name}.su")) as handle:
                for line in handle:
                    where, amount, _ = line.rsplit("\t", 2) if line.count("\t") >= 2 else (line, "0", "")
                    stacks[where.rsplit(":", 1)[-1]] = int(amount)
            undefined = subprocess.run(["arm-none-eabi-nm", "-u", obj], capture_output=True, text=True,
                                       check=True).stdout.split()
            doubles[name] = sorted(u for u in undefined if u.startswith("__aeabi_d"))
            for function in sorted(sizes):
                print(f"| {name} | {function} | {sizes[function]} | {stacks.get(function, '-')} |")
    for name, routines in doubles.items():
        print(f"{name}: double-precision routines referenced: {', '.join(routines) or 'none'}")


if __name__ == "__main__":
    main()
