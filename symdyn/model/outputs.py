"""The functions symdyn can produce for a robot: their names, inputs and symbols in the notes."""

from __future__ import annotations

#: every output, in the order generated code and documentation list them
OUTPUTS = ("inverse_dynamics", "mass_matrix", "coriolis", "coriolis_matrix", "gravity",
           "forward_dynamics")

#: the inputs each output depends on, in the order of the generated functions' arguments
OUTPUT_INPUTS = {
    "inverse_dynamics": ("q", "qd", "qdd"),
    "mass_matrix": ("q",),
    "coriolis": ("q", "qd"),
    "coriolis_matrix": ("q", "qd"),
    "gravity": ("q",),
    "forward_dynamics": ("q", "qd", "tau"),
}

#: the symbol of each output in the notes (and the name of its output argument everywhere)
OUTPUT_SYMBOLS = {
    "inverse_dynamics": "tau",
    "mass_matrix": "D",
    "coriolis": "h",
    "coriolis_matrix": "C",
    "gravity": "c",
    "forward_dynamics": "qdd",
}
