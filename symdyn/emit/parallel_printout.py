"""Printing a platform robot's derivation (:mod:`symdyn.derive.parallel_steps`) as text,
LaTeX or Markdown: each step of the parallel-manipulator notes with its formula and its values at the state.  Numbers
are shown with 6 significant digits (``digits``; entries below 1e-9, relative to the larger of 1 and their
array's largest entry, as 0).  No derivation happens here."""

from __future__ import annotations

import numpy as np

from .._version import __version__
from ..derive.parallel_steps import ParallelDerivation
from .emission import source_label, template_environment

TEMPLATES = {"text": "parallel_derivation.txt.j2", "latex": "parallel_derivation.tex.j2",
             "markdown": "parallel_derivation.md.j2"}

#: the formulas of the steps in LaTeX (the plain-text ones come with the steps), by title
LATEX = {
    "Leg Jacobians": r"\mathbf{J}_J \dot{\boldsymbol\theta}_J = \mathbf{t}_{\mathcal{M}}, \quad "
                     r"\mathbf{J}_J = \begin{bmatrix} \mathbf{e}_1 & \cdots & \mathbf{e}_6 \\ "
                     r"\mathbf{e}_1 \times \mathbf{r}_1 & \cdots & \mathbf{e}_6 \times \mathbf{r}_6 \end{bmatrix}",
    "A_J": r"\mathbf{A}_J = [\mathbf{R}_{J1} \;\; \mathbf{1}], \quad \mathbf{A}_J \mathbf{J}_J = "
           r"[\mathbf{0} \;\; \mathbf{0} \;\; \mathbf{0} \;\; \mathbf{e}_4 \times (\mathbf{r}_4 - \mathbf{r}_1) \;\; "
           r"\mathbf{e}_5 \times (\mathbf{r}_5 - \mathbf{r}_1) \;\; \mathbf{e}_6 \times (\mathbf{r}_5 - \mathbf{r}_1)]",
    "Scalar twist-shape relations": r"\zeta_J \dot q_J = \mathbf{y}_J^T \mathbf{t}_{\mathcal{M}}, \quad "
                                    r"\mathbf{u}_J = [\mathbf{e}_5 \times (\mathbf{r}_5 - \mathbf{r}_1)] \times "
                                    r"[\mathbf{e}_6 \times (\mathbf{r}_5 - \mathbf{r}_1)], \quad "
                                    r"\zeta_J = \mathbf{u}_J \cdot \mathbf{e}_k \times (\mathbf{r}_k - \mathbf{r}_1), \quad "
                                    r"\mathbf{y}_J = \begin{bmatrix} -\mathbf{r}_1 \times \mathbf{u}_J \\ \mathbf{u}_J \end{bmatrix}",
    "Y": r"\mathbf{Y} = \begin{bmatrix} \mathbf{y}_I^T \\ \vdots \\ \mathbf{y}_{VI}^T \end{bmatrix}",
    "Z": r"\mathbf{Z} = \operatorname{diag}(\zeta_I, \ldots, \zeta_{VI})",
    "T": r"\mathbf{T} = \mathbf{Y}^{-1} \mathbf{Z} \quad (\mathbf{t}_{\mathcal{M}} = \mathbf{T} \dot{\mathbf{q}})",
    "L_J": r"\mathbf{L}_J = \mathbf{J}_J^{-1} \mathbf{T} \quad (\dot{\boldsymbol\theta}_J = \mathbf{L}_J \dot{\mathbf{q}})",
    "M": r"\mathbf{M}(\mathbf{q}) = \mathbf{T}^T \mathbf{M}_{\mathcal{M}} \mathbf{T} + \sum_J \mathbf{L}_J^T \mathbf{I}_J \mathbf{L}_J",
    "N": r"\mathbf{N}(\mathbf{q}, \dot{\mathbf{q}}) \dot{\mathbf{q}} = \mathbf{T}^T (\mathbf{M}_{\mathcal{M}} \dot{\mathbf{T}} "
         r"+ \mathbf{W}_{\mathcal{M}} \mathbf{M}_{\mathcal{M}} \mathbf{T}) \dot{\mathbf{q}} + \sum_J \mathbf{L}_J^T "
         r"(\mathbf{I}_J \dot{\mathbf{L}}_J + \mathbf{C}_J \mathbf{L}_J) \dot{\mathbf{q}}",
    "Lambda": r"\boldsymbol\Lambda = [\mathbf{L}_I^T \mathbf{e}_{Ik} \;\; \cdots \;\; \mathbf{L}_{VI}^T \mathbf{e}_{VIk}]",
    "phi": r"\boldsymbol\phi = \boldsymbol\Lambda^{-1} [\mathbf{M}(\mathbf{q}) \ddot{\mathbf{q}} + "
           r"\mathbf{N}(\mathbf{q}, \dot{\mathbf{q}}) \dot{\mathbf{q}} - \boldsymbol\tau^W]",
}


def _number(x: float, digits: int = 6) -> str:
    text = f"{x:.{digits}g}"
    return "0" if text in ("0", "-0") else text


def _latex_number(text: str) -> str:
    """6.1e-05 as 6.1 \\cdot 10^{-5} (math mode)."""
    if "e" not in text:
        return text
    mantissa, exponent = text.split("e")
    return f"{mantissa} \\cdot 10^{{{int(exponent)}}}"


#: entries below this times the larger of 1 and the array's largest entry print as 0 (rounding
#: noise: the home pose of a file is written to 10 digits, so the legs' joint values at it are
#: zero only to about 1e-10)
NOISE = 1e-9


def _rows(value, digits: int = 6) -> list[list[str]]:
    array = np.atleast_1d(np.asarray(value, dtype=float))
    array = np.where(np.abs(array) < NOISE * max(1.0, float(np.abs(array).max())), 0.0, array)
    if array.ndim == 1:
        return [[_number(x, digits)] for x in array]  # a column vector
    return [[_number(x, digits) for x in row] for row in array]


def _latex_label(label: str) -> str:
    out = label.replace("theta", r"\theta").replace("zeta", r"\zeta").replace("Lambda", r"\Lambda") \
        .replace("phi", r"\phi").replace("tau^W", r"\tau^W").replace("q_dot", r"\dot q").replace("q_ddot", r"\ddot q")
    if "_" in out and "{" not in out:
        head, _, tail = out.partition("_")
        out = f"{head}_{{{tail}}}"
    return out


def render_parallel(derivation: ParallelDerivation, fmt: str, source_name: str = "", source_hash: str = "",
                    digits: int = 6) -> str:
    """The derivation as ``text``, ``latex`` or ``markdown``, numbers to ``digits`` significant
    digits (``symdyn derive --digits``)."""
    robot = derivation.robot
    steps = []
    for number, step in enumerate(derivation.steps, start=1):
        values = []
        for label, value in step.values:
            rows = _rows(value, digits)
            width = max(len(x) for row in rows for x in row)
            values.append({"label": label, "latex_label": _latex_label(label), "rows": rows,
                           "latex_rows": [[_latex_number(x) for x in row] for row in rows],
                           "text": ["[ " + "  ".join(x.rjust(width) for x in row) + " ]" for row in rows],
                           "scalar": np.ndim(value) == 0})
        steps.append({"number": number, "title": step.title, "formula": step.formula,
                      "latex": LATEX[step.title], "entries": values})
    context = {
        "name": robot.name, "version": __version__,
        "source_name": source_label(source_name or robot.source),
        "source_hash": source_hash or robot.source_hash,
        "pose": [row[0] for row in _rows(derivation.pose, digits)],
        "twist": [_number(x, digits) for x in derivation.twist],
        "accelerations": [_number(x, digits) for x in derivation.accelerations],
        "legs": [(leg.name, leg.actuated + 1, leg.actuated_link.name,
                  "revolute" if leg.actuated_link.is_revolute else "prismatic") for leg in robot.legs],
        "steps": steps,
    }
    return template_environment().get_template(TEMPLATES[fmt]).render(**context)
