"""Long function bodies in parts (symdyn.emit.cbody.SPLIT_FROM_STATEMENTS): with the limits
lowered so that puma560's functions are split into many parts, every function gives the same
bytes as the unsplit build, statuses included, and the split C is warning-free (gcc strict,
clang -Weverything, header-only too)."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

import symdyn
import symdyn.emit.cbody as cbody
from helpers import robot_path
from symdyn.check.cbuild import build_and_load
from symdyn.emit.cgen import generate_c
from symdyn.model.outputs import OUTPUTS, TASK_OUTPUTS

FUNCTIONS = OUTPUTS + TASK_OUTPUTS


@pytest.fixture(scope="module")
def puma():
    robot = symdyn.load(robot_path("puma560"))
    return robot, symdyn.derive(robot, outputs=FUNCTIONS)


def _split_files(eqs, monkeypatch, **kwargs):
    for limit, size in (("SPLIT_FROM_STATEMENTS", "PART_LINES"),):
        monkeypatch.setattr(cbody, limit, 50)
        monkeypatch.setattr(cbody, size, 37)
    return generate_c(eqs, FUNCTIONS, **kwargs)


def test_split_bodies_give_the_same_bytes(puma, tmp_path, monkeypatch):
    robot, eqs = puma
    (tmp_path / "plain").mkdir()
    (tmp_path / "split").mkdir()
    plain = build_and_load(generate_c(eqs, FUNCTIONS), robot.name, 6, 0, "double", str(tmp_path / "plain"))
    files = _split_files(eqs, monkeypatch)
    assert files["puma560_dynamics.c"].count("_part") > 100
    split = build_and_load(files, robot.name, 6, 0, "double", str(tmp_path / "split"))
    rng = np.random.default_rng(0)
    for k in range(12):
        q, qd, qdd, tau = (rng.uniform(-2, 2, 6) for _ in range(4))
        if k == 10:
            q[4] = 0.0  # the wrist straight: the task is singular (status 3)
        if k == 11:
            q[2] = np.nan  # status 2
        for name, args in (("inverse_dynamics", (q, qd, qdd)), ("mass_matrix", (q,)), ("coriolis", (q, qd)),
                           ("coriolis_matrix", (q, qd)), ("gravity", (q,)), ("forward_kinematics", (q,)),
                           ("jacobian", (q,)), ("jacobian_dot_qd", (q, qd))):
            a, b = getattr(plain, name)(*args), getattr(split, name)(*args)
            if k == 11:  # NaN in, NaN out (a NaN's sign bit may differ with the order of operations)
                assert np.array_equal(np.isnan(a), np.isnan(b)) and np.array_equal(a[~np.isnan(a)], b[~np.isnan(b)]), name
            else:
                assert a.tobytes() == b.tobytes(), name
        a, b = plain.forward_dynamics_checked(q, qd, tau), split.forward_dynamics_checked(q, qd, tau)
        assert a[0] == b[0] and a[1].tobytes() == b[1].tobytes()
        a, b = plain.with_status("task_space", q, qd), split.with_status("task_space", q, qd)
        assert a[0] == b[0] and all(x.tobytes() == y.tobytes() for x, y in zip(a[1], b[1]))
        assert (a[0], b[0]) != (0, 0) or k < 10


@pytest.mark.parametrize("compiler", ["gcc", "clang"])
def test_split_bodies_compile_without_warnings(puma, tmp_path, monkeypatch, compiler):
    if shutil.which(compiler) is None:
        pytest.skip(f"{compiler} is not installed")
    from test_cgen import CLANG_EVERYTHING
    flags = CLANG_EVERYTHING if compiler == "clang" else ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror"]
    _, eqs = puma
    for precision, header_only in (("double", False), ("float", True)):  # each form and each precision once
        folder = tmp_path / f"{precision}{int(header_only)}"
        folder.mkdir()
        for name, text in _split_files(eqs, monkeypatch, precision=precision, header_only=header_only).items():
            (folder / name).write_text(text)
        target = folder / "puma560_dynamics.c"
        if header_only:
            target = folder / "main.c"
            target.write_text('#include "puma560_dynamics.h"\nint main(void) { return 0; }\n')
        # gcc warns after optimizing (-O2); clang's warnings come from its front end
        build = ["-fsyntax-only"] if compiler == "clang" else ["-O2", "-c", "-o", str(folder / "out.o")]
        run = subprocess.run([compiler, *flags, *build, str(target)], capture_output=True, text=True)
        assert run.returncode == 0, (precision, header_only, run.stderr[:2000])


def _parts(text: str) -> dict[str, list[str]]:
    """The body lines of each part function in a generated C file, by name."""
    parts, name, lines = {}, None, []
    for line in text.splitlines():
        if line.startswith("static") and "_part" in line and "(" in line:
            name, lines = line.split("(")[0].split()[-1], []
        elif name and line == "}":
            parts[name], name = lines, None
        elif name and line != "{":
            lines.append(line.strip())
    return parts


def test_parts_keep_their_budget_and_load_carried_values_where_used(puma, monkeypatch):
    """Each part holds about PART_LINES lines (statements, results and loads from earlier parts
    counted alike); a value from an earlier part is loaded right before its first use and stored
    right after it is made (so it is not live through the whole part)."""
    _, eqs = puma
    text = _split_files(eqs, monkeypatch)["puma560_dynamics.c"]
    parts = _parts(text)
    assert len(parts) > 100
    last = {}
    for name in parts:
        function, k = name.rsplit("_part", 1)
        last[function] = max(last.get(function, 0), int(k))
    for name, lines in parts.items():
        body = [line for line in lines if not line.startswith(("(void)", "carry[")) and line]
        counted = [line for line in body if line.endswith(";") or line.endswith("{")]
        function, k_part = name.rsplit("_part", 1)
        if int(k_part) < last[function]:  # (the last part also writes the results at the end and runs the loops)
            assert len(counted) <= 37 + 8, (name, len(counted))  # one statement's lines may cross the budget
        defined = {}
        for k, line in enumerate(body):
            if line.startswith("const ") and "= carry[" in line:
                symbol = line.split()[2]
                uses = [j for j, other in enumerate(body) if j > k and f" {symbol}" in f" {other}".replace("(", " ")
                        .replace(",", " ").replace("*", " ").replace("-", " ")]
                assert uses, (name, symbol)  # loaded only where read
                if int(k_part) < last[function]:  # (the last part loads the results' values before writing them)
                    between = [other for other in body[k:uses[0]] if "= carry[" not in other]
                    assert len(between) <= 3, (name, symbol)  # just before the statement (or its check) reading it
                defined[symbol] = k
        for line in lines:
            if line.startswith("carry["):
                symbol = line.split("=")[1].strip(" ;")
                made = [j for j, other in enumerate(lines) if other.startswith("const ") and other.split()[2] == symbol]
                stored = lines.index(line)
                assert made and stored - made[0] <= 12, (name, symbol)  # right after its statement and early writes


def test_c_in_several_files_gives_the_same_bytes(puma, tmp_path):
    """C over the file budget is written as NAME_dynamics.c, NAME_dynamics_2.c, ... of whole
    functions (symdyn.emit.cgen.C_FILE_BYTES): each file compiles on its own warning-free, the
    header says to compile them all, one warning says so, and the library of them all computes the
    same bytes as the one file."""
    robot, eqs = puma
    from symdyn.model.errors import SymdynWarning
    one = generate_c(eqs, FUNCTIONS)
    with pytest.warns(SymdynWarning, match="written as [0-9]+ files"):
        several = generate_c(eqs, FUNCTIONS, file_bytes=len(one["puma560_dynamics.c"]) // 4)
    sources = [name for name in several if name.endswith(".c")]
    assert sources[0] == "puma560_dynamics.c" and sources[1:] == [f"puma560_dynamics_{k}.c" for k in range(2, len(sources) + 1)]
    assert len(sources) >= 4
    assert all(name in several["puma560_dynamics.h"] for name in sources)  # the header's note lists them
    for name, text in several.items():
        (tmp_path / name).write_text(text)
    for name in sources:  # each a translation unit of its own, warning-free
        run = subprocess.run(["gcc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O0", "-c",
                              str(tmp_path / name), "-o", str(tmp_path / (name + ".o"))], capture_output=True, text=True)
        assert run.returncode == 0, (name, run.stderr[:2000])
    (tmp_path / "one").mkdir()
    (tmp_path / "several").mkdir()
    a = build_and_load(one, robot.name, 6, 0, "double", str(tmp_path / "one"))
    b = build_and_load(several, robot.name, 6, 0, "double", str(tmp_path / "several"))
    rng = np.random.default_rng(1)
    for _ in range(3):
        q, qd, qdd, tau = (rng.uniform(-2, 2, 6) for _ in range(4))
        for name, args in (("inverse_dynamics", (q, qd, qdd)), ("mass_matrix", (q,)), ("coriolis_matrix", (q, qd)),
                           ("jacobian", (q,)), ("gravity", (q,))):
            assert getattr(a, name)(*args).tobytes() == getattr(b, name)(*args).tobytes(), name
        assert a.forward_dynamics_checked(q, qd, tau)[1].tobytes() == b.forward_dynamics_checked(q, qd, tau)[1].tobytes()


def test_many_numbers_are_written_by_tables_with_the_same_bytes(puma, tmp_path, monkeypatch):
    """An output with many entries that are numbers (symdyn.emit.cbody.NUMBER_TABLE_FROM: TIAGo
    dual's mass matrix has 8700 zeros) writes each value shared by many entries by a loop over a
    table of indices: lowered so that puma560's outputs use them, the same bytes, warning-free."""
    robot, eqs = puma
    plain = build_and_load(generate_c(eqs, FUNCTIONS), robot.name, 6, 0, "double", str(tmp_path))
    monkeypatch.setattr(cbody, "NUMBER_TABLE_FROM", 3)
    monkeypatch.setattr(cbody, "NUMBER_TABLE_MIN", 2)
    monkeypatch.setattr(cbody, "EARLY_OUTPUTS_FROM", -1)  # (the entries that are numbers are written first)
    files = generate_c(eqs, FUNCTIONS)
    text = files["puma560_dynamics.c"]
    assert text.count("static const unsigned int puma560_") >= 3
    (tmp_path / "tables").mkdir()
    for name, content in files.items():
        (tmp_path / "tables" / name).write_text(content)
    run = subprocess.run(["gcc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O2", "-c",
                          str(tmp_path / "tables" / "puma560_dynamics.c"), "-o", str(tmp_path / "t.o")],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[:2000]
    tables = build_and_load(files, robot.name, 6, 0, "double", str(tmp_path / "tables"))
    rng = np.random.default_rng(2)
    for _ in range(3):
        q, qd = rng.uniform(-2, 2, 6), rng.uniform(-2, 2, 6)
        for name, args in (("mass_matrix", (q,)), ("coriolis_matrix", (q, qd)), ("jacobian", (q,))):
            a, b = getattr(plain, name)(*args), getattr(tables, name)(*args)
            assert a.tobytes() == b.tobytes(), name
