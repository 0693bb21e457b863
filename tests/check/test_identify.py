"""symdyn identify: base parameters from samples, round trip on simulated data (torques from
Pinocchio's rnea plus friction), with and without noise; bad data files are refused."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import symdyn
from helpers import REPO, PinocchioReference, robot_path
from symdyn.cli import main
from symdyn.derive.regressor import parameter_names, standard_parameters
from symdyn.model.samples import Samples, write_samples

PUMA = robot_path("puma560")


def _exciting(robot, count, seed):
    """Samples on a sum-of-sines trajectory per joint (five harmonics of 0.1 Hz, random
    amplitudes and phases), torques from Pinocchio's rnea plus viscous and Coulomb friction."""
    rng = np.random.default_rng(seed)
    n = robot.dof
    t = np.linspace(0, 20, count)[:, None]
    q, qd, qdd = np.zeros((count, n)), np.zeros((count, n)), np.zeros((count, n))
    for j in range(n):
        for harmonic in range(1, 6):
            w = 2 * np.pi * 0.1 * harmonic
            a, phase = rng.uniform(0.1, 0.5) / harmonic, rng.uniform(0, 2 * np.pi)
            q[:, j] += a * np.sin(w * t[:, 0] + phase)
            qd[:, j] += a * w * np.cos(w * t[:, 0] + phase)
            qdd[:, j] -= a * w * w * np.sin(w * t[:, 0] + phase)
    ref = PinocchioReference(robot)
    tau = np.array([ref.inverse_dynamics(q[k], qd[k], qdd[k]) for k in range(count)])
    return Samples(q, qd, qdd, tau)


@pytest.fixture(scope="module")
def puma():
    robot = symdyn.load(PUMA)
    eqs = symdyn.derive(robot, outputs=["base_regressor"])
    symbols = [sp.Symbol(n, real=True) for n in parameter_names(robot)]
    pi = dict(zip(symbols, (float(v) for v in standard_parameters(robot))))
    truth = np.array([float(expr.xreplace(pi)) for _, expr in eqs.base_parameters])
    return robot, eqs, truth


def test_noise_free_round_trip(puma, tmp_path, capsys):
    """Identified base parameters equal the true ones <= 1e-8 (relative to the largest); the
    written robot file loads and carries the friction values."""
    from symdyn.check.identify import identify
    robot, eqs, truth = puma
    samples = _exciting(robot, 400, seed=61)
    result = identify(eqs, samples)
    assert np.max(np.abs(result.values - truth)) <= 1e-8 * np.max(np.abs(truth))
    data = tmp_path / "data.csv"
    data.write_text(write_samples(samples))
    out = tmp_path / "identified.yaml"
    assert main(["identify", PUMA, str(data), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "condition number" in printed and "fv1" in printed
    identified = symdyn.load(str(out))
    for original, new in zip(robot.links, identified.links):
        assert abs(float(new.damping) - float(original.damping)) <= 1e-8 * (1 + abs(float(original.damping)))
        assert abs(float(new.coulomb) - float(original.coulomb)) <= 1e-8 * (1 + abs(float(original.coulomb)))


@pytest.mark.parametrize("weighted", [False, True])
def test_noisy_data_within_reported_deviations(puma, weighted):
    """With Gaussian torque noise (0.05 N m on joints 1-3, 0.005 on 4-6), every identified base
    parameter lies within 4 reported standard deviations of the truth."""
    from symdyn.check.identify import identify
    robot, eqs, truth = puma
    samples = _exciting(robot, 600, seed=62)
    noise = np.random.default_rng(63).normal(0, 1, samples.tau.shape) * np.array([0.05] * 3 + [0.005] * 3)
    noisy = Samples(samples.q, samples.qd, samples.qdd, samples.tau + noise)
    result = identify(eqs, noisy, weighted=weighted)
    assert np.all(np.abs(result.values - truth) <= 4 * result.std), np.max(np.abs(result.values - truth) / result.std)
    assert np.all(result.std > 0)


def test_bad_data_files_are_refused(tmp_path, capsys):
    """Too short, a NaN, wrong columns, text in a number: one line naming the file, exit 1."""
    robot = symdyn.load(PUMA)
    samples = _exciting(robot, 5, seed=64)
    good = write_samples(samples)
    cases = {
        "short.csv": (good, "too short"),
        "nan.csv": (good.replace(good.splitlines()[2].split(",")[3], "nan", 1), "not a finite number"),
        "columns.csv": (good.replace("tau6", "torque6"), "wrong columns"),
        "text.csv": (good.replace(good.splitlines()[1].split(",")[0], "abc", 1), "is not a number"),
        "semicolons.csv": (good.replace(",", ";"), "separated by semicolons"),
        "longfield.csv": (good + "9" * 200_000 + "," + ",".join(["1"] * 23) + "\n", "not a readable CSV file"),
        "underscore.csv": (good.replace(good.splitlines()[1].split(",")[0], "1_000", 1), "is not a number"),
        "huge.csv": (good.replace(good.splitlines()[3].split(",")[20], "1e308", 1), "is beyond 1e+09 in magnitude"),
        "large.csv": (good.replace(good.splitlines()[3].split(",")[2], "-2e9", 1), "is beyond 1e+09 in magnitude"),
    }
    for name, (text, message) in cases.items():
        path = tmp_path / name
        path.write_text(text)
        assert main(["identify", PUMA, str(path)]) == 1, name
        err = capsys.readouterr().err
        assert message in err and name in err and err.count("\n") == 1, err


def test_spreadsheet_export_reads(tmp_path):
    """A byte-order mark, Windows line endings and comment lines are read as the plain file."""
    from symdyn.model.samples import read_samples
    samples = _exciting(symdyn.load(PUMA), 5, seed=65)
    plain = write_samples(samples)
    path = tmp_path / "excel.csv"
    path.write_bytes(b"\xef\xbb\xbf# exported\r\n" + plain.replace("\n", "\r\n").encode())
    again = read_samples(str(path), 6)
    assert np.array_equal(again.tau, samples.tau) and np.array_equal(again.q, samples.q)


def test_scara_round_trip():
    """A parameter with no effect (scara's my1: link 1 turns about the vertical) is not a base
    parameter, so identification of a 4-joint SCARA recovers its base parameters exactly."""
    from symdyn.check.identify import identify
    robot = symdyn.load(robot_path("scara"))
    eqs = symdyn.derive(robot, outputs=["base_regressor"])
    symbols = [sp.Symbol(n, real=True) for n in parameter_names(robot)]
    pi = dict(zip(symbols, (float(v) for v in standard_parameters(robot))))
    truth = np.array([float(expr.xreplace(pi)) for _, expr in eqs.base_parameters])
    result = identify(eqs, _exciting(robot, 300, seed=66))
    assert "my1" not in [name for name, _ in eqs.base_parameters]
    assert np.max(np.abs(result.values - truth)) <= 1e-8 * np.max(np.abs(truth))


def test_an_unreadable_robot_file_is_never_written(tmp_path):
    """identify refuses to write what symdyn would refuse to read (here a negative mass)."""
    from symdyn.cli.identify import _check_readable
    text = (REPO / "robots" / "planar2r.yaml").read_text()
    _check_readable(text, str(tmp_path / "ok.yaml"))
    broken = text.replace("m1: 1.0", "m1: -4.9e305") if "m1: 1.0" in text else None
    doc = "format: 1\nname: bad\nconvention: standard\nlinks:\n  - {joint: revolute, a: 1, alpha: 0, d: 0, theta: 0, mass: -3}\n"
    for bad in filter(None, (broken, doc)):
        with pytest.raises(symdyn.SymdynError, match="not writing .*symdyn would refuse the identified robot file"):
            _check_readable(bad, str(tmp_path / "bad.yaml"))



@pytest.mark.parametrize("weighted", [False, True])
def test_blocks_give_the_stacked_solution(puma, tmp_path, weighted):
    """Identification block by block (per-joint QR triangles updated as the samples stream in)
    gives what a least-squares solve of the whole stacked system gives (values, standard
    deviations, residuals, condition number), and the file read in blocks of 7 rows is the file
    read whole; a bad line in a later block is named by its line number."""
    from symdyn.check.identify import identify
    from symdyn.model.samples import read_samples, sample_blocks
    robot, eqs, _ = puma
    samples = _exciting(robot, 300, seed=64)
    noise = np.random.default_rng(65).normal(0, 0.02, samples.tau.shape)
    noisy = Samples(samples.q, samples.qd, samples.qdd, samples.tau + noise)
    data = tmp_path / "data.csv"
    data.write_text(write_samples(noisy))
    whole = read_samples(str(data), 6)
    blocks = list(sample_blocks(str(data), 6, rows=7))
    assert max(b.count for b in blocks) == 7 and sum(b.count for b in blocks) == 300
    streamed = identify(eqs, iter(blocks), weighted=weighted)
    # the reference: the stacked system solved at once (numpy's least squares)
    n, nb = 6, len(eqs.base_parameters)
    W = np.vstack([eqs.numeric.base_regressor(q, qd, qdd).reshape(n, nb) for q, qd, qdd in zip(whole.q, whole.qd, whole.qdd)])
    T = whole.tau.reshape(-1)
    scale = np.tile(streamed.weights, 300)
    beta, *_ = np.linalg.lstsq(W * scale[:, None], T * scale, rcond=None)
    np.testing.assert_allclose(streamed.values, beta, rtol=1e-9, atol=1e-9 * np.max(np.abs(beta)))
    residual = (T - W @ beta).reshape(-1, n)
    np.testing.assert_allclose(streamed.residual_rms, np.sqrt(np.mean(residual ** 2, axis=0)), rtol=1e-8)
    singular = np.linalg.svd(W * scale[:, None], compute_uv=False)
    assert streamed.condition == pytest.approx(singular[0] / singular[-1], rel=1e-8)
    lines = data.read_text().splitlines()
    lines[250] = lines[250].replace(",", ",x", 1)
    data.write_text("\n".join(lines) + "\n")
    with pytest.raises(symdyn.SymdynError, match="line 251"):
        list(sample_blocks(str(data), 6, rows=7))
