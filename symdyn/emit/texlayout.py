"""Laying out long LaTeX equations of the derivation printouts so that every line fits the page.

:func:`width` estimates the natural width, in TeX points, of a formula in display math as
``sympy.latex`` writes it (Computer Modern at 10 pt: the glyph widths of cmmi10/cmr10 rounded up,
the spaces TeX puts around binary operators and relations, scripts at 80 %, fractions as wide as
their wider part, matrices column by column).  It errs on the wide side, so a line it passes fits.
:func:`break_lines` splits an expression into display lines no wider than a given width: a sum
between its terms, and a term too wide for a line (a product with a long sum, a fraction with a
long numerator) inside its parentheses, as one breaks an equation by hand.
No derivation happens here.
"""

from __future__ import annotations

import re
from typing import Callable

import sympy as sp

#: \textwidth of the LaTeX printout (A4 landscape, 1.5 cm margins: 297 mm - 30 mm), in pt
TEXT_WIDTH = 267 / 25.4 * 72.27
#: the part of it a line may fill (the estimate's own margin of error, and room for the name)
FILL = 0.97

_MU = 10 / 18  # 1 mu at 10 pt
_BIN = 7.78 + 2 * 4 * _MU  # + - \times \pm with medium spaces
_REL = 7.78 + 2 * 5 * _MU  # = < > with thick spaces
_LOWER = dict(zip("abcdefghijklmnopqrstuvwxyz",
                  (5.3, 4.3, 4.4, 5.3, 4.7, 5.0, 4.8, 5.8, 3.5, 4.2, 5.3, 3.0, 8.8, 6.0, 4.9, 5.1, 4.5,
                   4.6, 4.7, 3.7, 5.8, 4.9, 7.2, 5.8, 4.9, 4.7)))
_CHARS = {".": 2.8, ",": 2.8 + 3 * _MU, ";": 2.8 + 3 * _MU, ":": 2.8 + 10 * _MU, "(": 3.9, ")": 3.9,
          "[": 2.8, "]": 2.8, "|": 2.8, "/": 5.0, "'": 2.8, "!": 2.8, "+": _BIN, "-": _BIN, "*": _BIN,
          "=": _REL, "<": _REL, ">": _REL, "~": 3.4, "?": 4.8, "\"": 5.0}
_SPACES = {",": 3 * _MU, ":": 4 * _MU, ";": 5 * _MU, "!": -3 * _MU, " ": 3.4, "quad": 10.0, "qquad": 20.0,
           "{": 5.0, "}": 5.0, "|": 5.0, "\\": 0.0, "&": 7.8, "%": 8.4, "_": 5.0, "#": 8.4, "$": 5.0}
_OPS = {"cdot": 2.8 + 2 * 4 * _MU, "times": _BIN, "pm": _BIN, "mp": _BIN, "circ": 5.0 + 8 * _MU,
        "ldots": 13.4 + 6 * _MU, "cdots": 13.4 + 6 * _MU, "dots": 13.4 + 6 * _MU, "vdots": 2.8,
        "ddots": 13.4, "infty": 10.0, "partial": 5.8, "nabla": 8.4, "leq": _REL, "geq": _REL,
        "neq": _REL, "approx": _REL, "equiv": _REL, "to": _REL, "rightarrow": _REL, "mapsto": _REL,
        "prime": 2.8, "ell": 4.2, "hbar": 5.8, "imath": 3.5, "jmath": 4.2, "wedge": _BIN, "vee": _BIN,
        "cap": _BIN, "cup": _BIN, "in": _REL, "sum": 14.5, "prod": 12.8, "int": 8.4}
_ARGUMENT_ONLY = {"dot", "ddot", "dddot", "bar", "hat", "tilde", "vec", "check", "breve", "acute", "grave",
                  "overline", "underline", "widehat", "widetilde", "mathit", "mathnormal", "mathopen",
                  "mathclose", "mathord", "mathbin", "mathrel"}
_ROMAN = {"mathrm", "text", "textrm", "textit", "mathsf", "mathtt", "texttt", "mathcal", "mathbb",
          "mathfrak", "mathscr", "operatorname"}
_BOLD = {"mathbf", "boldsymbol", "bm", "textbf", "pmb"}
_FUNCTIONS = {"sin", "cos", "tan", "cot", "sec", "csc", "arcsin", "arccos", "arctan", "sinh", "cosh", "tanh",
              "coth", "log", "ln", "exp", "det", "max", "min", "sup", "inf", "lim", "arg", "sgn", "operatorname",
              "atan", "asin", "acos", "dim", "ker", "deg", "gcd", "Pr", "tr"}
_TOKEN = re.compile(r"\\[A-Za-z]+\*?|\\.|[{}^_&]|\\\\|[^\\{}^_&]", re.S)


def _tokens(tex: str) -> list[str]:
    return _TOKEN.findall(tex)


class _Reader:
    """Measures a token list: each method returns the width of what it consumed, in pt."""

    def __init__(self, tokens: list[str]):
        self.tokens = tokens
        self.pos = 0

    def peek(self):
        return self.tokens[self.pos] if self.pos < len(self.tokens) else None

    def take(self):
        token = self.peek()
        self.pos += 1
        return token

    def group_tokens(self) -> list[str]:
        """The tokens of the next argument: a braced group or one token."""
        token = self.take()
        if token != "{":
            return [token] if token is not None else []
        depth, out = 1, []
        while self.peek() is not None:
            token = self.take()
            depth += (token == "{") - (token == "}")
            if depth == 0:
                break
            out.append(token)
        return out

    def argument(self, scale: float, font: str = "") -> float:
        return _measure(self.group_tokens(), scale, font)

    def environment(self, scale: float) -> float:
        name = "".join(self.group_tokens())
        body, depth = [], 1
        while self.peek() is not None:
            token = self.take()
            if token in ("\\begin", "\\end"):
                inner = self.group_tokens()
                depth += 1 if token == "\\begin" else -1
                if depth == 0:
                    break
                body += [token, "{", *inner, "}"]
                continue
            body.append(token)
        rows = _split(body, "\\\\")
        cells = [[_measure(cell, scale) for cell in _split(row, "&")] for row in rows]
        columns = max((len(r) for r in cells), default=0)
        widths = [max((r[c] for r in cells if c < len(r)), default=0.0) for c in range(columns)]
        extra = 2 * 5.0 + 2 * 1.2 if name in ("bmatrix", "pmatrix", "vmatrix", "Bmatrix") else 0.0
        return sum(widths) + 10.0 * max(columns - 1, 0) + extra


def _split(tokens: list[str], separator: str) -> list[list[str]]:
    """``tokens`` split at ``separator`` outside braces and nested environments."""
    parts, current, depth = [], [], 0
    for token in tokens:
        depth += (token in ("{", "\\begin")) - (token in ("}", "\\end"))
        if token == separator and depth == 0:
            parts.append(current)
            current = []
            continue
        current.append(token)
    parts.append(current)
    return parts


def _measure(tokens: list[str], scale: float = 1.0, font: str = "") -> float:
    """The width of a token list at ``scale`` (1 text size, 0.7 script, 0.5 scriptscript) in
    ``font`` ('' math italic, 'roman', 'bold')."""
    reader = _Reader(tokens)
    total = 0.0
    last_script = None  # (kind, width) of a script just set: a second one stacks over it
    while reader.peek() is not None:
        token = reader.take()
        script = None
        if token in ("^", "_"):
            w = reader.argument(max(scale * 0.8, 0.65), font) + 0.5
            if last_script is not None and last_script[0] != token:
                total += max(0.0, w - last_script[1])
                last_script = None
            else:
                total += w
                script = (token, w)
            last_script = script
            continue
        last_script = None
        if token == "{":
            reader.pos -= 1
            total += reader.argument(scale, font)
        elif token == "}" or token == "&" or token.isspace():
            continue
        elif token.startswith("\\"):
            total += _command(token[1:], reader, scale, font)
        elif token.islower() and token.isascii():
            total += (5.6 if font == "roman" else 6.4 if font == "bold" else _LOWER[token]) * scale
        elif token.isupper() and token.isascii():
            total += (8.6 if font != "bold" else 9.9) * scale
        elif token.isdigit():
            total += (5.0 if font != "bold" else 5.8) * scale
        else:
            total += _CHARS.get(token, 8.0) * scale
    return total


def _command(name: str, reader: _Reader, scale: float, font: str) -> float:
    if name in ("left", "right", "bigl", "bigr", "Bigl", "Bigr", "biggl", "biggr", "big", "Big", "bigg", "Bigg"):
        delimiter = reader.take()
        return 1.2 * scale if delimiter == "." else 6.7 * scale
    if name == "frac" or name == "dfrac" or name == "tfrac":
        inner = scale if scale >= 1.0 and name != "tfrac" else max(scale * 0.7, 0.5)
        return max(reader.argument(inner, font), reader.argument(inner, font)) + 2.4 * scale
    if name == "sqrt":
        if reader.peek() == "[":
            while reader.peek() not in (None, "]"):
                reader.take()
            reader.take()
        return reader.argument(scale, font) + 8.4 * scale
    if name == "begin":
        return reader.environment(scale)
    if name in ("end", "displaystyle", "textstyle", "limits", "nolimits", "mathstrut", "strut", "phantom",
                "label", "nonumber", "notag"):
        if name in ("end", "phantom", "label"):
            reader.argument(scale)
        return 0.0
    if name in _ARGUMENT_ONLY:
        return reader.argument(scale, font)
    if name in _BOLD:
        return reader.argument(scale, "bold")
    if name in _ROMAN:
        width = reader.argument(scale, "roman")
        return width + (3 * _MU * scale if name == "operatorname" else 0.0)
    if name in _FUNCTIONS:
        return (5.0 * len(name) + 3 * _MU) * scale
    if name in _OPS:
        return _OPS[name] * scale
    if len(name) == 1 and not name.isalpha():
        return _SPACES.get(name, 5.0) * scale
    if name in _SPACES:
        return _SPACES[name] * scale
    # Greek and other symbols
    return (8.4 if name[:1].isupper() else 6.5) * scale


def width(tex: str) -> float:
    """Estimated natural width, in pt, of ``tex`` set in display math (10 pt Computer Modern);
    an upper bound for what ``sympy.latex`` writes."""
    return _measure(_tokens(tex))


def _signed(text: str, first: bool) -> str:
    """A term's LaTeX as a summand: ``- x`` or ``+ x`` after the first."""
    if first:
        return text
    return "- " + text[1:].lstrip() if text.startswith("-") else "+ " + text


def break_lines(expr, available: float, latex: Callable[[sp.Basic], str], first: float | None = None) -> list[str]:
    """``expr`` as LaTeX display lines each at most ``available`` pt wide (the first at most
    ``first``, default ``available``): a sum split between terms, packed greedily; a term wider
    than a line split inside its parentheses (:func:`_break_term`; a parenthesis open at the end
    of a line is closed there by ``\\right.`` and reopened by ``\\left.``).  A part that cannot be
    split (a long single factor) stays on a line of its own."""
    first = available if first is None else first
    text = latex(expr)
    if width(text) <= first:
        return [text]
    lines: list[str] = []
    current: list[str] = []
    current_width, depth, start_depth = 0.0, 0, 0
    for piece, delta in _pieces(expr, available, latex):
        w = width(piece)
        limit = (first if not lines else available) - 1.2 * (depth + max(depth + delta, 0))
        if current and current_width + w > limit:
            lines.append(" ".join(["\\left." * start_depth] + current + ["\\right." * depth]).strip())
            current, current_width, start_depth = [], 0.0, depth
        current.append(piece)
        current_width += w
        depth += delta
    lines.append(" ".join(["\\left." * start_depth] + current + ["\\right." * depth]).strip())
    return lines


def _pieces(expr, available: float, latex) -> list[tuple[str, int]]:
    """The unbreakable pieces of ``expr`` in order (with their signs), each at most one line
    wide where possible: the terms of a sum; the parts of a term too wide for a line.  Each with
    the parentheses it opens (1) or closes (-1)."""
    terms = expr.as_ordered_terms() if isinstance(expr, sp.Add) else [expr]
    pieces: list[tuple[str, int]] = []
    for k, term in enumerate(terms):
        text = _signed(latex(term), k == 0)
        if width(text) <= available:
            pieces.append((text, 0))
            continue
        parts = _break_term(term, available, latex)
        if parts is None:
            pieces.append((text, 0))
            continue
        if k > 0:
            parts[0] = (_signed(parts[0][0], False), parts[0][1])
        pieces.extend(parts)
    return pieces


def _break_term(term, available: float, latex) -> list[tuple[str, int]] | None:
    """A product or fraction too wide for a line as pieces: its other factors and an opening
    parenthesis with the first piece of its widest sum, the other pieces of that sum, and the
    closing parenthesis (a fraction as the reciprocal of its denominator times its numerator).
    None when there is no sum to open."""
    numerator, denominator = sp.fraction(term)
    if denominator != 1:
        head = f"\\frac{{1}}{{{latex(denominator)}}}"
        if numerator.is_Add:
            return _parenthesized(head, _pieces(numerator, available, latex))
        inner = _break_term(numerator, available, latex)
        if inner is None:
            return None
        return [(head + " " + inner[0][0], inner[0][1])] + inner[1:]
    factors = sp.Mul.make_args(term)
    sums = [f for f in factors if f.is_Add]
    if not sums:
        return None
    widest = max(sums, key=lambda f: width(latex(f)))
    coeff = sp.Mul(*[f for f in factors if f is not widest])
    head = "" if coeff == 1 else "-" if coeff == -1 else latex(coeff)
    return _parenthesized(head, _pieces(widest, available, latex))


def _parenthesized(head: str, inner: list[tuple[str, int]]) -> list[tuple[str, int]]:
    """``head ( inner... )`` as pieces."""
    opening = (f"{head} \\left(".strip() + " " + inner[0][0], 1 + inner[0][1])
    return [opening] + inner[1:] + [("\\right)", -1)]
