"""The closed-loop reference of symdyn verify and bench for platforms (symdyn.check.closed_loop,
Pinocchio only: its legs solved on Pinocchio's model) against the numeric natural orthogonal
complement of symdyn.check.parallel_reference (symdyn's serial leg equations, Newton inverse
kinematics): two independent computations of every platform function."""

import numpy as np
import pytest

from closed_loop import PLATFORMS, states
from helpers import REPO
from symdyn.model import parallel

pytest.importorskip("pinocchio")


@pytest.mark.parametrize("name", sorted(PLATFORMS))
def test_reference_agrees_with_the_numeric_complement(name):
    from symdyn.check.closed_loop import ClosedLoopReference, pose_vector
    from symdyn.check.parallel_reference import ParallelReference
    robot = parallel.load(REPO / "robots" / "parallel" / f"{name}.yaml")
    ref, numeric = ClosedLoopReference(robot), ParallelReference(robot)
    assert np.allclose(ref.home_position, [0, 0, PLATFORMS[name][0]], atol=1e-9)
    for p, R, twist, rate in states(name, 4, seed=21):
        pose = pose_vector(p, R)
        expected = numeric.seed_matrices(p, R)
        phi = numeric.inverse_dynamics(p, R, twist, rate)
        legs = numeric.leg_states(p, R, twist)
        for function, args, values in (
                ("inverse_dynamics", (pose, twist, rate), [phi]),
                ("forward_dynamics", (pose, twist, 1.1 * phi), [numeric.forward_dynamics(p, R, twist, 1.1 * phi)]),
                ("mass_matrix", (pose,), [expected["M"]]),
                ("twist_map", (pose,), [expected["T"]]),
                ("leg_rate_maps", (pose,), [np.vstack(expected["L"])]),
                ("inverse_kinematics", (pose, twist), [[leg.theta[k] for leg, k in zip(legs, numeric.actuated)],
                                                       [leg.theta_dot[k] for leg, k in zip(legs, numeric.actuated)]])):
            status, *outputs = getattr(ref, function)(*args)
            assert status == 0, function
            for ours, theirs in zip(outputs, values):
                theirs = np.asarray(theirs, dtype=float)
                assert np.abs(ours - theirs).max() <= 1e-9 * (1 + np.abs(theirs).max()), function


def test_reference_statuses():
    """A zero quaternion is UNREACHABLE (1) everywhere; the S-R-U platform raised by ten leg
    lengths too (its legs have a fixed length), not the flight simulator's (prismatic legs);
    a twist of 1e155 overflows the dynamics (NOT_FINITE, 4), not the inverse kinematics."""
    from symdyn.check.closed_loop import ClosedLoopReference, pose_vector
    for name, far in (("sru_platform", 1), ("flight_simulator", 0)):
        ref = ClosedLoopReference(parallel.load(REPO / "robots" / "parallel" / f"{name}.yaml"))
        zero, home = np.zeros(6), pose_vector(ref.home_position, ref.home_rotation)
        assert ref.mass_matrix(np.concatenate([ref.home_position, np.zeros(4)]))[0] == 1
        raised = pose_vector(ref.home_position + [0, 0, 10 * ref.length], ref.home_rotation)
        assert ref.twist_map(raised)[0] == far
        huge = np.full(6, 1e155)
        assert ref.inverse_dynamics(home, huge, zero)[0] == 4 and ref.forward_dynamics(home, huge, zero)[0] == 4
        assert ref.inverse_kinematics(home, huge)[0] == 0
