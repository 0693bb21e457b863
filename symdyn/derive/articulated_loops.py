"""Forward dynamics of a long chain by the articulated-body algorithm written as three loops over
the joints: one joint's step derived once, symbolically, with the chain's per-joint constants as
the columns of a table.

Written out for the whole chain (:mod:`symdyn.derive.articulated_body`), the algorithm's code
grows by about 450 operations a joint; past a dozen joints the straight-line body no longer fits
a core's instruction cache and runs slower per operation (docs/benchmarks.md, "Forward dynamics
as loops over the joints").  Here the step of one joint is derived once with symbols for what
differs from joint to joint (a column of the table) and numbers for what every joint shares (the
structural zeros and ones of the DH placements and of the spatial inertias fold as before), so
that the code is three short loops whose length does not depend on n.

The three steps, for joint j (1-based in the comments, as in Algorithm 1 of the force-to-torque
articulated-body note; every quantity in joint frame j, ``S_j = [e_z; 0]``)::

    velocity:      v_j = X_j v_{j-1} + S_j qd_j,    z_j = v_j x S_j qd_j           (j = 1..n)
    backward:      I^A_j = I_j + K_j,  p^A_j = v_j x* I_j v_j + k_j
                   d_j = S^T I^A_j S + armature_j,  b_j = I^A_j S / d_j,  ud_j = (tau_j - S^T p^A_j) / d_j
                   K_{j-1} = X_j^T (I^A_j - b_j S^T I^A_j) X_j,
                   k_{j-1} = X_j^T (p^A_j + I^a_j z_j + I^A_j S ud_j)            (j = n..2; K_n = k_n = 0)
    acceleration:  a'_j = X_j a_{j-1} + z_j,  qdd_j = ud_j - b_j^T a'_j,  a_j = a'_j + S_j qdd_j
                                                                                  (j = 1..n, a_0 = [0; -g])

``K_j`` and ``k_j`` are the children's articulated inertia and bias force carried into joint j
(the loop's accumulators); joint 1 runs only the backward step's first lines (``d``, ``b``,
``ud``).  ``tau_j`` here is the joint force less its friction (computed before the loops).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import sympy as sp

from ..model.geometry import joint_motion
from .articulated_body import (JointTransform, joint_transforms, link_inertia, transform_force_back,
                              transform_inertia_back, transform_motion)
from .chain import Chain
from .program import Program, ProgramBuilder
from .spatial import Placement, cross_force, cross_motion, named_symmetric

#: from this many joints a fixed-base serial chain of revolute joints with numeric constants may
#: have its articulated-body forward dynamics emitted as loops over the joints, when the loops'
#: operations are no more than the chain's written out (:func:`articulated_loops`).  Generic
#: chains (gcc, AMD EPYC; docs/benchmarks.md): the loops ran 1.15x / 1.34x faster than the
#: straight-line form at 8 joints (-O3 -march=native / -O2), 0.88x / 0.98x at 6
LOOPED_ABA_FROM_DOF = 8

#: the upper triangle of a symmetric 6 x 6 matrix, row by row (21 entries)
UPPER = tuple((r, c) for r in range(6) for c in range(r, 6))

#: the prefix of every symbol of the steps (inputs and intermediates): C names of their own
PREFIX = "fdl_"


def _symbols(name: str, count: int) -> tuple[sp.Symbol, ...]:
    return tuple(sp.Symbol(f"{PREFIX}{name}{k}", real=True) for k in range(count))


def _symmetric(entries) -> sp.Matrix:
    """The symmetric 6 x 6 matrix of an upper triangle (:data:`UPPER` order)."""
    M = sp.zeros(6, 6)
    for (r, c), e in zip(UPPER, entries):
        M[r, c] = M[c, r] = e
    return M


@dataclass(frozen=True)
class ArticulatedLoops:
    """The articulated-body algorithm of one chain as three steps over a table (module docstring).

    The table: ``slots`` (the symbols the steps read from a joint's row) and ``table`` (n rows of
    numbers, base to tip): the columns of the constant placement ``^{j-1}X_j`` (rotation 9,
    translation 3, m), of the link's spatial inertia in joint frame j (upper triangle, 21,
    kg, kg m, kg m^2) and the armature, those that differ between joints; the others are numbers
    in the steps.

    The steps (each a :class:`Program` and its outputs, expressions in the program's symbols
    and the step's inputs):

    - ``velocity``: inputs ``cos_sin`` (cos and sin of the joint angle), ``qd``, ``parent_velocity``
      (6); outputs ``velocity`` (6) then ``bias_accel`` (z, 6).
    - ``backward``: inputs ``cos_sin``, ``tau`` (force less friction), ``velocity``, ``bias_accel``,
      ``carried_inertia`` (K, upper triangle 21), ``carried_force`` (k, 6); outputs ``pivot``
      (d, a symbol of the program: checked before anything divides by it), ``gain`` (b, 6),
      ``scaled_force`` (ud), then the parent's K (21) and k (6).
    - ``acceleration``: inputs ``cos_sin``, ``bias_accel``, ``gain``, ``scaled_force``,
      ``parent_accel`` (6); outputs qdd_j then a_j (6).

    ``gravity``: a_0 = [0; -g] (6 numbers); ``angles``: per joint the main program's
    ``(cos, sin)`` symbols of its angle; ``tau_effective``: per joint ``tau_j - friction_j`` in the
    main program's symbols (n)."""

    slots: tuple
    table: tuple
    gravity: tuple
    angles: tuple
    tau_effective: tuple
    velocity: Program
    velocity_outputs: tuple
    backward: Program
    backward_outputs: tuple
    acceleration: Program
    acceleration_outputs: tuple

    def astuple(self) -> tuple:
        """The fields in order (what :attr:`symdyn.derive.equations.Equations.fd_loops` holds:
        plain tuples and programs, as the derivation cache stores them)."""
        return tuple(getattr(self, f.name) for f in dataclasses.fields(self))

    @property
    def n(self) -> int:
        return len(self.table)


# the steps' inputs (fixed names: the emitters bind them to their arrays)
COS_SIN = _symbols("cs", 2)
QD, TAU, SCALED_FORCE = (sp.Symbol(f"{PREFIX}{name}", real=True) for name in ("qd", "tau", "ud"))
PARENT_VELOCITY, VELOCITY, BIAS_ACCEL = _symbols("vp", 6), _symbols("v", 6), _symbols("z", 6)
CARRIED_INERTIA, CARRIED_FORCE = _symbols("K", 21), _symbols("k", 6)
GAIN, PARENT_ACCEL = _symbols("b", 6), _symbols("ap", 6)


def applies(robot) -> bool:
    """Whether the robot's forward dynamics by the articulated-body algorithm is written as
    loops: a fixed-base serial chain of at least :data:`LOOPED_ABA_FROM_DOF` revolute joints
    whose constants are numbers (no runtime parameters: the table is ``static const``)."""
    return (not robot.floating and not robot.is_tree and robot.dof >= LOOPED_ABA_FROM_DOF
            and not robot.parameters and all(link.is_revolute for link in robot.links))


def _rows(chain: Chain):
    """Per joint, the candidate table entries (numbers), or None if one is not a number (a
    runtime parameter)."""
    rows = []
    for j, (T, post) in enumerate(joint_transforms(chain)):
        link = chain.robot.links[j]
        inertia = link_inertia(link, post)
        values = [*T.constant.R, *T.constant.p, *(inertia[r, c] for r, c in UPPER), link.armature]
        row = []
        for value in values:
            value = sp.sympify(value)
            if value.free_symbols:
                return None
            number = float(sp.N(value, 30))
            row.append(sp.Integer(int(number)) if number in (0.0, 1.0, -1.0) else sp.Float(number))
        rows.append(row)
    return rows


def _count(expr) -> int:
    """Arithmetic operations of an expression as written (each sum of k terms k - 1, each product
    of k factors k - 1 with a sign not counted, x**k |k| - 1 and a division for k < 0, a function
    1): what :func:`operations` compares, several times faster than ``sp.count_ops``."""
    if expr.is_Atom:
        return 0
    args = expr.args
    if expr.is_Add:
        own = len(args) - 1
    elif expr.is_Mul:
        own = len(args) - 1 - (1 if args[0] in (-1, 1) else 0)
    elif expr.is_Pow and expr.exp.is_Integer:
        return abs(int(expr.exp)) - 1 + (1 if expr.exp < 0 else 0) + _count(expr.base)
    else:
        own = 1
    return own + sum(_count(a) for a in args)


def operations(program: Program, outputs) -> int:
    """The arithmetic operations (:func:`_count`) of ``outputs`` and of the statements of
    ``program`` they need."""
    return (sum(_count(rhs) for _, rhs in program.needed_for(list(outputs)))
            + sum(_count(sp.sympify(e)) for e in outputs))


def loop_operations(loops: ArticulatedLoops) -> int:
    """:func:`operations` of the three loops, each step's times its trips."""
    n = loops.n
    return (operations(loops.velocity, loops.velocity_outputs) * n
            + operations(loops.backward, loops.backward_outputs) * (n - 1)
            + operations(loops.backward, loops.backward_outputs[:8])
            + operations(loops.acceleration, loops.acceleration_outputs) * n)


def articulated_loops(chain: Chain, friction, qdd) -> ArticulatedLoops | None:
    """The loop form of the chain's articulated-body forward dynamics, or None where it does not
    apply (:func:`applies`) or would cost more operations (:func:`loop_operations`) than ``qdd``,
    the accelerations written out in the chain's program (n; a chain whose joints share little
    structure folds about as much in the loops' step as written out, and loses nothing).
    ``friction``: the damping and Coulomb terms (n, no qdd) subtracted from tau before the loops."""
    if not applies(chain.robot):
        return None
    rows = _rows(chain)
    if rows is None:
        return None
    columns = list(zip(*rows))
    varying = [k for k, column in enumerate(columns) if len({float(v) for v in column}) > 1]
    slots = tuple(sp.Symbol(f"{PREFIX}p{k}", real=True) for k in range(len(varying)))
    entry = list(columns[k][0] for k in range(len(columns)))
    for symbol, k in zip(slots, varying):
        entry[k] = symbol
    pose = sp.Matrix(sp.BlockMatrix([[sp.Matrix(3, 3, entry[0:9]), sp.Matrix(entry[9:12])],
                                     [sp.zeros(1, 3), sp.ones(1, 1)]]))
    transform = JointTransform(constant=Placement(pose),
                               moving=Placement(joint_motion(chain.robot.links[0], sp.S.Zero, COS_SIN)))
    inertia = _symmetric(entry[12:33])
    armature = entry[33]
    velocity, velocity_outputs = _velocity_step(transform)
    backward, backward_outputs = _backward_step(transform, inertia, armature)
    acceleration, acceleration_outputs = _acceleration_step(transform)
    tau = [sp.expand(chain.tau[j] - friction[j]) for j in range(chain.n)]
    loops = ArticulatedLoops(
        slots=slots, table=tuple(tuple(row[k] for k in varying) for row in rows),
        gravity=(0, 0, 0, *(-g for g in chain.gravity)), angles=tuple(chain.joint_trig), tau_effective=tuple(tau),
        velocity=velocity, velocity_outputs=velocity_outputs, backward=backward, backward_outputs=backward_outputs,
        acceleration=acceleration, acceleration_outputs=acceleration_outputs)
    return loops if loop_operations(loops) <= operations(chain.builder.build(), list(qdd)) else None


def _vector(b: ProgramBuilder, hint: str, exprs) -> sp.Matrix:
    return sp.Matrix(b.vector(hint, [sp.expand(e) for e in exprs]))


def _velocity_step(T: JointTransform):
    b = ProgramBuilder(PREFIX)
    v = transform_motion(b, T, sp.Matrix(PARENT_VELOCITY), "vt")
    v[2] += QD
    v = _vector(b, "vj", v)
    joint_velocity = sp.zeros(6, 1)
    joint_velocity[2] = QD
    z = [sp.expand(e) for e in cross_motion(v, joint_velocity)]
    return b.build(), (*v, *z)


def _backward_step(T: JointTransform, inertia: sp.Matrix, armature):
    b = ProgramBuilder(PREFIX)
    v, z = sp.Matrix(VELOCITY), sp.Matrix(BIAS_ACCEL)
    IA = named_symmetric(b, "IA", inertia + _symmetric(CARRIED_INERTIA))
    momentum = _vector(b, "Iv", inertia * v)  # named first: v x* (I v) stays bilinear
    pA = _vector(b, "pA", cross_force(v, momentum) + sp.Matrix(CARRIED_FORCE))
    U = IA[:, 2]
    pivot = b.define("d", sp.expand(U[2] + armature), force=True)
    inverse = b.define("inv", 1 / pivot)
    gain = _vector(b, "g", U * inverse)
    scaled = b.define("udj", sp.expand((TAU - pA[2]) * inverse), force=True)
    projected = IA - gain * U.T
    if armature == 0:  # I^a S = 0 exactly: the joint's row and column vanish (as in the straight-line form)
        projected[2, :] = sp.zeros(1, 6)
        projected[:, 2] = sp.zeros(6, 1)
    Ia = named_symmetric(b, "Ia", projected)
    pa = _vector(b, "pa", pA + Ia * z + U * scaled)
    carried_inertia = transform_inertia_back(b, T, Ia, "Kt")
    carried_force = transform_force_back(b, T, pa, "kt")
    outputs = (pivot, *gain, scaled, *(sp.expand(carried_inertia[r, c]) for r, c in UPPER),
               *(sp.expand(e) for e in carried_force))
    return b.build(), outputs


def _acceleration_step(T: JointTransform):
    b = ProgramBuilder(PREFIX)
    ap = _vector(b, "aj", transform_motion(b, T, sp.Matrix(PARENT_ACCEL), "at") + sp.Matrix(BIAS_ACCEL))
    qdd = b.define("qdd", sp.expand(SCALED_FORCE - sum(g * a for g, a in zip(GAIN, ap))), force=True)
    accel = list(ap)
    accel[2] = sp.expand(accel[2] + qdd)
    return b.build(), (qdd, *accel)
