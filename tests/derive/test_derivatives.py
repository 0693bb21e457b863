"""Derivatives of the dynamics (inverse_dynamics_dq, inverse_dynamics_dqd and their combined
inverse_dynamics_derivatives; gravity_derivative; forward_dynamics_dq, forward_dynamics_dqd,
mass_matrix_inverse and their combined forward_dynamics_derivatives) against Pinocchio's
computeRNEADerivatives, computeGeneralizedGravityDerivatives, computeABADerivatives and
computeMinverse, and against central differences of symdyn's own compiled functions (a check that
cannot agree by construction)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from symdyn.model.outputs import Dimensions
import symdyn
from helpers import (REPO, ROBOTS, TOL, fma_hardware, mp_base_configuration, mp_exp6, mp_pose, parameter_values,
                     random_states, robot_path)
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import PinocchioReference, UrdfReference, compare
from symdyn.emit.cgen import generate_c


DERIVATIVES = ("inverse_dynamics_dq", "inverse_dynamics_dqd", "gravity_derivative", "mass_matrix_inverse",
               "forward_dynamics_dq", "forward_dynamics_dqd")
#: the outputs multiplied by M^-1
INVERSE = ("mass_matrix_inverse", "forward_dynamics_dq", "forward_dynamics_dqd")
#: the derivatives compared as they are (dc/dq of a robot without gravity torques is checked apart)
COMPARED = tuple(name for name in DERIVATIVES if name != "gravity_derivative")


#: the 12- and 7-joint chains' derivatives in numpy (21 s and 10 s): with -m slow; the C
#: derivatives of the 7-joint iiwa14 and of puma560 are checked below, these on every other arm
SLOW_DERIVATIVES = ("chain12", "panda")


@pytest.mark.parametrize("name", [pytest.param(name, marks=[pytest.mark.slow] if name in SLOW_DERIVATIVES else [])
                                  for name in ROBOTS])
def test_derivatives_agree_with_pinocchio(name):
    """Every bundled robot (chain12: 12 joints; the symbolic ones with their nominal values), at
    50 states: dtau/dq and dtau/dqd (viscous damping on its diagonal), dc/dq, M^-1 and dqdd/dq,
    dqdd/dqd (Pinocchio's at the torques less friction, and less M^-1 diag(damping) for dqd)."""
    robot = symdyn.load(robot_path(name))
    values = parameter_values(robot)
    eqs = symdyn.derive(robot, outputs=DERIVATIVES)
    p = [values[s] for s in eqs.parameters]
    states = random_states(robot.dof, 50, seed=30)
    reference = PinocchioReference(robot, values)
    errors = compare(eqs.numeric, reference, states, COMPARED, p)
    # M^-1 and what is multiplied by it carry errors of about cond(M) * 1e-16 on both sides
    # (Pinocchio's own, against 50 digits, is 30 times symdyn's on pendulum_leg, cond(M) 4e4):
    # their tolerance grows with cond(M) past 1000
    condition = max(np.linalg.cond(reference.mass_matrix(q) + np.diag(reference.armature)) for q, _, _, _ in states)
    tolerance = {name: TOL * (max(1.0, condition / 1e3) if name in INVERSE else 1.0) for name in COMPARED}
    assert all(errors[name] <= tolerance[name] for name in COMPARED), (errors, condition)
    scale = max(np.max(np.abs(reference.gravity_derivative(q))) for q, _, _, _ in states)
    if scale < 1e-12:  # a SCARA's vertical axes: dc/dq is zero (Pinocchio's rounding noise, 1e-33)
        assert all(np.max(np.abs(eqs.numeric.gravity_derivative(q, p or None))) <= 1e-12 for q, _, _, _ in states)
        return
    errors = compare(eqs.numeric, reference, states, ["gravity_derivative"], p)
    assert errors["gravity_derivative"] <= TOL, errors


def test_derivatives_of_a_urdf_arm_and_a_tree():
    """A URDF arm against Pinocchio's own reading of the file, and the hand-written tree."""
    from helpers import example_robot_data
    from test_trees import _snapped
    path = example_robot_data("ur_description/urdf/ur5_robot.urdf")
    robot = symdyn.load(path, tip="tool0")
    eqs = symdyn.derive(robot, outputs=DERIVATIVES)
    reference = UrdfReference(path, "tool0", quarter_turns=_snapped(robot))  # the same model (angles read as symdyn does)
    errors = compare(eqs.numeric, reference, random_states(robot.dof, 50, seed=32), DERIVATIVES)
    assert all(e <= TOL for e in errors.values()), errors
    tree = symdyn.load(str(REPO / "examples" / "trees" / "torso_two_arms.yaml"))
    eqs = symdyn.derive(tree, outputs=DERIVATIVES)
    errors = compare(eqs.numeric, PinocchioReference(tree), random_states(tree.dof, 50, seed=33), DERIVATIVES)
    assert all(e <= TOL for e in errors.values()), errors


def test_derivatives_against_central_differences_of_the_compiled_functions(tmp_path):
    """The compiled derivatives against central differences (step 1e-6) of the compiled inverse
    dynamics, gravity and forward dynamics on the Stanford arm (a prismatic joint; its friction
    too, away from qd = 0): within 1e-6 relative (M^-1 as dqdd/dtau); the combined functions give
    the single ones' numbers; a floating base is refused in one line."""
    robot = symdyn.load(robot_path("stanford"))
    functions = ("inverse_dynamics", "gravity", "forward_dynamics") + DERIVATIVES
    eqs = symdyn.derive(robot, outputs=functions)
    lib = build_and_load(generate_c(eqs, functions + ("inverse_dynamics_derivatives", "forward_dynamics_derivatives")),
                         robot.name, robot.dof, 0, workdir=str(tmp_path))
    step = 1e-6

    def central(f, x):
        return np.column_stack([(f(x + step * e) - f(x - step * e)) / (2 * step) for e in np.eye(robot.dof)])
    for q, qd, qdd, _ in random_states(robot.dof, 10, seed=34):
        qd = np.where(np.abs(qd) < 1e-3, 0.5, qd)  # Coulomb friction's sign stays put
        for exact, numeric in ((lib.inverse_dynamics_dq(q, qd, qdd), central(lambda x: lib.inverse_dynamics(x, qd, qdd), q)),
                               (lib.inverse_dynamics_dqd(q, qd, qdd), central(lambda x: lib.inverse_dynamics(q, x, qdd), qd)),
                               (lib.gravity_derivative(q), central(lib.gravity, q))):
            assert np.max(np.abs(exact - numeric)) <= 1e-6 * max(1.0, np.max(np.abs(exact))), (exact, numeric)
        together = lib.inverse_dynamics_derivatives(q, qd, qdd)
        np.testing.assert_allclose(together[0], lib.inverse_dynamics_dq(q, qd, qdd), rtol=0, atol=1e-12)
        np.testing.assert_allclose(together[1], lib.inverse_dynamics_dqd(q, qd, qdd), rtol=0, atol=1e-12)
    for q, qd, _, tau in random_states(robot.dof, 10, seed=35):
        qd = np.where(np.abs(qd) < 1e-3, 0.5, qd)
        for exact, numeric in ((lib.forward_dynamics_dq(q, qd, tau), central(lambda x: lib.forward_dynamics(x, qd, tau), q)),
                               (lib.forward_dynamics_dqd(q, qd, tau), central(lambda x: lib.forward_dynamics(q, x, tau), qd)),
                               (lib.mass_matrix_inverse(q), central(lambda x: lib.forward_dynamics(q, qd, x), tau))):
            assert np.max(np.abs(exact - numeric)) <= 1e-6 * max(1.0, np.max(np.abs(exact))), (exact, numeric)
        status, together = lib.with_status("forward_dynamics_derivatives", q, qd, tau)
        assert status == 0
        for value, single in zip(together, (lib.forward_dynamics_dq(q, qd, tau), lib.forward_dynamics_dqd(q, qd, tau),
                                            lib.mass_matrix_inverse(q))):
            np.testing.assert_allclose(value, single, rtol=0, atol=1e-12)


@pytest.mark.parametrize("path, by_columns", [pytest.param(str(REPO / "examples" / "trees" / "space_robot.yaml"), True,
                                                           marks=pytest.mark.slow),  # (18 s of a CPU)
                                              (robot_path("puma560"), False)])
def test_forward_dynamics_derivatives_not_finite_write_nothing(path, by_columns, tmp_path):
    """The forward-dynamics derivatives' final test of finite results (the product -M^-1 dtau/dx
    by columns on the satellite's tree, by rows on the Puma), double and float: torques from
    ordinary up past where the accelerations overflow; a status 0 writes finite numbers, any
    other status writes nothing, and on the satellite the derivatives overflow at torques where
    forward dynamics' accelerations are still finite (status 2 from that test itself)."""
    from symdyn.check.states import random_configuration
    from symdyn.emit.cplan import product_columns
    robot = symdyn.load(path)
    parts = ("forward_dynamics", "forward_dynamics_dq", "forward_dynamics_dqd", "mass_matrix_inverse")
    eqs = symdyn.derive(robot, outputs=parts)
    assert (product_columns(eqs, parts) is not None) == by_columns
    rng = np.random.default_rng(41)
    q, qd = random_configuration(robot, rng), rng.uniform(-1, 1, robot.nv)
    for precision, top in (("double", 1e306), ("float", 4e35)):
        workdir = tmp_path / precision
        workdir.mkdir()
        lib = build_and_load(generate_c(eqs, parts, precision), robot.name, Dimensions.of(robot), 0, precision,
                             workdir=str(workdir))
        caught = 0
        for scale in np.concatenate([[1.0, 1e-300 * top], top * np.linspace(1, 20, 191)]):
            tau = np.full(robot.nv, scale) * np.linspace(1, 0.5, robot.nv)
            fd_status, _ = lib.forward_dynamics_checked(q, qd, tau)
            status, outputs = lib.with_status("forward_dynamics_derivatives", q, qd, tau)
            if status == 0:
                assert all(np.all(np.isfinite(o)) for o in outputs), (precision, scale)
            else:
                assert status == 2 and all(np.all(np.isnan(o)) for o in outputs), (precision, scale, status)
            caught += fd_status == 0 and status == 2
        assert caught or not by_columns, precision


FLOATING_DERIVATIVES = ("inverse_dynamics_dq", "inverse_dynamics_dqd", "gravity_derivative", "mass_matrix_inverse",
                        "forward_dynamics_dq", "forward_dynamics_dqd")


@pytest.mark.parametrize("name", [pytest.param(name, marks=pytest.mark.slow) for name in ("space_robot", "solo12", "anymal")])
# (slow: the quick suite checks a floating base's derivatives by the 50-digit differences below and the fuzzer's cases)
def test_floating_base_derivatives_in_the_tangent_space(name, tmp_path):
    """A floating base's derivatives (nv x nv, by q along q (+) dv, Pinocchio's ``integrate``: the
    base moved and turned in its own frame) against computeRNEADerivatives,
    computeGeneralizedGravityDerivatives, computeABADerivatives and computeMinverse with its
    free-flyer, numpy and C (the C at a quaternion of another scale), and the C's dtau/dq and
    dc/dq against central differences of its own inverse dynamics along pinocchio.integrate
    (the space robot has no gravity: the legged robots' dc/dq turns gravity with the base)."""
    import pinocchio as pin
    from helpers import example_robot_data
    from symdyn.check.pinocchio_model import build_model, normalized_error
    from symdyn.check.states import random_configuration
    if name in ("solo12", "anymal"):
        path = {"solo12": "solo_description/robots/solo12.urdf", "anymal": "anymal_b_simple_description/robots/anymal.urdf"}
        robot = symdyn.load(example_robot_data(path[name]), floating_base=True)
    else:
        robot = symdyn.load(str(REPO / "examples" / "trees" / "space_robot.yaml"))
    assert robot.floating
    eqs = symdyn.derive(robot, outputs=list(FLOATING_DERIVATIVES) + ["inverse_dynamics", "gravity"])
    reference = PinocchioReference(robot)
    rng = np.random.default_rng(37)
    states = [(random_configuration(robot, rng), *(rng.uniform(-2, 2, robot.nv) for _ in range(2))) for _ in range(20)]
    lib = build_and_load(generate_c(eqs, list(FLOATING_DERIVATIVES) + ["inverse_dynamics", "gravity"]), robot.name,
                         Dimensions.of(robot), 0, workdir=str(tmp_path))
    for function in FLOATING_DERIVATIVES:
        one = function in ("gravity_derivative", "mass_matrix_inverse")
        mine = [getattr(eqs.numeric, function)(*((q,) if one else (q, v, a))) for q, v, a in states]
        theirs = [getattr(reference, function)(*((q,) if one else (q, v, a))) for q, v, a in states]
        scaled = [np.concatenate([q[:3], 3.7 * q[3:7], q[7:]]) for q, _, _ in states]
        compiled = [getattr(lib, function)(*((s,) if one else (s, v, a))) for s, (_, v, a) in zip(scaled, states)]
        assert normalized_error(mine, theirs) <= TOL, function
        assert normalized_error(compiled, mine) <= 1e-12, function
    if name != "space_robot":
        assert max(np.max(np.abs(eqs.numeric.gravity_derivative(q))) for q, _, _ in states) > 0.1  # (gravity turns)
    model, _ = build_model(robot)
    h = 1e-6
    for q, v, a in states[:4]:
        columns = [(lib.inverse_dynamics(pin.integrate(model, q, h * e), v, a)
                    - lib.inverse_dynamics(pin.integrate(model, q, -h * e), v, a)) / (2 * h) for e in np.eye(robot.nv)]
        np.testing.assert_allclose(np.array(columns).T, lib.inverse_dynamics_dq(q, v, a), rtol=0, atol=1e-6)
        columns = [(lib.gravity(pin.integrate(model, q, h * e)) - lib.gravity(pin.integrate(model, q, -h * e))) / (2 * h)
                   for e in np.eye(robot.nv)]
        np.testing.assert_allclose(np.array(columns).T, lib.gravity_derivative(q), rtol=0, atol=1e-6)


def test_floating_base_mass_matrix_inverse(tmp_path):
    """A floating base's M^-1 (nv x nv, the L^T D L that follows the tree, the base's block
    first) against Pinocchio's computeMinverse with its free-flyer at 50 states, numpy and C."""
    from symdyn.check.states import random_configuration
    robot = symdyn.load(str(REPO / "examples" / "trees" / "space_robot.yaml"))
    eqs = symdyn.derive(robot, outputs=["mass_matrix_inverse"])
    rng = np.random.default_rng(36)
    states = [[random_configuration(robot, rng)] for _ in range(50)]
    reference = PinocchioReference(robot)
    lib = build_and_load(generate_c(eqs, ["mass_matrix_inverse"]), robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
    mine = [eqs.numeric.mass_matrix_inverse(q) for q, in states]
    theirs = [reference.mass_matrix_inverse(q) for q, in states]
    compiled = [lib.mass_matrix_inverse(q) for q, in states]
    from symdyn.check.pinocchio_model import normalized_error
    assert normalized_error(mine, theirs) <= TOL and normalized_error(compiled, mine) <= 1e-13


def test_inverse_and_forward_derivatives_statuses(tmp_path):
    """The planar arm with runtime parameters: M^-1 times M is the identity (status 0); a
    weightless second link (m2 = I2 = 0) makes M singular at every q: status 1 and nothing
    written; a NaN or infinite input: status 2 and nothing written."""
    robot = symdyn.load(robot_path("planar2r"))
    eqs = symdyn.derive(robot, outputs=("mass_matrix",) + INVERSE)
    lib = build_and_load(generate_c(eqs, ("mass_matrix",) + INVERSE + ("forward_dynamics_derivatives",)), robot.name,
                         robot.dof, len(robot.parameters), workdir=str(tmp_path))
    values = {"g": 9.81, "m1": 2.0, "lc1": 0.3, "I1": 0.05, "l1": 0.6, "m2": 1.5, "lc2": 0.25, "I2": 0.03}
    p = np.array([values[s.name] for s in eqs.parameters])
    q, qd, tau = np.array([0.3, -1.1]), np.array([0.4, 0.7]), np.array([1.0, -2.0])
    status, (Minv,) = lib.with_status("mass_matrix_inverse", q, p=p)
    assert status == 0
    np.testing.assert_allclose(Minv @ lib.mass_matrix(q, p), np.eye(2), rtol=0, atol=1e-14)
    weightless = np.where([s.name in ("m2", "I2") for s in eqs.parameters], 0.0, p)
    for name, args in (("mass_matrix_inverse", (q,)), ("forward_dynamics_derivatives", (q, qd, tau))):
        status, outputs = lib.with_status(name, *args, p=weightless, fill=7.0)
        assert status == 1 and all(np.all(out == 7.0) for out in outputs), name
        for bad in (np.nan, np.inf):
            status, outputs = lib.with_status(name, *[np.where(np.arange(2) == 1, bad, a) for a in args], p=p, fill=7.0)
            assert status == 2 and all(np.all(out == 7.0) for out in outputs), (name, bad)


def test_ilqr_example_converges(tmp_path):
    """examples/ilqr: iLQR with the generated forward dynamics and its derivatives only moves
    puma560 from rest to within 1e-3 rad of its target pose and 1e-2 rad/s of rest; the cost
    falls by more than 1e4."""
    import subprocess
    from symdyn.check.cbuild import find_compiler
    from symdyn.cli import main
    out = tmp_path / "gen"
    assert main(["generate", robot_path("puma560"), "--out", str(out), "--quiet",
                 "--functions", "forward_dynamics,forward_dynamics_derivatives,gravity"]) == 0
    program = tmp_path / "ilqr"
    built = subprocess.run([find_compiler(), "-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic", "-Werror",
                            "-I", str(out), str(REPO / "examples" / "ilqr" / "ilqr_puma560.c"),
                            str(out / "puma560_dynamics.c"), "-lm", "-o", str(program)], capture_output=True, text=True)
    assert built.returncode == 0, built.stderr[:2000]
    ran = subprocess.run([str(program)], capture_output=True, text=True, timeout=60)
    assert ran.returncode == 0, ran.stdout[-2000:] + ran.stderr
    costs = [float(line.split("cost ")[1].split()[0]) for line in ran.stdout.splitlines() if "cost " in line]
    assert "converged" in ran.stdout.splitlines()[-1] and costs[-1] < 1e-4 * costs[0], ran.stdout


@pytest.mark.parametrize("name, budget", [pytest.param("iiwa14", None, marks=pytest.mark.slow), ("puma560", 0)])
def test_tangent_loops_in_c_agree_with_pinocchio(name, budget, tmp_path, monkeypatch):
    """The derivatives written as vector tangents (one loop per statement, the C form of robots
    past symdyn.derive.equations.TANGENT_LOOPS_FROM_OPS): iiwa14 on its own (-m slow: 19 s),
    puma560 (Coulomb friction, viscous damping on dtau/dqd's diagonal) with the budget at 0; the
    compiled single and combined functions against Pinocchio at 20 states (the same outputs in
    numpy: 50 states above), and each other; the fused multiply-adds' builds."""
    from symdyn.derive import equations
    if budget is not None:
        monkeypatch.setattr(equations, "TANGENT_LOOPS_FROM_OPS", budget)
    robot = symdyn.load(robot_path(name))
    functions = ("inverse_dynamics_dq", "inverse_dynamics_dqd", "mass_matrix_inverse", "forward_dynamics_dq",
                 "forward_dynamics_dqd")
    eqs = symdyn.derive(robot, outputs=functions)
    assert [parts for parts, _ in eqs.tangent_loops] == [("inverse_dynamics_dq", "inverse_dynamics_dqd"),
                                                         ("forward_dynamics_dq", "forward_dynamics_dqd")]
    files = generate_c(eqs, functions + ("inverse_dynamics_derivatives", "forward_dynamics_derivatives"))
    assert files[f"{robot.name}_dynamics.c"].count("dv_t[") > 100  # the loops, not the straight-line form
    lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
    states = random_states(robot.dof, 20, seed=36)
    errors = compare(lib, PinocchioReference(robot), states, functions)
    assert all(e <= TOL for e in errors.values()), errors
    for q, qd, qdd, tau in states[:5]:
        together = lib.inverse_dynamics_derivatives(q, qd, qdd)
        np.testing.assert_allclose(together[0], lib.inverse_dynamics_dq(q, qd, qdd), rtol=0, atol=1e-12)
        np.testing.assert_allclose(together[1], lib.inverse_dynamics_dqd(q, qd, qdd), rtol=0, atol=1e-12)
        status, together = lib.with_status("forward_dynamics_derivatives", q, qd, tau)
        assert status == 0
        for value, single in zip(together, (lib.forward_dynamics_dq(q, qd, tau), lib.forward_dynamics_dqd(q, qd, tau))):
            np.testing.assert_allclose(value, single, rtol=0, atol=1e-10 * max(1.0, np.max(np.abs(single))))
    _check_fused_multiply_adds(files, robot, lib, states[:5], functions, tmp_path)


def _check_fused_multiply_adds(files, robot, lib, states, functions, tmp_path):
    """The forward-dynamics derivatives' PREFIX_FMA: built for FMA hardware (-mfma: fma()), every
    function agrees with Pinocchio, the inverse-dynamics derivatives (plain sums) are the plain
    build's (-O2 without -mfma: a*b + c) bit for bit and the forward-dynamics derivatives differ
    from it by rounding only, somewhere.  (With the macro as a*b + c the sums are the plain ones:
    tests/emit/test_cgen.py.)"""
    if not fma_hardware():
        pytest.skip("no FMA hardware (x86-64 with fma) to run the fused build on")
    fused = build_and_load(files, robot.name, Dimensions.of(robot), 0, workdir=str(_fresh(tmp_path / "fma")),
                           extra_flags=["-mfma", "-fno-tree-slp-vectorize"])
    assert all(e <= TOL for e in compare(fused, PinocchioReference(robot), states, functions).values())
    differs = False
    for q, qd, qdd, tau in states:
        for name in ("inverse_dynamics_dq", "inverse_dynamics_dqd"):
            np.testing.assert_array_equal(getattr(fused, name)(q, qd, qdd), getattr(lib, name)(q, qd, qdd))
        status, together = fused.with_status("forward_dynamics_derivatives", q, qd, tau)
        plain_status, plain_together = lib.with_status("forward_dynamics_derivatives", q, qd, tau)
        assert status == plain_status == 0
        for value, reference in zip(together, plain_together):
            np.testing.assert_allclose(value, reference, rtol=0, atol=1e-10 * max(1.0, np.max(np.abs(reference))))
            differs |= not np.array_equal(value, reference)
    assert differs  # the fused build does fuse


def _fresh(path):
    path.mkdir()
    return path


def test_vector_tangents_are_the_written_out_derivatives(monkeypatch):
    """The vector tangents (symdyn.derive.tangents) of the hand-written tree (two arms on a torso)
    and of the planar arm derived by Lagrange-Euler, evaluated step by step in floating point,
    against the straight-line derivatives they stand for (budget 0: every robot gets them): dtau/dq
    and dtau/dqd, and the forward-dynamics derivatives' dtau at the accelerations of forward
    dynamics."""
    from symdyn.derive import equations
    monkeypatch.setattr(equations, "TANGENT_LOOPS_FROM_OPS", 0)
    rng = np.random.default_rng(37)
    for path, method in ((str(REPO / "examples" / "trees" / "torso_two_arms.yaml"), "newton-euler"),
                         (robot_path("planar2r"), "lagrange-euler")):
        robot = symdyn.load(path)
        eqs = symdyn.derive(robot, method=method, outputs=("inverse_dynamics_dq", "inverse_dynamics_dqd",
                                                           "forward_dynamics_dq", "forward_dynamics_dqd"))
        values = {s: float(rng.uniform(-1, 1)) for s in eqs.q + eqs.qd + eqs.qdd + eqs.tau}
        values.update({s: float(v) for s, v in parameter_values(robot).items()})
        for sym, rhs in eqs.program.assignments:
            values[sym] = float(rhs.xreplace(values))
        number = lambda e: float(sp.sympify(e).xreplace(values))  # noqa: E731
        assert len(eqs.tangent_loops) == 2
        for parts, tangents in eqs.tangent_loops:
            rows: dict[int, np.ndarray] = {}
            for step in tangents.steps:
                row = np.zeros(tangents.directions)
                for source, coefficient in step.terms:
                    row += number(coefficient) * rows[source]
                for direction, value in step.direct:
                    row[direction] += number(value)
                rows[step.target] = row
            for group, part in enumerate(parts):
                got = np.array([rows[r] if r is not None else np.zeros(tangents.directions) for r in tangents.rows[group]])
                written = eqs.output(part) if part.startswith("inverse") else eqs.inverse_products[1 + group]
                expected = np.array(sp.Matrix(written).xreplace(values), dtype=float)
                np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12 * max(1.0, np.max(np.abs(expected))))


def test_floating_base_derivatives_against_50_digit_differences(tmp_path):
    """dtau/dq and dqdd/dq of a floating robot under gravity (the satellite turned upright, so
    that turning the base turns gravity in its frame), numpy and C, against central differences
    of its own inverse and forward dynamics evaluated in 50 digits along q (+) h e_j: the base
    moved by SE(3)'s exponential (mpmath's matrix exponential of the twist), the joints by
    addition, h = 1e-20 (truncation ~1e-40, rounding ~1e-30): the derivatives' tangent-space
    chain rule, not only their agreement with Pinocchio, to 1e-12 of their size."""
    import dataclasses
    import mpmath
    from symdyn.check.states import random_configuration
    from symdyn.derive.numeric import compile_function
    robot = symdyn.load(str(REPO / "examples" / "trees" / "space_robot.yaml"))
    robot = dataclasses.replace(robot, gravity=(0.3, -1.2, -9.81))
    names = ["inverse_dynamics_dq", "forward_dynamics_dq", "inverse_dynamics", "forward_dynamics"]
    eqs = symdyn.derive(robot, outputs=names)
    precise = {name: compile_function([eqs.q, eqs.qd, eqs.qdd if name == "inverse_dynamics" else eqs.tau],
                                      eqs.program, eqs.output(name), name, digits=50)
               for name in ("inverse_dynamics", "forward_dynamics")}
    lib = build_and_load(generate_c(eqs, names), robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
    rng = np.random.default_rng(38)

    def moved(q, step):
        """q (+) step in 50 digits (step: nv mpf): the base by SE(3)'s exponential in its frame."""
        base = mp_base_configuration(mp_pose(q) * mp_exp6(step[:6]))
        return base + [mpmath.mpf(float(q[7 + i])) + step[6 + i] for i in range(robot.dof)]

    with mpmath.workdps(50):
        h = mpmath.mpf("1e-20")
        for _ in range(2):
            q = random_configuration(robot, rng)
            qd, other = rng.uniform(-2, 2, robot.nv), rng.uniform(-2, 2, robot.nv)
            for name, derivative in (("inverse_dynamics", "inverse_dynamics_dq"),
                                     ("forward_dynamics", "forward_dynamics_dq")):
                columns = []
                for j in range(robot.nv):
                    step = [h if k == j else mpmath.mpf(0) for k in range(robot.nv)]
                    plus = precise[name](moved(q, step), list(qd), list(other))
                    minus = precise[name](moved(q, [-s for s in step]), list(qd), list(other))
                    columns.append([float((a[0] - b[0]) / (2 * h)) for a, b in zip(plus, minus)])
                reference = np.array(columns).T
                scale = max(1.0, np.max(np.abs(reference)))
                for value in (getattr(eqs.numeric, derivative)(q, qd, other), getattr(lib, derivative)(q, qd, other)):
                    assert np.max(np.abs(value - reference)) <= 1e-12 * scale, (derivative, np.max(np.abs(value - reference)))


@pytest.mark.slow
def test_solo12_ddp_example_converges_as_on_pinocchio(tmp_path):
    """examples/ilqr/solo12_ddp.py: iLQR of Solo-12 on its floating base (a squat in the air)
    with the generated C only converges (the joints within 1e-3 rad of the crouch and the
    stance, their rates within 1e-2 rad/s) to the same cost as the same solver linked against
    Pinocchio (1e-6 of it)."""
    import subprocess
    import sys
    done = subprocess.run([sys.executable, str(REPO / "examples" / "ilqr" / "solo12_ddp.py"), "--out", str(tmp_path),
                           "--flags=-O1", "--runs", "1"],
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    finals = [line for line in done.stdout.splitlines() if line.startswith("final: cost")]
    assert len(finals) == 2 and all(line.endswith(": converged") for line in finals), done.stdout
    assert "the same" in done.stdout.splitlines()[-1]
