"""--precision float on a Cortex-M4 (single-precision FPU): the generated file compiles with
arm-none-eabi-gcc and references no double-precision routine (no __aeabi_d*, no sin/cos)."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from helpers import REPO
from symdyn.cli import main

ARM_GCC = shutil.which("arm-none-eabi-gcc")
ARM_NM = shutil.which("arm-none-eabi-nm")


def _has_newlib() -> bool:
    """arm-none-eabi-gcc with a C library's headers (Debian: libnewlib-arm-none-eabi)."""
    if ARM_GCC is None:
        return False
    probe = subprocess.run([ARM_GCC, "-x", "c", "-fsyntax-only", "-"], input="#include <math.h>\n",
                           capture_output=True, text=True)
    return probe.returncode == 0

CORTEX_M4 = ["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard", "-mfpu=fpv4-sp-d16", "-O2", "-std=c99",
             "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wdouble-promotion", "-fstack-usage"]


@pytest.mark.skipif(ARM_NM is None or not _has_newlib(),
                    reason="arm-none-eabi-gcc with newlib not installed (.ci/run installs gcc-arm-none-eabi "
                           "and libnewlib-arm-none-eabi)")
@pytest.mark.parametrize("name, functions", [("puma560", None), ("chain12", "forward_dynamics")])
def test_float_code_uses_no_double_on_cortex_m4(name, functions, tmp_path):
    """Every function of puma560, and chain12's forward dynamics (its D has cond 6.6e4)."""
    assert main(["generate", str(REPO / "robots" / f"{name}.yaml"), "--out", str(tmp_path),
                 "--precision", "float", "--quiet"] + (["--functions", functions] if functions else [])) == 0
    obj = tmp_path / f"{name}.o"
    subprocess.run([ARM_GCC, *CORTEX_M4, "-c", str(tmp_path / f"{name}_dynamics.c"), "-o", str(obj)],
                   check=True, cwd=tmp_path)
    undefined = subprocess.run([ARM_NM, "-u", str(obj)], capture_output=True, text=True, check=True).stdout.split()
    names = {entry for entry in undefined if entry != "U"}
    assert not {n for n in names if n.startswith("__aeabi_d")}, names
    assert not names & {"sin", "cos", "sqrt", "fabs", "pow"}, names
    assert {"sinf", "cosf"} <= names
    stack = (tmp_path / f"{name}.su").read_text()
    assert f"{name}_forward_dynamics_checked" in stack
