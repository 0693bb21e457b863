"""Symbolic identities: Lagrange-Euler = Newton-Euler exactly; planar2r textbook closed forms."""

import numpy as np
import pytest
import sympy as sp

import symdyn
from helpers import ROBOTS, robot_path

OUTPUTS = ("mass_matrix", "coriolis", "coriolis_matrix", "gravity", "inverse_dynamics")


def trig_polynomial(eqs, exprs):
    """Expand intermediates keeping each angle's (cos, sin) as a pair of polynomial variables.

    Returns the expanded expressions and the list of (c, s) pairs.  Joint angles keep their
    trig symbols (_c_i, _s_i of theta_i + q_i); constant angles (alpha) get a pair of their own."""
    import re
    full = {}
    pairs = {}
    for sym, rhs in eqs.program.needed_for(exprs):
        joint = re.fullmatch(r"_([cs])(\d+)", sym.name)
        if joint:  # the chain's cos/sin(theta_i + q_i), however they are computed
            angle = sp.Symbol(f"theta{joint.group(2)}+q{joint.group(2)}")
            c, s_ = pairs.setdefault(angle, (sp.Symbol(f"cos({angle})"), sp.Symbol(f"sin({angle})")))
            full[sym] = c if joint.group(1) == "c" else s_
        elif isinstance(rhs, (sp.cos, sp.sin)) and rhs.args[0].free_symbols & set(eqs.q):
            c, s_ = pairs.setdefault(rhs.args[0], (sp.Symbol(f"cos({rhs.args[0]})"), sp.Symbol(f"sin({rhs.args[0]})")))
            full[sym] = c if isinstance(rhs, sp.cos) else s_
        else:
            full[sym] = rhs.xreplace(full)
    out = [sp.sympify(e).xreplace(full) for e in exprs]
    const = {}
    for f in set().union(*(e.atoms(sp.sin, sp.cos) for e in out)):
        c, s_ = pairs.setdefault(f.args[0], (sp.Symbol(f"cos({f.args[0]})"), sp.Symbol(f"sin({f.args[0]})")))
        const[f] = c if isinstance(f, sp.cos) else s_
    return [e.xreplace(const) for e in out], list(pairs.values())


def is_exactly_zero(expr, pairs) -> bool:
    """Exact test: the polynomial's normal form modulo {c^2 + s^2 - 1} is zero.  The pairs share
    no variables, so R[c, s]/(c^2 + s^2 - 1) = R[s] + c R[s]: rewriting every c^k (k >= 2) as
    c^(k-2) (1 - s^2) until each c appears at most linearly gives that normal form."""
    cosine_of = {c: s_ for c, s_ in pairs}

    def reducible(x):
        return x.is_Pow and x.base in cosine_of and x.exp.is_Integer and x.exp >= 2

    def reduce(x):
        k = int(x.exp)
        return x.base ** (k % 2) * (1 - cosine_of[x.base] ** 2) ** (k // 2)
    return sp.expand(sp.expand(expr).replace(reducible, reduce)) == 0


@pytest.mark.parametrize("method", ["lagrange-euler", "jacobian-newton-euler"])
@pytest.mark.parametrize("name", ["planar2r", "three_standard"])  # modified DH: planar2r (suite time)
def test_method_minus_newton_euler_is_exactly_zero(derived, name, method):
    """Lagrange-Euler and the Jacobian-projected Newton-Euler minus the recursive Newton-Euler
    vanish exactly (as trig polynomials modulo c^2 + s^2 = 1), every output but the forward
    dynamics (a quotient: it follows from D, h and c)."""
    ne, other = derived(name, "newton-euler"), derived(name, method)
    for output in OUTPUTS:
        a, b = ne.output(output), other.output(output)
        ea, pairs_a = trig_polynomial(ne, list(a))
        eb, pairs_b = trig_polynomial(other, list(b))
        pairs = list(dict.fromkeys(pairs_a + pairs_b))
        for x, y in zip(ea, eb):
            assert is_exactly_zero(x - y, pairs), f"{name} {output}: {method} - NE does not vanish"


def test_exact_check_detects_a_difference(derived):
    ne = derived("three_standard")
    [x], pairs = trig_polynomial(ne, [ne.mass_matrix[0, 0]])
    assert x != 0
    assert not is_exactly_zero(x * (1 + sp.Rational(1, 10**9)) - x, pairs)
    c, s_ = pairs[0]
    assert is_exactly_zero(x * (c**2 + s_**2) - x, pairs)


@pytest.mark.parametrize("name", [r for r in ROBOTS if r != "chain12"])  # chain12's LE: D and c only,
def test_methods_agree_numerically(derived, name):                       # tests/check/test_pinocchio_agreement.py
    ne, le = derived(name, "newton-euler"), derived(name, "lagrange-euler")
    rng = np.random.default_rng(3)
    p = rng.uniform(0.5, 1.5, len(ne.parameters))
    for _ in range(5):
        q, qd, qdd = rng.uniform(-2, 2, (3, ne.n))
        for fn, args in (("mass_matrix", (q,)), ("coriolis_matrix", (q, qd)), ("gravity", (q,)),
                         ("inverse_dynamics", (q, qd, qdd))):
            a = getattr(ne.numeric, fn)(*args, p)
            b = getattr(le.numeric, fn)(*args, p)
            assert np.allclose(a, b, rtol=1e-11, atol=1e-11 * max(1.0, np.abs(a).max()))


def _symbols(*names):
    return [sp.Symbol(n, real=True) for n in names]


@pytest.mark.parametrize("method", ["newton-euler", "lagrange-euler", "jacobian-newton-euler"])
def test_planar2r_textbook_closed_forms(derived, method):
    eqs = derived("planar2r", method)
    m1, m2, l1, lc1, lc2, I1, I2, g = _symbols("m1", "m2", "l1", "lc1", "lc2", "I1", "I2", "g")
    q1, q2 = eqs.q
    qd1, qd2 = eqs.qd
    c2, s2 = sp.cos(q2), sp.sin(q2)
    D = sp.Matrix([
        [m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2) + I1 + I2, m2 * (lc2**2 + l1 * lc2 * c2) + I2],
        [m2 * (lc2**2 + l1 * lc2 * c2) + I2, m2 * lc2**2 + I2]])
    hh = -m2 * l1 * lc2 * s2
    h = sp.Matrix([hh * (2 * qd1 * qd2 + qd2**2), -hh * qd1**2])
    C = sp.Matrix([[hh * qd2, hh * (qd1 + qd2)], [-hh * qd1, 0]])
    c = sp.Matrix([(m1 * lc1 + m2 * l1) * g * sp.cos(q1) + m2 * lc2 * g * sp.cos(q1 + q2),
                   m2 * lc2 * g * sp.cos(q1 + q2)])
    for output, expected in (("mass_matrix", D), ("coriolis", h), ("coriolis_matrix", C), ("gravity", c)):
        got = eqs.expanded(output)
        diff = (got - expected).applyfunc(lambda e: sp.simplify(sp.expand_trig(e)))
        assert diff == sp.zeros(*expected.shape), f"{output}: {diff}"
