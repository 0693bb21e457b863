"""--precision float on a Cortex-M4 (single-precision FPU): the generated file compiles with
arm-none-eabi-gcc and references no double-precision routine (no __aeabi_d*, no sin/cos)."""

from __future__ import annotations

import subprocess

import pytest

from helpers import ARM_GCC, ARM_NM, CORTEX_M4, REPO, has_newlib as _has_newlib
from symdyn.cli import main
from symdyn.model.outputs import OUTPUTS


#: puma560: every standard function and the derivatives (inverse and forward dynamics, gravity; M^-1)
PUMA_FUNCTIONS = ",".join(OUTPUTS) + ",inverse_dynamics_derivatives,gravity_derivative,forward_dynamics_derivatives"


@pytest.mark.skipif(ARM_NM is None or not _has_newlib(),
                    reason="arm-none-eabi-gcc with newlib not installed (.ci/run installs gcc-arm-none-eabi "
                           "and libnewlib-arm-none-eabi)")
@pytest.mark.parametrize("name, functions", [
    ("puma560", PUMA_FUNCTIONS), ("chain12", "forward_dynamics"),
    ("ur5", "task_mass_matrix,task_bias,task_gravity,task_inverse"),
    ("iiwa14", "inverse_dynamics_derivatives")])
def test_float_code_uses_no_double_on_cortex_m4(name, functions, tmp_path):
    """Every function of puma560 and its derivatives, chain12's forward dynamics (its D has cond
    6.6e4), ur5's task-space functions (their tolerance macro is a double literal: cast where
    it is used), and iiwa14's derivatives (their vector-tangent loops)."""
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
    listed = functions.split(",")
    checked = [f"{name}_{f}" for f, given in (("forward_dynamics_checked", "forward_dynamics"),
                                             ("forward_dynamics_derivatives",) * 2, ("task_space", "task_inverse"),
                                             ("inverse_dynamics_derivatives",) * 2) if given in listed]
    assert checked
    assert all(function in stack for function in checked)


@pytest.mark.skipif(ARM_NM is None or not _has_newlib(),
                    reason="arm-none-eabi-gcc with newlib not installed (.ci/run installs gcc-arm-none-eabi "
                           "and libnewlib-arm-none-eabi)")
def test_size_report_documents_every_function(tmp_path):
    """--size-report: the header gives each function's Cortex-M4 code size and stack use, the
    numbers arm-none-eabi-nm and -fstack-usage give for the same file, and the C is the same
    as without the report; the pendulum leg's float C, reaction map included, uses no double."""
    import re
    leg = str(REPO / "robots" / "pendulum_leg.yaml")
    for out, extra in (("plain", []), ("sized", ["--size-report"])):
        assert main(["generate", leg, "--out", str(tmp_path / out), "--precision", "float", "--quiet", *extra]) == 0
    sized = tmp_path / "sized"
    assert (sized / "pendulum_leg_dynamics.c").read_bytes() == (tmp_path / "plain" / "pendulum_leg_dynamics.c").read_bytes()
    header = (sized / "pendulum_leg_dynamics.h").read_text()
    assert "Double-precision routines\n * referenced: none." in header
    documented = {fn: sizes for sizes, fn in re.findall(
        r"Cortex-M4: (\d+) bytes of code, \d+ bytes of stack[^\n]*\n \*/\n(?:int|void) (pendulum_leg_\w+)\(", header)}
    functions = re.findall(r"^(?:int|void) (pendulum_leg_\w+)\(", header, re.M)
    assert set(documented) == set(functions) and "pendulum_leg_reaction_map" in functions
    obj = tmp_path / "leg.o"
    subprocess.run([ARM_GCC, *CORTEX_M4[:6], "-c", str(sized / "pendulum_leg_dynamics.c"), "-o", str(obj)], check=True)
    listing = subprocess.run([ARM_NM, "--size-sort", "-S", str(obj)], capture_output=True, text=True, check=True).stdout
    sizes = {parts[3]: int(parts[1], 16) for parts in (line.split() for line in listing.splitlines()) if len(parts) == 4}
    assert {fn: int(text) for fn, text in documented.items()} == {fn: sizes[fn] for fn in documented}


def test_size_report_needs_the_c_target(tmp_path, capsys):
    assert main(["generate", str(REPO / "robots" / "planar2r.yaml"), "--out", str(tmp_path), "--target", "casadi",
                 "--size-report"]) == 1
    assert "--size-report" in capsys.readouterr().err
