"""``symdyn derive``: the derivation of a robot's equations of motion, step by step, as text,
LaTeX or Markdown, in the notation of the notes."""

from __future__ import annotations

import os
import sys

from ..model.files import check_output_dir, check_targets, write_files
from ..derive.derivation import STEPS, TASK_CLOSED_FORM_MAX_DOF, derive_steps
from ..model.errors import SymdynError
from ..emit.printout import DEFAULT_DIGITS, FORMATS, MAX_DIGITS, render
from ..derive.equations import METHOD_ALIASES
from ..emit.pipeline import PLATFORM, SERIAL, kind_of
from .common import add_size_options, check_size, load_robot, progress_printer

HELP = "print the derivation of the equations of motion (text, LaTeX or Markdown)"


def add_parser(sub) -> None:
    p = sub.add_parser("derive", help=HELP, description=HELP + ": Lagrange-Euler (link matrices, "
                       "U_ij, U_ijk, pseudo-inertias J_i, D_ik, h_ikm, h_i, c_i), Newton-Euler "
                       "(forward and backward recursion of Table 3.2), ending with D, h, c, or the "
                       "articulated-body algorithm (forward dynamics, and the reaction map of a robot with "
                       "passive joints).")
    p.add_argument("robot", metavar="ROBOT", help="robot file (.yaml), URDF (.urdf), MuJoCo MJCF (.xml, .mjcf) or scene, or a platform robot "
                   "(kind: parallel): its derivation by the natural orthogonal complement in the order of "
                   "the parallel-manipulator notes (leg Jacobians, A_J, the scalar twist-shape relations, Y, Z, T, L_J, M, N, "
                   "Lambda, phi), each evaluated at one state")
    p.add_argument("--method", default="newton-euler",
                   choices=sorted(set(METHOD_ALIASES) | {"articulated-body", "aba"}),
                   help="newton-euler (default), lagrange-euler, jacobian-newton-euler, or articulated-body "
                        "(forward dynamics by the three sweeps of the articulated-body algorithm, in the "
                        "named form; with passive joints also the force-to-torque reaction map)")
    add_size_options(p)
    p.add_argument("--base-parameters", action="store_true",
                   help="end with the base parameters (identification): each as a combination of the standard "
                        "parameters (needs a numeric link geometry)")
    p.add_argument("--task", action="store_true",
                   help="end with the equations of motion in the tool's task coordinates, F = M_x xdd + V_x + G_x "
                        "(the lecture's Cartesian space; the robot file's or scene's task, default the tool's pose), "
                        "in closed form, up to 3 joints")
    p.add_argument("--format", default="text", choices=FORMATS,
                   help="text (Unicode, for the terminal), latex (a complete document for pdflatex) "
                        "or markdown (math blocks that render on GitHub); default text")
    p.add_argument("--out", metavar="FILE", help="write to FILE (atomically; never over the robot file, "
                   "a link or a device) instead of standard output")
    p.add_argument("--steps", default="all", choices=STEPS,
                   help="all (default): every intermediate quantity; summary: link matrices, "
                        "inertias and the final D, h, c")
    p.add_argument("--form", default="auto", choices=("auto", "closed", "named"),
                   help="closed: every quantity expanded and simplified (s12, c1 shorthand); named: "
                        "in terms of named intermediate quantities; auto (default): closed up to 3 joints")
    p.add_argument("--pose", metavar="X,Y,Z,QX,QY,QZ,QW",
                   help="platform robots: the pose of the platform frame (position, m; quaternion x, y, z, w) "
                        "the derivation is evaluated at (default: the file's home pose)")
    p.add_argument("--twist", metavar="WX,WY,WZ,VX,VY,VZ",
                   help="platform robots: the platform's twist t_M = [omega; c_dot] (rad/s, m/s; default 0)")
    p.add_argument("--qdd", metavar="A1,...,A6",
                   help="platform robots: the actuated joints' accelerations for phi (default 0)")
    p.add_argument("--digits", type=int, default=DEFAULT_DIGITS, metavar="N",
                   help=f"print numbers as decimals of N significant digits (1 to {MAX_DIGITS}; default "
                        f"{DEFAULT_DIGITS}); the derivation itself is exact, integers stay exact")
    p.add_argument("--quiet", action="store_true",
                   help=f"no progress line (shown on a terminal when a derivation takes over {PROGRESS_AFTER:g} s)")
    p.set_defaults(run=run)


#: the most joints --form closed is accepted for (measured on the 2-core reference machine: a
#: 4-joint SCARA by Lagrange-Euler 9 s; the 6-joint Stanford arm by Newton-Euler 87 s, the
#: Puma 560 over 100 s)
CLOSED_FORM_MAX_DOF = 4

#: the largest magnitude of a --pose, --twist or --qdd entry
MAX_STATE_VALUE = 1e9

#: seconds after which a derivation still running shows its progress (on a terminal)
PROGRESS_AFTER = 2.0


def _numbers(text, count: int, option: str):
    """``count`` comma-separated finite numbers (never evaluated as code), or None."""
    import math
    if text is None:
        return None
    parts = [t.strip() for t in str(text).split(",")]
    if len(parts) != count:
        raise SymdynError(f"{option} takes {count} comma-separated numbers, not {len(parts)}")
    try:
        values = [float(t) for t in parts]
    except ValueError:
        raise SymdynError(f"{option}: not a number in {str(text)[:60]!r}") from None
    if not all(math.isfinite(v) for v in values):
        raise SymdynError(f"{option}: every number must be finite")
    if any(abs(v) > MAX_STATE_VALUE for v in values):
        raise SymdynError(f"{option}: every number must be at most {MAX_STATE_VALUE:g} in magnitude (m, rad/s, "
                          "m/s, N: the printout's products would overflow)")
    return values


def _parallel_text(args, robot):
    """Check a platform robot's options; returns the function that derives and renders it
    (symdyn.derive.parallel_steps)."""
    from ..derive.parallel_steps import parallel_steps
    from ..emit.parallel_printout import render_parallel
    refused = [flag for flag, on in (("--method", args.method != "newton-euler"), ("--steps", args.steps != "all"),
                                     ("--form", args.form != "auto"), ("--base-parameters", args.base_parameters),
                                     ("--task", args.task)) if on]
    if refused:
        raise SymdynError(f"{args.robot}: {refused[0]} does not apply to a platform robot (kind: parallel)")
    pose = _numbers(args.pose, 7, "--pose")
    twist = _numbers(args.twist, 6, "--twist")
    qdd = _numbers(args.qdd, 6, "--qdd")

    def text(progress):
        if progress is not None:
            progress(f"{robot.name}: natural orthogonal complement")
        return render_parallel(parallel_steps(robot, pose, twist, qdd), args.format,
                               source_name=os.path.basename(args.robot), source_hash=robot.source_hash,
                               digits=args.digits)
    return text


def _serial_text(args, robot):
    """Check a serial robot's options; returns the function that derives and renders it."""
    if args.pose or args.twist or args.qdd:
        raise SymdynError("--pose, --twist and --qdd apply to platform robots (kind: parallel) only")
    check_size(robot, args, args.robot)
    closed = {"auto": None, "closed": True, "named": False}[args.form]
    if closed and robot.dof > CLOSED_FORM_MAX_DOF:
        raise SymdynError(f"{args.robot}: --form closed expands every quantity in the joint variables, which does not "
                          f"finish in minutes beyond {CLOSED_FORM_MAX_DOF} joints (this robot has {robot.dof}; "
                          "6 joints take over 100 s by Newton-Euler): use --form named (the default for more "
                          "than 3 joints)")
    if args.method in ("articulated-body", "aba"):
        if closed:
            raise SymdynError("--form closed: the articulated-body derivation is printed in the named form "
                              "only (its quantities are rational in the joint variables)")
        closed = None
    if args.task and robot.dof > TASK_CLOSED_FORM_MAX_DOF:
        raise SymdynError(f"{args.robot}: --task prints closed forms, kept to robots of up to {TASK_CLOSED_FORM_MAX_DOF} "
                          f"joints (this one has {robot.dof}); the task-space C functions have no such limit "
                          "(symdyn generate --functions task_space)")
    return lambda progress: render(
        derive_steps(robot, args.method, args.steps, closed, args.base_parameters, progress=progress, task=args.task),
        args.format,
        source_name=os.path.basename(args.robot), source_hash=robot.source_hash, digits=args.digits,
        progress=progress)


def run(args) -> int:
    """Load, check the options and where ``--out`` goes (before the derivation, which can take
    long), derive, render (on a terminal with a progress line once it takes over
    :data:`PROGRESS_AFTER` seconds, unless ``--quiet``), and print or write
    (:func:`symdyn.model.files.write_files`, the inputs protected)."""
    from ..model.scene import input_files
    if not 1 <= args.digits <= MAX_DIGITS:
        raise SymdynError(f"--digits must be from 1 to {MAX_DIGITS}, not {args.digits}")
    robot, _ = load_robot(args.robot, args, parallel=True)
    text_of = BY_KIND[kind_of(robot).name](args, robot)
    if args.out:
        directory, name = os.path.split(os.path.abspath(args.out))
        if not os.path.isdir(directory):
            raise SymdynError(f"cannot write {args.out}: directory {directory} does not exist")
        protect = input_files(args.robot)
        check_output_dir(directory, option="the directory of --out")
        check_targets(directory, [name], protect)
    progress = progress_printer(args, after=PROGRESS_AFTER, rewrite=True)
    try:
        text = text_of(progress)
    finally:
        if progress is not None:
            progress.close()
    if args.out:
        write_files(directory, {name: text.encode("utf-8")}, protect=protect)
    else:
        sys.stdout.write(text)
    return 0


#: how each kind of robot (symdyn.emit.pipeline.KINDS) is printed: a function of (args, robot)
#: giving the renderer of its derivation
BY_KIND = {SERIAL.name: _serial_text, PLATFORM.name: _parallel_text}
