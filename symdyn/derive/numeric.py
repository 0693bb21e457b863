"""Numeric evaluation of derived equations in Python (double precision, via ``math``).

The straight-line program is translated once into a Python function per output; symbols are
renamed to ``v0, v1, ...`` so that no name from a robot file ever appears in the source, and the
source contains nothing but arithmetic on those variables.
"""

from __future__ import annotations

import math
from typing import Sequence

import mpmath
import numpy as np
import sympy as sp
from sympy.printing.pycode import MpmathPrinter, PythonCodePrinter

from ..model.outputs import OUTPUT_INPUTS, SPECS


class _Printer(PythonCodePrinter):
    def _print_sign(self, expr):
        arg = self._print(expr.args[0])
        return f"(({arg} > 0) - ({arg} < 0))"


class _PrecisePrinter(MpmathPrinter):
    def _print_sign(self, expr):
        arg = self._print(expr.args[0])
        return f"(({arg} > 0) - ({arg} < 0))"


def compile_function(inputs: Sequence[Sequence[sp.Symbol]], program, outputs: sp.MatrixBase, name: str = "f",
                     digits: int | None = None):
    """A Python function ``f(*arrays) -> numpy array`` evaluating ``outputs`` (shape kept).

    With ``digits``, the function computes in mpmath at that many significant digits (the
    robot's numbers taken exactly as written) and returns a list of rows of ``mpmath.mpf``;
    its arguments may then be lists of ``mpmath.mpf`` too (taken as they are, not rounded to
    doubles: central differences in 50 digits step by 1e-20)."""
    rename: dict[sp.Symbol, sp.Symbol] = {}
    counter = 0

    def fresh(sym):
        nonlocal counter
        new = sp.Symbol(f"v{counter}", real=True)
        counter += 1
        rename[sym] = new
        return new

    lines = [f"def {name}(" + ", ".join(f"a{k}" for k in range(len(inputs))) + "):"]
    for k, group in enumerate(inputs):
        for j, sym in enumerate(group):
            lines.append(f"    {fresh(sym)} = a{k}[{j}]")
    printer = (_Printer if digits is None else _PrecisePrinter)({"fully_qualified_modules": True})
    for sym, rhs in program.needed_for(list(outputs)):
        expr = rhs.xreplace(rename)
        lines.append(f"    {fresh(sym)} = {printer.doprint(expr)}")
    rows, cols = outputs.shape
    cells = [[printer.doprint(sp.sympify(outputs[r, c]).xreplace(rename)) for c in range(cols)] for r in range(rows)]
    lines.append("    return [" + ", ".join("[" + ", ".join(row) + "]" for row in cells) + "]")
    namespace = {"math": math, "mpmath": mpmath}
    exec(compile("\n".join(lines), f"<symdyn {name}>", "exec"), namespace)  # our own arithmetic only
    raw = namespace[name]
    if digits is not None:
        def entries(array):
            if isinstance(array, list) and all(isinstance(x, mpmath.mpf) for x in array):
                return list(array)
            return [mpmath.mpf(float(x)) for x in np.asarray(array, dtype=float).ravel()]

        def precise(*arrays):
            with mpmath.workdps(digits):
                return raw(*[entries(a) for a in arrays])
        return precise

    def wrapped(*arrays):
        return np.array(raw(*[np.asarray(a, dtype=float).ravel().tolist() for a in arrays]), dtype=float)
    return wrapped


class NumericEquations:
    """Numeric functions of an :class:`~symdyn.derive.equations.Equations`.

    Each method takes numpy arrays of length n (``p`` of length ``len(parameters)`` when the
    robot has runtime parameters) and returns numpy arrays: vectors of shape (n,), matrices
    (n, n).
    """

    def __init__(self, eqs):
        self.eqs = eqs
        self._cache = {}

    def _function(self, name):
        if name not in self._cache:
            groups = [getattr(self.eqs, arg) for arg in OUTPUT_INPUTS[name]] + [self.eqs.parameters]
            self._cache[name] = compile_function(groups, self.eqs.program, self.eqs.output(name), name)
        return self._cache[name]

    def _call(self, name, args, p, matrix: bool = False):
        """Check the arguments and evaluate ``name``; a one-column result is returned as a vector
        unless ``matrix``."""
        m = len(self.eqs.parameters)
        for label, value in zip(OUTPUT_INPUTS[name], args):
            size, n = np.size(value), len(getattr(self.eqs, label))
            if size != n:
                raise ValueError(f"{name}: {label} has {size} entries, expected {n} "
                                 f"({'one per joint' if n == self.eqs.robot.dof else 'as the header lays out'})")
        if m and (p is None or np.size(p) != m):
            given = "none" if p is None else f"{np.size(p)}"
            raise ValueError(f"{name}: p has {given} entries, expected {m} "
                             f"({', '.join(s.name for s in self.eqs.parameters)})")
        if not m and p is not None and np.size(p):
            raise ValueError(f"{name}: this robot has no runtime parameters, but p has {np.size(p)} entries")
        if self.eqs.robot.floating:
            args = [_scaled_quaternion(a) if label in ("q", "q1") else a for label, a in zip(OUTPUT_INPUTS[name], args)]
        out = self._function(name)(*args, p if p is not None else [])
        return out[:, 0] if out.shape[1] == 1 and not matrix else out


def _scaled_quaternion(q) -> np.ndarray:
    """A floating base's configuration with its quaternion (entries 3-6) divided by its largest
    magnitude, as the generated C does: any nonzero scale, subnormal to 1e308, gives the same
    rotation (a zero quaternion gives NaN)."""
    q = np.array(q, dtype=float).reshape(-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        q[3:7] = q[3:7] / np.max(np.abs(q[3:7]))
    return q


def _numeric_method(spec):
    """``NumericEquations.<output>(*inputs, p=None)`` for one registered output."""
    def method(self, *args, p=None):
        if len(args) == len(spec.inputs) + 1 and p is None:  # p given by position
            *args, p = args
        if len(args) != len(spec.inputs):
            raise TypeError(f"{spec.name} takes {', '.join(spec.inputs)}[, p]")
        return self._call(spec.name, tuple(args), p, matrix=not spec.is_vector)
    method.__name__ = spec.name
    rows = "(n,)" if spec.shape_text == "N" else f"({spec.shape_text.replace(' x ', ', ')})"
    method.__doc__ = f"{spec.summary} Arguments {', '.join(spec.inputs)}[, p]; returns {rows} ({spec.units})."
    return method


for _spec in SPECS:
    setattr(NumericEquations, _spec.name, _numeric_method(_spec))
