"""Deriving the equations of motion from a robot description, symbolically (SymPy).

Kinematics, the Newton-Euler and Lagrange-Euler derivations, the composite-rigid-body mass
matrix, the straight-line program they build with intermediate symbols, the immutable
:class:`~symdyn.derive.equations.Equations`, their numpy evaluation, the textbook steps for
printouts and the on-disk derivation cache.  Imports only :mod:`symdyn.model`: no printer, no
template, no check.
"""

import sys as _sys
import types as _types


class _CallablePackage(_types.ModuleType):
    """``symdyn.derive`` is this package and, called, the public derivation entry point, so that
    both ``symdyn.derive(robot)`` and ``import symdyn.derive.cache`` work."""

    def __call__(self, robot, method: str = "newton-euler", outputs=None, progress=None, fd_method: str = "ldlt",
                 parameters: str = "standard"):
        """Derive the equations of motion of ``robot``: see :func:`symdyn.derive.equations.derive`
        (``method``: ``'newton-euler'``, ``'lagrange-euler'`` or ``'jacobian-newton-euler'``;
        ``outputs``: names from ``symdyn.OUTPUTS``, default all; ``progress``: called with a
        text per part; ``fd_method``: ``'ldlt'`` or ``'aba'`` for forward dynamics;
        ``parameters``: ``'standard'`` or ``'base'`` for inverse dynamics).  Returns an immutable
        ``Equations``."""
        from .equations import derive
        return derive(robot, method, outputs, progress, fd_method, parameters)


_sys.modules[__name__].__class__ = _CallablePackage
