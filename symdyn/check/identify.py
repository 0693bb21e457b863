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
    ``samples`` (:class:`symdyn.model.samples.Samples`); ``p``: runtime parameter values."""
    names = tuple(name for name, _ in eqs.base_parameters)
    nb, n = len(names), eqs.n
    if samples.count * n <= nb:
        raise SymdynError(f"{source}: {samples.count} samples give {samples.count * n} equations for {nb} base "
                          f"parameters: too short (give at least {nb // n + 1} samples, and many more for "
                          "reliable values)")
    blocks = [np.asarray(eqs.numeric.base_regressor(q, qd, qdd, p), dtype=float).reshape(n, nb)
              for q, qd, qdd in zip(samples.q, samples.qd, samples.qdd)]
    W = np.vstack(blocks)  # rows: sample 0 joints 1..n, sample 1 ...
    T = samples.tau.reshape(-1)
    weights = np.ones(n)
    values, condition = _solve(W, T, source)
    if weighted:
        residual = (T - W @ values).reshape(-1, n)
        dof = max(samples.count - nb / n, 1.0)
        sigma = np.sqrt(np.sum(residual ** 2, axis=0) / dof)
        sigma[sigma <= 0] = 1.0
        weights = 1.0 / sigma
        scale = np.tile(weights, samples.count)
        W, T = W * scale[:, None], T * scale
        values, condition = _solve(W, T, source)
    residual = T - W @ values
    rows = W.shape[0]
    variance = float(residual @ residual) / max(rows - nb, 1)
    _, R = np.linalg.qr(W)
    inverse = np.linalg.inv(R)
    std = np.sqrt(variance * np.sum(inverse ** 2, axis=1))
    rms = np.sqrt(np.mean(((residual / np.tile(weights, samples.count)).reshape(-1, n)) ** 2, axis=0))
    return Identification(names, values, std, condition, rows, rms, weights)


def _solve(W, T, source):
    singular = np.linalg.svd(W, compute_uv=False)
    condition = float(singular[0] / singular[-1]) if singular[-1] > 0 else float("inf")
    if not condition <= MAX_CONDITION:
        raise SymdynError(f"{source}: the samples do not excite every base parameter (condition number of the "
                          f"stacked regressor {condition:.3g}): use richer trajectories (every joint moving, "
                          "varied speeds and accelerations)")
    Q, R = np.linalg.qr(W)
    return np.linalg.solve(R, Q.T @ T), condition
