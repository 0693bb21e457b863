"""Least-squares identification of the base parameters from measured samples.

``tau = Y_b(q, qd, qdd) beta`` stacked over the samples gives ``W beta = T`` (one row per joint
and sample).  :func:`identify` solves it (QR least squares), optionally weighted per joint as
Gautier does (each joint's rows divided by the standard deviation of its residual from a first
unweighted solve), and reports each parameter's standard deviation from
``sigma^2 (W^T W)^-1`` with ``sigma^2 = |r|^2 / (rows - NB)``, and the condition number of the
stacked (weighted) regressor.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.errors import SymdynError
from ..model.tolerances import IDENTIFICATION_MAX_CONDITION

#: a stacked regressor above this condition number does not determine every base parameter
MAX_CONDITION = IDENTIFICATION_MAX_CONDITION


@dataclass(frozen=True)
class Identification:
    """The result: base parameters ``names``, their ``values`` and standard deviations ``std``;
    ``condition``: condition number of the stacked regressor; ``rows``: equations used;
    ``residual_rms``: per joint, RMS of tau - Y_b beta; ``weights``: per joint (1 unweighted)."""

    names: tuple[str, ...]
    values: np.ndarray
    std: np.ndarray
    condition: float
    rows: int
    residual_rms: np.ndarray
    weights: np.ndarray


def identify(eqs, samples, weighted: bool = False, p=None, source: str = "the samples") -> Identification:
    """Identify ``eqs``' base parameters (``eqs`` derived with ``base_regressor``) from
    ``samples``: a :class:`symdyn.model.samples.Samples`, or an iterable of them (blocks, as
    :func:`symdyn.model.samples.sample_blocks` reads a file: memory does not grow with the
    samples); ``p``: runtime parameter values.

    The samples are reduced block by block to one triangle per joint, ``R_j`` of the QR of
    ``[W_j | T_j]`` (joint j's rows of the stacked regressor and torques): everything follows
    from them exactly as from the stacked system (the solve, the weights, each joint's residual
    ``|R_j [-beta; 1]|``, the condition number and the standard deviations)."""
    names = tuple(name for name, _ in eqs.base_parameters)
    nb, n = len(names), eqs.n
    triangles, count = _joint_triangles(eqs, [samples] if hasattr(samples, "q") else samples, nb, p)
    if count * n <= nb:
        raise SymdynError(f"{source}: {count} samples give {count * n} equations for {nb} base "
                          f"parameters: too short (give at least {nb // n + 1} samples, and many more for "
                          "reliable values)")
    weights = np.ones(n)
    values, condition, R = _solve(triangles, weights, nb, source)
    residuals = np.array([_residual(Rj, values) for Rj in triangles])  # |T_j - W_j beta| per joint
    if weighted:
        sigma = residuals / np.sqrt(max(count - nb / n, 1.0))
        sigma[sigma <= 0] = 1.0
        weights = 1.0 / sigma
        values, condition, R = _solve(triangles, weights, nb, source)
        residuals = np.array([_residual(Rj, values) for Rj in triangles])
    rows = count * n
    variance = float(np.hypot.reduce(weights * residuals) ** 2) / max(rows - nb, 1)
    inverse = np.linalg.inv(R)
    std = np.sqrt(variance * np.sum(inverse ** 2, axis=1))
    return Identification(names, values, std, condition, rows, residuals / np.sqrt(count), weights)


def _joint_triangles(eqs, blocks, nb: int, p) -> tuple[list[np.ndarray], int]:
    """``([R_j], samples)``: per joint, the triangle of the QR of ``[W_j | T_j]`` over every
    block of samples (updated block by block), and the number of samples."""
    n = eqs.n
    triangles = [np.zeros((0, nb + 1)) for _ in range(n)]
    count = 0
    for block in blocks:
        rows = [np.asarray(eqs.numeric.base_regressor(q, qd, qdd, p), dtype=float).reshape(n, nb)
                for q, qd, qdd in zip(block.q, block.qd, block.qdd)]
        if not rows:
            continue
        W = np.stack(rows)  # samples x joints x base parameters
        for j in range(n):
            augmented = np.column_stack([W[:, j, :], block.tau[:, j]])
            triangles[j] = np.linalg.qr(np.vstack([triangles[j], augmented]), mode="r")
        count += len(rows)
    return triangles, count


def _residual(R: np.ndarray, values: np.ndarray) -> float:
    """``|T_j - W_j beta|`` from joint j's triangle: ``|R_j [-beta; 1]|``."""
    return float(np.linalg.norm(R @ np.append(-values, 1.0)))


def _solve(triangles, weights, nb: int, source: str):
    """``(beta, condition, R)``: the least-squares solution of the stacked system with joint j's
    rows times ``weights[j]``, from the joints' triangles; the condition number of the stacked
    regressor (its singular values are R's); R, its triangle."""
    stacked = np.linalg.qr(np.vstack([w * Rj for w, Rj in zip(weights, triangles)]), mode="r")
    R, z = stacked[:nb, :nb], stacked[:nb, nb]
    singular = np.linalg.svd(R, compute_uv=False) if R.shape[0] == nb else np.zeros(1)
    condition = float(singular[0] / singular[-1]) if singular[-1] > 0 else float("inf")
    if not condition <= MAX_CONDITION:
        raise SymdynError(f"{source}: the samples do not excite every base parameter (condition number of the "
                          f"stacked regressor {condition:.3g}): use richer trajectories (every joint moving, "
                          "varied speeds and accelerations)")
    return np.linalg.solve(R, z), condition, R
