"""URDF in and out: the reader (symdyn.model.urdf) against Pinocchio's own URDF parser, the
writer (symdyn.emit.urdf) against the Pinocchio model symdyn builds, round trips, each
rejection as one line, and ``symdyn convert``."""

from __future__ import annotations

import hashlib
import math
import os
import warnings
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
import yaml

import symdyn
from helpers import REPO, ROBOTS, error_line, parameter_values, robot_path
from symdyn.check.pinocchio_model import PinocchioReference, UrdfReference, build_model, normalized_error
from symdyn.cli import main
from symdyn.emit.urdf import robot_to_urdf
from symdyn.model.errors import RobotFileError, SymdynError, SymdynWarning
from symdyn.model.robot import from_document
from symdyn.model.urdf import Quarter, matrix_rpy, number_text, read_urdf, rpy_rotation

pin = pytest.importorskip("pinocchio")

DATA = REPO / "tests" / "data" / "urdf"
HANDMADE = DATA / "handmade.urdf"
BRANCHING = DATA / "branching.urdf"
SHARED_NAMES = DATA / "shared_names.urdf"  # links named as their joints, as ANYmal's LF_HAA
SCENES = sorted(p.stem for p in (REPO / "robots" / "scenes").glob("*.yaml"))


def read(path, **options):
    """``(document, notes, warnings)`` of a URDF file."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", SymdynWarning)
        doc, notes = read_urdf(path.read_text(), str(path), **options)
    return doc, notes, [str(w.message) for w in caught if issubclass(w.category, SymdynWarning)]




def agree(mine: PinocchioReference, ref: PinocchioReference, dof: int, tolerance: float) -> None:
    """Dynamics (friction included) and tool kinematics agree at seeded random states."""
    rng = np.random.default_rng(3)
    states = [(rng.uniform(-np.pi, np.pi, dof), rng.uniform(-2, 2, dof), rng.uniform(-5, 5, dof))
              for _ in range(10)]
    for name, args in (("mass_matrix", 1), ("gravity", 1), ("inverse_dynamics", 3)):
        error = normalized_error([getattr(mine, name)(*s[:args]) for s in states],
                                 [getattr(ref, name)(*s[:args]) for s in states])
        assert error < tolerance, (name, error)
    for name in ("forward_kinematics", "jacobian"):
        difference = max(np.max(np.abs(getattr(mine, name)(s[0]) - getattr(ref, name)(s[0]))) for s in states)
        assert difference < tolerance, (name, difference)


# ---------------------------------------------------------------------------------------------
# Reading


def test_handmade_document():
    doc, notes, caught = read(HANDMADE)
    assert caught == []
    assert [link["name"] for link in doc["links"]] == ["shoulder_pan", "shoulder_lift", "elbow", "slide",
                                                      "wrist_roll", "wrist_flex"]
    assert [link["joint"] for link in doc["links"]] == ["revolute"] * 3 + ["prismatic"] + ["revolute"] * 2
    assert doc["convention"] == "general" and doc["gravity"] == [0, 0, "-9.81"]
    first, lift, elbow, slide, roll, flex = doc["links"]
    # the base's fixed joint composes into the first origin; quarter turns are exact
    assert first["origin"] == {"xyz": ["0.1", "-0.05", "0.32"], "rpy": ["0", "0", "pi/2"]}
    assert lift["origin"] == {"xyz": ["0.05", "0.02", "0.1"], "rpy": ["pi/2", "0", "0.25"]}
    assert roll["origin"]["rpy"] == ["0", "-pi/2", "0"]
    # a joint as written keeps the file's own texts; the one after the fixed joint is composed
    assert slide["origin"] == {"xyz": ["0.1", "0", "0.05"], "rpy": ["0", "0", "-0.3"]}
    assert all(isinstance(v, str) and "pi" not in v for v in elbow["origin"]["rpy"])
    assert elbow["axis"] == ["0.6", "0", "0.8"] and lift["axis"] == ["0", "-1", "0"]
    assert flex["axis"] == ["1", "0", "0"]  # no <axis>: the URDF default
    # the motor housing (fixed joint) is merged into the link above it
    assert lift["mass"] == "5.5" and flex["mass"] == "0.5"  # the tool link too
    assert slide["mass"] == "0.8" and slide["com"] == ["0.05", "0", "0"]  # as written
    assert (first["damping"], first["coulomb"]) == ("0.8", "1.5")
    assert "coulomb" not in lift and "damping" not in flex and flex["coulomb"] == "0.1"
    assert first["limits"] == {"lower": "-3.1", "upper": "3.1", "velocity": "2.0", "effort": "150"}
    assert elbow["limits"] == {"velocity": "3.0", "effort": "80"}  # continuous: no position limits
    assert doc["tool"] == {"xyz": ["0.01", "0", "0.12"], "rpy": ["0", "pi/2", "0"]}
    text = " | ".join(notes)
    for words in ("chain world -> tool0, 6 moving joints", "continuous joints read as revolute",
                  "elbow_mount", "base_mount", "inertia left out (5 kg)", "Coulomb"):
        assert words in text, words
    robot = from_document(doc, str(HANDMADE))
    assert robot.dof == 6 and robot.convention == "general" and robot.tool is not None


def test_handmade_agrees_with_pinocchio_urdf_parser(tmp_path):
    """symdyn's reading = Pinocchio's buildModelFromUrdf.  Quarter turns written to fewer digits
    (1.57079632679 for pi/2, 5e-12 away) are read as pi/2 exactly: the results then differ from
    Pinocchio's reading of the digits as written by about 1e-11."""
    doc, _, _ = read(HANDMADE)
    robot = from_document(doc, str(HANDMADE))
    agree(PinocchioReference(robot), UrdfReference(str(HANDMADE), "tool0"), robot.dof, 1e-12)
    short = tmp_path / "short.urdf"
    short.write_text(HANDMADE.read_text().replace("1.5707963267948966", "1.57079632679"))
    assert read(short)[0] == doc
    agree(PinocchioReference(robot), UrdfReference(str(short), "tool0"), robot.dof, 1e-10)


def test_branches_are_locked_and_merged_as_pinocchio_reduces_them():
    doc, notes, caught = read(BRANCHING, tip="tcp")
    assert doc["name"] == "branching_cell" and [link["name"] for link in doc["links"]] == ["a1", "a2"]
    assert len(caught) == 3 and "'Branching-Cell'" in caught[0] and "'branching_cell'" in caught[0]
    assert "'object_joint', 'cart_joint', 'camera_pan'" in caught[1] and "4.4 kg" in caught[1]
    assert "'finger_left', 'finger_right'" in caught[2] and "0.1 kg" in caught[2] and "'a2'" in caught[2]
    assert all("\n" not in w for w in caught)
    robot = from_document(doc, str(BRANCHING))
    agree(PinocchioReference(robot), UrdfReference(str(BRANCHING), "tcp"), 2, 1e-12)
    # a tool link named explicitly, two fixed joints below the last moving link (composed)
    doc, notes, _ = read(BRANCHING, tip="hand", tool="tcp")
    assert doc["tool"] == {"xyz": ["0.4", "0", "0"], "rpy": ["pi/2", "0.7853981633974483", "pi/2"]}
    robot = from_document(doc, str(BRANCHING))
    agree(PinocchioReference(robot), UrdfReference(str(BRANCHING), "hand", "tcp"), 2, 1e-12)
    # a finger as the tip: the prismatic joint is on the chain, the mimic finger is locked
    doc, _, caught = read(BRANCHING, tip="finger_l")
    assert [link["joint"] for link in doc["links"]] == ["revolute", "revolute", "prismatic"]
    robot = from_document(doc, str(BRANCHING))
    agree(PinocchioReference(robot), UrdfReference(str(BRANCHING), "finger_l"), 3, 1e-12)


def test_links_named_as_joints_are_found_by_name_and_type(capsys):
    """A leg whose links carry their joints' names (ANYmal's LF_HAA: Pinocchio's frame lookup by
    name alone raised 'Several frames match the filter'): Pinocchio's own parser is the reference
    with the tip or the tool on such a link, and verify compares with it (no fallback warning)."""
    for tip, dof in (("HAA", 1), ("FOOT", 3)):
        doc, _, _ = read(SHARED_NAMES, tip=tip)
        robot = from_document(doc, str(SHARED_NAMES))
        agree(PinocchioReference(robot), UrdfReference(str(SHARED_NAMES), tip), dof, 1e-12)
        assert main(["verify", str(SHARED_NAMES), "--tip", tip, "--states", "3", "--functions", "mass_matrix,jacobian"]) == 0
        captured = capsys.readouterr()
        assert "against Pinocchio's own URDF parser" in captured.out and captured.out.count(" ok") == 2
        assert "cannot read it" not in captured.err and "Traceback" not in captured.err


def test_rpy_of_composed_rotations():
    """matrix_rpy inverts rpy_rotation: quarter turns exactly, others to 30 digits, and at
    pitch = +-pi/2 (gimbal lock) it puts the whole turn about z into roll."""
    rng = np.random.default_rng(0)
    for rpy in [tuple(Fraction(int(v * 1000), 1000) for v in rng.uniform([-3, -1.5, -3], [3, 1.5, 3]))
                for _ in range(20)]:  # pitch in (-pi/2, pi/2): the triple is unique
        back = matrix_rpy(rpy_rotation(rpy))
        assert all(abs(float(a) - float(b)) < 1e-15 for a, b in zip(back, rpy))
    for k in range(-2, 3):
        for j in range(-2, 3):
            rpy = (Quarter(k), Quarter(j), Quarter(1))
            back = matrix_rpy(rpy_rotation(rpy))
            assert all(isinstance(a, Quarter) for a in back)
            assert rpy_rotation(back) == rpy_rotation(rpy)  # exact
    assert matrix_rpy(rpy_rotation((Fraction(3, 10), Quarter(1), Fraction(1, 5))))[1:] == (Quarter(1), Quarter(0))
    roll = matrix_rpy(rpy_rotation((Fraction(3, 10), Quarter(-1), Fraction(1, 5))))[0]
    assert abs(float(roll) - 0.5) < 1e-15  # roll + yaw
    assert number_text(Fraction(1, 3)) == "1/3" and number_text(Fraction(-1, 8)) == "-0.125"
    assert number_text(Quarter(-3)) == "-3*pi/2" and number_text(10 ** 70) == "1e+70"
    merged = Fraction(94812479387383249, 8067700000000000000)  # a merged link's COM: the shortest double
    assert number_text(merged) == repr(float(merged)) == "0.01175210771191086"
    assert number_text(Fraction(3, 1000)) == "0.003" and number_text(Fraction(2, 3)) == "2/3"


def test_quarter_turn_rule_and_names():
    text = """<robot name="9 Axis">
      <link name="a"/><link name="b"/><link name="c"/>
      <joint name="1st-joint" type="revolute"><parent link="a"/><child link="b"/>
        <origin rpy="1.5707963268 1.5707 -3.14159265359"/><axis xyz="0 0 2"/></joint>
      <joint name="1st_joint" type="prismatic"><parent link="b"/><child link="c"/>
        <origin rpy="4.71238898038 0 0" xyz="+1 .5 1e-3"/><axis xyz="0 0 1"/></joint>
    </robot>"""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", SymdynWarning)
        doc, _ = read_urdf(text, "names.urdf")
    messages = [str(w.message) for w in caught]
    assert doc["name"] == "robot_9_axis"
    first, second = doc["links"]
    assert first["name"] == "_1st_joint" and second["name"] == "_1st_joint_2"
    assert first["origin"]["rpy"] == ["pi/2", "1.5707", "-pi"]  # 1.5707 is 8e-5 away: kept
    assert second["origin"] == {"xyz": ["1", ".5", "1e-3"], "rpy": ["3*pi/2", "0", "0"]}
    assert len(messages) == 2 and all(m.startswith("names.urdf: ") for m in messages)  # the joints' in one
    assert "'1st-joint' -> '_1st_joint'" in messages[1] and "'1st_joint' -> '_1st_joint_2'" in messages[1]
    robot = from_document(doc, "names.urdf")
    assert robot.links[0].axis == (0, 0, 1)


# ---------------------------------------------------------------------------------------------
# Rejections: one line each, naming the file, the joint or link, and the attribute

ARM = """<robot name="arm">
  <link name="base"/><link name="l1"/><link name="l2"/>
  <joint name="j1" type="{kind}"><parent link="base"/><child link="l1"/>{extra}</joint>
  <joint name="j2" type="revolute"><parent link="{parent}"/><child link="l2"/><axis xyz="{axis}"/></joint>
</robot>"""


def arm(kind="revolute", extra="", parent="l1", axis="0 0 1"):
    return ARM.format(kind=kind, extra=extra, parent=parent, axis=axis)


REJECTIONS = [
    ("doctype", '<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY big "xxxxxxxx">]>\n<robot name="r">&big;</robot>',
     [], ["DOCTYPE", "line 2", "no entity is ever expanded"]),
    ("entity", '<!DOCTYPE robot SYSTEM "file:///etc/passwd"><robot name="r"/>', [], ["DOCTYPE"]),
    ("malformed", '<robot name="r">\n  <link name="a">\n</robot>', [], ["not valid XML (line 3, column 3)", "mismatched tag"]),
    ("not_urdf", "<sdf/>", [], ["the top element is <sdf>, not <robot>"]),
    ("floating", arm(kind="floating"), [], ["joint 'j1'", "field 'type'", "a floating joint is on the chain"]),
    ("planar", arm(kind="planar"), [], ["joint 'j1'", "field 'type'", "a planar joint"]),
    ("unknown_type", arm(kind="ball"), [], ["joint 'j1'", "unknown joint type 'ball'"]),
    ("mimic_zero", arm(extra='<mimic joint="j2" multiplier="0"/>'), [], ["joint 'j1'", "field 'mimic multiplier'",
                                                                         "make it a fixed joint"]),
    ("mimic_itself", arm(extra='<mimic joint="j1"/>'), [], ["joint 'j1'", "mimic joints follow each other in a circle"]),
    ("mimic_fixed", arm(kind="fixed").replace('<axis xyz="0 0 1"/></joint>', '<axis xyz="0 0 1"/><mimic joint="j1"/></joint>'),
     [], ["joint 'j2'", "'j1', which is a fixed joint"]),
    ("unknown_tip", BRANCHING.read_text(), ["--tip", "tpc"], ["tip link 'tpc' is not a link", "did you mean 'tcp'?"]),
    ("tool_not_rigid", BRANCHING.read_text(), ["--tip", "tcp", "--tool", "finger_l"],
     ["tool link 'finger_l' is not rigidly attached to link 'l2'", "'a2'", "fixed joints only"]),
    ("unknown_tool", BRANCHING.read_text(), ["--tip", "tcp", "--tool", "tcpp"], ["tool link 'tcpp'", "did you mean 'tcp'?"]),
    ("no_moving_joint", arm(kind="fixed").replace('type="revolute"', 'type="fixed"'), [],
     ["no moving joint", "'base' to 'l2'"]),
    ("missing_parent", arm(parent="l11"), [], ["joint 'j2'", "field 'parent'", "parent link 'l11' is not a link",
                                              "did you mean 'l1'?"]),
    ("zero_axis", arm(axis="0 0 0"), [], ["joint 'j2'", "field 'axis xyz'", "the axis is zero"]),
    ("bad_number", arm(axis="0 0 one"), [], ["joint 'j2'", "field 'axis xyz'", "'one' is not a decimal number"]),
    ("two_parents", arm(parent="base").replace('<child link="l2"/>', '<child link="l1"/>'), [],
     ["is the child of two joints"]),
    ("cycle", arm().replace('<parent link="base"/><child link="l1"/>', '<parent link="l2"/><child link="l1"/>'),
     [], ["form a cycle"]),
    ("negative_mass", arm().replace('<link name="l2"/>', '<link name="l2"><inertial><mass value="-1"/>'
                                    '<inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>'),
     [], ["link 'l2'", "mass must not be negative"]),
]


@pytest.mark.parametrize("case", REJECTIONS, ids=[c[0] for c in REJECTIONS])
def test_rejections_are_one_line(tmp_path, capsys, case):
    name, text, options, words = case
    path = tmp_path / f"{name}.urdf"
    path.write_text(text)
    assert main(["convert", str(path), "--to", "yaml", *options]) == 1
    line = error_line(capsys)
    assert f"{name}.urdf" in line
    for word in words:
        assert word in line, (word, line)
    assert capsys.readouterr().out == ""


def test_generate_reads_urdf_options_too(tmp_path, capsys):
    assert main(["generate", str(BRANCHING), "--out", str(tmp_path / "out")]) == 1
    assert "--tip LINK" in error_line(capsys)


# ---------------------------------------------------------------------------------------------
# Writing


@pytest.mark.parametrize("name", ROBOTS + ["general_arm"] + [f"scenes/{s}" for s in SCENES])
def test_written_urdf_has_the_same_dynamics_in_pinocchio(name):
    path = REPO / "robots" / f"{name}.yaml" if name.startswith("scenes/") else robot_path(name)
    robot = symdyn.load(path)
    if robot.parameters:  # planar2r is symbolic
        robot = robot.substitute(parameter_values(robot))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SymdynWarning)
        text = robot_to_urdf(robot)
    model = pin.buildModelFromXML(text)
    reference, info = build_model(robot)
    assert model.nq == model.nv == robot.dof
    assert np.allclose(model.damping, info["damping"]) and np.allclose(model.friction, info["coulomb"])
    model.gravity.linear = reference.gravity.linear.copy()  # URDF carries none
    model.armature = reference.armature.copy()  # URDF has no armature
    data, ref_data = model.createData(), reference.createData()
    rng = np.random.default_rng(5)
    for _ in range(10):
        q, v, a = (rng.uniform(-np.pi, np.pi, robot.dof), rng.uniform(-2, 2, robot.dof),
                   rng.uniform(-5, 5, robot.dof))
        for f in (lambda m, d: pin.rnea(m, d, q, v, a), lambda m, d: pin.crba(m, d, q),
                  lambda m, d: pin.computeGeneralizedGravity(m, d, q)):
            mine, ref = f(model, data), f(reference, ref_data)
            assert np.max(np.abs(mine - ref)) <= 1e-10 * max(1.0, np.max(np.abs(ref)))
        pin.framesForwardKinematics(model, data, q)
        pin.framesForwardKinematics(reference, ref_data, q)
        tool = data.oMf[model.getFrameId("tool")].homogeneous
        assert np.max(np.abs(tool - ref_data.oMf[reference.getFrameId("tool")].homogeneous)) < 1e-12
    # and back: URDF -> document -> robot keeps the dynamics
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SymdynWarning)  # planar2r's planar inertias
        doc, _ = read_urdf(text, "written.urdf")
        back, _ = build_model(from_document(doc, "written.urdf"))
    back.gravity.linear = reference.gravity.linear.copy()
    back.armature = reference.armature.copy()
    back_data = back.createData()
    q, v, a = rng.uniform(-np.pi, np.pi, robot.dof), rng.uniform(-2, 2, robot.dof), rng.uniform(-5, 5, robot.dof)
    assert np.allclose(pin.rnea(back, back_data, q, v, a), pin.rnea(reference, ref_data, q, v, a), rtol=1e-12, atol=1e-10)


def test_writer_names_the_contact_set(tmp_path):
    """A robot file's contact set has no place in a URDF: a comment and a warning name it (and a
    Baumgarte correction lost), and --contacts with the comment's set reads it back."""
    path = str(REPO / "examples" / "contacts" / "tip_on_board.yaml")
    robot = symdyn.load(path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", SymdynWarning)
        text = robot_to_urdf(robot)
    assert "<!-- contact set of the contact dynamics: tip:3d (read it back with - -contacts tip:3d) -->" in text
    assert any("the contact set (tip:3d) is left out of the URDF" in str(w.message)
               and "Baumgarte correction of tip is lost" in str(w.message) for w in caught), [str(w.message) for w in caught]
    out = tmp_path / "board.urdf"
    out.write_text(text)
    from symdyn.model.scene import load_input
    back, _ = load_input(str(out), contacts="tip:3d")
    assert [(back.frames[c.frame].name, c.kind, c.corrected) for c in back.contacts] == [("tip", "3d", False)]


def test_writer_output(capsys):
    robot = symdyn.load(robot_path("puma560"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", SymdynWarning)
        text = robot_to_urdf(robot)
        assert text == robot_to_urdf(robot)  # deterministic
    assert f"symdyn {symdyn.__version__} from puma560.yaml (sha256 {robot.source_hash})" in text
    assert "Do not edit" in text and "<!-- armature" in text
    assert [str(w.message) for w in caught] == 2 * [
        "puma560.yaml: armature of waist, shoulder, elbow, wrist_roll, wrist_bend, flange is left out of the "
        "URDF (URDF has no rotor inertia; the values are in comments)"]
    assert '<joint name="waist" type="revolute">' in text and '<link name="waist_link">' in text
    assert '<link name="tool"/>' in text and "<limit lower=" in text
    # a symbolic robot cannot be written
    with pytest.raises(SymdynError, match="URDF needs numbers: parameters g, m1, lc1, I1, l1 and 3 more have "
                                          "no value; give them values or use a scene"):
        robot_to_urdf(symdyn.load(robot_path("planar2r")))
    assert main(["convert", robot_path("planar2r"), "--to", "urdf"]) == 1
    assert "URDF needs numbers" in error_line(capsys)


def test_urdf_limits_and_gravity_are_carried(tmp_path, capsys):
    doc, _, _ = read(HANDMADE)
    text = robot_to_urdf(from_document(doc, str(HANDMADE)))
    assert '<limit lower="-3.1" upper="3.1" effort="150.0" velocity="2.0"/>' in text
    assert f'<limit lower="{-math.pi!r}" upper="{math.pi!r}" effort="80.0" velocity="3.0"/>' in text
    model = pin.buildModelFromXML(text)
    assert np.allclose(model.lowerPositionLimit[:2], [-3.1, -2.0])
    # a gravity URDF cannot hold is a warning (an error with --strict)
    path = tmp_path / "planar.yaml"
    path.write_text((REPO / "robots" / "planar2r.yaml").read_text().replace("{runtime: true}", "1.5"))
    assert main(["convert", str(path), "--to", "urdf", "--out", str(tmp_path / "p.urdf")]) == 0
    assert "gravity [0.0, -1.5, 0.0] m/s^2" in capsys.readouterr().err
    assert main(["convert", str(path), "--to", "urdf", "--strict", "--out", str(tmp_path / "q.urdf")]) == 1
    assert "(--strict)" in error_line(capsys) and not (tmp_path / "q.urdf").exists()


# ---------------------------------------------------------------------------------------------
# symdyn convert


def test_convert_urdf_to_yaml_reads_back(tmp_path, capsys):
    out = tmp_path / "handmade.yaml"
    assert main(["convert", str(HANDMADE), "--to", "yaml", "--out", str(out)]) == 0
    assert capsys.readouterr().out == f"wrote {out}\n"
    text = out.read_text()
    assert text.startswith(f"# Converted by symdyn {symdyn.__version__} from handmade.urdf (sha256 "
                           f"{hashlib.sha256(HANDMADE.read_bytes()).hexdigest()})")
    assert "#   - fixed joints merged" in text
    loaded = yaml.safe_load(text)
    assert list(loaded) == ["format", "name", "convention", "gravity", "tool", "links"]
    direct = from_document(read(HANDMADE)[0], "x")
    robot = symdyn.load(out)
    assert_same_doubles(robot, direct)
    # stdout by default, the same text
    assert main(["convert", str(HANDMADE), "--to", "yaml"]) == 0
    assert capsys.readouterr().out == text
    # the YAML converts to URDF, and so does the URDF itself (normalized)
    assert main(["convert", str(out), "--to", "urdf", "--out", str(tmp_path / "a.urdf"), "--quiet"]) == 0
    assert main(["convert", str(HANDMADE), "--to", "urdf", "--out", str(tmp_path / "b.urdf"), "--quiet"]) == 0
    assert capsys.readouterr().out == ""
    a, b = (pin.buildModelFromUrdf(str(tmp_path / n)) for n in ("a.urdf", "b.urdf"))
    q = np.linspace(-1, 1, 6)
    assert np.allclose(pin.crba(a, a.createData(), q), pin.crba(b, b.createData(), q), atol=1e-14)


def assert_same_doubles(robot, direct):
    """Every number of ``robot`` (read back from YAML) is the double of ``direct``'s exact value."""
    assert len(robot.links) == len(direct.links)
    for mine, theirs in zip(robot.links, direct.links):
        for name in ("mass", "com", "inertia", "a", "d", "alpha", "theta", "origin", "damping", "coulomb", "armature"):
            a, b = getattr(mine, name), getattr(theirs, name)
            flat_a = [float(x) for x in sp.flatten([a]) if x is not None] if not hasattr(a, "xyz") else \
                [float(x) for x in (*a.xyz, *a.rpy)]
            flat_b = [float(x) for x in sp.flatten([b]) if x is not None] if not hasattr(b, "xyz") else \
                [float(x) for x in (*b.xyz, *b.rpy)]
            assert flat_a == flat_b, (mine.name, name, a, b)
    assert [float(x) for x in robot.gravity] == [float(x) for x in direct.gravity]


def test_converted_merged_links_are_short_decimals(tmp_path, capsys):
    """Merged links (masses and centres of mass weighted exactly) are written as the shortest
    decimal of the same double, not as p/q of 17-digit integers; quarter turns stay exact."""
    out = tmp_path / "branching.yaml"
    assert main(["convert", str(BRANCHING), "--tip", "tcp", "--to", "yaml", "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    body = "\n".join(line for line in out.read_text().splitlines() if not line.startswith("#"))
    import re
    assert not re.search(r"\d{12,}/", body) and not re.search(r"/\d{12,}", body), body
    assert "pi/2" in body
    direct = from_document(read(BRANCHING, tip="tcp")[0], "x")
    assert_same_doubles(symdyn.load(out), direct)


def test_convert_refusals(tmp_path, capsys):
    source = tmp_path / "arm.urdf"
    source.write_text(HANDMADE.read_text())
    before = source.read_bytes()
    assert main(["convert", str(source), "--to", "yaml", "--out", str(source)]) == 1
    assert "it is an input file" in error_line(capsys) and source.read_bytes() == before
    assert main(["convert", robot_path("ur5"), "--to", "yaml"]) == 1
    assert "is a robot file already" in error_line(capsys)
    assert main(["convert", robot_path("ur5"), "--to", "urdf", "--tip", "x"]) == 1
    assert "apply to URDF input only" in error_line(capsys)
    assert main(["convert", str(source), "--to", "sdf"]) == 2
    capsys.readouterr()
    # a scene converts; its notes go into the URDF
    assert main(["convert", str(REPO / "robots" / "scenes" / "puma560_wrist_locked.yaml"), "--to", "urdf"]) == 0
    out = capsys.readouterr().out
    assert "Note: locked: joint 4 (wrist_roll)" in out and out.count('type="revolute"') == 3


def test_uppercase_extension_and_scene_tip(tmp_path):
    path = tmp_path / "ARM.URDF"
    path.write_text(BRANCHING.read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SymdynWarning)
        assert symdyn.load(path, tip="tcp").dof == 2
        scene = tmp_path / "cell.yaml"
        scene.write_text("scene: 1\nrobot: ARM.URDF\ntip: finger_l\nname: cell\n")
        assert symdyn.load(scene).dof == 3
    assert os.path.exists(path)


def test_reading_is_fast_enough_for_big_files():
    """A 1000-link chain with non-quarter-turn rotations everywhere reads in a few seconds."""
    parts = ['<robot name="big">', '<link name="l0"/>']
    for k in range(1, 1000):
        parts.append(f'<link name="l{k}"><inertial><origin xyz="0.1 0.2 0.3" rpy="0.1 0.2 0.3"/>'
                     '<mass value="1.5"/><inertia ixx="0.1" iyy="0.2" izz="0.25" ixy="0.01" ixz="0" iyz="0"/>'
                     '</inertial></link>')
        parts.append(f'<joint name="j{k}" type="{"fixed" if k % 2 == 0 else "revolute"}"><parent link="l{k - 1}"/>'
                     f'<child link="l{k}"/><origin xyz="0.1 0 0.2" rpy="0.3 0.1 0.2"/><axis xyz="0 0 1"/></joint>')
    doc, _ = read_urdf("\n".join(parts + ["</robot>"]), "big.urdf")
    assert len(doc["links"]) == 500
    with pytest.raises(RobotFileError, match="more than 2000 links"):
        read_urdf("<robot name='r'>" + "".join(f"<link name='a{k}'/>" for k in range(2001)) + "</robot>",
                  "many.urdf")


def test_a_mimic_of_no_joint_is_read_free_with_one_warning(tmp_path):
    """Alex's hands follow 'index_q1' where the file names it 'Left_index_q1': Pinocchio reads such
    a file only without mimic joints, and so does symdyn, saying so once (with the likely name)."""
    path = tmp_path / "arm.urdf"
    path.write_text(arm(extra='<mimic joint="j22"/>'))
    with pytest.warns(SymdynWarning, match=r"1 <mimic> element follows a joint that the file does not have \(j1 "
                                           r"follows 'j22' \(perhaps 'j2'\)\): those joints are read with coordinates"):
        robot = symdyn.load(str(path))
    assert robot.dof == 2 and not robot.mimics
    assert any("follow no joint of the file" in note for note in robot.notes)
