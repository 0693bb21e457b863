"""The private per-user directory of symdyn (the derivation cache's) and its secret key.

The directory is ``$SYMDYN_CACHE_DIR``, else ``$XDG_CACHE_HOME/symdyn``, else
``~/.cache/symdyn``.  It is used only if it is a real directory (not a symbolic link) owned by
the current user and not writable by group or others (a missing one is created with mode
0700).  :data:`KEY_FILE` in it holds a random 32-byte secret (mode 0600, created atomically): it
authenticates the cache's entries (:mod:`symdyn.derive.cache`) and the commit journals and
temporaries of output directories (:mod:`symdyn.model.files`), which a copy of a directory
(a clone of a repository) cannot carry.
"""

from __future__ import annotations

import os
import secrets
import stat

KEY_FILE = "hmac-key"
KEY_BYTES = 32


class Untrusted(Exception):
    """The cache directory (or an entry in it) must not be used; the message says why."""


def user_dir() -> str:
    """Where the directory is (see the module docstring); nothing is created."""
    base = os.environ.get("SYMDYN_CACHE_DIR")
    if not base:
        xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        base = os.path.join(xdg, "symdyn")
    return base


def open_private_dir(path: str) -> int:
    """A descriptor of the cache directory (created with mode 0700 if missing); raises
    :class:`Untrusted` unless it is a directory, not a link, owned by this user and not
    writable by group or others."""
    if not hasattr(os, "geteuid"):
        raise Untrusted("file ownership cannot be checked on this system")
    try:
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        os.mkdir(path, 0o700)
    except FileExistsError:
        pass  # checked below, whatever it is
    except OSError as exc:
        raise Untrusted(f"cannot create it ({exc.strerror})") from None
    try:
        if stat.S_ISLNK(os.lstat(path).st_mode):
            raise Untrusted("it is a symbolic link")
        fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC)
    except OSError as exc:
        raise Untrusted(f"cannot open it ({exc.strerror})") from None
    st = os.fstat(fd)
    reason = (None if stat.S_ISDIR(st.st_mode) else "it is not a directory") \
        or (f"it is owned by uid {st.st_uid}, not by uid {os.geteuid()}" if st.st_uid != os.geteuid() else None) \
        or ("it is writable by group or others" if st.st_mode & 0o022 else None)
    if reason:
        os.close(fd)
        raise Untrusted(reason)
    return fd


def read_private_file(dir_fd: int, name: str, limit: int, private: bool = False) -> bytes | None:
    """Contents of ``name`` in the directory: ``None`` if missing, at most ``limit + 1`` bytes.
    Never follows a link nor blocks; raises :class:`Untrusted` for anything but a regular file
    owned by this user (``private``: and not readable or writable by group or others)."""
    try:
        st = os.stat(name, dir_fd=dir_fd, follow_symlinks=False)
    except FileNotFoundError:
        return None
    except OSError as exc:
        raise Untrusted(f"cannot read {name} ({exc.strerror})") from None
    check_regular(name, st)
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | os.O_NOFOLLOW | os.O_CLOEXEC, dir_fd=dir_fd)
    except FileNotFoundError:
        return None
    except OSError as exc:  # a link (ELOOP) or a socket (ENXIO) put there since the stat
        raise Untrusted(f"cannot read {name} ({exc.strerror})") from None
    try:
        st = os.fstat(fd)
        check_regular(name, st)
        if private and st.st_mode & 0o066:
            raise Untrusted(f"{name} is readable or writable by group or others")
        return read_at_most(fd, limit + 1)
    finally:
        os.close(fd)


def read_at_most(fd: int, count: int) -> bytes:
    """Up to ``count`` bytes from the open file ``fd`` (fewer at its end), read in chunks of at
    most 1 MiB."""
    chunks, size = [], 0
    while size < count:
        chunk = os.read(fd, min(count - size, 1 << 20))
        if not chunk:
            break
        chunks.append(chunk)
        size += len(chunk)
    return b"".join(chunks)


def check_regular(name: str, st: os.stat_result) -> None:
    if not stat.S_ISREG(st.st_mode):
        raise Untrusted(f"{name} is not a regular file")
    if st.st_uid != os.geteuid():
        raise Untrusted(f"{name} is owned by uid {st.st_uid}, not by uid {os.geteuid()}")


def write_private_file(dir_fd: int, name: str, data: bytes, replace: bool = True) -> None:
    """Write ``name`` (mode 0600) atomically: a new temporary file in the directory, then a
    rename (``replace=False``: a hard link, which fails if ``name`` exists)."""
    tmp = f".tmp-{secrets.token_hex(8)}"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o600,
                 dir_fd=dir_fd)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        if replace:
            os.replace(tmp, name, src_dir_fd=dir_fd, dst_dir_fd=dir_fd)
        else:
            os.link(tmp, name, src_dir_fd=dir_fd, dst_dir_fd=dir_fd, follow_symlinks=False)
    finally:
        try:
            os.unlink(tmp, dir_fd=dir_fd)
        except FileNotFoundError:
            pass


def secret_of(dir_fd: int) -> bytes:
    """The directory's secret key, created (``os.urandom``, mode 0600, atomically) if missing;
    raises :class:`Untrusted` if the key file is not a private regular file of 32 bytes."""
    for _ in range(2):
        data = read_private_file(dir_fd, KEY_FILE, KEY_BYTES, private=True)
        if data is not None:
            if len(data) != KEY_BYTES:
                raise Untrusted(f"{KEY_FILE} is not {KEY_BYTES} bytes long")
            return data
        try:
            write_private_file(dir_fd, KEY_FILE, os.urandom(KEY_BYTES), replace=False)
        except FileExistsError:
            pass  # another process made it first: read theirs
        except OSError as exc:
            raise Untrusted(f"cannot create {KEY_FILE} ({exc.strerror})") from None
    raise Untrusted(f"cannot create {KEY_FILE}")


def user_secret() -> bytes | None:
    """The per-user secret (created if missing), or None where the directory or its key file
    cannot be trusted or made (then nothing that needs the secret is trusted either)."""
    try:
        dir_fd = open_private_dir(user_dir())
    except Untrusted:
        return None
    try:
        return secret_of(dir_fd)
    except Untrusted:
        return None
    finally:
        os.close(dir_fd)
