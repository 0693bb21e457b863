"""``symdyn identify``: the base parameters of a robot from measured samples, by least squares.

Reads the robot (a robot file, scene or URDF) and a CSV of samples (:mod:`symdyn.model.samples`),
derives the base regressor (cached), solves for the base parameters (:mod:`symdyn.check.identify`)
and prints a table: each base parameter, its expression in the standard parameters, the value
identified, its standard deviation (absolute and relative) and the robot file's value. With
``--out`` it writes a robot file with the identified values where they are identifiable: viscous
and Coulomb friction and armature that no other parameter is regrouped with, and a link's mass,
centre of mass and inertia when all ten of its inertial parameters are identifiable one by one;
every base parameter's value is listed in the file's comments.
"""

from __future__ import annotations

import os

import numpy as np
import sympy as sp

from ..derive.cache import derive_cached
from ..derive.regressor import LINK_PARAMETERS, PER_LINK, parameter_names, standard_parameters
from ..model.errors import SymdynError
from ..model.files import write_atomic
from ..model.samples import sample_blocks
from .common import add_method_option, add_size_options, check_size, load_robot, progress_printer
from ..model.scene import input_files

HELP = "identify the base parameters from measured samples (CSV of q, qd, qdd, tau) by least squares"


def add_parser(sub) -> None:
    p = sub.add_parser("identify", help=HELP, description=HELP + ". The CSV has a header naming the "
                       "columns q1..qN, qd1..qdN, qdd1..qddN, tau1..tauN (any order) and one sample per row "
                       "(SI units, rad; '#' lines are comments).")
    p.add_argument("robot", metavar="ROBOT", help="robot file, scene, URDF or MuJoCo MJCF (numeric link geometry)")
    p.add_argument("data", metavar="DATA.csv", help="the samples")
    p.add_argument("--weighted", action="store_true",
                   help="weight each joint's equations by the inverse standard deviation of its residual "
                        "(from a first, unweighted solve)")
    p.add_argument("--out", metavar="FILE.yaml", help="write a robot file with the identified values where they "
                   "are identifiable (atomically; never over an input)")
    add_method_option(p)
    add_size_options(p)  # --max-joints, and --tip, --tool, --exact-angles for a URDF
    p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    p.set_defaults(run=run)


def run(args) -> int:
    from ..check.identify import identify
    robot, _ = load_robot(args.robot, args)
    check_size(robot, args, args.robot)
    # the whole file is checked before the derivation (a bad line fails at once), and read again
    # block by block by the fit: memory does not grow with the samples
    count = sum(block.count for block in sample_blocks(args.data, robot.dof))
    if args.out:
        from ..model.files import check_targets
        directory, name = os.path.split(os.path.abspath(args.out))
        if not os.path.isdir(directory):
            raise SymdynError(f"cannot write {args.out}: directory {directory} does not exist")
        check_targets(directory, [name], input_files(args.robot) + [args.data])
    eqs = derive_cached(robot, args.method, ("base_regressor",), progress=progress_printer(args))
    p = None
    if robot.parameters:
        missing = [s.name for s, v in zip(robot.parameters, robot.nominal) if v is None]
        if missing:
            raise SymdynError(f"{args.robot}: runtime parameters {', '.join(missing)} have no value; identify needs them")
        p = [float(v) for v in robot.nominal]
    result = identify(eqs, sample_blocks(args.data, robot.dof), args.weighted, p, source=os.path.basename(args.data))
    nominal = _file_values(eqs)
    if not args.quiet:
        _print(args, eqs, result, nominal, count)
    if args.out:
        text = _identified_robot_file(args, eqs, result)
        _check_readable(text, args.out)
        write_atomic(args.out, text.encode("utf-8"), protect=input_files(args.robot) + [args.data])
        if not args.quiet:
            print(f"wrote {args.out}")
    return 0


def _file_values(eqs):
    """The robot file's value of each base parameter (None where a parameter is symbolic)."""
    symbols = [sp.Symbol(n, real=True) for n in parameter_names(eqs.robot)]
    values = dict(zip(symbols, (sp.sympify(v).xreplace(eqs.robot.nominal_values()) for v in standard_parameters(eqs.robot))))
    out = []
    for _, expr in eqs.base_parameters:
        value = expr.xreplace(values)
        out.append(float(value) if value.is_number else None)
    return out


def _print(args, eqs, result, nominal, count) -> None:
    print(f"symdyn identify {args.robot} {args.data}: {count} samples, {result.rows} equations, "
          f"{len(result.names)} base parameters{', weighted per joint' if args.weighted else ''}")
    print(f"condition number of the stacked regressor: {result.condition:.3g}; residual RMS per joint: "
          + ", ".join(f"{r:.3g}" for r in result.residual_rms))
    print(f"{'parameter':<10} {'identified':>14} {'std':>11} {'std %':>8} {'file value':>14}  expression")
    for k, name in enumerate(result.names):
        value, std = result.values[k], result.std[k]
        relative = f"{100 * std / abs(value):8.2f}" if abs(value) > 1e-12 else "       -"
        file_value = f"{nominal[k]:14.6g}" if nominal[k] is not None else f"{'-':>14}"
        expression = sp.sstr(eqs.base_parameters[k][1])
        shown = expression if len(expression) <= 100 else expression[:99] + "…"
        print(f"{name:<10} {value:14.6g} {std:11.3g} {relative} {file_value}  {shown}")


def _check_readable(text: str, out: str) -> None:
    """Refuse to write a robot file symdyn would not read back (an identified mass that is
    negative, a damping beyond the limits, ...): one line naming the problem."""
    import warnings
    from ..model.errors import SymdynWarning
    from ..model.robot import loads
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SymdynWarning)
            loads(text, out)
    except SymdynError as exc:
        raise SymdynError(f"not writing {out}: symdyn would refuse the identified robot file ({exc}); the samples "
                          "do not determine physical values: excite the robot more, or check the data") from None


def _identified_robot_file(args, eqs, result) -> str:
    """The robot file's document with the identifiable values replaced (see the module's
    documentation), as YAML with the identification in comments."""
    from .convert import document_to_yaml
    from ..model.scene import is_robot_xml, read_robot_document
    robot = eqs.robot
    if is_robot_xml(args.robot):
        doc, _, _ = read_robot_document(args.robot, args.tip, args.tool, exact_angles=args.exact_angles)
    else:
        import yaml
        from ..model.inputs import SafeLoader, decode_text, read_input
        doc = yaml.load(decode_text(read_input(args.robot), args.robot), Loader=SafeLoader)
        if not isinstance(doc, dict) or "links" not in doc:
            raise SymdynError(f"--out needs a robot file or URDF, not a scene ({args.robot})")
    names = parameter_names(robot)
    symbols = [sp.Symbol(n, real=True) for n in names]
    alone = {}  # standard parameter index -> identified value, where a base parameter is it alone
    for k, (_, expr) in enumerate(eqs.base_parameters):
        if expr in symbols:
            alone[symbols.index(expr)] = float(result.values[k])
    changed = []
    for j, link in enumerate(doc["links"]):
        base = PER_LINK * j
        for field, c in (("armature", 10), ("damping", 11), ("coulomb", 12)):
            if base + c in alone:
                link[field] = alone[base + c]
                changed.append(f"{names[base + c]} -> link {j + 1} {field}")
        if all(base + c in alone for c in range(10)):
            m, mx, my, mz, ixx, ixy, iyy, ixz, iyz, izz = (alone[base + c] for c in range(10))
            if m > 0:
                com = np.array([mx, my, mz]) / m
                origin = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
                central = origin - m * (com @ com * np.eye(3) - np.outer(com, com))
                link["mass"] = m
                link["com"] = [float(x) for x in com]
                link["inertia"] = {"xx": float(central[0, 0]), "yy": float(central[1, 1]), "zz": float(central[2, 2]),
                                   "xy": float(central[0, 1]), "xz": float(central[0, 2]), "yz": float(central[1, 2])}
                changed.append(f"link {j + 1} mass, com, inertia")
    comments = [f"Identified by symdyn identify from {os.path.basename(args.data)} ({len(result.names)} base "
                f"parameters, condition number {result.condition:.3g}), robot {os.path.basename(args.robot)}.",
                "Values written: " + ("; ".join(changed) if changed else "none (every identified parameter is a "
                                       "combination; see below)") + ".",
                "Base parameters (identified value +- standard deviation = expression in the standard parameters):"]
    for k, name in enumerate(result.names):
        comments.append(f"  {name} = {result.values[k]:.9g} +- {result.std[k]:.3g} = {sp.sstr(eqs.base_parameters[k][1])}")
    comments.append("Standard parameters per link: " + ", ".join(LINK_PARAMETERS) + " (symdyn.derive.regressor).")
    return document_to_yaml(doc, comments)
