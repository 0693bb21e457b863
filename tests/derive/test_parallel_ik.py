"""Closed-form inverse kinematics of S-X-U legs (symdyn.derive.parallel_ik), issue: parallel
platforms: against the numeric reference's Newton iterations, symbolically, every branch, and
the structures it refuses."""

import copy

import numpy as np
import pytest
import sympy as sp
import yaml

from helpers import REPO
from symdyn.derive.parallel_ik import LegIK, LegStructureError
from symdyn.model import parallel

pin = pytest.importorskip("pinocchio")

from closed_loop import PLATFORMS, states as _states  # noqa: E402


def _target(leg, p, R):
    """Pose (4x4) of the leg's frame 6 in its frame 0 for platform pose (p, R)."""
    base = np.array(leg.chain.base_matrix(), dtype=float).reshape(4, 4)
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = R, p
    return np.linalg.inv(base) @ pose @ np.array(leg.attachment.matrix(), dtype=float)


def _as_angles(solution, leg):
    """Joint variables q from a closed-form solution ((cos, sin) pairs and prismatic values)."""
    return np.array([np.arctan2(float(v[1]), float(v[0])) - float(link.theta) if link.is_revolute else float(v)
                     for v, link in zip(solution, leg.chain.links)])


@pytest.mark.parametrize("name", sorted(PLATFORMS))
def test_closed_form_equals_newton(name):
    """Every leg of both bundled platforms: the closed form, with the branches of the home
    configuration (the file's), gives the joint values the reference's Newton iterations find
    (<= 1e-12)."""
    from symdyn.check.parallel_reference import ParallelReference
    robot = parallel.load(REPO / "robots" / "parallel" / f"{name}.yaml")
    ref = ParallelReference(robot)
    solvers = [LegIK.of(leg.chain) for leg in robot.legs]
    branches = [ik.branches_of(leg.home) for ik, leg in zip(solvers, robot.legs)]  # the file's home
    numeric = [ik.with_floats() for ik in solvers]
    for p, R, _, _ in _states(name, 5, seed=7):
        newton = ref.leg_positions(p, R)
        for k, leg in enumerate(robot.legs):
            target = _target(leg, p, R)
            ours = _as_angles(numeric[k].solve(target[:3, :3].tolist(), target[:3, 3].tolist(), branches[k], np.sqrt), leg)
            wrapped = (ours - newton[k] + np.pi) % (2 * np.pi) - np.pi
            revolute = [link.is_revolute for link in leg.chain.links]
            error = np.where(revolute, wrapped, ours - newton[k])
            assert np.abs(error).max() <= 1e-12, (name, k, error)


def test_other_branches_close_the_loop_too():
    """The S-R-U leg's other knee branch (and the other universal-joint and spherical branches)
    are configurations too: the leg's forward kinematics puts frame 6 on the target."""
    import symdyn
    robot = parallel.load(REPO / "robots" / "parallel" / "sru_platform.yaml")
    leg = robot.legs[0]
    ik = LegIK.of(leg.chain).with_floats()
    fk = symdyn.derive(leg.chain, outputs=["forward_kinematics"]).numeric
    p, R, _, _ = next(_states("sru_platform", 1, seed=8))
    target = _target(leg, p, R)
    base = np.array(leg.chain.base_matrix(), dtype=float).reshape(4, 4)
    seen = set()
    for branches in [(1, 1, 1), (-1, 1, 1), (1, -1, 1), (1, 1, -1), (-1, -1, -1)]:
        q = _as_angles(ik.solve(target[:3, :3].tolist(), target[:3, 3].tolist(), branches, np.sqrt), leg)
        pose = np.linalg.inv(base) @ np.asarray(fk.forward_kinematics(q, []), dtype=float).reshape(4, 4)
        assert np.abs(pose - target).max() <= 1e-12, branches
        seen.add(tuple(np.round(q, 6)))
    assert len(seen) == 5, "the branches are not distinct configurations"


def test_symbolic_solution_evaluates_to_the_numeric_one():
    """On SymPy symbols (the generated code's inputs) the closed form gives expressions that
    evaluate to the numeric solution."""
    robot = parallel.load(REPO / "robots" / "parallel" / "flight_simulator.yaml")
    leg = robot.legs[2]
    ik = LegIK.of(leg.chain)
    R = sp.Matrix(3, 3, sp.symbols("r0:9", real=True))
    pos = sp.symbols("x y z", real=True)
    exprs = ik.solve([[R[i, j] for j in range(3)] for i in range(3)], list(pos))
    p, Rn, _, _ = next(_states("flight_simulator", 1, seed=9))
    target = _target(leg, p, Rn)
    values = {**{R[i, j]: target[i, j] for i in range(3) for j in range(3)}, **dict(zip(pos, target[:3, 3]))}
    numeric = ik.with_floats().solve(target[:3, :3].tolist(), target[:3, 3].tolist(), sqrt=np.sqrt)
    for sym, num in zip(exprs, numeric):
        for a, b in zip(sym if isinstance(sym, tuple) else (sym,), num if isinstance(num, tuple) else (num,)):
            assert abs(float(sp.sympify(a).xreplace(values)) - float(b)) <= 1e-12


def test_refuses_legs_of_another_structure(tmp_path):
    """A leg whose first three axes do not meet, or with a prismatic joint in the spherical pair,
    is not solved by this closed form: LegStructureError says which joints."""
    doc = yaml.safe_load((REPO / "robots" / "parallel" / "flight_simulator.yaml").read_text())
    del doc["leg"]["home"]  # the changed legs no longer meet the platform at the home pose
    moved = copy.deepcopy(doc)
    moved["leg"]["links"][1]["origin"] = {"xyz": [0, 0, 0.1]}  # axis 2 no longer meets axis 1
    path = tmp_path / "moved.yaml"
    path.write_text(yaml.safe_dump(moved))
    with pytest.raises(LegStructureError, match="joints 1-3 do not meet|joints 1 and 2: the axes do not meet"):
        LegIK.of(parallel.load(path).legs[0].chain)
    slid = copy.deepcopy(doc)
    slid["leg"]["links"][1]["joint"] = "prismatic"
    path.write_text(yaml.safe_dump(slid))
    with pytest.raises(LegStructureError, match="must be revolute"):
        LegIK.of(parallel.load(path).legs[0].chain)
