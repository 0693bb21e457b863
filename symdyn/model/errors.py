"""Exceptions raised for user mistakes.

Every error about a robot file names the file, and where it applies the link and the field,
so that the command line can print it as one readable line.
"""

from __future__ import annotations


class SymdynError(Exception):
    """Base class of all errors caused by user input (bad files, bad options)."""


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
        where = [self.path]
        if link is not None:
            where.append(link)
        if field is not None:
            where.append(f"field '{field}'")
        super().__init__(f"{': '.join(where)}: {reason}")
