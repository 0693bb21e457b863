"""Textbook derivations: the steps of Lagrange-Euler and Newton-Euler for one robot, as data.

This module derives and simplifies; it prints nothing (see :mod:`symdyn.emit.printout`).  The steps
follow the source notes: the trace form (``^{i-1}A_i``, ``^0A_i``, ``Q_j``, ``U_ij``,
``U_ijk``, pseudo-inertias ``J_i``, then ``D_ik``, ``h_ikm``, ``h_i``, ``c_i``) and the recursive
Newton-Euler equations of Table 3.2 (forward: omega_i, omegadot_i, vdot_i, abar_i; backward:
F_i, N_i, f_i, n_i, tau_i), every vector in the frame of its own link.

Two forms:

- *closed form* (default up to 3 joints): every quantity fully expanded in the joint variables,
  simplified the way a textbook writes it: trigonometric shorthand ``s1 = sin q1``,
  ``c12 = cos(q1 + q2)``, terms collected by joint accelerations and velocity products;
- *named form* (more joints): each quantity written in terms of the previous link's named
  quantities (``omega_2x``, ``vdot_3y``, ...) and ``c_i``/``s_i``, as one computes it by hand, and
  the final D, h, c in terms of numbered intermediate quantities ``x_k``, instead of pages of
  expansion.

Display symbols: ``q1`` (joint variable), ``qdot1``, ``qddot1`` (its rate and acceleration; the
printers show q-dot and q-double-dot), ``s12``/``c1`` (trig shorthand), the robot's own
parameter names.  :meth:`Derivation.to_joint_symbols` maps any printed value back to symdyn's
joint symbols (``q, qd, qdd``) for checking.
"""

from __future__ import annotations

import itertools
import time
from dataclasses import dataclass
from typing import Callable, Iterable

import sympy as sp

from .chain import make_chain
from .articulated_body import accelerations, reaction_map, sweeps
from .equations import armature_matrix, check_tree_request, friction_terms, normalize_method, derive
from .jacobian_newton_euler import JacobianNewtonEuler
from .lagrange_euler import LagrangeEuler, q_operator, pseudo_inertia
from .newton_euler import recursion
from ..model.errors import SymdynError, warn
from ..model.robot import Robot

STEPS = ("all", "summary")

#: methods ``derive_steps`` prints: the equations-of-motion methods, and the articulated-body
#: algorithm (forward dynamics, and the reaction map of a robot with passive joints)
DERIVATION_METHODS = ("newton-euler", "lagrange-euler", "jacobian-newton-euler", "articulated-body")
ABA_ALIASES = {"articulated-body": "articulated-body", "aba": "articulated-body"}
AXES = "xyz"


@dataclass(frozen=True)
class Quantity:
    """One printed quantity: ``kind`` is its notation key (see :data:`KINDS`), ``indices``
    its subscripts (1-based), ``value`` a SymPy expression or immutable matrix in display
    symbols."""

    kind: str
    indices: tuple[int, ...]
    value: sp.Basic


@dataclass(frozen=True)
class Section:
    """A group of quantities instantiating one general formula of the notes (``kind``)."""

    kind: str
    quantities: tuple[Quantity, ...]


#: notation keys and what they are (the printers hold their typography)
KINDS = {
    "link_transform": "^{i-1}A_i, 4x4",
    "base_transform": "^0A_i, 4x4",
    "q_operator": "Q_j, 4x4",
    "u": "U_ij = d(^0A_i)/dq_j, 4x4",
    "u3": "U_ijk = dU_ij/dq_k, 4x4",
    "pseudo_inertia": "J_i, 4x4",
    "d_entry": "D_ik",
    "h_entry": "h_ikm",
    "h_i": "h_i",
    "c_i": "c_i",
    "omega": "omega_i, 3x1 in frame i",
    "omegadot": "omegadot_i, 3x1",
    "vdot": "vdot_i, 3x1 (origin of frame i)",
    "abar": "abar_i, 3x1 (centre of mass of link i)",
    "F": "F_i = m_i abar_i",
    "N": "N_i = I_i omegadot_i + omega_i x (I_i omega_i)",
    "f": "f_i, force on link i from link i-1",
    "n": "n_i, moment on link i from link i-1 about O_i",
    "tau": "tau_i, joint force",
    "jc": "J_ci, 6 x n: centre-of-mass and angular velocity of link i per joint rate (world axes)",
    "projected": "J_ci^T M_i J_ci, n x n: link i's mass matrix projected on the joints",
    "omega_w": "omega_i, 3x1, world axes",
    "omegadot_w": "omegadot_i at qdd = 0 (gamma), world axes",
    "vdot_w": "vdot_i of the centre of mass at qdd = 0 (gamma, with -g at the base), world axes",
    "fJ": "f_Ji, force through joint i",
    "tJ": "t_Ji, torque through joint i about its axis point",
    "X": "^iX_{i-1}, 6x6 motion transform from frame i-1 to joint frame i",
    "I": "I_i, 6x6 spatial inertia of body i about its joint frame's origin",
    "v": "v_i, spatial velocity [omega; v] of body i, joint frame i",
    "cbar": "c_i = v_i x S_i qd_i, velocity-product acceleration",
    "p": "p_i = v_i x* I_i v_i, bias force of body i alone",
    "U": "U_i = I^A_i S_i",
    "d": "d_i = S_i^T U_i (+ armature)",
    "aba_u": "u_i = tau_i - S_i^T p^A_i (- friction)",
    "Ia": "I^a_i = I^A_i - U_i U_i^T / d_i",
    "pa": "p^a_i = p^A_i + I^a_i c_i + U_i u_i / d_i",
    "IA": "I^A_{i-1}, articulated inertia with the children of body i-1 added",
    "pA": "p^A_{i-1}, articulated bias force with the children added",
    "ap": "a'_i = ^iX_{i-1} a_{i-1} + c_i",
    "qdd": "qdd_i = (u_i - U_i^T a'_i) / d_i",
    "a": "a_i = a'_i + S_i qdd_i",
    "b": "b_i = U_i / d_i (eq. 3)",
    "A": "A_i = 1 - b_i S_i^T (eq. 4)",
    "pa0": "p^a_i at tau = 0",
    "k": "k_i = p^A_{i-1} at tau = 0 (eq. 5)",
    "k1": "k_1, acceleration of body 1 at tau = 0 without its bias force (eq. 7)",
    "k0": "k_0 = [f_1]_0 at tau = 0 (eqs. 9-10)",
    "W": "W_{j,i} = A_i X_{i+1}^T ... X_j^T b_j, partial product of eq. (10)",
    "column": "[e_j; d_j] = X_1^T A_1 ... X_j^T b_j, base wrench per unit tau_j (eq. 14)",
    "Dmap": "D = [d_1 ... d_na], 6 x na (eq. 13)",
    "beta": "beta_k, a base parameter: name = combination of the standard parameters",
    "task_J": "J, the task's rows of the tool Jacobian (world axes at the tool origin)",
    "task_det": "det J (square tasks)",
    "Mx": "M_x(q) = (J D^-1 J^T)^-1, task-space mass matrix",
    "Vx": "V_x(q, qdot) = M_x (J D^-1 h - Jdot qdot), task-space Coriolis and centrifugal force",
    "Gx": "G_x(q) = M_x J D^-1 c, task-space gravity force",
    "contact_J": "J, the contacts' rows of their frames' Jacobians (world-aligned axes at each frame's origin)",
    "contact_gamma": "gamma = Jdot qdot, the contacts' acceleration at qdd = 0",
    "contact_det": "det J_c (contacts that pin the robot: as many rows as joints)",
    "contact_qdd": "qdd = -J_c^-1 gamma (the contacts alone set the accelerations)",
    "contact_lambda": "lambda = J_c^-T (D qdd - (tau - h - c)), the contact forces on the robot",
    "D": "D(q), n x n",
    "h": "h(q, qdot), n x 1",
    "c": "c(q), n x 1",
    "where": "named intermediate quantity x_k",
}


@dataclass(frozen=True)
class Derivation:
    """A derivation ready to print (immutable).

    ``sections`` hold the steps; ``results`` the final D, h, c (section ``"results"``);
    ``where`` the named intermediate quantities ``x_k`` used by the named form;
    ``shorthand`` the trig symbols used, with their meaning in joint symbols.
    """

    robot: Robot
    method: str
    steps: str
    closed_form: bool
    sections: tuple[Section, ...]
    where: tuple[tuple[sp.Symbol, sp.Expr], ...]
    named: tuple[tuple[sp.Symbol, sp.Expr], ...]  # named recursion quantities (omega_2x, ...) and their values
    shorthand: tuple[tuple[sp.Symbol, sp.Expr], ...]
    joint_symbols: tuple[tuple[sp.Symbol, sp.Symbol], ...]  # (display, joint symbol)

    def section(self, kind: str) -> Section:
        for s in self.sections:
            if s.kind == kind:
                return s
        raise KeyError(kind)

    def quantity(self, kind: str, *indices: int) -> sp.Basic:
        for s in self.sections:
            for q in s.quantities:
                if q.kind == kind and q.indices == tuple(indices):
                    return q.value
        raise KeyError((kind, indices))

    def program(self):
        """Every display symbol the printed values use (joint rates, trig shorthand, named
        quantities, x_k) as a :class:`~symdyn.derive.program.Program` over the joint symbols, in
        evaluation order: for evaluating printed values numerically."""
        from .program import Program
        definitions = dict(self.joint_symbols) | dict(self.shorthand) | dict(self.named) | dict(self.where)
        order: list = []
        state: dict = {}

        def visit(sym):  # depth-first topological order; the definitions form a DAG
            stack = [(sym, False)]
            while stack:
                node, done = stack.pop()
                if done:
                    if state.get(node) != 2:
                        state[node] = 2
                        order.append(node)
                    continue
                if state.get(node):
                    continue
                state[node] = 1
                stack.append((node, True))
                for dep in sp.sympify(definitions[node]).free_symbols:
                    if dep in definitions and not state.get(dep):
                        stack.append((dep, False))
        for sym in definitions:
            visit(sym)
        return Program(tuple((sym, sp.sympify(definitions[sym])) for sym in order))

    def to_joint_symbols(self, value):
        """``value`` with the named quantities, trig shorthand and display symbols replaced, in
        symdyn's joint symbols ``q``, ``qd``, ``qdd`` and the robot's parameters."""
        full: dict = {}
        for sym, rhs in self.where:
            full[sym] = sp.sympify(rhs).xreplace(full)
        definitions = dict(self.named)

        def resolve(sym):
            if sym not in full:
                rhs = sp.sympify(definitions[sym])
                full[sym] = rhs.xreplace({s: resolve(s) for s in rhs.free_symbols if s in definitions})
            return full[sym]
        for sym in definitions:
            resolve(sym)
        mapping = dict(self.shorthand)
        mapping.update(dict(self.joint_symbols))
        if isinstance(value, sp.MatrixBase):
            return sp.ImmutableMatrix(value.applyfunc(lambda e: e.xreplace(full).xreplace(mapping)))
        return sp.sympify(value).xreplace(full).xreplace(mapping)


class _Notation:
    """Display symbols and the textbook simplification of one robot."""

    def __init__(self, chain):
        self.chain = chain
        self.q = tuple(chain.joint_q)
        self.qdot = tuple(sp.Symbol(f"qdot{k + 1}", real=True) for k in range(chain.n))
        self.qddot = tuple(sp.Symbol(f"qddot{k + 1}", real=True) for k in range(chain.n))
        #: a floating base's display symbols: velocity (v_0, omega_0), its rate (a_0, alpha_0),
        #: both in the base frame, and the quaternion (qx, qy, qz, qw); () on a fixed base
        self.base_rates, self.base_accelerations, self.quaternion = (), (), ()
        self.to_display = {}
        if chain.robot.floating:
            axes = [(name, a) for name in ("v", "omega") for a in AXES]
            self.base_rates = tuple(sp.Symbol(f"{name}_0{a}", real=True) for name, a in axes)
            self.base_accelerations = tuple(sp.Symbol(f"{'a' if name == 'v' else 'alpha'}_0{a}", real=True)
                                            for name, a in axes)
            self.quaternion = tuple(sp.Symbol(f"q{a}", real=True) for a in "xyzw")
            # the joints' coordinates are shown as q_1..q_n, printed as q1..qn are (the
            # configuration's symbols q1..q7 are the base's position and quaternion)
            names = [sp.Symbol(f"q_{k + 1}", real=True) for k in range(chain.n)]
            self.to_display = dict(zip(chain.q[3:7], self.quaternion)) | dict(zip(self.q, names))
        self.to_display |= (dict(zip(chain.qd, self.base_rates + self.qdot))
                            | dict(zip(chain.qdd, self.base_accelerations + self.qddot)))
        self.shorthand: dict[sp.Symbol, sp.Expr] = {}
        self._taken = {s.name for s in chain.robot.parameters}
        # the joints' trig symbols of the derivation: _c_i = cos(theta_i + q_i), _s_i
        self.trig = dict(chain.trig)
        self.trig_of: dict[int, tuple[sp.Symbol, sp.Symbol]] = {}
        self.trig_display: dict[sp.Symbol, sp.Symbol] = {}
        self.sine_to_cosine: dict[sp.Symbol, sp.Symbol] = {}
        for i in range(chain.n):
            c = sp.Symbol(f"{chain.builder.prefix}c{i + 1}", real=True)
            s = sp.Symbol(f"{chain.builder.prefix}s{i + 1}", real=True)
            if c in self.trig:
                self.trig_of[i] = (c, s)
                self.sine_to_cosine[s] = c
                self.trig_display[c] = self.trig_symbol(sp.cos, (i,))
                self.trig_display[s] = self.trig_symbol(sp.sin, (i,))
        # angle-sum shorthand only when every joint angle is q_i itself (theta_i = 0)
        self.plain_angles = all(link.theta == 0 for link in chain.robot.links if link.is_revolute)

    def trig_symbol(self, func, joints: tuple[int, ...]) -> sp.Symbol:
        prefix = "s" if func is sp.sin else "c"
        name = prefix + "".join(str(j + 1) for j in joints)
        while name in self._taken:
            name = prefix.upper() + name[1:] if name[0] == prefix else name + "_"
        sym = sp.Symbol(name, real=True)
        links = self.chain.robot.links
        self.shorthand[sym] = func(sp.Add(*[self.q[j] + links[j].theta for j in joints])).xreplace(self.to_display)
        return sym

    def shorten(self, expr: sp.Expr) -> sp.Expr:
        """sin/cos of a plain sum of joint variables -> s12, c1, ..."""
        index = {q: k for k, q in enumerate(self.q)}

        def is_short(e):
            if not isinstance(e, (sp.sin, sp.cos)):
                return False
            terms = sp.Add.make_args(e.args[0])
            return all(t in index for t in terms)

        def short(e):
            joints = tuple(sorted(index[t] for t in sp.Add.make_args(e.args[0])))
            return self.trig_symbol(type(e), joints)
        return expr.replace(is_short, short)

    def collect(self, expr: sp.Expr) -> sp.Expr:
        rates = list(self.base_rates) + list(self.qdot)
        monomials = list(self.base_accelerations) + list(self.qddot)
        monomials += [a * b for a, b in itertools.combinations_with_replacement(rates, 2)]
        monomials += rates
        collected = sp.collect(sp.expand(expr), monomials, evaluate=False)
        total = sp.S.Zero
        for key, coeff in collected.items():
            total += sp.factor_terms(coeff) * key
        return total

    def to_trig_symbols(self, program, value):
        """``value`` with every intermediate expanded except the joints' ``_c_i``/``_s_i``."""
        full: dict = {}
        for sym, rhs in program.needed_for(list(value) if isinstance(value, sp.MatrixBase) else [value]):
            if sym not in self.trig:
                full[sym] = rhs.xreplace(full)
        if isinstance(value, sp.MatrixBase):
            return sp.Matrix(value).applyfunc(lambda e: sp.sympify(e).xreplace(full))
        return sp.sympify(value).xreplace(full)

    def diff(self, expr, k: int):
        """d expr / dq_k for an expression in the trig symbols (chain rule through c_k, s_k)."""
        result = sp.diff(expr, self.q[k])
        if k in self.trig_of:
            c, s = self.trig_of[k]
            result += sp.diff(expr, c) * (-s) + sp.diff(expr, s) * c
        return result

    def textbook(self, expr: sp.Expr) -> sp.Expr:
        """Closed form of an expression in the joints' trig symbols: simplified, collected,
        with shorthand.

        The polynomial in ``c_i = cos(theta_i + q_i)``, ``s_i`` is expanded and reduced modulo
        ``s_i^2 + c_i^2 = 1`` (each sine at most linear: a canonical form, so equal terms always
        cancel); small results without numeric offsets are then rewritten with angle-sum
        shorthand (c12 = cos(q1 + q2)) by SymPy's trigsimp."""
        e = sp.sympify(expr).xreplace(self.to_display)
        if e.is_number:
            return e
        # sin/cos of constant angles (alpha = 0.4) become numbers
        e = e.replace(lambda x: isinstance(x, (sp.sin, sp.cos)) and x.args[0].is_number,
                      lambda x: sp.Float(sp.N(x, 30), 30))
        e = sp.expand(e)

        def reducible(x):
            return x.is_Pow and x.base in self.sine_to_cosine and x.exp.is_Integer and x.exp >= 2

        def reduce(x):
            k = int(x.exp)
            return x.base ** (k % 2) * (1 - self.sine_to_cosine[x.base] ** 2) ** (k // 2)
        e = sp.expand(e.replace(reducible, reduce))
        e = e.replace(lambda x: x.is_Float and abs(x) < 1e-25, lambda x: sp.S.Zero)
        if self.plain_angles and not e.has(sp.Float) and sp.count_ops(e) <= self.TRIGSIMP_LIMIT:
            e = sp.trigsimp(e.xreplace(self.trig))
            e = self.collect(e)
            return self.shorten(e)
        return self.collect(e).xreplace(self.trig_display)

    #: larger expressions (SymPy count_ops) keep the reduced c_i/s_i polynomial form
    TRIGSIMP_LIMIT = 200

    def textbook_matrix(self, mat) -> sp.ImmutableMatrix:
        return sp.ImmutableMatrix(sp.Matrix(mat).applyfunc(self.textbook))


class _Namer:
    """The named form: program symbols become readable names or are inlined."""

    def __init__(self, program, notation: _Notation):
        self.rhs = dict(program.assignments)
        self.notation = notation
        self.names: dict[sp.Symbol, sp.Symbol] = dict(notation.trig_display)
        self.memo: dict[sp.Symbol, sp.Expr] = {}
        self.inputs = notation.to_display
        self.auto: list[sp.Symbol] = []  # intermediates named xi_1, xi_2, ... because they were too long to inline

    #: an intermediate whose inlined form has more operations (SymPy count_ops) is shown as a
    #: numbered quantity xi_k with its own definition (inlining everything grew without bound:
    #: the Jacobian-projected form of a 6-joint URDF ran out of 8 GB)
    INLINE_LIMIT = 300

    def name(self, sym: sp.Symbol, shown: sp.Symbol):
        if isinstance(sym, sp.Symbol) and sym in self.rhs and sym not in self.names:
            self.names[sym] = shown

    def inline(self, expr) -> sp.Expr:
        """``expr`` with unnamed intermediates expanded until named quantities or inputs."""
        expr = sp.sympify(expr)
        subs = {}
        for s in expr.free_symbols:
            if s in self.names:
                subs[s] = self.names[s]
            elif s in self.rhs:
                if s not in self.memo:
                    value = self.inline(self.rhs[s])
                    if sp.count_ops(value) > self.INLINE_LIMIT:  # shown as a numbered quantity instead
                        shown = sp.Symbol(f"xi_{len(self.auto) + 1}", real=True)
                        self.auto.append(s)
                        self.names[s] = shown
                        self.memo[s] = value
                        subs[s] = shown
                        continue
                    self.memo[s] = value
                subs[s] = self.memo[s]
            elif s in self.inputs:
                subs[s] = self.inputs[s]
        return sp.expand(expr.xreplace(subs))

    def definitions(self, exclude) -> tuple:
        """``(shown, definition)`` of every named intermediate not in ``exclude``: the numbered
        ones first (in the order they were made, each after those it uses), then the others."""
        out, done = [], set()
        while True:
            pending = [sym for sym in list(self.names) if sym not in done and sym in self.rhs and sym not in exclude]
            if not pending:
                break
            for sym in pending:
                done.add(sym)
                out.append((sym, self.names[sym], self.definition(sym)))
        auto = {sym: k for k, sym in enumerate(self.auto)}
        out.sort(key=lambda item: (0, auto[item[0]]) if item[0] in auto else (1, 0))  # stable: the others keep their order
        return tuple((shown, value) for _, shown, value in out)

    def definition(self, sym) -> sp.Expr:
        """The right-hand side of a named symbol, one level down (a joint's sin/cos: its shorthand)."""
        if isinstance(sym, sp.Symbol) and sym in self.notation.trig_display:
            return self.notation.trig_display[sym]
        if isinstance(sym, sp.Symbol) and sym in self.auto:
            return self.memo[sym]
        if isinstance(sym, sp.Symbol) and sym in self.rhs:
            return self.inline(self.rhs[sym])
        return self.inline(sym)


def _numbered(program, exprs: list, notation: _Notation):
    """Rename every intermediate the expressions need to x_1, x_2, ... (trig to c_i/s_i)."""
    mapping = dict(notation.trig_display) | notation.to_display
    where = []
    for sym, rhs in program.needed_for(exprs):
        if sym in notation.trig_display:
            continue
        shown = sp.Symbol(f"x_{len(where) + 1}", real=True)
        where.append((shown, sp.expand(rhs.xreplace(mapping))))
        mapping[sym] = shown
    return [sp.sympify(e).xreplace(mapping) for e in exprs], tuple(where)


#: the most joints the task-space section (closed forms) is printed for
TASK_CLOSED_FORM_MAX_DOF = 3


def _rational(notation: _Notation, expr) -> sp.Expr:
    """A rational expression in the joints' trig symbols in closed form: numerator and
    denominator each reduced as :meth:`_Notation.textbook` reduces a polynomial, the denominator
    factored."""
    numerator, denominator = sp.fraction(sp.cancel(sp.together(expr)))
    top = notation.textbook(numerator)
    bottom = sp.factor(notation.textbook(denominator))
    return sp.factor_terms(top) / bottom if bottom != 1 else top


def task_section(robot: Robot, notation: _Notation, progress=None) -> Section:
    """The task-space equations of motion ``F = M_x xdd + V_x + G_x`` of the ECE 470 lecture
    ("Cartesian space") for the robot's task rows, in closed form: J, det J (square tasks),
    M_x, V_x, G_x; square tasks in the lecture's form ``J^-T D J^-1``, ``J^-T (h - D J^-1 Jdot
    qdot)``, ``J^-T c``, others as ``(J D^-1 J^T)^-1`` and its products.  D includes the armature."""
    n, rows = robot.dof, robot.task_rows
    if n > TASK_CLOSED_FORM_MAX_DOF:
        raise SymdynError(f"{robot.source or robot.name}: the task-space section is printed in closed form, which is "
                          f"kept to robots of up to {TASK_CLOSED_FORM_MAX_DOF} joints (this one has {n}); its C "
                          "functions (symdyn generate --functions task_space) have no such limit")
    eqs = derive(robot, "newton-euler", ["mass_matrix", "coriolis", "gravity", "jacobian", "jacobian_dot_qd"],
                 progress=progress)
    trig = lambda M: sp.Matrix(notation.to_trig_symbols(eqs.program, sp.Matrix(M)))  # noqa: E731
    D = trig(eqs.mass_matrix) + armature_matrix(robot)
    h, c = trig(eqs.coriolis), trig(eqs.gravity)
    J = trig(eqs.jacobian)[list(rows), :]
    jdot = trig(eqs.jacobian_dot_qd)[list(rows), :]
    quantities = [Quantity("task_J", (), notation.textbook_matrix(J))]
    if len(rows) == n:
        det = J.det()
        quantities.append(Quantity("task_det", (), sp.factor(notation.textbook(det))))
        J_inv_T = J.adjugate().T / det
        Mx = J_inv_T * D * J_inv_T.T
        Vx = J_inv_T * (h - D * J_inv_T.T * jdot)
        Gx = J_inv_T * c
    else:
        D_inv = D.adjugate() / D.det()
        Mx = (J * D_inv * J.T).inv()
        Vx = Mx * (J * D_inv * h - jdot)
        Gx = Mx * J * D_inv * c
    shown = lambda M: sp.ImmutableMatrix(sp.Matrix(M).applyfunc(lambda e: _rational(notation, e)))  # noqa: E731
    quantities += [Quantity("Mx", (), shown(Mx)), Quantity("Vx", (), shown(Vx)), Quantity("Gx", (), shown(Gx))]
    return Section("task_space", tuple(quantities))


def _with_task(derivation: Derivation, wanted: bool, progress=None) -> Derivation:
    """``derivation`` with a last section ``task_space`` (:func:`task_section`)."""
    if not wanted:
        return derivation
    notation = _Notation(make_chain(derivation.robot))
    return _appended(derivation, task_section(derivation.robot, notation, progress), notation)


def _appended(derivation: Derivation, section: Section, notation: _Notation) -> Derivation:
    """``derivation`` with ``section`` last and ``notation``'s shorthand added to its own."""
    from dataclasses import replace
    shorthand = dict(derivation.shorthand) | notation.shorthand
    return replace(derivation, sections=derivation.sections + (section,),
                   shorthand=tuple(sorted(shorthand.items(), key=lambda kv: (len(kv[0].name), kv[0].name))))


def contact_section(robot: Robot, notation: _Notation, progress=None) -> Section:
    """The contact dynamics of the robot's contact set (the functions contact_forward_dynamics):
    J_c, the contacts' rows of their frames' Jacobians (world-aligned axes at each frame's origin;
    a point's three linear rows, a sole's six) and gamma = J_c-dot qd as the functions hold them;
    when the contacts pin the robot (as many rows as joints, at most
    :data:`TASK_CLOSED_FORM_MAX_DOF`, det J_c not identically zero) the closed forms
    ``qdd = -J_c^-1 gamma`` and ``lambda = J_c^-T (D qdd - (tau - h - c))`` (D includes the
    armature; friction left out)."""
    from .contact import contact_drift, contact_rows
    eqs = derive(robot, "newton-euler", ["mass_matrix", "coriolis", "gravity", "frame_poses", "frame_jacobians",
                                         "frame_jacobian_dot_v"], progress=progress)
    trig = lambda M: sp.Matrix(notation.to_trig_symbols(eqs.program, sp.Matrix(M)))  # noqa: E731
    J = contact_rows(robot.contacts, trig(eqs.output("frame_jacobians")))
    poses = trig(eqs.output("frame_poses")) if any(c.corrected for c in robot.contacts) else None
    gamma = sp.Matrix(contact_drift(robot.contacts, J, trig(eqs.output("frame_jacobian_dot_v")), eqs.qd, poses=poses,
                                    sole_logs=False))  # (a corrected sole's log term: stated in the notes, not expanded)
    quantities = [Quantity("contact_J", (), notation.textbook_matrix(J)),
                  Quantity("contact_gamma", (), notation.textbook_matrix(gamma))]
    if J.shape[0] == robot.dof <= TASK_CLOSED_FORM_MAX_DOF and not robot.floating:
        det = sp.factor(notation.textbook(J.det()))
        if det != 0:
            quantities.append(Quantity("contact_det", (), det))
            J_inv = J.adjugate() / det
            qdd = -J_inv * gamma
            rhs = sp.Matrix(eqs.tau) - trig(eqs.coriolis) - trig(eqs.gravity)
            D = trig(eqs.mass_matrix) + armature_matrix(robot)
            forces = J_inv.T * (D * qdd - rhs)
            shown = lambda M: sp.ImmutableMatrix(sp.Matrix(M).applyfunc(lambda e: _rational(notation, e)))  # noqa: E731
            quantities += [Quantity("contact_qdd", (), shown(qdd)), Quantity("contact_lambda", (), shown(forces))]
    return Section("contact_dynamics", tuple(quantities))


def _with_contacts(derivation: Derivation, progress=None) -> Derivation:
    """``derivation`` with a last section ``contact_dynamics`` (:func:`contact_section`) when the
    robot has a contact set and a fixed base (a floating base's rows expand the base's rotation
    from its quaternion: minutes of printing; one warning line says it is left out)."""
    robot = derivation.robot
    if not robot.contacts:
        return derivation
    if robot.floating:
        warn(f"{robot.source or robot.name}: the contact dynamics of a floating base are not printed (its contact "
             "rows expand the base's rotation from its quaternion); the generated contact functions have no such limit")
        return derivation
    notation = _Notation(make_chain(robot))
    return _appended(derivation, contact_section(robot, notation, progress), notation)


def configuration_section(notation: _Notation) -> Section:
    """The configuration space of a floating base (the functions integrate, difference and their
    Jacobians, :mod:`symdyn.derive.configuration`): the base's rotation from its quaternion, and
    each coefficient of SE(3)'s exponential, logarithm and Jacobians as a function of the angle
    theta = |omega|, its closed form equal to the Taylor series used below theta^2 = 1/4."""
    from . import configuration
    x, y, z, w = notation.quaternion
    norm = x * x + y * y + z * z + w * w
    rotation = sp.ImmutableMatrix([[1 - 2 * (y * y + z * z) / norm, 2 * (x * y - z * w) / norm, 2 * (x * z + y * w) / norm],
                                   [2 * (x * y + z * w) / norm, 1 - 2 * (x * x + z * z) / norm, 2 * (y * z - x * w) / norm],
                                   [2 * (x * z - y * w) / norm, 2 * (y * z + x * w) / norm, 1 - 2 * (x * x + y * y) / norm]])
    theta = sp.Symbol("theta", positive=True)
    quantities = [Quantity("cfg_rotation", (), rotation)]
    for k, (_, closed, series) in enumerate(configuration.coefficient_series(theta)):
        quantities.append(Quantity("cfg_coefficient", (k + 1,), sp.Eq(closed, series, evaluate=False)))
    return Section("configuration_space", tuple(quantities))


def _with_configuration(derivation: Derivation) -> Derivation:
    """``derivation`` with a last section ``configuration_space`` for a floating base."""
    if not derivation.robot.floating:
        return derivation
    from dataclasses import replace
    notation = _Notation(make_chain(derivation.robot))
    return replace(derivation, sections=derivation.sections + (configuration_section(notation),))


def derive_steps(robot: Robot, method: str = "lagrange-euler", steps: str = "all",
                 closed_form: bool | None = None, base_parameters: bool = False,
                 progress: Callable[[str], None] | None = None, task: bool = False) -> Derivation:
    """The derivation of ``robot``'s equations of motion by ``method``, step by step
    (``base_parameters``: with a last section listing the base parameters, each as an equation
    ``name = expression in the standard parameters``; needs a numeric link geometry).

    ``task``: with a last section of the task-space equations of motion (:func:`task_section`,
    closed forms, up to :data:`TASK_CLOSED_FORM_MAX_DOF` joints).

    ``steps='summary'`` keeps the link matrices, inertias and final results only.
    ``closed_form`` defaults to ``robot.dof <= 3``.  ``progress`` (optional) is called with a
    short text as each step starts (the closed form of a 3-joint robot takes seconds to minutes).
    """
    key = str(method).lower().replace("_", "-")
    if robot.mimics:
        raise SymdynError(f"{robot.source or robot.name}: the printed derivation does not cover mimic joints yet (the "
                          "recursion is the tree's with every joint free, then projected on the coordinates: print the "
                          "robot without its 'mimic:' fields for the first part); the C, CasADi and Python functions "
                          "do cover them")
    if robot.is_tree:
        check_tree_request(robot, "newton-euler" if key in ABA_ALIASES else normalize_method(key),
                           ["mass_matrix", "coriolis", "gravity"] + ["base_regressor"] * base_parameters
                           + ["task_mass_matrix"] * task, "aba" if key in ABA_ALIASES else "ldlt", "standard")
    if key in ABA_ALIASES:
        if steps not in STEPS:
            raise ValueError(f"steps must be one of {', '.join(STEPS)}, not {steps!r}")
        if closed_form:
            raise ValueError("the articulated-body derivation is printed in the named form only "
                             "(its quantities are rational in the joint variables)")
        report = _reporter(robot, "articulated-body", progress)
        return _with_configuration(_with_contacts(_with_task(_with_base_parameters(
            _articulated_body_steps(robot, steps, report), base_parameters, progress), task, progress), progress))
    method = normalize_method(method)
    if steps not in STEPS:
        raise ValueError(f"steps must be one of {', '.join(STEPS)}, not {steps!r}")
    closed = robot.dof <= 3 if closed_form is None else closed_form
    report = _reporter(robot, method, progress)
    chain = make_chain(robot)
    notation = _Notation(chain)
    report("link matrices")
    # link matrices are short in either form
    sections: list[Section] = [Section("link_transform", tuple(
        Quantity("link_transform", (i + 1,), notation.textbook_matrix(chain.transforms[i])) for i in range(chain.n)))]
    steps_of = {"lagrange-euler": _lagrange_euler_steps, "jacobian-newton-euler": _jacobian_steps}.get(
        method, _newton_euler_steps)
    more, named, results = steps_of(chain, notation, steps, closed, report)
    sections += more
    where: tuple = ()
    if results is None:
        report("D, h, c" + (" in closed form" if closed else ""))
        results, where = _final_results(robot, method, closed, notation, progress)
    # the intermediates too long to inline (xi_k) are listed with the numbered quantities
    where = tuple(item for item in named if item[0].name.startswith("xi_")) + tuple(where)
    sections.append(Section("results", (Quantity("D", (), results[0]), Quantity("h", (), results[1]),
                                        Quantity("c", (), results[2]))))
    joint = tuple((shown, sym) for sym, shown in notation.to_display.items())
    return _with_configuration(_with_contacts(_with_task(_with_base_parameters(Derivation(
        robot=robot, method=method, steps=steps, closed_form=closed, sections=tuple(sections),
        where=where, named=named, shorthand=tuple(sorted(notation.shorthand.items(), key=lambda kv: (len(kv[0].name), kv[0].name))),
        joint_symbols=joint), base_parameters, progress), task, progress), progress))


def _reporter(robot: Robot, method: str, progress):
    """``report(text)``: ``progress('robot: method: text (t s)')``, or nothing without ``progress``."""
    start = time.perf_counter()

    def report(text: str) -> None:
        if progress is not None:
            progress(f"{robot.name}: {method}: {text} ({time.perf_counter() - start:.1f} s)")
    return report


def _closed_valuer(chain, notation: _Notation):
    """The closed form of a quantity of the chain's recursion (every intermediate expanded)."""
    def closed_value(value):
        program = chain.builder.build()
        if isinstance(value, sp.MatrixBase):
            return notation.textbook_matrix(notation.to_trig_symbols(program, value))
        return notation.textbook(notation.to_trig_symbols(program, value))
    return closed_value


def _lagrange_euler_steps(chain, notation: _Notation, steps: str, closed: bool, report):
    """The Lagrange-Euler sections after the link matrices, no named quantities, and in the
    closed form D, h, c (else None: :func:`_final_results` gives them)."""
    robot, n = chain.robot, chain.n
    sections: list[Section] = []
    le = LagrangeEuler(chain)
    if closed and steps == "all":
        report("base-to-link matrices")
        closed_value = _closed_valuer(chain, notation)
        A0 = [closed_value(le.A[i]) for i in range(n)]
        sections.append(Section("base_transform", tuple(Quantity("base_transform", (i + 1,), A0[i]) for i in range(n))))
    sections.append(Section("q_operator", tuple(
        Quantity("q_operator", (j + 1,), sp.ImmutableMatrix(q_operator(link.is_revolute)))
        for j, link in enumerate(robot.links))))
    sections.append(Section("pseudo_inertia", tuple(
        Quantity("pseudo_inertia", (i + 1,), sp.ImmutableMatrix(pseudo_inertia(link)))
        for i, link in enumerate(robot.links))))
    if not closed:
        return sections, (), None
    report("U_ij and U_ijk")
    for i in range(n):
        for j in range(i + 1):
            le.U(i, j)
    program = chain.builder.build()
    Uq = {(i, j): notation.to_trig_symbols(program, le.U(i, j)).applyfunc(sp.expand)
          for i in range(n) for j in range(i + 1)}
    U3 = {}
    for (i, j), u in Uq.items():
        for k in range(i + 1):
            U3[(i, j, k)] = u.applyfunc(lambda e: sp.expand(notation.diff(e, k)))
    J = [sp.Matrix(pseudo_inertia(link)) for link in robot.links]
    g = sp.Matrix([[*chain.gravity, 0]])

    def trace(X, Y):
        return (X * Y.T).trace()

    report("D_ik, h_ikm and c_i (traces)")
    D = sp.zeros(n, n)
    h_ikm = {}
    for i in range(n):
        for k in range(n):
            D[i, k] = sum((trace(Uq[(j, k)] * J[j], Uq[(j, i)]) for j in range(max(i, k), n)), sp.S.Zero)
            for m in range(n):
                h_ikm[(i, k, m)] = sum((trace(U3[(j, k, m)] * J[j], Uq[(j, i)])
                                        for j in range(max(i, k, m), n)), sp.S.Zero)
    h = sp.Matrix([sum((h_ikm[(i, k, m)] * chain.qd[k] * chain.qd[m] for k in range(n) for m in range(n)), sp.S.Zero)
                   for i in range(n)])
    c = sp.Matrix([sum((-robot.links[j].mass * (g * Uq[(j, i)] * sp.Matrix([*robot.links[j].com, 1]))[0]
                        for j in range(i, n)), sp.S.Zero) for i in range(n)])
    if steps == "all":
        report("closed form of U_ij")
        sections.append(Section("u", tuple(Quantity("u", (i + 1, j + 1), notation.textbook_matrix(Uq[(i, j)]))
                                           for i in range(n) for j in range(i + 1))))
        report("closed form of U_ijk")
        sections.append(Section("u3", tuple(Quantity("u3", (i + 1, j + 1, k + 1), notation.textbook_matrix(U3[(i, j, k)]))
                                            for i in range(n) for j in range(i + 1) for k in range(i + 1)
                                            if not U3[(i, j, k)].is_zero_matrix)))
        report("closed form of D_ik")
        sections.append(Section("d_entry", tuple(Quantity("d_entry", (i + 1, k + 1), notation.textbook(D[i, k]))
                                                 for i in range(n) for k in range(i, n))))
        report("closed form of h_ikm")
        sections.append(Section("h_entry", tuple(Quantity("h_entry", (i + 1, k + 1, m + 1), notation.textbook(h_ikm[(i, k, m)]))
                                                 for i in range(n) for k in range(n) for m in range(n))))
        report("closed form of h_i and c_i")
        sections.append(Section("h_i", tuple(Quantity("h_i", (i + 1,), notation.textbook(h[i])) for i in range(n))))
        sections.append(Section("c_i", tuple(Quantity("c_i", (i + 1,), notation.textbook(c[i])) for i in range(n))))
    report("closed form of D, h, c")
    return sections, (), (notation.textbook_matrix(D), notation.textbook_matrix(h), notation.textbook_matrix(c))


def _jacobian_steps(chain, notation: _Notation, steps: str, closed: bool, report):
    """The Jacobian-projected Newton-Euler sections after the link matrices, the named
    quantities of the named form, and None (D, h, c come from :func:`_final_results`)."""
    robot, n = chain.robot, chain.n
    sections: list[Section] = []
    named: tuple = ()
    report("link Jacobians and the recursion")
    jne = JacobianNewtonEuler(chain)
    jacobians = [jne.link_jacobian(i) for i in range(n)]
    zero = [sp.S.Zero] * n
    motions = jne.forward(chain.qd, zero, chain.gravity, "b")
    jne.backward(motions, "b")
    program = chain.builder.build()
    namer = None if closed else _Namer(program, notation)
    if namer is not None:
        for i in range(n):
            for label, vec in (("k", jne.k[i]), ("d", jne.d[i]), ("h", jne.h[i]), ("r", jne.r[i])):
                for a in range(3):
                    namer.name(vec[a], sp.Symbol(f"{label}_{i + 1}{AXES[a]}", real=True))
            for a in range(3):
                for c in range(a, 3):
                    namer.name(jne.inertia[i][a, c], sp.Symbol(f"I_{i + 1}{AXES[a]}{AXES[c]}", real=True))

    show = _shower(_closed_valuer(chain, notation) if closed else None, namer)
    if steps == "all":
        report("link Jacobians" + (" in closed form" if closed else ""))
        sections.append(Section("jacobian_link", tuple(Quantity("jc", (i + 1,), show(jacobians[i])) for i in range(n))))
        if closed:
            projected = []
            for i, link in enumerate(robot.links):
                report(f"projected mass matrix of link {i + 1} in closed form")
                J = jacobians[i]
                Mi = sp.diag(link.mass, link.mass, link.mass, 1, 1, 1)
                Mi[3:, 3:] = jne.inertia[i]
                projected.append(Quantity("projected", (i + 1,), show(J.T * Mi * J)))
            sections.append(Section("projected", tuple(projected)))
        if namer is not None:
            for i, m in enumerate(motions):
                for attr, name in (("omega", "omega"), ("omegadot", "omegadot"), ("vdot", "vdot"),
                                   ("f_J", "f_J"), ("t_J", "t_J")):
                    vec = getattr(m, attr)
                    for a in range(3):
                        namer.name(vec[a], sp.Symbol(f"{name}{i + 1}{AXES[a]}", real=True))
        forward_q = []
        for i, m in enumerate(motions):
            report(f"forward recursion, link {i + 1}")
            forward_q += [Quantity("omega_w", (i + 1,), show(m.omega)),
                          Quantity("omegadot_w", (i + 1,), show(m.omegadot)),
                          Quantity("vdot_w", (i + 1,), show(m.vdot))]
        backward_q = []
        for i in reversed(range(n)):
            report(f"backward recursion, link {i + 1}")
            m = motions[i]
            backward_q += [Quantity("fJ", (i + 1,), show(m.f_J)), Quantity("tJ", (i + 1,), show(m.t_J)),
                           Quantity("tau", (i + 1,), show(m.tau))]
        sections.append(Section("jne_forward", tuple(forward_q)))
        sections.append(Section("jne_backward", tuple(backward_q)))
        if namer is not None:
            named = namer.definitions(notation.trig)
    return sections, named, None


def _newton_euler_steps(chain, notation: _Notation, steps: str, closed: bool, report):
    """The forward and backward recursion of Table 3.2, the named quantities of the named form,
    and None (D, h, c come from :func:`_final_results`)."""
    n = chain.n
    sections: list[Section] = []
    named: tuple = ()
    report("the recursion")
    base_motion, base_wrench = [], []
    states = recursion(chain, chain.qd, chain.qdd, chain.gravity, "", textbook=True,
                       base_motion=base_motion, base_wrench=base_wrench)
    program = chain.builder.build()
    namer = None if closed else _Namer(program, notation)
    if steps == "all":
        fields = (("omega", "omega", "omega"), ("omegad", "omegadot", "omegadot"), ("vd", "vdot", "vdot"),
                  ("abar", "abar", "abar"))
        backward = (("F", "F", "F"), ("N", "N", "N"), ("f", "f", "f"), ("n", "n", "n"))
        if namer is not None:
            for i, st in enumerate(states):
                for attr, _, name in fields + backward:
                    vec = getattr(st, attr)
                    for a in range(3):
                        namer.name(vec[a], sp.Symbol(f"{name}_{i + 1}{AXES[a]}", real=True))
                namer.name(st.tau, sp.Symbol(f"tau{i + 1}", real=True))
            # a floating base: its origin's acceleration and the wrench that moves it
            for vec, name in zip(base_motion[2:] + base_wrench if chain.robot.floating else [], ("vdot", "f", "n")):
                for a in range(3):
                    namer.name(vec[a], sp.Symbol(f"{name}_0{AXES[a]}", real=True))

        show = _shower(_closed_valuer(chain, notation) if closed else None, namer)
        forward_q, backward_q = [], []
        if chain.robot.floating:
            forward_q.append(Quantity("vdot", (0,), show(base_motion[2])))
        for i, st in enumerate(states):
            report(f"forward recursion, link {i + 1}" + (" in closed form" if closed else ""))
            for attr, kind, _ in fields:
                forward_q.append(Quantity(kind, (i + 1,), show(getattr(st, attr))))
        for i in reversed(range(n)):
            report(f"backward recursion, link {i + 1}" + (" in closed form" if closed else ""))
            st = states[i]
            for attr, kind, _ in backward:
                backward_q.append(Quantity(kind, (i + 1,), show(getattr(st, attr))))
            backward_q.append(Quantity("tau", (i + 1,), show(st.tau)))
        if base_wrench:
            backward_q += [Quantity("f", (0,), show(base_wrench[0])), Quantity("n", (0,), show(base_wrench[1]))]
        if namer is not None:
            named = namer.definitions(notation.trig)
        sections.append(Section("ne_forward", tuple(forward_q)))
        sections.append(Section("ne_backward", tuple(backward_q)))
    return sections, named, None


def _with_base_parameters(derivation: Derivation, wanted: bool, progress=None) -> Derivation:
    """``derivation`` with a last section ``base_parameters`` (one equation per base parameter)."""
    if not wanted:
        return derivation
    from dataclasses import replace
    eqs = derive(derivation.robot, "newton-euler", ["base_regressor"], progress=progress)
    section = Section("base_parameters", tuple(
        Quantity("beta", (k + 1,), sp.Eq(sp.Symbol(name, real=True), expr, evaluate=False))
        for k, (name, expr) in enumerate(eqs.base_parameters)))
    return replace(derivation, sections=derivation.sections + (section,))


def _shower(closed_value, namer):
    """How a recursion's quantity is shown: its closed form (``closed_value``), or written in
    terms of the named quantities of the previous link (``namer``)."""
    def show(value):
        if closed_value is not None:
            return closed_value(value)
        if isinstance(value, sp.MatrixBase):
            return sp.ImmutableMatrix(sp.Matrix(value).applyfunc(namer.definition))
        return namer.definition(value)
    return show


def _final_results(robot: Robot, method: str, closed: bool, notation: _Notation, progress=None):
    """(D, h, c) as printed, and the numbered intermediates x_k they use in the named form."""
    eqs = derive(robot, method, ["mass_matrix", "coriolis", "gravity"], progress=progress)
    if closed:
        return tuple(notation.textbook_matrix(notation.to_trig_symbols(eqs.program, eqs.output(name)))
                     for name in ("mass_matrix", "coriolis", "gravity")), ()
    return _named_results(eqs, notation)


def _named_results(eqs, notation: _Notation):
    n = eqs.n
    D, h, c = eqs.mass_matrix, eqs.coriolis, eqs.gravity
    upper = [D[i, k] for i in range(n) for k in range(i, n)]
    exprs = upper + list(h) + list(c)
    renamed, where = _numbered(eqs.program, exprs, notation)
    Dm = sp.zeros(n, n)
    it = iter(renamed[:len(upper)])
    for i in range(n):
        for k in range(i, n):
            Dm[i, k] = Dm[k, i] = next(it)
    hm = sp.Matrix(renamed[len(upper):len(upper) + n])
    cm = sp.Matrix(renamed[len(upper) + n:])
    return (sp.ImmutableMatrix(Dm), sp.ImmutableMatrix(hm), sp.ImmutableMatrix(cm)), where


_SPATIAL = ("wx", "wy", "wz", "x", "y", "z")  # entry labels of spatial vectors [angular; linear]


def _name_sweeps(namer: "_Namer", notation: "_Notation", sw, a_prime, qdd, rm, n: int) -> None:
    """Give the sweeps' entries (and the reaction map's, ``rm``) the names the printout shows:
    X_k, v_k, c_k, p_k, d_k, u_k, Ia_k, pa_k, IA_k, pA_k, ap_k, the accelerations, b_k, k_k, W, D."""
    def name_vec(vec, label):
        for m in range(6):
            namer.name(vec[m], sp.Symbol(f"{label},{_SPATIAL[m]}", real=True))

    def name_sym6(mat, label):
        for r in range(6):
            for c in range(r, 6):
                namer.name(mat[r, c], sp.Symbol(f"{label},{r + 1}{c + 1}", real=True))

    for j in range(n):
        k = j + 1
        for r in range(6):
            for c in range(6):
                namer.name(sw.X[j][r, c], sp.Symbol(f"X_{k},{r + 1}{c + 1}", real=True))
        name_vec(sw.v[j], f"v_{k}")
        name_vec(sw.c[j], f"c_{k}")
        name_vec(sw.pA0[j], f"p_{k}")
    for j in range(n):
        namer.name(sw.d[j], sp.Symbol(f"d_{j + 1}", real=True))
        namer.name(sw.u[j], sp.Symbol(f"u_{j + 1}", real=True))
    for j in reversed(range(1, n)):
        k = j + 1
        name_sym6(sw.Ia[j], f"Ia_{k}")
        name_vec(sw.pa[j], f"pa_{k}")
        name_sym6(sw.IA[j - 1], f"IA_{k - 1}")
        name_vec(sw.pA[j - 1], f"pA_{k - 1}")
    for j in range(n):
        name_vec(a_prime[j], f"ap_{j + 1}")
        namer.name(qdd[j], notation.qddot[j])
    if rm is not None:
        rsw = rm.sweeps
        for j in range(n):
            name_vec(rm.b[j], f"b_{j + 1}")
        for j in reversed(range(n)):
            k = j + 1
            namer.name(rsw.u[j], sp.Symbol(f"u0_{k}", real=True))
            if j > 0:
                name_vec(rsw.pa[j], f"pa0_{k}")
                name_vec(rsw.pA[j - 1], f"k_{k}")
        name_vec(rm.k1, "k_1")
        name_vec(rm.k0, "k_0")
        for j, i, w in rm.partials:
            name_vec(w, f"W_{j + 1},{i + 1}")
        for col, j in zip(rm.columns, rm.actuated):
            name_vec(col, f"D_{j + 1}")


def _reaction_map_sections(q, namer: "_Namer", rm, n: int, steps: str) -> list:
    """The printout's sections of the force-to-torque map (eqs. 3-14): gains, bias sweep,
    wrench, columns and results; ``q`` shows a quantity (see :func:`_articulated_body_steps`)."""
    out: list = []
    rsw = rm.sweeps
    out.append(Section("rm_gains", tuple(
        [q("b", (j + 1,), rm.b[j], f"b_{j + 1},") for j in range(n)] + [q("A", (j + 1,), rm.A[j]) for j in range(n)])))
    if steps == "all":
        bias = []
        for j in reversed(range(1, n)):
            k = j + 1
            bias += [q("aba_u", (k,), rsw.u[j], f"u0_{k}"), q("pa0", (k,), rsw.pa[j], f"pa0_{k},"), q("k", (k,), rsw.pA[j - 1], f"k_{k},")]
        out.append(Section("rm_bias", tuple(bias)))
    out.append(Section("rm_wrench", (q("k1", (1,), rm.k1, "k_1,"), q("k0", (0,), rm.k0, "k_0,"))))
    columns = []
    for col, j in zip(rm.columns, rm.actuated):
        columns += [q("W", (j + 1, i + 1), w, f"W_{j + 1},{i + 1},") for jj, i, w in rm.partials if jj == j]
        columns.append(q("column", (j + 1,), col, f"D_{j + 1},"))
    out.append(Section("rm_columns", tuple(columns)))
    out.append(Section("rm_results", (
        Quantity("k0", (0,), sp.ImmutableMatrix([namer.names.get(e, e) for e in rm.k0])),
        Quantity("Dmap", (), sp.ImmutableMatrix(sp.Matrix.hstack(*[
            sp.Matrix([namer.names.get(e, e) for e in col]) for col in rm.columns]))))))
    return out


def _articulated_body_steps(robot: Robot, steps: str, report=lambda text: None) -> Derivation:
    """The articulated-body algorithm (the force-to-torque articulated-body note, Algorithm 1) written out for ``robot`` in the
    named form, and for a robot with passive joints the force-to-torque map (eqs. 3-14)."""
    report("the three sweeps" + (" and the reaction map" if robot.passive_joints else ""))
    chain = make_chain(robot)
    notation = _Notation(chain)
    n = chain.n
    friction = friction_terms(robot, chain.qd, [sp.S.Zero] * n)
    sw = sweeps(chain, chain.tau, friction)
    a_prime, qdd, accel = accelerations(chain, sw)
    rm = reaction_map(chain, friction) if robot.passive_joints else None
    program = chain.builder.build()
    namer = _Namer(program, notation)

    _name_sweeps(namer, notation, sw, a_prime, qdd, rm, n)
    def q(kind, indices, value, own=""):
        """A quantity shown by the definitions of the entries it names (prefix ``own``) and by
        name where an entry is another quantity's."""
        def entry(e):
            shown = namer.names.get(e) if isinstance(e, sp.Symbol) else None
            if shown is not None and e not in notation.trig_display and not (own and shown.name.startswith(own)):
                return shown
            return namer.definition(e)
        if isinstance(value, sp.MatrixBase):
            return Quantity(kind, indices, sp.ImmutableMatrix(sp.Matrix(value).applyfunc(entry)))
        return Quantity(kind, indices, entry(value))

    sections: list[Section] = [Section("link_transform", tuple(
        Quantity("link_transform", (i + 1,), notation.textbook_matrix(chain.transforms[i])) for i in range(n)))]
    sections.append(Section("aba_model", tuple(
        [q("X", (j + 1,), sw.X[j], f"X_{j + 1},") for j in range(n)] + [q("I", (j + 1,), sw.I[j]) for j in range(n)])))
    if steps == "all":
        forward = []
        for j in range(n):
            forward += [q("v", (j + 1,), sw.v[j], f"v_{j + 1},"), q("cbar", (j + 1,), sw.c[j], f"c_{j + 1},"), q("p", (j + 1,), sw.pA0[j], f"p_{j + 1},")]
        sections.append(Section("aba_forward", tuple(forward)))
        backward = []
        for j in reversed(range(n)):
            k = j + 1
            backward += [q("U", (k,), sw.U[j]), q("d", (k,), sw.d[j], f"d_{k}"), q("aba_u", (k,), sw.u[j], f"u_{k}")]
            if j > 0:
                backward += [q("Ia", (k,), sw.Ia[j], f"Ia_{k},"), q("pa", (k,), sw.pa[j], f"pa_{k},"),
                             q("IA", (k - 1,), sw.IA[j - 1], f"IA_{k - 1},"), q("pA", (k - 1,), sw.pA[j - 1], f"pA_{k - 1},")]
        sections.append(Section("aba_backward", tuple(backward)))
    acc = []
    for j in range(n):
        acc += [q("ap", (j + 1,), a_prime[j], f"ap_{j + 1},"), q("qdd", (j + 1,), qdd[j], notation.qddot[j].name), q("a", (j + 1,), accel[j])]
    sections.append(Section("aba_accel", tuple(acc)))
    if rm is not None:
        sections += _reaction_map_sections(q, namer, rm, n, steps)
    named = namer.definitions(notation.trig)
    joint = tuple(zip(notation.qdot, chain.qd))
    return Derivation(robot=robot, method="articulated-body", steps=steps, closed_form=False,
                      sections=tuple(sections), where=(), named=named,
                      shorthand=tuple(sorted(notation.shorthand.items(), key=lambda kv: (len(kv[0].name), kv[0].name))),
                      joint_symbols=joint)
