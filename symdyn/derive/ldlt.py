"""Unrolled LDL^T factorizations of symmetric positive definite matrices, symbolic.

``M = L diag(d) L^T`` with L unit lower triangular, written out for one matrix of expressions:
every pivot ``d_j``, its reciprocal and every entry of L named in a
:class:`~symdyn.derive.program.ProgramBuilder` as they are made (n divisions in all, no square
root).  Forward dynamics solves ``(D + diag(armature)) qdd = rhs`` with it; task-space dynamics
factors the mass matrix with it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import sympy as sp


@dataclass(frozen=True)
class Factorization:
    """``M = L diag(d) L^T`` of a symmetric n x n ``M``: ``L`` (n x n, unit lower triangular,
    entries named), ``d`` and ``inv`` (the pivots and their reciprocals, named), ``diagonal``
    (``M_jj``, for the run-time check ``d_j > rtol * M_jj``)."""

    L: sp.Matrix
    d: tuple
    inv: tuple
    diagonal: tuple

    @property
    def size(self) -> int:
        return len(self.d)

    @property
    def pivots(self) -> tuple[tuple[sp.Expr, sp.Expr], ...]:
        """``(d_j, M_jj)`` per pivot, in order."""
        return tuple(zip(self.d, self.diagonal))


def factor(b, M: sp.Matrix, hint: str = "ldl", on_zero: Callable[[int], None] | None = None) -> Factorization:
    """The unrolled LDL^T of the symmetric ``M`` (its lower triangle is read), named in ``b`` as
    ``{hint}_d{j}``, ``{hint}_inv{j}``, ``{hint}_L{i}{j}`` (1-based).  ``on_zero(j)`` (0-based) is
    called when pivot j is identically zero (it should raise)."""
    n = M.shape[0]
    L = sp.eye(n)
    d: list[sp.Expr] = []
    inv: list[sp.Expr] = []
    for j in range(n):
        dj = M[j, j] - sp.Add(*[L[j, k] ** 2 * d[k] for k in range(j)])
        if dj == 0 and on_zero is not None:
            on_zero(j)
        d.append(b.define(f"{hint}_d{j + 1}", dj))
        inv.append(b.define(f"{hint}_inv{j + 1}", 1 / d[j]))
        for i in range(j + 1, n):
            lij = (M[i, j] - sp.Add(*[L[i, k] * L[j, k] * d[k] for k in range(j)])) * inv[j]
            L[i, j] = b.define(f"{hint}_L{i + 1}{j + 1}", lij)
    return Factorization(L=L, d=tuple(d), inv=tuple(inv), diagonal=tuple(M[j, j] for j in range(n)))


def forward_substitute(b, f: Factorization, rhs, hint: str) -> list[sp.Expr]:
    """``y`` with ``L y = rhs`` (L unit lower triangular; n entries, named ``{hint}{i}``, 1-based)."""
    L, y = f.L, [sp.S.Zero] * f.size
    for i in range(f.size):
        y[i] = b.define(f"{hint}{i + 1}", rhs[i] - sp.Add(*[L[i, k] * y[k] for k in range(i)]))
    return y


def back_substitute(b, f: Factorization, values, hint: str) -> list[sp.Expr]:
    """``x`` with ``L^T x = values`` (n entries, named ``hint`` with ``{i}`` replaced by the
    1-based row)."""
    L, x = f.L, [sp.S.Zero] * f.size
    for i in reversed(range(f.size)):
        x[i] = b.define(hint.format(i=i + 1), values[i] - sp.Add(*[L[k, i] * x[k] for k in range(i + 1, f.size)]))
    return x


def solve(b, f: Factorization, rhs, forward_hint: str, back_hint: str) -> list[sp.Expr]:
    """``x`` with ``M x = rhs`` (n entries) by forward and back substitution, each entry named
    (``{forward_hint}{i}``, ``{back_hint}`` with ``{i}`` replaced by the 1-based row)."""
    y = forward_substitute(b, f, rhs, forward_hint)
    return back_substitute(b, f, [y[i] * f.inv[i] for i in range(f.size)], back_hint)


@dataclass(frozen=True)
class TreeFactorization:
    """``M = L^T diag(d) L`` of a symmetric n x n ``M`` whose nonzero off-diagonal entries are
    those of joints on one path to the base (a kinematic tree's mass matrix, joints numbered
    so that each comes after its parent): L is unit lower triangular with ``L_ki`` nonzero only
    for ancestors i of k, so the factorization fills in nothing (Featherstone's LTDL, Rigid
    Body Dynamics Algorithms, section 6.5).  ``L`` holds the named entries, ``d``, ``inv`` and
    ``diagonal`` as :class:`Factorization`'s."""

    L: dict
    d: tuple
    inv: tuple
    diagonal: tuple
    parents: tuple

    @property
    def pivots(self) -> tuple[tuple[sp.Expr, sp.Expr], ...]:
        """``(d_j, M_jj)`` per joint j, in joint order."""
        return tuple(zip(self.d, self.diagonal))

    def ancestors(self, k: int):
        i = self.parents[k]
        while i >= 0:
            yield i
            i = self.parents[i]


def factor_tree(b, M: sp.Matrix, parents, hint: str = "ltl",
                on_zero: Callable[[int], None] | None = None) -> TreeFactorization:
    """The unrolled ``L^T D L`` factorization of a tree's symmetric ``M`` (``parents[k]``: joint
    k's parent, -1 for the base, each below its joint), from the last joint to the first; named
    in ``b`` as ``{hint}_d{k}``, ``{hint}_inv{k}``, ``{hint}_L{k}_{i}`` (1-based).
    ``on_zero(k)`` (0-based) is called when pivot k is identically zero (it should raise)."""
    n = M.shape[0]
    work = {(i, j): M[i, j] for i in range(n) for j in range(i + 1)}  # lower triangle, updated
    f = TreeFactorization({}, (), (), tuple(M[j, j] for j in range(n)), tuple(parents))
    d: list = [sp.S.Zero] * n
    inv: list = [sp.S.Zero] * n
    for k in reversed(range(n)):
        if work[k, k] == 0 and on_zero is not None:
            on_zero(k)
        d[k] = b.define(f"{hint}_d{k + 1}", work[k, k])
        inv[k] = b.define(f"{hint}_inv{k + 1}", 1 / d[k])
        path = list(f.ancestors(k))
        for i in path:  # the entry before scaling is named: every update below reuses it
            work[k, i] = b.define(f"{hint}_M{k + 1}_{i + 1}", work[k, i])
            f.L[k, i] = b.define(f"{hint}_L{k + 1}_{i + 1}", work[k, i] * inv[k])
        for pos, i in enumerate(path):  # M_ij -= L_ki d_k L_kj = M_ki L_kj (the entry before scaling)
            for j in path[pos:]:
                work[i, j] = work[i, j] - work[k, i] * f.L[k, j]
    return TreeFactorization(f.L, tuple(d), tuple(inv), f.diagonal, f.parents)


def solve_tree(b, f: TreeFactorization, rhs, forward_hint: str, back_hint: str) -> list[sp.Expr]:
    """``x`` with ``M x = rhs`` for ``M = L^T diag(d) L`` (:func:`factor_tree`): ``L^T y = rhs``
    from the leaves to the base (entries named ``{forward_hint}{i}``), then ``L x = y / d`` from
    the base out (``back_hint`` with ``{i}`` replaced by the 1-based row)."""
    n = len(f.d)
    y = [sp.sympify(v) for v in rhs]
    for k in reversed(range(n)):
        y[k] = b.define(f"{forward_hint}{k + 1}", y[k])
        for i in f.ancestors(k):
            y[i] = y[i] - f.L[k, i] * y[k]
    x: list = [sp.S.Zero] * n
    for k in range(n):
        x[k] = b.define(back_hint.format(i=k + 1),
                        y[k] * f.inv[k] - sp.Add(*[f.L[k, i] * x[i] for i in f.ancestors(k)]))
    return x


def tree_transposed_solve(b, f: TreeFactorization, rhs, hint: str) -> list[sp.Expr]:
    """``y`` with ``L^T y = rhs`` (:func:`factor_tree`'s L, from the leaves to the base: entry k
    reaches k's ancestors only; named ``{hint}{k}``, 1-based)."""
    y = [sp.sympify(v) for v in rhs]
    for k in reversed(range(len(f.d))):
        y[k] = b.define(f"{hint}{k + 1}", y[k])
        for i in f.ancestors(k):
            y[i] = y[i] - f.L[k, i] * y[k]
    return y


def tree_lower_solve(b, f: TreeFactorization, rhs, hint: str) -> list[sp.Expr]:
    """``x`` with ``L x = rhs`` (:func:`factor_tree`'s L, from the base out; named ``{hint}{k}``)."""
    x: list = [sp.S.Zero] * len(f.d)
    for k in range(len(f.d)):
        x[k] = b.define(f"{hint}{k + 1}", rhs[k] - sp.Add(*[f.L[k, i] * x[i] for i in f.ancestors(k)]))
    return x


def inverse_tree(b, f: TreeFactorization, hint: str) -> sp.Matrix:
    """``M^-1`` (n x n, symmetric) of ``M = L^T diag(d) L`` (:func:`factor_tree`) as
    ``L^-1 diag(1/d) L^-T``: ``U = L^-1`` is unit lower triangular with the sparsity of L
    (``U_ik`` nonzero only for ancestors k of i: a tree's L^-1 fills in nothing), so that

        U_ik = -L_ik - sum_m L_im U_mk        (m on the path strictly between k and i)
        (M^-1)_ij = sum_k U_ik (U_jk / d_k)   (k an ancestor, or itself, of both i and j)

    about half the operations of n solves with unit right-hand sides on Solo-12's floating
    base.  ``U_jk / d_k`` named ``{hint}_W{j}_{k}``, the entries ``{hint}{i}_{j}`` (1-based,
    the lower triangle: the upper one is the same symbols)."""
    n = len(f.d)
    chains = [[k, *f.ancestors(k)] for k in range(n)]  # each joint, then its ancestors upward
    U: dict = {}
    W: dict = {}
    for i in range(n):
        U[i, i] = sp.S.One
        path = chains[i]
        for pos in range(1, len(path)):  # ancestors k of i, nearest first
            k = path[pos]
            U[i, k] = b.define(f"{hint}_U{i + 1}_{k + 1}",
                               -f.L[i, k] - sp.Add(*[f.L[i, m] * U[m, k] for m in path[1:pos]]))
        for k in path:
            W[i, k] = f.inv[k] if k == i else b.define(f"{hint}_W{i + 1}_{k + 1}", U[i, k] * f.inv[k])
    Minv = sp.zeros(n, n)
    for i in range(n):
        for j in range(i + 1):
            shared = [k for k in chains[j] if k in set(chains[i])]
            Minv[i, j] = Minv[j, i] = b.define(f"{hint}{i + 1}_{j + 1}", sp.Add(*[U[i, k] * W[j, k] for k in shared]))
    return Minv
