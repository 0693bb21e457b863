"""The articulated-body algorithm as loops over a table of the joints
(:mod:`symdyn.derive.articulated_loops`): its three steps, run numerically joint by joint, agree
with Pinocchio's ``aba``; which chains get the loop form."""

from __future__ import annotations

import re
import sys

import numpy as np
import pytest
import sympy as sp

import symdyn
from symdyn.derive import articulated_loops as al
from symdyn.derive.numeric import compile_function

from helpers import REPO, TOL, PinocchioReference, normalized_error, random_states, robot_path

sys.path.insert(0, str(REPO / "benchmarks"))
from long_chains import generic_chain  # noqa: E402


def with_friction(text: str) -> str:
    """A generic chain's robot file with armature, damping and Coulomb friction on every other
    link and an angle offset on every third (the loop form's general pivot and friction)."""
    lines = text.splitlines()
    out = []
    links = 0
    for line in lines:
        if line.startswith("  - {joint: revolute"):
            if links % 2 == 0:
                line = line[:-1] + ", armature: 0.05, damping: 0.4, coulomb: 0.2}"
            if links % 3 == 0:
                line = line.replace("theta: 0,", "theta: 0.3,")
            links += 1
        out.append(line)
    return "\n".join(out) + "\n"


def structured_chain(n: int) -> str:
    """An arm-like chain: twists alternating +-90 degrees, no link lengths, principal inertias."""
    lines = ["format: 1", f"name: structured{n}", "convention: standard", "gravity: [0, 0, -9.81]", "links:"]
    for j in range(n):
        alpha = "pi/2" if j % 2 == 0 else "-pi/2"
        lines.append(f"  - {{joint: revolute, a: 0, alpha: {alpha}, d: {0.1 + 0.01 * j:.2f}, theta: 0, "
                     f"mass: {1.0 + 0.1 * j:.1f}, com: [0, 0, {0.02 * j:.2f}], inertia: [0.01, 0.012, 0.008, 0, 0, 0]}}")
    return "\n".join(lines) + "\n"


def run_loops(eqs, q, qd, tau) -> np.ndarray:
    """qdd by the three steps of ``eqs.articulated_loops``, evaluated numerically joint by joint
    exactly as the emitted loops run them (table rows, carried K and k, stored v, z, b, ud)."""
    loops = eqs.articulated_loops
    n = loops.n
    main = compile_function([eqs.q, eqs.qd, eqs.tau], eqs.program,
                            sp.Matrix([e for pair in loops.angles for e in pair] + list(loops.tau_effective)), "main")
    values = main(q, qd, tau).ravel()
    cos_sin, tau_eff = values[:2 * n].reshape(n, 2), values[2 * n:]
    step = {}
    for name, inputs in (("velocity", [al.COS_SIN, [al.QD], al.PARENT_VELOCITY]),
                         ("backward", [al.COS_SIN, [al.TAU], al.VELOCITY, al.BIAS_ACCEL, al.CARRIED_INERTIA,
                                       al.CARRIED_FORCE]),
                         ("acceleration", [al.COS_SIN, al.BIAS_ACCEL, al.GAIN, [al.SCALED_FORCE], al.PARENT_ACCEL])):
        step[name] = compile_function([loops.slots, *inputs], getattr(loops, name),
                                      sp.Matrix(getattr(loops, f"{name}_outputs")), name)
    table = np.array(loops.table, dtype=float)
    v, z = np.zeros((n, 6)), np.zeros((n, 6))
    parent = np.zeros(6)
    for j in range(n):
        out = step["velocity"](table[j], cos_sin[j], [qd[j]], parent).ravel()
        v[j], z[j] = out[:6], out[6:]
        parent = v[j]
    K, k = np.zeros(21), np.zeros(6)
    gains, scaled = np.zeros((n, 6)), np.zeros(n)
    for j in reversed(range(n)):
        out = step["backward"](table[j], cos_sin[j], [tau_eff[j]], v[j], z[j], K, k).ravel()
        assert out[0] > 0
        gains[j], scaled[j], K, k = out[1:7], out[7], out[8:29], out[29:35]
    a = np.array([float(g) for g in loops.gravity])
    qdd = np.zeros(n)
    for j in range(n):
        out = step["acceleration"](table[j], cos_sin[j], z[j], gains[j], [scaled[j]], a).ravel()
        qdd[j], a = out[0], out[1:]
    return qdd


@pytest.fixture(scope="module")
def chains(tmp_path_factory):
    """name -> (robot, its equations with forward dynamics by the articulated-body algorithm),
    each written and derived once per module."""
    folder = tmp_path_factory.mktemp("loops")
    texts = {"generic9": generic_chain(9), "generic24": generic_chain(24), "frictional13": with_friction(generic_chain(13)),
             "structured9": structured_chain(9)}
    done = {}

    def get(name):
        if name not in done:
            path = folder / f"{name}.yaml"
            path.write_text(texts[name])
            robot = symdyn.load(str(path))
            done[name] = robot, symdyn.derive(robot, outputs=["forward_dynamics"], fd_method="aba")
        return done[name]
    return get


@pytest.mark.parametrize("name", ["generic9", "frictional13", pytest.param("generic24", marks=pytest.mark.slow)])
def test_loops_agree_with_pinocchio(name, chains):
    robot, eqs = chains(name)
    loops = eqs.articulated_loops
    assert loops is not None and loops.n == robot.dof
    if name == "frictional13":  # the armature differs between joints: a column of the table
        assert len(loops.slots) == 22
    ref = PinocchioReference(robot)
    states = random_states(robot.dof, 4, seed=9)
    mine = [run_loops(eqs, q, qd, tau) for q, qd, _, tau in states]
    assert normalized_error(mine, [ref.forward_dynamics(q, qd, tau) for q, qd, _, tau in states]) < TOL


def test_table_holds_only_what_differs(chains):
    """The DH placement's rotation about x (4 entries), its translation (a, d) and the inertia's
    15 entries that are not structural zeros differ between a generic chain's joints; the rest
    of the 34 candidates are numbers in the steps."""
    loops = chains("generic9")[1].articulated_loops
    assert len(loops.slots) == 4 + 2 + 15
    names = {s.name for s in loops.slots}
    for program in (loops.velocity, loops.backward, loops.acceleration):
        for symbol, _ in program.assignments:
            assert symbol.name.startswith(al.PREFIX) and re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", symbol.name)
            assert symbol.name not in names


@pytest.mark.parametrize("name, method", [("panda", "aba"), ("chain12", "aba"), ("generic9", "ldlt")])
def test_which_chains_get_loops(name, method, chains):
    """Under 8 joints (the Panda), with a prismatic joint (chain12) or by LDL^T: the written-out form only."""
    robot = chains(name)[0] if name == "generic9" else symdyn.load(robot_path(name))
    eqs = symdyn.derive(robot, outputs=["forward_dynamics"], fd_method=method)
    assert eqs.articulated_loops is None and eqs.fd_loops == ()


def test_loops_are_kept_only_when_they_cost_no_more(chains):
    """The rule of :func:`articulated_loops`: the structured arm's written-out form folds the
    per-joint +-1 and zeros the loops' step cannot (they differ between joints), so it keeps
    that form; a generic chain's loops count less than its written-out form."""
    robot, eqs = chains("structured9")
    assert al.applies(robot) and eqs.articulated_loops is None
    _, eqs = chains("generic9")
    loops = eqs.articulated_loops
    assert loops is not None
    assert al.loop_operations(loops) < 0.9 * al.operations(eqs.program, list(eqs.output("forward_dynamics")))
