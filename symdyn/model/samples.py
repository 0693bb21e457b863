"""Measured samples for identification: a CSV file of joint positions, rates, accelerations and
torques (``symdyn identify``).

Format: UTF-8 text, comma-separated, a header row naming the columns, then one sample per row.
For a robot of n joints the columns are ``q1..qn``, ``qd1..qdn``, ``qdd1..qddn`` and
``tau1..taun`` (rad, rad/s, rad/s^2, N m; m, m/s, m/s^2, N for prismatic joints), in any order,
each exactly once and nothing else.  Lines starting with ``#`` are comments.  Every value must be
a finite number.
"""

from __future__ import annotations

import csv
import math
import os
import stat
from dataclasses import dataclass

import numpy as np

from .errors import SymdynError

#: largest data file read (bytes)
MAX_SAMPLES_BYTES = 512 * 1024 * 1024
#: the largest magnitude of a sample value (rad, m, their rates, N m, N): far beyond any robot,
#: and small enough that the regressor's products and squares stay finite in double
MAX_SAMPLE_MAGNITUDE = 1e9
GROUPS = ("q", "qd", "qdd", "tau")


@dataclass(frozen=True)
class Samples:
    """Arrays of shape (samples, n): positions, rates, accelerations, torques."""

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray

    @property
    def count(self) -> int:
        return self.q.shape[0]


def expected_columns(n: int) -> list[str]:
    return [f"{g}{k + 1}" for g in GROUPS for k in range(n)]


#: rows per block of :func:`sample_blocks`
BLOCK_ROWS = 4096


def read_samples(path: str, n: int) -> Samples:
    """Read and check a samples file for a robot of ``n`` joints (see the module's
    documentation), whole; a problem raises :class:`SymdynError` naming the file, row and
    column.  :func:`sample_blocks` reads it block by block."""
    blocks = list(sample_blocks(path, n))
    return Samples(*(np.concatenate([getattr(b, g) for b in blocks]) for g in GROUPS)) if blocks else \
        Samples(*(np.empty((0, n)) for _ in GROUPS))


def sample_blocks(path: str, n: int, rows: int = BLOCK_ROWS):
    """The samples of a file for a robot of ``n`` joints, checked as they are read, in blocks of
    at most ``rows`` samples (:class:`Samples` each): memory does not grow with the file (a
    million rows took 985 MB read whole)."""
    name = os.path.basename(path)
    try:
        info = os.stat(path)
    except OSError as exc:
        raise SymdynError(f"{name}: cannot read the file: {exc.strerror or exc}") from None
    if not stat.S_ISREG(info.st_mode):
        raise SymdynError(f"{name}: is not a regular file")
    if info.st_size > MAX_SAMPLES_BYTES:
        raise SymdynError(f"{name}: {info.st_size} bytes, more than the {MAX_SAMPLES_BYTES} a samples file may have")
    try:
        with open(path, encoding="utf-8-sig", newline="") as handle:  # a spreadsheet's BOM is fine
            numbered = _data_lines(handle)
            reader = csv.reader(numbered.lines())
            try:
                header = [h.strip() for h in next(reader)]
            except StopIteration:
                raise SymdynError(f"{name}: no header row (expected the columns {', '.join(expected_columns(n)[:3])}, "
                                  "...)") from None
            columns = _columns(name, header, n)
            block = []
            for row in reader:
                block.append(_values(name, numbered.current, header, row))
                if len(block) == rows:
                    yield _block(block, columns)
                    block = []
            if block:
                yield _block(block, columns)
    except UnicodeDecodeError:
        raise SymdynError(f"{name}: the file is not UTF-8 text") from None
    except csv.Error as exc:
        raise SymdynError(f"{name}: not a readable CSV file ({exc})") from None
    except OSError as exc:
        raise SymdynError(f"{name}: cannot read the file: {exc.strerror or exc}") from None


class _data_lines:
    """The lines of an open file that hold data (not blank, not ``#`` comments), with the number
    of the last one handed out (``current``, from 1)."""

    def __init__(self, handle):
        self.handle, self.current = handle, 0

    def lines(self):
        for number, line in enumerate(self.handle, start=1):
            if line.strip() and not line.lstrip().startswith("#"):
                self.current = number
                yield line


def _columns(name: str, header: list[str], n: int) -> list[list[int]]:
    """Per group (q, qd, qdd, tau), the header's column of each joint; a wrong header raises."""
    if len(header) == 1 and any(sep in header[0] for sep in (";", "\t")):
        raise SymdynError(f"{name}: the header is separated by {'semicolons' if ';' in header[0] else 'tabs'}: "
                          "symdyn reads comma-separated values (export the file as CSV with commas)")
    expected = expected_columns(n)
    missing = [c for c in expected if c not in header]
    extra = [h for h in header if h not in expected]
    duplicated = sorted({h for h in header if header.count(h) > 1})
    if missing or extra or duplicated:
        problems = []
        if missing:
            problems.append(f"missing {', '.join(missing[:6])}{' ...' if len(missing) > 6 else ''}")
        if extra:
            problems.append(f"unexpected {', '.join(repr(e) for e in extra[:6])}{' ...' if len(extra) > 6 else ''}")
        if duplicated:
            problems.append(f"repeated {', '.join(duplicated)}")
        raise SymdynError(f"{name}: wrong columns for a robot of {n} joints ({'; '.join(problems)}); the header "
                          f"must name q1..q{n}, qd1..qd{n}, qdd1..qdd{n} and tau1..tau{n} ({4 * n} columns)")
    index = {h: k for k, h in enumerate(header)}
    return [[index[f"{g}{k + 1}"] for k in range(n)] for g in GROUPS]


def _values(name: str, line_number: int, header: list[str], row: list[str]) -> list[float]:
    """The numbers of one data row, checked (finite, of magnitude at most
    :data:`MAX_SAMPLE_MAGNITUDE`)."""
    if len(row) != len(header):
        raise SymdynError(f"{name}: line {line_number} has {len(row)} value{'' if len(row) == 1 else 's'}, "
                          f"the header {len(header)}")
    values = []
    for c, cell in enumerate(row):
        try:
            if "_" in cell:  # Python's float() reads 1_000; a data file should not
                raise ValueError(cell)
            value = float(cell)
        except ValueError:
            raise SymdynError(f"{name}: line {line_number}, column {header[c]}: {cell.strip()[:40]!r} is not a number") from None
        if not math.isfinite(value):
            raise SymdynError(f"{name}: line {line_number}, column {header[c]}: {cell.strip()} is not a finite number")
        if abs(value) > MAX_SAMPLE_MAGNITUDE:
            raise SymdynError(f"{name}: line {line_number}, column {header[c]}: {cell.strip()[:40]} is beyond "
                              f"{MAX_SAMPLE_MAGNITUDE:g} in magnitude: no joint position (rad or m), rate or "
                              "torque is that large, and the least-squares fit would lose every other "
                              "sample to it (check the units and the column order)")
        values.append(value)
    return values


def _block(rows: list[list[float]], columns: list[list[int]]) -> Samples:
    data = np.array(rows, dtype=float)
    return Samples(*(data[:, index] for index in columns))


def write_samples(samples: Samples) -> str:
    """The CSV text of ``samples`` (as :func:`read_samples` reads it)."""
    n = samples.q.shape[1]
    out = [",".join(expected_columns(n))]
    for row in np.hstack([samples.q, samples.qd, samples.qdd, samples.tau]):
        out.append(",".join(repr(float(v)) for v in row))
    return "\n".join(out) + "\n"
