"""Shared test helpers: Pinocchio references and the normalized error measure."""

from __future__ import annotations

import numpy as np

import symdyn
from symdyn.check.pinocchio_model import PinocchioReference, normalized_error  # noqa: F401 (re-exported)

REPO = __import__("pathlib").Path(__file__).resolve().parents[1]
ROBOTS = sorted(p.stem for p in (REPO / "robots").glob("*.yaml"))
TOL = 1e-10


def robot_path(name: str) -> str:
    path = REPO / "robots" / f"{name}.yaml"
    return str(path if path.exists() else REPO / "tests" / "data" / f"{name}.yaml")


def parameter_values(robot, seed: int = 7) -> dict:
    """Seeded positive values for every runtime parameter and free symbol (g = 9.81)."""
    rng = np.random.default_rng(seed)
    values = {}
    for sym in robot.parameters:
        values[sym] = 9.81 if sym.name == "g" else float(rng.uniform(0.3, 1.5))
    return values


def random_states(n: int, count: int, seed: int = 0):
    """Seeded states: q in [-pi, pi], qd in [-2, 2], qdd in [-5, 5], tau in [-20, 20]."""
    rng = np.random.default_rng(seed)
    return [(rng.uniform(-np.pi, np.pi, n), rng.uniform(-2, 2, n), rng.uniform(-5, 5, n),
             rng.uniform(-20, 20, n)) for _ in range(count)]
