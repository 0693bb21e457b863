"""Platform robots: the generated C and CasADi functions (symdyn.derive.parallel,
symdyn.emit.parallel_c, symdyn.emit.parallel_casadi) against Pinocchio's closed-loop model.

Each bundled platform is generated once by the CLI (the files are also checked against
generated/parallel/) and compiled once (strict warnings as errors).  Pinocchio's side
(tests/closed_loop.py) takes the legs' joint values from the numeric reference's Newton
inverse kinematics, not from the generated closed form.
"""

from __future__ import annotations

import dataclasses
import shutil
import subprocess

import numpy as np
import pytest

from closed_loop import (PLATFORMS, free_flyer_twist_rate, pinocchio_forward_dynamics, pinocchio_inverse_dynamics,
                         pinocchio_state, states)
from helpers import REPO, run_sanitized
from symdyn.cli import main
from symdyn.model import parallel

pin = pytest.importorskip("pinocchio")
CC = shutil.which("gcc") or shutil.which("cc")
pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler")
GENERATED = REPO / "generated" / "parallel"
STATES = 50


@pytest.fixture(scope="module")
def regenerated(tmp_path_factory):
    out = tmp_path_factory.mktemp("platforms")
    paths = [str(REPO / "robots" / "parallel" / f"{name}.yaml") for name in sorted(PLATFORMS)]
    assert main(["generate", *paths, "--out", str(out), "--quiet"]) == 0
    return out


@pytest.fixture(scope="module", params=[pytest.param(name, marks=pytest.mark.slow) if name == "sru_platform" else name
                                        for name in sorted(PLATFORMS)])
def platform(request, regenerated):
    from symdyn.check.cbuild import build_platform
    from symdyn.check.parallel_reference import ParallelReference
    from symdyn.check.pinocchio_model import build_closed_loop_model
    from symdyn.derive.parallel import derive_parallel
    from symdyn.emit.parallel_casadi import parallel_casadi_functions
    name = request.param
    robot = parallel.load(REPO / "robots" / "parallel" / f"{name}.yaml")
    files = {f.name: f.read_text() for f in regenerated.glob(f"{name}_dynamics.*")}
    lib = build_platform(files, name)
    model, constraints, info = build_closed_loop_model(robot)
    models, datas = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    for cm in constraints:
        models.append(cm)
        datas.append(cm.createData())
    # the CasADi functions (a derivation of their own: 10-20 s) are made on first use, by the
    # worker that runs a test that needs them
    casadi = _Lazy(lambda: parallel_casadi_functions(derive_parallel(robot)))
    return dict(robot=robot, lib=lib, casadi=casadi, ref=ParallelReference(robot), model=model,
                data=model.createData(), models=models, datas=datas, info=info)


class _Lazy:
    """A mapping made by ``make()`` when an item is first asked for."""

    def __init__(self, make):
        self.make, self.value = make, None

    def __getitem__(self, key):
        if self.value is None:
            self.value = self.make()
        return self.value[key]


def _pose(p, R):
    return np.concatenate([p, pin.Quaternion(R).coeffs()])


def test_generated_files_are_current(regenerated):
    """generated/parallel/ is what the CLI writes now (regenerate with the command in docs)."""
    for name in PLATFORMS:
        for ext in ("h", "c"):
            fresh = (regenerated / f"{name}_dynamics.{ext}").read_bytes()
            assert fresh == (GENERATED / f"{name}_dynamics.{ext}").read_bytes(), \
                f"generated/parallel/{name}_dynamics.{ext} is stale: run the command in docs/parallel-format.md"


def test_inverse_dynamics_against_pinocchio(platform):
    """phi of the generated C at 50 random states equals the actuator forces of Pinocchio's
    closed-loop model (rnea of the tree and the constraint Jacobian), <= 1e-8 of the largest."""
    P = platform
    for p, R, twist, rate in states(P["robot"].name, STATES, seed=11):
        status, phi = P["lib"].inverse_dynamics(_pose(p, R), twist, rate)
        assert status == 0
        legs = P["ref"].leg_states(p, R, twist, rate)
        q, v, a = pinocchio_state(P["model"], P["info"], P["ref"], p, R, twist, rate, legs)
        theirs = pinocchio_inverse_dynamics(P["model"], P["data"], P["models"], P["datas"], P["info"], q, v, a)
        assert np.abs(phi - theirs).max() <= 1e-8 * np.abs(theirs).max(), (phi, theirs)


def test_forward_dynamics_against_pinocchio(platform):
    """The twist rate and actuated accelerations of the generated C under forces phi at 50
    random states equal Pinocchio's constrained forward dynamics, <= 1e-8 (normalized by 1 +
    the largest)."""
    P = platform
    ref, robot = P["ref"], P["robot"]
    for p, R, twist, rate in states(robot.name, STATES, seed=12):
        phi = ref.inverse_dynamics(p, R, twist, rate) * 1.1  # not the forces of that motion
        status, ours, qdd = P["lib"].forward_dynamics(_pose(p, R), twist, phi)
        assert status == 0
        legs = ref.leg_states(p, R, twist)
        q, v, _ = pinocchio_state(P["model"], P["info"], ref, p, R, twist, None,
                                  [dataclasses.replace(leg, theta_ddot=None) for leg in legs])
        a = pinocchio_forward_dynamics(P["model"], P["data"], P["models"], P["info"], q, v, phi)
        theirs = free_flyer_twist_rate(R, ref.com, twist, a)
        assert np.abs(ours - theirs).max() <= 1e-8 * (1.0 + np.abs(theirs).max()), (ours, theirs)
        actuated = np.array([a[leg["actuated_v"]] for leg in P["info"]["legs"]])
        assert np.abs(qdd - actuated).max() <= 1e-8 * (1.0 + np.abs(actuated).max()), (qdd, actuated)


def test_matrices_and_kinematics(platform):
    """M, T, L_J and the inverse kinematics of the generated C against the numeric reference
    (Newton inverse kinematics, numpy solves), and M symmetric positive definite; the CasADi
    functions equal the C ones."""
    P = platform
    ref, lib = P["ref"], P["lib"]
    for p, R, twist, rate in states(P["robot"].name, 8, seed=13):
        pose = _pose(p, R)
        expected = ref.seed_matrices(p, R)
        status, M = lib.mass_matrix(pose)
        assert status == 0
        assert np.abs(M - expected["M"]).max() <= 1e-10 * np.abs(expected["M"]).max()
        assert np.array_equal(M, M.T) and np.linalg.eigvalsh(M).min() > 0
        status, T = lib.twist_map(pose)
        assert status == 0 and np.abs(T - expected["T"]).max() <= 1e-10 * np.abs(expected["T"]).max()
        status, L = lib.leg_rate_maps(pose)
        assert status == 0
        for k in range(6):
            assert np.abs(L[6 * k:6 * k + 6] - expected["L"][k]).max() <= 1e-10 * (1 + np.abs(expected["L"][k]).max())
        status, q, qd = lib.inverse_kinematics(pose, twist)
        legs = ref.leg_states(p, R, twist)
        assert status == 0
        assert np.allclose(q, [leg.theta[k] for leg, k in zip(legs, ref.actuated)], rtol=0, atol=1e-12)
        assert np.allclose(qd, [leg.theta_dot[k] for leg, k in zip(legs, ref.actuated)], rtol=0, atol=1e-12)
        for name, args in (("inverse_dynamics", (pose, twist, rate)), ("forward_dynamics", (pose, twist, rate)),
                           ("mass_matrix", (pose,)), ("leg_rate_maps", (pose,)), ("inverse_kinematics", (pose, twist))):
            ours = getattr(lib, name)(*args)[1:]
            theirs = P["casadi"][name](*args)
            theirs = theirs if isinstance(theirs, (list, tuple)) else [theirs]
            for a, b in zip(ours, theirs):
                b = np.array(b).reshape(np.shape(a))
                assert np.abs(a - b).max() <= 1e-11 * (1 + np.abs(b).max()), name


def test_power_balance_of_the_generated_forward_dynamics(platform):
    """Simulated with the generated C (RK4 from rest at the home pose, actuator forces varying
    about those that hold it): the work of phi equals the change of the mechanism's kinetic plus
    potential energy (Pinocchio's, from every body) to the integration's accuracy."""
    from closed_loop import energy_balance
    P = platform

    def forward(p, R, twist, phi):
        status, rate, _ = P["lib"].forward_dynamics(_pose(p, R), twist, phi)
        assert status == 0
        return rate
    change, work = energy_balance(P["robot"], P["ref"], P["model"], P["info"], forward, steps=60)
    assert abs(change - work) <= 1e-6 * max(abs(work), abs(change)), (change, work)


def _leg_along_axis(robot, leg_index, axis, length):
    """A level platform pose that puts leg ``leg_index``'s universal-joint centre at ``length``
    along axis ``axis`` of the leg's base frame from its spherical centre."""
    from symdyn.derive.parallel_ik import LegIK
    leg = robot.legs[leg_index]
    ik = LegIK.of(leg.chain)
    base = np.array(leg.chain.base_matrix(), dtype=float)
    centre = base[:3, :3] @ np.array(ik.centre_s, dtype=float) + base[:3, 3]
    attach = np.array(leg.attachment.matrix(), dtype=float)
    u_in_platform = attach[:3, :3] @ np.array(ik.u_in_6, dtype=float) + attach[:3, 3]
    return np.concatenate([centre + length * base[:3, axis] - u_in_platform, [0.0, 0.0, 0.0, 1.0]])


def _statuses(lib, pose):
    zeros = np.zeros(6)
    calls = {"inverse_dynamics": (pose, zeros, zeros), "forward_dynamics": (pose, zeros, zeros),
             "mass_matrix": (pose,), "twist_map": (pose,), "leg_rate_maps": (pose,),
             "inverse_kinematics": (pose, zeros)}
    out = {}
    for name, args in calls.items():
        status, *outputs = getattr(lib, name)(*args)
        out[name] = status
        if status:  # nothing written: the zeros the caller passed in
            assert all(np.all(o == 0) for o in outputs), name
        else:
            assert all(np.all(np.isfinite(o)) for o in outputs), name
    return out


def test_singular_and_unreachable_poses_return_a_status(platform):
    """A zero quaternion and a pose out of reach give UNREACHABLE (1); the flight simulator
    turned 90 degrees about the vertical (a parallel singularity: K singular) gives SINGULAR (3)
    from every function that solves with K (forward dynamics solves with the platform's
    generalized inertia and K^T phi, defined there; inverse kinematics needs the legs only); a leg whose spherical pair is
    in gimbal lock gives LEG_SINGULAR (2), a pose 1e-6 m away none (1e-9 m away, forward dynamics
    reports the platform's generalized inertia singular: the leg's rates grow as 1e9 there); no
    function writes NaN."""
    P = platform
    robot, lib = P["robot"], P["lib"]
    height = PLATFORMS[robot.name][0]
    assert set(_statuses(lib, np.array([0.0, 0.0, height, 0.0, 0.0, 0.0, 0.0])).values()) == {1}
    assert set(_statuses(lib, np.array([0.0, 0.0, 50.0 * height, 0.0, 0.0, 0.0, 1.0])).values()) == (
        {0} if robot.name == "flight_simulator" else {1})  # prismatic legs reach any height
    if robot.name != "flight_simulator":
        return
    turned = np.array([0.0, 0.0, height, 0.0, 0.0, np.sin(np.pi / 4), np.cos(np.pi / 4)])
    assert _statuses(lib, turned) == {"inverse_dynamics": 3, "forward_dynamics": 0, "mass_matrix": 3,
                                      "twist_map": 3, "leg_rate_maps": 3, "inverse_kinematics": 0}
    gimbal = _leg_along_axis(robot, 0, 1, 3.0)
    assert set(_statuses(lib, gimbal).values()) == {2}
    near = gimbal + np.array([1e-6, 1e-6, 0, 0, 0, 0, 0])
    assert set(_statuses(lib, near).values()) == {0}


def test_overflow_returns_a_status_and_tiny_quaternions_are_normalized(platform):
    """Finite inputs never give NaN with status 0: a twist of 1e155 (its products overflow
    double) returns NOT_FINITE (4) from the dynamics, writing nothing; a
    quaternion scaled by 1e-300, a subnormal 4e-320 or 1e300 is the same orientation (normalized
    without underflow or overflow: divided by its scale, whose reciprocal would overflow), not
    'zero'."""
    P = platform
    robot, lib = P["robot"], P["lib"]
    pose = _pose(np.array([0.0, 0.0, PLATFORMS[robot.name][0]]), np.eye(3))
    huge = np.full(6, 1e155)
    for name, args in (("inverse_dynamics", (pose, huge, np.zeros(6))), ("forward_dynamics", (pose, huge, np.zeros(6)))):
        status, *outputs = getattr(lib, name)(*args)  # quadratic in the twist: 1e310
        assert status == 4 and all(np.all(o == 0) for o in outputs), (name, status)
    status, q, qd = lib.inverse_kinematics(pose, huge)  # linear in the twist: finite, written
    assert status == 0 and np.all(np.isfinite(qd)) and np.abs(qd).max() > 1e150
    for scale in (1e-300, 4e-320, 1e300):
        scaled = np.concatenate([pose[:3], pose[3:] * scale])
        assert _statuses(lib, scaled) == _statuses(lib, pose)
        status, M = lib.mass_matrix(scaled)
        assert status == 0 and np.allclose(M, lib.mass_matrix(pose)[1], rtol=1e-14, atol=0)


def test_float_code(platform, tmp_path):
    """--precision float: compiles warning-free, agrees with double to float accuracy (inverse
    dynamics and kinematics), and on a Cortex-M4 (when arm-none-eabi-gcc is installed)
    references no double-precision routine."""
    from helpers import ARM_GCC, ARM_NM, CORTEX_M4, has_newlib as _has_newlib

    from symdyn.check.cbuild import build_platform
    robot = platform["robot"]
    path = REPO / "robots" / "parallel" / f"{robot.name}.yaml"
    # two functions that take every kind of step: blocks, checks, the LU, square roots, atan2 (the
    # others are made of the same; one file of all six takes 3 times as long to compile)
    assert main(["generate", str(path), "--out", str(tmp_path), "--precision", "float", "--quiet", "--functions",
                 "inverse_dynamics,inverse_kinematics"]) == 0
    files = {f.name: f.read_text() for f in tmp_path.glob(f"{robot.name}_dynamics.*")}
    lib = build_platform(files, robot.name, "float", workdir=str(tmp_path))
    for p, R, twist, rate in states(robot.name, 5, seed=14):
        pose = _pose(p, R)
        status, phi = lib.inverse_dynamics(pose, twist, rate)
        _, expected = platform["lib"].inverse_dynamics(pose, twist, rate)
        assert status == 0 and np.abs(phi - expected).max() <= 1e-4 * np.abs(expected).max()
        status, q, qd = lib.inverse_kinematics(pose, twist)
        _, q_double, qd_double = platform["lib"].inverse_kinematics(pose, twist)
        assert status == 0 and np.abs(q - q_double).max() <= 1e-5 and np.abs(qd - qd_double).max() <= 1e-5
    if ARM_NM is None or not _has_newlib():
        pytest.skip("arm-none-eabi-gcc with newlib not installed")
    obj = tmp_path / "platform.o"
    subprocess.run([ARM_GCC, *CORTEX_M4, "-c", str(tmp_path / f"{robot.name}_dynamics.c"), "-o", str(obj)],
                   check=True, cwd=tmp_path)
    undefined = subprocess.run([ARM_NM, "-u", str(obj)], capture_output=True, text=True, check=True).stdout.split()
    names = {entry for entry in undefined if entry != "U"}
    assert not {n for n in names if n.startswith("__aeabi_d")}, names
    assert not names & {"sqrt", "fabs", "atan2"}, names


def test_cli_casadi_target_and_refusals(tmp_path, capsys):
    """--target casadi writes one loadable Function per function; serial-only options and
    unknown functions are refused in one line, by generate and by verify (which checks platforms:
    tests/cli/test_platform_verify_bench.py)."""
    import casadi as ca
    path = str(REPO / "robots" / "parallel" / "sru_platform.yaml")
    assert main(["generate", path, "--out", str(tmp_path), "--target", "casadi", "--functions",
                 "mass_matrix", "--quiet"]) == 0
    assert sorted(f.name for f in tmp_path.iterdir()) == ["sru_platform_casadi.txt", "sru_platform_mass_matrix.casadi"]
    M = np.array(ca.Function.load(str(tmp_path / "sru_platform_mass_matrix.casadi"))([0, 0, 0.55, 0, 0, 0, 1]))
    assert np.array_equal(M, M.T) and np.linalg.eigvalsh(M).min() > 0
    # a subset of the C functions: only the helpers they call (no unused static function)
    assert main(["generate", path, "--out", str(tmp_path / "c"), "--functions", "inverse_kinematics", "--quiet"]) == 0
    subprocess.run([CC, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O0", "-c",
                    str(tmp_path / "c" / "sru_platform_dynamics.c"), "-o", str(tmp_path / "c" / "x.o")], check=True)
    for extra in (["--batch"], ["--header-only"], ["--functions", "coriolis"], ["--target", "casadi-c"]):
        capsys.readouterr()
        assert main(["generate", path, "--out", str(tmp_path / "x"), *extra]) != 0
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0 and "error" in err, err
    assert not (tmp_path / "x").exists()
    assert main(["verify", path, "--method", "lagrange-euler"]) != 0
    assert "kind: parallel" in capsys.readouterr().err


def test_derivation_in_seed_order(platform, tmp_path, capsys):
    """symdyn derive of a platform: the seed's steps in order, in the three formats (LaTeX
    compiles where pdflatex is installed); the printed quantities agree with the generated
    functions at the same state: M, T, L_J, Lambda = 1, and phi drives the forward dynamics to
    the q_ddot it was computed for."""
    from symdyn.derive.parallel_steps import parallel_steps
    robot = platform["robot"]
    path = str(REPO / "robots" / "parallel" / f"{robot.name}.yaml")
    height = PLATFORMS[robot.name][0]
    pose = np.array([0.01, -0.02, height + 0.01, 0.02, -0.01, 0.03, 1.0])
    pose[3:] /= np.linalg.norm(pose[3:])
    twist, qdd = np.array([0.1, -0.2, 0.05, 0.2, 0.1, -0.1]), np.array([0.5, -0.3, 0.2, 0.0, 0.1, -0.4])
    derivation = parallel_steps(robot, pose, twist, qdd)
    titles = [step.title for step in derivation.steps]
    assert titles == ["Leg Jacobians", "A_J", "Scalar twist-shape relations", "Y", "Z", "T", "L_J", "M", "N",
                      "Lambda", "phi"]
    value = {label: v for step in derivation.steps for label, v in step.values}
    lib = platform["lib"]
    _, M = lib.mass_matrix(pose)
    _, T = lib.twist_map(pose)
    _, L = lib.leg_rate_maps(pose)
    assert np.abs(value["M(q)"] - M).max() <= 1e-10 * np.abs(M).max()
    assert np.abs(value["T"] - T).max() <= 1e-10 * np.abs(T).max()
    for k, roman in enumerate(("I", "II", "III", "IV", "V", "VI")):
        assert np.abs(value[f"L_{roman}"] - L[6 * k:6 * k + 6]).max() <= 1e-10 * (1 + np.abs(L).max())
        assert np.abs(value[f"A_{roman} J_{roman}"][:, :3]).max() <= 1e-12 * np.abs(value[f"J_{roman}"]).max()
    assert np.allclose(value["Lambda"], np.eye(6), rtol=0, atol=1e-12)
    status, _, accelerations = lib.forward_dynamics(pose, twist, value["phi"])
    assert status == 0 and np.abs(accelerations - qdd).max() <= 1e-9 * (1 + np.abs(qdd).max())
    for fmt in ("text", "markdown", "latex"):
        out = tmp_path / f"derivation.{fmt}"
        assert main(["derive", path, "--format", fmt, "--out", str(out), "--pose", ",".join(str(float(x)) for x in pose),
                     "--twist", ",".join(str(float(x)) for x in twist), "--qdd", ",".join(str(float(x)) for x in qdd)]) == 0
        text = out.read_text()
        heading = {"text": "{n}. {t}\n", "markdown": "## {n}. {t}\n", "latex": "\\subsection*{{{n}. {t}}}"}[fmt]
        positions = [text.find(heading.format(n=n, t=t.replace("_", "\\_") if fmt == "latex" else t))
                     for n, t in enumerate(titles, 1)]
        assert all(p >= 0 for p in positions) and positions == sorted(positions), (fmt, positions)
    if shutil.which("pdflatex"):
        result = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "derivation.latex"],
                                cwd=tmp_path, capture_output=True, text=True)
        assert result.returncode == 0, result.stdout[-2000:]
    assert main(["derive", path, "--pose", "1,2,3"]) != 0
    assert "--pose takes 7" in capsys.readouterr().err


def test_casadi_derivatives(platform):
    """The CasADi functions differentiate through their solves: d phi / d t_dot times T is the
    mass matrix M (phi = M q_ddot + ... with t_dot = T q_ddot + ...), and forward dynamics'
    d t_dot / d phi is the inverse of inverse dynamics' d phi / d t_dot."""
    import casadi as ca
    P = platform
    p, R, twist, rate = next(states(P["robot"].name, 1, seed=15))
    pose = _pose(p, R)
    x = ca.SX.sym("x", 6)
    inverse = ca.Function("d_inverse", [x], [ca.jacobian(P["casadi"]["inverse_dynamics"](pose, twist, x), x)])
    forward = ca.Function("d_forward", [x], [ca.jacobian(P["casadi"]["forward_dynamics"](pose, twist, x)[0], x)])
    d_phi = np.array(inverse(rate))
    _, T = P["lib"].twist_map(pose)
    _, M = P["lib"].mass_matrix(pose)
    assert np.abs(d_phi @ T - M).max() <= 1e-9 * np.abs(M).max()
    _, phi = P["lib"].inverse_dynamics(pose, twist, rate)
    assert np.abs(d_phi @ np.array(forward(phi)) - np.eye(6)).max() <= 1e-9


def test_sanitizers_and_no_division_by_zero(platform, tmp_path):
    """Every function under AddressSanitizer and UndefinedBehaviorSanitizer, with
    float-divide-by-zero trapping, at regular states, singular and unreachable poses and
    non-finite inputs: each check comes before the division it guards."""
    robot = platform["robot"]
    name = robot.name
    height = PLATFORMS[name][0]
    poses = [list(_pose(p, R)) for p, R, _, _ in states(name, 3, seed=16)]
    poses += [[0, 0, height, 0, 0, 0, 0], [0, 0, 50 * height, 0, 0, 0, 1],
              [0, 0, height, 0, 0, np.sin(np.pi / 4), np.cos(np.pi / 4)],
              list(_leg_along_axis(robot, 0, 1, 3.0)), [float("nan")] * 7, [float("inf")] * 7, [1e300] * 7,
              [0, 0, 0, 0, 0, 0, 1]]
    rows = ",\n".join("{" + ", ".join(repr(float(x)) if np.isfinite(x) else ("NAN" if np.isnan(x) else "INFINITY")
                                      for x in pose) + "}" for pose in poses)
    program = f"""#include <math.h>
#include <stdio.h>
#include "{name}_dynamics.h"
int main(void) {{
    static const {name}_real poses[][7] = {{{rows}}};
    const {name}_real twist[6] = {{0.1, -0.2, 0.3, 0.05, -0.1, 0.2}}, rate[6] = {{0.5, 0.1, -0.3, 1.0, -0.5, 0.2}};
    {name}_real a[216], b[6];
    int statuses = 0;
    for (unsigned k = 0; k < sizeof poses / sizeof poses[0]; ++k) {{
        statuses += {name}_inverse_dynamics(poses[k], twist, rate, a);
        statuses += {name}_forward_dynamics(poses[k], twist, rate, a, b);
        statuses += {name}_mass_matrix(poses[k], a);
        statuses += {name}_twist_map(poses[k], a);
        statuses += {name}_leg_rate_maps(poses[k], a);
        statuses += {name}_inverse_kinematics(poses[k], twist, a, b);
    }}
    printf("%d\\n", statuses);
    return 0;
}}
"""
    files = {f"{name}_dynamics.{suffix}": (GENERATED / f"{name}_dynamics.{suffix}").read_bytes() for suffix in ("c", "h")}
    stdout = run_sanitized(tmp_path, program, files)
    assert int(stdout) > 0  # the bad poses did return statuses


def test_files_and_poses_refused_in_one_line(tmp_path, capsys):
    """A misspelt kind, a platform file without one, a leg at a singular configuration at its
    home pose, and derive at a parallel singularity: one line each, nothing written."""
    import yaml
    source = REPO / "robots" / "parallel" / "sru_platform.yaml"
    doc = yaml.safe_load(source.read_text())
    cases = []
    misspelt = dict(doc, kind="paralel")
    cases.append((misspelt, "unknown kind 'paralel'"))
    cases.append(({k: v for k, v in doc.items() if k != "kind"}, "add 'kind: parallel'"))
    text = source.read_text().replace("name: knee, joint: revolute", "name: knee, joint: prismatic")
    assert text != source.read_text()
    cases.append((yaml.safe_load(text), "singular configuration at its home pose"))
    for k, (case, message) in enumerate(cases):
        path = tmp_path / f"case{k}.yaml"
        path.write_text(yaml.safe_dump(case))
        assert main(["generate", str(path), "--out", str(tmp_path / "out")]) != 0
        err = capsys.readouterr().err.strip()
        assert message in err and len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert not (tmp_path / "out").exists()
    turned = f"0,0,2,0,0,{float(np.sin(np.pi / 4))!r},{float(np.cos(np.pi / 4))!r}"
    assert main(["derive", str(REPO / "robots" / "parallel" / "flight_simulator.yaml"), "--pose", turned]) != 0
    err = capsys.readouterr().err.strip()
    assert "parallel singularity" in err and len(err.splitlines()) == 1, err
