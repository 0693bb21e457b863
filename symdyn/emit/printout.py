"""Printing derivations (:mod:`symdyn.derive.derivation`) as text, LaTeX or Markdown.

This module derives nothing: it names each quantity in the notation of the notes, prints the
values (SymPy's LaTeX and Unicode printers) and renders the templates
``derivation.{txt,tex,md}.j2``.  Numbers with decimals are printed as decimals of
:data:`DEFAULT_DIGITS` significant digits (``digits``; the derivation itself stays exact), and
long LaTeX equations are broken into lines that fit the page (:mod:`symdyn.emit.texlayout`).
"""

from __future__ import annotations

import decimal

import sympy as sp
from mpmath.libmp import to_str as mlib_to_str
from sympy.printing.latex import LatexPrinter
from sympy.printing.pretty.pretty import PrettyPrinter
from sympy.printing.pretty.pretty_symbology import pretty_use_unicode
from sympy.printing.pretty.stringpict import prettyForm

from .._version import __version__
from ..derive.derivation import Derivation
from . import texlayout
from .emission import source_label, template_environment

FORMATS = ("text", "latex", "markdown")
METHOD_TITLES = {"lagrange-euler": "Lagrange–Euler", "newton-euler": "Newton–Euler",
                 "jacobian-newton-euler": "the Jacobian-projected Newton–Euler equations",
                 "articulated-body": "the articulated-body algorithm"}
TEMPLATES = {"text": "derivation.txt.j2", "latex": "derivation.tex.j2", "markdown": "derivation.md.j2"}

_SUP = str.maketrans("0123456789-+", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺")
_SUB = str.maketrans("0123456789-+", "₀₁₂₃₄₅₆₇₈₉₋₊")

#: (LaTeX, Unicode) name of each quantity kind; {i}, {j}, {k}, {m} are its indices, {p} = i-1
_NAMES = {
    "link_transform": (r"{{}}^{{{p}}}A_{{{i}}}", "{P}A{I}"),
    "base_transform": (r"{{}}^{{0}}A_{{{i}}}", "⁰A{I}"),
    "q_operator": (r"Q_{{{i}}}", "Q{I}"),
    "u": (r"U_{{{i}{j}}}", "U{I}{J}"),
    "u3": (r"U_{{{i}{j}{k}}}", "U{I}{J}{K}"),
    "pseudo_inertia": (r"J_{{{i}}}", "J{I}"),
    "d_entry": (r"D_{{{i}{j}}}", "D{I}{J}"),
    "h_entry": (r"h_{{{i}{j}{k}}}", "h{I}{J}{K}"),
    "h_i": (r"h_{{{i}}}", "h{I}"),
    "c_i": (r"c_{{{i}}}", "c{I}"),
    "omega": (r"{{}}^{{{i}}}\omega_{{{i}}}", "{S}ω{I}"),
    "omegadot": (r"{{}}^{{{i}}}\dot{{\omega}}_{{{i}}}", "{S}ω̇{I}"),
    "vdot": (r"{{}}^{{{i}}}\dot{{v}}_{{{i}}}", "{S}v̇{I}"),
    "abar": (r"{{}}^{{{i}}}\bar{{a}}_{{{i}}}", "{S}ā{I}"),
    "F": (r"F_{{{i}}}", "F{I}"),
    "N": (r"N_{{{i}}}", "N{I}"),
    "f": (r"f_{{{i}}}", "f{I}"),
    "n": (r"n_{{{i}}}", "n{I}"),
    "tau": (r"\tau_{{{i}}}", "τ{I}"),
    "jc": (r"J_{{c{i}}}", "J_c{I}"),
    "projected": (r"J_{{c{i}}}^T M_{{{i}}} J_{{c{i}}}", "J_c{I}ᵀ M{I} J_c{I}"),
    "omega_w": (r"\omega_{{{i}}}", "ω{I}"),
    "omegadot_w": (r"\dot{{\omega}}_{{{i}}}", "ω̇{I}"),
    "vdot_w": (r"\dot{{v}}_{{{i}}}", "v̇{I}"),
    "fJ": (r"f_{{J{i}}}", "f_J{I}"),
    "tJ": (r"t_{{J{i}}}", "t_J{I}"),
    "X": (r"{{}}^{{{i}}}X_{{{p}}}", "{S}X{P_}"),
    "I": (r"\bar{{I}}_{{{i}}}", "Ī{I}"),
    "v": (r"\bar{{v}}_{{{i}}}", "v̄{I}"),
    "cbar": (r"\bar{{c}}_{{{i}}}", "c̄{I}"),
    "p": (r"\bar{{p}}_{{{i}}}", "p̄{I}"),
    "U": (r"\bar{{U}}_{{{i}}}", "Ū{I}"),
    "d": (r"d_{{{i}}}", "d{I}"),
    "aba_u": (r"u_{{{i}}}", "u{I}"),
    "Ia": (r"\bar{{I}}^{{a}}_{{{i}}}", "Īᵃ{I}"),
    "pa": (r"\bar{{p}}^{{a}}_{{{i}}}", "p̄ᵃ{I}"),
    "IA": (r"\bar{{I}}^{{A}}_{{{i}}}", "Īᴬ{I}"),
    "pA": (r"\bar{{p}}^{{A}}_{{{i}}}", "p̄ᴬ{I}"),
    "ap": (r"\bar{{a}}'_{{{i}}}", "ā'{I}"),
    "qdd": (r"\ddot{{q}}_{{{i}}}", "q̈{I}"),
    "a": (r"\bar{{a}}_{{{i}}}", "ā{I}"),
    "b": (r"\boldsymbol{{b}}_{{{i}}}", "b{I}"),
    "A": (r"\boldsymbol{{A}}_{{{i}}}", "A{I}"),
    "pa0": (r"\bar{{p}}^{{a}}_{{{i}}}\big|_{{\tau=0}}", "p̄ᵃ{I}|τ=0"),
    "k": (r"\boldsymbol{{k}}_{{{i}}}", "k{I}"),
    "k1": (r"\boldsymbol{{k}}_{{{i}}}", "k{I}"),
    "k0": (r"\boldsymbol{{k}}_{{{i}}}", "k{I}"),
    "column": (r"\begin{{bmatrix}} \boldsymbol{{e}} \\ \boldsymbol{{d}} \end{{bmatrix}}_{{{i}}}", "[e; d]{I}"),
    "Dmap": (r"\boldsymbol{{D}}", "D"),
    "W": (r"W_{{{i},{j}}}", "W{I},{J}"),
    "beta": (r"\beta_{{{i}}}", "β{I}"),
    "task_J": (r"J", "J"),
    "task_det": (r"\det J", "det J"),
    "Mx": (r"M_x(\Theta)", "Mₓ(Θ)"),
    "Vx": (r"V_x(\Theta, \dot{{\Theta}})", "Vₓ(Θ, Θ̇)"),
    "Gx": (r"G_x(\Theta)", "Gₓ(Θ)"),
    "contact_J": (r"J_c", "J_c"),
    "contact_gamma": (r"\gamma", "γ"),
    "contact_det": (r"\det J_c", "det J_c"),
    "contact_lambda": (r"\lambda", "λ"),
    "contact_qdd": (r"\ddot{{q}}", "q̈"),
    "cfg_rotation": (r"{{}}^{{W}}R_0", "ᵂR₀"),
    "cfg_coefficient": (r"\sigma_{{{i}}}", "σ{I}"),
    "D": (r"D(q)", "D(q)"),
    "h": (r"h(q, \dot{{q}})", "h(q, q̇)"),
    "c": (r"c(q)", "c(q)"),
}


def quantity_name(kind: str, indices: tuple[int, ...], fmt: str, parent: int | None = None) -> str:
    """The name of a quantity in the notes' notation (LaTeX for latex/markdown, else Unicode);
    ``parent``: the link the first index's link hangs on (a tree; default the one before)."""
    latex, text = _NAMES[kind]
    before = (indices[0] - 1 if parent is None else parent) if indices else ""
    sep = "," if any(i >= 10 for i in indices) else ""
    keys = dict(zip("ijkm", [str(i) for i in indices]))
    if sep and len(indices) > 1:
        keys = dict(zip("ijkm", [str(indices[0])] + [sep + str(i) for i in indices[1:]]))
    if fmt == "text":
        up = dict(zip("IJKM", [k.translate(_SUB) for k in keys.values()]))
        return text.format(P=str(before).translate(_SUP), P_=str(before).translate(_SUB),
                           S=str(indices[0]).translate(_SUP) if indices else "", **up)
    return latex.format(p=before, **keys)


#: significant digits of the printed numbers (``symdyn derive --digits``); the derivation is exact
DEFAULT_DIGITS = 6
#: the most significant digits ``digits`` may ask for
MAX_DIGITS = 20
#: integers with more digits than this are printed as decimals too
MAX_INTEGER_DIGITS = 12
#: a rational with a numerator or denominator beyond this is a decimal from the robot file (or
#: a product of such): ``2159/5000``, not ``3/4``
_SMALL = 1000


def _looks_decimal(n, digits: int) -> bool:
    """Whether the number ``n`` is one to print as a decimal rather than exactly."""
    if n.is_Float:
        return True
    if n.is_Integer:
        return abs(int(n)) >= 10 ** digits
    return n.is_Rational and (abs(n.p) > _SMALL or n.q > _SMALL)


def _spread(expr, digits: int):
    """``expr`` (exactly) with the numeric factor of a product moved into its sum when the sum
    holds numbers printed as decimals, or the factor is one: ``1/10**24 q1 (-2264478143158287783995
    sin(2 q2) + ...)`` as ``q1 (-0.00226447... sin(2 q2) + ...)``, so that no long integer is
    left over once the numbers are rounded (the factor's sign stays in front)."""
    if expr.is_Atom or not expr.args:
        return expr
    if expr.is_Pow:
        return sp.Pow(_spread(expr.base, digits), expr.exp)
    args = [_spread(a, digits) for a in expr.args]
    new = expr.func(*args, evaluate=False) if isinstance(expr, sp.core.relational.Relational) else expr.func(*args)
    if not new.is_Mul:
        return new
    coeff, rest = new.as_coeff_Mul()
    if coeff in (1, -1):
        return new
    factors = sp.Mul.make_args(rest)
    sums = [f for f in factors if f.is_Add]
    inexact = [f for f in sums if any(_looks_decimal(n, digits) for n in f.atoms(sp.Number))]
    if inexact or (sums and _looks_decimal(coeff, digits)):
        target = (inexact or sums)[0]
        spread = sp.Add(*[abs(coeff) * t for t in target.args])  # the sign stays in front
        return sp.Mul(sp.sign(coeff), *[f for f in factors if f is not target], spread)
    return new


def _decimal(n, digits: int):
    """The number ``n`` rounded (half to even) to ``digits`` significant decimal digits, as a
    Float that prints exactly those digits."""
    exact = sp.Rational(n)
    with decimal.localcontext(decimal.Context(prec=digits, rounding=decimal.ROUND_HALF_EVEN)):
        text = str(decimal.Decimal(exact.p) / decimal.Decimal(exact.q))
    return sp.Float(text, digits + 5)


def _round(expr, digits: int):
    """``expr`` with its numbers (not its exponents) as :func:`_decimal`: every non-integer but
    a small rational multiple of pi (pi/2), and integers beyond :data:`MAX_INTEGER_DIGITS`.  No
    arithmetic happens, so each printed number is its exact value rounded once."""
    if expr.is_Number:
        if expr.is_Integer and abs(int(expr)) < 10 ** MAX_INTEGER_DIGITS:
            return expr
        return _decimal(expr, digits)
    if expr.is_Atom or not expr.args:
        return expr
    if expr.is_Pow:
        return sp.Pow(_round(expr.base, digits), expr.exp, evaluate=False)
    exact_multiple = expr.is_Mul and any(isinstance(a, sp.NumberSymbol) for a in expr.args)
    args = [a if exact_multiple and a.is_Rational and not _looks_decimal(a, digits) else _round(a, digits)
            for a in expr.args]  # pi/2 stays pi/2
    try:
        return expr.func(*args, evaluate=False)
    except TypeError:
        return expr.func(*args)


def shown(value, digits: int = DEFAULT_DIGITS):
    """``value`` (an expression, equation or matrix) as printed: functions of numbers (sin(2/5))
    evaluated, numbers with decimals and long integers as decimals of ``digits`` significant
    digits, small integers and pi/2 exact."""
    value = sp.sympify(value)
    if isinstance(value, sp.MatrixBase):
        return sp.ImmutableMatrix(value.rows, value.cols, [shown(e, digits) for e in value])
    # sin(2/5) cos(1/10): numbers (to 30 digits), so that products of them fold into one
    constants = [f for f in value.atoms(sp.Function) if f.is_number]
    if constants:
        value = value.xreplace({f: sp.Float(sp.N(f, 30), 30) for f in constants})
    return _round(_spread(value, digits), digits)


def _float_text(value, digits: int) -> str:
    """A rounded Float's digits: fixed point from 1e-5 to 10**digits, else ``1.5e-7``."""
    return mlib_to_str(value._mpf_, digits, strip_zeros=True, min_fixed=-5, max_fixed=digits)


class _TextPrinter(PrettyPrinter):
    """SymPy's Unicode printer with the printout's decimals."""

    def __init__(self, digits: int, settings):
        super().__init__(settings)
        self.digits = digits

    def _print_Float(self, expr):
        return prettyForm(_float_text(expr, self.digits))

    def _print_Mul(self, expr):
        """A rational multiple of pi on one line (``-π/2``: it sits in the link table's rows)."""
        coeff, rest = expr.as_coeff_Mul()
        if coeff.is_Rational and not coeff.is_Integer and isinstance(rest, sp.NumberSymbol):
            numerator = "" if abs(coeff.p) == 1 else f"{abs(coeff.p)}⋅"
            sign = "-" if coeff < 0 else ""
            form = prettyForm(f"{sign}{numerator}{self._print(rest)}/{coeff.q}")
            form.binding = prettyForm.NEG if sign else prettyForm.MUL
            return form
        return super()._print_Mul(expr)


class _TexPrinter(LatexPrinter):
    """SymPy's LaTeX printer with the printout's decimals (``1.5 \\cdot 10^{-7}``)."""

    def __init__(self, digits: int, settings):
        super().__init__(settings)
        self.digits = digits

    def _print_Float(self, expr):
        mantissa, _, exponent = _float_text(expr, self.digits).partition("e")
        return f"{mantissa} \\cdot 10^{{{int(exponent)}}}" if exponent else mantissa


_LATEX_NAME = __import__("re").compile(r"(IA|Ia|pA|pa0|pa|ap|u0)_(.+)\Z")
_LATEX_HEAD = {"IA": r"\bar{I}^{A}", "Ia": r"\bar{I}^{a}", "pA": r"\bar{p}^{A}", "pa": r"\bar{p}^{a}",
               "pa0": r"\bar{p}^{a0}", "ap": r"\bar{a}'", "u0": r"u^{0}"}


def _latex(value, digits: int = DEFAULT_DIGITS) -> str:
    """LaTeX of a value already :func:`shown`, with the articulated-body algorithm's names
    typeset as in the notes (``IA_2,15`` as I-bar^A_{2,15}, ``ap_3,x`` as a-bar'_{3,x}, ...)."""
    names = {}
    for sym in getattr(value, "free_symbols", ()):
        match = _LATEX_NAME.match(sym.name)
        if match:
            names[sym] = f"{_LATEX_HEAD[match.group(1)]}_{{{match.group(2)}}}"
    return _TexPrinter(digits, {"symbol_names": names}).doprint(value)


def _rows(items: list[str], head: str, width: int = 100) -> list[str]:
    """``head`` and the items, separated by commas and ended by a period, in rows of at most
    ``width`` characters (an item is never split; the rows after the first indented as the first)."""
    rows, row = [], head
    for k, item in enumerate(items):
        text = item + ("." if k == len(items) - 1 else ",")
        if len(row) + len(text) + 1 > width and row.strip():
            rows.append(row.rstrip())
            row = " " * len(head)
        row += text + " "
    rows.append(row.rstrip())
    return rows


def _pretty(value, digits: int = DEFAULT_DIGITS, label: str = "") -> str:
    """The Unicode text of ``value``, over several rows where it has exponents or fractions, lines
    wrapped at 100 columns; with ``label``, as ``label = value`` with the label on the value's
    baseline (the rows above and below indented under the value)."""
    printer = _TextPrinter(digits, {"use_unicode": True, "num_columns": 100})
    flag = pretty_use_unicode(True)
    try:
        if not label:
            return printer.doprint(value)
        form = printer._print(value)
        return prettyForm(*form.left(prettyForm(f"{label} = "))).render(**printer._settings)
    finally:
        pretty_use_unicode(flag)


#: the width, in TeX points, a displayed line may take: the LaTeX page (less the estimate's margin),
#: and about the text column of a Markdown page on GitHub
LINE_WIDTH = {"latex": texlayout.TEXT_WIDTH * texlayout.FILL, "markdown": 480.0}


class _Printer:
    """Prints values in one format; long LaTeX expressions are split over lines that fit the
    page (:mod:`symdyn.emit.texlayout`).  Remembers each value's printed form (a value is often
    printed more than once: measured, then shown)."""

    def __init__(self, fmt: str, digits: int = DEFAULT_DIGITS):
        self.fmt = fmt
        self.digits = digits
        self.width = LINE_WIDTH.get(fmt, 0.0)
        self._shown: dict = {}
        self._latex: dict = {}

    def shown(self, value):
        """``value`` as printed (:func:`shown`)."""
        value = sp.sympify(value)
        if isinstance(value, sp.MatrixBase):
            return sp.ImmutableMatrix(value.rows, value.cols, [self.shown(e) for e in value])
        if value not in self._shown:
            self._shown[value] = shown(value, self.digits)
        return self._shown[value]

    def latex(self, value) -> str:
        """LaTeX of a value already :meth:`shown`."""
        if isinstance(value, sp.MatrixBase):
            return _latex(value, self.digits)
        if value not in self._latex:
            self._latex[value] = _latex(value, self.digits)
        return self._latex[value]

    def value(self, value) -> str:
        value = self.shown(value)
        if self.fmt == "text":
            return _pretty(value, self.digits)
        return self.latex(value)

    def lines(self, value, name: str = "") -> list[str]:
        """The value as display lines after ``name =`` (LaTeX: a long sum broken between terms,
        a long term inside its parentheses, so that every line fits the page)."""
        value = self.shown(value)
        if self.fmt == "text":
            return [_pretty(value, self.digits)]
        if isinstance(value, sp.MatrixBase):
            return [self.latex(value)]
        available = self.width - texlayout.width(f"{name} ={{}}")
        if isinstance(value, sp.Equality):
            head = self.latex(value.lhs) + " ="
            lines = texlayout.break_lines(value.rhs, available, self.latex,
                                          first=available - texlayout.width(head + " {}"))
            return [f"{head} {lines[0]}"] + lines[1:]
        return texlayout.break_lines(value, available, self.latex)

    def is_wide(self, value, name: str) -> bool:
        """Whether a matrix is too wide to show whole (it is then shown entry by entry): in
        LaTeX wider than a line, in text with an entry of over 60 LaTeX characters."""
        if not isinstance(value, sp.MatrixBase):
            return False
        value = self.shown(value)
        if self.fmt == "text":
            return any(len(self.latex(e)) > 60 for e in value)
        return texlayout.width(f"{name} = {self.latex(value)}") > self.width


def _items(printer: _Printer, fmt: str, kind: str, indices, value, parents=()):
    """[(name, lines)] for one quantity: a wide matrix is shown entry by entry; ``parents``:
    a tree's parent of each link (0-based, -1 the base), for the link matrices' names."""
    parent = parents[indices[0] - 1] + 1 if kind == "link_transform" and parents else None
    name = quantity_name(kind, indices, fmt, parent)
    if printer.is_wide(value, name):
        rows, cols = value.shape
        out = []
        symmetric = kind in ("D", "pseudo_inertia") or (rows == cols and value == value.T)
        for r in range(rows):
            for c in range(cols):
                if symmetric and c < r:
                    continue
                if value[r, c] == 0 and kind in ("base_transform", "link_transform", "u", "u3", "X", "I",
                                                  "IA", "Ia", "A", "Dmap"):
                    continue
                index = f"{r + 1}{c + 1}" if cols > 1 else f"{r + 1}"
                if kind in ("D", "h", "c"):  # entries of the results: D_ik, h_i, c_i
                    entry = f"{kind}_{{{index}}}" if fmt != "text" else kind + index.translate(_SUB)
                elif fmt != "text":
                    entry = f"({name})_{{{index}}}"
                else:
                    entry = f"{name}[{r + 1},{c + 1}]" if cols > 1 else f"{name}[{r + 1}]"
                out.append((entry, printer.lines(value[r, c], entry)))
        return out
    return [(name, printer.lines(value, name))]


def render(derivation: Derivation, fmt: str = "text", source_name: str = "", source_hash: str = "",
           digits: int = DEFAULT_DIGITS, progress=None) -> str:
    """The derivation as a complete document in ``fmt`` (text, latex or markdown), numbers to
    ``digits`` significant digits; ``progress`` (optional) is called with a short text per
    section printed."""
    if fmt not in FORMATS:
        raise ValueError(f"format must be one of {', '.join(FORMATS)}, not {fmt!r}")
    if not isinstance(digits, int) or not 1 <= digits <= MAX_DIGITS:
        raise ValueError(f"digits must be an integer from 1 to {MAX_DIGITS}, not {digits!r}")
    printer = _Printer(fmt, digits)
    robot = derivation.robot
    sections = []
    for number, section in enumerate(derivation.sections, start=1):
        if progress is not None:
            progress(f"{robot.name}: printing section {number} of {len(derivation.sections)}")
        items = []
        for q in section.quantities:
            items.extend(_items(printer, fmt, q.kind, q.indices, q.value, robot.parent_indices))
        sections.append({"kind": section.kind, "items": items})
    symbol = (lambda s: sp.pretty(s, use_unicode=True)) if fmt == "text" else sp.latex
    shorthand = [(symbol(s), printer.value(meaning)) for s, meaning in derivation.shorthand]
    shorthand_rows = _rows([f"{s} = {meaning}" for s, meaning in shorthand], "Shorthand: ")
    parents = [(k + 1, p + 1) for k, p in enumerate(robot.parent_indices)] if robot.is_tree else []
    parent_rows = _rows([f"p({i}) = {p}" for i, p in parents], "A kinematic tree: link i hangs on link p(i) (0 is the "
                        "base): ") if parents else []
    if progress is not None and derivation.where:
        progress(f"{robot.name}: printing the intermediate quantities")
    where = [(symbol(s), [_pretty(printer.shown(rhs), printer.digits, symbol(s))] if fmt == "text"
              else printer.lines(rhs, symbol(s))) for s, rhs in derivation.where]
    dh = []
    for k, link in enumerate(robot.links):
        com = ", ".join(printer.value(c) for c in link.com)
        inertia = ", ".join(printer.value(c) for c in link.inertia)
        row = {"index": k + 1, "name": link.name, "joint": link.joint,
               "a": printer.value(link.a), "alpha": printer.value(link.alpha),
               "d": printer.value(link.d), "theta": printer.value(link.theta),
               "mass": printer.value(link.mass), "com": com, "inertia": inertia}
        if robot.convention == "general":
            row.update(xyz=", ".join(printer.value(v) for v in link.origin.xyz),
                       rpy=", ".join(printer.value(v) for v in link.origin.rpy),
                       axis=", ".join(printer.value(v) for v in link.axis))
        dh.append(row)
    placements = [(label, ", ".join(printer.value(v) for v in placement.xyz),
                   ", ".join(printer.value(v) for v in placement.rpy))
                  for label, placement in (("base", robot.base), ("tool", robot.tool)) if placement is not None]
    context = {
        "robot": robot.name, "dof": robot.dof, "convention": robot.convention,
        "method": derivation.method, "method_title": METHOD_TITLES[derivation.method], "steps": derivation.steps, "closed_form": derivation.closed_form,
        "version": __version__, "source_name": source_label(source_name or robot.source),
        "source_hash": source_hash or robot.source_hash,
        "gravity": printer.value(sp.Matrix(robot.base_gravity).T if fmt == "text" else sp.Matrix(robot.base_gravity)),
        "convention_text": ("general joint placements (origin, axis)" if robot.convention == "general"
                            else f"{robot.convention} Denavit–Hartenberg convention"),
        "placements": placements,
        "dh": dh, "sections": sections, "shorthand": shorthand, "shorthand_rows": shorthand_rows, "parent_rows": parent_rows, "where": where,
        "revolute": [link.is_revolute for link in robot.links], "digits": digits,
        # a tree: (link, parent) 1-based, 0 the base; a floating base: its body
        "parents": parents,
        "floating": robot.floating,
        "base_mass": printer.value(robot.base_inertia.mass) if robot.floating else "",
        "base_com": ", ".join(printer.value(c) for c in robot.base_inertia.com) if robot.floating else "",
    }
    return template_environment().get_template(TEMPLATES[fmt]).render(**context)
