"""The library API under ``symdyn generate``: what to generate, resolved once, and one function
that derives and emits it, for every kind of robot.

>>> from symdyn.emit.pipeline import GenerateOptions, configure, generate
>>> config = configure("robots/puma560.yaml", GenerateOptions(precision="float"))
>>> files = generate(config)          # {"puma560_dynamics.h": b"...", "puma560_dynamics.c": b"..."}
>>> owners = provenance(config, files)  # what write_files checks before replacing a file

:class:`GenerateOptions` is what a user asks for (``None``: the scene's choice, else the
default); :func:`configure` loads the input (robot file, URDF, scene or platform robot), looks up
its :class:`RobotKind`, checks the options against it and applies the scene's defaults, giving
a :class:`GenerateConfig`; :func:`generate` derives (through the cache) and emits, writing
nothing.  Each kind of robot registers its functions, the options that apply to it and its
emitter once, in :data:`KINDS`.
"""

from __future__ import annotations

import functools
import math
import os
from dataclasses import dataclass, field, replace
from typing import Callable

from ..derive.articulated_loops import LOOPED_ABA_FROM_DOF
from ..derive.articulated_loops import applies as loops_apply
from ..derive.cache import derive_cached
from ..model.outputs import PLATFORM_REGISTRY as PLATFORM_FUNCTIONS
from ..model.errors import SymdynError, describe
from ..model.files import Provenance
from ..model.outputs import ALL_OUTPUTS, COMBINED, OUTPUTS, default_outputs, with_requirements
from ..model.parallel import ParallelRobot
from ..model.robot import MAX_NAME, ROBOT_NAME_PATTERN, Robot
from .cgen import PRECISION_CHOICES
from .emission import source_label

TARGETS = ("c", "casadi", "casadi-c")


@dataclass(frozen=True)
class GenerateOptions:
    """What to generate.  ``functions``: names or a comma-separated text (None: the scene's, else
    the kind's default); ``precision`` (None: the scene's, else double); ``fd_method`` (None:
    ``ldlt`` in double, ``aba`` in float); ``size_report``: a function ``(files, prefix=...)``
    measuring code size and stack use (:func:`symdyn.check.firmware.measure`), or None;
    ``name``: the C prefix and file names (``NAME_dynamics.h``, ``NAME_forward_dynamics``, ...)
    instead of the robot's or scene's own name, for one input (None: the input's name);
    ``c_file_mb``: C of more megabytes than this is written as several files (None: the default,
    :data:`symdyn.emit.cgen.C_FILE_BYTES`; 0: always one file)."""

    functions: tuple[str, ...] | str | None = None
    precision: str | None = None
    target: str = "c"
    method: str = "newton-euler"
    fd_method: str | None = None
    parameters: str = "standard"
    header_only: bool = False
    batch: bool = False
    size_report: Callable | None = None
    use_cache: bool = True
    name: str | None = None
    c_file_mb: float | None = None


@dataclass(frozen=True)
class RobotKind:
    """One kind of robot the pipeline generates code for.

    ``options``: the names of the :class:`GenerateOptions` fields that apply beyond
    ``functions``, ``precision`` and ``target`` (the others are refused when set);
    ``parse_functions(text or names or None, robot)``: the functions asked, checked;
    ``emit(config, progress)``: ``{file name: bytes}``."""

    name: str
    label: str
    plural: str
    robot_type: type
    functions: tuple[str, ...]
    precisions: tuple[str, ...]
    targets: tuple[str, ...]
    options: frozenset
    parse_functions: Callable
    emit: Callable


@dataclass(frozen=True)
class GenerateConfig:
    """A generation resolved once: the input, its kind, and every choice made."""

    path: str
    robot: object
    scene: object
    kind: RobotKind
    options: GenerateOptions
    functions: tuple[str, ...]
    precision: str
    fd_method: str
    notes: tuple[str, ...] = field(default=())

    @property
    def source_name(self) -> str:
        return os.path.basename(self.path)


def default_fd_method(precision: str, robot=None) -> str:
    """How forward dynamics is solved unless asked: LDL^T of D in double (fewer operations,
    faster on the bundled arms), the articulated-body algorithm in float (about twice as
    accurate there: chain12 3e-5 against 6e-5; docs/benchmarks.md); a kinematic tree's
    ``robot`` always by the L^T D L factorization of its mass matrix ("ldlt")."""
    return "aba" if precision == "float" and not getattr(robot, "is_tree", False) else "ldlt"


def parse_functions(text, robot=None) -> tuple[str, ...]:
    """The serial functions named by ``text`` (comma-separated, or a sequence of names), in
    registry order; ``None`` or empty: the standard outputs.  The name of a combined function
    (``task_space``, ``kinematics``) stands for its parts (the combined function is emitted
    with them)."""
    if text and isinstance(text, str):
        text = ",".join(",".join(COMBINED.get(t.strip(), (t.strip(),))) for t in text.split(","))
    elif text:
        text = [part for t in text for part in COMBINED.get(t, (t,))]
    return _parse(text, ALL_OUTPUTS, OUTPUTS, "")


def parse_platform_functions(text, robot=None) -> tuple[str, ...] | None:
    """The platform functions named by ``text``; ``None``: all of them."""
    if not text:
        return None
    return _parse(text, PLATFORM_FUNCTIONS, PLATFORM_FUNCTIONS, " for a platform robot")


def _parse(text, known, default, where: str) -> tuple[str, ...]:
    if not text:
        return tuple(default)
    names = [t.strip() for t in text.split(",") if t.strip()] if isinstance(text, str) else list(text)
    unknown = [n for n in names if n not in known]
    if unknown:
        raise SymdynError(f"unknown function '{unknown[0]}' in --functions{where} (known: {', '.join(known)})")
    if not names:
        raise SymdynError("--functions lists no function")
    return tuple(n for n in known if n in names)


def scene_choices(robot, scene, functions=None, precision=None, default_functions=None):
    """``(functions, precision, notes)``: what was asked, else the scene's choice, else the
    defaults (``default_functions``, or the robot's default outputs; double; the robot's notes).
    The one place where a scene's defaults apply (generate, verify and bench read it)."""
    notes = tuple(getattr(robot, "notes", ()))
    if scene is not None:
        functions = functions or scene.functions
        precision = precision or scene.precision
        notes = scene.notes
    if not functions:
        functions = default_functions if default_functions is not None else default_outputs(robot)
    return tuple(functions), precision or "double", notes


#: from this many joints, forward dynamics in double (unless --fd-method says) is derived both
#: ways and the form with fewer operations is emitted; below it LDL^T always had fewer (the
#: bundled arms and generic chains of 6 and 7 joints; at 12 the articulated-body algorithm has
#: fewer: docs/benchmarks.md)
AUTO_FD_FROM_DOF = 10

#: from this many joints the articulated-body algorithm is taken without building LDL^T's C to
#: compare: LDL^T's operations grow as n^3 and ABA's as n (generic chains: 9561 against 6986
#: multiplications at 24 joints; at 48 LDL^T's 39,004 are twice ABA's at 64, 19,272), and
#: building both took a 64-joint generation from 74 to 123 s
AUTO_FD_ABA_FROM_DOF = 24


def choose_fd_method(config: GenerateConfig, progress=None) -> GenerateConfig:
    """``config`` with its forward-dynamics method settled by operation count (deterministic:
    the counts of the emitted C, mul + add + div, ties to LDL^T) where no method was asked for,
    the arithmetic is double and the chain has at least :data:`AUTO_FD_FROM_DOF` joints (from
    :data:`AUTO_FD_ABA_FROM_DOF`, the articulated-body algorithm without counting); from
    :data:`~symdyn.derive.articulated_loops.LOOPED_ABA_FROM_DOF` joints, where the
    articulated-body algorithm's loop form applies and is kept (its operations no more than
    the chain written out), that; the header notes the choice."""
    from .cgen import build_function
    robot, options = config.robot, config.options
    if options.fd_method or config.precision != "double" or "forward_dynamics" not in config.functions \
            or robot.dof < min(AUTO_FD_FROM_DOF, LOOPED_ABA_FROM_DOF) or robot.is_tree:
        return config
    if loops_apply(robot) and robot.dof < AUTO_FD_ABA_FROM_DOF:  # from there ABA without deriving to choose
        eqs = derive_cached(robot, options.method, with_requirements(["forward_dynamics"]), use_cache=options.use_cache,
                            progress=progress, fd_method="aba", parameters=options.parameters)
        if eqs.fd_loops:
            note = ("forward dynamics by the articulated-body algorithm as loops over the joints (a fixed-base chain of "
                    f"{LOOPED_ABA_FROM_DOF} revolute joints or more whose joints' step costs no more than the chain "
                    "written out: code that does not grow with n, faster than either written-out form)")
            return replace(config, fd_method="aba", notes=(*config.notes, note))
    if robot.dof < AUTO_FD_FROM_DOF:
        return config
    if robot.dof >= AUTO_FD_ABA_FROM_DOF:
        note = (f"forward dynamics by the articulated-body algorithm (O(n) operations; from {AUTO_FD_ABA_FROM_DOF} "
                "joints LDL^T of D, O(n^3), always needs more)"
                + ("; as loops over the joints where its step costs no more than the chain written out"
                   if loops_apply(robot) else ""))
        return replace(config, fd_method="aba", notes=(*config.notes, note))
    counts = {}
    for method in ("ldlt", "aba"):
        eqs = derive_cached(robot, options.method, with_requirements(["forward_dynamics"]), use_cache=options.use_cache,
                            progress=progress, fd_method=method, parameters=options.parameters)
        ops = build_function(eqs, "forward_dynamics", config.precision, robot.name).ops
        counts[method] = ops["mul"] + ops["add"] + ops["div"]
    chosen = "aba" if counts["aba"] < counts["ldlt"] else "ldlt"
    note = (f"forward dynamics by {'the articulated-body algorithm' if chosen == 'aba' else 'LDL^T of D'}, "
            f"chosen by operation count: {counts['aba']} (articulated-body) against {counts['ldlt']} (LDL^T)")
    return replace(config, fd_method=chosen, notes=(*config.notes, note))


def _derive_serial(config: GenerateConfig, progress=None):
    """``(config, eqs)``: the derivation of the functions to generate.  Where the mass matrix is
    singular for every q (a massless subtree: Romeo's hands) and the functions are the defaults
    (none asked for, by the command or the scene), the functions that solve with it are left out,
    with one warning and a header note that name the joints; asked for, they are refused."""
    from ..derive.equations import SingularMassMatrix
    from ..model.errors import one_line, warn
    from ..model.outputs import factors_mass_matrix
    robot, options = config.robot, config.options

    def derive(functions):
        return derive_cached(robot, options.method, with_requirements(functions), use_cache=options.use_cache,
                             progress=progress, fd_method=config.fd_method, parameters=options.parameters)
    try:
        return config, derive(config.functions)
    except SingularMassMatrix as exc:
        if options.functions or (config.scene is not None and config.scene.functions):
            raise
        dropped = [f for f in config.functions if factors_mass_matrix(f)]
        kept = tuple(f for f in config.functions if f not in dropped)
        reason = one_line(str(exc).removeprefix(f"{robot.source}: "), 400)  # (the header names no path)
        warn(f"{robot.source}: {reason} (generating the other default functions: {', '.join(dropped)} left out)")
        config = replace(config, functions=kept,
                         notes=(*config.notes, f"left out, the mass matrix being singular for every q: {', '.join(dropped)} "
                                f"({reason})"))
        return config, derive(kept)


def _emit_serial(config: GenerateConfig, progress=None) -> dict[str, bytes]:
    from .cgen import C_FILE_BYTES, generate_c
    config = choose_fd_method(config, progress)
    robot, options = config.robot, config.options
    config, eqs = _derive_serial(config, progress)
    if options.target == "c":
        report = None if options.size_report is None else functools.partial(options.size_report, prefix=robot.name)
        file_bytes = C_FILE_BYTES if options.c_file_mb is None else (int(options.c_file_mb * 1e6) or None)
        files = generate_c(eqs, config.functions, config.precision, options.header_only, file_bytes=file_bytes,
                           source_name=config.source_name, source_hash=robot.source_hash, notes=config.notes,
                           progress=progress, size_report=report, batch=options.batch,
                           locked=config.scene.locked if config.scene is not None else ())
        return {name: text.encode("utf-8") for name, text in files.items()}
    from .casadi_backend import casadi_files
    return casadi_files(eqs, config.functions, casadi_c=options.target == "casadi-c", source_name=config.source_name,
                        source_hash=robot.source_hash)


def _emit_platform(config: GenerateConfig, progress=None) -> dict[str, bytes]:
    from ..derive.parallel import derive_parallel
    robot = config.robot
    eqs = derive_parallel(robot, config.functions, progress=progress)
    if config.options.target == "c":
        from .parallel_c import generate_parallel_c
        files = generate_parallel_c(eqs, config.functions, config.precision, source_name=config.source_name,
                                    source_hash=robot.source_hash, progress=progress)
        return {name: text.encode("utf-8") for name, text in files.items()}
    from .parallel_casadi import parallel_casadi_files
    return parallel_casadi_files(eqs, config.functions, source_name=config.source_name,
                                 source_hash=robot.source_hash)


SERIAL = RobotKind(
    name="serial", label="a serial robot", plural="serial robots", robot_type=Robot, functions=ALL_OUTPUTS,
    precisions=PRECISION_CHOICES, targets=TARGETS,
    options=frozenset({"method", "fd_method", "parameters", "header_only", "batch", "size_report", "c_file_mb"}),
    parse_functions=parse_functions, emit=_emit_serial)

PLATFORM = RobotKind(
    name="parallel", label="a platform robot (kind: parallel)", plural="platform robots", robot_type=ParallelRobot,
    functions=tuple(PLATFORM_FUNCTIONS), precisions=("double", "float"), targets=("c", "casadi"),
    options=frozenset(), parse_functions=parse_platform_functions, emit=_emit_platform)

#: every kind of robot, looked up by the type of the loaded robot
KINDS = (SERIAL, PLATFORM)

#: how each option is called on the command line, in the order refusals are reported
_FLAGS = (("header_only", "--header-only"), ("batch", "--batch"), ("size_report", "--size-report"),
          ("c_file_mb", "--c-file-mb"),
          ("parameters", "--parameters base"), ("fd_method", "--fd-method"), ("method", "--method"))
_UNSET = GenerateOptions()


def kind_of(robot) -> RobotKind:
    """The registered kind of a loaded robot."""
    for kind in KINDS:
        if isinstance(robot, kind.robot_type):
            return kind
    raise SymdynError(f"{getattr(robot, 'source', '') or robot!r}: not a robot symdyn generates code for")


def check_options(options: GenerateOptions) -> None:
    """Refuse combinations of options that apply to no robot (before anything is loaded)."""
    if options.target not in TARGETS:
        raise SymdynError(f"unknown target {options.target!r} (known: {', '.join(TARGETS)})")
    if options.target != "c" and (options.precision not in (None, "double") or options.header_only):
        raise SymdynError(f"--precision and --header-only apply to the c target only, not {options.target}")
    if options.batch and options.target != "c":
        raise SymdynError(f"--batch applies to the c target only, not {options.target}")
    if options.c_file_mb is not None and not (math.isfinite(options.c_file_mb) and options.c_file_mb >= 0):
        raise SymdynError(f"--c-file-mb {options.c_file_mb}: give 0 (always one file) or a positive number of megabytes")
    if options.size_report is not None and (options.target != "c" or options.header_only):
        raise SymdynError("--size-report applies to the c target with .h + .c files (not --header-only)")
    check_name(options.name)


def check_name(name) -> None:
    """Refuse a ``--name`` that is not a valid robot name (as a robot file's ``name``: lower-case
    letters, digits and '_', starting with a letter, at most :data:`~symdyn.model.robot.MAX_NAME`
    characters), in one line."""
    if name is not None and (not isinstance(name, str) or not ROBOT_NAME_PATTERN.match(name)
                             or len(name) > MAX_NAME):
        raise SymdynError(f"--name {describe(name)} is not a valid name: use lower-case letters, digits and "
                          f"'_', starting with a letter, at most {MAX_NAME} characters")


def check_inputs(paths, options: GenerateOptions) -> None:
    """Refuse options that need a single input when several are given (``--name``: one prefix
    for two robots would write the same files twice)."""
    if options.name is not None and len(paths) != 1:
        raise SymdynError(f"--name names the code of one input, but {len(paths)} were given: "
                          "generate each robot in its own run, with its own --name")


def check_kind_options(kind: RobotKind, options: GenerateOptions, path: str) -> None:
    """Refuse, in one line naming ``path``, the options that do not apply to ``kind``."""
    for name, flag in _FLAGS:
        if name not in kind.options and getattr(options, name) != getattr(_UNSET, name) \
                and not (name == "method" and options.method in (None, "newton-euler")):
            raise SymdynError(f"{path}: {flag} does not apply to {kind.label}")
    if options.precision is not None and options.precision not in kind.precisions:
        raise SymdynError(f"{path}: {kind.plural} are generated in {' or '.join(kind.precisions)} precision, "
                          f"not {options.precision}")
    if options.target not in kind.targets:
        raise SymdynError(f"{path}: --target {options.target} is not available for {kind.plural} "
                          f"(use {' or '.join(kind.targets)})")


def configure(path, options: GenerateOptions = _UNSET, loaded=None) -> GenerateConfig:
    """Resolve one input: load it (``loaded``: ``(robot, scene)`` when the caller has read it),
    look up its kind, check the options against it, and apply the scene's defaults."""
    from ..model.scene import load_input
    path = os.fspath(path)
    check_options(options)
    robot, scene = loaded if loaded is not None else load_input(path, parallel=True)
    kind = kind_of(robot)
    if options.name is not None:
        robot = replace(robot, name=options.name)
    check_kind_options(kind, options, path)
    functions = kind.parse_functions(options.functions, robot) if options.functions else None
    if kind is SERIAL:
        functions, precision, notes = scene_choices(robot, scene, functions, options.precision)
    else:
        functions, precision, notes = functions, options.precision or "double", ()
    return GenerateConfig(path=path, robot=robot, scene=scene, kind=kind, options=options, functions=functions,
                          precision=precision, fd_method=options.fd_method or default_fd_method(precision, robot),
                          notes=notes)


def generate(config: GenerateConfig, progress=None) -> dict[str, bytes]:
    """Derive (through the cache) and emit ``config``: ``{file name: content}``, written nowhere.
    ``progress``: called with a short text per derivation part and emitted function."""
    return config.kind.emit(config, progress)


def provenance(config: GenerateConfig, files) -> dict[str, Provenance]:
    """What each of ``files`` (the names :func:`generate` returned for ``config``) says it was
    generated from: the input's file name as the banners print it and the SHA-256 they give.
    :func:`symdyn.model.files.write_files` (``owners=``) compares it with the banner of a file it
    would replace; a binary ``.casadi`` file has no banner, the ``NAME_casadi.txt`` written with
    it speaks for it."""
    origin = Provenance(source_label(config.source_name), config.robot.source_hash)
    readme = f"{config.robot.name}_casadi.txt"
    return {name: replace(origin, banner=readme) if name.endswith(".casadi") and readme in files else origin
            for name in files}
