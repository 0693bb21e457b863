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


def second_configuration(q, qdd) -> np.ndarray:
    """A second configuration drawn from a state (difference's end, ``q1``): the joints moved
    by qdd; a floating base's position moved by qdd's first 3 entries / 5 and its quaternion by
    (qdd[3:6], qdd[0]) / 2, then scaled by 1 + |qdd[1]| (the generated functions take a
    quaternion of any scale; the turn is any, up to a half turn and past it)."""
    q, qdd = np.asarray(q, dtype=float), np.asarray(qdd, dtype=float)
    if len(q) == len(qdd):
        return q + qdd
    quaternion = (q[3:7] + np.array([qdd[3], qdd[4], qdd[5], qdd[0]]) / 2) * (1 + abs(qdd[1]))
    return np.concatenate([q[:3] + qdd[:3] / 5, quaternion, q[7:] + qdd[6:]])


def state_arguments(function: str, state, contact_rows: int | None = None) -> list:
    """The arguments of a generated function (an output or a combined function) at a state
    ``[q, qd, qdd, tau]``, in its order: the state's groups as they are, the external forces at
    the contacts (``contact_rows`` entries) as :func:`contact_forces_of`, the tangent vector v
    of integrate as qd (a displacement of one second) and the second configuration q1 as
    :func:`second_configuration`."""
    from ..model.outputs import function_inputs
    q, qd, qdd, tau = state[:4]
    given = {"q": q, "qd": qd, "qdd": qdd, "tau": tau, "v": qd}
    groups = function_inputs(function)
    if "restitution" in groups:  # in (0, 1), from the state
        given["restitution"] = np.array([0.5 * (1.0 + np.tanh(float(np.asarray(qdd).reshape(-1)[0])))])
    if "f" in groups:
        if contact_rows is None:
            raise ValueError(f"{function} takes external forces at the contacts: give contact_rows")
        given["f"] = contact_forces_of(tau, contact_rows)
    return [second_configuration(q, qdd) if group == "q1" else given[group] for group in groups]


def contact_forces_of(tau, count: int) -> np.ndarray:
    """External forces at the contacts drawn from a state (``count`` entries): tau's entries
    cycled and scaled by 3 (forces of tens of newtons against a leg's torques)."""
    return 3.0 * np.resize(np.asarray(tau, dtype=float), count)
