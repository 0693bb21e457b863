"""Property test of the one C printer (:class:`symdyn.emit.cprinter.CPrinter`): random SymPy
expressions -- nested negations, negative constants, products and quotients of sums, functions
of constants, powers, constants near 0 and 1e+-300 -- printed, compiled and evaluated agree with
SymPy's own evaluation in 50 digits, in double and float, plain and with the fused multiply-add
macros (defined as the plain sums here, so the printed expression tree is what is checked).

The tolerance of each expression is relative to its *magnitude*: the value it would have with
every sum replaced by the sum of its terms' magnitudes (the rounding a correct evaluation may
make in cancelling sums).  A sign or precedence fault changes a value by a term's magnitude and
is found at once; a constant left unfolded is found by the check that the printed text calls no
function of a constant.
"""

from __future__ import annotations

import ctypes
import math
import random
import re
import shutil
import subprocess

import mpmath
import pytest
import sympy as sp

from symdyn.emit.cprinter import CPrinter
from symdyn.model.errors import SymdynError

X = sp.symbols("x0:4", real=True)
NAMES = {s: f"x[{k}]" for k, s in enumerate(X)}
CASES = 400
SEED = 20261128
CONSTANTS = [sp.Integer(3), sp.Integer(-2), sp.Rational(-3, 7), sp.Rational(5, 2), sp.Float(0.25), sp.Float(-1.75),
             sp.Float(1.5707963267948966), sp.Float(1e-300), sp.Float(-3e-290), sp.Float(1e300), sp.Float(-2e295),
             sp.Float(1e-12), sp.pi, sp.cos(sp.Float(1.5707963267948966)), sp.sin(sp.Float(2.064540186490215)),
             -sp.cos(sp.Rational(2, 5)), sp.sqrt(2) / 2, sp.cos(2) - sp.Rational(1, 3)]


def _leaf(rng: random.Random) -> sp.Expr:
    return rng.choice(X) if rng.random() < 0.6 else rng.choice(CONSTANTS)


def random_expression(rng: random.Random, depth: int) -> sp.Expr:
    """A random real expression of the kinds derivations produce (no division by a value that
    can be 0: denominators are squares plus a positive constant, roots of positive values)."""
    if depth <= 0 or rng.random() < 0.2:
        return _leaf(rng)
    a = random_expression(rng, depth - 1)
    b = random_expression(rng, depth - 1)
    kind = rng.randrange(13)
    if kind == 0:
        return a + b
    if kind == 1:
        return a - b
    if kind == 2:
        return a * b
    if kind == 3:
        return -a
    if kind == 4:
        return sp.Mul(-1, a - b, evaluate=False)  # -(a - b) kept as written
    if kind == 5:
        return a / (b**2 + rng.choice([sp.Rational(1, 2), sp.Integer(3)]))
    if kind == 6:
        return sp.sin(a)
    if kind == 7:
        return sp.cos(a) * b
    if kind == 8:
        return a ** rng.choice([2, 3, -1, -2, 7])  if not a.is_number else a * b
    if kind == 9:
        return sp.sqrt(a**2 + 1)
    if kind == 10:
        return sp.sign(a) * b
    if kind == 11:
        return sp.Add(a, sp.Mul(-1, b, evaluate=False), evaluate=False)
    return rng.choice([-1, 1]) * (a * b + rng.choice(CONSTANTS))


def magnitude(expr: sp.Expr, values: dict, seen: list | None = None) -> mpmath.mpf:
    """The value of ``expr`` with every sum taken over its terms' magnitudes (see the module
    docstring): the scale of the rounding a correct evaluation may make.  ``seen`` collects
    the magnitude of every subexpression (an intermediate beyond the precision's range is
    skipped: any finite printer overflows there)."""
    seen = [] if seen is None else seen
    if expr.is_Add:
        out = sum((magnitude(a, values, seen) for a in expr.args), mpmath.mpf(0))
    elif expr.is_Mul:
        out = mpmath.mpf(1)
        for a in expr.args:
            out *= magnitude(a, values, seen)
    elif expr.is_Pow and expr.exp.is_number and expr.exp < 0:
        base = abs(mpmath.mpf(sp.N(expr.base.subs(values), 50)))
        power = abs(float(expr.exp))
        out = (magnitude(expr.base, values, seen) / base) ** power / base ** power if base else mpmath.inf
    elif expr.is_Pow:
        out = magnitude(expr.base, values, seen) ** float(expr.exp)
    elif isinstance(expr, (sp.sin, sp.cos)):
        out = 1 + magnitude(expr.args[0], values, seen)
    elif isinstance(expr, sp.sign):
        magnitude(expr.args[0], values, seen)
        out = mpmath.mpf(1)
    else:
        out = abs(mpmath.mpf(sp.N(expr.subs(values), 50)))
    seen.append(out)
    return out


def _compile(tmp_path, name: str, source: str):
    c = tmp_path / f"{name}.c"
    c.write_text(source)
    lib = tmp_path / f"{name}.so"
    built = subprocess.run(["cc", "-std=c99", "-O1", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-fno-fast-math",
                    "-ffp-contract=off", "-shared", "-fPIC", str(c), "-o", str(lib), "-lm"],
                           capture_output=True, text=True)
    assert built.returncode == 0, built.stderr[:3000]
    return ctypes.CDLL(str(lib))


@pytest.fixture(scope="module")
def expressions():
    rng = random.Random(SEED)
    return [random_expression(rng, rng.randrange(2, 6)) for _ in range(CASES)]


UNFOLDED = re.compile(r"\b(sin|cos|sqrt|sinf|cosf|sqrtf|pow|powf)\(\s*-?[0-9.][0-9.eE+-]*F?\s*[,)]")


@pytest.mark.parametrize("precision,fma", [("double", ""), ("double", "T_FMA"), ("float", ""), ("float", "T_FMA")])
def test_printed_expressions_evaluate_as_sympy(tmp_path, expressions, precision, fma):
    if shutil.which("cc") is None:
        pytest.skip("no C compiler")
    real = "float" if precision == "float" else "double"
    limit = 3.4e38 if precision == "float" else 1.7e308
    printed, skipped = [], 0
    for k, expr in enumerate(expressions):
        try:
            text = CPrinter(NAMES, precision, fma=fma).doprint(expr)
        except SymdynError:  # a folded constant beyond the precision's range: refused, as it must be
            value = mpmath.mpf(abs(sp.N(expr.subs({s: 1 for s in X}), 30))) if expr.is_number else None
            assert value is None or value > limit or any(
                abs(float(sp.N(c, 30))) > limit for c in expr.atoms(sp.Float, sp.Mul) if c.is_number), (
                f"refused a printable constant: {expr}")
            skipped += 1
            continue
        assert not UNFOLDED.search(text), f"a function of a constant left for run time: {text}"
        assert "--" not in text.replace(" ", ""), f"a doubled sign: {text}"
        printed.append((k, expr, text))
    macros = (f"#define T_FMA(a, b, c) ((c) + (a)*(b))\n#define T_FMA_NEG(a, b, c) ((c) - (a)*(b))\n")
    source = "#include <math.h>\n" + macros + "".join(
        f"{real} f{k}(const {real} *x) {{ (void)x; return {text}; }}\n" for k, _, text in printed)
    lib = _compile(tmp_path, f"printed_{precision}_{bool(fma)}", source)
    rng = random.Random(SEED + 1)
    ctype = ctypes.c_float if precision == "float" else ctypes.c_double
    rtol = 2e-5 if precision == "float" else 1e-12
    checked = 0
    for k, expr, text in printed:
        function = getattr(lib, f"f{k}")
        function.restype = ctype
        function.argtypes = [ctypes.POINTER(ctype)]
        for _ in range(3):
            point = [rng.uniform(-2.0, 2.0) for _ in X]
            values = {s: sp.Float(v, 50) for s, v in zip(X, point)}
            if precision == "float":
                values = {s: sp.Float(float(ctypes.c_float(v).value), 50) for s, v in zip(X, point)}
            exact = sp.N(expr.subs(values), 50)
            if not exact.is_real or not exact.is_finite:
                continue
            seen: list = []
            scale = magnitude(expr, values, seen)
            if not all(mpmath.isfinite(m) and m < limit / 1e6 for m in seen):
                continue  # beyond the precision's range on the way: any finite printer overflows
            got = function((ctype * len(X))(*[float(values[s]) for s in X]))
            bound = rtol * float(scale) + (1e-35 if precision == "float" else 1e-290)
            assert math.isfinite(got) and abs(got - float(exact)) <= bound, (
                f"{expr}\nprinted: {text}\nat {point}: C {got!r}, SymPy {float(exact)!r}, bound {bound:.3g}")
            checked += 1
    assert checked > CASES, f"only {checked} evaluations compared ({skipped} expressions refused)"
