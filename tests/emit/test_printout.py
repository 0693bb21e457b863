"""Textbook derivation printouts: the lecture's worked example, the textbook closed forms,
numerical agreement of every printed result with the derived equations, LaTeX that compiles,
and the checked-in examples in docs/derivations."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest
import sympy as sp

import symdyn
from helpers import REPO, parameter_values, random_states, robot_path
from symdyn.cli import main
from symdyn.derive.derivation import derive_steps
from symdyn.emit.printout import render

_DERIVATIONS = {}


def steps_of(name, method, form=None):
    key = (name, method, form)
    if key not in _DERIVATIONS:
        _DERIVATIONS[key] = derive_steps(symdyn.load(robot_path(name)), method,
                                         closed_form={None: None, "closed": True, "named": False}[form])
    return _DERIVATIONS[key]


def _symbols(*names):
    return [sp.Symbol(n, real=True) for n in names]


def _is_zero(expr) -> bool:
    return sp.simplify(sp.expand_trig(sp.expand(expr))) == 0


def test_planar2r_newton_euler_link_accelerations_match_the_worked_example():
    """Lecture 10, example Q3.4: with ^0vdot_0 = g Y0, in each link's own frame,
    ^1vdot_1 = (g s1, g c1, 0) and ^2vdot_2 = (l1 qdd1 s2 - l1 qd1^2 c2 + g s12,
    l1 qdd1 c2 + l1 qd1^2 s2 + g c12, 0); omega and omegadot add up the joint rates."""
    d = steps_of("planar2r", "newton-euler")
    q1, q2 = _symbols("q1", "q2")
    qd1, qd2 = _symbols("qd1", "qd2")
    qdd1, qdd2 = _symbols("qdd1", "qdd2")
    g, l1 = _symbols("g", "l1")
    s1, c1, s2, c2 = sp.sin(q1), sp.cos(q1), sp.sin(q2), sp.cos(q2)
    s12, c12 = sp.sin(q1 + q2), sp.cos(q1 + q2)
    expected = {
        ("omega", 1): sp.Matrix([0, 0, qd1]),
        ("omegadot", 1): sp.Matrix([0, 0, qdd1]),
        ("vdot", 1): sp.Matrix([g * s1, g * c1, 0]),
        ("omega", 2): sp.Matrix([0, 0, qd1 + qd2]),
        ("omegadot", 2): sp.Matrix([0, 0, qdd1 + qdd2]),
        ("vdot", 2): sp.Matrix([l1 * qdd1 * s2 - l1 * qd1**2 * c2 + g * s12,
                                l1 * qdd1 * c2 + l1 * qd1**2 * s2 + g * c12, 0]),
    }
    for (kind, link), value in expected.items():
        printed = d.to_joint_symbols(d.quantity(kind, link))
        assert all(_is_zero(e) for e in printed - value), f"{kind}_{link}: {printed}"
    # and a wrong acceleration is caught
    wrong = d.to_joint_symbols(d.quantity("vdot", 2)) - expected[("vdot", 2)] + sp.Matrix([g * s2, 0, 0])
    assert not all(_is_zero(e) for e in wrong)


@pytest.mark.parametrize("method", ["lagrange-euler", "newton-euler", "jacobian-newton-euler"])
def test_planar2r_ends_with_the_textbook_equations(method):
    d = steps_of("planar2r", method)
    m1, m2, l1, lc1, lc2, I1, I2, g = _symbols("m1", "m2", "l1", "lc1", "lc2", "I1", "I2", "g")
    q1, q2 = _symbols("q1", "q2")
    qd1, qd2 = _symbols("qd1", "qd2")
    c2, s2 = sp.cos(q2), sp.sin(q2)
    D = sp.Matrix([
        [m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2) + I1 + I2, m2 * (lc2**2 + l1 * lc2 * c2) + I2],
        [m2 * (lc2**2 + l1 * lc2 * c2) + I2, m2 * lc2**2 + I2]])
    h = sp.Matrix([-m2 * l1 * lc2 * s2 * (2 * qd1 * qd2 + qd2**2), m2 * l1 * lc2 * s2 * qd1**2])
    c = sp.Matrix([(m1 * lc1 + m2 * l1) * g * sp.cos(q1) + m2 * lc2 * g * sp.cos(q1 + q2),
                   m2 * lc2 * g * sp.cos(q1 + q2)])
    assert d.section("results") is d.sections[-1]
    for kind, expected in (("D", D), ("h", h), ("c", c)):
        printed = d.to_joint_symbols(d.quantity(kind))
        assert all(_is_zero(e) for e in printed - expected), f"{kind}: {printed}"
    if method == "lagrange-euler":
        h112 = d.to_joint_symbols(d.quantity("h_entry", 1, 1, 2))
        assert _is_zero(h112 + m2 * l1 * lc2 * s2)  # h_112 = -m2 l1 lc2 s2
    if method == "jacobian-newton-euler":  # H is the sum of the printed projected link mass matrices
        H = d.to_joint_symbols(d.quantity("projected", 1)) + d.to_joint_symbols(d.quantity("projected", 2))
        assert all(_is_zero(e) for e in H - D), f"sum of J_ci^T M_i J_ci: {H}"


#: the 6-joint puma560 by Lagrange-Euler and Jacobian-projected Newton-Euler prints with the same
#: code as the general 3-joint arm (three_standard) and takes 9 s more: run with -m slow
SLOW_PRINTOUTS = {("puma560", "lagrange-euler"), ("puma560", "jacobian-newton-euler")}
CASES = [("planar2r", "lagrange-euler", None), ("planar2r", "newton-euler", None),
         ("three_standard", "lagrange-euler", None), ("three_modified", "newton-euler", None),
         ("puma560", "newton-euler", None), ("puma560", "lagrange-euler", None),
         ("scara", "newton-euler", "closed"), ("planar2r", "jacobian-newton-euler", None),
         ("three_standard", "jacobian-newton-euler", None), ("puma560", "jacobian-newton-euler", None)]


@pytest.mark.parametrize("name,method,form", [
    pytest.param(*case, marks=[pytest.mark.slow] if case[:2] in SLOW_PRINTOUTS else []) for case in CASES])
def test_printed_results_equal_the_derived_equations(derived, name, method, form):
    """D, h, c as printed (closed form or with the x_k intermediates), and for the Newton-Euler
    methods every tau_i of the backward recursion (Jacobian-projected: at qdd = 0, so h + c),
    evaluated at seeded states against the equations."""
    from symdyn.derive.numeric import compile_function
    d = steps_of(name, method, form)
    eqs = derived(name, method)
    robot = eqs.robot
    values = parameter_values(robot)
    inputs = [eqs.q, eqs.qd, eqs.qdd, robot.parameters]
    program = d.program()
    fns = {k: compile_function(inputs, program, sp.Matrix(d.quantity(k))) for k in ("D", "h", "c")}
    taus = None
    if method != "lagrange-euler" and any(q.kind == "tau" for s in d.sections for q in s.quantities):
        taus = compile_function(inputs, program, sp.Matrix([d.quantity("tau", i + 1) for i in range(eqs.n)]))
    p = [values[s] for s in robot.parameters]
    num = eqs.numeric
    for q, qd, qdd, _ in random_states(eqs.n, 5, seed=9):
        args = (q, qd, qdd, p)
        pp = p or None
        np.testing.assert_allclose(fns["D"](*args), num.mass_matrix(q, pp), rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(fns["h"](*args).ravel(), num.coriolis(q, qd, pp), rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(fns["c"](*args).ravel(), num.gravity(q, pp), rtol=1e-9, atol=1e-9)
        if taus is not None and method == "jacobian-newton-euler":
            np.testing.assert_allclose(taus(*args).ravel(), num.coriolis(q, qd, pp) + num.gravity(q, pp),
                                       rtol=1e-9, atol=1e-9)
        elif taus is not None:
            friction = np.array([float(l.armature) * a + float(l.damping) * v + float(l.coulomb) * np.sign(v)
                                 for l, a, v in zip(robot.links, qdd, qd)])
            np.testing.assert_allclose(taus(*args).ravel(),
                                       num.inverse_dynamics(q, qd, qdd, pp) - friction, rtol=1e-9, atol=1e-9)
    # the symbolic route agrees with the numeric one on a small case
    if name == "planar2r":
        closed = d.to_joint_symbols(d.quantity("D")).subs(values)
        q = random_states(2, 1, seed=9)[0][0]
        at = closed.subs(dict(zip(eqs.q, q)))
        np.testing.assert_allclose(np.array(at, float), num.mass_matrix(q, p), rtol=1e-12)


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="pdflatex not installed (.ci/run installs it)")
@pytest.mark.parametrize("name,method", [("planar2r", "lagrange-euler"), ("planar2r", "newton-euler"),
                                         ("planar2r", "jacobian-newton-euler"),
                                         ("puma560", "newton-euler")])
def test_latex_output_compiles(tmp_path, name, method):
    tex = tmp_path / f"{name}.tex"
    tex.write_text(render(steps_of(name, method), "latex"))
    result = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", tex.name],
                            cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout[-2000:]
    assert (tmp_path / f"{name}.pdf").stat().st_size > 1000
    assert "Overfull \\hbox" not in (tmp_path / f"{name}.log").read_text(errors="replace")  # every line fits


def test_every_format_renders_every_section(tmp_path, capsys):
    d = steps_of("planar2r", "lagrange-euler")
    for fmt in ("text", "latex", "markdown"):
        text = render(d, fmt)
        assert "DO NOT EDIT" in text
        if fmt != "text":
            assert text.count("$$") % 2 == 0
    assert main(["derive", robot_path("planar2r"), "--format", "markdown", "--steps", "summary",
                 "--out", str(tmp_path / "p.md")]) == 0
    summary = (tmp_path / "p.md").read_text()
    assert "U_{21}" not in summary and "D(q)" in summary
    assert main(["derive", robot_path("planar2r"), "--steps", "summary"]) == 0
    assert "D(q)" in capsys.readouterr().out


def test_derive_cli_errors(tmp_path, capsys):
    assert main(["derive", str(tmp_path / "missing.yaml")]) == 1
    assert capsys.readouterr().err.count("\n") == 1
    target = tmp_path / "keep.md"
    target.write_text("precious")
    assert main(["derive", robot_path("planar2r"), "--out", str(tmp_path / "no" / "dir.md")]) == 1
    assert "does not exist" in capsys.readouterr().err
    assert main(["derive", robot_path("planar2r"), "--format", "pdf"]) == 2
    bad = tmp_path / "bad.yaml"
    bad.write_text("format: 1\nname: bad\nconvention: standard\nlinks: [{joint: revolute, a: 0, alpha: 0, d: 0, theta: __import__}]\n")
    assert main(["derive", str(bad), "--out", str(target)]) == 1
    assert target.read_text() == "precious"


DOCS = [("planar2r", "newton-euler", "planar2r_newton_euler.md"),
        ("planar2r", "lagrange-euler", "planar2r_lagrange_euler.md"),
        ("puma560", "newton-euler", "puma560_newton_euler.md"),
        ("planar2r", "jacobian-newton-euler", "planar2r_jacobian_newton_euler.md"),
        ("planar2r", "articulated-body", "planar2r_articulated_body.md"),
        ("pendulum_leg", "articulated-body", "pendulum_leg_articulated_body.md")]


@pytest.mark.parametrize("name,method,filename", DOCS)
def test_checked_in_derivations_are_up_to_date(tmp_path, name, method, filename):
    out = tmp_path / filename
    assert main(["derive", str(REPO / "robots" / f"{name}.yaml"), "--method", method,
                 "--format", "markdown", "--out", str(out)]) == 0
    assert out.read_bytes() == (REPO / "docs" / "derivations" / filename).read_bytes(), \
        "docs/derivations is stale: remake it with the commands in docs/derivations/README.md"


@pytest.mark.parametrize("name", ["cylindrical_held", "compass_biped"])
def test_checked_in_contact_derivation_is_up_to_date(tmp_path, name):
    """docs/derivations/cylindrical_held.md and compass_biped.md: the contact dynamics of an arm
    its contact pins, and of a planar biped in double support (a planar contact)."""
    out = tmp_path / f"{name}.md"
    assert main(["derive", str(REPO / "examples" / "contacts" / f"{name}.yaml"), "--steps", "summary",
                 "--format", "markdown", "--out", str(out)]) == 0
    assert out.read_bytes() == (REPO / "docs" / "derivations" / f"{name}.md").read_bytes(), \
        "docs/derivations is stale: remake it with the commands in docs/derivations/README.md"


def test_checked_in_platform_derivation_is_up_to_date(tmp_path):
    """docs/derivations/sru_platform.md: the seed's worked example (identical S-R-U legs,
    actuated joint 4) at its home pose with a twist and actuated accelerations."""
    out = tmp_path / "sru_platform.md"
    assert main(["derive", str(REPO / "robots" / "parallel" / "sru_platform.yaml"), "--format", "markdown",
                 "--twist", "0.1,-0.05,0.2,0.02,0.01,-0.03", "--qdd", "0.5,-0.2,0.1,0,0.3,-0.4",
                 "--out", str(out)]) == 0
    assert out.read_bytes() == (REPO / "docs" / "derivations" / "sru_platform.md").read_bytes(), \
        "docs/derivations is stale: remake it with the commands in docs/derivations/README.md"


def test_named_form_names_what_is_too_long_to_inline(tmp_path):
    """The Jacobian-projected printout of a 6-joint URDF with general placements (it ran out of
    8 GB inlining every intermediate): intermediates longer than the inline limit are shown as
    xi_k, each defined under 'Intermediate quantities' before the numbered results; the run
    takes seconds."""
    import time
    from symdyn.cli import main
    out = tmp_path / "jne.txt"
    start = time.process_time()  # CPU time: the work done, whatever the machine's load
    assert main(["derive", str(REPO / "tests" / "data" / "urdf" / "handmade.urdf"), "--method",
                 "jacobian-newton-euler", "--out", str(out), "--quiet"]) == 0
    assert time.process_time() - start < 60
    text = out.read_text()
    used = {line for line in text.splitlines() if "ξ₁" in line}
    defined = text.split("Intermediate quantities", 1)[1]
    assert used and "ξ₁ = " in defined and "ξ₂ = " in defined


def test_text_rows_fit_and_labels_sit_on_the_baseline(tmp_path):
    """The text printout of a 6-joint arm in the named form: no row over 120 characters (the
    shorthand in rows of 100, expressions wrapped at 100), and an intermediate quantity with an
    exponent keeps its label on the expression's baseline, the exponent's row indented above it
    (not the exponent on the label's row and the rest unindented below)."""
    from symdyn.cli import main
    out = tmp_path / "puma.txt"
    assert main(["derive", robot_path("puma560"), "--out", str(out), "--quiet"]) == 0
    rows = out.read_text(encoding="utf-8").splitlines()
    assert max(len(row) for row in rows) <= 120
    start = rows.index("Intermediate quantities")
    raised = [k for k in range(start + 2, len(rows)) if rows[k].strip() and rows[k].startswith(" ")]
    assert raised  # some intermediates are squares
    for k in raised[:20]:
        m = next(m for m in range(k + 1, len(rows)) if not rows[m].startswith(" "))  # the baseline's row
        assert " = " in rows[m] and rows[k][:len(rows[m].split(" = ")[0]) + 3].strip() == "", (rows[k], rows[m])


CYLINDRICAL = """format: 1
name: cylindrical
convention: general
gravity: [0, 0, -9.81]
links:
  - {name: waist, joint: revolute, origin: {xyz: [0, 0, 0.3]}, axis: [0, 0, 1], mass: 4, com: [0, 0, 0.1],
     inertia: {xx: 0.05, yy: 0.05, zz: 0.02}, armature: 0.01}
  - {name: lift, joint: prismatic, axis: [0, 0, 1], mass: 2, com: [0.05, 0, 0], inertia: {xx: 0.01, yy: 0.02, zz: 0.02}}
  - {name: reach, joint: prismatic, origin: {xyz: [0.1, 0, 0]}, axis: [1, 0, 0], mass: 1, com: [-0.2, 0.01, 0],
     inertia: {xx: 0.002, yy: 0.01, zz: 0.01}}
contacts: [KIND]
"""


@pytest.mark.parametrize("kind", ["reach:3d", "reach:6d"])
def test_contact_section_equals_the_contact_functions(tmp_path, kind):
    """A robot with contacts gets a last section, contact dynamics: J_c and gamma always (J_c
    equal to the frame's Jacobian rows at seeded states), and where the contacts pin the robot
    (a point held by three joints) the closed forms of qdd and lambda, equal to the generated
    contact functions (checked against Pinocchio elsewhere; D with the armature)."""
    from symdyn.derive.equations import derive
    path = tmp_path / "cylindrical.yaml"
    path.write_text(CYLINDRICAL.replace("KIND", kind))
    robot = symdyn.load(str(path))
    d = derive_steps(robot, "newton-euler", steps="summary")
    assert d.sections[-1].kind == "contact_dynamics"
    kinds = [q.kind for q in d.sections[-1].quantities]
    pinned = kind.endswith("3d")
    assert kinds == (["contact_J", "contact_gamma", "contact_det", "contact_qdd", "contact_lambda"] if pinned
                     else ["contact_J", "contact_gamma"])
    eqs = derive(robot, outputs=["contact_accelerations", "contact_forces", "frame_jacobians"])
    q, qd, tau = sp.symbols("q1:4"), sp.symbols("qd1:4"), sp.symbols("tau1:4")
    joint = lambda kind_: sp.lambdify([q, qd, tau], d.to_joint_symbols(d.quantity(kind_)).subs(  # noqa: E731
        dict(zip(eqs.q, q)) | dict(zip(eqs.qd, qd)) | dict(zip(eqs.tau, tau))), "numpy")
    J = joint("contact_J")
    rows = 3 if pinned else 6
    for state, speed, _, torque in random_states(3, 4, seed=5):
        state[2] = 0.3 + abs(state[2])  # the reach away from the axis: J_c regular
        frames = eqs.numeric.frame_jacobians(state)
        np.testing.assert_allclose(np.array(J(state, speed, torque), dtype=float), frames[:rows, :], rtol=1e-10, atol=1e-12)
        if pinned:
            np.testing.assert_allclose(np.array(joint("contact_qdd")(state, speed, torque), dtype=float).ravel(),
                                       eqs.numeric.contact_accelerations(state, speed, torque), rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(np.array(joint("contact_lambda")(state, speed, torque), dtype=float).ravel(),
                                       eqs.numeric.contact_forces(state, speed, torque), rtol=1e-9, atol=1e-9)
    text = render(d, "text")
    assert "Contact dynamics" in text and "J_c" in text


def test_compass_biped_closed_forms_equal_the_contact_functions():
    """The planar biped's printout (a planar contact, xz: two rows pinning two joints): J_c is
    the swing foot's x and z rows, det J_c = sin q2 (zero at the aligned legs), and the closed
    forms of qdd and lambda equal the generated contact functions at seeded states."""
    from symdyn.derive.equations import derive
    robot = symdyn.load(str(REPO / "examples" / "contacts" / "compass_biped.yaml"))
    d = derive_steps(robot, "newton-euler", steps="summary")
    assert [q.kind for q in d.sections[-1].quantities] == ["contact_J", "contact_gamma", "contact_det", "contact_qdd",
                                                           "contact_lambda"]
    eqs = derive(robot, outputs=["contact_accelerations", "contact_forces", "frame_jacobians"])
    q, qd, tau = sp.symbols("q1:3"), sp.symbols("qd1:3"), sp.symbols("tau1:3")
    joint = lambda kind_: sp.lambdify([q, qd, tau], d.to_joint_symbols(d.quantity(kind_)).subs(  # noqa: E731
        dict(zip(eqs.q, q)) | dict(zip(eqs.qd, qd)) | dict(zip(eqs.tau, tau))), "numpy")
    for state, speed, _, torque in random_states(2, 4, seed=5):
        state[1] = 0.3 + abs(state[1])  # the legs apart
        frames = eqs.numeric.frame_jacobians(state)
        np.testing.assert_allclose(np.array(joint("contact_J")(state, speed, torque), dtype=float), frames[[0, 2], :],
                                   rtol=1e-10, atol=1e-12)
        assert float(joint("contact_det")(state, speed, torque)) == pytest.approx(np.sin(state[1]), rel=1e-12)
        np.testing.assert_allclose(np.array(joint("contact_qdd")(state, speed, torque), dtype=float).ravel(),
                                   eqs.numeric.contact_accelerations(state, speed, torque), rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(np.array(joint("contact_lambda")(state, speed, torque), dtype=float).ravel(),
                                   eqs.numeric.contact_forces(state, speed, torque), rtol=1e-9, atol=1e-9)
