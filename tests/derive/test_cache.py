"""The derivation cache (symdyn/derive/cache.py) cannot be used to run code or to change the
generated C: entries are authenticated JSON read by a bounded decoder, the directory and key
file must be private, and nothing in place of an entry blocks or is trusted.

Every test points ``$SYMDYN_CACHE_DIR`` at its own directory; robots are small (planar2r,
three_standard) so that each derivation takes a fraction of a second."""

import json
import os
import pickle
import socket
import stat
import subprocess
import sys
import textwrap

import pytest
import sympy as sp
from symdyn.derive.tangents import TangentStep, VectorTangents

import symdyn
import symdyn.derive.cache as cache
from helpers import REPO
from symdyn.cli import main
from symdyn.derive.equations import OUTPUTS

PLANAR = str(REPO / "robots" / "planar2r.yaml")
THREE = str(REPO / "tests" / "data" / "three_standard.yaml")
OTHER_UID = 65534  # nobody


@pytest.fixture
def cache_path(tmp_path, monkeypatch):
    """A fresh cache directory (not created yet) and a fresh once-per-process warning, shown
    as the command line shows it (one ``symdyn: warning:`` line on stderr)."""
    from symdyn.cli import _warnings_as_lines
    path = tmp_path / "cache"
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(path))
    monkeypatch.setattr(cache, "_warned", False)
    with _warnings_as_lines():
        yield path


@pytest.fixture
def derive_calls(monkeypatch):
    """Counts the derivations derive_cached runs itself (0 when it read its entry)."""
    calls = []
    real = cache.derive

    def counting(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)
    monkeypatch.setattr(cache, "derive", counting)
    return calls


def entry_path(cache_path, robot_file, functions=OUTPUTS, method="newton-euler"):
    robot = symdyn.load(robot_file)
    wanted = tuple(o for o in OUTPUTS if o in functions)
    return cache_path / f"{cache.cache_key(robot, method, wanted)}.json"


def generate(robot_file, out, *extra):
    assert main(["generate", robot_file, "--out", str(out), "--quiet", *extra]) == 0
    return {p.name: p.read_bytes() for p in sorted(out.iterdir())}


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """reference(robot file, *extra options) -> {file: bytes} generated with --no-cache."""
    done = {}

    def get(robot_file, *extra):
        if (robot_file, extra) not in done:
            out = tmp_path_factory.mktemp("reference")
            done[robot_file, extra] = generate(robot_file, out, "--no-cache", *extra)
        return done[robot_file, extra]
    return get


def sign(cache_path, key: str, payload: bytes) -> bytes:
    """An entry for ``payload`` authenticated with the real key (as if the key had leaked)."""
    secret = (cache_path / cache.KEY_FILE).read_bytes()
    return cache.MAGIC + cache._mac(secret, key, payload) + b"\n" + payload


def snapshot(directory):
    return {p.name: (p.lstat().st_mode, p.lstat().st_uid, p.lstat().st_mtime_ns,
                     p.read_bytes() if p.is_file() and not p.is_symlink() else None)
            for p in sorted(directory.iterdir())}


def warning_lines(capsys):
    return [line for line in capsys.readouterr().err.splitlines() if "derivation cache" in line]


# --- the happy path ---------------------------------------------------------------------------

@pytest.mark.parametrize("robot_file, method", [(PLANAR, "newton-euler"), (THREE, "lagrange-euler")],
                         ids=["planar2r-newton-euler", "three_standard-lagrange-euler"])
def test_round_trip_reads_the_entry(cache_path, derive_calls, robot_file, method):
    robot = symdyn.load(robot_file)
    first = cache.derive_cached(robot, method)
    assert len(derive_calls) == 1
    assert stat.S_IMODE(cache_path.stat().st_mode) == 0o700
    assert stat.S_IMODE((cache_path / cache.KEY_FILE).stat().st_mode) == 0o600
    entry = entry_path(cache_path, robot_file, method=method)
    assert entry.read_bytes().startswith(cache.MAGIC)
    assert sorted(p.name for p in cache_path.iterdir()) == sorted([entry.name, cache.KEY_FILE])

    secret = (cache_path / cache.KEY_FILE).read_bytes()
    payload = entry.read_bytes().split(b"\n", 2)[2]
    assert cache._mac(secret, entry.stem, payload) != cache._mac(secret, "0" * 64, payload)  # bound to its key
    assert cache._mac(secret, entry.stem, payload) != cache._mac(os.urandom(32), entry.stem, payload)

    second = cache.derive_cached(robot, method)
    assert len(derive_calls) == 1, "the second call derived again instead of reading its entry"
    fresh = symdyn.derive(robot, method)
    assert second is not first and second == fresh == first
    assert second.program.assignments == fresh.program.assignments
    assert second.outputs == fresh.outputs
    assert second.pivots == fresh.pivots and len(second.pivots) == robot.dof
    for (s1, e1), (s2, e2) in zip(second.program.assignments, fresh.program.assignments):
        assert s1.assumptions0 == s2.assumptions0 and s1.is_real
        assert sp.srepr(e1) == sp.srepr(e2)  # the same tree, not only equal


def test_cached_generate_matches_no_cache(cache_path, tmp_path, reference, derive_calls):
    expected = reference(PLANAR)
    derive_calls.clear()
    assert generate(PLANAR, tmp_path / "a") == expected
    assert generate(PLANAR, tmp_path / "b") == expected
    assert len(derive_calls) == 1


def test_encode_decode_every_node_kind():
    x = sp.Symbol("x", real=True)
    m = sp.Symbol("m", positive=True)
    values = [
        sp.Integer(-12345678901234567890), sp.Rational(-3, 7), sp.S.Half, sp.S.Zero, sp.S.NegativeOne,
        sp.Float("0.1", 30), sp.Float(-2.5), sp.Float(0), sp.pi,
        sp.sin(x) * sp.cos(m) + sp.sign(x) * x ** sp.Rational(1, 2) - m ** -2 + sp.pi / 3,
        sp.Mul(2, x + m, evaluate=False),  # unevaluated structure is kept as it is
        sp.ImmutableMatrix([[x, 1], [m, sp.Rational(2, 3)]]),
        (("gravity", sp.ImmutableMatrix([x])), 0.125, 3, "text", ()),
        VectorTangents(2, (TangentStep(0, 0, (), ((1, x),)), TangentStep(1, 1, ((0, -2 * m),), ((0, sp.S.One),))),
                       ((0, None), (None, 1))),
        # the configuration-space functions' branches and angles
        sp.Piecewise((1 + x / 6, sp.StrictLessThan(x, sp.Rational(1, 4))), (sp.sin(x) / x, True)),
        2 * sp.atan2(m, x), sp.StrictLessThan(x, 0),
    ]
    for value in values:
        tree = json.loads(json.dumps(cache.encode(value)))
        back = cache.decode(tree)
        assert back == value and type(back) is type(value)
        assert sp.srepr(back) == sp.srepr(value)
    back = cache.decode(cache.encode(m))
    assert back.assumptions0 == m.assumptions0 and back.is_positive
    f = sp.Float("0.1", 30)
    assert cache.decode(cache.encode(f))._mpf_ == f._mpf_ and cache.decode(cache.encode(f))._prec == f._prec


def test_encoder_refuses_other_types():
    for value in (sp.Function("f")(sp.Symbol("x")), sp.Dummy("d"), sp.exp(sp.Symbol("x")), True,
                  sp.oo, {"a": 1}, sp.Integer(10) ** 5000):
        with pytest.raises(cache.CacheFormatError):
            cache.encode(value)


def deep(depth, leaf=("Int", "1")):
    tree = list(leaf)
    for _ in range(depth):
        tree = ["sin", tree]
    return tree


BAD_TREES = {
    "unknown kind": ["exp", ["Int", "1"]],
    "a class name": ["Symbol", "x"],
    "not a list": {"Int": "1"},
    "empty node": [],
    "huge integer": ["Int", "9" * 100_000],
    "unicode digits": ["Int", "\u0661\u0662"],
    "zero denominator": ["Rat", "1", "0"],
    "negative denominator": ["Rat", "1", "-2"],
    "bad assumption": ["Sym", "x", {"__class__": True}],
    "assumption not a bool": ["Sym", "x", {"real": 1}],
    "contradictory assumptions": ["Sym", "x", {"positive": True, "negative": True}],
    "long name": ["Sym", "x" * 10_000, {}],
    "empty name": ["Sym", "", {}],
    "infinite float": ["PyFloat", "1e999"],
    "nan": ["PyFloat", "nan"],
    "Add of one": ["Add", ["Int", "1"]],
    "Pow of three": ["Pow", ["Int", "1"], ["Int", "2"], ["Int", "3"]],
    "sin of two": ["sin", ["Int", "1"], ["Int", "2"]],
    "sin of a string": ["sin", ["Str", "x"]],
    "Matrix shape": ["Matrix", 2, 2, ["Int", "1"]],
    "Matrix header": ["Matrix", 1],
    "Program of numbers": ["Program", ["Tuple", ["Tuple", ["Int", "1"], ["Int", "2"]]]],
    "Piecewise without a default": ["Piecewise", ["Tuple", ["Int", "1"], ["Lt", ["Int", "1"], ["Int", "2"]]]],
    "Piecewise of a number": ["Piecewise", ["Int", "1"]],
    "Piecewise with a number for a condition": ["Piecewise", ["Tuple", ["Int", "1"], ["Int", "1"]]],
    "atan2 of one": ["atan2", ["Int", "1"]],
    "Lt of three": ["Lt", ["Int", "1"], ["Int", "2"], ["Int", "3"]],
    "deep": deep(20_000),
    # a step reading a tangent not yet written, and one in a direction out of range
    "Tangents forward reference": ["Tangents", ["Tuple", ["PyInt", "2"], ["Tuple", ["Tuple", ["PyInt", "0"], ["PyInt", "0"],
                                   ["Tuple", ["Tuple", ["PyInt", "0"], ["Int", "1"]]], ["Tuple"]]], ["Tuple"]]],
    "Tangents direction": ["Tangents", ["Tuple", ["PyInt", "2"], ["Tuple", ["Tuple", ["PyInt", "0"], ["PyInt", "0"],
                           ["Tuple"], ["Tuple", ["Tuple", ["PyInt", "5"], ["Int", "1"]]]]], ["Tuple"]]],
}


@pytest.mark.parametrize("name", sorted(BAD_TREES))
def test_decoder_refuses(name):
    with pytest.raises(cache.CacheFormatError):
        cache.decode(BAD_TREES[name])


def test_decoder_limits(monkeypatch):
    """Exactly MAX_DEPTH levels and MAX_NODES nodes are accepted, one more is refused."""
    value = sp.Integer(1)
    for _ in range(cache.MAX_DEPTH):
        value = sp.sin(value, evaluate=False)
    assert cache.decode(deep(cache.MAX_DEPTH)) == value
    with pytest.raises(cache.CacheFormatError):
        cache.decode(deep(cache.MAX_DEPTH + 1))
    monkeypatch.setattr(cache, "MAX_NODES", 1000)
    assert len(cache.decode(["Tuple"] + [["Int", "1"]] * 999)) == 999
    with pytest.raises(cache.CacheFormatError):
        cache.decode(["Tuple"] + [["Int", "1"]] * 1000)


# --- planted, tampered and damaged entries ----------------------------------------------------

class Planted:
    """Unpickling this creates the marker file (a stand-in for running any code)."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        return (open, (self.marker, "w"))


@pytest.mark.parametrize("framing", ["old header", "old header, old name", "new header"])
def test_planted_pickle_is_never_loaded(cache_path, tmp_path, reference, framing):
    marker = tmp_path / "marker"
    payload = pickle.dumps(Planted(str(marker)), protocol=4)
    proof = tmp_path / "proof"  # such a payload is live: loading it does create its marker
    pickle.loads(pickle.dumps(Planted(str(proof)), protocol=4))
    assert proof.exists()

    entry = entry_path(cache_path, PLANAR)
    key = entry.stem
    if framing.startswith("old"):
        import hashlib
        blob = b"SYMDYN-CACHE-1\n" + f"{key} {hashlib.sha256(payload).hexdigest()}\n".encode() + payload
    else:
        blob = cache.MAGIC + cache._mac(b"guessed key", key, payload) + b"\n" + payload
    cache_path.mkdir(mode=0o700)
    (entry.with_suffix(".pickle") if framing.endswith("old name") else entry).write_bytes(blob)

    assert generate(PLANAR, tmp_path / "out") == reference(PLANAR)
    assert not marker.exists()
    assert cache._load(str(entry), key) is not None  # rebuilt as a valid entry
    assert generate(PLANAR, tmp_path / "out2") == reference(PLANAR)
    assert not marker.exists()


def test_tampered_entry_is_not_trusted(cache_path, tmp_path, reference):
    functions = ("--functions", "gravity")
    assert generate(THREE, tmp_path / "a", *functions) == reference(THREE, *functions)
    entry = entry_path(cache_path, THREE, ["gravity"])
    key = entry.stem
    payload = entry.read_bytes().split(b"\n", 2)[2]
    assert payload.count(b'["Rat","981","100"]') >= 1
    doubled = payload.replace(b'["Rat","981","100"]', b'["Rat","981","50"]')

    # with the real key, the change does reach the C: the checks below can fail
    entry.write_bytes(sign(cache_path, key, doubled))
    assert generate(THREE, tmp_path / "b", *functions) != reference(THREE, *functions)

    import hashlib
    for checksum in (hashlib.sha256(doubled).hexdigest().encode(),
                     hashlib.sha256(key.encode() + b"\n" + doubled).hexdigest().encode(),
                     cache._mac(b"", key, doubled), cache._mac(b"\0" * 32, key, doubled)):
        entry.write_bytes(cache.MAGIC + checksum + b"\n" + doubled)
        assert generate(THREE, tmp_path / "c", *functions) == reference(THREE, *functions)
        rewritten = entry.read_bytes().split(b"\n", 2)[2]  # with the true value
        assert rewritten.count(b'["Rat","981","100"]') == payload.count(b'["Rat","981","100"]')


def signed_payloads(cache_path, entry):
    """Entries that pass the MAC (as if written with the real key) but not the decoder."""
    key = entry.stem

    def doc(tree_text, key=key):  # JSON text built by hand: json.dumps cannot nest 20,000 deep
        fields = ",".join(f'"{name}":{tree_text}' for name in cache.stored_fields())
        return f'{{"format":{cache.FORMAT},"key":"{key}","fields":{{{fields}}}}}'.encode()
    good = json.loads(entry.read_bytes().split(b"\n", 2)[2])
    return {
        "deep json": doc('["sin",' * 20_000 + '["Int","1"]' + "]" * 20_000),
        "deep raw json": b"[" * 20_000 + b"]" * 20_000,
        "huge integer string": doc('["Int","' + "9" * 1_000_000 + '"]'),
        "huge json integer": doc('["Matrix",' + "9" * 1_000_000 + ',1,["Int","1"]]'),
        "unknown kind": doc('["__import__",["Str","os"]]'),
        "missing field": json.dumps({**good, "fields": {"program": good["fields"]["program"]}}).encode(),
        "extra field": json.dumps({**good, "fields": {**good["fields"], "robot": ["Str", "x"]}}).encode(),
        "wrong key": json.dumps({**good, "key": "0" * 64}).encode(),
        "wrong outputs": json.dumps({**good, "fields": {**good["fields"], "outputs": ["Tuple"]}}).encode(),
        "not utf-8": b"\xff\xfe" + json.dumps(good).encode(),
        "nan": json.dumps({**good, "fields": {**good["fields"], "seconds": float("nan")}}).encode(),
    }


DAMAGE = ["random bytes", "empty", "truncated", "magic only", "flipped byte", "deep json",
          "deep raw json", "huge integer string", "huge json integer", "unknown kind",
          "missing field", "extra field", "wrong key", "wrong outputs", "not utf-8", "nan",
          "entry of other outputs", "too long"]


@pytest.mark.parametrize("damage", DAMAGE)
def test_damaged_entry_is_rebuilt(cache_path, tmp_path, monkeypatch, reference, derive_calls, damage):
    assert generate(PLANAR, tmp_path / "a") == reference(PLANAR)
    entry = entry_path(cache_path, PLANAR)
    good = entry.read_bytes()
    if damage == "random bytes":
        import random
        blob = random.Random(0).randbytes(100_000)
    elif damage == "empty":
        blob = b""
    elif damage == "truncated":
        blob = good[:len(good) // 2]
    elif damage == "magic only":
        blob = cache.MAGIC
    elif damage == "flipped byte":
        blob = bytearray(good)
        blob[-100] ^= 0x01
        blob = bytes(blob)
    elif damage == "entry of other outputs":
        cache.derive_cached(symdyn.load(PLANAR), outputs=["gravity"])
        blob = entry_path(cache_path, PLANAR, ["gravity"]).read_bytes()
    elif damage == "too long":  # valid and signed, but padded (with JSON whitespace) past the limit
        monkeypatch.setattr(cache, "MAX_ENTRY_BYTES", len(good) + 1000)
        blob = sign(cache_path, entry.stem, good.split(b"\n", 2)[2] + b" " * 1001)
    else:
        blob = sign(cache_path, entry.stem, signed_payloads(cache_path, entry)[damage])
    entry.write_bytes(blob)
    expected = reference(PLANAR)
    derive_calls.clear()
    assert generate(PLANAR, tmp_path / "b") == expected
    assert len(derive_calls) == 1  # derived again
    assert cache._load(str(entry), entry.stem) is not None  # and rewritten as a valid entry
    fields = cache.unpack(blob, entry.stem, (cache_path / cache.KEY_FILE).read_bytes())
    assert fields is None or cache._build(symdyn.load(PLANAR), "newton-euler", OUTPUTS, fields) is None


# --- things that are not regular files, or not ours -------------------------------------------

def test_fifo_entry_does_not_block(cache_path, tmp_path, reference):
    entry = entry_path(cache_path, PLANAR)
    cache_path.mkdir(mode=0o700)
    os.mkfifo(entry)
    out = tmp_path / "out"
    code = textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {str(REPO)!r})
        from symdyn.cli import main
        sys.exit(main(["generate", {PLANAR!r}, "--out", {str(out)!r}, "--quiet"]))
    """)
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                            env={**os.environ, "SYMDYN_CACHE_DIR": str(cache_path)})
    assert result.returncode == 0, result.stderr
    assert {p.name: p.read_bytes() for p in sorted(out.iterdir())} == reference(PLANAR)
    assert result.stderr.count("symdyn: warning: not using the derivation cache") == 1
    assert "is not a regular file" in result.stderr
    assert stat.S_ISFIFO(entry.lstat().st_mode)  # left alone


@pytest.mark.parametrize("kind", ["directory", "symlink", "socket", "other owner"])
def test_entry_that_is_not_our_regular_file_is_ignored(cache_path, tmp_path, monkeypatch, capsys,
                                                       derive_calls, kind):
    robot = symdyn.load(PLANAR)
    entry = entry_path(cache_path, PLANAR)
    cache.derive_cached(robot)  # a valid entry ...
    valid = tmp_path / "valid.json"
    os.replace(entry, valid)
    if kind == "directory":
        entry.mkdir()
    elif kind == "symlink":  # ... reachable only through a link
        entry.symlink_to(valid)
    elif kind == "socket":
        monkeypatch.chdir(cache_path)  # a socket path is limited to about 100 characters
        server = socket.socket(socket.AF_UNIX)
        server.bind(entry.name)
        server.listen()
        monkeypatch.chdir(tmp_path)
    else:
        os.replace(valid, entry)
        os.chown(entry, OTHER_UID, OTHER_UID)
    before = snapshot(cache_path)
    derive_calls.clear()
    capsys.readouterr()
    eqs = cache.derive_cached(robot)
    assert eqs == symdyn.derive(robot)
    assert len(derive_calls) == 1, "the entry was read"
    assert snapshot(cache_path) == before, "the entry was replaced"
    (line,) = warning_lines(capsys)
    assert line.startswith(f"symdyn: warning: not using the derivation cache {cache_path}: ")
    cache.derive_cached(robot)
    assert warning_lines(capsys) == []  # once per process
    if kind == "socket":
        server.close()


def make_untrusted(cache_path, tmp_path, how):
    if how == "mode 0777":
        cache_path.chmod(0o777)
    elif how == "group writable":
        cache_path.chmod(0o770)
    elif how == "other owner":
        os.chown(cache_path, OTHER_UID, OTHER_UID)
    elif how == "symlink":
        real = tmp_path / "real-cache"
        os.replace(cache_path, real)
        cache_path.symlink_to(real)
        return real
    return cache_path


@pytest.mark.parametrize("how", ["mode 0777", "group writable", "other owner", "symlink"])
def test_untrusted_directory_is_not_used(cache_path, tmp_path, capsys, reference, derive_calls, how):
    robot = symdyn.load(PLANAR)
    cache.derive_cached(robot)  # a valid entry and key, then the directory becomes untrusted
    listing = make_untrusted(cache_path, tmp_path, how)
    before = snapshot(listing)
    expected = reference(PLANAR)
    derive_calls.clear()
    capsys.readouterr()
    assert generate(PLANAR, tmp_path / "out") == expected
    assert len(derive_calls) == 1, "the entry in an untrusted directory was read"
    assert generate(PLANAR, tmp_path / "out", "--functions", "gravity")
    assert len(derive_calls) == 2
    assert snapshot(listing) == before, "something was written into an untrusted directory"
    (line,) = warning_lines(capsys)  # one line for both runs
    assert line.startswith(f"symdyn: warning: not using the derivation cache {cache_path}: ")


@pytest.mark.parametrize("how", ["mode 0644", "mode 0660", "other owner", "symlink", "fifo", "short"])
def test_key_file_must_be_private(cache_path, tmp_path, capsys, derive_calls, how):
    robot = symdyn.load(PLANAR)
    cache.derive_cached(robot)
    key_file = cache_path / cache.KEY_FILE
    if how.startswith("mode"):
        key_file.chmod(int(how.split()[1], 8))
    elif how == "other owner":
        os.chown(key_file, OTHER_UID, OTHER_UID)
    elif how == "symlink":
        private = tmp_path / "key"
        os.replace(key_file, private)
        key_file.symlink_to(private)
    elif how == "fifo":
        key_file.unlink()
        os.mkfifo(key_file)
    else:
        key_file.write_bytes(key_file.read_bytes()[:16])
    before = snapshot(cache_path)
    derive_calls.clear()
    capsys.readouterr()
    assert cache.derive_cached(robot) == symdyn.derive(robot)
    assert len(derive_calls) == 1, "the cache was used with a key file that is not private"
    assert snapshot(cache_path) == before
    (line,) = warning_lines(capsys)
    assert cache.KEY_FILE in line


def test_unwritable_cache_costs_only_time(tmp_path, monkeypatch, capsys, reference):
    (tmp_path / "file").write_text("not a directory")
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(tmp_path / "file" / "cache"))
    monkeypatch.setattr(cache, "_warned", False)
    assert generate(PLANAR, tmp_path / "out") == reference(PLANAR)
    assert len(warning_lines(capsys)) == 1


def test_cache_info_limit_and_clear(cache_path, tmp_path, capsys, monkeypatch):
    """``symdyn cache info`` shows the directory, entries, size and limit; beyond the limit the
    least recently used entries go (a hit counts as a use), and $SYMDYN_CACHE_MAX_MB sets it;
    ``symdyn cache clear`` removes every entry and nothing else (the key, a file not an entry)."""
    import os
    import time
    generate(PLANAR, tmp_path / "a", "--functions", "gravity")
    first = entry_path(cache_path, PLANAR, ("gravity",))
    assert first.is_file()
    capsys.readouterr()
    assert main(["cache", "info"]) == 0
    out = capsys.readouterr().out
    assert f"directory: {cache_path}" in out and "entries:   1 (" in out and "limit:     256.0 MB" in out
    generate(THREE, tmp_path / "b", "--functions", "gravity")
    generate(THREE, tmp_path / "c", "--functions", "mass_matrix")
    second, third = entry_path(cache_path, THREE, ("gravity",)), entry_path(cache_path, THREE, ("mass_matrix",))
    for age, path in ((100, first), (50, second), (10, third)):
        os.utime(path, (time.time() - age, time.time() - age))
    generate(PLANAR, tmp_path / "d", "--functions", "gravity")  # a hit: planar2r's entry is now the newest
    fd = os.open(cache_path, os.O_RDONLY)
    try:
        cache._trim(fd, first.stat().st_size + third.stat().st_size)
    finally:
        os.close(fd)
    assert first.is_file() and not second.is_file() and third.is_file()
    (cache_path / "notes.txt").write_text("mine")
    capsys.readouterr()
    assert main(["cache", "clear"]) == 0
    assert capsys.readouterr().out.startswith("removed 2 entries (")
    assert sorted(p.name for p in cache_path.iterdir()) == sorted([cache.KEY_FILE, "notes.txt"])
    assert main(["cache", "info"]) == 0 and "entries:   0 (0.0 MB)" in capsys.readouterr().out
    monkeypatch.setenv("SYMDYN_CACHE_MAX_MB", "0.5")
    assert cache.max_cache_bytes() == 2**19
    monkeypatch.setenv("SYMDYN_CACHE_MAX_MB", "0")  # no room: each entry goes as soon as it is written
    generate(PLANAR, tmp_path / "e", "--functions", "gravity")
    assert not first.exists() and (cache_path / "notes.txt").is_file()
    monkeypatch.setenv("SYMDYN_CACHE_MAX_MB", "lots")
    assert cache.max_cache_bytes() == cache.DEFAULT_MAX_CACHE_BYTES
