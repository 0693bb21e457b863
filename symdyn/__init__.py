"""symdyn: symbolic equations of motion for serial robot arms.

Public API::

    robot = symdyn.load("robots/puma560.yaml")       # immutable Robot
    eqs = symdyn.derive(robot, method="newton-euler")  # immutable Equations
    eqs.mass_matrix, eqs.coriolis, eqs.coriolis_matrix, eqs.gravity,
    eqs.inverse_dynamics, eqs.forward_dynamics          # SymPy matrices
    eqs.numeric.inverse_dynamics(q, qd, qdd)            # numpy evaluation
    fns = symdyn.to_casadi(robot)                       # {name: casadi.Function}
    files = symdyn.generate("robots/puma560.yaml", precision="float")  # {file name: bytes}, as the CLI writes
"""

from ._version import __version__
from . import derive  # the derivation package, callable: symdyn.derive(robot, method, outputs)
from .derive.equations import ALL_OUTPUTS, METHODS, OUTPUTS, Equations
from .model.errors import RobotFileError, SymdynError, SymdynWarning
from .model.robot import Link, Robot, loads
from .model.scene import load  # a robot file or a scene


def to_casadi(source, functions=None, method="newton-euler", prefix="", use_cache=True):
    """The equations of motion as named ``casadi.Function``s; see
    :func:`symdyn.emit.casadi_backend.to_casadi` (CasADi is imported on first use)."""
    from .emit.casadi_backend import to_casadi as build
    return build(source, functions, method, prefix, use_cache)


def generate(path, **options) -> dict:
    """The files ``symdyn generate`` writes for one input (robot file, URDF, scene or platform
    robot), ``{file name: bytes}``, written nowhere; ``options`` are the fields of
    :class:`symdyn.emit.pipeline.GenerateOptions` (functions, precision, target, method,
    fd_method, parameters, header_only, batch, size_report, use_cache, and ``name``: the C
    prefix and file names instead of the robot's name)."""
    from .emit.pipeline import GenerateOptions, configure
    from .emit.pipeline import generate as emit
    return emit(configure(path, GenerateOptions(**options)))


__all__ = ["__version__", "load", "loads", "derive", "Robot", "Link", "Equations", "OUTPUTS", "ALL_OUTPUTS",
           "METHODS", "RobotFileError", "SymdynError", "SymdynWarning", "to_casadi", "generate"]
