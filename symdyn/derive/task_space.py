"""Task-space (operational-space) dynamics of the tool frame, symbolic.

The equations of motion written in the tool's coordinates (the ECE 470 dynamics lecture,
"Cartesian space"; Khatib's operational-space formulation)::

    F = M_x(q) xdd + V_x(q, qd) + G_x(q)

for the task rows ``J_s`` (m x n) of the tool Jacobian (world axes at the tool origin, linear
rows first, as ``NAME_jacobian``) and ``M = D + diag(armature)`` (n x n)::

    Lambda^-1 = J_s M^-1 J_s^T                     (m x m)
    M_x  = Lambda                                  (= J_s^-T M J_s^-1 for a square, regular J_s)
    V_x  = Lambda (J_s M^-1 h - Jdot_s qd)         (h: Coriolis and centrifugal torques)
    G_x  = Lambda J_s M^-1 c                       (= J_s^-T c for a square J_s)
    Jbar = M^-1 J_s^T Lambda                       (n x m, the dynamically consistent inverse)

so that ``tau = J_s^T (Lambda a + V_x + G_x)`` gives the tool the classical acceleration
``xdd = a`` (friction compensated separately), and ``(1 - J_s^T Jbar^T) tau_0`` adds joint
torques that leave it unchanged.  Viscous and Coulomb friction are not part of the model.

How, without ever forming ``J_s M^-1 J_s^T`` (whose condition number is the square of the
task's: forming it costs two of the sixteen digits near a singularity)::

    M = L D L^T                          (the LDL^T forward dynamics uses; pivots checked)
    B^T = D^-1/2 L^-1 J_s^T              (n x m, so that J_s M^-1 J_s^T = B B^T)
    B^T = Q R                            (modified Gram-Schmidt: R upper triangular, m x m)
    Lambda = R^-1 R^-T,  G_x = R^-1 Q^T D^-1/2 L^-1 c,
    V_x = R^-1 (Q^T D^-1/2 L^-1 h - R^-T Jdot_s qd),  Jbar = L^-T D^-1/2 Q R^-T

``R^T R = J_s M^-1 J_s^T``, so ``R_kk^2`` is the k-th pivot of its LDL^T: the generated code
checks it against ``||b_k||^2`` (the diagonal entry) before dividing by it, and a pivot not above
the tolerance is a kinematic singularity of the task (or a task direction the joints cannot
move the tool in).  Modified Gram-Schmidt's R is as accurate as Householder's (Bjorck, 1967),
and the right-hand sides are reduced as extra columns of the same sweep (Q^T applied as the
columns were made), so that the results carry errors of the order of the task's own condition
number, as a QR least-squares solve does.  m + n square roots, 2 m + n divisions.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model.outputs import TASK_OUTPUTS  # noqa: F401 (the outputs this module derives, together)
from .ldlt import Factorization, back_substitute, factor, forward_substitute


@dataclass(frozen=True)
class TaskSpace:
    """The task-space quantities of one robot and task (expressions in a program's symbols):
    ``Lambda`` (m x m), ``bias`` (V_x, m x 1), ``gravity`` (G_x, m x 1), ``inverse`` (Jbar,
    n x m); ``mass`` the LDL^T of M, ``task_pivots`` the pivots ``(R_kk^2, (J M^-1 J^T)_kk)``
    of the task's QR factorization, which the generated code checks."""

    Lambda: sp.Matrix
    bias: sp.Matrix
    gravity: sp.Matrix
    inverse: sp.Matrix
    mass: Factorization
    task_pivots: tuple

    def outputs(self) -> dict[str, sp.Matrix]:
        return {"task_mass_matrix": self.Lambda, "task_bias": self.bias, "task_gravity": self.gravity,
                "task_inverse": self.inverse}


def _whiten(b, f: Factorization, inv_roots, vector, hint: str) -> list[sp.Expr]:
    """``D^-1/2 L^-1 vector`` (n entries, named ``{hint}{i}``): forward substitution with the
    unit lower triangular L, then each entry divided by the square root of its pivot."""
    y = forward_substitute(b, f, vector, f"{hint}y")
    return [b.define(f"{hint}{i + 1}", y[i] * inv_roots[i]) for i in range(f.size)]


def _project_out(b, q, vector, coefficient_hint: str, hint: str, reduce: bool = True):
    """One modified Gram-Schmidt step: ``(q . vector, vector - (q . vector) q)`` (the reduced
    vector only when ``reduce``, else ``vector``), every entry named."""
    coefficient = b.define(coefficient_hint, sp.Add(*[a * e for a, e in zip(q, vector)]))
    if not reduce:
        return coefficient, vector
    return coefficient, [b.define(f"{hint}{i + 1}", e - coefficient * a) for i, (a, e) in enumerate(zip(q, vector))]


def task_space(b, M: sp.Matrix, J: sp.Matrix, jacobian_dot_qd: sp.Matrix, h: sp.Matrix, c: sp.Matrix,
               rows: tuple[int, ...], on_zero=None) -> TaskSpace:
    """Task-space dynamics for the Jacobian rows ``rows`` (indices into the 6 rows of ``J``:
    0-2 linear, 3-5 angular), from ``M`` (n x n, with armature), the tool Jacobian ``J`` (6 x n),
    ``J-dot qd`` (6 x 1), ``h`` and ``c`` (n x 1), every intermediate named in ``b``.
    ``on_zero(j)``: called when pivot j of M is identically zero."""
    n, m = M.shape[0], len(rows)
    fM = factor(b, M, "ldl", on_zero)
    inv_roots = [b.define(f"ts_iroot{j + 1}", 1 / sp.sqrt(fM.d[j])) for j in range(n)]  # D^-1/2
    columns = [_whiten(b, fM, inv_roots, [J[row, k] for k in range(n)], f"tsB{s + 1}_") for s, row in enumerate(rows)]
    gravity_column = _whiten(b, fM, inv_roots, list(c), "tsC")
    bias_column = _whiten(b, fM, inv_roots, list(h), "tsH")
    diagonal = [b.define(f"tsA_{k}{k}", sp.Add(*[e * e for e in columns[k]])) for k in range(m)]  # (J M^-1 J^T)_kk
    # modified Gram-Schmidt on B^T = [b_1 ... b_m], the two right-hand sides carried along
    R = sp.zeros(m, m)
    Q: list[list[sp.Expr]] = []
    pivots, inv_diagonal, gravity_coefficients, bias_coefficients = [], [], [], []
    work = [list(col) for col in columns]
    for k in range(m):
        square = diagonal[k] if k == 0 else b.define(f"tsR{k + 1}sq", sp.Add(*[e * e for e in work[k]]))
        pivots.append((square, diagonal[k]))
        R[k, k] = b.define(f"tsR{k + 1}{k + 1}", sp.sqrt(square))
        inv_diagonal.append(b.define(f"tsRinv{k + 1}", 1 / R[k, k]))
        q = [b.define(f"tsQ{k + 1}_{i + 1}", e * inv_diagonal[k]) for i, e in enumerate(work[k])]
        Q.append(q)
        for j in range(k + 1, m):
            R[k, j], work[j] = _project_out(b, q, work[j], f"tsR{k + 1}{j + 1}", f"tsB{j + 1}_{k + 1}_")
        for hint, column, coefficients in (("tsC", gravity_column, gravity_coefficients),
                                           ("tsH", bias_column, bias_coefficients)):
            coefficient, column[:] = _project_out(b, q, column, f"{hint}r{k + 1}", f"{hint}_{k + 1}_", k + 1 < m)
            coefficients.append(coefficient)
    # W = R^-1 (upper triangular), column by column
    W = sp.zeros(m, m)
    for j in range(m):
        W[j, j] = inv_diagonal[j]
        for i in reversed(range(j)):
            W[i, j] = b.define(f"tsW{i + 1}{j + 1}", -sp.Add(*[W[i, l] * R[l, j] for l in range(i, j)]) * inv_diagonal[j])
    Lambda = sp.zeros(m, m)
    for i in range(m):
        for j in range(i, m):
            Lambda[i, j] = Lambda[j, i] = b.define(f"tsL_{i}{j}", sp.Add(*[W[i, l] * W[j, l] for l in range(j, m)]))
    gravity = sp.Matrix([b.define(f"tsG{i + 1}", sp.Add(*[W[i, l] * gravity_coefficients[l] for l in range(i, m)]))
                         for i in range(m)])
    accel = [jacobian_dot_qd[row] for row in rows]
    back = [b.define(f"tsV{l + 1}r", bias_coefficients[l] - sp.Add(*[W[k, l] * accel[k] for k in range(l + 1)]))
            for l in range(m)]  # Q^T D^-1/2 L^-1 h - R^-T Jdot qd
    bias = sp.Matrix([b.define(f"tsV{i + 1}", sp.Add(*[W[i, l] * back[l] for l in range(i, m)])) for i in range(m)])
    # Jbar = L^-T D^-1/2 Q W^T: each column by back substitution
    Jbar = sp.zeros(n, m)
    for s in range(m):
        scaled = [b.define(f"tsJ{s + 1}_s{i + 1}", inv_roots[i] * sp.Add(*[Q[k][i] * W[s, k] for k in range(s, m)]))
                  for i in range(n)]
        Jbar[:, s] = sp.Matrix(back_substitute(b, fM, scaled, f"tsJ{s + 1}_{{i}}"))
    return TaskSpace(Lambda=Lambda, bias=bias, gravity=gravity, inverse=Jbar, mass=fM, task_pivots=tuple(pivots))
