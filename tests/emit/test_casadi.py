"""CasADi functions: agreement with Pinocchio, derivatives, saved files, and a real optimal
control problem solved with the ipopt that the casadi wheel ships."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import casadi as ca
import numpy as np
import pytest

import symdyn
from helpers import (ROBOTS, TOL, PinocchioReference, normalized_error, parameter_values,
                     random_states, robot_path)
from symdyn.emit.casadi_backend import casadi_function, combined_function, to_casadi
from symdyn.cli import main
from symdyn.derive.equations import OUTPUT_INPUTS

ARGS = OUTPUT_INPUTS

_FUNCTIONS = {}


def functions_of(derived, name):
    if name not in _FUNCTIONS:
        eqs = derived(name)
        _FUNCTIONS[name] = (eqs, {f: casadi_function(eqs, f) for f in symdyn.OUTPUTS})
    return _FUNCTIONS[name]


def values_of(robot):
    values = parameter_values(robot)
    return values, [values[s] for s in robot.parameters]


@pytest.mark.parametrize("name", ROBOTS)
def test_casadi_agrees_with_pinocchio(derived, name):
    eqs, fns = functions_of(derived, name)
    values, p = values_of(eqs.robot)
    ref = PinocchioReference(eqs.robot, values)
    states = random_states(eqs.n, 30, seed=11)
    for fname, f in fns.items():
        assert f.name_out(0) == {"inverse_dynamics": "tau", "mass_matrix": "D", "coriolis": "h",
                                 "coriolis_matrix": "C", "gravity": "c", "forward_dynamics": "qdd",
                                 "forward_kinematics": "T", "jacobian": "J", "jacobian_dot_qd": "a"}[fname]
        assert [f.name_in(k) for k in range(f.n_in())] == list(ARGS[fname]) + (["p"] if p else [])
        mine, theirs = [], []
        for q, qd, qdd, tau in states:
            given = {"q": q, "qd": qd, "qdd": qdd, "tau": tau}
            args = [given[a] for a in ARGS[fname]]
            out = np.array(f(*(args + ([p] if p else []))), dtype=float)
            mine.append(out.reshape(-1) if out.shape[1] == 1 else out)
            theirs.append(getattr(ref, fname)(*args))
        err = normalized_error(mine, theirs)
        assert err <= TOL, f"{name} {fname}: normalized error {err:.2e}"


@pytest.mark.parametrize("name", ROBOTS)
def test_derivatives_agree_with_pinocchio_rnea_derivatives(derived, name):
    """CasADi's automatic derivatives of tau(q, qd, qdd) against computeRNEADerivatives (which
    include the armature in dtau/dqdd; viscous friction adds diag(damping) to dtau/dqd)."""
    import pinocchio as pin
    eqs, fns = functions_of(derived, name)
    values, p = values_of(eqs.robot)
    ref = PinocchioReference(eqs.robot, values)
    n = eqs.n
    q, qd, qdd = ca.SX.sym("q", n), ca.SX.sym("qd", n), ca.SX.sym("qdd", n)
    tau = fns["inverse_dynamics"](q, qd, qdd, *([p] if p else []))
    jac = ca.Function("jacobians", [q, qd, qdd], [ca.jacobian(tau, q), ca.jacobian(tau, qd), ca.jacobian(tau, qdd)])
    mine, theirs = [[], [], []], [[], [], []]
    for qv, qdv, qddv, _ in random_states(n, 10, seed=5):
        refs = pin.computeRNEADerivatives(ref.model, ref.data, qv, qdv, qddv)
        refs = [np.array(refs[0]), np.array(refs[1]) + np.diag(ref.damping), np.array(refs[2])]
        refs[2] = np.triu(refs[2]) + np.triu(refs[2], 1).T
        for k, value in enumerate(jac(qv, qdv, qddv)):
            mine[k].append(np.array(value))
            theirs[k].append(refs[k])
    for k, label in enumerate(("dtau/dq", "dtau/dqd", "dtau/dqdd")):
        err = normalized_error(mine[k], theirs[k])
        assert err <= 1e-8, f"{name} {label}: normalized error {err:.2e}"


@pytest.mark.parametrize("name", ["planar2r", "stanford", "chain12"])
def test_derivatives_match_central_differences(derived, name):
    """Jacobians of every vector function against central differences (step 1e-6), away from
    qd = 0 where Coulomb friction's sign would jump."""
    eqs, fns = functions_of(derived, name)
    _, p = values_of(eqs.robot)
    n = eqs.n
    rng = np.random.default_rng(3)
    step = 1e-6
    for fname in ("inverse_dynamics", "forward_dynamics", "coriolis", "gravity"):
        f = fns[fname]
        symbols = [ca.SX.sym(a, n) for a in ARGS[fname]]
        out = f(*(symbols + ([p] if p else [])))
        jac = ca.Function("jacobians", symbols, [ca.jacobian(out, s) for s in symbols])
        point = [rng.uniform(0.3, 1.0, n) * rng.choice([-1, 1], n) for _ in symbols]
        analytic = jac(*point)
        analytic = [analytic] if len(symbols) == 1 else analytic
        for k in range(len(symbols)):
            numeric = np.zeros((n, n))
            for j in range(n):
                plus = [x.copy() for x in point]
                minus = [x.copy() for x in point]
                plus[k][j] += step
                minus[k][j] -= step
                numeric[:, j] = (np.array(f(*(plus + ([p] if p else [])))).ravel()
                                 - np.array(f(*(minus + ([p] if p else [])))).ravel()) / (2 * step)
            scale = max(1.0, float(np.abs(numeric).max()))
            np.testing.assert_allclose(np.array(analytic[k]), numeric, rtol=0, atol=1e-6 * scale,
                                       err_msg=f"{name} {fname} d/d{ARGS[fname][k]}")


def test_combined_function_matches_single_functions(derived):
    eqs, fns = functions_of(derived, "puma560")
    combined = combined_function(eqs)
    assert [combined.name_in(k) for k in range(combined.n_in())] == ["q", "qd", "qdd", "tau"]
    q, qd, qdd, tau = random_states(6, 1, seed=2)[0]
    out = combined(q=q, qd=qd, qdd=qdd, tau=tau)
    given = {"q": q, "qd": qd, "qdd": qdd, "tau": tau}
    for fname, f in fns.items():
        np.testing.assert_array_equal(np.array(out[fname]), np.array(f(*[given[a] for a in ARGS[fname]])))


def test_to_casadi_from_a_path_and_a_subset():
    fns = to_casadi(robot_path("scara"), functions=["gravity", "forward_dynamics"])
    assert list(fns) == ["gravity", "forward_dynamics"]
    assert fns["gravity"].name() == "gravity"
    with pytest.raises(symdyn.SymdynError):
        to_casadi(robot_path("scara"), functions=["mass"])


LOADER = r"""
import importlib.abc, json, sys
class Block(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name == "symdyn" or name.startswith("symdyn."):
            raise ImportError("symdyn is blocked in this process")
sys.meta_path.insert(0, Block())
try:
    import symdyn  # noqa: F401
    raise SystemExit("symdyn was importable")
except ImportError:
    pass
import casadi
folder, name, q, qd, qdd, tau = json.loads(sys.argv[1])
single = casadi.Function.load(f"{folder}/{name}_inverse_dynamics.casadi")
both = casadi.Function.load(f"{folder}/{name}_dynamics.casadi")
out = both(q=q, qd=qd, qdd=qdd, tau=tau)
print(json.dumps({"tau": single(q, qd, qdd).full().ravel().tolist(),
                  "D": out["mass_matrix"].full().tolist(),
                  "qdd": out["forward_dynamics"].full().ravel().tolist(),
                  "names": [single.name_in(k) for k in range(single.n_in())]}))
"""


def test_saved_files_load_in_a_process_without_symdyn(tmp_path, capsys):
    out = tmp_path / "out"
    path = robot_path("puma560")
    assert main(["generate", path, "--target", "casadi", "--out", str(out), "--quiet"]) == 0
    names = sorted(os.listdir(out))
    assert "puma560_dynamics.casadi" in names and "puma560_casadi.txt" in names
    assert "puma560_inverse_dynamics.casadi" in names
    readme = (out / "puma560_casadi.txt").read_text()
    assert "DO NOT EDIT" in readme and symdyn.__version__ in readme and "puma560.yaml" in readme
    q, qd, qdd, tau = (v.tolist() for v in random_states(6, 1, seed=4)[0])
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    result = subprocess.run([sys.executable, "-I", "-c", LOADER, json.dumps([str(out), "puma560", q, qd, qdd, tau])],
                            capture_output=True, text=True, cwd=str(tmp_path), env=env, timeout=120)
    assert result.returncode == 0, result.stderr
    got = json.loads(result.stdout)
    assert got["names"] == ["q", "qd", "qdd"]
    robot = symdyn.load(path)
    ref = PinocchioReference(robot)
    assert normalized_error([got["tau"]], [ref.inverse_dynamics(*map(np.array, (q, qd, qdd)))]) <= TOL
    assert normalized_error([got["D"]], [ref.mass_matrix(np.array(q))]) <= TOL
    assert normalized_error([got["qdd"]], [ref.forward_dynamics(*map(np.array, (q, qd, tau)))]) <= TOL


def test_casadi_target_is_byte_identical_and_atomic(tmp_path, capsys):
    first, second = tmp_path / "a", tmp_path / "b"
    path = robot_path("planar2r")
    for out in (first, second):
        assert main(["generate", path, "--target", "casadi-c", "--out", str(out), "--quiet", "--no-cache"]) == 0
    names = sorted(os.listdir(first))
    assert names == sorted(os.listdir(second))
    assert {"planar2r_casadi.c", "planar2r_casadi.h", "planar2r_dynamics.casadi"} <= set(names)
    for n in names:
        assert (first / n).read_bytes() == (second / n).read_bytes(), n
    # a C-only option with the casadi target: one clear line, nothing written
    assert main(["generate", path, "--target", "casadi", "--precision", "float", "--out", str(tmp_path / "c")]) == 1
    assert "c target only" in capsys.readouterr().err
    assert not (tmp_path / "c").exists()


def _rk4(f, x, u, dt):
    k1 = f(x, u)
    k2 = f(x + dt / 2 * k1, u)
    k3 = f(x + dt / 2 * k2, u)
    k4 = f(x + dt * k3, u)
    return x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def test_minimum_effort_move_solves_and_replays_through_pinocchio(derived):
    """Point-to-point move of planar2r in 1 s, rest to rest, minimizing the integral of tau^2,
    by multiple shooting (RK4 on symdyn's forward dynamics) in casadi.Opti with ipopt.  The
    optimal torques, replayed through Pinocchio's aba with the same integrator, reproduce the
    planned states."""
    import pinocchio as pin
    eqs, fns = functions_of(derived, "planar2r")
    values, p = values_of(eqs.robot)
    forward = fns["forward_dynamics"]
    steps, duration = 40, 1.0
    dt = duration / steps
    start, goal = np.array([0.0, 0.0]), np.array([1.2, -0.8])

    opti = ca.Opti()
    X = opti.variable(4, steps + 1)
    U = opti.variable(2, steps)

    def xdot(x, u):
        return ca.vertcat(x[2:], forward(x[:2], x[2:], u, p))

    for k in range(steps):
        opti.subject_to(X[:, k + 1] == _rk4(xdot, X[:, k], U[:, k], dt))
    opti.subject_to(X[:, 0] == np.r_[start, 0, 0])
    opti.subject_to(X[:, -1] == np.r_[goal, 0, 0])
    opti.minimize(dt * ca.sumsqr(U))
    guess = np.linspace(start, goal, steps + 1).T
    opti.set_initial(X[:2, :], guess)
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": 1e-10})
    solution = opti.solve()
    assert solution.stats()["success"]
    planned = np.array(solution.value(X))
    torques = np.array(solution.value(U))
    assert np.abs(torques).max() > 0.1  # a real move, not a trivial solution

    ref = PinocchioReference(eqs.robot, values)

    def xdot_pin(x, u):
        return np.r_[x[2:], pin.aba(ref.model, ref.data, x[:2], x[2:], u)]

    x = planned[:, 0].copy()
    worst = 0.0
    for k in range(steps):
        x = _rk4(xdot_pin, x, torques[:, k], dt)
        worst = max(worst, float(np.abs(x - planned[:, k + 1]).max()))
    print(f"replay: worst state error {worst:.2e}, max |tau| {np.abs(torques).max():.3f}")
    assert worst <= 1e-7, f"replayed trajectory leaves the plan by {worst:.2e}"
    np.testing.assert_allclose(x[:2], goal, atol=1e-7)
