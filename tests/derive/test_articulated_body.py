"""Forward dynamics by the articulated-body algorithm (seed 004, Algorithm 1), derived
symbolically: against Pinocchio's aba and the LDL^T variant, through the CLI and the cache."""

from __future__ import annotations

import numpy as np
import pytest

import symdyn
from helpers import (REPO, ROBOTS, TOL, PinocchioReference, normalized_error, parameter_values,
                     random_states, robot_path)
from symdyn.check.pinocchio_model import compare
from symdyn.cli import main

GENERAL = str(REPO / "tests" / "data" / "general_arm.yaml")


@pytest.mark.parametrize("name", [pytest.param(name, marks=[pytest.mark.slow] if name == "chain12" else [])
                                  for name in ROBOTS + ["general_arm"]])  # chain12 with -m slow: 12 and 24 joints in test_scaling_paths
def test_aba_agrees_with_pinocchio_and_ldlt(name, derived):
    """qdd by ABA against Pinocchio's aba (friction and armature included) at 30 states, and
    against symdyn's LDL^T solve of the same robot."""
    robot = symdyn.load(GENERAL if name == "general_arm" else robot_path(name))
    aba = symdyn.derive(robot, outputs=["forward_dynamics"], fd_method="aba")
    assert aba.fd_method == "aba" and len(aba.pivots) == robot.dof
    values = parameter_values(robot)
    p = [values[s] for s in robot.parameters] or None
    states = random_states(robot.dof, 30, seed=31)
    errors = compare(aba.numeric, PinocchioReference(robot, values), states, ["forward_dynamics"], p)
    assert errors["forward_dynamics"] <= TOL, errors
    ldlt = derived(name) if name != "general_arm" else symdyn.derive(robot, outputs=["forward_dynamics"])
    assert ldlt.fd_method == "ldlt"
    mine = [aba.numeric.forward_dynamics(q, qd, tau, p) for q, qd, _, tau in states]
    theirs = [ldlt.numeric.forward_dynamics(q, qd, tau, p) for q, qd, _, tau in states]
    difference = normalized_error(mine, theirs)
    assert difference <= 1e-10, difference


def test_cli_generates_and_verifies_aba(tmp_path, capsys):
    """--fd-method aba: the header says how forward dynamics is solved and keeps the checked
    function, the compiled C agrees with Pinocchio, and the cache keeps the two methods apart
    (the second generation would otherwise reuse the first's entry)."""
    scara = robot_path("scara")
    assert main(["generate", scara, "--out", str(tmp_path / "aba"), "--fd-method", "aba", "--quiet",
                 "--functions", "forward_dynamics"]) == 0
    assert main(["generate", scara, "--out", str(tmp_path / "ldlt"), "--quiet", "--functions", "forward_dynamics"]) == 0
    aba_header = (tmp_path / "aba" / "scara_dynamics.h").read_text()
    assert "articulated-body algorithm" in aba_header and "int scara_forward_dynamics_checked(" in aba_header
    assert "LDL^T" in (tmp_path / "ldlt" / "scara_dynamics.h").read_text()
    assert (tmp_path / "aba" / "scara_dynamics.c").read_bytes() != (tmp_path / "ldlt" / "scara_dynamics.c").read_bytes()
    assert main(["verify", scara, "--fd-method", "aba", "--functions", "forward_dynamics", "--states", "20"]) == 0
    assert "forward_dynamics" in capsys.readouterr().out


def test_unknown_fd_method_is_refused():
    with pytest.raises(ValueError, match="forward-dynamics method"):
        symdyn.derive(symdyn.load(robot_path("planar2r")), fd_method="cholesky")


@pytest.mark.parametrize("name", ["scara", "pendulum_leg"])
def test_printed_derivation_evaluates_to_pinocchio(name):
    """`derive --method articulated-body`: the printed quantities, evaluated from their printed
    definitions (q-double-dot from the third sweep; with passive joints k_0 and the columns of D
    of the reaction map), equal Pinocchio's aba and transmitted wrench."""
    import sympy as sp
    from symdyn.derive.derivation import derive_steps
    from symdyn.derive.numeric import compile_function
    from symdyn.emit.printout import render
    robot = symdyn.load(robot_path(name))
    d = derive_steps(robot, "aba")
    kinds = {s.kind for s in d.sections}
    assert {"aba_model", "aba_forward", "aba_backward", "aba_accel"} <= kinds
    assert ({"rm_gains", "rm_bias", "rm_wrench", "rm_columns", "rm_results"} <= kinds) == bool(robot.passive_joints)
    n = robot.dof
    eqs = symdyn.derive(robot, outputs=["gravity"])
    program = d.program()
    inputs = [eqs.q, eqs.qd, eqs.tau]
    qdd = compile_function(inputs, program, sp.Matrix([d.quantity("qdd", i + 1) for i in range(n)]))
    ref = PinocchioReference(robot)
    reaction = None
    if robot.passive_joints:
        results = {q.kind: q.value for q in d.section("rm_results").quantities}
        reaction = compile_function(inputs, program, sp.Matrix.hstack(sp.Matrix(results["k0"]), sp.Matrix(results["Dmap"])))
    for q, qd, _, tau in random_states(n, 5, seed=33):
        np.testing.assert_allclose(qdd(q, qd, tau).ravel(), ref.forward_dynamics(q, qd, tau), rtol=1e-9, atol=1e-9)
        if reaction is not None:
            np.testing.assert_allclose(reaction(q, qd, tau), ref.reaction_map(q, qd), rtol=1e-9, atol=1e-8)
    for fmt in ("text", "latex", "markdown"):
        text = render(d, fmt)
        assert "articulated-body algorithm" in text
        assert ("Mapping (eqs. 13-14)" in text) == bool(robot.passive_joints)
