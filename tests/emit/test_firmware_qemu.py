"""The firmware example (examples/firmware/cortex-m4) built with arm-none-eabi-gcc and run on
QEMU's mps2-an386 board (a Cortex-M4 with FPU): every number it prints (float, on the emulated
target) agrees with the same functions compiled for the host in double, within 1e-4 normalized
per joint; the firmware references no double-precision routine; forward dynamics reports its
statuses; and each function's instruction count is printed."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections import defaultdict

import numpy as np
import pytest

from helpers import ARM_GCC, ARM_NM, REPO, example_robot_data, has_newlib
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import normalized_error

EXAMPLE = REPO / "examples" / "firmware" / "cortex-m4"
QEMU = shutil.which("qemu-system-arm")
MAKE = shutil.which("make")
MISSING = [what for what, ok in (("arm-none-eabi-gcc with newlib (gcc-arm-none-eabi, libnewlib-arm-none-eabi)",
                                  ARM_GCC is not None and ARM_NM is not None and has_newlib()),
                                 ("qemu-system-arm", QEMU is not None), ("make", MAKE is not None)) if not ok]

pytestmark = pytest.mark.skipif(bool(MISSING), reason=f"not installed: {', '.join(MISSING)} (.ci/run installs them)")


def build_and_run(robot: str, build, make_args=()) -> list[str]:
    """Build the example for ``robot`` into ``build`` and run it on QEMU; its output lines."""
    subprocess.run([MAKE, "-C", str(EXAMPLE), f"ROBOT={robot}", f"BUILD={build}",
                    f"SYMDYN={sys.executable} -m symdyn", *make_args], check=True, capture_output=True, text=True)
    elf = build / "firmware.elf"
    undefined = subprocess.run([ARM_NM, str(elf)], capture_output=True, text=True, check=True).stdout
    assert "__aeabi_d" not in undefined, "the float firmware pulls in double-precision routines"
    run = subprocess.run([QEMU, "-M", "mps2-an386", "-nographic", "-monitor", "none", "-serial", "none",
                          "-chardev", "stdio,id=console", "-semihosting-config",
                          "enable=on,target=native,chardev=console", "-icount", "shift=0", "-kernel", str(elf)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    return run.stdout.splitlines()


def parse(lines):
    """``(states, statuses, instructions)``: per state, {name: float32 values} of inputs and
    outputs; the forward dynamics status per state; instructions per function."""
    states, statuses, instructions = [], [], {}
    for line in lines:
        words = line.split()
        if words[0] == "state":
            states.append(defaultdict(list))
        elif words[0] in ("in", "out"):
            kind, name, index, bits = words[:4]
            name = f"{kind} {name}"
            assert int(index) == len(states[-1][name])
            states[-1][name].append(np.frombuffer(bytes.fromhex(bits)[::-1], dtype=np.float32)[0])
        elif words[0] == "status":
            statuses.append(int(words[2]))
        elif words[0] == "instructions":
            instructions[words[1]] = int(words[2])
    assert lines[-1] == "done", lines[-5:]
    return states, statuses, instructions


SOLO = "solo_description/robots/solo12.urdf"
FEET = "FL_FOOT,HR_FOOT"
#: (robot, its file, symdyn generate's options): two arms of robots/, and a quadruped on its
#: floating base with two feet as frames (q of NQ = 19 numbers, the frame functions)
FIRMWARE_ROBOTS = [("puma560", None, ()), ("panda", None, ()),
                   pytest.param("solo", SOLO, ("--floating-base", "--frames", FEET), marks=pytest.mark.slow, id="solo")]


@pytest.mark.parametrize("robot,relative,options", FIRMWARE_ROBOTS)
def test_firmware_on_qemu_matches_host_double(robot, relative, options, tmp_path):
    import symdyn
    from symdyn.cli import main
    from symdyn.model.outputs import Dimensions
    path = str(REPO / "robots" / f"{robot}.yaml") if relative is None else example_robot_data(relative)
    make_args = () if relative is None else (f"ROBOT_FILE={path}", f"GENERATE_FLAGS={' '.join(options)}")
    lines = build_and_run(robot, tmp_path / "build", make_args)
    assert lines[0] == f"robot {robot}"
    states, statuses, instructions = parse(lines[1:])
    floating = "--floating-base" in options
    model = symdyn.load(path, floating_base=floating, frames=FEET.split(",") if floating else None)
    assert main(["generate", path, *options, "--out", str(tmp_path / "host"), "--quiet"]) == 0
    files = {name: (tmp_path / "host" / name).read_text() for name in os.listdir(tmp_path / "host")}
    host = build_and_load(files, robot, Dimensions.of(model), 0, "double", str(tmp_path))
    kinematics = (("frame_poses", lambda q, qd: host.frame_poses(q)),
                  ("frame_jacobians", lambda q, qd: host.frame_jacobians(q)),
                  ("frame_jacobian_dot_v", lambda q, qd: host.frame_jacobian_dot_v(q, qd))) if floating else (
                  ("forward_kinematics", lambda q, qd: host.forward_kinematics(q)),
                  ("jacobian", lambda q, qd: host.jacobian(q)))
    # the last state has an infinite velocity: status 2, nothing written; the others are solved
    assert statuses == [0, 0, 0, 2] and "out forward_dynamics" not in states[3]
    target, reference = defaultdict(list), defaultdict(list)
    for state in states[:3]:
        q, qd, qdd, tau = (np.array(state[f"in {x}"], dtype=float) for x in ("q", "qd", "qdd", "tau"))
        assert len(q) == model.nq and len(qd) == model.nv
        status, qdd_host = host.forward_dynamics_checked(q, qd, tau)
        assert status == 0
        outputs = [("inverse_dynamics", host.inverse_dynamics(q, qd, qdd)), ("mass_matrix", host.mass_matrix(q)),
                   ("forward_dynamics", qdd_host)] + [(name, f(q, qd)) for name, f in kinematics]
        for name, value in outputs:
            target[name].append(np.array(state[f"out {name}"], dtype=float).reshape(np.shape(value)))
            reference[name].append(np.asarray(value, dtype=float))
    for name in reference:
        mine, ref = np.array(target[name]), np.array(reference[name])
        if name in ("jacobian", "frame_jacobians"):  # per joint: the columns
            mine, ref = mine.transpose(0, 2, 1), ref.transpose(0, 2, 1)
        error = normalized_error(mine, ref)
        assert error <= 1e-4, (robot, name, error)
    expected = {"inverse_dynamics", "mass_matrix", "gravity", "forward_dynamics_checked"} | (
        {"frame_poses", "frame_jacobians", "frame_kinematics"} if floating
        else {"forward_kinematics", "jacobian", "kinematics"})
    assert set(instructions) == expected and all(100 < count < 100000 for count in instructions.values()), instructions
