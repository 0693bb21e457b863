"""A small, safe parser for the numeric expressions allowed in robot files.

Grammar (nothing else is accepted, nothing is ever evaluated as code)::

    expr   := term (('+' | '-') term)*
    term   := unary (('*' | '/') unary)*
    unary  := ('+' | '-') unary | power
    power  := atom ('**' unary)?
    atom   := NUMBER | NAME | '(' expr ')'

NUMBER is a decimal literal (``2``, ``0.4318``, ``1e-05``, ``.5``); it becomes an exact SymPy
Rational so that symbolic identities (for example Lagrange-Euler minus Newton-Euler) cancel
exactly.  NAME is ``pi`` or a parameter name; the caller decides what a name maps to.

Work is bounded whatever the text: at most :data:`MAX_LENGTH` characters, :data:`MAX_DEPTH`
nested parentheses or signs, literals of at most :data:`MAX_LITERAL` characters with a decimal
exponent of magnitude at most :data:`MAX_EXPONENT`; an exponent after ``**`` must be a number of
magnitude at most :data:`MAX_POWER`, and a numeric power whose result would pass 1e300 (or fall
below 1e-300) is refused instead of computed (``9**9**9``, ``10**10**10``).  A result that is
not a finite number or a finite expression (``0**-1``, ``zoo``) is refused.  An expression that
uses earlier parameters is measured on its shared graph, in time linear in it, before anything
walks it: at most :data:`MAX_TREE_NODES` nodes written out as a tree, and at most
:data:`MAX_POLYNOMIAL_TERMS` terms expanded (parameters defined by repeated products of earlier
ones double their size at each step).
"""

from __future__ import annotations

import math
import re
from fractions import Fraction
from typing import Callable

import sympy as sp

_TOKEN = re.compile(
    r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<name>[A-Za-z_][A-Za-z0-9_]*)|(?P<op>\*\*|[-+*/()]))"
)

#: names of parameters (used with ``match``; ``\Z`` so that a trailing newline is not accepted)
NAME_PATTERN = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")

MAX_LENGTH = 1000
MAX_DEPTH = 50
MAX_LITERAL = 64
MAX_EXPONENT = 400
MAX_POWER = 64
#: the most terms a power of a sum may expand to ((a+b+c+d)**64 would be 47,905: minutes and
#: gigabytes once it meets the trigonometry of a derivation)
MAX_EXPANDED_TERMS = 1000
#: the most nodes an expression may stand for once written out as a tree (each use of an earlier
#: parameter copies its expression): counted on the shared graph, in time linear in its size,
#: before anything walks the tree (a chain of 24 parameters p_i = (p_(i-1) + a)*(p_(i-1) - a) is
#: a 1.2 kB file and a tree of 10^8 nodes)
MAX_TREE_NODES = 20000
#: the most terms an expression may expand to as a polynomial in its symbols (a bound from its
#: degree: :func:`expanded_terms_bound`); the derivation multiplies fields together, and a
#: 2-link robot whose fields are polynomials of 153 terms in two runtime parameters ran for
#: minutes, of 561 terms out of 8 GB
MAX_POLYNOMIAL_TERMS = 200
#: the most digits of an exact number in a parsed expression (parameters defined from earlier
#: ones, p2 = p1*p1, ..., double their digits at every step)
MAX_DIGITS = 1000
_LOG10_LIMIT = 300


class ExpressionError(ValueError):
    """The text is not an expression of the allowed grammar."""


def number_to_rational(text: str) -> sp.Rational:
    """Exact rational value of a decimal literal such as ``'0.4318'`` or ``'1e-05'``.

    Raises ``ExpressionError`` for a literal longer than :data:`MAX_LITERAL` characters or with
    a decimal exponent beyond :data:`MAX_EXPONENT` (``1e999999999`` is never expanded)."""
    if len(text) > MAX_LITERAL:
        raise ExpressionError(f"number '{text[:20]}...' is longer than {MAX_LITERAL} characters")
    mantissa, _, exponent = text.lower().partition("e")
    if exponent and abs(int(exponent)) > MAX_EXPONENT:
        raise ExpressionError(f"number '{text}' is out of range (decimal exponent beyond {MAX_EXPONENT})")
    frac = Fraction(text)
    return sp.Rational(frac.numerator, frac.denominator)


def _tokenize(text: str) -> list[tuple[str, str]]:
    tokens: list[tuple[str, str]] = []
    pos = 0
    text = text.rstrip()
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if not match or match.end() == pos:
            bad = text[pos:].strip()[:20]
            hint = " (functions such as sin or sqrt are not allowed: give the value)" if bad[:1] == "(" else ""
            raise ExpressionError(f"unexpected text '{bad}' in expression '{_short(text)}'{hint}")
        kind = match.lastgroup
        tokens.append((kind, match.group(kind)))
        pos = match.end()
    return tokens


def _short(text: str, limit: int = 80) -> str:
    text = " ".join(text.split())
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _check_power(base: sp.Expr, exponent: sp.Expr, text: str) -> None:
    """Refuse a power whose exponent is not a bounded number, or whose numeric result would
    overflow (before computing it)."""
    if not exponent.is_number or exponent.free_symbols or not exponent.is_real:
        raise ExpressionError(f"the exponent after '**' must be a number in expression '{_short(text)}'")
    if abs(exponent) > MAX_POWER:
        raise ExpressionError(f"exponent {float(exponent):g} is larger than {MAX_POWER} in expression '{_short(text)}'")
    if base.free_symbols and exponent.is_integer and abs(exponent) >= 2:
        k, n = len(sp.Add.make_args(sp.expand(base))), int(abs(exponent))
        if k > 1 and math.comb(n + k - 1, k - 1) > MAX_EXPANDED_TERMS:
            raise ExpressionError(f"the power in expression '{_short(text)}' expands to {math.comb(n + k - 1, k - 1)} "
                                  f"terms, more than {MAX_EXPANDED_TERMS}: write it with fewer terms or a smaller exponent")
    if base.is_number and not base.free_symbols:
        if base == 0:
            if exponent.is_negative:
                raise ExpressionError(f"division by zero in expression '{_short(text)}'")
            return
        magnitude = abs(sp.N(base, 15))
        if magnitude.is_number and magnitude != 0:
            scale = float(exponent) * float(sp.log(magnitude, 10).evalf(15))
            if abs(scale) > _LOG10_LIMIT:
                raise ExpressionError(f"the power in expression '{_short(text)}' is out of range (about 1e{scale:.0f})")


def parse_expression(text: str, resolve_name: Callable[[str], sp.Expr]) -> sp.Expr:
    """Parse ``text`` into a SymPy expression.

    ``resolve_name(name)`` maps every NAME other than ``pi`` to an expression; it may raise
    ``ExpressionError`` for names it does not accept.
    """
    if not isinstance(text, str):
        raise ExpressionError(f"expected an expression string, got {type(text).__name__}")
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"expression of {len(text)} characters, more than {MAX_LENGTH}")
    tokens = _tokenize(text)
    if not tokens:
        raise ExpressionError("empty expression")
    parser = _Parser(text, tokens, resolve_name)
    result = parser.expr()
    if parser.pos != len(tokens):
        raise ExpressionError(f"unexpected '{tokens[parser.pos][1]}' in expression '{_short(text)}'")
    if tree_size(result, MAX_TREE_NODES) > MAX_TREE_NODES:
        raise ExpressionError(f"expression '{_short(text)}' stands for more than {MAX_TREE_NODES} terms once the "
                              "parameters it uses are written out (parameters defined from earlier ones, each use a "
                              "copy): give it a value, or declare it a runtime parameter")
    terms = expanded_terms_bound(result)
    if terms > MAX_POLYNOMIAL_TERMS:
        raise ExpressionError(f"expression '{_short(text)}' expands to up to {_count_text(terms)} terms, more than "
                              f"{MAX_POLYNOMIAL_TERMS} (a polynomial of high degree in its runtime parameters, e.g. "
                              "parameters defined by repeated products of earlier ones): give it a value, or declare "
                              "it a runtime parameter")
    if result.has(sp.zoo, sp.oo, -sp.oo, sp.nan, sp.I) or (result.is_number and result.is_extended_real is not True):
        raise ExpressionError(f"expression '{_short(text)}' has no finite real value")
    limit = 10 ** MAX_DIGITS
    if any(abs(r.p) >= limit or r.q >= limit for r in result.atoms(sp.Rational)):
        raise ExpressionError(f"expression '{_short(text)}' makes an exact number of more than {MAX_DIGITS} digits "
                              "(parameters defined by repeated products of earlier ones?): write a decimal value")
    return result


def expanded_terms_bound(expr: sp.Basic) -> int:
    """An upper bound of the terms ``expr`` expands to as a polynomial in its symbols (numerator
    and denominator alike): the monomials of its degree in its symbols, C(degree + s, s); the
    degree is computed once per distinct node (:func:`_fold`; a sum: the largest of its terms';
    a product: the sum; a power: times the exponent's magnitude, rounded up)."""
    symbols = expr.free_symbols
    if not symbols:
        return 1

    def degree(node, args: list[int]) -> int:
        if node.is_Symbol:
            return 1
        if not args or not node.free_symbols:
            return 0
        if node.is_Pow:
            exponent = node.args[1]
            return min(args[0] * (math.ceil(abs(float(exponent))) if exponent.is_number else 64), 10**6)
        if node.is_Mul:
            return min(sum(args), 10**6)
        return max(args)  # a sum, or a function of its arguments
    return math.comb(_fold(expr, degree) + len(symbols), len(symbols))


def _count_text(count: int) -> str:
    return f"{count}" if count < 10**6 else f"1e{len(str(count)) - 1}"


def tree_size(expr: sp.Basic, limit: int) -> int:
    """The nodes of ``expr`` written out as a tree (a shared subexpression counted at each use),
    computed once per distinct node (:func:`_fold`: linear in the graph, not in the tree);
    capped just past ``limit`` (a number above it means "more")."""
    return _fold(expr, lambda node, args: min(1 + sum(args), limit + 1))


def _fold(expr: sp.Basic, combine: Callable[[sp.Basic, list], int]) -> int:
    """``combine(node, [its arguments' values])`` for every distinct node of ``expr``'s graph,
    arguments first (an iterative post-order, memoized per node: time linear in the graph, no
    recursion depth); the value of ``expr``."""
    values: dict[sp.Basic, int] = {}
    stack = [(expr, False)]
    while stack:
        node, expanded = stack.pop()
        if node in values:
            continue
        if node.args and not expanded:
            stack.append((node, True))
            stack.extend((arg, False) for arg in node.args if arg not in values)
            continue
        values[node] = combine(node, [values[arg] for arg in node.args])
    return values[expr]


class _Parser:
    """The recursive-descent parser of :func:`parse_expression` over ``tokens`` (sums, products,
    signs, powers, numbers, names, parentheses; nesting bounded by :data:`MAX_DEPTH`)."""

    def __init__(self, text: str, tokens: list, resolve_name: Callable[[str], sp.Expr]):
        self.text, self.tokens, self.resolve_name = text, tokens, resolve_name
        self.pos = 0
        self.depth = 0

    def nested(self, parse):
        """Run ``parse()`` one nesting level deeper (parentheses, signs, exponents)."""
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise ExpressionError(f"expression nested more than {MAX_DEPTH} levels deep")
        try:
            return parse()
        finally:
            self.depth -= 1

    def peek(self) -> tuple[str, str] | None:
        return self.tokens[self.pos] if self.pos < len(self.tokens) else None

    def take(self, value: str | None = None) -> tuple[str, str]:
        tok = self.peek()
        if tok is None:
            raise ExpressionError(f"expression '{_short(self.text)}' ends too early")
        if value is not None and tok[1] != value:
            raise ExpressionError(f"expected '{value}' but found '{tok[1]}' in expression '{_short(self.text)}'")
        self.pos += 1
        return tok

    def expr(self) -> sp.Expr:
        value = self.term()
        while self.peek() is not None and self.peek()[1] in ("+", "-"):
            op = self.take()[1]
            rhs = self.term()
            value = value + rhs if op == "+" else value - rhs
        return value

    def term(self) -> sp.Expr:
        value = self.unary()
        while self.peek() is not None and self.peek()[1] in ("*", "/"):
            op = self.take()[1]
            rhs = self.unary()
            if op == "/":
                if rhs == 0:
                    raise ExpressionError(f"division by zero in expression '{_short(self.text)}'")
                value = value / rhs
            else:
                value = value * rhs
        return value

    def unary(self) -> sp.Expr:
        tok = self.peek()
        if tok is not None and tok[1] in ("+", "-"):
            self.take()
            value = self.nested(self.unary)
            return -value if tok[1] == "-" else value
        return self.power()

    def power(self) -> sp.Expr:
        base = self.atom()
        tok = self.peek()
        if tok is not None and tok[1] == "**":
            self.take()
            exponent = self.nested(self.unary)
            _check_power(base, exponent, self.text)
            if base.is_number and exponent.is_number and not exponent.is_integer and base.is_extended_negative:
                raise ExpressionError(f"expression '{_short(self.text)}': a negative number to a fractional power "
                                      "has no real value")
            return base**exponent
        return base

    def atom(self) -> sp.Expr:
        kind, value = self.take()
        if kind == "num":
            return number_to_rational(value)
        if kind == "name":
            if self.peek() is not None and self.peek()[1] == "(":
                raise ExpressionError(f"'{value}(...)': functions are not allowed in expression "
                                      f"'{_short(self.text)}' (give the value as a number)")
            if value == "pi":
                return sp.pi
            return self.resolve_name(value)
        if value == "(":
            inner = self.nested(self.expr)
            self.take(")")
            return inner
        raise ExpressionError(f"unexpected '{value}' in expression '{_short(self.text)}'")
