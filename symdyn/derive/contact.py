"""Contact dynamics: the accelerations and contact forces of a robot whose contacts are held,
symbolic.

With ``M = D + diag(armature)`` (n x n), the contacts' constraint rows ``J`` (m x n: the rows of
their frames' Jacobians, world-aligned axes), their drift ``gamma`` (m: J-dot qd) and the
free-motion right-hand side ``r = tau - h - c - friction``, the constrained system is

    [M  J^T] [ qdd  ]   [   r    ]
    [J   0 ] [-lambda] = [-gamma ]        (M qdd = r + J^T lambda,  J qdd + gamma = 0)

solved without forming M^-1, J M^-1 J^T or the system's inverse (the same route as the task
space's, :mod:`symdyn.derive.task_space`)::

    M = the factorization forward dynamics uses (L D L^T of a chain, L^T D L of a tree)
    W = M^-1/2 in that factorization: W W^T = M^-1 (D^-1/2 L^-1 for a chain's, D^-1/2 L^-T a tree's)
    B^T = W^T J^T = Q R                  (modified Gram-Schmidt: R m x m upper triangular)
    w = W^T r                            (carried through the same sweep: c = Q^T w, w_perp = w - Q c)
    t = R^-T gamma,  lambda = -R^-1 (c + t),  qdd = W (w_perp - Q t)

``R^T R = J M^-1 J^T``: ``R_kk^2`` is the k-th pivot of its LDL^T, checked at run time against
``||b_k||^2`` (the diagonal entry) before anything divides by it; a pivot not above the
tolerance means dependent constraints (two soles on one body) or a singular posture.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from . import ldlt
from .configuration import relative_log


@dataclass(frozen=True)
class ContactDynamics:
    """``accelerations`` (n x 1) and ``forces`` (m x 1) in a program's symbols; ``pivots`` the
    ``(R_kk^2, (J M^-1 J^T)_kk)`` of the constraints' QR, which the generated code checks."""

    accelerations: sp.Matrix
    forces: sp.Matrix
    pivots: tuple
    #: the QR's orthonormal columns (m, each n entries), R (m x m upper triangular) and 1/R_kk
    Q: tuple = ()
    R: sp.Matrix | None = None
    inverse: tuple = ()


def _whitening(b, f, tree: bool, hint: str):
    """``(whiten, unwhiten)``: ``v -> W^T v`` and ``u -> W u`` for the factorization ``f`` of M
    (W W^T = M^-1), each entry named."""
    roots = [b.define(f"{hint}_iroot{j + 1}", 1 / sp.sqrt(d)) for j, d in enumerate(f.d)]  # D^-1/2
    if tree:  # M = L^T D L: M^-1 = L^-1 D^-1 L^-T, W = L^-1 D^-1/2
        first = lambda v, hint: ldlt.tree_transposed_solve(b, f, v, hint)  # noqa: E731
        second = lambda u, hint: ldlt.tree_lower_solve(b, f, u, hint)  # noqa: E731
    else:  # M = L D L^T: M^-1 = L^-T D^-1 L^-1, W = L^-T D^-1/2
        first = lambda v, hint: ldlt.forward_substitute(b, f, v, hint)  # noqa: E731
        second = lambda u, hint: ldlt.back_substitute(b, f, u, hint + "{i}")  # noqa: E731

    def whiten(v, name):
        return [b.define(f"{name}w{i + 1}", e * roots[i]) if e != 0 else sp.S.Zero
                for i, e in enumerate(first(v, f"{name}y"))]

    def unwhiten(u, name):
        return second([e * roots[i] for i, e in enumerate(u)], name)
    return whiten, unwhiten


def _dot(a, b) -> sp.Expr:
    return sp.Add(*[x * y for x, y in zip(a, b) if x != 0 and y != 0])


def contact_rows(contacts, frame_jacobians: sp.Matrix) -> sp.Matrix:
    """The contacts' constraint rows J (NC x N) from every frame's Jacobian ``frame_jacobians``
    (6 rows per frame, linear first, world-aligned axes at its origin): a point's three linear
    rows, a sole's six, a planar contact's two (its kind's axes)."""
    return sp.Matrix.vstack(*[frame_jacobians[6 * c.frame + a, :] for c in contacts for a in c.axes])


def correction(contact, J_rows: sp.Matrix, pose: sp.Matrix, qd, define=lambda name, e: e, hint: str = "cb",
               sole_log: bool = True, solved: dict | None = None) -> list:
    """A contact's Baumgarte correction (an entry per row, world axes; zeros without gains),
    Pinocchio's ``corrector`` with the gain on every axis (its LOCAL_WORLD_ALIGNED error
    R diag(K) R^T e is K e then): a point's ``kd v + kp (p - reference)`` on its axes, a sole's
    ``kd v - kp X log6(M^-1 M_ref)`` (X = diag(R, R): :func:`sole_error`), with ``v = J_rows qd``
    its velocity (``J_rows``: the contact's rows) and ``p``, R, M from ``pose`` (the frame's 4 x 4
    pose in the world); ``define(name, expr)`` names a sole's intermediates; ``sole_log`` False
    leaves a sole's log term out (a printout states it instead of expanding it); ``solved``: a
    dict that gets a sole's :func:`sole_error` under ``hint`` (its derivatives reuse it)."""
    if not contact.corrected:
        return [sp.S.Zero] * contact.rows
    velocity = J_rows * sp.Matrix(qd) if contact.kd != 0 else sp.zeros(contact.rows, 1)
    if contact.kp == 0 or (contact.kind == "6d" and not sole_log):
        error = [sp.S.Zero] * contact.rows
    elif contact.kind == "6d":
        found = sole_error(contact, pose, define, hint)
        if solved is not None:
            solved[hint] = found
        error = [-e for e in found[0]]
    else:
        error = [pose[a, 3] - contact.reference[a] for a in contact.axes]
    return [contact.kd * v + contact.kp * e for v, e in zip(velocity, error)]


def sole_error(contact, pose: sp.Matrix, define, hint: str):
    """``(error, jacobian)`` of a sole held with a correction: ``X log6(M^-1 M_ref)`` (6 entries,
    world-aligned: the placement's log in the frame's axes turned to the world's, X = diag(R, R))
    and a function returning ``X Jl^-1 X^T`` (6 x 6), what the error's derivative along the
    frame's world-aligned motion ``delta`` (its Jacobian's columns) is made of:
    ``d(X xi) = -[[R xi_lin]x; [R xi_ang]x] delta_ang - X Jl^-1(xi) X^T delta`` (M moving by the
    local twist X^T delta turns M^-1 M_ref by its inverse on the left)."""
    R1, p1 = pose[:3, :3], pose[:3, 3]
    R2, p2 = contact.reference_placement()
    rho, phi, jacobian = relative_log(define, R1, p1, R2, p2, hint)
    error = [define(f"{hint}_e{i + 1}", e) for i, e in enumerate(list(R1 * rho) + list(R1 * phi))]

    def turned_jacobian() -> sp.Matrix:
        X = sp.diag(R1, R1)
        product = X * jacobian() * X.T
        return sp.Matrix(6, 6, lambda i, j: define(f"{hint}_X{i + 1}_{j + 1}", product[i, j]))
    return error, turned_jacobian


def contact_drift(contacts, J: sp.Matrix, drift_all, qd, define=lambda name, e: e, poses=None,
                  sole_logs: bool = True, solved: dict | None = None) -> list:
    """The contacts' drift gamma (NC entries, world-aligned axes), as Pinocchio's
    ``constraintDynamics`` holds its 3D and 6D contacts: a point's classical acceleration at
    qdd = 0 (its frame's J-dot v, linear rows), a sole's spatial one (the classical minus
    omega x v, then the angular rows; a planar contact's two rows of the point's), plus a
    corrected point's :func:`correction`.
    ``contacts``: the robot's contact set; ``J`` its rows (NC x N); ``drift_all``: every frame's
    J-dot v (6 per frame, linear first); ``qd`` (N); ``define(name, expr)`` names an
    intermediate (the identity by default); ``poses``: every frame's pose (4 rows per frame,
    world), needed when a contact is corrected; ``sole_logs`` False, ``solved``: see
    :func:`correction` (contact k's sole error under ``f"ctb{k + 1}"``)."""
    gamma, at = [], 0
    qd = sp.Matrix(qd)
    for k, contact in enumerate(contacts):
        drift = list(drift_all[6 * contact.frame:6 * contact.frame + 6])
        if contact.kind == "6d":
            linear = [define(f"ctv{k + 1}_{i + 1}", e) for i, e in enumerate(J[at:at + 3, :] * qd)]
            angular = [define(f"ctw{k + 1}_{i + 1}", e) for i, e in enumerate(J[at + 3:at + 6, :] * qd)]
            turn = sp.Matrix(angular).cross(sp.Matrix(linear))
            drift = [drift[i] - turn[i] for i in range(3)] + drift[3:]
        drift = [drift[a] for a in contact.axes]
        if contact.corrected:
            pose = poses[4 * contact.frame:4 * contact.frame + 4, :]
            held = correction(contact, J[at:at + contact.rows, :], pose, qd, define, f"ctb{k + 1}", sole_logs, solved)
            drift = [a + c for a, c in zip(drift, held)]
        gamma += [define(f"ctg{k + 1}_{i + 1}", e) for i, e in enumerate(drift)]
        at += contact.rows
    return gamma


@dataclass(frozen=True)
class GramSchmidt:
    """The QR of k columns ``A = Q R``: ``Q`` (k orthonormal columns, each a tuple of the
    columns' length), ``R`` (k x k upper triangular), ``inverse`` (the k 1/R_jj) and ``pivots``
    (the k ``(R_jj^2, ||a_j||^2)``, which the generated code checks before dividing)."""

    Q: tuple
    R: sp.Matrix
    inverse: tuple
    pivots: tuple


def gram_schmidt(b, columns, hint: str) -> GramSchmidt:
    """The modified Gram-Schmidt QR of ``columns`` (k lists of one length, the matrix's columns),
    every entry named in ``b`` (``{hint}A``: the squared norms, ``{hint}R``, ``{hint}Rinv``,
    ``{hint}Q``, ``{hint}B``: the columns as they are swept); entries that are exact zeros stay
    zeros (a contact's rows read few joints)."""
    k_count = len(columns)
    diagonal = [b.define(f"{hint}A{k + 1}", _dot(col, col)) for k, col in enumerate(columns)]
    R = sp.zeros(k_count, k_count)
    Q, inverse, pivots = [], [], []
    work = [list(col) for col in columns]
    for k in range(k_count):
        square = diagonal[k] if k == 0 else b.define(f"{hint}R{k + 1}sq", _dot(work[k], work[k]))
        pivots.append((square, diagonal[k]))
        R[k, k] = b.define(f"{hint}R{k + 1}_{k + 1}", sp.sqrt(square))
        inverse.append(b.define(f"{hint}Rinv{k + 1}", 1 / R[k, k]))
        q = [b.define(f"{hint}Q{k + 1}_{i + 1}", e * inverse[k]) if e != 0 else sp.S.Zero for i, e in enumerate(work[k])]
        Q.append(tuple(q))
        for j in range(k + 1, k_count):
            R[k, j] = b.define(f"{hint}R{k + 1}_{j + 1}", _dot(q, work[j]))
            work[j] = [b.define(f"{hint}B{j + 1}_{k + 1}_{i + 1}", e - R[k, j] * qi) if qi != 0 else e
                       for i, (e, qi) in enumerate(zip(work[j], q))]
    return GramSchmidt(tuple(Q), R, tuple(inverse), tuple(pivots))


def contact_dynamics(b, f, tree: bool, J: sp.Matrix, gamma, rhs, hint: str = "ct") -> ContactDynamics:
    """The constrained accelerations and contact forces (module docstring) for the factorization
    ``f`` of M (``tree``: :func:`symdyn.derive.ldlt.factor_tree`'s, else :func:`~symdyn.derive.ldlt.factor`'s),
    the constraint rows ``J`` (m x n), their drift ``gamma`` (m) and ``rhs`` (n), every
    intermediate named in ``b`` (``{hint}...``: the impulse dynamics solve the same system again)."""
    m, n = J.shape
    whiten, unwhiten = _whitening(b, f, tree, hint)
    columns = [whiten([J[k, i] for i in range(n)], f"{hint}B{k + 1}_") for k in range(m)]
    w = whiten(list(rhs), f"{hint}W")
    qr = gram_schmidt(b, columns, hint)
    Q, R, inverse = qr.Q, qr.R, qr.inverse
    c = []
    for k, q in enumerate(Q):  # c = Q^T w, w_perp = w - Q c, one column at a time (modified Gram-Schmidt)
        c.append(b.define(f"{hint}c{k + 1}", _dot(q, w)))
        w = [b.define(f"{hint}W{k + 1}_{i + 1}", e - c[k] * qi) if qi != 0 else e for i, (e, qi) in enumerate(zip(w, q))]
    t: list[sp.Expr] = []
    for k in range(m):  # R^T t = gamma
        t.append(b.define(f"{hint}t{k + 1}", (gamma[k] - sp.Add(*[R[l, k] * t[l] for l in range(k)])) * inverse[k]))
    forces: list[sp.Expr] = [sp.S.Zero] * m
    for k in reversed(range(m)):  # R lambda = -(c + t)
        forces[k] = b.define(f"{hint}lambda{k + 1}",
                             (-(c[k] + t[k]) - sp.Add(*[R[k, l] * forces[l] for l in range(k + 1, m)])) * inverse[k])
    u = [b.define(f"{hint}u{i + 1}", w[i] - sp.Add(*[Q[k][i] * t[k] for k in range(m) if Q[k][i] != 0]))
         for i in range(n)]
    qdd = unwhiten(u, f"{hint}_x")
    return ContactDynamics(sp.Matrix(qdd), sp.Matrix(forces), qr.pivots, Q, R, inverse)


@dataclass(frozen=True)
class ConstrainedInverse:
    """The blocks of the constrained system's inverse,

        [M  J^T]^-1   [K     S   ]
        [J   0 ]    = [S^T  -A^-1]    K = M^-1 - Z Z^T,  S = Z R^-T = M^-1 J^T A^-1,  A = J M^-1 J^T = R^T R

    with ``Z = W Q`` (n x m); ``K`` (n x n, symmetric), ``S`` (n x m) and ``A_inverse`` (m x m,
    symmetric), every entry named; ``Z`` and ``R_inverse`` (m x m, upper triangular) they are
    formed from: ``[K S; -S^T A^-1] = diag(M^-1, 0) + [Z; R^-1] [-Z; R^-1]^T``."""

    K: sp.Matrix
    S: sp.Matrix
    A_inverse: sp.Matrix
    Z: sp.Matrix
    R_inverse: sp.Matrix


def constrained_inverse(b, f, tree: bool, system: ContactDynamics, Minv: sp.Matrix, hint: str = "ck") -> ConstrainedInverse:
    """:class:`ConstrainedInverse` of a solved contact system ``system`` (its QR) for the
    factorization ``f`` of M and M^-1 ``Minv`` (n x n) from it: Z's columns are W q_k (one solve
    with the factorization each), R^-1 by back substitution (m^3 / 6 products)."""
    n, m = Minv.shape[0], len(system.Q)
    _, unwhiten = _whitening(b, f, tree, "ct")
    Z = sp.Matrix.hstack(*[sp.Matrix(unwhiten(list(q), f"{hint}Z{k + 1}_")) for k, q in enumerate(system.Q)])
    Rinv = sp.zeros(m, m)
    for k in range(m):  # R Rinv = 1, column by column from the bottom
        Rinv[k, k] = system.inverse[k]
        for i in reversed(range(k)):
            Rinv[i, k] = b.define(f"{hint}Ri{i + 1}_{k + 1}",
                                  -sp.Add(*[system.R[i, l] * Rinv[l, k] for l in range(i + 1, k + 1)]) * system.inverse[i])
    S = sp.Matrix(n, m, lambda i, k: b.define(f"{hint}S{i + 1}_{k + 1}",
                                              sp.Add(*[Z[i, l] * Rinv[k, l] for l in range(k, m) if Z[i, l] != 0])))
    A_inverse = sp.zeros(m, m)
    for i in range(m):
        for k in range(i, m):
            A_inverse[i, k] = A_inverse[k, i] = b.define(
                f"{hint}Ai{i + 1}_{k + 1}", sp.Add(*[Rinv[i, l] * Rinv[k, l] for l in range(k, m)]))
    K = sp.zeros(n, n)
    for i in range(n):
        for j in range(i, n):
            K[i, j] = K[j, i] = b.define(f"{hint}K{i + 1}_{j + 1}",
                                         Minv[i, j] - sp.Add(*[Z[i, l] * Z[j, l] for l in range(m) if Z[i, l] != 0]))
    return ConstrainedInverse(K, S, A_inverse, Z, Rinv)
