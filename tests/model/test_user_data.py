"""Users' own robot data: published models generate (with warnings), real mistakes are named,
nothing is misread silently, and the small things a user hits behave."""

from __future__ import annotations

import numpy as np
import pytest

import symdyn
from helpers import REPO
from symdyn.cli import main

FIVE = "inverse_dynamics,mass_matrix,coriolis,coriolis_matrix,gravity"

# Corke's Robotics Toolbox, mdl_puma560 (Armstrong, Khatib and Burdick 1986): link 1 has only
# Iyy = 0.35 and link 3's moments (0.066, 0.086, 0.0125) break the triangle inequality as well.
TOOLBOX_PUMA = """\
format: 1
name: puma_toolbox
convention: standard
links:
  - {joint: revolute, a: 0, alpha: pi/2, d: 0, theta: 0, mass: 0, inertia: [0, 0.35, 0, 0, 0, 0]}
  - {joint: revolute, a: 0.4318, alpha: 0, d: 0, theta: 0, mass: 17.4, com: [-0.3638, 0.006, 0.2275],
     inertia: [0.13, 0.524, 0.539, 0, 0, 0]}
  - {joint: revolute, a: 0.0203, alpha: -pi/2, d: 0.15005, theta: 0, mass: 4.8, com: [-0.0203, -0.0141, 0.070],
     inertia: [0.066, 0.086, 0.0125, 0, 0, 0]}
  - {joint: revolute, a: 0, alpha: pi/2, d: 0.4318, theta: 0, mass: 0.82, com: [0, 0.019, 0],
     inertia: [1.8e-3, 1.3e-3, 1.8e-3, 0, 0, 0]}
  - {joint: revolute, a: 0, alpha: -pi/2, d: 0, theta: 0, mass: 0.34, inertia: [0.3e-3, 0.4e-3, 0.3e-3, 0, 0, 0]}
  - {joint: revolute, a: 0, alpha: 0, d: 0, theta: 0, mass: 0.09, com: [0, 0, 0.032],
     inertia: [0.15e-3, 0.15e-3, 0.04e-3, 0, 0, 0]}
"""

# The toolbox's mdl_ur5: point masses only; link 6's lies on joint 6's axis, so D[6,6] = 0.
TOOLBOX_UR5 = """\
format: 1
name: ur5_points
convention: standard
links:
  - {joint: revolute, a: 0, alpha: pi/2, d: 0.089459, theta: 0, mass: 3.7, com: [0, -0.02561, 0.00193], inertia: 0}
  - {joint: revolute, a: -0.425, alpha: 0, d: 0, theta: 0, mass: 8.393, com: [0.2125, 0, 0.11336], inertia: 0}
  - {joint: revolute, a: -0.39225, alpha: 0, d: 0, theta: 0, mass: 2.275, com: [0.15, 0, 0.0265], inertia: 0}
  - {joint: revolute, a: 0, alpha: pi/2, d: 0.10915, theta: 0, mass: 1.219, com: [0, -0.0018, 0.01634], inertia: 0}
  - {joint: revolute, a: 0, alpha: -pi/2, d: 0.09465, theta: 0, mass: 1.219, com: [0, 0.0018, 0.01634], inertia: 0}
  - {joint: revolute, a: 0, alpha: 0, d: 0.0823, theta: 0, mass: 0.1879, com: [0, 0, -0.001159], inertia: 0}
"""


def stderr_lines(capsys):
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    return captured.out, captured.err.strip().splitlines()


def test_toolbox_puma560_generates_with_warnings_and_agrees_with_pinocchio(tmp_path, capsys):
    robot = tmp_path / "puma_toolbox.yaml"
    robot.write_text(TOOLBOX_PUMA)
    assert main(["generate", str(robot), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    _, lines = stderr_lines(capsys)
    assert len(lines) == 2 and all(line.startswith("symdyn: warning: ") for line in lines), lines
    assert "link 1 ('j1'): field 'inertia'" in lines[0] and "triangle inequality" in lines[0]
    assert "link 3 ('j3'): field 'inertia'" in lines[1]
    assert (tmp_path / "out" / "puma_toolbox_dynamics.c").is_file()
    assert main(["verify", str(robot), "--states", "10"]) == 0  # every function within 1e-10
    out, _ = stderr_lines(capsys)
    assert out.count(" ok") == 9 and "FAIL" not in out
    assert main(["generate", str(robot), "--out", str(tmp_path / "strict"), "--strict"]) == 1
    _, lines = stderr_lines(capsys)
    assert len(lines) == 1 and lines[0].startswith("symdyn: error: ") and "triangle" in lines[0]
    assert "(--strict)" in lines[0] and not (tmp_path / "strict").exists()


def test_point_mass_ur5_refuses_forward_dynamics_only(tmp_path, capsys):
    robot = tmp_path / "ur5_points.yaml"
    robot.write_text(TOOLBOX_UR5)
    # asked for, forward dynamics is refused in one line; by default the rest is generated, with a warning
    assert main(["generate", str(robot), "--out", str(tmp_path / "fd"), "--functions", "forward_dynamics"]) == 1
    _, lines = stderr_lines(capsys)
    assert len(lines) == 1
    assert lines[0].startswith(f"symdyn: error: {robot}: forward dynamics: D[6,6] is identically 0: joint 6")
    assert "armature" in lines[0] and "leave forward_dynamics out" in lines[0]
    assert main(["generate", str(robot), "--out", str(tmp_path / "all")]) == 0
    _, lines = stderr_lines(capsys)
    assert [line for line in lines if "D[6,6] is identically 0" in line and "forward_dynamics left out" in line]
    assert main(["generate", str(robot), "--out", str(tmp_path / "five"), "--functions", FIVE, "--quiet"]) == 0
    assert stderr_lines(capsys)[1] == []  # inertia: 0 says point masses: no warning
    assert main(["verify", str(robot), "--functions", FIVE, "--states", "10"]) == 0
    out, _ = stderr_lines(capsys)
    assert out.count(" ok") == 5 and "FAIL" not in out
    # with an armature on joint 6 the model is fine for forward dynamics too
    fixed = tmp_path / "ur5_armature.yaml"
    fixed.write_text(TOOLBOX_UR5.replace("com: [0, 0, -0.001159], inertia: 0}", "com: [0, 0, -0.001159], inertia: 0, armature: 0.01}"))
    assert main(["generate", str(fixed), "--out", str(tmp_path / "arm"), "--quiet", "--functions", "forward_dynamics"]) == 0


BASE = """\
format: 1
name: user
convention: standard
{top}links:
  - {{joint: revolute, a: 0.3, alpha: {alpha}, d: 0.1, theta: {theta}, mass: 2, com: [0.1, 0, 0]{inertia}}}
  - {{joint: revolute, a: 0.2, alpha: 0, d: 0, theta: 0, mass: 1, com: [0.1, 0, 0], inertia: [0.01, 0.01, 0.01, 0, 0, 0]}}
"""


def write(tmp_path, top="", alpha="pi/2", theta="0", inertia=", inertia: [0.02, 0.02, 0.02, 0, 0, 0]"):
    path = tmp_path / "user.yaml"
    path.write_text(BASE.format(top=top, alpha=alpha, theta=theta, inertia=inertia))
    return path


@pytest.mark.parametrize("change, words", [
    (dict(alpha="90"), ["link 1 ('j1'): field 'alpha'", "looks like degrees"]),
    (dict(theta="-180"), ["field 'theta'", "looks like degrees"]),
    (dict(top="angles: degrees\n", alpha="-pi/2"), ["link 1 ('j1'): field 'alpha'", "contains pi", "-1.5708 degrees", "(-90 if '-pi/2'"]),
    (dict(top="angles: degrees\nparameters: {quarter: pi/2}\n", alpha="90", theta="quarter"),
     ["field 'theta'", "contains pi", "(90 if 'pi/2' is in radians)"]),
    (dict(inertia=""), ["link 1 ('j1'): field 'inertia'", "point mass is assumed", "inertia: 0"]),
    (dict(inertia=", inertia: [0.1, 0.01, 0.01, 0, 0, 0]"), ["field 'inertia'", "triangle inequality"]),
])
def test_each_warning_is_one_line_and_strict_refuses(tmp_path, capsys, change, words):
    path = write(tmp_path, **change)
    assert main(["generate", str(path), "--out", str(tmp_path / "out"), "--quiet", "--functions", "gravity"]) == 0
    _, lines = stderr_lines(capsys)
    assert len(lines) == 1 and lines[0].startswith("symdyn: warning: ") and str(path) in lines[0]
    for word in words:
        assert word in lines[0]
    for command in (["generate", str(path), "--out", str(tmp_path / "s")], ["derive", str(path)]):
        assert main([*command, "--strict"]) == 1
        _, lines = stderr_lines(capsys)
        assert len(lines) == 1 and lines[0].startswith("symdyn: error: ")


def test_no_warning_for_clean_data(tmp_path, capsys):
    path = write(tmp_path, inertia=", inertia: 0")
    assert main(["generate", str(path), "--out", str(tmp_path / "out"), "--quiet", "--strict"]) == 0
    assert stderr_lines(capsys)[1] == []


def test_angles_in_degrees_equal_radians(tmp_path):
    radians = symdyn.load(write(tmp_path, alpha="pi/2", theta="pi/6"))
    (tmp_path / "deg").mkdir()
    degrees = symdyn.load(write(tmp_path / "deg", top="angles: degrees\n", alpha="90", theta="30"))
    assert [(l.alpha, l.theta) for l in degrees.links] == [(l.alpha, l.theta) for l in radians.links]


def test_scene_names_must_exist(tmp_path, capsys):
    scenes = REPO / "robots" / "scenes"
    text = (scenes / "ur5_payload.yaml").read_text().replace("robot: ../ur5.yaml", f"robot: {REPO / 'robots' / 'ur5.yaml'}")
    for old, new, words in (("runtime: [m_p, c_z]", "runtime: [mp, c_z]", ["field 'runtime'", "'mp'", "did you mean 'm_p'"]),
                            ("runtime: [m_p, c_z]\nvalues: {m_p: 1.0, c_z: 0.05}", "runtime: [c_z]\nvalues: {c_z: 0.05}",
                             ["field 'payload'", "'m_p'", "runtime:"]),
                            ("values: {m_p: 1.0, c_z: 0.05}", "values: {m_p: 1.0, c_z: 0.05, r2: 3}",
                             ["field 'values'", "no parameter 'r2'", "did you mean"])):
        scene = tmp_path / "scene.yaml"
        assert old in text
        scene.write_text(text.replace(old, new))
        assert main(["generate", str(scene), "--out", str(tmp_path / "out")]) == 1
        _, lines = stderr_lines(capsys)
        assert len(lines) == 1 and str(scene) in lines[0], lines
        for word in words:
            assert word in lines[0], lines[0]


def test_scene_lock_value_in_degrees_warns(tmp_path, capsys):
    scene = tmp_path / "scene.yaml"
    scene.write_text(f"scene: 1\nrobot: {REPO / 'robots' / 'puma560.yaml'}\nlock: {{6: 90}}\nfunctions: [gravity]\n")
    assert main(["generate", str(scene), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    _, lines = stderr_lines(capsys)
    assert len(lines) == 1 and "lock.6" in lines[0] and "looks like degrees" in lines[0]


def test_verify_honors_the_scene(capsys):
    assert main(["verify", str(REPO / "robots" / "scenes" / "puma560_gravity.yaml"), "--states", "3"]) == 0
    out, _ = stderr_lines(capsys)
    assert "float" in out.splitlines()[0] and "tolerance 0.0001" in out.splitlines()[0]
    lines = out.splitlines()
    header = next(k for k, line in enumerate(lines) if line.startswith("function "))
    rows = [line.split()[0] for line in lines[header + 1:]]
    assert rows == ["gravity"]


def test_bench_honors_the_scene(monkeypatch, capsys):
    from symdyn.check import bench
    seen = []
    monkeypatch.setattr(bench, "bench_robot", lambda robot, functions, variants, *a, **k: seen.append((functions, variants)) or [])
    assert main(["bench", str(REPO / "robots" / "scenes" / "puma560_gravity.yaml"), "--quiet"]) == 0
    (functions, variants), = seen
    assert functions == ("gravity",) and "ne-float" in variants and "ne-double" not in variants


def test_header_describes_parameters_and_constants(tmp_path):
    assert main(["generate", str(REPO / "robots" / "scenes" / "ur5_payload.yaml"), "--out", str(tmp_path), "--quiet"]) == 0
    header = (tmp_path / "ur5_payload_dynamics.h").read_text()
    assert "p[0] = m_p" in header and "link 6 (wrist_3): mass (kg), com (m)" in header
    assert "gravity = [0.0, 0.0, -9.81]" in header and "link 1 (shoulder_pan): revolute joint" in header
    assert "mass = 3.7; com = [0.0, -0.02561, 0.00193]" in header
    assert " 1 divisions" not in header and " 1 multiplications" not in header


def test_python_api_loads_scenes_and_checks_lengths():
    robot = symdyn.load(REPO / "robots" / "scenes" / "ur5_payload.yaml")
    assert robot.name == "ur5_payload" and [s.name for s in robot.parameters] == ["m_p", "c_z"]
    eqs = symdyn.derive(symdyn.load(REPO / "robots" / "planar2r.yaml"), outputs=["gravity"])
    p = np.linspace(0.5, 1.5, 8)
    assert eqs.numeric.gravity(np.zeros(2), p).shape == (2,)
    with pytest.raises(ValueError, match="q has 3 entries, expected 2"):
        eqs.numeric.gravity(np.zeros(3), p)
    with pytest.raises(ValueError, match="p has 2 entries, expected 8"):
        eqs.numeric.gravity(np.zeros(2), p[:2])
