"""Hostile input: no code injection, NaN-proof checks, checked forward dynamics, bounded work,
overflow refused, no traceback ever.  Each case runs the command line in-process and asserts the
exit status, the one line on stderr, and that nothing outside the output directory changed.
(The derivation cache and output-file safety have their own files: test_cache.py and
test_output_files.py; random mutations are in test_fuzz.py.)"""

from __future__ import annotations

import ctypes
import os
import pathlib
import time

import numpy as np
import pytest

from helpers import REPO, run_sanitized
from symdyn.check.cbuild import build_and_load, compile_shared
from symdyn.check.pinocchio_model import normalized_error
from symdyn.cli import main

MARKER_CODE = 'static void p(void){extern int system(const char *); system("touch MARKER");}'


def robot_text(name="hostile", links=None, extra=""):
    links = links or ["{joint: revolute, a: 0.4, alpha: 0, d: 0, theta: 0, mass: 2, com: [0.2, 0, 0], "
                      "inertia: [0.01, 0.02, 0.02, 0, 0, 0]}",
                      "{joint: revolute, a: 0.3, alpha: 0, d: 0, theta: 0, mass: 1, com: [0.1, 0, 0], "
                      "inertia: [0.01, 0.01, 0.01, 0, 0, 0]}"]
    return (f"format: 1\nname: {name}\nconvention: standard\n{extra}links:\n"
            + "".join(f"  - {link}\n" for link in links))


def snapshot(*roots):
    """(path, size, mtime) of every file under the roots, for 'nothing else changed'."""
    found = {}
    for root in roots:
        for path in pathlib.Path(root).rglob("*"):
            if path.is_file() and not path.is_symlink():
                info = path.stat()
                found[str(path)] = (info.st_size, info.st_mtime_ns)
    return found


def run_cli(argv, capsys, expect):
    """main(argv) with the exit status ``expect``; returns stderr's lines (exactly one line, an
    error, when ``expect`` is 1)."""
    argv = [str(a) for a in argv]
    outputs = [argv[k + 1] for k, a in enumerate(argv[:-1]) if a == "--out"]
    here = pathlib.Path.cwd()

    def others():  # every file under the working directory but the output
        return {path: info for path, info in snapshot(here).items()
                if not any(path == out or path.startswith(out.rstrip("/") + "/") for out in outputs)}
    before = others()
    start = time.process_time()  # this process's CPU time: the work done, not the machine's load
    status = main(argv)
    seconds = time.process_time() - start
    assert others() == before, "a file outside the output changed"
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert status == expect, (status, captured.err[-2000:])
    assert "Traceback" not in captured.err
    if expect == 1:  # warnings about the data may come first, then exactly one error line
        lines = [line for line in lines if not line.startswith("symdyn: warning: ")]
        assert len(lines) == 1 and lines[0].startswith("symdyn: error: "), lines
        assert len(lines[0]) < 800
    return lines, seconds


@pytest.fixture
def workspace(tmp_path, monkeypatch):
    """A scratch directory (the marker's home, as the current directory) and the repo snapshot."""
    monkeypatch.chdir(tmp_path)
    before = snapshot(REPO / "robots", REPO / "generated", REPO / "templates")
    yield tmp_path
    assert snapshot(REPO / "robots", REPO / "generated", REPO / "templates") == before
    assert not (tmp_path / "MARKER").exists()


# ---------------------------------------------------------------------------------------------
# 1. Code injection through names and paths

@pytest.mark.parametrize("bad_name", [
    f"'x */ __attribute__((constructor)) {MARKER_CODE} /* y'",
    '"r\\n"', '"elbow\\n/* x */"', '"a "', '"1st"', '"' + "n" * 32 + '"', '"l\u00e9"'])
def test_link_names_must_be_identifiers(workspace, capsys, bad_name):
    links = [f"{{name: {bad_name}, joint: revolute, a: 0.4, alpha: 0, d: 0, theta: 0, mass: 1}}"]
    (workspace / "r.yaml").write_text(robot_text(links=links), encoding="utf-8")
    (line,), _ = run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out"], capsys, 1)
    assert "link 1" in line and "'name'" in line and "valid link name" in line
    assert not (workspace / "out").exists()


@pytest.mark.parametrize("field, value", [("name", '"r\\n"'), ("name", '"' + "r" * 32 + '"')])
def test_robot_name_must_be_an_identifier(workspace, capsys, field, value):
    (workspace / "r.yaml").write_text(robot_text(name=value), encoding="utf-8")
    (line,), _ = run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out"], capsys, 1)
    assert "'name'" in line


@pytest.mark.parametrize("bad", ["nan", "inf", "zoo", "oo", "NaN", "Infinity", '"m\\n"', "E", "I"])
def test_parameter_names_refused(workspace, capsys, bad):
    text = robot_text(extra=f"parameters:\n  {bad}: {{value: 1.5, runtime: true}}\n")
    (workspace / "r.yaml").write_text(text)
    (line,), _ = run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out"], capsys, 1)
    assert "parameter name" in line


def test_paths_never_reach_generated_text_raw(workspace, capsys):
    """A scene's robot path and verify's path carry C and LaTeX payloads: the output compiles,
    loading it runs no constructor, and the LaTeX printout has no markup from the path."""
    evil_dir = workspace / f"x */ __attribute__((constructor)) {MARKER_CODE} /* y"
    evil_dir.mkdir(parents=True)
    robot_file = evil_dir / "robot.yaml"
    robot_file.write_text(robot_text())
    scene = workspace / "scene.yaml"
    scene.write_text(f"scene: 1\nrobot: '{robot_file.relative_to(workspace)}'\nfunctions: [gravity]\n")
    out = workspace / "out"
    run_cli(["generate", scene, "--out", out, "--quiet", "--no-cache"], capsys, 0)
    source = (out / "hostile_dynamics.c").read_text()
    assert "*/ __attribute__" not in source and "system(" not in source
    lib = compile_shared(str(out / "hostile_dynamics.c"), str(out))
    ctypes.CDLL(lib)  # a constructor would run here
    assert not (workspace / "MARKER").exists()
    # verify builds and loads the library of the weird path itself
    lines, _ = run_cli(["verify", robot_file, "--states", "2"], capsys, 0)
    assert not (workspace / "MARKER").exists()
    # LaTeX: the path shows sanitized inside \texttt, no brace, backslash or percent from it
    latex_dir = workspace / "a}\\input{evil}%b"
    latex_dir.mkdir()
    (latex_dir / "r.yaml").write_text(robot_text())
    run_cli(["derive", latex_dir / "r.yaml", "--format", "latex", "--out", workspace / "d.tex"], capsys, 0)
    tex = (workspace / "d.tex").read_text()
    assert "\\input{evil}" not in tex and "}%b" not in tex


# ---------------------------------------------------------------------------------------------
# 3. NaN is a failure wherever errors are measured

def test_normalized_error_sees_nan_and_inf():
    ref = np.array([[1.0, 2.0], [3.0, 4.0]])
    for bad in (np.nan, np.inf, -np.inf):
        mine = ref.copy()
        mine[1, 0] = bad
        assert normalized_error(mine, ref) == np.inf
        assert normalized_error(ref, mine) == np.inf
    assert normalized_error(ref, ref) == 0.0


def test_verify_fails_on_a_nan_output(workspace, capsys, monkeypatch):
    import symdyn.emit.cgen as cgen  # what verify's compile (symdyn.check.agreement.compile_equations) calls

    real = cgen.generate_c

    def poisoned(*args, **kwargs):
        files = real(*args, **kwargs)
        name = next(k for k in files if k.endswith(".c"))
        files[name] = files[name].replace("    c[0] = ", "    c[0] = NAN + ", 1)
        assert "NAN + " in files[name]
        return files
    monkeypatch.setattr(cgen, "generate_c", poisoned)
    assert main(["verify", str(REPO / "robots" / "planar2r.yaml"), "--states", "3"]) == 1
    out = capsys.readouterr().out
    gravity = next(line for line in out.splitlines() if line.startswith("gravity"))
    assert "FAIL" in gravity and "inf" in gravity


# ---------------------------------------------------------------------------------------------
# 4. Forward dynamics: refused when singular for every q, a status where singular at some q

def test_all_zero_mass_refuses_forward_dynamics_only(workspace, capsys):
    links = ["{joint: revolute, a: 0.4, alpha: 0, d: 0, theta: 0}", "{joint: revolute, a: 0.3, alpha: 0, d: 0, theta: 0}"]
    (workspace / "r.yaml").write_text(robot_text(links=links))
    (line,), _ = run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out", "--no-cache",
                          "--functions", "forward_dynamics"], capsys, 1)
    assert "r.yaml: forward dynamics" in line and "joints 1 ('j1'), 2 ('j2')" in line and "leave forward_dynamics out" in line
    assert not (workspace / "out").exists()
    run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out", "--quiet", "--no-cache",
             "--functions", "inverse_dynamics,mass_matrix,coriolis,coriolis_matrix,gravity"], capsys, 0)
    assert "NAN" not in (workspace / "out" / "hostile_dynamics.c").read_text()


def _compile(path, out, capsys, *extra):
    run_cli(["generate", path, "--out", out, "--quiet", "--no-cache", *extra], capsys, 0)


@pytest.fixture(scope="module")
def massless_first_link(tmp_path_factory):
    """A 2R arm whose first link has no mass: D is singular at q2 = 0 only."""
    import symdyn
    from symdyn.emit.cgen import generate_c
    root = tmp_path_factory.mktemp("massless")
    links = ["{joint: revolute, a: 0.5, alpha: 0, d: 0, theta: 0}",
             "{joint: revolute, a: 0.5, alpha: 0, d: 0, theta: 0, mass: 1, com: [0.2, 0, 0]}"]
    robot = symdyn.loads(robot_text(links=links))
    eqs = symdyn.derive(robot)
    libs = {}
    for precision in ("double", "float"):
        (root / precision).mkdir()
        libs[precision] = build_and_load(generate_c(eqs, None, precision), "hostile", 2, 0, precision, str(root / precision))
    return libs, eqs


def test_pivot_tolerance_follows_the_precision(massless_first_link):
    """The LDL^T pivot check is relative to the arithmetic (symdyn.model.tolerances): near the
    stretched pose the second pivot is about (0.7 q2)^2 of its diagonal entry; at q2 = 4e-5
    (1e-9) double solves it and float reports singular; at q2 = 3e-3 (5e-6) both solve it."""
    from symdyn.model.tolerances import PIVOT_RTOL
    libs, eqs = massless_first_link
    qd, tau = np.array([0.1, 0.2]), np.array([1.0, 2.0])
    D = eqs.numeric.mass_matrix
    for q2, expect in ((4e-5, {"double": 0, "float": 1}), (3e-3, {"double": 0, "float": 0})):
        q = np.array([0.3, q2])
        M = D(q)
        ratio = (M[1, 1] - M[1, 0] ** 2 / M[0, 0]) / M[1, 1]
        assert PIVOT_RTOL["double"] < ratio and (ratio < PIVOT_RTOL["float"]) == (expect["float"] == 1), ratio
        for precision, lib in libs.items():
            status, qdd = lib.forward_dynamics_checked(q, qd, tau)
            assert status == expect[precision], (q2, precision, ratio)
            if status == 0:
                expected = eqs.numeric.forward_dynamics(q, qd, tau)
                bound = 1e-6 if precision == "double" else 0.5  # the solution's error grows as 1/ratio
                assert np.allclose(qdd, expected, rtol=bound, atol=0), (precision, qdd, expected)


@pytest.mark.parametrize("precision", ["double", "float"])
def test_forward_dynamics_status(massless_first_link, precision):
    libs, eqs = massless_first_link
    lib = libs[precision]
    sentinel = np.array([7.0, -7.0])
    for q in ([0.3, 0.0], [0.0, 0.0], [-1.0, 0.0]):  # singular: the arm is stretched
        status, qdd = lib.forward_dynamics_checked(q, [0.1, 0.2], [1.0, 2.0], qdd=sentinel)
        assert status == 1 and np.array_equal(qdd, sentinel)
        assert np.array_equal(lib.forward_dynamics(q, [0.1, 0.2], [1.0, 2.0]), np.zeros(2))  # untouched
    for bad in (np.nan, np.inf):
        status, qdd = lib.forward_dynamics_checked([0.3, bad], [0.1, 0.2], [1.0, 2.0], qdd=sentinel)
        assert status == 2 and np.array_equal(qdd, sentinel)
        status, qdd = lib.forward_dynamics_checked([0.3, 1.0], [bad, 0.2], [1.0, 2.0], qdd=sentinel)
        assert status == 2 and np.array_equal(qdd, sentinel)
    q, qd, tau = np.array([0.3, 1.2]), np.array([0.1, 0.2]), np.array([1.0, 2.0])
    status, qdd = lib.forward_dynamics_checked(q, qd, tau)
    assert status == 0
    expected = eqs.numeric.forward_dynamics(q, qd, tau)
    assert np.allclose(qdd, expected, rtol=1e-5 if precision == "float" else 1e-12)


def test_chain12_far_configuration_never_writes_nan(derived, tmp_path):
    from symdyn.emit.cgen import generate_c
    eqs = derived("chain12")
    lib = build_and_load(generate_c(eqs, ["forward_dynamics"]), "chain12", 12, 0, "double", str(tmp_path))
    rng = np.random.default_rng(3)
    for q in (np.full(12, 1e8), rng.uniform(-1e8, 1e8, 12), np.full(12, 1e300)):
        sentinel = np.full(12, 5.0)
        status, qdd = lib.forward_dynamics_checked(q, rng.uniform(-1, 1, 12), rng.uniform(-1, 1, 12), qdd=sentinel)
        if status == 0:
            assert np.all(np.isfinite(qdd))
        else:
            assert np.array_equal(qdd, np.full(12, 5.0))


# ---------------------------------------------------------------------------------------------
# 5. Bounded work: refused in a bounded time with one line

BILLION_LAUGHS = (
    'a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]\n'
    "b: &b [*a,*a,*a,*a,*a,*a,*a,*a,*a]\nc: &c [*b,*b,*b,*b,*b,*b,*b,*b,*b]\n"
    "d: &d [*c,*c,*c,*c,*c,*c,*c,*c,*c]\ne: &e [*d,*d,*d,*d,*d,*d,*d,*d,*d]\n"
    "f: &f [*e,*e,*e,*e,*e,*e,*e,*e,*e]\ng: &g [*f,*f,*f,*f,*f,*f,*f,*f,*f]\n"
    "h: &h [*g,*g,*g,*g,*g,*g,*g,*g,*g]\ni: &i [*h,*h,*h,*h,*h,*h,*h,*h,*h]\n")


def _bounded_cases(root: pathlib.Path):
    """(label, path, expected words in the message) of every bounded-work input."""
    cases = []

    def write(label, text, words):
        path = root / f"{label}.yaml"
        path.write_text(text)
        cases.append((label, path, words))
    write("laughs", BILLION_LAUGHS, ["aliases"])
    write("laughs_links", robot_text(links=["*i"]).replace("links:\n", BILLION_LAUGHS.replace("a: &a", "x: &a") + "links:\n", 1), ["aliases"])
    for label, expr, words in (("pow9", "9**9**9", ["exponent"]), ("pow10", "10**10**10", ["exponent"]),
                               ("bigexp", "1e999999999", ["out of range"]),
                               ("parens", "(" * 5000 + "1" + ")" * 5000, ["characters"]),
                               ("deepparens", "(" * 200 + "1" + ")" * 200, ["nested"]),
                               ("zeropow", "0**(-x)", ["exponent"])):
        links = [f"{{joint: revolute, a: '{expr}', alpha: 0, d: 0, theta: 0, mass: 1, inertia: 0}}"]
        write(label, robot_text(links=links, extra="parameters: {x: {runtime: true}}\n"), [words[0], "'a'"])
    write("deepyaml", robot_text().replace("links:", "gravity: " + "[" * 20000 + "]" * 20000 + "\nlinks:"), ["nested"])
    write("deepblock", "format: 1\nx:\n" + "".join(" " * (k + 1) + f"k{k}:\n" for k in range(2500)), ["nested"])
    write("complexkey", "? [a]\n: 1\n", ["key"])
    big = root / "big.yaml"
    with open(big, "wb") as handle:
        handle.truncate(100 * 1024 * 1024)
    cases.append(("big", big, ["bytes"]))
    cases.append(("devzero", pathlib.Path("/dev/zero"), ["not a regular file"]))
    cases.append(("directory", root, ["directory"]))
    fifo = root / "fifo.yaml"
    os.mkfifo(fifo)
    cases.append(("fifo", fifo, ["not a regular file"]))
    return cases


def test_bounded_work(workspace, capsys):
    for label, path, words in _bounded_cases(workspace):
        for command in (["generate", path, "--out", workspace / "out"], ["derive", path]):
            (line,), seconds = run_cli(command, capsys, 1)
            assert seconds < 10, (label, seconds)  # CPU seconds (the hostile-input goal: 10 s)
            for word in words:
                assert word in line, (label, line)
    assert not (workspace / "out").exists()


def test_max_joints_refused_before_deriving(workspace, capsys, monkeypatch):
    import symdyn.emit.pipeline as pipeline

    def never(*args, **kwargs):
        raise AssertionError("derived although the robot is too large")
    monkeypatch.setattr(pipeline, "derive_cached", never)
    link = "{joint: revolute, a: 0.1, alpha: 0, d: 0, theta: 0, mass: 1, inertia: [0.01, 0.01, 0.01, 0, 0, 0]}"
    (workspace / "r.yaml").write_text(robot_text(links=[link] * 41))
    (line,), seconds = run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out", "--max-joints", "40"],
                               capsys, 1)
    assert "41 joints" in line and "--max-joints 40" in line and seconds < 10  # CPU seconds
    (line,), _ = run_cli(["derive", workspace / "r.yaml", "--max-joints", "12"], capsys, 1)
    assert "--max-joints 12" in line
    assert not (workspace / "out").exists()


def test_progress_on_a_terminal(workspace, capsys, monkeypatch):
    """Long derivations say what they are doing when stderr is a terminal (and only then)."""
    import sys
    robot = REPO / "robots" / "planar2r.yaml"
    lines, _ = run_cli(["generate", robot, "--out", workspace / "a", "--no-cache", "--functions", "gravity,coriolis"], capsys, 0)
    assert lines == []  # not a terminal: no progress
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    lines, _ = run_cli(["generate", robot, "--out", workspace / "b", "--no-cache", "--functions", "gravity,coriolis"], capsys, 0)
    assert any("planar2r: newton-euler: gravity" in line for line in lines), lines
    assert any("C for coriolis" in line for line in lines), lines
    lines, _ = run_cli(["generate", robot, "--out", workspace / "c", "--no-cache", "--quiet"], capsys, 0)
    assert lines == []


def test_bounded_work_in_a_scene(workspace, capsys):
    (workspace / "laughs.yaml").write_text(BILLION_LAUGHS)
    (workspace / "s.yaml").write_text("scene: 1\nrobot: laughs.yaml\n")
    (line,), seconds = run_cli(["generate", workspace / "s.yaml", "--out", workspace / "out"], capsys, 1)
    assert "aliases" in line and seconds < 10  # CPU seconds


# ---------------------------------------------------------------------------------------------
# 6. Values that overflow

@pytest.mark.parametrize("mass, com, words", [
    ("1e400", "[0.1, 0, 0]", ["'mass'", "too large"]),  # YAML 1.1 reads it as text: an expression
    ("1.0e+400", "[0.1, 0, 0]", ["'mass'", "finite"]),  # a YAML float: infinity
    ("1e300", "[1e300, 0, 0]", ["'mass'", "too large"]),
    ("'1e300*1e300'", "[0.1, 0, 0]", ["'mass'", "too large"]),
])
def test_overflowing_values(workspace, capsys, mass, com, words):
    links = [f"{{joint: revolute, a: 0.4, alpha: 0, d: 0, theta: 0, mass: {mass}, com: {com}}}"]
    (workspace / "r.yaml").write_text(robot_text(links=links))
    (line,), _ = run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out"], capsys, 1)
    for word in words:
        assert word in line
    assert not (workspace / "out").exists()


def test_constant_beyond_float_range(workspace, capsys):
    """A constant beyond FLT_MAX: the float C (whose literal would be inf) is refused, double is
    fine.  (Products of in-range constants that overflow at run time are the arithmetic's own
    inf, as for any non-finite input.)"""
    links = ["{joint: revolute, a: 1, alpha: 0, d: 0, theta: 0, mass: 1e39, com: [0.5, 0, 0]}"]
    (workspace / "r.yaml").write_text(robot_text(links=links, extra="gravity: [0, -9.81, 0]\n"))
    (line,), _ = run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out", "--precision", "float",
                          "--functions", "gravity", "--no-cache"], capsys, 1)
    assert "not finite in float precision" in line
    run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out", "--functions", "gravity",
             "--quiet", "--no-cache"], capsys, 0)


# ---------------------------------------------------------------------------------------------
# 8. No traceback, ever

def test_scene_lock_nan_and_payload_named_link(workspace, capsys):
    links = ["{joint: revolute, a: 0.4, alpha: 0, d: 0, theta: 0, mass: 2, com: [0.2, 0, 0]}",
             "{name: payload, joint: revolute, a: 0.3, alpha: 0, d: 0, theta: 0, mass: 1, com: [0.1, 0, 0], "
             "inertia: [0.01, 0.01, 0.01, 0, 0, 0]}"]
    (workspace / "r.yaml").write_text(robot_text(links=links))
    (workspace / "nan.yaml").write_text("scene: 1\nrobot: r.yaml\nlock: {2: .nan}\n")
    (line,), _ = run_cli(["generate", workspace / "nan.yaml", "--out", workspace / "out"], capsys, 1)
    assert "lock.2" in line and "finite" in line
    (workspace / "pay.yaml").write_text("scene: 1\nrobot: r.yaml\nfunctions: [gravity]\n"
                                       "payload: {mass: 0.5, com: [0.05, 0, 0]}\n")
    run_cli(["generate", workspace / "pay.yaml", "--out", workspace / "out", "--quiet", "--no-cache"], capsys, 0)


def test_internal_errors_are_one_line(workspace, capsys, monkeypatch):
    """The last line of defence: an unexpected exception is one line and exit status 3."""
    import symdyn.cli.generate as generate

    def broken(*args, **kwargs):
        raise ZeroDivisionError("boom\nsecond line")
    monkeypatch.setattr(generate, "generate", broken)
    assert main(["generate", str(REPO / "robots" / "planar2r.yaml"), "--out", str(workspace / "o")]) == 3
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("symdyn: internal error: ZeroDivisionError: boom second line")


def test_generated_c_compiles_under_sanitizers(massless_first_link, tmp_path):
    """The checked forward dynamics is clean under ASan/UBSan (float-cast-overflow included)
    for singular, non-finite and huge inputs."""
    libs, eqs = massless_first_link
    from symdyn.emit.cgen import generate_c
    files = generate_c(eqs, None, "float")
    stdout = run_sanitized(tmp_path, """
#include <math.h>
#include <stdio.h>
#include "hostile_dynamics.h"
int main(void) {
    const float qs[4][2] = {{0.3F, 0.0F}, {0.3F, 1.0F}, {0.3F, NAN}, {1e30F, 3e38F}};
    const float qd[2] = {0.1F, 0.2F}, tau[2] = {3e38F, -3e38F};
    int k;
    for (k = 0; k < 4; ++k) {
        float qdd[2] = {7.0F, 7.0F};
        int status = hostile_forward_dynamics_checked(qs[k], qd, tau, qdd);
        printf("%d %g %g\\n", status, (double)qdd[0], (double)qdd[1]);
    }
    {   /* the regular pose with ordinary torques: solved */
        const float torque[2] = {1.0F, -2.0F};
        float qdd[2] = {7.0F, 7.0F};
        int status = hostile_forward_dynamics_checked(qs[1], qd, torque, qdd);
        printf("%d %g %g\\n", status, (double)qdd[0], (double)qdd[1]);
    }
    return 0;
}
""", files)
    rows = [line.split() for line in stdout.split("\n") if line.strip()]
    statuses = [int(row[0]) for row in rows]
    # singular pose: 1; regular pose, torques of 3e38 N m: the accelerations overflow float, 2;
    # NaN in q: 2 (an input not finite, checked first); huge q and torques: nonzero; regular and ordinary: 0
    assert statuses[:3] == [1, 2, 2] and statuses[3] != 0 and statuses[4] == 0, rows
    assert all(np.isfinite(float(x)) and float(x) != 7.0 for x in rows[4][1:]), rows  # solved, written
    assert all(row[1:] == ["7", "7"] for row in rows if row[0] != "0"), rows  # not written on a status


def test_round_two_internal_errors_are_one_line(workspace, capsys):
    """Inputs that ended in internal errors: a non-real number, a platform printout at a twist
    of 1e300, a negative seed, and a URDF with an xmlns on <robot> (which the reference's own
    leaf search once failed on): each a one-line error, or for the URDF a clean verify."""
    link = "{joint: revolute, a: 0.4, alpha: 0, d: 0, theta: 0, mass: '(-8)**(1/3)', com: [0.2, 0, 0], inertia: 0}"
    (workspace / "r.yaml").write_text(robot_text(links=[link]))
    (line,), _ = run_cli(["generate", workspace / "r.yaml", "--out", workspace / "out"], capsys, 1)
    assert "field 'mass'" in line and "has no real value" in line
    (line,), _ = run_cli(["derive", REPO / "robots" / "parallel" / "sru_platform.yaml", "--twist", "1e300,0,0,0,0,0"],
                         capsys, 1)
    assert "--twist" in line and "at most 1e+09" in line
    text = (REPO / "tests" / "data" / "urdf" / "handmade.urdf").read_text().replace(
        "<robot ", '<robot xmlns="http://www.ros.org" ', 1)
    (workspace / "ns.urdf").write_text(text)
    assert main(["verify", str(workspace / "ns.urdf"), "--states", "3"]) == 0
    captured = capsys.readouterr()
    # the tip is found as symdyn finds it (symdyn.model.urdf.default_tip, namespaces read), and
    # Pinocchio's own parser reads the file: compared against it, no warning
    assert not captured.err.strip(), captured.err
    assert "against Pinocchio's own URDF parser" in captured.out and "FAIL" not in captured.out


def test_urdf_that_urdfdom_chokes_on_is_verified_quietly(workspace, capsys):
    """A URDF with 100,000 nested unknown elements and one with a mesh scale of 1e400 (urdfdom
    printed errors, then an internal error): verify answers with at most one warning line and
    compares every requested function."""
    text = (REPO / "tests" / "data" / "urdf" / "handmade.urdf").read_text()
    nested = text.replace('<link name="world"/>', '<link name="world"/>' + "<x>" * 100000 + "</x>" * 100000, 1)
    mesh = text.replace('<link name="base_link">', '<link name="base_link"><visual><geometry><mesh '
                        'filename="package://a/b.stl" scale="1e400 1 1"/></geometry></visual>', 1)
    for name, body in (("nested", nested), ("mesh", mesh)):
        (workspace / f"{name}.urdf").write_text(body)
        assert main(["verify", str(workspace / f"{name}.urdf"), "--states", "3", "--functions", "gravity,jacobian"]) == 0
        captured = capsys.readouterr()
        err = captured.err.strip().splitlines()
        assert len(err) <= 1 and all(line.startswith("symdyn: warning: ") for line in err), err
        assert captured.out.count(" ok") == 2 and "FAIL" not in captured.out, captured.out


def test_memory_budget_stops_a_derivation_in_one_line(workspace, capsys):
    """--max-memory bounds the run's memory: chain12 needs about 110 MB, so at 0.1 GB the
    derivation stops with one line naming the option, and nothing is written; in process, the
    limit is lifted again after main returns."""
    import resource
    import subprocess
    import sys
    argv = [sys.executable, "-m", "symdyn", "generate", str(REPO / "robots" / "chain12.yaml"),
            "--out", str(workspace / "out"), "--no-cache", "--quiet", "--max-memory", "0.1"]
    result = subprocess.run(argv, capture_output=True, text=True, timeout=120)
    assert result.returncode == 1, result.stderr[-2000:]
    assert result.stderr.strip() == ("symdyn: error: out of memory: the run needed more than --max-memory 0.1 GB "
                                     "(a very large robot, or many functions: raise --max-memory, or ask for fewer "
                                     "--functions)")
    assert not (workspace / "out").exists()
    before = resource.getrlimit(resource.RLIMIT_DATA)
    run_cli(["generate", REPO / "robots" / "planar2r.yaml", "--out", workspace / "small", "--quiet",
             "--functions", "gravity", "--max-memory", "64"], capsys, 0)
    assert resource.getrlimit(resource.RLIMIT_DATA) == before


def test_long_flat_expressions_are_read_deep_ones_refused(workspace, capsys):
    """A sum of 100 terms is flat (read, no "nested too deeply"); 230 unary minus signs are
    nested 230 deep: one line naming the file, link and field."""
    extra = "parameters: {a: 0.001}\n"
    flat = "{joint: revolute, a: '" + "+".join(["a"] * 100) + "', alpha: 0, d: 0, theta: 0, mass: 1, com: [0.2, 0, 0], inertia: 0}"
    (workspace / "flat.yaml").write_text(robot_text(links=[flat], extra=extra))
    run_cli(["generate", workspace / "flat.yaml", "--out", workspace / "flat", "--no-cache", "--quiet"], capsys, 0)
    deep = "{joint: revolute, a: 0.4, alpha: '" + "-" * 230 + "1', d: 0, theta: 0, mass: 1, com: [0.2, 0, 0], inertia: 0}"
    (workspace / "deep.yaml").write_text(robot_text(links=[deep]))
    (line,), _ = run_cli(["generate", workspace / "deep.yaml", "--out", workspace / "deep"], capsys, 1)
    assert "deep.yaml" in line and "field 'alpha'" in line and "nested more than" in line


def test_round_two_small_files_that_ran_for_minutes(workspace, capsys):
    """A power of a sum that expands to 47,905 terms (287 bytes: 120 s and 1 GB before),
    parameters defined by repeated products of earlier ones (exact numbers doubling their digits:
    still running at 180 s before), and a closed-form printout of 12 joints: each refused in one
    line within seconds."""
    import time
    runtime = "parameters: {a: {runtime: true}, b: {runtime: true}, c: {runtime: true}, d: {runtime: true}}\n"
    link = "{joint: revolute, a: 0.4, alpha: '(a+b+c+d)**64', d: 0, theta: 0, mass: 1, com: [0.2, 0, 0], inertia: 0}"
    (workspace / "power.yaml").write_text(robot_text(links=[link], extra=runtime))
    chain = "parameters:\n  x0: 0.3\n" + "".join(f"  x{i}: x{i - 1}*x{i - 1}\n" for i in range(1, 41))
    link = "{joint: revolute, a: x40, alpha: 0, d: 0, theta: 0, mass: 1, com: [0.2, 0, 0], inertia: 0}"
    (workspace / "chain.yaml").write_text(robot_text(links=[link], extra=chain))
    cases = [(["generate", workspace / "power.yaml", "--out", workspace / "out"], "expands to 47905 terms"),
             (["generate", workspace / "chain.yaml", "--out", workspace / "out"], "more than 1000 digits"),
             (["derive", REPO / "robots" / "chain12.yaml", "--form", "closed"], "--form closed")]
    for argv, needle in cases:
        (line,), seconds = run_cli(argv, capsys, 1)
        assert needle in line and seconds < 10, (argv, line, seconds)  # CPU seconds
    assert not (workspace / "out").exists()


def test_nearly_singular_mass_matrix_is_a_warning_exact_zero_an_error(workspace, capsys):
    """A wrist whose point mass sits 1e-7 m off its axis, 1 m away along it (D[2,2] = 1e-14 of
    the inertia joint 2 could move): numerically zero in double, not zero in the model, so a
    warning and forward dynamics generated; the same mass exactly on the axis is refused when
    forward dynamics is asked for (by default the other functions are generated, with a warning)."""
    def links(offset):
        return ["{joint: revolute, a: 0.4, alpha: 0, d: 0, theta: 0, mass: 1, com: [-0.2, 0, 0], inertia: 0}",
                f"{{joint: revolute, a: {offset}, alpha: 0, d: 1, theta: 0, mass: 1, com: [0, 0, 0], inertia: 0}}"]
    (workspace / "near.yaml").write_text(robot_text(links=links("1e-7")))
    err, _ = run_cli(["generate", workspace / "near.yaml", "--out", workspace / "near", "--no-cache"], capsys, 0)
    warning = [line for line in err if "nearly singular" in line]
    assert len(warning) == 1 and "near.yaml" in warning[0] and "joint 2" in warning[0], err
    assert "hostile_forward_dynamics" in (workspace / "near" / "hostile_dynamics.h").read_text()
    (workspace / "exact.yaml").write_text(robot_text(links=links("0")))
    (line,), _ = run_cli(["generate", workspace / "exact.yaml", "--out", workspace / "exact", "--no-cache",
                          "--functions", "forward_dynamics"], capsys, 1)
    assert "exact.yaml: forward dynamics: D[2,2] is identically 0: joint 2" in line
    assert not (workspace / "exact").exists()


def test_coaxial_links_of_very_different_inertia_are_not_singular(workspace, capsys):
    """Two coaxial links, 1e9 and 0.01 kg m^2 about the shared axis: D is regular (the second
    joint moves 0.01 kg m^2), so forward dynamics is generated and agrees with Pinocchio; the
    singularity check judges each joint against the inertia its own subtree could have, not
    against the largest diagonal entry."""
    links = ["{joint: revolute, a: 0, alpha: 0, d: 0, theta: 0, mass: 1, com: [0, 0, 0], inertia: [1e9, 1e9, 1e9, 0, 0, 0]}",
             "{joint: revolute, a: 0, alpha: 0, d: 0.1, theta: 0, mass: 1, com: [0, 0, 0], inertia: [0.01, 0.01, 0.01, 0, 0, 0]}"]
    (workspace / "coax.yaml").write_text(robot_text(links=links))
    run_cli(["generate", workspace / "coax.yaml", "--out", workspace / "out", "--quiet", "--no-cache"], capsys, 0)
    assert (workspace / "out" / "hostile_dynamics.c").is_file()
    assert main(["verify", str(workspace / "coax.yaml"), "--functions", "forward_dynamics,mass_matrix",
                 "--states", "5"]) == 0


def test_warnings_are_concise_once_per_run_and_wrapped_on_a_terminal(workspace, capsys, monkeypatch):
    """A URDF leg whose other leg is locked: verify reads the file more than once, the warning is
    printed once, in one line when standard error is not a terminal; on a terminal of 60
    columns it is wrapped (indented continuation lines, none wider); from Python the warning is
    a SymdynWarning shown once, with no line of symdyn's source under it."""
    import io
    import subprocess
    import sys
    from symdyn.cli import _wrapped
    urdf = REPO / "tests" / "data" / "urdf" / "shared_names.urdf"
    assert main(["verify", str(urdf), "--tip", "FOOT", "--states", "2", "--functions", "gravity"]) == 0
    err = [line for line in capsys.readouterr().err.splitlines() if line.startswith("symdyn: warning: ")]
    assert len(err) == 1 and "'RHAA' are off the chain to 'FOOT': locked at 0" in err[0], err
    assert "never move" not in err[0] and len(err[0]) < 200

    class Terminal(io.StringIO):
        def isatty(self):
            return True
    monkeypatch.setattr(sys, "stderr", Terminal())
    monkeypatch.setenv("COLUMNS", "60")
    text = _wrapped("symdyn: warning: " + err[0][len("symdyn: warning: "):])
    lines = text.splitlines()
    assert len(lines) >= 3 and all(len(line) <= 59 for line in lines), lines
    assert all(line.startswith("    ") for line in lines[1:]) and " ".join(l.strip() for l in lines) == err[0]
    monkeypatch.undo()
    code = f"import symdyn\nfor _ in range(3):\n    symdyn.load({str(urdf)!r}, tip='FOOT')\n"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0 and result.stderr.strip().splitlines() == [
        f"symdyn:0: SymdynWarning: {urdf}: joints 'RHAA' are off the chain to 'FOOT': locked at 0, their links "
        "(1 kg) left out with the fixed base"], result.stderr
