"""The output registry (symdyn.model.outputs): every registered output is derived, emitted in C
and CasADi, compiled and called, timed and verified against Pinocchio, so that none can be
half-added."""

import dataclasses
import re
import shutil
import subprocess

import numpy as np
import pytest

import symdyn
from helpers import REPO, robot_path
from symdyn.check.cbuild import build_and_load, find_compiler
from symdyn.check.timing import symdyn_harness
from symdyn.cli import main
from symdyn.cli.common import parse_functions
from symdyn.derive.equations import DERIVATIONS
from symdyn.emit.casadi_backend import casadi_function
from symdyn.emit.cgen import generate_c
from symdyn.model.outputs import (ALL_OUTPUTS, COMBINED_SPECS, INPUT_GROUPS, OUTPUTS, SPECS, Dimensions, default_outputs,
                                  functions_help, with_requirements)
from symdyn.model.outputs import REGISTRY, functions_table
from symdyn.model.robot import TASKS, Contact, NamedFrame, Placement

#: passive joints (a nontrivial reaction map) and a numeric geometry (base parameters)
ROBOT = "pendulum_leg"
#: its task for the task-space functions: the tool's orientation (its position lies on a sphere
#: about the foot's spherical joint, so a task with linear rows would be singular everywhere)
TASK = "orientation"


@pytest.fixture(scope="module")
def everything(tmp_path_factory):
    """(robot, Equations of every output, compiled library, generated files)."""
    loaded = symdyn.load(robot_path(ROBOT))
    # two frames: the last link's own, and one fixed in link 2 away from its origin
    frames = (NamedFrame(loaded.links[-1].name, loaded.dof - 1),
              NamedFrame("offset", 1, tuple(Placement((0.1, -0.2, 0.3), (0.4, 0.5, 0.6)).matrix())),
              NamedFrame("held", loaded.dof - 1, tuple(Placement((0.1, -0.2, 0.3), (0.4, 0.5, 0.6)).matrix())))
    # a point contact away from the last link's origin (where the foot's axes meet)
    robot = dataclasses.replace(loaded, task=TASKS[TASK], frames=frames, contacts=(Contact(2, "3d"),))
    eqs = symdyn.derive(robot, outputs=ALL_OUTPUTS)
    files = generate_c(eqs, ALL_OUTPUTS)
    workdir = tmp_path_factory.mktemp("registry")
    lib = build_and_load(files, robot.name, eqs.dimensions, len(robot.parameters), workdir=str(workdir))
    return robot, eqs, lib, files, workdir


def test_specs_are_consistent():
    assert [s.name for s in SPECS] == list(ALL_OUTPUTS) and len(set(ALL_OUTPUTS)) == len(ALL_OUTPUTS)
    for spec in SPECS:
        assert spec.inputs and set(spec.inputs) <= set(INPUT_GROUPS), spec.name
        assert spec.arguments and spec.summary and spec.units, spec.name
        assert all(r in REGISTRY for r in spec.requires), spec.name
        names = [a.name for a in spec.arguments]
        assert len(set(names)) == len(names), spec.name
    for combined in COMBINED_SPECS:
        assert combined.name not in REGISTRY and all(p in REGISTRY for p in combined.parts)
    assert with_requirements(["forward_dynamics"]) == ("mass_matrix", "forward_dynamics")


def test_every_output_has_a_derivation():
    missing = [spec.name for spec in SPECS if spec.derivation not in DERIVATIONS]
    assert not missing, f"registered without a derivation: {missing}"
    unused = set(DERIVATIONS) - {spec.derivation for spec in SPECS} - {"fd_bias"}  # (forward dynamics' bias)
    assert not unused, f"derivations no output names: {unused}"


def test_readme_table_is_the_registry():
    """README's table of outputs is the one written from the specs (names, meanings, shapes,
    Pinocchio's equivalents, the combined functions)."""
    assert functions_table() in (REPO / "README.md").read_text(encoding="utf-8"), \
        "README's table of outputs is stale: paste symdyn.model.outputs.functions_table()"


def test_platform_table_is_the_registry():
    """docs/parallel-dynamics.md's table of the platform functions is the one written from their
    specs, and the platform derivation's function table is read from them."""
    from symdyn.derive.parallel import FUNCTIONS
    from symdyn.model.outputs import PLATFORM_SPECS, platform_functions_table
    assert platform_functions_table() in (REPO / "docs" / "parallel-dynamics.md").read_text(encoding="utf-8"), \
        "docs/parallel-dynamics.md's table of functions is stale: paste symdyn.model.outputs.platform_functions_table()"
    assert list(FUNCTIONS) == [spec.name for spec in PLATFORM_SPECS]


def test_shapes_are_written_as_they_are():
    """The shape's text and whether an output is a vector come from its shape function alone."""
    dims = Dimensions(dof=5, actuated=3, base_parameters=7, task=2, frames=4, contacts=6)
    for spec in SPECS:
        rows, cols = spec.shape(dims)
        text = spec.shape_text.replace("NC", "6").replace("NQ", "5").replace("NA", "3").replace("NB", "7").replace("N", "5").replace("M", "2").replace("K", "4")
        sizes = [eval(part.replace(" ", "*").replace("(", "").replace(")", "").replace("*+*", "+"))
                 for part in text.split(" x ")]
        assert sizes == ([rows] if spec.is_vector else [rows, cols]), spec.name
        assert spec.is_vector == (cols == 1 and spec.shape(Dimensions(9, 9, 9, 9, 9))[1] == 1), spec.name


def test_functions_option_knows_every_output():
    assert parse_functions(",".join(reversed(ALL_OUTPUTS))) == ALL_OUTPUTS
    for name in ALL_OUTPUTS:
        assert name in functions_help()
    with pytest.raises(symdyn.SymdynError, match="unknown function 'kinematic'"):
        parse_functions("kinematic")


def test_default_outputs_follow_the_registry():
    robot = symdyn.load(robot_path(ROBOT))
    assert default_outputs(robot) == OUTPUTS + ("reaction_map",)
    assert default_outputs(symdyn.load(robot_path("puma560"))) == tuple(s.name for s in SPECS if s.default)


def test_every_output_derived_emitted_and_called(everything):
    """Each registered output: its derived matrix has the registered shape, and the compiled C
    function returns the numbers the numpy evaluation of the same equations gives."""
    robot, eqs, lib, files, _ = everything
    dims = Dimensions(robot.dof, len(robot.actuated_joints), len(eqs.base_parameters), len(robot.task_rows),
                      len(robot.frames), contacts=robot.contact_rows)
    rng = np.random.default_rng(5)
    state = {g: rng.uniform(-1, 1, {"f": robot.contact_rows, "restitution": 1}.get(g, robot.dof)) for g in INPUT_GROUPS}
    for spec in SPECS:
        assert eqs.output(spec.name).shape == spec.shape(dims), spec.name
        prototype = re.search(rf"\b{robot.name}_{spec.name}\(([^)]*)\)", files[f"{robot.name}_dynamics.h"])
        assert prototype, spec.name
        for argument in spec.arguments:  # each output argument by its name, in the function's parameters
            assert re.search(rf"\*\s*{argument.name}\b", prototype.group(1)), (spec.name, argument.name, prototype.group(1))
        args = [state[g] for g in spec.inputs]
        mine = getattr(lib, spec.name)(*args)
        expected = getattr(eqs.numeric, spec.name)(*args)
        assert mine.shape == expected.shape, spec.name
        scale = max(1.0, float(np.max(np.abs(expected))))
        np.testing.assert_allclose(mine, expected, rtol=0, atol=1e-12 * scale, err_msg=spec.name)
    for combined in COMBINED_SPECS:
        results = getattr(lib, combined.name)(*[state[g] for g in combined.inputs])
        for part, value in zip(combined.parts, results):
            single = getattr(lib, part)(*[state[g] for g in REGISTRY[part].inputs])
            assert np.all(np.isfinite(single)), part
            # the same sums, in another order where the combined function is emitted otherwise
            # (forward_dynamics_derivatives: in two stages)
            np.testing.assert_allclose(value, single, rtol=0, atol=1e-14 * max(1.0, float(np.max(np.abs(single)))),
                                       err_msg=part)


def test_every_output_as_casadi(everything):
    robot, eqs, _, _, _ = everything
    rng = np.random.default_rng(6)
    state = {g: rng.uniform(-1, 1, {"f": robot.contact_rows, "restitution": 1}.get(g, robot.dof)) for g in INPUT_GROUPS}
    for spec in SPECS:
        function = casadi_function(eqs, spec.name)
        assert [function.name_out(k) for k in range(function.n_out())] == (
            [spec.symbol] if len(spec.arguments) == 1 else [a.name for a in spec.arguments]), spec.name
        args = [state[g] for g in spec.inputs]
        values = [np.array(v) for v in function(*args)] if function.n_out() > 1 else [np.array(function(*args))]
        got = np.hstack(values) if len(values) > 1 else values[0]
        expected = getattr(eqs.numeric, spec.name)(*args)
        np.testing.assert_allclose(got.reshape(expected.shape), expected, rtol=0,
                                   atol=1e-12 * max(1.0, float(np.max(np.abs(expected)))), err_msg=spec.name)


@pytest.mark.skipif(shutil.which("gcc") is None and shutil.which("cc") is None, reason="no C compiler")
def test_every_output_can_be_timed(everything):
    """The timing harness calls every generated function (compiled and linked, not run)."""
    robot, eqs, _, files, workdir = everything
    names = list(ALL_OUTPUTS) + [c.name for c in COMBINED_SPECS]
    harness = workdir / "bench.c"
    harness.write_text(symdyn_harness(robot.name, eqs.dimensions, names))
    result = subprocess.run([find_compiler(), "-std=c99", "-Wall", "-Werror", "-O0", str(harness),
                             str(workdir / f"{robot.name}_dynamics.c"), "-o", str(workdir / "bench"), "-lm"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[:2000]


def test_every_output_verified(capsys, tmp_path):
    """symdyn verify compares every registered output with Pinocchio (regressors as torques)."""
    pytest.importorskip("pinocchio")
    path = tmp_path / f"{ROBOT}.yaml"
    text = open(robot_path(ROBOT)).read() + f"task: {TASK}\n"
    last = re.findall(r"- name: (\w+)", text)[-1]
    path.write_text(text + f"frames: [{last}, {{name: offset, link: {last}, xyz: [0.1, -0.2, 0.3], rpy: [0.4, 0.5, 0.6]}}]\n"
                    "contacts: ['offset:3d']\n")
    code = main(["verify", str(path), "--functions", ",".join(ALL_OUTPUTS), "--states", "4"])
    out = capsys.readouterr().out
    assert code == 0, out
    for name in ALL_OUTPUTS:
        line = next(line for line in out.splitlines() if line.split()[:1] == [name])
        assert line.split()[-1] == "ok", line
