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
#: division by zero and out-of-range conversions, the first report fatal; at -O0 (nothing optimized
#: away before the checks, and big straight-line functions build in seconds where -O1 -g takes minutes)
SANITIZER_FLAGS = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O0", "-g",
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


# SE(3) in 50 digits (mpmath), an independent reference for a floating base's configuration
# space: the pose of a configuration, the exponential of a twist, and back to a configuration.

def mp_pose(q):
    """The 4x4 pose (mpmath) of a configuration's base: position q[0:3] and the quaternion
    q[3:7] (x, y, z, w; of any scale)."""
    import mpmath

    def exact(c):
        return c if isinstance(c, mpmath.mpf) else mpmath.mpf(float(c))
    x, y, z, w = (exact(c) for c in q[3:7])
    n = mpmath.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    R = mpmath.matrix([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                       [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                       [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    M = mpmath.eye(4)
    for i in range(3):
        M[i, 3] = exact(q[i])
        for j in range(3):
            M[i, j] = R[i, j]
    return M


def mp_exp6(v):
    """SE(3)'s exponential of the twist [v_lin; omega] (mpmath's matrix exponential)."""
    import mpmath
    X = mpmath.zeros(4, 4)
    vx, vy, vz, wx, wy, wz = v
    X[0, 1], X[0, 2], X[1, 0], X[1, 2], X[2, 0], X[2, 1] = -wz, wy, wz, -wx, -wy, wx
    X[0, 3], X[1, 3], X[2, 3] = vx, vy, vz
    return mpmath.expm(X)


def mp_base_configuration(M):
    """[position; quaternion (x, y, z, w)] (mpmath) of a pose: the inverse of :func:`mp_pose`
    up to the quaternion's sign and scale (Shepperd's choice of the largest component)."""
    import mpmath
    trace = M[0, 0] + M[1, 1] + M[2, 2]
    largest = max(range(4), key=lambda k: trace if k == 3 else M[k, k])
    if largest == 3:
        w = mpmath.sqrt(1 + trace) / 2
        x, y, z = (M[2, 1] - M[1, 2]) / (4 * w), (M[0, 2] - M[2, 0]) / (4 * w), (M[1, 0] - M[0, 1]) / (4 * w)
    else:
        i, j, k = largest, (largest + 1) % 3, (largest + 2) % 3
        axis = [mpmath.mpf(0)] * 3
        axis[i] = mpmath.sqrt(1 + M[i, i] - M[j, j] - M[k, k]) / 2
        axis[j] = (M[j, i] + M[i, j]) / (4 * axis[i])
        axis[k] = (M[k, i] + M[i, k]) / (4 * axis[i])
        w = (M[k, j] - M[j, k]) / (4 * axis[i])
        x, y, z = axis
    return [M[0, 3], M[1, 3], M[2, 3], x, y, z, w]
