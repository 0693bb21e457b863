"""The ``symdyn`` command line: ``main(argv) -> int``, one module per subcommand."""

from __future__ import annotations

import argparse
import contextlib
import sys
import warnings

from .._version import __version__
from ..model.errors import SymdynError, SymdynWarning, one_line
from . import bench, cache, convert, derive, fuzz, generate, identify, verify

SUBCOMMANDS = {"generate": generate, "verify": verify, "derive": derive, "bench": bench,
               "convert": convert, "identify": identify, "cache": cache, "fuzz": fuzz}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="symdyn",
        description="Symbolic equations of motion for robot arms and parallel platforms: derive them "
                    "from a robot file (Denavit-Hartenberg or general placements), a URDF or a scene, "
                    "and generate C and CasADi code, checked against Pinocchio.",
        epilog="Run 'symdyn COMMAND --help' for the options of each command.")
    parser.add_argument("--version", action="version", version=f"symdyn {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, module in SUBCOMMANDS.items():
        module.add_parser(sub)
    return parser


def main(argv=None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a usage error already printed by argparse
        return int(exc.code or 0)
    if not args.command:
        parser.print_help()
        return 2
    from .common import memory_budget, time_budget
    try:
        with _warnings_as_lines(strict=getattr(args, "strict", False)), memory_budget(getattr(args, "max_memory", None)), \
                time_budget(getattr(args, "max_seconds", None), _inputs(args)):
            return int(args.run(args) or 0)
    except SymdynError as exc:
        print(f"symdyn: error: {exc}", file=sys.stderr)
        return 1
    except SymdynWarning as exc:  # --strict: a warning is an error
        print(f"symdyn: error: {one_line(exc)} (--strict)", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("symdyn: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (symdyn derive ... | head): not an error of symdyn's
        _quiet_stdout()
        return 141
    except RecursionError:
        print("symdyn: error: the input is nested too deeply to process", file=sys.stderr)
        return 1
    except MemoryError:
        return _out_of_memory(args)
    except Exception as exc:  # a bug in symdyn, never a traceback for the user
        print(f"symdyn: internal error: {type(exc).__name__}: {one_line(exc, 300)} "
              "(please report it with the input file)", file=sys.stderr)
        return 3


def _inputs(args) -> str:
    """The robot files a command reads, for its messages."""
    paths = getattr(args, "robots", None) or ([args.robot] if getattr(args, "robot", None) else [])
    return ", ".join(str(p) for p in paths)


def _out_of_memory(args) -> int:
    """The one line of a run that ran out of memory (its budget, or the machine's)."""
    limit = getattr(args, "max_memory", None)
    budget = f"more than --max-memory {limit:g} GB" if limit else "more memory than the machine has"
    print(f"symdyn: error: out of memory: the run needed {budget} (a very large robot, or many "
          "functions: raise --max-memory, or ask for fewer --functions)", file=sys.stderr)
    return 1


@contextlib.contextmanager
def _warnings_as_lines(strict: bool = False):
    """Show each :class:`SymdynWarning` as one ``symdyn: warning: ...`` line on stderr (``strict``:
    raise it instead, so that the command fails with it as its error)."""
    previous = warnings.showwarning
    shown: set[str] = set()

    def show(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, SymdynWarning):
            text = one_line(message)
            if text not in shown:  # once per run, however often the input is read
                shown.add(text)
                print(_wrapped(f"symdyn: warning: {text}"), file=sys.stderr)
        else:
            previous(message, category, filename, lineno, file, line)
    warnings.showwarning = show
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error" if strict else "always", SymdynWarning)
            warnings.showwarning = show
            yield
    finally:
        warnings.showwarning = previous


def _wrapped(line: str) -> str:
    """``line`` wrapped to the terminal's width (continuation lines indented) when standard error
    is a terminal; one line otherwise (for logs and for programs reading it)."""
    try:
        terminal = sys.stderr.isatty()
    except (AttributeError, ValueError):
        terminal = False
    if not terminal:
        return line
    import shutil
    import textwrap
    width = max(40, shutil.get_terminal_size((100, 24)).columns - 1)
    return "\n".join(textwrap.wrap(line, width, subsequent_indent="    ", break_on_hyphens=False)) or line


def _quiet_stdout() -> None:
    """Point standard output at the null device, so that the interpreter's final flush of a
    closed pipe raises nothing."""
    import os
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):
        pass


def run() -> None:
    """Console-script entry point."""
    sys.exit(main())
