"""``symdyn fuzz``: the differential fuzzer (:mod:`symdyn.check.fuzz`) from the command line.

Checks the random robots numbered ``--first`` to ``--first + --cases - 1`` (each drawn with its
number as the random seed: the same robots on every machine), prints one line per robot, shrinks
each failing one and writes it to ``--keep DIR`` as ``fuzzN.case.yaml`` (a file for
``tests/data/fuzz/``, where the test suite checks it again), and exits 1 when anything failed.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from ..model.errors import SymdynError

HELP = "check random robots' every function in C, numpy and CasADi against Pinocchio (differential fuzzing)"


@dataclass(frozen=True)
class FuzzOptions:
    """What ``symdyn fuzz`` runs: cases ``first`` .. ``first + cases - 1``; failing ones shrunk
    for at most ``shrink_seconds`` each and written to ``keep`` (or not kept)."""

    cases: int = 30
    first: int = 0
    keep: str | None = None
    shrink_seconds: float = 300.0
    jobs: int = 1


def add_parser(sub) -> None:
    p = sub.add_parser("fuzz", help=HELP, description=HELP + ". Random URDF trees and DH tables (fixed and floating "
                       "bases, frames, scenes, friction, double, float and mixed precision), every function each "
                       "supports, compared with Pinocchio's own model of the file at random states; the derivation "
                       "cache checked by a second derivation with one field changed. The random seed of robot k is "
                       "k. Needs Pinocchio and a C compiler. Exit status 1 when any robot fails.")
    p.add_argument("--cases", type=int, default=30, help="how many robots (default 30)")
    p.add_argument("--first", type=int, default=0, help="the first robot's number (default 0)")
    p.add_argument("--keep", metavar="DIR", help="write each failing robot, shrunk, to DIR as fuzzN.case.yaml")
    p.add_argument("--shrink-seconds", type=float, default=300.0,
                   help="time spent shrinking each failing robot (default 300)")
    p.add_argument("--jobs", type=int, default=1, help="robots checked at once, one process each (default 1)")
    p.set_defaults(run=run)


def options_of(args) -> FuzzOptions:
    if args.cases < 1 or args.first < 0 or args.jobs < 1:
        raise SymdynError("--cases and --jobs must be at least 1 and --first at least 0")
    return FuzzOptions(args.cases, args.first, args.keep, args.shrink_seconds, args.jobs)


def run(args) -> int:
    try:
        import pinocchio  # noqa: F401
    except ImportError:
        raise SymdynError("symdyn fuzz needs Pinocchio: pip install 'symdyn[verify]' (the pin package)") from None
    from ..check.fuzz import run_campaign
    options = options_of(args)
    started = time.perf_counter()
    outcomes = run_campaign(range(options.first, options.first + options.cases), options.keep,
                            report=lambda line: print(line, flush=True), shrink_seconds=options.shrink_seconds,
                            jobs=options.jobs)
    failed = [o for o in outcomes if o.findings]
    compared = sum(o.compared for o in outcomes)
    worst = max((o.worst for o in outcomes), default=0.0)
    print(f"symdyn fuzz: {len(outcomes)} robots, {compared} comparisons, worst normalized error {worst:.2g}, "
          f"{time.perf_counter() - started:.0f} s")
    print(f"fuzz: {len(outcomes) - len(failed)} passed, {len(failed)} failed")
    return 1 if failed else 0
