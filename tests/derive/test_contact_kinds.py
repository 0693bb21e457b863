"""Contacts held with a Baumgarte correction (``kp``, ``kd``, ``reference`` on a point contact)
and planar contacts (``xz``, ``xy``, ``yz``: a point held along two world axes).

The correction: the reference against Pinocchio's constraintDynamics and
computeConstraintDynamicsDerivatives with its corrector; symdyn's numpy, CasADi and C (runtime
parameters for the point held) against the reference; the correction changes the answer; gains
that cannot be read are refused in one line naming the file and field.

Planar contacts: Pinocchio has none, so the reference solves the KKT system with the rows of
Pinocchio's frame Jacobians and accelerations that the plane holds (its derivatives by finite
differences, lambda held in the world); symdyn's numpy and C against it on a floating base (where
the held directions do not turn with the base: the derivatives' base columns need their own
terms, and leaving them out is caught) and on the compass biped."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import sympy as sp

from helpers import REPO, error_line, example_robot_data, normalized_error
from symdyn.check.agreement import CasadiTarget, NumpyTarget
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import PinocchioReference, UrdfReference, compare, reduced
from symdyn.check.states import random_state
from symdyn.cli import main
from symdyn.derive.equations import derive
from symdyn.emit.cgen import generate_c
from symdyn.model.errors import SymdynError
from symdyn.model.outputs import CONTACT_DERIVATIVES, CONTACT_OUTPUTS, EXTERNAL_OUTPUTS, IMPULSE_OUTPUTS, Dimensions
from symdyn.model.scene import load_input

pin = pytest.importorskip("pinocchio")

SOLO = "solo_description/robots/solo12.urdf"
FEET = ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")
BOARD = REPO / "examples" / "contacts" / "tip_on_board.yaml"
NO_PARAMETERS = np.zeros(0)


def _corrected(robot, seed=3):
    """The robot's contacts each with gains and a reference of its own (exact numbers; a sole's
    placement turned by up to 0.4 rad about each axis)."""
    rng = np.random.default_rng(seed)
    return dataclasses.replace(robot, contacts=tuple(
        dataclasses.replace(c, kp=sp.Integer(30 + 20 * k), kd=sp.Integer(5 + k),
                            reference=tuple(sp.Rational(int(v), 1000)
                                            for v in rng.integers(-300, 300, 6 if c.kind == "6d" else 3)))
        for k, c in enumerate(robot.contacts)))


def _pinocchio_corrected(robot, ref):
    """``(model, data, models, datas, settings)``: Pinocchio's contact models of the corrected
    set (joint2_placement the reference, its Baumgarte parameters kp and kd), prepared."""
    model, data = ref.model, ref.model.createData()
    models = []
    for contact in robot.contacts:
        frame = model.frames[model.getFrameId(robot.frames[contact.frame].name)]
        numbers = [float(e) for e in contact.reference]
        sole = contact.kind == "6d"
        held = pin.SE3(pin.rpy.rpyToMatrix(*numbers[3:]) if sole else np.eye(3), np.array(numbers[:3]))
        cm = pin.RigidConstraintModel(pin.ContactType.CONTACT_6D if sole else pin.ContactType.CONTACT_3D, model,
                                      frame.parentJoint, frame.placement, 0, held, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        cm.setBaumgarteCorrectorParameters(pin.BaumgarteCorrectorParameters(float(contact.kp), float(contact.kd)))
        models.append(cm)
    models = pin.StdVec_RigidConstraintModel(models)
    datas = pin.StdVec_RigidConstraintData([m.createData() for m in models])
    pin.initConstraintDynamics(model, data, models, datas)
    return model, data, models, datas, pin.ProximalSettings(1e-14, 0.0, 1)


def _solo(feet):
    robot, _ = load_input(example_robot_data(SOLO), floating_base=True, contacts=",".join(f"{f}:3d" for f in feet))
    return robot


def _reference(robot):
    return reduced(UrdfReference(example_robot_data(SOLO), floating_base=True, frames=[f.name for f in robot.frames]),
                   robot)


def _states(robot, count, seed=11):
    rng = np.random.default_rng(seed)
    return [random_state(robot, rng) for _ in range(count)]


@pytest.mark.parametrize("contacts", [",".join(f"{f}:3d" for f in FEET), "FR_FOOT:3d,HL_FOOT:3d",
                                      "FR_FOOT:6d,HL_FOOT:3d"])
def test_reference_is_pinocchio_corrector(contacts):
    """The reference's contact dynamics with corrected contacts equal Pinocchio's own
    constraintDynamics with its corrector (a sole's error -log6(c1Mc2) too), and differ from the
    uncorrected ones by far more than the tolerance.  Its derivatives equal Pinocchio's
    computeConstraintDynamicsDerivatives on points; with a corrected sole Pinocchio 4.1's
    derivative along the base's rotation is not that of its own constraintDynamics (O(1) apart),
    so there they are checked against central differences of constraintDynamics itself."""
    plain = _solo_set(contacts)
    robot = _corrected(plain)
    ref, uncorrected = _reference(robot), _reference(plain)
    model, data, models, datas, settings = _pinocchio_corrected(robot, ref)
    damping = np.diag(ref.damping)
    sole = any(c.kind == "6d" for c in robot.contacts)
    for q, qd, _, tau in _states(robot, 3, seed=5):
        torque = tau - ref.friction(qd)
        theirs = pin.constraintDynamics(model, data, ref.configuration(q), qd, torque, models, datas, settings)
        mine = ref.contact_accelerations(q, qd, tau)
        assert normalized_error([mine], [theirs]) < 1e-9
        assert normalized_error([ref.contact_forces(q, qd, tau)], [data.lambda_c]) < 1e-9
        assert normalized_error([uncorrected.contact_accelerations(q, qd, tau)], [theirs]) > 1e-3
        pin.computeConstraintDynamicsDerivatives(model, data, models, datas, settings)
        expected = (data.ddq_dq, data.ddq_dv - data.ddq_dtau @ damping, data.ddq_dtau,
                    data.dlambda_dq, data.dlambda_dv - data.dlambda_dtau @ damping, data.dlambda_dtau)
        for name, value in zip(CONTACT_DERIVATIVES, expected):
            if sole and name in ("contact_accelerations_dq", "contact_forces_dq"):
                continue
            assert normalized_error([getattr(ref, name)(q, qd, tau)], [value]) < 1e-9, name
        if sole:  # d qdd / dq by central differences of constraintDynamics: a base-turn column, joints
            mine = ref.contact_accelerations_dq(q, qd, tau)
            h, at = 1e-5, ref.configuration(q)
            for j in (3, 4, 5, 7, 13):
                step = np.zeros(robot.nv)
                step[j] = h
                ahead, behind = (pin.constraintDynamics(model, data, pin.integrate(model, at, sign * step), qd, torque,
                                                        models, datas, settings).copy() for sign in (1, -1))
                column = (ahead - behind) / (2 * h)
                assert np.abs(mine[:, j] - column).max() < 1e-6 * np.abs(column).max(), j


@pytest.mark.slow  # (17 s of compiling the Panda's corrected sole)
def test_corrected_sole_both_branches(tmp_path):
    """A sole held with a correction, the Panda's last link: the placement error's log near the
    reference (its coefficients' series, turned by 0.1 rad) and far from it (the closed forms):
    symdyn's numpy (derivatives too) and C against the reference."""
    robot, _ = load_input(str(REPO / "robots" / "panda.yaml"))
    robot, _ = load_input(str(REPO / "robots" / "panda.yaml"), contacts=f"{robot.links[-1].name}:6d")
    home = np.array([0.1, -0.4, 0.2, -1.8, 0.1, 1.4, 0.3])
    from symdyn.check.pinocchio_model import PinocchioReference as Reference
    pose = Reference(robot).frame_poses(home)[4 * robot.contacts[0].frame:4 * robot.contacts[0].frame + 4]
    rpy = pin.rpy.matrixToRpy(pose[:3, :3] @ pin.rpy.rpyToMatrix(0.1, -0.05, 0.08))
    exact = [sp.Rational(round(v * 10 ** 6), 10 ** 6) for v in list(pose[:3, 3] + [0.01, -0.02, 0.015]) + list(rpy)]
    near = dataclasses.replace(robot, contacts=(dataclasses.replace(robot.contacts[0], kp=sp.Integer(80), kd=sp.Integer(12),
                                                                    reference=tuple(exact)),))
    rng = np.random.default_rng(4)
    states = [(home + rng.normal(0, 0.03, 7), rng.normal(0, 0.5, 7), None, rng.normal(0, 5, 7)) for _ in range(3)]
    ref = reduced(PinocchioReference(near), near)
    wanted = CONTACT_OUTPUTS + CONTACT_DERIVATIVES
    errors = compare(NumpyTarget(derive(near, outputs=wanted)), ref, states, wanted, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors
    lib = build_and_load(generate_c(derive(near, outputs=CONTACT_OUTPUTS), CONTACT_OUTPUTS), near.name,
                         Dimensions.of(near), 0, "double", str(tmp_path))
    far_states = _states(near, 3)
    errors = compare(lib, ref, states + far_states, CONTACT_OUTPUTS, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors


@pytest.mark.slow
def test_corrected_sole_on_a_floating_base():
    """Solo-12 holding a foot as a sole with a correction (and another as a point): the
    derivatives' base columns of the sole's log term, in numpy against the reference."""
    wanted = CONTACT_OUTPUTS + CONTACT_DERIVATIVES
    solo = _corrected(_solo_set("FR_FOOT:6d,HL_FOOT:3d"))
    errors = compare(NumpyTarget(derive(solo, outputs=wanted)), _reference(solo), _states(solo, 3), wanted, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors


@pytest.mark.slow
def test_corrected_feet_numpy_and_casadi():
    """Solo-12 on two corrected feet: symdyn's contact dynamics and their derivatives (a floating
    base: the base's columns carry the correction's kp terms) in numpy, the contact dynamics in
    CasADi, against the reference."""
    robot = _corrected(_solo(FEET[1:3]))
    ref = _reference(robot)
    states = _states(robot, 4, seed=7)
    eqs = derive(robot, outputs=CONTACT_OUTPUTS + CONTACT_DERIVATIVES)
    errors = compare(NumpyTarget(eqs), ref, states, CONTACT_OUTPUTS + CONTACT_DERIVATIVES, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors
    errors = compare(CasadiTarget(derive(robot, outputs=CONTACT_OUTPUTS)), ref, states, CONTACT_OUTPUTS, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors


def test_point_held_at_runtime_reference(tmp_path):
    """examples/contacts/tip_on_board.yaml: the point held and kp are runtime parameters (p): the
    C functions at values other than the nominal ones against Pinocchio's model with those values,
    derivatives included; the header documents the correction."""
    robot, _ = load_input(str(BOARD))
    names = [s.name for s in robot.parameters]
    assert names == ["board_x", "board_y", "board_z", "kp_tip"]
    values = dict(zip(robot.parameters, (0.4, -0.1, 0.3, 60.0)))
    p = np.array([values[s] for s in robot.parameters])
    ref = reduced(PinocchioReference(robot, values), robot, values)
    wanted = CONTACT_OUTPUTS + CONTACT_DERIVATIVES
    files = generate_c(derive(robot, outputs=wanted), wanted)
    header = next(text for name, text in files.items() if name.endswith(".h"))
    assert "Baumgarte correction" in header and "reference = (board_x, board_y, board_z)" in header
    lib = build_and_load(files, robot.name, Dimensions.of(robot), len(p), "double", str(tmp_path))
    states = _states(robot, 5)
    errors = compare(lib, ref, states, wanted, p)
    assert max(errors.values()) < 1e-9, errors
    nominal = reduced(PinocchioReference(robot), robot)  # the reference moved: another answer
    q, qd, _, tau = states[0]
    assert normalized_error([lib.contact_accelerations(q, qd, tau, p)], [nominal.contact_accelerations(q, qd, tau)]) > 1e-3


@pytest.mark.parametrize("entry,expected,field", [
    ("{frame: tip, kind: 3d, kp: -5, reference: [0, 0, 0]}", "a gain is at least 0", "contacts[0].kp"),
    ("{frame: tip, kind: 3d, kp: 5}", "kp needs reference", "contacts[0]"),
    ("{frame: tip, kind: 3d, kd: 5, reference: [0, 0, 0]}", "reference without kp", "contacts[0].reference"),
    ("{frame: tip, kind: 3d, kp: 5, reference: [0, 0]}", "expected [x, y, z]", "contacts[0].reference"),
    ("{frame: tip, kind: 6d, kp: 5, reference: [0, 0, 0]}", "expected [x, y, z, roll, pitch, yaw]",
     "contacts[0].reference"),
    ("{frame: tip, kind: 3d, kp: k_tip, reference: [0, 0, 0]}", "unknown name 'k_tip'", "contacts[0].kp"),
    ("{frame: tip, kind: 3d, kp: 5, reference: [0, .nan, 0]}", "finite", "contacts[0].reference[1]"),
    ("{frame: tip, kind: 3d, gain: 5}", "unknown field 'gain'", "contacts[0]"),
])
def test_correction_errors(entry, expected, field, tmp_path, capsys):
    """Gains that cannot be used stop the CLI with one line naming the file, the field and the
    problem, and write nothing."""
    text = BOARD.read_text().split("contacts:")[0] + f"contacts:\n  - {entry}\n"
    path = tmp_path / "board.yaml"
    path.write_text(text)
    with pytest.raises(SymdynError) as caught:
        load_input(str(path))
    assert expected in str(caught.value) and field in str(caught.value), str(caught.value)
    out = tmp_path / "out"
    assert main(["generate", str(path), "--out", str(out)]) != 0
    line = error_line(capsys)
    assert expected in line and "board.yaml" in line and "Traceback" not in line
    assert not out.exists()


def test_scene_correction_numbers_only(tmp_path):
    """A scene's contacts over a URDF take gains and a reference in numbers (read as a robot
    file's); a name there is refused, pointing to the robot file."""
    scene = tmp_path / "standing.yaml"
    scene.write_text(f"scene: 1\nrobot: {example_robot_data(SOLO)}\nfloating_base: true\n"
                     "contacts: [{frame: FL_FOOT, kind: 3d, kp: 40, kd: 8, reference: [0.2, 0.15, 0]}, HR_FOOT:3d]\n")
    robot, found = load_input(str(scene))
    first, second = robot.contacts
    assert (first.kp, first.kd, first.reference) == (40, 8, (sp.Rational(1, 5), sp.Rational(3, 20), 0))
    assert not second.corrected
    assert any("FL_FOOT:3d (kp 40, kd 8)" in note for note in found.notes)
    scene.write_text(f"scene: 1\nrobot: {example_robot_data(SOLO)}\nfloating_base: true\n"
                     "contacts: [{frame: FL_FOOT, kind: 3d, kp: k, reference: [0, 0, 0]}]\n")
    with pytest.raises(SymdynError, match="belong in the robot file"):
        load_input(str(scene))


#: (slow: the fixed fuzz campaign's cases 0 and 27 hold planar contacts on floating bases too)
PLANAR_SETS = [pytest.param("FR_FOOT:xz,HL_FOOT:3d", marks=pytest.mark.slow),
               pytest.param("FR_FOOT:yz,HL_FOOT:xy,FL_FOOT:3d", marks=pytest.mark.slow)]


@pytest.mark.parametrize("contacts", PLANAR_SETS)
def test_planar_contacts_on_a_floating_base(contacts, monkeypatch):
    """Solo-12 holding feet in coordinate planes (the second set corrected too): every contact
    function and the derivatives in numpy against the reference; the reference's solution keeps
    the plane's rows of the feet still and the equations of motion hold, by Pinocchio's numbers;
    without the planar contacts' base-turn terms the derivatives by q disagree."""
    robot = _solo_set(contacts)
    if robot.contacts[-1].kind == "3d" and len(robot.contacts) == 3:
        robot = _corrected(robot)
    ref = _reference(robot)
    states = _states(robot, 3, seed=13)
    wanted = CONTACT_OUTPUTS + CONTACT_DERIVATIVES + IMPULSE_OUTPUTS + EXTERNAL_OUTPUTS
    errors = compare(NumpyTarget(derive(robot, outputs=wanted)), ref, states, wanted, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors
    q, qd, _, tau = states[0]
    qdd, forces = ref.contact_accelerations(q, qd, tau), ref.contact_forces(q, qd, tau)
    J_all, drift = ref.frame_jacobians(q), ref.frame_jacobian_dot_v(q, qd)
    rows = [6 * c.frame + a for c in robot.contacts for a in c.axes]
    assert len(rows) == robot.contact_rows == len(forces)
    if not any(c.corrected for c in robot.contacts):
        assert np.abs(J_all[rows] @ qdd + drift[rows]).max() < 1e-10 * (1 + np.abs(drift[rows]).max())
    M, b = ref.system_matrix(q), ref.inverse_dynamics(q, qd, np.zeros(robot.nv))
    assert np.abs(M @ qdd - (tau - b + J_all[rows].T @ forces)).max() < 1e-9 * (1 + np.abs(tau - b).max())
    from symdyn.derive import equations
    monkeypatch.setattr(equations, "_planar_base_columns", lambda d, contact, force, point, dF1_q, rows, R_w, p_w: rows)
    errors = compare(NumpyTarget(derive(robot, outputs=("contact_accelerations_dq",))), ref, states,
                     ("contact_accelerations_dq",), NO_PARAMETERS)
    assert errors["contact_accelerations_dq"] > 1e-4, errors


def _solo_set(contacts):
    robot, _ = load_input(example_robot_data(SOLO), floating_base=True, contacts=contacts)
    return robot


def test_compass_biped_in_c(tmp_path):
    """examples/contacts/compass_biped.yaml (a planar contact on a fixed base, two rows pinning
    two joints): C against Pinocchio's model, derivatives and impulse dynamics included, away
    from the aligned legs (dqdd/dtau zero but for rounding: pinned); at the aligned legs status
    3 (CONTACT_SINGULAR)."""
    robot, _ = load_input(str(REPO / "examples" / "contacts" / "compass_biped.yaml"))
    assert [(robot.frames[c.frame].name, c.kind, c.rows) for c in robot.contacts] == [("swing_foot", "xz", 2)]
    ref = reduced(PinocchioReference(robot), robot)
    wanted = CONTACT_OUTPUTS + CONTACT_DERIVATIVES + IMPULSE_OUTPUTS
    files = generate_c(derive(robot, outputs=wanted), wanted)
    header = next(text for name, text in files.items() if name.endswith(".h"))
    assert "a point held in the xz plane: force (N) x, z" in header
    lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, "double", str(tmp_path))
    states = _states(robot, 5)
    for state in states:
        state[0][1] = 0.4 + abs(state[0][1])  # the legs apart: det J_c = s2 away from 0
    pinned = "contact_accelerations_dtau"  # zero: the contacts leave no motion to the torques
    errors = compare(lib, ref, states, [f for f in wanted if f != pinned], NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors
    q, qd, _, tau = states[0]
    scale = np.abs(np.linalg.inv(ref.system_matrix(q))).max()
    assert np.abs(lib.contact_accelerations_dtau(q, qd, tau)).max() < 1e-13 * scale
    q = np.array([0.3, 0.0])
    status, (qdd, forces) = lib.with_status("contact_forward_dynamics", q, qd, tau)
    assert status == 3 and np.all(np.isnan(qdd)) and np.all(np.isnan(forces))
