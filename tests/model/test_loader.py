"""The robot file format: everything it allows is read; every mistake is named precisely."""

import textwrap

import numpy as np
import pytest
import sympy as sp

import symdyn
from symdyn.model.errors import RobotFileError, SymdynWarning

BASE = """\
format: 1
name: demo
convention: standard
links:
  - name: first
    joint: revolute
    a: 0.5
    alpha: pi/2
    d: 0.1
    theta: 0
    mass: 2
    com: [0.1, 0, 0]
    inertia: {xx: 0.1, yy: 0.1, zz: 0.1, xy: 0, xz: 0, yz: 0}
"""


def load_text(tmp_path, text, name="robot.yaml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return symdyn.load(path)


def test_full_format_is_read(tmp_path):
    robot = load_text(tmp_path, """\
        format: 1
        name: full_demo
        convention: modified
        gravity: [0, 0, -9.80665]
        parameters:
          l2: 0.4318
          half: l2/2
          m_load: {value: 0.5, runtime: true}
          k1: {runtime: true}
          I3: {runtime: true}
          b: {value: 1e-05}
        links:
          - {joint: revolute, a: 0, alpha: 0, d: 0.6718, theta: 0, mass: 1,
             inertia: [0.1, 0.2, 0.25, 0, 0, 0], armature: 0.01, damping: b, coulomb: 0.2}
          - {name: slider, joint: prismatic, a: l2, alpha: -pi/2, d: 1e-05, theta: pi/4,
             mass: 2 + m_load, com: [half, 0, k1], inertia: {zz: 2*I3}}
        """)
    assert robot.name == "full_demo" and robot.convention == "modified" and robot.dof == 2
    assert [s.name for s in robot.parameters] == ["m_load", "k1", "I3"]
    assert robot.nominal == (sp.Rational(1, 2), None, None)
    slider = robot.links[1]
    assert slider.joint == "prismatic" and slider.name == "slider"
    assert slider.a == sp.Rational(4318, 10000)
    assert slider.d == sp.Rational(1, 100000)
    assert slider.theta == sp.pi / 4
    assert slider.com[0] == sp.Rational(4318, 20000)
    assert robot.links[0].damping == sp.Rational(1, 100000)
    assert robot.links[0].name == "j1"
    assert robot.gravity[2] == sp.Rational(-980665, 100000)
    # inertia as a list is [xx, yy, zz, xy, xz, yz]
    assert robot.links[0].inertia == tuple(sp.nsimplify(v) for v in (0.1, 0.2, 0.25, 0, 0, 0))


def test_default_gravity_and_zero_fields(tmp_path):
    robot = load_text(tmp_path, """\
        format: 1
        name: bare
        convention: standard
        links:
          - {joint: revolute, a: 1, alpha: 0, d: 0, theta: 0}
        """)
    assert robot.gravity == (0, 0, sp.Rational(-981, 100))
    link = robot.links[0]
    assert link.mass == 0 and link.com == (0, 0, 0) and link.inertia == (0,) * 6
    assert link.armature == link.damping == link.coulomb == 0


def test_json_is_accepted(tmp_path):
    robot = load_text(tmp_path, '{"format": 1, "name": "j", "convention": "standard", '
                      '"links": [{"joint": "prismatic", "a": 0, "alpha": 0, "d": 0, "theta": 0, "mass": 1}]}',
                      name="robot.json")
    assert robot.links[0].joint == "prismatic"


def test_nothing_is_evaluated_as_code(tmp_path):
    with pytest.raises(RobotFileError) as err:
        load_text(tmp_path, BASE.replace("a: 0.5", "a: \"__import__('os').system('echo hi')\""))
    assert "link 1 ('first')" in str(err.value) and "field 'a'" in str(err.value)
    with pytest.raises(RobotFileError):
        load_text(tmp_path, BASE.replace("a: 0.5", "a: sin(1)"))


def test_substitute_and_nominal(tmp_path):
    robot = load_text(tmp_path, BASE.replace("mass: 2", "mass: m1").replace("links:", "parameters: {m1: {runtime: true}}\nlinks:"))
    assert robot.parameters == (sp.Symbol("m1", real=True),)
    fixed = robot.substitute({"m1": 3.5})
    assert fixed.parameters == () and fixed.links[0].mass == sp.Rational(7, 2)
    assert robot.links[0].mass == sp.Symbol("m1", real=True)  # the original is unchanged


CASES = [
    # (replacement old -> new, expected fragments in the message)
    (("format: 1", "format: 2"), ["field 'format'", "unsupported format 2"]),
    (("format: 1\n", ""), ["field 'format'", "missing"]),
    (("name: demo", "name: Demo-Robot"), ["field 'name'", "not a valid name"]),
    (("convention: standard", "convention: craig"), ["field 'convention'", "unknown convention"]),
    (("convention: standard\n", "convention: standard\ncolour: red\n"), ["field 'colour'", "unknown key"]),
    (("    mass: 2", "    mass: 2\n    masss: 3"), ["link 1 ('first')", "field 'masss'", "unknown key"]),
    (("    joint: revolute", "    joint: spherical"), ["link 1 ('first')", "field 'joint'", "unknown joint type"]),
    (("    joint: revolute\n", ""), ["link 1 ('first')", "field 'joint'", "missing"]),
    (("    alpha: pi/2\n", ""), ["link 1 ('first')", "field 'alpha'", "missing"]),
    (("    d: 0.1", "    d: [0.1]"), ["link 1 ('first')", "field 'd'", "expected a number"]),
    (("    d: 0.1", "    d: true"), ["link 1 ('first')", "field 'd'", "expected a number"]),
    (("    d: 0.1", "    d: 0.1 +* 2"), ["link 1 ('first')", "field 'd'", "bad expression"]),
    (("    d: 0.1", "    d: (0.1"), ["link 1 ('first')", "field 'd'", "bad expression"]),
    (("    d: 0.1", "    d: 1/0"), ["link 1 ('first')", "field 'd'", "division by zero"]),
    (("    d: 0.1", "    d: q1"), ["link 1 ('first')", "field 'd'", "unknown name 'q1'"]),
    (("name: demo", "name: demo\nparameters: {q1: {runtime: true}}"), ["field 'parameters.q1'", "cannot be used"]),
    (("    d: 0.1", "    d: 0.17415 + l_of"), ["link 1 ('first')", "field 'd'", "unknown name 'l_of'", "declare it"]),
    (("    d: 0.1", "    d: sin(0.2)"), ["field 'd'", "functions are not allowed"]),
    (("name: demo", "name: demo\nangles: grads"), ["field 'angles'", "radians or degrees"]),
    (("name: demo", "name: demo\nparameters: {m: {runtime: false}}"), ["field 'parameters.m.value'", "needs a value"]),
    (("    mass: 2", "    mass: -2"), ["link 1 ('first')", "field 'mass'", "must not be negative"]),
    (("    com: [0.1, 0, 0]", "    com: [0.1, 0]"), ["link 1 ('first')", "field 'com'", "list of 3"]),
    (("xx: 0.1, yy: 0.1, zz: 0.1", "xx: 0.1, yy: 0.1, zz: 0.1, xw: 1"), ["field 'inertia.xw'", "unknown inertia"]),
    (("    inertia: {xx: 0.1, yy: 0.1, zz: 0.1, xy: 0, xz: 0, yz: 0}", "    inertia: [0.1, 0.1]"), ["field 'inertia'", "6 values"]),
    (("    theta: 0\n", "    theta: 0\n    damping: -1\n"), ["link 1 ('first')", "field 'damping'", "must not be negative"]),
    (("name: demo", "name: demo\nname: again"), ["duplicate key 'name'"]),
    (("name: demo", "name: demo\nparameters: {pi: 3}"), ["field 'parameters.pi'", "cannot be used"]),
    (("name: demo", "name: demo\nparameters: {k: {value: 2, runtime: maybe}}"), ["field 'parameters.k.runtime'"]),
    (("name: demo", "name: demo\nparameters: {k: j + 1}"), ["field 'parameters.k'", "unknown name 'j'"]),
    (("name: demo", "name: demo\nparameters: {k: {value: x, runtime: true}}"), ["field 'parameters.k.value'", "unknown name 'x'"]),
    (("    a: 0.5", "    a: 0.5\n    name: again"), ["duplicate key 'name'"]),
]


@pytest.mark.parametrize("change,fragments", CASES, ids=[c[1][-1] + f"-{k}" for k, c in enumerate(CASES)])
def test_rejections_name_file_link_and_field(tmp_path, change, fragments):
    old, new = change
    assert old in BASE
    with pytest.raises(RobotFileError) as err:
        load_text(tmp_path, BASE.replace(old, new, 1))
    message = str(err.value)
    assert message.startswith(str(tmp_path / "robot.yaml"))
    for fragment in fragments:
        assert fragment in message, message


@pytest.mark.parametrize("inertia", ["xx: -0.1, yy: 0.1, zz: 0.1, xy: 0, xz: 0, yz: 0",
                                     "xx: 0.1, yy: 0.1, zz: 0.1, xy: 0.2, xz: 0, yz: 0"])
def test_a_negative_principal_moment_is_said_and_computed(tmp_path, inertia):
    """An inertia with a negative principal moment (published data, a merged URDF body: Romeo's
    small model) is computable, as Pinocchio computes it: one warning naming the link, not a refusal."""
    with pytest.warns(SymdynWarning, match=r"link 1 \('first'\): field 'inertia': .*negative principal moment.*"
                                           r"computed as given"):
        robot = load_text(tmp_path, BASE.replace("xx: 0.1, yy: 0.1, zz: 0.1, xy: 0, xz: 0, yz: 0", inertia, 1))
    assert robot.dof >= 1


def test_unreadable_and_non_yaml_files(tmp_path):
    with pytest.raises(RobotFileError, match="cannot read the file"):
        symdyn.load(tmp_path / "missing.yaml")
    with pytest.raises(RobotFileError, match="not valid YAML"):
        load_text(tmp_path, "format: 1\nlinks: [\n")
    with pytest.raises(RobotFileError, match="expected a mapping"):
        load_text(tmp_path, "- just\n- a list\n")


def test_empty_chain(tmp_path):
    with pytest.raises(RobotFileError) as err:
        load_text(tmp_path, "format: 1\nname: demo\nconvention: standard\nlinks: []\n")
    assert "field 'links'" in str(err.value) and "empty" in str(err.value)


def test_second_link_is_named_in_errors(tmp_path):
    text = BASE + "  - {joint: revolute, a: 0, alpha: 0, d: 0, theta: 0, mass: x y}\n"
    with pytest.raises(RobotFileError) as err:
        load_text(tmp_path, text)
    assert "link 2 ('j2')" in str(err.value) and "field 'mass'" in str(err.value)


def test_numeric_inertia_about_com_is_validated_with_parameters_folded(tmp_path):
    text = BASE.replace("name: demo", "name: demo\nparameters: {big: 5}").replace("zz: 0.1", "zz: big")
    with pytest.warns(symdyn.SymdynWarning, match="triangle"):
        load_text(tmp_path, text)


def test_undeclared_name_suggests_the_declared_one(tmp_path):
    text = BASE.replace("name: demo", "name: demo\nparameters: {l_off: 0.1}").replace("d: 0.1", "d: 0.17415 + l_of")
    with pytest.raises(RobotFileError) as err:
        load_text(tmp_path, text)
    message = str(err.value)
    assert "link 1 ('first')" in message and "field 'd'" in message
    assert "unknown name 'l_of'" in message and "did you mean 'l_off'?" in message


@pytest.mark.parametrize("name", ["qdot2", "qddot1", "cse0", "cse12", "c1", "s3", "q", "tau4"])
def test_names_that_print_like_symdyns_own_are_reserved(tmp_path, name):
    """A parameter named like a joint rate of the printouts (qdot2), the sin/cos shorthand (c1)
    or the C emitter's temporaries (cse0) is refused, naming it: it would merge with them."""
    text = textwrap.dedent(f"""\
        format: 1
        name: two
        convention: standard
        parameters:
          {name}: 0.5
        links:
          - {{joint: revolute, a: 0.4, alpha: 0, d: 0, theta: 0, mass: {name}, com: [0.2, 0, 0], inertia: 0}}
        """)
    with pytest.raises(RobotFileError, match=f"'{name}' cannot be used as a"):
        load_text(tmp_path, text)


def test_temporaries_never_take_a_name_in_use():
    """The C emitter's temporaries skip every name the expressions use (a parameter named cse0
    reaching the emitter some other way is never replaced by a temporary)."""
    import sympy as sp
    from symdyn.emit.emission import fresh_symbols, pair_cse
    a, b, c, used = sp.symbols("a b c cse0", real=True)
    exprs = [used * a * b + c, used * a * b - 2 * c, a * b * c]
    replacements, reduced = pair_cse(exprs, fresh_symbols("cse", exprs))
    assert replacements and all(s.name != "cse0" for s, _ in replacements)
    values = {a: 1.5, b: -0.7, c: 0.3, used: 2.0}
    back = dict(replacements)
    for original, rewritten in zip(exprs, reduced):
        for _ in range(3):
            rewritten = rewritten.xreplace(back)
        assert abs(float(original.xreplace(values)) - float(rewritten.xreplace(values))) < 1e-12
