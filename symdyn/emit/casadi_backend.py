"""CasADi emitter: the derived equations as ``casadi.Function`` SX graphs.

This module derives nothing.  It takes the same :class:`~symdyn.derive.equations.Equations` as the C
emitter (one derivation, two emitters) and maps each intermediate assignment of the program to
one SX node, so the graph shares every sub-result the derivation named; CasADi's own common
subexpression elimination (``cse``) then runs on top.  Constants are folded to doubles exactly
as for C.

Functions, in symdyn's notation (see :mod:`symdyn.derive.equations`), N joints, NP parameters::

    inverse_dynamics(q, qd, qdd[, p]) -> tau      N x 1
    mass_matrix(q[, p]) -> D                      N x N (symmetric, without armature)
    coriolis(q, qd[, p]) -> h                     N x 1
    coriolis_matrix(q, qd[, p]) -> C              N x N
    gravity(q[, p]) -> c                          N x 1
    forward_dynamics(q, qd, tau[, p]) -> qdd      N x 1

``p`` (runtime parameters and free symbols, in the order of ``robot.parameters``) is an input
only when the robot has parameters.  All are SX functions: differentiate them with
``casadi.jacobian``/``Function.jacobian``, call them on MX inside ``Opti``, or generate C.
"""

from __future__ import annotations

import os
from typing import Iterable

import casadi as ca
import sympy as sp

from .emission import fold_constants
from ..derive.equations import Equations
from ..model.outputs import ALL_OUTPUTS, INPUT_GROUPS, OUTPUT_INPUTS, OUTPUT_SYMBOLS, REGISTRY, default_outputs, with_requirements
from ..model.errors import SymdynError

INPUT_DOCS = {
    "q": "joint positions (rad or m)",
    "qd": "joint velocities (rad/s or m/s)",
    "qdd": "joint accelerations (rad/s^2 or m/s^2)",
    "tau": "joint torques/forces (N m or N)",
    "v": "a displacement of the joints (rad or m)",
    "q1": "joint positions of a second configuration (rad or m)",
    "f": "external forces at the contacts (laid out as the contact forces; N, N m, world axes)",
    "restitution": "restitution of the impact (one entry: 0 the contacts stop, 1 they bounce back)",
    "p": "runtime parameters, in the order of robot.parameters",
}
#: a floating base's inputs (Pinocchio's free-flyer first, then the joints)
FLOATING_INPUT_DOCS = {
    **INPUT_DOCS,
    "q": "NQ = N + 1: base position (m), quaternion x, y, z, w (normalized inside), joint positions",
    "qd": "base linear and angular velocity (base frame; m/s, rad/s), joint velocities",
    "qdd": "their derivatives (the base's spatial acceleration in its frame), joint accelerations",
    "tau": "force (N) and moment (N m) on the base in its frame, joint torques/forces",
    "v": "tangent vector laid out as qd (the base's displacement in its frame, m and rad), joint displacements",
    "q1": "a second configuration, laid out as q",
}

#: SymPy's comparisons as CasADi's
_COMPARISONS = {"<": ca.lt, "<=": ca.le, ">": ca.gt, ">=": ca.ge}
_UNARY = {sp.sin: ca.sin, sp.cos: ca.cos, sp.tan: ca.tan, sp.exp: ca.exp, sp.log: ca.log,
          sp.Abs: ca.fabs, sp.sign: ca.sign}


class SxConverter:
    """SymPy expression -> SX, with inputs and intermediate symbols looked up in ``env``."""

    def __init__(self, env: dict[sp.Symbol, ca.SX]):
        self.env = env
        self.memo: dict[sp.Expr, ca.SX] = {}

    def __call__(self, expr: sp.Expr) -> ca.SX:
        expr = sp.sympify(expr)
        if expr in self.env:
            return self.env[expr]
        hit = self.memo.get(expr)
        if hit is not None:
            return hit
        value = self._convert(expr)
        self.memo[expr] = value
        return value

    def _power(self, base, k: int):
        if k == 2:
            return base ** 2  # CasADi keeps this as sq(x)
        result = base
        for _ in range(k - 1):
            result = result * base
        return result

    def _convert(self, e: sp.Expr) -> ca.SX:
        if e.is_Number:
            return ca.SX(float(e))
        if e.is_Symbol:
            raise SymdynError(f"symbol {e} is neither an input, a parameter nor an intermediate")
        if e.is_Add:
            total = self(e.args[0])
            for a in e.args[1:]:
                total = total + self(a)
            return total
        if e.is_Mul:
            numerator, denominator = [], []
            for a in e.args:
                if a.is_Pow and a.exp.is_Integer and a.exp < 0:
                    denominator.append(sp.Pow(a.base, -a.exp))
                else:
                    numerator.append(a)
            value = self(numerator[0]) if numerator else ca.SX(1.0)
            for a in numerator[1:]:
                value = value * self(a)
            for a in denominator:
                value = value / self(a)
            return value
        if e.is_Pow:
            base, exp = e.args
            if exp.is_Integer:
                k = int(exp)
                if k > 0:
                    return self._power(self(base), k)
                return 1 / self._power(self(base), -k)
            if exp == sp.S.Half:
                return ca.sqrt(self(base))
            if exp == -sp.S.Half:
                return 1 / ca.sqrt(self(base))
            return ca.power(self(base), self(exp))
        func = _UNARY.get(type(e))
        if func is not None:
            return func(self(e.args[0]))
        if isinstance(e, sp.atan2):
            return ca.atan2(self(e.args[0]), self(e.args[1]))
        if isinstance(e, sp.Piecewise):  # (both branches are finite: the closed forms divide by guarded values)
            result = self(e.args[-1].expr)
            for value, condition in reversed(e.args[:-1]):
                result = ca.if_else(self(condition), self(value), result)
            return result
        if isinstance(e, sp.core.relational.Relational) and e.rel_op in _COMPARISONS:
            return _COMPARISONS[e.rel_op](self(e.lhs), self(e.rhs))
        raise SymdynError(f"no CasADi form for {type(e).__name__} in the equations")


def _inputs_for(eqs: Equations, groups: Iterable[str]):
    """SX symbols of the named input groups (+ p when the robot has parameters), and the map
    from symdyn's scalar symbols to their entries."""
    env: dict[sp.Symbol, ca.SX] = {}
    symbols, names = [], []
    for group in groups:
        sym = ca.SX.sym(group, len(getattr(eqs, group)))
        for k, s in enumerate(getattr(eqs, group)):
            env[s] = sym[k]
        if group in ("q", "q1") and eqs.robot.floating:
            # a floating base's quaternion divided by its largest magnitude (as the generated C
            # does): any nonzero scale, subnormal to 1e308, gives the same rotation
            scale = ca.fmax(ca.fmax(ca.fabs(sym[3]), ca.fabs(sym[4])), ca.fmax(ca.fabs(sym[5]), ca.fabs(sym[6])))
            for k, s in enumerate(getattr(eqs, group)[3:7]):
                env[s] = sym[3 + k] / scale
        symbols.append(sym)
        names.append(group)
    if eqs.parameters:
        p = ca.SX.sym("p", len(eqs.parameters))
        for k, s in enumerate(eqs.parameters):
            env[s] = p[k]
        symbols.append(p)
        names.append("p")
    return symbols, names, env


def _outputs_sx(eqs: Equations, names: Iterable[str], env: dict) -> list[ca.SX]:
    names = list(names)
    matrices = [eqs.output(name) for name in names]
    convert = SxConverter(env)
    for sym, rhs in eqs.program.needed_for([e for m in matrices for e in m]):
        env[sym] = convert(fold_constants(rhs))
    results = []
    for matrix in matrices:
        rows, cols = matrix.shape
        out = ca.SX(rows, cols)
        for r in range(rows):
            for c in range(cols):
                out[r, c] = convert(fold_constants(sp.sympify(matrix[r, c])))
        results.append(out)
    return results


def casadi_function(eqs: Equations, name: str, function_name: str | None = None, cse: bool = True) -> ca.Function:
    """One output of ``eqs`` (a name from :data:`symdyn.OUTPUTS`) as a ``casadi.Function``
    with named inputs (``q``, ``qd``, ``qdd``/``tau``, ``p``) and output (``tau``, ``D``, ``h``,
    ``C``, ``c`` or ``qdd``; the reaction map has two: ``k0`` (6) and ``D`` (6 x actuated joints))."""
    if name not in ALL_OUTPUTS:
        raise SymdynError(f"unknown function {name!r} (known: {', '.join(ALL_OUTPUTS)})")
    symbols, in_names, env = _inputs_for(eqs, OUTPUT_INPUTS[name])
    [out] = _outputs_sx(eqs, [name], env)
    arguments = REGISTRY[name].arguments
    if len(arguments) > 1:  # one CasADi output per argument, the output's columns split as in C
        blocks = [out[:, a.first:(out.size2() if a.end is None else a.end)] for a in arguments]
        return ca.Function(function_name or name, symbols, blocks, in_names, [a.name for a in arguments],
                           {"cse": cse})
    return ca.Function(function_name or name, symbols, [out], in_names, [OUTPUT_SYMBOLS[name]],
                       {"cse": cse})


def combined_function(eqs: Equations, functions: Iterable[str] | None = None,
                      function_name: str | None = None, cse: bool = True) -> ca.Function:
    """All the asked outputs in one ``casadi.Function`` (``NAME_dynamics``): inputs are the union
    of theirs in the order q, qd, qdd, tau, p; outputs are named after the functions
    (``inverse_dynamics``, ``mass_matrix``, ...; ``reaction_map`` as ``[k0 | D]``)."""
    functions = [f for f in ALL_OUTPUTS if f in (functions or eqs.output_names)]
    groups = [g for g in INPUT_GROUPS if any(g in OUTPUT_INPUTS[f] for f in functions)]
    symbols, in_names, env = _inputs_for(eqs, groups)
    outs = _outputs_sx(eqs, functions, env)
    return ca.Function(function_name or f"{eqs.robot.name}_dynamics", symbols, outs, in_names,
                       list(functions), {"cse": cse})


def to_casadi(source, functions: Iterable[str] | None = None, method: str = "newton-euler",
              prefix: str = "", use_cache: bool = True, fd_method: str = "ldlt") -> dict[str, ca.Function]:
    """The equations of motion as named ``casadi.Function``s.

    Parameters
    ----------
    source : an :class:`~symdyn.derive.equations.Equations`, a :class:`~symdyn.model.robot.Robot`, or the
        path of a robot file (then derived with ``method``, through the on-disk cache).
    functions : names from :data:`symdyn.OUTPUTS` (default: all).
    prefix : prepended to each Function's name (for example ``"puma560_"``).
    fd_method : forward dynamics by ``'ldlt'`` (default) or the articulated-body algorithm ``'aba'``.

    Returns
    -------
    ``{name: casadi.Function}`` in the order of :data:`symdyn.OUTPUTS`, for example
    ``fns["inverse_dynamics"](q, qd, qdd) -> tau`` (DM in, DM out; SX or MX in, expressions out).
    """
    from ..derive.cache import derive_cached
    from ..model.robot import load, serial_robot

    unknown = [f for f in (functions or ()) if f not in ALL_OUTPUTS]
    if unknown:
        raise SymdynError(f"unknown function {unknown[0]!r} (known: {', '.join(ALL_OUTPUTS)})")
    if isinstance(source, (str, os.PathLike)):
        source = load(os.fspath(source))
    if isinstance(source, Equations):
        wanted = tuple(f for f in ALL_OUTPUTS if f in (functions or source.output_names))
    else:  # a robot (anything else is refused in one line, naming it)
        robot = serial_robot(source)
        wanted = tuple(f for f in ALL_OUTPUTS if f in (functions or default_outputs(robot)))
        source = derive_cached(robot, method, with_requirements(wanted), use_cache=use_cache, fd_method=fd_method)
    return {name: casadi_function(source, name, prefix + name) for name in wanted}


def signature_text(function: ca.Function) -> str:
    def part(k, io):
        name = function.name_in(k) if io == "in" else function.name_out(k)
        sp_ = function.sparsity_in(k) if io == "in" else function.sparsity_out(k)
        shape = f"{sp_.size1()}" if sp_.size2() == 1 else f"{sp_.size1()}x{sp_.size2()}"
        return f"{name}[{shape}]"
    ins = ", ".join(part(k, "in") for k in range(function.n_in()))
    outs = ", ".join(part(k, "out") for k in range(function.n_out()))
    return f"{function.name()}({ins}) -> ({outs})"


def _saved_bytes(function: ca.Function, workdir: str) -> bytes:
    path = os.path.join(workdir, f"{function.name()}.casadi")
    function.save(path)
    with open(path, "rb") as handle:
        return handle.read()


def casadi_files(eqs: Equations, functions: Iterable[str] | None = None, casadi_c: bool = False,
                 source_name: str = "", source_hash: str = "") -> dict[str, bytes]:
    """The CasADi target's files, ``{file name: content}``, written nowhere:

    - ``NAME_dynamics.casadi``: one Function ``NAME_dynamics`` with every asked output;
    - ``NAME_<function>.casadi``: one Function ``NAME_<function>`` each;
    - ``NAME_casadi.txt``: what the files hold, their signatures, input file and versions;
    - with ``casadi_c``: ``NAME_casadi.c``/``.h``, CasADi's generated C of the same functions.
    """
    import tempfile

    from .._version import __version__
    from .emission import banner_fields, robot_words, source_label, template_environment

    prefix = eqs.robot.name
    functions = [f for f in ALL_OUTPUTS if f in (functions or eqs.output_names)]
    combined = combined_function(eqs, functions, f"{prefix}_dynamics")
    single = [casadi_function(eqs, f, f"{prefix}_{f}") for f in functions]
    files: dict[str, bytes] = {}
    with tempfile.TemporaryDirectory(prefix="symdyn-casadi-") as workdir:
        for function in [combined] + single:
            files[f"{function.name()}.casadi"] = _saved_bytes(function, workdir)
        if casadi_c:
            banner = template_environment().get_template("banner.j2").render(
                prefix=prefix, version=__version__, **banner_fields(prefix, "double", eqs.method, eqs.robot),
                source_name=source_label(source_name or eqs.robot.source),
                source_hash=source_hash or eqs.robot.source_hash,
                notes=[f"C generated by CasADi {ca.__version__} (for comparison; symdyn's own C "
                       "is the c target)"])
            generator = ca.CodeGenerator(f"{prefix}_casadi.c", {"with_header": True})
            for f in functions:
                generator.add(casadi_function(eqs, f, f"{prefix}_casadi_{f}"))
            generator.generate(workdir + os.sep)
            for ext in ("c", "h"):
                with open(os.path.join(workdir, f"{prefix}_casadi.{ext}"), "rb") as handle:
                    files[f"{prefix}_casadi.{ext}"] = banner.encode() + handle.read()
    robot = eqs.robot
    readme = template_environment().get_template("casadi_readme.txt.j2").render(
        prefix=prefix, robot_words=robot_words(robot), nv=eqs.n, version=__version__,
        casadi_version=ca.__version__, method=eqs.method,
        source_name=source_label(source_name or robot.source), source_hash=source_hash or robot.source_hash,
        combined_inputs=[combined.name_in(k) for k in range(combined.n_in())],
        files=[(f"{fn.name()}.casadi", signature_text(fn)) for fn in [combined] + single],
        casadi_c=casadi_c,
        input_docs=[(k, v) for k, v in (FLOATING_INPUT_DOCS if robot.floating else INPUT_DOCS).items()
                    if k != "p" or robot.parameters],
        parameters=[(k, s.name, "runtime parameter" if s.name in robot.runtime_names else "free symbol",
                     (repr(float(v)) if v is not None else None))
                    for k, (s, v) in enumerate(zip(robot.parameters, robot.nominal))])
    files[f"{prefix}_casadi.txt"] = readme.encode()
    return files
