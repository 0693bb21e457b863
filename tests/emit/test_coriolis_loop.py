"""The Coriolis matrix written as a loop over its factor arrays (chains of 8 joints or more,
:data:`symdyn.emit.cplan.LOOPED_CORIOLIS_FROM_DOF`): the vector-type form and the plain loop give
the same bits, and both agree with Pinocchio."""

from __future__ import annotations

import numpy as np

from symdyn.model.outputs import Dimensions
import symdyn
from symdyn.check.cbuild import CompiledDynamics, compile_shared
from symdyn.emit.cgen import generate_c
from symdyn.emit.cplan import LOOPED_CORIOLIS_FROM_DOF

from helpers import TOL, PinocchioReference, normalized_error, random_states, robot_path


def test_vector_and_plain_loops_agree_bit_for_bit_and_with_pinocchio(tmp_path):
    robot = symdyn.load(robot_path("chain12"))
    assert robot.dof >= LOOPED_CORIOLIS_FROM_DOF
    eqs = symdyn.derive(robot, outputs=["coriolis_matrix"])
    assert eqs.coriolis_factors  # the recursion, whose C is the loop
    files = generate_c(eqs, ["coriolis_matrix"])
    assert "cor_f[" in files["chain12_dynamics.c"] and "_GRAM_BYTES" in files["chain12_dynamics.c"]
    results = {}
    states = random_states(robot.dof, 20, seed=4)
    for label, flags in (("vector", ()), ("plain", ("-DSYMDYN_NO_VECTOR",))):
        folder = tmp_path / label
        folder.mkdir()
        for name, text in files.items():
            (folder / name).write_text(text)
        library = compile_shared(str(folder / "chain12_dynamics.c"), str(folder), flags)
        lib = CompiledDynamics(library, "chain12", Dimensions.of(robot), len(robot.parameters))
        results[label] = np.array([lib.coriolis_matrix(q, qd) for q, qd, _, _ in states])
    assert results["vector"].tobytes() == results["plain"].tobytes()
    ref = PinocchioReference(robot)
    assert normalized_error(results["vector"], [ref.coriolis_matrix(q, qd) for q, qd, _, _ in states]) < TOL
