"""The float C's sin/cos block (templates/trig.j2, NAME_sincosf): float only, within 1e-7 of the
exact sine and cosine of the float argument for |x| <= 1e5, libm's sinf and cosf beyond."""

import ctypes
import math

import numpy as np
import pytest

from symdyn.check.cbuild import compile_shared
from symdyn.emit.pipeline import GenerateOptions, configure, generate

from helpers import robot_path


@pytest.fixture(scope="module")
def sincosf(tmp_path_factory):
    """sincosf(x) -> (s, c): the generated block of a float build, compiled with the test's
    strict flags (the .c included by a wrapper that exposes the static function)."""
    folder = tmp_path_factory.mktemp("trig_float")
    files = generate(configure(robot_path("puma560"), GenerateOptions(functions="gravity", precision="float")))
    for name, data in files.items():
        (folder / name).write_bytes(data)
    wrapper = folder / "wrapper.c"
    wrapper.write_text('#include "puma560_dynamics.c"\n'
                       "void sincosf_all(int n, const float *x, float *s, float *c);\n"
                       "void sincosf_all(int n, const float *x, float *s, float *c) { puma560_sincosf(n, x, s, c); }\n")
    lib = ctypes.CDLL(compile_shared(str(wrapper), str(folder), extra_flags=[f"-I{folder}"]))
    pointer = ctypes.POINTER(ctypes.c_float)

    def call(x):
        x = np.ascontiguousarray(x, dtype=np.float32)
        s, c = np.empty_like(x), np.empty_like(x)
        lib.sincosf_all(len(x), x.ctypes.data_as(pointer), s.ctypes.data_as(pointer), c.ctypes.data_as(pointer))
        return s, c
    return call


@pytest.mark.parametrize("limit", [1.0, 8.0, 1e3, 1e5])
def test_within_1e_7_of_the_exact_values(sincosf, limit):
    x = np.random.default_rng(int(limit)).uniform(-limit, limit, 100_000).astype(np.float32)
    s, c = sincosf(x)
    exact = x.astype(np.float64)
    assert np.abs(s - np.sin(exact)).max() <= 1e-7
    assert np.abs(c - np.cos(exact)).max() <= 1e-7


def test_quadrant_boundaries_and_signs(sincosf):
    """Multiples of pi/4 up to +-2000 pi/4 (where the rounded x 2/pi changes quadrant), and
    the sign of each result in every quadrant."""
    x = (np.arange(-2000, 2001) * np.pi / 4).astype(np.float32)
    s, c = sincosf(x)
    exact = x.astype(np.float64)
    assert np.abs(s - np.sin(exact)).max() <= 1e-7 and np.abs(c - np.cos(exact)).max() <= 1e-7
    quarter = np.array([0.3, 1.9, 3.5, 5.1, -0.3, -1.9, -3.5, -5.1], dtype=np.float32)
    s, c = sincosf(quarter)
    assert np.array_equal(np.sign(s), np.sign(np.sin(quarter.astype(np.float64))))
    assert np.array_equal(np.sign(c), np.sign(np.cos(quarter.astype(np.float64))))


def test_angles_beyond_the_range_go_to_libm(sincosf):
    x = np.array([1.5e5, -3.0e7, np.inf, -np.inf, np.nan], dtype=np.float32)
    s, c = sincosf(x)
    for value, sine, cosine in zip(x[:2], s[:2], c[:2]):
        assert abs(sine - math.sin(float(value))) <= 1e-6 and abs(cosine - math.cos(float(value))) <= 1e-6
    assert np.isnan(s[2:]).all() and np.isnan(c[2:]).all()
