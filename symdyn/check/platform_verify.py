"""``symdyn verify`` of a platform robot: every generated function compared with Pinocchio's
closed loop (:class:`symdyn.check.closed_loop.ClosedLoopReference`) at seeded random states about
the home pose, and the statuses at states where the functions must refuse.

Numbers: for each function, the normalized error (:func:`symdyn.check.pinocchio_model.normalized_error`:
per output component, its largest difference over the states divided by the RMS of the
reference's values; matrices per row) over the random states where both return 0; the outputs
of a function that writes several arrays are compared side by side.  Statuses: the generated
function and the reference must return the same status at every random state (0 there, for
the reference's ranges) and at the special states :func:`special_states` finds; a function
returning nonzero must leave its outputs unwritten.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..derive.parallel import FUNCTIONS, STATUS
from .closed_loop import ClosedLoopReference, PlatformStatus, pose_vector, rcond
from .pinocchio_model import normalized_error

#: the names of the status codes, by value
STATUS_NAMES = {code: name.upper() for name, code in STATUS.items()}


@dataclass(frozen=True)
class State:
    """The inputs of every platform function at one state (``label`` for special states)."""

    pose: np.ndarray
    twist: np.ndarray
    twist_rate: np.ndarray
    phi: np.ndarray
    label: str = ""

    def arguments(self, function: str) -> list:
        return [getattr(self, name) for name in FUNCTIONS[function][0]]

    def rounded(self, precision: str) -> "State":
        """The state as the generated code of ``precision`` reads it (float: rounded once)."""
        if precision != "float":
            return self
        return State(*(np.asarray(x, dtype=np.float32).astype(float) for x in
                       (self.pose, self.twist, self.twist_rate, self.phi)), self.label)


@dataclass
class PlatformCheck:
    """The outcome: ``errors`` (function -> normalized error, NaN where no state compares),
    ``mismatches`` (function -> texts of the states where the statuses differ or a refusing
    function wrote), ``cases`` (special states: ``(label, reference statuses, generated
    statuses, ok)``, statuses in the order of ``functions``), ``regular`` (random states where
    the reference returns 0 for every function)."""

    functions: tuple
    errors: dict = field(default_factory=dict)
    mismatches: dict = field(default_factory=dict)
    cases: list = field(default_factory=list)
    regular: int = 0

    def function_ok(self, name: str, tolerance: float) -> bool:
        err = self.errors[name]
        return bool(np.isfinite(err) and err <= tolerance and not self.mismatches[name])

    def ok(self, tolerance: float) -> bool:
        return all(self.function_ok(f, tolerance) for f in self.functions) and all(case[3] for case in self.cases)


def random_states(reference: ClosedLoopReference, count: int, seed: int) -> list[State]:
    """Seeded states about the home pose (:meth:`ClosedLoopReference.random_states`); forward
    dynamics' forces are 1.1 times those of the sampled motion (the reference's inverse dynamics),
    so that the platform accelerates otherwise than sampled."""
    states = []
    for p, R, twist, rate in reference.random_states(count, seed):
        pose = pose_vector(p, R)
        status, phi = reference.inverse_dynamics(pose, twist, rate)
        states.append(State(pose, twist, rate, 1.1 * phi if status == 0 else np.zeros(6)))
    return states


def special_states(reference: ClosedLoopReference, precision: str = "double") -> tuple[list[State], list[str]]:
    """States at which the functions must refuse (or not), and notes on the kinds not found: a
    zero quaternion; the platform raised by ten times the legs' length scale (out of reach of
    legs of fixed length); turned about the vertical through its home position to a parallel
    singularity (K singular), found by bisection where det K changes sign; leg 1's U centre put on
    an axis of its base frame through its S centre at its home distance, where that makes leg 1
    (and no other) singular; and a twist whose squares overflow the scalar type."""
    home_p, home_R, length = reference.home_position, reference.home_rotation, reference.length
    zeros = np.zeros(6)
    home = pose_vector(home_p, home_R)
    cases = [State(np.concatenate([home_p, np.zeros(4)]), zeros, zeros, zeros, "zero quaternion"),
             State(pose_vector(home_p + [0.0, 0.0, 10 * length], home_R), zeros, zeros, zeros,
                   f"raised {10 * length:.3g} m above the home pose")]
    notes = []
    found = _parallel_singularity(reference)
    if found is None:
        notes.append("no parallel singularity found turning the platform about the vertical or moving it up or down "
                     "from its home pose: SINGULAR not checked")
    else:
        cases.append(State(found[1], zeros, zeros, zeros, f"{found[0]} (parallel singularity)"))
    leg = _leg_singularity(reference)
    if leg is None:
        notes.append("no serial singularity of leg 1 found on the axes of its base frame: LEG_SINGULAR not checked")
    else:
        cases.append(State(leg[1], zeros, zeros, zeros, f"leg 1's U centre on the {leg[0]} axis of its base frame "
                                                        "(serial singularity)"))
    big = 1e20 if precision == "float" else 1e155
    cases.append(State(home, np.full(6, big), zeros, zeros, f"twist {big:g} at the home pose (the dynamics overflow)"))
    return [case.rounded(precision) for case in cases], notes


def _paths(reference):
    """One-parameter paths from the home pose: ``(describe(s), pose(s), step, end)``."""
    import pinocchio as pin
    home_p, home_R, length = reference.home_position, reference.home_rotation, reference.length

    def turned(angle):
        return pose_vector(home_p, pin.rpy.rpyToMatrix(0.0, 0.0, angle) @ home_R)

    def moved(height):
        return pose_vector(home_p + [0.0, 0.0, height], home_R)
    return [(lambda a: f"turned {np.degrees(a):.6g} deg about the vertical", turned, np.radians(5.0), np.pi),
            (lambda h: f"lowered {-h:.6g} m from the home pose", moved, -0.05 * length, -2 * length),
            (lambda h: f"raised {h:.6g} m from the home pose", moved, 0.05 * length, 2 * length)]


def _parallel_singularity(reference: ClosedLoopReference):
    """``(description, pose)``: the first point of the first path of :func:`_paths` where det K
    changes sign (the loops closing all the way), bisected to where K is singular to the
    reference; None if no path has one."""
    for describe, pose_at, step, end in _paths(reference):
        def det(s, start):
            kin = reference.kinematics(pose_at(s), start)
            return float(np.linalg.det(kin.K)), kin.q
        try:
            low, (d_low, q_low) = 0.0, det(0.0, None)
            for k in range(1, int(round(end / step)) + 1):
                high = k * step
                d_high, q_high = det(high, q_low)
                if np.sign(d_high) != np.sign(d_low):
                    break
                low, d_low, q_low = high, d_high, q_high
            else:
                continue
            for _ in range(60):
                mid = 0.5 * (low + high)
                d_mid, q_mid = det(mid, q_low)
                if np.sign(d_mid) == np.sign(d_low):
                    low, d_low, q_low = mid, d_mid, q_mid
                else:
                    high = mid
            for s in (low, high):
                if rcond(reference.kinematics(pose_at(s), q_low).K) < reference.rtol:
                    return describe(s), pose_at(s)
        except PlatformStatus:  # out of reach, or a leg singular, before any sign change
            continue
    return None


def _leg_singularity(reference: ClosedLoopReference):
    """``(axis name, pose)``: the platform at its home orientation, leg 1's U centre on an axis
    of leg 1's base frame through its S centre at the home distance, where the reference finds
    leg 1 singular and every other leg regular; None where no axis does."""
    from ..derive.parallel_ik import LegIK, LegStructureError
    leg = reference.robot.legs[0]
    try:
        ik = LegIK.of(leg.chain).with_floats()
    except LegStructureError:
        return None
    base = np.array(leg.chain.base_matrix(), dtype=float)
    centre = base[:3, :3] @ np.array(ik.centre_s) + base[:3, 3]
    attach = np.array(leg.attachment.matrix(), dtype=float)
    u_platform = attach[:3, :3] @ np.array(ik.u_in_6) + attach[:3, 3]
    distance = np.linalg.norm(reference.home_position + reference.home_rotation @ u_platform - centre)
    for axis in range(3):
        for sign in (1.0, -1.0):
            p = centre + sign * distance * base[:3, axis] - reference.home_rotation @ u_platform
            pose = pose_vector(p, reference.home_rotation)
            try:
                reference.kinematics(pose)
            except PlatformStatus as status:
                if status.code == "leg_singular" and status.legs == (0,):
                    return f"{'-' if sign < 0 else '+'}{'xyz'[axis]}", pose
    return None


def check_platform(lib, reference: ClosedLoopReference, functions, states: list[State],
                   cases: list[State]) -> PlatformCheck:
    """Compare ``lib`` (a :class:`symdyn.check.cbuild.CompiledPlatform`) with ``reference``."""
    result = PlatformCheck(tuple(functions))
    regular = [True] * len(states)
    statuses = {case.label: ([], [], []) for case in cases}  # reference, generated, problems
    for name in functions:
        mine, theirs, wrong = [], [], []
        for k, state in enumerate(states):
            ours, ref = _call(lib, name, state), _call(reference, name, state)
            problem = _status_problem(ours, ref)
            if problem:
                wrong.append(f"random state {k + 1}: {problem}")
            regular[k] &= ref[0] == 0
            if ours[0] == 0 and ref[0] == 0:
                mine.append(flat_outputs(ours[1:]))
                theirs.append(aligned_reference(name, reference, ours[1:], ref[1:]))
        for case in cases:
            ours, ref = _call(lib, name, case), _call(reference, name, case)
            problem = _status_problem(ours, ref)
            for column, value in zip(statuses[case.label], (ref[0], ours[0], problem)):
                column.append(value)
            if problem:
                wrong.append(f"{case.label}: {problem}")
        result.errors[name] = normalized_error(mine, theirs) if mine else float("nan")
        result.mismatches[name] = wrong
    result.regular = sum(regular)
    result.cases = [(case.label, tuple(statuses[case.label][0]), tuple(statuses[case.label][1]),
                     not any(statuses[case.label][2])) for case in cases]
    return result


def _call(target, name, state: State):
    return getattr(target, name)(*state.arguments(name))


def _status_problem(ours, ref) -> str:
    """What is wrong with the generated function's ``(status, outputs...)`` against the
    reference's status (empty: nothing)."""
    if ours[0] != ref[0]:
        return f"status {ours[0]} ({STATUS_NAMES.get(ours[0], '?')}), the reference's {ref[0]} " \
               f"({STATUS_NAMES.get(ref[0], 'success') if ref[0] else 'success'})"
    if ours[0] and any(np.any(np.asarray(o) != 0) for o in ours[1:]):
        return f"status {ours[0]} but outputs written"
    if not ours[0] and not all(np.all(np.isfinite(o)) for o in ours[1:]):
        return "status 0 with a non-finite output"
    return ""


def flat_outputs(outputs) -> np.ndarray:
    """One output as it is (vector or matrix), several side by side (vectors, concatenated)."""
    if len(outputs) == 1:
        return np.asarray(outputs[0], dtype=float)
    return np.concatenate([np.ravel(o) for o in outputs]).astype(float)


def aligned_reference(name, reference, ours, ref) -> np.ndarray:
    """The reference's outputs, revolute actuated angles of inverse kinematics moved by whole
    turns to the generated ones (an angle is the same modulo 2 pi)."""
    if name == "inverse_kinematics":
        q = np.asarray(ref[0], dtype=float)
        turns = np.round((np.asarray(ours[0], dtype=float) - q) / (2 * np.pi))
        ref = (q + np.where(reference.revolute, 2 * np.pi * turns, 0.0), *ref[1:])
    return flat_outputs(ref)
