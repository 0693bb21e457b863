"""The README runs as written: its Python blocks execute, and its first command line (install,
generate, verify) passes in a fresh virtual environment.  (The second line, the test command,
is what CI runs in a fresh venv: .ci/run.)"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import venv

import pytest

from helpers import REPO

README = (REPO / "README.md").read_text()


def blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", README, flags=re.S)


def test_python_blocks_run_as_written(tmp_path):
    """All Python blocks, in order, as one script (later blocks use the names earlier ones define)."""
    code = "\n".join(blocks("python"))
    assert "symdyn.load" in code and "to_casadi" in code
    script = tmp_path / "readme.py"
    script.write_text(code)
    env = dict(os.environ, SYMDYN_CACHE_DIR=str(tmp_path / "cache"))
    result = subprocess.run([sys.executable, str(script)], cwd=REPO, capture_output=True, text=True,
                            timeout=600, env=env)
    assert result.returncode == 0, result.stderr[-3000:]


@pytest.mark.slow  # 30 s of pip install (CI installs the project in a fresh venv for the second line itself)
def test_first_command_line_in_a_fresh_venv(tmp_path):
    """README line 1, verbatim, in a new venv and a copy of the project (nothing in the checkout
    changes).  Packages come from pip's cache or the registry, as for a user."""
    line = blocks("bash")[0].strip().splitlines()[0]
    assert "pip install" in line and "symdyn verify" in line
    if shutil.which("cc") is None and shutil.which("gcc") is None:
        pytest.skip("no C compiler")
    project = tmp_path / "project"
    listed = subprocess.run(["git", "ls-files", "-z"], cwd=REPO, capture_output=True, check=True).stdout
    for name in filter(None, listed.decode().split("\0")):
        target = project / name
        target.parent.mkdir(parents=True, exist_ok=True)
        if (REPO / name).is_file():
            shutil.copy2(REPO / name, target)
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONPATH", "PYTHONHOME")}
    env["PATH"] = f"{env_dir / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    env["VIRTUAL_ENV"] = str(env_dir)
    env["SYMDYN_CACHE_DIR"] = str(tmp_path / "cache")
    result = subprocess.run(["bash", "-c", line], cwd=project, capture_output=True, text=True,
                            timeout=1500, env=env)
    assert result.returncode == 0, (result.stdout[-2000:], result.stderr[-3000:])
    assert (project / "out" / "puma560" / "puma560_dynamics.c").is_file()
    assert "FAIL" not in result.stdout and result.stdout.count(" ok") >= 6
