"""The force-to-torque reaction map (seed 004, sections 2-4): the wrench the base exerts on body
1, k0 + D tau_H, against Pinocchio (aba with the passive joints' torques zero, then rnea and
data.f[1] moved to the base frame), in the symbolic derivation, the compiled C (double and float)
and CasADi; passive joints in the robot file."""

from __future__ import annotations

import numpy as np
import pytest

import symdyn
from helpers import REPO, PinocchioReference, robot_path
from symdyn.check.cbuild import build_and_load
from symdyn.cli import main
from symdyn.emit.cgen import generate_c
from symdyn.model.errors import SymdynError
from symdyn.model.outputs import Dimensions

LEG = robot_path("pendulum_leg")
MIDDLE = str(REPO / "tests" / "data" / "passive_middle.yaml")


def _states(robot, count, seed):
    """(q, qd, tau_H): random configurations, rates and actuated torques."""
    rng = np.random.default_rng(seed)
    n, na = robot.dof, len(robot.actuated_joints)
    return [(rng.uniform(-np.pi, np.pi, n), rng.uniform(-2, 2, n), rng.uniform(-20, 20, na))
            for _ in range(count)]


def _worst(mine, theirs):
    """Largest |mine - theirs| over states, per wrench component divided by that component's RMS
    (the whole wrench's RMS where a component is zero throughout), worst component."""
    mine, theirs = np.asarray(mine), np.asarray(theirs)
    overall = np.sqrt(np.mean(theirs ** 2))
    rms = np.sqrt(np.mean(theirs ** 2, axis=0))
    scale = np.where(rms > 1e-9 * overall, rms, overall)
    return float(np.max(np.abs(mine - theirs) / scale))


@pytest.fixture(scope="module")
def leg_eqs(derived):
    return derived("pendulum_leg")


@pytest.mark.parametrize("path", [LEG, MIDDLE], ids=["pendulum_leg", "passive_middle"])
def test_symbolic_map_agrees_with_pinocchio(path, derived):
    """k0 + D tau_H equals Pinocchio's transmitted wrench <= 1e-10 at 20 random states."""
    robot = symdyn.load(path)
    eqs = derived("pendulum_leg") if path == LEG else symdyn.derive(robot, outputs=["reaction_map"])
    assert eqs.reaction_map.shape == (6, 1 + len(robot.actuated_joints))
    ref = PinocchioReference(robot)
    mine, theirs = [], []
    for q, qd, tau_h in _states(robot, 20, seed=41):
        k0_d = eqs.numeric.reaction_map(q, qd)
        mine.append(k0_d[:, 0] + k0_d[:, 1:] @ tau_h)
        theirs.append(ref.base_wrench(q, qd, tau_h))
    assert _worst(mine, theirs) <= 1e-10


def test_leg_physics(leg_eqs):
    """The seed's spatial pendulum: with tau = 0 on the foot joints, inverse dynamics at the
    accelerations forward dynamics gives is zero there and tau_H at the hip; and the reaction
    force obeys Newton's law for the whole leg, f = m_total (a_com - g), with the centre-of-mass
    acceleration from Pinocchio's centerOfMass (another algorithm than the wrench above)."""
    import pinocchio as pin
    robot = leg_eqs.robot
    assert robot.passive_joints == (0, 1, 2) and robot.actuated_joints == (3, 4, 5)
    num = leg_eqs.numeric
    ref = PinocchioReference(robot)
    total_mass = sum(float(link.mass) for link in robot.links)
    gravity = np.array([0, 0, -9.81])
    for q, qd, tau_h in _states(robot, 5, seed=42):
        tau = np.concatenate([np.zeros(3), tau_h])
        qdd = num.forward_dynamics(q, qd, tau)
        assert np.allclose(num.inverse_dynamics(q, qd, qdd), tau, rtol=0, atol=1e-9)
        pin.centerOfMass(ref.model, ref.data, q, qd, qdd)
        k0_d = num.reaction_map(q, qd)
        force = (k0_d[:, 0] + k0_d[:, 1:] @ tau_h)[3:]
        assert np.allclose(force, total_mass * (ref.data.acom[0] - gravity), rtol=1e-10, atol=1e-9)


def test_compiled_c_agrees_with_pinocchio(leg_eqs, tmp_path):
    """The checked-in C (double) and a float build: NAME_reaction_map(q, qd, k0, D) against
    Pinocchio, <= 1e-10 (double) and <= 1e-4 (float)."""
    robot = leg_eqs.robot
    files = {p.name: p.read_text() for p in (REPO / "generated").glob("pendulum_leg_dynamics.*")}
    assert "void pendulum_leg_reaction_map(const pendulum_leg_real *q, const pendulum_leg_real *qd, " \
           "pendulum_leg_real *k0, pendulum_leg_real *D);" in files["pendulum_leg_dynamics.h"]
    assert "#define PENDULUM_LEG_NA 3" in files["pendulum_leg_dynamics.h"]
    ref = PinocchioReference(robot)
    states = _states(robot, 20, seed=43)
    theirs = [ref.base_wrench(q, qd, tau_h) for q, qd, tau_h in states]
    float_files = generate_c(leg_eqs, ["reaction_map"], "float")
    for precision, built, tolerance in (("double", files, 1e-10), ("float", float_files, 1e-4)):
        (tmp_path / precision).mkdir()
        lib = build_and_load(built, "pendulum_leg", Dimensions(6, actuated=3), 0, precision, str(tmp_path / precision))
        mine = []
        for q, qd, tau_h in states:
            if precision == "float":
                q, qd = q.astype(np.float32), qd.astype(np.float32)
            k0_d = lib.reaction_map(q, qd).astype(float)
            mine.append(k0_d[:, 0] + k0_d[:, 1:] @ tau_h)
        assert _worst(mine, theirs) <= tolerance, precision


def test_casadi_function_matches(leg_eqs):
    """CasADi: reaction_map(q, qd) -> (k0, D), the same numbers as the derivation."""
    from symdyn.emit.casadi_backend import casadi_function
    f = casadi_function(leg_eqs, "reaction_map")
    assert [f.name_out(k) for k in range(2)] == ["k0", "D"]
    q, qd, _ = _states(leg_eqs.robot, 1, seed=44)[0]
    k0, D = (np.array(x) for x in f(q, qd))
    expected = leg_eqs.numeric.reaction_map(q, qd)
    assert np.allclose(k0[:, 0], expected[:, 0], rtol=1e-12, atol=1e-12)
    assert np.allclose(D, expected[:, 1:], rtol=1e-12, atol=1e-12)


def test_cli_defaults_and_verify(tmp_path, capsys):
    """A robot with passive joints gets reaction_map by default, one without does not (but can
    ask for it); verify checks it against Pinocchio."""
    assert main(["generate", robot_path("planar2r"), "--out", str(tmp_path), "--quiet",
                 "--functions", "gravity,reaction_map"]) == 0
    header = (tmp_path / "planar2r_dynamics.h").read_text()
    assert "planar2r_reaction_map(" in header and "#define PLANAR2R_NA 2" in header
    assert "reaction_map" not in symdyn.derive(symdyn.load(robot_path("scara")), outputs=None,
                                               fd_method="ldlt").output_names
    assert main(["verify", MIDDLE, "--functions", "reaction_map", "--states", "10"]) == 0
    assert "reaction_map" in capsys.readouterr().out


def test_actuated_must_be_a_boolean(tmp_path):
    text = (REPO / "tests" / "data" / "passive_middle.yaml").read_text().replace("actuated: false", "actuated: 'no'", 1)
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(SymdynError, match=r"link 2.*actuated.*true or false"):
        symdyn.load(str(path))


def test_every_joint_passive(tmp_path, capsys):
    """A chain with no actuated joint: NAME_NA is 0, D has no column, the C compiles cleanly and
    k0 agrees with Pinocchio."""
    text = (REPO / "tests" / "data" / "passive_middle.yaml").read_text().replace("{joint: revolute, a: 0.05",
                                                                               "{joint: revolute, actuated: false, a: 0.05")
    text = text.replace("{joint: prismatic, a: 0", "{joint: prismatic, actuated: false, a: 0")
    path = tmp_path / "passive_middle.yaml"
    path.write_text(text)
    assert not symdyn.load(str(path)).actuated_joints
    assert main(["verify", str(path), "--functions", "reaction_map", "--states", "10"]) == 0
    assert main(["generate", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    assert "#define PASSIVE_MIDDLE_NA 0" in (tmp_path / "out" / "passive_middle_dynamics.h").read_text()
