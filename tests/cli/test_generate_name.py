"""symdyn generate --name (the C prefix and file names, for two chains of one URDF in one --out)
and the refusal to replace files generated from another input (or not by symdyn) without
--force: one line, exit 1, nothing changed."""

from __future__ import annotations

import os
import pathlib
import re
import shutil
import subprocess

import pytest

import symdyn
from helpers import REPO
from symdyn.cli import main
from symdyn.emit.pipeline import GenerateOptions, configure
from symdyn.model.files import Provenance, read_provenance

PLANAR = REPO / "robots" / "planar2r.yaml"
CC = shutil.which("gcc") or shutil.which("cc")

#: a body with two 2-joint legs: two chains of one URDF (tips LF_FOOT and RF_FOOT)
TWO_LEGS = """<?xml version="1.0"?>
<robot name="quad">
  <link name="base"><inertial><mass value="5"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
""" + "".join(f"""
  <joint name="{leg}_HIP" type="revolute"><parent link="base"/><child link="{leg}_THIGH"/>
    <origin xyz="0.2 {y} 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="5"/></joint>
  <link name="{leg}_THIGH"><inertial><origin xyz="0 0 -0.1"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="{leg}_KNEE" type="revolute"><parent link="{leg}_THIGH"/><child link="{leg}_SHANK"/>
    <origin xyz="0 0 -0.25"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="5"/></joint>
  <link name="{leg}_SHANK"><inertial><origin xyz="0 0 -0.1"/><mass value="{mass}"/><inertia ixx="0.005" iyy="0.005" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="{leg}_FOOT_j" type="fixed"><parent link="{leg}_SHANK"/><child link="{leg}_FOOT"/><origin xyz="0 0 -0.25"/></joint>
  <link name="{leg}_FOOT"/>""" for leg, y, mass in (("LF", 0.1, 0.5), ("RF", -0.1, 0.7))) + "\n</robot>\n"


def error_line(capsys) -> str:
    err = [line for line in capsys.readouterr().err.strip().splitlines() if ": warning: " not in line]
    assert len(err) == 1, err
    assert err[0].startswith("symdyn: error: ") and "Traceback" not in err[0]
    return err[0]


def contents(directory) -> dict:
    return {name: (pathlib.Path(directory) / name).read_bytes() for name in sorted(os.listdir(directory))}


@pytest.fixture
def legs(tmp_path):
    path = tmp_path / "quad.urdf"
    path.write_text(TWO_LEGS)
    return str(path)


def generate(*argv) -> int:
    return main(["generate", *map(str, argv), "--quiet"])


# ---------------------------------------------------------------------------------------------
# --name

def test_two_legs_of_one_urdf_into_one_out(tmp_path, legs, capsys):
    out = tmp_path / "out"
    assert generate(legs, "--tip", "LF_FOOT", "--name", "lf_leg", "--out", out) == 0
    assert generate(legs, "--tip", "RF_FOOT", "--name", "rf_leg", "--out", out) == 0
    assert sorted(os.listdir(out)) == ["lf_leg_dynamics.c", "lf_leg_dynamics.h", "rf_leg_dynamics.c", "rf_leg_dynamics.h"]
    for prefix, other in (("lf_leg", "rf_leg"), ("rf_leg", "lf_leg")):
        header = (out / f"{prefix}_dynamics.h").read_text()
        assert f"int {prefix}_forward_dynamics_checked(" in header and f"void {prefix}_gravity(" in header
        assert f"#ifndef {prefix.upper()}_DYNAMICS_H" in header and other not in header
        assert f"#include \"{prefix}_dynamics.h\"" in (out / f"{prefix}_dynamics.c").read_text()
        assert "quad_" not in header and "input     : quad.urdf" in header
    assert "chain base -> LF_FOOT" in (out / "lf_leg_dynamics.h").read_text()
    if CC is None:
        pytest.skip("no C compiler: the two legs were generated, not built into one program")
    # both legs in one program: distinct symbols, and the right masses in each
    (tmp_path / "main.c").write_text(
        '#include "lf_leg_dynamics.h"\n#include "rf_leg_dynamics.h"\n#include <stdio.h>\n'
        "int main(void) { double q[2] = {0.3, -0.2}, c[2], d[2];\n"
        "  lf_leg_gravity(q, c); rf_leg_gravity(q, d); printf(\"%.17g %.17g\\n\", c[1], d[1]); return 0; }\n")
    exe = tmp_path / "both"
    build = subprocess.run([CC, "-std=c99", "-Wall", "-Wextra", "-Werror", "-I", str(out), str(tmp_path / "main.c"),
                            str(out / "lf_leg_dynamics.c"), str(out / "rf_leg_dynamics.c"), "-o", str(exe), "-lm"],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    left, right = map(float, subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split())
    assert right == pytest.approx(left * 0.7 / 0.5, rel=1e-12)  # the knee carries only its shank


def test_name_for_casadi_and_the_library_api(tmp_path, legs):
    import casadi
    out = tmp_path / "out"
    assert generate(legs, "--tip", "LF_FOOT", "--name", "lf_leg", "--out", out, "--target", "casadi",
                    "--functions", "gravity") == 0
    assert sorted(os.listdir(out)) == ["lf_leg_casadi.txt", "lf_leg_dynamics.casadi", "lf_leg_gravity.casadi"]
    assert casadi.Function.load(str(out / "lf_leg_gravity.casadi")).name() == "lf_leg_gravity"
    files = symdyn.generate(PLANAR, functions="gravity", name="arm_a")
    assert sorted(files) == ["arm_a_dynamics.c", "arm_a_dynamics.h"]
    assert b"void arm_a_gravity(" in files["arm_a_dynamics.h"] and b"planar2r_" not in files["arm_a_dynamics.c"]


def test_name_applies_to_scenes_and_platform_robots():
    """The one pipeline renames every kind of input (the emitters take the prefix from it)."""
    for path in (REPO / "robots" / "scenes" / "ur5_payload.yaml", REPO / "robots" / "parallel" / "sru_platform.yaml"):
        config = configure(path, GenerateOptions(name="cell_a"))
        assert config.robot.name == "cell_a"
        assert config.robot.source_hash == configure(path).robot.source_hash


@pytest.mark.parametrize("argv, words", [
    (["--name", "Leg-1"], ["--name 'Leg-1' is not a valid name", "lower-case"]),
    (["--name", "a" * 32], ["is not a valid name", "at most 31 characters"]),
    ([str(REPO / "robots" / "scara.yaml"), "--name", "x"], ["--name", "one input", "2 were given"]),
])
def test_bad_name_is_one_line_and_writes_nothing(tmp_path, capsys, argv, words):
    out = tmp_path / "out"
    assert generate(PLANAR, *argv, "--out", out) == 1
    line = error_line(capsys)
    assert all(word in line for word in words), line
    assert not out.exists()
    with pytest.raises(symdyn.SymdynError, match="not a valid name"):
        symdyn.generate(PLANAR, name="9lives")


# ---------------------------------------------------------------------------------------------
# Files of another input are not replaced without --force

@pytest.fixture
def other(tmp_path):
    """A different robot file that produces planar2r's files (same name, other content)."""
    path = tmp_path / "other.yaml"
    path.write_text(PLANAR.read_text().replace("inertia: {zz: I2}", "inertia: {zz: I2, xx: I2}"))
    return path


def test_another_input_is_refused_then_forced(tmp_path, capsys, other):
    out = tmp_path / "out"
    assert generate(PLANAR, "--out", out, "--functions", "gravity") == 0
    before = contents(out)
    source_hash = symdyn.load(PLANAR).source_hash
    assert generate(other, "--out", out, "--functions", "gravity") == 1
    line = error_line(capsys)
    assert re.fullmatch(rf"symdyn: error: {re.escape(str(out))}/planar2r_dynamics\.[ch] was generated from "
                        rf"planar2r\.yaml \(sha256 {source_hash}\), not from other\.yaml: use --name to write "
                        r"beside it, or --force to replace it", line), line
    assert contents(out) == before  # nothing changed, no temporary left
    assert generate(other, "--out", out, "--functions", "gravity", "--force") == 0
    assert b"input     : other.yaml" in (out / "planar2r_dynamics.h").read_bytes()
    # and --name writes beside it instead
    assert generate(PLANAR, "--out", out, "--functions", "gravity", "--name", "planar2r_b") == 0
    assert sorted(os.listdir(out)) == ["planar2r_b_dynamics.c", "planar2r_b_dynamics.h",
                                       "planar2r_dynamics.c", "planar2r_dynamics.h"]


def test_same_input_is_replaced_with_other_options(tmp_path, other):
    """A re-run of the same input replaces its files, whatever the options; an edited input
    file (same name, new content) too."""
    out = tmp_path / "out"
    assert generate(PLANAR, "--out", out, "--functions", "gravity") == 0
    assert generate(PLANAR, "--out", out, "--functions", "gravity,mass_matrix", "--precision", "float") == 0
    assert "planar2r_mass_matrix" in (out / "planar2r_dynamics.h").read_text()
    edited = tmp_path / "edited" / "planar2r.yaml"
    edited.parent.mkdir()
    edited.write_bytes(other.read_bytes())
    assert generate(edited, "--out", out, "--functions", "gravity") == 0
    assert symdyn.load(edited).source_hash in (out / "planar2r_dynamics.h").read_text()


def test_a_file_symdyn_did_not_write_is_kept(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "planar2r_dynamics.h").write_bytes(b"/* my own header */\n")
    assert generate(PLANAR, "--out", out, "--functions", "gravity") == 1
    line = error_line(capsys)
    assert "planar2r_dynamics.h: it was not generated by symdyn" in line and "--force" in line
    assert contents(out) == {"planar2r_dynamics.h": b"/* my own header */\n"}
    assert generate(PLANAR, "--out", out, "--functions", "gravity", "--force") == 0
    assert b"GENERATED FILE" in (out / "planar2r_dynamics.h").read_bytes()


def test_casadi_files_speak_through_their_description(tmp_path, capsys, other):
    """A .casadi file has no banner: the NAME_casadi.txt beside it says where it came from."""
    out = tmp_path / "out"
    argv = ["--out", out, "--target", "casadi", "--functions", "gravity"]
    assert generate(PLANAR, *argv) == 0
    assert generate(PLANAR, *argv) == 0  # a re-run
    before = contents(out)
    assert generate(other, *argv) == 1
    assert "was generated from planar2r.yaml" in error_line(capsys)
    assert contents(out) == before
    (out / "planar2r_casadi.txt").unlink()
    assert generate(PLANAR, *argv) == 1
    assert "planar2r_casadi.txt" in error_line(capsys)


def test_banners_name_their_input():
    """Every kind of generated file carries the banner the check reads (C, CasADi description)."""
    expected = Provenance("planar2r.yaml", symdyn.load(PLANAR).source_hash)
    for target, names in (("c", ["planar2r_dynamics.h", "planar2r_dynamics.c"]), ("casadi", ["planar2r_casadi.txt"])):
        files = symdyn.generate(PLANAR, functions="gravity", target=target)
        for name in names:
            assert read_provenance(files[name][:4096]) == expected, name
    assert read_provenance(b"input: x.yaml\nsha256: " + b"0" * 64) is None  # no symdyn banner
