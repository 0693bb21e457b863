"""The library API under the CLI (symdyn.emit.pipeline, symdyn.generate): one configuration per
input, resolved once (the kind of robot looked up, options checked against it, a scene's
defaults applied), the same files as the command line."""

import pytest

from symdyn.model.outputs import Dimensions
import symdyn
from helpers import REPO
from symdyn.emit.pipeline import (KINDS, PLATFORM, SERIAL, GenerateOptions, check_options, configure, generate,
                                  kind_of)

PUMA = REPO / "robots" / "puma560.yaml"
PLATFORM_FILE = REPO / "robots" / "parallel" / "sru_platform.yaml"


def test_library_gives_the_checked_in_files():
    files = symdyn.generate(PUMA)
    assert set(files) == {"puma560_dynamics.h", "puma560_dynamics.c"}
    for name, text in files.items():
        assert text == (REPO / "generated" / name).read_bytes(), name


def test_kinds_are_looked_up():
    assert kind_of(symdyn.load(PUMA)) is SERIAL
    config = configure(PLATFORM_FILE)
    assert config.kind is PLATFORM and config.functions is None and config.precision == "double"
    assert {k.name for k in KINDS} == {"serial", "parallel"}
    with pytest.raises(symdyn.SymdynError, match="not a robot"):
        kind_of(object())


@pytest.mark.parametrize("options, message", [
    (GenerateOptions(batch=True), "--batch does not apply to a platform robot"),
    (GenerateOptions(header_only=True), "--header-only does not apply to a platform robot"),
    (GenerateOptions(method="lagrange-euler"), "--method does not apply to a platform robot"),
    (GenerateOptions(fd_method="aba"), "--fd-method does not apply"),
    (GenerateOptions(precision="mixed"), "platform robots are generated in double or float precision, not mixed"),
    (GenerateOptions(target="casadi-c"), "--target casadi-c is not available for platform robots"),
    (GenerateOptions(functions="mass_matrix,jacobian"), "unknown function 'jacobian' in --functions for a platform"),
])
def test_platform_options_refused_in_one_line(options, message):
    with pytest.raises(symdyn.SymdynError, match=message) as caught:
        configure(PLATFORM_FILE, options)
    assert str(PLATFORM_FILE) in str(caught.value) or "unknown function" in str(caught.value)


def test_options_checked_before_loading():
    with pytest.raises(symdyn.SymdynError, match="--batch applies to the c target only"):
        check_options(GenerateOptions(batch=True, target="casadi"))
    with pytest.raises(symdyn.SymdynError, match="--batch applies to the c target only"):
        configure(REPO / "robots" / "no_such_file.yaml", GenerateOptions(batch=True, target="casadi"))


def test_scene_defaults_apply_once(tmp_path):
    """A scene's functions and precision are the defaults (and its notes go to the header);
    what is asked wins; without a scene, the robot's defaults."""
    scene = tmp_path / "cell.yaml"
    scene.write_text(f"scene: 1\nrobot: {PUMA}\nname: cell\nlock: {{flange: 1.0}}\n"
                     "functions: [inverse_dynamics, gravity]\nprecision: float\n")
    config = configure(scene)
    assert config.functions == ("inverse_dynamics", "gravity") and config.precision == "float"
    assert config.fd_method == "aba" and config.notes == config.scene.notes and config.notes
    asked = configure(scene, GenerateOptions(functions="mass_matrix", precision="double"))
    assert asked.functions == ("mass_matrix",) and asked.precision == "double" and asked.fd_method == "ldlt"
    plain = configure(PUMA)
    assert plain.functions == symdyn.OUTPUTS and plain.precision == "double" and plain.scene is None


def test_serial_functions_in_registry_order():
    config = configure(PUMA, GenerateOptions(functions=("jacobian", "gravity")))
    assert config.functions == ("gravity", "jacobian")
    files = generate(config)
    header = files["puma560_dynamics.h"].decode()
    assert "puma560_gravity(" in header and "puma560_jacobian(" in header and "puma560_mass_matrix(" not in header


def test_forward_dynamics_method_chosen_by_operation_count(tmp_path, monkeypatch):
    """A generic chain of AUTO_FD_FROM_DOF (10) joints, one prismatic, in double without --fd-method: both forms
    are derived and the one with fewer operations emitted (here the articulated-body algorithm),
    the header says so, and the C agrees with
    Pinocchio's aba; --fd-method ldlt is obeyed as asked."""
    import sys
    import numpy as np
    from helpers import random_states
    from symdyn.check.cbuild import build_and_load
    from symdyn.check.pinocchio_model import PinocchioReference, compare
    sys.path.insert(0, str(REPO / "benchmarks"))
    from long_chains import generic_chain
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(tmp_path / "cache"))
    from symdyn.emit import pipeline
    n = pipeline.AUTO_FD_FROM_DOF
    path = tmp_path / f"generic{n}.yaml"  # the last joint prismatic: not the articulated-body loops
    path.write_text("joint: prismatic".join(generic_chain(n).rsplit("joint: revolute", 1)))
    options = GenerateOptions(functions="forward_dynamics")
    first = generate(configure(path, options))  # deterministic: generated/chain12 (the same choice), test_cgen
    header = first[f"generic{n}_dynamics.h"].decode()
    import re
    counts = re.search(r"chosen by operation count: (\d+) \(articulated-body\) against (\d+) \(LDL\^T\)", header)
    assert counts and int(counts[1]) < int(counts[2]), header[:2000]
    assert "by the articulated-body algorithm" in header
    robot = symdyn.load(str(path))
    files = {k: v.decode() for k, v in first.items()}
    lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, "double", str(tmp_path))
    errors = compare(lib, PinocchioReference(robot), random_states(robot.dof, 10, seed=5), ("forward_dynamics",), np.zeros(0))
    assert errors["forward_dynamics"] <= 1e-10, errors
    asked = generate(configure(path, GenerateOptions(functions="forward_dynamics", fd_method="ldlt")))
    assert "chosen by operation count" not in asked[f"generic{n}_dynamics.h"].decode()
    assert "LDL^T factorization" in asked[f"generic{n}_dynamics.h"].decode()


def test_long_chains_take_the_articulated_body_algorithm_without_counting(tmp_path, monkeypatch):
    """From AUTO_FD_ABA_FROM_DOF joints the choice is made without deriving or building LDL^T
    (its n^3 operations always exceed ABA's there), and so from LOOPED_ABA_FROM_DOF joints
    where the articulated-body loops apply; the header says why."""
    import sys
    from symdyn.emit import pipeline
    sys.path.insert(0, str(REPO / "benchmarks"))
    from long_chains import generic_chain
    path = tmp_path / "generic.yaml"  # a prismatic joint: not the loop form (below), the rule by n
    path.write_text(generic_chain(pipeline.AUTO_FD_ABA_FROM_DOF).replace("joint: revolute", "joint: prismatic", 1))
    config = configure(path, GenerateOptions(functions="forward_dynamics"))

    def refuse(*args, **kwargs):
        raise AssertionError("nothing is derived to choose")
    monkeypatch.setattr(pipeline, "derive_cached", refuse)
    chosen = pipeline.choose_fd_method(config)
    assert chosen.fd_method == "aba"
    assert any("from 24 joints LDL^T of D, O(n^3), always needs more" in note for note in chosen.notes)
    short = tmp_path / "short.yaml"  # below it, both are counted
    short.write_text(generic_chain(pipeline.AUTO_FD_ABA_FROM_DOF - 1).replace("joint: revolute", "joint: prismatic", 1))
    with pytest.raises(AssertionError, match="nothing is derived"):
        pipeline.choose_fd_method(configure(short, GenerateOptions(functions="forward_dynamics")))


def test_fixed_base_revolute_chains_take_the_articulated_body_loops(tmp_path, monkeypatch):
    """From LOOPED_ABA_FROM_DOF joints a generic fixed-base revolute chain takes the
    articulated-body algorithm's loops (only its derivation is run to choose: the loops are kept
    when they cost no more operations than the chain written out); below, LDL^T as before."""
    import sys
    from symdyn.derive.articulated_loops import LOOPED_ABA_FROM_DOF
    from symdyn.emit import pipeline
    sys.path.insert(0, str(REPO / "benchmarks"))
    from long_chains import generic_chain
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(tmp_path / "cache"))
    derived = []
    real = pipeline.derive_cached

    def spy(robot, method, wanted, **kwargs):
        derived.append(kwargs["fd_method"])
        return real(robot, method, wanted, **kwargs)
    monkeypatch.setattr(pipeline, "derive_cached", spy)
    looped = tmp_path / "looped.yaml"
    looped.write_text(generic_chain(LOOPED_ABA_FROM_DOF))
    chosen = pipeline.choose_fd_method(configure(looped, GenerateOptions(functions="forward_dynamics")))
    assert chosen.fd_method == "aba" and any("as loops over the joints" in note for note in chosen.notes)
    assert derived == ["aba"]
    short = tmp_path / "short.yaml"
    short.write_text(generic_chain(LOOPED_ABA_FROM_DOF - 1))
    assert pipeline.choose_fd_method(configure(short, GenerateOptions(functions="forward_dynamics"))).fd_method == "ldlt"
    assert derived == ["aba"]
