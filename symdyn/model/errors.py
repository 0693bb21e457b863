"""Exceptions raised for user mistakes, and the helpers that keep their messages one bounded line.

Every error about a robot file names the file, and where it applies the link and the field,
so that the command line can print it as one readable line.  Messages never carry raw user data
unbounded: :func:`describe` shows a value in a few dozen characters, :func:`display_path` a path
without control or markup characters, and every message is folded to one line of at most
:data:`MAX_MESSAGE` characters.
"""

from __future__ import annotations

import re

#: the longest message an error carries (characters)
MAX_MESSAGE = 600

_UNPRINTABLE = re.compile(r"[\x00-\x1f\x7f-\x9f\u2028\u2029]")
_PATH_UNSAFE = re.compile(r"[^A-Za-z0-9._+/@,=-]")


def one_line(text: str, limit: int = MAX_MESSAGE) -> str:
    """``text`` with control characters (newlines included) shown as spaces, cut to ``limit``."""
    text = _UNPRINTABLE.sub(" ", str(text))
    return text if len(text) <= limit else text[:limit - 3] + "..."


def display_path(path, limit: int = 160) -> str:
    """A path as generated files and messages show it: characters outside ``[A-Za-z0-9._+/@,=-]``
    (spaces, quotes, ``*``, ``\\``, ``$``, braces, control characters ...) become ``?`` and a long
    path keeps its end.  Safe inside C comments, LaTeX ``\\texttt``, Markdown and one-line messages."""
    text = _PATH_UNSAFE.sub("?", str(path))
    return text if len(text) <= limit else "..." + text[-(limit - 3):]


def describe(value, limit: int = 60) -> str:
    """A short description of a value read from a file, for messages: scalars by ``repr``
    (cut to ``limit``), containers by their type and length, never walked."""
    if isinstance(value, (list, tuple)):
        return f"a list of {len(value)} item{'s' if len(value) != 1 else ''}"
    if isinstance(value, dict):
        return f"a mapping of {len(value)} key{'s' if len(value) != 1 else ''}"
    if value is None:
        return "nothing"
    if isinstance(value, (str, int, float, bool)):
        text = repr(value) if not isinstance(value, int) or isinstance(value, bool) or abs(value) < 10**40 \
            else f"an integer of about {int(value.bit_length() * 0.30103) + 1} digits"
        return one_line(text if len(text) <= limit else text[:limit - 3] + "...", limit)
    return f"a {type(value).__name__}"


class SymdynWarning(UserWarning):
    """Something in the input looks wrong but can be computed (the command line prints it as
    one ``symdyn: warning:`` line)."""


#: where Python's warning machinery records the warnings already shown (each text once per
#: process under the default filter)
_SHOWN: dict = {}


def warn(message: str) -> None:
    """Issue a :class:`SymdynWarning` (one line, bounded).

    The warning is attributed to ``symdyn`` itself rather than to a line of its source, so that
    Python users see ``symdyn:0: SymdynWarning: <message>`` without a line of symdyn's code under
    it; under Python's default filter each text is shown once per process."""
    import warnings
    warnings.warn_explicit(one_line(message), SymdynWarning, "symdyn", 0, module="symdyn", registry=_SHOWN)


class SymdynError(Exception):
    """Base class of all errors caused by user input (bad files, bad options).  The message is
    always one line of at most :data:`MAX_MESSAGE` characters."""

    def __init__(self, message: str = ""):
        super().__init__(one_line(message))


class RobotFileError(SymdynError):
    """A robot (or scene) file is malformed.

    Attributes
    ----------
    path : str      the file the problem is in
    link : str|None the link's name (or ``link 3`` when it has none), None for top-level fields
    field : str|None the offending field, e.g. ``inertia.xx``
    reason : str    what is wrong, in plain words
    """

    def __init__(self, path: str, reason: str, *, link: str | None = None, field: str | None = None):
        self.path = str(path)
        self.link = link
        self.field = field
        self.reason = reason
        where = [one_line(self.path, 200)]
        if link is not None:
            where.append(one_line(link, 120))
        if field is not None:
            where.append(f"field '{one_line(field, 80)}'")
        super().__init__(f"{': '.join(where)}: {reason}")
