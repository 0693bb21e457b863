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


@pytest.mark.parametrize("name", ROBOTS + ["general_arm"])
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
