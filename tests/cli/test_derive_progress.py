"""``symdyn derive`` on a terminal: a progress line, rewritten in place, once the derivation takes
longer than PROGRESS_AFTER seconds; nothing when stderr is not a terminal, nothing with --quiet;
``--digits`` and its errors."""

from __future__ import annotations

import io
import sys
import time

import pytest

import symdyn.cli.derive as derive_cli
from helpers import REPO, robot_path
from symdyn.cli import main
from symdyn.cli.common import Progress

PLANAR2R = robot_path("planar2r")
HANDMADE = str(REPO / "tests" / "data" / "urdf" / "handmade.urdf")


def _derive(capsys, *args):
    assert main(["derive", *map(str, args)]) == 0
    captured = capsys.readouterr()
    return captured.out, captured.err


def test_progress_only_on_a_terminal_and_not_with_quiet(capsys, monkeypatch):
    monkeypatch.setattr(derive_cli, "PROGRESS_AFTER", 0.0)  # as if the derivation were slow
    out, err = _derive(capsys, HANDMADE, "--tip", "link2", "--steps", "summary")
    assert "D(q)" in out and "symdyn: handmade" not in err  # not a terminal
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    out, err = _derive(capsys, HANDMADE, "--tip", "link2")
    assert "D(q)" in out
    assert "\r\033[Ksymdyn: handmade: newton-euler: link matrices (0." in err
    assert "backward recursion, link 1 in closed form" in err and "printing section 4 of 4" in err
    assert err.endswith("\r\033[K")  # the line is cleared before the printout
    assert "\n" not in err[err.index("\r"):]  # one line (after the URDF's warnings), rewritten
    out, err = _derive(capsys, HANDMADE, "--tip", "link2", "--steps", "summary", "--quiet")
    assert "D(q)" in out and "symdyn: handmade" not in err


def test_short_derivations_show_nothing(capsys, monkeypatch):
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    monkeypatch.setattr(derive_cli, "PROGRESS_AFTER", 3600.0)  # a derivation shorter than the delay, however loaded the machine
    out, err = _derive(capsys, PLANAR2R, "--steps", "summary")
    assert "D(q)" in out and "symdyn: planar2r" not in err


def test_progress_shows_a_long_step_once_it_is_due():
    stream = io.StringIO()
    with Progress(stream, after=3600.0, rewrite=True) as progress:  # the timer cannot fire during the test
        progress("deriving")
        assert stream.getvalue() == ""
        progress.start -= 3600.0  # the delay has passed (as on a loaded machine, whatever the wall clock says)
        progress._due()  # what the timer does then: the step still running shows
        assert stream.getvalue() == "\r\033[Ksymdyn: deriving"
        progress("printing")
        assert stream.getvalue().endswith("\r\033[Ksymdyn: printing")
    assert stream.getvalue().endswith("\r\033[K")
    quick = io.StringIO()
    with Progress(quick, after=3600.0, rewrite=True) as progress:
        progress("deriving")
    progress._due()  # the timer firing after the run finished: nothing, ever
    assert quick.getvalue() == ""
    timed = io.StringIO()
    with Progress(timed, after=0.05, rewrite=True) as progress:  # the real timer, waited for
        progress("deriving")
        deadline = time.monotonic() + 30
        while "deriving" not in timed.getvalue() and time.monotonic() < deadline:
            time.sleep(0.01)
        assert timed.getvalue() == "\r\033[Ksymdyn: deriving"
    lines = io.StringIO()
    progress = Progress(lines)  # symdyn generate's: a line per step, at once
    progress("a")
    progress("b")
    assert lines.getvalue() == "symdyn: a\nsymdyn: b\n"


def test_digits_option(capsys):
    out, _ = _derive(capsys, HANDMADE, "--tip", "link2", "--steps", "summary", "--digits", "3")
    assert "decimals rounded to 3 significant digits" in out and "--digits 3" in out
    assert "0.4 " in out or "(0.4," in out  # centre of mass x 0.400188 to 3 digits
    assert "0.400188" not in out


@pytest.mark.parametrize("digits", ["0", "21", "x"])
def test_digits_errors_are_one_line(capsys, digits):
    code = main(["derive", PLANAR2R, "--digits", digits])
    assert code in (1, 2)
    err = capsys.readouterr().err
    assert "--digits" in err and (code == 2 or err.count("\n") == 1)
