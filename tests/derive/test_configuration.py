"""The configuration-space functions (integrate, difference and their Jacobians): against
Pinocchio's integrate / difference / dIntegrate / dDifference on whole legged robots (numpy, C and
CasADi, at quaternions of any scale), and against an independent 50-digit reference (SE(3)'s
exponential and logarithm as mpmath's matrix exp and log, the Jacobians by central differences)
at the angles where closed forms lose accuracy: near 0 (down to 1e-8 rad and exactly 0), on both
sides of the series' threshold, near and past pi."""

import mpmath
import numpy as np
import pytest

import symdyn
from helpers import REPO, example_robot_data, mp_exp6, mp_pose
from symdyn.check.cbuild import build_and_load
from symdyn.check.states import random_configuration
from symdyn.derive.configuration import SERIES_BELOW
from symdyn.emit.casadi_backend import casadi_function
from symdyn.emit.cgen import generate_c
from symdyn.model.outputs import CONFIGURATION_OUTPUTS, OUTPUT_INPUTS, Dimensions

NAMES = list(CONFIGURATION_OUTPUTS)
#: quaternion scales the functions must not care about (subnormal to huge, and negative)
SCALES = (1.0, 3.7, -2.5e-300, 1e200)


def _built(robot, tmp_path, precision="double"):
    eqs = symdyn.derive(robot, outputs=NAMES)
    lib = build_and_load(generate_c(eqs, NAMES, precision=precision), robot.name, Dimensions.of(robot), 0,
                         workdir=str(tmp_path), precision=precision)
    return eqs, lib


def _pinocchio(model, q, v, q1):
    """Pinocchio's values of the six functions with the robot's own model (unit quaternions)."""
    import pinocchio as pin
    return {"integrate": pin.integrate(model, q, v),
            "integrate_dq": pin.dIntegrate(model, q, v, pin.ARG0),
            "integrate_dv": pin.dIntegrate(model, q, v, pin.ARG1),
            "difference": pin.difference(model, q, q1),
            "difference_dq0": pin.dDifference(model, q, q1, pin.ARG0),
            "difference_dq1": pin.dDifference(model, q, q1, pin.ARG1)}


def _same_configuration(a, b):
    """The largest difference of two configurations, a quaternion and its negative the same."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    quaternion = min(np.max(np.abs(a[3:7] - b[3:7])), np.max(np.abs(a[3:7] + b[3:7])))
    return max(np.max(np.abs(np.delete(a - b, range(3, 7)))), quaternion)


LEGGED = {
    "solo12": "solo_description/robots/solo12.urdf",
    "anymal": "anymal_b_simple_description/robots/anymal.urdf",
    "talos_reduced": "talos_data/robots/talos_reduced.urdf",
}


@pytest.mark.parametrize("name", ["solo12", pytest.param("anymal", marks=pytest.mark.slow),
                                  pytest.param("talos_reduced", marks=pytest.mark.slow)])
def test_against_pinocchio_on_legged_robots(name, tmp_path):
    """Each function of a whole legged robot on its free-flyer, against Pinocchio's with the
    robot's own model (buildModelFromUrdf + JointModelFreeFlyer: the same Lie group as symdyn's
    when every joint has one coordinate), at 30 states with rotations up to and past pi: numpy,
    C and CasADi, q's and q1's quaternions at scales from 2.5e-300 to 1e200 and negative."""
    import pinocchio as pin
    path = example_robot_data(LEGGED[name])
    robot = symdyn.load(path, floating_base=True)
    model = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
    assert model.nq == robot.nq and model.nv == robot.nv
    eqs, lib = _built(robot, tmp_path)
    casadi = {n: casadi_function(eqs, n) for n in NAMES}
    rng = np.random.default_rng(41)
    for k in range(30):
        q, q1 = random_configuration(robot, rng), random_configuration(robot, rng)
        v = rng.uniform(-2, 2, robot.nv)  # |omega| up to 3.5 rad: past pi too
        expected = _pinocchio(model, q, v, q1)
        scale, scale1 = SCALES[k % 4], SCALES[(k + 1) % 4]
        given = {"q": np.concatenate([q[:3], scale * q[3:7], q[7:]]), "v": v,
                 "q1": np.concatenate([q1[:3], scale1 * q1[3:7], q1[7:]])}
        for function in NAMES:
            args = [given[g] for g in OUTPUT_INPUTS[function]]
            values = {"numpy": getattr(eqs.numeric, function)(*args), "c": getattr(lib, function)(*args),
                      "casadi": np.array(casadi[function](*args)).reshape(np.shape(expected[function]))}
            for target, value in values.items():
                if function == "integrate":
                    error = _same_configuration(value, expected[function])
                    assert abs(np.linalg.norm(value[3:7]) - 1) <= 1e-14, target  # a unit quaternion out
                    assert np.dot(value[3:7], np.sign(scale) * q[3:7]) >= 0  # in the hemisphere of the input (Pinocchio)
                else:
                    error = np.max(np.abs(value - expected[function]))
                assert error <= 1e-12 * max(1.0, np.max(np.abs(expected[function]))), (function, target, k, error)


# ---------------------------------------------------------------------------------------------
# An independent reference in 50 digits: SE(3)'s exp and log as matrix functions
# ---------------------------------------------------------------------------------------------

def _log6(M):
    """[v_lin; omega] of a pose in 50 digits, by another route than the generated code's: the
    angle as atan2 of the rotation's skew part (its sine) and trace (its cosine), the axis from
    the skew part, then v_lin solving V(omega) v_lin = p with V's columns the translations of
    exp6([e_i; omega]) (mpmath's matrix exponential).  (mpmath's logm fails near pi.)"""
    skew = [(M[2, 1] - M[1, 2]) / 2, (M[0, 2] - M[2, 0]) / 2, (M[1, 0] - M[0, 1]) / 2]
    sine = mpmath.sqrt(sum(x * x for x in skew))
    angle = mpmath.atan2(sine, (M[0, 0] + M[1, 1] + M[2, 2] - 1) / 2)
    omega = [x * (angle / sine if sine else 1) for x in skew]
    V = mpmath.matrix(3, 3)
    for i in range(3):
        column = mp_exp6([1 if k == i else 0 for k in range(3)] + omega)
        for j in range(3):
            V[j, i] = column[j, 3]
    v_lin = mpmath.lu_solve(V, mpmath.matrix([M[0, 3], M[1, 3], M[2, 3]]))
    return [v_lin[0], v_lin[1], v_lin[2], *omega]


def _jacobian(f, n=6, h=mpmath.mpf("1e-22")):
    """Central differences of f: R^n -> R^6 at 0 (50 digits: truncation ~1e-44, rounding ~1e-28)."""
    columns = []
    for i in range(n):
        e = [mpmath.mpf(0)] * n
        e[i] = h
        plus, minus = f(e), f([-x for x in e])
        columns.append([(a - b) / (2 * h) for a, b in zip(plus, minus)])
    return np.array([[float(columns[j][i]) for j in range(n)] for i in range(6)])


def _reference(q, v, q1):
    """The six functions of a base alone (no joints) in 50 digits."""
    with mpmath.workdps(50):
        M, M1 = mp_pose(q), mp_pose(q1)
        v = [mpmath.mpf(float(x)) for x in v]
        step = mp_exp6(v)
        out = M * step
        rel = mpmath.inverse(M) * M1
        log = _log6(rel)
        add = lambda a, b: [x + y for x, y in zip(a, b)]
        return {
            "integrate": (out, None),
            "integrate_dq": _jacobian(lambda e: _log6(mpmath.inverse(out) * M * mp_exp6(e) * step)),
            "integrate_dv": _jacobian(lambda e: _log6(mpmath.inverse(out) * M * mp_exp6(add(v, e)))),
            "difference": np.array([float(x) for x in log]),
            "difference_dq0": _jacobian(lambda e: _log6(mpmath.inverse(M * mp_exp6(e)) * M1)),
            "difference_dq1": _jacobian(lambda e: _log6(mpmath.inverse(M) * M1 * mp_exp6(e))),
        }


def _angle_cases():
    """(label, rotation angle) of the tangent vectors and relative rotations checked."""
    threshold = float(np.sqrt(float(SERIES_BELOW)))
    return [("zero", 0.0), ("1e-8 rad", 1e-8), ("1e-4 rad", 1e-4), ("1e-3 rad", 1e-3), ("1e-2 rad", 1e-2),
            ("below the series' threshold", threshold * (1 - 1e-9)), ("above it", threshold * (1 + 1e-9)),
            ("1 rad", 1.0), ("pi - 1e-6", np.pi - 1e-6), ("pi - 1e-8", np.pi - 1e-8)]


@pytest.fixture(scope="module")
def free_body(tmp_path_factory):
    """A free-flying body with one joint, its six functions in numpy and C (double and float)."""
    robot = symdyn.load(str(REPO / "examples" / "trees" / "space_robot.yaml"))
    eqs = symdyn.derive(robot, outputs=NAMES)
    libs = {precision: build_and_load(generate_c(eqs, NAMES, precision=precision), robot.name, Dimensions.of(robot),
                                      0, workdir=str(tmp_path_factory.mktemp(precision)), precision=precision)
            for precision in ("double", "float")}
    return robot, eqs, libs


@pytest.mark.parametrize("label, angle", _angle_cases())
def test_exact_near_zero_and_pi(free_body, label, angle):
    """At rotation angles where the closed forms cancel (near 0) or their axis is ill-defined
    (near pi), the six functions against the 50-digit reference, numpy and C in double (1e-13
    of the values, whose size is about 1), the C in float (1e-5)."""
    robot, eqs, libs = free_body
    rng = np.random.default_rng(int(angle * 1e6) % 1000 + 7)
    q = random_configuration(robot, rng)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    v = np.concatenate([rng.uniform(-1, 1, 3), angle * axis, rng.uniform(-1, 1, robot.dof)])
    # q1: q turned by the same angle about another axis, and moved
    other = rng.normal(size=3)
    other /= np.linalg.norm(other)
    turn = np.concatenate([np.sin(angle / 2) * other, [np.cos(angle / 2)]])
    x, y, z, w = q[3:7]
    a, b, c, d = turn
    quaternion = [w * a + x * d + y * c - z * b, w * b - x * c + y * d + z * a, w * c + x * b - y * a + z * d,
                  w * d - x * a - y * b - z * c]
    q1 = np.concatenate([q[:3] + rng.uniform(-1, 1, 3), quaternion, rng.uniform(-3, 3, robot.dof)])
    reference = _reference(q, v[:6], q1)
    given = {"q": q, "v": v, "q1": q1}
    for target, function_of, tolerance in (("numpy", lambda f: getattr(eqs.numeric, f), 1e-13),
                                           ("c", lambda f: getattr(libs["double"], f), 1e-13),
                                           ("c float", lambda f: getattr(libs["float"], f), 2e-5)):
        for function in NAMES:
            value = np.asarray(function_of(function)(*[given[g] for g in OUTPUT_INPUTS[function]]), dtype=float)
            if function == "integrate":
                with mpmath.workdps(50):
                    mine = mp_pose(value)
                    out = reference["integrate"][0]
                    error = max(abs(float(mine[i, j] - out[i, j])) for i in range(3) for j in range(4))
                np.testing.assert_allclose(value[7:], q[7:] + v[6:], rtol=0, atol=tolerance * 4)
            elif function in ("difference", "difference_dq0", "difference_dq1"):
                block = value[:6] if function == "difference" else value[:6, :6]
                error = np.max(np.abs(block - reference[function])) / max(1.0, np.max(np.abs(reference[function])))
                joints = value[6:] if function == "difference" else value[6:, 6:]
                expected = (q1[7:] - q[7:] if function == "difference"
                            else (-1 if function == "difference_dq0" else 1) * np.eye(robot.dof))
                np.testing.assert_allclose(joints, expected, rtol=0, atol=tolerance * 4)
            else:
                error = np.max(np.abs(value[:6, :6] - reference[function])) / max(1.0, np.max(np.abs(reference[function])))
                np.testing.assert_allclose(value[6:, 6:], np.eye(robot.dof), rtol=0, atol=0)
            assert error <= tolerance, (label, target, function, error)


def test_round_trips_and_zero(free_body):
    """integrate and difference undo each other (angles below pi), integrate by 0 is q itself
    (to the rounding of the quaternion's normalization), difference of q and itself is 0, and the Jacobians at v = 0 and
    q1 = q are the identity (integrate's) and -/+ the identity (difference's), exactly."""
    robot, eqs, libs = free_body
    lib = libs["double"]
    rng = np.random.default_rng(43)
    for _ in range(20):
        q = random_configuration(robot, rng)
        v = rng.uniform(-1.5, 1.5, robot.nv)  # |omega| < 2.6 rad < pi
        q1 = lib.integrate(3.0 * np.concatenate([q[:3] / 3.0, q[3:7], q[7:] / 3.0]), v)
        np.testing.assert_allclose(lib.difference(q, q1), v, rtol=0, atol=1e-13)
        assert _same_configuration(lib.integrate(q, lib.difference(q, q1)), q1) <= 1e-14
        # Ad(exp6(v))^-1 Ad(exp6(-v))^-1 = 1, and the right Jacobians: Jr(v) = Jr(-v) Ad(exp6(v))^-1
        np.testing.assert_allclose(lib.integrate_dq(v) @ lib.integrate_dq(-v), np.eye(robot.nv), rtol=0, atol=1e-13)
        np.testing.assert_allclose(lib.integrate_dv(v), lib.integrate_dv(-v) @ lib.integrate_dq(v), rtol=0, atol=1e-13)
    zero = np.zeros(robot.nv)
    q = random_configuration(robot, rng)
    assert _same_configuration(lib.integrate(q, zero), q) <= 4e-16  # (the rounding of the normalization)
    assert np.max(np.abs(lib.difference(q, q))) <= 2e-16  # (u^-1 u to rounding)
    assert np.all(lib.integrate_dq(zero) == np.eye(robot.nv)) and np.all(lib.integrate_dv(zero) == np.eye(robot.nv))
    assert np.max(np.abs(lib.difference_dq1(q, q) - np.eye(robot.nv))) <= 1e-15
    assert np.max(np.abs(lib.difference_dq0(q, q) + np.eye(robot.nv))) <= 1e-15


def test_fixed_base_is_the_joints_space():
    """A fixed base's configuration is R^N: integrate adds, difference subtracts, the Jacobians
    are -/+ the identity (Pinocchio's revolute joints' Lie group, R^N)."""
    robot = symdyn.load(str(REPO / "robots" / "puma560.yaml"))
    eqs = symdyn.derive(robot, outputs=NAMES)
    rng = np.random.default_rng(44)
    q, v, q1 = (rng.uniform(-4, 4, 6) for _ in range(3))
    np.testing.assert_array_equal(eqs.numeric.integrate(q, v), q + v)
    np.testing.assert_array_equal(eqs.numeric.difference(q, q1), q1 - q)
    np.testing.assert_array_equal(eqs.numeric.integrate_dv(v), np.eye(6))
    np.testing.assert_array_equal(eqs.numeric.difference_dq0(q, q1), -np.eye(6))


def test_printed_configuration_section_reproduces_pinocchio():
    """A floating base's printed derivation ends with the configuration space: its rotation of
    the quaternion (at any scale) is Pinocchio's, and the coefficients it prints, each a closed
    form equal to the series used below theta^2 = 1/4, put into the printed formulas give
    Pinocchio's exp3, exp6's translation V(omega) v, Jexp3 (J_r3) and log6's V(omega)^-1 at angles
    on both sides of the threshold; each series agrees with its closed form to 1e-15 below it."""
    import pinocchio as pin
    import sympy as sp
    from symdyn.derive.derivation import derive_steps
    derivation = derive_steps(symdyn.load(str(REPO / "examples" / "trees" / "space_robot.yaml")), "newton-euler",
                              steps="summary")
    section = derivation.section("configuration_space")
    rotation = next(q.value for q in section.quantities if q.kind == "cfg_rotation")
    coefficients = [q.value for q in section.quantities if q.kind == "cfg_coefficient"]
    assert len(coefficients) == 6
    rng = np.random.default_rng(42)
    quaternion = rng.normal(size=4) * 37.0
    symbols = sorted(rotation.free_symbols, key=lambda s: "xyzw".index(s.name[-1]))
    R = np.array(rotation.subs(dict(zip(symbols, quaternion))), dtype=float)
    unit = quaternion / np.linalg.norm(quaternion)
    expected = pin.Quaternion(unit[3], unit[0], unit[1], unit[2]).toRotationMatrix()
    np.testing.assert_allclose(R, expected, rtol=0, atol=1e-14)
    theta = next(iter(coefficients[0].lhs.free_symbols))
    closed = [sp.lambdify(theta, c.lhs, "mpmath") for c in coefficients]
    series = [sp.lambdify(theta, c.rhs, "mpmath") for c in coefficients]
    for angle in (1e-3, 0.2, 0.499, 0.51, 1.3, 3.0):
        with mpmath.workdps(40):  # (the closed forms cancel near 0: evaluated in 40 digits)
            sigma = [float(f(mpmath.mpf(angle))) for f in closed]
            if angle * angle < SERIES_BELOW:
                assert all(abs(float(s(mpmath.mpf(angle))) - c) <= 1e-15 * abs(c) for s, c in zip(series, sigma))
        axis = rng.normal(size=3)
        omega = angle * axis / np.linalg.norm(axis)
        W = pin.skew(omega)
        first = (1 - np.cos(angle)) / angle ** 2
        exp3 = np.eye(3) + np.sin(angle) / angle * W + first * W @ W
        np.testing.assert_allclose(exp3, pin.exp3(omega), rtol=0, atol=1e-14)
        half = pin.Quaternion(np.cos(angle / 2), *(sigma[0] * omega))  # quat * [sigma_1 omega; cos(theta/2)]
        np.testing.assert_allclose(half.toRotationMatrix(), pin.exp3(omega), rtol=0, atol=1e-14)
        V = np.eye(3) + first * W + sigma[1] * W @ W
        v_lin = rng.normal(size=3)
        np.testing.assert_allclose(V @ v_lin, pin.exp6(np.concatenate([v_lin, omega])).translation, rtol=0, atol=1e-14)
        np.testing.assert_allclose(np.eye(3) - first * W + sigma[1] * W @ W, pin.Jexp3(omega), rtol=0, atol=1e-14)
        V_inv = np.eye(3) - W / 2 + sigma[4] * W @ W
        np.testing.assert_allclose(V_inv @ V, np.eye(3), rtol=0, atol=1e-13)
        assert abs(sigma[5] * np.sin(angle / 2) - angle) <= 1e-14
