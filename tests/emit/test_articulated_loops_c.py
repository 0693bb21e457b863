"""Forward dynamics emitted as the articulated-body algorithm's loops over a table of the joints
(long fixed-base revolute chains, :data:`symdyn.derive.articulated_loops.LOOPED_ABA_FROM_DOF`):
the compiled C agrees with Pinocchio in double, float and mixed precision, returns the status of
the contract, runs sanitizer-clean, and its code does not grow with the joints."""

from __future__ import annotations

import re
import sys

import numpy as np
import pytest

from symdyn.model.outputs import Dimensions
import symdyn
from symdyn.check.pinocchio_model import compare
from symdyn.check.cbuild import build_and_load
from symdyn.emit.cgen import generate_c
from symdyn.emit.cplan import collect_targets

from helpers import REPO, PinocchioReference, random_states, run_sanitized

sys.path.insert(0, str(REPO / "benchmarks"))
sys.path.insert(0, str(REPO / "tests" / "derive"))
from long_chains import generic_chain  # noqa: E402
from test_articulated_loops import with_friction  # noqa: E402


@pytest.fixture(scope="module")
def frictional(tmp_path_factory):
    """A 13-joint generic chain with armature, friction and angle offsets, derived once."""
    path = tmp_path_factory.mktemp("loops_c") / "frictional13.yaml"
    path.write_text(with_friction(generic_chain(13)).replace("name: generic13", "name: frictional13"))
    robot = symdyn.load(str(path))
    return robot, symdyn.derive(robot, outputs=["forward_dynamics"], fd_method="aba")


@pytest.mark.parametrize("precision, tolerance", [("double", 1e-10), ("float", 2e-3), ("mixed", 1e-4)])
def test_loops_agree_with_pinocchio_and_keep_the_status_contract(precision, tolerance, frictional, tmp_path):
    robot, eqs = frictional
    assert collect_targets(eqs, "forward_dynamics").sweeps is not None
    files = generate_c(eqs, ["forward_dynamics"], precision)
    assert "fd_table[13][" in files["frictional13_dynamics.c"]
    lib = build_and_load(files, robot.name, Dimensions.of(robot), 0, precision, str(tmp_path))
    states = []
    for state in random_states(robot.dof, 12, seed=3):
        if precision != "double":
            state = [x.astype(np.float32).astype(float) for x in state]
        states.append(state)
    errors = compare(lib, PinocchioReference(robot), states, ("forward_dynamics",), np.zeros(0))
    assert errors["forward_dynamics"] <= tolerance, errors
    q, qd, _, tau = states[0]
    for k, bad in enumerate((np.inf, -np.inf, np.nan)):  # an input not finite: 2, qdd untouched
        args = [q.copy(), qd.copy(), tau.copy()]
        args[k][robot.dof - 1] = bad
        status, qdd = lib.forward_dynamics_checked(*args, qdd=np.full(robot.dof, 7.0))
        assert status == 2 and np.all(qdd == 7.0)
    huge = 1e200 if precision == "double" else 1e30  # finite inputs, results out of range: 2
    status, qdd = lib.forward_dynamics_checked(q, np.full(robot.dof, huge), tau, qdd=np.full(robot.dof, 7.0))
    assert status == 2 and np.all(qdd == 7.0)


def test_code_does_not_grow_with_the_joints(tmp_path_factory):
    """The loops are the same lines at 8 and 11 joints; only the table (a row a joint) and the
    straight-line part before it (each joint's cos, sin and force: a few lines a joint) grow."""
    loops, before = {}, {}
    for n in (8, 11):
        path = tmp_path_factory.mktemp(f"g{n}") / f"generic{n}.yaml"
        path.write_text(generic_chain(n))
        eqs = symdyn.derive(symdyn.load(str(path)), outputs=["forward_dynamics"], fd_method="aba")
        source = generate_c(eqs, ["forward_dynamics"])[f"generic{n}_dynamics.c"]
        body = source[source.index(f"generic{n}_forward_dynamics_checked("):]
        body = body[:body.index("\n}\n")]
        table = re.search(r"fd_table\[\d+\]\[\d+\] = \{\n(.*?)\n\s*\};\n", body, re.S)
        assert table is not None and len(table.group(1).splitlines()) == n
        loops[n] = (body[table.end():].replace(f"generic{n}_", "NAME_").replace(f"GENERIC{n}_", "NAME_").replace(f"< {n};", "< N;")
                    .replace(f"= {n - 1};", "= N - 1;"))
        before[n] = len(body[:table.start()].splitlines())
    assert loops[11] == loops[8] and len(loops[8].splitlines()) < 800
    assert before[11] - before[8] <= 6 * 3


HARNESS = r"""
#include <stdio.h>
#include "frictional13_dynamics.h"
int main(void) {
    frictional13_real q[13], qd[13], tau[13], qdd[13];
    double sum = 0;
    int i, status;
    for (i = 0; i < 13; ++i) { q[i] = 0.3 * i - 1.7; qd[i] = 0.1 * i - 0.5; tau[i] = 2.0 - 0.4 * i; }
    status = frictional13_forward_dynamics_checked(q, qd, tau, qdd);
    for (i = 0; i < 13; ++i) sum += qdd[i];
    printf("%d %.17g\n", status, sum);
    return status;
}
"""


def test_loops_run_sanitizer_clean(frictional, tmp_path):
    _, eqs = frictional
    files = generate_c(eqs, ["forward_dynamics"])
    status, total = run_sanitized(tmp_path, HARNESS, files).split()
    assert status == "0" and np.isfinite(float(total))


def test_batch_form_loops_over_the_scalar_function(frictional, tmp_path):
    """The batch form of the loops (no lane-wise form: the batch function calls the scalar one per
    state) equals the scalar calls byte for byte, vectorized sin/cos block or not."""
    import subprocess
    sys.path.insert(0, str(REPO / "tests" / "emit"))
    from test_batch import GCC, harness
    from symdyn.check.cbuild import WARNING_FLAGS
    if GCC is None:
        pytest.skip("no C compiler")
    robot, eqs = frictional
    for name, text in generate_c(eqs, ["forward_dynamics"], batch=True).items():
        (tmp_path / name).write_text(text)
    (tmp_path / "check.c").write_text(harness(robot.name, robot, eqs, ["forward_dynamics"], 0))
    for flags in (["-O2"], ["-O2", "-DSYMDYN_NO_VECTOR"]):
        exe = tmp_path / f"check{len(flags)}"
        subprocess.run([GCC, *WARNING_FLAGS, *flags, str(tmp_path / "check.c"),
                        str(tmp_path / f"{robot.name}_dynamics.c"), "-o", str(exe), "-lm"], check=True)
        run = subprocess.run([str(exe)], capture_output=True, text=True)
        assert run.returncode == 0, (flags, run.stdout)
