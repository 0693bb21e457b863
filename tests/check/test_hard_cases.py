"""Numerically hard cases: the compiled C (double and float) against an independent 50-digit
mpmath Newton-Euler (symdyn.check.reference), error normalized per joint by the RMS of that joint's
reference value.  Bounds: double <= 1e-12, float <= 1e-4, never NaN or Inf.  In float the
reference is evaluated at the inputs as rounded to float, so only the arithmetic is judged."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from symdyn.model.outputs import Dimensions
import symdyn
from helpers import normalized_error, robot_path
from symdyn.check.states import state_arguments
from symdyn.check.cbuild import build_and_load
from symdyn.emit.cgen import generate_c
from symdyn.check.reference import MpReference

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None and shutil.which("cc") is None,
                                reason="no C compiler")

BOUNDS = {"double": 1e-12, "float": 1e-4}
FUNCTIONS = ("inverse_dynamics", "mass_matrix", "coriolis", "coriolis_matrix", "gravity", "forward_dynamics")

# a 4-joint spatial arm; masses and inertias filled in per case
ARM = """format: 1
name: {name}
convention: standard
gravity: [0, 0, -9.81]
links:
  - {{joint: revolute, a: {L}, alpha: pi/2, d: {L}, theta: 0.3, mass: {m0}, com: [{c}, {c}, {c}], inertia: [{i0}, {i0}, {i0}, 0, 0, 0], damping: 0.1}}
  - {{joint: revolute, a: {L2}, alpha: 0, d: 0, theta: -0.2, mass: {m1}, com: [-{c}, 0, {c}], inertia: [{i1}, {j1}, {i1}, 0, 0, 0], armature: {arm}}}
  - {{joint: revolute, a: {L}, alpha: -pi/2, d: {L}, theta: 0, mass: {m2}, com: [0, {c}, -{c}], inertia: [{i2}, {i2}, {j2}, 0, 0, 0]}}
  - {{joint: revolute, a: 0, alpha: pi/2, d: {L2}, theta: 0.1, mass: {m3}, com: [{c}, 0, {c}], inertia: [{i3}, {j3}, {i3}, 0, 0, 0]}}
"""


def arm(name, masses, length=0.3, armature=0.0):
    fields = {"name": name, "L": length, "L2": 2 * length, "c": length / 3, "arm": armature}
    for k, m in enumerate(masses):
        fields[f"m{k}"] = m
        fields[f"i{k}"] = m * length ** 2 / 6
        fields[f"j{k}"] = m * length ** 2 / 4
    return symdyn.loads(ARM.format(**fields), path=f"<{name}>")


def states(n, count, seed, q=(-np.pi, np.pi), qd=(-2, 2), qdd=(-5, 5), tau=(-20, 20), fix=None):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        s = [rng.uniform(*q, n), rng.uniform(*qd, n), rng.uniform(*qdd, n), rng.uniform(*tau, n)]
        if fix:
            fix(s, rng)
        out.append(s)
    return out


def _wrist_aligned(s, rng):
    s[0][4] = rng.choice([0.0, 1e-9, -1e-7])  # puma560: q5 = 0 aligns the axes of joints 4 and 6


def _elbow_stretched(s, rng):
    s[0][2] = rng.choice([0.0, 1e-9])  # ur5: q3 = 0 stretches the arm


def _prismatic_far(s, rng):
    s[0][2] = rng.uniform(50, 100)  # stanford: the boom 50-100 m out


def _near_zero_torque(s, rng):
    s[1][:] = rng.uniform(-1e-6, 1e-6, len(s[1]))  # almost at rest: joints 4-6 carry almost nothing
    s[2][:] = rng.uniform(-1e-6, 1e-6, len(s[2]))


CASES = {
    "wrist_aligned": (lambda: symdyn.load(robot_path("puma560")), dict(fix=_wrist_aligned)),
    "elbow_stretched": (lambda: symdyn.load(robot_path("ur5")), dict(fix=_elbow_stretched)),
    "mass_ratio_light_to_heavy": (lambda: arm("heavy_tip", [1e-3, 1.0, 1e3, 1e3], armature=0.01), {}),
    "mass_ratio_heavy_to_light": (lambda: arm("light_tip", [1e3, 1e3, 1.0, 1e-3], armature=0.01), {}),
    "huge_angles": (lambda: arm("offsets", [2.0, 1.5, 1.0, 0.5]), dict(q=(-1e4, 1e4))),
    "huge_rates": (lambda: symdyn.load(robot_path("ur5")), dict(qd=(-1e3, 1e3), tau=(-1e5, 1e5))),
    "tiny_links": (lambda: arm("tiny", [1e-3, 1e-3, 1e-3, 1e-3], length=1e-6), dict(tau=(-1e-12, 1e-12))),
    "prismatic_far": (lambda: symdyn.load(robot_path("stanford")), dict(fix=_prismatic_far)),
    "near_zero_torque": (lambda: symdyn.load(robot_path("puma560")), dict(fix=_near_zero_torque, tau=(-1, 1))),
}

_BUILT = {}
_DERIVED = {}  # robot name -> (robot, equations): one derivation for both precisions and every case


def compiled(case, precision, tmp_path_factory):
    """The robot of ``case`` and its library in ``precision``, built once per robot (the cases on
    puma560 and on ur5 share theirs)."""
    robot = CASES[case][0]()
    key = (robot.name, precision)
    if key not in _BUILT:
        if robot.name not in _DERIVED:
            _DERIVED[robot.name] = (robot, symdyn.derive(robot, outputs=FUNCTIONS))
        robot, eqs = _DERIVED[robot.name]
        files = generate_c(eqs, FUNCTIONS, precision=precision)
        workdir = tmp_path_factory.mktemp(f"{robot.name}_{precision}")
        _BUILT[key] = (robot, build_and_load(files, robot.name, Dimensions.of(robot), 0, precision, str(workdir)))
    return _BUILT[key]


@pytest.mark.parametrize("case", sorted(CASES))
def test_hard_case_against_mpmath(case, tmp_path_factory):
    """Double and float C at the same states, each number representable in float (so that the
    one derivation and the 50-digit reference serve both), against the reference."""
    reference = None
    options = CASES[case][1]
    values = {}  # (function, inputs' bytes) -> the 50-digit value

    def exact(fname, args):
        key = (fname, b"".join(a.tobytes() for a in args))
        if key not in values:
            values[key] = getattr(reference, fname)(*args)
        return values[key]
    bad = {}
    for precision in ("double", "float"):
        robot, lib = compiled(case, precision, tmp_path_factory)
        reference = reference or MpReference(robot)
        errors, conditions = {}, []
        for fname in FUNCTIONS:
            mine, theirs = [], []
            for s in states(robot.dof, 6, seed=len(case), **options):
                s = [x.astype(np.float32).astype(float) for x in s]
                args = state_arguments(fname, s)
                value = np.asarray(getattr(lib, fname)(*args), dtype=float)
                assert np.all(np.isfinite(value)), f"{case} {precision} {fname}: not finite"
                mine.append(value)
                theirs.append(exact(fname, args))
                if fname == "forward_dynamics":
                    conditions.append(exact("condition_number", [s[0]]))
            errors[fname] = normalized_error(mine, theirs)
        print(f"{case} {precision}: worst cond(D) {max(conditions):.1e}; "
              + ", ".join(f"{k} {v:.1e}" for k, v in errors.items()))
        bad.update({f"{precision} {k}": f"{v:.2e}" for k, v in errors.items() if not v <= BOUNDS[precision]})
    assert not bad, f"{case} (cond(D) up to {max(conditions):.1e}): {bad}"


def test_reference_is_independent_and_exact_on_a_textbook_case():
    """The mpmath reference reproduces the planar two-link closed forms at 50 digits."""
    robot = symdyn.load(robot_path("planar2r"))
    values = {"g": 9.81, "m1": 2.0, "lc1": 0.25, "I1": 0.1, "l1": 0.5, "m2": 1.5, "lc2": 0.2, "I2": 0.05}
    ref = MpReference(robot, values)
    q = np.array([0.3, -0.7])
    qd = np.array([1.1, -0.4])
    c2, s2 = np.cos(q[1]), np.sin(q[1])
    m1, lc1, I1, l1, m2, lc2, I2, g = (values[k] for k in ("m1", "lc1", "I1", "l1", "m2", "lc2", "I2", "g"))
    D = np.array([[m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2) + I1 + I2, m2 * (lc2**2 + l1 * lc2 * c2) + I2],
                  [m2 * (lc2**2 + l1 * lc2 * c2) + I2, m2 * lc2**2 + I2]])
    h = np.array([-m2 * l1 * lc2 * s2 * (2 * qd[0] * qd[1] + qd[1]**2), m2 * l1 * lc2 * s2 * qd[0]**2])
    c = np.array([(m1 * lc1 + m2 * l1) * g * np.cos(q[0]) + m2 * lc2 * g * np.cos(q[0] + q[1]),
                  m2 * lc2 * g * np.cos(q[0] + q[1])])
    np.testing.assert_allclose(ref.mass_matrix(q), D, rtol=1e-14)
    np.testing.assert_allclose(ref.coriolis(q, qd), h, rtol=1e-14)
    np.testing.assert_allclose(ref.gravity(q), c, rtol=1e-14)
    np.testing.assert_allclose(ref.coriolis_matrix(q, qd) @ qd, h, rtol=1e-14)


@pytest.mark.slow
def test_bench_measures_every_variant(tmp_path, capsys):
    """symdyn bench on a 3-joint chain: every variant measured, each error within its bound,
    table and plot written; a robot with free parameters is refused in one line."""
    from symdyn.check import bench
    from symdyn.cli import main
    robot = symdyn.load(robot_path("three_modified"))
    results = bench.bench_robot(robot, ("inverse_dynamics", "mass_matrix", "forward_dynamics"),
                                ("ne-double", "ne-float", "jne-double", "closed-double", "casadi-sx", "casadi-c",
                                 "pinocchio"),
                                count=3, workdir=str(tmp_path))
    seen = {(r.variant, r.function) for r in results}
    assert ("closed-double", "mass_matrix") in seen and ("casadi-c", "forward_dynamics") in seen
    assert ("jne-double", "inverse_dynamics") in seen
    assert ("closed-double", "forward_dynamics") not in seen  # not offered for the closed form
    for r in results:
        bound = 1e-4 if r.variant == "ne-float" else 1e-12
        assert r.error <= bound, r
        assert r.ns is not None and r.ns > 0
    out = tmp_path / "out"
    assert main(["bench", robot_path("scara"), "--variants", "ne-double,casadi-sx", "--functions", "gravity",
                 "--states", "2", "--out", str(out), "--quiet"]) == 0
    assert "| scara | gravity | ne-double |" in capsys.readouterr().out
    assert (out / "bench.png").read_bytes()[:4] == b"\x89PNG"
    assert "symdyn bench" in (out / "bench.md").read_text()
    rows = (out / "bench.csv").read_text().splitlines()
    assert rows[0].startswith("robot,function,variant,") and len(rows) == 3 and rows[1].startswith("scara,gravity,")
    assert float(rows[1].split(",")[3]) > 0
    assert main(["bench", robot_path("planar2r"), "--quiet"]) == 1
    assert "no value" in capsys.readouterr().err


def test_bench_without_matplotlib_keeps_the_table_and_data(tmp_path, capsys, monkeypatch):
    """No matplotlib: said once before the measurements, with how to get the plot; bench.md and
    bench.csv written, exit 0. A plot that fails otherwise costs only the plot."""
    from symdyn.check import bench
    from symdyn.cli import main
    monkeypatch.setattr(bench, "can_plot", lambda: False)
    out = tmp_path / "out"
    argv = ["bench", robot_path("scara"), "--variants", "ne-double", "--functions", "gravity", "--states", "2", "--quiet"]
    assert main([*argv, "--out", str(out)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "matplotlib is not installed" in err[0] and "symdyn[plot]" in err[0], err
    assert sorted(p.name for p in out.iterdir()) == ["bench.csv", "bench.md"]
    assert "| scara | gravity | ne-double |" in (out / "bench.md").read_text()
    assert "bench.png" not in (out / "bench.md").read_text()
    monkeypatch.setattr(bench, "can_plot", lambda: True)

    def broken(results, path):
        raise RuntimeError("no display")
    monkeypatch.setattr(bench, "plot", broken)
    assert main([*argv, "--out", str(tmp_path / "again")]) == 0
    err = capsys.readouterr().err
    assert "the plot failed (RuntimeError: no display)" in err
    assert sorted(p.name for p in (tmp_path / "again").iterdir()) == ["bench.csv", "bench.md"]
    assert main(["bench", robot_path("scara"), "--variants", "fastest"]) == 1
