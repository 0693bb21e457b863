"""A floating base's quaternion at any nonzero scale gives the same numbers (docs/robot-format.md):
every function of a floating robot (its dynamics, frames, centre of mass and centroidal
momentum, kinetic energy, integrate and difference: both configurations scaled), compiled in double and float and evaluated by numpy and CasADi, at
quaternion scales from subnormal to 1e300 (float: its own range) equals the same function at the
unit quaternion of the same direction; a zero quaternion is NaN, and NAME_NOT_FINITE where the
function returns a status."""

from __future__ import annotations

import dataclasses
import shutil

import numpy as np
import pytest

import symdyn
from helpers import REPO
from symdyn.check.agreement import compile_equations
from symdyn.check.states import random_state, second_configuration
from symdyn.derive.cache import derive_cached
from symdyn.emit.casadi_backend import casadi_function
from symdyn.model.outputs import REGISTRY, STATUS_CODES, supported_outputs, with_requirements
from symdyn.model.robot import NamedFrame, Placement

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")

#: scales of the quaternion, per precision of the arithmetic: tiny, subnormal, huge
SCALES = {"double": (1e-160, 1e-300, 4e-320, 1e160, 1e300), "float": (1e-30, 1e-38, 1e-41, 1e30, 3e38)}


@pytest.fixture(scope="module")
def satellite():
    """The two-arm satellite on its floating base, with two frames, under gravity; every
    function it supports, derived once."""
    robot = symdyn.load(str(REPO / "examples" / "trees" / "space_robot.yaml"))
    frames = (NamedFrame(robot.links[-1].name, robot.dof - 1),
              NamedFrame("offset", 1, tuple(Placement((0.1, -0.2, 0.3), (0.4, 0.5, 0.6)).matrix())))
    robot = dataclasses.replace(robot, frames=frames, gravity=(0.3, -1.2, -9.81))
    functions = supported_outputs(robot)
    return robot, functions, derive_cached(robot, "newton-euler", with_requirements(functions))


_COMPILED: dict = {}


def _compiled(satellite, precision, tmp_path_factory):
    """The satellite's C in ``precision``, compiled once for the module."""
    if precision not in _COMPILED:
        _, functions, eqs = satellite
        _COMPILED[precision] = compile_equations(eqs, functions, precision, str(tmp_path_factory.mktemp(precision)))
    return _COMPILED[precision]


def _arguments(spec, state):
    """A function's arguments from ``[q, qd, qdd, tau, q1]`` (integrate's v is qd)."""
    q, qd, qdd, tau, q1 = state
    return [{"q": q, "qd": qd, "qdd": qdd, "tau": tau, "v": qd, "q1": q1}[group] for group in spec.inputs]


def _scaled(q, scale, dtype):
    """``(q with its quaternion times scale, q with that quaternion's unit direction)`` in
    ``dtype``'s arithmetic (a subnormal quaternion holds fewer digits: the reference is its own
    direction, not the unscaled one)."""
    scaled = q.astype(dtype).copy()
    scaled[3:7] *= dtype(scale)
    unit = scaled.copy()
    unit[3:7] = scaled[3:7] / np.max(np.abs(scaled[3:7]))
    return scaled.astype(float), unit.astype(float)


@pytest.mark.parametrize("precision", ["double", pytest.param("float", marks=pytest.mark.slow)])
def test_every_function_at_every_scale(satellite, precision, tmp_path_factory):
    robot, functions, eqs = satellite
    lib = _compiled(satellite, precision, tmp_path_factory)
    dtype, tol = (np.float64, 1e-12) if precision == "double" else (np.float32, 2e-5)
    rng = np.random.default_rng(5)
    for _ in range(3):
        q, *rest = random_state(robot, rng)
        q1 = second_configuration(q, rest[1])
        q1[3:7] /= np.max(np.abs(q1[3:7]))  # (entries within 1, as q's: times 3e38 is still a float)
        for scale in SCALES[precision]:
            scaled, unit = _scaled(q, scale, dtype)
            scaled1, unit1 = _scaled(q1, scale, dtype)
            for name in functions:
                spec = REGISTRY[name]
                got = np.asarray(getattr(lib, name)(*_arguments(spec, [scaled, *rest, scaled1])), dtype=float)
                want = np.asarray(getattr(lib, name)(*_arguments(spec, [unit, *rest, unit1])), dtype=float)
                assert np.all(np.isfinite(got)), (precision, scale, name)
                np.testing.assert_allclose(got, want, rtol=tol, atol=tol * max(1.0, np.max(np.abs(want))),
                                           err_msg=f"{precision} {name} at scale {scale:g}")


def test_numpy_and_casadi_at_every_scale(satellite):
    robot, functions, eqs = satellite
    q, *rest = random_state(robot, np.random.default_rng(6))
    q1 = second_configuration(q, rest[1])
    for scale in SCALES["double"]:
        scaled, unit = _scaled(q, scale, np.float64)
        scaled1, unit1 = _scaled(q1, scale, np.float64)
        for name in functions:
            spec = REGISTRY[name]
            want = np.asarray(getattr(eqs.numeric, name)(*_arguments(spec, [unit, *rest, unit1])), dtype=float)
            got = np.asarray(getattr(eqs.numeric, name)(*_arguments(spec, [scaled, *rest, scaled1])), dtype=float)
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12, err_msg=f"numpy {name} {scale:g}")
            if name in ("inverse_dynamics", "gravity", "center_of_mass", "frame_poses", "difference_dq0"):
                casadi = casadi_function(eqs, name)
                value = np.array(casadi(*_arguments(spec, [scaled, *rest, scaled1]))).reshape(np.shape(want))
                np.testing.assert_allclose(value, want, rtol=1e-12, atol=1e-12, err_msg=f"CasADi {name} {scale:g}")


def test_zero_quaternion_is_a_status_or_nan(satellite, tmp_path_factory):
    """Forward dynamics' checked function returns NAME_NOT_FINITE and writes nothing; the
    functions without a status give NaN (documented in docs/robot-format.md)."""
    robot, functions, eqs = satellite
    lib = _compiled(satellite, "double", tmp_path_factory)
    q, qd, qdd, tau = random_state(robot, np.random.default_rng(7))
    q[3:7] = 0.0
    status, (qdd_out,) = lib.with_status("forward_dynamics_checked", q, qd, tau)
    assert status == STATUS_CODES["NOT_FINITE"][0] and np.all(np.isnan(qdd_out))
    assert np.all(np.isnan(lib.gravity(q)))
