"""On-disk cache of derivations: authenticated JSON entries in a private per-user directory.

An entry is keyed (:func:`cache_key`) by a hash of the robot's content, the method, the outputs,
symdyn's version and the source of the derivation modules, so a changed derivation never reads
an entry written by older code, even within one version.  The cache lives in
``$SYMDYN_CACHE_DIR``, else ``$XDG_CACHE_HOME/symdyn``, else ``~/.cache/symdyn``.

Nothing read from the cache is ever executed or parsed as code (no pickle, no eval, no sympify):

* The directory is used only if it is a real directory (not a symbolic link) owned by the
  current user and not writable by group or others; a missing one is created with mode 0700.
  Otherwise the cache is neither read nor written and one line
  ``symdyn: warning: not using the derivation cache DIR: REASON`` goes to stderr (once per
  process).
* :data:`KEY_FILE` in it holds a random 32-byte secret (mode 0600, created atomically); it must
  be a regular file owned by the user and not readable or writable by group or others, else
  the cache is not used.
* An entry ``<cache key>.json`` is the bytes ``MAGIC``, the hex HMAC-SHA256 under the secret of
  ``cache key + b"\\n" + payload``, ``b"\\n"``, then ``payload``: UTF-8 JSON
  ``{"format": 2, "key": "<cache key>", "fields": {NAME: NODE, ...}}`` with one NODE per field
  of :class:`Equations` other than robot, method, q, qd, qdd and tau (program, outputs,
  seconds, pivots, ...).  NODE is the tree format of :func:`encode` / :func:`decode`.
* An entry is opened without following links and without blocking, must be a regular file
  owned by the user and at most :data:`MAX_ENTRY_BYTES` long.  A FIFO, socket, device,
  directory or link in its place is left alone and the derivation is not cached (with the
  warning).  An entry with a wrong MAC, wrong key or anything the decoder refuses is ignored,
  rebuilt and overwritten.
* Writes go through a temporary file in the directory and a rename (atomic); an unwritable
  cache only costs time, never an error.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import hmac
import json
import math
import os
import re
import stat

import sympy as sp

from .._version import __version__
from ..model.errors import warn
from ..model.userdir import KEY_BYTES, KEY_FILE, Untrusted, user_dir as cache_dir  # noqa: F401 (KEY_*: this module's API)
from ..model.userdir import open_private_dir as _open_dir
from ..model.userdir import read_private_file as _read_file
from ..model.userdir import secret_of as _secret
from ..model.userdir import write_private_file as _write_file
from .equations import Equations, derive
from .program import Program
from .tangents import TangentStep, VectorTangents

MAGIC = b"SYMDYN-CACHE-2\n"
FORMAT = 2
SUFFIX = ".json"

#: limits on what is read back (an entry beyond them is damaged and rebuilt)
MAX_ENTRY_BYTES = 64 * 2**20
#: the whole cache's size limit: after each new entry, the least recently used entries beyond it
#: are removed (``$SYMDYN_CACHE_MAX_MB`` overrides it; ``symdyn cache info`` shows it)
DEFAULT_MAX_CACHE_BYTES = 256 * 2**20
MAX_NODES = 4_000_000    # nodes of the whole payload tree
MAX_DEPTH = 200          # nesting of nodes (derivations reach about 10; far below the JSON parser's limit)
MAX_STRING = 256         # characters of a symbol name, output name or float text
MAX_DIGITS = 4000        # decimal digits of an integer (numerator, denominator, mantissa)

#: fields of :class:`Equations` rebuilt from the robot instead of stored
REBUILT_FIELDS = ("robot", "method", "q", "qd", "qdd", "tau")

_warned = False


#: fields of the model's dataclasses that a derivation never reads, with the reason; every
#: other field of every dataclass reachable from a robot is part of the key (a field added later
#: is in the key without anyone listing it: tests/derive/test_cache_key.py changes each one)
NOT_DERIVED = {
    ("Robot", "source"): "the path it was read from: one robot read from two places shares its entry",
    ("Robot", "source_hash"): "the file's bytes: the key holds what was read from them",
}


def canonical(value) -> str:
    """The complete canonical text of a model value: every field of a dataclass (but those of
    :data:`NOT_DERIVED`) by name, tuples, lists and dicts item by item, SymPy expressions by
    ``srepr`` (with the symbols' assumptions), Python scalars by type and ``repr``.  A value of any
    other type is a ``TypeError``: nothing can be left out of the key silently."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        kind = type(value).__name__
        items = ",".join(f"{f.name}={canonical(getattr(value, f.name))}" for f in dataclasses.fields(value)
                         if (kind, f.name) not in NOT_DERIVED)
        return f"{kind}({items})"
    if isinstance(value, (tuple, list)):
        return f"{type(value).__name__}[" + ",".join(canonical(v) for v in value) + "]"
    if isinstance(value, dict):
        return "dict{" + ",".join(f"{canonical(k)}:{canonical(v)}" for k, v in sorted(value.items(), key=repr)) + "}"
    if isinstance(value, sp.Basic):
        return sp.srepr(value)
    if value is None or isinstance(value, (bool, int, float, str)):
        return f"{type(value).__name__}:{value!r}"
    raise TypeError(f"the cache key cannot read a {type(value).__name__}")


def robot_fingerprint(robot) -> str:
    """Hash of the canonical form of everything in a robot (see :func:`canonical`)."""
    return hashlib.sha256(canonical(robot).encode()).hexdigest()


#: modules whose code decides what a derivation produces
#: the folders whose source a derivation depends on (every module in them is hashed, so a new
#: derivation module cannot be forgotten)
DERIVATION_FOLDERS = ("derive", "model")


def derivation_modules() -> tuple[str, ...]:
    """``folder/module`` of every Python module a derivation may depend on, sorted."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    return tuple(sorted(f"{folder}/{name[:-3]}" for folder in DERIVATION_FOLDERS
                        for name in os.listdir(os.path.join(package, folder)) if name.endswith(".py")))


@functools.lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """Hash of the source of the derivation modules."""
    digest = hashlib.sha256()
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    for name in derivation_modules():
        with open(os.path.join(package, f"{name}.py"), "rb") as handle:
            digest.update(name.encode() + b"\0" + handle.read())
    return digest.hexdigest()


def cache_key(robot, method: str, outputs, fd_method: str = "ldlt", parameters: str = "standard") -> str:
    """The key of a derivation: symdyn's version, the source of the derivation modules, the
    canonical form of the robot (every field), and every argument of :func:`derive`."""
    options = {"method": method, "outputs": tuple(sorted(outputs)), "fd_method": fd_method, "parameters": parameters}
    text = "\n".join([__version__, code_fingerprint(), canonical(robot), canonical(options)])
    return hashlib.sha256(text.encode()).hexdigest()


# ---------------------------------------------------------------------------------------------
# Values as JSON trees
# ---------------------------------------------------------------------------------------------
#
# Every node is a JSON array whose first item names its kind:
#
#   ["Int", "-12"]                  sympy Integer (decimal digits)
#   ["Rat", "-3", "4"]              sympy Rational p/q, q > 0
#   ["Float", "-1a2b", "-105", 103] sympy Float: (hex mantissa with sign) * 2**exp, precision bits
#   ["Sym", "q1", {"real": true}]   sympy Symbol with the assumptions it was created with
#   ["pi"]                          sympy pi
#   ["Add", a, b, ...], ["Mul", a, b, ...], ["Pow", base, exp]     (rebuilt unevaluated, as stored)
#   ["sin", x], ["cos", x], ["sign", x], ["atan2", y, x]
#   ["Piecewise", ["Tuple", expr, condition], ...]   sympy Piecewise (the last condition ["true"])
#   ["Lt", a, b]                    sympy StrictLessThan a < b;  ["true"]  sympy true
#   ["Matrix", rows, cols, e11, e12, ...]   sympy ImmutableMatrix, row-major
#   ["Tuple", a, ...]               Python tuple;  ["Str", "text"]  Python str
#   ["PyFloat", "0.25"]             Python float (finite);  ["PyInt", "3"]  Python int
#   ["Program", ["Tuple", ["Tuple", symbol, expr], ...]]            a Program's assignments
#   ["Tangents", ["Tuple", directions, steps, rows]]   a VectorTangents: each step a tuple
#                                   (group, target, terms, direct), rows with -1 for None
#
# These are exactly the node types the derivations of all bundled robots and scenes produce
# (Symbol, Integer, Rational, Add, Mul, Pow, sin, cos, sign; atan2, Piecewise and < in the
# configuration-space functions), plus pi and Float.  Anything
# else is refused by both directions.

_FUNCTIONS = {"sin": sp.sin, "cos": sp.cos, "sign": sp.sign}
_BINARY = {"atan2": sp.atan2, "Lt": sp.StrictLessThan}
_OPERATORS = {"Add": sp.Add, "Mul": sp.Mul, "Pow": sp.Pow}
_ASSUMPTIONS = frozenset((
    "algebraic", "antihermitian", "commutative", "complex", "composite", "even", "extended_negative",
    "extended_nonnegative", "extended_nonpositive", "extended_nonzero", "extended_positive",
    "extended_real", "finite", "hermitian", "imaginary", "infinite", "integer", "irrational",
    "negative", "noninteger", "nonnegative", "nonpositive", "nonzero", "odd", "polar", "positive",
    "prime", "rational", "real", "transcendental", "zero"))
_INTEGER = re.compile(r"-?[0-9]{1,%d}\Z" % MAX_DIGITS)
_HEX = re.compile(r"-?[0-9a-f]{1,%d}\Z" % MAX_DIGITS)
_FLOAT_TEXT = re.compile(r"-?[0-9]+(\.[0-9]+)?(e[-+]?[0-9]+)?\Z")


class CacheFormatError(ValueError):
    """A value cannot be stored, or stored data is not a valid tree (the entry is rebuilt)."""


def encode(value, _depth: int = 0):
    """The JSON tree of ``value`` (see the node list above); raises :class:`CacheFormatError`
    for a type outside it or a value beyond the decoder's limits (such a value is not cached)."""
    if _depth > MAX_DEPTH:
        raise CacheFormatError(f"nested more than {MAX_DEPTH} levels")
    deeper = _depth + 1
    if isinstance(value, Program):
        return ["Program", encode(tuple(value.assignments), deeper)]
    if isinstance(value, VectorTangents):
        steps = tuple((s.group, s.target, s.terms, s.direct) for s in value.steps)
        rows = tuple(tuple(-1 if r is None else r for r in group) for group in value.rows)
        return ["Tangents", encode((value.directions, steps, rows), deeper)]
    if isinstance(value, (tuple, list)):
        return ["Tuple", *(encode(v, deeper) for v in value)]
    if isinstance(value, str):
        return ["Str", _check_string(value)]
    if isinstance(value, float):
        if not math.isfinite(value):
            raise CacheFormatError(f"cannot store {value}")
        return ["PyFloat", repr(value)]
    if isinstance(value, int) and not isinstance(value, bool):
        return ["PyInt", _int_text(value)]
    if isinstance(value, sp.MatrixBase):
        rows, cols = value.shape
        return ["Matrix", rows, cols, *(encode(e, deeper) for e in value)]
    if isinstance(value, sp.Integer):
        return ["Int", _int_text(value.p)]
    if isinstance(value, sp.Rational):
        return ["Rat", _int_text(value.p), _int_text(value.q)]
    if isinstance(value, sp.Float):
        sign, man, exp, _ = value._mpf_
        if (not man and exp) or man.bit_length() > 4 * MAX_DIGITS or abs(exp) >= 10**12:  # inf, nan
            raise CacheFormatError(f"cannot store {value}")
        return ["Float", ("-" if sign else "") + format(man, "x"), str(exp), value._prec]
    if type(value) is sp.Symbol:
        (name,), assumptions = value.__getnewargs_ex__()
        return ["Sym", _check_string(name), {k: bool(v) for k, v in assumptions.items()}]
    if value is sp.pi:
        return ["pi"]
    if value is sp.true:
        return ["true"]
    if type(value) is sp.Piecewise:
        return ["Piecewise", *(encode(tuple(pair), deeper) for pair in value.args)]
    if type(value) is sp.StrictLessThan:
        return ["Lt", *(encode(a, deeper) for a in value.args)]
    kind = type(value).__name__
    if kind == "atan2" and type(value) is sp.atan2:
        return [kind, *(encode(a, deeper) for a in value.args)]
    if {**_OPERATORS, **_FUNCTIONS}.get(kind) is type(value):
        return [kind, *(encode(a, deeper) for a in value.args)]
    raise CacheFormatError(f"cannot store a {kind}")


def _check_string(text: str) -> str:
    if len(text) > MAX_STRING:
        raise CacheFormatError(f"string of {len(text)} characters")
    return text


def _int_text(number: int) -> str:
    if number.bit_length() > MAX_DIGITS * 3.32 or len(str(abs(number))) > MAX_DIGITS:
        raise CacheFormatError(f"an integer of more than {MAX_DIGITS} digits")
    return str(number)


def _leaf(node: list):
    """The value of a node without child nodes; :class:`CacheFormatError` if it is malformed."""
    kind, rest = node[0], node[1:]
    if kind == "Int" and len(rest) == 1 and _digits(rest[0]):
        return sp.Integer(int(rest[0]))
    if kind == "Rat" and len(rest) == 2 and _digits(rest[0]) and _digits(rest[1]) and int(rest[1]) > 0:
        return sp.Rational(int(rest[0]), int(rest[1]))
    if kind == "Float" and len(rest) == 3 and isinstance(rest[0], str) and _HEX.match(rest[0]) \
            and _digits(rest[1]) and len(rest[1]) <= 12 and _small(rest[2], 1, 100_000):
        man, exp = int(rest[0], 16), int(rest[1])
        return sp.Float((int(man < 0), format(abs(man), "x"), exp, abs(man).bit_length()), precision=rest[2])
    if kind == "Sym" and len(rest) == 2 and _text(rest[0]) and rest[0] and isinstance(rest[1], dict) \
            and all(k in _ASSUMPTIONS and isinstance(v, bool) for k, v in rest[1].items()):
        return sp.Symbol(rest[0], **rest[1])
    if kind == "pi" and not rest:
        return sp.pi
    if kind == "true" and not rest:
        return sp.true
    if kind == "Str" and len(rest) == 1 and _text(rest[0]):
        return rest[0]
    if kind == "PyFloat" and len(rest) == 1 and _text(rest[0]) and _FLOAT_TEXT.match(rest[0]) \
            and math.isfinite(float(rest[0])):
        return float(rest[0])
    if kind == "PyInt" and len(rest) == 1 and _digits(rest[0]):
        return int(rest[0])
    raise CacheFormatError(f"bad {kind} node")


def _digits(text) -> bool:
    return isinstance(text, str) and bool(_INTEGER.match(text))


def _text(text) -> bool:
    return isinstance(text, str) and len(text) <= MAX_STRING


def _small(number, low: int, high: int) -> bool:
    return type(number) is int and low <= number <= high


#: kinds with child nodes: the number of plain items before the children
_BRANCHES = {"Add": 0, "Mul": 0, "Pow": 0, "sin": 0, "cos": 0, "sign": 0, "Tuple": 0,
             "Program": 0, "Tangents": 0, "Matrix": 2, "atan2": 0, "Lt": 0, "Piecewise": 0}
_LEAVES = frozenset(("Int", "Rat", "Float", "Sym", "pi", "Str", "PyFloat", "PyInt", "true"))


def _branch(node: list, args: list):
    """The value of a node with child nodes, from its decoded children ``args``."""
    kind = node[0]
    if kind == "Tuple":
        return tuple(args)
    if kind == "Program":
        if len(args) == 1 and isinstance(args[0], tuple) and all(
                isinstance(a, tuple) and len(a) == 2 and type(a[0]) is sp.Symbol and isinstance(a[1], sp.Expr)
                for a in args[0]):
            return Program(args[0])
        raise CacheFormatError("bad Program node")
    if kind == "Tangents":
        if len(args) == 1:
            return _tangents(args[0])
        raise CacheFormatError("bad Tangents node")
    if kind == "Piecewise":
        if args and all(isinstance(a, tuple) and len(a) == 2 and isinstance(a[0], sp.Expr)
                        and isinstance(a[1], sp.logic.boolalg.Boolean) for a in args) and args[-1][1] is sp.true:
            return sp.Piecewise(*args, evaluate=False)
        raise CacheFormatError("bad Piecewise node")
    if not all(isinstance(a, sp.Expr) for a in args):
        raise CacheFormatError(f"{kind} of something that is not an expression")
    if kind in _BINARY:
        if len(args) != 2:
            raise CacheFormatError(f"{kind} of {len(args)} arguments")
        return _BINARY[kind](*args, evaluate=False)
    if kind == "Matrix":
        rows, cols = node[1], node[2]
        if _small(rows, 0, 10_000) and _small(cols, 0, 10_000) and rows * cols == len(args):
            return sp.ImmutableMatrix(rows, cols, args)
        raise CacheFormatError("bad Matrix node")
    if kind in _FUNCTIONS:
        if len(args) != 1:
            raise CacheFormatError(f"{kind} of {len(args)} arguments")
        return _FUNCTIONS[kind](args[0], evaluate=False)
    if len(args) < 2 or (kind == "Pow" and len(args) != 2):
        raise CacheFormatError(f"{kind} of {len(args)} arguments")
    return _OPERATORS[kind](*args, evaluate=False)


def _tangents(value) -> VectorTangents:
    """A VectorTangents from its stored tuple, checked: each step writes the next tangent id and
    reads earlier ones only, each row names a written tangent (or -1)."""
    def pairs(items, limit):
        return isinstance(items, tuple) and all(
            isinstance(p, tuple) and len(p) == 2 and type(p[0]) is int and 0 <= p[0] < limit
            and isinstance(p[1], sp.Expr) for p in items)
    if not (isinstance(value, tuple) and len(value) == 3 and type(value[0]) is int and 0 <= value[0] <= 10_000):
        raise CacheFormatError("bad Tangents node")
    directions, steps, rows = value
    built = []
    for k, step in enumerate(steps if isinstance(steps, tuple) else (None,)):
        if not (isinstance(step, tuple) and len(step) == 4 and type(step[0]) is int and step[1] == k
                and pairs(step[2], k) and pairs(step[3], directions)):
            raise CacheFormatError("bad Tangents step")
        built.append(TangentStep(*step))
    if not (isinstance(rows, tuple) and all(isinstance(r, tuple) and all(type(i) is int and -1 <= i < len(built)
                                                                       for i in r) for r in rows)):
        raise CacheFormatError("bad Tangents rows")
    return VectorTangents(directions, tuple(built), tuple(tuple(None if i < 0 else i for i in r) for r in rows))


def _construct(build, *args):
    """``build(*args)``, with any error of SymPy or Python (contradictory assumptions, ...) as a
    :class:`CacheFormatError`."""
    try:
        return build(*args)
    except CacheFormatError:
        raise
    except (ValueError, TypeError, ArithmeticError, AttributeError) as exc:
        raise CacheFormatError(f"bad {args[0][0]} node ({type(exc).__name__})") from None


def decode(tree):
    """The value of a JSON tree written by :func:`encode`, rebuilt without evaluating anything.

    Only the node kinds listed above are accepted; at most :data:`MAX_NODES` nodes nested at
    most :data:`MAX_DEPTH` deep, strings of at most :data:`MAX_STRING` characters and integers of
    at most :data:`MAX_DIGITS` digits.  Iterative (no recursion), so any input is refused with
    :class:`CacheFormatError` instead of exhausting the stack or the memory."""
    done: list = []                   # values of finished nodes, in order
    todo = [(tree, 0, False)]         # (node, depth, children already decoded)
    count = 0
    while todo:
        node, depth, expanded = todo.pop()
        if expanded:
            start = len(done) - (len(node) - 1 - _BRANCHES[node[0]])
            args = done[start:]
            del done[start:]
            done.append(_construct(_branch, node, args))
            continue
        count += 1
        if count > MAX_NODES:
            raise CacheFormatError(f"more than {MAX_NODES} nodes")
        if depth > MAX_DEPTH:
            raise CacheFormatError(f"nested more than {MAX_DEPTH} levels")
        if not isinstance(node, list) or not node or not isinstance(node[0], str):
            raise CacheFormatError("a node is not a list starting with its kind")
        kind = node[0]
        if kind in _LEAVES:
            done.append(_construct(_leaf, node))
        elif kind in _BRANCHES:
            if len(node) <= _BRANCHES[kind]:
                raise CacheFormatError(f"bad {kind} node")
            todo.append((node, depth, True))
            todo.extend((child, depth + 1, False) for child in reversed(node[1 + _BRANCHES[kind]:]))
        else:
            raise CacheFormatError(f"unknown node kind {kind[:40]!r}")
    if len(done) != 1:
        raise CacheFormatError("not one tree")
    return done[0]


# ---------------------------------------------------------------------------------------------
# Entries
# ---------------------------------------------------------------------------------------------

def stored_fields() -> tuple[str, ...]:
    """Names of the :class:`Equations` fields an entry holds (all but :data:`REBUILT_FIELDS`)."""
    return tuple(f.name for f in dataclasses.fields(Equations) if f.name not in REBUILT_FIELDS)


def _mac(secret: bytes, key: str, payload: bytes) -> bytes:
    return hmac.new(secret, key.encode() + b"\n" + payload, hashlib.sha256).hexdigest().encode()


def pack(eqs: Equations, key: str, secret: bytes) -> bytes:
    """The bytes of the entry for ``eqs`` under cache key ``key`` (see the module docstring)."""
    fields = {name: encode(getattr(eqs, name)) for name in stored_fields()}
    payload = json.dumps({"format": FORMAT, "key": key, "fields": fields},
                         separators=(",", ":"), ensure_ascii=True).encode()
    return MAGIC + _mac(secret, key, payload) + b"\n" + payload


def _refuse(text):
    raise CacheFormatError(f"unexpected JSON value {text[:20]!r}")


def _json_int(text: str) -> int:
    if len(text) > 9:
        raise CacheFormatError("JSON integer too long")
    return int(text)


def unpack(blob: bytes, key: str, secret: bytes) -> dict | None:
    """The stored fields ``{name: value}`` of an entry, or ``None`` if it is not a valid entry
    for ``key`` under ``secret`` (wrong framing, MAC, key, format or tree)."""
    if len(blob) > MAX_ENTRY_BYTES or not blob.startswith(MAGIC):
        return None
    mac, newline, payload = blob[len(MAGIC):].partition(b"\n")
    if not newline or not hmac.compare_digest(mac, _mac(secret, key, payload)):
        return None
    try:
        doc = json.loads(payload.decode("utf-8"), parse_float=_refuse, parse_constant=_refuse,
                         parse_int=_json_int)
        if not isinstance(doc, dict) or doc.get("format") != FORMAT or doc.get("key") != key:
            return None
        trees = doc.get("fields")
        if not isinstance(trees, dict) or sorted(trees) != sorted(stored_fields()):
            return None
        return {name: decode(tree) for name, tree in trees.items()}
    except (ValueError, TypeError, RecursionError, MemoryError):  # CacheFormatError is a ValueError
        return None


def _build(robot, method: str, wanted: tuple[str, ...], fields: dict) -> Equations | None:
    """Equations from stored fields, or ``None`` if they do not fit the request."""
    from .kinematics import joint_symbols
    outputs, program = fields.get("outputs"), fields.get("program")
    if not isinstance(program, Program) or not isinstance(outputs, tuple) \
            or tuple(o[0] if isinstance(o, tuple) and len(o) == 2 else None for o in outputs) != wanted \
            or not all(isinstance(m, sp.ImmutableMatrix) for _, m in outputs):
        return None
    q, qd, qdd, tau = joint_symbols(robot.nq, robot.nv)
    try:
        return Equations(robot=robot, method=method, q=q, qd=qd, qdd=qdd, tau=tau, **fields)
    except TypeError:
        return None


# ---------------------------------------------------------------------------------------------
# The directory, its key file and entry files
# ---------------------------------------------------------------------------------------------

def _warn(directory: str, reason: str) -> None:
    """One ``symdyn: warning:`` line on stderr, at most once per process."""
    global _warned
    if not _warned:
        _warned = True
        warn(f"not using the derivation cache {directory}: {reason}")


def _load(path: str, key: str):
    """The stored fields of the entry at ``path`` under cache key ``key`` (``None`` if it is
    missing, damaged, or its directory or key file is not trusted); nothing is written."""
    directory, name = os.path.split(os.path.abspath(path))
    try:
        dir_fd = _open_dir(directory)
        try:
            secret = _secret(dir_fd)
            blob = _read_file(dir_fd, name, MAX_ENTRY_BYTES)
        finally:
            os.close(dir_fd)
    except Untrusted:
        return None
    return None if blob is None else unpack(blob, key, secret)


def derive_cached(robot, method: str = "newton-euler", outputs=None, use_cache: bool = True,
                  progress=None, fd_method: str = "ldlt", parameters: str = "standard") -> Equations:
    """:func:`symdyn.derive` with the on-disk cache (``use_cache=False`` bypasses it;
    ``progress`` is passed on to the derivation when one runs; ``fd_method``: how forward
    dynamics is solved, ``'ldlt'`` or ``'aba'``)."""
    from .equations import ALL_OUTPUTS, normalize_method, default_outputs
    method = normalize_method(method)
    wanted = tuple(o for o in ALL_OUTPUTS if o in (outputs or default_outputs(robot)))
    if not use_cache:
        return derive(robot, method, wanted, progress, fd_method, parameters)
    key = cache_key(robot, method, wanted, fd_method, parameters)
    directory, name = cache_dir(), f"{key}{SUFFIX}"
    try:
        dir_fd = _open_dir(directory)
    except Untrusted as exc:
        _warn(directory, str(exc))
        return derive(robot, method, wanted, progress, fd_method, parameters)
    try:
        try:
            secret = _secret(dir_fd)
            blob = _read_file(dir_fd, name, MAX_ENTRY_BYTES)
        except Untrusted as exc:
            _warn(directory, str(exc))
            return derive(robot, method, wanted, progress, fd_method, parameters)
        if blob is not None:
            fields = unpack(blob, key, secret)
            eqs = _build(robot, method, wanted, fields) if fields is not None else None
            if eqs is not None:
                try:
                    os.utime(name, dir_fd=dir_fd, follow_symlinks=False)  # recently used: kept longest
                except (OSError, NotImplementedError):
                    pass
                return eqs
        eqs = derive(robot, method, wanted, progress, fd_method, parameters)
        try:
            _write_file(dir_fd, name, pack(eqs, key, secret))
            _trim(dir_fd, max_cache_bytes())
        except CacheFormatError as exc:
            _warn(directory, f"cannot store this derivation ({exc})")
        except OSError:
            pass  # an unwritable cache only costs time
        return eqs
    finally:
        os.close(dir_fd)


# ---------------------------------------------------------------------------------------------
# Size: what is there, the limit, trimming and clearing (``symdyn cache``)
# ---------------------------------------------------------------------------------------------

_ENTRY_NAME = re.compile(r"[0-9a-f]{16,128}" + re.escape(SUFFIX) + r"\Z")


def max_cache_bytes() -> int:
    """The cache's size limit in bytes: ``$SYMDYN_CACHE_MAX_MB`` (megabytes, at least 0) or
    :data:`DEFAULT_MAX_CACHE_BYTES`."""
    text = os.environ.get("SYMDYN_CACHE_MAX_MB", "").strip()
    try:
        value = float(text) if text else None
    except ValueError:
        value = None
    if value is None or not math.isfinite(value) or value < 0:
        return DEFAULT_MAX_CACHE_BYTES
    return int(value * 2**20)


def _entries(dir_fd: int) -> list[tuple[float, int, str]]:
    """``(last use, bytes, name)`` of every entry file in the directory (regular files of this
    user named as entries; anything else is not the cache's and is left alone)."""
    out = []
    for name in os.listdir(dir_fd):
        if not _ENTRY_NAME.match(name):
            continue
        try:
            st = os.stat(name, dir_fd=dir_fd, follow_symlinks=False)
        except OSError:
            continue
        if stat.S_ISREG(st.st_mode) and st.st_uid == os.geteuid():
            out.append((st.st_mtime, st.st_size, name))
    return sorted(out)


def _trim(dir_fd: int, limit: int) -> None:
    """Remove the least recently used entries until the entries take at most ``limit`` bytes."""
    entries = _entries(dir_fd)
    total = sum(size for _, size, _ in entries)
    for _, size, name in entries:
        if total <= limit:
            break
        try:
            os.unlink(name, dir_fd=dir_fd)
            total -= size
        except FileNotFoundError:
            total -= size
        except OSError:
            pass


@dataclasses.dataclass(frozen=True)
class CacheInfo:
    directory: str
    entries: int
    bytes: int
    limit: int
    usable: str | None  # None, or why the directory is not used


def cache_info() -> CacheInfo:
    """Where the cache is, how many entries and bytes it holds, its limit, and whether it is
    used (nothing is created or changed, except the directory itself if missing)."""
    directory = cache_dir()
    try:
        dir_fd = _open_dir(directory)
    except Untrusted as exc:
        return CacheInfo(directory, 0, 0, max_cache_bytes(), str(exc))
    try:
        entries = _entries(dir_fd)
    finally:
        os.close(dir_fd)
    return CacheInfo(directory, len(entries), sum(size for _, size, _ in entries), max_cache_bytes(), None)


def clear_cache() -> tuple[int, int]:
    """Remove every entry (the key file stays); returns ``(entries, bytes)`` removed. Raises
    :class:`Untrusted` if the directory is not one symdyn uses."""
    dir_fd = _open_dir(cache_dir())
    try:
        entries = _entries(dir_fd)
        removed = 0
        for _, size, name in entries:
            try:
                os.unlink(name, dir_fd=dir_fd)
                removed += 1
            except FileNotFoundError:
                pass
        return removed, sum(size for _, size, _ in entries)
    finally:
        os.close(dir_fd)
