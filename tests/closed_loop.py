"""Platform robots in the tests: random states about the home pose of each bundled platform
(Pinocchio's side of the closed loop: symdyn.check.pinocchio_model)."""

import numpy as np
import pinocchio as pin

from symdyn.check.pinocchio_model import (actuation_matrix, closure_accelerations, closure_mismatch,  # noqa: F401
                                          free_flyer_twist_rate, pinocchio_forward_dynamics,
                                          pinocchio_inverse_dynamics, pinocchio_state)

#: bundled platform -> (home height of P (m), range of the positions (m) and angles (rad) of the
#: random states about the home pose)
PLATFORMS = {"flight_simulator": (2.0, 0.2, 0.17), "sru_platform": (0.55, 0.03, 0.08)}


def states(name, count, seed):
    """Platform states about the home pose (level, P at the home height), twists and twist rates
    of order 1."""
    height, reach, tilt = PLATFORMS[name]
    rng = np.random.default_rng(seed)
    for _ in range(count):
        p = np.array([0.0, 0.0, height]) + rng.uniform(-reach, reach, 3)
        R = pin.rpy.rpyToMatrix(*rng.uniform(-tilt, tilt, 3))
        yield p, R, rng.uniform(-0.5, 0.5, 6), rng.uniform(-1.0, 1.0, 6)
