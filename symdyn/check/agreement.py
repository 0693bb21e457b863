"""Every target of a derivation compared with an independent reference: the compiled C, the
numpy functions and the CasADi functions, output by output, by :func:`normalized_error`.

``symdyn verify`` and the differential fuzzer (:mod:`symdyn.check.fuzz`) both read their numbers
through here.  The regressors, which Pinocchio has not, are compared as torques (``Y pi`` and
``Y_b beta`` with the file's parameters against inverse dynamics); the task-space functions at the
states whose task is away from singularities (:data:`TASK_REGULAR`).
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..model.tolerances import VERIFY_FLOOR
from ..model.outputs import CONTACT_INVERSE, REGISTRY, TASK_OUTPUTS
from .pinocchio_model import compare

#: the task-space functions are compared at states whose task's smallest relative pivot (the
#: reference's :meth:`~symdyn.check.pinocchio_model.PinocchioReference.task_pivot_ratio`) is above this
TASK_REGULAR = 1e-3

REGRESSORS = ("regressor", "base_regressor")


def derive_supported(robot, method: str, functions, fd_method: str = "ldlt", use_cache: bool = True,
                     progress=None, parameters: str = "standard"):
    """``(eqs, functions)``: ``functions`` derived, less the task-space ones when the robot's task
    cannot be moved in at any configuration (:class:`symdyn.derive.equations.TaskUnreachable`:
    those functions do not exist for it)."""
    from ..derive.cache import derive_cached
    from ..derive.equations import TaskUnreachable
    from ..model.outputs import with_requirements
    functions = tuple(functions)
    try:
        return derive_cached(robot, method, with_requirements(functions), use_cache, progress, fd_method,
                             parameters), functions
    except TaskUnreachable:
        if not any(f in TASK_OUTPUTS for f in functions):
            raise
        functions = tuple(f for f in functions if f not in TASK_OUTPUTS)
        return derive_cached(robot, method, with_requirements(functions), use_cache, progress, fd_method,
                             parameters), functions


def compile_equations(eqs, functions, precision: str, workdir: str, source_name: str = "", extra_flags=(),
                      small_pieces: bool = False):
    """Generate the C of ``functions`` of ``eqs``, compile it in ``workdir`` and load it, with
    every size the library needs (joints, actuated joints, task rows, frames, base parameters).
    ``small_pieces``: the C in the shapes of a big robot's (:func:`symdyn.emit.cbody.small_pieces`:
    bodies in parts, tables of numbers) and in files of at most 20 kB."""
    import contextlib
    import warnings
    from ..emit import cbody
    from ..emit.cgen import C_FILE_BYTES, generate_c
    from .cbuild import build_and_load
    robot = eqs.robot
    with cbody.small_pieces() if small_pieces else contextlib.nullcontext(), warnings.catch_warnings():
        if small_pieces:
            warnings.filterwarnings("ignore", message=".*written as [0-9]+ files")
        files = generate_c(eqs, functions, precision, source_name=source_name, source_hash=robot.source_hash,
                           file_bytes=20_000 if small_pieces else C_FILE_BYTES)
    return build_and_load(files, robot.name, eqs.dimensions, len(robot.parameters), precision, workdir, extra_flags)


def parameter_values(robot, eqs, values):
    """``(pi, beta)``: the robot's standard and base parameters as numbers (``values``: a number
    for each of its symbols)."""
    from ..derive.regressor import parameter_names, standard_parameters
    pi = [float(sp.sympify(v).xreplace(values)) for v in standard_parameters(robot)]
    symbols = dict(zip((sp.Symbol(n, real=True) for n in parameter_names(robot)), pi))
    beta = [float(expr.xreplace(symbols)) for _, expr in eqs.base_parameters]
    return np.array(pi), np.array(beta)


class AsTorques:
    """A target whose regressors are evaluated as torques, ``Y pi`` and ``Y_b beta``."""

    def __init__(self, target, pi, beta):
        self._target, self._pi, self._beta = target, pi, beta

    def regressor(self, q, qd, qdd, *p):
        return np.asarray(self._target.regressor(q, qd, qdd, *p)) @ self._pi

    def base_regressor(self, q, qd, qdd, *p):
        return np.asarray(self._target.base_regressor(q, qd, qdd, *p)) @ self._beta

    def __getattr__(self, name):
        return getattr(self._target, name)


class ReferenceTorques:
    """A reference whose regressors are its inverse dynamics (see :class:`AsTorques`)."""

    def __init__(self, reference):
        self._reference = reference

    def regressor(self, q, qd, qdd):
        return self._reference.inverse_dynamics(q, qd, qdd)

    base_regressor = regressor

    def __getattr__(self, name):
        return getattr(self._reference, name)


class NumpyTarget:
    """``eqs.numeric`` with the compiled library's calling convention (``p`` last, by position)."""

    def __init__(self, eqs):
        self._numeric = eqs.numeric
        self._parameters = bool(eqs.parameters)

    def __getattr__(self, name):
        function = getattr(self._numeric, name)

        def call(*args):
            *inputs, p = args
            return function(*inputs, p=p if self._parameters else None)
        return call


class CasadiTarget:
    """One ``casadi.Function`` per output (:func:`symdyn.emit.casadi_backend.casadi_function`),
    called with numbers; a function of several outputs gives its blocks side by side, as C."""

    def __init__(self, eqs):
        self._eqs = eqs
        self._functions = {}

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        from ..emit.casadi_backend import casadi_function
        if name not in self._functions:
            self._functions[name] = casadi_function(self._eqs, name)
        function = self._functions[name]
        vector = REGISTRY[name].is_vector

        def call(*args):
            *inputs, p = args
            values = function(*inputs, *([p] if self._eqs.parameters else []))
            blocks = values if isinstance(values, (list, tuple)) else [values]
            out = np.hstack([np.array(block, dtype=float) for block in blocks])
            return out[:, 0] if vector and out.shape[1] == 1 else out
        return call


def mass_conditioning(reference, states) -> float:
    """The largest 2-norm condition number of the reference's ``M = D + diag(armature)`` over
    ``states`` (1 where it cannot be computed)."""
    worst = 1.0
    for q, *_ in states:
        try:
            worst = max(worst, float(np.linalg.cond(reference.system_matrix(q))))
        except (np.linalg.LinAlgError, ValueError):
            continue
    return worst if np.isfinite(worst) else 1.0


def robot_floors(reference, states, functions, relative: float = VERIFY_FLOOR) -> dict[str, float]:
    """The floor of each function's normalized error (:func:`normalized_error`), from the
    robot's own scale at ``states``: ``relative`` times the RMS of the reference's inverse
    dynamics for an output in torques (its spec's ``floor_scale``), that divided by the RMS
    joint rate for one in torques per unit rate, the RMS over the states of its Jacobian's norm
    times the joint rates' squared norm for an acceleration bias (J-dot qd: exactly zero where the Jacobian does not change,
    and Pinocchio's rounding then is not the measure); 0 (the output's own values) for the others."""
    scaled = {f: REGISTRY[f].floor_scale for f in functions if f in REGISTRY and REGISTRY[f].floor_scale != "own"}
    if not scaled:
        return {}
    rates = np.array([qd for _, qd, _, _ in states])
    rate = float(np.sqrt(np.mean(rates ** 2))) or 1.0
    floors = {}
    if any(scale != "drift" for scale in scaled.values()):
        torques = np.array([reference.inverse_dynamics(q, qd, qdd) for q, qd, qdd, _ in states])
        torque = float(np.sqrt(np.mean(torques ** 2))) if np.all(np.isfinite(torques)) else 0.0
        floors = {f: relative * (torque if scale == "torque" else torque / rate) for f, scale in scaled.items()
                  if scale != "drift"}
    for f in (f for f, scale in scaled.items() if scale == "drift"):  # |J-dot qd| of the order |J| |qd|^2
        sizes = np.array([np.linalg.norm(getattr(reference, REGISTRY[f].floor_jacobian)(q)) * float(qd @ qd)
                          for q, qd, _, _ in states])
        floors[f] = relative * float(np.sqrt(np.mean(sizes ** 2))) if np.all(np.isfinite(sizes)) else 0.0
    return floors


def target_errors(target, reference, robot, eqs, functions, states, p, values, floor: float | dict = 0.0,
                  task_regular: float = TASK_REGULAR, row_floor: float = 0.0) -> dict[str, float]:
    """The normalized error of each function of ``target`` (a compiled library, a
    :class:`NumpyTarget` or a :class:`CasadiTarget`) against ``reference`` over ``states``
    (regressors as torques, task-space functions at regular states: NaN when there is none;
    ``floor``, ``row_floor``: see :func:`symdyn.check.pinocchio_model.normalized_error`; ``task_regular``: the
    smallest relative pivot of the task's J M^-1 J^T at the states the task-space functions are
    compared at)."""
    functions = list(functions)
    regressors = [f for f in functions if f in REGRESSORS]
    if regressors:
        target = AsTorques(target, *parameter_values(robot, eqs, values))
        reference = ReferenceTorques(reference)
    conditioned = [f for group, _ in CONDITIONED for f in group if f in functions]
    errors = compare(target, reference, states, [f for f in functions if f not in conditioned], p, floor, row_floor)
    for group, regular in regular_states(reference, states, functions, task_regular).items():
        errors.update(compare(target, reference, regular, group, p, floor, row_floor) if regular
                      else {f: float("nan") for f in group})
    return errors


#: the outputs compared only at the states where their problem is regular, and the reference's
#: measure of that (the smallest pivot of their factorization relative to its diagonal entry):
#: the task-space functions (J M^-1 J^T) and contact inverse dynamics (the QR of the contacts'
#: unactuated columns)
CONDITIONED = ((TASK_OUTPUTS, "task_pivot_ratio"), (CONTACT_INVERSE, "contact_inverse_pivot_ratio"))


def regular_states(reference, states, functions, threshold: float = TASK_REGULAR) -> dict[tuple, list]:
    """For each group of :data:`CONDITIONED` outputs among ``functions``: ``(its outputs among
    them) -> the states whose pivot ratio is above ``threshold``."""
    out = {}
    for group, measure in CONDITIONED:
        wanted = tuple(f for f in group if f in functions)
        if wanted:
            out[wanted] = [state for state in states if getattr(reference, measure)(state[0]) > threshold]
    return out
