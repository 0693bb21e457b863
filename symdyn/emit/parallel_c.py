"""C99 source and header of a platform robot's functions (:mod:`symdyn.derive.parallel`).

Each function is the steps of its program laid out in order: a block of assignments becomes
``const`` locals (common subexpressions named, constants folded), a requirement an early
``return`` of its status, a factorization a call of the 6x6 LU with partial pivoting in the
source (``NAME_lu6``: status when a pivot is not above ``NAME_PIVOT_RTOL`` times the matrix's
largest entry), a solve a call of the LU's forward and back substitution.  Outputs are written
last, so a nonzero status leaves them untouched (and no NaN is ever written by a check that
fails).  No derivation happens here.
"""

from __future__ import annotations

import functools
from collections import Counter
from dataclasses import dataclass, field

import sympy as sp

from .._version import __version__
from ..model.outputs import PLATFORM_SPECS
from ..model.tolerances import PIVOT_RTOL, PIVOT_RTOL_SYMBOL as RTOL_SYMBOL
from ..derive.parallel import (FORWARD_SINGULAR_DOC, FUNCTIONS, INPUT_SIZES, STATUS, STATUS_DOC, Block, Factor,
                               ParallelEquations, Require, Solve)
from .cgen import CFunction, scalar_type
from .cplan import merge_cse
from .cprinter import CPrinter, count_operations
from .emission import (banner_fields, comment_text, factor_coefficients, fold_constants, fresh_symbols, pair_cse,
                       platform_constant_rows, source_label, template_environment)


INPUT_DOCS = {
    "pose": "platform pose: position of the platform frame P's origin (m, world frame), then P's "
            "orientation as a quaternion (x, y, z, w): any nonzero quaternion, it is normalized",
    "twist": "platform twist t = [omega; c_dot]: angular velocity (rad/s) and velocity of the "
             "platform's mass centre (m/s), world axes",
    "twist_rate": "t_dot = [omega_dot; c_ddot] (rad/s^2, m/s^2, world axes)",
    "phi": "actuator forces (N) or torques (N m), leg by leg",
}
#: what each output argument holds, from the functions' specs
OUTPUT_DOCS = {argument.name: argument.doc for spec in PLATFORM_SPECS for argument in spec.arguments}
#: operations of the LU helpers (6x6): factorization, and one solve (either side) per column
LU_OPS = Counter(mul=70, add=55, div=6)
SOLVE_OPS = Counter(mul=36, add=30)


@dataclass
class _Body:
    lines: list = field(default_factory=list)
    ops: Counter = field(default_factory=Counter)


def _c_name(sym: sp.Symbol) -> str:
    return sym.name.lstrip("_")


@functools.lru_cache(maxsize=None)
def _folded(expr: sp.Expr) -> sp.Expr:
    """:func:`fold_constants`, once per expression (the functions share most of their steps)."""
    return fold_constants(expr)


def _emit_function(eqs: ParallelEquations, name: str, precision: str, prefix: str) -> CFunction:
    function = eqs.function(name)
    real = f"{prefix}_real"
    names: dict = {RTOL_SYMBOL: f"{prefix.upper()}_PIVOT_RTOL"}
    for group, syms in function.inputs:
        for k, s in enumerate(syms):
            names[s] = f"{group}[{k}]"
    printer = CPrinter(names, precision)
    body = _Body()
    factors: dict[str, str] = {}
    cse_count = [0]

    def block(assignments, outputs=()):
        """Lines of a block (and of the output stores, CSE'd with it)."""
        folded = [(s, _folded(r)) for s, r in assignments]
        outs = [(target, _folded(sp.sympify(e))) for target, e in outputs]
        exprs = [r for _, r in folded] + [e for _, e in outs]
        symbols = fresh_symbols("cse", exprs + [s for s, _ in folded], start=cse_count[0])
        replacements, reduced = pair_cse(exprs, symbols)
        if replacements:  # the next block's temporaries are numbered after the last one taken
            cse_count[0] = int(replacements[-1][0].name[3:]) + 1
        statements = merge_cse([(s, r) for (s, _), r in zip(folded, reduced[:len(folded)])], replacements)
        for sym, rhs in statements:
            names[sym] = _c_name(sym)
            rhs = factor_coefficients(rhs)
            body.ops += count_operations(rhs)
            body.lines.append(f"const {real} {names[sym]} = {printer.doprint(rhs)};")
        for (target, _), e in zip(outs, reduced[len(folded):]):
            e = factor_coefficients(sp.sympify(e))
            body.ops += count_operations(e)
            body.lines.append(f"{target} = {printer.doprint(e)};")

    for step in function.steps:
        if isinstance(step, Block):
            block(step.assignments)
        elif isinstance(step, Require):
            test = ">" if step.strict else ">="
            value = _folded(step.value)
            body.ops += count_operations(value)
            body.lines.append(f"if (!({printer.doprint(value)} {test} 0)) return {prefix.upper()}_"
                              f"{step.status.upper()};")
        elif isinstance(step, Factor):
            lu = f"lu_{step.name}"
            factors[step.name] = lu
            entries = ", ".join(printer.doprint(fold_constants(sp.sympify(e))) for e in step.matrix)
            body.lines.append(f"{real} {lu}[36] = {{{entries}}};")
            body.lines.append(f"int {lu}_piv[6];")
            body.lines.append(f"if ({prefix}_lu6({lu}, {lu}_piv)) return {prefix.upper()}_{step.status.upper()};")
            body.ops += LU_OPS
        else:  # Solve
            assert isinstance(step, Solve)
            lu = factors[step.factor]
            rows, cols = step.rhs.shape
            array = f"sol_{_c_name(step.result[0, 0]).rsplit('_', 1)[0]}"
            entries = ", ".join(printer.doprint(fold_constants(sp.sympify(step.rhs[i, j])))
                                for j in range(cols) for i in range(rows))
            body.lines.append(f"{real} {array}[{rows * cols}] = {{{entries}}};")
            helper = f"{prefix}_lu6_solve{'_t' if step.transpose else ''}"
            if cols == 1:
                body.lines.append(f"{helper}({lu}, {lu}_piv, {array});")
            else:
                body.lines.append(f"for (int col = 0; col < {cols}; ++col) {helper}({lu}, {lu}_piv, {array} + 6*col);")
            for i in range(rows):
                for j in range(cols):
                    names[step.result[i, j]] = f"{array}[{6 * j + i}]"
            body.ops += Counter({k: v * cols for k, v in SOLVE_OPS.items()})
    # the results into a local array first: every one finite, else a status and no output written
    stores, copies, size = [], [], 0
    for arg, matrix in function.outputs:
        count = matrix.rows * matrix.cols
        stores += [(f"result[{size + k}]", matrix[k // matrix.cols, k % matrix.cols]) for k in range(count)]
        copies.append((arg, size, count))
        size += count
    body.lines.append(f"{real} result[{size}];")
    block([], stores)
    fabs, limit = ("fabsf", "FLT_MAX") if precision == "float" else ("fabs", "DBL_MAX")
    body.lines += [f"for (int k = 0; k < {size}; ++k) {{",
                   f"    if (!({fabs}(result[k]) <= {limit})) return {prefix.upper()}_NOT_FINITE;",
                   "}"]
    for arg, offset, count in copies:
        body.lines += [f"for (int k = 0; k < {count}; ++k) {{", f"    {arg}[k] = result[{offset} + k];", "}"]
    body.lines.append("return 0;")
    args = [(f"const {real} ", f"{group}[{INPUT_SIZES[group]}]", INPUT_DOCS[group], False)
            for group, _ in function.inputs]
    args += [(f"{real} ", f"{arg}[{m.rows * m.cols}]", OUTPUT_DOCS[arg], True) for arg, m in function.outputs]
    statuses = function.statuses
    docs = dict(STATUS_DOC, singular=FORWARD_SINGULAR_DOC) if name == "forward_dynamics" else STATUS_DOC
    returns_doc = f"Returns {prefix.upper()}_OK (0) on success; " + "; ".join(
        f"{prefix.upper()}_{s.upper()} ({STATUS[s]}) when {docs[s]}" for s in statuses) + \
        ". On a nonzero return no output is written."
    return CFunction(name=name, summary=function.summary, args=args, lines=body.lines, ops=body.ops,
                     returns="int", returns_doc=returns_doc)


def generate_parallel_c(eqs: ParallelEquations, functions=None, precision: str = "double",
                        source_name: str = "", source_hash: str = "", notes=(), progress=None) -> dict[str, str]:
    """Render ``NAME_dynamics.h`` and ``NAME_dynamics.c`` for a platform robot (``precision``
    ``double`` or ``float``).  Returns ``{file name: text}``."""
    robot = eqs.robot
    prefix = robot.name
    wanted = [f for f in FUNCTIONS if f in (functions or eqs.function_names)]
    built = []
    for f in wanted:
        if progress is not None:
            progress(f"{prefix}: C for {f}")
        built.append(_emit_function(eqs, f, precision, prefix))
    legs = []
    for leg, branch in zip(robot.legs, eqs.branches):
        link = leg.actuated_link
        legs.append(f"{leg.name}: actuated joint {leg.actuated + 1} ({link.name}, "
                    f"{'revolute' if link.is_revolute else 'prismatic'}); inverse-kinematics branches "
                    f"(joint 4, universal, spherical) {tuple(branch)}")
    context = {
        "prefix": prefix,
        "upper": prefix.upper(),
        "guard": f"{prefix.upper()}_DYNAMICS_H",
        "version": __version__,
        "source_name": source_label(source_name or robot.source),
        "source_hash": source_hash or robot.source_hash,
        "precision": precision,
        "real": scalar_type(precision),
        "float": precision == "float",
        **banner_fields(prefix, precision),
        "rtol": CPrinter({}, precision).literal(PIVOT_RTOL[precision]),
        "rtol_text": repr(PIVOT_RTOL[precision]),
        "statuses": [("OK", 0, "success: every output written")] + [(k.upper(), v, STATUS_DOC[k]) for k, v in STATUS.items()],
        "legs": legs,
        # rounded to 1e-9: the file's home configuration holds the pose to about 1e-10
        "home": ", ".join(f"{(round(x, 9) or 0.0):.10g}" for x in eqs.home_pose),
        "constants": platform_constant_rows(robot),
        "functions": built,
        "notes": [comment_text(note) for note in notes],
        # the LU helpers the functions call (an unused static function is a warning)
        "helpers": {helper: any(f"{prefix}_{helper}(" in line for f in built for line in f.lines)
                    for helper in ("lu6", "lu6_solve", "lu6_solve_t")},
    }
    env = template_environment()
    return {f"{prefix}_dynamics.h": env.get_template("parallel.h.j2").render(**context),
            f"{prefix}_dynamics.c": env.get_template("parallel.c.j2").render(**context)}
