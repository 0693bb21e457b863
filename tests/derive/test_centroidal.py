"""The whole robot's centre of mass and centroidal momentum (center_of_mass,
center_of_mass_jacobian, center_of_mass_bias, centroidal_momentum_matrix, centroidal_bias) against
Pinocchio's centerOfMass, jacobianCenterOfMass, ccrba and computeCentroidalMomentumTimeVariation:
serial arms (one with a base placement), a kinematic tree, floating bases (a satellite, Solo-12,
TALOS reduced), in numpy, compiled C (double and float) and CasADi."""

from __future__ import annotations

import numpy as np
import pytest

from symdyn.model.outputs import Dimensions
import symdyn
from helpers import REPO, TOL, example_robot_data, robot_path
from symdyn.check.cbuild import build_and_load
from symdyn.check.pinocchio_model import PinocchioReference, UrdfReference, compare
from symdyn.check.states import random_state
from symdyn.emit.cgen import generate_c
from symdyn.model.errors import SymdynError
from symdyn.model.outputs import CENTROIDAL_OUTPUTS
from test_trees import HAND_TREE, SOLO

STATES = 50


def _states(robot, count=STATES, seed=3):
    rng = np.random.default_rng(seed)
    return [random_state(robot, rng) for _ in range(count)]


def _check(robot, reference, tmp_path, compiled=True, float_too=False):
    """Every centroidal output at 50 states: numpy, and (``compiled``) the C of all of them in one
    library; ``float_too``: the float C within float's precision."""
    eqs = symdyn.derive(robot, outputs=CENTROIDAL_OUTPUTS)
    states = _states(robot)
    errors = compare(eqs.numeric, reference, states, CENTROIDAL_OUTPUTS)
    assert all(e <= TOL for e in errors.values()), (robot.name, errors)
    if compiled:
        files = generate_c(eqs, CENTROIDAL_OUTPUTS, "double")
        assert f"{robot.name.upper()}_TOTAL_MASS" in files[f"{robot.name}_dynamics.h"]
        lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, workdir=str(tmp_path))
        errors = compare(lib, reference, states, CENTROIDAL_OUTPUTS)
        assert all(e <= TOL for e in errors.values()), (robot.name, errors)
    if float_too:
        files = generate_c(eqs, CENTROIDAL_OUTPUTS, "float")
        (tmp_path / "float").mkdir()
        lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, "float", workdir=str(tmp_path / "float"))
        rounded = [[np.asarray(x, dtype=np.float32).astype(float) for x in s] for s in states[:10]]
        errors = compare(lib, reference, rounded, CENTROIDAL_OUTPUTS)
        assert all(e <= 2e-5 for e in errors.values()), (robot.name, errors)
    return eqs


@pytest.mark.parametrize("name", ["puma560", "stanford", "general_arm"])
def test_serial_arms_agree_with_pinocchio(name, tmp_path):
    """Two bundled arms (the Stanford arm's prismatic joint) and an arm on a placed, rotated base
    (world axes, not the base's)."""
    path = robot_path(name) if name != "general_arm" else str(REPO / "tests" / "data" / "general_arm.yaml")
    robot = symdyn.load(path)
    _check(robot, PinocchioReference(robot), tmp_path, float_too=name == "puma560")


def test_tree_and_floating_satellite_agree_with_pinocchio(tmp_path):
    """The hand-written tree, and the satellite on its floating base under gravity."""
    robot = symdyn.load(HAND_TREE)
    _check(robot, PinocchioReference(robot), tmp_path / "tree", compiled=False)
    text = (REPO / "examples" / "trees" / "space_robot.yaml").read_text()
    path = tmp_path / "grounded.yaml"
    path.write_text(text.replace("gravity: [0, 0, 0]", "gravity: [0.3, -1.2, -9.81]"))
    robot = symdyn.load(str(path))
    (tmp_path / "satellite").mkdir()
    _check(robot, PinocchioReference(robot), tmp_path / "satellite")


def test_solo12_floating_agrees_with_pinocchio_urdf_parser(tmp_path):
    """Solo-12 on Pinocchio's free-flyer, its model read by buildModelFromUrdf: numpy, C and
    CasADi; the momentum of a pure base translation is exactly m v (no angular part)."""
    path = example_robot_data(SOLO)
    robot = symdyn.load(path, floating_base=True)
    eqs = _check(robot, UrdfReference(path, floating_base=True), tmp_path)
    from symdyn.emit.casadi_backend import casadi_function
    q, qd, _, _ = _states(robot, 1, seed=9)[0]
    for name in CENTROIDAL_OUTPUTS:
        function = casadi_function(eqs, name)
        args = [q] if len(function.name_in()) == 1 else [q, qd]
        mine = np.array(function(*args)).reshape(np.shape(getattr(eqs.numeric, name)(*args)))
        np.testing.assert_allclose(mine, getattr(eqs.numeric, name)(*args), rtol=1e-12, atol=1e-12)
    A = eqs.numeric.centroidal_momentum_matrix(q)
    assert np.all(A[3:, :3] == 0.0)


@pytest.mark.slow
def test_talos_reduced_floating_agrees_with_pinocchio_urdf_parser(tmp_path):
    """TALOS reduced (32 joints, two legs, two arms, torso, head) on the free-flyer."""
    path = example_robot_data("talos_data/robots/talos_reduced.urdf")
    robot = symdyn.load(path, floating_base=True)
    _check(robot, UrdfReference(path, floating_base=True), tmp_path)


def test_a_massless_robot_is_refused():
    """No mass, no centre of mass: refused in one line naming the file."""
    from dataclasses import replace
    robot = symdyn.load(robot_path("planar2r"))
    massless = replace(robot, links=tuple(replace(link, mass=0) for link in robot.links))
    with pytest.raises(SymdynError, match="need a robot with mass") as caught:
        symdyn.derive(massless, outputs=["center_of_mass"])
    assert "\n" not in str(caught.value) and "planar2r.yaml" in str(caught.value)
