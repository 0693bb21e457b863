"""Every bundled robot, every method: all outputs agree with Pinocchio at 50 seeded states (20 for
the methods other than the default Newton-Euler)."""

import zlib

import numpy as np
import pytest

from helpers import ROBOTS, TOL, PinocchioReference, normalized_error, parameter_values, random_states
from symdyn.check.pinocchio_model import compare
from symdyn.model.outputs import ALL_OUTPUTS

STATES = 50
#: the derivations other than the default one are checked at fewer states (they share no code
#: with it, and 20 seeded states find any mistake the 50 would)
OTHER_METHOD_STATES = 20


#: (robot, method) checked on D and c only: Lagrange-Euler's velocity terms grow as n^4 and derive
#: in about 30 s for chain12's 12 joints (it is checked whole on every other robot, and equal to
#: Newton-Euler exactly on 3-joint chains, tests/derive/test_symbolic.py)
PARTIAL = {("chain12", "lagrange-euler"): ("mass_matrix", "gravity")}


#: (robot, method) pairs run with -m slow only: the other methods on the 7- and 12-joint robots
#: and on three of the 6-joint arms (3-9 s each); by default they run on puma560 (revolute, the
#: textbook arm), scara and planar2r (prismatic and planar), Lagrange-Euler equals Newton-Euler
#: exactly on 3-joint chains and numerically on panda and iiwa14 (tests/derive/test_symbolic.py),
#: and the default method runs on every robot
SLOW = {(name, method) for name in ("chain12", "iiwa14", "panda", "ur5", "pendulum_leg", "stanford")
        for method in ("lagrange-euler", "jacobian-newton-euler")}


@pytest.mark.parametrize("name,method", [
    pytest.param(name, method, marks=[pytest.mark.slow] if (name, method) in SLOW else [], id=f"{name}-{method}")
    for method in ("newton-euler", "lagrange-euler", "jacobian-newton-euler") for name in ROBOTS])
def test_agrees_with_pinocchio(derived, name, method):
    if (name, method) in PARTIAL:
        import symdyn
        from helpers import robot_path
        eqs = symdyn.derive(symdyn.load(robot_path(name)), method, PARTIAL[(name, method)])
    else:
        eqs = derived(name, method)
    values = parameter_values(eqs.robot)
    p = [values[s] for s in eqs.parameters]
    ref = PinocchioReference(eqs.robot, values)
    # every derived output, in the registry's order; each must have its independent reference
    functions = [name for name in ALL_OUTPUTS if name in eqs.output_names]
    missing = [f for f in functions if not hasattr(ref, f)]
    assert not missing, f"no Pinocchio reference for {missing}"
    count = STATES if method == "newton-euler" else OTHER_METHOD_STATES
    states = list(random_states(eqs.n, count, seed=zlib.crc32(name.encode()) % 1000))
    errors = compare(eqs.numeric, ref, states, functions, p)
    assert set(errors) == set(functions) and all(np.isfinite(v) for v in errors.values()), errors
    bad = {k: v for k, v in errors.items() if v > TOL}
    assert not bad, f"{name} {method}: normalized errors over {TOL}: {bad}"


def test_error_measure_catches_a_wrong_model(derived):
    """The comparison is not vacuous: a robot with one changed mass disagrees."""
    import symdyn
    from helpers import robot_path
    robot = symdyn.load(robot_path("puma560"))
    eqs = derived("puma560")
    from dataclasses import replace
    heavier = replace(robot, links=robot.links[:2] + (replace(robot.links[2], mass=robot.links[2].mass * 1.001),) + robot.links[3:])
    ref = PinocchioReference(heavier, {})
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    err = normalized_error(eqs.numeric.gravity(q)[None, :], ref.gravity(q)[None, :])
    assert err > 1e-5


def test_error_measure_does_not_overflow():
    """Values near 1e200 are compared by their ratio, not by squares that overflow: a relative
    difference of 1e-3 measures as at scale 1 (not 0), an overflowing difference is inf, and numpy warns of
    nothing."""
    import warnings
    ref = np.array([[1e200, -2e200, 3e200], [2e200, 1e200, -1e200]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        unit = normalized_error(ref / 1e200 * (1 + 1e-3), ref / 1e200)  # the same comparison at scale 1
        assert unit > 1e-3 and abs(normalized_error(ref * (1 + 1e-3), ref) - unit) < 1e-12
        assert normalized_error(ref, ref) == 0.0
        assert normalized_error(np.array([[1e308, 1.0]]), np.array([[-1e308, 1.0]])) == float("inf")
        assert normalized_error(np.array([[1e-300, 0.0]]), np.array([[2e-300, 0.0]])) > 0.4


def test_error_measure_row_floor():
    """A row far smaller than the rest of its output (a Jacobian's row of a tool 1 mm from an
    axis) is measured against ``row_floor`` times the output's RMS, never less; rows above that
    keep their own scale, and without the floor the small row is judged on its own."""
    ref = np.tile(np.array([[1.0, -0.8], [1e-3, 2e-3], [0.5, 0.7]]), (4, 1, 1))  # 4 states, rows of 3 scales
    overall = float(np.sqrt(np.mean(ref ** 2)))
    mine = ref.copy()
    mine[:, 1, 0] += 3e-7  # rounding of the large entries reaching the small row
    own = 3e-7 / float(np.sqrt(np.mean(ref[:, 1, :] ** 2)))
    assert normalized_error(mine, ref) == pytest.approx(own, rel=1e-9)
    assert normalized_error(mine, ref, row_floor=1e-2) == pytest.approx(3e-7 / (1e-2 * overall), rel=1e-9)
    mine = ref.copy()
    mine[:, 0, 1] *= 1 + 1e-5  # a large row keeps its own scale under the floor
    assert normalized_error(mine, ref, row_floor=1e-2) == pytest.approx(0.8e-5 / float(np.sqrt(np.mean(ref[:, 0, :] ** 2))),
                                                                        rel=1e-6)
