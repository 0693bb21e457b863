"""Results written as soon as computed (symdyn.emit.cbody.EARLY_OUTPUTS_FROM): with every
function of puma560 forced to write its results early, and again early inside a body split into
parts, every function gives the same bytes as the build that writes them all at the end (the
mirrors of the symmetric outputs included); and which functions write early by default: a
floating robot's mass matrix (Solo-12; TALOS's, 38 x 38, is the case the rule was measured on),
not the arms' inverse dynamics nor any checked function."""

from __future__ import annotations

import numpy as np
import pytest

import symdyn
import symdyn.emit.cbody as cbody
from helpers import example_robot_data, robot_path
from symdyn.check.cbuild import build_and_load
from symdyn.emit.cgen import generate_c
from symdyn.model.outputs import OUTPUTS

CALLS = (("inverse_dynamics", 3), ("mass_matrix", 1), ("coriolis", 2), ("coriolis_matrix", 2), ("gravity", 1),
         ("forward_kinematics", 1), ("jacobian", 1), ("jacobian_dot_qd", 2))


@pytest.fixture(scope="module")
def puma():
    robot = symdyn.load(robot_path("puma560"))
    return robot, symdyn.derive(robot, outputs=OUTPUTS)


def _build(eqs, robot, folder, monkeypatch, early: bool, split: bool = False):
    monkeypatch.setattr(cbody, "EARLY_OUTPUTS_FROM", -1 if early else 10 ** 9)
    if split:
        for limit, size in (("SPLIT_FROM_STATEMENTS", "PART_LINES"),):
            monkeypatch.setattr(cbody, limit, 50)
            monkeypatch.setattr(cbody, size, 37)
    files = generate_c(eqs, OUTPUTS)
    monkeypatch.undo()
    folder.mkdir()
    return files, build_and_load(files, robot.name, 6, 0, "double", str(folder))


def test_early_results_give_the_same_bytes(puma, tmp_path, monkeypatch):
    robot, eqs = puma
    late_files, late = _build(eqs, robot, tmp_path / "late", monkeypatch, early=False)
    early_files, early = _build(eqs, robot, tmp_path / "early", monkeypatch, early=True)
    split_files, split = _build(eqs, robot, tmp_path / "split", monkeypatch, early=True, split=True)
    assert early_files != late_files and "_part" in split_files["puma560_dynamics.c"]
    rng = np.random.default_rng(3)
    for _ in range(10):
        q, qd, qdd = (rng.uniform(-3, 3, 6) for _ in range(3))
        for name, inputs in CALLS:
            args = (q, qd, qdd)[:inputs]
            reference = getattr(late, name)(*args)
            for other in (early, split):
                assert getattr(other, name)(*args).tobytes() == reference.tobytes(), name
        mass = early.mass_matrix(q)
        assert np.array_equal(mass, mass.T)  # each mirror written with its entry


@pytest.mark.parametrize("robot_file, function, early", [
    ("solo12", "mass_matrix", True),  # 18 x 18 entries, their distinct values far over the limit
    ("puma560", "inverse_dynamics", False),  # 6 results
    ("puma560", "forward_dynamics", False),  # checked: written once every check has passed
])
def test_which_functions_write_their_results_early(robot_file, function, early):
    from symdyn.emit.cplan import collect_targets, reduce_targets
    if robot_file == "solo12":
        robot = symdyn.load(example_robot_data("solo_description/robots/solo12.urdf"), floating_base=True)
    else:
        robot = symdyn.load(robot_path(robot_file))
    eqs = symdyn.derive(robot, outputs=(function,))
    plan = collect_targets(eqs, function)
    assert cbody.writes_results_early(plan, reduce_targets(eqs, plan)) is early
