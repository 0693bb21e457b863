"""The functions symdyn can produce for a robot: their names, inputs and symbols in the notes."""

from __future__ import annotations

#: the standard outputs, in the order generated code and documentation list them
OUTPUTS = ("inverse_dynamics", "mass_matrix", "coriolis", "coriolis_matrix", "gravity",
           "forward_dynamics", "forward_kinematics", "jacobian", "jacobian_dot_qd")

#: outputs derived and generated only when asked for (``--functions``): the base reaction wrench
#: as an affine map of the actuated torques (seed 004; by default for a robot with passive joints,
#: ``actuated: false``), and the identification regressors (tau = Y pi, tau = Y_b beta)
EXTRA_OUTPUTS = ("reaction_map", "regressor", "base_regressor")

#: every output symdyn can produce
ALL_OUTPUTS = OUTPUTS + EXTRA_OUTPUTS


def default_outputs(robot) -> tuple[str, ...]:
    """What is derived and generated when nothing is asked for: :data:`OUTPUTS`, and the
    reaction map when the robot has passive joints."""
    return OUTPUTS + (("reaction_map",) if robot.passive_joints else ())


#: the outputs about the tool frame (the others are joint-space dynamics)
KINEMATIC_OUTPUTS = ("forward_kinematics", "jacobian", "jacobian_dot_qd")

#: the inputs each output depends on, in the order of the generated functions' arguments
OUTPUT_INPUTS = {
    "inverse_dynamics": ("q", "qd", "qdd"),
    "mass_matrix": ("q",),
    "coriolis": ("q", "qd"),
    "coriolis_matrix": ("q", "qd"),
    "gravity": ("q",),
    "forward_dynamics": ("q", "qd", "tau"),
    "forward_kinematics": ("q",),
    "jacobian": ("q",),
    "jacobian_dot_qd": ("q", "qd"),
    "reaction_map": ("q", "qd"),
    "regressor": ("q", "qd", "qdd"),
    "base_regressor": ("q", "qd", "qdd"),
}

#: the symbol of each output in the notes (and the name of its output argument everywhere)
OUTPUT_SYMBOLS = {
    "inverse_dynamics": "tau",
    "mass_matrix": "D",
    "coriolis": "h",
    "coriolis_matrix": "C",
    "gravity": "c",
    "forward_dynamics": "qdd",
    "forward_kinematics": "T",
    "jacobian": "J",
    "jacobian_dot_qd": "a",
    "reaction_map": "k0_D",
    "regressor": "Y",
    "base_regressor": "Yb",
}


def output_shape(name: str, n: int, actuated: int | None = None) -> tuple[int, int]:
    """Rows and columns of an output for a robot of ``n`` joints (``actuated`` of them actuated,
    default all): the reaction map is ``[k0 | D]``, 6 x (1 + actuated)."""
    return {"forward_kinematics": (4, 4), "jacobian": (6, n), "jacobian_dot_qd": (6, 1),
            "mass_matrix": (n, n), "coriolis_matrix": (n, n),
            "reaction_map": (6, 1 + (n if actuated is None else actuated)),
            "regressor": (n, 13 * n)}.get(name, (n, 1))
