"""symdyn verify and symdyn bench of platform robots (kind: parallel): every generated function
against Pinocchio's closed loop (symdyn.check.closed_loop) with the same table as for arms, the
statuses at states out of reach, singular and overflowing, a poisoned generated C that fails,
a small bench report, and the options that do not apply refused in one line."""

import re

import pytest

from helpers import REPO
from symdyn.cli import main
from symdyn.derive.parallel import FUNCTIONS

pytest.importorskip("pinocchio")
FLIGHT = str(REPO / "robots" / "parallel" / "flight_simulator.yaml")
SRU = str(REPO / "robots" / "parallel" / "sru_platform.yaml")


def _errors(out: str) -> dict:
    """verify's table: {function: (normalized error, 'ok' or 'FAIL')}."""
    rows = {}
    for line in out.splitlines():
        match = re.match(r"^(\w+)\s+(\S+)\s+(ok|FAIL)$", line)
        if match and match.group(1) in FUNCTIONS:
            rows[match.group(1)] = (float(match.group(2)), match.group(3))
    return rows


def _statuses(out: str) -> dict:
    """verify's status table: {state: (reference's statuses, the C's, 'ok' or 'FAIL')}."""
    lines = out.splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith("state ")) + 1
    rows = {}
    for line in lines[start:]:
        match = re.match(r"^(.*?)\s{2,}([\d ]+?)\s{2,}([\d ]+?)\s{2,}(ok|FAIL)$", line)
        if match:
            rows[match.group(1)] = match.group(2, 3, 4)
    return rows


def _case(rows: dict, words: str):
    (found,) = [value for label, value in rows.items() if words in label]
    return found


def test_verify_platform_checks_every_function_and_status(capsys):
    """The flight simulator: the six functions within 1e-10 of Pinocchio's closed loop at seeded
    random states, and the documented statuses, the same from the C and the reference: a zero
    quaternion UNREACHABLE (1), turned 90 degrees about the vertical SINGULAR (3) where K is used
    (forward dynamics and inverse kinematics are defined there), a leg in a serial singularity
    LEG_SINGULAR (2), a twist of 1e155 NOT_FINITE (4) from the dynamics."""
    assert main(["verify", FLIGHT, "--states", "20"]) == 0
    out = capsys.readouterr().out
    assert "against Pinocchio's closed-loop model" in out and "FAIL" not in out
    errors = _errors(out)
    assert set(errors) == set(FUNCTIONS)
    assert all(status == "ok" and 0 <= error <= 1e-10 for error, status in errors.values()), errors
    assert "the reference returns 0 at 20 of the 20 random states" in out
    rows = _statuses(out)
    for words, codes in (("zero quaternion", "1 1 1 1 1 1"), ("turned 90 deg", "3 0 3 3 3 0"),
                         ("serial singularity", "2 2 2 2 2 2"), ("overflow", "4 4 0 0 0 0")):
        assert _case(rows, words) == (codes, codes, "ok"), (words, rows)


def test_verify_platform_fails_on_poisoned_code(monkeypatch, capsys):
    """A generated twist map with one entry off by 1e-7 of itself and its pivot check switched off
    fails: its error shows in the table and, lowered to its parallel singularity, the platform
    returns 0 where the reference says SINGULAR (3)."""
    import symdyn.cli.verify as verify
    real = verify.generate_parallel_c

    def poisoned(*args, **kwargs):
        files = real(*args, **kwargs)
        source = next(k for k in files if k.endswith(".c"))
        header = next(k for k in files if k.endswith(".h"))
        text = files[source].replace("result[7] = sol_T[7];", "result[7] = 1.0000001 * sol_T[7];", 1)
        rtol = re.sub(r"(#define SRU_PLATFORM_PIVOT_RTOL) \S+", r"\1 0.0", files[header], count=1)
        assert "1.0000001 *" in text and "PIVOT_RTOL 0.0" in rtol
        files[source], files[header] = text, rtol
        return files
    monkeypatch.setattr(verify, "generate_parallel_c", poisoned)
    assert main(["verify", SRU, "--functions", "twist_map", "--states", "5"]) == 1
    out = capsys.readouterr().out
    error, status = _errors(out)["twist_map"]
    assert status == "FAIL" and 1e-9 < error < 1e-5, out
    ref, ours, status = _case(_statuses(out), "parallel singularity")
    assert ref == "3" and ours != "3" and status == "FAIL", out
    assert "twist_map: lowered" in out  # the mismatch, named


def test_bench_platform_report(tmp_path, capsys):
    """A small bench of a platform: the table, bench.md and bench.csv of the serial bench, symdyn
    C timed with its error against the closed loop, Pinocchio's closed-loop inverse dynamics
    timed, and a row saying Pinocchio has no equivalent of the twist map."""
    out = tmp_path / "report"
    assert main(["bench", FLIGHT, "--functions", "inverse_dynamics,twist_map", "--variants", "noc-double,pinocchio",
                 "--states", "3", "--out", str(out), "--quiet"]) == 0
    table = capsys.readouterr().out
    rows = {}
    for line in table.splitlines()[2:]:
        robot, function, variant, ns, ops, error = (cell.strip() for cell in line.strip("|").split("|"))
        rows[function, variant] = (ns, ops, error)
    assert set(rows) == {("inverse_dynamics", "noc-double"), ("twist_map", "noc-double"),
                         ("inverse_dynamics", "pinocchio rnea + constraint Jacobian + LU (Python bindings)"),
                         ("twist_map", "pinocchio: no closed-loop equivalent")}, rows
    for function in ("inverse_dynamics", "twist_map"):
        ns, ops, error = rows[function, "noc-double"]
        assert float(ns) > 0 and int(ops) > 1000 and float(error) <= 1e-10
    ns, ops, error = rows["inverse_dynamics", "pinocchio rnea + constraint Jacobian + LU (Python bindings)"]
    assert float(ns) > 0 and ops == "-" and float(error) <= 1e-12
    assert rows["twist_map", "pinocchio: no closed-loop equivalent"] == ("-", "-", "-")
    report = (out / "bench.md").read_text()
    assert table in report and "Pinocchio's closed-loop model" in report and "no equivalent of mass_matrix" in report
    data = (out / "bench.csv").read_text().splitlines()
    assert data[0].startswith("robot,function,variant") and len(data) == 5
    assert any(line.startswith("flight_simulator,twist_map,noc-double,") for line in data)


@pytest.mark.parametrize("argv, words", [
    (["verify", FLIGHT, "--method", "lagrange-euler"], "--method does not apply to a platform robot (kind: parallel)"),
    (["verify", FLIGHT, "--precision", "mixed"], "generated in double or float precision, not mixed"),
    (["verify", FLIGHT, "--functions", "coriolis"], "unknown function 'coriolis' in --functions for a platform robot"),
    (["bench", FLIGHT, "--variants", "ne-double"], "no variant in --variants applies to a platform robot"),
    (["bench", FLIGHT, "--fd-method", "aba"], "--fd-method does not apply to a platform robot"),
    (["bench", FLIGHT, "--variants", "fastest"], "unknown variant 'fastest'"),
    (["bench", str(REPO / "robots" / "puma560.yaml"), "--variants", "noc-double"],
     "no variant in --variants applies to a serial robot"),
])
def test_platform_options_refused_in_one_line(argv, words, capsys):
    assert main(argv) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("symdyn: error: ") and words in err[0], err
