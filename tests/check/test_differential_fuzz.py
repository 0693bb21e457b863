"""The differential fuzzer (symdyn.check.fuzz): its kept regression cases pass, it finds the
faults it exists for (a cache key missing a field, a printer fault), it shrinks a failing robot,
and its cases are the same on every run.  The fixed campaign of at least 30 robots runs in
.ci/run (``symdyn fuzz --cases 30``); a long campaign's command is in docs/contributing.md.
"""

from __future__ import annotations

import dataclasses
import re
import shutil

import pytest

from helpers import REPO
from symdyn.check import fuzz

KEPT = sorted((REPO / "tests" / "data" / "fuzz").glob("*.case.yaml"))

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(tmp_path / "cache"))
    pytest.importorskip("pinocchio")


#: the kept cases whose check takes the longest (13-50 s of a CPU each): they run with the slow
#: tests, the others with every test run
SLOW_KEPT = {"fuzz7.case.yaml", "fuzz208.case.yaml", "fuzz304.case.yaml", "fuzz323.case.yaml"}


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow) if p.name in SLOW_KEPT else p for p in KEPT],
                         ids=[p.name for p in KEPT])
def test_kept_cases_pass(path, tmp_path):
    case = fuzz.load_case(str(path))
    outcome = fuzz.check_case(case, str(tmp_path))
    assert not outcome.findings, "\n".join(map(str, outcome.findings))
    assert outcome.compared >= len(outcome.functions)


def test_cases_are_reproducible():
    assert fuzz.random_case(17) == fuzz.random_case(17)
    assert fuzz.random_case(17) != fuzz.random_case(18)
    kinds = {fuzz.random_case(k).kind for k in range(20)}
    assert kinds == {"urdf", "dh"}


TWO_FRAMES = fuzz.Case(
    number=9001, kind="dh", frames=("j2", "j3"), text="""format: 1
name: twoframes
convention: standard
gravity: [0, 0, -9.81]
links:
  - {name: j1, joint: revolute, a: 0.3, alpha: 1.5707963267948966, d: 0.1, theta: 0, mass: 2.0, com: [0.1, 0, 0], inertia: [0.02, 0.03, 0.025, 0, 0, 0]}
  - {name: j2, joint: revolute, a: 0.25, alpha: 0, d: 0, theta: 0, mass: 1.5, com: [0.1, 0.02, 0], inertia: [0.01, 0.02, 0.015, 0, 0, 0]}
  - {name: j3, joint: prismatic, a: 0, alpha: -pi/2, d: 0.1, theta: 0.3, mass: 1.0, com: [0, 0, 0.05], inertia: [0.01, 0.01, 0.01, 0, 0, 0], damping: 0.2}
""")


def test_finds_a_cache_key_that_misses_the_frames(tmp_path, monkeypatch):
    """The first fault of the trust issue, planted again: the key leaves out the frames."""
    from symdyn.derive import cache
    original = cache.canonical

    def without_frames(value):
        if isinstance(value, symdyn_robot()):
            value = dataclasses.replace(value, frames=())
        return original(value)
    monkeypatch.setattr(cache, "canonical", without_frames)
    outcome = fuzz.check_case(TWO_FRAMES, str(tmp_path), targets=("cache",))
    assert [f.function for f in outcome.findings if f.target == "cache"] == ["frame_poses"], outcome.findings


def symdyn_robot():
    from symdyn.model.robot import Robot
    return Robot


def test_finds_a_printer_fault(tmp_path, monkeypatch):
    """Operands printed without the parentheses their precedence needs (the class of the second
    fault: ``-(a - b)`` printed as ``-a - b``)."""
    from symdyn.emit import cprinter
    monkeypatch.setattr(cprinter.CPrinter, "parenthesize", lambda self, item, level, strict=False: self._print(item))
    outcome = fuzz.check_case(TWO_FRAMES, str(tmp_path), targets=("c",))
    assert any(f.target in ("c", "compile") for f in outcome.findings), outcome.findings


def test_shrinks_to_the_links_that_matter(tmp_path, monkeypatch):
    """A finding that needs link l2 only: the shrunk URDF keeps l2 and its joint, little else."""
    case = next(c for c in map(fuzz.random_case, range(200)) if c.kind == "urdf" and c.text.count("<joint") >= 4
                and 'child link="l2"' in c.text)

    def fails_with_l2(candidate, workdir, targets=()):
        outcome = fuzz.Outcome(candidate)
        if 'name="l2"' in candidate.text:
            outcome.findings.append(fuzz.Finding(candidate.number, "c", "gravity", 1.0))
        return outcome
    monkeypatch.setattr(fuzz, "check_case", fails_with_l2)
    small = fuzz.shrink(case, fuzz.Finding(case.number, "c", "gravity", 1.0), str(tmp_path))
    assert 'name="l2"' in small.text
    assert small.text.count("<joint") < case.text.count("<joint")
    assert not small.frames or small.frames == tuple(f for f in case.frames if f in small.text)


@pytest.mark.slow
def test_a_small_campaign(tmp_path):
    """Three robots end to end through the command line's campaign (the fixed campaign of 30
    is .ci/run's); a failure is kept as a case file."""
    lines = []
    outcomes = fuzz.run_campaign([2, 8, 102], str(tmp_path / "kept"), report=lines.append, shrink_seconds=30)
    assert len(outcomes) == 3 and all(o.compared > 10 for o in outcomes), lines
    assert not [o for o in outcomes if o.findings], "\n".join(lines)


def test_some_cases_take_a_big_robots_code_shapes(tmp_path, monkeypatch):
    """About one case in three compiles its C in the shapes of a big robot's (bodies in parts,
    numbers written by tables, several files: symdyn.emit.cbody.small_pieces), and a fault planted
    in one of those shapes (a table writing another value) is found."""
    from symdyn.emit import cbody
    assert 5 <= sum(fuzz.random_case(k).small_pieces for k in range(30)) <= 15
    case = fuzz.random_case(2)
    assert case.small_pieces and "C in small pieces" in case.describe()
    (tmp_path / "right").mkdir()
    outcome = fuzz.check_case(case, str(tmp_path / "right"), targets=("c",))
    assert not outcome.findings, "\n".join(map(str, outcome.findings))
    original = cbody.number_writes

    def wrong_value(lines, name, vector=False):
        return [re.sub(r"\[k\]\] = .*;$", "[k]] = 0.5;", line) for line in original(lines, name, vector)]
    monkeypatch.setattr(cbody, "number_writes", wrong_value)
    (tmp_path / "planted").mkdir()
    outcome = fuzz.check_case(case, str(tmp_path / "planted"), targets=("c",))
    assert any(f.target == "c" for f in outcome.findings), outcome.findings


HELD = fuzz.Case(
    number=9002, kind="urdf", floating=True, contacts=("l2:3d",), correction=(60.0, 9.0, 0.1, -0.2, 0.05),
    text="""<robot name="fz9002">
  <link name="l0"><inertial><origin xyz="0 0 0.05"/><mass value="2.0"/><inertia ixx="0.02" iyy="0.03" izz="0.025" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="1.0"/><inertia ixx="0.01" iyy="0.02" izz="0.015" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0 0.02 0.1"/><mass value="0.5"/><inertia ixx="0.004" iyy="0.005" izz="0.003" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="l0"/><child link="l1"/><origin xyz="0 0 0.1" rpy="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="5"/></joint>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/><origin xyz="0.2 0 0"/><axis xyz="0 0 1"/><limit lower="-0.2" upper="0.2" effort="10" velocity="5"/></joint>
</robot>
""")


@pytest.mark.slow
def test_finds_a_correction_left_out(tmp_path, monkeypatch):
    """A point held with a Baumgarte correction (half of the cases holding a point carry one, the
    fixed campaign's cases 22 and 27 among them): the case passes, and a derivation that leaves
    the correction out is found in the contact functions."""
    assert [k for k in range(30) if fuzz.random_case(k).correction] == [22, 27]
    assert "corrected (kp 60" in HELD.describe()
    (tmp_path / "right").mkdir()
    outcome = fuzz.check_case(HELD, str(tmp_path / "right"), targets=("numpy",))
    assert not outcome.findings, "\n".join(map(str, outcome.findings))
    from symdyn.derive import equations
    monkeypatch.setattr(equations, "correction", lambda contact, *args, **kwargs: [0] * contact.rows)
    monkeypatch.setattr("symdyn.derive.contact.correction", lambda contact, *args, **kwargs: [0] * contact.rows)
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(tmp_path / "planted_cache"))  # (not the right derivation's)
    (tmp_path / "planted").mkdir()
    outcome = fuzz.check_case(HELD, str(tmp_path / "planted"), targets=("numpy",))
    found = {f.function for f in outcome.findings if f.target == "numpy"}
    assert {"contact_accelerations", "contact_forces", "contact_accelerations_dq"} <= found, outcome.findings
