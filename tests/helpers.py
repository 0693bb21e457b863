"""Shared test helpers: Pinocchio references and the normalized error measure."""

from __future__ import annotations

import numpy as np

import symdyn
from symdyn.check.pinocchio_model import PinocchioReference, normalized_error  # noqa: F401 (re-exported)

REPO = __import__("pathlib").Path(__file__).resolve().parents[1]
ROBOTS = sorted(p.stem for p in (REPO / "robots").glob("*.yaml"))
TOL = 1e-10


def robot_path(name: str) -> str:
    path = REPO / "robots" / f"{name}.yaml"
    return str(path if path.exists() else REPO / "tests" / "data" / f"{name}.yaml")


def example_robot_data(relative: str) -> str:
    """The path of ``relative`` in the example-robot-data wheel (a test extra)."""
    import os
    import sysconfig

    import pytest
    path = os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix", "share", "example-robot-data", "robots",
                        relative)
    if not os.path.exists(path):
        pytest.fail("the example-robot-data wheel is missing: pip install -e '.[test]'")
    return path


def parameter_values(robot, seed: int = 7) -> dict:
    """Seeded positive values for every runtime parameter and free symbol (g = 9.81)."""
    rng = np.random.default_rng(seed)
    values = {}
    for sym in robot.parameters:
        values[sym] = 9.81 if sym.name == "g" else float(rng.uniform(0.3, 1.5))
    return values


def random_states(n: int, count: int, seed: int = 0):
    """Seeded states: q in [-pi, pi], qd in [-2, 2], qdd in [-5, 5], tau in [-20, 20]."""
    rng = np.random.default_rng(seed)
    return [(rng.uniform(-np.pi, np.pi, n), rng.uniform(-2, 2, n), rng.uniform(-5, 5, n),
             rng.uniform(-20, 20, n)) for _ in range(count)]


#: the sanitizers every C test program runs under: addresses, undefined behaviour, float
#: division by zero and out-of-range conversions, the first report fatal
SANITIZER_FLAGS = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O1", "-g",
                   "-fsanitize=address,undefined", "-fsanitize=float-divide-by-zero,float-cast-overflow",
                   "-fno-sanitize-recover=all"]


def run_sanitized(workdir, program: str, files: dict) -> str:
    """Compile ``program`` (the text of main.c) with the generated ``files`` ({name: str or
    bytes}; every ``.c`` among them is compiled) under :data:`SANITIZER_FLAGS`, run it, check
    that it exits 0 with no sanitizer report, and return its standard output.  Skips the test
    where the compiler has no sanitizer runtime."""
    import os
    import shutil
    import subprocess

    import pytest
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler")
    workdir = __import__("pathlib").Path(workdir)
    for name, text in files.items():
        (workdir / name).write_bytes(text if isinstance(text, bytes) else text.encode())
    (workdir / "main.c").write_text(program)
    exe = workdir / "sanitized"
    sources = [str(workdir / "main.c")] + [str(workdir / name) for name in sorted(files) if name.endswith(".c")]
    build = subprocess.run([compiler, *SANITIZER_FLAGS, *sources, "-o", str(exe), "-lm"], capture_output=True, text=True)
    if build.returncode != 0 and "sanitize" in build.stderr and ("cannot find" in build.stderr or "unrecognized" in build.stderr):
        pytest.skip("compiler without sanitizer runtime")
    assert build.returncode == 0, build.stderr[-3000:]
    run = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120,
                         env={**os.environ, "ASAN_OPTIONS": "detect_leaks=1"})
    assert run.returncode == 0, run.stderr[-3000:]
    assert "runtime error" not in run.stderr and "Sanitizer" not in run.stderr, run.stderr[-3000:]
    return run.stdout


# the Cortex-M4 toolchain (gcc-arm-none-eabi, libnewlib-arm-none-eabi), for the firmware tests
import shutil as _shutil  # noqa: E402
import subprocess as _subprocess  # noqa: E402

ARM_GCC = _shutil.which("arm-none-eabi-gcc")
ARM_NM = _shutil.which("arm-none-eabi-nm")


def fma_hardware() -> bool:
    """This machine runs x86-64 FMA instructions (what a build with -mfma needs)."""
    import platform
    try:
        with open("/proc/cpuinfo") as handle:
            return platform.machine() in ("x86_64", "AMD64") and " fma " in handle.read()
    except OSError:
        return False


def has_newlib() -> bool:
    """arm-none-eabi-gcc with a C library's headers (Debian: libnewlib-arm-none-eabi)."""
    if ARM_GCC is None:
        return False
    probe = _subprocess.run([ARM_GCC, "-x", "c", "-fsyntax-only", "-"], input="#include <math.h>\n",
                           capture_output=True, text=True)
    return probe.returncode == 0


#: the flags of the firmware tests: Cortex-M4, single-precision FPU, strict warnings
CORTEX_M4 = ["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard", "-mfpu=fpv4-sp-d16", "-O2", "-std=c99",
             "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wdouble-promotion", "-fstack-usage"]


def error_line(capsys) -> str:
    """The one error line of a failed command (warning lines may come before it)."""
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines and lines[-1].startswith("symdyn: error: "), lines
    assert all(line.startswith("symdyn: warning: ") for line in lines[:-1]), lines
    assert "Traceback" not in lines[-1]
    return lines[-1]
