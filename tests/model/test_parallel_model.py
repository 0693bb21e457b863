"""Parallel (platform) robot files: reading and validation (issue: parallel platforms)."""

import copy
import warnings

import pytest
import sympy as sp
import yaml

from symdyn.cli import main
from symdyn.model import parallel
from symdyn.model.errors import RobotFileError, SymdynWarning

LEG = {"convention": "standard", "actuated": 4, "links": [
    {"name": "s1", "joint": "revolute", "a": 0, "alpha": 90, "d": 0, "theta": 0},
    {"name": "s2", "joint": "revolute", "a": 0, "alpha": 90, "d": 0, "theta": 0},
    {"name": "s3", "joint": "revolute", "a": 0, "alpha": 0, "d": 0, "theta": 0,
     "mass": 20, "com": [0, 0, 0.5], "inertia": {"xx": 1, "yy": 1, "zz": 0.05}},
    {"name": "p", "joint": "prismatic", "a": 0, "alpha": 90, "d": 0, "theta": 0,
     "mass": 10, "com": [0, 0, -0.5], "inertia": {"xx": 0.5, "yy": 0.5, "zz": 0.02}},
    {"name": "u1", "joint": "revolute", "a": 0, "alpha": 90, "d": 0, "theta": 0},
    {"name": "u2", "joint": "revolute", "a": 0, "alpha": 0, "d": 0, "theta": 0}]}

DOC = {"format": 1, "kind": "parallel", "name": "plat", "angles": "degrees",
       "parameters": {"payload": {"value": 50, "runtime": True}},
       "platform": {"mass": "100 + payload", "com": [0, 0, 0.1], "inertia": {"xx": 10, "yy": 10, "zz": 18}},
       "leg": LEG,
       "legs": [{"base": {"xyz": [3, 0, 0], "rpy": [0, 0, 120 * (k // 2)]},
                 "platform": {"xyz": [1, 0.1 * (-1) ** k, 0]}} for k in range(6)]}


def _read(doc, tmp_path, name="plat.yaml"):
    path = tmp_path / name
    path.write_text(yaml.safe_dump(doc))
    return parallel.load(path)


def test_reads_a_platform_with_a_shared_leg_table(tmp_path):
    robot = _read(DOC, tmp_path)
    assert robot.dof == 6 and robot.name == "plat"
    assert robot.actuated_joints == tuple(f"leg{k}.p" for k in range(1, 7))
    assert robot.platform.mass == 100 + sp.Symbol("payload", real=True)
    assert [str(s) for s in robot.parameters] == ["payload"] and robot.nominal == (50,)
    leg = robot.legs[2]
    assert leg.chain.name == "plat_leg3" and leg.actuated == 3 and leg.actuated_link.joint == "prismatic"
    assert leg.chain.base.rpy[2] == 2 * sp.pi / 3  # degrees converted
    assert leg.chain.links[0].alpha == sp.pi / 2
    assert leg.attachment.xyz == (1, sp.Rational(1, 10), 0)
    assert robot.legs[0].chain.base.rpy == (0, 0, 0)
    assert all(len(leg.chain.links) == 6 for leg in robot.legs)
    assert robot.legs[0].chain.parameters == ()  # the payload is the platform's, not a leg's
    assert robot.gravity == (0, 0, sp.Rational(-981, 100))


def test_a_leg_may_bring_its_own_table(tmp_path):
    doc = copy.deepcopy(DOC)
    own = copy.deepcopy(LEG)
    own["actuated"] = 1
    own["links"][0]["joint"] = "prismatic"
    doc["legs"][5].update(own)
    robot = _read(doc, tmp_path)
    assert robot.legs[5].actuated == 0 and robot.legs[5].actuated_link.joint == "prismatic"
    assert robot.legs[4].actuated == 3


@pytest.mark.parametrize("change,where,why", [
    (lambda d: d["legs"].pop(), "field 'legs'", "expected a list of 6 legs"),
    (lambda d: d["leg"]["links"].pop(), "leg: field 'links'", "a leg has 6 joints"),
    (lambda d: d["leg"].update(actuated=7), "leg: field 'actuated'", "1 to 6"),
    (lambda d: d["leg"].update(actuated=True), "leg: field 'actuated'", "1 to 6"),
    (lambda d: d["leg"]["links"][3].update(actuated=True), "leg, link 4: field 'actuated'", "not per link"),
    (lambda d: d["legs"][1].update(foot=1), "leg 2: field 'foot'", "unknown key 'foot'"),
    (lambda d: d["legs"][1].pop("platform"), "leg 2 ('leg2'): field 'platform'", "missing required field"),
    (lambda d: d["legs"][1].update(name="leg1"), "leg 2: field 'name'", "duplicate leg name"),
    (lambda d: d["legs"][1].update(actuated=2), "leg 2 ('leg2'): field 'actuated'", "goes with its own 'links'"),
    (lambda d: d.pop("platform"), "field 'platform'", "missing required field"),
    (lambda d: d["platform"].update(mass=-1), "field 'platform.mass'", "must not be negative"),
    (lambda d: d["leg"]["links"][2].update(mass="m_leg"), "leg, link 3 ('s3'): field 'mass'",
     "unknown name 'm_leg'"),
    (lambda d: d.update(tool={}), "field 'tool'", "unknown key 'tool'"),
    (lambda d: d.pop("leg"), "leg 1 ('leg1'): field 'links'", "missing required field"),
])
def test_errors_name_the_file_leg_link_and_field(tmp_path, change, where, why):
    doc = copy.deepcopy(DOC)
    change(doc)
    with pytest.raises(RobotFileError) as info:
        _read(doc, tmp_path)
    message = str(info.value)
    assert message.startswith(str(tmp_path / "plat.yaml")), message
    assert where in message and why in message, message
    assert "\n" not in message


def test_a_platform_inertia_with_a_negative_principal_moment_is_said_and_computed(tmp_path):
    doc = copy.deepcopy(DOC)
    doc["platform"]["inertia"] = {"xx": -1, "yy": 1, "zz": 1}
    with pytest.warns(SymdynWarning, match="platform: field 'inertia': .*negative principal moment.*computed as given"):
        _read(doc, tmp_path)


def test_a_massless_platform_is_computed_with_a_warning(tmp_path):
    doc = copy.deepcopy(DOC)
    doc["platform"] = {"mass": 0}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = _read(doc, tmp_path)
    assert robot.platform.mass == 0
    assert any(issubclass(w.category, SymdynWarning) and "massless platform" in str(w.message) for w in caught)


def test_commands_refuse_what_they_cannot_do_for_a_platform_in_one_line(tmp_path, capsys):
    """generate, verify and bench take platform files, and refuse what they cannot do for one
    (here runtime parameters) in one line; nothing is written."""
    path = tmp_path / "plat.yaml"
    path.write_text(yaml.safe_dump(DOC))
    for command in (["verify", str(path)], ["bench", str(path), "--out", str(tmp_path / "out")],
                    ["generate", str(path), "--out", str(tmp_path / "out")]):
        assert main(command) != 0
        err = capsys.readouterr().err.strip()
        assert "runtime parameters" in err and "Traceback" not in err and len(err.splitlines()) == 1, err
    assert not (tmp_path / "out").exists()


def test_home_configurations_must_hold_the_platform_at_one_pose(tmp_path):
    """The bundled platforms' home configurations close every loop; a home that does not, or one
    given for some legs only, is refused naming the leg."""
    from helpers import REPO
    for name in ("flight_simulator", "sru_platform"):
        robot = parallel.load(REPO / "robots" / "parallel" / f"{name}.yaml")
        assert all(leg.home is not None and len(leg.home) == 6 for leg in robot.legs)
    doc = yaml.safe_load((REPO / "robots" / "parallel" / "flight_simulator.yaml").read_text())
    doc["legs"][2]["home"] = [0, 0, 0, 3.2, 0, 0]  # 4.6 cm too long
    with pytest.raises(RobotFileError, match=r"leg 3 \('leg3'\): field 'home': the legs' home configurations do "
                                             r"not hold the platform at one pose"):
        _read(doc, tmp_path)
    doc["legs"][2]["home"] = [0, 0, 0, 3.153800684, 0, 0]
    assert _read(doc, tmp_path).legs[2].home[3] == sp.Rational(788450171, 250000000)
    del doc["leg"]["home"]
    with pytest.raises(RobotFileError, match="field 'home': give the home configuration of every leg"):
        _read(doc, tmp_path)
    doc = copy.deepcopy(DOC)
    doc["leg"]["home"] = [0, 0, 0, 1, 0, 0]  # DOC's legs meet no common platform pose
    with pytest.raises(RobotFileError, match="do not hold the platform at one pose"):
        _read(doc, tmp_path)
    doc["leg"]["home"] = [0, 0, 0, 1, 0]
    with pytest.raises(RobotFileError, match="leg: field 'home': expected a list of 6 numbers"):
        _read(doc, tmp_path)
