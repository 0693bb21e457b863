"""The O(n) and O(n^2) paths that make long chains scale, against Pinocchio: the articulated-body
forward dynamics and the Coriolis-matrix recursion, on every bundled robot and on generic chains
(full inertia tensors, general DH twists) of 12, 24 and 48 joints."""

from __future__ import annotations

import sys

import numpy as np
import pytest
import sympy as sp

import symdyn
from symdyn.derive.chain import make_chain
from symdyn.derive.coriolis import coriolis_matrix
from symdyn.derive.numeric import compile_function

from helpers import (REPO, ROBOTS, TOL, PinocchioReference, normalized_error, parameter_values, random_states,
                     robot_path)

sys.path.insert(0, str(REPO / "benchmarks"))
from long_chains import generic_chain  # noqa: E402


@pytest.fixture(scope="module")
def generic(tmp_path_factory):
    """n -> the generic n-joint chain (a Robot), written once per module."""
    folder = tmp_path_factory.mktemp("generic")
    robots = {}

    def get(n: int):
        if n not in robots:
            path = folder / f"generic{n}.yaml"
            path.write_text(generic_chain(n))
            robots[n] = symdyn.load(str(path))
        return robots[n]
    return get


def _recursion_error(robot, states: int) -> float:
    chain = make_chain(robot)
    C, factors = coriolis_matrix(chain)
    values = parameter_values(robot)
    evaluate = compile_function([chain.q, chain.qd, robot.parameters], chain.builder.build(), C, "C")
    p = [values[s] for s in robot.parameters]
    ref = PinocchioReference(robot, values)
    pairs = [(q, qd) for q, qd, _, _ in random_states(robot.dof, states, seed=11)]
    mine = [evaluate(q, qd, p) for q, qd in pairs]
    # the factors are what the matrix is made of: C qd = h, with h from Pinocchio too
    for (q, qd), value in zip(pairs[:2], mine):
        assert normalized_error([value @ qd], [ref.coriolis(q, qd)]) < TOL
    return normalized_error(mine, [ref.coriolis_matrix(q, qd) for q, qd in pairs])


@pytest.mark.parametrize("name", ROBOTS + ["general_arm", "passive_middle", "three_modified"])
def test_coriolis_recursion_agrees_with_pinocchio(name):
    assert _recursion_error(symdyn.load(robot_path(name)), 8) < TOL


@pytest.mark.parametrize("n", [12, 24, pytest.param(48, marks=pytest.mark.slow)])
def test_coriolis_recursion_on_generic_chains(n, generic):
    assert _recursion_error(generic(n), 4) < TOL


@pytest.mark.parametrize("n", [12, 24, pytest.param(48, marks=pytest.mark.slow)])
def test_articulated_body_on_generic_chains(n, generic):
    robot = generic(n)
    eqs = symdyn.derive(robot, outputs=["forward_dynamics"], fd_method="aba")
    evaluate = compile_function([eqs.q, eqs.qd, eqs.tau], eqs.program, eqs.output("forward_dynamics"), "fd")
    ref = PinocchioReference(robot)
    states = random_states(n, 4, seed=5)
    mine = [evaluate(q, qd, tau).ravel() for q, qd, _, tau in states]
    theirs = [ref.forward_dynamics(q, qd, tau) for q, qd, _, tau in states]
    assert normalized_error(mine, theirs) < TOL


def test_coriolis_choice_is_by_operation_count():
    """Below the threshold both ways are built and the cheaper kept: the sparse SCARA keeps the
    derivative of h, a general arm takes the recursion; the choice is reproducible."""
    from symdyn.derive import equations
    counts = {}  # name -> whether the recursion was kept
    for name in ("scara", "general_arm"):
        robot = symdyn.load(robot_path(name))
        eqs = symdyn.derive(robot, outputs=["coriolis_matrix"])
        counts[name] = bool(eqs.coriolis_factors)
        again = symdyn.derive(robot, outputs=["coriolis_matrix"])
        assert again.program == eqs.program and again.outputs == eqs.outputs
    assert counts == {"scara": False, "general_arm": True}
    assert robot.dof < equations.CORIOLIS_RECURSION_FROM_DOF
