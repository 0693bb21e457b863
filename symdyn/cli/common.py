"""Helpers shared by the subcommands."""

from __future__ import annotations

import contextlib
import shutil
import sys
import threading
import time

from ..derive.equations import METHOD_ALIASES
from ..emit.pipeline import default_fd_method, parse_functions  # noqa: F401 (the subcommands' helpers)
from ..model.errors import SymdynError


def add_fd_method_option(parser) -> None:
    parser.add_argument("--fd-method", default=None, choices=("ldlt", "aba"),
                        help="forward dynamics by an LDL^T factorization of D or by the articulated-body "
                             "algorithm (default: ldlt, or aba with --precision float, chosen by measurement: "
                             "docs/benchmarks.md)")


def add_method_option(parser) -> None:
    parser.add_argument("--method", default="newton-euler", choices=sorted(set(METHOD_ALIASES)),
                        help="derivation: newton-euler (default; recursive, smallest code), lagrange-euler (trace form) or "
                             "jacobian-newton-euler (world-frame link Jacobians, H = sum J_ci^T M_i J_ci)")


#: default of --max-joints: no count (None): the cost of a robot follows its structure more than
#: its joints (a generic 40-joint DH chain: 29 s and 161 MB on the 2-core reference machine;
#: TIAGo's 48 joints 36 s; other 40-joint robots past 240 s), so the time and memory budgets
#: (--max-seconds, --max-memory) bound a run, not a joint count; docs/untrusted-input.md
DEFAULT_MAX_JOINTS = None
#: default of --max-memory (GB): the most memory a run may take before it stops with one line
DEFAULT_MAX_MEMORY_GB = 8.0
#: default of --max-seconds: the most CPU time a run may take before it stops with one line (a
#: run a user can wait for; a generic 40-joint chain takes longer, and says how to go on)
DEFAULT_MAX_SECONDS = 120.0


class TimeBudgetExceeded(SymdynError):
    """The run took more CPU time than ``--max-seconds``."""


def add_urdf_options(parser) -> None:
    """--tip, --tool and --exact-angles: how a URDF input is read."""
    parser.add_argument("--tip", metavar="LINK", default=None,
                        help="URDF input: the link the chain ends at (default: the only leaf, the end of the one "
                             "chain of moving joints, or else the whole tree)")
    parser.add_argument("--tool", metavar="LINK", default=None,
                        help="URDF input: a link rigidly attached to the last moving link whose frame is the "
                             "tool frame (default: the tip link's frame)")
    parser.add_argument("--floating-base", action="store_true",
                        help="URDF input: the whole tree on a free-floating root link (a free-flyer joint with "
                             "Pinocchio's conventions: q = [position, quaternion x y z w, joints], v = [linear, "
                             "angular velocity in the base frame, joint rates])")
    parser.add_argument("--frames", metavar="A,B,...", type=lambda text: [n.strip() for n in text.split(",") if n.strip()],
                        help="the frames of the frame functions (poses, Jacobians, J-dot v), in order: URDF links "
                             "(a foot merged by fixed joints too), or a robot file's links and the frames its "
                             "'frames:' defines (in place of the file's list); an MJCF's sites are its frames, "
                             "and this adds bodies (or sites) by name")
    parser.add_argument("--contacts", metavar="A:3d,B:6d,...", default=None,
                        help="the contact set of the contact dynamics, in order: frames (as --frames names them) "
                             "held by the ground, each 3d (a point: its linear velocity zero) or 6d (a sole: its "
                             "whole velocity zero), in place of the file's 'contacts:'")
    parser.add_argument("--exact-angles", action="store_true",
                        help="URDF and MJCF input: keep rpy angles as written (default: an angle within 1e-9 rad of a "
                             "multiple of pi/2, such as 1.57079632679, is taken as that multiple so that zeros "
                             "fold; the header lists them)")


def add_size_options(parser) -> None:
    """--strict, --max-joints and the URDF options, shared by every subcommand that reads robots."""
    add_urdf_options(parser)
    parser.add_argument("--strict", action="store_true",
                        help="treat every warning (inertia breaking the triangle inequality, angles that "
                             "look like degrees, a mass without inertia, ...) as an error")
    parser.add_argument("--max-joints", type=int, default=DEFAULT_MAX_JOINTS, metavar="N",
                        help="refuse robots with more than N joints before deriving (default: no count; the time "
                             "and memory budgets, --max-seconds and --max-memory, bound the run)")
    parser.add_argument("--max-memory", type=float, default=DEFAULT_MAX_MEMORY_GB, metavar="GB",
                        help=f"stop with an error when the run needs more than GB gigabytes of memory "
                             f"(default {DEFAULT_MAX_MEMORY_GB:g}; 0: no limit)")
    parser.add_argument("--max-seconds", type=float, default=DEFAULT_MAX_SECONDS, metavar="S",
                        help=f"stop with an error, writing nothing, when the run has taken more than S seconds of "
                             f"CPU time (default {DEFAULT_MAX_SECONDS:g}; 0: no limit)")


def load_robot(path, args, parallel: bool = False):
    """``(robot, scene or None)`` of a robot file, URDF (with ``--tip``/``--tool``) or scene;
    with ``parallel``, a platform robot file gives ``(ParallelRobot, None)``."""
    from ..model.scene import load_input
    return load_input(path, getattr(args, "tip", None), getattr(args, "tool", None),
                      getattr(args, "exact_angles", False), parallel=parallel,
                      floating_base=getattr(args, "floating_base", False), frames=getattr(args, "frames", None),
                      contacts=getattr(args, "contacts", None))


def check_size(robot, args, path) -> None:
    """Refuse a robot with more joints than ``--max-joints`` before any derivation starts."""
    limit = getattr(args, "max_joints", DEFAULT_MAX_JOINTS)
    if limit is not None and robot.dof > limit:
        raise SymdynError(f"{path}: {robot.dof} joints, more than --max-joints {limit}: the derivation "
                          "would take long (about 90 s for 40 joints); raise --max-joints to go on")


class Progress:
    """Shows progress texts on a terminal (``stream``) as ``symdyn: TEXT``: one line each, or
    (``rewrite``) one line rewritten in place and cleared by :meth:`close`.  With ``after`` > 0
    nothing shows before that many seconds: a text given earlier is shown then (from a timer
    thread) if no later one came, so that a short run prints nothing."""

    def __init__(self, stream, after: float = 0.0, rewrite: bool = False):
        self.stream = stream
        self.rewrite = rewrite
        self.start = time.monotonic()
        self.after = after
        self.pending: str | None = None
        self.shown = False
        self.closed = False
        self.lock = threading.Lock()
        self.timer = None
        if after > 0:
            self.timer = threading.Timer(after, self._due)
            self.timer.daemon = True
            self.timer.start()

    def __call__(self, text: str) -> None:
        with self.lock:
            self.pending = text
            if not self.closed and time.monotonic() - self.start >= self.after:
                self._write()

    def _due(self) -> None:
        with self.lock:
            if not self.closed and self.pending is not None:
                self._write()

    def _write(self) -> None:
        line, self.pending = f"symdyn: {self.pending}", None
        if self.rewrite:  # cut to the terminal's width: a wrapped line cannot be rewritten
            self.stream.write("\r\033[K" + line[:max(shutil.get_terminal_size().columns - 1, 20)])
        else:
            self.stream.write(line + "\n")
        self.stream.flush()
        self.shown = True

    def close(self) -> None:
        """Stop (no text shows afterwards) and clear a rewritten line."""
        with self.lock:
            self.closed = True
            if self.timer is not None:
                self.timer.cancel()
            if self.rewrite and self.shown:
                self.stream.write("\r\033[K")
                self.stream.flush()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def progress_printer(args, after: float = 0.0, rewrite: bool = False):
    """A :class:`Progress` on stderr when it is a terminal (and not ``--quiet``), else None:
    a line per text, or with ``after``/``rewrite`` only once a run takes longer than ``after``
    seconds, on one line rewritten in place."""
    if getattr(args, "quiet", False) or not sys.stderr.isatty():
        return None
    return Progress(sys.stderr, after, rewrite)


@contextlib.contextmanager
def time_budget(seconds: float | None, inputs: str = ""):
    """Stop the block with :class:`TimeBudgetExceeded` (naming ``inputs``, the files the run
    reads) once this process has used ``seconds`` of CPU time in it (a profiling timer: the
    derivation's Python code is interrupted between two steps, and the command writes nothing);
    nothing for 0/None, off the main thread, or where the platform has no such timer."""
    import signal
    if not seconds or seconds <= 0 or not hasattr(signal, "setitimer"):
        yield
        return

    def expired(signum, frame):
        raise TimeBudgetExceeded(f"{inputs + ': ' if inputs else ''}stopped after {seconds:g} s of CPU time (--max-seconds): a large robot or many "
                                 "functions take longer; raise --max-seconds (0: no limit), or ask for fewer "
                                 "--functions or joints")
    try:
        previous = signal.signal(signal.SIGPROF, expired)
    except ValueError:  # not the main thread
        yield
        return
    signal.setitimer(signal.ITIMER_PROF, seconds, 1.0)  # again each second, should a handler swallow it
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, previous)


@contextlib.contextmanager
def memory_budget(gigabytes: float | None):
    """Limit this process's data segment (heap and private mappings: where SymPy's expressions
    live) to ``gigabytes`` while the block runs, so that a derivation that outgrows it ends in a
    MemoryError instead of the machine's swap; the previous soft limit is restored after.
    Nothing where the platform has no such limit, or for 0/None."""
    try:
        import resource
        kind = resource.RLIMIT_DATA
    except (ImportError, AttributeError):
        yield
        return
    if not gigabytes or gigabytes <= 0:
        yield
        return
    soft, hard = resource.getrlimit(kind)
    wanted = int(gigabytes * 2 ** 30)
    if hard != resource.RLIM_INFINITY:
        wanted = min(wanted, hard)
    try:
        resource.setrlimit(kind, (wanted, hard))
    except (ValueError, OSError):
        yield
        return
    try:
        yield
    except (MemoryError, SymdynError):
        raise
    except Exception as exc:
        if near_memory_budget(gigabytes):  # a C extension that failed to allocate raises something else
            raise MemoryError(f"{type(exc).__name__} at the memory budget") from exc
        raise
    finally:
        resource.setrlimit(kind, (soft, hard))


def near_memory_budget(gigabytes: float | None) -> bool:
    """Whether this process's data segment is within 10% of ``gigabytes`` (then an error
    raised in a C extension, such as a SystemError without its MemoryError, is the budget
    running out rather than a bug); False where it cannot be read (non-Linux)."""
    if not gigabytes or gigabytes <= 0:
        return False
    try:
        with open("/proc/self/status", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("VmData:"):
                    return int(line.split()[1]) * 1024 >= 0.9 * gigabytes * 2 ** 30
    except (OSError, ValueError, IndexError):
        pass
    return False
