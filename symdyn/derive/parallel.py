"""Platform robots: the dynamics of the natural orthogonal complement (parallel-manipulator notes) as programs of
straight-line statements and 6x6 linear solves.

The platform's closed loops make some quantities the solutions of linear systems whose
symbolic inverse would be enormous (each leg's Jacobian J_J, the map K from the platform's
twist to the actuated joint rates, the platform's generalized inertia).  So a function here is
a sequence of steps (:data:`Step`): blocks of assignments to intermediate symbols (built as the
serial derivations build theirs, :mod:`symdyn.derive.program`), LU factorizations of 6x6
matrices, solves with them, and run-time requirements (a radicand not negative, a denominator
positive).  Emitters print the blocks and call a numeric LU for the rest; each factorization
and requirement has the status code a function returns when it fails (:data:`STATUS`).

State (every function): the platform pose ``pose`` = ``[p; quat]`` (7): the position ``p`` of
the platform frame P's origin (m, world frame W) and P's orientation as a quaternion
``(x, y, z, w)`` (Pinocchio's free-flyer order; any nonzero quaternion, it is normalized);
the twist ``t = [omega; c_dot]`` (6: rad/s and m/s, W axes): the platform's angular velocity and
the velocity of its mass centre C_M, as in the notes; ``t_dot = [omega_dot; c_ddot]`` its
(classical) time derivative.  ``q`` are the six actuated joint variables, leg by leg.

Per leg J (actuated joint k, frame 6 fixed to the platform at U_J, r_J = U_J - C_M):

- ``theta_J``: closed-form inverse kinematics (:mod:`symdyn.derive.parallel_ik`), branch of the
  file's home configuration;
- ``J_J theta_dot_J = S_J t`` with ``S_J = [[-[r_J]x, 1], [1, 0]]`` (the twist of U_J, linear
  part first, as the serial Jacobian);
- ``J_J theta_ddot_J = S_J t_dot + [omega x (omega x r_J); 0] - J_J-dot theta_dot_J``;
- the rows ``e_k^T J_J^-1 S_J`` make ``K`` (``q_dot = K t``); the notes' ``T = K^-1`` and
  ``L_J = J_J^-1 S_J T``;
- inverse dynamics by power balance: ``K^T phi = w_M + sum_J S_J^T J_J^-T tau_J`` (tau_J the
  leg's own inverse dynamics, gravity, armature and friction included; w_M the wrench the
  platform's motion needs, at C_M);
- forward dynamics: the same relation is ``A t_dot + b = K^T phi`` with
  ``A = M_M + sum_J R_J^T (D_J + armature_J) R_J`` (R_J = J_J^-1 S_J) and ``b`` its value at
  t_dot = 0;
- the mass matrix in actuated coordinates ``M = T^T A T`` (= the notes'
  ``T^T M_M T + sum L_J^T I_J L_J``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Union

import numpy as np
import sympy as sp

from ..model.errors import SymdynError
from ..model.parallel import ParallelRobot
from ..model.outputs import PLATFORM_SPECS, platform_outputs
from ..model.tolerances import PIVOT_RTOL_SYMBOL
from .parallel_ik import LegIK, LegStructureError, leg_error
from .program import ProgramBuilder
from .spatial import cross, skew

#: status codes of the generated functions (0: success)
STATUS = {"unreachable": 1, "leg_singular": 2, "singular": 3, "not_finite": 4}
STATUS_DOC = {
    "unreachable": "the pose is out of a leg's reach (its closed-form inverse kinematics has no real "
                   "solution), or the quaternion is zero",
    "leg_singular": "a leg is at a serial singularity at the pose (its Jacobian J_J is singular, or an angle "
                    "of its inverse kinematics is not defined)",
    "singular": "the platform is at a parallel singularity: K (q_dot = K t, the inverse of the twist map T) "
                "is singular",
    "not_finite": "a result is not finite (NaN, or beyond the range of the scalar type: a twist or force "
                  "so large that the dynamics overflow)",
}
#: forward dynamics' SINGULAR: it solves with the generalized inertia, not with K
FORWARD_SINGULAR_DOC = ("the platform's generalized inertia A (twist coordinates) is singular; forward dynamics is "
                        "defined at a parallel singularity and returns 0 there")

#: the generated functions, read from their specs (symdyn.model.outputs.PLATFORM_SPECS): name ->
#: (inputs, outputs (name, rows, cols), summary)
FUNCTIONS = {spec.name: (spec.inputs, platform_outputs(spec.name), spec.summary) for spec in PLATFORM_SPECS}
INPUT_SIZES = {"pose": 7, "twist": 6, "twist_rate": 6, "phi": 6}
#: the relative tolerance of the singularity checks, a symbol: emitters give its value for the
#: precision (the C functions' ``NAME_PIVOT_RTOL``; :mod:`symdyn.model.tolerances`)
PIVOT_RTOL = PIVOT_RTOL_SYMBOL


@dataclass(frozen=True)
class Block:
    """Assignments ``(symbol, expression)`` in evaluation order."""
    assignments: tuple


@dataclass(frozen=True)
class Factor:
    """LU factorization of the 6x6 ``matrix`` (entries: expressions of earlier symbols), named
    ``name``; a (numerically) singular matrix makes the function return ``status``."""
    name: str
    matrix: sp.ImmutableMatrix
    status: str


@dataclass(frozen=True)
class Solve:
    """``result = A^-1 rhs`` (``A^-T rhs`` when ``transpose``) with the factorization
    ``factor``; ``rhs`` 6 x m expressions, ``result`` 6 x m new symbols."""
    factor: str
    transpose: bool
    rhs: sp.ImmutableMatrix
    result: sp.ImmutableMatrix


@dataclass(frozen=True)
class Require:
    """``value > 0`` (``strict``) or ``value >= 0`` at run time, else return ``status``."""
    value: sp.Expr
    strict: bool
    status: str


Step = Union[Block, Factor, Solve, Require]


@dataclass(frozen=True)
class ParallelFunction:
    """One generated function: its inputs (name, symbols), steps and outputs (name, matrix)."""
    name: str
    summary: str
    inputs: tuple
    steps: tuple
    outputs: tuple

    @property
    def statuses(self) -> tuple[str, ...]:
        """The status codes this function can return (names of :data:`STATUS`), in order."""
        found = {s.status for s in self.steps if isinstance(s, (Factor, Require))} | {"not_finite"}
        return tuple(k for k in STATUS if k in found)


@dataclass(frozen=True)
class ParallelEquations:
    """The derived dynamics of a :class:`ParallelRobot` (immutable): every step of every
    function (:attr:`steps`) and each function's outputs; :meth:`function` keeps what one needs."""
    robot: ParallelRobot
    inputs: tuple  # (name, tuple of symbols) for pose, twist, twist_rate, phi
    steps: tuple
    outputs: tuple  # (function name, ((output name, matrix), ...))
    branches: tuple  # per leg: the closed form's branches (joint 4, universal, spherical)
    seconds: float = 0.0
    #: the platform's pose at the file's home configuration: position (m) and quaternion (x, y, z, w)
    home_pose: tuple = ()

    @property
    def function_names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.outputs)

    def function(self, name: str) -> ParallelFunction:
        """The steps function ``name`` needs, in order (everything else removed)."""
        if name not in FUNCTIONS:
            raise KeyError(f"unknown function {name!r}; known: {', '.join(FUNCTIONS)}")
        inputs, _, summary = FUNCTIONS[name]
        outputs = dict(self.outputs)[name]
        return ParallelFunction(name, summary, tuple((k, dict(self.inputs)[k]) for k in inputs),
                                _needed_steps(self.steps, [e for _, m in outputs for e in m]), outputs)


def _needed_steps(steps, results) -> tuple:
    """Dead-code elimination over a step list: the assignments, solves and factorizations the
    results depend on; then the requirements on what is kept."""
    needed: set = set().union(*(sp.sympify(e).free_symbols for e in results))
    kept: list = []
    factors_used: set = set()
    for step in reversed(steps):
        if isinstance(step, Block):
            block = []
            for sym, rhs in reversed(step.assignments):
                if sym in needed:
                    block.append((sym, rhs))
                    needed |= rhs.free_symbols
            if block:
                kept.append(Block(tuple(reversed(block))))
        elif isinstance(step, Solve):
            if needed & set(step.result):
                kept.append(step)
                factors_used.add(step.factor)
                needed |= set().union(*(e.free_symbols for e in step.rhs))
        elif isinstance(step, Factor):
            if step.name in factors_used:
                kept.append(step)
                needed |= set().union(*(e.free_symbols for e in step.matrix))
        else:
            kept.append(step)
    kept.reverse()
    defined = set().union(*(set(s for s, _ in b.assignments) for b in kept if isinstance(b, Block)))
    out = []
    for step in kept:
        if isinstance(step, Require):
            if not step.value.free_symbols - {PIVOT_RTOL} <= defined | needed:
                continue
        out.append(step)
    # merge consecutive blocks (a removed step between them)
    merged: list = []
    for step in out:
        if isinstance(step, Block) and merged and isinstance(merged[-1], Block):
            merged[-1] = Block(merged[-1].assignments + step.assignments)
        else:
            merged.append(step)
    return tuple(merged)


class _Steps:
    """Collects steps; assignments go to one :class:`ProgramBuilder` (hash-consed), cut into
    blocks wherever another step comes between."""

    def __init__(self):
        self.b = ProgramBuilder("_")
        self.steps: list = []
        self._mark = 0

    def define(self, hint, expr):
        return self.b.define(hint, expr)

    def vector(self, hint, exprs):
        return sp.Matrix([self.define(f"{hint}{k}", e) for k, e in enumerate(exprs)])

    def _flush(self):
        assigns = self.b.build().assignments
        if len(assigns) > self._mark:
            self.steps.append(Block(tuple(assigns[self._mark:])))
            self._mark = len(assigns)

    def require(self, value, strict: bool, status: str, what: str):
        value = sp.sympify(value)
        if not (value.free_symbols - {PIVOT_RTOL}):
            value = value.subs(PIVOT_RTOL, 0)
            ok = (value > 0) if strict else (value >= 0)
            if not bool(ok):
                raise SymdynError(f"{what}: the closed-form inverse kinematics is never defined for this leg")
            return
        self._flush()
        self.steps.append(Require(value, strict, status))

    def factor(self, name, matrix, status):
        self._flush()
        self.steps.append(Factor(name, sp.ImmutableMatrix(matrix), status))

    def solve(self, factor, rhs, hint, transpose=False) -> sp.Matrix:
        self._flush()
        rhs = sp.Matrix(rhs)
        result = sp.Matrix(rhs.rows, rhs.cols, lambda i, j: sp.Symbol(f"{hint}_{i}{j}" if rhs.cols > 1
                                                                       else f"{hint}_{i}", real=True))
        self.steps.append(Solve(factor, transpose, sp.ImmutableMatrix(rhs), sp.ImmutableMatrix(result)))
        return result

    def build(self) -> tuple:
        self._flush()
        return tuple(self.steps)


class _LegImport:
    """Brings a leg's serial equations into the platform's steps, with its joint functions
    replaced: the sin/cos symbols and prismatic variables by the inverse kinematics, qd and qdd
    by given expressions.  ``mapping`` (old symbol -> new expression) is shared by the imports
    that see the same joint values."""

    def __init__(self, steps: _Steps, eqs, tag: str, mapping: dict):
        self.steps, self.eqs, self.tag, self.mapping = steps, eqs, tag, mapping

    def get(self, output: str, extra: dict | None = None, suffix: str = "") -> sp.Matrix:
        mapping = self.mapping if extra is None else {**self.mapping, **extra}
        matrix = self.eqs.output(output)
        for sym, rhs in self.eqs.program.needed_for(list(matrix)):
            if sym in mapping:
                continue
            mapping[sym] = self.steps.define(f"{self.tag}{sym.name.lstrip('_')}{suffix}", rhs.xreplace(mapping))
        out = sp.Matrix(matrix).applyfunc(lambda e: e.xreplace(mapping))
        leftover = set().union(*(e.free_symbols for e in out)) & set(self.eqs.q + self.eqs.qd + self.eqs.qdd)
        if leftover:  # a joint variable outside sin/cos: not expected of a serial derivation
            raise SymdynError(f"{self.eqs.robot.name}: {output} uses {sorted(map(str, leftover))} directly")
        return out


def _det3(m: sp.Matrix):
    return (m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1]) - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
            + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]))


def _inverse3(st: _Steps, hint: str, m: sp.Matrix, scale, what: str) -> sp.Matrix:
    """The inverse of the 3x3 ``m`` (adjugate over determinant), named; requires
    ``det^2 > PIVOT_RTOL^2 * scale`` (``scale``: the square of the product of the columns'
    lengths) at run time, else LEG_SINGULAR."""
    det = st.define(f"{hint}det", _det3(m))
    st.require(det * det - PIVOT_RTOL ** 2 * scale, True, "leg_singular", what)
    inv = st.define(f"{hint}inv", 1 / det)
    adj = m.adjugate()
    return sp.Matrix(3, 3, lambda i, j: st.define(f"{hint}{i}{j}", adj[i, j] * inv))


def leg_inverse(st: _Steps, tag: str, d: sp.Matrix, fourth: sp.Matrix, axes, revolute: bool, what: str) -> sp.Matrix:
    """The inverse of an S-X-U leg's Jacobian at the universal joint's centre U (6x6: joint
    rates from the twist [v_U; omega] of the leg's last link), in closed form.

    ``d`` = U - S (S the spherical pair's centre), ``axes`` the six joints' unit axes (world),
    ``fourth`` the linear column of joint 4 at U (prismatic: its axis; revolute: axis x (U -
    a point of the axis)).  The universal joint's axes pass through U and the spherical pair's
    through S, so with omega_S = a1 qd1 + a2 qd2 + a3 qd3:

        v_U = omega_S x d + l4 qd4        omega = omega_S + a4 qd4 + a5 qd5 + a6 qd6

    d . v_U gives qd4 = g . v_U (g = d / (d . l4)); the part of omega_S normal to d is
    P v_U (P = [d]x (1 - l4 g^T) / (d . d)); its part s d along d and qd5, qd6 solve
    [d a5 a6] [s; qd5; qd6] = omega - (P + a4 g^T) v_U; then [a1 a2 a3] qd1..3 = omega_S.
    Singular (LEG_SINGULAR at run time, relative to PIVOT_RTOL) where d . l4 = 0 (joint 4 cannot
    change the length of the leg), or either 3x3 matrix is singular (the universal joint's
    axes coplanar with the leg, the spherical pair in gimbal lock)."""
    a4 = axes[3] if revolute else sp.zeros(3, 1)
    dd = st.define(f"{tag}dd", (d.T * d)[0])
    dl = st.define(f"{tag}dl", (d.T * fourth)[0])
    st.require(dl * dl - PIVOT_RTOL ** 2 * dd * (fourth.T * fourth)[0], True, "leg_singular", what)
    inv_dl = st.define(f"{tag}dlinv", 1 / dl)
    g = st.vector(f"{tag}g", d * inv_dl)
    inv_dd = st.define(f"{tag}ddinv", 1 / dd)
    P = skew(d) * (sp.eye(3) - fourth * g.T) * inv_dd
    P = sp.Matrix(3, 3, lambda i, j: st.define(f"{tag}P{i}{j}", sp.expand(P[i, j])))
    Q = sp.Matrix(3, 3, lambda i, j: st.define(f"{tag}Q{i}{j}", P[i, j] + a4[i] * g[j]))
    N = _inverse3(st, f"{tag}N", sp.Matrix.hstack(d, axes[4], axes[5]), dd, what)
    S = _inverse3(st, f"{tag}S", sp.Matrix.hstack(axes[0], axes[1], axes[2]), 1, what)
    # rows of [s; qd5; qd6] = N^-1 [-Q, 1]
    rest = sp.Matrix(3, 6, lambda i, j: st.define(
        f"{tag}W{i}{j}", -(N[i, :] * Q[:, j])[0] if j < 3 else N[i, j - 3]))
    # omega_S = [P, 0] + d (row s); qd1..3 = S^-1 omega_S
    omega_s = sp.Matrix(3, 6, lambda i, j: st.define(
        f"{tag}O{i}{j}", (P[i, j] if j < 3 else 0) + d[i] * rest[0, j]))
    first = sp.Matrix(3, 6, lambda i, j: st.define(f"{tag}Ji{i}{j}", (S[i, :] * omega_s[:, j])[0]))
    row4 = sp.Matrix([[*g, 0, 0, 0]])
    return sp.Matrix.vstack(first, row4, rest[1:, :])


def check_derivable(robot: ParallelRobot) -> None:
    """Refuse (SymdynError naming the file) a platform robot :func:`derive_parallel` cannot
    derive: one with runtime parameters or without a home configuration."""
    where = robot.source or robot.name
    if robot.parameters:
        raise SymdynError(f"{where}: runtime parameters ({', '.join(s.name for s in robot.parameters)}) are not "
                          "supported for platform robots yet: give numbers")
    if any(leg.home is None for leg in robot.legs):
        raise SymdynError(f"{where}: platform robots need 'home' (it picks the branch of each leg's inverse "
                          "kinematics)")


def _platform_rotation(st: "_Steps", quaternion, where: str) -> sp.Matrix:
    """R (3 x 3, defined steps) from the pose's quaternion (x, y, z, w), normalized: divided by
    the sum of its components' magnitudes first (a division each: the reciprocal of a subnormal
    sum would overflow), so that subnormal, 1e-300 or 1e300 components neither underflow nor
    overflow in the squares; only the zero quaternion is refused."""
    scale = st.define("quat_m", sum(sp.Abs(c) for c in quaternion))
    st.require(scale, True, "unreachable", where)
    x, y, z, w = (st.define(f"quat_{c}", value / scale) for c, value in zip("xyzw", quaternion))
    norm2 = st.define("quat_n2", x * x + y * y + z * z + w * w)
    s = st.define("quat_s", 2 / norm2)
    R = sp.Matrix([[1 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w)],
                   [s * (x * y + z * w), 1 - s * (x * x + z * z), s * (y * z - x * w)],
                   [s * (x * z - y * w), s * (y * z + x * w), 1 - s * (x * x + y * y)]])
    return sp.Matrix(3, 3, lambda i, j: st.define(f"R{i}{j}", R[i, j]))


def _leg_terms(st: "_Steps", leg, k: int, frame: dict, where: str, report) -> tuple[dict, tuple]:
    """Leg ``k``'s steps (its inverse kinematics, Jacobian inverse, joint rates and accelerations,
    torques, rate map and mass matrix) on the platform's motion ``frame`` (R, p, omega, c_dot,
    omega_dot, c_ddot, com): the leg's terms for :func:`_platform_outputs` and its branch."""
    from .equations import derive
    R, p, com = frame["R"], frame["p"], frame["com"]
    omega, c_dot, omega_dot, c_ddot = frame["omega"], frame["c_dot"], frame["omega_dot"], frame["c_ddot"]
    tag = f"leg{k + 1}_"
    report(f"leg {k + 1}: serial equations")
    eqs = derive(leg.chain, outputs=["jacobian", "jacobian_dot_qd", "inverse_dynamics", "mass_matrix"])
    try:
        ik = LegIK.of(leg.chain)
        branch = ik.branches_of(leg.home)
    except LegStructureError as err:
        raise SymdynError(f"{where}: leg {leg.name}: {leg_error(err, leg)}") from None
    home_jacobian = np.asarray(eqs.numeric.jacobian(np.array([float(v) for v in leg.home]), []), dtype=float)
    if not np.linalg.cond(home_jacobian.reshape(6, 6)) < 1e12:
        raise SymdynError(f"{where}: leg {leg.name}: the leg is at a singular configuration at its home pose "
                          "(its Jacobian is singular): the generated functions would return a status there; "
                          "check the leg's table and 'home'")
    base = sp.Matrix(leg.chain.base_matrix())
    attach = sp.Matrix(leg.attachment.matrix())
    rot6 = R * attach[:3, :3]
    pos6 = p + R * attach[:3, 3]
    rot06 = base[:3, :3].T * rot6
    pos06 = base[:3, :3].T * (pos6 - base[:3, 3])
    rot06 = [[st.define(f"{tag}R06_{i}{j}", sp.expand(rot06[i, j])) for j in range(3)] for i in range(3)]
    pos06 = [st.define(f"{tag}p06_{i}", sp.expand(pos06[i])) for i in range(3)]

    def name(hint, value, tag=tag):
        return st.define(f"{tag}{hint}", value)

    def check(kind, value, scale=None, leg=leg):
        if kind == "rad":  # a negative radicand: no real solution
            st.require(value, False, "unreachable", f"{where}: leg {leg.name}")
        else:  # a denominator (a sum of squares) not above PIVOT_RTOL^2 of its scale: singular
            st.require(value - PIVOT_RTOL ** 2 * scale, True, "leg_singular", f"{where}: leg {leg.name}")
    joints = ik.solve(rot06, pos06, branch, sp.sqrt, name, check)
    mapping: dict = {}
    for i, (link, value) in enumerate(zip(leg.chain.links, joints)):
        if link.is_revolute:
            cos_symbol, sin_symbol = eqs.joint_trig[i]
            mapping[cos_symbol], mapping[sin_symbol] = value
        else:
            mapping[eqs.q[i]] = value
    imp = _LegImport(st, eqs, tag, mapping)
    report(f"leg {k + 1}: Jacobian and rates")
    # the leg's Jacobian at the universal joint's centre U (world axes) and its inverse in
    # closed form (leg_inverse): J_U^-1 replaces a 6x6 factorization
    jac6 = imp.get("jacobian")  # at frame 6's origin
    u_in_platform = sp.Matrix(attach[:3, :3]) * sp.Matrix(ik.u_in_6) + attach[:3, 3]
    u_offset = st.vector(f"{tag}uP", R * u_in_platform)  # U - p
    rho = st.vector(f"{tag}rho", R * sp.Matrix(attach[:3, 3]) - u_offset)  # frame 6's origin - U
    centre = base[:3, :3] * sp.Matrix(ik.centre_s) + base[:3, 3]
    leg_vector = st.vector(f"{tag}d", p + u_offset - centre)  # U - S
    axes = [sp.Matrix(jac6[3:6, i]) for i in range(6)]
    fourth = sp.Matrix(jac6[0:3, 3]) + (cross(rho, axes[3]) if leg.chain.links[3].is_revolute else sp.zeros(3, 1))
    jinv = leg_inverse(st, tag, leg_vector, st.vector(f"{tag}l4", fourth), axes,
                       leg.chain.links[3].is_revolute, f"{where}: leg {leg.name}")
    r = st.vector(f"{tag}r", R * (u_in_platform - com))  # U - C_M
    v_u = c_dot + cross(omega, r)
    theta_dot = st.vector(f"{tag}qd", jinv * sp.Matrix.vstack(v_u, omega))
    mapping.update(dict(zip(eqs.qd, theta_dot)))
    jdqd6 = imp.get("jacobian_dot_qd")  # J-dot qd at frame 6's origin: at U, see below
    centripetal = st.vector(f"{tag}cp", cross(omega, cross(omega, r)))
    bias = sp.Matrix.vstack(
        sp.Matrix(jdqd6[0:3, 0]) - cross(sp.Matrix(jdqd6[3:6, 0]), rho) - cross(omega, cross(omega, rho)),
        sp.Matrix(jdqd6[3:6, 0]))
    bias = st.vector(f"{tag}jdqd", bias)
    # inverse dynamics: theta_ddot from t_dot, the leg's torques, S^T J^-T tau
    acc = sp.Matrix.vstack(c_ddot + cross(omega_dot, r) + centripetal, omega_dot) - bias
    theta_ddot = st.vector(f"{tag}qdd", jinv * acc)
    tau = imp.get("inverse_dynamics", dict(zip(eqs.qdd, theta_ddot)))
    y_lt = st.vector(f"{tag}y", jinv.T * tau)
    # forward dynamics: theta_ddot at t_dot = 0, R_J = J^-1 S, the leg's D
    offset = st.vector(f"{tag}qdd0", jinv * (sp.Matrix.vstack(centripetal, sp.zeros(3, 1)) - bias))
    tau0 = imp.get("inverse_dynamics", dict(zip(eqs.qdd, offset)), suffix="_0")
    shift = sp.Matrix(sp.BlockMatrix([[-skew(r), sp.eye(3)], [sp.eye(3), sp.zeros(3)]]))
    rates = sp.Matrix(6, 6, lambda i, j: st.define(f"{tag}R{i}{j}", (jinv[i, :] * shift[:, j])[0]))
    mass = imp.get("mass_matrix") + sp.diag(*[link.armature for link in leg.chain.links])
    terms = dict(tag=tag, leg=leg, r=r, y=y_lt, rates=rates, mass=mass, tau0=tau0,
                 offset=offset, theta_dot=theta_dot, joint=joints[leg.actuated], link=leg.actuated_link)
    return terms, branch


def _platform_outputs(st: "_Steps", legs: list, platform: dict, report) -> dict:
    """The outputs from the legs' terms and the platform's own (``platform``: inertia,
    bias_moment, weight, mass, omega, omega_dot, c_ddot, phi): K, inverse and forward dynamics,
    M, T, L_J and the inverse kinematics."""
    inertia, bias_moment, weight = platform["inertia"], platform["bias_moment"], platform["weight"]
    omega_dot, c_ddot, phi = platform["omega_dot"], platform["c_ddot"], platform["phi"]
    plat = platform["plat"]
    report("platform")
    outputs = {}
    # K (q_dot = K t): row J is leg J's actuated row of R_J = J_J^-1 S_J; one factorization serves
    # inverse dynamics (K^T phi = ...) and T = K^-1
    K = sp.Matrix([list(lg["rates"][lg["leg"].actuated, :]) for lg in legs])
    # inverse dynamics: K^T phi = w_M + sum S^T J^-T tau
    wrench = sp.Matrix.vstack(inertia * omega_dot + bias_moment, plat.mass * c_ddot + weight)
    for lg in legs:
        y_f, y_m = lg["y"][:3, 0], lg["y"][3:, 0]
        wrench += sp.Matrix.vstack(cross(lg["r"], y_f) + y_m, y_f)
    wrench = st.vector("wrench", wrench)
    st.factor("K", K, "singular")
    phi_out = st.solve("K", wrench, "phi", transpose=True)
    outputs["inverse_dynamics"] = (("phi", sp.ImmutableMatrix(phi_out)),)

    # forward dynamics: A t_dot = K^T phi - b
    platform_mass = sp.diag(inertia, plat.mass * sp.eye(3))
    A = sp.Matrix(platform_mass)
    b = sp.Matrix.vstack(bias_moment, weight)
    for lg in legs:
        Rj = lg["rates"]
        DR = sp.Matrix(6, 6, lambda i, j: st.define(f"{lg['tag']}DR{i}{j}", (lg["mass"][i, :] * Rj[:, j])[0]))
        A += sp.Matrix(6, 6, lambda i, j: (Rj[:, i].T * DR[:, j])[0] if i <= j else 0)
        b += Rj.T * lg["tau0"]
    A = sp.Matrix(6, 6, lambda i, j: st.define(f"A{min(i, j)}{max(i, j)}", A[min(i, j), max(i, j)]))
    rhs = st.vector("fd_rhs", K.T * phi - b)
    st.factor("A", A, "singular")
    t_dot = st.solve("A", rhs, "tdot")
    qdd = sp.Matrix([(K[k, :] * t_dot)[0] + lg["offset"][lg["leg"].actuated] for k, lg in enumerate(legs)])
    outputs["forward_dynamics"] = (("twist_rate", sp.ImmutableMatrix(t_dot)), ("qdd", sp.ImmutableMatrix(qdd)))

    # T = K^-1, M = T^T A T, L_J = R_J T
    T = st.solve("K", sp.eye(6), "T")
    AT = sp.Matrix(6, 6, lambda i, j: st.define(f"AT{i}{j}", (A[i, :] * T[:, j])[0]))
    M = sp.Matrix(6, 6, lambda i, j: (T[:, min(i, j)].T * AT[:, max(i, j)])[0])
    outputs["mass_matrix"] = (("M", sp.ImmutableMatrix(M)),)
    outputs["twist_map"] = (("T", sp.ImmutableMatrix(T)),)
    outputs["leg_rate_maps"] = (("L", sp.ImmutableMatrix(sp.Matrix.vstack(*[lg["rates"] * T for lg in legs]))),)

    # inverse kinematics
    positions = []
    for lg in legs:
        if lg["link"].is_revolute:
            c, s_ = lg["joint"]
            positions.append(sp.atan2(s_, c) - lg["link"].theta)
        else:
            positions.append(lg["joint"])
    rates_out = [lg["theta_dot"][lg["leg"].actuated] for lg in legs]
    outputs["inverse_kinematics"] = (("q", sp.ImmutableMatrix(positions)), ("qd", sp.ImmutableMatrix(rates_out)))

    return outputs


def derive_parallel(robot: ParallelRobot, functions=None, progress=None) -> ParallelEquations:
    """Derive the functions of :data:`FUNCTIONS` (default: all) for ``robot``.

    Needs numbers for every parameter (runtime parameters of platform robots are not supported)
    and a home configuration in the file (it picks each leg's inverse-kinematics branch).
    """
    start = time.perf_counter()
    wanted = tuple(FUNCTIONS) if functions is None else tuple(functions)
    for name in wanted:
        if name not in FUNCTIONS:
            raise SymdynError(f"unknown function {name!r} for a platform robot; known: {', '.join(FUNCTIONS)}")
    where = robot.source or robot.name
    check_derivable(robot)

    def report(part):
        if progress is not None:
            progress(f"{robot.name}: {part} ({time.perf_counter() - start:.1f} s)")

    inputs = {k: tuple(sp.Symbol(f"{k}[{i}]", real=True) for i in range(n)) for k, n in INPUT_SIZES.items()}
    pose, twist, rate, phi = (sp.Matrix(inputs[k]) for k in ("pose", "twist", "twist_rate", "phi"))
    st = _Steps()
    R = _platform_rotation(st, pose[3:7], where)
    p = pose[:3, 0]
    omega, c_dot = twist[:3, 0], twist[3:, 0]
    omega_dot, c_ddot = rate[:3, 0], rate[3:, 0]
    plat = robot.platform
    com = sp.Matrix(plat.com)
    gravity = sp.Matrix(robot.gravity)

    # the platform's own wrench at C_M, [moment; force]: M_M t_dot + bias
    inertia = R * sp.Matrix(plat.inertia_matrix) * R.T
    inertia = sp.Matrix(3, 3, lambda i, j: st.define(f"plat_I{min(i, j)}{max(i, j)}", sp.expand(inertia[i, j])))
    i_omega = st.vector("plat_Iw", inertia * omega)
    bias_moment = st.vector("plat_gyro", cross(omega, i_omega))
    weight = -plat.mass * gravity

    frame = dict(R=R, p=p, com=com, omega=omega, c_dot=c_dot, omega_dot=omega_dot, c_ddot=c_ddot)
    legs, branches = [], []
    for k, leg in enumerate(robot.legs):
        terms, branch = _leg_terms(st, leg, k, frame, where, report)
        legs.append(terms)
        branches.append(branch)
    outputs = _platform_outputs(st, legs, dict(inertia=inertia, bias_moment=bias_moment, weight=weight, plat=plat,
                                               omega_dot=omega_dot, c_ddot=c_ddot, phi=phi), report)
    return ParallelEquations(robot=robot, inputs=tuple((k, v) for k, v in inputs.items()), steps=st.build(),
                             outputs=tuple((name, outputs[name]) for name in wanted), branches=tuple(branches),
                             seconds=time.perf_counter() - start, home_pose=home_pose(robot))


def home_pose(robot: ParallelRobot) -> tuple:
    """The platform's pose (position, m; quaternion (x, y, z, w)) at the file's home
    configuration, from the first leg (the file's legs agree to 1e-6)."""
    from ..model.geometry import numeric_pose
    leg = robot.legs[0]
    frame6 = np.array(leg.chain.base_matrix(), dtype=float) @ numeric_pose(leg.chain, leg.home)
    pose = frame6 @ np.linalg.inv(np.array(leg.attachment.matrix(), dtype=float))
    return (*[float(x) for x in pose[:3, 3]], *quaternion(pose[:3, :3]))


def quaternion(R) -> tuple:
    """(x, y, z, w) of a 3x3 rotation matrix, w >= 0 (Shepperd's method: the largest of the four
    first)."""
    R = np.asarray(R, dtype=float)
    trace = float(np.trace(R))
    k = int(np.argmax([trace, R[0, 0], R[1, 1], R[2, 2]]))
    if k == 0:
        w = 0.5 * np.sqrt(1 + trace)
        x, y, z = (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)
    elif k == 1:
        x = 0.5 * np.sqrt(1 + 2 * R[0, 0] - trace)
        w, y, z = (R[2, 1] - R[1, 2]) / (4 * x), (R[0, 1] + R[1, 0]) / (4 * x), (R[0, 2] + R[2, 0]) / (4 * x)
    elif k == 2:
        y = 0.5 * np.sqrt(1 + 2 * R[1, 1] - trace)
        w, x, z = (R[0, 2] - R[2, 0]) / (4 * y), (R[0, 1] + R[1, 0]) / (4 * y), (R[1, 2] + R[2, 1]) / (4 * y)
    else:
        z = 0.5 * np.sqrt(1 + 2 * R[2, 2] - trace)
        w, x, y = (R[1, 0] - R[0, 1]) / (4 * z), (R[0, 2] + R[2, 0]) / (4 * z), (R[1, 2] + R[2, 1]) / (4 * z)
    q = np.array([x, y, z, w], dtype=float)
    return tuple(float(v) for v in (q if q[3] >= 0 else -q))
