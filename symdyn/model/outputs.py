"""The functions symdyn can produce for a serial robot: one frozen spec per output.

Every consumer reads this registry and nothing else: derivation dispatch
(:mod:`symdyn.derive.equations`), numpy evaluation (:mod:`symdyn.derive.numeric`), C and CasADi
emission (:mod:`symdyn.emit.cgen`, :mod:`symdyn.emit.casadi_backend`), the compile-and-call
wrapper (:mod:`symdyn.check.cbuild`), timing (:mod:`symdyn.check.timing`), ``verify``'s
comparison list and ``--functions`` (help and validation).  Adding an output is its
:class:`OutputSpec` here, its derivation (``symdyn.derive.equations.DERIVATIONS``), its
independent reference (hand-written on purpose, :mod:`symdyn.check.pinocchio_model`) and its tests.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterable

import sympy as sp

#: the standard inertial, drive and friction parameters of one link (the regressor's columns):
#: mass, first moment (m * com, 3), inertia about the link origin (6), armature, viscous and
#: Coulomb friction
LINK_PARAMETERS = ("m", "mx", "my", "mz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz", "Ia", "fv", "fc")
#: how many standard parameters each link has
PARAMETERS_PER_LINK = len(LINK_PARAMETERS)

#: the input groups of the serial functions, in the order they are passed: the configuration q
#: (NQ entries), the velocity qd, acceleration qdd and forces tau (NV each), a tangent vector v
#: (NV: a displacement of the configuration, integrate's), a second configuration q1 (NQ:
#: difference's end), external forces f at the contacts (NC: laid out as the contact forces) and
#: the restitution of an impact (1 entry: 0 the contacts stop, 1 they bounce back)
INPUT_GROUPS = ("q", "qd", "qdd", "tau", "v", "q1", "f", "restitution")


@dataclass(frozen=True)
class Dimensions:
    """Every size an output's shape depends on, in one object (:meth:`of` a robot): the
    velocity coordinates (``dof``: the joints, and 6 for a floating base), the actuated joints,
    the base parameters (0 when not derived), the task's rows and the frames."""

    dof: int
    actuated: int | None = None
    base_parameters: int = 0
    #: rows of the task (the task-space functions' M): 6 for the tool's pose (the default)
    task: int = 6
    #: frames of the frame functions (``frames:``)
    frames: int = 0
    #: entries of q (``dof`` but for a floating base, whose quaternion has 4; None: ``dof``)
    configuration: int | None = None
    #: rows of the contact constraints (``contacts:``: 3 per point, 6 per sole): the forces' entries
    contacts: int = 0

    @classmethod
    def of(cls, robot, base_parameters: int = 0) -> "Dimensions":
        """The sizes of a serial robot's outputs (``base_parameters``: how many the derivation
        found, for the base regressor)."""
        return cls(robot.nv, len(robot.actuated_joints), base_parameters, len(robot.task_rows), len(robot.frames),
                   robot.nq, getattr(robot, "contact_rows", 0))

    @property
    def na(self) -> int:
        return self.dof if self.actuated is None else self.actuated

    @property
    def nq(self) -> int:
        return self.dof if self.configuration is None else self.configuration


@dataclass(frozen=True)
class OutputArgument:
    """One output argument of a generated function: its name (C and CasADi), what it holds and
    which columns of the output matrix it is (``first``, ``end``; ``end`` None: to the last)."""

    name: str
    doc: str
    first: int = 0
    end: int | None = None

    @property
    def whole(self) -> bool:
        return self.first == 0 and self.end is None

    def shape(self, full: tuple[int, int]) -> tuple[int, int]:
        """Rows and columns of this argument's block of an output of shape ``full``."""
        rows, cols = full
        end = cols if self.end is None else self.end
        return rows, max(0, end - self.first)


@dataclass(frozen=True)
class Family:
    """A family of outputs: what the generated header groups them under, and which robots have
    them (``trees``: kinematic trees and floating bases too; ``floating``: floating bases too)."""

    name: str
    title: str
    trees: bool = False
    floating: bool = False


#: the families of outputs, in the order the documentation lists them
FAMILIES: dict[str, Family] = {f.name: f for f in (
    Family("dynamics", "joint-space dynamics", trees=True, floating=True),
    Family("tool", "the tool frame's kinematics"),
    Family("reaction", "the base reaction of a chain with passive joints"),
    Family("identification", "identification"),
    Family("task", "task-space dynamics of the tool"),
    Family("derivatives", "derivatives of the dynamics", trees=True, floating=True),
    Family("frames", "the frames' kinematics", trees=True, floating=True),
    Family("contact", "contact dynamics: the contacts held by the ground", trees=True, floating=True),
    Family("centroidal", "centre of mass and centroidal momentum", trees=True, floating=True),
    Family("configuration", "the configuration space: integrate, difference and their Jacobians", trees=True,
           floating=True),
    Family("platform", "a platform robot's functions (kind: parallel, by the natural orthogonal complement)"),
)}

#: the letters the documentation writes each size with (``shape_text``)
_SIZE_LETTERS = Dimensions(*sp.symbols("N NA NB M K NQ NC", positive=True, integer=True))


@dataclass(frozen=True)
class OutputSpec:
    """One output symdyn can derive and generate: everything about it is here, and every
    consumer (derivation, emission, the compiled library, numpy and CasADi evaluation, timing,
    verify, the fuzzer, ``--functions`` and README's table) reads it from here.

    ``shape`` maps :class:`Dimensions` to (rows, columns) of the output matrix (a vector is
    one column, whatever the robot); ``arguments`` are the output arguments it is written to
    (most outputs one, the reaction map two); ``family`` one of :data:`FAMILIES`;
    ``derivation`` the key of the function that derives it (``symdyn.derive.equations``; by
    default its own name: outputs derived together share one); ``requires`` lists outputs its
    derivation or emission needs derived beside it; ``status`` documents the return value of
    the function that checks its inputs (and solves with the mass matrix), formatted with
    ``rtol``, ``real`` and ``prefix`` (empty: none); ``meaning`` and ``pinocchio`` are README's
    table (what it is, and Pinocchio's equivalent, which the references compute it with).
    """

    name: str
    symbol: str
    family: str
    inputs: tuple[str, ...]
    shape: Callable[[Dimensions], tuple[int, int]]
    units: str
    summary: str
    arguments: tuple[OutputArgument, ...]
    meaning: str
    pinocchio: str
    derivation: str = ""
    default: bool = True
    requires: tuple[str, ...] = ()
    symmetric: bool = False
    status: str = ""
    #: summaries and statuses that replace the above for another forward-dynamics method
    fd_variants: tuple[tuple[str, str, str], ...] = ()
    #: what the comparison with a reference measures small values of this output against
    #: (symdyn.check.agreement.robot_floors): "torque" (the robot's torques: outputs in N m or N,
    #: or per rad), "torque_per_rate" (outputs in N m s), "drift" (an acceleration bias J-dot qd:
    #: the output ``floor_jacobian``, its Jacobian, times the joint rates squared), "own" (the
    #: output's own values)
    floor_scale: str = "own"
    floor_jacobian: str = ""

    def __post_init__(self):
        if self.family not in FAMILIES:
            raise ValueError(f"{self.name}: unknown family {self.family!r}")
        if self.floor_scale not in ("own", "torque", "torque_per_rate", "drift"):
            raise ValueError(f"{self.name}: unknown floor scale {self.floor_scale!r}")
        if (self.floor_scale == "drift") != bool(self.floor_jacobian):
            raise ValueError(f"{self.name}: a drift floor names its Jacobian (floor_jacobian), and only it")
        if not self.derivation:
            object.__setattr__(self, "derivation", self.name)

    @property
    def kinematic(self) -> bool:
        """Whether it is about the tool frame (the joint-space outputs are not)."""
        return self.family == "tool"

    @property
    def shape_text(self) -> str:
        """The shape as the documentation writes it: ``N x N``, ``6``, ``6 x (1 + NA)``..."""
        rows, cols = (sp.sympify(e) for e in self.shape(_SIZE_LETTERS))
        text = [_size_text(rows)] + ([] if cols == 1 else [_size_text(cols)])
        return " x ".join(text)

    @property
    def is_vector(self) -> bool:
        """Whether the output is a vector (one column whatever the robot), not a matrix that
        may have one column (the Jacobian of a one-joint robot is 6 x 1, still a matrix)."""
        return sp.sympify(self.shape(_SIZE_LETTERS)[1]) == 1

    def summary_for(self, fd_method: str = "") -> str:
        return next((s for m, s, _ in self.fd_variants if m == fd_method), self.summary)

    def status_for(self, fd_method: str = "") -> str:
        return next((s for m, _, s in self.fd_variants if m == fd_method), self.status)

    def argument_shapes(self, dims: Dimensions) -> list[tuple[OutputArgument, tuple[int, int]]]:
        full = self.shape(dims)
        return [(arg, arg.shape(full)) for arg in self.arguments]


def _size_text(size) -> str:
    """A size in the documentation's letters: ``13 N``, ``(1 + NA)``, ``4 K``."""
    if size.is_Add:
        constant, rest = size.as_coeff_Add()
        return f"({int(constant)} + {_size_text(rest)})" if constant else str(size)
    return str(size).replace("*", " ")


@dataclass(frozen=True)
class CombinedSpec:
    """A generated function that writes several outputs in one call, sharing their intermediate
    quantities; emitted beside the single ones when all its parts are generated."""

    name: str
    parts: tuple[str, ...]
    summary: str

    @property
    def inputs(self) -> tuple[str, ...]:
        """The inputs of all its parts, in the order of :data:`INPUT_GROUPS`."""
        wanted = {group for part in self.parts for group in REGISTRY[part].inputs}
        return tuple(group for group in INPUT_GROUPS if group in wanted)


#: the status codes of the functions that check their inputs and solve with the mass matrix, as
#: the generated header names them (``NAME_<code>``, NAME in capitals): value and meaning
STATUS_CODES: dict[str, tuple[int, str]] = {
    "OK": (0, "success: every output written"),
    "SINGULAR": (1, "the mass matrix M = D + diag(armature) is singular at q: a pivot of its factorization is not "
                    "above NAME_PIVOT_RTOL times its diagonal entry (the articulated-body algorithm: an articulated "
                    "inertia is not positive)"),
    "NOT_FINITE": (2, "an input is NaN or infinite, or a result is not finite (NaN, or beyond the range of the "
                      "scalar type)"),
    "TASK_SINGULAR": (3, "the task is singular at q: a pivot of the factorization of J M^-1 J^T is not above "
                         "NAME_TASK_RTOL times its diagonal entry"),
    "CONTACT_SINGULAR": (3, "the contacts' constraints are dependent at q: a pivot of the factorization of "
                            "J M^-1 J^T (J: the contacts' rows) is not above NAME_CONTACT_RTOL times its diagonal entry"),
}

_PIVOTS = ("Returns {{prefix}}_OK (0) on success; {{prefix}}_SINGULAR (1) when the mass matrix is singular at q ({why}); "
           "{{prefix}}_NOT_FINITE (2) when an input is NaN or infinite, or a result is not finite (NaN or beyond the "
           "range of {{real}}). On a nonzero return qdd is not written.")
_ABA_PIVOTS = _PIVOTS.format(why="an articulated inertia d_j about joint j's axis, by which the algorithm divides, is "
                                 "not positive, or is not a number")

_TASK_STATUS = ("Returns {prefix}_OK (0) on success; {prefix}_SINGULAR (1) when the mass matrix is singular at q (a "
                "pivot of its LDL^T factorization is not above {prefix}_PIVOT_RTOL, {rtol:g} unless defined, times its "
                "diagonal entry, or is not a number); {prefix}_NOT_FINITE (2) when an input is NaN or infinite, or a "
                "result is not finite (NaN or beyond the range of {real}); {prefix}_TASK_SINGULAR (3) when the task is "
                "singular at q: a pivot of the LDL^T factorization of J M^-1 J^T (the inverse of Lambda) is not "
                "above {prefix}_TASK_RTOL times its diagonal entry (a kinematic singularity, or a task direction "
                "the joints cannot move the tool in). On a nonzero return nothing is written.")
_INVERSE_STATUS = ("Returns {prefix}_OK (0) on success; {prefix}_SINGULAR (1) when the mass matrix is singular at q (a "
                   "pivot of its LDL^T factorization is not above {prefix}_PIVOT_RTOL, {rtol:g} unless defined, times its "
                   "diagonal entry, or is not a number); {prefix}_NOT_FINITE (2) when an input is NaN or infinite, or a "
                   "result is not finite (NaN or beyond the range of {real}). On a nonzero return nothing is written.")

_CONTACT_STATUS = ("Returns {prefix}_OK (0) on success; {prefix}_SINGULAR (1) when the mass matrix is singular at q (a "
                   "pivot of its factorization is not above {prefix}_PIVOT_RTOL, {rtol:g} unless defined, times its "
                   "diagonal entry, or is not a number); {prefix}_NOT_FINITE (2) when an input is NaN or infinite, or a "
                   "result is not finite (NaN or beyond the range of {real}); {prefix}_CONTACT_SINGULAR (3) when the "
                   "contacts' constraints are dependent at q: a pivot of the factorization of J M^-1 J^T is not above "
                   "{prefix}_CONTACT_RTOL times its diagonal entry (two soles, or three point contacts, on one body: "
                   "more rows than its six motions; legs that cannot move their feet apart). On a nonzero return "
                   "nothing is written.")
#: what the contact outputs are derived from
_CONTACT_ID_STATUS = ("Returns {prefix}_OK (0) on success; {prefix}_NOT_FINITE (2) when an input is NaN or infinite, "
                      "or a result is not finite (NaN or beyond the range of {real}); {prefix}_CONTACT_SINGULAR (3) "
                      "when the contacts cannot push the base in every direction at q: a pivot of the QR of J_u is not "
                      "above {prefix}_CONTACT_RTOL times its column's squared norm (fewer than six independent "
                      "wrenches: one or two point feet, or feet on a line). On a nonzero return nothing is written.")

_CONTACT_REQUIRES = ("mass_matrix", "coriolis", "gravity", "frame_poses", "frame_jacobians", "frame_jacobian_dot_v")

#: what the task-space outputs are derived from
_TASK_REQUIRES = ("mass_matrix", "coriolis", "gravity", "jacobian", "jacobian_dot_qd")
_TASK_UNITS = "kg, kg m or kg m^2 (rows: N and N m per m/s^2 and rad/s^2)"

SPECS: tuple[OutputSpec, ...] = (
    OutputSpec(
        name="inverse_dynamics", symbol="tau", family="dynamics", inputs=("q", "qd", "qdd"),
        shape=lambda d: (d.dof, 1), units="N m or N",
        summary="Inverse dynamics: torques that produce accelerations qdd at state (q, qd) (recursive Newton-Euler when derived by it).",
        arguments=(OutputArgument("tau", "joint torques/forces tau = D qdd + h + c + armature qdd + damping qd + coulomb sign(qd), N (N m or N)"),),
        meaning="τ(q, q̇, q̈) incl. armature and friction",
        pinocchio="`rnea` + friction terms",
        floor_scale="torque"),
    OutputSpec(
        name="mass_matrix", symbol="D", family="dynamics", inputs=("q",),
        shape=lambda d: (d.dof, d.dof), units="kg m^2, kg m or kg",
        summary="Mass (joint-space inertia) matrix D(q), without armature.",
        arguments=(OutputArgument("D", "joint-space inertia matrix D(q), N*N row-major, symmetric (kg m^2, kg m or kg)"),),
        meaning="D(q)",
        pinocchio="`crba` (armature 0)",
        symmetric=True),
    OutputSpec(
        name="coriolis", symbol="h", family="dynamics", inputs=("q", "qd"),
        shape=lambda d: (d.dof, 1), units="N m or N",
        summary="Coriolis and centrifugal torques h(q, qd).",
        arguments=(OutputArgument("h", "Coriolis and centrifugal vector h(q, qd) = C(q, qd) qd, N (N m or N)"),),
        meaning="h(q, q̇) = C q̇",
        pinocchio="`nonLinearEffects − computeGeneralizedGravity`",
        floor_scale="torque"),
    OutputSpec(
        name="coriolis_matrix", symbol="C", family="dynamics", inputs=("q", "qd"),
        shape=lambda d: (d.dof, d.dof), units="N m s or N s",
        summary="Coriolis matrix C(q, qd), C qd = h.",
        arguments=(OutputArgument("C", "Coriolis matrix C(q, qd) from the Christoffel symbols of D, N*N row-major (dD/dt - 2C is skew-symmetric)"),),
        meaning="C(q, q̇), Christoffel symbols of D",
        pinocchio="`computeCoriolisMatrix`",
        floor_scale="torque_per_rate"),
    OutputSpec(
        name="gravity", symbol="c", family="dynamics", inputs=("q",),
        shape=lambda d: (d.dof, 1), units="N m or N",
        summary="Gravity torques c(q).",
        arguments=(OutputArgument("c", "gravity vector c(q), N (N m or N)"),),
        meaning="c(q)",
        pinocchio="`computeGeneralizedGravity`",
        floor_scale="torque"),
    OutputSpec(
        name="forward_dynamics", symbol="qdd", family="dynamics", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.dof, 1), units="rad/s^2 or m/s^2",
        summary="Forward dynamics: accelerations for torques tau at state (q, qd), by an LDL^T factorization unrolled for this robot (no inverse, at most one division per joint).",
        arguments=(OutputArgument("qdd", "joint accelerations solving (D + diag(armature)) qdd = tau - h - c - damping qd - coulomb sign(qd), N"),),
        meaning="q̈(q, q̇, τ)",
        pinocchio="`aba`",
        requires=("mass_matrix",),
        status=_PIVOTS.format(why="a pivot d_j of its LDL^T factorization is not above {prefix}_PIVOT_RTOL, {rtol:g} "
                                  "unless defined, times its diagonal entry, or is not a number"),
        fd_variants=(("aba", "Forward dynamics: accelerations for torques tau at state (q, qd), by the articulated-body "
                             "algorithm written out for this robot (three sweeps, at most one division per joint, no mass matrix).",
                      _ABA_PIVOTS),
                     ("aba-loops", "Forward dynamics: accelerations for torques tau at state (q, qd), by the articulated-body "
                                   "algorithm as three loops over the joints (one joint's step derived once for this chain, "
                                   "what differs between its joints read from a constant table: the code does not grow with "
                                   "the joints; at most one division per joint, no mass matrix).",
                      _ABA_PIVOTS))),
    OutputSpec(
        name="forward_kinematics", symbol="T", family="tool", inputs=("q",),
        shape=lambda d: (4, 4), units="m",
        summary="Forward kinematics: pose of the tool frame in the world (base placement * chain * tool).",
        arguments=(OutputArgument("T", "pose of the tool frame in the world, 4*4 row-major homogeneous transform [R p; 0 0 0 1] (p in m)"),),
        meaning="tool pose T(q) in the world",
        pinocchio="`framesForwardKinematics`, `oMf`",
        derivation="tool"),
    OutputSpec(
        name="jacobian", symbol="J", family="tool", inputs=("q",),
        shape=lambda d: (6, d.dof), units="m/s and rad/s per unit qd",
        summary="Geometric Jacobian of the tool frame: [v; omega] = J qd, world axes.",
        arguments=(OutputArgument("J", "tool Jacobian, 6*N row-major, world axes at the tool origin (Pinocchio's LOCAL_WORLD_ALIGNED): rows 0-2 map qd to the tool origin's linear velocity (m/s), rows 3-5 to the angular velocity (rad/s)"),),
        meaning="tool Jacobian J(q), world axes (linear rows first)",
        pinocchio="`getFrameJacobian`, `LOCAL_WORLD_ALIGNED`",
        derivation="tool"),
    OutputSpec(
        name="jacobian_dot_qd", symbol="a", family="tool", inputs=("q", "qd"),
        shape=lambda d: (6, 1), units="m/s^2 and rad/s^2",
        summary="J-dot qd: the tool's acceleration bias, so that [a; alpha] = J qdd + J-dot qd (classical acceleration), world axes.",
        arguments=(OutputArgument("a", "J-dot times qd, 6: the tool origin's classical linear acceleration (m/s^2, rows 0-2) and angular acceleration (rad/s^2, rows 3-5) at qdd = 0, world axes"),),
        meaning="J̇ q̇: the tool's classical acceleration at q̈ = 0",
        pinocchio="`getFrameClassicalAcceleration`",
        derivation="tool", floor_scale="drift", floor_jacobian="jacobian"),
    OutputSpec(
        name="reaction_map", symbol="k0_D", family="reaction", inputs=("q", "qd"),
        shape=lambda d: (6, 1 + d.na), units="N m and N",
        summary="Force-to-torque map (the note 'Force to Torque - Articulated Body Mapping Analysis', eqs. 5-14): the wrench the base exerts on body 1 through joint 1 is [n; f] = k0 + D tau_H, affine in the actuated joints' torques tau_H with the passive joints' torques zero; derived from the articulated-body recursion (k0 at tau = 0, D's columns X_1^T A_1 ... X_j^T b_j).",
        arguments=(OutputArgument("k0", "base wrench at zero actuated torques, 6: [n; f], the moment (N m, about the base origin) "
                              "and force (N) the base exerts on body 1 through joint 1, base-frame axes", 0, 1),
         OutputArgument("D", "wrench per unit actuated torque, 6*NA row-major (column j: actuated joint j in the order "
                             "listed above): [n; f] = k0 + D tau_H", 1, None)),
        meaning="`[k0 \\| D]`: base wrench on body 1 = k0 + D τ_H",
        pinocchio="`aba`, `rnea`, `data.f[1]` in the base frame",
        default=False),
    OutputSpec(
        name="regressor", symbol="Y", family="identification", inputs=("q", "qd", "qdd"),
        shape=lambda d: (d.dof, PARAMETERS_PER_LINK * d.dof), units="N m or N per unit parameter",
        summary="Inverse dynamics in linear form: the regressor Y(q, qd, qdd) with tau = Y pi, pi the standard parameters (13 per link: mass, first moment, inertia about the link origin, armature, viscous and Coulomb friction).",
        arguments=(OutputArgument("Y", "regressor, N*P row-major (P = 13 N standard parameters in the order listed above): tau = Y pi"),),
        meaning="Y(q, q̇, q̈): τ = Y π, 13 standard parameters per link",
        pinocchio="`computeJointTorqueRegressor` (10 per body) + armature and friction columns",
        default=False),
    OutputSpec(
        name="base_regressor", symbol="Yb", family="identification", inputs=("q", "qd", "qdd"),
        shape=lambda d: (d.dof, d.base_parameters), units="N m or N per unit parameter",
        summary="Inverse dynamics in the base parameters: the columns of the regressor that the identifiable combinations beta of the standard parameters multiply, tau = Yb beta.",
        arguments=(OutputArgument("Yb", "base regressor, N*NB row-major (NB base parameters in the order listed above): tau = Yb beta"),),
        meaning="Y_b(q, q̇, q̈): τ = Y_b β in the base parameters",
        pinocchio="Y_b β against `rnea` + friction terms",
        default=False),
    OutputSpec(
        name="task_mass_matrix", symbol="Lambda", family="task", inputs=("q",),
        shape=lambda d: (d.task, d.task), units=_TASK_UNITS,
        summary="Task-space mass matrix M_x = Lambda = (J M^-1 J^T)^-1 of the tool (J: the task's rows of NAME_jacobian, M = D + "
        "diag(armature)); for a square, regular J it equals J^-T M J^-1.",
        arguments=(OutputArgument("Lambda", "task-space mass matrix Lambda, M*M row-major, symmetric (M task rows, as listed "
                                  "above): F = Lambda xdd + mu + Gx"),),
        meaning="Λ = M_x = (J M⁻¹ Jᵀ)⁻¹ for the task's m rows of the tool Jacobian",
        pinocchio="inverse of `getFrameJacobian` · `computeMinverse` · Jᵀ",
        derivation="task",
        default=False,
        requires=_TASK_REQUIRES,
        symmetric=True,
        status=_TASK_STATUS),
    OutputSpec(
        name="task_bias", symbol="mu", family="task", inputs=("q", "qd"),
        shape=lambda d: (d.task, 1), units="N or N m",
        summary="Task-space Coriolis and centrifugal force V_x = mu = Lambda (J M^-1 h - J-dot qd) of the tool (friction not included).",
        arguments=(OutputArgument("mu", "task-space Coriolis and centrifugal force mu = V_x, M (N for linear rows, N m for angular ones)"),),
        meaning="V_x = μ = Λ (J M⁻¹ h − J̇ q̇)",
        pinocchio="the same from `nonLinearEffects`, `getFrameClassicalAcceleration`",
        derivation="task",
        default=False,
        requires=_TASK_REQUIRES,
        status=_TASK_STATUS),
    OutputSpec(
        name="task_gravity", symbol="Gx", family="task", inputs=("q",),
        shape=lambda d: (d.task, 1), units="N or N m",
        summary="Task-space gravity force G_x = Lambda J M^-1 c of the tool (= J^-T c for a square J).",
        arguments=(OutputArgument("Gx", "task-space gravity force G_x, M (N for linear rows, N m for angular ones)"),),
        meaning="G_x = Λ J M⁻¹ c",
        pinocchio="the same from `computeGeneralizedGravity`",
        derivation="task",
        default=False,
        requires=_TASK_REQUIRES,
        status=_TASK_STATUS),
    OutputSpec(
        name="task_inverse", symbol="Jbar", family="task", inputs=("q",),
        shape=lambda d: (d.dof, d.task), units="(rad/s or m/s) per (m/s or rad/s)",
        summary="Dynamically consistent inverse of the task Jacobian, Jbar = M^-1 J^T Lambda: the null-space projector "
        "of joint torques is 1 - J^T Jbar^T.",
        arguments=(OutputArgument("Jbar", "dynamically consistent inverse Jbar = M^-1 J^T Lambda, N*M row-major: tau = J^T F "
                                "+ (1 - J^T Jbar^T) tau0 leaves the tool's acceleration to F"),),
        meaning="J̄ = M⁻¹ Jᵀ Λ, the dynamically consistent inverse",
        pinocchio="`computeMinverse`, `getFrameJacobian`",
        derivation="task",
        default=False,
        requires=_TASK_REQUIRES,
        status=_TASK_STATUS),
    OutputSpec(
        name="inverse_dynamics_dq", symbol="dtau_dq", family="derivatives", inputs=("q", "qd", "qdd"),
        shape=lambda d: (d.dof, d.dof), units="N m or N per rad or m",
        summary="Derivative of inverse dynamics by the joint positions, dtau/dq (Pinocchio's computeRNEADerivatives), by forward-mode differentiation of the Newton-Euler recursion.",
        arguments=(OutputArgument("dtau_dq", "dtau/dq, N*N row-major: row i = tau_i, column j = q_j"),),
        meaning="∂τ/∂q (a floating base's along q ⊕ δv, Pinocchio's tangent space)",
        pinocchio="`computeRNEADerivatives`",
        derivation="inverse_dynamics_derivatives",
        default=False,
        floor_scale="torque"),
    OutputSpec(
        name="inverse_dynamics_dqd", symbol="dtau_dqd", family="derivatives", inputs=("q", "qd", "qdd"),
        shape=lambda d: (d.dof, d.dof), units="N m s or N s per rad or m",
        summary="Derivative of inverse dynamics by the joint velocities, dtau/dqd, viscous friction included (Coulomb friction's derivative is zero away from qd = 0, and is left out); dtau/dqdd is the mass matrix plus the armature.",
        arguments=(OutputArgument("dtau_dqd", "dtau/dqd, N*N row-major: row i = tau_i, column j = qd_j (viscous damping on the diagonal)"),),
        meaning="∂τ/∂q̇, viscous damping included",
        pinocchio="`computeRNEADerivatives`",
        derivation="inverse_dynamics_derivatives",
        default=False,
        floor_scale="torque_per_rate"),
    OutputSpec(
        name="gravity_derivative", symbol="dc_dq", family="derivatives", inputs=("q",),
        shape=lambda d: (d.dof, d.dof), units="N m or N per rad or m",
        summary="Derivative of the gravity torques, dc/dq (gravity compensation gains, static stiffness; Pinocchio's computeGeneralizedGravityDerivatives), by forward-mode differentiation of c's recursion.",
        arguments=(OutputArgument("dc_dq", "derivative of the gravity vector, N*N row-major: row i = c_i, column j = q_j"),),
        meaning="∂c/∂q (a floating base's along q ⊕ δv)",
        pinocchio="`computeGeneralizedGravityDerivatives`",
        default=False,
        floor_scale="torque"),
    OutputSpec(
        name="mass_matrix_inverse", symbol="Minv", family="derivatives", inputs=("q",),
        shape=lambda d: (d.dof, d.dof), units="1/(kg m^2), 1/(kg m) or 1/kg",
        summary="Inverse of the mass matrix with armature, (D + diag(armature))^-1 (Pinocchio's computeMinverse), from the LDL^T factorization forward dynamics uses (no general inverse).",
        arguments=(OutputArgument("Minv", "inverse mass matrix (D + diag(armature))^-1, N*N row-major, symmetric"),),
        meaning="M⁻¹ = (D + diag(armature))⁻¹, with a status (singular M)",
        pinocchio="`computeMinverse`",
        derivation="inverse",
        default=False,
        symmetric=True,
        status=_INVERSE_STATUS),
    OutputSpec(
        name="forward_dynamics_dq", symbol="dqdd_dq", family="derivatives", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.dof, d.dof), units="rad/s^2 or m/s^2 per rad or m",
        summary="Derivative of forward dynamics by the joint positions, dqdd/dq = -M^-1 dtau/dq at qdd = forward_dynamics(q, qd, tau) (Pinocchio's computeABADerivatives).",
        arguments=(OutputArgument("dqdd_dq", "dqdd/dq, N*N row-major: row i = qdd_i, column j = q_j"),),
        meaning="∂q̈/∂q, with a status (a floating base's along q ⊕ δv)",
        pinocchio="`computeABADerivatives`",
        derivation="inverse",
        default=False,
        status=_INVERSE_STATUS),
    OutputSpec(
        name="forward_dynamics_dqd", symbol="dqdd_dqd", family="derivatives", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.dof, d.dof), units="rad/s^2 or m/s^2 per rad/s or m/s",
        summary="Derivative of forward dynamics by the joint velocities, dqdd/dqd = -M^-1 dtau/dqd at qdd = forward_dynamics(q, qd, tau), viscous friction included (Coulomb friction's derivative is zero away from qd = 0); dqdd/dtau is NAME_mass_matrix_inverse.",
        arguments=(OutputArgument("dqdd_dqd", "dqdd/dqd, N*N row-major: row i = qdd_i, column j = qd_j"),),
        meaning="∂q̈/∂q̇, with a status",
        pinocchio="`computeABADerivatives`",
        derivation="inverse",
        default=False,
        status=_INVERSE_STATUS),
    OutputSpec(
        name="frame_poses", symbol="T", family="frames", inputs=("q",),
        shape=lambda d: (4 * d.frames, 4), units="m",
        summary="Poses of the frames listed above in the world, each a homogeneous transform (Pinocchio's framesForwardKinematics, oMf).",
        arguments=(OutputArgument("T", "poses of the K frames in the world, K*4*4 row-major: frame k's [R p; 0 0 0 1] at T + 16 k (p in m)"),),
        meaning="the poses of the robot's frames in the world",
        pinocchio="`framesForwardKinematics`, `oMf`",
        derivation="frames",
        default=False),
    OutputSpec(
        name="frame_jacobians", symbol="J", family="frames", inputs=("q",),
        shape=lambda d: (6 * d.frames, d.dof), units="m/s and rad/s per unit qd",
        summary="Geometric Jacobians of the frames listed above, world axes at each frame's origin (Pinocchio's getFrameJacobian, LOCAL_WORLD_ALIGNED).",
        arguments=(OutputArgument("J", "frame Jacobians, K*6*N row-major: frame k's 6 x N block at J + 6 N k, rows 0-2 map qd to its origin's linear velocity (m/s), rows 3-5 to its angular velocity (rad/s), world axes"),),
        meaning="their Jacobians, world axes at each frame's origin",
        pinocchio="`getFrameJacobian`, `LOCAL_WORLD_ALIGNED`",
        derivation="frames",
        default=False),
    OutputSpec(
        name="frame_jacobian_dot_v", symbol="a", family="frames", inputs=("q", "qd"),
        shape=lambda d: (6 * d.frames, 1), units="m/s^2 and rad/s^2",
        summary="J-dot qd of each frame listed above: its classical acceleration at zero accelerations, world axes (Pinocchio's getFrameClassicalAcceleration, LOCAL_WORLD_ALIGNED).",
        arguments=(OutputArgument("a", "J-dot times qd, K*6: frame k's origin's classical linear acceleration (m/s^2) then its angular acceleration (rad/s^2) at qdd = 0, at a + 6 k, world axes"),),
        meaning="their J̇ q̇ (classical accelerations at q̈ = 0)",
        pinocchio="`getFrameClassicalAcceleration`",
        derivation="frames", floor_scale="drift", floor_jacobian="frame_jacobians",
        default=False),
    OutputSpec(
        name="contact_accelerations", symbol="qdd", family="contact", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.dof, 1), units="rad/s^2 or m/s^2",
        summary="The accelerations of the constrained system with the contacts listed above held: M qdd = tau - h - c "
                "- friction + J^T lambda with J qdd + gamma = 0 (J: the contacts' rows of their frames' Jacobians, "
                "gamma their J-dot qd: a point's classical acceleration, a sole's spatial one, as Pinocchio's "
                "constraintDynamics; plus kd v + kp (p - reference) for a point with a Baumgarte correction, as "
                "listed above), by the factorization of M and a QR of the whitened J (M^-1 and J M^-1 J^T are "
                "not formed).",
        arguments=(OutputArgument("qdd", "accelerations of the constrained system, N"),),
        meaning="q̈ of [M Jᵀ; J 0][q̈; −λ] = [τ − h − c; −γ]", pinocchio="`constraintDynamics`",
        derivation="contact", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="contact_forces", symbol="lambda", family="contact", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.contacts, 1), units="N, N m",
        summary="The contact forces lambda of the constrained system (see NAME_contact_accelerations): contact by "
                "contact as listed above, each its force on the robot at the frame's origin in world-aligned axes "
                "(Pinocchio's LOCAL_WORLD_ALIGNED: 3 entries for a point, force then moment for a sole), so that "
                "M qdd = tau - h - c - friction + J^T lambda.",
        arguments=(OutputArgument("lambda", "contact forces, NC: contact k's force (N) and, for a sole, moment (N m) "
                                            "on the robot, world axes at its frame's origin"),),
        meaning="λ: the contacts' forces on the robot", pinocchio="`data.lambda_c` of `constraintDynamics`",
        derivation="contact", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="contact_accelerations_dq", symbol="dqdd_dq", family="contact", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.dof, d.dof), units="rad/s^2 or m/s^2 per rad or m",
        summary="Derivative of the constrained accelerations (NAME_contact_accelerations) by the joint positions "
                "(a floating base's along q (+) dv, Pinocchio's computeConstraintDynamicsDerivatives): the implicit "
                "function theorem on ID(q, qd, qdd) - J^T lambda = tau, J qdd + gamma = 0, differentiated at the "
                "solution and solved with the blocks of the constrained system's inverse.",
        arguments=(OutputArgument("dqdd_dq", "dqdd/dq, N*N row-major: row i = qdd_i, column j = q_j"),),
        meaning="∂q̈/∂q of the constrained system", pinocchio="`ddq_dq` of `computeConstraintDynamicsDerivatives`",
        derivation="contact_derivatives", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="contact_accelerations_dqd", symbol="dqdd_dqd", family="contact", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.dof, d.dof), units="rad/s^2 or m/s^2 per rad/s or m/s",
        summary="Derivative of the constrained accelerations by the joint velocities, viscous friction included "
                "(Coulomb friction's derivative is zero away from qd = 0).",
        arguments=(OutputArgument("dqdd_dqd", "dqdd/dqd, N*N row-major: row i = qdd_i, column j = qd_j"),),
        meaning="∂q̈/∂q̇ of the constrained system", pinocchio="`ddq_dv` of `computeConstraintDynamicsDerivatives`",
        derivation="contact_derivatives", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="contact_accelerations_dtau", symbol="dqdd_dtau", family="contact", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.dof, d.dof), units="1/(kg m^2), 1/(kg m) or 1/kg",
        summary="Derivative of the constrained accelerations by the joint forces: M^-1 - M^-1 J^T (J M^-1 J^T)^-1 J "
                "M^-1, the constrained system's inverse inertia (symmetric).",
        arguments=(OutputArgument("dqdd_dtau", "dqdd/dtau, N*N row-major, symmetric"),),
        meaning="∂q̈/∂τ of the constrained system", pinocchio="`ddq_dtau` of `computeConstraintDynamicsDerivatives`",
        derivation="contact_derivatives", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="contact_forces_dq", symbol="dlambda_dq", family="contact", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.contacts, d.dof), units="N or N m per rad or m",
        summary="Derivative of the contact forces (NAME_contact_forces, world-aligned axes) by the joint positions "
                "(a floating base's along q (+) dv: turning the base turns the forces' axes too).",
        arguments=(OutputArgument("dlambda_dq", "dlambda/dq, NC*N row-major: row i = lambda_i, column j = q_j"),),
        meaning="∂λ/∂q", pinocchio="`dlambda_dq` of `computeConstraintDynamicsDerivatives`",
        derivation="contact_derivatives", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="contact_forces_dqd", symbol="dlambda_dqd", family="contact", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.contacts, d.dof), units="N or N m per rad/s or m/s",
        summary="Derivative of the contact forces by the joint velocities, viscous friction included.",
        arguments=(OutputArgument("dlambda_dqd", "dlambda/dqd, NC*N row-major: row i = lambda_i, column j = qd_j"),),
        meaning="∂λ/∂q̇", pinocchio="`dlambda_dv` of `computeConstraintDynamicsDerivatives`",
        derivation="contact_derivatives", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="contact_forces_dtau", symbol="dlambda_dtau", family="contact", inputs=("q", "qd", "tau"),
        shape=lambda d: (d.contacts, d.dof), units="N or N m per N m or N",
        summary="Derivative of the contact forces by the joint forces: -(J M^-1 J^T)^-1 J M^-1.",
        arguments=(OutputArgument("dlambda_dtau", "dlambda/dtau, NC*N row-major: row i = lambda_i, column j = tau_j"),),
        meaning="∂λ/∂τ", pinocchio="`dlambda_dtau` of `computeConstraintDynamicsDerivatives`",
        derivation="contact_derivatives", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="contact_inverse_torques", symbol="tau", family="contact", inputs=("q", "qd", "qdd"),
        shape=lambda d: (d.dof, 1), units="N m or N",
        summary="Contact inverse dynamics (the whole-body controller's problem): the joint forces that give the "
                "accelerations qdd with a floating base unactuated, tau = ID(q, qd, qdd) - J^T lambda, the contact "
                "forces lambda (NAME_contact_inverse_forces) the least-norm ones that move the base as asked, "
                "J_u^T lambda = ID_u (J_u: the contact rows' six base columns, ID_u: inverse dynamics' base rows), "
                "by a QR of J_u; tau's base entries are zero (a fixed base has none: lambda = 0, tau = ID; passive "
                "joints get the force they would need). The contacts' own accelerations are not constrained: give a "
                "qdd that keeps them held (J qdd + gamma = 0) for a standing robot.",
        arguments=(OutputArgument("tau", "joint forces, N (a floating base's 6 first, zero)"),),
        meaning="τ with the base unactuated, least-norm contact forces", pinocchio="`rnea` − Jᵀλ, λ by least squares",
        derivation="contact_inverse", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_ID_STATUS),
    OutputSpec(
        name="contact_inverse_forces", symbol="lambda", family="contact", inputs=("q", "qd", "qdd"),
        shape=lambda d: (d.contacts, 1), units="N, N m",
        summary="The contact forces of the contact inverse dynamics (see NAME_contact_inverse_torques): the "
                "least-norm lambda with J_u^T lambda = ID_u, laid out as NAME_contact_forces (on the robot, world axes "
                "at each frame's origin).",
        arguments=(OutputArgument("lambda", "contact forces, NC, as NAME_contact_forces"),),
        meaning="λ of the contact inverse dynamics", pinocchio="least squares on `rnea`'s base rows",
        derivation="contact_inverse", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_ID_STATUS),
    OutputSpec(
        name="impulse_velocities", symbol="qd_plus", family="contact", inputs=("q", "qd", "restitution"),
        shape=lambda d: (d.dof, 1), units="rad/s or m/s",
        summary="The velocity just after the contacts listed above close in an impact at velocity qd (Pinocchio's "
                "impulseDynamics): M qd_plus = M qd + J^T impulse with J qd_plus = -restitution J qd, by the same "
                "factorization of M and QR of the whitened constraints as the contact dynamics.",
        arguments=(OutputArgument("qd_plus", "velocity just after the impact, N"),),
        meaning="q̇⁺ of [M Jᵀ; J 0][q̇⁺; −Λ] = [M q̇⁻; −e J q̇⁻]", pinocchio="`impulseDynamics`",
        derivation="impulse", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="impulse_forces", symbol="impulse", family="contact", inputs=("q", "qd", "restitution"),
        shape=lambda d: (d.contacts, 1), units="N s, N m s",
        summary="The contact impulses of that impact (see NAME_impulse_velocities), laid out as the contact forces: "
                "each contact's impulse on the robot, world axes at its frame's origin.",
        arguments=(OutputArgument("impulse", "contact impulses, NC: contact k's (N s; a sole's moment's, N m s) on the "
                                             "robot, world axes at its frame's origin"),),
        meaning="Λ: the contacts' impulses", pinocchio="`data.impulse_c` of `impulseDynamics`",
        derivation="impulse", default=False, requires=_CONTACT_REQUIRES, status=_CONTACT_STATUS),
    OutputSpec(
        name="inverse_dynamics_ext", symbol="tau", family="contact", inputs=("q", "qd", "qdd", "f"),
        shape=lambda d: (d.dof, 1), units="N m or N",
        summary="Inverse dynamics with external forces f at the contacts listed above (each laid out as its contact "
                "force: a point's force, a sole's force then moment, on the robot, world axes at its frame's "
                "origin): tau = ID(q, qd, qdd) - J^T f (Pinocchio's rnea with fext), friction included as in "
                "NAME_inverse_dynamics; dtau/df = -J^T.",
        arguments=(OutputArgument("tau", "joint torques/forces, N, that give qdd with the external forces f applied"),),
        meaning="τ = ID(q, q̇, q̈) − Jᵀ f", pinocchio="`rnea` with `fext`",
        derivation="external", default=False, requires=("inverse_dynamics", "frame_jacobians"),
        floor_scale="torque"),
    OutputSpec(
        name="forward_dynamics_ext", symbol="qdd", family="contact", inputs=("q", "qd", "tau", "f"),
        shape=lambda d: (d.dof, 1), units="rad/s^2 or m/s^2",
        summary="Forward dynamics with external forces f at the contacts listed above (laid out as "
                "NAME_inverse_dynamics_ext's): M qdd = tau + J^T f - h - c - friction (Pinocchio's aba with fext), by "
                "the factorization forward dynamics uses; dqdd/df = M^-1 J^T.",
        arguments=(OutputArgument("qdd", "accelerations under tau and the external forces f, N"),),
        meaning="q̈ of M q̈ = τ + Jᵀ f − h − c", pinocchio="`aba` with `fext`",
        derivation="external", default=False, requires=("mass_matrix", "frame_jacobians"), status=_INVERSE_STATUS),
    OutputSpec(
        name="center_of_mass", symbol="com", family="centroidal", inputs=("q",),
        shape=lambda d: (3, 1), units="m",
        summary="Centre of mass of the whole robot (every link, and a floating base's body) in the world, as Pinocchio's centerOfMass.",
        arguments=(OutputArgument("com", "centre of mass c = sum(m_i c_i) / m in the world, 3 (m)"),),
        meaning="c(q): the whole robot's centre of mass in the world",
        pinocchio="`centerOfMass`",
        derivation="centroidal",
        default=False),
    OutputSpec(
        name="center_of_mass_jacobian", symbol="Jcom", family="centroidal", inputs=("q",),
        shape=lambda d: (3, d.dof), units="m/s per unit qd",
        summary="Jacobian of the centre of mass, c-dot = Jcom qd, world axes (Pinocchio's jacobianCenterOfMass).",
        arguments=(OutputArgument("Jcom", "centre-of-mass Jacobian, 3*N row-major, world axes: c-dot = Jcom qd (m/s)"),),
        meaning="J_c(q), world axes: ċ = J_c q̇",
        pinocchio="`jacobianCenterOfMass`",
        derivation="centroidal",
        default=False),
    OutputSpec(
        name="center_of_mass_bias", symbol="acom", family="centroidal", inputs=("q", "qd"),
        shape=lambda d: (3, 1), units="m/s^2",
        summary="Jcom-dot qd: the centre of mass's acceleration at zero accelerations, so that c-ddot = Jcom qdd + Jcom-dot qd, world axes.",
        arguments=(OutputArgument("acom", "Jcom-dot times qd, 3: the centre of mass's acceleration at qdd = 0 (m/s^2), world axes"),),
        meaning="J̇_c q̇: ċ's rate at q̈ = 0",
        pinocchio="`centerOfMass(q, v, 0)`, `acom`",
        derivation="centroidal", floor_scale="drift", floor_jacobian="center_of_mass_jacobian",
        default=False),
    OutputSpec(
        name="centroidal_momentum_matrix", symbol="Ag", family="centroidal", inputs=("q",),
        shape=lambda d: (6, d.dof), units="kg m/s and kg m^2/s per unit qd",
        summary="Centroidal momentum matrix A_G (Orin's): the momentum about the centre of mass h_G = A_G qd, linear rows first, world axes (Pinocchio's ccrba).",
        arguments=(OutputArgument("Ag", "centroidal momentum matrix, 6*N row-major: rows 0-2 map qd to the linear momentum m c-dot (kg m/s), rows 3-5 to the angular momentum about the centre of mass (kg m^2/s), world axes"),),
        meaning="A_G(q): momentum about the centre of mass h_G = A_G q̇ (linear rows first)",
        pinocchio="`ccrba`, `Ag`",
        derivation="centroidal",
        default=False),
    OutputSpec(
        name="centroidal_bias", symbol="dhg", family="centroidal", inputs=("q", "qd"),
        shape=lambda d: (6, 1), units="N and N m",
        summary="A_G-dot qd: the rate of the centroidal momentum at zero accelerations, so that h_G-dot = A_G qdd + A_G-dot qd, world axes (Pinocchio's computeCentroidalMomentumTimeVariation at zero acceleration).",
        arguments=(OutputArgument("dhg", "A_G-dot times qd, 6: the rate of the linear momentum (N, rows 0-2) and of the angular momentum about the centre of mass (N m, rows 3-5) at qdd = 0, world axes"),),
        meaning="Ȧ_G q̇: ḣ_G at q̈ = 0",
        pinocchio="`computeCentroidalMomentumTimeVariation(q, v, 0)`, `dhg`",
        derivation="centroidal",
        default=False),
    OutputSpec(
        name="kinetic_energy", symbol="Ek", family="dynamics", inputs=("q", "qd"),
        shape=lambda d: (1, 1), units="J",
        summary="Kinetic energy of the bodies and the rotors, Ek = 1/2 qd^T (D(q) + diag(armature)) qd, from D qd "
                "by the Newton-Euler recursion at zero rates (O(n), no mass matrix).",
        arguments=(OutputArgument("Ek", "kinetic energy, 1: 1/2 qd^T (D + diag(armature)) qd (J)"),),
        meaning="E_k(q, q̇) = ½ q̇ᵀ (D + diag(armature)) q̇", pinocchio="`computeKineticEnergy`",
        default=False),
    OutputSpec(
        name="integrate", symbol="q_out", family="configuration", inputs=("q", "v"),
        shape=lambda d: (d.nq, 1), units="m, rad",
        summary="The configuration q (+) v reached from q by the tangent vector v (Pinocchio's integrate): a "
                "floating base moves by SE(3)'s exponential of v's first 6 entries in its own frame (its quaternion "
                "taken as the unit quaternion of q's, the result's in the hemisphere of q's), the joints add.",
        arguments=(OutputArgument("q_out", "q (+) v, NQ, laid out as q (a unit quaternion)"),),
        meaning="q ⊕ v (a floating base by SE(3)'s exponential, the joints add)", pinocchio="`integrate`",
        derivation="configuration", default=False),
    OutputSpec(
        name="integrate_dq", symbol="J_q", family="configuration", inputs=("v",),
        shape=lambda d: (d.dof, d.dof), units="1 (m per m, rad per rad, m per rad)",
        summary="Jacobian of q (+) v by q in the tangent space (Pinocchio's dIntegrate, ARG0): for a floating "
                "base Ad(exp6(v))^-1 on its 6 coordinates, the identity on the joints; it does not depend on q.",
        arguments=(OutputArgument("J_q", "d(q (+) v)/dq, NV*NV row-major: row i = (q (+) v)'s tangent i, column j = "
                                         "q's tangent j"),),
        meaning="∂(q ⊕ v)/∂q in the tangent space", pinocchio="`dIntegrate` (`ARG0`)",
        derivation="configuration", default=False),
    OutputSpec(
        name="integrate_dv", symbol="J_v", family="configuration", inputs=("v",),
        shape=lambda d: (d.dof, d.dof), units="1 (m per m, rad per rad, m per rad)",
        summary="Jacobian of q (+) v by v in the tangent space (Pinocchio's dIntegrate, ARG1): for a floating base "
                "SE(3)'s right Jacobian Jr(v) on its 6 coordinates, the identity on the joints; it does not depend "
                "on q.",
        arguments=(OutputArgument("J_v", "d(q (+) v)/dv, NV*NV row-major: row i = (q (+) v)'s tangent i, column j "
                                         "= v_j"),),
        meaning="∂(q ⊕ v)/∂v", pinocchio="`dIntegrate` (`ARG1`)",
        derivation="configuration", default=False),
    OutputSpec(
        name="difference", symbol="v_out", family="configuration", inputs=("q", "q1"),
        shape=lambda d: (d.dof, 1), units="m, rad",
        summary="The tangent vector q1 (-) q from q to q1, the inverse of integrate (Pinocchio's difference): a "
                "floating base's log6(M^-1 M1), its rotation's angle within [0, pi], the joints subtract.",
        arguments=(OutputArgument("v_out", "q1 (-) q, NV: v with q (+) v = q1"),),
        meaning="q₁ ⊖ q (integrate's inverse)", pinocchio="`difference`",
        derivation="configuration", default=False),
    OutputSpec(
        name="difference_dq0", symbol="J_q0", family="configuration", inputs=("q", "q1"),
        shape=lambda d: (d.dof, d.dof), units="1 (m per m, rad per rad, m per rad)",
        summary="Jacobian of q1 (-) q by q in the tangent space (Pinocchio's dDifference, ARG0): for a floating "
                "base -Jr(log6 M)^-1 Ad(M^-1), M = M^-1 M1, on its 6 coordinates, minus the identity on the joints.",
        arguments=(OutputArgument("J_q0", "d(q1 (-) q)/dq, NV*NV row-major"),),
        meaning="∂(q₁ ⊖ q)/∂q", pinocchio="`dDifference` (`ARG0`)",
        derivation="configuration", default=False),
    OutputSpec(
        name="difference_dq1", symbol="J_q1", family="configuration", inputs=("q", "q1"),
        shape=lambda d: (d.dof, d.dof), units="1 (m per m, rad per rad, m per rad)",
        summary="Jacobian of q1 (-) q by q1 in the tangent space (Pinocchio's dDifference, ARG1): for a floating "
                "base Jr(log6 M)^-1 on its 6 coordinates, the identity on the joints.",
        arguments=(OutputArgument("J_q1", "d(q1 (-) q)/dq1, NV*NV row-major"),),
        meaning="∂(q₁ ⊖ q)/∂q₁", pinocchio="`dDifference` (`ARG1`)",
        derivation="configuration", default=False),
)

#: every output by name, in the order generated code and documentation list them
REGISTRY: dict[str, OutputSpec] = {spec.name: spec for spec in SPECS}

_PHI = "actuator forces (N) or torques (N m), leg by leg"
_TWIST_RATE = "t_dot = [omega_dot; c_ddot] (rad/s^2, m/s^2, world axes)"
_CLOSED_LOOP = "Pinocchio's closed-loop model (symdyn.check.closed_loop)"

#: the functions of a platform robot (kind: parallel: six legs, by the natural orthogonal
#: complement), specs of the same kind as the serial outputs' (their sizes are fixed: six
#: actuated joints; inputs pose[7], twist[6], twist_rate[6], phi[6]; every function returns a
#: status, its codes derived with it, symdyn.derive.parallel)
PLATFORM_SPECS: tuple[OutputSpec, ...] = (
    OutputSpec(
        name="inverse_dynamics", symbol="phi", family="platform", inputs=("pose", "twist", "twist_rate"),
        shape=lambda d: (6, 1), units="N or N m",
        summary="Actuator forces phi (N or N m, leg by leg) that give the platform the twist rate t_dot at state "
                "(pose, t): inverse dynamics.",
        arguments=(OutputArgument("phi", _PHI),),
        meaning="φ(pose, t, ṫ): the actuator forces", pinocchio="`rnea` + constraint Jacobian + LU on " + _CLOSED_LOOP),
    OutputSpec(
        name="forward_dynamics", symbol="twist_rate", family="platform", inputs=("pose", "twist", "phi"),
        shape=lambda d: (6, 2), units="rad/s^2, m/s^2",
        summary="The platform's twist rate t_dot = [omega_dot; c_ddot] and the actuated joints' accelerations qdd "
                "under actuator forces phi at state (pose, t): forward dynamics.",
        arguments=(OutputArgument("twist_rate", _TWIST_RATE, 0, 1),
                   OutputArgument("qdd", "actuated joint accelerations (rad/s^2 or m/s^2), leg by leg", 1, 2)),
        meaning="ṫ and q̈(pose, t, φ)", pinocchio="`constraintDynamics`, `lcaba` on " + _CLOSED_LOOP),
    OutputSpec(
        name="mass_matrix", symbol="M", family="platform", inputs=("pose",),
        shape=lambda d: (6, 6), units="kg m^2, kg m or kg",
        summary="The mass matrix M (6x6, row-major) in actuated coordinates: the kinetic energy is qd^T M qd / 2 "
                "(M = T^T M_M T + sum_J L_J^T I_J L_J, natural orthogonal complement).",
        arguments=(OutputArgument("M", "mass matrix in actuated coordinates, 6x6 row-major (kg m^2, kg m, kg as "
                                       "the joints are)"),),
        meaning="M(pose) in actuated coordinates", pinocchio="G^T `crba` G on " + _CLOSED_LOOP),
    OutputSpec(
        name="twist_map", symbol="T", family="platform", inputs=("pose",),
        shape=lambda d: (6, 6), units="m/s and rad/s per unit qd",
        summary="The twist map T (6x6, row-major): the platform's twist t = T qd for actuated joint rates qd "
                "(T = K^-1).",
        arguments=(OutputArgument("T", "the notes' T, 6x6 row-major: t = T qd"),),
        meaning="T(pose): t = T q̇", pinocchio="K^-1, K from the closures' constraint Jacobian on " + _CLOSED_LOOP),
    OutputSpec(
        name="leg_rate_maps", symbol="L", family="platform", inputs=("pose",),
        shape=lambda d: (36, 6), units="rad/s or m/s per unit qd",
        summary="The leg rate maps L_J for the six legs (6 blocks of 6x6, row-major, leg by leg): leg J's joint "
                "rates are L_J qd.",
        arguments=(OutputArgument("L", "the notes' L_J, leg by leg: 6 blocks of 6x6 row-major (leg J's joint "
                                       "rates = L_J qd)"),),
        meaning="L_J(pose): leg J's joint rates = L_J q̇", pinocchio="each leg's block of the closures' constraint "
                                                                "Jacobian on " + _CLOSED_LOOP),
    OutputSpec(
        name="inverse_kinematics", symbol="q", family="platform", inputs=("pose", "twist"),
        shape=lambda d: (6, 2), units="rad or m, rad/s or m/s",
        summary="The actuated joints' positions q (rad or m) and rates qd at state (pose, t): inverse kinematics "
                "(the closed form of each leg, on the branch of the robot file's home configuration).",
        arguments=(OutputArgument("q", "actuated joint positions (rad or m), leg by leg", 0, 1),
                   OutputArgument("qd", "actuated joint rates (rad/s or m/s), leg by leg", 1, 2)),
        meaning="q, q̇(pose, t) of the actuated joints", pinocchio="Gauss-Newton on each closure (`log6`) on "
                                                                  + _CLOSED_LOOP),
)

#: every platform function by name, in the order generated code and documentation list them
PLATFORM_REGISTRY: dict[str, OutputSpec] = {spec.name: spec for spec in PLATFORM_SPECS}
#: the sizes of every platform robot (six actuated joints)
PLATFORM_DIMENSIONS = Dimensions(6)


def platform_outputs(name: str) -> tuple[tuple[str, int, int], ...]:
    """``(argument, rows, columns)`` of each output argument of platform function ``name``."""
    return tuple((argument.name, rows, cols)
                 for argument, (rows, cols) in PLATFORM_REGISTRY[name].argument_shapes(PLATFORM_DIMENSIONS))

#: functions that write several outputs in one call
COMBINED_SPECS: tuple[CombinedSpec, ...] = (
    CombinedSpec("kinematics", ("forward_kinematics", "jacobian"),
                 "Pose and Jacobian of the tool in one call: the same results as NAME_forward_kinematics and "
                 "NAME_jacobian, sharing their sin/cos and link poses (about half the cost of the two calls)."),
    CombinedSpec("inverse_dynamics_derivatives", ("inverse_dynamics_dq", "inverse_dynamics_dqd"),
                 "Both derivatives of inverse dynamics in one call, dtau/dq and dtau/dqd (as NAME_inverse_dynamics_dq "
                 "and NAME_inverse_dynamics_dqd), sharing the recursion they differentiate."),
    CombinedSpec("forward_dynamics_derivatives", ("forward_dynamics_dq", "forward_dynamics_dqd", "mass_matrix_inverse"),
                 "The derivatives of forward dynamics in one call: dqdd/dq, dqdd/dqd and dqdd/dtau = M^-1 (as "
                 "NAME_forward_dynamics_dq, NAME_forward_dynamics_dqd and NAME_mass_matrix_inverse), sharing one "
                 "factorization of M, the accelerations and the recursion they differentiate."),
    CombinedSpec("integrate_jacobians", ("integrate_dq", "integrate_dv"),
                 "Both Jacobians of integrate in one call, d(q (+) v)/dq and d(q (+) v)/dv (as NAME_integrate_dq and "
                 "NAME_integrate_dv, sharing the angle's functions): what a DDP solver carries derivatives through a "
                 "time step with."),
    CombinedSpec("difference_jacobians", ("difference_dq0", "difference_dq1"),
                 "Both Jacobians of difference in one call, d(q1 (-) q)/dq and d(q1 (-) q)/dq1 (as "
                 "NAME_difference_dq0 and NAME_difference_dq1, sharing log6 and its Jacobian)."),
    CombinedSpec("frame_kinematics", ("frame_poses", "frame_jacobians", "frame_jacobian_dot_v"),
                 "Poses, Jacobians and J-dot qd of the frames in one call: the same results as NAME_frame_poses, "
                 "NAME_frame_jacobians and NAME_frame_jacobian_dot_v, sharing their sin/cos and link poses."),
    CombinedSpec("contact_forward_dynamics", ("contact_accelerations", "contact_forces"),
                 "Contact dynamics in one call: the constrained system's accelerations and the contact forces (as "
                 "NAME_contact_accelerations and NAME_contact_forces), sharing one factorization of M and one QR of "
                 "the whitened constraints: the dynamics of a legged robot standing or walking on the contacts listed "
                 "above."),
    CombinedSpec("contact_forward_dynamics_derivatives",
                 ("contact_accelerations", "contact_forces", "contact_accelerations_dq", "contact_accelerations_dqd",
                  "contact_accelerations_dtau", "contact_forces_dq", "contact_forces_dqd", "contact_forces_dtau"),
                 "Contact dynamics and their derivatives in one call: the constrained accelerations and contact forces "
                 "(as NAME_contact_forward_dynamics) and their derivatives by q, qd and tau (as "
                 "NAME_contact_accelerations_dq ... NAME_contact_forces_dtau), sharing one factorization of M, one QR "
                 "of the whitened constraints and the recursion they differentiate: what a DDP or MPC solver "
                 "linearizes a legged robot's dynamics in contact with."),
    CombinedSpec("contact_inverse_dynamics", ("contact_inverse_torques", "contact_inverse_forces"),
                 "Contact inverse dynamics in one call: the joint forces and the least-norm contact forces that give "
                 "the accelerations qdd with the base unactuated (as NAME_contact_inverse_torques and "
                 "NAME_contact_inverse_forces), sharing the recursion and one QR: a whole-body controller's "
                 "feedforward for a robot standing or walking on the contacts listed above."),
    CombinedSpec("impulse_dynamics", ("impulse_velocities", "impulse_forces"),
                 "An impact in one call: the velocity just after the contacts listed above close and their impulses "
                 "(as NAME_impulse_velocities and NAME_impulse_forces), sharing one factorization of M and one QR of "
                 "the whitened constraints: a foot's touchdown in a walking robot's simulation or MPC."),
    CombinedSpec("task_space", ("task_mass_matrix", "task_bias", "task_gravity", "task_inverse"),
                 "Task-space dynamics of the tool in one call, F = Lambda xdd + mu + Gx: Lambda, mu and Gx as "
                 "NAME_task_mass_matrix, NAME_task_bias and NAME_task_gravity, and Jbar as NAME_task_inverse, "
                 "sharing one factorization of M and one of J M^-1 J^T. A controller applies tau = J^T (Lambda a + mu "
                 "+ Gx) + (1 - J^T Jbar^T) tau0 for a tool acceleration a and a null-space torque tau0."),
)
COMBINED: dict[str, tuple[str, ...]] = {c.name: c.parts for c in COMBINED_SPECS}

#: the standard outputs, in the order generated code and documentation list them
OUTPUTS = tuple(s.name for s in SPECS if s.default)

#: outputs derived and generated only when asked for (``--functions``): the base reaction wrench
#: as an affine map of the actuated torques (the force-to-torque note; by default for a robot with passive joints,
#: ``actuated: false``), and the identification regressors (tau = Y pi, tau = Y_b beta)
EXTRA_OUTPUTS = tuple(s.name for s in SPECS if not s.default)

#: every output symdyn can produce
ALL_OUTPUTS = OUTPUTS + EXTRA_OUTPUTS



def family(name: str) -> tuple[str, ...]:
    """The outputs of a family (:data:`FAMILIES`), in registry order."""
    if name not in FAMILIES:
        raise ValueError(f"unknown family {name!r}")
    return tuple(s.name for s in SPECS if s.family == name)


#: the outputs about the tool frame (the others are joint-space dynamics)
KINEMATIC_OUTPUTS = family("tool")

#: the task-space outputs (derived together; generated when asked for, or when the robot file
#: or scene names a task)
TASK_OUTPUTS = family("task")

#: the inputs each output depends on, in the order of the generated functions' arguments
OUTPUT_INPUTS = {s.name: s.inputs for s in SPECS}

#: the symbol of each output in the notes (and the name of its output argument everywhere)
OUTPUT_SYMBOLS = {s.name: s.symbol for s in SPECS}


def spec(name: str) -> OutputSpec:
    """The spec of an output; a ValueError naming the known ones for anything else."""
    try:
        return REGISTRY[name]
    except KeyError:
        raise ValueError(f"unknown output {name!r}; known: {', '.join(ALL_OUTPUTS)}") from None


#: the outputs of a kinematic tree (links with ``parent:``) or a floating base by default: its
#: joint-space dynamics (the others are about one tool, or written for serial chains)
TREE_OUTPUTS = tuple(s.name for s in SPECS if s.default and FAMILIES[s.family].trees)

#: the centre of mass and the centroidal momentum (derived together; when asked for)
CENTROIDAL_OUTPUTS = family("centroidal")

#: the frame functions (the robot's ``frames:``; by default when it lists frames)
FRAME_OUTPUTS = family("frames")

#: the contact dynamics (the robot's ``contacts:``; derived together, by default when it lists
#: contacts), and the dynamics with external forces at the contacts (inputs f)
CONTACT_OUTPUTS = tuple(s.name for s in SPECS if s.family == "contact" and s.derivation == "contact")
EXTERNAL_OUTPUTS = tuple(s.name for s in SPECS if s.family == "contact" and s.derivation == "external")
IMPULSE_OUTPUTS = tuple(s.name for s in SPECS if s.family == "contact" and s.derivation == "impulse")
#: the derivatives of the contact dynamics by q, qd and tau (when asked for)
CONTACT_DERIVATIVES = tuple(s.name for s in SPECS if s.family == "contact" and s.derivation == "contact_derivatives")
#: the outputs that solve with the contacts' constraints (their status 3 is NAME_CONTACT_SINGULAR)
#: contact inverse dynamics (floating bases; when asked for)
CONTACT_INVERSE = tuple(s.name for s in SPECS if s.family == "contact" and s.derivation == "contact_inverse")
CONTACT_SOLVED = CONTACT_OUTPUTS + IMPULSE_OUTPUTS + CONTACT_DERIVATIVES + CONTACT_INVERSE

#: the derivatives of the dynamics and the inverse mass matrix (when asked for)
DERIVATIVE_OUTPUTS = family("derivatives")

#: integrate, difference and their Jacobians (derived together; when asked for)
CONFIGURATION_OUTPUTS = family("configuration")

#: the derivatives of forward dynamics (-M^-1 dtau/dq and -M^-1 dtau/dqd: the derivatives that
#: are functions of tau)
FORWARD_DERIVATIVES = tuple(name for name in DERIVATIVE_OUTPUTS if "tau" in REGISTRY[name].inputs)

#: the outputs that share the factorization of M and return its status (mass_matrix_inverse and
#: the forward-dynamics derivatives)
INVERSE_OUTPUTS = tuple(name for name in DERIVATIVE_OUTPUTS if REGISTRY[name].status)

#: what a kinematic tree or a floating base can have derived: the outputs of the families trees
#: have (its joint-space dynamics, the derivatives (a floating base's in its tangent space), its frames' kinematics and
#: the whole robot's centre of mass and centroidal momentum)
TREE_AVAILABLE = tuple(s.name for s in SPECS if FAMILIES[s.family].trees)


def returns_status(name: str) -> bool:
    """Whether the generated function ``name`` (an output, or a combined function) returns a
    status and writes nothing on a nonzero one: the task-space functions, the inverse mass
    matrix and the forward-dynamics derivatives (forward dynamics' own status is
    ``NAME_forward_dynamics_checked``'s)."""
    parts = COMBINED.get(name, (name,))
    return name != "forward_dynamics" and all(REGISTRY[part].status for part in parts)


def factors_mass_matrix(name: str) -> bool:
    """Whether the generated function ``name`` (an output, or a combined function) solves with
    the mass matrix (forward dynamics, its derivatives, the inverse mass matrix, the task-space
    functions): the functions precision ``mixed`` computes in double inside."""
    return any(REGISTRY[part].status for part in COMBINED.get(name, (name,)))


def default_outputs(robot) -> tuple[str, ...]:
    """What is derived and generated when nothing is asked for: :data:`OUTPUTS`, the reaction
    map when the robot has passive joints, and the task-space outputs when it names a task;
    for a kinematic tree, :data:`TREE_OUTPUTS`."""
    frames = FRAME_OUTPUTS if getattr(robot, "frames", ()) else ()
    frames += CONTACT_OUTPUTS + IMPULSE_OUTPUTS + EXTERNAL_OUTPUTS if getattr(robot, "contacts", ()) else ()
    if getattr(robot, "is_tree", False):
        return TREE_OUTPUTS + frames
    return (OUTPUTS + (("reaction_map",) if robot.passive_joints else ())
            + (TASK_OUTPUTS if getattr(robot, "task", None) is not None else ()) + frames)


def supported_outputs(robot) -> tuple[str, ...]:
    """Every output ``robot`` can have derived, in :data:`ALL_OUTPUTS`' order (``symdyn verify
    --all`` and the fuzzer check them all): a kinematic tree or floating base has
    :data:`TREE_AVAILABLE` (a floating base's derivatives in its tangent space), a chain every output (the
    reaction map when it has passive joints); the frame functions need frames."""
    names = set(ALL_OUTPUTS)
    if getattr(robot, "is_tree", False):
        names = {s.name for s in SPECS if FAMILIES[s.family].trees and (FAMILIES[s.family].floating or not robot.floating)}
    elif not robot.passive_joints:
        names.discard("reaction_map")
    if not getattr(robot, "frames", ()):
        names -= set(FRAME_OUTPUTS)
    if not getattr(robot, "contacts", ()):
        names -= set(family("contact"))
    return tuple(name for name in ALL_OUTPUTS if name in names)


def function_inputs(name: str) -> tuple[str, ...]:
    """The input groups of a generated function (an output, or a combined function), in order."""
    for combined in COMBINED_SPECS:
        if combined.name == name:
            return combined.inputs
    return spec(name).inputs


def with_requirements(names: Iterable[str]) -> tuple[str, ...]:
    """``names`` and every output they require (transitively), in registry order."""
    wanted = set(names)
    pending = list(wanted)
    while pending:
        for needed in spec(pending.pop()).requires:
            if needed not in wanted:
                wanted.add(needed)
                pending.append(needed)
    return tuple(n for n in ALL_OUTPUTS if n in wanted)


def in_order(names: Iterable[str]) -> tuple[str, ...]:
    """The known outputs among ``names``, in registry order."""
    names = set(names)
    return tuple(n for n in ALL_OUTPUTS if n in names)


def output_shape(name: str, n: int, actuated: int | None = None, base_parameters: int = 0,
                 task: int = 6, frames: int = 0) -> tuple[int, int]:
    """Rows and columns of an output for a robot of ``n`` joints (``actuated`` of them actuated,
    default all; ``base_parameters`` columns of the base regressor; ``task`` rows of the task;
    ``frames`` frames of the frame functions)."""
    return spec(name).shape(Dimensions(n, actuated, base_parameters, task, frames))


def functions_table() -> str:
    """README's table of the outputs, from the registry: each output's name, what it is, its
    shape and Pinocchio's equivalent (the references compute it with), then the combined
    functions."""
    rows = ["| symdyn | meaning | shape | Pinocchio |", "|---|---|---|---|"]
    rows += [f"| `{s.name}` | {s.meaning} | {s.shape_text} | {s.pinocchio} |" for s in SPECS]
    rows += [f"| `{c.name}` | " + ", ".join(f"`{part}`" for part in c.parts) + " in one call (shared work) | | |"
             for c in COMBINED_SPECS]
    return "\n".join(rows) + "\n"


def platform_functions_table() -> str:
    """docs/parallel-dynamics.md's table of the platform functions, from their specs: inputs,
    output arguments with their sizes, what they are, the reference they are checked against."""
    rows = ["| function | inputs | outputs | meaning | checked against |", "|---|---|---|---|---|"]
    rows += [f"| `{s.name}` | {', '.join(s.inputs)} | "
             + ", ".join(f"`{name}[{r * c}]`" for name, r, c in platform_outputs(s.name))
             + f" | {s.meaning} | {s.pinocchio} |" for s in PLATFORM_SPECS]
    return "\n".join(rows) + "\n"


def functions_help() -> str:
    """The ``--functions`` help text of serial robots, from the registry."""
    return (f"comma-separated subset of: {', '.join(ALL_OUTPUTS)} (default: the scene's functions, else "
            f"{', '.join(OUTPUTS)}, reaction_map when the robot has passive joints, the task_* functions when it "
            f"names a task)")
