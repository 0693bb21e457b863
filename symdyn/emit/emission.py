"""Helpers shared by every emitter (C, CasADi, printouts); no derivation happens here.

Text that comes from outside symdyn (paths, notes) reaches generated files only through
:func:`source_label` and :func:`comment_text`; names in robot files are identifiers by the time
they get here (see :mod:`symdyn.model.robot`).
"""

from __future__ import annotations

import functools
import math
import re

import jinja2
import sympy as sp
from sympy.printing.str import StrPrinter

from ..model.errors import display_path

_COMMENT_UNSAFE = re.compile(r"[^\x20-\x7e]|\\")


def source_label(path: str) -> str:
    """How generated files name their input: the path with every character outside
    ``[A-Za-z0-9._+/@,=-]`` shown as ``?`` (see :func:`symdyn.model.errors.display_path`), so it
    cannot end a C comment, start LaTeX markup or break a Markdown code span."""
    return display_path(path)


def comment_text(text: str, limit: int = 300) -> str:
    """``text`` made safe inside a C block comment (and any other comment syntax symdyn writes):
    printable ASCII only (no backslash: no line splicing), no ``*/`` or ``/*``, no trigraph
    ``??``, at most ``limit`` characters."""
    text = _COMMENT_UNSAFE.sub("?", str(text))
    while "*/" in text or "/*" in text or "??" in text:
        text = text.replace("*/", "* /").replace("/*", "/ *").replace("??", "? ?")
    return text if len(text) <= limit else text[:limit - 3] + "..."


def fold_constants(expr: sp.Expr, digits: int = 30) -> sp.Expr:
    """Replace every symbol-free, non-rational subexpression (cos(2/5), sqrt(3)/2, pi/4) by a
    Float of ``digits`` digits, so emitted code has no constant function calls."""
    # a non-rational constant contains a function of a number, a non-integer power of one or a
    # number symbol (pi); each is folded once (a 24-joint Coriolis matrix has thousands of
    # statements sharing the sines and cosines of a few twists), and putting the Floats in
    # re-evaluates the numeric products and sums around them, as folding the whole tree
    # bottom-up would (SymPy's replace: 14 of the 23 s of that function's emission)
    atoms = expr.atoms(sp.Function, sp.Pow, sp.NumberSymbol)
    constants = [a for a in atoms if a.is_number]
    if constants:
        expr = expr.xreplace({a: _fold_constant(a, digits) for a in constants})
    if any(_outsized(a) for a in expr.atoms(sp.Add)):  # rare: only then the bottom-up pass
        expr = expr.replace(_has_outsized_factor, _rescaled)
    return expr


#: a sum whose numeric coefficients are all beyond this factor from 1 is written as its largest
#: coefficient times a sum of ordinary numbers: exact rational arithmetic on a file's decimal
#: numbers can build ``3.1e46/(6.6e47 + 3.1e47*m_p)``, fine in double but not finite in float;
#: written so, the outsized factors of a quotient's two sides combine into one ordinary number
OUTSIZED = 1e15


def _outsized(expr) -> bool:
    """Whether ``expr`` is a sum whose every term's numeric coefficient is beyond
    :data:`OUTSIZED` from 1 (and not a number itself)."""
    if not expr.is_Add or expr.is_number:
        return False
    for term in expr.args:
        c = abs(float(term.as_coeff_Mul()[0]))
        if not (c > OUTSIZED or 0 < c < 1 / OUTSIZED):
            return False
    return True


def _factors(expr):
    """``(base, exponent)`` of each factor of a product or power."""
    for factor in ([expr] if expr.is_Pow else expr.args):
        yield (factor.base, factor.exp) if factor.is_Pow and factor.exp.is_Integer else (factor, sp.S.One)


def _has_outsized_factor(expr) -> bool:
    """Whether a product or integer power has an :func:`_outsized` sum among its factors."""
    return (expr.is_Mul or (expr.is_Pow and expr.exp.is_Integer)) and any(_outsized(b) for b, _ in _factors(expr))


def _rescaled(expr) -> sp.Expr:
    """The product with each outsized sum ``s`` (to the power ``e``) written as ``k**e *
    (s/k)**e``, ``k`` the largest magnitude of its numeric coefficients: the ``k**e`` combine with
    the product's own number (a quotient's two outsized sides into one ordinary number)."""
    scale, factors = sp.S.One, []
    for base, exponent in _factors(expr):
        if _outsized(base):
            k = sp.Float(max(abs(float(t.as_coeff_Mul()[0])) for t in base.args), 17)
            scale *= k ** exponent
            factors.append(sp.Add(*[t / k for t in base.args]) ** exponent)
        else:
            factors.append(base ** exponent)
    return sp.Mul(scale, *factors)


@functools.lru_cache(maxsize=4096)
def _fold_constant(expr: sp.Expr, digits: int) -> sp.Expr:
    """A constant subexpression folded bottom-up (its own constant parts first)."""
    def is_const(e):
        return (e.is_number and not e.is_Rational and not e.is_Float and not e.is_Atom) or e is sp.pi
    return expr.replace(is_const, lambda e: sp.Float(sp.N(e, digits), digits))


def banner_fields(prefix: str, precision: str, method: str = "", robot=None) -> dict:
    """``banner_title`` and ``banner_generator`` of ``templates/banner.j2``: a serial robot's
    (``method``, ``robot``: :func:`robot_words`) or, without a method, a platform robot's."""
    if not method:
        return {"banner_title": f"dynamics of platform robot '{prefix}' (6 legs, one actuated joint each; "
                                "natural orthogonal complement)",
                "banner_generator": f"platform robot, {precision} precision"}
    return {"banner_title": f"equations of motion of robot '{prefix}' ({robot_words(robot)})",
            "banner_generator": f"{method}, {precision} precision"}


def robot_words(robot) -> str:
    """What a serial robot is, in the words of the generated files: ``6 joints, standard DH``,
    ``12 joints, a tree, general joint placements``, ``12 joints on a floating base (NV = 18), a
    tree, general joint placements``."""
    placements = "general joint placements" if robot.convention == "general" else f"{robot.convention} DH"
    floating = f" on a floating base (NV = {robot.nv})" if robot.floating else ""
    tree = ", a tree" if any(p != k - 1 for k, p in enumerate(robot.parent_indices)) else ""
    count = len(robot.mimics)
    mimics = f" and {count} mimic joint{'s' if count > 1 else ''}" if count else ""
    return f"{robot.dof} joints{mimics}{floating}{tree}, {placements}"


# ---------------------------------------------------------------------------------------------
# The header's list of the model constants folded into the code

#: the longest exact expression shown before a constant's value (longer ones: the value only)
MAX_EXACT_TEXT = 40


def _decimal(value: sp.Rational) -> str | None:
    """``repr(float(value))`` (the shortest decimal that reads back as the same double) when
    that decimal is exactly ``value``, else None."""
    text = repr(float(value))
    return text if sp.Rational(text) == value else None


class _ConstantPrinter(StrPrinter):
    """SymPy's str printer, with every rational that is a short decimal printed as that decimal
    (0.4318, not 2159/5000); other rationals stay exact (1/3)."""

    def _print_Rational(self, expr):
        text = _decimal(expr)
        return text if text is not None else super()._print_Rational(expr)


_PRINTER = _ConstantPrinter({"full_prec": False})


def constant_text(value) -> str:
    """A model constant as the header lists it: a number as the shortest decimal that reads back
    as the double the code uses (Python's ``repr``: ``0.4318``, ``-9.81``, ``0.0``); an exact value
    that is not such a decimal as its expression, `` = ``, then that double (``pi/2 =
    1.5707963267948966``, ``1/3 = 0.3333333333333333``; only the double when the expression is
    long); an expression of runtime parameters as the expression (``m_p + 0.1879``)."""
    value = sp.sympify(value)
    if value.free_symbols:
        return _PRINTER.doprint(value)
    if value.is_Rational:
        text = _decimal(value)
        if text is not None:
            return text
    double = repr(float(sp.N(value, 30)))
    exact = _PRINTER.doprint(value)
    turns = value / sp.pi
    if turns.is_Rational and _decimal(turns * 180) is not None:  # an angle read in degrees
        in_degrees = f"{_decimal(turns * 180)}*pi/180"
        exact = in_degrees if len(in_degrees) < len(exact) else exact
    return f"{exact} = {double}" if len(exact) <= MAX_EXACT_TEXT and exact != double else double


def _vector(values) -> str:
    return "[" + ", ".join(constant_text(v) for v in values) + "]"


def _matrix_rows(key: str, entries) -> list[str]:
    """A constant 4x4 transform (16 entries, row-major) as four rows ``key.row1 = [...]``."""
    entries = list(entries)
    return [f"{key}.row{r + 1} = {_vector(entries[4 * r:4 * r + 4])}" for r in range(4)]


def _placement(key: str, placement) -> str:
    xyz, rpy = (placement.xyz, placement.rpy) if placement is not None else ((0, 0, 0), (0, 0, 0))
    return f"{key}.xyz = {_vector(xyz)}; {key}.rpy = {_vector(rpy)}"


def link_constant_rows(link, index: int, convention: str, indent: str = "") -> list[str]:
    """The rows of one link (``index`` from 1): a title (joint type, placement convention,
    passive), then its fields under the robot file's names (``a``, ``alpha``, ``d``, ``theta``
    or ``origin.xyz``, ``origin.rpy``, ``axis``; ``mass``, ``com``, ``inertia``, ``armature``,
    ``damping``, ``coulomb``, ``limits.*``; ``fixed.row1..4``: the constant transform a scene's
    locked joints put before the joint)."""
    general = convention == "general"
    title = f"link {index} ({link.name}): {link.joint} joint, " + ("general placement" if general
                                                                    else f"{convention} DH")
    rows = [title + ("" if link.actuated else ", passive (not actuated)")]
    inner = indent + "  "
    if link.fixed is not None:
        rows += [inner + row for row in _matrix_rows("fixed", link.fixed)]
    dh = "; ".join(f"{key} = {constant_text(getattr(link, key))}" for key in ("a", "alpha", "d", "theta"))
    if general:
        origin = link.origin
        rows.append(inner + _placement("origin", origin) + f"; axis = {_vector(link.axis or (0, 0, 1))}")
        if any(sp.sympify(getattr(link, key)) != 0 for key in ("a", "alpha", "d", "theta")):
            rows.append(inner + dh)
    else:
        rows.append(inner + dh)
    rows.append(inner + f"mass = {constant_text(link.mass)}; com = {_vector(link.com)}")
    rows.append(inner + f"inertia = {_vector(link.inertia)}")
    rows.append(inner + "; ".join(f"{key} = {constant_text(getattr(link, key))}"
                                  for key in ("armature", "damping", "coulomb")))
    if link.limits is not None:
        limits = [(key, getattr(link.limits, key)) for key in ("lower", "upper", "velocity", "effort")]
        present = [f"limits.{key} = {constant_text(value)}" for key, value in limits if value is not None]
        if present:
            rows.append(inner + "; ".join(present))
    return [indent + rows[0]] + rows[1:]


def constant_rows(robot, locked=()) -> list[str]:
    """Every constant folded into the code of a serial robot, one row each (the header's model
    constants; units and conventions are the template's legend): gravity, the base and tool
    frames, the joints a scene locked (``locked``: ``(joint from 1, link name, value)`` of the
    robot the scene read) and where they went, the passive joints, the runtime parameters (names,
    not folded) and every link's fields (:func:`link_constant_rows`)."""
    rows = [f"gravity = {_vector(robot.gravity)}", _placement("base", robot.base), _placement("tool", robot.tool)]
    if robot.floating:  # (no placement: the base's pose is in q)
        body = robot.base_inertia
        rows[1:3] = ["base: floating (Pinocchio's free-flyer)",
                     f"  base_body: mass = {constant_text(body.mass)}; com = {_vector(body.com)}",
                     f"  base_body: inertia = {_vector(body.inertia)}"]
    elif robot.is_tree:  # a tree has no tool frame
        rows = rows[:2]
    if robot.tool_fixed is not None:
        rows += _matrix_rows("tool.fixed", robot.tool_fixed)
    if locked:
        rows.append("locked by the scene (not in q; their links merged into the link before, their "
                    "placements into fixed): " + "; ".join(f"joint {k} ({comment_text(name, 60)}) = "
                                                         f"{constant_text(value)}" for k, name, value in locked))
    if robot.mimics:
        rows.append("mimic joints (no coordinate: q = multiplier * q_joint + offset, rates times the multiplier; their "
                    "joint force acts on the joint they follow, times the multiplier): " + "; ".join(
                        f"{link.name} = {constant_text(link.mimic.multiplier)} * {robot.links[link.mimic.leader].name} + "
                        f"{constant_text(link.mimic.offset)}" for link in robot.links if link.mimic is not None))
        rows.append("the joints in q, qd, qdd and tau (after a floating base's entries), in link order without the mimics: "
                    + ", ".join(f"[{k}] {robot.links[j].name}" for k, j in enumerate(robot.coordinate_links)))
    passive = [f"{k + 1} ({robot.links[robot.coordinate_links[k]].name})" for k in robot.passive_joints]
    if passive:
        rows.append(f"passive joints (tau 0, not actuated): {', '.join(passive)}")
    if robot.parameters:
        rows.append("runtime parameters (inputs in p, not folded): "
                    + "; ".join(f"p[{k}] = {s.name}" for k, s in enumerate(robot.parameters)))
    for k, link in enumerate(robot.links):
        link_rows = link_constant_rows(link, k + 1, robot.convention)
        if link.mimic is not None:
            link_rows.insert(1, f"  mimic.joint = {robot.links[link.mimic.leader].name}; mimic.multiplier = "
                                f"{constant_text(link.mimic.multiplier)}; mimic.offset = {constant_text(link.mimic.offset)}")
        if robot.is_tree:  # a tree: where each link hangs (the robot file's parent field)
            up = robot.parent_indices[k]
            link_rows.insert(1, "  parent = " + ("base" if up < 0 else robot.links[up].name))
        rows += link_rows
    return rows


def platform_constant_rows(robot) -> list[str]:
    """Every constant folded into the code of a platform robot
    (:class:`symdyn.model.parallel.ParallelRobot`): gravity, the platform's inertial data, each
    leg's placements (``base``: its frame 0 in the world; ``platform``: its last link frame in
    the platform frame), actuated joint and home configuration, and the legs' link tables (once
    when every leg has the same table)."""
    plat = robot.platform
    rows = [f"gravity = {_vector(robot.gravity)}",
            f"platform.mass = {constant_text(plat.mass)}; platform.com = {_vector(plat.com)}",
            f"platform.inertia = {_vector(plat.inertia)}"]
    if robot.parameters:
        rows.append("runtime parameters (inputs in p, not folded): "
                    + "; ".join(f"p[{k}] = {s.name}" for k, s in enumerate(robot.parameters)))
    tables = {(leg.chain.convention, leg.chain.links) for leg in robot.legs}
    for leg in robot.legs:
        link = leg.actuated_link
        rows.append(f"leg {leg.name}: actuated joint {leg.actuated + 1} ({link.name})")
        rows.append("  " + _placement("base", leg.chain.base))
        rows.append("  " + _placement("platform", leg.attachment))
        if leg.home is not None:
            rows.append(f"  home = {_vector(leg.home)}")
        if len(tables) > 1:
            for k, chain_link in enumerate(leg.chain.links):
                rows += link_constant_rows(chain_link, k + 1, leg.chain.convention, "  ")
    if len(tables) == 1:
        rows.append(f"links of every leg (one table for all {len(robot.legs)}):")
        chain = robot.legs[0].chain
        for k, chain_link in enumerate(chain.links):
            rows += link_constant_rows(chain_link, k + 1, chain.convention, "  ")
    return rows


def template_environment() -> jinja2.Environment:
    """The Jinja2 environment of the shipped templates (``symdyn.templates``), StrictUndefined."""
    from importlib.resources import files
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(files("symdyn.templates"))),
        undefined=jinja2.StrictUndefined, keep_trailing_newline=True,
        trim_blocks=True, lstrip_blocks=True, autoescape=False)


def factor_coefficients(expr: sp.Expr) -> sp.Expr:
    """``expr`` with the terms of a top-level sum that share a numeric coefficient (up to sign)
    grouped: ``0.9*a + 0.9*b - 0.9*c`` becomes ``0.9*(a + b - c)``, one multiplication instead
    of three.  The result is unevaluated (SymPy would distribute the number again): use it for
    printing and counting only.  The value changes by rounding only."""
    if not expr.is_Add:
        return expr
    groups: dict[sp.Expr, list[sp.Expr]] = {}
    order: list[tuple[bool, sp.Expr]] = []  # (is a group key, term or key) in order of appearance
    for term in expr.args:
        coeff, rest = term.as_coeff_Mul()
        if not (coeff.is_Number and abs(coeff) != 1 and rest != 1):
            order.append((False, term))
            continue
        key = abs(coeff)
        if key not in groups:
            groups[key] = []
            order.append((True, key))
        groups[key].append(rest if coeff > 0 else -rest)
    if all(len(members) < 2 for members in groups.values()):
        return expr
    terms = []
    for is_group, item in order:
        if not is_group:
            terms.append(item)
        elif len(groups[item]) == 1:
            terms.append(item * groups[item][0])
        else:
            terms.append(sp.Mul(item, sp.Add(*groups[item]), evaluate=False))
    return sp.Add(*terms, evaluate=False)


def _product_parts(term: sp.Expr) -> tuple[int, list[sp.Expr]]:
    """``(sign, factors)`` of a product: its numeric coefficient's magnitude first (when not 1),
    then the other factors in SymPy's order."""
    coeff, rest = term.as_coeff_Mul()
    sign = -1 if coeff.is_Number and coeff < 0 else 1
    coeff = -coeff if sign < 0 else coeff
    factors = list(rest.args) if rest.is_Mul else [rest]
    return sign, ([coeff] if coeff != 1 else []) + factors


def fresh_symbols(prefix: str, exprs, start: int = 0):
    """``prefix0, prefix1, ...`` (from ``start``) as real SymPy symbols, skipping every name a
    free symbol of ``exprs`` already has: a temporary never takes the name of a parameter or
    an intermediate (a robot parameter called ``cse0``)."""
    used = {s.name for e in exprs for s in sp.sympify(e).free_symbols}
    k = start
    while True:
        name = f"{prefix}{k}"
        k += 1
        if name not in used:
            yield sp.Symbol(name, real=True)


def pair_cse(exprs, symbols) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.Expr]]:
    """Common products of two factors, named once: the common-subexpression pass for very long
    straight-line programs (same results as ``sp.cse(exprs, symbols=symbols, order="none")``:
    ``(replacements, reduced expressions)``).

    Programs built with intermediate symbols (hash-consed, see
    :class:`symdyn.derive.program.ProgramBuilder`) have no repeated subtrees; what SymPy's CSE
    finds in them is products of two factors (a number and a symbol, or two symbols) shared by
    terms of different statements.  This pass counts every pair of factors over the terms of all
    expressions (a coefficient by its magnitude: ``-0.3*x*y`` and ``0.3*x*z`` share ``0.3*x``),
    names each pair that occurs at least twice, and rewrites each term with its most frequent
    pairs, in one linear pass.  Generic 12-joint chain, Coriolis matrix: 8773 multiplications
    against SymPy's 9232, 2.5 against 4.7 s, 9 against 27 MB; SymPy's CSE also groups common
    sums, which this pass does not (see :data:`symdyn.emit.cplan.PAIR_CSE_FROM`)."""
    exprs = list(exprs)

    def terms(e):
        return e.args if e.is_Add else (e,)
    counts: dict[tuple[sp.Expr, sp.Expr], int] = {}
    for e in exprs:
        for term in terms(e):
            if term.is_Mul:
                _, items = _product_parts(term)
                for i in range(len(items)):
                    for j in range(i + 1, len(items)):
                        counts[items[i], items[j]] = counts.get((items[i], items[j]), 0) + 1
    named: dict[tuple[sp.Expr, sp.Expr], sp.Symbol] = {}
    replacements: list[tuple[sp.Symbol, sp.Expr]] = []

    def rewrite(term):
        if not term.is_Mul:
            return term
        sign, items = _product_parts(term)
        shared = sorted((-counts[items[i], items[j]], i, j) for i in range(len(items))
                        for j in range(i + 1, len(items)) if counts[items[i], items[j]] >= 2)
        if not shared:
            return term
        used = [False] * len(items)
        factors = []
        for _, i, j in shared:
            if used[i] or used[j]:
                continue
            used[i] = used[j] = True
            key = (items[i], items[j])
            if key not in named:
                named[key] = next(symbols)
                replacements.append((named[key], sp.Mul(*key)))
            factors.append(named[key])
        factors += [x for x, u in zip(items, used) if not u]
        return sign * sp.Mul(*factors)
    reduced = []
    for e in exprs:
        new = [rewrite(t) for t in terms(e)]
        changed = any(a is not b for a, b in zip(new, terms(e)))
        reduced.append((sp.Add(*new) if e.is_Add else new[0]) if changed else e)
    return replacements, reduced
