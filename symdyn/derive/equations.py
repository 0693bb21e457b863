"""Equations of motion: derive them from a robot, and the immutable result.

One notation, used everywhere in symdyn (and compared with Pinocchio in the tests)::

    tau = D(q) qdd + h(q, qd) + c(q) + armature .* qdd + damping .* qd + coulomb .* sign(qd)

=================  =========================================  ==================================
symdyn             meaning                                     Pinocchio
=================  =========================================  ==================================
``mass_matrix``    D(q), n x n, symmetric positive definite    ``crba`` (with armature = 0)
``coriolis``       h(q, qd) = C(q, qd) qd, n                   ``nonLinearEffects - c``
``coriolis_matrix`` C(q, qd) from the Christoffel symbols of D  ``computeCoriolisMatrix``
``gravity``        c(q), n                                     ``computeGeneralizedGravity``
``inverse_dynamics`` tau(q, qd, qdd) with armature + friction  ``rnea`` + friction terms
``forward_dynamics`` qdd(q, qd, tau)                           ``aba`` (same terms)
=================  =========================================  ==================================

Units: q in rad (m for prismatic joints), qd in rad/s, qdd in rad/s^2, tau in N m (N).
C satisfies ``dD/dt - 2C`` skew-symmetric; with Newton-Euler it is computed by the O(n^2)
recursion of :mod:`symdyn.derive.coriolis` (sums of 6-vector dot products), or, where that
costs more operations (short sparse arms, see :data:`CORIOLIS_RECURSION_FROM_DOF`), as
``C = (1/2) dh/dqd`` (h is quadratic in qd and its symmetric coefficient tensor is exactly the
Christoffel symbols of the first kind); with Lagrange-Euler as ``C_ik = sum_m h_ikm qd_m``.

With Newton-Euler, D comes from the composite-rigid-body method (:mod:`symdyn.derive.composite`), the
recursive companion of Table 3.2; with Lagrange-Euler from the trace form over U_ij and the
pseudo-inertias.

Forward dynamics solves ``(D + diag(armature)) qdd = tau - h - c - friction`` with an LDL^T
factorization written out for the robot (no inverse).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, Iterable, Mapping

import mpmath
import numpy as np
import sympy as sp

from ..model.errors import SymdynError, warn
from . import ldlt
from .articulated_body import forward_dynamics as articulated_body_fd
from .articulated_body import reaction_map
from .articulated_loops import ArticulatedLoops, articulated_loops
from .regressor import base_parameters as find_base_parameters
from .regressor import standard_parameters
from .regressor import base_equivalent
from .regressor import regressor as regressor_matrix
from .chain import make_chain
from .composite import mass_matrix_factored
from .coriolis import coriolis_matrix as recursive_coriolis_matrix
from .coriolis import tree_coriolis_matrix
from .jacobian_newton_euler import JacobianNewtonEuler
from .lagrange_euler import LagrangeEuler
from .newton_euler import joint_forces
from .program import Program, ProgramBuilder, differentiate
from .tangents import vector_tangents
from ..model.outputs import (ALL_OUTPUTS, REGISTRY, EXTRA_OUTPUTS, KINEMATIC_OUTPUTS, OUTPUT_INPUTS,  # noqa: F401 (part of this module's API)
                             OUTPUT_SYMBOLS, OUTPUTS, PARAMETERS_PER_LINK, TASK_OUTPUTS, TREE_OUTPUTS, TREE_AVAILABLE,
                             CENTROIDAL_OUTPUTS, CONFIGURATION_OUTPUTS, CONTACT_DERIVATIVES, CONTACT_INVERSE, CONTACT_OUTPUTS, IMPULSE_OUTPUTS, FORWARD_DERIVATIVES, FRAME_OUTPUTS, INVERSE_OUTPUTS, Dimensions, default_outputs,
                             spec,
                             with_requirements)
from ..model.robot import JACOBIAN_ROWS, Robot, serial_robot
from ..model.tolerances import PIVOT_RTOL as TOLERANCES
from .configuration import configuration_outputs
from .kinematics import RESTITUTION, configuration_symbols, contact_force_symbols, joint_symbols
from .numeric import NumericEquations, compile_function
from .task_space import task_space
from .contact import constrained_inverse, contact_drift, contact_dynamics, contact_rows, correction, gram_schmidt
from .poses import tree_poses, world_placement
from .newton_euler import recursion
from .spatial import named_vector, skew
from .tool import tool_kinematics
from .centroidal import centroidal_quantities
from .frames import frame_kinematics

#: how inverse dynamics is written: in the robot's standard parameters, or in its base parameters
PARAMETER_FORMS = ("standard", "base")

METHODS = ("newton-euler", "lagrange-euler", "jacobian-newton-euler")
METHOD_ALIASES = {"ne": "newton-euler", "newton-euler": "newton-euler", "rne": "newton-euler",
                  "le": "lagrange-euler", "lagrange-euler": "lagrange-euler", "lagrange": "lagrange-euler",
                  "jne": "jacobian-newton-euler", "jacobian-newton-euler": "jacobian-newton-euler"}

@dataclass(frozen=True)
class Equations:
    """The derived equations of motion of one robot by one method (immutable).

    ``outputs`` maps each derived quantity's name (see :data:`OUTPUTS`) to a SymPy matrix
    (vectors are n x 1, matrices n x n) whose entries use the joint symbols ``q, qd, qdd, tau``,
    the robot's ``parameters`` and the intermediate symbols assigned by ``program``.
    """

    robot: Robot
    method: str
    q: tuple[sp.Symbol, ...]
    qd: tuple[sp.Symbol, ...]
    qdd: tuple[sp.Symbol, ...]
    tau: tuple[sp.Symbol, ...]
    program: Program
    outputs: tuple[tuple[str, sp.ImmutableMatrix], ...]
    seconds: float = field(default=0.0, compare=False)
    #: ``(d_j, M_jj)`` for each pivot d_j of the LDL^T factorization forward dynamics divides by,
    #: with M_jj the diagonal entry of ``M = D + diag(armature)`` it comes from (expressions in
    #: the program's symbols), in joint order; empty when forward dynamics was not derived.
    #: Emitters check ``d_j > PIVOT_RTOL * M_jj`` at run time: M is (numerically) singular
    #: at that state otherwise.
    pivots: tuple[tuple[sp.Expr, sp.Expr], ...] = ()
    #: how forward dynamics was solved ("ldlt" or "aba"; empty when it was not derived)
    fd_method: str = ""
    #: the base parameters, ``(name, expression in the standard parameters)`` per column of
    #: ``base_regressor`` (:mod:`symdyn.derive.regressor`); empty when it was not derived
    base_parameters: tuple[tuple[str, sp.Expr], ...] = ()
    #: "base" when inverse dynamics was written in the base parameters, else "standard"
    parameter_form: str = "standard"
    #: ``(S, F)`` when the mass matrix's off-diagonal entries are dot products
    #: ``D[i, j] = S[i] . F[j - 1]`` (i < j; 6 entries each, see
    #: :func:`symdyn.derive.composite.mass_matrix_factored`), else ``()``
    mass_factors: tuple = ()
    #: ``(M, rhs, factors)`` when forward dynamics is to be emitted as a solve of
    #: ``M qdd = rhs`` (``M = D + diag(armature)``, n x n; ``rhs``, n x 1; ``factors`` as
    #: :attr:`mass_factors` for M's off-diagonal entries, or ``()``) by a loop, instead of the
    #: unrolled LDL^T of the ``forward_dynamics`` output, whose size grows as n^3 (chains of
    #: :data:`LOOPED_SOLVE_FROM_DOF` joints or more); else ``()``.  Both give the same
    #: solution up to rounding; the pivots checked are the same.
    fd_system: tuple = ()
    #: the fields of :class:`symdyn.derive.articulated_loops.ArticulatedLoops` when forward
    #: dynamics by the articulated-body algorithm is to be emitted as three loops over a table
    #: of the joints (long fixed-base chains of revolute joints,
    #: :data:`~symdyn.derive.articulated_loops.LOOPED_ABA_FROM_DOF`); else ``()``.  The output
    #: ``forward_dynamics`` holds the same accelerations written out (for every other consumer).
    fd_loops: tuple = ()
    #: ``(S, dS, F, g, e)`` when the Coriolis matrix was built by the O(n^2) recursion
    #: (:mod:`symdyn.derive.coriolis`): each a tuple of n 6-vectors in the recursion's frame
    #: (tuples of expressions in the program's symbols) with ``C[i, k] = S_i . F_k`` (i <= k) and
    #: ``g_i . dS_k + e_i . S_k`` (k < i), for emitters that write C as a loop; else ``()``
    coriolis_factors: tuple = ()
    #: per joint, the program's symbols ``(c_j, s_j)`` for the cosine and sine of a revolute
    #: joint's angle theta_j + q_j (:func:`symdyn.derive.chain.make_chain`), ``()`` for a
    #: prismatic joint: what a consumer substitutes to give the joint angles another way
    joint_trig: tuple = ()
    #: ``((outputs, checks), ...)``: for each group of outputs whose functions return a status
    #: (:func:`symdyn.model.outputs.returns_status`), the ``(pivot, diagonal entry, status)`` of
    #: every pivot they divide by, in program order.  The task-space outputs: the LDL^T of
    #: ``M = D + diag(armature)`` (status 1, checked at the pivot tolerance) and the squared
    #: diagonal ``R_kk^2`` of the QR that factors ``J M^-1 J^T`` (status 3, checked at the
    #: header's ``NAME_TASK_RTOL``); the inverse mass matrix and the forward-dynamics
    #: derivatives: the LDL^T of M (status 1).  Only groups with a derived output are listed.
    checks: tuple = ()
    #: ``(Minv, dtau_dq, dtau_dqd, qdd)`` (n x n each, qdd n x 1) when a forward-dynamics
    #: derivative was derived: M^-1, the derivatives of inverse dynamics at the accelerations
    #: forward dynamics gives, and those accelerations (program symbols, held constant in
    #: dtau_dq and dtau_dqd), for emitters that write ``dqdd/dq = -Minv dtau_dq`` and
    #: ``dqdd/dqd = -Minv dtau_dqd`` as a loop (the outputs hold the same products written
    #: out); else ``()``
    inverse_products: tuple = ()
    #: ``(Minv, U, V, dF_q, dF_qd, solution)`` when a contact derivative (by q or qd) was
    #: derived, for emitters that write its products as loops (the outputs hold the same
    #: products written out): ``[dqdd/dx; dlambda/dx] = -W [dF1/dx; dF2/dx]`` with
    #: ``W = [K S; -S^T A^-1] = diag(M^-1, 0) + U V^T`` ((n + m) x (n + m), the constrained
    #: system's inverse with its force rows negated: its first n columns are dqdd/dtau and
    #: dlambda/dtau), ``U = [Z; R^-1]`` and ``V = [-Z; R^-1]`` ((n + m) x m), M^-1 (n x n), the
    #: residuals' derivatives ``dF_q`` and ``dF_qd`` ((n + m) x n; a floating base's turn of the
    #: forces folded into dF1 as ``-J^T [lambda]x R``) and the solution ``[qdd; lambda]``
    #: ((n + m) x 1); else ``()``
    contact_products: tuple = ()
    #: ``((parts, tangents), ...)``: for derivative outputs whose straight-line statements pass
    #: :data:`TANGENT_LOOPS_FROM_OPS`, their vector forward-mode form
    #: (:class:`symdyn.derive.tangents.VectorTangents`) for emitters that write them as loops:
    #: ``parts`` names the output of each group of the tangents (``inverse_dynamics_dq``,
    #: ``inverse_dynamics_dqd``; for ``forward_dynamics_dq`` and ``forward_dynamics_dqd``, the
    #: dtau/dq and dtau/dqd of :attr:`inverse_products`, rows = tau); the outputs hold the same
    #: derivatives written out
    tangent_loops: tuple = ()

    def tangents_for(self, part: str):
        """``(tangents, group)`` of an output written as loops (:attr:`tangent_loops`), or None."""
        for parts, tangents in self.tangent_loops:
            if part in parts:
                return tangents, parts.index(part)
        return None

    @property
    def n(self) -> int:
        """Entries of qd, qdd and tau (the joints, and a floating base's 6): the outputs' size."""
        return self.robot.nv

    @property
    def nq(self) -> int:
        """Entries of q (the joints, and a floating base's 7)."""
        return self.robot.nq

    @property
    def v(self) -> tuple[sp.Symbol, ...]:
        """The tangent vector of the configuration-space functions (n symbols)."""
        return configuration_symbols(self.nq, self.n)[0]

    @property
    def restitution(self) -> tuple[sp.Symbol, ...]:
        """The restitution of an impact (one symbol)."""
        return RESTITUTION

    @property
    def f(self) -> tuple[sp.Symbol, ...]:
        """The external forces at the contacts (NC symbols, laid out as the contact forces)."""
        return contact_force_symbols(self.robot.contact_rows)

    @property
    def q1(self) -> tuple[sp.Symbol, ...]:
        """The second configuration of the configuration-space functions (nq symbols)."""
        return configuration_symbols(self.nq, self.n)[1]

    @property
    def dimensions(self) -> Dimensions:
        """The sizes of the outputs (the base parameters' count among them)."""
        return Dimensions.of(self.robot, len(self.base_parameters))

    @property
    def parameters(self) -> tuple[sp.Symbol, ...]:
        return self.robot.parameters

    @property
    def articulated_loops(self):
        """:attr:`fd_loops` as an :class:`~symdyn.derive.articulated_loops.ArticulatedLoops`, or None."""
        return ArticulatedLoops(*self.fd_loops) if self.fd_loops else None

    def checks_for(self, parts: Iterable[str]) -> tuple:
        """The ``(pivot, diagonal entry, status)`` checks of a function writing ``parts``: those
        of every group with one of them (:attr:`checks`), each once, in order."""
        parts = set(parts)
        found: list = []
        for outputs, checks in self.checks:
            if parts & set(outputs):
                found += [c for c in checks if c not in found]
        return tuple(found)

    def output(self, name: str) -> sp.ImmutableMatrix:
        for key, value in self.outputs:
            if key == name:
                return value
        if name not in ALL_OUTPUTS:
            raise KeyError(f"unknown output {name!r}; known: {', '.join(ALL_OUTPUTS)}")
        raise KeyError(f"{name!r} was not derived (derived: {', '.join(self.output_names)})")

    @property
    def output_names(self) -> tuple[str, ...]:
        return tuple(k for k, _ in self.outputs)

    mass_matrix = property(lambda self: self.output("mass_matrix"), doc="D(q), n x n")
    coriolis = property(lambda self: self.output("coriolis"), doc="h(q, qd), n x 1")
    coriolis_matrix = property(lambda self: self.output("coriolis_matrix"), doc="C(q, qd), n x n")
    gravity = property(lambda self: self.output("gravity"), doc="c(q), n x 1")
    inverse_dynamics = property(lambda self: self.output("inverse_dynamics"), doc="tau, n x 1")
    forward_dynamics = property(lambda self: self.output("forward_dynamics"), doc="qdd, n x 1")
    forward_kinematics = property(lambda self: self.output("forward_kinematics"),
                                  doc="tool pose in the world, 4 x 4 homogeneous")
    jacobian = property(lambda self: self.output("jacobian"),
                        doc="tool Jacobian, 6 x n: linear (rows 0-2) and angular velocity, world axes")
    jacobian_dot_qd = property(lambda self: self.output("jacobian_dot_qd"),
                               doc="J-dot qd, 6 x 1: tool classical acceleration at qdd = 0, world axes")
    regressor = property(lambda self: self.output("regressor"),
                         doc="Y, n x 13n: tau = Y pi (standard parameters, symdyn.derive.regressor)")
    base_regressor = property(lambda self: self.output("base_regressor"),
                              doc="Y_b, n x (base parameters): tau = Y_b beta")
    reaction_map = property(lambda self: self.output("reaction_map"),
                            doc="[k0 | D], 6 x (1 + actuated joints): the base wrench on body 1 "
                                "[n; f] = k0 + D tau_H in the base frame (moment about its origin first)")

    def assignments_for(self, names: Iterable[str]):
        """The intermediate assignments the named outputs need, in order."""
        return self.program.needed_for([e for name in names for e in self.output(name)])

    def expanded(self, name: str) -> sp.ImmutableMatrix:
        """An output with every intermediate symbol substituted (closed form in q, qd, ...)."""
        return sp.ImmutableMatrix(self.program.expand(sp.Matrix(self.output(name))))

    def count_ops(self, names: Iterable[str] | None = None) -> int:
        """SymPy ``count_ops`` of the assignments and final expressions the outputs need."""
        names = self.output_names if names is None else tuple(names)
        exprs = [rhs for _, rhs in self.assignments_for(names)]
        exprs += [e for name in names for e in self.output(name)]
        return int(sum(sp.count_ops(e) for e in exprs))

    @cached_property
    def numeric(self):
        """Compiled numeric evaluation (:class:`symdyn.derive.numeric.NumericEquations`)."""
        return NumericEquations(self)


class TaskUnreachable(SymdynError):
    """The task of the task-space functions has dependent rows at every configuration (their
    Lambda does not exist): ``symdyn verify --all`` and the fuzzer leave those functions out."""


def check_tree_request(robot: Robot, method: str, wanted, fd_method: str, parameters: str) -> None:
    """Refuse, in one line, what is not derived for kinematic trees: another method than
    Newton-Euler, the articulated-body forward dynamics, the base-parameter form and the
    outputs of a single tool or chain (kinematics, task space, regressors, reaction map)."""
    where = robot.source or robot.name
    kind = ("has mimic joints (whose dynamics are a tree's projected on their leaders)" if robot.mimics
            else "is a kinematic tree (links with 'parent:')")
    if method != "newton-euler":
        raise SymdynError(f"{where}: {method} is written for serial chains; this robot {kind}: use newton-euler")
    if fd_method != "ldlt":
        raise SymdynError(f"{where}: the articulated-body forward dynamics is written for serial chains; a kinematic "
                          "tree's forward dynamics is the L^T D L factorization of its mass matrix (--fd-method ldlt)")
    if parameters != "standard":
        raise SymdynError(f"{where}: the base-parameter form is written for serial chains (this robot {kind})")
    other = [name for name in wanted if name not in TREE_AVAILABLE]
    if other:
        which = ("a robot with mimic joints (its tool functions are a tree's: frames)" if robot.mimics
                 else "a kinematic tree (links with 'parent:'), which has no single tool")
        raise SymdynError(f"{where}: {', '.join(other)} {'is' if len(other) == 1 else 'are'} not available for "
                          f"{which}; available: {', '.join(TREE_AVAILABLE)}")


def normalize_method(method: str) -> str:
    key = method.lower().replace("_", "-")
    if key not in METHOD_ALIASES:
        raise ValueError(f"unknown method {method!r}; use newton-euler, lagrange-euler or jacobian-newton-euler")
    return METHOD_ALIASES[key]


def friction_terms(robot: Robot, qd, qdd) -> sp.Matrix:
    """Armature, viscous and Coulomb friction of each joint (nv x 1: a floating base's 6 rows
    have none)."""
    base = 6 if robot.floating else 0
    return sp.Matrix([0] * base + [link.armature * qdd[base + i] + link.damping * qd[base + i]
                                   + link.coulomb * sp.sign(qd[base + i]) for i, link in enumerate(robot.links)])


def armature_matrix(robot: Robot) -> sp.Matrix:
    """diag(armature), nv x nv (zero on a floating base's rows; a mimic joint's armature on its
    leader's entry times the square of its multiplier)."""
    return sp.diag(*([0] * (6 if robot.floating else 0) + list(coordinate_sums(robot, "armature"))))


def coordinate_sums(robot: Robot, field: str) -> tuple:
    """A per-joint coefficient (armature, damping) per coordinate (:meth:`Robot.per_coordinate`)."""
    return robot.per_coordinate([getattr(link, field) for link in robot.links])


#: forward dynamics in double reports a singular mass matrix where a pivot d_j <= PIVOT_RTOL * M_jj
#: (the solution would carry a relative error of about 1e-16 / PIVOT_RTOL or more); every
#: precision's value is in :mod:`symdyn.model.tolerances`
PIVOT_RTOL = TOLERANCES["double"]


def _subtree_scales(robot: Robot, values) -> np.ndarray:
    """For each joint j, an upper bound of the inertia about its axis that links j..n could
    have (kg m^2 or kg): a revolute joint's, their masses times the square of their reach from
    joint j (link offsets, origins and centres of mass added up) and their rotational inertias'
    traces; a prismatic joint's, their masses (what it moves along its axis is their total
    mass: a length would mix kg m^2 into kg); and joint j's armature; at the parameter
    ``values``."""
    def number(e):
        return abs(float(sp.sympify(e).xreplace(values)))
    links = robot.links
    reach = [sum(number(x) for x in (link.a, link.d, *(link.origin.xyz if link.origin is not None else ())))
             for link in links]
    out = np.zeros(len(links))
    for j in range(len(links)):
        total = number(links[j].armature)
        for k in robot.subtree(j):
            if not links[j].is_revolute:
                total += number(links[k].mass)
                continue
            path = [k, *robot.ancestors(k)]
            distance = sum(reach[i] for i in path[:path.index(j) + 1]) + sum(number(c) for c in links[k].com)
            total += number(links[k].mass) * distance ** 2 + sum(number(x) for x in links[k].inertia[:3])
        out[j] = total
    if robot.mimics:  # per coordinate: its links' and its mimics' (times the multiplier squared)
        return np.array([float(v) for v in robot.per_coordinate(out)])
    return out


def _zero_pivots(Mv, scale, rtol, zero) -> tuple[set[int], set[int]]:
    """An LDL^T of the symmetric ``Mv`` (n x n rows of numbers, float or mpmath); returns the
    joints whose pivot, and whose diagonal entry, is at most ``rtol`` times the joint's
    ``scale`` (such pivots count as ``zero``, so that the factorization goes on)."""
    n = len(Mv)
    L = [[zero] * n for _ in range(n)]
    d = [zero] * n
    pivots, diagonals = set(), set()
    for j in range(n):
        d[j] = Mv[j][j] - sum((L[j][k] ** 2 * d[k] for k in range(j)), zero)
        if abs(Mv[j][j]) <= rtol * scale[j]:
            diagonals.add(j)
        if abs(d[j]) <= rtol * scale[j]:
            d[j] = zero
            pivots.add(j)
            continue
        for i in range(j + 1, n):
            L[i][j] = (Mv[i][j] - sum((L[i][k] * L[j][k] * d[k] for k in range(j)), zero)) / d[j]
    return pivots, diagonals


#: a pivot found zero in double is confirmed at this many digits, where "zero" means below
#: 10**-PRECISE_ZERO_EXPONENT of the joint's scale (the robot's numbers are taken exactly)
PRECISE_DIGITS, PRECISE_ZERO_EXPONENT = 120, 90


def check_not_singular(robot: Robot, program: Program, M: sp.Matrix, states: int = 2, seed: int = 0) -> None:
    """Refuse forward dynamics of a chain whose ``M = D + diag(armature)`` is singular for every
    q, warn where it only looks singular.

    M is evaluated at ``states`` random configurations (random positive values for the
    parameters) and factorized in double: a pivot that vanishes relative to the inertia its
    joint could move (:func:`_subtree_scales`) at every state is then recomputed at
    ``PRECISE_DIGITS`` digits from the robot's exact numbers. Still zero there (an exact zero
    in the model, e.g. a point-mass wrist), it is refused with a :class:`SymdynError` naming
    the file and joint; otherwise (a regular but extremely ill-conditioned M) a warning says the
    generated code will report it singular at run time."""
    n = M.shape[0]
    q = joint_symbols(robot.dof)[0]
    evaluate = compile_function([q, robot.parameters], program, M, "mass_matrix_check")
    rng = np.random.default_rng(seed)
    zero_pivot, zero_diagonal = set(range(n)), set(range(n))
    witness = None
    for _ in range(states):
        values, pose = rng.uniform(0.5, 1.5, len(robot.parameters)), rng.uniform(-np.pi, np.pi, n)
        try:
            Mv = evaluate(pose, values)
            subtree = _subtree_scales(robot, dict(zip(robot.parameters, values)))
        except (ZeroDivisionError, OverflowError, ValueError, TypeError):
            return  # not evaluable here: leave it to the run-time check
        if not np.all(np.isfinite(Mv)) or not np.all(np.isfinite(subtree)):
            return
        # each joint's entries are judged against the inertia that joint could move at most
        # (a 0.01 kg m^2 wrist under a 1e9 kg m^2 first link is not zero)
        scale = np.maximum(np.maximum(subtree, np.abs(np.diag(Mv))), 1e-300)
        pivots, diagonals = _zero_pivots(Mv.tolist(), scale, 1e-10, 0.0)
        zero_pivot &= pivots
        zero_diagonal &= diagonals
        witness = (pose, values, scale)
    if not zero_pivot:
        return
    pose, values, scale = witness
    # the robot's numbers may span many decades (1e100 lengths with 0.1 kg m^2 inertias): the
    # digits grow with that span, so that a pivot the size of the smallest numbers is resolved
    span = _decades(robot, dict(zip(robot.parameters, values)))
    digits = PRECISE_DIGITS + 2 * span
    precise = compile_function([q, robot.parameters], program, M, "mass_matrix_exact", digits=digits)
    with mpmath.workdps(digits):
        exact_pivot, exact_diagonal = _zero_pivots(precise(pose, values), [mpmath.mpf(float(x)) for x in scale],
                                                   mpmath.mpf(10) ** -(PRECISE_ZERO_EXPONENT + 2 * span),
                                                   mpmath.mpf(0))
    where = f"{robot.source}: " if robot.source else ""
    exact = zero_pivot & exact_pivot
    if not exact:
        j = min(zero_pivot)
        warn(f"{where}forward dynamics: the mass matrix is nearly singular at every sampled q (pivot of joint "
             f"{j + 1} ('{_name(robot, j)}') below 1e-10 of the inertia it could move, but not zero); the "
             "generated code returns status 1 (singular) wherever a pivot fails its run-time check")
        return
    j = min(exact)
    if j in zero_diagonal and j in exact_diagonal:
        zero = sorted(exact & zero_diagonal & exact_diagonal)
        raise SingularMassMatrix(f"{where}forward dynamics: D[{j + 1},{j + 1}] is identically 0: {_joints(robot, zero)} "
                                 f"{'has' if len(zero) == 1 else 'have'} no inertia about {'its' if len(zero) == 1 else 'their'} "
                                 "axis; give the links inertia or an armature, or leave forward_dynamics out")
    raise SingularMassMatrix(f"{where}forward dynamics: the mass matrix is singular for every q: "
                             f"{_joints(robot, sorted(exact))} {'moves' if len(exact) == 1 else 'move'} no inertia that "
                             "the joints before do not already move; give the links inertia or an armature, or leave "
                             "forward_dynamics out")


class SingularMassMatrix(SymdynError):
    """The mass matrix (plus armature) is singular for every q: forward dynamics, its derivatives,
    the inverse mass matrix and the task-space functions cannot be generated (the others can)."""


def _name(robot: Robot, k: int) -> str:
    """The name of joint coordinate k (its link's; a leader's for the mimics that follow it)."""
    return robot.links[robot.coordinate_links[k]].name


def _joints(robot: Robot, joints: list[int], shown: int = 6) -> str:
    """``joint 61 ('RThumb3')``, or ``joints 61 ('RThumb3'), 62 (...), ... (24 joints)``."""
    names = [f"{k + 1} ('{_name(robot, k)}')" for k in joints]
    if len(names) == 1:
        return f"joint {names[0]}"
    more = f", ... ({len(names)} joints)" if len(names) > shown else ""
    return f"joints {', '.join(names[:shown])}{more}"


def _zero_pivot(robot: Robot, M: sp.Matrix, what: str = "forward dynamics", leave: str = "forward_dynamics"):
    """The callback of a factorization that meets an identically zero pivot: a
    :class:`SingularMassMatrix` naming every joint whose diagonal entry of ``M`` is zero (a
    massless subtree without armature), or the joint of the pivot."""
    def raise_singular(j: int):
        offset = 6 if robot.floating else 0  # a floating base's 6 rows come first
        joints = [k - offset for k in range(offset, M.shape[0]) if sp.sympify(M[k, k]) == 0] or \
            ([j - offset] if j >= offset else [])
        where = f"{robot.source}: " if robot.source else ""
        what_moves = (f"{_joints(robot, joints)} {'moves' if len(joints) == 1 else 'move'} no inertia (massless links "
                      "without armature)") if joints else "the floating base has no inertia"
        raise SingularMassMatrix(f"{where}{what}: pivot {j + 1} of the mass matrix is identically 0: {what_moves}; "
                                 f"give them inertia or an armature, or leave {leave} out")
    return raise_singular


def _decades(robot: Robot, values) -> int:
    """How many decades the robot's nonzero numbers (lengths, masses, centres of mass,
    inertias, armatures) span beyond 1e-10..1e10, at the parameter ``values`` (0 for ordinary
    robots)."""
    exponents = []
    for link in robot.links:
        fields = (link.a, link.d, link.mass, link.armature, *link.com, *link.inertia,
                  *(link.origin.xyz if link.origin is not None else ()))
        for e in fields:
            try:
                x = abs(float(sp.sympify(e).xreplace(values)))
            except (TypeError, ValueError):
                continue
            if x > 0 and math.isfinite(x):
                exponents.append(math.log10(x))
    if not exponents:
        return 0
    return int(math.ceil(max(0.0, max(exponents) - 10) + max(0.0, -10 - min(exponents))))


def _ldlt_solve(b: ProgramBuilder, M: sp.Matrix, rhs: sp.Matrix, robot: Robot) -> tuple[sp.Matrix, tuple[tuple[sp.Expr, sp.Expr], ...]]:
    """Solve M x = rhs for symmetric positive definite M with an unrolled LDL^T (n divisions);
    returns the solution (n x 1) and the n pairs (pivot d_j, diagonal entry M_jj)."""
    factorization = ldlt.factor(b, M, "ldl", _zero_pivot(robot, M))
    x = ldlt.solve(b, factorization, rhs, "ldl_y", "qdd{i}_fd")
    return sp.Matrix(x), factorization.pivots


#: from this many joints, emitters solve ``M qdd = rhs`` for forward dynamics by an LDL^T loop
#: over arrays (:attr:`Equations.fd_system`) instead of the unrolled factorization, whose code
#: grows as n^3: on generic chains (benchmarks/long_chains.py, gcc -O2 / -O3 -march=native) the
#: unrolled form is faster at 12 joints (1739 against 2118 ns), the loop from about 18
#: (3515 against 3604 ns; -O3: 3255 against 4327)
LOOPED_SOLVE_FROM_DOF = 16

#: how forward dynamics is solved: an LDL^T factorization of D unrolled for the robot, or the
#: articulated-body algorithm (:mod:`symdyn.derive.articulated_body`)
FD_METHODS = ("ldlt", "aba")


#: from this many joints the Coriolis matrix is always built by the O(n^2) recursion
#: (:mod:`symdyn.derive.coriolis`); below, both ways are built and the one with fewer operations
#: (SymPy's count of the statements) kept.  Multiplications + additions of the emitted C,
#: derivative of h against recursion: SCARA 58 / 125 and Stanford arm 1215 / 1318 keep the
#: derivative; Puma 560 1372 / 1293 and the Panda 3740 / 2687 take the recursion, as do generic
#: chains (6 joints: 3727 / 2432; 12: 16,370 / 7574; 24: 66,041 / 20,606)
CORIOLIS_RECURSION_FROM_DOF = 12


def _coriolis_matrix_of(b, h: sp.Matrix, qd) -> sp.Matrix:
    """C = dh/dqd / 2 (n x n), the Christoffel-consistent Coriolis matrix (h is quadratic in qd),
    by forward-mode differentiation of h's recursion, seeded with 1/2."""
    columns = differentiate(b.build(), h, qd, b, "dh", scale=sp.Rational(1, 2))
    n = len(qd)
    return sp.Matrix(n, n, lambda i, k: b.define(f"C{i + 1}{k + 1}", columns[k][i]))


class _Derivation:
    """The quantities of one derivation, each derived once on first use (:meth:`get`), in the
    program of one :class:`ProgramBuilder`: the order of first use is the order of the
    program's statements (so the output of a derivation is reproducible)."""

    def __init__(self, robot: Robot, method: str, need: set[str], fd_method: str, parameters: str, report):
        self.robot, self.method, self.need, self.fd_method, self.parameters = robot, method, need, fd_method, parameters
        self.report = report
        self.chain = chain = make_chain(robot)
        self.b, self.n = chain.builder, robot.nv
        self.zero = [sp.S.Zero] * robot.nv
        #: the inputs (symbols per coordinate) and the joints' coordinates (q after a floating base's 7)
        _, self.qd, self.qdd, self.tau = chain.coordinates
        self.joint_q = chain.coordinate_q
        #: the parent array the factorization of M follows (:func:`_factor_parents`), or None
        self.factor_parents = _factor_parents(robot)
        self.friction = chain.project(friction_terms(robot, chain.qd, chain.qdd))
        self.values: dict[str, sp.Matrix] = {}
        self.mass_factors: tuple = ()
        self.coriolis_factors: tuple = ()
        self.fd_system: tuple = ()
        self.fd_loops: tuple = ()
        self.pivots: tuple = ()
        self.checks: list = []
        self.base: tuple = ()
        self.mass_factorization = None
        self.mass_inverse = None
        #: the solved contact system: (J, gamma, ContactDynamics), for its derivatives
        self.contact_system: tuple = ()
        #: each corrected sole's :func:`~symdyn.derive.contact.sole_error` from the contact
        #: dynamics' drift, its Jacobian evaluated (key ``f"ctb{k}"``, k its 1-based place in the
        #: set), for the derivatives
        self.sole_errors: dict = {}
        self.inverse_products: tuple = ()
        self.contact_products: tuple = ()
        self.tangent_loops: list = []
        self.jne = self.le = None
        if method == "jacobian-newton-euler":
            report("world-frame link quantities (k_i, d_i, h_i, I_i)")
            self.jne = JacobianNewtonEuler(chain)
        elif method == "lagrange-euler":
            report("link transforms, U_ij, U_ijk")
            self.le = LagrangeEuler(chain)

    def get(self, name: str) -> sp.Matrix:
        if name not in self.values:  # (a derivation that writes several outputs stores them itself)
            value = DERIVATIONS[REGISTRY[name].derivation if name in REGISTRY else name](self)  # (which may
            # replace self.values: read it after)
            self.values.setdefault(name, value)
        return self.values[name]

    def forces(self, qd, qdd, gravity, tag: str) -> sp.Matrix:
        """Generalized forces of the rigid bodies (no friction) by the method's recursion, at
        the coordinates' rates ``qd`` and accelerations ``qdd`` (nv each; mimic joints follow)."""
        chain = self.chain
        qd, qdd = chain.expand(qd), chain.expand(qdd)
        if self.jne is not None:
            return self.jne.joint_forces(qd, qdd, gravity, tag)
        return chain.project(joint_forces(chain, qd, qdd, gravity, tag))

    @property
    def static_friction(self) -> sp.Matrix:
        """Friction and armature terms at qdd = 0 (viscous and Coulomb friction)."""
        return self.friction.subs({v: 0 for v in self.qdd})


def _gravity(d: _Derivation) -> sp.Matrix:
    if d.le is not None:
        return d.le.gravity()
    d.report("gravity (backward recursion at qd = qdd = 0)" if d.jne is not None else "gravity")
    return d.forces(d.zero, d.zero, d.chain.gravity, "g")


def _coriolis(d: _Derivation) -> sp.Matrix:
    if d.le is not None:
        C = d.get("coriolis_matrix")
        return sp.Matrix([d.b.define(f"h{i + 1}", (C[i, :] * sp.Matrix(d.chain.qd))[0]) for i in range(d.n)])
    d.report("coriolis (J_c^T (M gamma + u_n))" if d.jne is not None else "coriolis")
    return d.forces(d.qd, d.zero, sp.zeros(3, 1), "h")


def _coriolis_matrix(d: _Derivation) -> sp.Matrix:
    if d.le is not None:
        return d.le.coriolis_matrix(d.chain.qd)
    if d.robot.is_tree:
        d.report("coriolis_matrix (the tree's recursion over its subtrees)")
        return d.chain.project_columns(d.chain.project(tree_coriolis_matrix(d.chain)))
    if d.jne is not None:
        return _derivative_coriolis_matrix(d)
    if d.n >= CORIOLIS_RECURSION_FROM_DOF:
        return _recursive_coriolis_matrix(d)
    return _cheaper_coriolis_matrix(d)


def _derivative_coriolis_matrix(d: _Derivation) -> sp.Matrix:
    d.report("coriolis_matrix (derivative of h by qd)")
    return _coriolis_matrix_of(d.b, d.get("coriolis"), d.chain.qd)


def _recursive_coriolis_matrix(d: _Derivation) -> sp.Matrix:
    d.report("coriolis_matrix (O(n^2) recursion)")
    C, factors = recursive_coriolis_matrix(d.chain)
    d.coriolis_factors = factors.as_tuple()
    return C


def _cheapest(d: _Derivation, builds, beside=()) -> sp.Matrix:
    """The matrix of whichever of ``builds`` (each ``build(d)``, in order: ties to the first)
    needs fewer operations (SymPy's count over every statement it and the expressions ``beside``,
    computed in the same function, need), each built on a copy of the program so far, with the
    derivation's values and Coriolis factors as they were: the derivation goes on with the
    chosen copy only (deterministic: the counts depend on the robot alone)."""
    start, values, factors = d.b.build(), dict(d.values), d.coriolis_factors
    candidates = []
    for build in builds:
        d.b = d.chain.builder = ProgramBuilder(d.b.prefix, start=start)
        d.values, d.coriolis_factors = dict(values), factors
        matrix = build(d)
        needed = d.b.build().needed_for(list(matrix) + list(beside))
        cost = sum(sp.count_ops(rhs) for _, rhs in needed) + sum(sp.count_ops(e) for e in matrix)
        candidates.append((cost, d.b, d.values, d.coriolis_factors, matrix))
    _, builder, d.values, d.coriolis_factors, matrix = min(candidates, key=lambda c: c[0])
    d.b = d.chain.builder = builder
    return matrix


def _cheaper_coriolis_matrix(d: _Derivation) -> sp.Matrix:
    """C by whichever of the two ways needs fewer operations (:func:`_cheapest`; ties to the
    recursion)."""
    return _cheapest(d, (_recursive_coriolis_matrix, _derivative_coriolis_matrix))


def _mass_matrix(d: _Derivation) -> sp.Matrix:
    if d.le is not None:
        return d.le.mass_matrix()
    if d.jne is not None:
        d.report("mass_matrix (sum of J_ci^T M_i J_ci)")
        return d.jne.mass_matrix()
    d.report("mass_matrix (composite rigid bodies)")
    D, d.mass_factors = mass_matrix_factored(d.chain)
    if d.robot.mimics:  # G^T D G: its entries are no longer the factors' dot products
        D, d.mass_factors = d.chain.project_columns(d.chain.project(D)), ()
    return D


def _inverse_dynamics(d: _Derivation) -> sp.Matrix:
    chain = d.chain
    if d.le is not None:
        return (d.get("mass_matrix") * sp.Matrix(chain.qdd) + d.get("coriolis") + d.get("gravity") + d.friction)
    d.report("inverse_dynamics")
    return d.forces(d.qd, d.qdd, chain.gravity, "") + d.friction


def _bias(d: _Derivation) -> sp.Matrix:
    """h + c, the right-hand side of forward dynamics at tau = 0 (without friction)."""
    if d.le is not None:
        return d.get("coriolis") + d.get("gravity")
    d.report("forward_dynamics (bias forces)")
    return d.forces(d.qd, d.zero, d.chain.gravity, "b")


def _tool(d: _Derivation) -> sp.Matrix:
    """Every kinematic output needed, derived together (they share the link poses)."""
    kinematic = [name for name in KINEMATIC_OUTPUTS if name in d.need]
    d.report("tool kinematics")
    d.values.update(tool_kinematics(d.chain, kinematic))
    return d.values[kinematic[0]]


def _centroidal(d: _Derivation) -> sp.Matrix:
    """Every centre-of-mass and centroidal output needed, derived together (they share the
    link poses and the subtree sums)."""
    wanted = [name for name in CENTROIDAL_OUTPUTS if name in d.need]
    d.report("centre of mass and centroidal momentum")
    d.values.update(_per_coordinate(d, centroidal_quantities(d.chain, wanted)))
    return d.values[wanted[0]]


#: the outputs whose columns are per joint rate (the links' rates: projected on the coordinates
#: for mimic joints, :meth:`symdyn.derive.chain.Chain.project_columns`)
_RATE_COLUMNS = ("jacobian", "frame_jacobians", "center_of_mass_jacobian", "centroidal_momentum_matrix")


def _per_coordinate(d: _Derivation, values: dict) -> dict:
    return {name: d.chain.project_columns(value) if name in _RATE_COLUMNS else value for name, value in values.items()}


def _kinetic_energy(d: _Derivation) -> sp.Matrix:
    """``1/2 qd^T (D + diag(armature)) qd``, the bodies' and the rotors' kinetic energy, with
    ``D qd`` the joint forces of the recursion at zero rates, zero gravity and accelerations
    ``qd`` (linear in the accelerations there: O(n), no D)."""
    d.report("kinetic_energy (D qd by the recursion at zero rates, accelerations qd)")
    qd = list(d.qd)
    momenta = d.forces(d.zero, qd, sp.zeros(3, 1), "K") + armature_matrix(d.robot) * sp.Matrix(qd)
    return sp.Matrix([sp.Rational(1, 2) * sum((v * p for v, p in zip(qd, momenta)), sp.Integer(0))])


def _by_velocity(d: _Derivation, rigid: sp.Matrix, held: frozenset = frozenset(), beside=()) -> sp.Matrix:
    """d rigid / d qd (n x n: row i = rigid_i, column j = qd_j) of the rigid-body joint forces
    ``rigid`` (no friction) at fixed q and qdd: forward-mode derivatives of their recursion, or,
    with Newton-Euler, 2 C(q, qd) from the O(n^2) Coriolis recursion (h is quadratic in qd and C
    holds its Christoffel symbols, so dh/dqd = 2 C; D qdd and c do not depend on qd), whichever
    needs fewer operations (:func:`_cheapest`, with ``beside``); chains of
    :data:`CORIOLIS_RECURSION_FROM_DOF` joints or more take 2 C without counting.  Panda: both
    derivatives of inverse dynamics 3891 -> 3526 multiplications; puma560 keeps the
    forward-mode derivatives."""
    chain, n = d.chain, d.n

    def forward_mode(d):
        columns = differentiate(d.b.build(), rigid, list(d.qd), d.b, "dv", held=held)
        return sp.Matrix(n, n, lambda i, j: columns[j][i])

    def christoffel(d):
        C = tree_coriolis_matrix(chain) if d.robot.is_tree else recursive_coriolis_matrix(chain)[0]
        return 2 * C
    if d.le is not None or d.jne is not None or d.robot.mimics or d.robot.floating:
        return forward_mode(d)  # (a free base's h in its own frame's velocities is not Christoffel-symmetric: dh/dv != 2 C)
    if d.n >= CORIOLIS_RECURSION_FROM_DOF and not d.robot.is_tree:  # the recursion, as for C itself
        return christoffel(d)
    return _cheapest(d, (christoffel, forward_mode), beside)


#: derivatives of inverse dynamics whose straight-line statements need this many operations or
#: more (SymPy's count) are also given as vector tangents (:attr:`Equations.tangent_loops`),
#: which the C emitter writes as one loop per statement: gcc -O3 -march=native, dtau/dq and
#: dtau/dqd together, straight-line against loops: puma560 (3218 operations) 368 against 396 ns,
#: pendulum_leg 396 / 374, iiwa14 (5691) 1206 / 558, the Panda 1634 / 802, chain12 3562 /
#: 2497 (docs/benchmarks.md)
TANGENT_LOOPS_FROM_OPS = 4500


def _tau_derivatives(d: _Derivation, qdd, tag: str, hint: str, held: frozenset = frozenset(), loops: bool = True):
    """``(dtau/dq, dtau/dqd)`` (n x n each: row i = tau_i) of inverse dynamics at the
    accelerations ``qdd`` (``held`` constant): the rigid bodies' forces differentiated by the
    joint positions (forward mode, new statements ``{hint}q...``) and velocities
    (:func:`_by_velocity`), viscous damping on dtau/dqd's diagonal (Coulomb friction's
    derivative is zero away from qd = 0; the armature's term does not depend on q or qd).  Past
    :data:`TANGENT_LOOPS_FROM_OPS`, the same derivatives as vector tangents too
    (:attr:`Equations.tangent_loops`, for the forward-dynamics derivatives' parts when ``held``)."""
    n = d.n
    rigid, by_q = _forces_by_q(d, d.qd, qdd, tag, hint, held)
    by_qd = _by_velocity(d, rigid, held, beside=[e for column in by_q for e in column])
    damping = [sp.S.Zero] * (n - d.robot.dof) + list(coordinate_sums(d.robot, "damping"))  # (none on a free base)
    dq = sp.Matrix(n, n, lambda i, j: by_q[j][i])
    dqd = sp.Matrix(n, n, lambda i, j: by_qd[i, j] + (damping[i] if i == j else 0))
    program = d.b.build()
    size = sum(sp.count_ops(rhs) for _, rhs in program.needed_for(list(dq) + list(dqd), held))
    if loops and size >= TANGENT_LOOPS_FROM_OPS and not d.robot.mimics and not d.robot.floating:
        d.report(f"the same derivatives as vector tangents ({size} operations written out)")
        tangents = vector_tangents(program, list(rigid), [d.joint_q, d.qd], held,
                                   {(1, i, i): damping[i] for i in range(n)})
        parts = FORWARD_DERIVATIVES if held else ("inverse_dynamics_dq", "inverse_dynamics_dqd")
        d.tangent_loops.append((parts, tangents))
    return dq, dqd


def _forces_by_q(d: _Derivation, qd, qdd, tag: str, hint: str, held: frozenset) -> tuple[sp.Matrix, list]:
    """``(rigid, columns)``: the rigid bodies' forces at ``qd``, ``qdd`` and their derivative by
    each coordinate of q (forward mode, new statements ``{hint}q...``), a floating base's 6
    first (:func:`_base_pose_columns`: its orientation enters through gravity in its frame only,
    named ``{hint}gb...`` for that)."""
    gravity = d.chain.gravity
    if d.robot.floating:
        gravity = sp.Matrix([d.b.define(f"{hint}gb{k + 1}{tag}", g, force=True) for k, g in enumerate(gravity)])
    rigid = d.forces(qd, qdd, gravity, tag)
    by_q = differentiate(d.b.build(), rigid, list(d.joint_q), d.b, f"{hint}q", held=held)
    if d.robot.floating:
        by_q = _base_pose_columns(d, rigid, gravity, hint, held) + by_q
    return rigid, by_q


def _base_pose_columns(d: _Derivation, rigid: sp.Matrix, gravity: sp.Matrix, hint: str, held: frozenset) -> list:
    """A floating base's 6 columns of d rigid / d q in the tangent space (Pinocchio's: q (+) dv,
    the base moved by dv's linear part and turned by its angular part in its own frame): zero for
    the position (the forces are the base frame's, gravity is uniform), and for the orientation
    ``d rigid / d g_b [g_b]x``, since turning the base by dtheta turns gravity in its frame
    ``g_b = R^T g`` into ``g_b + [g_b]x dtheta`` to first order."""
    by_gravity = differentiate(d.b.build(), rigid, list(gravity), d.b, f"{hint}gq", held=held)
    g = list(gravity)
    cross = sp.Matrix([[0, -g[2], g[1]], [g[2], 0, -g[0]], [-g[1], g[0], 0]])
    turn = [sum((by_gravity[k] * cross[k, j] for k in range(3)), sp.zeros(*rigid.shape)) for j in range(3)]
    return [sp.zeros(*rigid.shape)] * 3 + turn


def _inverse_dynamics_derivatives(d: _Derivation) -> sp.Matrix:
    """dtau/dq and dtau/dqd (n x n each), :func:`_tau_derivatives` at the input accelerations."""
    d.report("inverse_dynamics derivatives (forward-mode, dtau/dq and dtau/dqd)")
    dq, dqd = _tau_derivatives(d, d.qdd, "", "d")
    b, n = d.b, d.n
    d.values["inverse_dynamics_dq"] = sp.Matrix(n, n, lambda i, j: b.define(f"dTq{i + 1}_{j + 1}", dq[i, j]))
    d.values["inverse_dynamics_dqd"] = sp.Matrix(n, n, lambda i, j: b.define(f"dTv{i + 1}_{j + 1}", dqd[i, j]))
    return d.values["inverse_dynamics_dq"]


def _gravity_derivative(d: _Derivation) -> sp.Matrix:
    """dc/dq (n x n), forward-mode derivatives of c's recursion by each joint coordinate (the
    sin/cos of each joint angle differentiated into each other's symbols); a floating base's in
    its tangent space, as the other derivatives (:func:`_forces_by_q`)."""
    d.report("gravity_derivative (forward-mode, dc/dq)")
    if d.robot.floating:
        _, columns = _forces_by_q(d, d.zero, d.zero, "gd", "dg", frozenset())
    else:
        c = d.get("gravity")
        columns = differentiate(d.b.build(), c, list(d.joint_q), d.b, "dg")
    n = d.n
    return sp.Matrix(n, n, lambda i, j: d.b.define(f"dG{i + 1}_{j + 1}", columns[j][i]))


def coordinate_parents(robot: Robot) -> tuple[int, ...] | None:
    """Per joint coordinate, the coordinate its row of the tree's L^T D L hangs on (-1: none), so
    that M has no entry off the paths to the root: a tree's parent array, or with mimic joints
    (M = G^T D G couples a leader with everything its mimics move) the nearest coordinate each
    is coupled to, when every coupled pair lies on one path (fingers that mimic their siblings);
    None for a serial chain, and where no such tree exists (then M is dense to the
    factorization)."""
    if not robot.is_tree:
        return None
    if not robot.mimics:
        return robot.parent_indices
    coordinate = [k for k, _ in robot.link_coordinates]
    coupled = {(min(coordinate[a], coordinate[i]), max(coordinate[a], coordinate[i]))
               for i in range(len(robot.links)) for a in robot.ancestors(i) if coordinate[a] != coordinate[i]}
    parents = [-1] * robot.dof
    for a, b in coupled:
        parents[b] = max(parents[b], a)

    def on_path(a: int, b: int) -> bool:
        while b >= 0 and b != a:
            b = parents[b]
        return b == a
    return tuple(parents) if all(on_path(a, b) for a, b in coupled) else None


def _factor_parents(robot: Robot) -> tuple | None:
    """The parent array the L^T D L of a tree's M follows: the joints', after a floating base's
    6 coordinates taken as a chain (their block is dense); with mimic joints, the coordinates'
    (:func:`coordinate_parents`); None for a serial chain and where M's sparsity follows no tree
    (then M is factorized as a dense matrix, LDL^T)."""
    parents = coordinate_parents(robot)
    if parents is None:
        return None
    if robot.floating:
        parents = (-1, 0, 1, 2, 3, 4) + tuple(5 if p < 0 else p + 6 for p in parents)
    return parents


def _mass_factorization(d: _Derivation):
    """The factorization of ``M = D + diag(armature)`` the inverse and the forward-dynamics
    derivatives share with forward dynamics (the same statements: LDL^T for a chain, L^T D L
    following the parent array for a tree), checked once for a singular M."""
    if d.mass_factorization is None:
        robot, b = d.robot, d.b
        M = d.get("mass_matrix") + armature_matrix(robot)
        if "forward_dynamics" not in d.need and not robot.floating:  # (as forward dynamics checks it)
            check_not_singular(robot, b.build(), M)
        on_zero = _zero_pivot(robot, M, "the inverse mass matrix", "mass_matrix_inverse and the forward-dynamics "
                                                                  "derivatives")
        if d.factor_parents is not None:
            d.mass_factorization = ldlt.factor_tree(b, M, d.factor_parents, "ltl", on_zero)
        else:
            d.mass_factorization = ldlt.factor(b, M, "ldl", on_zero)
    return d.mass_factorization


def _solve_mass(d: _Derivation, rhs, forward_hint: str, back_hint: str) -> list:
    """``x`` with ``M x = rhs`` by the shared factorization (:func:`_mass_factorization`)."""
    f = _mass_factorization(d)
    solve = ldlt.solve_tree if d.factor_parents is not None else ldlt.solve
    return solve(d.b, f, rhs, forward_hint, back_hint)


def _mass_inverse(d: _Derivation) -> sp.Matrix:
    """M^-1 (n x n) from the shared factorization: a tree's (and a floating base's) as L^-1
    diag(1/d) L^-T (:func:`symdyn.derive.ldlt.inverse_tree`), a chain's by solves of M x = e_j,
    its lower triangle only (mirrored)."""
    if d.mass_inverse is None:
        n, b, f = d.n, d.b, _mass_factorization(d)
        if d.factor_parents is not None:
            d.mass_inverse = ldlt.inverse_tree(b, f, "Minv")
        else:
            Minv = sp.zeros(n, n)
            for j in range(n):
                column = _solve_mass(d, [sp.S.One if i == j else sp.S.Zero for i in range(n)], f"mi{j + 1}_y",
                                     f"Minv{{i}}_{j + 1}")
                for i in range(j, n):
                    Minv[i, j] = Minv[j, i] = column[i]
            d.mass_inverse = Minv
    return d.mass_inverse


def _inverse_outputs(d: _Derivation) -> sp.Matrix:
    """M^-1 and, when asked for, dqdd/dq = -M^-1 dtau/dq and dqdd/dqd = -M^-1 dtau/dqd, the
    derivatives of inverse dynamics taken at the accelerations forward dynamics gives (held
    constant while differentiating: the implicit function theorem on tau = ID(q, qd, qdd)).
    M^-1 of a tree (and a floating base) as L^-1 diag(1/d) L^-T from the shared factorization
    (:func:`symdyn.derive.ldlt.inverse_tree`), of a chain by solves of M x = e_j, the lower
    triangle only (its entries of rows above j are not needed, and are never emitted); a floating base's M^-1 too
    (nv x nv), and its derivatives in its tangent space (:func:`_forces_by_q`)."""
    n, b = d.n, d.b
    d.report("mass_matrix_inverse (solves with the factorization of M)")
    f = _mass_factorization(d)
    Minv = _mass_inverse(d)
    d.values["mass_matrix_inverse"] = Minv
    d.checks.append((INVERSE_OUTPUTS, tuple((p, m, 1) for p, m in f.pivots)))
    if not set(FORWARD_DERIVATIVES) & d.need:
        return Minv
    d.report("forward_dynamics derivatives (-M^-1 dtau/dq and -M^-1 dtau/dqd at qdd = forward dynamics)")
    rhs = sp.Matrix(d.tau) - d.get("fd_bias") - d.static_friction
    rhs = [b.define(f"rhs{i + 1}", e) for i, e in enumerate(rhs)]
    qdd = [b.define(f"fdd{i + 1}", e, force=True) for i, e in enumerate(_solve_mass(d, rhs, "ldl_y", "qdd{i}_fd"))]
    dq, dqd = _tau_derivatives(d, qdd, "fa", "a", frozenset(qdd))
    b = d.b
    d.inverse_products = tuple(sp.ImmutableMatrix(m) for m in (Minv, dq, dqd, qdd))
    d.values["forward_dynamics_dq"] = sp.Matrix(n, n, lambda i, j: b.define(
        f"dAq{i + 1}_{j + 1}", -sp.Add(*[Minv[i, k] * dq[k, j] for k in range(n)])))
    d.values["forward_dynamics_dqd"] = sp.Matrix(n, n, lambda i, j: b.define(
        f"dAv{i + 1}_{j + 1}", -sp.Add(*[Minv[i, k] * dqd[k, j] for k in range(n)])))
    return Minv


def _configuration(d: _Derivation) -> sp.Matrix:
    """Every configuration-space output needed (integrate, difference, their Jacobians), derived
    together (:mod:`symdyn.derive.configuration`)."""
    wanted = [name for name in CONFIGURATION_OUTPUTS if name in d.need]
    d.report("the configuration space (integrate, difference)")
    v, q1 = configuration_symbols(d.robot.nq, d.robot.nv)
    d.values.update(configuration_outputs(d.b, d.robot.floating, d.chain.coordinates[0], v, q1, wanted))
    return d.values[wanted[0]]


def _frames(d: _Derivation) -> sp.Matrix:
    """Every frame output needed, derived together (they share the link poses)."""
    wanted = [name for name in FRAME_OUTPUTS if name in d.need]
    d.report("frame kinematics")
    d.values.update(_per_coordinate(d, frame_kinematics(d.chain, wanted)))
    return d.values[wanted[0]]


def _forward_dynamics(d: _Derivation) -> sp.Matrix:
    robot, chain, b = d.robot, d.chain, d.b
    M = d.get("mass_matrix") + armature_matrix(robot)
    d.report("forward_dynamics (LDL^T solve)")
    if not robot.floating:  # (a floating base's block is regular whenever the robot has a mass)
        check_not_singular(robot, b.build(), M)
    if d.fd_method == "aba":
        d.report("forward_dynamics (articulated-body algorithm)")
        qdd, d.pivots = articulated_body_fd(chain, chain.tau, d.static_friction)
        loops = articulated_loops(chain, d.static_friction, qdd)
        d.fd_loops = loops.astuple() if loops is not None else ()
        return qdd
    rhs = sp.Matrix(d.tau) - d.get("fd_bias") - d.static_friction
    rhs = sp.Matrix([b.define(f"rhs{i + 1}", e) for i, e in enumerate(rhs)])
    if d.factor_parents is not None:
        d.report("forward_dynamics (L^T D L of the tree's mass matrix: no fill-in)")
        factorization = ldlt.factor_tree(b, M, d.factor_parents, "ltl", _zero_pivot(robot, M))
        d.pivots = factorization.pivots
        return sp.Matrix(ldlt.solve_tree(b, factorization, rhs, "ltl_y", "qdd{i}_fd"))
    qdd, d.pivots = _ldlt_solve(b, M, rhs, robot)
    if d.n >= LOOPED_SOLVE_FROM_DOF:
        d.fd_system = (sp.ImmutableMatrix(M), sp.ImmutableMatrix(rhs), d.mass_factors)
    return qdd


def _task(d: _Derivation) -> sp.Matrix:
    """Every task-space output, derived together (:mod:`symdyn.derive.task_space`)."""
    robot = d.robot
    M = d.get("mass_matrix") + armature_matrix(robot)
    J, jdot, h, c = d.get("jacobian"), d.get("jacobian_dot_qd"), d.get("coriolis"), d.get("gravity")
    d.report("task space (LDL^T of M, J M^-1 J^T and its LDL^T)")

    ts = task_space(d.b, M, J, jdot, h, c, robot.task_rows, _zero_pivot(robot, M, "task space", "the task-space functions"))
    check_task_regular(robot, d.b.build(), ts.task_pivots)
    d.values.update(ts.outputs())
    d.checks.append((TASK_OUTPUTS, tuple((p, m, 1) for p, m in ts.mass.pivots)
                     + tuple((p, m, 3) for p, m in ts.task_pivots)))
    return d.values[TASK_OUTPUTS[0]]


def _contact(d: _Derivation) -> sp.Matrix:
    """The contact dynamics (:mod:`symdyn.derive.contact`): the constraint rows of each contact's
    frame (a point's linear rows, a sole's six), their drift (a point's classical acceleration;
    a sole's spatial one, the classical minus omega x v: Pinocchio's), by the factorization of M
    forward dynamics uses; status 1 for a singular M, 3 for dependent constraints."""
    robot, b = d.robot, d.b
    J = _contact_rows(d)
    d.report("contact dynamics (factorization of M, QR of the whitened constraints)")
    f = _mass_factorization(d)
    rhs = sp.Matrix(d.tau) - d.get("fd_bias") - d.static_friction
    rhs = [b.define(f"ctr{i + 1}", e) for i, e in enumerate(rhs)]
    solved: dict = {}
    gamma = contact_drift(robot.contacts, J, d.get("frame_jacobian_dot_v"), d.qd, b.define, _corrected_poses(d),
                          solved=solved)
    if set(CONTACT_DERIVATIVES) & d.need:  # their X Jl^-1 X^T now, in this builder (a later one may replace it)
        d.sole_errors = {key: (error, jacobian()) for key, (error, jacobian) in solved.items()}
    result = contact_dynamics(b, f, d.factor_parents is not None, J, gamma, rhs)
    d.contact_system = (J, gamma, result)
    d.values["contact_accelerations"] = result.accelerations
    d.values["contact_forces"] = result.forces
    d.checks.append((CONTACT_OUTPUTS, tuple((p, m, 1) for p, m in f.pivots) + tuple((p, m, 3) for p, m in result.pivots)))
    return result.accelerations


def _contact_derivatives(d: _Derivation) -> sp.Matrix:
    """The derivatives of the contact dynamics by q, qd and tau (Pinocchio's
    computeConstraintDynamicsDerivatives): the implicit function theorem on the residuals
    ``F1 = ID(q, qd, qdd) - J^T lambda - tau`` and ``F2 = J qdd + gamma`` at the solution (qdd and
    lambda held), ``[M J^T; J 0][dqdd; -dlambda] = -[dF1; dF2]``, solved with the blocks of the
    system's inverse (:func:`symdyn.derive.contact.constrained_inverse`):
    ``dqdd = -K dF1 - S dF2``, ``dlambda = S^T dF1 - A^-1 dF2``, ``dqdd/dtau = K``,
    ``dlambda/dtau = -S^T``.  A floating base's columns along q (+) dv, the system written in the
    base's axes (lambda_b = R^T lambda, R the base's orientation): its position moves nothing
    (every quantity is relative), turning it by dtheta (its own axes) turns gravity in its frame
    only, ``dF1 = dID/dg_b [g_b]x``, ``dF2 = 0``, and the forces' world-aligned axes with it,
    ``dlambda = R dlambda_b - [lambda]x R dtheta`` per 3 rows (holding lambda in the world
    instead adds ``-J^T [lambda]x R`` to dF1 and gives the same: S^T J^T = 1, K J^T = 0)."""
    robot, b, n = d.robot, d.b, d.n
    d.get("contact_accelerations")
    J, gamma, system = d.contact_system
    m = J.shape[0]
    d.report("contact dynamics derivatives (implicit function theorem at the solution)")
    qdd = [b.define(f"cdd{i + 1}", e, force=True) for i, e in enumerate(system.accelerations)]
    force = [b.define(f"cdf{i + 1}", e, force=True) for i, e in enumerate(system.forces)]
    held = frozenset(qdd + force)
    inverse = constrained_inverse(b, _mass_factorization(d), d.factor_parents is not None, system, _mass_inverse(d))
    dF1_q, dF1_qd = _tau_derivatives(d, qdd, "ca", "c", held, loops=False)
    b = d.b  # (a chain's dtau/dqd may have been built in a builder of its own: _cheapest)
    applied = sp.Matrix([b.define(f"cJf{i + 1}", e) for i, e in enumerate(J.T * sp.Matrix(force))])
    by_q = differentiate(b.build(), applied, list(d.joint_q), b, "cjq", held=held)
    base = n - len(d.joint_q)
    for j, column in enumerate(by_q):
        dF1_q[:, base + j] -= column
    constraint, points = _contact_accelerations_at(d, J, qdd)
    dF2_q = sp.zeros(m, n)
    for j, column in enumerate(differentiate(b.build(), constraint, list(d.joint_q), b, "cgq", held=held)):
        dF2_q[:, base + j] = column
    dF2_qd = sp.Matrix.hstack(*differentiate(b.build(), constraint, list(d.qd), b, "cgv", held=held))
    _sole_columns(d, dF2_q)
    turn = sp.zeros(m, n)  # -[lambda]x R per 3 rows in the base's turn columns
    if robot.floating:
        R_w, p_w = world_placement(d.chain)
        _corrected_base_columns(robot, dF2_q, R_w, p_w, b)
        at = 0
        for contact, point in zip(robot.contacts, points):
            if contact.kind in ("3d", "6d"):
                for first in range(at, at + contact.rows, 3):
                    block = -skew(sp.Matrix(force[first:first + 3])) * R_w
                    turn[first:first + 3, 3:6] = block.applyfunc(lambda e: b.define("cLt", e))
            else:
                dF2_q[at:at + contact.rows, :] = _planar_base_columns(d, contact, force[at:at + contact.rows], point,
                                                                      dF1_q, dF2_q[at:at + contact.rows, :], R_w, p_w)
            at += contact.rows
    K, S, Ainv = inverse.K, inverse.S, inverse.A_inverse
    d.contact_products = _contact_products(d, inverse, _mass_inverse(d), J, turn, (dF1_q, dF2_q), (dF1_qd, dF2_qd),
                                           qdd + force)

    def combination(hint, *terms, extra=None):
        """``extra`` plus the products ``sign * A B`` of ``terms`` (``(sign, A, B)``), each entry
        one named sum (the zeros of A and B skipped)."""
        rows, cols = terms[0][1].shape[0], terms[0][2].shape[1]
        extra = sp.zeros(rows, cols) if extra is None else extra
        return sp.Matrix(rows, cols, lambda i, j: b.define(f"{hint}{i + 1}_{j + 1}", extra[i, j] + sp.Add(*[
            sign * A[i, k] * B[k, j] for sign, A, B in terms for k in range(A.shape[1]) if A[i, k] != 0 and B[k, j] != 0])))
    d.values["contact_accelerations_dq"] = combination("cAq", (-1, K, dF1_q), (-1, S, dF2_q))
    d.values["contact_accelerations_dqd"] = combination("cAv", (-1, K, dF1_qd), (-1, S, dF2_qd))
    d.values["contact_accelerations_dtau"] = K
    d.values["contact_forces_dq"] = combination("cLq", (1, S.T, dF1_q), (-1, Ainv, dF2_q), extra=turn)
    d.values["contact_forces_dqd"] = combination("cLv", (1, S.T, dF1_qd), (-1, Ainv, dF2_qd))
    d.values["contact_forces_dtau"] = -S.T
    f = _mass_factorization(d)
    d.checks.append((CONTACT_DERIVATIVES, tuple((p, mm, 1) for p, mm in f.pivots) + tuple((p, mm, 3) for p, mm in system.pivots)))
    return d.values["contact_accelerations_dq"]


#: the contact derivatives :attr:`Equations.contact_products` gives as products
CONTACT_PRODUCT_OUTPUTS = ("contact_accelerations_dq", "contact_accelerations_dqd", "contact_forces_dq",
                           "contact_forces_dqd")


def _contact_products(d: _Derivation, inverse, Minv: sp.Matrix, J: sp.Matrix, turn: sp.Matrix, by_q, by_qd,
                      solution) -> tuple:
    """:attr:`Equations.contact_products`: M^-1, ``U = [Z; R^-1]``, ``V = [-Z; R^-1]`` (``W =
    diag(M^-1, 0) + U V^T``) and the stacked residual derivatives, a floating base's turn of the
    forces (``turn``, m x n: ``-[lambda]x R`` in the base's turn columns) folded into dF1/dq as
    ``J^T turn`` (S^T J^T = 1 gives dlambda its ``turn``, K J^T = 0 leaves dqdd alone), so that
    one product ``-W dF`` gives every entry."""
    n, m = d.n, J.shape[0]
    Z, Rinv = inverse.Z, inverse.R_inverse
    U, V = sp.Matrix.vstack(Z, Rinv), sp.Matrix.vstack(-Z, Rinv)
    dF1_q = sp.Matrix(by_q[0])
    if any(e != 0 for e in turn):
        folded = (J.T * turn).applyfunc(lambda e: d.b.define("cLj", e) if e != 0 else e)
        dF1_q = (dF1_q + folded).applyfunc(lambda e: d.b.define("cLk", e) if e.is_Add else e)
    dF_q = sp.Matrix.vstack(dF1_q, by_q[1])
    dF_qd = sp.Matrix.vstack(*by_qd)
    assert U.shape == V.shape == (n + m, m) and Minv.shape == (n, n) and dF_q.shape == dF_qd.shape == (n + m, n)
    return tuple(sp.ImmutableMatrix(x) for x in (Minv, U, V, dF_q, dF_qd, sp.Matrix(solution)))


def _sole_columns(d: _Derivation, dF2_q: sp.Matrix) -> None:
    """The derivative of a corrected sole's placement term ``-kp X log6(M^-1 M_ref)`` (left out
    of the residual :func:`_contact_accelerations_at` differentiates) added to its rows of dF2/dq
    in place, in closed form (:func:`symdyn.derive.contact.sole_error`): along its frame's
    world-aligned motion delta (the columns of its Jacobian J6), ``kp [[e_lin]x; [e_ang]x]
    delta_ang + kp X Jl^-1 X^T delta`` (e = X xi).  A floating base's columns (the system in the
    base's axes) keep the second term only: turning the base turns the residual's other terms,
    kp X xi at the solution, by ``-kp [[e_lin]x; [e_ang]x] R dtheta``, which cancels the first."""
    robot, b = d.robot, d.b
    at = 0
    for k, contact in enumerate(robot.contacts):
        if contact.kind == "6d" and contact.kp != 0:
            error, jacobian = d.sole_errors[f"ctb{k + 1}"]  # (the contact dynamics' drift made it)
            J6 = d.get("frame_jacobians")[6 * contact.frame:6 * contact.frame + 6, :]
            along = contact.kp * jacobian * J6
            turning = contact.kp * sp.Matrix.vstack(skew(sp.Matrix(error[:3])), skew(sp.Matrix(error[3:]))) * J6[3:6, :]
            base = 6 if robot.floating else 0
            for i in range(6):
                for j in range(dF2_q.shape[1]):
                    extra = along[i, j] + (turning[i, j] if j >= base else 0)
                    if extra != 0:
                        dF2_q[at + i, j] = b.define("cgS", dF2_q[at + i, j] + extra)
        at += contact.rows


def _planar_base_columns(d: _Derivation, contact, force, point, dF1_q: sp.Matrix, rows: sp.Matrix, R_w, p_w) -> sp.Matrix:
    """A planar contact's rows of dF2/dq with a floating base's columns filled in (``rows``: its
    rows so far; dF1_q gains its term in place).  The directions it holds are the world's, which
    do not turn with the base, so its force is held in the world (no turn term): turning the base
    by dtheta turns J^T lambda = J3^T f (f its force as a world vector, J3 its frame's linear rows)
    by ``J3^T [f]x R dtheta`` (dF1 loses it), and its point's acceleration a (all three axes: it
    moves out of the plane freely), velocity v and offset from the base by ``-[.]x R dtheta``: its
    rows gain ``-P [a + kd v]x R - kp P [p - p_b]x R`` (P: its axes), and ``kp P R`` along the
    base's displacement."""
    b = d.b
    f = sp.zeros(3, 1)
    for a, value in zip(contact.axes, force):
        f[a] = value
    J3 = d.get("frame_jacobians")[6 * contact.frame:6 * contact.frame + 3, :]
    moment = (-J3.T * skew(f) * R_w).applyfunc(lambda e: b.define("cPf", e) if e != 0 else e)
    dF1_q[:, 3:6] = dF1_q[:, 3:6] + moment
    moving = sp.Matrix(point)
    if contact.kd != 0:
        moving += contact.kd * (J3 * sp.Matrix(d.qd))
    turned = -skew(moving) * R_w
    if contact.kp != 0:
        origin = d.get("frame_poses")[4 * contact.frame:4 * contact.frame + 3, 3]
        turned -= contact.kp * skew(origin - p_w) * R_w
        rows[:, 0:3] = sp.Matrix([list(contact.kp * R_w[a, :]) for a in contact.axes])
    rows[:, 3:6] = sp.Matrix([list(turned[a, :]) for a in contact.axes])
    rows[:, 0:6] = rows[:, 0:6].applyfunc(lambda e: b.define("cPg", e) if e != 0 else e)
    return rows


def _corrected_base_columns(robot, dF2_q: sp.Matrix, R_w: sp.Matrix, p_w: sp.Matrix, b) -> None:
    """A floating base's columns of dF2/dq for the contacts with a Baumgarte correction, in
    place: moving the base moves every point by R dv_lin (the position error's kp R), turning
    it by dtheta (its own axes) turns the system about the base's origin; at the solution the
    contact's acceleration terms are -kp (p - reference), so the row's change is
    ``kp [p_b - reference]x R dtheta`` (the velocity terms turn with the rest: no column)."""
    at = 0
    for contact in robot.contacts:
        if contact.kind == "3d" and contact.kp != 0:  # (a planar contact's: _planar_base_columns)
            arm = p_w - sp.Matrix(contact.reference)
            dF2_q[at:at + 3, 0:3] = (contact.kp * R_w).applyfunc(lambda e: b.define("cgb", e))
            dF2_q[at:at + 3, 3:6] = (contact.kp * skew(arm) * R_w).applyfunc(lambda e: b.define("cgb", e))
        at += contact.rows


def _contact_inverse(d: _Derivation) -> sp.Matrix:
    """Contact inverse dynamics: ``tau = ID(q, qd, qdd) - J^T lambda`` with a floating base's six
    coordinates (the unactuated ones) given no force, lambda the least-norm solution of
    ``J_u^T lambda = ID_u`` (J_u the contact rows' base columns, m x 6; ID_u inverse dynamics'
    base rows): with the modified Gram-Schmidt QR ``J_u = Q R`` (Q m x 6, R 6 x 6),
    ``lambda = Q R^-T ID_u`` (status 3 when a pivot R_kk^2 is not above the tolerance times the
    column's squared norm: the contacts cannot push the base in every direction).  The base's
    rows of tau are exact zeros.  A fixed base has none: lambda = 0 and tau is inverse dynamics
    (passive joints are not held by the contacts here: their entries of tau are the forces they
    would need)."""
    robot, b = d.robot, d.b
    J = _contact_rows(d)
    m = J.shape[0]
    unactuated = list(range(6 if robot.floating else 0))
    u = len(unactuated)
    d.report("contact inverse dynamics (least-norm contact forces by a QR of the base's columns)")
    tau = d.get("inverse_dynamics")
    qr = gram_schmidt(b, [[J[i, c] for i in range(m)] for c in unactuated], "ci")
    Q, R, inverse = qr.Q, qr.R, qr.inverse
    t: list[sp.Expr] = []
    for k, c in enumerate(unactuated):  # R^T t = ID_u
        t.append(b.define(f"cit{k + 1}", (tau[c] - sp.Add(*[R[l, k] * t[l] for l in range(k)])) * inverse[k]))
    forces = [b.define(f"cilambda{i + 1}", sp.Add(*[Q[k][i] * t[k] for k in range(u) if Q[k][i] != 0]))
              for i in range(m)]
    applied = J.T * sp.Matrix(forces)
    d.values["contact_inverse_forces"] = sp.Matrix(forces)
    d.values["contact_inverse_torques"] = sp.Matrix([sp.S.Zero if i in unactuated else
                                                     b.define(f"citau{i + 1}", tau[i] - applied[i]) for i in range(d.n)])
    d.checks.append((CONTACT_INVERSE, tuple((p, mm, 3) for p, mm in qr.pivots)))
    return d.values["contact_inverse_torques"]


def _contact_accelerations_at(d: _Derivation, J: sp.Matrix, qdd) -> tuple[sp.Matrix, list]:
    """``(J qdd + gamma, points)`` (NC x 1, world-aligned axes; ``J`` the contact rows) at accelerations
    ``qdd``, and each contact frame origin's classical acceleration (3 x 1, world axes: all three
    entries, a planar contact's third too): each contact's acceleration on its axes (a point's
    classical, a sole's spatial: the classical minus omega x v; a Baumgarte correction added) from the
    Newton-Euler forward recursion at zero gravity, formed in its link's frame and turned to the
    world through named rotations (what the derivatives differentiate: far fewer operations than
    the world-frame J qdd + gamma, whose entries expand into the rotations' products)."""
    robot, b = d.robot, d.b
    poses = _corrected_poses(d)
    motion: list = []
    states = recursion(d.chain, d.chain.expand(d.qd), d.chain.expand(qdd), sp.zeros(3, 1), "cF", joint_frames=False,
                       base_motion=motion)  # (per link: mimic joints follow their leaders)
    _, links = tree_poses(d.chain)
    R_w, _ = world_placement(d.chain)
    rows: list = []
    points: list = []
    for k, contact in enumerate(robot.contacts):
        at = len(rows)
        frame = robot.frames[contact.frame]
        r = frame.matrix()[:3, 3]
        if frame.link >= 0:
            st = states[frame.link]
            omega, omegad, vd = st.omega, st.omegad, st.vd
            R = links[frame.link][:3, :3]
        else:
            (omega, omegad, vd), R = motion, sp.eye(3)
        linear = named_vector(b, f"cFl{k + 1}", vd + omegad.cross(r) + omega.cross(omega.cross(r)))
        rotation = b.matrix(f"cFR{k + 1}", (R_w * R).applyfunc(sp.expand))
        classical = named_vector(b, f"cF2_{k + 1}", rotation * linear)
        points.append(classical)
        if contact.kind != "6d":
            pose = poses[4 * contact.frame:4 * contact.frame + 4, :] if contact.corrected else None
            held = correction(contact, J[at:at + contact.rows, :], pose, d.qd)
            rows += [classical[a] + c for a, c in zip(contact.axes, held)]
            continue
        spin = named_vector(b, f"cFw{k + 1}", rotation * omega)  # the sole's, world axes
        velocity = named_vector(b, f"cFv{k + 1}", J[at:at + 3, :] * sp.Matrix(d.qd))
        damping = contact.kd  # (0 without a correction; its log term: _sole_columns, in closed form)
        rows += list(named_vector(b, f"cF2s{k + 1}", classical - spin.cross(velocity) + damping * velocity))
        rows += list(named_vector(b, f"cF2w{k + 1}", rotation * omegad + damping * spin))
    return sp.Matrix(rows), points


def _corrected_poses(d: _Derivation):
    """Every frame's pose (4 rows per frame, world) when a contact has a Baumgarte correction
    (its position error needs them), else None."""
    return d.get("frame_poses") if any(c.corrected for c in d.robot.contacts) else None


def _contact_rows(d: _Derivation) -> sp.Matrix:
    """The contacts' constraint rows (NC x N): each contact's frame's Jacobian, a point's three
    linear rows, a sole's six (world-aligned axes at the frame's origin)."""
    if not d.robot.contacts:
        raise SymdynError(f"{d.robot.source or d.robot.name}: the contact functions need contacts: list them under "
                          "'contacts:' in the robot file or scene (FRAME:3d for a point held, FRAME:6d for a sole), "
                          "or give --contacts")
    J = contact_rows(d.robot.contacts, d.get("frame_jacobians"))
    _check_rows_move(d.robot, J)
    return J


def _check_rows_move(robot, J: sp.Matrix) -> None:
    """Warn about a contact row that is zero at every configuration (no joint moves the frame
    along that axis: a planar robot's point held in 3D): the contacts are dependent everywhere
    (status 3 at every state, and the C of some robots divides by zero); say which row, and the
    kind that leaves it out."""
    names = ("x", "y", "z", "rotation about x", "rotation about y", "rotation about z")
    row = 0
    for contact in robot.contacts:
        zero = [a for k, a in enumerate(contact.axes) if all(e == 0 for e in J[row + k, :])]
        if zero:
            frame = robot.frames[contact.frame].name
            kept = "".join("xyz"[a] for a in contact.axes if a not in zero and a < 3)
            hint = (f": hold it with {frame}:{kept}" if contact.kind == "3d" and len(kept) == 2 else "")
            warn(f"{robot.source or robot.name}: contact {frame}:{contact.kind}: its "
                 f"{' and '.join(names[a] for a in zero)} row{'s are' if len(zero) > 1 else ' is'} zero at every "
                 f"configuration (no joint moves the frame that way: the contacts are dependent everywhere, status 3)"
                 f"{hint}")
        row += len(contact.axes)


def _impulse(d: _Derivation) -> sp.Matrix:
    """The impulse dynamics (Pinocchio's impulseDynamics): [M J^T; J 0][qd+; -impulse] = [M qd;
    -e J qd], M qd from the recursion at zero velocity and gravity (plus the armature), solved as
    the contact dynamics are (:mod:`symdyn.derive.contact`); status 1 and 3 as theirs."""
    robot, b = d.robot, d.b
    J = _contact_rows(d)
    d.report("impulse dynamics (factorization of M, QR of the whitened constraints)")
    f = _mass_factorization(d)
    v = sp.Matrix(d.qd)
    momentum = d.forces(d.zero, list(d.qd), sp.zeros(3, 1), "iv") + armature_matrix(robot) * v
    rhs = [b.define(f"imr{i + 1}", e) for i, e in enumerate(momentum)]
    gamma = [b.define(f"img{i + 1}", RESTITUTION[0] * e) for i, e in enumerate(J * v)]
    result = contact_dynamics(b, f, d.factor_parents is not None, J, gamma, rhs, "im")
    d.values["impulse_velocities"] = result.accelerations
    d.values["impulse_forces"] = result.forces
    d.checks.append((IMPULSE_OUTPUTS, tuple((p, m, 1) for p, m in f.pivots) + tuple((p, m, 3) for p, m in result.pivots)))
    return result.accelerations


def _external(d: _Derivation) -> sp.Matrix:
    """Inverse and forward dynamics with external forces f at the contacts (Pinocchio's rnea and
    aba with fext): tau = ID - J^T f, and M qdd = tau + J^T f - h - c - friction by the
    factorization forward dynamics uses (status 1 for a singular M)."""
    robot, b = d.robot, d.b
    J = _contact_rows(d)
    force = sp.Matrix(contact_force_symbols(robot.contact_rows))
    applied = [b.define(f"extF{i + 1}", e) for i, e in enumerate(J.T * force)]  # J^T f, once for both
    d.report("dynamics with external forces at the contacts")
    if "inverse_dynamics_ext" in d.need:
        d.values["inverse_dynamics_ext"] = sp.Matrix(d.get("inverse_dynamics")) - sp.Matrix(applied)
    if "forward_dynamics_ext" in d.need:
        rhs = sp.Matrix(d.tau) + sp.Matrix(applied) - d.get("fd_bias") - d.static_friction
        f = _mass_factorization(d)
        d.values["forward_dynamics_ext"] = sp.Matrix(_solve_mass(d, [b.define(f"extr{i + 1}", e) for i, e in enumerate(rhs)],
                                                                 "ext_y", "qdd{i}_ext"))
        d.checks.append((("forward_dynamics_ext",), tuple((p, m, 1) for p, m in f.pivots)))
    return d.values.get("inverse_dynamics_ext", d.values.get("forward_dynamics_ext"))


def check_task_regular(robot: Robot, program: Program, pivots, states: int = 3, seed: int = 0) -> None:
    """Refuse a task the tool cannot move in at any configuration: the pivots ``(e_k, A_kk)`` of
    the LDL^T of ``A = J_s M^-1 J_s^T`` evaluated at ``states`` random configurations (random
    positive parameter values); when the same pivot is below 1e-9 of its diagonal entry at
    every one of them, the task rows are linearly dependent for every q (a planar arm asked for
    its whole pose, a leg whose tool spins freely about an axis) and every call would return
    status 3: a :class:`SymdynError` names the file, the field and the rank found."""
    q = joint_symbols(robot.dof)[0]
    ratios = sp.Matrix([[e / a for e, a in pivots]])
    evaluate = compile_function([q, robot.parameters], program, ratios, "task_check")
    rng = np.random.default_rng(seed)
    small = set(range(len(pivots)))
    for _ in range(states):
        values, pose = rng.uniform(0.5, 1.5, len(robot.parameters)), rng.uniform(-np.pi, np.pi, robot.dof)
        try:
            found = np.asarray(evaluate(pose, values), dtype=float).ravel()
        except (ZeroDivisionError, OverflowError, ValueError, TypeError):
            small &= set(range(len(pivots)))  # a zero diagonal entry: that row cannot move at all
            continue
        small &= {k for k, ratio in enumerate(found) if not ratio > 1e-9}
    if not small:
        return
    rows = robot.task_rows
    what = "field 'task'" if robot.task is not None else "the task-space functions' default task (the tool's pose)"
    raise TaskUnreachable(
        f"{robot.source or robot.name}: {what}: the tool cannot move independently in the {len(rows)} task "
        f"directions ({', '.join(JACOBIAN_ROWS[r] for r in rows)}) at any configuration (J's task rows have rank at most "
        f"{len(rows) - len(small)} at every sampled q), so the task-space mass matrix does not exist; choose fewer "
        "rows ('task: position', or a list of Jacobian rows such as [0, 1], in the robot file or scene)")


def _reaction_map(d: _Derivation) -> sp.Matrix:
    d.report("reaction_map (articulated-body recursion at tau = 0, eqs. 5-14 of the force-to-torque note)")
    return reaction_map(d.chain, d.static_friction).matrix


def _regressor(d: _Derivation) -> sp.Matrix:
    d.report("regressor (spatial Newton-Euler, linear in the standard parameters)")
    return regressor_matrix(d.chain)


def _base_regressor(d: _Derivation) -> sp.Matrix:
    robot, chain = d.robot, d.chain
    Y = d.get("regressor")
    geometric = set()
    for link in robot.links:
        placement = [link.a, link.alpha, link.d, link.theta, *(link.fixed or ()), *(link.axis or ()),
                     *(link.origin.expressions() if link.origin else ())]
        geometric |= set().union(*(sp.sympify(e).free_symbols for e in placement))
    geometric |= set().union(*(sp.sympify(e).free_symbols for e in robot.base_matrix()))
    if geometric:
        names = ", ".join(sorted(s.name for s in geometric))
        raise SymdynError(f"{robot.source or robot.name}: base parameters need a numeric geometry, but "
                          f"{names} (in the link placements) {'is' if len(geometric) == 1 else 'are'} "
                          "symbolic: their regrouping coefficients depend on it (give values, or use "
                          "the full regressor)")
    d.report("base parameters (QR of the regressor stacked at random states)")
    evaluate = compile_function([chain.q, chain.qd, chain.qdd, robot.parameters], d.b.build(), Y, "regressor_rank")
    values = np.random.default_rng(3).uniform(0.5, 1.5, len(robot.parameters))
    numbers = dict(zip(robot.parameters, values))
    standard = [float(sp.sympify(v).xreplace(numbers)) for v in standard_parameters(robot)]
    found = find_base_parameters(robot, lambda *state: evaluate(*state, values), standard=standard)
    d.base = tuple(zip(found.names, found.expressions))
    if d.parameters == "base" and "inverse_dynamics" in d.need:
        d.report("inverse_dynamics from the base parameters")
        pi = base_equivalent(robot, found)
        qd, qdd = chain.qd, chain.qdd
        rigid = joint_forces(chain, qd, qdd, chain.gravity, "B", parameters=pi)
        k = PARAMETERS_PER_LINK
        d.values["inverse_dynamics"] = sp.Matrix([
            rigid[j] + pi[k * j + 10] * qdd[j] + pi[k * j + 11] * qd[j] + pi[k * j + 12] * sp.sign(qd[j])
            for j in range(d.n)])
    return Y[:, list(found.independent)]


#: how each output (and the internal quantity ``fd_bias``) is derived, in the order a derivation
#: visits them: each function takes the :class:`_Derivation` and returns the matrix, asking
#: ``d.get`` for what it builds on.  Lagrange-Euler visits D, C, h, c first (its inverse
#: dynamics is assembled from them).  A test checks every registered output has an entry.
DERIVATIONS: dict[str, Callable[[_Derivation], sp.Matrix]] = {
    "gravity": _gravity, "coriolis": _coriolis, "coriolis_matrix": _coriolis_matrix, "mass_matrix": _mass_matrix,
    "inverse_dynamics": _inverse_dynamics, "fd_bias": _bias, "tool": _tool,
    "forward_dynamics": _forward_dynamics, "reaction_map": _reaction_map, "regressor": _regressor,
    "base_regressor": _base_regressor, "task": _task, "inverse_dynamics_derivatives": _inverse_dynamics_derivatives,
    "gravity_derivative": _gravity_derivative, "inverse": _inverse_outputs, "frames": _frames,
    "configuration": _configuration, "contact": _contact, "contact_derivatives": _contact_derivatives, "contact_inverse": _contact_inverse, "external": _external, "impulse": _impulse,
    "centroidal": _centroidal, "kinetic_energy": _kinetic_energy,
}
_LAGRANGE_ORDER = ("mass_matrix", "coriolis_matrix", "coriolis", "gravity")
#: the outputs visited before the others (then registry order): the intermediate symbols are
#: numbered in the order they are built, and the generated code keeps the names it always had
_VISITED_FIRST = ("gravity", "coriolis", "coriolis_matrix", "mass_matrix", "inverse_dynamics", "fd_bias") + KINEMATIC_OUTPUTS


def derive(robot: Robot, method: str = "newton-euler", outputs: Iterable[str] | None = None,
           progress: Callable[[str], None] | None = None, fd_method: str = "ldlt",
           parameters: str = "standard") -> Equations:
    """Derive the equations of motion of ``robot``.

    Parameters
    ----------
    robot : the robot description (see :func:`symdyn.load`).
    method : ``'newton-euler'`` (recursive, Table 3.2; D by composite rigid bodies), ``'lagrange-euler'``
        (trace form) or ``'jacobian-newton-euler'``.
    outputs : names from :data:`ALL_OUTPUTS` to derive (default: :func:`default_outputs`, all of
        :data:`OUTPUTS` and the reaction map when the robot has passive joints).
    progress : called with a short text as each part starts (for long derivations).
    fd_method : ``'ldlt'`` (solve with D, the default) or ``'aba'`` (articulated-body algorithm)
        for forward dynamics.
    parameters : ``'standard'`` (default) or ``'base'``: inverse dynamics by the Newton-Euler
        recursion in first moments (Khalil's form) with the base-equivalent parameters (the
        regrouped ones zero and folded away: fewer operations;
        :func:`symdyn.derive.regressor.base_equivalent`).

    Returns
    -------
    Equations, immutable.
    """
    robot = serial_robot(robot)
    method = normalize_method(method)
    if parameters not in PARAMETER_FORMS:
        raise ValueError(f"parameters must be one of {', '.join(PARAMETER_FORMS)}, not {parameters!r}")
    if fd_method not in FD_METHODS:
        raise ValueError(f"unknown forward-dynamics method {fd_method!r}; use {' or '.join(FD_METHODS)}")
    wanted = default_outputs(robot) if outputs is None else tuple(outputs)
    for name in wanted:
        spec(name)  # a ValueError for an unknown name
    if robot.is_tree:
        check_tree_request(robot, method, wanted, fd_method, parameters)
    start = time.perf_counter()

    def report(part: str) -> None:
        if progress is not None:
            progress(f"{robot.name}: {method}: {part} ({time.perf_counter() - start:.1f} s)")
    need = set(with_requirements(wanted))
    if "forward_dynamics" in need and fd_method == "ldlt":
        need.add("fd_bias")
    if parameters == "base" and "inverse_dynamics" in need:
        need.add("base_regressor")
    d = _Derivation(robot, method, need, fd_method, parameters, report)
    order = (_LAGRANGE_ORDER if method == "lagrange-euler" else ()) + _VISITED_FIRST + ALL_OUTPUTS
    for name in dict.fromkeys(order):
        if name in need:
            d.get(name)
    chain = d.chain
    outputs_tuple = tuple((name, sp.ImmutableMatrix(d.values[name])) for name in ALL_OUTPUTS if name in wanted)
    q, qd, qdd, tau = chain.coordinates
    return Equations(robot=robot, method=method, q=q, qd=qd, qdd=qdd, tau=tau,
                     program=d.b.build(), outputs=outputs_tuple,
                     seconds=time.perf_counter() - start,
                     pivots=d.pivots if "forward_dynamics" in wanted else (),
                     fd_method=fd_method if "forward_dynamics" in wanted else "",
                     base_parameters=d.base if ("base_regressor" in wanted or parameters == "base") else (),
                     parameter_form="base" if (parameters == "base" and "inverse_dynamics" in wanted) else "standard",
                     mass_factors=d.mass_factors if "mass_matrix" in wanted else (),
                     coriolis_factors=d.coriolis_factors if "coriolis_matrix" in wanted else (),
                     fd_system=d.fd_system if "forward_dynamics" in wanted else (),
                     fd_loops=d.fd_loops if "forward_dynamics" in wanted else (),
                     joint_trig=chain.joint_trig,
                     inverse_products=d.inverse_products if set(FORWARD_DERIVATIVES) & set(wanted) else (),
                     contact_products=d.contact_products if set(CONTACT_PRODUCT_OUTPUTS) & set(wanted) else (),
                     tangent_loops=tuple((parts, t) for parts, t in d.tangent_loops if set(parts) & set(wanted)),
                     checks=tuple((outputs, checks) for outputs, checks in d.checks
                                  if any(name in wanted for name in outputs)))
