"""Differential fuzzing: random robots, every output they support in every target, against
Pinocchio.

A case is drawn from its number, the random seed (:func:`random_case`): a URDF tree (branching at any link,
fixed links with and without mass, revolute, prismatic and continuous joints, axis-aligned and
general axes, rotated inertias written with rpy or as full tensors, damping and friction, rpy
angles written as 1.5707963267948966 or 1.570796327, a fixed or floating base, frames on any
link, fixed ones too) or a Denavit-Hartenberg table (standard or modified, twists written as
numbers, as ``pi/2`` or as 1.5707963267948966, prismatic joints, armature, damping and Coulomb
friction, a tool, passive joints), sometimes behind a scene (a locked joint, a payload whose mass
is a runtime parameter), in double, float or mixed precision, by one of the methods.  Three URDF
trees in ten (those without mimic joints) are read as the MJCF of the same robot
(:mod:`symdyn.check.fuzz_mjcf`), still against Pinocchio's reading of the URDF.

:func:`check_case` derives every output the robot supports
(:func:`symdyn.model.outputs.supported_outputs`), emits and compiles the C with ``-Wall -Wextra
-Wpedantic -Werror``, and compares the C, numpy and CasADi functions with Pinocchio (for a URDF:
Pinocchio's own reading of the file) at seeded random states.  It derives through a private
derivation cache twice, with one field of the robot changed in between, and checks that the
second derivation is the uncached one's.  Every finding is a :class:`Finding`; :func:`shrink`
removes links and features while the finding stays, and the campaign keeps the small robot as
a file (``tests/data/fuzz/`` holds the ones kept as regression tests).
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import tempfile
import time
import traceback
from dataclasses import dataclass, field

import numpy as np

from ..model.tolerances import ROW_FLOOR, VERIFY_TOLERANCE, solve_tolerance

#: normalized error (per joint, see :func:`symdyn.check.pinocchio_model.normalized_error`)
#: allowed for each precision of the C (mixed: float arguments, and float inside but for the
#: functions that solve with D, which are double inside); numpy and CasADi evaluate in double
TOLERANCE = {"double": 1e-9, "mixed": VERIFY_TOLERANCE["mixed"], "float": VERIFY_TOLERANCE["float"]}
#: the random robots' quantities are of order 1 in SI units (masses 0.2-4 kg, lengths up to
#: 0.4 m): an output whose reference's RMS is below this is measured against it, not against
#: its own rounding noise (:func:`symdyn.check.pinocchio_model.normalized_error`'s ``floor``)
FLOOR = 1e-3
#: the task-space functions are compared at states whose task's smallest relative pivot is above
#: this: in float a factorization's rounding grows with the task's condition, so the float code
#: is held to its tolerance where that condition is moderate (case 197: 2.4e-3 at pivots near
#: 1e-3, 1e-11 in double at the same states); mixed solves in double
TASK_REGULAR = {"double": 1e-3, "mixed": 1e-3, "float": 0.05}
STATES = 6
#: the compiled C is called at more states (cheap): the task-space functions in float are compared
#: only at well-conditioned ones (:data:`TASK_REGULAR`)
C_STATES = 24
#: after the warning flags (-Wall -Wextra -Wpedantic -Werror): -O1 keeps the flow analysis the
#: warnings need at a third of -O2's compile time on a 13,700-line file (6.4 s against 10.7 s);
#: the bundled robots' tests build at -O2
COMPILE_FLAGS = ("-O1",)
QUARTER = "1.5707963267948966"


@dataclass(frozen=True)
class Case:
    """One random robot and how it is generated: ``kind`` ``'urdf'`` or ``'dh'``, ``text`` the
    robot file, ``scene`` a scene file over it (or ``''``), the options of the command line."""

    number: int  # the case's number: its random seed
    kind: str
    text: str
    scene: str = ""
    floating: bool = False
    frames: tuple[str, ...] = ()
    precision: str = "double"
    method: str = "newton-euler"
    #: the contact set (``FRAME:3d`` / ``FRAME:6d``, as ``--contacts`` takes it)
    contacts: tuple[str, ...] = ()
    #: a Baumgarte correction of its point contacts, ``(kp, kd, x, y, z)`` (the reference point), or ()
    correction: tuple[float, ...] = ()
    #: a URDF case read as the MJCF of the same robot (:mod:`symdyn.check.fuzz_mjcf`; the
    #: reference stays Pinocchio's reading of the URDF)
    as_mjcf: bool = False

    @property
    def robot_file(self) -> str:
        return f"fuzz{self.number}.{'urdf' if self.kind == 'urdf' else 'yaml'}"

    @property
    def small_pieces(self) -> bool:
        """Whether its C takes the shapes of a big robot's (parts, tables of numbers, several
        files: symdyn.emit.cbody.small_pieces); drawn from its own random stream, so that every
        other choice of the case stays as it was."""
        return bool(np.random.default_rng([self.number, 11]).random() < 0.3)

    def describe(self) -> str:
        parts = [self.kind + (" + scene" if self.scene else "") + (" as MJCF" if self.as_mjcf else ""), self.precision,
                 self.method]
        parts += ["floating base"] if self.floating else []
        parts += ["C in small pieces"] if self.small_pieces else []
        parts += [f"frames {','.join(self.frames)}"] if self.frames else []
        parts += [f"contacts {','.join(self.contacts)}"] if self.contacts else []
        parts += ["corrected (kp {:.4g}, kd {:.4g})".format(*self.correction[:2])] if self.correction else []
        return ", ".join(parts)


@dataclass(frozen=True)
class Finding:
    """A disagreement: ``target`` (``c``, ``numpy``, ``casadi``, ``cache``, or the stage that
    failed: ``load``, ``derive``, ``emit``, ``compile``), the function, and the normalized error
    or what went wrong."""

    number: int
    target: str
    function: str
    error: float = float("nan")
    message: str = ""

    def __str__(self) -> str:
        what = f"normalized error {self.error:.3g}" if not self.message else self.message
        return f"case {self.number}: {self.target} {self.function}: {what}"


# ---------------------------------------------------------------------------------------------
# Random robots
# ---------------------------------------------------------------------------------------------

def _number(x: float) -> str:
    return repr(float(x))


def _angle(rng) -> str:
    """An rpy angle or twist as files write it."""
    pick = rng.integers(7)
    return [lambda: "0", lambda: QUARTER, lambda: "-" + QUARTER, lambda: "3.141592653589793",
            lambda: "1.570796327", lambda: _number(rng.uniform(-math.pi, math.pi)),
            lambda: _number(rng.uniform(-0.3, 0.3))][pick]()


def _inertia(rng) -> tuple[list[float], list[str]]:
    """A physical inertia (principal moments obeying the triangle inequality), as ``([xx, yy, zz,
    xy, xz, yz], rpy)``: rotated either by the rpy of its frame or written as a full tensor."""
    a, b, c = rng.uniform(0.001, 0.03, 3)
    principal = np.diag([b + c, a + c, a + b])
    if rng.random() < 0.5:
        return [b + c, a + c, a + b, 0.0, 0.0, 0.0], [_angle(rng) for _ in range(3)]
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    rot = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    full = rot @ principal @ rot.T
    return [full[0, 0], full[1, 1], full[2, 2], full[0, 1], full[0, 2], full[1, 2]], ["0", "0", "0"]


def _axis(rng) -> list[float]:
    if rng.random() < 0.6:
        axis = [0.0, 0.0, 0.0]
        axis[rng.integers(3)] = float(rng.choice([-1.0, 1.0]))
        return axis
    v = rng.normal(size=3)
    return list(v / np.linalg.norm(v))


def _urdf_inertial(rng) -> str:
    values, rpy = _inertia(rng)
    com = " ".join(_number(x) for x in rng.uniform(-0.15, 0.15, 3))
    names = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    return (f'<inertial><origin xyz="{com}" rpy="{" ".join(rpy)}"/><mass value="{_number(rng.uniform(0.2, 3.0))}"/>'
            f'<inertia {" ".join(f"{k}={chr(34)}{_number(v)}{chr(34)}" for k, v in zip(names, values))}/></inertial>')


def random_urdf(rng, name: str, floating: bool) -> tuple[str, list[str]]:
    """A URDF tree and its link names (see the module docstring)."""
    moving = int(rng.integers(2, 7))
    kinds = ["revolute"] * moving + ["fixed"] * int(rng.integers(0, 3))
    rng.shuffle(kinds)
    for k in range(len(kinds)):
        if kinds[k] == "revolute" and rng.random() < 0.35:
            kinds[k] = str(rng.choice(["prismatic", "continuous"]))
    links = ["base"]
    root_mass = floating or rng.random() < 0.4
    body = [f'  <link name="base">{_urdf_inertial(rng) if root_mass else ""}</link>']
    joints = []
    for k, kind in enumerate(kinds):
        parent = links[-1] if rng.random() < 0.55 else links[int(rng.integers(len(links)))]
        child = f"l{k + 1}" + ("f" if kind == "fixed" else "")
        links.append(child)
        massive = kind != "fixed" or rng.random() < 0.5
        body.append(f'  <link name="{child}">{_urdf_inertial(rng) if massive else ""}</link>')
        xyz = " ".join(_number(x) for x in rng.uniform(-0.3, 0.3, 3))
        parts = [f'<origin xyz="{xyz}" rpy="{" ".join(_angle(rng) for _ in range(3))}"/>',
                 f'<parent link="{parent}"/>', f'<child link="{child}"/>']
        if kind != "fixed":
            parts.append(f'<axis xyz="{" ".join(_number(x) for x in _axis(rng))}"/>')
            if kind != "continuous":
                parts.append('<limit lower="-2.5" upper="2.5" effort="100" velocity="10"/>')
            if rng.random() < 0.4:
                parts.append(f'<dynamics damping="{_number(rng.uniform(0, 0.5))}" '
                             f'friction="{_number(rng.uniform(0, 0.5))}"/>')
        joints.append(f'  <joint name="j{k + 1}" type="{kind}">' + "".join(parts) + "</joint>")
    return f'<robot name="{name}">\n' + "\n".join(body + joints) + "\n</robot>\n", links


def random_dh(rng, name: str) -> tuple[str, list[str]]:
    """A Denavit-Hartenberg table in the robot file format (see the module docstring)."""
    n = int(rng.integers(2, 7))
    lines = ["format: 1", f"name: {name}", f"convention: {rng.choice(['standard', 'modified'])}",
             "gravity: " + ("[0, 0, -9.81]" if rng.random() < 0.7 else
                            "[" + ", ".join(_number(x) for x in rng.uniform(-6, 6, 3)) + "]")]
    if rng.random() < 0.4:
        lines.append(f"tool: {{xyz: [{', '.join(_number(x) for x in rng.uniform(-0.1, 0.1, 3))}], "
                     f"rpy: [{_angle(rng)}, 0, {_angle(rng)}]}}")
    lines.append("links:")
    names = []
    passive = int(rng.integers(1, n)) if n >= 3 and rng.random() < 0.15 else -1
    for k in range(n):
        values, _ = _inertia(rng)
        twist = str(rng.choice([QUARTER, "-" + QUARTER, "pi/2", "-pi/2", "0", _number(rng.uniform(-3, 3))]))
        prismatic = rng.random() < 0.2
        entries = [f"name: j{k + 1}", f"joint: {'prismatic' if prismatic else 'revolute'}",
                   f"a: {_number(rng.uniform(-0.4, 0.4)) if rng.random() < 0.7 else 0}", f"alpha: {twist}",
                   f"d: {_number(rng.uniform(-0.3, 0.3)) if rng.random() < 0.6 else 0}",
                   f"theta: {_angle(rng) if prismatic or rng.random() < 0.3 else 0}",
                   f"mass: {_number(rng.uniform(0.2, 4.0))}",
                   f"com: [{', '.join(_number(x) for x in rng.uniform(-0.2, 0.2, 3))}]",
                   f"inertia: [{', '.join(_number(v) for v in values)}]"]
        for friction in ("armature", "damping", "coulomb"):
            if rng.random() < 0.3:
                entries.append(f"{friction}: {_number(rng.uniform(0.0, 0.4))}")
        if k == passive:
            entries.append("actuated: false")
        lines.append("  - {" + ", ".join(entries) + "}")
        names.append(f"j{k + 1}")
    return "\n".join(lines) + "\n", names


def random_scene(rng, robot_file: str, names: list[str]) -> str:
    """A scene over a DH table: a locked joint, a payload with a runtime mass, or both."""
    lines = ["scene: 1", f"robot: {robot_file}"]
    if len(names) > 2 and rng.random() < 0.6:
        lines.append(f"lock: {{{names[int(rng.integers(len(names)))]}: {_number(rng.uniform(-1, 1))}}}")
    lines += ["payload: {mass: m_p, com: [0, 0, c_z], inertia: [0.002, 0.003, 0.001, 0, 0, 0]}",
              "runtime: [m_p, c_z]", f"values: {{m_p: {_number(rng.uniform(0.1, 2))}, c_z: 0.05}}"]
    return "\n".join(lines) + "\n"


def with_mimics(rng, text: str) -> str:
    """The URDF ``text`` with, three times in ten (when it has three moving joints or more), one
    moving joint made a mimic of an earlier one (a multiplier in [-2, 2] away from 0, an offset in
    [-0.3, 0.3])."""
    joints = re.findall(r'<joint name="(j[0-9]+)" type="(revolute|prismatic|continuous)"', text)
    if len(joints) < 3 or rng.random() >= 0.3:
        return text
    k = int(rng.integers(1, len(joints)))
    leader = joints[int(rng.integers(0, k))][0]
    multiplier = float(rng.uniform(0.3, 2.0)) * float(rng.choice([-1, 1]))
    mimic = f'<mimic joint="{leader}" multiplier="{_number(multiplier)}" offset="{_number(rng.uniform(-0.3, 0.3))}"/>'
    start = text.index(f'<joint name="{joints[k][0]}" ')
    end = text.index("</joint>", start)
    return text[:end] + mimic + text[end:]


def random_case(number: int) -> Case:
    """Case ``number`` (drawn with random seed ``number``: the same on every machine)."""
    rng = np.random.default_rng(number)
    name = f"fz{number}"
    precision = str(rng.choice(["double"] * 6 + ["float", "mixed"]))
    if rng.random() < 0.6:
        floating = bool(rng.random() < 0.3)
        text, links = random_urdf(rng, name, floating)
        text = with_mimics(np.random.default_rng([number, 7]), text)  # (its own stream: the cases stay the same)
        frames = tuple(str(f) for f in rng.choice(links[1:], size=int(rng.integers(0, 3)), replace=False))
        contacts = _random_contacts(number, floating, links)
        as_mjcf = bool(np.random.default_rng([number, 23]).random() < 0.3) and "<mimic" not in text
        return Case(number, "urdf", text, "", floating, frames, precision, contacts=contacts,
                    correction=_random_correction(number, contacts), as_mjcf=as_mjcf)
    text, names = random_dh(rng, name)
    method = str(rng.choice(["newton-euler"] * 3 + ["lagrange-euler", "jacobian-newton-euler"]))
    scene = random_scene(rng, f"fuzz{number}.yaml", names) if rng.random() < 0.25 else ""
    frames = tuple(str(f) for f in rng.choice(names, size=int(rng.integers(0, 2)), replace=False))
    return Case(number, "dh", text, scene, False, frames, precision, method)


def _random_contacts(number: int, floating: bool, links) -> tuple[str, ...]:
    """Half of the floating robots hold one link (a point, a point in a coordinate plane, or a
    sole): the base's six motions
    span any one contact's, so the set is regular at every state (two contacts, or one on a
    fixed base, can be dependent everywhere: status 3, not a disagreement).  Drawn from the
    case's own stream, so that every other choice of the case stays as it was."""
    rng = np.random.default_rng([number, 13])
    if not floating or len(links) < 2 or rng.random() < 0.5:
        return ()
    link, kind = rng.choice(links[1:]), str(rng.choice(['3d', '6d']))
    plane = np.random.default_rng([number, 19])  # (a stream of its own: the other choices stay)
    if kind == "3d" and plane.random() < 0.3:
        kind = str(plane.choice(["xz", "xy", "yz"]))
    return (f"{link}:{kind}",)


def _random_correction(number: int, contacts) -> tuple[float, ...]:
    """Half of the cases holding a point get a Baumgarte correction ``(kp, kd, x, y, z)``: gains
    in [10, 200] 1/s^2 and [1, 30] 1/s, a reference point in [-0.5, 0.5]^3 m; half of those
    holding a sole ``(kp, kd, x, y, z, roll, pitch, yaw)``, the angles in [-1, 1] rad.  Its own
    stream."""
    rng = np.random.default_rng([number, 17])
    if not contacts:
        return ()
    sole = any(c.endswith(":6d") for c in contacts)
    if rng.random() < 0.5 or (sole and rng.random() < 0.3):  # (a sole's draw after: the points' stay)
        return ()
    drawn = [rng.uniform(10, 200), rng.uniform(1, 30), *rng.uniform(-0.5, 0.5, 3)]
    return tuple(round(float(v), 6) for v in drawn + (list(rng.uniform(-1, 1, 3)) if sole else []))


def corrected(robot, correction):
    """``robot`` with its contacts held by the Baumgarte ``correction`` ``(kp, kd, x, y, z)``, or
    ``(kp, kd, x, y, z, roll, pitch, yaw)`` for a sole."""
    from ..model.expr import number_to_rational
    kp, kd, *reference = (number_to_rational(repr(float(v))) for v in correction)
    return dataclasses.replace(robot, contacts=tuple(
        dataclasses.replace(c, kp=kp, kd=kd, reference=tuple(reference[:c.rows if c.kind == "6d" else 3]))
        for c in robot.contacts))


# ---------------------------------------------------------------------------------------------
# One case
# ---------------------------------------------------------------------------------------------

@dataclass
class Outcome:
    """What checking one case found, and what it checked."""

    case: Case
    findings: list[Finding] = field(default_factory=list)
    functions: tuple[str, ...] = ()
    compared: int = 0
    worst: float = 0.0
    seconds: float = 0.0
    stages: dict = field(default_factory=dict)  # stage -> seconds

    def enter(self, stage: str) -> str:
        """Start ``stage`` (the time since the last one goes to that one)."""
        now = time.perf_counter()
        if self.stages.get("_last"):
            last, since = self.stages["_last"]
            self.stages[last] = self.stages.get(last, 0.0) + now - since
        self.stages["_last"] = (stage, now)
        return stage

    def slowest(self) -> str:
        timed = [(v, k) for k, v in self.stages.items() if k != "_last"]
        return ", ".join(f"{k} {v:.0f} s" for v, k in sorted(timed, reverse=True)[:3])


def write_case(case: Case, directory: str) -> str:
    """Write the case's files into ``directory``; the path symdyn reads (the scene, if any; the
    MJCF of a case read as one, beside its URDF)."""
    with open(os.path.join(directory, case.robot_file), "w") as handle:
        handle.write(case.text)
    if case.as_mjcf:
        from .fuzz_mjcf import mjcf_of_urdf
        path = os.path.join(directory, f"fuzz{case.number}.xml")
        with open(path, "w") as handle:
            handle.write(mjcf_of_urdf(case.text, case.number, case.floating))
        return path
    if not case.scene:
        return os.path.join(directory, case.robot_file)
    path = os.path.join(directory, f"fuzz{case.number}_scene.yaml")
    with open(path, "w") as handle:
        handle.write(case.scene)
    return path


def _reference(case: Case, path: str, robot, values):
    """Pinocchio's model of the case: of symdyn's reading of a DH table; else Pinocchio's own
    reading of the URDF (of the URDF beside it for a case read as MJCF, which keeps its angles as
    written, as MuJoCo does)."""
    from .pinocchio_model import PinocchioReference, UrdfReference, reduced
    if case.kind != "urdf":
        return reduced(PinocchioReference(robot, values), robot, values)
    from ..model.urdf import QUARTER_TOLERANCE
    snapped = any("multiple of pi/2" in note for note in robot.notes)
    path = os.path.join(os.path.dirname(path), case.robot_file)
    tip = None
    if case.as_mjcf and not robot.is_tree and not robot.floating:  # an MJCF's chain ends at its last joint's body
        import xml.etree.ElementTree as ET  # (the fuzzer's own URDF)
        tip = next(j.find("child").get("link") for j in ET.fromstring(case.text).iter("joint")
                   if j.get("name") == robot.links[-1].name)
    return reduced(UrdfReference(path, tip, None, QUARTER_TOLERANCE if snapped else None, floating_base=case.floating,
                                 frames=[f.name for f in robot.frames] or None), robot)


def _states(robot, precision: str, number: int, count: int = STATES):
    from .states import random_state
    rng = np.random.default_rng(number)
    states = [random_state(robot, rng) for _ in range(count)]
    if precision != "double":  # judge the arithmetic, not the rounding of the inputs
        states = [[x.astype(np.float32).astype(float) for x in s] for s in states]
    return states


def _parameter_values(robot, number: int):
    """``(values, p)``: each runtime parameter's nominal value, else a seeded one in [0.3, 1.5]
    ({symbol: number}), and the same as the array ``p`` in the robot's order."""
    rng = np.random.default_rng(number)
    values = {s: float(v) if v is not None else float(rng.uniform(0.3, 1.5))
              for s, v in zip(robot.parameters, robot.nominal)}
    return values, np.array([values[s] for s in robot.parameters])


def _derive(case: Case, robot, functions, use_cache: bool = True):
    """``(eqs, functions)`` (see :func:`symdyn.check.agreement.derive_supported`); one case in
    four of a Newton-Euler chain solves forward dynamics by the articulated-body algorithm."""
    from .agreement import derive_supported
    fd_method = "aba" if case.method == "newton-euler" and not robot.is_tree and case.number % 4 == 1 else "ldlt"
    return derive_supported(robot, case.method, functions, fd_method, use_cache)


def _supported(case: Case, robot) -> tuple[str, ...]:
    from ..model.outputs import supported_outputs
    names = supported_outputs(robot)
    if case.method != "newton-euler":  # the derivatives are recursions of Newton-Euler's
        from ..model.outputs import DERIVATIVE_OUTPUTS
        names = tuple(n for n in names if n not in DERIVATIVE_OUTPUTS)
    return names


def _record(outcome: Outcome, target: str, errors: dict, tolerance: float, solved: float | None = None) -> None:
    """Count ``errors`` ({function: normalized error}) and keep those over ``tolerance`` (over
    ``solved`` for a function that solves with M, :func:`symdyn.model.tolerances.solve_tolerance`)."""
    from ..model.outputs import factors_mass_matrix
    for name, error in errors.items():
        if math.isnan(error):  # a task-space function with no regular state among the few
            continue
        outcome.compared += 1
        outcome.worst = max(outcome.worst, error)
        if not error <= (solved if solved is not None and factors_mass_matrix(name) else tolerance):
            outcome.findings.append(Finding(outcome.case.number, target, name, error))


def check_case(case: Case, workdir: str, targets=("c", "numpy", "casadi", "cache")) -> Outcome:
    """Check every supported output of ``case`` in every target (see the module docstring)."""
    from .agreement import CasadiTarget, NumpyTarget, compile_equations, mass_conditioning, target_errors
    from ..model.outputs import factors_mass_matrix
    from ..model.scene import load_input
    started = time.perf_counter()
    outcome = Outcome(case)
    stage = outcome.enter("load")
    try:
        path = write_case(case, workdir)
        robot, scene = load_input(path, floating_base=case.floating and not case.as_mjcf,  # (an MJCF says so itself)
                                  frames=list(case.frames) or None, contacts=",".join(case.contacts) or None)
        if case.correction and robot.contacts:
            robot = corrected(robot, case.correction)
        functions = _supported(case, robot)
        outcome.functions = functions
        values, p = _parameter_values(robot, case.number)
        stage = outcome.enter("derive")
        eqs, functions = _derive(case, robot, functions)
        outcome.functions = functions
        stage = outcome.enter("reference")
        reference = _reference(case, path, robot, values)
        states = _states(robot, case.precision, case.number, C_STATES)
        if "c" in targets:
            stage = outcome.enter("compile")
            lib = compile_equations(eqs, functions, case.precision, workdir, os.path.basename(path), COMPILE_FLAGS,
                                    small_pieces=case.small_pieces)
            stage = outcome.enter("c")
            solved = (solve_tolerance(TOLERANCE[case.precision], mass_conditioning(reference, states), case.precision,
                                      robot.nv) if any(factors_mass_matrix(f) for f in functions) else None)
            _record(outcome, "c", target_errors(lib, reference, robot, eqs, functions, states, p, values, FLOOR,
                                                TASK_REGULAR[case.precision], ROW_FLOOR[case.precision]),
                    TOLERANCE[case.precision], solved)
        double_states = _states(robot, "double", case.number)
        for target, build in (("numpy", NumpyTarget), ("casadi", CasadiTarget)):
            if target in targets:
                stage = outcome.enter(target)
                _record(outcome, target, target_errors(build(eqs), reference, robot, eqs, functions, double_states,
                                                       p, values, FLOOR, row_floor=ROW_FLOOR["double"]),
                        TOLERANCE["double"])
        if "cache" in targets:
            stage = outcome.enter("cache")
            _check_cache(case, robot, functions, outcome)
    except Exception as exc:  # noqa: BLE001 (every failure is a finding, with where it happened)
        detail = traceback.format_exception_only(type(exc), exc)[-1].strip()
        outcome.findings.append(Finding(case.number, stage, "", message=detail[:400]))
    outcome.enter("done")
    outcome.seconds = time.perf_counter() - started
    return outcome


def changed_robot(robot):
    """``robot`` with one field changed (the last link's mass plus 0.25 kg, or its frames one
    fewer where no contact is held at one): what a second run through the same cache must not
    read from the first."""
    import sympy as sp
    if robot.frames and len(robot.frames) > 1 and not robot.contacts:
        return dataclasses.replace(robot, frames=robot.frames[1:])
    last = robot.links[-1]
    links = robot.links[:-1] + (dataclasses.replace(last, mass=sp.sympify(last.mass) + sp.Rational(1, 4)),)
    return dataclasses.replace(robot, links=links)


#: the outputs the cache check compares (derived with all the case's functions, so that the
#: second derivation has the first one's key but for the changed field)
CACHE_CHECKED = ("gravity", "mass_matrix", "frame_poses", "center_of_mass")


def _check_cache(case: Case, robot, functions, outcome: Outcome) -> None:
    """Derive ``robot`` with one field changed (:func:`changed_robot`) through the cache that
    holds ``robot``'s derivation of the same functions, and compare a few outputs with a
    Pinocchio model of the changed robot: a key that missed the field would give the first
    robot's numbers."""
    from .pinocchio_model import PinocchioReference, compare, reduced
    other = changed_robot(robot)
    cached, _ = _derive(case, other, functions)
    values, p = _parameter_values(other, case.number)
    checked = [name for name in CACHE_CHECKED if name in functions]
    from .agreement import NumpyTarget
    errors = compare(NumpyTarget(cached), reduced(PinocchioReference(other, values), other, values),
                     _states(other, "double", case.number + 1),
                     checked, p, FLOOR, ROW_FLOOR["double"])
    for name, error in errors.items():
        outcome.compared += 1
        if not error <= TOLERANCE["double"]:
            outcome.findings.append(Finding(case.number, "cache", name, error, "after one field of the robot changed, "
                                            f"the derivation through the cache is {error:.2g} from the reference"))


def _inputs(name, state, contact_rows=None):
    from .states import state_arguments
    return state_arguments(name, state, contact_rows)


# ---------------------------------------------------------------------------------------------
# Shrinking and campaigns
# ---------------------------------------------------------------------------------------------

def _urdf_variants(case: Case):
    """Smaller URDF cases: each link that no other hangs on removed (with its joint), frames and
    friction dropped, the floating base fixed."""
    import xml.etree.ElementTree as ET
    root = ET.fromstring(case.text)
    parents = {j.find("parent").get("link") for j in root.findall("joint")}
    for joint in root.findall("joint"):
        child = joint.find("child").get("link")
        if child in parents or len(root.findall("joint")) <= 1:
            continue
        smaller = ET.fromstring(case.text)
        for j in smaller.findall("joint"):
            if j.find("child").get("link") == child:
                smaller.remove(j)
        for link in smaller.findall("link"):
            if link.get("name") == child:
                smaller.remove(link)
        yield dataclasses.replace(case, text=ET.tostring(smaller, encoding="unicode"),
                                  frames=tuple(f for f in case.frames if f != child),
                                  contacts=tuple(c for c in case.contacts if c.split(":")[0] != child))
    if case.frames:
        yield dataclasses.replace(case, frames=case.frames[:-1])
    if case.correction:
        yield dataclasses.replace(case, correction=())
    if case.contacts:
        yield dataclasses.replace(case, contacts=(), correction=())
    if case.floating:
        yield dataclasses.replace(case, floating=False, contacts=(), correction=())
    if "<dynamics" in case.text:
        import re
        yield dataclasses.replace(case, text=re.sub(r"<dynamics[^>]*/>", "", case.text))
    if case.as_mjcf:
        yield dataclasses.replace(case, as_mjcf=False)


def _dh_variants(case: Case):
    lines = case.text.splitlines()
    rows = [k for k, line in enumerate(lines) if line.startswith("  - {")]
    if len(rows) > 1 and not case.scene:
        for k in rows:
            name = lines[k].split("name: ")[1].split(",")[0]
            if name not in case.frames:
                yield dataclasses.replace(case, text="\n".join(lines[:k] + lines[k + 1:]) + "\n")
    if case.scene:
        yield dataclasses.replace(case, scene="")
    if case.frames:
        yield dataclasses.replace(case, frames=case.frames[:-1])
    if case.method != "newton-euler":
        yield dataclasses.replace(case, method="newton-euler")


def shrink(case: Case, finding: Finding, workdir: str, budget_seconds: float = 300.0) -> Case:
    """A smaller case on which ``finding``'s target and function still fail (greedy: the first
    smaller variant that fails is kept, until none does or the budget is spent)."""
    deadline = time.perf_counter() + budget_seconds

    def still_fails(candidate: Case) -> bool:
        with tempfile.TemporaryDirectory(dir=workdir) as where:
            outcome = check_case(candidate, where)
        return any(f.target == finding.target and f.function == finding.function for f in outcome.findings)

    improved = True
    while improved and time.perf_counter() < deadline:
        improved = False
        variants = _urdf_variants(case) if case.kind == "urdf" else _dh_variants(case)
        for candidate in variants:
            if time.perf_counter() >= deadline:
                break
            if still_fails(candidate):
                case, improved = candidate, True
                break
    return case


def _check_number(number: int, root: str) -> Outcome:
    """Check case ``number`` in a fresh directory under ``root`` (a campaign's worker)."""
    with tempfile.TemporaryDirectory(dir=root) as workdir:
        return check_case(random_case(number), workdir)


def run_campaign(numbers, out_dir: str | None = None, report=print, shrink_seconds: float = 300.0,
                 jobs: int = 1) -> list[Outcome]:
    """Check the cases of ``numbers`` (an iterable of ints), each in its own directory under a
    private derivation cache, ``jobs`` at a time (processes); a failing case is shrunk and
    written to ``out_dir`` (:func:`_keep`).  ``report`` is called with one line per case, in
    the cases' order."""
    import concurrent.futures
    import functools
    import multiprocessing
    outcomes = []
    with tempfile.TemporaryDirectory(prefix="symdyn_fuzz_") as root:
        previous = os.environ.get("SYMDYN_CACHE_DIR")
        os.environ["SYMDYN_CACHE_DIR"] = os.path.join(root, "cache")
        try:
            check = functools.partial(_check_number, root=root)
            if jobs > 1:
                pool = concurrent.futures.ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context("fork"))
                results = pool.map(check, numbers)
            else:
                pool, results = None, map(check, numbers)
            for outcome in results:
                outcomes.append(outcome)
                _report(outcome, report)
                if outcome.findings and out_dir:
                    small = shrink(outcome.case, outcome.findings[0], root, shrink_seconds)
                    _keep(small, outcome.findings[0], out_dir)
                    report(f"  shrunk to {os.path.join(out_dir, f'fuzz{small.number}.case.yaml')}")
            if pool is not None:
                pool.shutdown()
        finally:
            if previous is None:
                os.environ.pop("SYMDYN_CACHE_DIR", None)
            else:
                os.environ["SYMDYN_CACHE_DIR"] = previous
    return outcomes


def _report(outcome: Outcome, report) -> None:
    status = "ok" if not outcome.findings else f"{len(outcome.findings)} FAILED"
    report(f"case {outcome.case.number}: {outcome.case.describe()}: {len(outcome.functions)} functions, "
           f"{outcome.compared} comparisons, worst {outcome.worst:.2g}, {outcome.seconds:.1f} s ({outcome.slowest()}): "
           f"{status}")
    for finding in outcome.findings:
        report(f"  {finding}")


def _keep(case: Case, finding: Finding, out_dir: str) -> None:
    """Write ``case`` as ``fuzz<number>.case.yaml`` (every field of :class:`Case`, the finding as
    its note): :func:`load_case` reads it back, and a file kept in ``tests/data/fuzz/`` is a
    regression test."""
    import yaml
    os.makedirs(out_dir, exist_ok=True)
    doc = {"note": str(finding), **dataclasses.asdict(case)}
    doc["frames"] = list(case.frames)
    doc["contacts"] = list(case.contacts)
    doc["correction"] = list(case.correction)
    with open(os.path.join(out_dir, f"fuzz{case.number}.case.yaml"), "w") as handle:
        yaml.safe_dump(doc, handle, sort_keys=False, width=120)


def load_case(path: str) -> Case:
    """The :class:`Case` of a file written by a campaign (see :func:`_keep`)."""
    import yaml
    with open(path) as handle:
        doc = yaml.safe_load(handle)
    doc.pop("note", None)
    doc["frames"] = tuple(doc.get("frames") or ())
    doc["contacts"] = tuple(doc.get("contacts") or ())
    doc["correction"] = tuple(doc.get("correction") or ())
    return Case(**doc)
