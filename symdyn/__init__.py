"""symdyn: symbolic equations of motion for serial robot arms.

Public API::

    robot = symdyn.load("robots/puma560.yaml")       # immutable Robot
    eqs = symdyn.derive(robot, method="newton-euler")  # immutable Equations
    eqs.mass_matrix, eqs.coriolis, eqs.coriolis_matrix, eqs.gravity,
    eqs.inverse_dynamics, eqs.forward_dynamics          # SymPy matrices
    eqs.numeric.inverse_dynamics(q, qd, qdd)            # numpy evaluation
"""

from ._version import __version__
from .equations import METHODS, OUTPUTS, Equations, derive
from .errors import RobotFileError, SymdynError
from .robot import Link, Robot, load, loads

__all__ = ["__version__", "load", "loads", "derive", "Robot", "Link", "Equations", "OUTPUTS",
           "METHODS", "RobotFileError", "SymdynError"]
