"""Scenes: locked joints against Pinocchio's buildReducedModel, a runtime payload against
Pinocchio with the payload appended to the last body, and every specialization against the full
model at the same fixed values."""

from __future__ import annotations

import numpy as np
import pytest

from symdyn.model.outputs import Dimensions
import symdyn
from helpers import REPO, normalized_error, random_states
from symdyn.check.cbuild import build_and_load
from symdyn.cli import main
from symdyn.emit.pipeline import configure, generate
from symdyn.check.pinocchio_model import build_model
from symdyn.model.scene import load_scene

SCENES = REPO / "robots" / "scenes"
TOL = 1e-10


def _scene_file(tmp_path, text, name="scene.yaml"):
    path = tmp_path / name
    path.write_text(text.replace("ROBOTS", str(REPO / "robots")))
    return str(path)


LOCKS = {
    "puma560 wrist": ("puma560", {4: 0.3, 5: -0.5, 6: 1.0}),
    "ur5 base and elbow": ("ur5", {1: 0.7, 3: -1.1}),
    "stanford prismatic": ("stanford", {3: 0.35, 6: 0.2}),
}


@pytest.mark.parametrize("case", sorted(LOCKS))
def test_locked_joints_agree_with_pinocchio_reduced_model(tmp_path, case):
    import pinocchio as pin
    name, locked = LOCKS[case]
    lock = ", ".join(f"{k}: {v}" for k, v in locked.items())
    path = _scene_file(tmp_path, f"scene: 1\nrobot: ROBOTS/{name}.yaml\nlock: {{{lock}}}\n")
    scene = load_scene(path)
    full = symdyn.load(REPO / "robots" / f"{name}.yaml")
    assert scene.robot.dof == full.dof - len(locked)
    model, info = build_model(full)
    q_ref = np.zeros(full.dof)
    for k, v in locked.items():
        q_ref[k - 1] = v
    reduced = pin.buildReducedModel(model, list(locked), q_ref)
    data = reduced.createData()
    kept = [k for k in range(full.dof) if k + 1 not in locked]
    damping, coulomb = info["damping"][kept], info["coulomb"][kept]
    armature = np.array(reduced.armature)
    np.testing.assert_allclose(armature, np.array(model.armature)[kept])
    num = symdyn.derive(scene.robot).numeric
    pairs = {k: ([], []) for k in ("D", "c", "h", "tau", "fd")}
    for q, qd, qdd, tau in random_states(scene.robot.dof, 20, seed=3):
        friction = damping * qd + coulomb * np.sign(qd)
        M = pin.crba(reduced, data, q)
        M = np.triu(M) + np.triu(M, 1).T - np.diag(armature)
        c = pin.computeGeneralizedGravity(reduced, data, q).copy()
        for key, mine, theirs in (
                ("D", num.mass_matrix(q), M), ("c", num.gravity(q), c),
                ("h", num.coriolis(q, qd), pin.nonLinearEffects(reduced, data, q, qd) - c),
                ("tau", num.inverse_dynamics(q, qd, qdd), pin.rnea(reduced, data, q, qd, qdd) + friction),
                ("fd", num.forward_dynamics(q, qd, tau), pin.aba(reduced, data, q, qd, tau - friction))):
            pairs[key][0].append(mine)
            pairs[key][1].append(np.array(theirs))
    errors = {k: normalized_error(a, b) for k, (a, b) in pairs.items()}
    assert all(v <= TOL for v in errors.values()), errors


def test_locked_scene_equals_the_full_model_at_the_locked_values():
    scene = load_scene(str(SCENES / "puma560_wrist_locked.yaml"))
    full = symdyn.derive(symdyn.load(REPO / "robots" / "puma560.yaml")).numeric
    mine = symdyn.derive(scene.robot).numeric
    locked = np.array([0.3, -0.5, 1.0])
    for q, qd, qdd, _ in random_states(3, 10, seed=8):
        qf, qdf, qddf = np.r_[q, locked], np.r_[qd, 0, 0, 0], np.r_[qdd, 0, 0, 0]
        np.testing.assert_allclose(mine.mass_matrix(q), full.mass_matrix(qf)[:3, :3], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(mine.gravity(q), full.gravity(qf)[:3], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(mine.coriolis(q, qd), full.coriolis(qf, qdf)[:3], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(mine.inverse_dynamics(q, qd, qdd), full.inverse_dynamics(qf, qdf, qddf)[:3],
                                   rtol=1e-12, atol=1e-12)


def test_runtime_payload_agrees_with_pinocchio_for_several_payloads(tmp_path):
    """The scene's compiled C takes (m_p, c_z) at run time; Pinocchio's model gets the payload
    inertia appended to its last body, one model per payload value."""
    import pinocchio as pin
    scene = load_scene(str(SCENES / "ur5_payload.yaml"))
    robot = scene.robot
    assert [s.name for s in robot.parameters] == ["m_p", "c_z"]
    files = {k: v.decode() for k, v in generate(configure(SCENES / "ur5_payload.yaml")).items()}
    assert "ur5_payload.yaml" in files["ur5_payload_dynamics.h"] and "runtime parameters: m_p, c_z" in files["ur5_payload_dynamics.h"]
    lib = build_and_load(files, "ur5_payload", 6, 2, "double", str(tmp_path))
    full = symdyn.load(REPO / "robots" / "ur5.yaml")
    for m_p, c_z in ((0.0, 0.0), (0.5, 0.03), (3.0, 0.12)):
        model, info = build_model(full)
        payload = pin.Inertia(m_p, np.array([0.0, 0.0, c_z]), np.diag([0.002, 0.002, 0.001]))
        last = info["last_body"]
        model.appendBodyToJoint(6, pin.SE3(last[:3, :3], last[:3, 3]).act(payload), pin.SE3.Identity())
        data = model.createData()
        p = np.array([m_p, c_z])
        pairs = {k: ([], []) for k in ("D", "c", "tau", "fd")}
        for q, qd, qdd, tau in random_states(6, 10, seed=int(m_p * 10)):
            friction = info["damping"] * qd + info["coulomb"] * np.sign(qd)
            M = pin.crba(model, data, q)
            M = np.triu(M) + np.triu(M, 1).T - np.diag(model.armature)
            for key, mine, theirs in (
                    ("D", lib.mass_matrix(q, p), M),
                    ("c", lib.gravity(q, p), pin.computeGeneralizedGravity(model, data, q)),
                    ("tau", lib.inverse_dynamics(q, qd, qdd, p), pin.rnea(model, data, q, qd, qdd) + friction),
                    ("fd", lib.forward_dynamics(q, qd, tau, p), pin.aba(model, data, q, qd, tau - friction))):
                pairs[key][0].append(mine)
                pairs[key][1].append(np.array(theirs))
        errors = {k: normalized_error(a, b) for k, (a, b) in pairs.items()}
        assert all(v <= TOL for v in errors.values()), (m_p, c_z, errors)


def test_runtime_payload_equals_the_folded_payload(tmp_path):
    runtime = load_scene(str(SCENES / "ur5_payload.yaml")).robot
    folded_path = _scene_file(tmp_path, (SCENES / "ur5_payload.yaml").read_text()
                              .replace("robot: ../ur5.yaml", "robot: ROBOTS/ur5.yaml")
                              .replace("runtime: [m_p, c_z]", "runtime: []")
                              .replace("values: {m_p: 1.0, c_z: 0.05}", "values: {m_p: 2.5, c_z: 0.08}"))
    folded = load_scene(folded_path).robot
    assert folded.parameters == ()
    a, b = symdyn.derive(runtime).numeric, symdyn.derive(folded).numeric
    p = np.array([2.5, 0.08])
    for q, qd, qdd, tau in random_states(6, 5, seed=2):
        np.testing.assert_allclose(a.inverse_dynamics(q, qd, qdd, p), b.inverse_dynamics(q, qd, qdd), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(a.forward_dynamics(q, qd, tau, p), b.forward_dynamics(q, qd, tau), rtol=1e-12, atol=1e-12)


def test_gravity_only_float_scene_emits_only_gravity(tmp_path):
    path = str(SCENES / "puma560_gravity.yaml")
    files = {k: v.decode() for k, v in generate(configure(path)).items()}
    header = files["puma560_gravity_dynamics.h"]
    assert "typedef float puma560_gravity_real;" in header
    lib = build_and_load(files, "puma560_gravity", 6, 0, "float", str(tmp_path))
    assert hasattr(lib.lib, "puma560_gravity_gravity")
    assert not hasattr(lib.lib, "puma560_gravity_mass_matrix")
    full = symdyn.derive(symdyn.load(REPO / "robots" / "puma560.yaml")).numeric
    states = [s[0].astype(np.float32).astype(float) for s in random_states(6, 20, seed=1)]
    err = normalized_error([lib.gravity(q) for q in states], [full.gravity(q) for q in states])
    assert err <= 1e-5


def test_scene_errors_name_the_file_and_field(tmp_path, capsys):
    cases = {
        "unknown key": ("scene: 1\nrobot: ROBOTS/puma560.yaml\nfrobs: 1\n", "frobs"),
        "bad joint": ("scene: 1\nrobot: ROBOTS/puma560.yaml\nlock: {9: 0.1}\n", "lock.9"),
        "bad function": ("scene: 1\nrobot: ROBOTS/puma560.yaml\nfunctions: [mass]\n", "functions"),
        "missing robot": ("scene: 1\nrobot: ROBOTS/none.yaml\n", "robot"),
        "lock value": ("scene: 1\nrobot: ROBOTS/puma560.yaml\nlock: {2: __import__}\n", "lock.2"),
        "all locked": ("scene: 1\nrobot: ROBOTS/scara.yaml\nlock: {1: 0, 2: 0, 3: 0, 4: 0}\n", "free"),
        "locked twice": ("scene: 1\nrobot: ROBOTS/puma560.yaml\nlock: {1: 0, waist: 0.1}\n",
                         "joint 1 (waist) is locked twice, as 1 and as 'waist'"),
    }
    for label, (text, needle) in cases.items():
        path = _scene_file(tmp_path, text, f"{label.replace(' ', '_')}.yaml")
        assert main(["generate", path, "--out", str(tmp_path / "out")]) == 1, label
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and needle in err, (label, err)
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


class _Reduced:
    """Pinocchio's buildReducedModel of a robot's model (symdyn's notation, as PinocchioReference:
    the mass matrix without armature, friction in inverse and forward dynamics)."""

    def __init__(self, full, locked: dict[int, float], kept_robot):
        import pinocchio as pin
        self.pin = pin
        model, _ = build_model(full)
        first = 2 if full.floating else 1  # Pinocchio's joint id of link 1 (root_joint, universe)
        q_ref = pin.neutral(model)
        for k, v in locked.items():
            q_ref[(7 if full.floating else 0) + k - 1] = v
        self.model = pin.buildReducedModel(model, [first + k - 1 for k in locked], q_ref)
        self.data = self.model.createData()
        base = 6 if full.floating else 0
        self.damping = np.r_[np.zeros(base), [float(l.damping) for l in kept_robot.links]]
        self.coulomb = np.r_[np.zeros(base), [float(l.coulomb) for l in kept_robot.links]]
        self.armature = np.array(self.model.armature)

    def friction(self, qd):
        return self.damping * qd + self.coulomb * np.sign(qd)

    def mass_matrix(self, q):
        M = self.pin.crba(self.model, self.data, q)
        return np.triu(M) + np.triu(M, 1).T - np.diag(self.armature)

    def gravity(self, q):
        return self.pin.computeGeneralizedGravity(self.model, self.data, q).copy()

    def coriolis(self, q, qd):
        return self.pin.nonLinearEffects(self.model, self.data, q, qd).copy() - self.gravity(q)

    def inverse_dynamics(self, q, qd, qdd):
        return self.pin.rnea(self.model, self.data, q, qd, qdd).copy() + self.friction(qd)

    def forward_dynamics(self, q, qd, tau):
        return self.pin.aba(self.model, self.data, q, qd, tau - self.friction(qd)).copy()


@pytest.mark.parametrize("robot_file, locked, parents", [
    ("examples/trees/torso_two_arms.yaml", {3: 0.4, 5: -0.6}, (-1, 0, 1, 0, 3)),
    ("examples/trees/space_robot.yaml", {1: 0.5, 6: 0.1}, (-1, 0, -1, 2))], ids=["fixed", "floating"])
def test_locking_joints_of_a_tree_agrees_with_pinocchio_reduced_model(tmp_path, robot_file, locked, parents):
    """A scene locking joints of a kinematic tree: a locked link merges into its nearest moving
    ancestor (a floating base's body for link 1 of the satellite; its gravity turned on), the links
    on it hang on that ancestor; every joint-space function at 20 states against Pinocchio's
    buildReducedModel of the full model, and the compiled C of inverse dynamics and the mass
    matrix."""
    from symdyn.check.pinocchio_model import compare
    from symdyn.check.states import random_state
    from symdyn.emit.cgen import generate_c
    text = (REPO / robot_file).read_text().replace("gravity: [0, 0, 0]", "gravity: [0.3, -1.2, -9.81]")
    (tmp_path / "robot.yaml").write_text(text)
    lock = ", ".join(f"{k}: {v}" for k, v in locked.items())
    scene = load_scene(_scene_file(tmp_path, f"scene: 1\nrobot: robot.yaml\nlock: {{{lock}}}\n"))
    full = symdyn.load(str(tmp_path / "robot.yaml"))
    robot = scene.robot
    assert robot.dof == full.dof - len(locked) and robot.parent_indices == parents
    reference = _Reduced(full, locked, robot)
    eqs = symdyn.derive(robot)
    rng = np.random.default_rng(21)
    states = [random_state(robot, rng) for _ in range(20)]
    functions = ("inverse_dynamics", "mass_matrix", "coriolis", "gravity", "forward_dynamics")
    errors = compare(eqs.numeric, reference, states, functions)
    assert all(e <= TOL for e in errors.values()), errors
    compiled = ("inverse_dynamics", "mass_matrix")
    lib = build_and_load(generate_c(eqs, compiled, "double"), robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
    errors = compare(lib, reference, states, compiled)
    assert all(e <= TOL for e in errors.values()), errors
