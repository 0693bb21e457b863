"""On-disk cache of derivations, keyed by a hash of the robot's content, the method, the outputs,
symdyn's version and the source of the derivation modules (so a changed derivation never reads
an entry written by older code, even within one version).

Entries are written atomically and carry a checksum of their payload; an entry that fails to
read, has the wrong key or the wrong checksum is ignored and rebuilt, never trusted.  The cache
lives in ``$SYMDYN_CACHE_DIR``, else ``$XDG_CACHE_HOME/symdyn``, else ``~/.cache/symdyn``.
"""

from __future__ import annotations

import functools
import hashlib
import os
import pickle

import sympy as sp

from .._version import __version__
from ..model.files import write_atomic
from .equations import Equations, derive
from .program import Program

MAGIC = b"SYMDYN-CACHE-1\n"


def cache_dir() -> str:
    base = os.environ.get("SYMDYN_CACHE_DIR")
    if not base:
        xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        base = os.path.join(xdg, "symdyn")
    return base


def robot_fingerprint(robot) -> str:
    """Hash of everything in a robot that affects its equations (not where it was read from)."""
    parts = [robot.name, robot.convention, sp.srepr(tuple(robot.gravity)),
             sp.srepr(robot.parameters), repr(robot.runtime_names)]
    for link in robot.links:
        parts.append(link.joint)
        parts.append(sp.srepr(link.expressions()))
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()


#: modules whose code decides what a derivation produces
DERIVATION_MODULES = ("derive/chain", "derive/composite", "derive/equations", "derive/kinematics",
                      "derive/lagrange_euler", "derive/newton_euler", "derive/program", "model/expr",
                      "model/geometry", "model/outputs", "model/robot")


@functools.lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """Hash of the source of the derivation modules."""
    digest = hashlib.sha256()
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    for name in DERIVATION_MODULES:
        with open(os.path.join(package, f"{name}.py"), "rb") as handle:
            digest.update(name.encode() + b"\0" + handle.read())
    return digest.hexdigest()


def cache_key(robot, method: str, outputs) -> str:
    text = "|".join([__version__, code_fingerprint(), robot_fingerprint(robot), method,
                     ",".join(sorted(outputs))])
    return hashlib.sha256(text.encode()).hexdigest()


def _load(path: str, key: str):
    try:
        with open(path, "rb") as handle:
            blob = handle.read()
        if not blob.startswith(MAGIC):
            return None
        header, payload = blob[len(MAGIC):].split(b"\n", 1)
        stored_key, checksum = header.decode().split(" ")
        if stored_key != key or hashlib.sha256(payload).hexdigest() != checksum:
            return None
        return pickle.loads(payload)
    except Exception:  # any damage means: rebuild
        return None


def derive_cached(robot, method: str = "newton-euler", outputs=None, use_cache: bool = True) -> Equations:
    """:func:`symdyn.derive` with the on-disk cache (``use_cache=False`` bypasses it)."""
    from .equations import OUTPUTS, _normalize_method
    method = _normalize_method(method)
    wanted = tuple(o for o in OUTPUTS if o in (outputs or OUTPUTS))
    if not use_cache:
        return derive(robot, method, wanted)
    key = cache_key(robot, method, wanted)
    path = os.path.join(cache_dir(), f"{key}.pickle")
    state = _load(path, key)
    if state is not None:
        assignments, outputs_tuple, seconds = state
        from .kinematics import joint_symbols
        q, qd, qdd, tau = joint_symbols(robot.dof)
        return Equations(robot=robot, method=method, q=q, qd=qd, qdd=qdd, tau=tau,
                         program=Program(assignments), outputs=outputs_tuple, seconds=seconds)
    eqs = derive(robot, method, wanted)
    payload = pickle.dumps((eqs.program.assignments, eqs.outputs, eqs.seconds), protocol=4)
    blob = MAGIC + f"{key} {hashlib.sha256(payload).hexdigest()}\n".encode() + payload
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_atomic(path, blob)
    except OSError:
        pass  # an unwritable cache only costs time
    return eqs
