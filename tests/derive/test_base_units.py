"""Base parameters do not depend on the units a file is written in: the Puma 560 in mm and g,
and with lengths and masses near 1e6, generates base-parameter inverse dynamics as accurate as
in m and kg (before: 1.4e-8 in mm and g, a normalized error of 0.97 near 1e6)."""

from __future__ import annotations

import shutil

import pytest
import yaml

from helpers import robot_path
from symdyn.cli import main


def scaled_puma(tmp_path, length: float, mass: float) -> str:
    """puma560.yaml with lengths times ``length`` and masses times ``mass`` (inertias, armature,
    damping and Coulomb friction in the matching units, gravity in length per s^2)."""
    with open(robot_path("puma560")) as handle:
        doc = yaml.safe_load(handle)
    moment = mass * length**2
    doc["gravity"] = [f"({g}) * {length!r}" for g in doc["gravity"]]
    for link in doc["links"]:
        for key in ("a", "d"):
            link[key] = f"({link[key]}) * {length!r}"
        link["com"] = [f"({c}) * {length!r}" for c in link["com"]]
        link["mass"] = f"({link['mass']}) * {mass!r}"
        link["inertia"] = [f"({i}) * {moment!r}" for i in link["inertia"]]
        for key in ("armature", "damping", "coulomb"):  # revolute joints: kg m^2, N m s, N m
            if key in link:
                link[key] = f"({link[key]}) * {moment!r}"
    path = tmp_path / f"puma_{length:g}_{mass:g}.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return str(path)


@pytest.mark.parametrize("length,mass", [(1e3, 1e3), (1e6, 1e6), (1e-3, 1.0)])
def test_base_parameters_in_any_units(tmp_path, monkeypatch, capsys, length, mass):
    if shutil.which("cc") is None:
        pytest.skip("no C compiler")
    pytest.importorskip("pinocchio")
    monkeypatch.setenv("SYMDYN_CACHE_DIR", str(tmp_path / "cache"))
    path = scaled_puma(tmp_path, length, mass)
    status = main(["verify", path, "--parameters", "base", "--functions", "inverse_dynamics", "--states", "20"])
    out = capsys.readouterr().out
    assert status == 0, out
    error = float(out.strip().splitlines()[-1].split()[1])
    assert error < 1e-13, out  # m and kg: 5e-16; before, 6e-12 in mm and g
