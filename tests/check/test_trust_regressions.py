"""Regression tests of faults found on robots nobody here wrote (random URDF trees, published
tables): each reproducer as it was reported, through the command line a user runs.

- the derivative loops printed a negation before printed text (``--cos(2.06...)``: no compile;
  ``-(a - b)`` as ``-a - b``: wrong numbers on a tree);
- the derivation cache's key left out the frames: a second run with other frames got the
  first run's frame code.
"""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from helpers import REPO
from symdyn.cli import main

DATA = REPO / "tests" / "data" / "urdf"
DERIVATIVES = "inverse_dynamics_dq,inverse_dynamics_dqd,forward_dynamics_dq,forward_dynamics_dqd,mass_matrix_inverse"


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(tmp_path / "cache"))


@pytest.mark.parametrize("robot", [pytest.param("derivatives_chain", marks=pytest.mark.slow), "derivatives_tree"])
def test_derivatives_compile_and_agree(robot, capsys):
    if shutil.which("cc") is None:
        pytest.skip("no C compiler")
    pytest.importorskip("pinocchio")
    status = main(["verify", str(DATA / f"{robot}.urdf"), "--functions", DERIVATIVES, "--states", "12"])
    out = capsys.readouterr().out
    assert status == 0, out
    assert out.count(" ok") == len(DERIVATIVES.split(",")), out


@pytest.mark.slow
def test_derivative_c_has_no_constant_calls_and_builds_strict(tmp_path):
    if shutil.which("cc") is None:
        pytest.skip("no C compiler")
    assert main(["generate", str(DATA / "derivatives_chain.urdf"), "--name", "dchain", "--functions",
                 "inverse_dynamics_derivatives,forward_dynamics_derivatives", "--out", str(tmp_path / "c")]) == 0
    source = re.sub(r"/\*.*?\*/", "", (tmp_path / "c" / "dchain_dynamics.c").read_text(), flags=re.S)
    assert "cos(2.064540186490215)" not in source and "--" not in source
    built = subprocess.run(["cc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-c",
                            str(tmp_path / "c" / "dchain_dynamics.c"), "-o", str(tmp_path / "d.o")],
                           capture_output=True, text=True)
    assert built.returncode == 0, built.stderr[:2000]


def test_frames_change_the_cached_code(tmp_path, capsys):
    """The reproducer of the stale frame code: FL_FOOT then HR_FOOT (then two frames) through
    one cache give what a run without the cache gives."""
    from helpers import example_robot_data
    solo = example_robot_data("solo_description/robots/solo12.urdf")
    runs = [("FL_FOOT", "a", []), ("HR_FOOT", "b", []), ("HR_FOOT", "c", ["--no-cache"]),
            ("FL_FOOT,HR_FOOT", "d", []), ("FL_FOOT,HR_FOOT", "e", ["--no-cache"])]
    for frames, out, extra in runs:
        assert main(["generate", solo, "--floating-base", "--frames", frames, "--functions",
                     "frame_poses,frame_jacobians", "--out", str(tmp_path / out)] + extra) == 0, capsys.readouterr()
    read = {out: (tmp_path / out / "solo_dynamics.c").read_bytes() for _, out, _ in runs}
    assert read["a"] != read["b"]
    assert read["b"] == read["c"]
    assert read["d"] == read["e"]


def test_verify_all_checks_every_supported_function(capsys):
    """``verify --all``: every function the robot supports, each in the table and within the
    tolerance (the derivatives' fault was in functions ``verify`` did not check by default)."""
    if shutil.which("cc") is None:
        pytest.skip("no C compiler")
    pytest.importorskip("pinocchio")
    import symdyn
    from helpers import robot_path
    from symdyn.model.outputs import supported_outputs
    path = robot_path("three_standard")
    expected = supported_outputs(symdyn.load(path))
    status = main(["verify", path, "--all", "--states", "10"])
    out = capsys.readouterr().out
    assert status == 0, out
    rows = {line.split()[0] for line in out.splitlines() if line.endswith(" ok")}
    task = {"task_mass_matrix", "task_bias", "task_gravity", "task_inverse"}  # a 3-joint arm has no 6-row task
    assert rows | task >= set(expected) and set(expected) - rows <= task, out
    assert "inverse_dynamics_dq" in rows and "base_regressor" in rows
    assert main(["verify", path, "--all", "--functions", "gravity"]) == 1
    assert "give one" in capsys.readouterr().err
