"""Printouts of robots with decimal numbers (URDF, robots/*.yaml): numbers as decimals of the stated
significant digits that are the exact values rounded, no long integers (the exact rationals of
a URDF's decimals), and LaTeX whose every line fits the page (pdflatex's overfull boxes)."""

from __future__ import annotations

import math
import re
import shutil
import subprocess

import numpy as np
import pytest
import sympy as sp

from helpers import REPO
from symdyn.derive.derivation import derive_steps
from symdyn.emit import texlayout
from symdyn.emit.printout import DEFAULT_DIGITS, render, shown
from symdyn.model.scene import load_input

HANDMADE = REPO / "tests" / "data" / "urdf" / "handmade.urdf"
BRANCHING = REPO / "tests" / "data" / "urdf" / "branching.urdf"
LONG_INTEGER = re.compile(r"\d{13,}")
_DERIVED: dict = {}


def steps_of(path, method="newton-euler", tip=None, steps="all"):
    key = (str(path), method, tip, steps)
    if key not in _DERIVED:
        robot, _ = load_input(str(path), tip)
        _DERIVED[key] = derive_steps(robot, method, steps)
    return _DERIVED[key]


def _body(text: str) -> str:
    """The printout without its header's sha256 (hex digits)."""
    return "\n".join(line for line in text.splitlines() if "sha256" not in line)


def _close_to_digits(printed: float, exact, digits: int) -> bool:
    """``printed`` is ``exact`` rounded to ``digits`` significant digits (half an ulp of them)."""
    exact = float(sp.N(exact, 40))
    if exact == 0:
        return printed == 0
    ulp = 10.0 ** (math.floor(math.log10(abs(exact))) - digits + 1)
    return abs(printed - exact) <= 0.5 * ulp * (1 + 1e-9)


def _significant(number: str) -> int:
    mantissa = number.lower().split("e")[0].lstrip("-+").replace(".", "").lstrip("0")
    return len(mantissa.rstrip("0")) if "." in number.split("e")[0] else len(mantissa)


_SUBSCRIPT = str.maketrans("₀₁₂₃₄₅₆₇₈₉", "0123456789")
_TERM = re.compile(r"\s*([-+])?\s*(\d+(?:\.\d*)?(?:e[-+]?\d+)?)⋅(x[₀-₉]+)")


def _where_coefficients(text: str, derivation):
    """(printed number text, exact value) of every numeric coefficient of a one-line
    intermediate ``x_k = c⋅x_j + ...`` of a text printout."""
    where = {str(s): sp.expand(rhs) for s, rhs in derivation.where}
    out = []
    for line in text.splitlines():
        match = re.fullmatch(r"(x[₀-₉]+) = (.*)", line)
        if not match or "↪" in line:  # not a line the printer wrapped
            continue
        rhs = where[match.group(1).translate(_SUBSCRIPT).replace("x", "x_")]
        for term in _TERM.finditer(match.group(2)):
            sign, number, name = term.groups()
            coefficient = rhs.coeff(sp.Symbol(name.translate(_SUBSCRIPT).replace("x", "x_"), real=True))
            if coefficient.is_number:
                out.append(((sign or "") + number, coefficient))
    return out


@pytest.mark.parametrize("digits", [DEFAULT_DIGITS, 3])
def test_printed_numbers_are_the_exact_values_rounded(digits):
    """handmade.urdf (6 joints, named form): every numeric coefficient of the intermediate
    quantities x_k and the link table's centres of mass, parsed back, is the exact value rounded
    to the digits the header states."""
    d = steps_of(HANDMADE)
    text = render(d, "text", digits=digits)
    assert f"decimals rounded to {digits} significant digits" in text.splitlines()[5]
    assert not LONG_INTEGER.search(_body(text))
    pairs = _where_coefficients(text, d)
    assert len(pairs) > 100
    for number, exact in pairs:
        assert _close_to_digits(float(number), exact, digits), (number, exact)
        assert _significant(number) <= digits, number
    rows = [line for line in text.splitlines() if re.match(r"\d\s+(revolute|prismatic)", line)]
    assert len(rows) == 6
    for row, link in zip(rows, d.robot.links):
        com = re.search(r"\(([^()]*)\)$", row).group(1).split(", ")
        for number, exact in zip(com, link.com):
            assert _close_to_digits(float(number), exact, digits), (number, exact)


def test_closed_form_prints_no_long_integers():
    """Two joints of handmade.urdf in closed form: the collected coefficients used to print as
    ``1.0e-17 q̈₁ (-7.00805e+14 c₂ ... + 1920457385540143)``; the factor now goes into the sum,
    and the printed D(q) agrees with the exact one to the digits shown."""
    d = steps_of(HANDMADE, tip="link2")
    for fmt in ("text", "latex", "markdown"):
        body = _body(render(d, fmt))
        assert not LONG_INTEGER.search(body), LONG_INTEGER.search(body)
        assert not re.search(r"1\.0e-\d\d|10\^\{-1\d\}", body)
    exact = d.to_joint_symbols(d.quantity("D"))
    printed = d.to_joint_symbols(shown(d.quantity("D")))
    q = sorted(exact.free_symbols | printed.free_symbols, key=str)
    f_exact, f_printed = sp.lambdify(q, exact), sp.lambdify(q, printed)
    for point in np.random.default_rng(3).uniform(-2, 2, (5, len(q))):
        a, b = np.array(f_exact(*point), float), np.array(f_printed(*point), float)
        np.testing.assert_allclose(b, a, rtol=2e-5, atol=2e-5 * np.abs(a).max())


ROBOT_FILES = sorted(str(p.relative_to(REPO)) for p in (REPO / "robots").glob("*.yaml"))


@pytest.mark.parametrize("path", ROBOT_FILES + ["tests/data/urdf/handmade.urdf", "tests/data/urdf/branching.urdf"])
def test_no_long_integers_in_any_printout(path):
    tip = "tcp" if "branching" in path else None
    steps = "summary" if "chain12" in path else "all"
    d = steps_of(REPO / path, tip=tip, steps=steps)
    for fmt in ("text", "latex"):
        body = _body(render(d, fmt))
        assert not LONG_INTEGER.search(body), (fmt, LONG_INTEGER.search(body))


def test_small_rationals_and_pi_stay_exact_and_integers_stay_integers():
    x = sp.Symbol("x")
    assert shown(sp.pi / 2 * x) == sp.pi / 2 * x
    assert shown(sp.Integer(12345678) * x) == 12345678 * x
    big = shown(sp.Integer(10) ** 20 + 7)
    assert big.is_Float and abs(float(big) - 1e20) < 1e15
    value = shown(sp.Rational(1, 10 ** 24) * x * (sp.Integer(2264478143158287783995) * sp.sin(x) + 1))
    assert not LONG_INTEGER.search(str(value)) and "0.00226448" in str(value)
    assert shown(sp.Rational(2159, 5000) * x, 3) == sp.Float("0.432", 8) * x


def _overfull(tex: str, tmp_path, name: str = "doc") -> list[str]:
    """pdflatex's overfull-box warnings for the document ``tex`` (compiled in ``tmp_path``)."""
    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex not installed (apt-get install texlive-latex-base texlive-latex-extra)")
    (tmp_path / f"{name}.tex").write_text(tex)
    result = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", f"{name}.tex"],
                            cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout[-2000:]
    log = (tmp_path / f"{name}.log").read_text(errors="replace")
    return re.findall(r"Overfull \\hbox.*", log)


@pytest.mark.parametrize("method,tip", [("newton-euler", None), ("lagrange-euler", "link2"),
                                        ("newton-euler", "link2"), ("articulated-body", None)])
def test_latex_lines_fit_the_page(tmp_path, method, tip):
    """A URDF robot with long terms: every line of the LaTeX printout fits the page."""
    assert _overfull(render(steps_of(HANDMADE, method, tip), "latex"), tmp_path) == []


def _document(body: str) -> str:
    return ("\\documentclass[10pt]{article}\n\\usepackage[a4paper,landscape,margin=1.5cm]{geometry}\n"
            "\\usepackage{amsmath,amssymb}\n\\setcounter{MaxMatrixCols}{20}\n\\begin{document}\n"
            + body + "\n\\end{document}\n")


def test_long_terms_break_inside_their_parentheses(tmp_path):
    """A product with a sum of 60 terms, a fraction with a long numerator, a sum of such
    products: broken into lines no wider than the page, each line's parentheses balanced."""
    xs = sp.symbols("x_1:61", real=True)
    q1, q2, d = sp.symbols("q_1 q_2 d", real=True)
    long_sum = sum(sp.Rational(k * 7919 % 1000 + 1, 1000) * x * q2 for k, x in enumerate(xs))
    cases = [q1 * long_sum, long_sum / d, q1 * long_sum - q2 ** 2 * long_sum.subs(q2, q1) + sp.sin(q1)]
    body = []
    for value in cases:
        lines = texlayout.break_lines(shown(value), 500.0, sp.latex)
        assert len(lines) > 3
        for line in lines:
            assert texlayout.width(line) <= 500.0
            assert line.count("\\left") == line.count("\\right")
        body.append("\\begin{align*}\nv ={}& " + " \\\\\n&".join(lines) + "\n\\end{align*}")
    assert _overfull(_document("\n".join(body)), tmp_path) == []


def test_width_estimate_is_an_upper_bound(tmp_path):
    """texlayout.width against TeX's own measure of formulas as the printouts write them."""
    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex not installed (apt-get install texlive-latex-base texlive-latex-extra)")
    text = render(steps_of(HANDMADE, tip="link2"), "latex") + render(steps_of(HANDMADE, "articulated-body"), "latex")
    formulas = sorted({m.group(1) for m in re.finditer(r"^\\\[ (.*) \\\]$", text, re.M)}, key=len)[-60:]
    formulas += [r"\frac{\bar{I}^{A}_{4,23} \bar{a}'_{4,wy}}{d_{4}}", r"x_{1460} = x_{1000} x_{277} - x_{1001} x_{260}",
                 r"\left[\begin{matrix}0.608842 c_{3}\\x_{62}\\x_{59}\end{matrix}\right]"]
    lines = [r"\newlength\w"] + [r"\settowidth{\w}{$\displaystyle %s$}\typeout{WIDTH %d \the\w}" % (f, k)
                                 for k, f in enumerate(formulas)]
    (tmp_path / "w.tex").write_text(_document("\n".join(lines)).replace("\\begin{document}\n\\newlength\\w",
                                                                        "\\newlength\\w\n\\begin{document}"))
    subprocess.run(["pdflatex", "-interaction=nonstopmode", "w.tex"], cwd=tmp_path, capture_output=True, timeout=120)
    measured = {int(k): float(w) for k, w in re.findall(r"WIDTH (\d+) ([\d.]+)pt", (tmp_path / "w.log").read_text())}
    assert len(measured) == len(formulas)
    for k, formula in enumerate(formulas):
        assert measured[k] <= texlayout.width(formula) / texlayout.FILL, (formula, measured[k], texlayout.width(formula))
