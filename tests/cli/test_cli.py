"""The command line, through main([...]): help, errors as one line, atomic output, cache, verify."""

import os

import pytest

from helpers import REPO
from symdyn.cli import main

PUMA = str(REPO / "robots" / "puma560.yaml")


def one_error_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("symdyn: error: ")
    assert "Traceback" not in err[0]
    return err[0]


def test_help_is_complete(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "generate" in out and "verify" in out
    for sub, words in (("generate", ["--out", "--precision", "--functions", "--header-only", "--method"]),
                       ("verify", ["--states", "--precision", "--tolerance"])):
        assert main([sub, "--help"]) == 0
        text = capsys.readouterr().out
        for word in words:
            assert word in text


def test_missing_file(tmp_path, capsys):
    assert main(["generate", str(tmp_path / "nope.yaml"), "--out", str(tmp_path)]) == 1
    line = one_error_line(capsys)
    assert "nope.yaml" in line and "cannot read" in line


def test_bad_robot_file(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("format: 1\nname: bad\nconvention: standard\nlinks:\n  - {joint: revolute, a: 0, alpha: 0, d: 0, theta: 0, mass: -1}\n")
    assert main(["generate", str(bad), "--out", str(tmp_path / "out")]) == 1
    line = one_error_line(capsys)
    assert "bad.yaml" in line and "link 1" in line and "'mass'" in line
    assert not (tmp_path / "out").exists()


def test_unknown_function_name(tmp_path, capsys):
    assert main(["generate", PUMA, "--out", str(tmp_path), "--functions", "gravity,jacobain"]) == 1
    assert "jacobain" in one_error_line(capsys)
    assert os.listdir(tmp_path) == []


def test_unwritable_directory(tmp_path, capsys):
    target = tmp_path / "file-not-dir"
    target.write_text("x")
    assert main(["generate", PUMA, "--out", str(target / "sub"), "--functions", "gravity"]) == 1
    assert "cannot create output directory" in one_error_line(capsys)


@pytest.mark.skipif(os.geteuid() == 0, reason="root can write anywhere")
def test_read_only_directory(tmp_path, capsys):
    out = tmp_path / "ro"
    out.mkdir()
    out.chmod(0o500)
    try:
        assert main(["generate", PUMA, "--out", str(out), "--functions", "gravity"]) == 1
        assert "not writable" in one_error_line(capsys)
    finally:
        out.chmod(0o700)


def test_failed_run_leaves_existing_files_untouched(tmp_path, capsys):
    assert main(["generate", PUMA, "--out", str(tmp_path), "--functions", "gravity", "--quiet"]) == 0
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    bad = tmp_path / "puma560.yaml"
    bad.write_text(open(PUMA).read().replace("mass: 17.4", "mass: 17.4 +"))
    assert main(["generate", str(bad), "--out", str(tmp_path)]) == 1
    one_error_line(capsys)
    after = {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.name != "puma560.yaml"}
    assert after == before


def test_usage_error_returns_nonzero(capsys):
    assert main(["generate"]) == 2
    assert main(["frobnicate"]) == 2
    assert main([]) == 2


def test_corrupt_cache_entry_is_rebuilt(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(tmp_path / "cache"))
    out1, out2 = tmp_path / "a", tmp_path / "b"
    assert main(["generate", PUMA, "--out", str(out1), "--functions", "gravity", "--quiet"]) == 0
    entries = list((tmp_path / "cache").glob("*.json"))
    assert len(entries) == 1
    data = bytearray(entries[0].read_bytes())
    data[-10] ^= 0xFF  # damage the payload: the checksum must catch it
    entries[0].write_bytes(bytes(data))
    assert main(["generate", PUMA, "--out", str(out2), "--functions", "gravity", "--quiet"]) == 0
    assert (out1 / "puma560_dynamics.c").read_bytes() == (out2 / "puma560_dynamics.c").read_bytes()
    from symdyn.derive.cache import _load
    import re
    key = entries[0].stem
    assert _load(str(entries[0]), key) is not None  # rewritten, valid again
    entries[0].write_bytes(b"garbage")
    assert main(["generate", PUMA, "--out", str(out2), "--functions", "gravity", "--quiet"]) == 0


def test_verify_passes_and_fails(capsys):
    assert main(["verify", PUMA, "--states", "5"]) == 0
    out = capsys.readouterr().out
    for name in ("inverse_dynamics", "mass_matrix", "coriolis_matrix", "forward_dynamics"):
        assert name in out
    assert "FAIL" not in out
    # an impossible tolerance must fail with exit status 1
    assert main(["verify", PUMA, "--states", "3", "--tolerance", "1e-30"]) == 1
    assert "FAIL" in capsys.readouterr().out


def test_cache_key_covers_derivation_code(monkeypatch):
    """A stale entry written by other derivation code must not be found: the key includes a
    hash of every module in the derivation's folders, and every module they import is hashed."""
    import ast
    import symdyn.derive.cache as cache
    package = os.path.join(REPO, "symdyn")
    listed = set(cache.derivation_modules())
    assert {"derive/equations", "derive/newton_euler", "model/outputs", "model/robot"} <= listed
    for name in listed:
        tree = ast.parse(open(os.path.join(package, f"{name}.py")).read())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.level in (1, 2) and node.module:
                parts = node.module.split(".")
                module = f"{name.split('/')[0]}/{parts[0]}" if node.level == 1 else "/".join(parts[:2])
                if module not in ("model/errors", "model/inputs", "_version", "derive/numeric"):  # no effect on the result
                    assert module in listed, f"{name} imports {module}, missing from the cache key"
    robot = __import__("symdyn").load(PUMA)
    key = cache.cache_key(robot, "newton-euler", ["gravity"])
    cache.code_fingerprint.cache_clear()
    monkeypatch.setattr(cache, "code_fingerprint", lambda: "0" * 64)
    assert cache.cache_key(robot, "newton-euler", ["gravity"]) != key


def test_verify_by_the_jacobian_projected_method(capsys):
    """The third formulation through the CLI: generated C by the Jacobian-projected
    Newton-Euler, every function within 1e-10 of Pinocchio."""
    assert main(["verify", str(REPO / "robots" / "scara.yaml"), "--method", "jacobian-newton-euler",
                 "--states", "10"]) == 0
    out = capsys.readouterr().out
    assert "jacobian-newton-euler" in out and out.count(" ok") == 9


def test_verify_a_one_joint_robot_and_a_negative_seed(tmp_path, capsys):
    """A one-joint robot's Jacobian (6 x 1) is compared as a matrix on both sides; a negative
    --seed is a one-line error, not an internal one."""
    path = tmp_path / "one.yaml"
    path.write_text("format: 1\nname: one\nconvention: standard\nlinks:\n  - {joint: revolute, a: 0.4, alpha: 0, "
                    "d: 0, theta: 0, mass: 1.0, com: [0.2, 0, 0], inertia: [0.01, 0.01, 0.01, 0, 0, 0]}\n")
    assert main(["verify", str(path), "--states", "3"]) == 0
    out = capsys.readouterr().out
    assert "FAIL" not in out and any(line.split()[:1] == ["jacobian"] and line.endswith("ok") for line in out.splitlines())
    assert main(["verify", str(path), "--seed", "-1"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--seed must be a non-negative integer" in err[0]


def test_help_names_inputs_as_they_are(capsys):
    """Every subcommand that reads robots calls its input ROBOT (robot files, URDFs, scenes and
    platforms are all accepted), none says 'Denavit-Hartenberg robot file', and verify names
    the extra the README installs ([verify])."""
    from symdyn.cli import SUBCOMMANDS
    for name in ["", *SUBCOMMANDS]:
        assert main([name, "--help"] if name else ["--help"]) == 0
        text = capsys.readouterr().out
        assert "ROBOT.yaml" not in text and "Denavit-Hartenberg robot file" not in text, name
    main(["verify", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "symdyn[verify]" in text and "symdyn[test]" not in text
    assert 'pip install ".[verify]"' in (REPO / "README.md").read_text().splitlines()[7]


@pytest.mark.parametrize("size", ["-1", "nan", "inf"])
def test_c_file_size_must_be_a_size(tmp_path, capsys, size):
    assert main(["generate", PUMA, "--out", str(tmp_path / "out"), "--c-file-mb", size]) == 1
    assert "--c-file-mb" in one_error_line(capsys)
    assert not (tmp_path / "out").exists()


def test_c_over_its_file_size_is_written_as_several_files(tmp_path, capsys):
    """--c-file-mb: C over that size in several files (one warning line names them all), 0: one file."""
    assert main(["generate", PUMA, "--out", str(tmp_path / "several"), "--c-file-mb", "0.02",
                 "--functions", "inverse_dynamics,mass_matrix,coriolis_matrix"]) == 0
    captured = capsys.readouterr()
    written = sorted(os.listdir(tmp_path / "several"))
    assert written == ["puma560_dynamics.c", "puma560_dynamics.h", "puma560_dynamics_2.c", "puma560_dynamics_3.c"]
    warning = [line for line in captured.err.splitlines() if "written as 3 files" in line]
    assert len(warning) == 1 and "puma560_dynamics_3.c" in warning[0]
    assert main(["generate", PUMA, "--out", str(tmp_path / "one"), "--c-file-mb", "0",
                 "--functions", "inverse_dynamics,mass_matrix,coriolis_matrix"]) == 0
    assert sorted(os.listdir(tmp_path / "one")) == ["puma560_dynamics.c", "puma560_dynamics.h"]


def test_an_earlier_runs_extra_c_file_is_named(tmp_path, capsys):
    """A run that writes fewer C files than an earlier one into the same folder names the
    earlier run's extra file in one warning (compiled with the new ones it would bring back old code)."""
    out = str(tmp_path / "out")
    functions = ["--functions", "inverse_dynamics,mass_matrix,coriolis_matrix"]
    assert main(["generate", PUMA, "--out", out, "--c-file-mb", "0.02", *functions]) == 0
    capsys.readouterr()
    assert main(["generate", PUMA, "--out", out, *functions]) == 0
    err = capsys.readouterr().err.splitlines()
    stale = [line for line in err if "from an earlier run" in line]
    assert len(stale) == 2 and "puma560_dynamics_2.c" in stale[0] and "puma560_dynamics_3.c" in stale[1]
