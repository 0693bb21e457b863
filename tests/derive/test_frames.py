"""Named frames (a robot file's ``frames:``): frame_poses, frame_jacobians and
frame_jacobian_dot_v against Pinocchio's framesForwardKinematics, getFrameJacobian and
getFrameClassicalAcceleration (LOCAL_WORLD_ALIGNED) on a serial arm on a placed base, a kinematic
tree and a floating base, numpy and compiled C; and the field's errors."""

from __future__ import annotations

import numpy as np
import pytest

from symdyn.model.outputs import Dimensions
import symdyn
from helpers import REPO, TOL
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import PinocchioReference, compare
from symdyn.check.states import random_state
from symdyn.emit.cgen import generate_c
from symdyn.model.errors import SymdynError
from symdyn.model.outputs import FRAME_OUTPUTS

#: robot file -> the frames added to it: a link's own frame, frames fixed in links (rotated and
#: offset), a frame on the base
CASES = {
    "tests/data/general_arm.yaml": "  - flange\n  - {name: tip, link: slide, xyz: [0.1, 0.2, 0.3], rpy: [1, 2, 3]}\n"
                                   "  - {name: fixture, link: base, xyz: [0.5, 0, 0]}\n",
    "examples/trees/torso_two_arms.yaml": "  - l_wrist\n  - {name: r_grip, link: r_wrist, xyz: [0.02, -0.01, 0.12], "
                                          "rpy: [0.3, -0.2, 1.1]}\n  - {name: chest, link: torso, xyz: [0.1, 0.05, 0.3]}\n",
    "examples/trees/space_robot.yaml": "  - l_wrist\n  - {name: r_grip, link: r_slide, xyz: [0.02, -0.01, 0.12], "
                                       "rpy: [0.3, -0.2, 1.1]}\n  - {name: antenna, link: base, xyz: [0.1, 0.3, 0.7], "
                                       "rpy: [0.2, 0.5, 0]}\n",
}


def _with_frames(tmp_path, source: str, frames: str) -> str:
    text = (REPO / source).read_text().replace("gravity: [0, 0, 0]", "gravity: [0.3, -1.2, -9.81]")
    assert "\nlinks:\n" in text
    path = tmp_path / "robot.yaml"
    path.write_text(text.replace("\nlinks:\n", f"\nframes:\n{frames}links:\n", 1))
    return str(path)


@pytest.mark.parametrize("source", sorted(CASES), ids=lambda path: path.rsplit("/", 1)[-1][:-5])
def test_frames_agree_with_pinocchio(tmp_path, source):
    """Every frame output at 50 states in numpy and in the C of frame_kinematics (the three in
    one call, equal to the single functions up to rounding); the frames are the default outputs' last ones."""
    from symdyn.model.outputs import default_outputs
    robot = symdyn.load(_with_frames(tmp_path, source, CASES[source]))
    assert len(robot.frames) == 3 and default_outputs(robot)[-3:] == FRAME_OUTPUTS
    eqs = symdyn.derive(robot, outputs=FRAME_OUTPUTS)
    reference = PinocchioReference(robot)
    rng = np.random.default_rng(7)
    states = [random_state(robot, rng) for _ in range(50)]
    errors = compare(eqs.numeric, reference, states, FRAME_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), errors
    files = generate_c(eqs, FRAME_OUTPUTS + ("frame_kinematics",), "double")
    header = files[f"{robot.name}_dynamics.h"]
    assert f"#define {robot.name.upper()}_NFRAMES 3" in header
    lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
    errors = compare(lib, reference, states, FRAME_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), errors
    if source.endswith("general_arm.yaml"):  # float all the way: within float's precision
        (tmp_path / "float").mkdir()
        single = build_and_load(generate_c(eqs, FRAME_OUTPUTS, "float"), robot.name, Dimensions.of(robot), 0, "float",
                                workdir=str(tmp_path / "float"))
        rounded = [[np.asarray(x, dtype=np.float32).astype(float) for x in state] for state in states[:10]]
        errors = compare(single, reference, rounded, FRAME_OUTPUTS)
        assert all(e <= 2e-5 for e in errors.values()), errors
    q, qd, _, _ = states[0]
    for together, alone in zip(lib.frame_kinematics(q, qd),
                               (lib.frame_poses(q), lib.frame_jacobians(q), lib.frame_jacobian_dot_v(q, qd))):
        np.testing.assert_allclose(together, alone, rtol=0, atol=1e-14)  # the same up to rounding


def test_frame_field_errors(tmp_path):
    """Each mistake in ``frames:`` is refused in one line naming the file and the field; a robot
    without frames cannot have the frame functions."""
    source = "examples/trees/torso_two_arms.yaml"
    for frames, expected in (("  - l_wirst\n", ["frames[0]", "did you mean 'l_wrist'?"]),
                             ("  - {name: g, link: r_wirst}\n", ["frames[0].link", "did you mean 'r_wrist'?"]),
                             ("  - {name: torso, link: base}\n", ["frames[0].name", "name of a link"]),
                             ("  - {name: g, link: base, xyz: [m, 0, 0]}\n", ["frames[0]"]),
                             ("  - {name: g, link: base, spin: 1}\n", ["frames[0].spin", "unknown key"]),
                             ("  - l_wrist\n  - l_wrist\n", ["'l_wrist' is listed twice"])):
        path = _with_frames(tmp_path, source, frames)
        with pytest.raises(SymdynError) as caught:
            symdyn.load(path)
        message = str(caught.value)
        assert all(part in message for part in expected) and "\n" not in message, (frames, message)
    robot = symdyn.load(str(REPO / source))
    with pytest.raises(SymdynError, match="the frame functions need frames") as caught:
        symdyn.derive(robot, outputs=["frame_poses"])
    assert "\n" not in str(caught.value)


def test_frames_on_locked_links_ride_on_their_moving_ancestor(tmp_path):
    """A scene locking joints of the tree: the frames keep their poses, Jacobians (the kept
    joints' columns) and J-dot v, as the full robot gives them with the locked joints at their
    values and at rest."""
    source = "examples/trees/torso_two_arms.yaml"
    path = _with_frames(tmp_path, source, CASES[source])
    scene = tmp_path / "scene.yaml"
    scene.write_text("scene: 1\nrobot: robot.yaml\nlock: {r_wrist: 0.4, l_elbow: -0.3}\n")
    locked = symdyn.load(str(scene))
    full = symdyn.load(path)
    assert [f.name for f in locked.frames] == [f.name for f in full.frames]
    kept = [k for k, link in enumerate(full.links) if link.name not in ("r_wrist", "l_elbow")]
    mine = symdyn.derive(locked, outputs=FRAME_OUTPUTS).numeric
    theirs = symdyn.derive(full, outputs=FRAME_OUTPUTS).numeric
    rng = np.random.default_rng(4)
    for _ in range(5):
        q, qd = rng.uniform(-3, 3, locked.dof), rng.uniform(-2, 2, locked.dof)
        qf, qdf = np.zeros(full.dof), np.zeros(full.dof)
        qf[kept], qdf[kept] = q, qd
        qf[[k for k, link in enumerate(full.links) if link.name == "r_wrist"]] = 0.4
        qf[[k for k, link in enumerate(full.links) if link.name == "l_elbow"]] = -0.3
        np.testing.assert_allclose(mine.frame_poses(q), theirs.frame_poses(qf), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(mine.frame_jacobians(q), theirs.frame_jacobians(qf)[:, kept], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(mine.frame_jacobian_dot_v(q, qd), theirs.frame_jacobian_dot_v(qf, qdf),
                                   rtol=1e-12, atol=1e-12)


SOLO_FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]


def test_solo12_feet_agree_with_pinocchio_urdf_parser(tmp_path, capsys):
    """Solo-12's four feet (links merged by fixed joints into the lower legs) on the free-flyer,
    against Pinocchio's own reading of the URDF (its body frames of the same names), at 50
    states in numpy and C; the same through a scene's ``frames:`` and through ``symdyn verify
    --frames``; a misspelt link gets did-you-mean."""
    from symdyn.check.pinocchio_model import UrdfReference
    from symdyn.cli import main
    from helpers import example_robot_data
    from test_trees import SOLO
    path = example_robot_data(SOLO)
    robot = symdyn.load(path, floating_base=True, frames=SOLO_FEET)
    assert [(f.name, robot.links[f.link].name) for f in robot.frames] == [
        ("FL_FOOT", "FL_KFE"), ("FR_FOOT", "FR_KFE"), ("HL_FOOT", "HL_KFE"), ("HR_FOOT", "HR_KFE")]
    eqs = symdyn.derive(robot, outputs=FRAME_OUTPUTS)
    reference = UrdfReference(path, floating_base=True, frames=SOLO_FEET)
    rng = np.random.default_rng(11)
    states = [random_state(robot, rng) for _ in range(50)]
    errors = compare(eqs.numeric, reference, states, FRAME_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), errors
    lib = build_and_load(generate_c(eqs, FRAME_OUTPUTS, "double"), robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
    errors = compare(lib, reference, states, FRAME_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), errors
    scene = tmp_path / "solo.yaml"
    scene.write_text(f"scene: 1\nrobot: {path}\nfloating_base: true\nframes: [{', '.join(SOLO_FEET)}]\n")
    assert symdyn.load(str(scene)).frames == robot.frames
    assert main(["verify", path, "--floating-base", "--frames", ",".join(SOLO_FEET[:2]), "--functions",
                 "frame_jacobians", "--states", "10"]) == 0
    assert "frame_jacobians" in capsys.readouterr().out
    with pytest.raises(SymdynError, match="did you mean 'FL_FOOT'"):
        symdyn.load(path, floating_base=True, frames=["FL_FOTO"])


def test_talos_feet_and_hands_agree_with_pinocchio_urdf_parser():
    """TALOS reduced on the free-flyer: its soles and grippers' base links."""
    from symdyn.check.pinocchio_model import UrdfReference
    from helpers import example_robot_data
    path = example_robot_data("talos_data/robots/talos_reduced.urdf")
    names = ["left_sole_link", "right_sole_link", "gripper_left_base_link", "gripper_right_base_link"]
    robot = symdyn.load(path, floating_base=True, frames=names)
    eqs = symdyn.derive(robot, outputs=FRAME_OUTPUTS)
    rng = np.random.default_rng(12)
    states = [random_state(robot, rng) for _ in range(50)]
    errors = compare(eqs.numeric, UrdfReference(path, floating_base=True, frames=names), states, FRAME_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), errors


def test_command_line_frames_select_a_robot_files_frames(tmp_path):
    """--frames (symdyn.load(frames=...)) picks from a robot file's links and its frames:, in the
    order given."""
    source = "examples/trees/torso_two_arms.yaml"
    path = _with_frames(tmp_path, source, CASES[source])
    robot = symdyn.load(path, frames=["chest", "r_elbow"])
    assert [(f.name, f.link) for f in robot.frames] == [("chest", 0), ("r_elbow", 5)]
    with pytest.raises(SymdynError, match="did you mean 'r_elbow'"):
        symdyn.load(path, frames=["r_elbw"])


def test_frames_survive_conversion_to_urdf(tmp_path):
    """convert --to urdf writes each frame as a link on a fixed joint; read back with --frames,
    the frames give the same poses, Jacobians and J-dot v (the satellite on its floating base)."""
    from symdyn.emit.urdf import robot_to_urdf
    source = "examples/trees/space_robot.yaml"
    robot = symdyn.load(_with_frames(tmp_path, source, CASES[source]))
    urdf = tmp_path / "satellite.urdf"
    urdf.write_text(robot_to_urdf(robot))
    back = symdyn.load(str(urdf), floating_base=True, frames=[f.name for f in robot.frames])
    mine, theirs = (symdyn.derive(r, outputs=FRAME_OUTPUTS).numeric for r in (robot, back))
    rng = np.random.default_rng(3)
    for _ in range(5):
        q, qd, _, _ = random_state(robot, rng)
        np.testing.assert_allclose(theirs.frame_poses(q), mine.frame_poses(q), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(theirs.frame_jacobians(q), mine.frame_jacobians(q), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(theirs.frame_jacobian_dot_v(q, qd), mine.frame_jacobian_dot_v(q, qd),
                                   rtol=1e-12, atol=1e-12)


def test_bundled_arm_frames_agree_with_pinocchio():
    """A bundled arm (robots/puma560.yaml) with frames chosen by name (symdyn.load(frames=...),
    --frames): its wrist's and its last link's own frames, at 50 states."""
    from helpers import robot_path
    robot = symdyn.load(robot_path("puma560"), frames=["wrist_roll", "flange"])
    assert [(f.name, f.link, f.pose) for f in robot.frames] == [("wrist_roll", 3, None), ("flange", 5, None)]
    eqs = symdyn.derive(robot, outputs=FRAME_OUTPUTS)
    rng = np.random.default_rng(13)
    states = [random_state(robot, rng) for _ in range(50)]
    errors = compare(eqs.numeric, PinocchioReference(robot), states, FRAME_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), errors


def test_50_digit_reference_of_frames_and_centroidal_quantities(tmp_path):
    """symdyn bench's reference (mpmath, 50 digits, its own forward pass over the tree) agrees
    with Pinocchio on every frame and centroidal function (the hand tree with its frames), so that
    bench measures their error; and symdyn's double C is within 1e-13 of it."""
    from symdyn.check.reference import MpReference
    from symdyn.model.outputs import CENTROIDAL_OUTPUTS
    source = "examples/trees/torso_two_arms.yaml"
    robot = symdyn.load(_with_frames(tmp_path, source, CASES[source]))
    functions = FRAME_OUTPUTS + CENTROIDAL_OUTPUTS
    rng = np.random.default_rng(17)
    states = [random_state(robot, rng) for _ in range(3)]
    precise = MpReference(robot)
    errors = compare(precise, PinocchioReference(robot), states, functions)
    assert all(e <= TOL for e in errors.values()), errors
    eqs = symdyn.derive(robot, outputs=functions)
    errors = compare(eqs.numeric, precise, states, functions)
    assert all(e <= 1e-13 for e in errors.values()), errors
