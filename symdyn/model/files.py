"""Writing output and cache files safely: all of one run's files land as one unit, only regular
files are ever replaced, inputs are never overwritten, and concurrent runs take turns.

:func:`write_files` writes a set of files into one directory as a transaction;
:func:`write_atomic` is the same for one file (the derivation cache uses it);
:func:`check_output_dir` / :func:`output_directory` check (and create) an output directory before
any long work starts.  Every failure is an :class:`OutputError`: a :class:`SymdynError` (the
command line prints it as one line) that is also an :class:`OSError` (so a caller that treats any
failure to write as harmless, like the derivation cache, keeps doing so).

What a write guarantees
-----------------------
- **Modes.**  A new file gets the mode the umask gives (0644 under umask 022); a file that replaces
  an existing one keeps that file's permission bits (``rwx`` bits only: set-user-ID, set-group-ID
  and sticky are dropped); ``mode=`` forces a mode.  A temporary never has wider permissions than
  the file it becomes.
- **Only regular files are replaced.**  If a target name holds a symbolic link, a device, a FIFO,
  a socket or a directory, the whole write is refused (naming the path) before anything is
  written.  (A rename never writes through a link; the check keeps a user's link or node from being
  silently destroyed, and a refused link's target is never touched.)
- **Inputs are never overwritten.**  A target that is the same file (``st_dev``, ``st_ino``) as one
  of the ``protect`` paths (the run's input files) is refused.
- **Generated files of other inputs are kept (with ``owners``).**  An existing target is replaced
  only if its banner (read from its first :data:`BANNER_BYTES` bytes, or from the file of the set
  that speaks for it) names the same input as the file replacing it (:class:`Provenance`); a file
  of another input, or one without a symdyn banner (a file symdyn did not write), is refused in
  one line before anything is written.  ``symdyn generate`` passes ``owners`` unless ``--force``.
- **One unit.**  Every file is first written to a temporary ``.symdyn-tmp-*`` in the output
  directory and fsynced; only then are the temporaries renamed over their final names.  A failure
  before the renames (a refusal, a full disk, ^C) removes every temporary and leaves the old files
  as they were.  A rename that fails half-way puts back the files already renamed (from hard links
  to the old files taken just before), so the old set stays whole.
- **Serialized.**  An exclusive ``flock`` on the output directory itself (an ``O_RDONLY``
  descriptor of it: no lock file) is held from the first check to the last rename, so concurrent
  symdyn runs into one directory take turns; a reader that wants a consistent set takes it too
  (:func:`lock_directory`).
- **Signals.**  SIGINT, SIGTERM and SIGHUP are blocked while the renames run and delivered right
  after, so ^C or ``kill`` cannot leave a new ``.h`` next to an old ``.c``.  (If a ^C arrived just
  before the block, Python may raise ``KeyboardInterrupt`` inside the renames: they are then
  completed before it propagates.)
- **Journal.**  Before the renames, ``.symdyn-commit`` (written atomically) lists them; it is removed
  after.  If the process dies between the two (SIGKILL, power loss), the next write into the
  directory that writes every file the journal names, under the lock, *rolls the commit
  forward*: it completes the renames whose temporaries still exist, then deletes leftover symdyn
  temporaries.  A rollback after a failed rename is journaled the same way, so an interrupted
  rollback is completed too.  A write of other files is refused while a journal is pending
  (the message names the files and how to finish or drop it): a journal never replaces a file
  the run would not itself write.
- **Only symdyn's own traces are acted on.**  Temporaries carry a tag and the journal a MAC,
  HMAC-SHA256 under the per-user secret (:mod:`symdyn.model.userdir`), bound to the directory's
  device and inode and, for the journal, to its own inode.  A journal that does not verify
  (planted in a repository, copied with a directory, written without a usable secret) is
  refused in one line and nothing is changed; a ``.symdyn-tmp-*`` file without a valid tag is
  never deleted nor renamed.

What it does not guarantee
--------------------------
- Until the next symdyn write into the directory, a commit cut short by SIGKILL stays half done
  (some files new, some old, temporaries and the journal present).
- A reader that does not take the lock can see, during the few microseconds of the renames, a new
  file next to an old one.
- ``flock`` is advisory and only serializes symdyn runs; where a directory cannot be locked (NFS
  emulates ``flock`` with byte-range locks, which need a writable descriptor) the write goes ahead
  unlocked.  Another program changing the directory between the checks and the renames is not
  prevented (the renames still never follow links).
- A journal owned by another user is not acted on: the write is refused with a message saying so.
- Blocking signals covers the calling thread: in a multi-threaded program a signal delivered to
  another thread still reaches Python's handler (the renames are then completed as above).
- The owner and group of a replaced file are not kept (the new file belongs to the writer).
- A second failure *during* the rollback of a failed rename (an I/O error, or SIGKILL when the
  rollback journal could not be written) can leave a mixed set.

POSIX only (``fcntl``, ``dir_fd``); directories are handled through a descriptor, so renaming or
replacing the output directory's path during a write does not redirect it.
"""

from __future__ import annotations

import contextlib
import gc
import hashlib
import hmac
import os
import re
import secrets
import signal
import stat
from dataclasses import dataclass
from typing import Iterable, Iterator, Mapping

try:
    import fcntl
except ImportError:  # not POSIX: no locking
    fcntl = None

from .errors import SymdynError, one_line
from .userdir import read_at_most, user_secret

#: prefix of every temporary symdyn creates in an output directory (and deletes when left over)
TEMP_PREFIX = ".symdyn-tmp-"
#: name of the commit journal in an output directory
JOURNAL = ".symdyn-commit"
_JOURNAL_HEADER = b"symdyn-commit 2\n"
_MAX_JOURNAL = 1 << 20
_SIGNALS = {getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)}
_O_CLOEXEC = getattr(os, "O_CLOEXEC", 0)
_O_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_O_NONBLOCK = getattr(os, "O_NONBLOCK", 0)
_O_DIRECTORY = getattr(os, "O_DIRECTORY", 0)
_CREATE = os.O_WRONLY | os.O_CREAT | os.O_EXCL | _O_NOFOLLOW | _O_CLOEXEC


class OutputError(SymdynError, OSError):
    """A file could not be written, or writing it was refused (one line, naming the path)."""


def _reason(exc: OSError) -> str:
    return exc.strerror or str(exc)


def _kind(mode: int) -> str:
    """What a non-regular directory entry is, in words."""
    if stat.S_ISLNK(mode):
        return "a symbolic link"
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    return "a special file"


def _check_name(name: str) -> None:
    """A target must be a plain file name of the directory, outside symdyn's own names."""
    if (not isinstance(name, str) or name in ("", ".", "..") or "/" in name or os.sep in name
            or any(ord(ch) < 32 or ord(ch) == 127 for ch in name)
            or name.startswith(TEMP_PREFIX) or name == JOURNAL):
        raise OutputError(f"cannot write a file named {one_line(repr(name), 120)}: not a plain file name")


class _Signer:
    """Marks what symdyn writes into one output directory so that only this user's symdyn on
    this machine acts on it later: temporaries carry a tag and journals a MAC, both HMAC-SHA256
    under the per-user secret (:mod:`symdyn.model.userdir`) bound to the directory's device and
    inode (and a journal to its own inode).  A copy of the directory (a clone of a repository
    with a planted ``.symdyn-commit`` or ``.symdyn-tmp-*``) carries neither the secret nor the
    inodes.  Without a usable secret nothing is ever recognized as symdyn's."""

    def __init__(self, dfd: int):
        info = os.fstat(dfd)
        self.where = b"%d|%d" % (info.st_dev, info.st_ino)
        self.secret = user_secret()

    def _mac(self, kind: bytes, data: bytes) -> str:
        return hmac.new(self.secret or b"", kind + b"|" + self.where + b"|" + data, hashlib.sha256).hexdigest()

    def temp_name(self, suffix: str) -> str:
        """A new temporary's name: ``.symdyn-tmp-<random>-<tag><suffix>``."""
        token = secrets.token_hex(8)
        tag = self._mac(b"tmp", token.encode())[:16] if self.secret else "0" * 16
        return f"{TEMP_PREFIX}{token}-{tag}{suffix}"

    def is_ours(self, name: str) -> bool:
        """Whether ``name`` is a temporary symdyn made in this directory with this secret."""
        if not self.secret or not name.startswith(TEMP_PREFIX):
            return False
        token, _, rest = name[len(TEMP_PREFIX):].partition("-")
        return len(token) == 16 and hmac.compare_digest(rest[:16], self._mac(b"tmp", token.encode())[:16])

    def journal_mac(self, inode: int, body: bytes) -> str:
        return self._mac(b"journal", b"%d|" % inode + body) if self.secret else ""


# ---------------------------------------------------------------------------------------------
# The output directory: checked before the work, locked during the write

def check_output_dir(directory: str, option: str = "--out") -> list[str]:
    """Make sure ``directory`` can receive output, before any long work: create it (and its
    missing parents) if missing, refuse a path that exists and is not a directory
    (``"--out X is a file, not a directory"``; ``option`` names the option in the message) and a
    directory that is not writable (asked with ``os.access`` and, since root passes that, by
    creating and removing a temporary there).  Returns the directories it created, outermost
    first (see :func:`output_directory`).  Raises :class:`OutputError`."""
    directory = os.fspath(directory)
    try:
        info = os.stat(directory)
    except OSError:
        info = None
    if info is not None and not stat.S_ISDIR(info.st_mode):
        what = "a file" if stat.S_ISREG(info.st_mode) else _kind(info.st_mode)
        raise OutputError(f"{option} {directory} is {what}, not a directory")
    created = []
    if info is None:
        missing, path = [], os.path.abspath(directory)
        while not os.path.lexists(path) and path != os.path.dirname(path):
            missing.append(path)
            path = os.path.dirname(path)
        try:
            os.makedirs(directory, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"cannot create output directory {directory}: {_reason(exc)}") from None
        created = missing[::-1]
    try:
        if not os.access(directory, os.W_OK | os.X_OK):
            raise OutputError(f"output directory {directory} is not writable")
        try:
            _probe_writable(directory)
        except OSError as exc:
            raise OutputError(f"output directory {directory} is not writable: {_reason(exc)}") from None
    except BaseException:
        _remove_dirs(created)
        raise
    return created


def _probe_writable(directory: str) -> None:
    """Create and remove a temporary in ``directory``; raises OSError if that is not possible."""
    path = os.path.join(directory, f"{TEMP_PREFIX}probe-{secrets.token_hex(6)}")
    os.close(os.open(path, _CREATE, 0o600))
    with contextlib.suppress(FileNotFoundError):  # a concurrent write's clean-up may beat us to it
        os.unlink(path)


def _remove_dirs(created: list[str]) -> None:
    """Remove the directories :func:`check_output_dir` created, innermost first, if still empty."""
    for path in reversed(created):
        try:
            os.rmdir(path)
        except OSError:
            break


@contextlib.contextmanager
def output_directory(directory: str, option: str = "--out") -> Iterator[str]:
    """``with output_directory(out):`` runs :func:`check_output_dir` and, if the body then fails,
    removes the directories it created (when empty), so a failed run leaves no trace."""
    created = check_output_dir(directory, option)
    try:
        yield directory
    except MemoryError as exc:
        # at a memory limit (--max-memory) the failed run's data is still held by the traceback's
        # frames: let it go first, so that the clean-up itself can allocate
        exc.__traceback__ = None
        gc.collect()
        _remove_dirs(created)
        raise
    except BaseException:
        _remove_dirs(created)
        raise


@contextlib.contextmanager
def lock_directory(directory: str) -> Iterator[int]:
    """Hold the exclusive symdyn lock of ``directory`` (``flock`` on a descriptor of the directory
    itself); yields that descriptor.  Blocks while another symdyn write into it runs.  Where the
    file system cannot lock a directory, yields without the lock."""
    try:
        dfd = os.open(directory, os.O_RDONLY | _O_DIRECTORY | _O_CLOEXEC)
    except OSError as exc:
        raise OutputError(f"cannot open output directory {directory}: {_reason(exc)}") from None
    try:
        if fcntl is not None:
            try:
                fcntl.flock(dfd, fcntl.LOCK_EX)
            except OSError:
                pass  # e.g. NFS (EBADF/ENOLCK): documented as unlocked
        yield dfd
    finally:
        os.close(dfd)  # releases the lock


def _block_signals():
    """Block SIGINT/SIGTERM/SIGHUP for this thread; returns what to restore (None: nothing)."""
    if not hasattr(signal, "pthread_sigmask"):
        return None
    return signal.pthread_sigmask(signal.SIG_BLOCK, _SIGNALS)


def _restore_signals(previous) -> None:
    """Restore the mask; a signal that came meanwhile is delivered now."""
    if previous is not None:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _file_ids(paths: Iterable[str]) -> set[tuple[int, int]]:
    """(st_dev, st_ino) of each existing path (and of a link itself when a path is a link)."""
    ids = set()
    for path in paths:
        for follow in (True, False):
            try:
                info = os.stat(path, follow_symlinks=follow)
            except (OSError, ValueError):
                continue
            ids.add((info.st_dev, info.st_ino))
    return ids


def _check_target(dfd: int, directory: str, name: str, protected) -> int | None:
    """Refuse to replace anything but a regular file that is not an input; returns the
    permission bits of the file being replaced, None when the name is free."""
    path = os.path.join(directory, name)
    try:
        info = os.stat(name, dir_fd=dfd, follow_symlinks=False)
    except FileNotFoundError:
        return None
    except OSError as exc:
        raise OutputError(f"cannot write {path}: {_reason(exc)}") from None
    if not stat.S_ISREG(info.st_mode):
        what = _kind(info.st_mode)
        if stat.S_ISLNK(info.st_mode):
            with contextlib.suppress(OSError):
                what += f" to {one_line(os.readlink(name, dir_fd=dfd), 200)}"
        raise OutputError(f"refusing to replace {path}: it is {what}, not a regular file "
                          "(nothing was written; remove it or write elsewhere)")
    if (info.st_dev, info.st_ino) in protected:
        raise OutputError(f"refusing to overwrite {path}: it is an input file of this run (nothing was written)")
    return stat.S_IMODE(info.st_mode) & 0o777


# ---------------------------------------------------------------------------------------------
# Provenance: the input a generated file was made from, as its banner says

#: how much of an existing file is read to find its banner
BANNER_BYTES = 4096
#: the line every banner symdyn writes has (templates/banner.j2, the CasADi descriptions)
_BANNER_MARK = re.compile(rb"GENERATED FILES? \S{1,4} DO NOT EDIT\. Regenerate (?:it|them) with symdyn")
_BANNER_FIELD = re.compile(rb"^[ \t/*#%>]*(input|sha256)[ \t]*:[ \t]*([^\r\n]*?)[ \t]*$", re.M)
#: what a refusal to replace another input's file suggests (the options of symdyn generate)
ADVICE = "use --name to write beside it, or --force to replace it"


@dataclass(frozen=True)
class Provenance:
    """The input a generated file was made from, as its banner names it: ``input`` (the input's
    file name as banners print it) and ``sha256`` (of the input's content).  ``banner``: for a
    file without a banner of its own (a binary ``.casadi`` file), the file of the same set whose
    banner speaks for it, else ``""``."""

    input: str
    sha256: str
    banner: str = ""

    def same_input(self, other: "Provenance") -> bool:
        """Whether ``other`` names the same input: the same file name (an edited input file is
        regenerated in place) or the same content (a copy under another name)."""
        return self.input == other.input or (bool(self.sha256) and self.sha256 == other.sha256)


def read_provenance(head: bytes) -> Provenance | None:
    """The provenance a symdyn banner in ``head`` (the start of a file) gives, or None when
    there is no banner (not a file symdyn generated) or it does not name an input and its hash."""
    if not _BANNER_MARK.search(head):
        return None
    fields: dict[str, str] = {}
    for match in _BANNER_FIELD.finditer(head):
        fields.setdefault(match.group(1).decode(), match.group(2).decode("utf-8", "replace"))
    if "input" not in fields or "sha256" not in fields:
        return None
    return Provenance(fields["input"], fields["sha256"])


def _read_head(dfd: int, name: str) -> bytes | None:
    """The first :data:`BANNER_BYTES` bytes of the regular file ``name`` (no link followed, no
    blocking open), or None when there is no such file."""
    try:
        fd = os.open(name, os.O_RDONLY | _O_NOFOLLOW | _O_NONBLOCK | _O_CLOEXEC, dir_fd=dfd)
    except FileNotFoundError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        return read_at_most(fd, BANNER_BYTES)
    finally:
        os.close(fd)


def _check_owners(dfd: int, directory: str, names, owners: Mapping[str, Provenance], advice: str) -> None:
    """Refuse (one line, nothing written) to replace an existing file that does not name the
    input ``owners`` gives for it (see :class:`Provenance`)."""
    heads: dict[str, bytes | None] = {}
    for name in names:
        wanted = owners.get(name)
        if wanted is None or _lstat(dfd, name) is None:
            continue
        path = os.path.join(directory, name)
        source = wanted.banner or name
        try:
            if source not in heads:
                heads[source] = _read_head(dfd, source)
        except OSError as exc:
            raise OutputError(f"cannot read {os.path.join(directory, source)}: {_reason(exc)}") from None
        head = heads[source]
        if head is None:
            raise OutputError(f"refusing to replace {path}: {one_line(source, 120)}, which would say what it was "
                              f"generated from, is missing (nothing was written): {advice}")
        found = read_provenance(head)
        if found is None:
            where = "its" if source == name else f"{one_line(source, 120)}'s"
            raise OutputError(f"refusing to replace {path}: it was not generated by symdyn (no symdyn banner naming "
                              f"its input in {where} first {BANNER_BYTES} bytes; nothing was written): {advice}")
        if not found.same_input(wanted):
            raise OutputError(f"{path} was generated from {one_line(found.input, 160)} (sha256 "
                              f"{one_line(found.sha256, 64)}), not from {one_line(wanted.input, 160)}: {advice}")


def check_targets(directory: str, names: Iterable[str], protect: Iterable[str] = ()) -> None:
    """Check, without writing, that :func:`write_files` would accept ``names`` in ``directory``
    (plain names; no link, device, FIFO, socket, directory or input file in the way); for an early
    refusal before long work.  Raises :class:`OutputError`."""
    names = list(names)
    for name in names:
        _check_name(name)
    protected = _file_ids(protect)
    try:
        dfd = os.open(directory, os.O_RDONLY | _O_DIRECTORY | _O_CLOEXEC)
    except OSError as exc:
        raise OutputError(f"cannot open output directory {directory}: {_reason(exc)}") from None
    try:
        for name in names:
            _check_target(dfd, directory, name, protected)
    finally:
        os.close(dfd)


# ---------------------------------------------------------------------------------------------
# The journal: a list of ("rename", src, dst) and ("unlink", dst, inode) steps, replayed at most once

def _journal_body(steps) -> bytes:
    return b"".join(b"\t".join((op.encode(), os.fsencode(str(a)), os.fsencode(str(b)))) + b"\n"
                    for op, a, b in steps)


def _encode_journal(steps, mac: str) -> bytes:
    return _JOURNAL_HEADER + b"mac\t" + mac.encode() + b"\n" + _journal_body(steps)


def _parse_journal(data: bytes):
    """``(mac, body, steps)`` of a journal (None if it is not one); lines that are not
    well-formed symdyn steps are dropped from the steps (the MAC covers the whole body)."""
    if not data.startswith(_JOURNAL_HEADER):
        return None
    first, _, body = data[len(_JOURNAL_HEADER):].partition(b"\n")
    if not first.startswith(b"mac\t"):
        return None
    mac = first[4:].decode("ascii", "replace")
    steps = []
    for line in body.split(b"\n"):
        parts = line.split(b"\t")
        if len(parts) != 3:
            continue
        op, a, b = parts[0], os.fsdecode(parts[1]), os.fsdecode(parts[2])
        try:
            if op == b"rename" and a.startswith(TEMP_PREFIX) and "/" not in a:
                _check_name(b)
                steps.append(("rename", a, b))
            elif op == b"unlink" and b.isdigit():
                _check_name(a)
                steps.append(("unlink", a, int(b)))
        except OutputError:
            continue
    return mac, body, steps


def _lstat(dfd: int, name: str):
    try:
        return os.stat(name, dir_fd=dfd, follow_symlinks=False)
    except FileNotFoundError:
        return None


def _replay(dfd: int, steps, protected, signer: _Signer | None = None) -> None:
    """Apply journal steps that are still pending (idempotent): rename a temporary that still
    exists over its target (unless the target is not a regular file or is an input); unlink a
    target that is still the file the journal created.  With ``signer`` (a journal read back
    from the directory), only temporaries symdyn made there are renamed."""
    euid = os.geteuid()
    for op, a, b in steps:
        if op == "rename":
            if signer is not None and not signer.is_ours(a):
                continue
            src, dst = _lstat(dfd, a), _lstat(dfd, b)
            if src is None or not stat.S_ISREG(src.st_mode):
                continue  # already renamed
            if dst is not None and (not stat.S_ISREG(dst.st_mode) or (dst.st_dev, dst.st_ino) in protected):
                continue
            os.replace(a, b, src_dir_fd=dfd, dst_dir_fd=dfd)
        else:
            dst = _lstat(dfd, a)
            if dst is not None and stat.S_ISREG(dst.st_mode) and dst.st_ino == b and dst.st_uid == euid:
                os.unlink(a, dir_fd=dfd)


def _pending_steps(dfd: int, directory: str, signer: _Signer, names) -> list | None:
    """The steps of the journal in the directory, if there is one this user's symdyn wrote there
    and every file it would replace is one the current run writes (``names``); raises
    :class:`OutputError` (one line, nothing touched) for any other journal."""
    journal_path = os.path.join(directory, JOURNAL)
    info = _lstat(dfd, JOURNAL)
    if info is None:
        return None
    if not stat.S_ISREG(info.st_mode):
        raise OutputError(f"{journal_path} is {_kind(info.st_mode)}, not a symdyn journal: remove it")
    if info.st_uid != os.geteuid():
        raise OutputError(f"{journal_path}: an interrupted write by another user (uid {info.st_uid}) "
                          "is pending in this directory: run symdyn there as that user, or remove the file")
    fd = os.open(JOURNAL, os.O_RDONLY | _O_NOFOLLOW | _O_NONBLOCK | _O_CLOEXEC, dir_fd=dfd)
    try:
        inode = os.fstat(fd).st_ino
        data = os.read(fd, _MAX_JOURNAL)
    finally:
        os.close(fd)
    parsed = _parse_journal(data)
    expected = signer.journal_mac(inode, parsed[1]) if parsed is not None else ""
    if parsed is None or not expected or not hmac.compare_digest(parsed[0], expected):
        raise OutputError(f"{journal_path} was not written by symdyn on this machine for this directory "
                          "(copied or planted?): nothing was written and no file was changed; remove it")
    steps = parsed[2]
    others = sorted({step[1] if step[0] == "unlink" else step[2] for step in steps} - set(names))
    if others:
        raise OutputError(f"an interrupted symdyn write of {', '.join(others)} is pending in {directory}: "
                          "run the command that wrote them again (it finishes that write first), or remove "
                          f"{journal_path} to keep the files as they are; nothing was written")
    return steps


def _recover(dfd: int, directory: str, protected, names=()) -> _Signer:
    """Under the lock: finish a commit (or rollback) this user's symdyn left half done in the
    directory (when it only replaces files the current run writes, ``names``), then delete the
    leftover temporaries symdyn made there.  A journal or temporary it did not make is never
    acted on.  Returns the directory's signer, for the run's own temporaries and journal."""
    signer = _Signer(dfd)
    try:
        steps = _pending_steps(dfd, directory, signer, names)
        if steps is not None:
            blocked = _block_signals()
            try:
                _replay(dfd, steps, protected, signer)
                os.fsync(dfd)
                os.unlink(JOURNAL, dir_fd=dfd)
                os.fsync(dfd)
            finally:
                _restore_signals(blocked)
        for name in os.listdir(dfd):
            if signer.is_ours(name):
                leftover = _lstat(dfd, name)
                if leftover is not None and stat.S_ISREG(leftover.st_mode):
                    with contextlib.suppress(FileNotFoundError, PermissionError):  # sticky directory
                        os.unlink(name, dir_fd=dfd)
    except OSError as exc:
        if isinstance(exc, OutputError):
            raise
        raise OutputError(f"cannot finish an interrupted write in {directory}: {_reason(exc)}") from None
    return signer


# ---------------------------------------------------------------------------------------------
# The transaction

class _Transaction:
    """Temporaries of one write in a locked directory, and their commit or removal."""

    def __init__(self, dfd: int, directory: str, signer: _Signer):
        self.dfd = dfd
        self.directory = directory
        self.signer = signer
        self.staged: list[list] = []  # [temp, final, inode, backup or None]
        self.scratch: list[str] = []  # every name this transaction created (removed at the end)
        self.unresolved = False  # a journal is in place that the next run must replay

    def _path(self, name: str) -> str:
        return os.path.join(self.directory, name)

    def _create(self, suffix: str, mode: int) -> tuple[str, int]:
        while True:
            name = self.signer.temp_name(suffix)
            self.scratch.append(name)  # before creating: an interrupt right after still cleans up
            try:
                return name, os.open(name, _CREATE, mode, dir_fd=self.dfd)
            except FileExistsError:
                self.scratch.pop()

    def _write(self, fd: int, data: bytes) -> None:
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
        os.fsync(fd)

    def stage(self, final: str, data: bytes, mode: int | None) -> None:
        """Write ``data`` to a new temporary (fsynced) that will become ``final`` with ``mode``
        (None: the umask's)."""
        try:
            # created 0600 when a mode will be set, so that no one can open it with wider rights
            temp, fd = self._create(".new", 0o666 if mode is None else 0o600)
            try:
                if mode is not None:
                    os.fchmod(fd, mode)
                self._write(fd, bytes(data))
                inode = os.fstat(fd).st_ino
            finally:
                os.close(fd)
        except OSError as exc:
            raise OutputError(f"cannot write {self._path(final)}: {_reason(exc)}") from None
        self.staged.append([temp, final, inode, None])

    def _backup(self, entry) -> None:
        """Keep the file ``entry`` replaces under a temporary name (a hard link, else a copy)."""
        final = entry[1]
        if _lstat(self.dfd, final) is None:
            return
        while True:
            name = self.signer.temp_name(".old")
            self.scratch.append(name)
            try:
                os.link(final, name, src_dir_fd=self.dfd, dst_dir_fd=self.dfd, follow_symlinks=False)
                break
            except FileExistsError:
                self.scratch.pop()
            except OSError:  # no hard links here: copy
                self.scratch.pop()
                name = self._copy(final)
                break
        entry[3] = name

    def _copy(self, final: str) -> str:
        src = os.open(final, os.O_RDONLY | _O_NOFOLLOW | _O_NONBLOCK | _O_CLOEXEC, dir_fd=self.dfd)
        try:
            info = os.fstat(src)
            if not stat.S_ISREG(info.st_mode):
                raise OSError(0, f"it became {_kind(info.st_mode)}")
            name, dst = self._create(".old", 0o600)
            try:
                os.fchmod(dst, stat.S_IMODE(info.st_mode) & 0o777)
                chunks = []
                while chunk := os.read(src, 1 << 20):
                    chunks.append(chunk)
                self._write(dst, b"".join(chunks))
            finally:
                os.close(dst)
        finally:
            os.close(src)
        return name

    def _journal(self, steps) -> None:
        """Atomically put ``steps`` in place as the directory's journal."""
        name, fd = self._create(".journal", 0o600)
        try:  # the MAC binds the journal to its own inode (the rename keeps it) and the directory
            self._write(fd, _encode_journal(steps, self.signer.journal_mac(os.fstat(fd).st_ino, _journal_body(steps))))
        finally:
            os.close(fd)
        os.replace(name, JOURNAL, src_dir_fd=self.dfd, dst_dir_fd=self.dfd)
        os.fsync(self.dfd)
        self.unresolved = True

    def _close_journal(self) -> None:
        os.fsync(self.dfd)
        with contextlib.suppress(FileNotFoundError):
            os.unlink(JOURNAL, dir_fd=self.dfd)
        self.unresolved = False

    def commit(self) -> None:
        """Rename every temporary over its final name, as one unit (see the module docstring).
        The journal in place is the commit point: from then on an interrupt completes the commit."""
        try:
            for entry in self.staged:
                self._backup(entry)
        except OSError as exc:
            raise OutputError(f"cannot write into {self.directory}: {_reason(exc)}") from None
        blocked = _block_signals()
        try:
            try:
                self._journal([("rename", temp, final) for temp, final, _, _ in self.staged])
            except BaseException as exc:
                if self.unresolved:  # a ^C right after the journal was in place and synced:
                    self._finish()  # the commit point was passed
                    raise
                with contextlib.suppress(OSError):
                    os.unlink(JOURNAL, dir_fd=self.dfd)
                if isinstance(exc, OSError) and not isinstance(exc, OutputError):
                    raise OutputError(f"cannot write into {self.directory}: {_reason(exc)}") from None
                raise
            done = 0
            try:
                for temp, final, _, _ in self.staged:
                    os.replace(temp, final, src_dir_fd=self.dfd, dst_dir_fd=self.dfd)
                    done += 1
            except OSError as exc:
                self._rollback(self.staged[:done], exc)
            except BaseException:
                # a signal that reached Python just before the block: the commit point was
                # passed, so finish the commit, then let the interrupt through
                self._finish()
                raise
            try:
                self._close_journal()
            except OSError:
                pass  # the files are in place; a journal left behind is replayed harmlessly
            self.discard()
        finally:
            _restore_signals(blocked)

    def _finish(self) -> None:
        """Complete the journaled renames (idempotent: one that already happened is skipped)."""
        _replay(self.dfd, [("rename", temp, final) for temp, final, _, _ in self.staged], set())
        self._close_journal()

    def _rollback(self, done, exc: OSError) -> None:
        """Put back what the first ``done`` renames replaced, then raise the failure."""
        failed = self.staged[len(done)][1]
        steps = [("rename", backup, final) if backup else ("unlink", final, inode)
                 for _, final, inode, backup in done]
        try:
            self._journal(steps)  # an interrupted rollback is completed by the next run
        except OSError:
            pass  # the commit journal stays; a kill now may leave a mixed set (documented)
        try:
            _replay(self.dfd, steps, set())
            self._close_journal()
        except OSError as again:
            raise OutputError(f"cannot write {self._path(failed)}: {_reason(exc)}; putting back the "
                              f"previous files failed too ({_reason(again)}): the next symdyn write into "
                              f"{self.directory} will finish it") from None
        self.discard()
        raise OutputError(f"cannot write {self._path(failed)}: {_reason(exc)} "
                          "(the previous files were left as they were)") from None

    def discard(self) -> None:
        """Remove every temporary this transaction created, unless a journal still needs them."""
        if self.unresolved:
            return
        for name in self.scratch:
            with contextlib.suppress(OSError):
                os.unlink(name, dir_fd=self.dfd)
        self.scratch = []


def write_files(directory: str, files: Mapping[str, bytes], protect: Iterable[str] = (), *,
                mode: int | None = None, owners: Mapping[str, Provenance] | None = None,
                advice: str = ADVICE) -> list[str]:
    """Write ``files`` ({plain file name: content}) into the existing ``directory`` as one unit.

    ``protect``: paths of the run's input files, which are never overwritten.  ``mode``: the
    permission bits of every file (default: the umask's for a new file, the old file's for a
    replaced one).  ``owners``: ``{file name: Provenance}`` of generated files; an existing file
    is then replaced only if its banner names the same input (else the write is refused, in one
    line ending in ``advice``).  Returns the paths written, in the order of ``files``.  Raises
    :class:`OutputError` (nothing changed, except for the documented double faults); the
    guarantees are in the module docstring."""
    names = list(files)
    for name in names:
        _check_name(name)
    if not names:
        return []
    protected = _file_ids(protect)
    with lock_directory(directory) as dfd:
        signer = _recover(dfd, directory, protected, names)
        modes = {name: _check_target(dfd, directory, name, protected) for name in names}
        if owners is not None:
            _check_owners(dfd, directory, names, owners, advice)
        transaction = _Transaction(dfd, directory, signer)
        try:
            for name in names:
                transaction.stage(name, files[name], mode if mode is not None else modes[name])
            transaction.commit()
        except BaseException:
            transaction.discard()
            raise
    return [os.path.join(directory, name) for name in names]


def write_atomic(path: str, data: bytes, *, mode: int | None = None, protect: Iterable[str] = ()) -> None:
    """Replace ``path`` with ``data`` atomically: :func:`write_files` for one file, in the
    directory of ``path`` (which must exist).  Raises :class:`OutputError` (an OSError)."""
    directory, name = os.path.split(os.path.abspath(os.fspath(path)))
    write_files(directory, {name: data}, protect, mode=mode)
