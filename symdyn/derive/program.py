"""Straight-line symbolic programs: ordered assignments of intermediate symbols.

Derivations build their recursions with intermediate symbols as they go (as in Khalil's
customized Newton-Euler), so that 6-7 joint robots derive in seconds and the generated code
stays small.  A :class:`Program` is the immutable result: ``assignments`` in evaluation order,
each right-hand side using only inputs and earlier symbols.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Sequence

import sympy as sp


def is_trivial(expr: sp.Expr) -> bool:
    """Whether ``expr`` is cheap enough to inline instead of naming it (atom or -atom)."""
    if expr.is_Atom:
        return True
    if expr.is_Mul and len(expr.args) == 2 and expr.args[0] == -1 and expr.args[1].is_Atom:
        return True
    return expr.is_number and not expr.has(sp.Function)  # e.g. sqrt(2)/2


@dataclass(frozen=True)
class Program:
    """Assignments ``(symbol, expression)`` in evaluation order."""

    assignments: tuple[tuple[sp.Symbol, sp.Expr], ...] = ()

    @property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(s for s, _ in self.assignments)

    def needed_for(self, exprs: Iterable[sp.Expr], leaves: frozenset = frozenset()) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
        """The assignments the given expressions depend on, in order (dead code removed); the
        symbols in ``leaves`` are taken as given (neither they nor what only they need are kept)."""
        needed: set[sp.Symbol] = set()
        for e in exprs:
            needed |= sp.sympify(e).free_symbols
        needed -= leaves
        kept = []
        for sym, rhs in reversed(self.assignments):
            if sym in needed:
                kept.append((sym, rhs))
                needed |= rhs.free_symbols - leaves
        return tuple(reversed(kept))

    def expansion(self, exprs: Iterable[sp.Expr] | None = None) -> dict[sp.Symbol, sp.Expr]:
        """Map each needed intermediate symbol to its expression in the inputs only."""
        full: dict[sp.Symbol, sp.Expr] = {}
        source = self.assignments if exprs is None else self.needed_for(exprs)
        for sym, rhs in source:
            full[sym] = rhs.xreplace(full)
        return full

    def expand(self, expr):
        """``expr`` (expression or matrix) with every intermediate symbol substituted away."""
        if isinstance(expr, sp.MatrixBase):
            full = self.expansion(list(expr))
            return expr.applyfunc(lambda e: e.xreplace(full))
        return sp.sympify(expr).xreplace(self.expansion([expr]))

    def __add__(self, other: "Program") -> "Program":
        seen = {s for s, _ in self.assignments}
        extra = tuple(a for a in other.assignments if a[0] not in seen)
        return Program(self.assignments + extra)


class ProgramBuilder:
    """Collects assignments; identical right-hand sides share one symbol (hash-consing)."""

    def __init__(self, prefix: str = "_x", start: Program | None = None):
        self.prefix = prefix
        self._assignments: list[tuple[sp.Symbol, sp.Expr]] = list(start.assignments) if start else []
        self._by_expr: dict[sp.Expr, sp.Symbol] = {rhs: s for s, rhs in self._assignments}
        self._names: set[str] = {s.name for s, _ in self._assignments}

    def define(self, hint: str, expr: sp.Expr, force: bool = False) -> sp.Expr:
        """Name ``expr`` with a new intermediate symbol unless it is trivial or already named
        (``force``: always a new symbol, even for a trivial or already named expression)."""
        expr = sp.sympify(expr)
        if force:
            return self._new_symbol(hint, expr)
        if is_trivial(expr):
            return expr
        if expr in self._by_expr:
            return self._by_expr[expr]
        neg = -expr
        if neg in self._by_expr:
            return -self._by_expr[neg]
        return self._new_symbol(hint, expr)

    def _new_symbol(self, hint: str, expr: sp.Expr) -> sp.Symbol:
        name = f"{self.prefix}{hint}"
        if name in self._names:
            k = 2
            while f"{name}_{k}" in self._names:
                k += 1
            name = f"{name}_{k}"
        sym = sp.Symbol(name, real=True)
        self._names.add(name)
        self._by_expr.setdefault(expr, sym)
        self._assignments.append((sym, expr))
        return sym

    def vector(self, hint: str, exprs: Sequence[sp.Expr]) -> sp.Matrix:
        return sp.Matrix([self.define(f"{hint}_{k}", e) for k, e in enumerate(exprs)])

    def matrix(self, hint: str, mat: sp.MatrixBase) -> sp.Matrix:
        rows, cols = mat.shape
        return sp.Matrix(rows, cols, lambda r, c: self.define(f"{hint}_{r}{c}", mat[r, c]))

    def build(self) -> Program:
        return Program(tuple(self._assignments))


def partial_derivative(expr: sp.Expr, s: sp.Symbol) -> sp.Expr:
    """d expr / d s for the sums, products and integer powers the recursions are made of (the
    product rule written out: SymPy's general ``diff`` spends most of its time on dispatch and
    checks these expressions never need); anything else goes to ``sp.diff``."""
    if expr == s:
        return sp.S.One
    if expr.is_Atom or s not in expr.free_symbols:
        return sp.S.Zero
    if expr.is_Add:
        return sp.Add(*[partial_derivative(a, s) for a in expr.args if s in a.free_symbols])
    if expr.is_Mul:
        args = expr.args
        terms = []
        for k, a in enumerate(args):
            if s in a.free_symbols:
                terms.append(sp.Mul(*args[:k], partial_derivative(a, s), *args[k + 1:]))
        return sp.Add(*terms)
    if expr.is_Pow and expr.exp.is_Integer and s not in expr.exp.free_symbols:
        return expr.exp * expr.base ** (expr.exp - 1) * partial_derivative(expr.base, s)
    return sp.diff(expr, s)


def differentiate(program: Program, outputs: sp.MatrixBase, variables: Sequence[sp.Symbol],
                  builder: ProgramBuilder, hint: str, scale: sp.Expr = sp.S.One,
                  held: frozenset = frozenset()) -> list[sp.Matrix]:
    """Forward-mode derivatives of ``outputs`` with respect to each of ``variables``, times
    ``scale``.

    The chain rule runs through the program's intermediate symbols; new intermediate symbols
    for the derivatives are added to ``builder``.  Returns one matrix (shape of ``outputs``)
    per variable.  ``scale`` is the variable's own derivative (d x / d x), so a constant factor folds
    into the recursion's constants instead of costing one multiplication per result (C = dh/dqd
    / 2 with ``scale=1/2``; a power of two leaves every rounding unchanged).  The program's
    symbols in ``held`` are held constant: partial derivatives at fixed values of them (the
    accelerations of the forward-dynamics derivatives, dtau/dq at fixed qdd).
    """
    results = []
    needed = program.needed_for(list(outputs), held)
    free = [rhs.free_symbols for _, rhs in needed]  # once for every variable
    # the program's own sin/cos of a variable: d cos(x)/dx is minus the symbol of sin(x), not a
    # new call (a joint angle's c_i, s_i)
    trig = {rhs: sym for sym, rhs in needed if isinstance(rhs, (sp.sin, sp.cos))}
    for var in variables:
        deriv: dict[sp.Symbol, sp.Expr] = {}

        def d(expr: sp.Expr, symbols=None) -> sp.Expr:
            symbols = expr.free_symbols if symbols is None else symbols
            terms = [partial_derivative(expr, var) * scale] if var in symbols else []
            for s in symbols:
                ds = deriv.get(s)
                if ds is not None and ds != 0:
                    terms.append(partial_derivative(expr, s) * ds)
            return sp.Add(*terms)

        for (sym, rhs), symbols in zip(needed, free):
            if var not in symbols and deriv.keys().isdisjoint(symbols):
                continue  # does not depend on var: no SymPy call (most of the chain for a distal joint)
            if isinstance(rhs, (sp.sin, sp.cos)) and rhs.args[0].free_symbols == {var}:
                rate = partial_derivative(rhs.args[0], var)  # 1, or a mimic joint's multiplier
                if rate.is_number:
                    other = (sp.sin if isinstance(rhs, sp.cos) else sp.cos)(rhs.args[0])
                    value = trig.get(other, other)
                    deriv[sym] = (-value if isinstance(rhs, sp.cos) else value) * rate * scale
                    continue
            ds = d(rhs, symbols)
            if ds != 0:
                deriv[sym] = builder.define(f"{hint}{sym.name.lstrip('_')}_d{var.name}", ds)
        results.append(outputs.applyfunc(lambda e: builder.define(f"{hint}out_d{var.name}", d(e)) if not e.is_Atom else d(e)))
    return results
