import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import symdyn  # noqa: E402
from symdyn.check.cbuild import OPTIMIZATION_VARIABLE  # noqa: E402

#: the suite's libraries compile at -O1 (symdyn.check.cbuild.OPTIMIZATION_VARIABLE: the same
#: numbers, compiles about 40% faster); the tests of -O2's and -O3's warnings name their flags
os.environ.setdefault(OPTIMIZATION_VARIABLE, "-O1")
from helpers import robot_path  # noqa: E402

_EQUATIONS = {}


@pytest.fixture(scope="session")
def derived():
    """derived(name, method) -> Equations, derived once per test session."""
    def get(name, method="newton-euler"):
        key = (name, method)
        if key not in _EQUATIONS:
            _EQUATIONS[key] = symdyn.derive(symdyn.load(robot_path(name)), method)
        return _EQUATIONS[key]
    return get


#: pyproject.toml runs pytest-xdist with ``--dist loadfile``: each file on one worker, so that a
#: module-scoped fixture (several derive, emit and compile a whole robot, 12-16 s each) is set up
#: once rather than once per worker.  The files are handed out in collection order: these, the
#: longest in total (30-100 s each on 2 cores), first and longest first, so that no long file
#: starts last and keeps one worker busy while the other idles.
LONG_FIRST = (
    "tests/test_readme.py",
    "tests/check/test_differential_fuzz.py",
    "tests/check/test_trust_regressions.py",
    "tests/derive/test_derivatives.py",
    "tests/emit/test_cgen.py",
    "tests/emit/test_parallel_codegen.py",
    "tests/model/test_urdf_robots.py",
    "tests/emit/test_printout.py",
    "tests/check/test_hard_cases.py",
    "tests/emit/test_printout_layout.py",
    "tests/test_benchmark_scripts.py",
    "tests/check/test_pinocchio_agreement.py",
    "tests/emit/test_batch.py",
    "tests/derive/test_trees.py",
    "tests/derive/test_task_space.py",
    "tests/derive/test_symbolic.py",
    "tests/cli/test_platform_verify_bench.py",
    "tests/derive/test_scaling_paths.py",
    "tests/test_registry.py",
    "tests/derive/test_articulated_body.py",
    "tests/derive/test_regressor.py",
    "tests/emit/test_firmware.py",
    "tests/emit/test_pipeline.py",
)


def pytest_collection_modifyitems(config, items):
    """Run the files of :data:`LONG_FIRST` first, in that order (a stable sort: every worker
    sees the same order, and each file's tests stay together and in order)."""
    def rank(item):
        path = item.nodeid.split("::")[0]
        return LONG_FIRST.index(path) if path in LONG_FIRST else len(LONG_FIRST)
    items.sort(key=rank)
