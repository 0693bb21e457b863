"""Helpers shared by the subcommands."""

from __future__ import annotations

from ..derive.equations import METHOD_ALIASES, OUTPUTS
from ..model.errors import SymdynError


def parse_functions(text: str | None) -> tuple[str, ...]:
    if not text:
        return OUTPUTS
    names = [t.strip() for t in text.split(",") if t.strip()]
    unknown = [n for n in names if n not in OUTPUTS]
    if unknown:
        raise SymdynError(f"unknown function '{unknown[0]}' in --functions (known: {', '.join(OUTPUTS)})")
    if not names:
        raise SymdynError("--functions lists no function")
    return tuple(n for n in OUTPUTS if n in names)


def add_method_option(parser) -> None:
    parser.add_argument("--method", default="newton-euler", choices=sorted(set(METHOD_ALIASES)),
                        help="derivation: newton-euler (default; recursive, smallest code) or lagrange-euler")
