"""Reading input files with bounded work: regular files only, capped size, never blocking, and
YAML parsed safely (plain data only, no duplicate keys, bounded nesting and alias expansion).

Limits (each refused with one line naming the file):

- :data:`MAX_INPUT_BYTES` per file; a FIFO, device, socket or directory is refused without
  reading from it (the file is opened non-blocking and checked with ``fstat`` first);
- :data:`MAX_DEPTH` levels of nested mappings/lists;
- :data:`MAX_NODES` values after expanding YAML aliases (a "billion laughs" document of a few
  hundred bytes would otherwise stand for billions of values).
"""

from __future__ import annotations

import os
import stat

import yaml

from .errors import RobotFileError, describe, one_line

MAX_INPUT_BYTES = 4 * 1024 * 1024
MAX_DEPTH = 32
MAX_NODES = 100_000


def read_input(path: str) -> bytes:
    """The bytes of the input file ``path`` (a regular file of at most :data:`MAX_INPUT_BYTES`)."""
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        raise RobotFileError(path, f"cannot read the file: {exc.strerror or exc}") from None
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise RobotFileError(path, "is a directory, not a robot or scene file")
        if not stat.S_ISREG(info.st_mode):
            raise RobotFileError(path, "is not a regular file (a device, FIFO or socket): give a robot or scene file")
        if info.st_size > MAX_INPUT_BYTES:
            raise RobotFileError(path, f"the file is {info.st_size} bytes, more than the {MAX_INPUT_BYTES} "
                                       "a robot or scene file may have")
        chunks, total = [], 0
        while True:
            try:
                chunk = os.read(fd, 1 << 16)
            except OSError as exc:
                raise RobotFileError(path, f"cannot read the file: {exc.strerror or exc}") from None
            if not chunk:
                break
            total += len(chunk)
            if total > MAX_INPUT_BYTES:
                raise RobotFileError(path, f"the file is larger than the {MAX_INPUT_BYTES} bytes a robot "
                                           "or scene file may have")
            chunks.append(chunk)
        return b"".join(chunks)
    finally:
        os.close(fd)


def decode_text(data: bytes, path: str) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise RobotFileError(path, "the file is not UTF-8 text") from None


class _Limits(Exception):
    """Raised inside the YAML loader when a limit is exceeded (turned into a RobotFileError)."""


class SafeLoader(yaml.SafeLoader):
    """PyYAML's SafeLoader (plain data only) that refuses duplicate keys, keys that are not
    scalars, nesting deeper than :data:`MAX_DEPTH` and more than :data:`MAX_NODES` values after
    alias expansion."""

    def __init__(self, stream):
        super().__init__(stream)
        self._depth = 0

    def compose_node(self, parent, index):
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                raise _Limits(f"nested more than {MAX_DEPTH} levels deep")
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_document(self, node):
        _check_expanded_size(node)
        return super().construct_document(node)


def _check_expanded_size(root) -> None:
    """Count the values the node graph stands for once aliases are expanded (memoized per node,
    so the count itself takes time linear in the document, not in its expansion)."""
    sizes: dict[int, int] = {}
    open_nodes: set[int] = set()
    stack = [(root, False)]
    while stack:  # iterative post-order: children before parents
        node, done = stack.pop()
        if done:
            total = 1
            for child in _children(node):
                total += sizes[id(child)]
                if total > MAX_NODES:
                    raise _Limits(f"the document holds more than {MAX_NODES} values (aliases *name count the "
                                  "values they stand for at each use)")
            sizes[id(node)] = total
            open_nodes.discard(id(node))
            continue
        if id(node) in sizes:
            continue
        if id(node) in open_nodes:
            raise _Limits("a value contains itself (a recursive alias)")
        open_nodes.add(id(node))
        stack.append((node, True))
        for child in _children(node):
            if id(child) in open_nodes:
                raise _Limits("a value contains itself (a recursive alias)")
            if id(child) not in sizes:
                stack.append((child, False))


def _children(node):
    if isinstance(node, yaml.SequenceNode):
        return node.value
    if isinstance(node, yaml.MappingNode):
        return [item for pair in node.value for item in pair]
    return ()


def _construct_mapping(loader, node, deep=False):
    seen = set()
    for key_node, _ in node.value:
        if not isinstance(key_node, yaml.ScalarNode):
            raise yaml.constructor.ConstructorError(
                None, None, "a key must be a plain name or number, not a list or mapping", key_node.start_mark)
        key = loader.construct_object(key_node, deep=deep)
        if key in seen:
            raise yaml.constructor.ConstructorError(
                None, None, f"duplicate key {describe(key)}", key_node.start_mark)
        seen.add(key)
    return yaml.SafeLoader.construct_mapping(loader, node, deep=deep)


SafeLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def load_yaml(text: str, path: str, what: str = "YAML"):
    """Parse ``text`` (the content of ``path``) into plain data; any problem is one
    :class:`RobotFileError` line (``what`` names the expected kind of file in it)."""
    try:
        return yaml.load(text, Loader=SafeLoader)
    except _Limits as exc:
        raise RobotFileError(path, f"not accepted: {exc}") from None
    except ValueError as exc:  # e.g. an integer of more digits than Python converts
        raise RobotFileError(path, f"not accepted: {one_line(exc, 120)}") from None
    except RecursionError:
        raise RobotFileError(path, f"not accepted: nested more than {MAX_DEPTH} levels deep") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise RobotFileError(path, f"not valid {what}{where}: {problem}") from None
