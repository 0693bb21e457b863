"""Identification: the regressor tau = Y pi and the base parameters tau = Y_b beta, against
symdyn's inverse dynamics and Pinocchio's computeJointTorqueRegressor; the generated C and CasADi."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import symdyn
from helpers import ROBOTS, PinocchioReference, parameter_values, random_states, robot_path
from symdyn.check.cbuild import build_and_load
from symdyn.derive.regressor import PER_LINK, parameter_names, standard_parameters
from symdyn.emit.cgen import generate_c

_CACHE = {}


def _eqs(name):
    if name not in _CACHE:
        robot = symdyn.load(robot_path(name))
        base = [] if name in SYMBOLIC_GEOMETRY else ["base_regressor"]
        _CACHE[name] = symdyn.derive(robot, outputs=["inverse_dynamics", "regressor", *base])
    return _CACHE[name]


#: bundled robots whose link lengths are symbols (no base parameters: their coefficients need them)
SYMBOLIC_GEOMETRY = ("planar2r",)


def test_base_parameters_need_numeric_geometry():
    from symdyn.model.errors import SymdynError
    with pytest.raises(SymdynError, match=r"base parameters need a numeric geometry, but .*l1"):
        symdyn.derive(symdyn.load(robot_path("planar2r")), outputs=["base_regressor"])


def _pi(robot, values):
    return np.array([float(sp.sympify(v).xreplace(values)) for v in standard_parameters(robot)])


@pytest.mark.parametrize("name", [pytest.param(name, marks=[pytest.mark.slow] if name == "chain12" else [])
                                  for name in ROBOTS])  # chain12: 6 s, with -m slow
def test_regressor_times_parameters_is_inverse_dynamics(name):
    """Y pi = tau <= 1e-12 (relative to the largest torque) and Y_b beta = tau, at 8 states,
    friction and armature included; the base regressor has full column rank equal to the rank of
    the full regressor stacked over 40 states."""
    eqs = _eqs(name)
    robot = eqs.robot
    values = parameter_values(robot)
    p = [values[s] for s in robot.parameters] or None
    pi = _pi(robot, values)
    assert eqs.regressor.shape == (robot.dof, PER_LINK * robot.dof)
    symbols = [sp.Symbol(n, real=True) for n in parameter_names(robot)]
    beta = np.array([float(expr.xreplace(dict(zip(symbols, pi)))) for _, expr in eqs.base_parameters])
    for q, qd, qdd, _ in random_states(robot.dof, 8, seed=51):
        tau = eqs.numeric.inverse_dynamics(q, qd, qdd, p)
        scale = max(np.max(np.abs(tau)), 1.0)
        assert np.max(np.abs(eqs.numeric.regressor(q, qd, qdd, p) @ pi - tau)) <= 1e-12 * scale
        if name not in SYMBOLIC_GEOMETRY:
            assert np.max(np.abs(eqs.numeric.base_regressor(q, qd, qdd, p) @ beta - tau)) <= 1e-10 * scale
    if name in SYMBOLIC_GEOMETRY:
        return
    full = np.vstack([eqs.numeric.regressor(q, qd, qdd, p) for q, qd, qdd, _ in random_states(robot.dof, 40, seed=52)])
    base = np.vstack([eqs.numeric.base_regressor(q, qd, qdd, p) for q, qd, qdd, _ in random_states(robot.dof, 40, seed=52)])
    assert _rank(base) == base.shape[1] == _rank(full)


def _rank(W):
    """Numerical rank of a stacked regressor with its columns scaled to unit norm (columns below
    1e-10 of the largest norm dropped), singular values below 1e-9 of the largest counting as zero."""
    norms = np.linalg.norm(W, axis=0)
    kept = norms > 1e-10 * norms.max()  # columns zero up to rounding are zero
    singular = np.linalg.svd(W[:, kept] / norms[kept], compute_uv=False)
    return int(np.sum(singular > 1e-9 * singular[0]))


def test_base_parameters_hold_for_any_standard_parameters():
    """Y_b (K pi) = Y pi for random (not the file's) standard parameters: the regrouping is a
    property of the geometry, not of the masses."""
    eqs = _eqs("puma560")
    robot = eqs.robot
    symbols = [sp.Symbol(n, real=True) for n in parameter_names(robot)]
    rng = np.random.default_rng(53)
    for q, qd, qdd, _ in random_states(robot.dof, 5, seed=54):
        pi = rng.uniform(-1, 1, len(symbols))
        beta = np.array([float(expr.xreplace(dict(zip(symbols, pi)))) for _, expr in eqs.base_parameters])
        np.testing.assert_allclose(eqs.numeric.base_regressor(q, qd, qdd) @ beta,
                                   eqs.numeric.regressor(q, qd, qdd) @ pi, rtol=1e-10, atol=1e-10)


def _pinocchio_map(robot):
    """Per link, the 10 x 10 matrix T with pi_pinocchio = T pi_symdyn (Pinocchio's parameters are
    about its joint frames; symdyn's about the link frames of the robot file)."""
    import pinocchio as pin
    from symdyn.check.pinocchio_model import build_model
    model, _ = build_model(robot)
    rng = np.random.default_rng(55)
    maps = []
    for k in range(robot.dof):
        ours, theirs = [], []
        for _ in range(10):
            m = rng.uniform(0.5, 2)
            c = rng.uniform(-0.3, 0.3, 3)
            A = rng.uniform(-1, 1, (3, 3))
            inertia_com = A @ A.T + np.eye(3)
            inertia_origin = inertia_com + m * (c @ c * np.eye(3) - np.outer(c, c))
            ours.append([m, *(m * c), inertia_origin[0, 0], inertia_origin[0, 1], inertia_origin[1, 1],
                         inertia_origin[0, 2], inertia_origin[1, 2], inertia_origin[2, 2]])
            placed = _link_to_joint(robot, k).act(pin.Inertia(m, c, inertia_com))
            theirs.append(placed.toDynamicParameters())
        maps.append(np.array(theirs).T @ np.linalg.inv(np.array(ours).T))
    return maps


def _link_to_joint(robot, k):
    """The pose of link k's frame in Pinocchio's joint k frame (as build_model places inertias)."""
    import pinocchio as pin
    from symdyn.check.pinocchio_model import _rx, _rz, _t, numeric_links
    row = numeric_links(robot)[k]
    if robot.convention == "standard":
        body = (_t(z=row["d"]) @ _t(x=row["a"]) @ _rx(row["alpha"]) if row["revolute"]
                else _rz(row["theta"]) @ _t(z=row["d"]) @ _t(x=row["a"]) @ _rx(row["alpha"]))
    else:
        body = np.eye(4)
    return pin.SE3(body[:3, :3].copy(), body[:3, 3].copy())


@pytest.mark.parametrize("name", ["puma560", "stanford", "panda", "pendulum_leg"])
def test_inertial_columns_equal_pinocchio(name):
    """Y's inertial columns, mapped to Pinocchio's frames, equal computeJointTorqueRegressor
    <= 1e-10 (normalized by the largest entry)."""
    import pinocchio as pin
    eqs = _eqs(name)
    robot = eqs.robot
    ref = PinocchioReference(robot)
    maps = _pinocchio_map(robot)
    n = robot.dof
    for q, qd, qdd, _ in random_states(n, 5, seed=56):
        theirs = pin.computeJointTorqueRegressor(ref.model, ref.data, q, qd, qdd)
        mine = eqs.numeric.regressor(q, qd, qdd)
        mapped = np.hstack([theirs[:, 10 * k:10 * k + 10] @ maps[k] for k in range(n)])
        inertial = np.hstack([mine[:, PER_LINK * k:PER_LINK * k + 10] for k in range(n)])
        assert np.max(np.abs(inertial - mapped)) <= 1e-10 * max(1.0, np.max(np.abs(mapped)))


def test_generated_c_and_casadi(tmp_path):
    """NAME_regressor and NAME_base_regressor in C (the header lists both parameter sets) and
    CasADi equal the derivation."""
    from symdyn.emit.casadi_backend import casadi_function
    eqs = _eqs("puma560")
    files = generate_c(eqs, ["regressor", "base_regressor"])
    header = files["puma560_dynamics.h"]
    assert "pi[77] = fc6" in header and "beta[0] = " in header
    assert "void puma560_regressor(const puma560_real *q, const puma560_real *qd, const puma560_real *qdd, puma560_real *Y);" in header
    lib = build_and_load(files, "puma560", eqs.dimensions, 0, "double", str(tmp_path))
    regressor_fn = casadi_function(eqs, "regressor")
    for q, qd, qdd, _ in random_states(6, 5, seed=57):
        expected = eqs.numeric.regressor(q, qd, qdd)
        np.testing.assert_allclose(lib.regressor(q, qd, qdd), expected, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(lib.base_regressor(q, qd, qdd), eqs.numeric.base_regressor(q, qd, qdd),
                                   rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(np.array(regressor_fn(q, qd, qdd)), expected, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("name", ["puma560", "stanford", "panda", "pendulum_leg"])
def test_inverse_dynamics_in_base_parameters_agrees_with_pinocchio(name):
    """--parameters base: inverse dynamics from the base-equivalent parameters (regrouped ones
    zero) agrees with Pinocchio <= 1e-10 at 20 states, friction and armature included."""
    from symdyn.check.pinocchio_model import compare
    robot = symdyn.load(robot_path(name))
    eqs = symdyn.derive(robot, outputs=["inverse_dynamics"], parameters="base")
    assert eqs.parameter_form == "base" and eqs.base_parameters
    errors = compare(eqs.numeric, PinocchioReference(robot), random_states(robot.dof, 20, seed=58), ["inverse_dynamics"])
    assert errors["inverse_dynamics"] <= 1e-10, errors


def test_derive_prints_the_base_parameters(capsys):
    """derive --base-parameters ends with one equation per base parameter, the same expressions
    as the base regressor's; a symbolic geometry is refused in one line."""
    from symdyn.cli import main
    from symdyn.derive.derivation import derive_steps
    from symdyn.emit.printout import render
    eqs = _eqs("scara")
    d = derive_steps(eqs.robot, "newton-euler", "summary", base_parameters=True)
    printed = d.section("base_parameters").quantities
    assert [q.value.lhs.name for q in printed] == [n for n, _ in eqs.base_parameters]
    for q, (_, expr) in zip(printed, eqs.base_parameters):
        assert sp.simplify(q.value.rhs - expr) == 0
    for fmt in ("text", "latex", "markdown"):
        assert "Base parameters (identification)" in render(d, fmt)
    assert main(["derive", robot_path("planar2r"), "--base-parameters"]) == 1
    assert "numeric geometry" in capsys.readouterr().err


def test_verify_checks_the_regressors_as_torques(capsys):
    from symdyn.cli import main
    assert main(["verify", robot_path("scara"), "--functions", "regressor,base_regressor", "--states", "10"]) == 0
    out = capsys.readouterr().out
    assert "checked as torques" in out and out.count(" ok") == 2
