"""Every script in benchmarks/ runs on a tiny case, exits 0 and prints a Markdown table with
numbers, so that none rots unnoticed.  Timings are printed, never asserted.

The scripts that time Pinocchio compile its C++ once per machine and keep the objects in
$SYMDYN_BENCH_CACHE (default ~/.cache/symdyn/bench-build, see benchmarks/harness.py): the first
run on a fresh machine takes about 8 minutes of compiling more (.ci/run builds them before the
suite, by the tiny runs of the three scripts that compile C++); later runs take about 25 s on
2 cores.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
BENCHMARKS = REPO / "benchmarks"

#: script -> the arguments of its tiny run, slowest first (pytest-xdist hands them out in order)
TINY = {
    "parallel_speed.py": ["--smoke"],
    "forward_dynamics_speed.py": ["scara", "--smoke"],
    "kinematics_speed.py": ["--smoke"],
    "c_speed.py": ["scara", "--smoke"],
    "batch_speed.py": ["scara", "--smoke", "--functions", "inverse_dynamics,forward_dynamics"],
    "identification.py": ["scara", "--smoke"],
    "long_chains.py": ["3", "--smoke", "--functions", "inverse_dynamics,forward_dynamics"],
    "harness.py": ["3", "--smoke"],
    "scenes.py": ["--smoke"],
    "casadi_speed.py": ["scara", "--smoke", "--functions", "inverse_dynamics,forward_dynamics_dq,coriolis_matrix"],
    "fma.py": ["scara", "--smoke"],
    "firmware_instructions.py": ["scara"],
    "firmware_size.py": ["scara"],
    "derivation.py": ["--repeat", "1", "robots/scara.yaml"],
    "robots_table.py": ["--only", "double_pendulum", "--states", "3"],
}

#: a table cell that starts with a number (12, 3.5x, 1.2e-15, 99 (98-101), 58/39/3)
NUMERIC_CELL = re.compile(r"\|\s*-?\d+(?:\.\d+)?(?:e[-+]?\d+)?(?:x|\s*\(|/|\s*\|)")


#: the scripts that compile Pinocchio's C++ (benchmarks/harness.py and its users, and the two
#: with their own C++ timing programs)
CXX_SCRIPTS = {"parallel_speed.py", "forward_dynamics_speed.py", "kinematics_speed.py", "c_speed.py", "batch_speed.py",
               "identification.py", "long_chains.py", "harness.py", "casadi_speed.py", "scenes.py"}


def _missing_tool(script: str) -> str | None:
    """Why ``script`` cannot run here, or None."""
    if script in CXX_SCRIPTS and shutil.which("g++") is None:
        return "g++ is not installed (Pinocchio's C++ side of the comparison)"
    if script.startswith("firmware_"):
        for tool in ("arm-none-eabi-gcc", "qemu-system-arm", "make") if script == "firmware_instructions.py" \
                else ("arm-none-eabi-gcc",):
            if shutil.which(tool) is None:
                return f"{tool} is not installed (the Cortex-M4 toolchain)"
    if script in ("kinematics_speed.py", "robots_table.py"):
        robots = Path(sysconfig.get_paths()["purelib"]) / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if not robots.is_dir():  # where kinematics_speed.example_robot_data() looks
            return "the example-robot-data wheel (a test extra) is not installed"
    return None


def tables(text: str) -> list[list[str]]:
    """The data rows of each Markdown table in ``text``."""
    found, rows, in_table = [], [], False
    for line in text.splitlines():
        if re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", line.strip()):
            rows, in_table = [], True
            found.append(rows)
        elif in_table and line.startswith("|"):
            rows.append(line)
        else:
            in_table = False
    return found


def test_every_script_has_a_tiny_run():
    assert sorted(p.name for p in BENCHMARKS.glob("*.py")) == sorted(TINY)


#: the scripts whose tiny run takes longest (15 s on 2 cores), run with the slow-marked tests
SLOW_SCRIPTS = ("parallel_speed.py",)


@pytest.mark.parametrize("script", [pytest.param(s, marks=pytest.mark.slow) if s in SLOW_SCRIPTS else s for s in TINY])
def test_script_runs_tiny(script):
    reason = _missing_tool(script)
    if reason:
        pytest.skip(reason)
    run = subprocess.run([sys.executable, str(BENCHMARKS / script), *TINY[script]], cwd=REPO, capture_output=True,
                         text=True, timeout=900)
    assert run.returncode == 0, f"{script} failed:\n{run.stdout[-2000:]}\n{run.stderr[-4000:]}"
    found = [rows for rows in tables(run.stdout) if rows]
    assert found, f"{script} printed no table:\n{run.stdout[-2000:]}"
    for rows in found:
        for row in rows:
            assert NUMERIC_CELL.search(row), f"{script}: a row without numbers: {row}"


def test_harness_times_the_task_space_and_kinematics_functions():
    """The harness's task-space and tool-kinematics comparisons (Pinocchio's side in sources of
    their own, benchmarks/harness_pinocchio_task.cpp and _kin.cpp; no peer column) on a tiny run."""
    reason = _missing_tool("harness.py")
    if reason:
        pytest.skip(reason)
    functions = ("task_space", "forward_kinematics", "jacobian", "jacobian_dot_qd", "kinematics")
    run = subprocess.run([sys.executable, str(BENCHMARKS / "harness.py"), "ur5", "--functions", ",".join(functions),
                          "--smoke"], cwd=REPO, capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, f"harness.py failed:\n{run.stdout[-2000:]}\n{run.stderr[-4000:]}"
    for function in functions:
        rows = [row for rows in tables(run.stdout) for row in rows if f"| {function} |" in row]
        assert rows and all(NUMERIC_CELL.search(row) for row in rows), (function, run.stdout[-2000:])

