"""The generated header lists every model constant folded into the code (symdyn.emit.emission
constant_rows): parsed back from the header and compared, number by number, with the robot as
symdyn reads it (symdyn.load, the scene's locked joints, the platform robot's legs), so that a
missing or wrong constant fails; and the header's notes on unused functions and size reports."""

from __future__ import annotations

import re

import pytest
import sympy as sp

import symdyn
from helpers import REPO, ROBOTS
from symdyn.model.scene import load_input, load_scene

GENERATED = REPO / "generated"
SCENES = sorted(p.name for p in (REPO / "robots" / "scenes").glob("*.yaml"))
PLATFORMS = sorted(p.stem for p in (REPO / "robots" / "parallel").glob("*.yaml"))

_LINK = re.compile(r"link (\d+) \((\w+)\): (revolute|prismatic) joint, (general placement|standard DH|modified DH)"
                   r"(, passive \(not actuated\))?\Z")
_LEG = re.compile(r"leg (\w+): actuated joint (\d+) \((\w+)\)\Z")
_LIST_TITLES = ("passive joints", "locked by the scene", "runtime parameters")


# ---------------------------------------------------------------------------------------------
# Reading the listing back

def constant_lines(header: str) -> list[str]:
    """The rows of the header's model-constant listing, without the comment's ' *   ' (the
    indentation of nested rows kept)."""
    start = header.index(" * Model constants folded into the code")
    lines = header[start:].splitlines()
    first = lines.index(" *") + 1  # the legend ends with an empty comment line
    rows = []
    for line in lines[first:]:
        if not line.startswith(" *   "):
            break
        rows.append(line[len(" *   "):])
    assert rows, "no constant listed"
    return rows


def split_top(text: str, separator: str) -> list[str]:
    """``text`` split at ``separator`` outside brackets and parentheses."""
    parts, depth, current, k = [], 0, "", 0
    while k < len(text):
        if depth == 0 and text.startswith(separator, k):
            parts.append(current)
            current, k = "", k + len(separator)
            continue
        ch = text[k]
        depth += ch in "(["
        depth -= ch in ")]"
        current += ch
        k += 1
    return parts + [current]


def items(row: str) -> dict[str, str]:
    out = {}
    for item in split_top(row.strip(), "; "):
        key, sep, value = item.partition(" = ")
        assert sep, f"not 'key = value': {item!r} in {row!r}"
        assert key not in out, f"{key} twice in {row!r}"
        out[key] = value
    return out


def parse(rows: list[str]) -> dict:
    """``{"top": {key: text}, "lists": {title: text}, "links": [(title match, {key: text})],
    "legs": [(match, {key: text})]}``; for a platform, ``links`` are the shared table's (or,
    per leg, ``leg[2]``)."""
    parsed = {"top": {}, "lists": {}, "links": [], "legs": []}
    current = parsed["top"]
    for row in rows:
        text = row.strip()
        link, leg = _LINK.match(text), _LEG.match(text)
        if link:
            entry = (link, {})
            (parsed["legs"][-1][2] if parsed["legs"] and row.startswith("    ") else parsed["links"]).append(entry)
            current = entry[1]
        elif leg:
            entry = (leg, {}, [])
            parsed["legs"].append(entry)
            current = entry[1]
        elif text.startswith(_LIST_TITLES):
            title, _, rest = text.partition(": ")
            parsed["lists"][title.split(" (")[0]] = rest
        elif text.startswith("links of every leg"):
            current = None
        else:
            assert current is not None, row
            for key, value in items(text).items():
                assert key not in current, f"{key} twice"
                current[key] = value
    return parsed


def read_value(text: str, symbols: dict):
    """A listed value: its double (the text after the last ' = ') or, for an expression of
    runtime parameters, the SymPy expression; an exact form before ' = ' is returned too."""
    *exact, last = text.split(" = ")
    try:
        value = float(last)
    except ValueError:
        value = sp.sympify(last, locals=symbols, rational=True)  # its decimals exactly
    return value, (sp.sympify(exact[0], locals=symbols, rational=True) if exact else None)


def check_value(text: str, expected, symbols: dict, where: str) -> None:
    expected = sp.sympify(expected)
    value, exact = read_value(text, symbols)
    if expected.free_symbols:
        assert not isinstance(value, float) and sp.simplify(value - expected) == 0, f"{where}: {text} != {expected}"
        return
    assert isinstance(value, float), f"{where}: {text} is not a number"
    assert value == float(sp.N(expected, 30)), f"{where}: {text} != {float(sp.N(expected, 30))!r}"
    if exact is not None:
        assert sp.simplify(exact - expected) == 0, f"{where}: {exact} is not {expected}"


def check_vector(text: str, expected, symbols: dict, where: str) -> None:
    assert text.startswith("[") and text.endswith("]"), f"{where}: {text}"
    values = split_top(text[1:-1], ", ")
    assert len(values) == len(expected), f"{where}: {len(values)} values, expected {len(expected)}"
    for k, (value, want) in enumerate(zip(values, expected)):
        check_value(value, want, symbols, f"{where}[{k}]")


def check_fields(listed: dict, expected: dict, symbols: dict, where: str) -> None:
    """Every expected key listed with the expected value, and nothing else."""
    assert set(listed) == set(expected), f"{where}: listed {sorted(listed)}, expected {sorted(expected)}"
    for key, want in expected.items():
        if isinstance(want, (tuple, list)):
            check_vector(listed[key], want, symbols, f"{where} {key}")
        else:
            check_value(listed[key], want, symbols, f"{where} {key}")


# ---------------------------------------------------------------------------------------------
# What the listing must hold

ZEROS = (0, 0, 0)


def placement_fields(key: str, placement) -> dict:
    return {f"{key}.xyz": placement.xyz if placement else ZEROS, f"{key}.rpy": placement.rpy if placement else ZEROS}


def matrix_fields(key: str, entries) -> dict:
    entries = list(entries)
    return {f"{key}.row{r + 1}": entries[4 * r:4 * r + 4] for r in range(4)}


def link_fields(link, convention: str) -> dict:
    fields = {"mass": link.mass, "com": link.com, "inertia": link.inertia, "armature": link.armature,
              "damping": link.damping, "coulomb": link.coulomb}
    if convention == "general":
        fields.update(placement_fields("origin", link.origin))
        fields["axis"] = link.axis
    else:
        fields.update(a=link.a, alpha=link.alpha, d=link.d, theta=link.theta)
    if link.limits is not None:
        fields.update({f"limits.{key}": getattr(link.limits, key) for key in ("lower", "upper", "velocity", "effort")
                       if getattr(link.limits, key) is not None})
    if link.fixed is not None:
        fields.update(matrix_fields("fixed", link.fixed))
    return fields


def check_links(listed, links, convention: str, symbols: dict, where: str = "") -> None:
    assert len(listed) == len(links), f"{where}{len(listed)} links listed, the robot has {len(links)}"
    placement = "general placement" if convention == "general" else f"{convention} DH"
    for k, ((title, fields), link) in enumerate(zip(listed, links)):
        label = f"{where}link {k + 1} ({link.name})"
        assert title.groups()[:4] == (str(k + 1), link.name, link.joint, placement), label
        assert bool(title.group(5)) == (not link.actuated), label
        check_fields(fields, link_fields(link, convention), symbols, label)


def check_serial_header(header: str, robot, locked=()) -> None:
    """The listing of ``header`` holds exactly ``robot``'s constants (and the scene's ``locked``)."""
    symbols = {s.name: s for s in robot.parameters}
    parsed = parse(constant_lines(header))
    top = {"gravity": robot.gravity, **placement_fields("base", robot.base), **placement_fields("tool", robot.tool)}
    if robot.tool_fixed is not None:
        top.update(matrix_fields("tool.fixed", robot.tool_fixed))
    check_fields(parsed["top"], top, symbols, "top")
    lists = parsed["lists"]
    passive = ", ".join(f"{k + 1} ({robot.links[k].name})" for k in robot.passive_joints)
    assert lists.get("passive joints", "") == passive
    runtime = "; ".join(f"p[{k}] = {s.name}" for k, s in enumerate(robot.parameters))
    assert lists.get("runtime parameters", "") == runtime
    if locked:
        listed = split_top(lists["locked by the scene"], "; ")
        assert len(listed) == len(locked)
        for text, (index, name, value) in zip(listed, locked):
            key, _, shown = text.partition(" = ")
            assert key == f"joint {index} ({name})"
            check_value(shown, value, symbols, key)
    else:
        assert "locked by the scene" not in lists
    check_links(parsed["links"], robot.links, robot.convention, symbols)


# ---------------------------------------------------------------------------------------------
# The bundled robots, scenes and platform robots

@pytest.mark.parametrize("name", ROBOTS)
def test_checked_in_header_lists_every_constant(name):
    """generated/ is the current output (tests/emit/test_cgen.py): its headers, read back."""
    robot = symdyn.load(REPO / "robots" / f"{name}.yaml")
    check_serial_header((GENERATED / f"{name}_dynamics.h").read_text(), robot)


@pytest.mark.parametrize("scene", SCENES)
def test_scene_header_lists_merged_links_and_locked_joints(scene):
    path = REPO / "robots" / "scenes" / scene
    loaded = load_scene(path)
    files = symdyn.generate(path, functions="gravity")
    check_serial_header(files[f"{loaded.robot.name}_dynamics.h"].decode(), loaded.robot, loaded.locked)
    if scene == "puma560_wrist_locked.yaml":  # joints 4-6 locked: their placements in tool.fixed
        assert loaded.locked and loaded.robot.tool_fixed is not None


def test_urdf_header_lists_every_constant():
    path = REPO / "tests" / "data" / "urdf" / "handmade.urdf"
    files = symdyn.generate(path, functions="gravity")
    check_serial_header(files["handmade_dynamics.h"].decode(), symdyn.load(path))


@pytest.mark.parametrize("name", PLATFORMS)
def test_platform_header_lists_every_constant(name):
    robot, _ = load_input(str(REPO / "robots" / "parallel" / f"{name}.yaml"), parallel=True)
    parsed = parse(constant_lines((GENERATED / "parallel" / f"{name}_dynamics.h").read_text()))
    symbols = {s.name: s for s in robot.parameters}
    plat = robot.platform
    check_fields(parsed["top"], {"gravity": robot.gravity, "platform.mass": plat.mass, "platform.com": plat.com,
                                 "platform.inertia": plat.inertia}, symbols, "top")
    assert [m.group(1) for m, _, _ in parsed["legs"]] == [leg.name for leg in robot.legs]
    for (match, fields, links), leg in zip(parsed["legs"], robot.legs):
        assert match.group(2, 3) == (str(leg.actuated + 1), leg.actuated_link.name)
        expected = {**placement_fields("base", leg.chain.base), **placement_fields("platform", leg.attachment)}
        if leg.home is not None:
            expected["home"] = leg.home
        check_fields(fields, expected, symbols, leg.name)
        check_links(links or parsed["links"], leg.chain.links, leg.chain.convention, symbols, f"{leg.name}: ")


# ---------------------------------------------------------------------------------------------
# The check fails on a missing or wrong constant

def test_a_wrong_or_missing_constant_fails():
    header = (GENERATED / "puma560_dynamics.h").read_text()
    robot = symdyn.load(REPO / "robots" / "puma560.yaml")
    check_serial_header(header, robot)
    for broken in (header.replace("mass = 17.4;", "mass = 17.400000000000002;"),  # one ulp off
                   header.replace("alpha = -pi/2 = -1.5707963267948966", "alpha = -1.5707963267948966 = -pi/2"),
                   header.replace("; coulomb = 10.6197775", ""),
                   re.sub(r" \*     inertia = \[0\.13,.*\n", "", header)):
        assert broken != header
        with pytest.raises(AssertionError):
            check_serial_header(broken, robot)


def test_values_are_exact_round_trips():
    """Numbers print as repr of the double (round trip), exact non-decimal values with the
    expression first."""
    from symdyn.emit.emission import constant_text
    assert constant_text(sp.Rational(4318, 10000)) == "0.4318"
    assert constant_text(sp.Integer(0)) == "0.0"
    assert constant_text(sp.pi / 2) == "pi/2 = 1.5707963267948966"
    assert constant_text(sp.Rational(1, 3)) == "1/3 = 0.3333333333333333"
    angle = sp.Rational(6114393763, 18000000000) * sp.pi  # 61.14393763 degrees, read exactly
    assert constant_text(angle) == f"61.14393763*pi/180 = {float(sp.N(angle, 30))!r}"
    m = sp.Symbol("m_p", real=True)
    assert constant_text(m + sp.Rational(1879, 10000)) == "m_p + 0.1879"


# ---------------------------------------------------------------------------------------------
# The rest of the header's firmware notes

def test_header_says_how_to_drop_unused_functions():
    header = (GENERATED / "puma560_dynamics.h").read_text()
    assert "-ffunction-sections -fdata-sections" in header and "-Wl,--gc-sections" in header
    assert "--functions LIST" in header
    platform = (GENERATED / "parallel" / "sru_platform_dynamics.h").read_text()
    assert "-Wl,--gc-sections" in platform


def test_size_report_states_the_exact_flags(monkeypatch):
    """The size report's compile command, as the header states it (a fake measurement: the
    real one is tests/emit/test_firmware.py)."""
    from symdyn.check.firmware import FLAGS, FirmwareReport
    command = " ".join(["arm-none-eabi-gcc", *FLAGS, "-fstack-usage", "-c", "planar2r_dynamics.c"])

    def measure(files, prefix):
        return FirmwareReport({f"{prefix}_gravity": (120, 8)}, (), "arm-none-eabi-gcc (test) 1.0", command)
    files = symdyn.generate(REPO / "robots" / "planar2r.yaml", functions="gravity", size_report=measure)
    header = files["planar2r_dynamics.h"].decode()
    assert f" *   {command}\n" in header and "-std=c99" in header and "arm-none-eabi-gcc (test) 1.0" in header
    assert "Cortex-M4: 120 bytes of code, 8 bytes of stack" in header
