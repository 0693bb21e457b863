import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import symdyn  # noqa: E402
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


#: the files with the longest tests (10-35 s each on 2 cores), run first: with pytest-xdist's
#: load scheduling a long test that starts last keeps one worker busy while the other idles.
#: Whole files move, so that no module-scoped fixture is set up twice.
LONG_FIRST = (
    "tests/test_readme.py",
    "tests/emit/test_parallel_codegen.py",
    "tests/emit/test_cgen.py",
    "tests/derive/test_scaling_paths.py",
    "tests/emit/test_pipeline.py",
    "tests/derive/test_trees.py",
    "tests/check/test_hard_cases.py",
    "tests/derive/test_task_space.py",
    "tests/emit/test_split_bodies.py",
    "tests/cli/test_platform_verify_bench.py",
    "tests/test_benchmark_scripts.py",
    "tests/model/test_fuzz.py",
)


def pytest_collection_modifyitems(config, items):
    """Run the files of :data:`LONG_FIRST` first, in that order (a stable sort: every worker
    sees the same order, and each file's tests stay together and in order)."""
    def rank(item):
        path = item.nodeid.split("::")[0]
        return LONG_FIRST.index(path) if path in LONG_FIRST else len(LONG_FIRST)
    items.sort(key=rank)
