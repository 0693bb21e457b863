"""Real URDFs (the example-robot-data wheel, a test extra) and a hand-written one: symdyn's
reading of the file against Pinocchio's own URDF parser, every function; and the conversions
YAML -> URDF -> Pinocchio and URDF -> YAML -> symdyn."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

import symdyn
from helpers import REPO, ROBOTS, TOL, example_robot_data, parameter_values, random_states, robot_path
from symdyn.check.pinocchio_model import UrdfReference, compare
from symdyn.model.errors import SymdynWarning


HANDMADE = str(REPO / "tests" / "data" / "urdf" / "handmade.urdf")

#: (id, path under example-robot-data or absolute, tip (None: the only leaf), tool)
URDFS = [
    ("ur5", "ur_description/urdf/ur5_robot.urdf", "tool0", None),
    ("panda", "panda_description/urdf/panda.urdf", "panda_hand_tcp", None),
    ("z1", "z1_description/urdf/z1.urdf", None, None),
    ("kinova", "kinova_description/robots/kinova.urdf", "j2s6s200_end_effector", None),
    ("handmade", HANDMADE, None, None),
    # three leaves, two of them (ee_link, tool0) and the ROS "base" frame on fixed joints only:
    # the chain ends at the last moving joint's link without --tip
    ("ur10", "ur_description/urdf/ur10_robot.urdf", None, None),
    # SO-101 whole: its gripper jaw is the last joint of its one chain of moving joints (no --tip)
    ("so101", "so_arm_description/urdf/so101.urdf", None, None),
]

_DERIVED = {}


def derived_urdf(case, exact_angles=False):
    label, relative, tip, tool = case
    key = (label, exact_angles)
    if key not in _DERIVED:
        path = relative if os.path.isabs(relative) else example_robot_data(relative)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SymdynWarning)  # e.g. the Panda's fingers, locked
            robot = symdyn.load(path, tip=tip, tool=tool, exact_angles=exact_angles)
        _DERIVED[key] = (path, symdyn.derive(robot))
    return _DERIVED[key]


@pytest.mark.parametrize("case", [pytest.param(c, marks=[pytest.mark.slow] if c[0] == "kinova" else []) for c in URDFS],
                         ids=[c[0] for c in URDFS])  # kinova (7 s), a 6-joint arm like ur5, with -m slow
def test_urdf_agrees_with_pinocchio_urdf_parser(case):
    """Every function (dynamics and tool kinematics) at 50 states, double, against the model
    Pinocchio builds from the same file (joints off the chain locked at neutral, continuous
    joints given as (cos, sin)): read by default (near-quarter-turn rpy angles such as
    1.57079632679 made exact multiples of pi/2, so that zeros fold), against the file with those
    angles written exactly, which is the file as written when it has none; where it has some,
    also read with --exact-angles, against the file as written."""
    from symdyn.model.urdf import QUARTER_TOLERANCE
    label, _, tip, tool = case
    readings = [(False, QUARTER_TOLERANCE)]
    if any("multiple of pi/2" in note for note in derived_urdf(case)[1].robot.notes):
        readings.append((True, None))  # else the default reading is the file as written
    for exact_angles, snap in readings:
        path, eqs = derived_urdf(case, exact_angles)
        reference = UrdfReference(path, tip, tool, snap)
        assert reference.model.nv == eqs.n
        errors = compare(eqs.numeric, reference, random_states(eqs.n, 50, seed=21), symdyn.OUTPUTS)
        assert all(e <= TOL for e in errors.values()), f"{label} (exact_angles={exact_angles}): {errors}"


def test_quarter_turns_change_the_model_by_rounding_only():
    """Taking 1.57079632679 as pi/2 moves the Kinova's tool by less than 1e-10 m and changes its
    inverse dynamics by less than 1e-9 relative: a reading of the author's intent, not a guess
    that matters; it is listed in the notes (and the generated header)."""
    exact = derived_urdf(URDFS[3], exact_angles=True)[1]
    snapped = derived_urdf(URDFS[3])[1]
    assert any("multiple of pi/2" in note and "1.57079632679" in note for note in snapped.robot.notes)
    assert not any("multiple of pi/2" in note for note in exact.robot.notes)
    errors = compare(snapped.numeric, exact.numeric, random_states(6, 10, seed=24),
                     ("inverse_dynamics", "forward_kinematics"))
    assert errors["inverse_dynamics"] < 1e-9 and errors["forward_kinematics"] < 1e-10, errors


def test_continuous_joints_are_one_angle():
    """The Kinova arm's continuous joints are single angles (Pinocchio: (cos, sin), nq = 9)."""
    path, eqs = derived_urdf(URDFS[3])
    reference = UrdfReference(path, URDFS[3][2])
    assert eqs.n == 6 and reference.model.nq == 9 and sum(reference.continuous) == 3


def test_urdf_derivation_folds_like_dh():
    """The UR5 from its URDF (rpy 1.57079632679 taken as pi/2) costs about what the UR5 from
    its DH table does: zeros fold, no stray 1e-12 terms."""
    from symdyn.emit.cgen import build_function
    _, urdf = derived_urdf(URDFS[0])
    dh = symdyn.derive(symdyn.load(robot_path("ur5")), outputs=["inverse_dynamics"])
    ops = {name: sum(build_function(e, "inverse_dynamics", "double", "x").ops.values()) for name, e in
           (("urdf", urdf), ("dh", dh))}
    assert ops["urdf"] <= 1.3 * ops["dh"], ops


@pytest.mark.parametrize("name", ROBOTS)
def test_yaml_to_urdf_to_pinocchio_equals_symdyn(name, tmp_path, derived):
    """A bundled robot written as URDF (symdyn convert) and read by Pinocchio's parser gives
    symdyn's own numbers, every function; the tool frame becomes a link 'tool'."""
    from symdyn.cli import main
    robot = symdyn.load(robot_path(name))
    values = parameter_values(robot)
    eqs = derived(name)
    source = robot_path(name)
    if robot.parameters:  # URDF holds numbers: give the symbols values through a scene
        scene = tmp_path / "numeric.yaml"
        scene.write_text(f"scene: 1\nrobot: {source}\nvalues: {{{', '.join(f'{s.name}: {values[s]!r}' for s in robot.parameters)}}}\n")
        source = str(scene)
        eqs = symdyn.derive(symdyn.load(source))
    out = tmp_path / f"{name}.urdf"
    assert main(["convert", source, "--to", "urdf", "--out", str(out)]) == 0
    reference = UrdfReference(str(out), "tool")
    # URDF has no rotor inertia: the file leaves the armature out (with a warning); give it back
    reference.armature = np.array([float(link.armature) for link in eqs.robot.links])
    reference.model.armature = reference.armature
    # ... and no gravity (simulators assume (0, 0, -9.81); convert warns when it differs)
    reference.model.gravity.linear = np.array([float(g) for g in eqs.robot.gravity])
    errors = compare(eqs.numeric, reference, random_states(eqs.n, 10, seed=22), symdyn.OUTPUTS)
    assert all(e <= TOL for e in errors.values()), f"{name}: {errors}"


@pytest.mark.parametrize("case", [URDFS[0], URDFS[4]], ids=["ur5", "handmade"])
def test_urdf_to_yaml_to_symdyn_equals_urdf_to_symdyn(case, tmp_path):
    """symdyn convert ROBOT.urdf --to yaml writes the general form; reading it back gives the
    same equations (to rounding)."""
    from symdyn.cli import main
    label, _, tip, tool = case
    path, eqs = derived_urdf(case)
    out = tmp_path / f"{label}.yaml"
    args = ["convert", path, "--to", "yaml", "--out", str(out)] + (["--tip", tip] if tip else [])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SymdynWarning)
        assert main(args) == 0
    again = symdyn.derive(symdyn.load(out))
    assert again.robot.convention == "general"
    states = random_states(eqs.n, 10, seed=23)
    errors = compare(again.numeric, eqs.numeric, states, symdyn.OUTPUTS)
    assert all(e <= 1e-12 for e in errors.values()), errors


def test_derivation_printouts_of_a_urdf(tmp_path, capsys):
    """symdyn derive on a URDF: general placements instead of the DH table, both methods; the
    LaTeX compiles where pdflatex is installed (.ci/run installs it)."""
    import shutil
    import subprocess
    from symdyn.cli import main
    for method in ("newton-euler", "lagrange-euler"):
        assert main(["derive", HANDMADE, "--method", method, "--format", "markdown", "--steps", "summary",
                     "--out", str(tmp_path / f"{method}.md")]) == 0
        text = (tmp_path / f"{method}.md").read_text()
        assert "general joint placements (origin, axis)" in text and "origin $rpy$" in text
    assert main(["derive", HANDMADE, "--format", "latex", "--out", str(tmp_path / "arm.tex")]) == 0
    if shutil.which("pdflatex"):
        result = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "arm.tex"],
                                cwd=tmp_path, capture_output=True, text=True, timeout=120)
        assert result.returncode == 0, result.stdout[-2000:]


def test_tip_of_a_chain_with_fixed_leaves_and_the_whole_tree_of_a_branching_one(capsys):
    """ur10_robot.urdf (leaves ee_link, base, tool0 on fixed joints): no --tip needed, the
    header says which tip was taken and why; solo12.urdf (four legs, moving joints on every
    branch) is read as its whole tree, its joints in Pinocchio's order; --tip still picks one leg."""
    _, eqs = derived_urdf(next(case for case in URDFS if case[0] == "ur10"))
    assert eqs.n == 6
    assert any(note.startswith("tip: wrist_3_link, the link of the last moving joint") and "'tool0'" in note
               for note in eqs.robot.notes), eqs.robot.notes
    solo = example_robot_data("solo_description/robots/solo12.urdf")
    robot = symdyn.load(solo)
    assert robot.is_tree and robot.dof == 12 and robot.children(-1) == (0, 3, 6, 9)
    assert [link.name for link in robot.links] == list(UrdfReference(solo).joint_names)
    leg = symdyn.load(solo, tip="FL_FOOT")
    assert not leg.is_tree and leg.dof == 3



def test_a_legged_robot_read_on_a_fixed_base_says_so():
    """Solo-12 read without --floating-base: its root link's 1.16 kg is fixed to the ground with
    four legs on it, said in one warning naming the file, the root and --floating-base; read with
    it, nothing is said."""
    path = example_robot_data("solo_description/robots/solo12.urdf")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        symdyn.load(path)
    said = [str(w.message) for w in caught if issubclass(w.category, SymdynWarning) and "--floating-base" in str(w.message)]
    assert len(said) == 1 and "solo12.urdf" in said[0] and "'base_link'" in said[0] and "4 branches" in said[0], said
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        symdyn.load(path, floating_base=True)
    assert not [w for w in caught if "--floating-base" in str(w.message)]


def test_long_joint_names_are_said_once_and_kept_in_full(tmp_path):
    """Three URDF joints whose names pass 31 characters: one warning for the three, and the
    header's notes give each full URDF name beside the name used (TALOS's gripper joints)."""
    import re
    from symdyn.cli import main
    text = (REPO / "tests" / "data" / "urdf" / "handmade.urdf").read_text()
    names = re.findall(r'<joint name="([^"]+)" type="(?:revolute|continuous|prismatic)"', text)[:3]
    long = {name: f"{name}_with_a_suffix_long_enough_to_pass_the_limit_{k}" for k, name in enumerate(names)}
    for name, new in long.items():
        text = text.replace(f'"{name}"', f'"{new}"')
    path = tmp_path / "long.urdf"
    path.write_text(text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = symdyn.load(str(path))
    said = [str(w.message) for w in caught if "name" in str(w.message) and "changed" in str(w.message)]
    assert len(said) == 1 and "3 joint names changed" in said[0], said
    assert main(["generate", str(path), "--out", str(tmp_path / "out"), "--functions", "gravity", "--quiet"]) == 0
    header = (tmp_path / "out" / f"{robot.name}_dynamics.h").read_text()
    for new in long.values():
        assert new in header, new
