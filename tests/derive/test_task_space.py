"""Task-space dynamics of the tool (M_x = Lambda, V_x = mu, G_x, Jbar): against Pinocchio, the
operational-space controller property, statuses at singular poses and non-finite input, the
lecture's planar 2-link closed form, the robot file's task field."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import sympy as sp

from symdyn.model.outputs import Dimensions
import symdyn
from helpers import REPO, normalized_error, random_states, robot_path
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import PinocchioReference
from symdyn.cli import main
from symdyn.check.agreement import TASK_REGULAR
from symdyn.emit.cgen import generate_c
from symdyn.model.outputs import TASK_OUTPUTS, default_outputs
from symdyn.model.robot import TASKS

pin = pytest.importorskip("pinocchio")

#: bundled arms and their tasks: 6-joint arms and the two 7-joint (redundant) arms take the
#: whole pose, as does the redundant 12-joint chain; the SCARA moves in x, y, z and turns about z only
ARMS = {"puma560": None, "ur5": None, "stanford": None, "iiwa14": None, "panda": None, "scara": (0, 1, 2, 5),
        "chain12": None}
#: the arm whose library also has the batch functions
BATCH_ARM = "iiwa14"
_BUILT: dict = {}


def compiled(name, tmp_path_factory):
    """(robot, library with the task-space functions, Pinocchio reference): one compile per arm."""
    if name not in _BUILT:
        robot = symdyn.load(robot_path(name))
        if ARMS.get(name) is not None:
            robot = dataclasses.replace(robot, task=ARMS[name])
        eqs = symdyn.derive(robot, outputs=TASK_OUTPUTS)
        files = generate_c(eqs, TASK_OUTPUTS, batch=name == BATCH_ARM)  # one compile serves the batch test too
        lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, "double", str(tmp_path_factory.mktemp(name)))
        _BUILT[name] = (robot, lib, PinocchioReference(robot))
    return _BUILT[name]


def regular_states(robot, ref, count, seed=3):
    """``count`` seeded states whose task is away from singularities: every pivot of the LDL^T of
    J M^-1 J^T (what the generated code checks) above 1e-3 of its diagonal entry, by Pinocchio's
    numbers (the error of either side grows as the pivots shrink)."""
    states = []
    for q, qd, _, _ in random_states(robot.dof, 10 * count, seed):
        if ref.task_pivot_ratio(q) > TASK_REGULAR:
            states.append((q, qd))
        if len(states) == count:
            return states
    raise AssertionError(f"{robot.name}: fewer than {count} regular states")


@pytest.mark.parametrize("name", [pytest.param(name, marks=[pytest.mark.slow] if name in ("chain12", "panda") else [])
                                  for name in sorted(ARMS)])  # chain12: 13 s, panda 6 s (iiwa14, 7 joints too, runs), with -m slow
def test_task_space_matches_pinocchio(name, tmp_path_factory):
    """Lambda^-1 = J M^-1 J^T with computeMinverse and getFrameJacobian(LOCAL_WORLD_ALIGNED); mu
    and Gx from nonLinearEffects, computeGeneralizedGravity, getFrameClassicalAcceleration;
    <= 1e-10 normalized at 50 states; the combined function gives the same numbers, status 0."""
    robot, lib, ref = compiled(name, tmp_path_factory)
    states = regular_states(robot, ref, 50)
    for output in TASK_OUTPUTS:
        inputs = (lambda q, qd: (q, qd)) if output == "task_bias" else (lambda q, qd: (q,))
        mine = [getattr(lib, output)(*inputs(q, qd)) for q, qd in states]
        refs = [getattr(ref, output)(*inputs(q, qd)) for q, qd in states]
        error = normalized_error(mine, refs)
        assert error <= 1e-10, (name, output, error)
    q, qd = states[0]
    status, together = lib.with_status("task_space", q, qd)
    assert status == 0
    for part, value in zip(TASK_OUTPUTS, together):
        single = getattr(lib, part)(*((q, qd) if part == "task_bias" else (q,)))
        np.testing.assert_allclose(value, single, rtol=0, atol=1e-13 * max(1.0, float(np.max(np.abs(single)))))


def _tool_acceleration(ref, q, qd, tau):
    """The tool's classical acceleration (world axes, linear first) under joint torques tau, by
    Pinocchio's aba (no friction)."""
    qdd = pin.aba(ref.model, ref.data, q, qd, tau)
    return ref.jacobian(q) @ qdd + ref.jacobian_dot_qd(q, qd)


@pytest.mark.parametrize("name", ["ur5", "iiwa14"])
def test_operational_space_control_gives_the_commanded_acceleration(name, tmp_path_factory):
    """tau = J^T (Lambda a + mu + Gx) gives the tool the classical acceleration a (Pinocchio's
    aba, <= 1e-9 relative); adding (1 - J^T Jbar^T) tau0 leaves it unchanged (7 joints: a real
    null space)."""
    robot, lib, ref = compiled(name, tmp_path_factory)
    rng = np.random.default_rng(11)
    for q, qd in regular_states(robot, ref, 10, seed=8):
        status, (Lambda, mu, Gx, Jbar) = lib.with_status("task_space", q, qd)
        assert status == 0
        J = ref.jacobian(q)
        a = rng.uniform(-3, 3, 6)
        tau = J.T @ (Lambda @ a + mu + Gx)
        achieved = _tool_acceleration(ref, q, qd, tau)
        assert np.max(np.abs(achieved - a)) <= 1e-9 * max(1.0, np.max(np.abs(a))), (achieved, a)
        tau0 = rng.uniform(-20, 20, robot.dof)
        projected = tau + (np.eye(robot.dof) - J.T @ Jbar.T) @ tau0
        again = _tool_acceleration(ref, q, qd, projected)
        assert np.max(np.abs(again - a)) <= 1e-9 * max(1.0, np.max(np.abs(a))), (again, a)
        if robot.dof > 6:  # the null-space torque moves the joints, not the tool
            qdd = pin.aba(ref.model, ref.data, q, qd, tau)
            assert np.max(np.abs(pin.aba(ref.model, ref.data, q, qd, projected) - qdd)) > 1e-3


@pytest.mark.parametrize("pose, why", [({4: 0.0}, "wrist straight (q5 = 0)"), ({2: 0.0}, "elbow stretched out (q3 = 0)")])
def test_singular_pose_returns_3_and_writes_nothing(pose, why, tmp_path_factory):
    robot, lib, ref = compiled("ur5", tmp_path_factory)
    q = np.array([0.3, -1.1, 1.2, -0.4, 0.8, 0.5])
    for joint, value in pose.items():
        q[joint] = value
    assert np.linalg.matrix_rank(ref.jacobian(q), tol=1e-9) == 5, why
    qd = np.full(6, 0.2)
    for function, args in [("task_space", (q, qd)), ("task_mass_matrix", (q,)), ("task_bias", (q, qd)),
                           ("task_gravity", (q,)), ("task_inverse", (q,))]:
        status, outputs = lib.with_status(function, *args, fill=7.0)
        assert status == 3, (why, function)
        assert all(np.all(out == 7.0) for out in outputs), (why, function)
    q[4] = 0.8  # off the singularity: fine again
    q[2] = 1.2
    assert lib.with_status("task_space", q, qd)[0] == 0


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_input_returns_2_and_writes_nothing(bad, tmp_path_factory):
    _, lib, _ = compiled("ur5", tmp_path_factory)
    q, qd = np.array([0.3, -1.1, 1.2, -0.4, 0.8, 0.5]), np.full(6, 0.2)
    for which in (0, 1):
        args = [q.copy(), qd.copy()]
        args[which][3] = bad
        status, outputs = lib.with_status("task_space", *args, fill=7.0)
        assert status == 2 and all(np.all(out == 7.0) for out in outputs)
    status, outputs = lib.with_status("task_gravity", np.where(np.arange(6) == 1, bad, q), fill=7.0)
    assert status == 2 and np.all(outputs[0] == 7.0)


def test_planar_two_link_task_is_the_lecture_form():
    """The lecture's planar 2-link arm with its tool at the end of link 2, task rows x, y: the
    generated expressions (evaluated at 40 digits, every parameter a random number) equal the
    lecture's J^-T M J^-1, J^-T c and J^-T (h - M J^-1 Jdot qd) built symbolically from D, J."""
    from symdyn.derive.numeric import compile_function
    robot = symdyn.load(str(REPO / "examples" / "task_space" / "planar2r_task.yaml"))
    assert robot.task_rows == (0, 1)
    eqs = symdyn.derive(robot, outputs=("task_mass_matrix", "task_bias", "task_gravity", "mass_matrix", "coriolis",
                                        "gravity", "jacobian", "jacobian_dot_qd"))
    M = eqs.expanded("mass_matrix")
    J = eqs.expanded("jacobian")[[0, 1], :]
    J_inv = J.inv()
    lecture = {"task_mass_matrix": J_inv.T * M * J_inv, "task_gravity": J_inv.T * eqs.expanded("gravity"),
               "task_bias": J_inv.T * (eqs.expanded("coriolis") - M * J_inv * eqs.expanded("jacobian_dot_qd")[[0, 1], :])}
    rng = np.random.default_rng(4)
    for _ in range(3):
        q, qd, p = rng.uniform(-2, 2, 2), rng.uniform(-2, 2, 2), rng.uniform(0.3, 1.5, len(robot.parameters))
        values = dict(zip(eqs.q + eqs.qd + robot.parameters, [sp.Float(x, 40) for x in (*q, *qd, *p)]))
        for name, formula in lecture.items():
            mine = compile_function([eqs.q, eqs.qd, robot.parameters], eqs.program, sp.Matrix(eqs.output(name)), name,
                                    digits=40)(q, qd, p)
            expected = formula.evalf(40, subs=values)
            for got, want in zip([x for row in mine for x in row], expected):
                assert abs(got - want) <= 1e-30 * max(1, abs(want)), (name, got, want)


@pytest.mark.parametrize("value, rows", [("pose", (0, 1, 2, 3, 4, 5)), ("position", (0, 1, 2)),
                                         ("orientation", (3, 4, 5)), ("[0, 1]", (0, 1)), ("[5, 0, 2]", (5, 0, 2))])
def test_task_field_is_read(value, rows, tmp_path):
    path = tmp_path / "arm.yaml"
    path.write_text(open(robot_path("ur5")).read() + f"task: {value}\n")
    robot = symdyn.load(str(path))
    assert robot.task_rows == rows and TASKS.get(value, rows) == rows
    assert set(TASK_OUTPUTS) <= set(default_outputs(robot))
    assert not set(TASK_OUTPUTS) & set(default_outputs(symdyn.load(robot_path("ur5"))))


@pytest.mark.parametrize("value, message", [
    ("posture", "unknown task 'posture'"), ("[0, 6]", "a task row is an integer 0-5"),
    ("[1, 1]", "task row 1 is listed twice"), ("[]", "non-empty list"), ("[0.5]", "a task row is an integer 0-5"),
    ("{x: 1}", "or a non-empty list")])
def test_bad_task_field_is_one_clear_error(value, message, tmp_path, capsys):
    path = tmp_path / "arm.yaml"
    path.write_text(open(robot_path("ur5")).read() + f"task: {value}\n")
    assert main(["generate", str(path), "--out", str(tmp_path / "out")]) != 0
    err = capsys.readouterr().err.strip()
    assert message in err and "arm.yaml" in err and "task" in err and len(err.splitlines()) == 1, err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_a_task_the_tool_cannot_follow_is_refused(tmp_path, capsys):
    """The bundled planar arm's tool is its elbow: the whole pose (the default task) has rank 1
    everywhere (the tool moves on a circle): one line, no files."""
    code = main(["generate", robot_path("planar2r"), "--out", str(tmp_path), "--functions", "task_mass_matrix"])
    err = capsys.readouterr().err.strip()
    assert code != 0 and "rank at most 1" in err and "task: position" in err and len(err.splitlines()) == 1, err
    assert not any(tmp_path.iterdir())


def test_checked_in_task_derivation_is_up_to_date(tmp_path):
    """docs/derivations/planar2r_task.md: the lecture's planar arm in Cartesian space."""
    out = tmp_path / "planar2r_task.md"
    assert main(["derive", str(REPO / "examples" / "task_space" / "planar2r_task.yaml"), "--task", "--steps", "summary",
                 "--format", "markdown", "--out", str(out), "--quiet"]) == 0
    assert out.read_bytes() == (REPO / "docs" / "derivations" / "planar2r_task.md").read_bytes(), \
        "docs/derivations is stale: remake it with the commands in docs/derivations/README.md"


@pytest.mark.parametrize("path, message", [(robot_path("puma560"), "up to 3 joints"),
                                           (str(REPO / "robots" / "parallel" / "sru_platform.yaml"),
                                            "--task does not apply to a platform")])
def test_derive_task_refusals_are_one_line(path, message, capsys):
    assert main(["derive", path, "--task", "--quiet"]) == 1
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1, err


def test_scene_task_replaces_the_robot_files(tmp_path, capsys):
    """A scene's task: (here the position of ur5's tool) replaces the robot file's default
    pose, brings the task-space functions into the default set, and is checked like the robot
    file's (one line naming the scene and the field)."""
    from symdyn.model.scene import load_scene
    scene = tmp_path / "scene.yaml"
    scene.write_text(f"scene: 1\nrobot: {robot_path('ur5')}\ntask: position\n")
    loaded = load_scene(str(scene))
    assert loaded.robot.task_rows == (0, 1, 2) and set(TASK_OUTPUTS) <= set(default_outputs(loaded.robot))
    assert any(note.startswith("task: Jacobian rows 0, 1, 2") for note in loaded.notes)
    scene.write_text(f"scene: 1\nrobot: {robot_path('ur5')}\ntask: [0, 9]\n")
    assert main(["generate", str(scene), "--out", str(tmp_path / "out")]) != 0
    err = capsys.readouterr().err.strip()
    assert "scene.yaml" in err and "task" in err and "integer 0-5" in err and len(err.splitlines()) == 1, err


def test_batch_equals_the_scalar_function_bit_for_bit(tmp_path_factory):
    """NAME_task_space_batch (vector lanes where the compiler has them): the same bytes as one
    scalar call per state, statuses included (a NaN state and the singular zero pose of iiwa14
    counted as failed, their outputs untouched)."""
    import ctypes
    robot, compiled_lib, _ = compiled(BATCH_ARM, tmp_path_factory)
    lib = compiled_lib.lib
    n, m, count = robot.dof, 6, 37
    rng = np.random.default_rng(1)
    q, qd = rng.uniform(-3, 3, (count, n)), rng.uniform(-2, 2, (count, n))
    q[5, 1], q[6] = np.nan, 0.0
    pointer = ctypes.POINTER(ctypes.c_double)
    sizes = (m * m, m, m, n * m)
    batch = [np.full((count, size), 7.0) for size in sizes]
    lib.iiwa14_task_space_batch.restype = lib.iiwa14_task_space.restype = ctypes.c_int
    failed = lib.iiwa14_task_space_batch(count, q.ctypes.data_as(pointer), qd.ctypes.data_as(pointer),
                                         *[b.ctypes.data_as(pointer) for b in batch])
    codes = []
    for k in range(count):
        single = [np.full(size, 7.0) for size in sizes]
        codes.append(lib.iiwa14_task_space(np.ascontiguousarray(q[k]).ctypes.data_as(pointer),
                                           np.ascontiguousarray(qd[k]).ctypes.data_as(pointer),
                                           *[s.ctypes.data_as(pointer) for s in single]))
        for whole, one in zip(batch, single):
            assert whole[k].tobytes() == one.tobytes(), k
    assert codes[5] == 2 and codes[6] == 3 and failed == sum(code != 0 for code in codes) == 2
