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
"""

from __future__ import annotations

import re
from fractions import Fraction
from typing import Callable

import sympy as sp

_TOKEN = re.compile(
    r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<name>[A-Za-z_][A-Za-z0-9_]*)|(?P<op>\*\*|[-+*/()]))"
)

NAME_PATTERN = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


class ExpressionError(ValueError):
    """The text is not an expression of the allowed grammar."""


def number_to_rational(text: str) -> sp.Rational:
    """Exact rational value of a decimal literal such as ``'0.4318'`` or ``'1e-05'``."""
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
            raise ExpressionError(f"unexpected text '{bad}' in expression '{text}'")
        kind = match.lastgroup
        tokens.append((kind, match.group(kind)))
        pos = match.end()
    return tokens


def parse_expression(text: str, resolve_name: Callable[[str], sp.Expr]) -> sp.Expr:
    """Parse ``text`` into a SymPy expression.

    ``resolve_name(name)`` maps every NAME other than ``pi`` to an expression; it may raise
    ``ExpressionError`` for names it does not accept.
    """
    if not isinstance(text, str):
        raise ExpressionError(f"expected an expression string, got {type(text).__name__}")
    tokens = _tokenize(text)
    if not tokens:
        raise ExpressionError("empty expression")
    pos = 0

    def peek() -> tuple[str, str] | None:
        return tokens[pos] if pos < len(tokens) else None

    def take(value: str | None = None) -> tuple[str, str]:
        nonlocal pos
        tok = peek()
        if tok is None:
            raise ExpressionError(f"expression '{text}' ends too early")
        if value is not None and tok[1] != value:
            raise ExpressionError(f"expected '{value}' but found '{tok[1]}' in expression '{text}'")
        pos += 1
        return tok

    def expr() -> sp.Expr:
        value = term()
        while peek() is not None and peek()[1] in ("+", "-"):
            op = take()[1]
            rhs = term()
            value = value + rhs if op == "+" else value - rhs
        return value

    def term() -> sp.Expr:
        value = unary()
        while peek() is not None and peek()[1] in ("*", "/"):
            op = take()[1]
            rhs = unary()
            if op == "/":
                if rhs == 0:
                    raise ExpressionError(f"division by zero in expression '{text}'")
                value = value / rhs
            else:
                value = value * rhs
        return value

    def unary() -> sp.Expr:
        tok = peek()
        if tok is not None and tok[1] in ("+", "-"):
            take()
            value = unary()
            return -value if tok[1] == "-" else value
        return power()

    def power() -> sp.Expr:
        base = atom()
        tok = peek()
        if tok is not None and tok[1] == "**":
            take()
            exponent = unary()
            if base == 0 and exponent.is_number and exponent.is_negative:
                raise ExpressionError(f"division by zero in expression '{text}'")
            return base**exponent
        return base

    def atom() -> sp.Expr:
        kind, value = take()
        if kind == "num":
            return number_to_rational(value)
        if kind == "name":
            if value == "pi":
                return sp.pi
            return resolve_name(value)
        if value == "(":
            inner = expr()
            take(")")
            return inner
        raise ExpressionError(f"unexpected '{value}' in expression '{text}'")

    result = expr()
    if pos != len(tokens):
        raise ExpressionError(f"unexpected '{tokens[pos][1]}' in expression '{text}'")
    return result
