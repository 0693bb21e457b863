"""Contact dynamics (contact_accelerations, contact_forces, contact_forward_dynamics): the
reference against Pinocchio's constraintDynamics itself, symdyn's C, numpy and CasADi against the
reference on Solo-12 with 4, 3 and 2 point feet, TALOS reduced on two soles, an arm with its tool
held; the constraints and the equations of motion hold; dependent contacts return status 3, a
singular M 1, a NaN 2, and nothing is written; contact sets that cannot be read are refused in one
line."""

from __future__ import annotations

import numpy as np
import pytest

from helpers import REPO, error_line, example_robot_data, normalized_error, robot_path, run_sanitized
from symdyn.check.agreement import CasadiTarget, NumpyTarget
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import UrdfReference, compare, reduced
from symdyn.check.states import contact_forces_of, random_state
from symdyn.cli import main
from symdyn.derive.equations import derive
from symdyn.emit.cgen import generate_c
from symdyn.model.errors import SymdynError
from symdyn.model.outputs import CONTACT_DERIVATIVES, CONTACT_INVERSE, CONTACT_OUTPUTS, EXTERNAL_OUTPUTS, IMPULSE_OUTPUTS, Dimensions
from symdyn.model.scene import load_input

pin = pytest.importorskip("pinocchio")

SOLO = "solo_description/robots/solo12.urdf"
FEET = ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")
TALOS = "talos_data/robots/talos_reduced.urdf"
TOL = 1e-10
NO_PARAMETERS = np.zeros(0)
_BUILT: dict = {}


def _contacts(names, kind="3d") -> str:
    return ",".join(f"{name}:{kind}" for name in names)


def _robot(relative, contacts):
    robot, _ = load_input(example_robot_data(relative), floating_base=True, contacts=contacts)
    return robot


def _reference(relative, robot):
    ref = UrdfReference(example_robot_data(relative), floating_base=True, frames=[f.name for f in robot.frames])
    return reduced(ref, robot)


def _pinocchio_contacts(robot, ref):
    """``(model, data, models, datas, settings)``: Pinocchio's own contact models of the robot's
    contact set on the reference's model (LOCAL_WORLD_ALIGNED), its data prepared by
    initConstraintDynamics, and exact settings (one iteration, no proximal term)."""
    model = ref.model
    data = model.createData()
    models = []
    for contact in robot.contacts:
        frame = model.frames[model.getFrameId(robot.frames[contact.frame].name)]
        kind = pin.ContactType.CONTACT_3D if contact.kind == "3d" else pin.ContactType.CONTACT_6D
        models.append(pin.RigidConstraintModel(kind, model, frame.parentJoint, frame.placement,
                                               pin.ReferenceFrame.LOCAL_WORLD_ALIGNED))
    models = pin.StdVec_RigidConstraintModel(models)
    datas = pin.StdVec_RigidConstraintData([m.createData() for m in models])
    pin.initConstraintDynamics(model, data, models, datas)
    return model, data, models, datas, pin.ProximalSettings(1e-14, 0.0, 1)


def _states(robot, count, seed=11):
    rng = np.random.default_rng(seed)
    return [random_state(robot, rng) for _ in range(count)]


#: what Solo-12's four-feet library holds: one compile for every test of it
SOLO_WANTED = CONTACT_OUTPUTS + IMPULSE_OUTPUTS + CONTACT_INVERSE


def _compiled(key, robot, tmp_path_factory, precision="double", wanted=CONTACT_OUTPUTS):
    """One compile per robot and contact set: the ``wanted`` functions (the combined ones too)."""
    if key not in _BUILT:
        eqs = derive(robot, outputs=wanted)
        files = generate_c(eqs, wanted, precision=precision)
        _BUILT[key] = build_and_load(files, robot.name, Dimensions.of(robot), 0, precision,
                                     str(tmp_path_factory.mktemp("contact")))
    return _BUILT[key]


@pytest.mark.parametrize("relative,contacts", [(SOLO, _contacts(FEET)), (SOLO, _contacts(FEET[:3])),
                                               (SOLO, _contacts(FEET[1:3])),
                                               (TALOS, "left_sole_link:6d,right_sole_link:6d")])
def test_reference_is_pinocchio_constraint_dynamics(relative, contacts):
    """The reference (Pinocchio's M, bias, frame Jacobians and accelerations, a dense KKT solve)
    equals Pinocchio's own constraintDynamics with the same contact models (LOCAL_WORLD_ALIGNED
    point and 6D contacts; its lambda_c the forces on the robot) at random states."""
    robot = _robot(relative, contacts)
    ref = _reference(relative, robot)
    model, data, models, datas, settings = _pinocchio_contacts(robot, ref)
    theirs_qdd, theirs_f, mine_qdd, mine_f = [], [], [], []
    for q, qd, _, tau in _states(robot, 6):
        theirs_qdd.append(pin.constraintDynamics(model, data, ref.configuration(q), qd, tau - ref.friction(qd),
                                                 models, datas, settings))  # (friction is symdyn's, as in aba's)
        theirs_f.append(data.lambda_c.copy())
        mine_qdd.append(ref.contact_accelerations(q, qd, tau))
        mine_f.append(ref.contact_forces(q, qd, tau))
    assert normalized_error(mine_qdd, theirs_qdd) < 1e-9
    assert normalized_error(mine_f, theirs_f) < 1e-9


@pytest.mark.parametrize("feet", [FEET, FEET[:3], FEET[1:3]])
def test_solo_feet(feet, tmp_path_factory):
    """Solo-12 standing on 4, 3 and 2 point feet: the C functions (the combined one and the two
    single ones), numpy and CasADi against the reference; the constraints hold (J qdd + gamma = 0)
    and so do the equations of motion (M qdd = tau - b + J^T lambda), by Pinocchio's numbers."""
    robot = _robot(SOLO, _contacts(feet))
    ref = _reference(SOLO, robot)
    states = _states(robot, 8)
    targets = {"numpy": NumpyTarget(derive(robot, outputs=CONTACT_OUTPUTS))}
    if len(feet) == 4:  # (the impulse dynamics' test reads the same library)
        targets["c"] = _compiled(("solo", feet), robot, tmp_path_factory, wanted=SOLO_WANTED)
    if len(feet) == 2:
        targets["casadi"] = CasadiTarget(derive(robot, outputs=CONTACT_OUTPUTS))
    for target, lib in targets.items():
        errors = compare(lib, ref, states, CONTACT_OUTPUTS, NO_PARAMETERS)
        assert max(errors.values()) < TOL, (target, errors)
    lib = targets.get("c") or targets["numpy"]
    for q, qd, _, tau in states:
        qdd = lib.contact_accelerations(q, qd, tau, NO_PARAMETERS)
        forces = lib.contact_forces(q, qd, tau, NO_PARAMETERS)
        J_all = ref.frame_jacobians(q)
        J = np.vstack([J_all[6 * c.frame:6 * c.frame + 3] for c in robot.contacts])
        gamma = np.concatenate([ref.frame_jacobian_dot_v(q, qd)[6 * c.frame:6 * c.frame + 3] for c in robot.contacts])
        scale = np.abs(J).max() * np.abs(qdd).max() + np.abs(gamma).max()
        assert np.abs(J @ qdd + gamma).max() < 1e-11 * scale
        M, b = ref.system_matrix(q), ref.inverse_dynamics(q, qd, np.zeros(robot.nv))
        residual = M @ qdd - (tau - b + J.T @ forces)
        assert np.abs(residual).max() < 1e-11 * (np.abs(M @ qdd).max() + np.abs(tau - b).max())
    if "c" in targets:
        q, qd, _, tau = states[0]
        status, (qdd, forces) = targets["c"].with_status("contact_forward_dynamics", q, qd, tau)
        assert status == 0
        assert normalized_error([qdd], [ref.contact_accelerations(q, qd, tau)]) < TOL
        assert normalized_error([forces], [ref.contact_forces(q, qd, tau)]) < TOL


def test_dependent_contacts_status(tmp_path_factory):
    """Two soles on one rigid body (Solo's foot and the lower leg it is fixed to) are dependent at
    every q: status 3 (CONTACT_SINGULAR) and nothing written; a NaN input gives 2; the four feet
    at the same state return 0."""
    robot = _robot(SOLO, "FL_FOOT:6d,FL_LOWER_LEG:6d")
    lib = _compiled(("solo", "dependent"), robot, tmp_path_factory)
    q, qd, _, tau = _states(robot, 1)[0]
    status, (qdd, forces) = lib.with_status("contact_forward_dynamics", q, qd, tau)
    assert status == 3 and np.all(np.isnan(qdd)) and np.all(np.isnan(forces))
    regular = _robot(SOLO, _contacts(FEET))
    lib = _compiled(("solo", FEET), regular, tmp_path_factory, wanted=SOLO_WANTED)
    status, (qdd, forces) = lib.with_status("contact_forward_dynamics", q, qd, tau)
    assert status == 0 and np.all(np.isfinite(qdd)) and np.all(np.isfinite(forces))
    ref = _reference(SOLO, regular)
    assert normalized_error([qdd], [ref.contact_accelerations(q, qd, tau)]) < TOL
    bad = np.array(q)
    bad[8] = np.nan
    status, (qdd, _) = lib.with_status("contact_forward_dynamics", bad, qd, tau)
    assert status == 2 and np.all(np.isnan(qdd))


def test_arm_with_tool_held(tmp_path_factory):
    """A fixed-base arm whose last link is held (a 6D contact: a closed chain through the
    ground): the Panda's 7 joints keep one motion; its C against the reference."""
    robot, _ = load_input(robot_path("panda"), contacts=None)
    last = robot.links[-1].name
    robot, _ = load_input(robot_path("panda"), contacts=f"{last}:6d")
    from symdyn.check.pinocchio_model import PinocchioReference
    ref = reduced(PinocchioReference(robot), robot)
    lib = _compiled(("panda", "tool"), robot, tmp_path_factory)
    errors = compare(lib, ref, _states(robot, 8), CONTACT_OUTPUTS, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors


@pytest.mark.slow
def test_talos_soles(tmp_path_factory):
    """TALOS reduced on both soles (two 6D contacts, 12 constraint rows, 38 velocities): C against
    the reference (itself against constraintDynamics above)."""
    robot = _robot(TALOS, "left_sole_link:6d,right_sole_link:6d")
    ref = _reference(TALOS, robot)
    lib = _compiled(("talos", "soles"), robot, tmp_path_factory)
    errors = compare(lib, ref, _states(robot, 6), CONTACT_OUTPUTS, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors


def _pinocchio_derivatives(robot, ref, states):
    """Pinocchio's computeConstraintDynamicsDerivatives at each state, in symdyn's terms (viscous
    damping is symdyn's: tau - friction(qd) goes in, so d/dqd gains -d/dtau diag(damping))."""
    model, data, models, datas, settings = _pinocchio_contacts(robot, ref)
    damping = np.diag(ref.damping)
    out = []
    for q, qd, _, tau in states:
        pin.constraintDynamics(model, data, ref.configuration(q), qd, tau - ref.friction(qd), models, datas, settings)
        pin.computeConstraintDynamicsDerivatives(model, data, models, datas, settings)
        out.append((data.ddq_dq.copy(), data.ddq_dv - data.ddq_dtau @ damping, data.ddq_dtau.copy(),
                    data.dlambda_dq.copy(), data.dlambda_dv - data.dlambda_dtau @ damping, data.dlambda_dtau.copy()))
    return out


@pytest.mark.parametrize("relative,contacts", [
    (SOLO, _contacts(FEET)), (SOLO, _contacts(FEET[1:3])),
    pytest.param(TALOS, "left_sole_link:6d,right_sole_link:6d", marks=pytest.mark.slow)])
def test_derivative_reference_is_pinocchio(relative, contacts):
    """The reference's derivatives of the contact dynamics (the implicit function theorem on
    Pinocchio's RNEA derivatives and its frames' Jacobians and accelerations) against Pinocchio's
    own computeConstraintDynamicsDerivatives (LOCAL_WORLD_ALIGNED contacts; a floating base's
    columns along q (+) dv, the forces' axes held in the world)."""
    robot = _robot(relative, contacts)
    ref = _reference(relative, robot)
    states = _states(robot, 3, seed=5)
    theirs = _pinocchio_derivatives(robot, ref, states)
    for (q, qd, _, tau), expected in zip(states, theirs):
        mine = [getattr(ref, name)(q, qd, tau) for name in CONTACT_DERIVATIVES]
        for name, a, b in zip(CONTACT_DERIVATIVES, mine, expected):
            assert normalized_error([a], [b]) < 1e-9, name


@pytest.mark.slow
def test_contact_derivatives_solo():
    """Solo-12 on two feet: the derivatives of its contact dynamics in numpy and CasADi against the
    reference (its C: the squat on four feet below runs it, and the floating tree above checks C
    against the reference)."""
    robot = _robot(SOLO, _contacts(FEET[1:3]))
    ref = _reference(SOLO, robot)
    states = _states(robot, 4, seed=7)
    eqs = derive(robot, outputs=CONTACT_DERIVATIVES)
    for target, lib in (("numpy", NumpyTarget(eqs)), ("casadi", CasadiTarget(eqs))):
        errors = compare(lib, ref, states, CONTACT_DERIVATIVES, NO_PARAMETERS)
        assert max(errors.values()) < 1e-9, (target, errors)


@pytest.mark.slow
def test_contact_derivatives_arm(tmp_path_factory):
    """The derivatives on a fixed base: the Panda with its last link held (a closed chain), in C
    against the reference."""
    from symdyn.check.pinocchio_model import PinocchioReference
    robot, _ = load_input(robot_path("panda"), contacts=None)
    robot, _ = load_input(robot_path("panda"), contacts=f"{robot.links[-1].name}:6d")
    ref = reduced(PinocchioReference(robot), robot)
    lib = _compiled(("panda", "derivatives"), robot, tmp_path_factory, wanted=CONTACT_DERIVATIVES)
    errors = compare(lib, ref, _states(robot, 4), CONTACT_DERIVATIVES, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors


@pytest.mark.slow  # (22 s: the README suite keeps the arm's C and Solo's numpy; the fuzz campaign floating trees)
def test_contact_derivatives_tree(tmp_path_factory):
    """The derivatives on a floating tree of the examples holding one link (6D), in C against
    the reference; the combined function's parts are the single ones' values, dqdd/dtau is
    symmetric and keeps the contact held (J dqdd/dtau = 0, dlambda/dtau J^T = -1)."""
    from symdyn.check.pinocchio_model import PinocchioReference
    robot, _ = load_input(str(REPO / "examples" / "trees" / "space_robot.yaml"), contacts="l_wrist:6d")
    ref = reduced(PinocchioReference(robot), robot)
    lib = _compiled(("space", "derivatives"), robot, tmp_path_factory, wanted=CONTACT_DERIVATIVES + CONTACT_OUTPUTS)
    states = _states(robot, 4)
    errors = compare(lib, ref, states, CONTACT_DERIVATIVES, NO_PARAMETERS)
    assert max(errors.values()) < 1e-9, errors
    q, qd, _, tau = states[0]  # the combined function: its parts, and the identities of the blocks
    status, values = lib.with_status("contact_forward_dynamics_derivatives", q, qd, tau)
    assert status == 0
    parts = dict(zip(("contact_accelerations", "contact_forces") + CONTACT_DERIVATIVES, values))
    for name, value in parts.items():
        assert normalized_error([value], [getattr(ref, name)(q, qd, tau)]) < 1e-9, name
    K, dlambda_dtau = parts["contact_accelerations_dtau"], parts["contact_forces_dtau"]
    J = ref._contact_jacobian(q)
    assert np.abs(K - K.T).max() < 1e-12 * np.abs(K).max()
    assert np.abs(J @ K).max() < 1e-10 * np.abs(J).max() * np.abs(K).max()
    assert np.abs(dlambda_dtau @ J.T + np.eye(J.shape[0])).max() < 1e-10
    # torques from ordinary up past where the results overflow (the product loop's final test of
    # finite results stands behind the dynamics' own): status 0 writes finite numbers, any other
    # status writes nothing
    statuses = set()
    for scale in np.concatenate([[1.0], 1e306 * np.linspace(1, 179, 96)]):
        big = np.full(len(tau), scale) * np.linspace(1, 0.5, len(tau))
        status, values = lib.with_status("contact_forward_dynamics_derivatives", q, qd, big)
        statuses.add(status)
        if status == 0:
            assert all(np.all(np.isfinite(value)) for value in values), scale
        else:
            assert status == 2 and all(np.all(np.isnan(value)) for value in values), (scale, status)
    assert statuses == {0, 2}


def test_contact_inverse_dynamics(tmp_path_factory):
    """Solo-12 on four feet: the joint forces and least-norm contact forces that give qdd with the
    base unactuated, C (combined and single) and numpy against the reference; the equations of
    motion hold with them (ID = tau + J^T lambda, the base's tau zero) and lambda is the least-norm
    one (in the range of J_b, the base's columns); an arm whose joints are all actuated gets
    lambda = 0 and tau = ID.  (On two point feet, five independent base wrenches: status 3 and
    nothing written, which test_verify_contact_inverse_on_two_feet checks.)"""
    robot = _robot(SOLO, _contacts(FEET))
    ref = _reference(SOLO, robot)
    states = _states(robot, 6, seed=3)
    lib = _compiled(("solo", FEET), robot, tmp_path_factory, wanted=SOLO_WANTED)
    for target in (lib, NumpyTarget(derive(robot, outputs=CONTACT_INVERSE))):
        errors = compare(target, ref, states, CONTACT_INVERSE, NO_PARAMETERS)
        assert max(errors.values()) < 1e-10, errors
    for q, qd, qdd, _ in states:
        status, (tau, forces) = lib.with_status("contact_inverse_dynamics", q, qd, qdd)
        assert status == 0 and np.all(tau[:6] == 0)
        J = ref._contact_jacobian(q)
        ID = ref.inverse_dynamics(q, qd, qdd)
        assert np.abs(ID - tau - J.T @ forces).max() < 1e-10 * np.abs(ID).max()
        basis = np.linalg.qr(J[:, :6])[0]
        assert np.abs(forces - basis @ (basis.T @ forces)).max() < 1e-10 * np.abs(forces).max()
    # (on two point feet, status 3: test_verify_contact_inverse_on_two_feet, whose verify compiles it)
    held, _ = load_input(robot_path("panda"), contacts=None)  # every joint actuated: lambda = 0, tau = ID
    held, _ = load_input(robot_path("panda"), contacts=f"{held.links[-1].name}:6d")
    numbers = NumpyTarget(derive(held, outputs=CONTACT_INVERSE + ("inverse_dynamics",)))
    q, qd, qdd, _ = _states(held, 1)[0]
    assert np.all(numbers.contact_inverse_forces(q, qd, qdd, NO_PARAMETERS) == 0)
    assert np.allclose(numbers.contact_inverse_torques(q, qd, qdd, NO_PARAMETERS),
                       numbers.inverse_dynamics(q, qd, qdd, NO_PARAMETERS), rtol=0, atol=0)


def test_verify_contact_inverse_on_two_feet(capsys):
    """symdyn verify of contact inverse dynamics on two point feet (five independent wrenches at
    every q): nothing to compare, and the function must return status 3 at every state, which
    verify checks ('singular')."""
    code = main(["verify", example_robot_data(SOLO), "--floating-base", "--contacts", _contacts(FEET[1:3]),
                 "--functions", "contact_inverse_dynamics", "--states", "3"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert out.count("  singular") == 2, out


@pytest.mark.slow
def test_squat_on_four_feet(tmp_path):
    """examples/ilqr: iLQR of Solo-12's squat standing on its four feet, with the generated contact
    dynamics, their derivatives and contact inverse dynamics only, converges (joints within 1e-3
    rad of the crouch and the stance, at rest) and the feet stay within 1 cm of where they were."""
    import re
    import subprocess
    import sys
    done = subprocess.run([sys.executable, str(REPO / "examples" / "ilqr" / "solo12_ddp.py"), "--on-feet", "--flags=-O1",
                           "--out", str(tmp_path / "ddp")], capture_output=True, text=True, timeout=1500)
    assert done.returncode == 0, done.stdout + done.stderr
    assert ": converged" in done.stdout, done.stdout
    drift = float(re.search(r"the feet move at most (\S+) m", done.stdout).group(1))
    assert drift < 1e-2, done.stdout


@pytest.mark.parametrize("contacts,expected", [
    ("FL_FOT:3d", "did you mean 'FL_FOOT'"),
    ("FL_FOOT:4d", "is not 3d (a point held), 6d (a sole held) or xz, xy, yz"),
    ("FL_FOOT:3d,FL_FOOT:6d", "in contact twice"),
    ("FL_FOOT", "expected FRAME:3d, FRAME:6d or FRAME:xz"),
])
def test_contact_set_errors(contacts, expected, capsys, tmp_path):
    """A contact set that cannot be read stops the CLI with one line naming the file and the
    problem (never a traceback), and writes nothing."""
    out = tmp_path / "out"
    code = main(["generate", example_robot_data(SOLO), "--floating-base", "--contacts", contacts,
                 "--functions", "contact_forward_dynamics", "--out", str(out)])
    assert code != 0
    line = error_line(capsys)
    assert expected in line and "Traceback" not in line
    assert not out.exists()


def test_robot_file_contacts(tmp_path):
    """A robot file's ``contacts:`` (a link's own frame, or a frame of ``frames:``) gives the
    contact functions by default; a name that is neither is refused naming the field."""
    text = open(robot_path("panda")).read()
    robot, _ = load_input(robot_path("panda"))
    last = robot.links[-1].name
    path = tmp_path / "held.yaml"
    path.write_text(text + f"contacts: ['{last}:6d']\n")
    robot, _ = load_input(str(path))
    assert [robot.frames[c.frame].name for c in robot.contacts] == [last] and robot.contact_rows == 6
    from symdyn.model.outputs import default_outputs
    assert set(CONTACT_OUTPUTS) <= set(default_outputs(robot))
    path.write_text(text + "contacts: ['nowhere:3d']\n")
    with pytest.raises(SymdynError, match="contacts"):
        load_input(str(path))


def test_external_forces_are_pinocchio_fext(tmp_path_factory):
    """NAME_inverse_dynamics_ext and NAME_forward_dynamics_ext (C) against Pinocchio's rnea and
    aba with fext: each contact's force (world axes at its frame's origin; a sole's moment too)
    turned into its frame's axes and moved to its joint's frame, the torques less friction."""
    robot = _robot(SOLO, "FL_FOOT:3d,HR_FOOT:6d")
    ref = _reference(SOLO, robot)
    model, data = ref.model, ref.model.createData()
    eqs = derive(robot, outputs=EXTERNAL_OUTPUTS)
    lib = build_and_load(generate_c(eqs, EXTERNAL_OUTPUTS), robot.name, Dimensions.of(robot), 0, "double",
                         str(tmp_path_factory.mktemp("external")))
    mine_id, theirs_id, mine_fd, theirs_fd = [], [], [], []
    for q, qd, qdd, tau in _states(robot, 6):
        f = contact_forces_of(tau, robot.contact_rows)
        pq = ref.configuration(q)
        pin.framesForwardKinematics(model, data, pq)
        fext = pin.StdVec_Force([pin.Force.Zero() for _ in range(model.njoints)])
        at = 0
        for contact in robot.contacts:
            frame_id = model.getFrameId(robot.frames[contact.frame].name)
            frame, R = model.frames[frame_id], data.oMf[frame_id].rotation
            wrench = np.concatenate([f[at:at + 3], f[at + 3:at + 6] if contact.kind == "6d" else np.zeros(3)])
            local = pin.Force(R.T @ wrench[:3], R.T @ wrench[3:])
            fext[frame.parentJoint] = fext[frame.parentJoint] + frame.placement.act(local)
            at += contact.rows
        theirs_id.append(pin.rnea(model, data, pq, qd, qdd, fext) + ref.friction(qd))
        theirs_fd.append(pin.aba(model, data, pq, qd, tau - ref.friction(qd), fext))
        mine_id.append(lib.inverse_dynamics_ext(q, qd, qdd, f))
        mine_fd.append(lib.forward_dynamics_ext(q, qd, tau, f))
    assert normalized_error(mine_id, theirs_id) < TOL
    assert normalized_error(mine_fd, theirs_fd) < TOL


def test_scene_and_convert_contacts(tmp_path, capsys):
    """A scene's ``contacts:`` over a URDF (feet merged by fixed joints) is read as --contacts
    is, the command line's set replacing it; ``symdyn convert --contacts`` writes the set into the
    robot file, which reads back with the same contacts."""
    scene = tmp_path / "standing.yaml"
    scene.write_text(f"scene: 1\nrobot: {example_robot_data(SOLO)}\nfloating_base: true\n"
                     "contacts: [FL_FOOT:3d, HR_FOOT:6d]\n")
    robot, found = load_input(str(scene))
    assert [(robot.frames[c.frame].name, c.kind) for c in robot.contacts] == [("FL_FOOT", "3d"), ("HR_FOOT", "6d")]
    assert robot.contact_rows == 9 and any(note.startswith("contacts:") for note in found.notes)
    robot, _ = load_input(str(scene), contacts="FR_FOOT:3d")
    assert [robot.frames[c.frame].name for c in robot.contacts] == ["FR_FOOT"]
    out = tmp_path / "solo.yaml"
    assert main(["convert", example_robot_data(SOLO), "--floating-base", "--contacts", "FL_FOOT:3d,HR_FOOT:3d",
                 "--to", "yaml", "--out", str(out), "--quiet"]) == 0
    robot, _ = load_input(str(out))
    assert [(robot.frames[c.frame].name, c.kind) for c in robot.contacts] == [("FL_FOOT", "3d"), ("HR_FOOT", "3d")]
    assert main(["convert", str(out), "--contacts", "FL_FOOT:3d", "--to", "urdf"]) != 0
    assert "--contacts applies to a URDF" in error_line(capsys)


@pytest.mark.parametrize("relative,contacts", [(SOLO, _contacts(FEET)), (TALOS, "left_sole_link:6d,right_sole_link:6d")])
def test_impulse_dynamics_is_pinocchio(relative, contacts, tmp_path_factory):
    """The impact of the contacts closing: the reference against Pinocchio's impulseDynamics
    (Solo-12's four feet, TALOS reduced's two soles, restitutions in (0, 1)), Solo-12's C (the
    combined function) against the reference; after the impact the contacts move at -e times
    their velocity before it."""
    robot = _robot(relative, contacts)
    ref = _reference(relative, robot)
    model, data, models, datas, settings = _pinocchio_contacts(robot, ref)
    lib = (_compiled(("solo", FEET), robot, tmp_path_factory, wanted=SOLO_WANTED)
           if relative == SOLO else None)
    for k, (q, qd, _, _) in enumerate(_states(robot, 5)):
        e = np.array([0.2 * k])
        theirs = pin.impulseDynamics(model, data, ref.configuration(q), qd, models, datas, float(e[0]), settings)
        mine_v, mine_i = ref.impulse_velocities(q, qd, e), ref.impulse_forces(q, qd, e)
        assert normalized_error([mine_v], [theirs]) < 1e-9
        assert normalized_error([mine_i], [data.impulse_c.copy()]) < 1e-9
        J_all = ref.frame_jacobians(q)
        J = np.vstack([J_all[6 * c.frame:6 * c.frame + c.rows] for c in robot.contacts])
        assert np.allclose(J @ mine_v, -e[0] * (J @ qd), atol=1e-9 * np.abs(J @ qd).max())
        if lib is not None:
            status, (velocity, impulse) = lib.with_status("impulse_dynamics", q, qd, e)
            assert status == 0
            assert normalized_error([velocity], [mine_v]) < TOL
            assert normalized_error([impulse], [mine_i]) < TOL


SANITIZED_MAIN = r"""
#include <stdio.h>
#include <stdlib.h>
#include "space2arm_dynamics.h"
static double *filled(int count, double base) {  /* exactly count entries: a read past them is reported */
    double *x = malloc(sizeof(double) * (size_t)count);
    for (int i = 0; i < count; ++i) x[i] = base + 0.1 * i;
    return x;
}
int main(void) {
    double *q = filled(19, 0.1), *qd = filled(12, -0.3), *qdd = filled(12, 0.2), *tau = filled(12, 1.0);
    double *f = filled(SPACE2ARM_CONTACT_ROWS, 5.0), *e = filled(1, 0.5);
    double *out = filled(12, 0.0), *forces = filled(SPACE2ARM_CONTACT_ROWS, 0.0);
    int status = space2arm_contact_forward_dynamics(q, qd, tau, out, forces);
    status |= space2arm_impulse_dynamics(q, qd, e, out, forces);
    status |= space2arm_forward_dynamics_ext(q, qd, tau, f, out);
    space2arm_inverse_dynamics_ext(q, qd, qdd, f, out);
    double *dq = filled(144, 0.0), *dv = filled(144, 0.0), *dt = filled(144, 0.0);
    double *lq = filled(12 * SPACE2ARM_CONTACT_ROWS, 0.0), *lv = filled(12 * SPACE2ARM_CONTACT_ROWS, 0.0);
    double *lt = filled(12 * SPACE2ARM_CONTACT_ROWS, 0.0);
#if DERIVATIVES
    status |= space2arm_contact_forward_dynamics_derivatives(q, qd, tau, out, forces, dq, dv, dt, lq, lv, lt);
#endif
    int inverse = space2arm_contact_inverse_dynamics(q, qd, qdd, out, forces);  /* a point cannot hold a base */
    printf("%d %g %d\n", status, out[0] + dq[0] + lt[0], inverse);
    free(q); free(qd); free(qdd); free(tau); free(f); free(e); free(out); free(forces);
    free(dq); free(dv); free(dt); free(lq); free(lv); free(lt);
    return 0;
}
"""


def test_contact_functions_sanitizer_clean(tmp_path):
    """The contact, impulse and external-force functions, the contact dynamics' derivatives and
    contact inverse dynamics read their inputs within their sizes (f: NC entries, the restitution
    one) and are clean under the address and undefined-behaviour sanitizers, on a floating base
    whose contact rows are fewer than its velocities (one point cannot hold the base: contact
    inverse dynamics returns status 3)."""
    robot, _ = load_input(str(REPO / "examples" / "trees" / "space_robot.yaml"), contacts="l_wrist:3d")
    wanted = CONTACT_OUTPUTS + IMPULSE_OUTPUTS + EXTERNAL_OUTPUTS + CONTACT_INVERSE
    files = generate_c(derive(robot, outputs=wanted), wanted)
    status, value, inverse = run_sanitized(tmp_path, SANITIZED_MAIN.replace("DERIVATIVES", "0"), files).split()
    assert status == "0" and np.isfinite(float(value)) and inverse == "3"


@pytest.mark.slow
def test_contact_derivatives_sanitizer_clean(tmp_path):
    """The same with the contact dynamics' derivatives (a minute and a half of sanitized compiling)."""
    robot, _ = load_input(str(REPO / "examples" / "trees" / "space_robot.yaml"), contacts="l_wrist:3d")
    wanted = CONTACT_OUTPUTS + IMPULSE_OUTPUTS + EXTERNAL_OUTPUTS + CONTACT_INVERSE + CONTACT_DERIVATIVES
    files = generate_c(derive(robot, outputs=wanted), wanted)
    status, value, inverse = run_sanitized(tmp_path, SANITIZED_MAIN.replace("DERIVATIVES", "1"), files).split()
    assert status == "0" and np.isfinite(float(value)) and inverse == "3"
