"""Printing SymPy expressions as C99 for generated code (double or float), and counting the
operations the printed code performs.

- integer powers become products (``x*x``), ``x**-1`` a division, ``x**(1/2)`` ``sqrt``;
- every number is a floating literal of the chosen precision (``0.5`` or ``0.5F``): no integer
  division can happen, and floats never promote to double;
- ``sign(x)`` becomes the branch-free ``((x > 0) - (x < 0))``;
- a ``Piecewise`` (the series branches of the configuration-space functions) becomes nested
  conditional expressions ``(c ? a : b)`` on one line, a comparison named alone an ``int``;
- ``sin/cos/sqrt`` are ``sinf/cosf/sqrtf`` in float precision.
"""

from __future__ import annotations

import math
from collections import Counter

import sympy as sp
from sympy.printing.c import C99CodePrinter

from ..model.errors import SymdynError
from .emission import fold_constants  # noqa: F401 (re-exported)

PRECISIONS = ("double", "float")


class VectorUnsupported(Exception):
    """An expression the vector (batch) form cannot print; the batch function then loops over
    the scalar one."""


class CPrinter(C99CodePrinter):
    """C99 printer with symdyn's conventions (see module docstring)."""

    def __init__(self, names: dict[sp.Symbol, str], precision: str = "double", vector_prefix: str = "", fma: str = ""):
        super().__init__()
        #: the fused multiply-add macro (symdyn.emit.cbody.fma_macro) sums of products are
        #: printed with, or "" for plain sums
        self.fma = fma
        #: sin/cos already computed (in the block at the top of a function): expression -> C name
        self.trig: dict[sp.Expr, str] = {}
        #: print for the lanes of a batch function (GCC/Clang vector types of ``PREFIX_vreal``):
        #: sin, cos, sqrt and sign become the lane-wise helpers ``PREFIX_v<name>``
        self.vector_prefix = vector_prefix
        #: the lane-wise helpers the printed code calls
        self.vector_functions: set[str] = set()
        if precision not in PRECISIONS:
            raise ValueError(f"precision must be double or float, not {precision!r}")
        self.names = names
        self.precision = precision
        self.suffix = "F" if precision == "float" else ""
        self.real = "float" if precision == "float" else "double"

    def doprint(self, expr, assign_to=None):
        """The C of ``expr`` with its constant subexpressions (``cos(1.5707963267948966)``,
        ``sqrt(2)/2``) folded to literals first: every code path prints through here, so no
        function of a constant is left for run time."""
        if isinstance(expr, sp.Basic):
            expr = fold_constants(expr)
        return super().doprint(expr, assign_to)

    def literal(self, value) -> str:
        """A floating literal of ``value``; a value that is not finite in the chosen precision
        (a product of huge masses and lengths, a division by zero) is a :class:`SymdynError`."""
        try:
            number = float(value)
        except (OverflowError, TypeError, ValueError):
            number = float("nan")
        limit = 3.4028234663852886e38 if self.precision == "float" else 1.7976931348623157e308
        if not math.isfinite(number) or abs(number) > limit:
            raise SymdynError(f"a constant of the equations is not finite in {self.precision} precision "
                              f"({'about ' + format(number, '.3g') if math.isfinite(number) else 'infinite or undefined'}): "
                              "check the magnitudes of the masses, lengths and gravity")
        tiny = 7.006492321624085e-46 if self.precision == "float" else 2.4703282292062328e-324
        if abs(number) <= tiny:  # rounds to zero in this precision: say so, not a literal that warns
            number = 0.0
        text = repr(number)
        if "e" not in text and "." not in text and "inf" not in text:
            text += ".0"
        return text + self.suffix

    # Add and Mul are printed in SymPy's canonical argument order (no re-sorting of terms and
    # factors, no rebuilt expressions: the generic printers' ordering and sign handling took most
    # of the emission time on long chains); numbers are literals of the chosen precision.
    def _print_Add(self, expr, order=None):
        terms = []
        for term in expr.args:
            text = self._print(term)
            if term.is_Add:  # an unevaluated sum inside a sum: its own sign stays inside
                negative, text = False, f"({text})"
            else:  # a leading "-" of a product, power, number or call negates the whole term
                negative = text.startswith("-")
                if negative:
                    text = text[1:]
            split = _last_factor(text) if self.fma and terms else None
            terms.append((negative, *split) if split else (negative, "", text))
        return fused_sum(terms, self.fma)

    def _print_Mul(self, expr):
        coeff, rest = expr.as_coeff_Mul()
        sign = ""
        if coeff.is_Number and coeff < 0:
            sign, coeff = "-", -coeff
        numerator, denominator = [], []
        if coeff != 1:
            numerator.append(coeff)
        for factor in sp.Mul.make_args(rest):
            if factor.is_Pow and factor.exp.is_Rational and factor.exp.is_negative:
                denominator.append(factor.base if factor.exp == -1 else sp.Pow(factor.base, -factor.exp, evaluate=False))
            else:
                numerator.append(factor)
        if not numerator:
            numerator = [sp.S.One]
        mul = sp.printing.precedence.PRECEDENCE["Mul"]
        text = "*".join(self.parenthesize(f, mul) if not (f.is_Pow and f.exp.is_Integer and f.exp > 0)
                        else self._print(f) for f in numerator)
        if sign and len(numerator) == 1 and numerator[0].is_Add:
            text = f"({self._print(numerator[0])})"
        if not denominator:
            return sign + text
        dens = [self.parenthesize(f, mul) if not (f.is_Pow and f.exp.is_Integer and f.exp > 0) else self._print(f)
                for f in denominator]
        if len(dens) == 1 and not (denominator[0].is_Pow and denominator[0].exp.is_Integer and denominator[0].exp > 1):
            return f"{sign}{text}/{dens[0]}"
        return f"{sign}{text}/({'*'.join(dens)})"

    def _print_Symbol(self, expr):
        if expr in self.names:
            return self.names[expr]
        raise KeyError(f"no C name for symbol {expr}")

    def _print_Rational(self, expr):
        return self.literal(expr)

    def _print_Integer(self, expr):
        return self.literal(expr)

    def _print_Float(self, expr):
        return self.literal(expr)

    def _print_not_finite(self, expr):
        raise SymdynError("the equations contain an infinite or undefined value (a division by zero "
                          "in the robot's numbers?): check the masses, inertias and lengths")

    _print_Infinity = _print_NegativeInfinity = _print_ComplexInfinity = _print_NaN = _print_not_finite

    def _print_Pi(self, expr):
        return self.literal(sp.pi.evalf(20))

    def _vector(self, name, expr):
        self.vector_functions.add(name)
        return f"{self.vector_prefix}_v{name}({self._print(expr.args[0])})"

    def _print_sign(self, expr):
        if self.vector_prefix:
            return self._vector("sign", expr)
        arg = self._print(expr.args[0])
        return f"(({self.real})(({arg} > 0) - ({arg} < 0)))"

    def _fn(self, name, expr):
        if expr in self.trig:
            return self.trig[expr]
        if self.vector_prefix:
            return self._vector(name, expr)
        suffix = "f" if self.precision == "float" else ""
        return f"{name}{suffix}({self._print(expr.args[0])})"

    def _print_sin(self, expr):
        return self._fn("sin", expr)

    def _print_Abs(self, expr):
        return self._fn("fabs", expr)

    def _print_cos(self, expr):
        return self._fn("cos", expr)

    def _print_atan2(self, expr):
        if self.vector_prefix:
            raise VectorUnsupported("atan2")
        suffix = "f" if self.precision == "float" else ""
        return f"atan2{suffix}({self._print(expr.args[0])}, {self._print(expr.args[1])})"

    def _print_Piecewise(self, expr):
        """A branch as nested conditional expressions on one line: ``(c1 ? a : (c2 ? b : d))``
        (the last piece's condition is True); only the chosen branch is evaluated."""
        if self.vector_prefix:
            raise VectorUnsupported("a branch (Piecewise)")
        if expr.args[-1].cond != sp.true:
            raise ValueError("a Piecewise without a default branch")
        text = self._print(expr.args[-1].expr)
        for value, condition in reversed(expr.args[:-1]):
            text = f"({self._print(condition)} ? {self._print(value)} : {text})"
        return text

    def _print_Relational(self, expr):
        if self.vector_prefix:
            raise VectorUnsupported("a comparison")
        return super()._print_Relational(expr)

    def _print_Pow(self, expr):
        base, exp = expr.args
        if exp.is_Integer:
            k = int(exp)
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"] + 1)
            if 1 <= k <= 6:
                return "*".join([b] * k)
            if -6 <= k <= -1:
                den = "*".join([b] * (-k))
                return f"{self.literal(1)}/({den})" if -k > 1 else f"{self.literal(1)}/{b}"
        if exp == sp.S.Half:
            return self._fn("sqrt", sp.sqrt(base))
        if exp == -sp.S.Half:
            return f"{self.literal(1)}/{self._fn('sqrt', sp.sqrt(base))}"
        suffix = "f" if self.precision == "float" else ""
        if self.vector_prefix:
            raise VectorUnsupported("pow")
        return f"pow{suffix}({self._print(base)}, {self._print(exp)})"


def fused_sum(terms, fma: str = "") -> str:
    """The C of a sum, left to right, of the terms ``(negative, head, operand)``, each
    ``head*operand`` (``operand`` alone where ``head`` is "") or its opposite: with a fused
    multiply-add macro ``fma`` each product after the first is added as ``fma(head, operand,
    sum)``, or subtracted as ``fma_NEG(head, operand, sum)`` (templates/fma.j2), which with the
    macros as ``c + a*b`` and ``c - a*b`` is the plain sum, the same expression tree (gcc -O2
    gave ``(-a)*b + c`` more spills: the 24-joint chain's Coriolis matrix 4755 -> 5450 ns)."""
    text = ""
    for negative, head, operand in terms:
        product = f"{head}*{operand}" if head else operand
        if not text:
            text = f"-{product}" if negative else product
        elif head and fma:
            text = f"{fma}{'_NEG' if negative else ''}({head}, {operand}, {text})"
        else:
            text = f"{text} {'-' if negative else '+'} {product}"
    return text


def _last_factor(term: str):
    """``(head, last)`` where the printed product ``term`` is ``head*last`` (C's left-to-right
    ``*``: the last operand at parenthesis depth 0), or None for a term that is no such product
    (one operand, or a division at depth 0)."""
    depth, cut = 0, -1
    for k, ch in enumerate(term):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif depth == 0 and ch == "/":
            return None
        elif depth == 0 and ch == "*":
            cut = k
    return None if cut < 0 else (term[:cut], term[cut + 1:])


def count_operations(expr: sp.Expr) -> Counter:
    """Operations of the printed expression: ``add`` (additions and subtractions), ``mul``,
    ``div``, ``trig`` (sin/cos), ``sqrt`` and ``other`` (sign, pow)."""
    ops: Counter = Counter()

    def visit(e):
        if e.is_Atom:
            return
        if e.is_Add:
            ops["add"] += len(e.args) - 1
        elif e.is_Mul:
            factors = [a for a in e.args if not (a.is_Number and abs(a) == 1)]
            dens = [a for a in factors if a.is_Pow and a.exp.is_number and a.exp.is_negative]
            nums = len(factors) - len(dens)
            ops["mul"] += max(nums - 1, 0)
            ops["div"] += len(dens)
            for d in dens:
                k = -d.exp
                if k.is_Integer and k > 1:
                    ops["mul"] += int(k) - 1
                visit(d.base)
            for f in factors:
                if f not in dens:
                    visit(f)
            return
        elif e.is_Pow:
            k = e.exp
            if k.is_Integer and 1 <= k <= 6:
                ops["mul"] += int(k) - 1
            elif k.is_Integer and -6 <= k <= -1:
                ops["div"] += 1
                ops["mul"] += int(-k) - 1
            elif abs(k) == sp.S.Half:
                ops["sqrt"] += 1
                ops["div"] += 1 if k < 0 else 0
            else:
                ops["other"] += 1
            visit(e.base)
            return
        elif isinstance(e, (sp.sin, sp.cos)):
            ops["trig"] += 1
        elif isinstance(e, sp.Piecewise):  # the condition, and the longer branch
            branches = [count_operations(value) for value, _ in e.args]
            longest: Counter = Counter()
            for branch in branches:
                longest |= branch
            ops.update(longest)
            for _, condition in e.args:
                visit(condition)
            return
        elif isinstance(e, sp.core.relational.Relational):
            ops["other"] += 1
        else:
            ops["other"] += 1
        for a in e.args:
            visit(a)

    visit(expr)
    return ops
