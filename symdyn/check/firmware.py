"""Code size and stack use of generated C on a Cortex-M4 (single-precision FPU), measured with
``arm-none-eabi-gcc`` (Debian/Ubuntu: ``gcc-arm-none-eabi`` and ``libnewlib-arm-none-eabi``).

:func:`measure` compiles a generated ``NAME_dynamics.c`` with :data:`FLAGS` plus
``-fstack-usage`` and reads each function's text size (``arm-none-eabi-nm --size-sort -S``) and
stack use (the ``.su`` file), and the double-precision routines it references (``__aeabi_d*``,
and double ``sin``/``cos``/``sqrt``/``fabs``): float C must reference none.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass

from ..model.errors import SymdynError
from .cbuild import c_sources

COMPILER = "arm-none-eabi-gcc"
NM = "arm-none-eabi-nm"
FLAGS = ("-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard", "-mfpu=fpv4-sp-d16", "-O2", "-std=c99")
DOUBLE_LIBM = ("sin", "cos", "sqrt", "fabs", "sincos", "pow")


@dataclass(frozen=True)
class FirmwareReport:
    """``sizes``: function name -> (text bytes, stack bytes); ``doubles``: double-precision
    routines referenced; ``toolchain``: the compiler's version line; ``command``: the
    exact compile command that was measured (:data:`FLAGS`, ``-fstack-usage``, the source)."""

    sizes: dict
    doubles: tuple
    toolchain: str
    command: str = ""


def available() -> bool:
    return shutil.which(COMPILER) is not None and shutil.which(NM) is not None


def _compiled_sizes(command: list[str], source: str, work: str, sizes: dict) -> list[str]:
    """Compile ``source`` in ``work`` by ``command``; add each function's ``[code bytes, stack
    bytes]`` to ``sizes``; return the object's undefined symbols."""
    obj = source[:-2] + ".o"
    result = subprocess.run([*command, "-o", obj], cwd=work, capture_output=True, text=True)
    if result.returncode != 0:
        raise SymdynError(f"{COMPILER} failed on {source}: {result.stderr.strip()[:2000]}")
    listing = subprocess.run([NM, "--size-sort", "-S", obj], cwd=work, capture_output=True, text=True, check=True)
    for line in listing.stdout.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "Tt":
            sizes[parts[3]] = [int(parts[1], 16), 0]
    with open(os.path.join(work, source[:-2] + ".su"), encoding="utf-8") as handle:
        for line in handle:
            fields = line.rstrip("\n").split("\t")
            if len(fields) >= 2 and fields[0].rsplit(":", 1)[-1] in sizes:
                sizes[fields[0].rsplit(":", 1)[-1]][1] = int(fields[1])
    return subprocess.run([NM, "-u", obj], cwd=work, capture_output=True, text=True, check=True).stdout.split()


def measure(files: dict, prefix: str) -> FirmwareReport:
    """Compile ``files`` (``{name: text}`` with ``PREFIX_dynamics.c`` and its header) for a
    Cortex-M4 and report sizes, stack use and double routines.  Raises
    :class:`~symdyn.model.errors.SymdynError` when the toolchain is missing or the compile fails."""
    if not available():
        raise SymdynError(f"the size report needs {COMPILER} and {NM} (Debian/Ubuntu: apt install "
                          "gcc-arm-none-eabi libnewlib-arm-none-eabi)")
    with tempfile.TemporaryDirectory(prefix="symdyn-firmware-") as work:
        for name, text in files.items():
            with open(os.path.join(work, name), "w", encoding="utf-8") as handle:
                handle.write(text)
        sizes: dict[str, list[int]] = {}
        undefined = []
        sources = c_sources(files, prefix)
        for source in sources:  # (C of several files: each compiled alike)
            undefined += _compiled_sizes([COMPILER, *FLAGS, "-fstack-usage", "-c", source], source, work, sizes)
        command = [COMPILER, *FLAGS, "-fstack-usage", "-c", *sources]
        doubles = tuple(sorted(set(u for u in undefined if u.startswith("__aeabi_d") or u in DOUBLE_LIBM)))
        version = subprocess.run([COMPILER, "--version"], capture_output=True, text=True).stdout.splitlines()
    toolchain = version[0].strip() if version else COMPILER
    return FirmwareReport({k: tuple(v) for k, v in sizes.items()}, doubles, toolchain, " ".join(command))


__all__ = ["FirmwareReport", "measure", "available", "FLAGS"]
