"""Helpers shared by every emitter (C, CasADi, printouts); no derivation happens here."""

from __future__ import annotations

import jinja2
import sympy as sp


def fold_constants(expr: sp.Expr, digits: int = 30) -> sp.Expr:
    """Replace every symbol-free, non-rational subexpression (cos(2/5), sqrt(3)/2, pi/4) by a
    Float of ``digits`` digits, so emitted code has no constant function calls."""
    def is_const(e):
        return (e.is_number and not e.is_Rational and not e.is_Float and not e.is_Atom) or e is sp.pi
    return expr.replace(is_const, lambda e: sp.Float(sp.N(e, digits), digits))


def template_environment() -> jinja2.Environment:
    """The Jinja2 environment of the shipped templates (``symdyn.templates``), StrictUndefined."""
    from importlib.resources import files
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(files("symdyn.templates"))),
        undefined=jinja2.StrictUndefined, keep_trailing_newline=True,
        trim_blocks=True, lstrip_blocks=True, autoescape=False)
