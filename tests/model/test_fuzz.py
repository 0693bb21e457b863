"""Seeded fuzzing of the command line with mutated robot files and scenes.

Each case takes a bundled robot file or scene, mutates its parsed document (types, values,
names, nesting, deleted and unknown keys) or its raw text (truncation, byte changes), and runs
``symdyn generate`` on it in-process.  Every case must end with exit status 0 and C that compiles
warning-free, or exit status 1 and exactly one ``symdyn: error:`` line; never a traceback, never
an internal error, never more than :data:`CASE_SECONDS`.  The run is bounded by
:data:`BUDGET_SECONDS` (``SYMDYN_FUZZ_SECONDS`` overrides it) and reproducible from its seed.
"""

from __future__ import annotations

import os
import random
import shutil
import signal
import subprocess
import time

import pytest
import yaml

from helpers import REPO
from symdyn.cli import main

BUDGET_SECONDS = float(os.environ.get("SYMDYN_FUZZ_SECONDS", "12"))
CASE_SECONDS = 20
SEED = int(os.environ.get("SYMDYN_FUZZ_SEED", "20261122"))
SOURCES = ["planar2r", "scara", "stanford", "puma560", "ur5", "panda"]
SCENES = sorted((REPO / "robots" / "scenes").glob("*.yaml"))
FUNCTION_SETS = ["gravity", "gravity,mass_matrix", "inverse_dynamics", "forward_dynamics", "coriolis"]

ODD_VALUES = [None, True, False, "", " ", "abc", "1/0", "0**(-x)", "x**y", "9**9**9", "1e999999999",
              "sin(0.2)", "*/", "/*", "a\nb", "\u00e9", "pi/2", "-0.0", "1e-320", "2**0.5",
              "(" * 60 + "1" + ")" * 60, "q1", "tau", "nan", ".nan", "inf", [], {}, [1, 2], [[[]]],
              {"value": 1}, {"runtime": True}, 0, -1, 1e308, -1e308, 1e100, float("nan"),
              float("inf"), 10**40, 3, 0.5, "m1", "l2 + 1", "x" * 40,
              # round two: reserved names, powers of sums, non-real numbers, huge fields
              "qdot2", "cse0", "c1", "(m1+l1+l2+1)**64", "(l1+l2)**40", "(-8)**(1/3)", "1e100*1e100", -1e100]


class CaseTimeout(BaseException):
    """Raised by the alarm: a BaseException, so the CLI's last-resort handler cannot swallow it."""


def _leaves(node, path=()):
    """(path, value) of every position in a parsed document."""
    yield path, node
    if isinstance(node, dict):
        for key, value in list(node.items()):
            yield from _leaves(value, path + (key,))
    elif isinstance(node, list):
        for index, value in enumerate(node):
            yield from _leaves(value, path + (index,))


def _set(doc, path, value):
    if not path:
        return value
    target = doc
    for step in path[:-1]:
        target = target[step]
    target[path[-1]] = value
    return doc


def _mutate(doc, rng: random.Random):
    """One structural mutation of a parsed document."""
    positions = list(_leaves(doc))
    path, value = rng.choice(positions)
    kind = rng.randrange(8)
    if kind <= 2:
        return _set(doc, path, rng.choice(ODD_VALUES))
    if kind == 3 and path:  # delete the key or the item
        parent = doc
        for step in path[:-1]:
            parent = parent[step]
        del parent[path[-1]]
        return doc
    if kind == 4:  # an unknown or odd key
        if isinstance(value, dict):
            value[rng.choice(["colour", "Name", "", "1", "links", "a\nb", "*/"])] = rng.choice(ODD_VALUES)
        return doc
    if kind == 5:  # change the nesting
        return _set(doc, path, rng.choice([[value], {"value": value}, [[value]]]))
    if kind == 6 and isinstance(value, (int, float)) and not isinstance(value, bool):
        return _set(doc, path, rng.choice([value * 1e6, -value, value * 1e-9, value + 7, str(value) + "*2"]))
    if kind == 7 and isinstance(value, list) and value:  # duplicate or drop list items
        if rng.random() < 0.5:
            value.append(value[rng.randrange(len(value))])
        else:
            value.pop(rng.randrange(len(value)))
    return doc


def _mutated_text(text: str, rng: random.Random) -> str:
    choice = rng.random()
    if choice < 0.75:
        try:
            doc = yaml.safe_load(text)
        except yaml.YAMLError:
            return text
        for _ in range(rng.randint(1, 3)):
            doc = _mutate(doc, rng)
        try:
            return yaml.safe_dump(doc, sort_keys=False, allow_unicode=True)
        except (yaml.YAMLError, TypeError, ValueError):
            return text
    chars = list(text)
    if choice < 0.85:
        return text[:rng.randrange(len(text))]
    for _ in range(rng.randint(1, 5)):
        chars[rng.randrange(len(chars))] = rng.choice(list("{}[]:,-#&*!|>'\"%@` \n\t0aZ\u00e9"))
    return "".join(chars)


URDFS = sorted((REPO / "tests" / "data" / "urdf").glob("*.urdf"))
ODD_ATTRIBUTES = ["", " ", "nan", "inf", "-inf", "1e999", "1e-320", "abc", "0 0", "1 2 3 4", "0 0 0",
                  "-1", "1e100 0 0", "floating", "planar", "continuous", "fixed", "&amp;", "x\ny",
                  "1.57079632679 0 0", "é", "0x10", "1_000", "+.5 -.5 .5"]


def _mutated_urdf(text: str, rng: random.Random) -> str:
    """A URDF with attribute values replaced, elements dropped or doubled, or bytes changed."""
    import re
    choice = rng.random()
    if choice < 0.6:
        values = list(re.finditer(r'="([^"]*)"', text))
        for _ in range(rng.randint(1, 3)):
            match = rng.choice(values)
            text = text[:match.start(1)] + rng.choice(ODD_ATTRIBUTES + [match.group(1)[::-1]]) + text[match.end(1):]
            values = list(re.finditer(r'="([^"]*)"', text))
        return text
    lines = text.splitlines(keepends=True)
    if choice < 0.8:
        k = rng.randrange(len(lines))
        return "".join(lines[:k] + (lines[k:k + 1] * 2 if rng.random() < 0.5 else []) + lines[k + 1:])
    if choice < 0.9:
        return text[:rng.randrange(len(text))]
    chars = list(text)
    for _ in range(rng.randint(1, 5)):
        chars[rng.randrange(len(chars))] = rng.choice(list('<>/="& \n!?[]-0aZ\u00e9'))
    return "".join(chars)


def _cases(rng: random.Random, root):
    """Endless (label, file to generate, functions) cases; scenes name a mutated robot beside them."""
    robots = {name: (REPO / "robots" / f"{name}.yaml").read_text() for name in SOURCES}
    scenes = {path.name: path.read_text() for path in SCENES}
    urdfs = {path.name: path.read_text() for path in URDFS}
    index = 0
    while True:
        index += 1
        case = root / f"case{index}"
        case.mkdir()
        if rng.random() < 0.2:
            name, text = rng.choice(sorted(urdfs.items()))
            target = case / name
            target.write_text(_mutated_urdf(text, rng), encoding="utf-8")
            yield f"case{index} ({name})", target, rng.choice(FUNCTION_SETS)
            continue
        if rng.random() < 0.25:
            name, text = rng.choice(sorted(scenes.items()))
            doc = yaml.safe_load(text)
            robot_name = os.path.basename(doc["robot"])
            shutil.copy(REPO / "robots" / robot_name, case / robot_name)
            doc["robot"] = robot_name
            if rng.random() < 0.5:  # the robot is mutated, the scene kept
                (case / robot_name).write_text(_mutated_text((case / robot_name).read_text(), rng))
                text = yaml.safe_dump(doc, sort_keys=False)
            else:
                text = _mutated_text(yaml.safe_dump(doc, sort_keys=False), rng)
            target = case / name
        else:
            name, text = rng.choice(sorted(robots.items()))
            text = _mutated_text(text, rng)
            target = case / f"{name}.yaml"
        target.write_text(text, encoding="utf-8")
        yield f"case{index} ({name})", target, rng.choice(FUNCTION_SETS)


def _alarm(signum, frame):
    raise CaseTimeout()


@pytest.mark.skipif(not hasattr(signal, "SIGALRM"), reason="needs SIGALRM")
def test_fuzz_generate(tmp_path, capsys):
    rng = random.Random(SEED)
    compiler = shutil.which("cc") or shutil.which("gcc")
    deadline = time.monotonic() + BUDGET_SECONDS
    outcomes = {0: 0, 1: 0}
    problems = []
    previous = signal.signal(signal.SIGALRM, _alarm)
    try:
        for label, path, functions in _cases(rng, tmp_path):
            if time.monotonic() > deadline:
                break
            out = path.parent / "out"
            signal.alarm(CASE_SECONDS)
            try:
                status = main(["generate", str(path), "--out", str(out), "--quiet", "--no-cache",
                               "--functions", functions])
            except CaseTimeout:
                problems.append(f"{label}: more than {CASE_SECONDS} s")
                continue
            finally:
                signal.alarm(0)
            captured = capsys.readouterr()
            lines = captured.err.strip().splitlines()
            if status == 1:  # warnings may come first; then exactly one error line, the last
                if (not lines or not lines[-1].startswith("symdyn: error: ") or "Traceback" in captured.err
                        or any(not line.startswith("symdyn: warning: ") for line in lines[:-1])):
                    problems.append(f"{label}: exit 1 with {captured.err[:300]!r}")
            elif status == 0:
                if "Traceback" in captured.err or any(not line.startswith("symdyn: warning: ") for line in lines):
                    problems.append(f"{label}: exit 0 with {captured.err[:300]!r}")
                sources = sorted(out.glob("*.c"))
                if not sources:
                    problems.append(f"{label}: exit 0 but no C")
                elif compiler:
                    build = subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror",
                                            "-fsyntax-only", *map(str, sources)], capture_output=True, text=True)
                    if build.returncode != 0:
                        problems.append(f"{label}: C does not compile: {build.stderr[:300]}")
            else:
                problems.append(f"{label}: exit {status}: {captured.err[:300]!r}")
            if status in outcomes:
                outcomes[status] += 1
    finally:
        signal.signal(signal.SIGALRM, previous)
    print(f"fuzz: seed {SEED}, {outcomes[0]} generated, {outcomes[1]} refused")
    assert not problems, "\n".join(problems[:20])
    assert outcomes[0] + outcomes[1] >= 10, outcomes  # the budget ran real cases
    assert outcomes[0] and outcomes[1], outcomes  # and both kinds of outcome
