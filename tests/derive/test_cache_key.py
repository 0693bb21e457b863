"""The derivation cache's key reads every field of the model (tests/derive/test_cache.py has the
cache's storage and trust).

Every field of every dataclass reachable from :class:`symdyn.model.robot.Robot`'s type hints is
changed, one at a time, in a robot that has them all (a URDF tree on a floating base with frames,
a base, a tool and a task), and the key must change; the fields the key leaves out are exactly
those :data:`symdyn.derive.cache.NOT_DERIVED` names with a reason.  A field added later is
walked like the others without anyone listing it.  Every argument of :func:`symdyn.derive` but
``progress`` changes the key too.
"""

from __future__ import annotations

import dataclasses
import inspect
import typing

import pytest
import sympy as sp

import symdyn
from helpers import example_robot_data
from symdyn.derive import cache
from symdyn.derive.equations import derive
from symdyn.model import robot as robot_module
from symdyn.model.robot import Contact, Mimic, Placement, Robot

OUTPUTS = ("gravity", "frame_poses")


def _dataclasses_of(kind, found=None) -> dict:
    """Every dataclass type reachable from ``kind``'s field annotations: {name: type}."""
    found = {} if found is None else found
    if kind.__name__ in found:
        return found
    found[kind.__name__] = kind
    for hint in typing.get_type_hints(kind, vars(robot_module)).values():
        for arg in _flatten(hint):
            if dataclasses.is_dataclass(arg):
                _dataclasses_of(arg, found)
    return found


def _flatten(hint):
    yield hint
    for arg in typing.get_args(hint):
        yield from _flatten(arg)


def _changed(value):
    """A different value of a field (any type the key must read differently)."""
    if value is None:
        return sp.Integer(7)
    if isinstance(value, bool):
        return not value
    if isinstance(value, (int, float)):
        return value + 1
    if isinstance(value, str):
        return value + "_x"
    if isinstance(value, sp.Basic):
        return value + 1 if isinstance(value, sp.Expr) and not isinstance(value, sp.Symbol) else sp.Symbol("z_new", real=True)
    if dataclasses.is_dataclass(value):
        return None
    if isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
        return value[:-1]  # one item fewer (each item's own fields are changed one by one)
    if isinstance(value, tuple):
        return (_changed(value[0]),) + value[1:] if value else (sp.Integer(7),)
    raise AssertionError(f"no change for a {type(value).__name__}")


def _variants(value, covered: set):
    """(path, changed copy of ``value``) for every field reachable in it, each changed alone."""
    if dataclasses.is_dataclass(value):
        for f in dataclasses.fields(value):
            covered.add((type(value).__name__, f.name))
            current = getattr(value, f.name)
            yield f.name, dataclasses.replace(value, **{f.name: _changed(current)})
            for path, inner in _variants(current, covered):
                yield f"{f.name}.{path}", dataclasses.replace(value, **{f.name: inner})
    elif isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
        for index in {0, len(value) - 1}:  # the first and the last (a root, a tip, a frame)
            for path, inner in _variants(value[index], covered):
                yield f"[{index}].{path}", value[:index] + (inner,) + value[index + 1:]


@pytest.fixture(scope="module")
def sample():
    """A robot in which every optional field is set."""
    robot = symdyn.load(example_robot_data("solo_description/robots/solo12.urdf"), floating_base=True,
                        frames=["FL_FOOT", "HR_FOOT"])
    place = Placement((sp.Float(0.1), sp.Integer(0), sp.Integer(0)), (sp.Integer(0), sp.Integer(0), sp.Float(0.2)))
    last = dataclasses.replace(robot.links[-1], mimic=Mimic(0, sp.Float(0.5), sp.Float(0.1)))
    robot = dataclasses.replace(robot, base=place, tool=place, task=(0, 1, 2), tool_fixed=tuple(sp.eye(4)),
                                notes=("a note",), links=robot.links[:-1] + (last,), contacts=(Contact(1, "3d"),))
    missing = [f"{type(v).__name__}.{f.name}" for v in (robot, robot.links[-1]) for f in dataclasses.fields(v)
               if getattr(v, f.name) is None]
    assert not [m for m in missing if m != "Link.fixed"], missing
    return robot


def test_every_field_changes_the_key(sample):
    key = cache.cache_key(sample, "newton-euler", OUTPUTS)
    covered: set = set()
    unchanged = []
    for path, variant in _variants(sample, covered):
        if (type(sample).__name__, path.split(".")[0]) in cache.NOT_DERIVED and "." not in path:
            assert cache.cache_key(variant, "newton-euler", OUTPUTS) == key, path
            continue
        if cache.cache_key(variant, "newton-euler", OUTPUTS) == key:
            unchanged.append(path)
    assert not unchanged, f"fields the key does not read: {unchanged}"
    every = {(name, f.name) for name, kind in _dataclasses_of(Robot).items() for f in dataclasses.fields(kind)}
    assert every - covered == set(), f"fields the walk did not reach: {sorted(every - covered)}"
    assert set(cache.NOT_DERIVED) <= every


def test_every_derive_argument_changes_the_key(sample):
    arguments = set(inspect.signature(derive).parameters) - {"robot", "progress"}
    assert arguments == {"method", "outputs", "fd_method", "parameters"}, "a new argument of derive: add it to the key"
    base = dict(method="newton-euler", outputs=OUTPUTS, fd_method="ldlt", parameters="standard")
    key = cache.cache_key(sample, **base)
    for name, other in [("method", "lagrange-euler"), ("outputs", OUTPUTS + ("mass_matrix",)), ("fd_method", "aba"),
                        ("parameters", "base")]:
        assert cache.cache_key(sample, **{**base, name: other}) != key, name


def test_unknown_types_are_refused():
    with pytest.raises(TypeError):
        cache.canonical(object())
