"""CasADi functions of a platform robot (:mod:`symdyn.derive.parallel`).

Each function takes the state arrays (``pose`` 7, ``twist`` 6, and ``twist_rate`` or ``phi``)
and returns its outputs, named as in the generated C.  The blocks of assignments become SX
expressions; each 6x6 solve is CasADi's symbolic ``solve`` (so the functions differentiate
through it).  The run-time checks of the C functions have no counterpart: at a singular or
unreachable pose the CasADi functions return NaN or infinity.
"""

from __future__ import annotations

import casadi as ca
import sympy as sp

from ..derive.parallel import FUNCTIONS, Block, Factor, ParallelEquations, Solve
from .casadi_backend import SxConverter
from .emission import fold_constants


def parallel_casadi_function(eqs: ParallelEquations, name: str, function_name: str | None = None,
                             cse: bool = True) -> ca.Function:
    """Function ``name`` of :data:`symdyn.derive.parallel.FUNCTIONS` as a ``casadi.Function``
    (called ``function_name``, default ``name``)."""
    function = eqs.function(name)
    env: dict = {}
    symbols, names = [], []
    for group, syms in function.inputs:
        sx = ca.SX.sym(group, len(syms))
        env.update({s: sx[k] for k, s in enumerate(syms)})
        symbols.append(sx)
        names.append(group)
    convert = SxConverter(env)
    factors: dict[str, ca.SX] = {}

    def matrix(m: sp.MatrixBase) -> ca.SX:
        out = ca.SX(m.rows, m.cols)
        for i in range(m.rows):
            for j in range(m.cols):
                out[i, j] = convert(fold_constants(sp.sympify(m[i, j])))
        return out
    for step in function.steps:
        if isinstance(step, Block):
            for sym, rhs in step.assignments:
                env[sym] = convert(fold_constants(rhs))
        elif isinstance(step, Factor):
            factors[step.name] = matrix(step.matrix)
        elif isinstance(step, Solve):
            a = factors[step.factor]
            x = ca.solve(a.T if step.transpose else a, matrix(step.rhs))
            for i in range(step.result.rows):
                for j in range(step.result.cols):
                    env[step.result[i, j]] = x[i, j]
    outputs = [matrix(m) for _, m in function.outputs]
    out_names = [k for k, _ in function.outputs]
    return ca.Function(function_name or name, symbols, outputs, names, out_names, {"cse": cse})


def parallel_casadi_functions(eqs: ParallelEquations, functions=None) -> dict[str, ca.Function]:
    """Every derived function (or the named ones) by name."""
    return {name: parallel_casadi_function(eqs, name) for name in (functions or eqs.function_names)
            if name in FUNCTIONS}


def parallel_casadi_files(eqs: ParallelEquations, functions=None, source_name: str = "",
                          source_hash: str = "") -> dict[str, bytes]:
    """The CasADi target's files for a platform robot, ``{file name: content}``, written nowhere:
    ``NAME_<function>.casadi`` (one Function ``NAME_<function>`` each) and ``NAME_casadi.txt``."""
    import os
    import tempfile

    from .._version import __version__
    from .casadi_backend import signature_text
    from .emission import source_label, template_environment
    from .parallel_c import INPUT_DOCS, OUTPUT_DOCS

    robot = eqs.robot
    prefix = robot.name
    wanted = [f for f in FUNCTIONS if f in (functions or eqs.function_names)]
    files: dict[str, bytes] = {}
    built = []
    with tempfile.TemporaryDirectory(prefix="symdyn-casadi-") as workdir:
        for name in wanted:
            function = parallel_casadi_function(eqs, name, f"{prefix}_{name}")
            path = os.path.join(workdir, f"{function.name()}.casadi")
            function.save(path)
            with open(path, "rb") as handle:
                files[f"{function.name()}.casadi"] = handle.read()
            built.append(function)
    docs = list(INPUT_DOCS.items()) + [(k, v) for k, v in OUTPUT_DOCS.items() if k not in INPUT_DOCS]
    readme = template_environment().get_template("parallel_casadi_readme.txt.j2").render(
        prefix=prefix, version=__version__, casadi_version=ca.__version__,
        source_name=source_label(source_name or robot.source), source_hash=source_hash or robot.source_hash,
        files=[(f"{fn.name()}.casadi", signature_text(fn)) for fn in built], docs=docs)
    files[f"{prefix}_casadi.txt"] = readme.encode("utf-8")
    return files

