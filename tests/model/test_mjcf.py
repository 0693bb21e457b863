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
QUIRKS = str(DATA / "quirks.xml")
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
    return {"every_form": EVERY_FORM, "walker": WALKER, "quirks": QUIRKS}.get(name) or gymnasium_asset(name)


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


def mujoco_model(path: str):
    """MuJoCo's compiled model of ``path``, compiled in a scratch folder: MuJoCo writes its
    warnings (settotalmass is deprecated in MuJoCo 4) to MUJOCO_LOG.TXT in the current folder."""
    import tempfile
    here = os.getcwd()
    with tempfile.TemporaryDirectory() as scratch:
        os.chdir(scratch)
        try:
            return mujoco.MjModel.from_xml_path(path)
        finally:
            os.chdir(here)


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


@pytest.mark.parametrize("name", GYM + ("every_form", "walker", "quirks"))
def test_reading_is_mujocos(name):
    """Mass matrix (with armature; a floating base through its velocity map), bias forces (with
    the model's gravity option), total mass and centre of mass of symdyn's reading against
    MuJoCo's compiled model, and every site's pose, at random states."""
    robot, model = read(name)
    m = mujoco_model(_path(name))
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
        roots = [b for b in moving if not _moves(m, m.body_parentid[b])]
        total = sum(m.body_subtreemass[b] for b in roots)
        com = sum(m.body_subtreemass[b] * d.subtree_com[b] for b in roots) / total
        assert abs(pin.computeTotalMass(model) - total) < 1e-12 * total
        assert np.abs(pin.centerOfMass(model, data, q) - com).max() < 1e-12
        pin.framesForwardKinematics(model, data, q)
        named = [site for site in range(m.nsite) if mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, site)]
        assert len(named) == len(robot.frames)  # (every named site a frame, in MuJoCo's order)
        for frame, site in zip(robot.frames, named):
            pose = data.oMf[model.getFrameId(f"frame_{frame.name}")]
            assert np.abs(pose.translation - d.site_xpos[site]).max() < 1e-12, frame.name
            assert np.abs(pose.rotation - d.site_xmat[site].reshape(3, 3)).max() < 1e-12, frame.name


@pytest.mark.parametrize("name", GYM + ("every_form", "walker", "quirks"))
def test_body_masses_and_inertias_are_mujocos(name):
    """Every moving body's mass, centre of mass and inertia tensor (with the bodies welded to it,
    which symdyn merges into it) against MuJoCo's compiled body_mass, body_ipos, body_iquat and
    body_inertia, compared in the world frame at a random state."""
    robot, model = read(name)
    m = mujoco_model(_path(name))
    d = mujoco.MjData(m)
    data = model.createData()
    q, v, _, _ = _states(model, 1, seed=3)[0]
    qpos, qvel, _ = _to_mujoco(model, q, v)
    d.qpos[:], d.qvel[:] = qpos, qvel
    mujoco.mj_forward(m, d)
    pin.forwardKinematics(model, data, q)
    joint_of = {link.name: k + 1 + (1 if robot.floating else 0) for k, link in enumerate(robot.links)}
    for weld in sorted({int(w) for w in m.body_weldid[1:] if w != 0}):
        members = [b for b in range(1, m.nbody) if m.body_weldid[b] == weld]
        theirs = pin.Inertia.Zero()
        for b in members:  # MuJoCo's body inertias, in the world
            R = d.ximat[b].reshape(3, 3)
            local = pin.Inertia(m.body_mass[b], np.zeros(3), R @ np.diag(m.body_inertia[b]) @ R.T)
            theirs += pin.SE3(np.eye(3), d.xipos[b]).act(local)
        jnt = [j for j in range(m.njnt) if m.jnt_bodyid[j] == weld]
        if m.jnt_type[jnt[0]] == mujoco.mjtJoint.mjJNT_FREE:
            joint = 1
        else:
            joint = joint_of[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, jnt[-1])]
        ours = data.oMi[joint].act(model.inertias[joint])
        assert abs(ours.mass - theirs.mass) < 1e-12 * theirs.mass, (name, weld)
        assert np.abs(ours.lever - theirs.lever).max() < 1e-12, (name, weld)
        assert np.abs(ours.inertia - theirs.inertia).max() < 1e-12 * max(np.abs(theirs.inertia).max(), 1e-9), (name, weld)


def _moves(m, body: int) -> bool:
    """Whether a MuJoCo body moves (else it is welded to the world, and left out)."""
    return m.body_weldid[body] != 0


def test_sites_are_frames_and_counted():
    """Every named site is a frame, in the file's order; the joints are MuJoCo's, in its order."""
    robot, _ = read("every_form")
    assert [f.name for f in robot.frames] == ["world_mark", "elbow_site", "tip", "bob_site"]
    m = mujoco_model(EVERY_FORM)
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(m.njnt)]
    assert [link.name for link in robot.links] == names
    robot, _ = read("walker")
    assert robot.floating and [f.name for f in robot.frames] == ["imu", "l_sole", "r_sole"]


def test_typos_and_degrees_are_warned_about():
    """An attribute or element MuJoCo's schema does not have (a typo: MuJoCo refuses the file) and
    angles beyond 2 pi under <compiler angle="radian"> (degrees by mistake) each draw one line."""
    from symdyn.model.mjcf import read_mjcf
    text = _ARM.format(extra='<jiont name="j2"/><body name="b" euler="0 90 0"><joint name="j3" dampng="1"/>'
                             '<geom size="0.1"/></body>')
    text = text.replace('<mujoco model="arm">', '<mujoco model="arm"><compiler angle="radian"/>')
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        read_mjcf(text, "typos.xml")
    lines = [str(w.message) for w in caught]
    schema = [line for line in lines if "not in MuJoCo's schema" in line]
    assert len(schema) == 1 and "element <jiont>" in schema[0] and "attribute 'dampng' of <joint>" in schema[0], lines
    assert any("angles beyond 2 pi rad (90)" in line for line in lines), lines


def test_what_the_reading_says():
    """The quirks file: sites renamed as frames are noted (a name that is not a C identifier, one
    repeated, one a body's), the spring-damper is in the one warning line, the fixed base with
    two branches draws no --floating-base advice (an MJCF says itself whether it floats), limits
    carry no effort or velocity the file does not give, and the mesh geoms (on the body welded to
    the world, and a weightless one) are accepted."""
    from symdyn.model.scene import read_robot_document
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        doc, _, notes = read_robot_document(QUIRKS)
    lines = [str(w.message) for w in caught]
    assert len(lines) == 1 and "1 joint spring-damper (springdamper" in lines[0], lines
    assert not any("--floating-base" in line for line in lines)
    renamed = next(note for note in notes if note.startswith("sites renamed"))
    assert "cam/rgb -> cam_rgb" in renamed and "cam_rgb -> cam_rgb_2" in renamed and "left_tip -> left_tip_site" in renamed
    assert [f if isinstance(f, str) else f["name"] for f in doc["frames"]] == ["cam_rgb", "cam_rgb_2", "left_tip_site"]
    limits = [link["limits"] for link in doc["links"] if "limits" in link]
    assert limits == [{"lower": "-0.1", "upper": "0.1"}], limits


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
    m = mujoco_model(_path(name))
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


# ---------------------------------------------------------------------------------------------
# The command line: generate, verify, convert, and hostile files

_ARM = """<mujoco model="arm">
  <worldbody>
    <body name="a" pos="0 0 0.1">
      <joint name="j1" axis="0 0 1"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      {extra}
    </body>
  </worldbody>
</mujoco>
"""


def test_verify_and_generate_an_mjcf(tmp_path, capsys):
    """symdyn verify compiles every default function of the hand-written floating walker (its
    includes, sites as frames) and agrees; generate writes C whose header names the MJCF, the
    joint order and the free joint's conventions."""
    from symdyn.cli import main
    assert main(["verify", WALKER, "--states", "3", "--functions",
                 "inverse_dynamics,mass_matrix,forward_dynamics,frame_poses"]) == 0
    out = capsys.readouterr().out
    assert out.count(" ok") == 4, out
    assert "against MuJoCo's own compiled model" in out
    assert main(["generate", EVERY_FORM, "--out", str(tmp_path / "c"), "--quiet", "--no-cache",
                 "--functions", "inverse_dynamics"]) == 0
    header = (tmp_path / "c" / "every_form_dynamics.h").read_text()
    assert "every_form.xml" in header and "joints numbered as MuJoCo numbers them" in header
    assert "not in the equations of motion: 1 actuator (symdyn's tau is" in capsys.readouterr().err


def test_mujoco_reference_is_independent(tmp_path, monkeypatch, capsys):
    """verify's reference for an MJCF is MuJoCo's own compile of the file: the same numbers as a
    Pinocchio model of symdyn's reading of a file MuJoCo reads alike (sites too), different ones
    when MuJoCo compiles another file (a heavier link: a reading that got the mass wrong would
    fail); without MuJoCo, verify says so in a warning and checks against the reading only."""
    from symdyn.check import mujoco_model
    from symdyn.check.mujoco_model import MujocoReference, MujocoUnavailable
    from symdyn.check.pinocchio_model import PinocchioReference
    from symdyn.cli import main
    robot, model = read("walker")
    theirs, ours = MujocoReference(robot, WALKER), PinocchioReference(robot)
    for q, v, a, tau in _states(model, 3):
        for name, args in (("mass_matrix", (q,)), ("coriolis", (q, v)), ("gravity", (q,)),
                           ("inverse_dynamics", (q, v, a)), ("forward_dynamics", (q, v, tau)), ("frame_poses", (q,))):
            assert _relative(getattr(theirs, name)(*args), getattr(ours, name)(*args)) < TOLERANCE, name
    heavier = tmp_path / "walker"
    (heavier / "parts").mkdir(parents=True)
    for part in ("robot.xml", "parts/defaults.xml", "parts/leg_left.xml", "parts/leg_right.xml"):
        (heavier / part).write_text((DATA / "walker" / part).read_text())
    text = (heavier / "parts" / "leg_left.xml").read_text()
    (heavier / "parts" / "leg_left.xml").write_text(text.replace('size="0.035"', 'size="0.035" density="1200"'))
    other = MujocoReference(robot, str(heavier / "robot.xml"))
    q = _states(model, 1)[0][0]
    assert _relative(other.mass_matrix(q), ours.mass_matrix(q)) > 1e-3

    monkeypatch.chdir(DATA)  # a path relative to the current folder (MuJoCo compiles in a scratch one)
    assert MujocoReference(read("every_form")[0], "every_form.xml").mj.nv == 7

    def refused(path):
        raise MujocoUnavailable("MuJoCo is not installed (pip install mujoco)")
    monkeypatch.setattr(mujoco_model, "compile_mjcf", refused)
    assert main(["verify", WALKER, "--states", "2", "--functions", "mass_matrix"]) == 0
    captured = capsys.readouterr()
    assert "against a Pinocchio model of symdyn's reading" in captured.out
    assert "MuJoCo is not installed" in captured.err


def test_convert_to_yaml_and_urdf(tmp_path, capsys):
    """convert --to yaml writes a robot file that reads as the same robot; --to urdf a URDF that
    Pinocchio's URDF parser reads as the same mass matrix (armature, which URDF cannot hold,
    named in a warning)."""
    from symdyn.cli import main
    robot, model = read("every_form")
    assert main(["convert", EVERY_FORM, "--to", "yaml", "--out", str(tmp_path / "r.yaml"), "--quiet"]) == 0
    again, _ = build_model(symdyn.load(str(tmp_path / "r.yaml")))
    assert main(["convert", EVERY_FORM, "--to", "urdf", "--out", str(tmp_path / "r.urdf"), "--quiet"]) == 0
    assert "armature" in capsys.readouterr().err
    urdf = pin.buildModelFromUrdf(str(tmp_path / "r.urdf"))
    urdf.gravity = model.gravity
    # Pinocchio's URDF parser takes a link's child joints by name: the same joints, another order
    order = [urdf.getJointId(link.name) - 1 for link in robot.links]
    assert sorted(order) == list(range(model.nv))
    for q, v, a, _ in _states(model, 3):
        M = pin.crba(model, model.createData(), q)
        assert _relative(pin.crba(again, again.createData(), q), M) < TOLERANCE
        q_urdf = np.empty(model.nq)
        q_urdf[order] = q
        M_urdf = pin.crba(urdf, urdf.createData(), q_urdf)[np.ix_(order, order)]
        assert _relative(M_urdf, M - np.diag(model.armature)) < TOLERANCE


HOSTILE = {
    "entity": ('<?xml version="1.0"?><!DOCTYPE m [<!ENTITY a "aaaa">]><mujoco><worldbody/></mujoco>',
               "DOCTYPE"),
    "outside": (_ARM.format(extra='<include file="../secret.xml"/>'), "outside the model's folder"),
    "absolute": (_ARM.format(extra='<include file="/etc/passwd"/>'), "relative to the model's folder"),
    "cycle": (_ARM.format(extra='<include file="model.xml"/>'), "includes itself"),
    "nan": (_ARM.format(extra='<geom type="sphere" size="nan"/>'), "not a decimal number"),
    "huge": (_ARM.replace('pos="0 0 0.1"', 'pos="0 0 1e400"'), "too large"),
    "huge_mass": (_ARM.format(extra='<inertial pos="0 0 0" mass="1e101" diaginertia="1 1 1"/>'), "too large"),
    "ball": (_ARM.replace('axis="0 0 1"', 'type="ball"'), "ball joints are not supported"),
    "mesh": (_ARM.format(extra='<geom type="mesh" mesh="m"/>'), "come from its mesh, which symdyn does not read"),
    "class": (_ARM.format(extra='<geom class="nope" size="0.1"/>'), "unknown default class"),
    "orientations": (_ARM.replace('pos="0 0 0.1"', 'pos="0 0 0.1" euler="0 0 1" quat="1 0 0 0"'),
                     "several orientations"),
    "free_deep": (_ARM.format(extra='<body name="b"><freejoint/></body>'), "a free joint must be"),
    "static": ('<mujoco><worldbody><body name="a"><geom size="0.1"/></body></worldbody></mujoco>',
               "no body has a joint"),
    "two_free": ('<mujoco><worldbody><body name="a"><freejoint/><geom size="0.1"/></body>'
                 '<body name="b"><freejoint/><geom size="0.1"/></body></worldbody></mujoco>', "a second free joint"),
    "missing_include": (_ARM.format(extra='<include file="nothere.xml"/>'), "<include file='nothere.xml'>"),
    "no_size": (_ARM.format(extra='<geom type="box"/>'), "a box needs its size"),
    "not_mjcf": ("<mujocomodel/>", "top element is '<mujocomodel>'"),
}


@pytest.mark.parametrize("case", sorted(HOSTILE))
def test_hostile_mjcf_refused_in_one_line(case, tmp_path, capsys, monkeypatch):
    """Entities, includes outside the folder, absolute or cyclic, NaN, numbers beyond the
    format's bounds, unsupported joints and geoms, unknown classes: one error line naming the
    file, exit 1, nothing written, no traceback."""
    from symdyn.cli import main
    monkeypatch.chdir(tmp_path)
    (tmp_path / "secret.xml").write_text("<mujoco/>")
    folder = tmp_path / "model"
    folder.mkdir()
    text, expected = HOSTILE[case]
    (folder / "model.xml").write_text(text)
    status = main(["generate", str(folder / "model.xml"), "--out", str(tmp_path / "out"), "--quiet", "--no-cache"])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 1 and "Traceback" not in "\n".join(err)
    assert len(err) == 1 or all(line.startswith("symdyn: warning: ") for line in err[:-1]), err
    assert err[-1].startswith("symdyn: error: ") and expected in err[-1] and "model.xml" in err[-1], err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("shape", ["flat", "nested"])
def test_a_hundred_thousand_bodies_refused_quickly(shape, tmp_path, capsys):
    """100,000 bodies, side by side or nested 100,000 deep: refused in one line (the body bound)
    within seconds of CPU time, no recursion error."""
    import time
    from symdyn.cli import main
    count = 100_000
    if shape == "flat":
        bodies = '<body><joint/><geom size="0.1"/></body>' * count
    else:
        bodies = '<body><joint/><geom size="0.1"/>' * count + "</body>" * count
    path = tmp_path / "many.xml"
    path.write_text(f"<mujoco><worldbody>{bodies}</worldbody></mujoco>")
    start = time.process_time()
    status = main(["convert", str(path), "--to", "yaml"])
    assert time.process_time() - start < 20
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 1 and len(err) == 1 and "more than 2000 bodies" in err[0], err


def test_fuzz_renditions_read_as_their_urdf(tmp_path):
    """The differential fuzzer's MJCF renditions of its random URDF trees (every orientation form,
    degrees and radians, both eulerseqs, full and principal inertias, free joints): symdyn's
    reading of each MJCF is its reading of the URDF (mass matrix, inverse dynamics and frames at
    random states, 20 cases); the campaign checks them against Pinocchio's reading of the URDF."""
    from symdyn.check import fuzz
    cases = [c for c in map(fuzz.random_case, range(400)) if c.as_mjcf][:20]
    assert {c.floating for c in cases} == {False, True}
    for case in cases:
        folder = tmp_path / str(case.number)
        folder.mkdir()
        mjcf = fuzz.write_case(case, str(folder))
        frames = list(case.frames) or None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SymdynWarning)
            # (an MJCF's angles are as written, as MuJoCo takes them: the URDF's too, not 1e-9 from a quarter turn snapped)
            from_urdf = symdyn.load(str(folder / case.robot_file), floating_base=case.floating, frames=frames,
                                    exact_angles=True)
            from_mjcf = symdyn.load(mjcf, frames=frames)
        assert [link.name for link in from_mjcf.links] == [link.name for link in from_urdf.links], case.number
        mine, _ = build_model(from_mjcf)
        theirs, _ = build_model(from_urdf)
        for q, v, a, _ in _states(mine, 3, seed=case.number):
            assert _relative(pin.crba(mine, mine.createData(), q), pin.crba(theirs, theirs.createData(), q)) < 1e-12
            assert _relative(pin.rnea(mine, mine.createData(), q, v, a),
                             pin.rnea(theirs, theirs.createData(), q, v, a)) < 1e-12, case.number
            mine_data, their_data = mine.createData(), theirs.createData()
            pin.framesForwardKinematics(mine, mine_data, q)
            pin.framesForwardKinematics(theirs, their_data, q)
            for frame in from_urdf.frames:
                ours = mine_data.oMf[mine.getFrameId(f"frame_{frame.name}")].homogeneous
                assert np.abs(ours - their_data.oMf[theirs.getFrameId(f"frame_{frame.name}")].homogeneous).max() < 1e-12


def test_verify_of_a_one_joint_robot_whose_tool_does_not_accelerate(tmp_path, capsys):
    """A one-joint MJCF whose body turns about its own origin (J-dot qd of its frame is exactly
    zero: Pinocchio's is rounding, which is not the measure) with two sites: verify passes every
    kinematic function (the frames' Jacobians of one joint stacked as 6-vectors read as a column)."""
    from symdyn.cli import main
    path = tmp_path / "turn.xml"
    path.write_text('<mujoco model="turn"><worldbody><body name="a"><joint name="j" axis="0 0 1"/>'
                    '<geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="1"/>'
                    '<site name="tip" pos="0.3 0 0"/><site name="mid" pos="0.2 0 0.1"/></body></worldbody></mujoco>')
    assert main(["verify", str(path), "--states", "5", "--functions",
                 "jacobian_dot_qd,frame_jacobians,frame_jacobian_dot_v,forward_kinematics"]) == 0
    out = capsys.readouterr().out
    assert out.count(" ok") == 4 and "FAIL" not in out, out
