"""Kinematic trees (links with ``parent:``, URDFs whose moving joints branch): every joint-space
function against Pinocchio, the mass matrix's sparsity, and what is refused for trees."""

from __future__ import annotations

import re
import shutil
import subprocess
import warnings
from dataclasses import replace

import numpy as np
import pytest

from symdyn.model.outputs import Dimensions
import symdyn
from helpers import REPO, TOL, example_robot_data, random_states
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import PinocchioReference, UrdfReference, compare
from symdyn.check.reference import MpReference
from symdyn.check.states import random_state
from symdyn.emit.cgen import generate_c
from symdyn.model.errors import SymdynError, SymdynWarning
from symdyn.model.outputs import TREE_OUTPUTS

HAND_TREE = str(REPO / "examples" / "trees" / "torso_two_arms.yaml")



@pytest.fixture(scope="module")
def hand_tree():
    robot = symdyn.load(HAND_TREE)
    return robot, symdyn.derive(robot)


def _snapped(robot):
    """The tolerance Pinocchio's reading takes quarter turns at when symdyn's did (its notes say
    so): both then read the same model."""
    from symdyn.model.urdf import QUARTER_TOLERANCE
    return QUARTER_TOLERANCE if any("multiple of pi/2" in note for note in robot.notes) else None


def _cross_branch_pairs(robot) -> set:
    """(i, j) of joints neither of which is an ancestor of the other."""
    n = robot.dof
    return {(i, j) for i in range(n) for j in range(n)
            if i != j and i not in robot.ancestors(j) and j not in robot.ancestors(i)}


def test_yaml_tree_with_dh_placements_agrees_with_pinocchio(hand_tree, tmp_path):
    """The hand-written tree (a torso turning two DH arms, one with a prismatic joint; armature,
    damping and Coulomb friction on some joints): every function at 50 states against Pinocchio
    (the model built joint by joint with each joint's parent), numerically and in compiled C; and
    the 50-digit reference, an independent recursion over the same parents, against Pinocchio."""
    robot, eqs = hand_tree
    assert robot.parents == (-1, 0, 1, 2, 0, 4, 5) and set(eqs.output_names) == set(TREE_OUTPUTS)
    reference = PinocchioReference(robot)
    states = random_states(robot.dof, 50, seed=5)
    errors = compare(eqs.numeric, reference, states, TREE_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), errors
    files = generate_c(eqs, TREE_OUTPUTS, "double")
    lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
    errors = compare(lib, reference, states, TREE_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), errors
    precise = MpReference(robot)
    errors = compare(precise, reference, states[:3], ("inverse_dynamics", "mass_matrix", "forward_dynamics"))
    assert all(e <= 1e-12 for e in errors.values()), errors


def test_mass_matrix_entries_across_branches_are_exact_zeros_not_computed(hand_tree):
    """The two arms' joints (3 x 3 pairs each way) have D_ij = 0 exactly, written as constants;
    every other entry is computed, and nonzero at a random state unless it is zero exactly."""
    robot, eqs = hand_tree
    D = eqs.mass_matrix
    zeros = {(i, j) for i in range(robot.dof) for j in range(robot.dof) if D[i, j] == 0}
    # (l_wrist slides along l_elbow's axis: D[2, 3] = 0 too, a zero of the geometry, not of the tree)
    assert _cross_branch_pairs(robot) <= zeros and len(_cross_branch_pairs(robot)) == 18
    values = eqs.numeric.mass_matrix(np.random.default_rng(2).uniform(-2, 2, robot.dof))
    assert np.all(np.abs(values[[i for i, _ in sorted(zeros)], [j for _, j in sorted(zeros)]]) == 0)
    assert np.count_nonzero(values) == robot.dof ** 2 - len(zeros)
    source = generate_c(eqs, ["mass_matrix"], "double")[f"{robot.name}_dynamics.c"]
    constant = {int(k) for k in re.findall(r"\bD\[(\d+)\] = 0\.0;", source)}
    copies = dict((int(a), int(b)) for a, b in re.findall(r"\bD\[(\d+)\] = D\[(\d+)\];", source))
    n = robot.dof
    assert {i * n + j for i, j in zeros if i < j} <= constant  # the upper triangle: constants
    assert all(copies[i * n + j] in constant for i, j in zeros if i > j)  # the lower: copies of them


@pytest.mark.parametrize("relative, floating", [("anymal_b_simple_description/robots/anymal.urdf", False),
                                                pytest.param("talos_data/robots/talos_reduced.urdf", True,
                                                             marks=pytest.mark.slow)],
                         ids=["anymal", "talos_reduced_floating"])
def test_whole_urdf_trees_agree_with_pinocchio_urdf_parser(relative, floating):
    """A quadruped, ANYmal (four legs on the base, links named as their joints), with a fixed
    base (Solo-12 floats below), and TALOS's reduced humanoid (32 joints: legs, torso, arms, head) on a floating base
    (38 velocities), read whole, against Pinocchio's own reading of the same file: the joint
    order is Pinocchio's, every function agrees at 50 states, and the mass matrix has exact
    zeros across branches."""
    path = example_robot_data(relative)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SymdynWarning)
        robot = symdyn.load(path, floating_base=floating)
    reference = UrdfReference(path, quarter_turns=_snapped(robot), floating_base=floating)
    assert robot.is_tree and [link.name for link in robot.links] == reference.joint_names
    eqs = symdyn.derive(robot)
    rng = np.random.default_rng(9)
    errors = compare(eqs.numeric, reference, [random_state(robot, rng) for _ in range(50)], eqs.output_names)
    assert all(e <= TOL for e in errors.values()), errors
    D, base = eqs.mass_matrix, 6 if floating else 0
    zeros = {(i, j) for i in range(robot.dof) for j in range(robot.dof) if D[base + i, base + j] == 0}
    assert _cross_branch_pairs(robot) <= zeros


def test_tree_fields_are_checked_and_what_trees_lack_is_refused(tmp_path):
    """``parent:`` names an earlier link or ``base`` (a misspelt name gets did-you-mean); a tree
    refuses, in one line each, Lagrange-Euler, the articulated-body forward dynamics and the
    single-tool functions."""
    text = open(HAND_TREE).read()
    for bad, expected in ((text.replace("parent: torso\n    joint: revolute\n    a: 0.1\n    alpha: pi/2",
                                        "parent: torsoo\n    joint: revolute\n    a: 0.1\n    alpha: pi/2"),
                           ["link 2 ('l_shoulder')", "field 'parent'", "no link named 'torsoo'", "did you mean 'torso'?"]),
                          (text.replace("parent: torso\n    joint: revolute\n    a: 0.1\n    alpha: -pi/2",
                                        "parent: r_wrist\n    joint: revolute\n    a: 0.1\n    alpha: -pi/2"),
                           ["link 5 ('r_shoulder')", "'r_wrist' comes after this link"]),
                          (text.replace("    parent: torso", "    parent: [torso]", 1),
                           ["field 'parent'", "expected the name of an earlier link or 'base'"])):
        assert bad != text
        path = tmp_path / "bad.yaml"
        path.write_text(bad)
        with pytest.raises(SymdynError) as caught:
            symdyn.load(str(path))
        message = str(caught.value)
        assert all(part in message for part in expected) and "\n" not in message, message
    robot = symdyn.load(HAND_TREE)
    for kwargs, expected in (({"method": "lagrange-euler"}, "use newton-euler"),
                             ({"fd_method": "aba"}, "--fd-method ldlt"),
                             ({"outputs": ["jacobian"]}, "jacobian is not available for a kinematic tree")):
        with pytest.raises(SymdynError, match=re.escape(expected)):
            symdyn.derive(robot, **kwargs)


def test_cli_on_a_tree(tmp_path, capsys):
    """generate takes a tree; derive prints its Newton-Euler recursion (the link matrices named
    after each link's parent) and refuses, in one line, the methods written for chains."""
    from symdyn.cli import main
    assert main(["generate", HAND_TREE, "--out", str(tmp_path), "--functions", "gravity,forward_dynamics",
                 "--quiet"]) == 0
    header = (tmp_path / "twoarms_dynamics.h").read_text()
    assert "5: r_shoulder, revolute, on joint 1 (torso)" in header and "L^T D L of the tree's D" in header
    assert main(["derive", HAND_TREE, "--out", str(tmp_path / "tree.txt"), "--quiet"]) == 0
    text = (tmp_path / "tree.txt").read_text()
    assert "¹A₅ =" in text and "⁴A₅" not in text and "p(5) = 1" in text
    for method, expected in (("aba", "--fd-method ldlt"), ("lagrange-euler", "use newton-euler")):
        assert main(["derive", HAND_TREE, "--method", method, "--out", str(tmp_path / "no.md"), "--quiet"]) == 1
        err = capsys.readouterr().err.strip()
        assert expected in err and len(err.splitlines()) == 1 and not (tmp_path / "no.md").exists()


@pytest.mark.parametrize("path", [HAND_TREE, str(REPO / "examples" / "trees" / "space_robot.yaml")],
                         ids=["fixed", "floating"])
def test_printed_tree_derivation_equals_pinocchio(path, tmp_path):
    """The printed Newton-Euler derivation of a tree (and of a floating base under gravity: the
    base's acceleration v0dot, force f0 and moment n0), every named quantity resolved: tau_i of
    the backward recursion (with the base's f0, n0: Pinocchio's first six rows) and D, h, c as
    printed, at seeded states against Pinocchio."""
    import sympy as sp
    from symdyn.derive.derivation import derive_steps
    from symdyn.derive.numeric import compile_function
    text = open(path).read()
    if "gravity: [0, 0, 0]" in text:  # the satellite, on the ground: the base's R^T g enters
        path = tmp_path / "grounded.yaml"
        path.write_text(text.replace("gravity: [0, 0, 0]", "gravity: [0.3, -1.2, -9.81]"))
    robot = symdyn.load(str(path))
    d = derive_steps(robot, "newton-euler")
    reference = PinocchioReference(robot)
    eqs = symdyn.derive(robot, outputs=["gravity"])
    inputs = [eqs.q, eqs.qd, eqs.qdd]
    program = d.program()
    rows = [d.quantity("tau", i + 1) for i in range(robot.dof)]
    if robot.floating:
        rows = list(d.quantity("f", 0)) + list(d.quantity("n", 0)) + rows
    taus = compile_function(inputs, program, sp.Matrix(rows))
    results = {k: compile_function(inputs, program, sp.Matrix(d.quantity(k))) for k in ("D", "h", "c")}
    rng = np.random.default_rng(12)
    for _ in range(5):
        q, qd, qdd, _ = random_state(robot, rng)
        args = (q, qd, qdd)
        friction = reference.friction(qd) + reference.armature * qdd
        for mine, theirs in ((taus(*args).ravel(), reference.inverse_dynamics(q, qd, qdd) - friction),
                             (results["D"](*args), reference.mass_matrix(q)),
                             (results["h"](*args).ravel(), reference.coriolis(q, qd)),
                             (results["c"](*args).ravel(), reference.gravity(q))):
            np.testing.assert_allclose(mine, theirs, rtol=1e-9, atol=1e-9)
    if robot.floating and shutil.which("pdflatex"):  # the base's paragraph and quantities typeset
        from symdyn.emit.printout import render
        (tmp_path / "tree.tex").write_text(render(d, "latex", source_name="grounded.yaml"))
        result = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "tree.tex"],
                                cwd=tmp_path, capture_output=True, text=True, timeout=120)
        assert result.returncode == 0, result.stdout[-2000:]
        assert "Overfull \\hbox" not in (tmp_path / "tree.log").read_text(errors="replace")


SOLO = "solo_description/robots/solo12.urdf"


def test_floating_base_quadruped_agrees_with_pinocchio_free_flyer(tmp_path):
    """solo12.urdf with --floating-base against Pinocchio's buildModelFromUrdf(path,
    JointModelFreeFlyer()): q has 19 entries (position, quaternion x y z w, 12 joints), v 18;
    every function (the Coriolis matrix too: Pinocchio's, in the base's velocities) at 50 states,
    numerically, and inverse dynamics, the mass matrix and forward dynamics in compiled C.  The same pose with the
    quaternion negated or scaled gives the same numbers (it is normalized); a zero quaternion
    makes forward dynamics return 2 (not finite) and write nothing."""
    path = example_robot_data(SOLO)
    robot = symdyn.load(path, floating_base=True)
    assert (robot.nq, robot.nv, robot.floating) == (19, 18, True)
    reference = UrdfReference(path, floating_base=True)
    assert reference.model.nq == 19 and [link.name for link in robot.links] == reference.joint_names
    eqs = symdyn.derive(robot)
    functions = TREE_OUTPUTS
    assert eqs.output_names == tuple(functions)
    rng = np.random.default_rng(4)
    states = [random_state(robot, rng) for _ in range(50)]
    errors = compare(eqs.numeric, reference, states, functions)
    assert all(e <= TOL for e in errors.values()), errors
    compiled = ("inverse_dynamics", "mass_matrix", "forward_dynamics")  # the others' C: the satellite's test
    lib = build_and_load(generate_c(eqs, compiled, "double"), robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
    errors = compare(lib, reference, states, compiled)
    assert all(e <= TOL for e in errors.values()), errors
    for q, qd, qdd, tau in states[:5]:
        for factor in (-1.0, 3.7, -0.02):
            other = np.concatenate([q[:3], factor * q[3:7], q[7:]])
            for name, args in (("inverse_dynamics", (qd, qdd)), ("mass_matrix", ()), ("forward_dynamics", (qd, tau))):
                mine, same = getattr(lib, name)(q, *args), getattr(lib, name)(other, *args)
                assert np.allclose(same, mine, rtol=1e-13, atol=1e-13 * np.max(np.abs(mine))), (name, factor)
    q, qd, _, tau = states[0]
    zero = np.concatenate([q[:3], np.zeros(4), q[7:]])
    status, qdd = lib.forward_dynamics_checked(zero, qd, tau, qdd=np.full(robot.nv, 7.0))
    assert status == 2 and np.all(qdd == 7.0)


def test_floating_base_robot_file_and_its_checks(tmp_path):
    """A robot file with 'base: floating' and 'base_body' (a satellite with two DH arms, one
    with a prismatic joint; armature and friction) agrees with Pinocchio's free-flyer model of
    it, in orbit and under gravity, every function (h, C and c in compiled C as well); 'base_body'
    without a floating base, and a
    base that is neither a placement nor 'floating', are refused in one line."""
    path = REPO / "examples" / "trees" / "space_robot.yaml"
    text = path.read_text()
    heavy = tmp_path / "grounded.yaml"
    heavy.write_text(text.replace("gravity: [0, 0, 0]", "gravity: [0.3, -1.2, -9.81]"))
    for source in (path, heavy):
        robot = symdyn.load(str(source))
        assert (robot.nq, robot.nv, robot.parents) == (13, 12, (-1, 0, 1, -1, 3, 4))
        eqs = symdyn.derive(robot)
        rng = np.random.default_rng(8)
        states = [random_state(robot, rng) for _ in range(50)]
        errors = compare(eqs.numeric, PinocchioReference(robot), states, eqs.output_names)
        assert all(e <= TOL for e in errors.values()), (source, errors)
    # the compiled C of the functions Solo-12's test leaves to numpy
    rest = ("coriolis", "coriolis_matrix", "gravity")
    lib = build_and_load(generate_c(eqs, rest, "double"), robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
    errors = compare(lib, PinocchioReference(robot), states, rest)
    assert all(e <= TOL for e in errors.values()), errors
    for bad, expected in ((text.replace("base: floating\n", ""), ["field 'base_body'", "needs 'base: floating'"]),
                          (text.replace("base: floating", "base: free"), ["field 'base'", "expected 'floating'"])):
        bad_path = tmp_path / "bad.yaml"
        bad_path.write_text(bad)
        with pytest.raises(SymdynError) as caught:
            symdyn.load(str(bad_path))
        assert all(part in str(caught.value) for part in expected) and "\n" not in str(caught.value)


def test_dual_arm_baxter_without_its_mimic_tags(tmp_path):
    """Baxter (head pan, two 7-joint arms, two prismatic fingers per gripper): its file couples
    each gripper's second finger to the first with <mimic> (read as mimic joints: 17 coordinates,
    tests/model/test_mimic.py); with those two tags removed (each finger its own coordinate, as
    Pinocchio reads them by default) the whole 19-joint tree agrees with Pinocchio's reading of
    the same file."""
    import xml.etree.ElementTree as ET
    original = example_robot_data("baxter_description/urdf/baxter.urdf")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SymdynWarning)
        assert symdyn.load(original).dof == 17
    tree = ET.parse(original)
    for joint in tree.getroot().iter("joint"):
        for mimic in joint.findall("mimic"):
            joint.remove(mimic)
    path = str(tmp_path / "baxter.urdf")
    tree.write(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SymdynWarning)
        robot = symdyn.load(path)
    reference = UrdfReference(path, quarter_turns=_snapped(robot))
    assert robot.dof == 19 and [link.name for link in robot.links] == reference.joint_names
    assert len(robot.children(-1)) == 3  # the head and the two arms hang on the torso
    eqs = symdyn.derive(robot)
    rng = np.random.default_rng(12)
    errors = compare(eqs.numeric, reference, [random_state(robot, rng) for _ in range(50)], TREE_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), errors


def test_trees_convert_to_urdf_and_back(tmp_path):
    """A tree and a floating base written as URDF (parents as the links' parents; the floating
    base's body on the root link, with a comment to read it with --floating-base) read back to
    the same dynamics (in the order Pinocchio numbers the joints, and without what URDF cannot
    hold: armature, a gravity other than URDF's)."""
    from symdyn.cli import main
    for source, floating in ((HAND_TREE, False), (str(REPO / "examples" / "trees" / "space_robot.yaml"), True)):
        out = tmp_path / "tree.urdf"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SymdynWarning)  # armature: no place for it in URDF
            assert main(["convert", source, "--to", "urdf", "--out", str(out), "--quiet"]) == 0
            back = symdyn.load(str(out), floating_base=floating)
        robot = symdyn.load(source)
        # URDF holds neither armature nor gravity (read back as -9.81 m/s^2 along z)
        robot = replace(robot, links=tuple(replace(link, armature=0) for link in robot.links), gravity=back.gravity)
        assert back.dof == robot.dof and back.floating == floating
        rng = np.random.default_rng(3)
        states = [random_state(robot, rng) for _ in range(5)]
        order = [robot.links.index(next(l for l in robot.links if l.name == b.name)) for b in back.links]
        mine, theirs = symdyn.derive(robot).numeric, symdyn.derive(back).numeric
        base = 6 if floating else 0
        index = list(range(base)) + [base + k for k in order]
        qindex = list(range(7 if floating else 0)) + [(7 if floating else 0) + k for k in order]
        for q, qd, qdd, _ in states:
            expected = mine.inverse_dynamics(q, qd, qdd)[index]
            found = theirs.inverse_dynamics(q[qindex], qd[index], qdd[index])
            assert np.allclose(found, expected, rtol=1e-9, atol=1e-9 * np.max(np.abs(expected)))


def test_scene_of_a_urdf_on_a_floating_base(tmp_path):
    """A scene's 'floating_base: true' reads its URDF as --floating-base does (and must be true
    or false), and may lock joints of the tree (their correctness: tests/model/test_scene.py)."""
    path = example_robot_data(SOLO)
    scene = tmp_path / "solo.yaml"
    scene.write_text(f"scene: 1\nrobot: {path}\nfloating_base: true\nfunctions: [gravity]\n")
    robot = symdyn.load(str(scene))
    assert robot.floating and (robot.nq, robot.nv) == (19, 18)
    scene.write_text(f"scene: 1\nrobot: {path}\nfloating_base: yes please\n")
    with pytest.raises(SymdynError, match="floating_base.*expected true or false"):
        symdyn.load(str(scene))
    scene.write_text(f"scene: 1\nrobot: {path}\nfloating_base: true\nlock: {{FL_KFE: -1.2, HR_KFE: 1.2}}\n")
    locked = symdyn.load(str(scene))
    names = [link.name for link in robot.links]
    assert (locked.nq, locked.nv) == (17, 16) and locked.floating
    assert [link.name for link in locked.links] == [n for n in names if n not in ("FL_KFE", "HR_KFE")]
    # the feet's parents are now the hip-flexion joints (the knees' links merged into them)
    assert locked.parent_indices[:4] == (-1, 0, -1, 2)
