"""``symdyn verify``: generate, compile, run against Pinocchio, print an error table."""

from __future__ import annotations

import tempfile

import numpy as np

from ..derive.cache import derive_cached
from ..model.outputs import PLATFORM_REGISTRY as PLATFORM_FUNCTIONS
from ..emit.cgen import PRECISION_CHOICES
from ..emit.parallel_c import generate_parallel_c
from ..emit.pipeline import PLATFORM, SERIAL, kind_of, scene_choices
from ..model.outputs import ALL_OUTPUTS, TASK_OUTPUTS, factors_mass_matrix, supported_outputs, with_requirements
from ..model.errors import SymdynError
from ..model.tolerances import ROW_FLOOR, VERIFY_FLOOR, VERIFY_TOLERANCE, solve_tolerance
from .common import add_fd_method_option, add_method_option, add_size_options, check_size, default_fd_method, load_robot, parse_functions, progress_printer

HELP = "compile the generated C and compare every function with Pinocchio"
DEFAULT_TOLERANCE = VERIFY_TOLERANCE


def add_parser(sub) -> None:
    p = sub.add_parser("verify", help=HELP, description=HELP + ". Errors are normalized per joint "
                       "by the RMS of Pinocchio's values over the states. Exit status 1 when any "
                       "error is over the tolerance. Free symbols get seeded random values in "
                       "[0.3, 1.5] (g gets 9.81); runtime parameters their nominal values. "
                       "A platform robot (kind: parallel) is compared with Pinocchio's closed-loop model "
                       "at random states about its home pose, and its statuses at states out of reach, "
                       "singular or overflowing. Needs Pinocchio (pip install 'symdyn[verify]').")
    p.add_argument("robot", metavar="ROBOT", help="robot file (.yaml: an arm or a platform), URDF (.urdf), MuJoCo MJCF (.xml, .mjcf) or scene")
    p.add_argument("--states", type=int, default=50, help="number of random states (default 50)")
    p.add_argument("--precision", default=None, choices=PRECISION_CHOICES,
                   help="default: the scene's precision, else double")
    p.add_argument("--functions", metavar="LIST",
                   help="comma-separated functions to check, from: " + ", ".join(ALL_OUTPUTS) + " (default: the scene's functions, else all that generate writes by default); "
                        "for a platform robot, from: " + ", ".join(PLATFORM_FUNCTIONS) + " (default: all)")
    p.add_argument("--all", action="store_true",
                   help="check every function this robot supports (symdyn.model.outputs.supported_outputs): "
                        "the derivatives, regressors, task-space, frame and centroidal functions too")
    p.add_argument("--tolerance", type=float, help="normalized error bound (default 1e-10 double, 1e-4 float)")
    p.add_argument("--seed", type=int, default=0, help="random seed for the states (default 0)")
    add_method_option(p)
    add_fd_method_option(p)
    p.add_argument("--parameters", default="standard", choices=("standard", "base"),
                   help="base: check inverse dynamics written in the base parameters (as generate --parameters base)")
    add_size_options(p)
    p.set_defaults(run=run)


def run(args) -> int:
    """Check the options, load the robot and verify it as its kind is verified (:data:`BY_KIND`)."""
    try:
        import pinocchio  # noqa: F401
    except ImportError:
        raise SymdynError("symdyn verify needs Pinocchio: pip install 'symdyn[verify]' (the pin package)") from None
    if args.states < 1:
        raise SymdynError("--states must be at least 1")
    if args.seed < 0:
        raise SymdynError(f"--seed must be a non-negative integer, not {args.seed}")
    robot, scene = load_robot(args.robot, args, parallel=True)
    check_size(robot, args, args.robot)
    return BY_KIND[kind_of(robot).name](args, robot, scene)


def _run_serial(args, robot, scene) -> int:
    """verify of a serial robot (a chain, a tree or a floating base): every function asked for,
    compiled, against Pinocchio (of the URDF itself where it can read it); one table of errors."""
    from ..check.agreement import (REGRESSORS, TASK_REGULAR, compile_equations, mass_conditioning, regular_states,
                                   robot_floors, target_errors)
    from ..check.pinocchio_model import PinocchioReference, reduced
    from ..check.states import random_state
    from ..model.scene import is_mjcf, is_urdf
    if args.all and args.functions:
        raise SymdynError("--all and --functions choose the functions two ways: give one")
    asked = supported_outputs(robot) if args.all else parse_functions(args.functions) if args.functions else None
    functions, precision, _ = scene_choices(robot, scene, asked, args.precision)
    rng = np.random.default_rng(args.seed)
    values = {}
    for sym, nominal in zip(robot.parameters, robot.nominal):
        values[sym] = float(nominal) if nominal is not None else (9.81 if sym.name == "g" else float(rng.uniform(0.3, 1.5)))
    p = np.array([values[s] for s in robot.parameters])
    fd_method = args.fd_method or default_fd_method(precision, robot)
    eqs, functions, skipped = _derive(args, robot, functions, fd_method)
    with tempfile.TemporaryDirectory(prefix="symdyn_verify_") as workdir:
        lib = compile_equations(eqs, functions, precision, workdir, args.robot)
        regressors = [f for f in functions if f in REGRESSORS]
        if is_urdf(args.robot) and scene is None:  # Pinocchio reads the file itself: an independent reading
            ref, reading = _urdf_reference(args, robot, values)
        elif is_mjcf(args.robot) and scene is None:  # MuJoCo compiles it: the format's own reading
            ref, reading = _mjcf_reference(args, robot, values)
        else:
            ref = PinocchioReference(robot, values)
            reading = "a Pinocchio model of symdyn's reading"
        ref = reduced(ref, robot, values)  # mimic joints projected, a tree's joints in Pinocchio's order
        if robot.mimics:
            reading += (", the mimic joint projected on its leader" if len(robot.mimics) == 1
                        else f", the {len(robot.mimics)} mimic joints projected on their leaders")
        states = []
        for _ in range(args.states):
            state = random_state(robot, rng)
            if precision != "double":  # judge the arithmetic, not the rounding of the inputs
                state = [x.astype(np.float32).astype(float) for x in state]
            states.append(state)
        floors = robot_floors(ref, states, functions)
        conditioning = mass_conditioning(ref, states) if any(factors_mass_matrix(f) for f in functions) else 1.0
        errors = target_errors(lib, ref, robot, eqs, functions, states, p, values, floors, row_floor=ROW_FLOOR[precision])
        regular = regular_states(ref, states, functions)
        singular = {f: _status_everywhere(lib, f, states, 3) for group, kept in regular.items() if not kept
                    for f in group if f not in TASK_OUTPUTS}
    tolerance = args.tolerance if args.tolerance is not None else DEFAULT_TOLERANCE[precision]
    # what solves with M cannot agree better than its condition number allows (two correct
    # solutions of an ill-conditioned system differ by about cond(M) times the unit roundoff)
    solved = solve_tolerance(tolerance, conditioning, precision, robot.nv) if args.tolerance is None else tolerance
    form = "; inverse dynamics in the base parameters" if args.parameters == "base" else ""
    print(f"symdyn verify {args.robot}: {robot.dof} joint{'' if robot.dof == 1 else 's'}"
          f"{' on a floating base' if robot.floating else ''}, "
          f"{args.method}{form}, {precision}, "
          f"{args.states} random states, tolerance {tolerance:g}, against {reading}")
    if skipped:
        print(f"({skipped})")
    if floors:
        print(f"(outputs in torques measured against at least {VERIFY_FLOOR:g} of the robot's own torques at these "
              "states, the RMS of its inverse dynamics: a value that is zero but for rounding is not judged against "
              "its own noise)")
    if precision != "double":
        print(f"(each joint's row measured against at least {ROW_FLOOR[precision]:g} of its output's RMS: float rounds the "
              "output's large entries, and that reaches its small ones)")
    for group, kept in regular.items():
        if group[0] in TASK_OUTPUTS:
            print(f"(task-space functions: compared at the {len(kept)} of the {args.states} states whose task is away "
                  f"from singularities: every pivot of J M^-1 J^T's factorization above {TASK_REGULAR:g} of its "
                  "diagonal entry)")
        else:
            print(f"(contact inverse dynamics: compared at the {len(kept)} of the {args.states} states where the "
                  "contacts can push the base in every direction: every pivot of the QR of their base columns "
                  f"above {TASK_REGULAR:g} of its column's squared norm; at none, 'singular' when the function "
                  "returns status 3 at every state, as it should)")
    if regressors:
        print(f"({', '.join(regressors)}: checked as torques, Y pi and Yb beta with this file's parameters, "
              "against inverse dynamics)")
    if solved > tolerance:
        print(f"(functions that solve with M = D + diag(armature): its condition number reaches {conditioning:.2g} at these "
              f"states, so they are judged at {solved:.2g}, N cond(M) times the unit roundoff of "
              f"{'float' if precision == 'float' else 'double'}, the arithmetic they run in)")
    width = max([18] + [len(name) for name in functions])
    print(f"{'function':<{width}} {'normalized error':>16}  status")
    failed = False
    for name in functions:
        err = errors[name]
        ok = singular[name] if name in singular else bool(
            np.isfinite(err) and err <= (solved if factors_mass_matrix(name) else tolerance))
        failed |= not ok
        print(f"{name:<{width}} {err:>16.3e}  {('singular' if ok else 'FAIL') if name in singular else 'ok' if ok else 'FAIL'}")
    return 1 if failed else 0


def _status_everywhere(lib, name: str, states, code: int) -> bool:
    """Whether the compiled function ``name`` returns status ``code`` at every state (where the
    reference finds its problem singular: contact inverse dynamics with too few contacts)."""
    from ..check.states import state_arguments
    rows = lib.dims.contacts
    return all(lib.with_status(name, *state_arguments(name, state, rows))[0] == code for state in states)


def _run_platform(args, robot, scene=None) -> int:
    """verify of a platform robot: every generated function against Pinocchio's closed loop
    (symdyn.check.platform_verify), one table of errors and one of statuses."""
    from ..check.cbuild import build_platform
    from ..check.closed_loop import ClosedLoopReference
    from ..check.platform_verify import STATUS_NAMES, check_platform, random_states, special_states
    from ..derive.parallel import derive_parallel
    from ..emit.pipeline import GenerateOptions, check_kind_options, parse_platform_functions
    check_kind_options(PLATFORM, GenerateOptions(precision=args.precision, method=args.method, fd_method=args.fd_method,
                                                 parameters=args.parameters), args.robot)
    functions = parse_platform_functions(args.functions) or tuple(PLATFORM_FUNCTIONS)
    precision = args.precision or "double"
    eqs = derive_parallel(robot, functions, progress=progress_printer(args))
    files = generate_parallel_c(eqs, functions, precision, source_name=args.robot, source_hash=robot.source_hash)
    reference = ClosedLoopReference(robot, precision)
    states = [state.rounded(precision) for state in random_states(reference, args.states, args.seed)]
    cases, notes = special_states(reference, precision)
    with tempfile.TemporaryDirectory(prefix="symdyn_verify_") as workdir:
        lib = build_platform(files, robot.name, precision, workdir)
        result = check_platform(lib, reference, functions, states, cases)
    tolerance = args.tolerance if args.tolerance is not None else DEFAULT_TOLERANCE[precision]
    print(f"symdyn verify {args.robot}: platform robot, {robot.dof} legs, natural orthogonal complement, {precision}, "
          f"{args.states} random states about the home pose, tolerance {tolerance:g}, against Pinocchio's closed-loop "
          "model (a free-flying platform, a 6D loop closure per leg)")
    print(f"{'function':<18} {'normalized error':>16}  status")
    for name in functions:
        print(f"{name:<18} {result.errors[name]:>16.3e}  {'ok' if result.function_ok(name, tolerance) else 'FAIL'}")
    codes = ", ".join(f"{code} {label}" for code, label in sorted(STATUS_NAMES.items()))
    print(f"statuses (0 success, {codes}); the reference returns 0 at {result.regular} of the {len(states)} random "
          f"states; at special states, in the order {', '.join(functions)}:")
    width, column = max([len(label) for label, *_ in result.cases] + [5]), max(9, 2 * len(functions) - 1)
    print(f"{'state':<{width}}  {'reference':<{column}}  {'C':<{column}}  status")
    for label, ref, ours, ok in result.cases:
        print(f"{label:<{width}}  {' '.join(map(str, ref)):<{column}}  {' '.join(map(str, ours)):<{column}}  "
              f"{'ok' if ok else 'FAIL'}")
    for note in notes:
        print(f"note: {note}")
    for name in functions:
        for problem in result.mismatches[name][:3]:
            print(f"{name}: {problem}")
    return 0 if result.ok(tolerance) else 1


def _derive(args, robot, functions, fd_method):
    """``(eqs, functions, skipped)``: the derivation of the functions to check; where the mass
    matrix is singular for every q (a massless subtree), without the functions that solve with
    it, ``skipped`` then saying which and why (else "")."""
    from ..check.agreement import derive_supported
    from ..derive.equations import SingularMassMatrix

    def derive(functions):
        if args.all:  # without the task-space functions where the robot's task does not exist
            return derive_supported(robot, args.method, functions, fd_method, progress=progress_printer(args),
                                    parameters=args.parameters)
        return derive_cached(robot, args.method, with_requirements(functions), progress=progress_printer(args),
                             fd_method=fd_method, parameters=args.parameters), functions
    try:
        return (*derive(functions), "")
    except SingularMassMatrix as exc:
        kept = tuple(f for f in functions if not factors_mass_matrix(f))
        if not kept:
            raise
        dropped = [f for f in functions if f not in kept]
        return (*derive(kept), f"skipped {', '.join(dropped)}: {exc}")


#: how each kind of robot (symdyn.emit.pipeline.KINDS) is verified
BY_KIND = {SERIAL.name: _run_serial, PLATFORM.name: _run_platform}


def _mjcf_reference(args, robot, values):
    """MuJoCo's compiled model of the MJCF for the dynamics and the sites' poses (or, without
    MuJoCo or where its compiler refuses the file, a Pinocchio model of symdyn's reading, with a
    warning) and the words that say which."""
    from ..check.mujoco_model import MujocoReference, MujocoUnavailable
    from ..check.pinocchio_model import PinocchioReference
    from ..model.errors import display_path, warn
    try:
        return MujocoReference(robot, args.robot, values), (
            "MuJoCo's own compiled model (mass matrix, h, c, inverse and forward dynamics, the sites' poses) and a "
            "Pinocchio model of symdyn's reading (the rest)")
    except MujocoUnavailable as exc:
        warn(f"{display_path(args.robot)}: {exc}: the reading is checked against a Pinocchio model of itself only")
        return PinocchioReference(robot, values), "a Pinocchio model of symdyn's reading"


def _urdf_reference(args, robot, values):
    """Pinocchio's own reading of the URDF (or, where its parser refuses the file, a Pinocchio
    model of symdyn's reading, with a warning) and the words that say which."""
    from ..check.pinocchio_model import PinocchioReference, UrdfReference
    from ..check.quiet import stderr_silenced
    from ..model.urdf import QUARTER_TOLERANCE
    snapped = not args.exact_angles and any("multiple of pi/2" in note for note in robot.notes)
    try:
        with stderr_silenced():  # urdfdom prints its complaints on the process's stderr
            ref = UrdfReference(args.robot, args.tip, args.tool, QUARTER_TOLERANCE if snapped else None,
                                floating_base=robot.floating, frames=[f.name for f in robot.frames] or None)
        return ref, "Pinocchio's own URDF parser" + (
            " (near-quarter-turn rpy angles made exact, as symdyn reads them; --exact-angles "
            "keeps them as written)" if snapped else "")
    except Exception as exc:  # Pinocchio's parser refuses what symdyn read: compare with symdyn's reading
        from ..model.errors import one_line, warn
        warn(f"{args.robot}: Pinocchio's URDF parser cannot read it ({type(exc).__name__}: "
             f"{one_line(exc, 160)}); comparing with a Pinocchio model of symdyn's reading instead")
        return PinocchioReference(robot, values), "a Pinocchio model of symdyn's reading"

