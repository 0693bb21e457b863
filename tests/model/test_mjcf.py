"""MuJoCo MJCF in: symdyn's reading of gymnasium's MuJoCo tasks and two hand-written files against
MuJoCo's own compiler (the format's authority: its mass matrix with armature, its bias forces,
its centre of mass and sites) and Pinocchio's ``buildModelFromMJCF`` (mass matrix, inverse and
forward dynamics, frames at sites) where Pinocchio 4.1 reads the file as MuJoCo does.

The robots are read by symdyn and built as Pinocchio models of that reading
(:func:`symdyn.check.pinocchio_model.build_model`, every link, inertia, armature and frame as
read), so these tests judge the reading; that the generated code equals such a model is what
every other test (and ``symdyn verify``) checks, and one test here runs verify on an MJCF."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

import symdyn
from helpers import REPO
from symdyn.check.pinocchio_model import build_model
from symdyn.model.errors import SymdynWarning

pin = pytest.importorskip("pinocchio")
mujoco = pytest.importorskip("mujoco")

DATA = REPO / "tests" / "data" / "mjcf"
EVERY_FORM = str(DATA / "every_form.xml")
WALKER = str(DATA / "walker" / "robot.xml")
GYM = ("ant", "humanoid", "half_cheetah", "walker2d", "hopper", "pusher")
TOLERANCE = 1e-11


def gymnasium_asset(name: str) -> str:
    """The path of gymnasium's ``name``.xml (gymnasium is a test extra; it is not imported)."""
    import importlib.util
    spec = importlib.util.find_spec("gymnasium")
    if spec is None or not spec.submodule_search_locations:
        pytest.fail("gymnasium is missing: pip install -e '.[test]'")
    return os.path.join(list(spec.submodule_search_locations)[0], "envs", "mujoco", "assets", f"{name}.xml")


def _path(name: str) -> str:
    return {"every_form": EVERY_FORM, "walker": WALKER}.get(name) or gymnasium_asset(name)


_READ = {}


def read(name: str):
    """symdyn's robot of a file (its unmodelled-element warning silenced) and its Pinocchio model."""
    if name not in _READ:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SymdynWarning)
            robot = symdyn.load(_path(name))
        model, _ = build_model(robot)
        _READ[name] = robot, model
    return _READ[name]


def _states(model, count: int, seed: int = 5):
    """Random (q, v, a, tau) in Pinocchio's conventions: joints in [-1.2, 1.2], a unit quaternion."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        q = rng.uniform(-1.2, 1.2, model.nq)
        if model.nq != model.nv:  # the free-flyer's quaternion (x y z w)
            quat = rng.normal(size=4)
            q[3:7] = quat / np.linalg.norm(quat)
        out.append((q, rng.normal(size=model.nv), rng.normal(size=model.nv), rng.normal(size=model.nv)))
    return out


def _relative(mine, theirs) -> float:
    mine, theirs = np.asarray(mine), np.asarray(theirs)
    return float(np.abs(mine - theirs).max() / max(np.abs(theirs).max(), 1e-300))


# ---------------------------------------------------------------------------------------------
# MuJoCo


def _mujoco_full_mass(m, d) -> np.ndarray:
    M = np.zeros((m.nv, m.nv))
    if hasattr(d, "qM"):  # MuJoCo 3
        mujoco.mj_fullM(m, M, d.qM)
    else:  # MuJoCo 4
        mujoco.mj_fullM(m, d, M)
    return M


def _to_mujoco(model, q, v):
    """MuJoCo's qpos and qvel of Pinocchio's (q, v), and T with M_mujoco = T M T^T (a free
    joint: quaternion w first, the linear velocity of the body origin in the world frame)."""
    if model.nq == model.nv:
        return q.copy(), v.copy(), np.eye(model.nv)
    R = pin.Quaternion(q[6], q[3], q[4], q[5]).toRotationMatrix()
    qpos = np.concatenate([q[:3], [q[6]], q[3:6], q[7:]])
    qvel = np.concatenate([R @ v[:3], v[3:]])
    T = np.eye(model.nv)
    T[:3, :3] = R
    return qpos, qvel, T


@pytest.mark.parametrize("name", GYM + ("every_form", "walker"))
def test_reading_is_mujocos(name):
    """Mass matrix (with armature; a floating base through its velocity map), bias forces (with
    the model's gravity option), total mass and centre of mass of symdyn's reading against
    MuJoCo's compiled model, and every site's pose, at random states."""
    robot, model = read(name)
    m = mujoco.MjModel.from_xml_path(_path(name))
    d = mujoco.MjData(m)
    data = model.createData()
    assert model.nv == m.nv
    for q, v, _, _ in _states(model, 4):
        qpos, qvel, T = _to_mujoco(model, q, v)
        d.qpos[:], d.qvel[:] = qpos, qvel
        mujoco.mj_forward(m, d)
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        assert _relative(T @ M @ T.T, _mujoco_full_mass(m, d)) < TOLERANCE, name
        a = np.zeros(model.nv)
        if model.nq != model.nv:  # MuJoCo's qacc = 0: the base origin's world acceleration zero
            a[:3] = -np.cross(v[3:6], v[:3])
        assert _relative(T @ pin.rnea(model, data, q, v, a), d.qfrc_bias) < TOLERANCE, name
        moving = [b for b in range(1, m.nbody) if _moves(m, b)]
        roots = [b for b in moving if m.body_parentid[b] == 0]
        total = sum(m.body_subtreemass[b] for b in roots)
        com = sum(m.body_subtreemass[b] * d.subtree_com[b] for b in roots) / total
        assert abs(pin.computeTotalMass(model) - total) < 1e-12 * total
        assert np.abs(pin.centerOfMass(model, data, q) - com).max() < 1e-12
        pin.framesForwardKinematics(model, data, q)
        for frame in robot.frames:
            site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, frame.name)
            pose = data.oMf[model.getFrameId(f"frame_{frame.name}")]
            assert np.abs(pose.translation - d.site_xpos[site]).max() < 1e-12, frame.name
            assert np.abs(pose.rotation - d.site_xmat[site].reshape(3, 3)).max() < 1e-12, frame.name


def _moves(m, body: int) -> bool:
    """Whether a MuJoCo body is in a tree with a joint (else it is fixed to the world, and left out)."""
    root = body
    while m.body_parentid[root] != 0:
        root = m.body_parentid[root]
    return any(m.body_rootid[j] == root for j in range(1, m.nbody) if m.body_jntnum[j] > 0)


def test_sites_are_frames_and_counted():
    """Every named site is a frame, in the file's order; the joints are MuJoCo's, in its order."""
    robot, _ = read("every_form")
    assert [f.name for f in robot.frames] == ["world_mark", "elbow_site", "tip", "bob_site"]
    m = mujoco.MjModel.from_xml_path(EVERY_FORM)
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(m.njnt)]
    assert [link.name for link in robot.links] == names
    robot, _ = read("walker")
    assert robot.floating and [f.name for f in robot.frames] == ["imu", "l_sole", "r_sole"]


# ---------------------------------------------------------------------------------------------
# Pinocchio


#: the files Pinocchio 4.1's buildModelFromMJCF reads as MuJoCo does (half_cheetah but for its
#: settotalmass, which Pinocchio ignores: its inertias are scaled to MuJoCo's total here). Not
#: pusher (Pinocchio keeps only the first body of the world and drops the arm's visual-class
#: geoms' mass) nor every_form (a <frame>, an upper-case eulerseq axis, a non-unit axisangle, a
#: class under a childclass, a geom mass from a default class: docs/mjcf.md lists them)
PINOCCHIO_AGREES = ("ant", "humanoid", "half_cheetah", "walker2d", "hopper", "walker")


def _flattened(path: str, out) -> str:
    """The MJCF at ``path`` with its includes written in place (Pinocchio 4.1 reads <include>
    at the top level only; MuJoCo anywhere): the same model, in one file under ``out``."""
    import re
    folder = os.path.dirname(path)

    def text(name):
        inner = open(os.path.join(folder, name)).read()
        inner = re.sub(r"<include file=\"([^\"]+)\"/>", lambda m: text(m.group(1)), inner)
        return re.sub(r"</?mujoco[^>]*>", "", inner) if name != os.path.basename(path) else inner
    flat = out / os.path.basename(path)
    flat.write_text(text(os.path.basename(path)))
    return str(flat)


def _pinocchio_model(name: str, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        theirs = pin.buildModelFromMJCF(_flattened(_path(name), tmp_path) if name == "walker" else _path(name))
    theirs = theirs[0] if isinstance(theirs, tuple) else theirs
    m = mujoco.MjModel.from_xml_path(_path(name))
    if name == "half_cheetah":  # settotalmass="14": MuJoCo scales every mass and inertia
        scale = m.body_subtreemass[1] / pin.computeTotalMass(theirs)
        for k in range(1, theirs.njoints):
            inertia = theirs.inertias[k]
            theirs.inertias[k] = pin.Inertia(inertia.mass * scale, inertia.lever, inertia.inertia * scale)
    return theirs


@pytest.mark.parametrize("name", PINOCCHIO_AGREES)
def test_reading_is_pinocchios(name, tmp_path):
    """Mass matrix (with armature), inverse and forward dynamics and the sites' frames of
    symdyn's reading against Pinocchio's own reading of the MJCF, at random states."""
    robot, model = read(name)
    theirs = _pinocchio_model(name, tmp_path)
    theirs.gravity = model.gravity
    assert (theirs.nq, theirs.nv) == (model.nq, model.nv)
    mine_data, their_data = model.createData(), theirs.createData()
    # Pinocchio 4.1 gives a free joint in the file a constant placement (a world translation
    # that does not change the dynamics; MuJoCo's qpos is the body's pose): its frames' world
    # poses are taken back through it
    offset = theirs.jointPlacements[1].inverse() if model.nq != model.nv else pin.SE3.Identity()
    for q, v, a, tau in _states(model, 4, seed=9):
        assert _relative(pin.crba(model, mine_data, q), pin.crba(theirs, their_data, q)) < TOLERANCE
        assert _relative(pin.rnea(model, mine_data, q, v, a), pin.rnea(theirs, their_data, q, v, a)) < TOLERANCE
        assert _relative(pin.aba(model, mine_data, q, v, tau), pin.aba(theirs, their_data, q, v, tau)) < TOLERANCE
        pin.framesForwardKinematics(model, mine_data, q)
        pin.framesForwardKinematics(theirs, their_data, q)
        for frame in robot.frames:
            mine = mine_data.oMf[model.getFrameId(f"frame_{frame.name}")]
            their = offset * their_data.oMf[theirs.getFrameId(frame.name)]
            assert np.abs(mine.homogeneous - their.homogeneous).max() < 1e-12, frame.name
