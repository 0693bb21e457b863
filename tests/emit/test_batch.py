"""Batch functions (``generate --batch``) equal the scalar ones bit for bit (a NaN equals any NaN), for counts 0, 1, 7 and
1000, vectorized (GCC/Clang vector types) and in the portable form; and the sin/cos block of every
generated function stays within 1 ulp of libm (libm itself beyond |x| = 1e5, NaN and infinity)."""

import shutil
import subprocess

import numpy as np
import pytest

import symdyn
from helpers import REPO
from symdyn.check.cbuild import WARNING_FLAGS
from symdyn.cli import main
from symdyn.model.outputs import COMBINED, REGISTRY, function_inputs, returns_status

GCC = shutil.which("gcc")
CLANG = shutil.which("clang")
pytestmark = pytest.mark.skipif(GCC is None, reason="no C compiler")

CASES = {  # robot or scene file: friction (sign), general placements, a prismatic joint, base and tool;
    # runtime parameters p shared by all states of a batch
    "general_arm": REPO / "tests" / "data" / "general_arm.yaml",
    "ur5_payload": REPO / "robots" / "scenes" / "ur5_payload.yaml",
}
COUNTS = (0, 1, 7, 1000)


def signature(robot, eqs, name):
    """(input arrays with their sizes, output arrays with their sizes) of NAME_<name>_batch."""
    parts = COMBINED.get(name, (name,))
    inputs = [(group, robot.dof) for group in function_inputs(name)]  # a combined function's: all its parts
    outputs = []
    for part in parts:  # the derived matrix's blocks, as the registry splits them
        matrix = eqs.output(part)
        for argument in REGISTRY[part].arguments:
            block = matrix[:, argument.first:argument.end]
            outputs.append((argument.name, block.rows * block.cols))
    return inputs, outputs


def harness(prefix, robot, eqs, names, n_params):
    """A C program: for every function and count, the batch result must equal count scalar calls
    byte for byte (output buffers prefilled, so a row that must stay unwritten is checked too);
    prints one line per mismatch and exits 1."""
    n = robot.dof
    states = 1000
    lines = [f'#include <stdio.h>\n#include <string.h>\n#include <math.h>\n#include "{prefix}_dynamics.h"',
             f"#define S {states}",
             f"static double q[S * {n}], qd[S * {n}], qdd[S * {n}], tau[S * {n}], p[{max(n_params, 1)}];",
             "static double a1[S * 1024], a2[S * 1024], b1[S * 1024], b2[S * 1024];",
             "static unsigned long seed = 12345;",
             # equal bit for bit, or both NaN (which NaN an operation returns is not specified)
             "static int same(const double *x, const double *y, size_t count) { size_t i; for (i = 0; i < count; ++i)"
             " if (memcmp(x + i, y + i, sizeof *x) && !(x[i] != x[i] && y[i] != y[i])) return 0; return 1; }",
             "static double uniform(double lo, double hi) { seed = seed * 6364136223846793005UL + 1442695040888963407UL;"
             " return lo + (hi - lo) * (double)(seed >> 11) / 9007199254740992.0; }",
             "int main(void) {", "    int k, c, bad = 0;",
             "    static const int counts[] = {" + ", ".join(map(str, COUNTS)) + "};",
             f"    for (k = 0; k < S * {n}; ++k) {{ q[k] = uniform(-4, 4); qd[k] = uniform(-2, 2); qdd[k] = uniform(-3, 3);"
             " tau[k] = uniform(-20, 20); }",
             f"    for (k = 0; k < {max(n_params, 1)}; ++k) p[k] = uniform(0.5, 1.5);",
             # hard lanes: angles beyond the polynomial's range (libm), a NaN state (forward
             # dynamics: nonzero status, row left unwritten), an infinite velocity
             f"    q[3 * {n}] = 2.5e5; q[5 * {n} + 1] = -1.0e7; q[{n} * 1 + 0] = 1.0e5;",
             f"    q[6 * {n}] = NAN; qd[500 * {n}] = INFINITY;"]
    for name in names:
        inputs, outputs = signature(robot, eqs, name)
        scalar = f"{name}_checked" if name == "forward_dynamics" and eqs.pivots else name
        param = ", p" if n_params else ""
        # two output arrays at most (reaction_map: k0, D; kinematics: T, J)
        out1 = outputs[0]
        out2 = outputs[1] if len(outputs) > 1 else None
        s_args = ", ".join(f"{g} + (size_t)k * {size}" for g, size in inputs)
        b_args = ", ".join(g for g, _ in inputs)
        s_out = f"a1 + (size_t)k * {out1[1]}" + (f", b1 + (size_t)k * {out2[1]}" if out2 else "")
        b_out = "a2" + (", b2" if out2 else "")
        ret = "int" if scalar.endswith("_checked") or returns_status(name) else None
        lines.append("    for (c = 0; c < 4; ++c) {")
        if ret:
            lines.append("        int failed = 0;")
        lines.append("        memset(a1, 0x5a, sizeof a1); memset(a2, 0x5a, sizeof a2); memset(b1, 0x5a, sizeof b1);"
                     " memset(b2, 0x5a, sizeof b2);")
        call = f"{prefix}_{scalar}({s_args}{param}, {s_out})"
        lines.append(f"        for (k = 0; k < counts[c]; ++k) {{ {'failed += ' + call + ' != 0' if ret else call}; }}")
        batch_call = f"{prefix}_{name}_batch(counts[c], {b_args}{param}, {b_out})"
        if ret:
            lines.append(f"        if ({batch_call} != failed) {{ printf(\"{name}: failure count, count %d\\n\", counts[c]); bad = 1; }}")
        else:
            lines.append(f"        {batch_call};")
        lines.append(f"        if (!same(a1, a2, S * 1024) || !same(b1, b2, S * 1024)) "
                     f"{{ printf(\"{name}: differs, count %d\\n\", counts[c]); bad = 1; }}")
        lines.append("    }")
    lines += ["    return bad;", "}"]
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module")
def batch_build(tmp_path_factory):
    """The generated files and the test harness of each case (one generate per case)."""
    out = tmp_path_factory.mktemp("batch")
    built = {}
    for case, path in CASES.items():
        names = ["inverse_dynamics", "mass_matrix", "coriolis", "coriolis_matrix", "gravity", "forward_dynamics",
                 "forward_kinematics", "jacobian", "jacobian_dot_qd"]
        if case == "general_arm":  # with two frames: the frame and centroidal functions too
            text = path.read_text().replace("\nlinks:\n", "\nframes: [wrist, {name: grip, link: flange, xyz: [0, 0.02, "
                                            "0.1], rpy: [0.1, 0, 0.4]}]\nlinks:\n", 1)
            path = out / "general_arm_frames.yaml"
            path.write_text(text)
            names += ["frame_poses", "frame_jacobians", "frame_jacobian_dot_v", "center_of_mass",
                      "center_of_mass_jacobian", "center_of_mass_bias", "centroidal_momentum_matrix", "centroidal_bias",
                      "mass_matrix_inverse"]  # (status-returning: failure counts checked)
        assert main(["generate", str(path), "--out", str(out / case), "--batch", "--quiet",
                     "--functions", ",".join(names)]) == 0
        robot = symdyn.load(str(path))
        eqs = symdyn.derive(robot, outputs=names)
        names += ["kinematics"]  # (frame_kinematics has three outputs, more than this harness checks)
        (out / case / "check.c").write_text(harness(robot.name, robot, eqs, names, len(robot.parameters)))
        built[case] = (out / case, robot.name)
    return built


#: GCC's SLP vectorizer fuses neighbouring a*b - c, a*b + c into vfmaddsub on FMA hardware even
#: with -ffp-contract=off (the generated header says so); -fno-tree-slp-vectorize keeps -O3's
#: other transformations and the IEEE results.  Clang honours the flag as it is.
GCC_O3_NATIVE = ["-O3", "-march=native", "-fno-tree-slp-vectorize"]

VARIANTS = [("gcc", ["-O2"]), ("gcc", GCC_O3_NATIVE), ("gcc", ["-O2", "-DSYMDYN_NO_VECTOR"]),
            ("gcc", ["-O2", "-DSYMDYN_LIBM_TRIG"]), ("clang", ["-O3", "-march=native"])]


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("compiler,flags", VARIANTS, ids=[" ".join([c, *f]) for c, f in VARIANTS])
def test_batch_equals_scalar_bit_for_bit(batch_build, case, compiler, flags):
    exe_compiler = GCC if compiler == "gcc" else CLANG
    if exe_compiler is None:
        pytest.skip(f"{compiler} not installed")
    folder, prefix = batch_build[case]
    exe = folder / f"check_{compiler}_{'_'.join(f.strip('-') for f in flags)}"
    subprocess.run([exe_compiler, *WARNING_FLAGS, *flags, str(folder / "check.c"),
                    str(folder / f"{prefix}_dynamics.c"), "-o", str(exe), "-lm"], check=True)
    run = subprocess.run([str(exe)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout


def test_sin_cos_block_within_one_ulp_of_libm(tmp_path):
    """The generated sin/cos helper against libm at 180,000 angles in [-1e5, 1e5] (a third near
    multiples of pi/4, where the reduction loses most): within 1 ulp (or 1e-29 absolute) for |x| <= 8
    (joint angles), 1.2e-16 absolute beyond; past 1e5, NaN and infinities it returns libm's values exactly (and
    sin(0) = 0; sin(-0) is +0, not libm's -0).  The vector form (2 lanes at -O2, 4 with AVX) and
    the scalar form (SYMDYN_NO_VECTOR) give identical bits."""
    out = tmp_path / "gen"
    assert main(["generate", str(REPO / "robots" / "planar2r.yaml"), "--out", str(out), "--quiet",
                 "--functions", "gravity"]) == 0
    rng = np.random.default_rng(5)
    angles = np.concatenate([rng.uniform(-4, 4, 60000), rng.uniform(-1e5, 1e5, 60000),
                             np.round(rng.uniform(-4e4, 4e4, 60000)) * (np.pi / 4) + rng.normal(0, 1e-9, 60000),
                             np.nextafter(np.pi / 4 * np.arange(-10, 11), np.inf), [1e5, -1e5]])
    special = [np.nextafter(1e5, np.inf), -2.5e5, 1e22, np.inf, -np.inf, np.nan, 0.0]  # sin(-0) gives +0
    values = ", ".join(repr(float(a)) if np.isfinite(a) else ("NAN" if np.isnan(a) else ("INFINITY" if a > 0 else "-INFINITY"))
                       for a in list(angles) + special)
    program = tmp_path / "trig.c"
    program.write_text(f"""#include <stdio.h>
#include <math.h>
#include <string.h>
#include "planar2r_dynamics.c"
static const double x[] = {{{values}}};
#define COUNT (int)(sizeof x / sizeof x[0])
static double s[COUNT], c[COUNT];
int main(void) {{
    int i, bad = 0;
    double worst = 0.0;
    unsigned long long digest = 0, bits;
    planar2r_sincos(COUNT - {len(special)}, x, s, c);
    planar2r_sincos({len(special)}, x + COUNT - {len(special)}, s + COUNT - {len(special)}, c + COUNT - {len(special)});
    for (i = 0; i < COUNT; ++i) {{
        double es = fabs(s[i] - sin(x[i])), ec = fabs(c[i] - cos(x[i]));
        memcpy(&bits, &s[i], sizeof bits);
        digest = digest * 1000003u ^ bits;
        memcpy(&bits, &c[i], sizeof bits);
        digest = digest * 1000003u ^ bits;
        if (i >= COUNT - {len(special)}) {{
            double ls = sin(x[i]), lc = cos(x[i]);
            if (memcmp(&s[i], &ls, sizeof ls) && !(isnan(s[i]) && isnan(ls))) bad = 1;
            if (memcmp(&c[i], &lc, sizeof lc) && !(isnan(c[i]) && isnan(lc))) bad = 1;
            continue;
        }}
        if (es > worst) worst = es;
        if (ec > worst) worst = ec;
        /* |x| <= 8: at most one unit in the last place of libm's value (or 1e-29 next to the
           multiples of pi/2, where the value itself is tiny); beyond, 1.2e-16 absolute */
        if (fabs(x[i]) <= 8.0 && es > fmax(nextafter(fabs(sin(x[i])), 2.0) - fabs(sin(x[i])), 1e-29)) bad = 1;
        if (fabs(x[i]) <= 8.0 && ec > fmax(nextafter(fabs(cos(x[i])), 2.0) - fabs(cos(x[i])), 1e-29)) bad = 1;
    }}
    printf("%.3g %llx\\n", worst, digest);
    return bad;
}}
""")
    digests = set()
    for label, flags in (("vector", ["-O2"]), ("scalar", ["-O2", "-DSYMDYN_NO_VECTOR"]), ("native", ["-O3", "-march=native"])):
        exe = tmp_path / f"trig_{label}"
        subprocess.run([GCC, "-std=c99", *flags, "-I", str(out), str(program), "-o", str(exe), "-lm"], check=True)
        run = subprocess.run([str(exe)], capture_output=True, text=True)
        assert run.returncode == 0, (label, run.stdout)
        worst, digest = run.stdout.split()
        assert float(worst) <= 1.2e-16, label
        digests.add(digest)
    assert len(digests) == 1, "the vector and scalar forms of the sin/cos block differ"


def test_looped_forms_batch_equals_scalar(tmp_path, monkeypatch):
    """The loop forms of long chains (the projected mass matrix's dot-product loop, forward
    dynamics' LDL^T loop; defaults from 16 joints) forced on general_arm: batch equals scalar
    bit for bit, vectorized and portable."""
    import symdyn.derive.composite as composite
    import symdyn.derive.equations as equations
    from symdyn.emit.cgen import generate_c
    monkeypatch.setattr(equations, "LOOPED_SOLVE_FROM_DOF", 1)
    monkeypatch.setattr(composite, "PROJECTED_FROM_DOF", 1)
    robot = symdyn.load(str(CASES["general_arm"]))
    names = ["mass_matrix", "forward_dynamics"]
    eqs = symdyn.derive(robot, outputs=names)
    assert eqs.fd_system and eqs.mass_factors
    for fname, text in generate_c(eqs, names, batch=True).items():
        (tmp_path / fname).write_text(text)
    (tmp_path / "check.c").write_text(harness(robot.name, robot, eqs, names, len(robot.parameters)))
    for flags in (["-O2"], GCC_O3_NATIVE, ["-O2", "-DSYMDYN_NO_VECTOR"]):
        exe = tmp_path / f"check_{'_'.join(f.strip('-') for f in flags)}"
        subprocess.run([GCC, *WARNING_FLAGS, *flags, str(tmp_path / "check.c"),
                        str(tmp_path / f"{robot.name}_dynamics.c"), "-o", str(exe), "-lm"], check=True)
        run = subprocess.run([str(exe)], capture_output=True, text=True)
        assert run.returncode == 0, (flags, run.stdout)
