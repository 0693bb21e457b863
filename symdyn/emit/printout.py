"""Printing derivations (:mod:`symdyn.derive.derivation`) as text, LaTeX or Markdown.

This module derives nothing: it names each quantity in the notation of the notes, prints the
values (SymPy's LaTeX and Unicode printers) and renders the templates
``derivation.{txt,tex,md}.j2``.  Numbers with decimals are shown with 6 significant digits.
"""

from __future__ import annotations

import sympy as sp

from .._version import __version__
from ..derive.derivation import Derivation
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
    "D": (r"D(q)", "D(q)"),
    "h": (r"h(q, \dot{{q}})", "h(q, q̇)"),
    "c": (r"c(q)", "c(q)"),
}


def quantity_name(kind: str, indices: tuple[int, ...], fmt: str) -> str:
    """The name of a quantity in the notes' notation (LaTeX for latex/markdown, else Unicode)."""
    latex, text = _NAMES[kind]
    sep = "," if any(i >= 10 for i in indices) else ""
    keys = dict(zip("ijkm", [str(i) for i in indices]))
    if sep and len(indices) > 1:
        keys = dict(zip("ijkm", [str(indices[0])] + [sep + str(i) for i in indices[1:]]))
    if fmt == "text":
        up = dict(zip("IJKM", [k.translate(_SUB) for k in keys.values()]))
        return text.format(P=str(indices[0] - 1).translate(_SUP) if indices else "",
                           P_=str(indices[0] - 1).translate(_SUB) if indices else "",
                           S=str(indices[0]).translate(_SUP) if indices else "", **up)
    return latex.format(p=indices[0] - 1 if indices else "", **keys)


def _rounded(value):
    """Numbers with decimals (floats, and fractions such as 2159/5000 that came from decimals in
    the robot file) shown with 6 significant digits; integers and symbols unchanged."""
    numbers = [a for a in value.atoms(sp.Number) if a.is_Float or (a.is_Rational and not a.is_Integer)]
    return value.xreplace({a: sp.Float(a, 6) for a in numbers}) if numbers else value


_LATEX_NAME = __import__("re").compile(r"(IA|Ia|pA|pa0|pa|ap|u0)_(.+)\Z")
_LATEX_HEAD = {"IA": r"\bar{I}^{A}", "Ia": r"\bar{I}^{a}", "pA": r"\bar{p}^{A}", "pa": r"\bar{p}^{a}",
               "pa0": r"\bar{p}^{a0}", "ap": r"\bar{a}'", "u0": r"u^{0}"}


def _latex(value) -> str:
    """``sp.latex`` with the articulated-body algorithm's names typeset as in the seed
    (``IA_2,15`` as I-bar^A_{2,15}, ``ap_3,x`` as a-bar'_{3,x}, ...)."""
    names = {}
    for sym in getattr(value, "free_symbols", ()):
        match = _LATEX_NAME.match(sym.name)
        if match:
            names[sym] = f"{_LATEX_HEAD[match.group(1)]}_{{{match.group(2)}}}"
    return sp.latex(value, symbol_names=names) if names else sp.latex(value)


class _Printer:
    """Prints values in one format; long expressions are split over lines."""

    LINE = 90  # LaTeX source characters per displayed line (a proxy for its width)

    def __init__(self, fmt: str):
        self.fmt = fmt

    def value(self, value) -> str:
        value = _rounded(sp.sympify(value))
        if self.fmt == "text":
            return sp.pretty(value, use_unicode=True, num_columns=100)
        return _latex(value)

    def lines(self, value) -> list[str]:
        """The value as display lines (LaTeX: terms of a long sum grouped per line)."""
        value = _rounded(sp.sympify(value))
        if self.fmt == "text" or isinstance(value, sp.MatrixBase) or not value.is_Add:
            return [self.value(value)]
        lines, current = [], ""
        for k, term in enumerate(value.as_ordered_terms()):
            text = _latex(term)
            if k > 0:
                text = "- " + text[1:].lstrip() if text.startswith("-") else "+ " + text
            if current and len(current) + len(text) > self.LINE:
                lines.append(current)
                current = text
            else:
                current = f"{current} {text}".strip()
        lines.append(current)
        return lines

    def is_wide(self, value) -> bool:
        if not isinstance(value, sp.MatrixBase):
            return False
        return any(len(_latex(_rounded(sp.sympify(e)))) > 60 for e in value)


def _items(printer: _Printer, fmt: str, kind: str, indices, value):
    """[(name, lines)] for one quantity: a wide matrix is shown entry by entry."""
    name = quantity_name(kind, indices, fmt)
    if printer.is_wide(value):
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
                out.append((entry, printer.lines(value[r, c])))
        return out
    return [(name, printer.lines(value))]


def render(derivation: Derivation, fmt: str = "text", source_name: str = "", source_hash: str = "") -> str:
    """The derivation as a complete document in ``fmt`` (text, latex or markdown)."""
    if fmt not in FORMATS:
        raise ValueError(f"format must be one of {', '.join(FORMATS)}, not {fmt!r}")
    printer = _Printer(fmt)
    robot = derivation.robot
    sections = []
    for section in derivation.sections:
        items = []
        for q in section.quantities:
            items.extend(_items(printer, fmt, q.kind, q.indices, q.value))
        sections.append({"kind": section.kind, "items": items})
    symbol = (lambda s: sp.pretty(s, use_unicode=True)) if fmt == "text" else sp.latex
    shorthand = [(symbol(s), printer.value(meaning)) for s, meaning in derivation.shorthand]
    where = [(symbol(s), printer.lines(rhs)) for s, rhs in derivation.where]
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
        "dh": dh, "sections": sections, "shorthand": shorthand, "where": where,
        "revolute": [link.is_revolute for link in robot.links],
    }
    return template_environment().get_template(TEMPLATES[fmt]).render(**context)
