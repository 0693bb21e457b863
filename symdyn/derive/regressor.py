"""The dynamics in linear form, ``tau = Y(q, qd, qdd) pi``, and the base parameters.

Standard parameters, 13 per link, link by link (``P = 13 n``)::

    m, mx, my, mz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz, Ia, fv, fc

``m`` the mass; ``(mx, my, mz) = m c`` the first moment (``c``: the centre of mass); ``I..`` the
inertia tensor about the *link frame's origin* (``I_O = I_C + m (|c|^2 1 - c c^T)``), all in
the link frame of the robot file (DH frame i, or the joint frame for ``convention: general``),
in Pinocchio's order for its 10 dynamic parameters; ``Ia`` the armature, ``fv`` the viscous and
``fc`` the Coulomb friction coefficient of the joint.  (Pinocchio's ``computeJointTorqueRegressor``
uses the same order but in *its* joint frames, which for standard DH are the previous DH frame:
:func:`symdyn.check.pinocchio_model.regressor_map` converts.)

The regressor is derived by the spatial Newton-Euler recursion written linearly in the
parameters: each link's body force ``f_j = A_j(v_j, a_j) pi_j`` (its 6 x 10 body regressor,
in the link frame), carried to the joints below it with the motion transforms' transposes,
``Y[i, j] = S_i^T X_{i+1}^T ... X_j^T A_j`` for ``j >= i``; friction columns are ``qdd_i``,
``qd_i`` and ``sign(qd_i)``.

Base parameters (:func:`base_parameters`): the dynamics depend on fewer combinations of the
standard parameters.  They are found numerically as SymPyBotics and Gautier do: the regressor
is evaluated at random states and stacked, a QR decomposition of the stack (columns in the
standard order) marks a column dependent where its ``|R_kk|`` is below a tolerance, and each
dependent column is written as a combination of the independent ones before it
(``Y_D = Y_B K``); the base parameters are then ``beta = pi_B + K pi_D`` and ``tau = Y_B beta``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from .articulated_body import joint_frames
from .spatial import cross_force, cross_motion, motion_transform
from .chain import Chain

from ..model.errors import SymdynError

from ..model.outputs import LINK_PARAMETERS  # the 13 standard parameters of a link, in order
from ..model.outputs import PARAMETERS_PER_LINK as PER_LINK

#: what each standard parameter is, with its unit (revolute joint; prismatic in parentheses)
PARAMETER_DOCS = {
    "m": "mass, kg", "mx": "first moment m c_x, kg m", "my": "first moment m c_y, kg m",
    "mz": "first moment m c_z, kg m", "Ixx": "inertia about the link origin, kg m^2",
    "Ixy": "inertia about the link origin, kg m^2", "Iyy": "inertia about the link origin, kg m^2",
    "Ixz": "inertia about the link origin, kg m^2", "Iyz": "inertia about the link origin, kg m^2",
    "Izz": "inertia about the link origin, kg m^2", "Ia": "armature, kg m^2 (kg)",
    "fv": "viscous friction, N m s/rad (N s/m)", "fc": "Coulomb friction, N m (N)",
}


def parameter_names(robot) -> tuple[str, ...]:
    """``m1, mx1, ..., fc1, m2, ...``: the standard parameters' names, in order."""
    return tuple(f"{p}{k + 1}" for k in range(robot.dof) for p in LINK_PARAMETERS)


def standard_parameters(robot) -> tuple[sp.Expr, ...]:
    """The robot's standard parameters (13 per link, :data:`LINK_PARAMETERS`) from its file's
    mass, centre of mass and inertia about the centre of mass."""
    values = []
    for link in robot.links:
        m = link.mass
        c = sp.Matrix(link.com)
        inertia = sp.Matrix(link.inertia_matrix) + m * ((c.T * c)[0] * sp.eye(3) - c * c.T)
        values += [m, m * c[0], m * c[1], m * c[2], inertia[0, 0], inertia[0, 1], inertia[1, 1],
                   inertia[0, 2], inertia[1, 2], inertia[2, 2], link.armature, link.damping, link.coulomb]
    return tuple(sp.expand(v) for v in values)


def _body_regressor():
    """``(symbols, A)``: the 6 x 10 matrix with ``I(pi) a + v x* I(pi) v = A pi`` for the
    spatial inertia ``I(pi)`` about a frame's origin, as expressions in placeholder symbols
    for v (6) and a (6)."""
    v = sp.Matrix(sp.symbols("v0:6", real=True))
    a = sp.Matrix(sp.symbols("a0:6", real=True))
    pi = sp.symbols("p0:10", real=True)
    m, hx, hy, hz, ixx, ixy, iyy, ixz, iyz, izz = pi
    h = sp.Matrix([[0, -hz, hy], [hz, 0, -hx], [-hy, hx, 0]])
    spatial = sp.zeros(6, 6)
    spatial[:3, :3] = sp.Matrix([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    spatial[:3, 3:] = h
    spatial[3:, :3] = -h
    spatial[3:, 3:] = m * sp.eye(3)
    force = (spatial * a + cross_force(v, spatial * v)).applyfunc(sp.expand)
    A = sp.Matrix(6, 10, lambda r, k: force[r].coeff(pi[k]))
    return v, a, A


def regressor(chain: Chain) -> sp.Matrix:
    """``Y`` (n x 13 n) with ``tau = Y pi`` (inverse dynamics with armature and friction), every
    entry named in the chain's program."""
    b = chain.builder
    robot = chain.robot
    n = chain.n
    qd, qdd = chain.qd, chain.qdd
    axis = [2 if link.is_revolute else 5 for link in robot.links]
    v_sym, a_sym, body = _body_regressor()

    def vec(hint, v):
        return sp.Matrix(b.vector(hint, [sp.expand(e) for e in v]))

    X, G = [], []
    accel = sp.Matrix([0, 0, 0, *[-g for g in chain.gravity]])
    for j, Xj, velocity, S_qd, post in joint_frames(chain):
        k = j + 1
        X.append(Xj)
        S_qdd = sp.zeros(6, 1)
        S_qdd[axis[j]] = qdd[j]
        accel = vec(f"sa{k}", Xj * accel + S_qdd + cross_motion(velocity, S_qd))
        # the body regressor in the link frame L (pose ``post`` in the joint frame J), carried to J
        Xp = motion_transform(post)
        v_link = vec(f"rv{k}", Xp * velocity)
        a_link = vec(f"ra{k}", Xp * accel)
        subs = dict(zip(v_sym, v_link)) | dict(zip(a_sym, a_link))
        A = body.xreplace(subs).applyfunc(sp.expand)
        A = sp.Matrix(6, 10, lambda r, c: b.define(f"rA{k}_{r}{c}", A[r, c]))
        G.append(Xp.T * A)

    Y = sp.zeros(n, PER_LINK * n)
    for j in range(n):
        Gj = sp.Matrix(6, 10, lambda r, c: b.define(f"rG{j + 1}_{j + 1}_{r}{c}", sp.expand(G[j][r, c])))
        for i in reversed(range(j + 1)):
            if i < j:
                Gj = (X[i + 1].T * Gj).applyfunc(sp.expand)
                Gj = sp.Matrix(6, 10, lambda r, c: b.define(f"rG{j + 1}_{i + 1}_{r}{c}", Gj[r, c]))
            for c in range(10):
                Y[i, PER_LINK * j + c] = Gj[axis[i], c]
        Y[j, PER_LINK * j + 10] = qdd[j]
        Y[j, PER_LINK * j + 11] = qd[j]
        Y[j, PER_LINK * j + 12] = sp.sign(qd[j])
    return Y


@dataclass(frozen=True)
class BaseParameters:
    """The base parameters of a robot.

    ``independent``: indices (into the standard parameters) of the regressor columns kept, in
    the order the QR considered them (per link: inertia, first moment, mass, armature, friction); ``combination``: the numeric matrix K (len(independent) x P) with ``beta = K_full pi``
    where K_full has 1 at each kept column and the regrouping coefficients at dependent ones;
    ``names``/``expressions``: each base parameter's name (that of its kept standard parameter,
    with an ``R`` suffix where others are regrouped into it) and its expression in the
    standard parameters' symbols."""

    independent: tuple[int, ...]
    combination: tuple[tuple[float, ...], ...]
    names: tuple[str, ...]
    expressions: tuple[sp.Expr, ...]

    def values(self, standard) -> np.ndarray:
        """``beta`` for numeric standard parameters ``standard`` (length P)."""
        return np.asarray(self.combination, dtype=float) @ np.asarray(standard, dtype=float)


#: the order in which the QR considers a link's columns (indices into LINK_PARAMETERS)
QR_ORDER = (4, 5, 7, 6, 8, 9, 1, 2, 3, 0, 10, 11, 12)

#: relative tolerance on |R_kk| (against the largest) below which a column is dependent
RANK_TOLERANCE = 1e-9


def _coefficient(x: float) -> sp.Expr:
    """A regrouping coefficient: an integer where it is one (to 1e-12), else a 12-digit Float."""
    return sp.Integer(int(round(x))) if abs(x - round(x)) < 1e-12 else sp.Float(x, 15)


#: the power of length in each standard parameter's regressor column, in a revolute joint's row
#: (torque per parameter: m -> m^2/s^2, m c -> m/s^2, inertia, armature and friction -> 1/s^2 ...)
_COLUMN_LENGTH_POWER = (2, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0)
#: a prismatic joint's own armature (kg), viscous (N s/m) and Coulomb (N) columns, in its row
#: counted as a torque (the row times a length): see :func:`_unit_scales`
_PRISMATIC_OWN_POWER = {10: 2, 11: 2, 12: 1}


def characteristic_length(robot) -> float:
    """The largest constant length of the robot's joint placements (DH a and d, origins' xyz,
    fixed transforms' translations), 1 where it has none: its unit of length for the rank
    decisions of :func:`base_parameters`."""
    lengths = []
    for link in robot.links:
        lengths += [link.a, link.d]
        if link.origin is not None:
            lengths += list(link.origin.xyz)
        if link.fixed:
            lengths += [link.fixed[3], link.fixed[7], link.fixed[11]]
    values = [abs(float(v)) for v in lengths if sp.sympify(v).is_number]
    largest = max(values, default=0.0)
    return largest if largest > 0 and math.isfinite(largest) else 1.0


def _unit_scales(robot, rows: int):
    """``(row_scale, column_scale)`` that turn the stacked regressor (``rows`` rows, joint ``k % n``
    for row k) into the regressor of the same robot with its lengths divided by
    :func:`characteristic_length`: a prismatic joint's rows (forces) times that length, each
    column divided by the length to the power of its parameter's unit.  The rank decisions and
    the regrouping coefficients are computed there, so that they do not depend on the units the
    file is written in (a Puma 560 in mm and g decides as in m and kg)."""
    n, length = robot.dof, characteristic_length(robot)
    prismatic = np.array([not link.is_revolute for link in robot.links])
    row_scale = np.where(np.tile(prismatic, rows // n), length, 1.0)
    power = np.array([[_PRISMATIC_OWN_POWER.get(c, p) if prismatic[j] else p
                       for c, p in enumerate(_COLUMN_LENGTH_POWER)] for j in range(n)], dtype=float).ravel()
    return row_scale, length ** -power


def base_parameters(robot, evaluate, states: int | None = None, seed: int = 0, standard=None) -> BaseParameters:
    """Find the base parameters numerically (see the module's documentation).

    ``evaluate(q, qd, qdd) -> Y`` (n x P) evaluates the regressor; it is called at ``states``
    random states (default: enough for three times as many rows as columns), q uniform in
    [-pi, pi], qd and qdd in [-3, 3] (nonzero friction signs).  The decisions are taken on the
    regressor of the robot in its own unit of length (:func:`_unit_scales`), each column scaled
    to unit norm.  ``standard`` (optional, P numbers): the robot's standard parameters, to check
    that the base parameters give its torques at the states to 1e-9 (else a
    :class:`~symdyn.model.errors.SymdynError` says the regrouping is inaccurate)."""
    n = robot.dof
    P = PER_LINK * n
    count = states or max(10, -(-3 * P // n))
    rng = np.random.default_rng(seed)
    rows = []
    for _ in range(count):
        q = rng.uniform(-np.pi, np.pi, n)
        qd = rng.uniform(0.2, 3, n) * rng.choice([-1, 1], n)
        qdd = rng.uniform(-3, 3, n)
        rows.append(np.asarray(evaluate(q, qd, qdd), dtype=float))
    raw = np.vstack(rows)
    if not np.all(np.isfinite(raw)):
        raise SymdynError(f"{robot.source or robot.name}: base parameters: the regressor is not finite at random "
                          "states (lengths beyond double precision's range?)")
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):  # judged on the results, said in one line
        return _base_parameters_of(robot, raw, standard)


def _column_norms(W: np.ndarray) -> np.ndarray:
    """The 2-norm of each column, without overflow or underflow in the squares."""
    largest = np.max(np.abs(W), axis=0)
    safe = np.where(largest > 0, largest, 1.0)
    return np.linalg.norm(W / safe, axis=0) * largest


def _base_parameters_of(robot, raw: np.ndarray, standard) -> BaseParameters:
    """:func:`base_parameters` from the stacked regressor ``raw`` (finite)."""
    n = robot.dof
    P = PER_LINK * n
    row_scale, column_scale = _unit_scales(robot, raw.shape[0])
    W = raw * row_scale[:, None] * column_scale[None, :]
    scale = _column_norms(W)
    # a column that is zero up to rounding (a parameter with no effect, whose terms cancel in
    # floating point) must not be scaled up to look like an independent one
    null = scale <= 1e-10 * max(scale.max(), 1e-300)
    W = np.where(null, 0.0, W)
    scale[null] = 1.0
    W = W / scale
    # the QR sees each link's columns as SymPyBotics and Khalil order them: inertia, first
    # moment, mass, then armature and friction; a column is kept where it adds to the span of
    # those before it, so a tip link's mass is regrouped into the links before it (M_{j-1} +
    # M_j, ...) with geometric coefficients (lengths, squared lengths)
    order = [PER_LINK * j + c for j in range(n) for c in QR_ORDER]
    _, R = np.linalg.qr(W[:, order])
    diag = np.abs(np.diag(R))
    kept = {order[k] for k in range(P) if diag[k] > RANK_TOLERANCE * max(diag.max(), 1e-300)}
    independent = [k for k in order if k in kept]
    dependent = [k for k in range(P) if k not in kept]
    K = np.zeros((len(independent), P))
    for row, k in enumerate(independent):
        K[row, k] = 1.0
    if dependent:
        # W's columns are Y's times s = column_scale / scale: Y_D = Y_B (s_B X / s_D)
        unit, *_ = np.linalg.lstsq(W[:, independent], W[:, dependent], rcond=None)
        unit[np.abs(unit) < 1e-12] = 0.0
        s = column_scale / scale
        coefficients = unit * s[independent][:, None] / s[dependent][None, :]
        # 12 significant digits: the least-squares noise (~1e-15) removed, so that the same robot
        # gives the same coefficients whatever else is derived with it; geometric coefficients
        # (products of a few lengths, 0.4318^2 = 0.18645124) come out exact
        K[:, dependent] = [[float(f"{x:.12g}") for x in row] for row in coefficients]
    if standard is not None:
        _check_regrouping(robot, raw, independent, K, np.asarray(standard, dtype=float))
    names = parameter_names(robot)
    symbols = [sp.Symbol(name, real=True) for name in names]
    base_names, expressions = [], []
    for row, k in enumerate(independent):
        expr = sp.Add(*[_coefficient(K[row, c]) * symbols[c] for c in range(P) if K[row, c] != 0.0])
        regrouped = any(K[row, c] != 0.0 for c in dependent)
        base_names.append(names[k] + ("R" if regrouped else ""))
        expressions.append(expr)
    return BaseParameters(tuple(independent), tuple(tuple(float(x) for x in r) for r in K),
                          tuple(base_names), tuple(expressions))


def _check_regrouping(robot, Y, independent, K, standard) -> None:
    """Refuse, in one line, base parameters whose torques ``Y_B (K pi)`` differ from the
    standard ones ``Y pi`` by more than 1e-9 of their size at the sampled states."""
    full, base = Y @ standard, Y[:, independent] @ (K @ standard)
    if not (np.all(np.isfinite(full)) and np.all(np.isfinite(base))):
        raise SymdynError(f"{robot.source or robot.name}: base parameters: the robot's torques are not finite in "
                          "double precision at random states (its masses, lengths and inertias multiply beyond "
                          "1e308): use --parameters standard (or the full regressor)")
    largest = float(np.max(np.abs(full)))
    size = float(np.linalg.norm(full / largest)) * largest if largest > 0 else 0.0
    error = float(np.linalg.norm((full - base) / largest)) * largest / size if size > 0 else 0.0
    if not error <= 1e-9:
        raise SymdynError(f"{robot.source or robot.name}: base parameters: regrouped, the robot's own parameters give "
                          f"torques {error:.1g} (relative) from the standard ones at random states; the regrouping is "
                          "not accurate for this robot's magnitudes: use --parameters standard (or the full regressor)")


def base_equivalent(robot, base: BaseParameters) -> tuple[sp.Expr, ...]:
    """Standard parameters (13 n) with the same dynamics as the robot's: each base parameter's
    value at its kept column (``beta = pi_B + K pi_D`` in the robot's own parameters, numbers or
    runtime symbols), zero at every regrouped one."""
    names = parameter_names(robot)
    symbols = {sp.Symbol(name, real=True): value for name, value in zip(names, standard_parameters(robot))}
    values = [sp.S.Zero] * len(names)
    for k, expr in zip(base.independent, base.expressions):
        values[k] = sp.expand(expr.xreplace(symbols))
    return tuple(values)
