"""The package layout follows the data: model -> derive -> emit -> check -> cli.

A folder imports only from itself and the folders before it (function-level imports included),
no two modules import each other (directly or through others), and the derivation folders load
no template engine and no code-generation target.
"""

import ast
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parent.parent
PACKAGE = REPO / "symdyn"
ORDER = ("model", "derive", "emit", "check", "cli")
FORBIDDEN_THIRD_PARTY = {"model": ("jinja2", "casadi", "pinocchio"),
                         "derive": ("jinja2", "casadi", "pinocchio"),
                         "emit": ("pinocchio",)}


def _module_name(path: pathlib.Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: pathlib.Path):
    """(imported symdyn module, line) for every import in the file, resolved to a module name;
    third-party top-level names as ``('<ext>', name, line)``."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "symdyn":
                out.append(("<ext>", target.split(".")[0], node.lineno))
                continue
            for alias in node.names:  # "from . import bench" imports the submodule bench
                sub = f"{target}.{alias.name}"
                out.append((sub if (PACKAGE.parent / (sub.replace(".", "/") + ".py")).exists()
                            or (PACKAGE.parent / sub.replace(".", "/")).is_dir() else target, node.lineno))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "symdyn":
                    out.append((alias.name, node.lineno))
                else:
                    out.append(("<ext>", alias.name.split(".")[0], node.lineno))
    return out


def _folder(module: str):
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in ORDER else None


MODULES = sorted(PACKAGE.rglob("*.py"))


def test_every_module_lives_in_a_folder():
    loose = [p.name for p in PACKAGE.glob("*.py") if p.name not in ("__init__.py", "__main__.py", "_version.py")]
    assert not loose, f"modules outside model/derive/emit/check/cli: {loose}"
    for folder in ORDER:
        init = PACKAGE / folder / "__init__.py"
        assert init.exists() and ast.get_docstring(ast.parse(init.read_text())), f"{folder}/__init__.py says what the folder is for"


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_follow_the_data(path):
    source = _folder(_module_name(path))
    if source is None:
        return  # symdyn/__init__.py (the public API) and _version.py
    rank = ORDER.index(source)
    for item in _imports(path):
        if item[0] == "<ext>":
            assert item[1] not in FORBIDDEN_THIRD_PARTY.get(source, ()), \
                f"{path.relative_to(PACKAGE)}:{item[2]} imports {item[1]}, which {source}/ must not use"
            continue
        target, line = item
        folder = _folder(target)
        if folder is not None:
            assert ORDER.index(folder) <= rank, \
                f"{path.relative_to(PACKAGE)}:{line} imports {target}: {source}/ must not import {folder}/"


def test_module_docstrings():
    for path in MODULES:
        if path.name == "__init__.py" and path.parent == PACKAGE / "templates":
            continue
        tree = ast.parse(path.read_text())
        if path.name != "_version.py":
            assert ast.get_docstring(tree), f"{path.relative_to(PACKAGE)} says in its docstring what it holds"


def test_no_import_cycles():
    graph = {}
    for path in MODULES:
        graph[_module_name(path)] = {t for t, *_ in _imports(path) if t != "<ext>" and t != _module_name(path)}
    # the package __init__ files re-export; a cycle through them is Python's normal package import
    graph = {m: {t for t in ts if not t.endswith(("symdyn", ".cli")) or t == m} for m, ts in graph.items()}
    state = {}

    def visit(node, stack):
        state[node] = "open"
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                cycle = stack[stack.index(nxt):] + [nxt] if nxt in stack else [node, nxt]
                raise AssertionError("import cycle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = "done"

    for module in sorted(graph):
        if module not in state:
            visit(module, [module])


def _package_import_problems(source: str, module: str, is_package: bool, label: str) -> list[str]:
    """Imports of another module's private name (``_x``) or of the package itself (``import
    symdyn``, ``from symdyn import ...``, ``from .. import ...`` at the top) in ``source``, the
    text of ``module``."""
    package = module if is_package else module.rsplit(".", 1)[0]
    problems = []
    for node in ast.walk(ast.parse(source, label)):
        where = f"{label}:{getattr(node, 'lineno', '?')}"
        if isinstance(node, ast.Import):
            if any(a.name == "symdyn" for a in node.names):
                problems.append(f"{where} imports the whole package")
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                target = ".".join(base[:len(base) - (node.level - 1)] + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "symdyn":
                continue
            if target == "symdyn" and not all(a.name == "_version" for a in node.names):
                problems.append(f"{where} imports from the whole package ({', '.join(a.name for a in node.names)})")
            private = [a.name for a in node.names if a.name.startswith("_") and a.name != "__version__"
                       and not (PACKAGE.parent / (f"{target}.{a.name}".replace(".", "/") + ".py")).exists()]
            if private:
                problems.append(f"{where} imports private names of {target}: {private}")
    return problems


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_private_names_or_whole_package_imports(path):
    """Inside the folders, no module imports another's private name, and none imports the
    package itself, which would load every folder, later ones included, past the layering."""
    if _folder(_module_name(path)) is None:
        return
    problems = _package_import_problems(path.read_text(), _module_name(path), path.name == "__init__.py",
                                        str(path.relative_to(PACKAGE)))
    assert not problems, problems


def test_layering_check_sees_whole_package_imports():
    """The check above is not vacuous: it finds each kind of import in a module's text."""
    probe = "symdyn.derive.probe"
    assert "imports the whole package" in _package_import_problems("import symdyn\n", probe, False, "p")[0]
    assert "whole package" in _package_import_problems("from .. import derive\n", probe, False, "p")[0]
    assert "private names" in _package_import_problems("from .equations import _Derivation\n", probe, False, "p")[0]
    assert not _package_import_problems("from .equations import derive\nfrom .._version import __version__\n",
                                        probe, False, "p")


def test_users_read_no_seeds():
    """What users read cites its sources by what they are (the ECE 470 dynamics lecture, the
    force-to-torque articulated-body note, ...), never as 'seeds' or 'design notes' they do not
    have: README, docs, generated files, templates, the package's docstrings and messages, the
    robot files, examples and benchmark scripts, and every command's --help."""
    import io
    import re
    from contextlib import redirect_stdout
    from symdyn.cli import SUBCOMMANDS, main
    word = re.compile(r"\bseeds?\b(?! *[=:),<]| \d)|seed's|design notes?|\bseed 0\d", re.IGNORECASE)
    allowed = re.compile(r"random seed|--seed|args\.seed|seed=|\[\"seed\"\]|rng", re.IGNORECASE)
    texts = {}
    for pattern in ("README.md", "docs/**/*.md", "generated/**/*.[ch]", "templates/*", "symdyn/**/*.py",
                    "robots/**/*.yaml", "examples/**/*.*", "benchmarks/*.py"):
        for path in REPO.glob(pattern):
            if path.is_file():
                texts[str(path.relative_to(REPO))] = path.read_text(errors="replace")
    for name in [None, *SUBCOMMANDS]:
        buffer = io.StringIO()
        with redirect_stdout(buffer):
            main([name, "--help"] if name else ["--help"])
        texts[f"symdyn {name or ''} --help"] = buffer.getvalue()
    found = []
    for where, text in texts.items():
        for number, line in enumerate(text.splitlines(), 1):
            if word.search(line) and not allowed.search(line):
                found.append(f"{where}:{number}: {line.strip()[:120]}")
    assert not found, "\n".join(found)


#: the longest a function in symdyn/ may be (lines, docstring included): a longer one is split
#: into functions that each say what they do
MAX_FUNCTION_LINES = 100


def test_no_function_over_a_hundred_lines():
    import ast
    long = []
    for path in sorted((REPO / "symdyn").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                lines = node.end_lineno - node.lineno + 1
                if lines > MAX_FUNCTION_LINES:
                    long.append(f"{path.relative_to(REPO)}:{node.lineno} {node.name}: {lines} lines")
    assert not long, "\n".join(long)


#: where the kind of a robot (a serial robot or a platform) may be tested: its description, and
#: the pipeline that resolves it (symdyn.emit.pipeline.kind_of); every command dispatches on
#: the kind through its own BY_KIND table
KIND_TESTS_ALLOWED = ("model/", "emit/pipeline.py")
ROBOT_TYPES = {"Robot", "ParallelRobot"}
KINDS = {"SERIAL", "PLATFORM"}


def kind_tests(source: str) -> list[int]:
    """The lines of ``source`` that test a robot's kind: ``isinstance(x, Robot or ParallelRobot)``
    (alone or in a tuple) and comparisons with a kind object (``is SERIAL``, ``== PLATFORM``)."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "isinstance" and len(node.args) == 2:
            kinds = node.args[1].elts if isinstance(node.args[1], ast.Tuple) else [node.args[1]]
            if any(getattr(k, "id", getattr(k, "attr", None)) in ROBOT_TYPES for k in kinds):
                lines.append(node.lineno)
        elif isinstance(node, ast.Compare):
            names = [node.left, *node.comparators]
            if any(getattr(n, "id", getattr(n, "attr", None)) in KINDS for n in names):
                lines.append(node.lineno)
    return lines


def test_no_command_branches_on_the_robot_kind():
    """Outside the model and the pipeline, nothing tests whether a robot is serial or a platform:
    the commands look their kind's function up in their BY_KIND table."""
    found = [f"{path.relative_to(PACKAGE)}:{line}" for path in MODULES
             if not str(path.relative_to(PACKAGE)).startswith(KIND_TESTS_ALLOWED)
             for line in kind_tests(path.read_text(encoding="utf-8"))]
    assert not found, "kind tests outside the model and the pipeline: " + ", ".join(found)


def test_kind_check_sees_kind_tests():
    assert kind_tests("isinstance(robot, ParallelRobot)\nisinstance(r, (int, model.Robot))\n"
                      "x = kind is PLATFORM\ny = SERIAL == k\nz = isinstance(r, dict)") == [1, 2, 3, 4]


def test_every_command_handles_every_kind():
    """Each command's BY_KIND table has an entry for every kind of robot the pipeline knows."""
    from symdyn.cli import bench, derive, verify
    from symdyn.emit.pipeline import KINDS
    for command in (bench, derive, verify):
        assert set(command.BY_KIND) == {kind.name for kind in KINDS}, command.__name__
