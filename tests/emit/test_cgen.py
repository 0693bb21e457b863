"""Generated C: checked-in files compile cleanly and regenerate byte-identically; the compiled
functions agree with Pinocchio in double and float; sanitizers; the header-only variant."""

import os
import re
import shutil
import subprocess
import zlib

import numpy as np
import pytest

from helpers import REPO, ROBOTS, PinocchioReference, parameter_values, random_states, run_sanitized
from symdyn.model.outputs import Dimensions
from symdyn.check.pinocchio_model import compare
from symdyn import OUTPUTS
from symdyn.check.cbuild import WARNING_FLAGS, CompiledDynamics, build_and_load, compile_shared
from symdyn.cli import main
from symdyn.emit.cgen import build_function
from symdyn.emit.cplan import collect_targets
from symdyn.emit.pipeline import GenerateOptions, configure, generate
from symdyn.model.outputs import with_requirements

GENERATED = REPO / "generated"
CC = shutil.which("gcc") or shutil.which("cc")
pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler")


@pytest.fixture(scope="session")
def regenerated(tmp_path_factory):
    out = tmp_path_factory.mktemp("regenerated")
    robots = [str(REPO / "robots" / f"{name}.yaml") for name in ROBOTS]
    assert main(["generate", *robots, "--out", str(out), "--quiet"]) == 0
    return out


def test_regeneration_is_byte_identical(regenerated):
    for name in ROBOTS:
        for ext in ("h", "c"):
            fresh = (regenerated / f"{name}_dynamics.{ext}").read_bytes()
            checked_in = (GENERATED / f"{name}_dynamics.{ext}").read_bytes()
            assert fresh == checked_in, f"generated/{name}_dynamics.{ext} is stale: run the command in docs"
        header = (GENERATED / f"{name}_dynamics.h").read_text()
        assert "N divisions" not in header  # the cost line counts them; the summary says 'at most one per joint'
        assert "at most one division per joint" in header


def _compare(lib, name, precision, tolerance, functions=OUTPUTS):
    import symdyn
    from helpers import robot_path
    robot = symdyn.load(robot_path(name))
    values = parameter_values(robot)
    p = np.array([values[s] for s in robot.parameters])
    ref = PinocchioReference(robot, values)
    states = []
    for state in random_states(robot.dof, 50, seed=zlib.crc32(name.encode()) % 997):
        if precision == "float":
            state = [x.astype(np.float32).astype(float) for x in state]
        states.append(state)
    errors = compare(lib, ref, states, functions, p)
    bad = {k: v for k, v in errors.items() if not v <= tolerance}
    assert not bad, f"{name} {precision}: {bad}"


@pytest.mark.parametrize("name", ROBOTS)
def test_compiled_double_agrees_with_pinocchio(name, tmp_path):
    """The checked-in C compiles with -std=c99 -Wall -Wextra -Wpedantic -Werror at -O2, what users
    build with (one compile per robot: any warning fails it), and agrees with Pinocchio."""
    import symdyn
    from helpers import robot_path
    robot = symdyn.load(robot_path(name))
    files = {f.name: f.read_text() for f in GENERATED.glob(f"{name}_dynamics.*")}
    lib = build_and_load(files, name, Dimensions.of(robot), len(robot.parameters), "double", str(tmp_path),
                         extra_flags=("-O2",))
    _compare(lib, name, "double", 1e-10)


@pytest.mark.parametrize("name", [pytest.param(name, marks=[pytest.mark.slow] if name in ("chain12", "panda", "iiwa14") else [])
                                  for name in ROBOTS])  # chain12's float: 8 s, the 7-joint arms' 4-5 s, with -m slow (their double runs)
def test_compiled_float_agrees_with_pinocchio(name, tmp_path):
    import symdyn
    from helpers import robot_path
    robot = symdyn.load(robot_path(name))
    # chain12 (12 joints, the slowest to build): the functions where float is hardest; its
    # other functions are checked in double, and in float on the other robots
    functions = ("inverse_dynamics", "mass_matrix", "forward_dynamics") if name == "chain12" else symdyn.OUTPUTS
    files = {k: v.decode() for k, v in
             generate(configure(robot_path(name), GenerateOptions(functions=functions, precision="float"))).items()}
    # float all the way: no call of a double-precision math function (the sin/cos block is sincosf)
    source = files[f"{name}_dynamics.c"]
    double_calls = re.findall(r"(?<![\w.])(sin|cos|tan|sqrt|fabs|exp|log|pow|floor|ceil|fmod)\s*\(", source)
    assert not double_calls, f"{name}: double-precision calls in float code: {sorted(set(double_calls))}"
    checked = ("gravity", "forward_dynamics")  # the emitter's record: a sin/cos block is float, or none
    eqs = symdyn.derive(robot, outputs=with_requirements(checked), fd_method="aba")
    kinds = {build_function(eqs, f, "float", name).trig_type for f in checked}
    assert kinds <= {"float", ""} and "float" in kinds, kinds  # (a SCARA's gravity has no angle)
    lib = build_and_load(files, name, Dimensions.of(robot), len(robot.parameters), "float", str(tmp_path))
    _compare(lib, name, "float", 1e-4, functions)


HARNESS = r"""
#include <stdio.h>
#include "puma560_dynamics.h"
int main(void) {
    puma560_real q[6] = {0.1, -0.4, 0.9, 1.3, -0.7, 0.2}, qd[6] = {0.5, -1, 0.3, 2, -0.1, 1};
    puma560_real qdd[6] = {1, 2, -1, 0.5, 0.2, -3}, tau[6], D[36], h[6], C[36], c[6], a[6];
    double sum = 0;
    int i;
    puma560_inverse_dynamics(q, qd, qdd, tau);
    puma560_mass_matrix(q, D);
    puma560_coriolis(q, qd, h);
    puma560_coriolis_matrix(q, qd, C);
    puma560_gravity(q, c);
    puma560_forward_dynamics(q, qd, tau, a);
    for (i = 0; i < 6; ++i) sum += tau[i] + h[i] + c[i] + (a[i] - qdd[i]);
    for (i = 0; i < 36; ++i) sum += D[i] + C[i];
    printf("%.17g\n", sum);
    for (i = 0; i < 6; ++i) if (a[i] - qdd[i] > 1e-9 || qdd[i] - a[i] > 1e-9) return 3;
    return 0;
}
"""


def test_sanitizers_run_clean(tmp_path):
    files = {name: (GENERATED / name).read_bytes() for name in ("puma560_dynamics.c", "puma560_dynamics.h")}
    assert np.isfinite(float(run_sanitized(tmp_path, HARNESS, files)))


def test_header_only_variant_in_a_plain_program(tmp_path, derived):
    assert main(["generate", str(REPO / "robots" / "puma560.yaml"), "--out", str(tmp_path),
                 "--header-only", "--functions", "gravity,mass_matrix", "--quiet"]) == 0
    assert sorted(os.listdir(tmp_path)) == ["puma560_dynamics.h"]
    header = (tmp_path / "puma560_dynamics.h").read_text()
    assert "static inline" in header and "puma560_inverse_dynamics" not in header
    q = np.array([0.3, -0.5, 0.8, 0.1, 0.6, -0.2])
    expected = derived("puma560").numeric.gravity(q)
    program = "#include <math.h>\n#include <stdio.h>\n#include \"puma560_dynamics.h\"\nint main(void) {\n" \
        f"    puma560_real q[6] = {{{', '.join(repr(float(x)) for x in q)}}};\n    puma560_real c[6];\n" \
        "    puma560_gravity(q, c);\n" + "".join(
            f"    if (fabs(c[{i}] - ({float(expected[i])!r})) > 1e-9 * (1.0 + fabs({float(expected[i])!r}))) return {i + 1};\n"
            for i in range(6)) + "    printf(\"ok\\n\");\n    return 0;\n}\n"
    (tmp_path / "main.c").write_text(program)
    build = subprocess.run([CC, *WARNING_FLAGS, str(tmp_path / "main.c"), "-I", str(tmp_path), "-o",
                            str(tmp_path / "main"), "-lm"], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(tmp_path / "main")], capture_output=True, text=True)
    assert run.returncode == 0 and run.stdout.strip() == "ok"


def test_functions_option_emits_only_those(tmp_path):
    assert main(["generate", str(REPO / "robots" / "scara.yaml"), "--out", str(tmp_path),
                 "--functions", "gravity", "--quiet"]) == 0
    text = (tmp_path / "scara_dynamics.c").read_text() + (tmp_path / "scara_dynamics.h").read_text()
    assert "scara_gravity(" in text
    for other in ("inverse_dynamics", "mass_matrix", "coriolis", "forward_dynamics"):
        assert f"scara_{other}(" not in text


def test_float_output_has_no_double_literals_or_functions(tmp_path):
    """--precision float is float all the way, forward dynamics included: no double function,
    no unsuffixed literal, nothing promoted to double (-Wdouble-promotion -Werror)."""
    assert main(["generate", str(REPO / "robots" / "ur5.yaml"), "--out", str(tmp_path),
                 "--precision", "float", "--quiet"]) == 0
    text = (tmp_path / "ur5_dynamics.c").read_text()
    header = (tmp_path / "ur5_dynamics.h").read_text()
    assert "typedef float ur5_real" in header and "articulated-body algorithm" in header
    assert "internally in double" not in header
    import re
    body = text.split("#include \"ur5_dynamics.h\"", 1)[1]
    assert not re.search(r"\b(sin|cos|sqrt|pow|fabs)\(|\bdouble\b|DBL_MAX", body)
    assert not re.search(r"(?<![\w.])\d+\.\d*(e[-+]?\d+)?(?![\dFe.])", body), "unsuffixed double literal"
    subprocess.run([CC, *WARNING_FLAGS, "-Wdouble-promotion", "-c", str(tmp_path / "ur5_dynamics.c"),
                    "-o", str(tmp_path / "x.o")], check=True)


def test_mixed_precision_computes_forward_dynamics_in_double(tmp_path):
    """--precision mixed: float arguments, forward dynamics and every other function that
    solves with D (M^-1 here) computed inside in double (and said so in the header); the other
    functions are float."""
    assert main(["generate", str(REPO / "robots" / "chain12.yaml"), "--out", str(tmp_path), "--precision", "mixed",
                 "--functions", "gravity,forward_dynamics", "--quiet"]) == 0
    header = (tmp_path / "chain12_dynamics.h").read_text()
    assert "typedef float chain12_real" in header and "Computed internally in double" in header
    import symdyn
    eqs = symdyn.derive(symdyn.load(str(REPO / "robots" / "chain12.yaml")),
                        outputs=["gravity", "forward_dynamics", "mass_matrix_inverse"])
    assert build_function(eqs, "gravity", "mixed", "chain12").trig_type == "float"
    assert build_function(eqs, "forward_dynamics", "mixed", "chain12").trig_type == "double"
    assert build_function(eqs, "mass_matrix_inverse", "mixed", "chain12").trig_type == "double"
    assert main(["verify", str(REPO / "robots" / "chain12.yaml"), "--precision", "mixed",
                 "--functions", "forward_dynamics", "--states", "20"]) == 0


@pytest.mark.parametrize("name", ["stanford", "scara", "panda", "chain12"])
def test_projected_mass_matrix_agrees_with_pinocchio(name, tmp_path, monkeypatch):
    """The projected composite-rigid-body form of D (every S_i and F_j in joint frame 1, the
    off-diagonal entries as a loop of dot products in C; the default from 16 joints, more than
    any bundled robot has): prismatic joints (stanford, scara), modified DH (panda) and 12
    joints (chain12), symbolic and compiled, double and float."""
    import symdyn
    import symdyn.derive.composite as composite
    from helpers import robot_path
    from symdyn.emit.cgen import generate_c
    monkeypatch.setattr(composite, "PROJECTED_FROM_DOF", 1)
    robot = symdyn.load(robot_path(name))
    eqs = symdyn.derive(robot, outputs=["mass_matrix"])
    assert eqs.mass_factors, "the projected form was not used"
    values = parameter_values(robot)
    p = [values[s] for s in robot.parameters]
    ref = PinocchioReference(robot, values)
    for q, *_ in random_states(robot.dof, 10, seed=3):
        np.testing.assert_allclose(eqs.numeric.mass_matrix(q, p), ref.mass_matrix(q), rtol=1e-10, atol=1e-12)
    # the off-diagonal loop: 16-byte vectors at -O2 on x86-64, 32-byte with AVX (2 and 4 lanes in
    # double, 4 and 8 in float; chain12's rows cover every remainder), the plain loop without
    variants = [[], ["-DSYMDYN_NO_VECTOR"]] + ([["-mavx"]] if _cpu_has("avx") else [])
    for precision, tolerance in (("double", 1e-10), ("float", 1e-4)):
        files = generate_c(eqs, ["mass_matrix"], precision)
        assert build_function(eqs, "mass_matrix", precision, name).gram_loop  # the emitter's record
        for k, flags in enumerate(variants if name == "chain12" else variants[:1]):
            workdir = tmp_path / f"{precision}{k}"
            workdir.mkdir()
            for fname, text in files.items():
                (workdir / fname).write_text(text)
            library = compile_shared(str(workdir / f"{name}_dynamics.c"), str(workdir), flags)
            lib = CompiledDynamics(library, name, Dimensions.of(robot), len(robot.parameters), precision)
            _compare(lib, name, precision, tolerance, ("mass_matrix",))


def _cpu_has(flag: str) -> bool:
    """Whether this machine's CPU reports ``flag`` (Linux /proc/cpuinfo; False elsewhere)."""
    try:
        with open("/proc/cpuinfo") as handle:
            return any(line.startswith("flags") and flag in line.split() for line in handle)
    except OSError:
        return False


@pytest.mark.parametrize("name,projected", [("general_arm", False), ("panda", True)])
def test_looped_forward_dynamics_agrees_with_pinocchio(name, projected, tmp_path, monkeypatch):
    """Forward dynamics as an LDL^T loop over M and rhs (the default from
    LOOPED_SOLVE_FROM_DOF joints, more than any bundled robot has) on short arms: friction, a
    prismatic joint, base and tool (general_arm), and the projected mass matrix feeding the loop
    (panda); double, float and mixed; a singular or non-finite state returns its status and
    leaves qdd unwritten, as the unrolled form does."""
    import symdyn
    import symdyn.derive.composite as composite
    import symdyn.derive.equations as equations
    from helpers import robot_path
    from symdyn.emit.cgen import generate_c
    monkeypatch.setattr(equations, "LOOPED_SOLVE_FROM_DOF", 1)
    monkeypatch.setattr(composite, "PROJECTED_FROM_DOF", 1 if projected else 99)
    path = REPO / "tests" / "data" / f"{name}.yaml" if name == "general_arm" else robot_path(name)
    robot = symdyn.load(str(path))
    eqs = symdyn.derive(robot, outputs=["forward_dynamics"])
    assert eqs.fd_system and bool(eqs.fd_system[2]) == projected
    values = parameter_values(robot)
    p = np.array([values[s] for s in robot.parameters])
    ref = PinocchioReference(robot, values)
    for precision, tolerance in (("double", 1e-10), ("float", 1e-3), ("mixed", 1e-4)):
        files = generate_c(eqs, ["forward_dynamics"], precision)
        assert collect_targets(eqs, "forward_dynamics").looped  # the emitter's plan: the LDL^T loop
        (tmp_path / precision).mkdir()
        lib = build_and_load(files, robot.name, Dimensions.of(robot), len(robot.parameters), precision, str(tmp_path / precision))
        states = []
        for state in random_states(robot.dof, 20, seed=11):
            if precision != "double":
                state = [x.astype(np.float32).astype(float) for x in state]
            states.append(state)
        errors = compare(lib, ref, states, ("forward_dynamics",), p)
        assert errors["forward_dynamics"] <= tolerance, (precision, errors)
        q, qd, _, tau = states[0]
        status, qdd = lib.forward_dynamics_checked(np.full(robot.dof, np.nan), qd, tau, p, qdd=np.full(robot.dof, 7.0))
        assert status == 2 and np.all(qdd == 7.0)  # an input not finite: 2, not "singular"
        for k, (name, bad) in enumerate((("q", np.inf), ("qd", -np.inf), ("tau", np.nan))):
            args = [q.copy(), qd.copy(), tau.copy()]
            args[k][robot.dof - 1] = bad
            status, qdd = lib.forward_dynamics_checked(*args, p, qdd=np.full(robot.dof, 7.0))
            assert status == 2 and np.all(qdd == 7.0), (precision, name)
        huge = 1e200 if precision == "double" else 1e30
        status, qdd = lib.forward_dynamics_checked(q, np.full(robot.dof, huge), tau, p, qdd=np.full(robot.dof, 7.0))
        assert status == 2 and np.all(qdd == 7.0)


def test_pair_cse_agrees_with_pinocchio(tmp_path, monkeypatch):
    """The pair CSE of very long programs (the default from PAIR_CSE_FROM statements, only long
    chains' Coriolis matrices reach it) forced on the dense 7-joint Panda, every function: the
    compiled C agrees with Pinocchio, with fewer multiplications than without any CSE (Coriolis
    matrix: 2088 against 2131; SymPy's CSE: 2093)."""
    import symdyn
    import symdyn.emit.cgen as cgen
    import symdyn.emit.cplan as cplan
    from helpers import robot_path
    robot = symdyn.load(robot_path("panda"))
    eqs = symdyn.derive(robot)
    monkeypatch.setattr(cplan.sp, "cse", lambda exprs, **kwargs: ([], list(exprs)))
    plain = cgen.build_function(eqs, "coriolis_matrix", "double", "panda").ops
    monkeypatch.undo()
    monkeypatch.setattr(cplan, "PAIR_CSE_FROM", 1)
    paired = cgen.build_function(eqs, "coriolis_matrix", "double", "panda").ops
    assert paired["mul"] < plain["mul"] and paired["add"] == plain["add"], (paired, plain)
    files = cgen.generate_c(eqs)
    lib = build_and_load(files, "panda", Dimensions.of(robot), len(robot.parameters), "double", str(tmp_path))
    _compare(lib, "panda", "double", 1e-10)


def test_pair_cse_is_an_identity():
    """pair_cse: the reduced expressions with the named products put back are the inputs, and a
    product shared up to the coefficient's sign is named once."""
    import sympy as sp
    from symdyn.emit.emission import pair_cse
    a, b, c, d, x = sp.symbols("a b c d x")
    exprs = [0.3 * a * b + 2 * c * d, -0.3 * a * c + x, 2 * c * d * a - b, a * b * x, sp.sin(a) + 1]
    replacements, reduced = pair_cse(exprs, sp.numbered_symbols("cse"))
    back = dict(replacements)
    for original, new in zip(exprs, reduced):
        assert sp.expand(new.xreplace(back) - original) == 0
    named = [e for _, e in replacements]
    assert 0.3 * a in named and 2 * c in named and a * b in named  # 2*c*d: the first of equal pairs
    assert len(named) == len(set(named))


#: clang's -Weverything, minus warnings that do not apply to generated C99:
#: -Wdeclaration-after-statement: C99 allows declarations after statements; every intermediate is
#:   declared const at its single assignment (C90 compatibility is not a goal);
#: -Wunused-macros: only reported for macros of the main file; the configuration macros
#:   (SYMDYN_LIBM_TRIG, SYMDYN_NO_VECTOR, the pivot tolerance) are there for the user to set.
CLANG_EVERYTHING = ["-std=c99", "-Weverything", "-Werror", "-Wno-declaration-after-statement", "-Wno-unused-macros"]


@pytest.mark.skipif(shutil.which("clang") is None, reason="clang is not installed")
def test_clang_weverything(tmp_path, monkeypatch):
    """Every checked-in file (arms and platforms) and the forms not checked in (float, mixed,
    batch vectors, articulated-body forward dynamics, the long chains' LDL^T and Gram loops)
    compile with clang -Weverything -Werror minus the justified list above; each file is
    included by a user's file that calls nothing (no warning for what it leaves unused)."""
    import symdyn
    import symdyn.derive.composite as composite
    import symdyn.derive.equations as equations
    from symdyn.emit.cgen import generate_c
    cases = {}
    for path in sorted(GENERATED.glob("*.c")) + sorted((GENERATED / "parallel").glob("*.c")):
        cases[path.stem] = {f.name: f.read_text() for f in path.parent.glob(path.stem + ".*")}
    for robot_name, options in (("scara", dict(precision="float", batch=True)), ("planar2r", dict(precision="mixed")),
                                ("ur5", dict(fd_method="aba", batch=True))):
        cases[f"{robot_name}_{'_'.join(str(v) for v in options.values())}"] = {
            k: v.decode() for k, v in generate(configure(REPO / "robots" / f"{robot_name}.yaml", GenerateOptions(**options))).items()}
    monkeypatch.setattr(equations, "LOOPED_SOLVE_FROM_DOF", 1)
    monkeypatch.setattr(composite, "PROJECTED_FROM_DOF", 1)
    eqs = symdyn.derive(symdyn.load(str(REPO / "robots" / "iiwa14.yaml")), outputs=["mass_matrix", "forward_dynamics"])
    assert eqs.fd_system and eqs.mass_factors
    cases["iiwa14_looped"] = generate_c(eqs, ["mass_matrix", "forward_dynamics"], batch=True)
    clang = shutil.which("clang")
    for case, files in cases.items():
        folder = tmp_path / case
        folder.mkdir()
        for name, text in files.items():
            (folder / name).write_text(text)
        header = next(name for name in files if name.endswith(".h"))
        (folder / "user.c").write_text(f'#include "{header}"\nint symdyn_user_unit(void);\n'
                                       "int symdyn_user_unit(void) { return 0; }\n")
        for source in [name for name in files if name.endswith(".c")] + ["user.c"]:
            # clang's warnings come from its front end (no optimization-dependent ones as in gcc)
            result = subprocess.run([clang, *CLANG_EVERYTHING, "-fsyntax-only", str(folder / source)],
                                    capture_output=True, text=True)
            assert result.returncode == 0, f"{case}/{source}:\n{result.stderr[-3000:]}"


def test_fused_sums_are_the_plain_sums_with_the_plain_macro():
    """CPrinter with a fused multiply-add macro: sums of products (signs, numbers, divisions,
    parenthesized sums, powers) evaluated with the macros as c + a*b and c - a*b (Python floats:
    IEEE double, C's order) give the plain printer's value bit for bit, and differ from it with
    the macros as correctly rounded fused a*b + c, -a*b + c somewhere."""
    import math
    from fractions import Fraction

    import sympy as sp
    from symdyn.emit.cprinter import CPrinter

    a, b, c, d, e, f = symbols = sp.symbols("a b c d e f")
    names = {s: s.name for s in symbols}
    expressions = [a * b + c * d, a - b * c * d - sp.Rational(3, 7) * e, 0.3 * a * b - c / d + e * (f + a) - b ** 2 * c,
                   -a * b - c * d * e + f, a / (b * c) + d * e * f + 2 * a, a * b * c ** 3 - d]
    plain_printer, fused_printer = CPrinter(names), CPrinter(names, fma="FMA")

    def value(text, env):
        return eval(text.replace("sqrt", "math.sqrt"), {"math": math}, env)  # the printed C of plain arithmetic

    def exact_fma(x, y, z):
        return float(Fraction(x) * Fraction(y) + Fraction(z))

    rng = np.random.default_rng(41)
    fused_differs = False
    for expr in expressions:
        plain, fused = plain_printer.doprint(expr), fused_printer.doprint(expr)
        assert "FMA" in fused
        for _ in range(200):
            env = {s.name: float(rng.uniform(-3, 3)) for s in symbols}
            plain_macros = {"FMA": lambda x, y, z: z + x * y, "FMA_NEG": lambda x, y, z: z - x * y}
            assert value(fused, {**env, **plain_macros}) == value(plain, env), (plain, fused)
            fused_macros = {"FMA": exact_fma, "FMA_NEG": lambda x, y, z: exact_fma(-x, y, z)}
            fused_differs |= value(fused, {**env, **fused_macros}) != value(plain, env)
    assert fused_differs


def test_long_bodies_fused_agree_with_pinocchio(tmp_path, monkeypatch):
    """Every body at or past symdyn.emit.cgen.FUSE_FROM_STATEMENTS prints its sums with the fused
    multiply-add macro (here every body of puma560: the limit set to 0): built for FMA hardware
    (-mfma: fma()) every default function agrees with Pinocchio at 50 states and differs from the
    plain build (a*b + c) by rounding only, somewhere; their batch forms (loops over the scalar
    functions: GCC's vector types have no fused multiply-add) give the scalar results bit for bit."""
    import symdyn
    from helpers import fma_hardware, robot_path
    from symdyn.emit import cgen
    if not fma_hardware():
        pytest.skip("no FMA hardware (x86-64 with fma) to run the fused build on")
    monkeypatch.setattr(cgen, "FUSE_FROM_STATEMENTS", 0)
    robot = symdyn.load(robot_path("puma560"))
    eqs = symdyn.derive(robot, outputs=OUTPUTS)
    files = cgen.generate_c(eqs, OUTPUTS, batch=True)
    fused, plain = tmp_path / "fused", tmp_path / "plain"
    fused.mkdir()
    plain.mkdir()
    fused_lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, workdir=str(fused), extra_flags=["-mfma"])
    plain_lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, workdir=str(plain))
    _compare(fused_lib, "puma560", "double", 1e-10)
    states = random_states(robot.dof, 5, seed=8)
    differs = False
    for q, qd, qdd, tau in states:
        a, b = fused_lib.inverse_dynamics(q, qd, qdd), plain_lib.inverse_dynamics(q, qd, qdd)
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)
        differs |= not np.array_equal(a, b) or not np.array_equal(fused_lib.mass_matrix(q), plain_lib.mass_matrix(q))
    assert differs  # the fused build does fuse
    import ctypes
    q = np.ascontiguousarray([state[0] for state in states], dtype=np.float64)
    batch = np.zeros((len(q), robot.dof * robot.dof))
    pointer = ctypes.POINTER(ctypes.c_double)
    fused_lib.lib.puma560_mass_matrix_batch(ctypes.c_int(len(q)), q.ctypes.data_as(pointer), batch.ctypes.data_as(pointer))
    assert np.array_equal(batch, np.array([fused_lib.mass_matrix(x).ravel() for x in q]))


def test_check_optimization_level(monkeypatch):
    """compile_shared's -O flag: -O2 (what users build with) unless SYMDYN_CHECK_OPTIMIZATION names
    another level (the suite sets -O1); anything else in it is ignored, never passed to the compiler."""
    from symdyn.check.cbuild import OPTIMIZATION_VARIABLE, optimization_flag
    monkeypatch.delenv(OPTIMIZATION_VARIABLE, raising=False)
    assert optimization_flag() == "-O2"
    for level in ("-O0", "-O1", "-O3", "-Os"):
        monkeypatch.setenv(OPTIMIZATION_VARIABLE, level)
        assert optimization_flag() == level
    for junk in ("-O9", "-O1 -fsanitize=address", "; rm -rf /", ""):
        monkeypatch.setenv(OPTIMIZATION_VARIABLE, junk)
        assert optimization_flag() == "-O2"
