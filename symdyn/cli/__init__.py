"""The ``symdyn`` command line: ``main(argv) -> int``, one module per subcommand."""

from __future__ import annotations

import argparse
import sys

from .._version import __version__
from ..model.errors import SymdynError
from . import bench, derive, generate, verify

SUBCOMMANDS = {"generate": generate, "verify": verify, "derive": derive, "bench": bench}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="symdyn",
        description="Symbolic equations of motion for serial robot arms: derive them from a "
                    "Denavit-Hartenberg robot file and generate C code, checked against Pinocchio.",
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
    try:
        return int(args.run(args) or 0)
    except SymdynError as exc:
        print(f"symdyn: error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("symdyn: interrupted", file=sys.stderr)
        return 130


def run() -> None:
    """Console-script entry point."""
    sys.exit(main())
