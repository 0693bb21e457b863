"""Random states of a robot for comparisons and timing: q, qd, qdd and tau in the layout of the
generated functions (a floating base's q: position, unit quaternion x y z w, then the joints)."""

from __future__ import annotations

import numpy as np


def random_configuration(robot, rng: np.random.Generator) -> np.ndarray:
    """q (nq): joint positions uniform in [-pi, pi]; a floating base's position uniform in
    [-1, 1] m and its orientation a uniformly random unit quaternion (x, y, z, w)."""
    joints = rng.uniform(-np.pi, np.pi, robot.dof)
    if not robot.floating:
        return joints
    quaternion = rng.normal(size=4)
    return np.concatenate([rng.uniform(-1, 1, 3), quaternion / np.linalg.norm(quaternion), joints])


def random_state(robot, rng: np.random.Generator) -> list[np.ndarray]:
    """``[q, qd, qdd, tau]``: q as :func:`random_configuration`, qd in [-2, 2], qdd in [-5, 5] and
    tau in [-20, 20] (nv entries each)."""
    nv = robot.nv
    return [random_configuration(robot, rng), rng.uniform(-2, 2, nv), rng.uniform(-5, 5, nv),
            rng.uniform(-20, 20, nv)]
