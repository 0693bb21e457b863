"""Vector forward-mode derivatives of a straight-line program: one tangent vector per
intermediate symbol, over every direction of a group of variables at once.

:func:`symdyn.derive.program.differentiate` writes one derivative statement per intermediate
symbol *and* variable: n times the statements of the recursion, straight-line.  Past a few
thousand statements that code is larger than the instruction cache and runs at half the speed
per operation (iiwa14, the Panda: docs/benchmarks.md, "Derivatives of the dynamics").  Here each
intermediate ``x = f(s_1, ..., s_k)`` of the program gets one tangent vector over the group's
directions,

    T_x[j] = sum_s (d f / d s) T_s[j]        (+ d f / d v_j where f reads the variable v_j itself)

so that the code is one short loop per statement, its size linear in the statements whatever
the number of directions, and each loop is what a compiler vectorizes.  The partials
``d f / d s`` are scalar expressions in the program's symbols, computed once for every
direction.  A tangent that is a factor times another one is not stored (``x = -y``, ``x = 2 y``,
``x = a y``: the factor goes into the partials that read x, one scalar product each instead of
a loop: the Panda's 435 loops 392, 699 -> 683 ns); a tangent that is nonzero in one
direction only (a function of one joint angle: its sine, cosine) is no vector either, but a
value added at that direction where it is read.

The result is a description (:class:`VectorTangents`), not code: emitters lay it out as loops
(:mod:`symdyn.emit.cbody`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import sympy as sp

from .program import Program, partial_derivative


@dataclass(frozen=True)
class TangentStep:
    """``T[target][j] = sum(coefficient * T[source][j]) for (source, coefficient) in terms``
    for every direction j of ``group``, then ``T[target][d] += value`` for each ``(d, value)`` of
    ``direct``.  Coefficients and values are expressions in the program's symbols (or numbers)."""

    group: int
    target: int
    terms: tuple[tuple[int, sp.Expr], ...]
    direct: tuple[tuple[int, sp.Expr], ...]


@dataclass(frozen=True)
class VectorTangents:
    """The tangents of some outputs of a program over the directions of one or more groups of
    variables (e.g. the joint positions, then the velocities).

    ``directions``: the size of the largest group; ``steps`` in evaluation order (each reads
    tangents of earlier steps only; a tangent id is written once); ``rows[g][i]``: the tangent
    id holding d output_i / d (group g's variables), or None where output i does not depend on
    them (a zero row)."""

    directions: int
    steps: tuple[TangentStep, ...]
    rows: tuple[tuple[int | None, ...], ...]

    def steps_of(self, groups) -> tuple[TangentStep, ...]:
        """The steps of the given groups only, in order."""
        wanted = set(groups)
        return tuple(s for s in self.steps if s.group in wanted)

    def coefficients(self, groups) -> tuple[sp.Expr, ...]:
        """Every coefficient and direct value the steps of ``groups`` read, each once, in order of
        first use."""
        seen: dict[sp.Expr, None] = {}
        for step in self.steps_of(groups):
            for _, value in step.terms + step.direct:
                seen.setdefault(value, None)
        return tuple(seen)


def _trig_partial(rhs, s, trig: Mapping[sp.Expr, sp.Symbol]):
    """d sin(u)/ds and d cos(u)/ds with the program's own symbol of the other function of the
    same argument where it has one (a joint angle's c_i, s_i); None for any other expression."""
    if not isinstance(rhs, (sp.sin, sp.cos)):
        return None
    u = rhs.args[0]
    du = partial_derivative(u, s)
    if du == 0:
        return sp.S.Zero
    other = sp.sin(u) if isinstance(rhs, sp.cos) else sp.cos(u)
    value = trig.get(other, other)
    return (-value if isinstance(rhs, sp.cos) else value) * du


def _local_partial(rhs, s, trig) -> sp.Expr:
    """d rhs / d s, one statement's own partial derivative."""
    p = _trig_partial(rhs, s, trig)
    return partial_derivative(rhs, s) if p is None else p


def vector_tangents(program: Program, outputs: Sequence[sp.Expr], groups: Sequence[Sequence[sp.Symbol]],
                    held: frozenset = frozenset(), row_direct: Mapping[tuple[int, int, int], sp.Expr] = {}) -> VectorTangents:
    """The tangents of ``outputs`` (expressions in the program's symbols) over each group of
    variables of ``groups`` (group g, direction j: the variable ``groups[g][j]``).  The
    program's symbols in ``held`` are held constant (their tangents are zero: partial
    derivatives at fixed values of them).  ``row_direct[(g, i, j)]``: a value added to
    d output_i / d groups[g][j] (viscous damping's diagonal)."""
    outputs = [sp.sympify(e) for e in outputs]
    needed = program.needed_for(outputs, held)
    trig = {rhs: sym for sym, rhs in needed if isinstance(rhs, (sp.sin, sp.cos))}
    # per group: symbol -> ("vector", id, factor): its tangent is factor times stored tangent id;
    # ("direct", direction, value): it is value in that direction and zero in the others
    kinds: list[dict] = [{v: ("direct", j, sp.S.One) for j, v in enumerate(group)} for group in groups]
    steps: list[TangentStep] = []
    rows: list[list[int | None]] = [[None] * len(outputs) for _ in groups]
    count = [0]

    def resolve(g, s, factor):
        """(("vector", id) or ("direct", direction), factor) that s's tangent times factor is."""
        kind, index, own = kinds[g][s]
        return (kind, index), factor * own

    def contributions(g, rhs):
        vector: dict[int, sp.Expr] = {}
        direct: dict[int, sp.Expr] = {}
        for s in sorted(rhs.free_symbols, key=lambda x: x.name):
            if s not in kinds[g]:
                continue
            p = _local_partial(rhs, s, trig)
            if p == 0:
                continue
            (kind, index), factor = resolve(g, s, p)
            into = vector if kind == "vector" else direct
            into[index] = into.get(index, sp.S.Zero) + factor
        return ({k: v for k, v in vector.items() if v != 0}, {k: v for k, v in direct.items() if v != 0})

    def new_step(g, vector, direct) -> int:
        target, count[0] = count[0], count[0] + 1
        steps.append(TangentStep(g, target, tuple(vector.items()), tuple(sorted(direct.items()))))
        return target

    for sym, rhs in needed:
        for g in range(len(groups)):
            vector, direct = contributions(g, rhs)
            if not vector and not direct:
                continue
            if not direct and len(vector) == 1:
                source, factor = next(iter(vector.items()))
                kinds[g][sym] = ("vector", source, factor)
                continue
            if not vector and len(direct) == 1:
                direction, value = next(iter(direct.items()))
                kinds[g][sym] = ("direct", direction, value)
                continue
            kinds[g][sym] = ("vector", new_step(g, vector, direct), sp.S.One)
    for i, e in enumerate(outputs):
        for g in range(len(groups)):
            vector, direct = contributions(g, e)
            for (gg, row, j), value in row_direct.items():
                if gg == g and row == i and value != 0:
                    direct[j] = direct.get(j, sp.S.Zero) + value
            if vector or direct:
                rows[g][i] = new_step(g, vector, direct)
    width = max((len(group) for group in groups), default=0)
    return VectorTangents(width, tuple(steps), tuple(tuple(r) for r in rows))

