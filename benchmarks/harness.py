"""The benchmark harness: symdyn's generated C against Pinocchio's C++ and against the
Pinocchio -> CasADi code-generation peer, timed alike in one process.

Usage:  python benchmarks/harness.py ROBOT_OR_N ... [--functions LIST] [--processes 5] [--passes 15]
            [--states 10000] [--flags O2,O3native] [--no-peer] [--seed 2026] [--smoke] [--keep DIR]
            [--precision float] [--batch] [--casadi]
        (--smoke: 1 process, 2 passes, 200 states, -O2 only: checks that every step runs)

ROBOT_OR_N: a name (robots/NAME.yaml) or a number N (the generic N-joint chain of
benchmarks/long_chains.py, ``generic_chain(N)``).  Functions (default all six) and their
counterparts: inverse_dynamics - rnea, mass_matrix - crba, gravity - computeGeneralizedGravity,
coriolis - nonLinearEffects (Pinocchio's includes gravity, symdyn's h does not),
coriolis_matrix - computeCoriolisMatrix, forward_dynamics - aba.

Method (every choice is the same for all three sides):

- symdyn's C is what ``symdyn generate ROBOT --functions LIST`` writes (the library pipeline,
  every automatic choice applied, e.g. the forward-dynamics method); Pinocchio's model is
  symdyn.check.pinocchio_model.build_model of the same robot, saved with ``saveToText`` and
  loaded by the timing program; the peer (benchmarks/harness_peer.cpp) casts that model to
  ``casadi::SX``, runs Pinocchio's algorithms on symbolic inputs and writes CasADi's C
  (``cse`` on).  For crba and aba both of Pinocchio's conventions (LOCAL, WORLD) are timed, on
  both Pinocchio and the peer, and the faster (lower median) is reported.
- One program per flag set (-O2; -O3 -march=native; each with -ffp-contract=off, and
  O3nativefma: -O3 -march=native -ffp-contract=fast): benchmarks/harness_main.c, symdyn's C, the
  peer's C (gcc -std=c99) and Pinocchio (benchmarks/harness_pinocchio.cpp, g++ -std=c++17), all
  with the same GCC and the same flags.  O2libm and O3nativelibm are O2 and O3native with
  symdyn's C compiled with -DSYMDYN_LIBM_TRIG (the C library's sin() and cos() instead of the
  generated sin/cos block): how much of the lead that block gives.
- States: ``--states`` seeded random states (q in [-pi, pi], qd in [-2, 2], qdd in [-5, 5],
  tau in [-20, 20]) written to one binary file that the program reads into the arrays every side
  reads.
- Time: thread CPU time (CLOCK_THREAD_CPUTIME_ID) of a pass over all states; the sides of one
  function take turns pass after pass (``--passes``, order rotated), after a warm-up pass; per
  process the median pass of each side; results summed into a printed checksum.
- ``--processes`` runs of the program, each from a fresh copy of the binary (shutil.copy to a
  new name: where the code lands in memory alone can move a big function's time by up to 2x).
  Reported: per side the median over processes and the min-max range; the ratios Pinocchio /
  symdyn and peer / symdyn per process, their median and min-max (> 1: symdyn is faster).
- Before timing, the peer's result on the first state is checked against Pinocchio's (they
  compute the same quantities); a difference beyond 1e-6 of the largest entry stops the run.
- More of symdyn's sides on request, in the same passes: ``--batch`` the batch functions
  (``NAME_f_batch`` over all states in one call, its time per state; checked against the scalar
  function on the first states), ``--casadi`` symdyn's CasADi functions compiled from CasADi's C
  (``symdyn generate --target casadi-c``).  ROBOT_OR_N may be a scene file (runtime parameters
  passed at the values in the file, Pinocchio's model built with them) and ``--precision float``
  times symdyn's float C (Pinocchio and the peer stay in double).  A function of symdyn's that
  Pinocchio lacks (e.g. ``inverse_dynamics_dq``) is timed on symdyn's sides only.

The Pinocchio objects and the peer's generator take minutes to compile (Pinocchio's templates);
they are built once per flag set and toolchain and kept in $SYMDYN_BENCH_CACHE (default
~/.cache/symdyn/bench-build).  Library use: :func:`run` and :func:`markdown`.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import fcntl
import hashlib
import importlib.metadata
import os
import re
import shutil
import statistics
import subprocess
import sys
import sysconfig
import tempfile
import time
from dataclasses import dataclass, field

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)
if HERE not in sys.path:
    sys.path.insert(0, HERE)

#: the flag sets, each used for every side.  Contraction of a*b + c into fused multiply-adds is
#: set explicitly: gcc -std=c99 leaves it off by default but g++ -std=c++17 turns it on, so the
#: same flags without it would give Pinocchio FMAs that the C sides do not get (-march=native).
#: O3nativefma: all sides with contraction.
FLAG_SETS = {"O2": ("-O2", "-ffp-contract=off"), "O3native": ("-O3", "-march=native", "-ffp-contract=off"),
             "O3nativefma": ("-O3", "-march=native", "-ffp-contract=fast"),
             "O2libm": ("-O2", "-ffp-contract=off"), "O3nativelibm": ("-O3", "-march=native", "-ffp-contract=off")}
#: defines for symdyn's C only, per flag set: the *libm sets compute the joints' sines and
#: cosines with the C library's sin() and cos(), one call each, instead of the generated code's
#: vectorized block (SYMDYN_LIBM_TRIG), to measure how much of symdyn's lead that block gives
#: (the other sides are compiled exactly as in the set without "libm")
SYMDYN_DEFINES = {"O2libm": ("-DSYMDYN_LIBM_TRIG",), "O3nativelibm": ("-DSYMDYN_LIBM_TRIG",)}


def flag_label(flag_set: str) -> str:
    """The flags of a set as the tables show them (symdyn-only defines marked)."""
    extra = SYMDYN_DEFINES.get(flag_set, ())
    return " ".join(FLAG_SETS[flag_set]) + (f" (symdyn: {' '.join(extra)})" if extra else "")
#: the functions timed by default (the tool kinematics and task_space on request, e.g. --functions kinematics)
FUNCTIONS = ("inverse_dynamics", "mass_matrix", "gravity", "coriolis", "coriolis_matrix", "forward_dynamics")
#: symdyn function -> (Pinocchio's functions timed for it (the faster is reported), the part of
#: benchmarks/harness_pinocchio.cpp that holds them)
PINOCCHIO = {"inverse_dynamics": (("rnea",), "RNEA"),
             "mass_matrix": (("crba_local", "crba_world"), "CRBA"),
             "gravity": (("computeGeneralizedGravity",), "RNEA"),
             "coriolis": (("nonLinearEffects",), "RNEA"),
             "coriolis_matrix": (("computeCoriolisMatrix",), "RNEA"),
             "forward_dynamics": (("aba_local", "aba_world"), "ABA"),
             "task_space": (("taskSpace",), "TASK"),
             "forward_kinematics": (("framePlacement",), "KIN"),
             "jacobian": (("frameJacobian",), "KIN"),
             "jacobian_dot_qd": (("frameClassicalAcceleration",), "KIN"),
             "kinematics": (("framePlacementJacobian",), "KIN"),
             "inverse_dynamics_derivatives": (("rneaDerivatives",), "DERIV"),
             "gravity_derivative": (("gravityDerivatives",), "DERIV"),
             "forward_dynamics_derivatives": (("abaDerivatives",), "DERIV"),
             "mass_matrix_inverse": (("computeMinverse",), "DERIV"),
             "frame_poses": (("framePoses_all", "framePoses_each"), "FRAMES"),
             "frame_jacobians": (("frameJacobians_all", "frameJacobians_each"), "FRAMES"),
             "frame_jacobian_dot_v": (("frameJacobianDotV",), "FRAMES"),
             "frame_kinematics": (("frameKinematics",), "FRAMES"),
             "center_of_mass": (("centerOfMass_subtrees", "centerOfMass_whole"), "CENT"),
             "center_of_mass_jacobian": (("jacobianCenterOfMass_subtrees", "jacobianCenterOfMass_whole"), "CENT"),
             "center_of_mass_bias": (("centerOfMassBias",), "CENT"),
             "centroidal_momentum_matrix": (("ccrba_ccrba", "ccrba_map"), "CENT"),
             "centroidal_bias": (("centroidalBias",), "CENT"),
             "contact_forward_dynamics": (("constraintDynamics",), "CONTACT"),
             "contact_forward_dynamics_derivatives": (("constraintDynamicsDerivatives",), "CONTACT")}
#: parts of Pinocchio's side in a source of their own (benchmarks/harness_pinocchio_task.cpp,
#: harness_pinocchio_kin.cpp), so that adding them leaves the cached objects of the others valid
OWN_SOURCE_PARTS = {"TASK": "harness_pinocchio_task.cpp", "KIN": "harness_pinocchio_kin.cpp",
                    "CENT": "harness_pinocchio_centroidal.cpp", "FRAMES": "harness_pinocchio_frames.cpp",
                    "DERIV": "harness_pinocchio_derivatives.cpp",
                    "FLOAT": "harness_pinocchio_floating.cpp", "CONTACT": "harness_pinocchio_contact.cpp"}
#: a floating base's Pinocchio calls that read q as nq numbers (benchmarks/harness_pinocchio_floating.cpp,
#: part FLOAT), in place of these; the peer and the cross-check keep the original names
FLOATING_VARIANTS = {"rnea": "rneaFF", "nonLinearEffects": "nonLinearEffectsFF",
                     "computeCoriolisMatrix": "computeCoriolisMatrixFF", "aba_local": "abaFF_local",
                     "aba_world": "abaFF_world"}
#: the Pinocchio functions the CasADi peer has (benchmarks/harness_peer.cpp); the others are
#: timed without a peer column
PEER_VARIANTS = ("rnea", "computeGeneralizedGravity", "nonLinearEffects", "computeCoriolisMatrix", "crba_local",
                 "crba_world", "aba_local", "aba_world", "rneaDerivatives", "abaDerivatives", "computeMinverse")
PINOCCHIO_ARGUMENTS = {"rnea": "Q, QD, QDD", "computeGeneralizedGravity": "Q", "nonLinearEffects": "Q, QD",
                       "computeCoriolisMatrix": "Q, QD", "crba_local": "Q", "crba_world": "Q",
                       "aba_local": "Q, QD, TAU", "aba_world": "Q, QD, TAU", "taskSpace": "Q, QD",
                       "framePlacement": "Q", "frameJacobian": "Q", "frameClassicalAcceleration": "Q, QD",
                       "framePlacementJacobian": "Q", "centerOfMass_subtrees": "Q", "centerOfMass_whole": "Q",
                       "jacobianCenterOfMass_subtrees": "Q", "jacobianCenterOfMass_whole": "Q",
                       "centerOfMassBias": "Q, QD", "ccrba_ccrba": "Q, QD", "ccrba_map": "Q, QD", "centroidalBias": "Q, QD",
                       "framePoses_all": "Q", "framePoses_each": "Q",
                       "frameJacobians_all": "Q", "frameJacobians_each": "Q", "frameJacobianDotV": "Q, QD",
                       "frameKinematics": "Q, QD", "rneaDerivatives": "Q, QD, QDD", "gravityDerivatives": "Q",
                       "abaDerivatives": "Q, QD, TAU", "computeMinverse": "Q", "constraintDynamics": "Q, QD, TAU",
                       "constraintDynamicsDerivatives": "Q, QD, TAU"}


def pinocchio_of(function: str) -> tuple:
    """``PINOCCHIO[function]``, or ``((), None)`` for a function of symdyn's that Pinocchio has
    no counterpart of (e.g. the single derivatives ``inverse_dynamics_dq``): timed without a
    Pinocchio side, e.g. beside symdyn's CasADi functions (``--casadi``)."""
    return PINOCCHIO.get(function, ((), None))


STATE_ARRAYS = {"q": "Q", "qd": "QD", "qdd": "QDD", "tau": "TAU"}
#: Pinocchio's headers need these with the pin wheel's Boost (its joint visitors take more
#: arguments than Boost's default limits allow)
PINOCCHIO_DEFINES = ("-DNDEBUG", "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS", "-DBOOST_MPL_LIMIT_LIST_SIZE=30",
                     "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30", "-DBOOST_FUSION_INVOKE_MAX_ARITY=12",
                     "-DBOOST_FUSION_INVOKE_FUNCTION_OBJECT_MAX_ARITY=12",
                     "-DBOOST_FUSION_INVOKE_PROCEDURE_MAX_ARITY=12")
CHECK_TOLERANCE = 1e-6


# ----------------------------------------------------------------------------------- building

def site_paths() -> dict[str, str]:
    """Where the pin wheel's headers and libraries and the casadi wheel's are."""
    site = sysconfig.get_paths()["purelib"]
    prefix = os.path.join(site, "cmeel.prefix")
    return {"prefix": prefix, "include": os.path.join(prefix, "include"), "lib": os.path.join(prefix, "lib"),
            "casadi": os.path.join(site, "casadi"), "eigen": os.path.join(site, "casadi", "include", "eigen3")}


def pinocchio_compile_flags(extra_includes=()) -> list[str]:
    """g++ flags (beyond optimization) for code using Pinocchio's headers."""
    paths = site_paths()
    return ["-std=c++17", "-w", *PINOCCHIO_DEFINES, f"-I{paths['include']}", f"-I{paths['eigen']}",
            *(f"-I{d}" for d in extra_includes)]


def cache_dir() -> str:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.environ.get("SYMDYN_BENCH_CACHE") or os.path.join(base, "symdyn", "bench-build")


def toolchain() -> str:
    """What a cached build depends on beyond its sources and flags."""
    versions = []
    for package in ("pin", "casadi"):
        try:
            versions.append(f"{package} {importlib.metadata.version(package)}")
        except importlib.metadata.PackageNotFoundError:
            versions.append(f"{package} absent")
    compilers = [subprocess.run([c, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
                 for c in ("gcc", "g++")]
    return "; ".join(compilers + versions + [platform_cpu()])


def cached_build(label: str, sources, command, suffix: str = ".o") -> str:
    """The path of a build kept in :func:`cache_dir`, made by ``command(output_path)`` (the
    arguments of one compiler run) when no build of the same sources, command and toolchain is
    there: the key leaves out where the checkout and the virtual environment are, so that a fresh
    clone or venv with the same packages finds the builds.  Safe between processes (a lock per
    build)."""
    digest = hashlib.sha256(toolchain().encode())
    text = " ".join(command("OUTPUT"))
    for path, name in ((HERE, "<benchmarks>"), (sysconfig.get_paths()["purelib"], "<site-packages>")):
        text = text.replace(path, name)
    digest.update(text.encode())
    for source in sources:
        with open(source, "rb") as handle:
            digest.update(handle.read())
    folder = cache_dir()
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, f"{label}-{digest.hexdigest()[:16]}{suffix}")
    if os.path.exists(path):
        return path
    with open(path + ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not os.path.exists(path):
            print(f"building {label} (Pinocchio's templates: a minute or two, kept in {folder})...", file=sys.stderr)
            temporary = f"{path}.{os.getpid()}.tmp"
            build = subprocess.run(command(temporary), capture_output=True, text=True)
            if build.returncode != 0:
                raise RuntimeError(f"building {label} failed:\n{build.stderr[-4000:]}")
            os.replace(temporary, path)
    return path


def pinocchio_part(part: str, flags) -> str:
    """The cached object of one part of benchmarks/harness_pinocchio.cpp compiled with ``flags``."""
    source = os.path.join(HERE, OWN_SOURCE_PARTS.get(part, "harness_pinocchio.cpp"))
    return cached_build(f"pinocchio-{part.lower()}-{'_'.join(f.strip('-') for f in flags)}",
                        [source] if part in OWN_SOURCE_PARTS else [source, os.path.join(HERE, "harness_pinocchio.h")],
                        lambda out: ["g++", *flags, *pinocchio_compile_flags(), f"-DPART_{part}", "-c", source,
                                     "-o", out])


def pinocchio_object(source: str, label: str, flags, defines=()) -> str:
    """A cached object of a C++ timing source of benchmarks/ (which may include
    bench_timing.hpp) built against Pinocchio's headers with ``flags``."""
    path = os.path.join(HERE, source)
    return cached_build(f"{label}-{'_'.join(f.strip('-') for f in flags)}",
                        [path, os.path.join(HERE, "bench_timing.hpp")],
                        lambda out: ["g++", *flags, *pinocchio_compile_flags([HERE]), *defines, "-c", path, "-o", out])


def link_pinocchio(objects, exe: str, flags, extra=()) -> str:
    """Link a timing program from ``objects`` (and ``extra`` linker arguments) against the pin
    wheel's libraries."""
    paths = site_paths()
    subprocess.run(["g++", *flags, *objects, *extra, f"-L{paths['lib']}", "-lpinocchio_default",
                    "-lboost_serialization",
                    f"-Wl,-rpath,{paths['lib']}", "-lm", "-o", exe], check=True)
    return exe


def peer_generator() -> str:
    """The cached Pinocchio -> CasADi generator (benchmarks/harness_peer.cpp); its own speed does
    not enter any timing, so it is built once, at -O1."""
    source, paths = os.path.join(HERE, "harness_peer.cpp"), site_paths()
    return cached_build("peer-generator", [source], lambda out: [
        "g++", "-O1", *pinocchio_compile_flags([os.path.join(paths["casadi"], "include")]), source, "-o", out,
        f"-L{paths['casadi']}", "-lcasadi", f"-L{paths['lib']}", "-lboost_serialization",
        f"-Wl,-rpath,{paths['casadi']}", f"-Wl,-rpath,{paths['lib']}"], suffix="")


#: runs a command and prints its wall time and the peak memory of its largest process; a small
#: process of its own, because a child's peak memory starts at its parent's size at fork
_MEASURE = ("import resource, subprocess, sys, time\n"
            "start = time.perf_counter()\n"
            "code = subprocess.run(sys.argv[1:], stdout=sys.stderr).returncode\n"
            "print(time.perf_counter() - start, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n"
            "sys.exit(code)\n")


def compile_cost(command) -> tuple[float, float]:
    """Run one compiler command; return (wall seconds, peak memory in MB of the compiler's
    largest process)."""
    run = subprocess.run([sys.executable, "-I", "-S", "-c", _MEASURE, *command], capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{run.stderr[-4000:]}")
    seconds, kilobytes = run.stdout.split()
    return float(seconds), float(kilobytes) / 1024


# ------------------------------------------------------------------------------- one robot

@dataclass
class Case:
    """One robot prepared for timing: its generated C, Pinocchio model, peer C and states."""

    label: str
    prefix: str
    dims: object  # the robot's sizes: a symdyn.model.outputs.Dimensions (Dimensions.of)
    folder: str
    functions: tuple
    header: str
    peer_instructions: dict = field(default_factory=dict)
    compile_costs: dict = field(default_factory=dict)  # (flag set, "symdyn" or "peer") -> (s, MB)
    sizes: dict = field(default_factory=dict)  # "symdyn", "peer" -> bytes of the generated C
    peer_difference: float = 0.0  # the largest relative difference of the cross-checks
    precision: str = "double"
    generate_seconds: float = 0.0  # derivation and emission (through symdyn's cache unless use_cache=False)
    parameters: tuple = ()  # the values of the runtime parameters (a scene's), passed as p
    sides: tuple = ()  # symdyn's extra sides timed: "casadi" (--target casadi-c), "batch" (--batch)

    @property
    def dof(self) -> int:
        return self.dims.dof

    @property
    def nq(self) -> int:
        return self.dims.nq

    @property
    def frames(self) -> int:
        return self.dims.frames

    @property
    def source(self) -> str:
        return os.path.join(self.folder, f"{self.prefix}_dynamics.c")

    @property
    def fd_method(self) -> str:
        found = re.search(r"forward dynamics by ([^,;)]+)", self.header)
        return found.group(1) if found else "-"

    def costs(self) -> dict[str, dict[str, int]]:
        """{function: {"mul", "add", "div", "trig": count}} from the generated header."""
        pattern = (r"/\*((?:(?!\*/).)*)\*/\s*(?:void|int) " + re.escape(self.prefix) + r"_(\w+)\(")
        found = {}
        for block, function in re.findall(pattern, self.header, re.S):
            cost = re.search(r"Cost: (\d+) multiplications, (\d+) additions/subtractions, (\d+) divisions?, "
                             r"(\d+) sin/cos", block)
            if cost and function not in found:
                found[function] = dict(zip(("mul", "add", "div", "trig"), map(int, cost.groups())))
        return found


def robot_file(spec: str, folder: str) -> str:
    """robots/NAME.yaml, a robot file's path, or for a number N the generic N-joint chain."""
    if spec.isdigit():
        from long_chains import generic_chain
        path = os.path.join(folder, f"generic{spec}.yaml")
        with open(path, "w") as handle:
            handle.write(generic_chain(int(spec)))
        return path
    for path in (os.path.join(ROOT, "robots", f"{spec}.yaml"), spec):
        if os.path.isfile(path):
            return path
    raise SystemExit(f"no robot '{spec}' (robots/{spec}.yaml) and no such file")


def output_sizes(function: str, dims) -> list[int]:
    """The sizes of NAME_<function>'s output arguments, in order (``dims``: the robot's
    :class:`symdyn.model.outputs.Dimensions`)."""
    from symdyn.model.outputs import COMBINED, REGISTRY
    return [rows * cols for part in COMBINED.get(function, (function,))
            for _, (rows, cols) in REGISTRY[part].argument_shapes(dims)]


def symdyn_inputs(function: str, precision: str = "double", parameters: bool = False, whole: bool = False) -> list[str]:
    """The input arguments of NAME_<function> in the harness: the state arrays of one state (Q,
    QD, ...; ``whole``: every state's, q, qd, ... for a batch function), then P for runtime
    parameters (float C: the float copies QF, ..., qf, ..., PF)."""
    from symdyn.model.outputs import function_inputs
    suffix = "F" if precision == "float" else ""
    names = [STATE_ARRAYS[name].lower() + suffix.lower() if whole else STATE_ARRAYS[name] + suffix
             for name in function_inputs(function)]
    return names + ([f"P{suffix}"] if parameters else [])


def output_pointers(function: str, dims, buffer: str = "OUT") -> list[str]:
    """Where NAME_<function>'s outputs go in the harness: each at its offset in ``buffer``."""
    pointers, offset = [], 0
    for size in output_sizes(function, dims):
        pointers.append(buffer if offset == 0 else f"{buffer} + {offset}")
        offset += size
    return pointers


def symdyn_arguments(function: str, dims, precision: str = "double", parameters: bool = False) -> str:
    """The arguments of NAME_<function> in the harness: :func:`symdyn_inputs`, then each output
    at its offset in OUT (float C: OUTF)."""
    buffer = "OUTF" if precision == "float" else "OUT"
    return ", ".join(symdyn_inputs(function, precision, parameters) + output_pointers(function, dims, buffer))


def casadi_call(case: Case, function: str) -> str:
    """One call of symdyn's CasADi function compiled from CasADi's C (a comma expression: the
    argument and result pointers, then the call with the harness's work vectors)."""
    inputs = symdyn_inputs(function, parameters=bool(case.parameters))
    outputs = output_pointers(function, case.dims)
    setters = [f"casadi_arg[{k}] = {a}" for k, a in enumerate(inputs)]
    setters += [f"casadi_res[{k}] = {r}" for k, r in enumerate(outputs)]
    return f"({', '.join(setters)}, {case.prefix}_casadi_{function}(casadi_arg, casadi_res, casadi_iw, casadi_w, 0))"


def batch_call(case: Case, function: str) -> str:
    """One call of symdyn's batch function over all S states, into OUTB (OUTBF)."""
    suffix = "F" if case.precision == "float" else ""
    if len(output_sizes(function, case.dims)) != 1:
        raise SystemExit(f"the harness times batch functions of one output; {function} has more")
    inputs = symdyn_inputs(function, case.precision, bool(case.parameters), whole=True)
    return f"{case.prefix}_{function}_batch((int)S, {', '.join(inputs)}, OUTB{suffix})"


def side_suffix(variant: str) -> str:
    """'_local', '_world' for a Pinocchio function timed in one convention, else ''."""
    return variant[variant.index("_"):] if "_" in variant else ""


def cases_header(case: Case, peer: bool) -> str:
    """harness_cases.h for benchmarks/harness_main.c."""
    lines = [f"#define N {case.dof}", f"#define NQ {case.nq or case.dof}",
             f"#define HARNESS_OUT_SIZE {3 * case.dof * case.dof + 8 * case.dof + 64 + case.frames * (22 + 6 * case.dof)}",
             f'#include "{case.prefix}_dynamics.h"']
    if case.parameters:
        lines.append(f"#define HARNESS_PARAMETERS {{{', '.join(repr(float(v)) for v in case.parameters)}}}")
    if "casadi" in case.sides:
        lines += ["#define HARNESS_CASADI 1", f'#include "{case.prefix}_casadi.h"',
                  "#define HARNESS_CASADI_FUNCTIONS(X) " + " ".join(f"X({case.prefix}_casadi_{f})"
                                                                    for f in case.functions)]
    if "batch" in case.sides:
        size = max(output_sizes(f, case.dims)[0] for f in case.functions)
        lines += [f"#define HARNESS_BATCH_SIZE {size}",
                  f"#define SCALAR_RESULT OUT{'F' if case.precision == 'float' else ''}"]
    floating = bool(case.nq) and case.nq != case.dof
    pin_name = (lambda v: FLOATING_VARIANTS.get(v, v)) if floating else (lambda v: v)  # noqa: E731
    for function in case.functions:  # the parts in their own sources, declared here
        for variant in pinocchio_of(function)[0]:
            if pinocchio_of(function)[1] in OWN_SOURCE_PARTS or pin_name(variant) != variant:
                arguments = ", ".join(f"const double *{a.lower()}" for a in PINOCCHIO_ARGUMENTS[variant].split(", "))
                lines.append(f"void pin_{pin_name(variant)}({arguments}, double *out);")
    if case.precision == "float":
        lines.append("#define SYMDYN_FLOAT 1")
    result = "OUTF[0]" if case.precision == "float" else "OUT[0]"
    cases, checks, peer_functions, batch_checks = [], [], [], []
    for function in case.functions:
        call = (f"{case.prefix}_{function}("
                f"{symdyn_arguments(function, case.dims, case.precision, bool(case.parameters))})")
        cases.append(f"X({function}, symdyn, {call}, {result}, 0)")
        if "casadi" in case.sides:
            cases.append(f"X({function}, casadi, {casadi_call(case, function)}, OUT[0], 0)")
        if "batch" in case.sides:
            outb, whole_call = ("OUTBF" if case.precision == "float" else "OUTB"), batch_call(case, function)
            cases.append(f"X({function}, batch, {whole_call}, {outb}[0], 1)")
            batch_checks.append(f"X({function}, {call}, {output_sizes(function, case.dims)[0]}, "
                                f"{whole_call}, {outb})")
        for variant in pinocchio_of(function)[0]:
            pin_call = f"pin_{pin_name(variant)}({PINOCCHIO_ARGUMENTS[variant]}, OUT)"
            cases.append(f"X({function}, pinocchio{side_suffix(variant)}, {pin_call}, OUT[0], 0)")
            if peer and variant in PEER_VARIANTS:
                arguments = (PINOCCHIO_ARGUMENTS[variant].split(", ") + ["0", "0"])[:3]
                peer_call = f"PEER(peer_{variant}, {', '.join(arguments)})"
                cases.append(f"X({function}, peer{side_suffix(variant)}, {peer_call}, OUT[0], 0)")
                checks.append(f"X({variant}, {pin_call}, {peer_call})")
                peer_functions.append(f"X(peer_{variant})")
    if peer:
        lines += ["#define HARNESS_PEER 1", '#include "peer.h"',
                  "#define HARNESS_CHECKS(X) " + " ".join(checks),
                  "#define HARNESS_PEER_FUNCTIONS(X) " + " ".join(peer_functions)]
    if batch_checks:
        lines.append("#define HARNESS_BATCH_CHECKS(X) " + " ".join(batch_checks))
    lines.append("#define HARNESS_CASES(X) " + " \\\n    ".join(cases))
    return "\n".join(lines) + "\n"


def write_states(path: str, dof: int, count: int, seed: int, robot=None) -> None:
    """``count`` seeded random states as four blocks of count x dof doubles: q in [-pi, pi], qd in
    [-2, 2], qdd in [-5, 5], tau in [-20, 20]; for a floating-base ``robot`` the q block is
    count x nq (base position in [-1, 1] m, a uniformly random unit quaternion, joints)."""
    rng = np.random.default_rng(seed)
    if robot is not None and robot.floating:
        from symdyn.check.states import random_configuration
        first = np.array([random_configuration(robot, rng) for _ in range(count)])
    else:
        first = rng.uniform(-np.pi, np.pi, (count, dof))
    blocks = [first.ravel(), rng.uniform(-2, 2, (count, dof)).ravel(),
              rng.uniform(-5, 5, (count, dof)).ravel(), rng.uniform(-20, 20, (count, dof)).ravel()]
    np.concatenate(blocks).astype("<f8").tofile(path)


def prepare_case(spec: str, functions, folder: str, peer: bool, states: int, seed: int,
                 generate_options: dict | None = None, sides=()) -> Case:
    """Generate symdyn's C as ``symdyn generate`` does (``generate_options``: more
    :class:`symdyn.emit.pipeline.GenerateOptions` fields, e.g. ``fd_method``, ``precision``:
    double or float, ``parameters``, ``use_cache``; ``sides``: "batch" adds the batch functions,
    "casadi" symdyn's CasADi functions as CasADi's C, ``--target casadi-c``), save Pinocchio's
    model (runtime parameters, e.g. a scene's payload, at their values in the file: the same
    values the timing passes to symdyn's functions), generate the peer's C, write the states and
    harness_cases.h into ``folder``."""
    from symdyn.check.pinocchio_model import build_model
    from symdyn.emit.pipeline import GenerateOptions, configure, generate
    from symdyn.model.outputs import Dimensions
    os.makedirs(folder, exist_ok=True)
    generate_options = dict(generate_options or {})
    if generate_options.get("precision", "double") not in ("double", "float"):
        raise SystemExit("the harness times double or float C")
    if "batch" in sides:
        generate_options["batch"] = True
    generate_options.setdefault("c_file_mb", 0)  # one file however big (the timing program compiles one)
    path = robot_file(spec, folder)
    config = configure(path, GenerateOptions(functions=tuple(functions), **generate_options))
    robot = config.robot
    if getattr(robot, "parameters", None) and (len(robot.nominal) != len(robot.parameters)
                                              or any(v is None for v in robot.nominal)):
        raise SystemExit(f"{spec}: runtime parameters ({', '.join(map(str, robot.parameters))}) without values")
    start = time.perf_counter()
    files = generate(config)
    generate_seconds = time.perf_counter() - start
    if "casadi" in sides:
        if config.precision != "double":
            raise SystemExit("the harness times symdyn's CasADi functions in double only")
        same = {k: v for k, v in generate_options.items() if k not in ("precision", "batch")}  # e.g. fd_method
        files.update(generate(configure(path, GenerateOptions(functions=tuple(functions), target="casadi-c", **same))))
    for name, data in files.items():
        with open(os.path.join(folder, name), "wb") as handle:
            handle.write(data)
    prefix = next(name[:-len("_dynamics.h")] for name in files if name.endswith("_dynamics.h"))
    label = f"{robot.name} (n={robot.dof}{', floating base' if robot.floating else ''})"
    parameters = tuple(float(v) for v in robot.nominal) if getattr(robot, "parameters", None) else ()
    case = Case(label, prefix, Dimensions.of(robot), folder, tuple(functions),
                files[f"{prefix}_dynamics.h"].decode(), precision=config.precision,
                generate_seconds=generate_seconds,
                parameters=parameters, sides=tuple(sides))
    model, _ = build_model(robot, dict(zip(robot.parameters, robot.nominal)) if parameters else None)
    model.saveToText(os.path.join(folder, "model.txt"))
    if peer:
        variants = [v for f in functions for v in pinocchio_of(f)[0] if v in PEER_VARIANTS]
        paths = site_paths()  # this environment's libraries, wherever the cached generator was built
        environment = {**os.environ, "LD_LIBRARY_PATH": os.pathsep.join(
            [paths["casadi"], paths["lib"], *filter(None, [os.environ.get("LD_LIBRARY_PATH")])])}
        output = subprocess.run([peer_generator(), os.path.join(folder, "model.txt"), folder, *variants],
                                capture_output=True, text=True, env=environment)
        if output.returncode != 0:
            raise RuntimeError(f"the peer generator failed on {spec}:\n{output.stderr[-4000:]}")
        case.peer_instructions = {w[0]: int(w[1]) for w in map(str.split, output.stdout.splitlines()) if len(w) == 2}
    case.sizes = {side: os.path.getsize(os.path.join(folder, name))
                  for side, name in (("symdyn", f"{prefix}_dynamics.c"), ("peer", "peer.c"))
                  if os.path.exists(os.path.join(folder, name))}
    write_states(os.path.join(folder, "states.bin"), robot.nv, states, seed, robot)
    with open(os.path.join(folder, "harness_cases.h"), "w") as handle:
        handle.write(cases_header(case, peer))
    return case


def build_program(case: Case, flag_set: str, peer: bool, objects: dict) -> str:
    """Compile and link the timing program of ``case`` for one flag set (every side with the
    same flags); ``objects``: {part: cached Pinocchio object} for this flag set."""
    flags, folder, paths = FLAG_SETS[flag_set], case.folder, site_paths()
    out = lambda name: os.path.join(folder, f"{flag_set}-{name}.o")  # noqa: E731
    case.compile_costs[flag_set, "symdyn"] = compile_cost(
        ["gcc", *flags, *SYMDYN_DEFINES.get(flag_set, ()), "-std=c99", "-w", "-c", case.source, "-o", out("symdyn")])
    linked = [out("main"), out("symdyn")]
    if "casadi" in case.sides:
        case.compile_costs[flag_set, "casadi"] = compile_cost(
            ["gcc", *flags, "-std=c99", "-w", "-c", os.path.join(folder, f"{case.prefix}_casadi.c"),
             "-o", out("casadi")])
        linked.append(out("casadi"))
    if peer:
        case.compile_costs[flag_set, "peer"] = compile_cost(
            ["gcc", *flags, "-std=c99", "-w", "-c", os.path.join(folder, "peer.c"), "-o", out("peer")])
        linked.append(out("peer"))
    compile_cost(["gcc", *flags, "-std=c99", "-w", f"-I{folder}", f"-I{HERE}", "-c",
                  os.path.join(HERE, "harness_main.c"), "-o", out("main")])
    exe = os.path.join(folder, f"harness-{flag_set}")
    compile_cost(["g++", *flags, *linked, *objects.values(), f"-L{paths['lib']}", "-lboost_serialization",
                  f"-Wl,-rpath,{paths['lib']}", "-lm", "-o", exe])
    return exe


def run_program(exe: str, case: Case, passes: int, index: int) -> dict:
    """One process, run from a fresh copy of the binary: {"time": {(function, side): [ns per
    pass]}, "check": {name: (difference, scale)}}."""
    return run_copy(exe, [os.path.join(case.folder, "states.bin"), os.path.join(case.folder, "model.txt"),
                          str(passes)], case.folder, index)


def run_copy(exe: str, arguments, folder: str, index: int) -> dict:
    """Run a timing program once from a fresh copy of its binary (in ``folder``; where the code
    lands in memory alone can move a big function's time by up to 2x) and read its "time
    FUNCTION SIDE ns ..." and "check NAME difference scale" lines: {"time": {(function, side): [ns
    per pass]}, "check": {name: (difference, scale)}}."""
    copy = os.path.join(folder, f"run{index}-{os.path.basename(exe)}")
    shutil.copy(exe, copy)
    try:
        run = subprocess.run([copy, *arguments], capture_output=True, text=True)
    finally:
        os.remove(copy)
    if run.returncode != 0:
        raise RuntimeError(f"{exe} failed ({run.returncode}):\n{run.stderr[-4000:]}")
    result = {"time": {}, "check": {}}
    for words in map(str.split, run.stdout.splitlines()):
        if words and words[0] == "time":
            result["time"][words[1], words[2]] = [float(w) for w in words[3:]]
        elif words and words[0] == "check":
            result["check"][words[1]] = (float(words[2]), float(words[3]))
    return result


# --------------------------------------------------------------------------- runs and tables

@dataclass
class Row:
    """One function of one robot at one flag set: per side, the median pass of each process."""

    case: Case
    flag_set: str
    function: str
    times: dict  # side -> [ns per call, one per process]

    def side(self, kind: str):
        """``(convention, per-process ns)`` of the faster of ``kind``'s variants ('pinocchio' or
        'peer'; convention '' where there is one variant), or None when not timed."""
        variants = {s: v for s, v in self.times.items() if s == kind or s.startswith(kind + "_")}
        if not variants:
            return None
        best = min(variants, key=lambda s: statistics.median(variants[s]))
        return best[len(kind) + 1:].upper(), variants[best]

    def ratio(self, kind: str):
        """Per process: ``kind``'s time / symdyn's (> 1: symdyn is faster), or None."""
        found = self.side(kind)
        return None if found is None else [t / s for t, s in zip(found[1], self.times["symdyn"])]


def summary(values, digits: int = 0) -> str:
    """'median (min-max)'."""
    if not values:
        return "-"
    form = f"{{:.{digits}f}}"
    return f"{form.format(statistics.median(values))} ({form.format(min(values))}–{form.format(max(values))})"


def build_objects(flag_sets, functions, pool) -> dict:
    """Start building the Pinocchio objects the functions need, per flag set, in ``pool``."""
    parts = ["LOAD"] + sorted({pinocchio_of(f)[1] for f in functions} - {None})
    return {(flag_set, part): pool.submit(pinocchio_part, part, FLAG_SETS[flag_set])
            for flag_set in flag_sets for part in parts}


def check_peer(case: Case, results) -> float:
    """The largest |peer - Pinocchio| / max(1, max |Pinocchio|) over the cross-checks; stops the
    run when the peer computes something else, or when a batch function's results differ from
    the scalar function's (checks named batch_FUNCTION) by more than that tolerance."""
    worst = 0.0
    for result in results:
        for name, (difference, scale) in result["check"].items():
            relative = difference / max(1.0, scale)
            if name.startswith("batch_"):
                if not relative <= CHECK_TOLERANCE:
                    raise SystemExit(f"{case.label}: symdyn's {name[len('batch_'):]}_batch differs from the scalar "
                                     f"function by {difference:.3g} (largest entry {scale:.3g})")
                continue
            if not relative <= CHECK_TOLERANCE:
                raise SystemExit(f"{case.label}: the CasADi peer's {name} differs from Pinocchio's by {difference:.3g} "
                                 f"(largest entry {scale:.3g})")
            worst = max(worst, relative)
    return worst


def run(specs, functions=FUNCTIONS, processes: int = 5, passes: int = 15, states: int = 10000,
        flag_sets=tuple(FLAG_SETS), peer: bool = True, seed: int = 2026, workdir: str | None = None,
        generate_options: dict | None = None, sides=()) -> list[Row]:
    """Time ``functions`` of each robot (name, robot or scene file, or number, see the module
    docstring) on every side; one :class:`Row` per robot, flag set and function
    (``generate_options``, ``sides``: see :func:`prepare_case`)."""
    from symdyn.model.outputs import COMBINED, REGISTRY
    unknown = [f for f in list(functions) if f not in PINOCCHIO and f not in REGISTRY and f not in COMBINED]
    unknown += [f for f in flag_sets if f not in FLAG_SETS]
    if unknown:
        raise SystemExit(f"unknown function or flag set {unknown[0]} (functions: {', '.join(PINOCCHIO)}, or any "
                         f"of symdyn's, timed without Pinocchio; flag sets: {', '.join(FLAG_SETS)})")
    functions = [f for f in PINOCCHIO if f in functions] + [f for f in functions if f not in PINOCCHIO]
    peer = peer and any(v in PEER_VARIANTS for f in functions for v in pinocchio_of(f)[0])  # task_space alone: no peer
    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool, \
            tempfile.TemporaryDirectory() as scratch:
        pending = build_objects(flag_sets, functions, pool)
        base = workdir or scratch
        cases = [prepare_case(str(spec), functions, os.path.join(base, f"{k}-{os.path.basename(str(spec))}"), peer,
                              states, seed, generate_options, sides) for k, spec in enumerate(specs)]
        if any(case.nq != case.dof for case in cases):  # a floating base: Pinocchio's calls that read nq
            pending.update({(fs, "FLOAT"): pool.submit(pinocchio_part, "FLOAT", FLAG_SETS[fs]) for fs in flag_sets})
        objects = {fs: {part: future.result() for (f, part), future in pending.items() if f == fs} for fs in flag_sets}
        programs = {(k, fs): build_program(case, fs, peer, objects[fs]) for k, case in enumerate(cases)
                    for fs in flag_sets}
        results = {key: [] for key in programs}
        for index in range(processes):
            for (k, fs), exe in programs.items():
                print(f"process {index + 1}/{processes}: {cases[k].label} {fs}", file=sys.stderr, flush=True)
                results[k, fs].append(run_program(exe, cases[k], passes, index))
    rows = []
    for (k, fs), runs in results.items():
        cases[k].peer_difference = check_peer(cases[k], runs)
        for function in functions:
            sides = [side for f, side in runs[0]["time"] if f == function]
            times = {side: [statistics.median(r["time"][function, side]) for r in runs] for side in sides}
            rows.append(Row(cases[k], fs, function, times))
    return rows


def markdown(rows, flag_set: str) -> str:
    """The Markdown table of one flag set."""
    lines = ["| robot | function | symdyn ns | Pinocchio ns | Pinocchio convention | CasADi peer ns | "
             "Pinocchio / symdyn | peer / symdyn |", "|---|---|---:|---:|---|---:|---:|---:|"]
    for row in (r for r in rows if r.flag_set == flag_set):
        pinocchio, peer = row.side("pinocchio"), row.side("peer")
        if pinocchio is None:
            continue
        peer_cell = "-" if peer is None else summary(peer[1]) + (f" {peer[0]}" if peer[0] else "")
        lines.append(f"| {row.case.label} | {row.function} | {summary(row.times['symdyn'])} | "
                     f"{summary(pinocchio[1])} | "
                     f"{pinocchio[0] or '-'} | {peer_cell} | {summary(row.ratio('pinocchio'), 2)} | "
                     f"{summary(row.ratio('peer'), 2) if peer else '-'} |")
    return "\n".join(lines)


def sides_table(rows, flag_set: str) -> str:
    """The Markdown table of symdyn's extra sides at one flag set, the columns of those timed:
    the batch function (ns per state; its time over the scalar call's; Pinocchio's per call over
    it) and symdyn's CasADi functions compiled from CasADi's C (its time over symdyn's C)."""
    rows = [r for r in rows if r.flag_set == flag_set]
    sides = [side for side in ("batch", "casadi") if any(r.side(side) for r in rows)]
    header = ["robot", "function", "symdyn C ns"]
    if "batch" in sides:
        header += ["batch ns/state", "batch / symdyn C"]
    if "casadi" in sides:
        header += ["CasADi C ns", "CasADi C / symdyn C"]
    header += ["Pinocchio ns"] + (["Pinocchio / batch"] if "batch" in sides else [])
    lines = ["| " + " | ".join(header) + " |", "|---|---|" + "---:|" * (len(header) - 2)]
    for row in rows:
        pinocchio = row.side("pinocchio")
        cells = [row.case.label, row.function, summary(row.times["symdyn"])]
        if "batch" in sides:
            batch = row.side("batch")
            cells += [summary(batch[1], 1), summary(row.ratio("batch"), 2)] if batch else ["-", "-"]
        if "casadi" in sides:
            casadi = row.side("casadi")
            cells += [summary(casadi[1]), summary(row.ratio("casadi"), 2)] if casadi else ["-", "-"]
        cells.append(summary(pinocchio[1]) if pinocchio else "-")
        if "batch" in sides:
            cells.append(summary([p / b for p, b in zip(pinocchio[1], batch[1])], 1) if batch and pinocchio else "-")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def build_table(rows) -> str:
    """Per robot and flag set: the size of each generated C file and what gcc took to compile it
    (wall seconds, peak memory), symdyn's forward-dynamics method and the peer cross-check."""
    lines = ["| robot | flags | symdyn C (kB) | symdyn compile (s) | symdyn compile peak (MB) | peer C (kB) | "
             "peer compile (s) | peer compile peak (MB) | symdyn forward dynamics | peer vs Pinocchio (rel.) |",
             "|---|---|---:|---:|---:|---:|---:|---:|---|---:|"]
    seen = set()
    for row in rows:
        case, fs = row.case, row.flag_set
        if (id(case), fs) in seen:
            continue
        seen.add((id(case), fs))
        sd_time, sd_mem = case.compile_costs[fs, "symdyn"]
        peer = case.compile_costs.get((fs, "peer"))
        peer_cells = f"{case.sizes['peer'] / 1000:.0f} | {peer[0]:.1f} | {peer[1]:.0f}" if peer else "- | - | -"
        check = f"{case.peer_difference:.1e}" if peer else "-"
        lines.append(f"| {case.label} | {flag_label(fs)} | {case.sizes['symdyn'] / 1000:.0f} | "
                     f"{sd_time:.1f} | {sd_mem:.0f} | {peer_cells} | {case.fd_method} | {check} |")
    return "\n".join(lines)


def operations_table(rows) -> str:
    """symdyn's operation counts per robot and function (the generated header's Cost lines)."""
    lines = ["| robot | function | mul | add | div | sin/cos |", "|---|---|---:|---:|---:|---:|"]
    seen = set()
    for row in rows:
        if (id(row.case), row.function) in seen:
            continue
        seen.add((id(row.case), row.function))
        ops = row.case.costs().get(row.function)
        if ops:
            lines.append(f"| {row.case.label} | {row.function} | {ops['mul']} | {ops['add']} | {ops['div']} | "
                         f"{ops['trig']} |")
    return "\n".join(lines)


# ------------------------------------------------------------------------------------- CLI

#: --smoke: the smallest run that goes through every step (tests/test_benchmark_scripts.py)
SMOKE = {"processes": 1, "passes": 2, "states": 200, "flags": "O2"}
DEFAULTS = {"processes": 5, "passes": 15, "states": 10000, "flags": "O2,O3native"}


def add_arguments(parser: argparse.ArgumentParser, peer: bool = True) -> None:
    """The harness's options, for this script and the scripts built on it."""
    parser.add_argument("--processes", type=int, help=f"timing processes (default {DEFAULTS['processes']})")
    parser.add_argument("--passes", type=int, help=f"passes per side and process (default {DEFAULTS['passes']})")
    parser.add_argument("--states", type=int, help=f"distinct random states (default {DEFAULTS['states']})")
    parser.add_argument("--flags", help="comma-separated flag sets: " + "; ".join(
        f"{k} ({flag_label(k)})" for k in FLAG_SETS) + f" (default {DEFAULTS['flags']})")
    parser.add_argument("--seed", type=int, default=2026, help="seed of the states")
    parser.add_argument("--smoke", action="store_true",
                        help="tiny run for tests: " + ", ".join(f"--{k} {v}" for k, v in SMOKE.items()))
    if peer:
        parser.add_argument("--no-peer", action="store_true", help="leave out the Pinocchio -> CasADi peer")


def options(args) -> dict:
    """:func:`run`'s keyword arguments from :func:`add_arguments`' options."""
    chosen = {key: getattr(args, key) if getattr(args, key) is not None else (SMOKE if args.smoke else DEFAULTS)[key]
              for key in DEFAULTS}
    return {"processes": chosen["processes"], "passes": chosen["passes"], "states": chosen["states"],
            "flag_sets": tuple(f.strip() for f in chosen["flags"].split(",") if f.strip()), "seed": args.seed,
            "peer": not getattr(args, "no_peer", True)}


def environment(kwargs: dict) -> str:
    """One line on the machine, the compiler and the run."""
    cpu = platform_cpu()
    compiler = subprocess.run(["gcc", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    return (f"{cpu}; {compiler}; Pinocchio {importlib.metadata.version('pin')}, CasADi "
            f"{importlib.metadata.version('casadi')}; {kwargs['states']} states, {kwargs['passes']} passes per side, "
            f"{kwargs['processes']} processes; thread CPU time; cells: median over processes (min–max)")


def platform_cpu() -> str:
    try:
        with open("/proc/cpuinfo") as handle:
            for line in handle:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


NOTES = """Where the sides compute slightly different things: coriolis is timed against nonLinearEffects,
which includes gravity (symdyn's h(q, qd) does not); Pinocchio's crba fills the upper triangle of
M only (symdyn and the peer write the whole matrix) and adds the armature (symdyn's mass_matrix
does not); symdyn's inverse_dynamics adds viscous and Coulomb friction where the robot file has
them (rnea has none).  Ratios > 1: symdyn is faster.  Pinocchio's results stay in its Data; the
harness reads the first entry of each side's result for its checksum."""


def flag_set_sections(kwargs: dict):
    """Print the run's environment line, then before each flag set its heading; yields the flag
    sets (the scripts built on the harness print their tables per flag set this way)."""
    print(environment(kwargs))
    for flag_set in kwargs["flag_sets"]:
        print(f"\n### {flag_label(flag_set)} (every side)\n")
        yield flag_set


def print_tables(rows, kwargs: dict) -> None:
    for flag_set in flag_set_sections(kwargs):
        print(markdown(rows, flag_set))
        if any(row.case.sides for row in rows):
            print(f"\n#### symdyn's batch functions and CasADi functions, {flag_label(flag_set)}\n")
            print(sides_table(rows, flag_set))
    print("\n### Builds (gcc -c of each generated file; peak memory of the compiler)\n")
    print(build_table(rows))
    print("\n" + NOTES)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("robots", nargs="*", default=["puma560"], help="robot names or joint counts N")
    parser.add_argument("--functions", default=",".join(FUNCTIONS),
                        help=f"comma-separated, of {', '.join(PINOCCHIO)} (default the first six)")
    parser.add_argument("--keep", help="build and run in this directory and keep it")
    parser.add_argument("--precision", choices=("double", "float"), help="of symdyn's C (default: the scene's, "
                        "else double; Pinocchio and the peer stay in double)")
    parser.add_argument("--batch", action="store_true", help="also time symdyn's batch functions (--batch), "
                        "ns per state over all states in one call")
    parser.add_argument("--casadi", action="store_true", help="also time symdyn's CasADi functions compiled "
                        "from CasADi's C (symdyn generate --target casadi-c), same flags")
    add_arguments(parser)
    args = parser.parse_args(argv)
    kwargs = options(args)
    functions = [f.strip() for f in args.functions.split(",") if f.strip()]
    sides = tuple(side for side, wanted in (("batch", args.batch), ("casadi", args.casadi)) if wanted)
    rows = run(args.robots, functions, workdir=args.keep, sides=sides,
               generate_options={"precision": args.precision} if args.precision else None, **kwargs)
    print_tables(rows, kwargs)


if __name__ == "__main__":
    main()
