"""Shared test helpers: Pinocchio references and the normalized error measure."""

from __future__ import annotations

import numpy as np

import symdyn
from symdyn.pinocchio_model import build_model

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


def normalized_error(mine, ref) -> float:
    """max over states and columns of |mine - ref| for joint j, divided by the RMS over states
    of joint j's reference; a joint whose reference is (numerically) zero everywhere is divided
    by the RMS of the whole output instead.  Arrays: (states, n) or (states, n, n)."""
    mine = np.asarray(mine, dtype=float)
    ref = np.asarray(ref, dtype=float)
    states, n = ref.shape[:2]
    diff = np.abs(mine - ref).reshape(states, n, -1)
    refs = ref.reshape(states, n, -1)
    overall = np.sqrt(np.mean(refs**2))
    worst = 0.0
    for j in range(n):
        rms = np.sqrt(np.mean(refs[:, j, :] ** 2))
        scale = rms if rms > 1e-9 * overall else overall
        worst = max(worst, float(np.max(diff[:, j, :])) / scale)
    return worst


class PinocchioReference:
    """Pinocchio's quantities for a robot with numbers substituted for its parameters."""

    def __init__(self, robot, values):
        import pinocchio as pin
        self.pin = pin
        self.model, info = build_model(robot, values)
        self.data = self.model.createData()
        self.damping, self.coulomb = info["damping"], info["coulomb"]
        self.armature = np.array(self.model.armature)

    def mass_matrix(self, q):
        M = self.pin.crba(self.model, self.data, q)
        M = np.triu(M) + np.triu(M, 1).T
        return M - np.diag(self.armature)

    def gravity(self, q):
        return self.pin.computeGeneralizedGravity(self.model, self.data, q).copy()

    def coriolis(self, q, qd):
        return self.pin.nonLinearEffects(self.model, self.data, q, qd).copy() - self.gravity(q)

    def coriolis_matrix(self, q, qd):
        return self.pin.computeCoriolisMatrix(self.model, self.data, q, qd).copy()

    def friction(self, qd):
        return self.damping * qd + self.coulomb * np.sign(qd)

    def inverse_dynamics(self, q, qd, qdd):
        return self.pin.rnea(self.model, self.data, q, qd, qdd).copy() + self.friction(qd)

    def forward_dynamics(self, q, qd, tau):
        return self.pin.aba(self.model, self.data, q, qd, tau - self.friction(qd)).copy()


def random_states(n: int, count: int, seed: int = 0):
    """Seeded states: q in [-pi, pi], qd in [-2, 2], qdd in [-5, 5], tau in [-20, 20]."""
    rng = np.random.default_rng(seed)
    return [(rng.uniform(-np.pi, np.pi, n), rng.uniform(-2, 2, n), rng.uniform(-5, 5, n),
             rng.uniform(-20, 20, n)) for _ in range(count)]
