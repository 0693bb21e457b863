"""Instructions per call of each function on an emulated Cortex-M4 (QEMU's mps2-an386 board).

Usage:  python benchmarks/firmware_instructions.py [ROBOT ...]   (default: puma560 ur5 iiwa14 panda chain12)

Builds examples/firmware/cortex-m4 for each robot (its float header, arm-none-eabi-gcc -O2
-std=c99), runs it under qemu-system-arm -icount shift=0 (one instruction per nanosecond of
virtual time; SysTick, calibrated by a loop of known length, then counts instructions) and
prints a Markdown table: instructions per call (16 calls averaged) and the time they would take
at 168 MHz assuming one instruction per cycle, an *estimate* (QEMU models no pipeline: a real
Cortex-M4 takes 2 cycles for a load and 14 for a division).
"""

import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "examples", "firmware", "cortex-m4")
CLOCK_HZ = 168e6


def instructions(robot: str, build: str) -> dict:
    subprocess.run(["make", "-C", EXAMPLE, f"ROBOT={robot}", f"BUILD={build}", f"SYMDYN={sys.executable} -m symdyn"],
                   check=True, capture_output=True, text=True)
    run = subprocess.run(["qemu-system-arm", "-M", "mps2-an386", "-nographic", "-monitor", "none", "-serial", "none",
                          "-chardev", "stdio,id=console", "-semihosting-config", "enable=on,target=native,chardev=console",
                          "-icount", "shift=0", "-kernel", os.path.join(build, "firmware.elf")],
                         check=True, capture_output=True, text=True, timeout=300)
    return {w[1]: int(w[2]) for w in (line.split() for line in run.stdout.splitlines()) if w and w[0] == "instructions"}


def main(argv=None):
    robots = (argv if argv is not None else sys.argv[1:]) or ["puma560", "ur5", "iiwa14", "panda", "chain12"]
    print("| robot | function | instructions per call | estimated us at 168 MHz (1 instruction per cycle) |")
    print("|---|---|---:|---:|")
    with tempfile.TemporaryDirectory() as work:
        for robot in robots:
            for function, count in instructions(robot, os.path.join(work, robot)).items():
                print(f"| {robot} | {function} | {count} | {count / CLOCK_HZ * 1e6:.1f} (estimate) |")


if __name__ == "__main__":
    main()
