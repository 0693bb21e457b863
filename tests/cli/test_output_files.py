"""Writing output files safely (symdyn.model.files): modes, refusing links/devices/inputs, one
transaction per run, roll-forward of an interrupted commit, concurrent runs, and the output
directory checked before any derivation."""

import os
import pathlib
import shutil
import signal
import stat
import subprocess
import sys
import textwrap

import pytest

import symdyn.emit.pipeline as pipeline
from symdyn.model.scene import input_files
import symdyn.model.files as files
from symdyn.cli import main
from symdyn.model.errors import SymdynError
from symdyn.model.files import JOURNAL, TEMP_PREFIX, OutputError, lock_directory, write_files

REPO = pathlib.Path(__file__).resolve().parents[2]
ROBOT = str(REPO / "robots" / "planar2r.yaml")
NAMES = ["planar2r_dynamics.c", "planar2r_dynamics.h"]


def generate(out, *extra, functions="gravity"):
    return main(["generate", ROBOT, "--out", str(out), "--quiet", "--functions", functions, *extra])


def error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("symdyn: error: "), err
    return err[0]


def contents(directory) -> dict:
    return {name: (pathlib.Path(directory) / name).read_bytes() for name in sorted(os.listdir(directory))}


def snapshot(root: pathlib.Path) -> dict:
    return {str(p): (p.stat().st_mtime_ns, p.stat().st_size) for p in sorted(root.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def cache_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("cache")


@pytest.fixture(autouse=True)
def isolated(cache_dir, monkeypatch):
    """A private derivation cache, and no file of the repository's robots/ changes."""
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(cache_dir))
    before = snapshot(REPO / "robots")
    yield
    assert snapshot(REPO / "robots") == before


@pytest.fixture
def umask022():
    old = os.umask(0o022)
    yield
    os.umask(old)


# ---------------------------------------------------------------------------------------------
# 1. Modes

@pytest.mark.parametrize("umask, expected", [(0o022, 0o644), (0o027, 0o640)])
def test_new_files_get_the_umask_mode(tmp_path, umask, expected):
    old = os.umask(umask)
    try:
        assert generate(tmp_path / "out") == 0
    finally:
        os.umask(old)
    for name in NAMES:
        assert stat.S_IMODE(os.stat(tmp_path / "out" / name).st_mode) == expected


def test_replaced_file_keeps_its_mode(tmp_path, umask022):
    out = tmp_path / "out"
    assert generate(out) == 0
    os.chmod(out / NAMES[0], 0o640)
    os.chmod(out / NAMES[1], 0o604)
    inodes = [os.stat(out / name).st_ino for name in NAMES]
    assert generate(out, functions="gravity,mass_matrix") == 0
    assert [os.stat(out / name).st_ino for name in NAMES] != inodes  # really replaced
    assert stat.S_IMODE(os.stat(out / NAMES[0]).st_mode) == 0o640
    assert stat.S_IMODE(os.stat(out / NAMES[1]).st_mode) == 0o604


def test_write_atomic_mode_and_umask(tmp_path, umask022):
    files.write_atomic(str(tmp_path / "a"), b"1")
    files.write_atomic(str(tmp_path / "b"), b"2", mode=0o600)
    assert stat.S_IMODE(os.stat(tmp_path / "a").st_mode) == 0o644
    assert stat.S_IMODE(os.stat(tmp_path / "b").st_mode) == 0o600
    assert (tmp_path / "a").read_bytes() == b"1"


# ---------------------------------------------------------------------------------------------
# 2. Only regular files are replaced

@pytest.mark.parametrize("link_target", ["outside", "/proc/self/fd/1"])
def test_symlink_at_a_target_is_refused(tmp_path, capsys, link_target):
    outside = tmp_path / "outside.txt"
    outside.write_bytes(b"precious\n")
    target = str(outside) if link_target == "outside" else link_target
    out = tmp_path / "out"
    out.mkdir()
    link = out / "planar2r_dynamics.h"
    os.symlink(target, link)
    assert generate(out) == 1
    line = error_line(capsys)
    assert str(link) in line and "symbolic link" in line
    assert os.path.islink(link) and os.readlink(link) == target
    assert outside.read_bytes() == b"precious\n"
    assert os.listdir(out) == ["planar2r_dynamics.h"]  # nothing else written


def test_fifo_at_a_target_is_refused_without_blocking(tmp_path, capsys):
    class Blocked(BaseException):
        pass

    def alarm(signum, frame):
        raise Blocked("the write blocked on the FIFO")
    out = tmp_path / "out"
    out.mkdir()
    os.mkfifo(out / "planar2r_dynamics.c")
    previous = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(20)
    try:
        assert generate(out) == 1
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    line = error_line(capsys)
    assert str(out / "planar2r_dynamics.c") in line and "FIFO" in line
    assert stat.S_ISFIFO(os.lstat(out / "planar2r_dynamics.c").st_mode)
    assert os.listdir(out) == ["planar2r_dynamics.c"]


def test_directory_at_a_target_is_refused(tmp_path, capsys):
    out = tmp_path / "out"
    (out / "planar2r_dynamics.h").mkdir(parents=True)
    assert generate(out) == 1
    line = error_line(capsys)
    assert str(out / "planar2r_dynamics.h") in line and "directory" in line
    assert os.listdir(out) == ["planar2r_dynamics.h"] and os.listdir(out / "planar2r_dynamics.h") == []


# ---------------------------------------------------------------------------------------------
# 3. Inputs are never overwritten

def test_protected_input_is_never_overwritten(tmp_path):
    robot = tmp_path / "robot.yaml"
    robot.write_bytes(b"original")
    os.link(robot, tmp_path / "alias.yaml")  # the same file under another name
    for name in ("robot.yaml", "alias.yaml"):
        with pytest.raises(SymdynError, match="input file"):
            write_files(str(tmp_path), {name: b"x"}, protect=[str(robot)])
        assert robot.read_bytes() == b"original"
    assert sorted(os.listdir(tmp_path)) == ["alias.yaml", "robot.yaml"]
    write_files(str(tmp_path), {"robot.yaml": b"x"})  # without protect it would have been replaced
    assert robot.read_bytes() == b"x"


def test_derive_out_onto_its_own_input_is_refused(tmp_path, capsys):
    robot = tmp_path / "r.yaml"
    robot.write_bytes(pathlib.Path(ROBOT).read_bytes())
    before = robot.read_bytes()
    assert main(["derive", str(robot), "--out", str(robot)]) == 1
    assert "input file" in error_line(capsys)
    assert robot.read_bytes() == before and os.listdir(tmp_path) == ["r.yaml"]


def test_input_files_of_a_scene_name_its_robot():
    scene = REPO / "robots" / "scenes" / "puma560_gravity.yaml"
    paths = input_files(str(scene))
    assert os.path.samefile(paths[0], scene)
    assert any(os.path.exists(p) and os.path.samefile(p, REPO / "robots" / "puma560.yaml") for p in paths)


# ---------------------------------------------------------------------------------------------
# 4. One unit: failures leave the old files, never temporaries

def _fail_on_second_rename(monkeypatch, exc):
    real = os.replace
    calls = []

    def replace(src, dst, **kwargs):
        if str(src).startswith(TEMP_PREFIX) and str(src).endswith(".new"):
            calls.append(dst)
            if len(calls) == 2:
                raise exc
        return real(src, dst, **kwargs)
    monkeypatch.setattr(os, "replace", replace)
    return calls


def test_failed_rename_leaves_the_old_pair(tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    assert generate(out) == 0
    before = contents(out)
    calls = _fail_on_second_rename(monkeypatch, OSError(5, "Input/output error"))
    assert generate(out, functions="gravity,mass_matrix") == 1
    assert len(calls) == 2  # the first file had been renamed: it was put back
    assert "Input/output error" in error_line(capsys)
    assert contents(out) == before


def test_failed_rename_of_new_files_leaves_nothing(tmp_path, capsys, monkeypatch):
    _fail_on_second_rename(monkeypatch, OSError(28, "No space left on device"))
    out = tmp_path / "out"
    out.mkdir()
    assert generate(out) == 1
    error_line(capsys)
    assert os.listdir(out) == []


def test_interrupt_while_writing_temporaries(tmp_path, monkeypatch):
    write_files(str(tmp_path), {"a.h": b"old h", "a.c": b"old c"})
    real, calls = os.fsync, []

    def fsync(fd):
        calls.append(fd)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(fd)
    monkeypatch.setattr(os, "fsync", fsync)
    with pytest.raises(KeyboardInterrupt):
        write_files(str(tmp_path), {"a.h": b"new h", "a.c": b"new c"})
    assert contents(tmp_path) == {"a.c": b"old c", "a.h": b"old h"}


def test_interrupt_during_the_renames_completes_the_commit(tmp_path, monkeypatch):
    """A ^C that reached Python just before the signals were blocked surfaces in the renames:
    the commit is finished first."""
    write_files(str(tmp_path), {"a.h": b"old h", "a.c": b"old c"})
    real, calls = os.replace, []

    def replace(src, dst, **kwargs):
        result = real(src, dst, **kwargs)
        if str(src).endswith(".new"):
            calls.append(dst)
            if len(calls) == 1:
                raise KeyboardInterrupt
        return result
    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(KeyboardInterrupt):
        write_files(str(tmp_path), {"a.h": b"new h", "a.c": b"new c"})
    assert contents(tmp_path) == {"a.c": b"new c", "a.h": b"new h"}


def test_signals_are_blocked_during_the_renames(tmp_path, monkeypatch):
    real, masks = os.replace, []

    def replace(src, dst, **kwargs):
        if str(src).endswith(".new"):
            masks.append(signal.pthread_sigmask(signal.SIG_BLOCK, []))
        return real(src, dst, **kwargs)
    monkeypatch.setattr(os, "replace", replace)
    before = signal.pthread_sigmask(signal.SIG_BLOCK, [])
    write_files(str(tmp_path), {"a.h": b"h", "a.c": b"c"})
    assert len(masks) == 2
    for mask in masks:
        assert {signal.SIGINT, signal.SIGTERM, signal.SIGHUP} <= mask
    assert signal.pthread_sigmask(signal.SIG_BLOCK, []) == before  # unblocked after


# A writer killed with SIGKILL at a chosen point of the commit (or of the rollback).
KILLED_WRITER = textwrap.dedent("""
    import os, signal, sys
    import symdyn.model.files as files
    directory, mode = sys.argv[1], sys.argv[2]
    real = os.replace
    renamed = []

    def replace(src, dst, **kwargs):
        if mode == "commit" and src.endswith(".new") and renamed:
            os.kill(os.getpid(), signal.SIGKILL)  # after the first rename
        if mode == "rollback" and src.endswith(".new") and renamed:
            raise OSError(5, "Input/output error")  # the second rename fails ...
        if mode == "rollback" and src.endswith(".old"):
            os.kill(os.getpid(), signal.SIGKILL)  # ... and the rollback is killed
        result = real(src, dst, **kwargs)
        if src.endswith(".new"):
            renamed.append(dst)
        return result
    os.replace = replace
    files.write_files(directory, {"a.h": b"new h", "a.c": b"new c"})
""")


@pytest.mark.parametrize("mode, expected", [("commit", b"new"), ("rollback", b"old")])
def test_killed_write_is_completed_by_the_next_one(tmp_path, mode, expected):
    write_files(str(tmp_path), {"a.h": b"old h", "a.c": b"old c"})
    run = subprocess.run([sys.executable, "-c", KILLED_WRITER, str(tmp_path), mode], timeout=60)
    assert run.returncode == -signal.SIGKILL
    left = os.listdir(tmp_path)
    assert JOURNAL in left and any(name.startswith(TEMP_PREFIX) for name in left)  # really cut short
    assert contents(tmp_path)["a.h"] == b"new h" and contents(tmp_path)["a.c"] == b"old c"  # a mixed pair
    before = sorted(os.listdir(tmp_path))
    # a write of other files does not replay into a.h and a.c: refused, nothing changed
    pending = "a.c, a.h" if mode == "commit" else "a.h"  # the rollback puts back a.h only
    with pytest.raises(OutputError, match=f"an interrupted symdyn write of {pending} is pending"):
        write_files(str(tmp_path), {"other.txt": b"x"})
    assert sorted(os.listdir(tmp_path)) == before and contents(tmp_path)["a.c"] == b"old c"
    if mode == "commit":  # a write of a.h alone would leave a.c pending: refused too
        with pytest.raises(OutputError, match="pending"):
            write_files(str(tmp_path), {"a.h": b"x"})
    write_files(str(tmp_path), {"a.h": expected + b" h", "a.c": expected + b" c", "other.txt": b"x"})
    assert sorted(os.listdir(tmp_path)) == ["a.c", "a.h", "other.txt"]  # journal and temporaries gone
    assert contents(tmp_path) == {"a.c": expected + b" c", "a.h": expected + b" h", "other.txt": b"x"}


def test_planted_temporaries_are_left_alone(tmp_path):
    """A file named like a symdyn temporary that symdyn did not make there is not deleted."""
    (tmp_path / ".symdyn-tmp-0123456789abcdef-0123456789abcdef.new").write_bytes(b"someone's file")
    (tmp_path / ".symdyn-tmp-notes").write_bytes(b"another")
    write_files(str(tmp_path), {"a.h": b"h"})
    assert contents(tmp_path) == {".symdyn-tmp-0123456789abcdef-0123456789abcdef.new": b"someone's file",
                                  ".symdyn-tmp-notes": b"another", "a.h": b"h"}


def test_a_copied_journal_is_refused(tmp_path):
    """A journal symdyn wrote is bound to its directory and its own inode (and the user's
    secret): a copy of the directory (as a clone of a repository would be) is refused in one
    line, and nothing in it changes."""
    original = tmp_path / "original"
    original.mkdir()
    write_files(str(original), {"a.h": b"old h", "a.c": b"old c"})
    run = subprocess.run([sys.executable, "-c", KILLED_WRITER, str(original), "commit"], timeout=60)
    assert run.returncode == -signal.SIGKILL
    copy = tmp_path / "copy"
    shutil.copytree(original, copy)
    snapshot = contents(copy)
    with pytest.raises(OutputError, match="was not written by symdyn on this machine for this directory"):
        write_files(str(copy), {"a.h": b"x", "a.c": b"y"})
    assert contents(copy) == snapshot


@pytest.mark.parametrize("version", [1, 2])
def test_planted_journal_never_replaces_a_file(tmp_path, capsys, version):
    """A .symdyn-commit and .symdyn-tmp-* committed to a repository (so owned by whoever
    clones it) that would rename a temporary over the Makefile: generate, convert, derive and
    identify refuse in one line and leave every file as it was."""
    from symdyn.cli import main
    out = tmp_path / "out"
    out.mkdir()
    (out / "Makefile").write_bytes(b"all:\n\tmake real\n")
    (out / ".symdyn-tmp-0123456789abcdef-0000000000000000.new").write_bytes(b"evil: rm -rf ~\n")
    mac = "" if version == 1 else "mac\t" + "0" * 64 + "\n"
    (out / ".symdyn-commit").write_bytes(f"symdyn-commit {version}\n{mac}rename\t.symdyn-tmp-0123456789abcdef-"
                                         "0000000000000000.new\tMakefile\n".encode())
    (out / ".symdyn-tmp-planted").write_bytes(b"a planted file")
    snapshot = contents(out)
    robot = str(REPO / "robots" / "planar2r.yaml")
    import numpy as np
    import symdyn
    from symdyn.model.samples import Samples, write_samples
    numeric = str(REPO / "robots" / "puma560.yaml")
    eqs = symdyn.derive(symdyn.load(numeric), outputs=["inverse_dynamics"])
    rng = np.random.default_rng(0)
    q, qd, qdd = (rng.uniform(-2, 2, (150, 6)) for _ in range(3))
    tau = np.array([eqs.numeric.inverse_dynamics(*state) for state in zip(q, qd, qdd)])
    data = tmp_path / "samples.csv"
    data.write_text(write_samples(Samples(q, qd, qdd, tau)))  # the file's own dynamics: physical values
    for argv in (["generate", robot, "--out", str(out)], ["convert", numeric, "--to", "urdf", "--out", str(out / "a.urdf")],
                 ["derive", robot, "--out", str(out / "d.txt")],
                 ["identify", numeric, str(data), "--out", str(out / "identified.yaml")]):
        assert main(argv) == 1, argv
        err = [line for line in capsys.readouterr().err.strip().splitlines() if "warning" not in line]
        assert len(err) == 1 and ".symdyn-commit" in err[0] and "nothing was written" in err[0], (argv, err)
        assert contents(out) == snapshot, argv


# ---------------------------------------------------------------------------------------------
# 5. Concurrent writers take turns

CONCURRENT_WRITER = textwrap.dedent("""
    import os, sys, time
    from symdyn.model.files import JOURNAL, TEMP_PREFIX, lock_directory, write_files
    directory, me, ready = sys.argv[1], sys.argv[2], sys.argv[3]
    open(os.path.join(ready, me), "w").close()
    deadline = time.time() + 30
    while len(os.listdir(ready)) < 2 and time.time() < deadline:
        time.sleep(0.001)
    for i in range(20):
        marker = f"{me} {i}\\n".encode() * 500
        write_files(directory, {"pair.h": marker, "pair.c": marker})
        with lock_directory(directory):
            names = os.listdir(directory)
            assert sorted(names) == ["pair.c", "pair.h"], names
            with open(os.path.join(directory, "pair.h"), "rb") as h, open(os.path.join(directory, "pair.c"), "rb") as c:
                assert h.read() == c.read(), "mixed pair"
    print("ok")
""")


def test_concurrent_writers_never_mix_a_pair(tmp_path):
    out, ready = tmp_path / "out", tmp_path / "ready"
    out.mkdir()
    ready.mkdir()
    procs = [subprocess.Popen([sys.executable, "-c", CONCURRENT_WRITER, str(out), name, str(ready)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for name in ("A", "B")]
    results = [proc.communicate(timeout=60) for proc in procs]
    for proc, (stdout, stderr) in zip(procs, results):
        assert proc.returncode == 0 and stdout.strip() == "ok", stderr
    final = contents(out)
    assert sorted(final) == ["pair.c", "pair.h"]
    assert final["pair.h"] == final["pair.c"] and final["pair.h"].split(b"\n")[0] in (b"A 19", b"B 19")


# ---------------------------------------------------------------------------------------------
# 6. The output directory is checked before deriving

@pytest.fixture
def no_derivation(monkeypatch):
    def derive_cached(*args, **kwargs):
        raise AssertionError("derived before the output directory was checked")
    monkeypatch.setattr(pipeline, "derive_cached", derive_cached)


def test_out_is_a_file(tmp_path, capsys, no_derivation):
    target = tmp_path / "file"
    target.write_bytes(b"keep")
    assert generate(target) == 1
    line = error_line(capsys)
    assert f"--out {target} is a file, not a directory" in line
    assert target.read_bytes() == b"keep"


def test_unwritable_out_is_refused_before_deriving(tmp_path, capsys, monkeypatch, no_derivation):
    """Root passes os.access: the probe (create and remove a temporary) is what catches it."""
    def probe(directory):
        raise PermissionError(13, "Permission denied")
    monkeypatch.setattr(files, "_probe_writable", probe)
    out = tmp_path / "new" / "out"
    assert generate(out) == 1
    line = error_line(capsys)
    assert "not writable" in line and str(out) in line
    assert not (tmp_path / "new").exists()  # the directories it created are removed again


def test_probe_really_writes(tmp_path):
    files._probe_writable(str(tmp_path))
    assert os.listdir(tmp_path) == []
    with pytest.raises(OSError):
        files._probe_writable(str(tmp_path / "missing"))


def test_failed_derivation_removes_the_directory_it_created(tmp_path, capsys, no_derivation):
    assert generate(tmp_path / "a" / "b") == 3  # the fake derivation's AssertionError: an internal error
    assert "derived before" in capsys.readouterr().err
    assert os.listdir(tmp_path) == []
