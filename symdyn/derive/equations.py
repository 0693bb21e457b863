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
C satisfies ``dD/dt - 2C`` skew-symmetric; with Newton-Euler it is computed as
``C = (1/2) dh/dqd`` (h is quadratic in qd and its symmetric coefficient tensor is exactly the
Christoffel symbols of the first kind), with Lagrange-Euler as ``C_ik = sum_m h_ikm qd_m``.

With Newton-Euler, D comes from the composite-rigid-body method (:mod:`symdyn.derive.composite`), the
recursive companion of Table 3.2; with Lagrange-Euler from the trace form over U_ij and the
pseudo-inertias.

Forward dynamics solves ``(D + diag(armature)) qdd = tau - h - c - friction`` with an LDL^T
factorization written out for the robot (no inverse).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import Iterable, Mapping

import sympy as sp

from .chain import make_chain
from .composite import mass_matrix as composite_mass_matrix
from .lagrange_euler import LagrangeEuler
from .newton_euler import joint_forces
from .program import Program, ProgramBuilder, differentiate
from ..model.outputs import OUTPUT_INPUTS, OUTPUT_SYMBOLS, OUTPUTS  # noqa: F401 (part of this module's API)
from ..model.robot import Robot
from .numeric import NumericEquations

METHODS = ("newton-euler", "lagrange-euler")
METHOD_ALIASES = {"ne": "newton-euler", "newton-euler": "newton-euler", "rne": "newton-euler",
                  "le": "lagrange-euler", "lagrange-euler": "lagrange-euler", "lagrange": "lagrange-euler"}

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

    @property
    def n(self) -> int:
        return self.robot.dof

    @property
    def parameters(self) -> tuple[sp.Symbol, ...]:
        return self.robot.parameters

    def output(self, name: str) -> sp.ImmutableMatrix:
        for key, value in self.outputs:
            if key == name:
                return value
        if name not in OUTPUTS:
            raise KeyError(f"unknown output {name!r}; known: {', '.join(OUTPUTS)}")
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


def _normalize_method(method: str) -> str:
    key = method.lower().replace("_", "-")
    if key not in METHOD_ALIASES:
        raise ValueError(f"unknown method {method!r}; use newton-euler or lagrange-euler")
    return METHOD_ALIASES[key]


def _friction(robot: Robot, qd, qdd) -> sp.Matrix:
    return sp.Matrix([link.armature * qdd[i] + link.damping * qd[i] + link.coulomb * sp.sign(qd[i])
                      for i, link in enumerate(robot.links)])


def _ldlt_solve(b: ProgramBuilder, M: sp.Matrix, rhs: sp.Matrix) -> sp.Matrix:
    """Solve M x = rhs for symmetric positive definite M with an unrolled LDL^T (n divisions)."""
    n = M.shape[0]
    L = sp.eye(n)
    d: list[sp.Expr] = []
    inv_d: list[sp.Expr] = []
    for j in range(n):
        dj = M[j, j] - sp.Add(*[L[j, k] ** 2 * d[k] for k in range(j)])
        d.append(b.define(f"ldl_d{j + 1}", dj))
        inv_d.append(b.define(f"ldl_inv{j + 1}", 1 / d[j]))
        for i in range(j + 1, n):
            lij = (M[i, j] - sp.Add(*[L[i, k] * L[j, k] * d[k] for k in range(j)])) * inv_d[j]
            L[i, j] = b.define(f"ldl_L{i + 1}{j + 1}", lij)
    y = [sp.S.Zero] * n
    for i in range(n):
        y[i] = b.define(f"ldl_y{i + 1}", rhs[i] - sp.Add(*[L[i, k] * y[k] for k in range(i)]))
    x = [sp.S.Zero] * n
    for i in reversed(range(n)):
        x[i] = b.define(f"qdd{i + 1}_fd", y[i] * inv_d[i] - sp.Add(*[L[k, i] * x[k] for k in range(i + 1, n)]))
    return sp.Matrix(x)


def derive(robot: Robot, method: str = "newton-euler", outputs: Iterable[str] | None = None) -> Equations:
    """Derive the equations of motion of ``robot``.

    Parameters
    ----------
    robot : the robot description (see :func:`symdyn.load`).
    method : ``'newton-euler'`` (recursive, Table 3.2; D by composite rigid bodies) or ``'lagrange-euler'`` (trace form).
    outputs : names from :data:`OUTPUTS` to derive (default: all of them).

    Returns
    -------
    Equations, immutable.
    """
    method = _normalize_method(method)
    wanted = tuple(OUTPUTS) if outputs is None else tuple(outputs)
    for name in wanted:
        if name not in OUTPUTS:
            raise ValueError(f"unknown output {name!r}; known: {', '.join(OUTPUTS)}")
    start = time.perf_counter()
    chain = make_chain(robot)
    b = chain.builder
    n = chain.n
    q, qd, qdd, tau = chain.q, chain.qd, chain.qdd, chain.tau
    zero = [sp.S.Zero] * n
    no_gravity = sp.zeros(3, 1)
    friction = _friction(robot, qd, qdd)
    result: dict[str, sp.Matrix] = {}
    need = set(wanted)
    if "forward_dynamics" in need:
        need |= {"mass_matrix"}

    if method == "newton-euler":
        if "gravity" in need:
            result["gravity"] = joint_forces(chain, zero, zero, chain.gravity, "g")
        if need & {"coriolis", "coriolis_matrix"}:
            h = joint_forces(chain, qd, zero, no_gravity, "h")
            result["coriolis"] = h
            if "coriolis_matrix" in need:
                columns = differentiate(b.build(), h, qd, b, "dh")
                C = sp.Matrix(n, n, lambda i, k: b.define(f"C{i + 1}{k + 1}", columns[k][i] / 2))
                result["coriolis_matrix"] = C
        if "mass_matrix" in need:
            result["mass_matrix"] = composite_mass_matrix(chain)
        if "inverse_dynamics" in need:
            rigid = joint_forces(chain, qd, qdd, chain.gravity, "")
            result["inverse_dynamics"] = rigid + friction
        if "forward_dynamics" in need:
            bias = joint_forces(chain, qd, zero, chain.gravity, "b")
    else:
        le = LagrangeEuler(chain)
        if need & {"mass_matrix", "inverse_dynamics"}:
            result["mass_matrix"] = le.mass_matrix()
        if need & {"coriolis", "coriolis_matrix", "inverse_dynamics", "forward_dynamics"}:
            C = le.coriolis_matrix(qd)
            result["coriolis_matrix"] = C
            result["coriolis"] = sp.Matrix([b.define(f"h{i + 1}", (C[i, :] * sp.Matrix(qd))[0]) for i in range(n)])
        if need & {"gravity", "inverse_dynamics", "forward_dynamics"}:
            result["gravity"] = le.gravity()
        if "inverse_dynamics" in need:
            result["inverse_dynamics"] = (result["mass_matrix"] * sp.Matrix(qdd) + result["coriolis"]
                                          + result["gravity"] + friction)
        if "forward_dynamics" in need:
            bias = result["coriolis"] + result["gravity"]

    if "forward_dynamics" in need:
        M = result["mass_matrix"] + sp.diag(*[link.armature for link in robot.links])
        rhs = sp.Matrix(tau) - bias - friction.subs({v: 0 for v in qdd})
        rhs = sp.Matrix([b.define(f"rhs{i + 1}", e) for i, e in enumerate(rhs)])
        result["forward_dynamics"] = _ldlt_solve(b, M, rhs)

    outputs_tuple = tuple((name, sp.ImmutableMatrix(result[name])) for name in OUTPUTS if name in wanted)
    return Equations(robot=robot, method=method, q=q, qd=qd, qdd=qdd, tau=tau,
                     program=b.build(), outputs=outputs_tuple,
                     seconds=time.perf_counter() - start)
