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
