"""Tolerances and condition limits, in one place, keyed by precision where they depend on it.

Generated code in ``double`` checks each pivot it divides by (an LDL^T pivot against its
diagonal entry, a 6x6 LU pivot against its matrix's largest entry, a determinant or denominator
against its scale) at a relative tolerance of 1e-12: a solution past it would carry a relative
error of about 1e-16 / 1e-12 = 1e-4 or more.  In ``float`` the same check is made at 1e-6
(single precision rounds at 6e-8, so a smaller pivot is rounding noise and the solution would
carry an error of several percent or more): serial chains and platforms alike.  The ``mixed``
precision computes forward dynamics in double inside, and checks as double does.  The
articulated-body algorithm checks that each articulated inertia it divides by is positive.
"""

from __future__ import annotations

import sympy as sp

#: relative pivot tolerance of the generated factorizations and singularity checks, per precision
#: of the arithmetic they run in
PIVOT_RTOL = {"double": 1e-12, "float": 1e-6}

#: the tolerance as a symbol, in derivations that leave its value to the emitter (the platform
#: functions' ``NAME_PIVOT_RTOL`` macro)
PIVOT_RTOL_SYMBOL = sp.Symbol("pivot_rtol", positive=True)

#: a matrix whose condition number is this or more is treated as singular where symdyn evaluates
#: it numerically (derivation printouts of platforms); the reciprocal of the double tolerance
SINGULAR_CONDITION = 1 / PIVOT_RTOL["double"]

#: a stacked identification regressor above this condition number does not determine every base
#: parameter
IDENTIFICATION_MAX_CONDITION = 1e12

#: the normalized error ``symdyn verify`` accepts by default, per precision of the generated code
VERIFY_TOLERANCE = {"double": 1e-10, "float": 1e-4, "mixed": 1e-4}

#: unit roundoff of the arithmetic the functions that solve with M = D + diag(armature) run in,
#: per precision of the generated code (mixed: double inside)
SOLVE_ROUNDOFF = {"double": 2.0 ** -53, "mixed": 2.0 ** -53, "float": 2.0 ** -24}


def solve_tolerance(tolerance: float, conditioning: float, precision: str, n: int) -> float:
    """The normalized error allowed to a function that solves with M (forward dynamics, M^-1,
    the forward-dynamics derivatives): ``tolerance``, or ``n cond(M) u`` where that is larger (the
    forward error bound of a backward-stable solve of n equations: two correct solutions of an
    ill-conditioned system differ by about that; in float a condition of 1400 alone is 8e-5)."""
    return max(tolerance, n * conditioning * SOLVE_ROUNDOFF[precision])


#: ``symdyn verify`` measures an output in torques (or torques per unit rate) against at least
#: this much of the robot's own torques at the states (the RMS of its inverse dynamics there,
#: divided by the RMS rate for the latter): an output that is zero but for rounding (the
#: Coriolis forces of coaxial links of 1e9 and 0.01 kg m^2) or made of subnormal numbers (a DH
#: a of 4e-320 m) is not judged against its own rounding noise
VERIFY_FLOOR = 1e-5

#: each joint's row of an output is measured against at least this fraction of the whole output's
#: RMS (:func:`symdyn.check.pinocchio_model.normalized_error`), per precision of the generated code:
#: the arithmetic rounds the output's large entries, and that rounding reaches its small ones.  A
#: tool 1.3 mm from a joint's axis has that joint's Jacobian column of 1e-3 m/rad, formed in float
#: from world positions of 0.3 m rounded at 6e-8 relative: 3e-7 absolute, 3e-4 of the column's own
#: size, 5e-7 of the Jacobian's.  3e-2 in float (its tolerance of 1e-4 then allows 3e-6 of the
#: whole output, about 50 roundings) and in mixed (which computes all but forward dynamics in
#: float); 1e-5 in double (10 roundings of the whole at verify's 1e-10)
ROW_FLOOR = {"double": 1e-5, "mixed": 3e-2, "float": 3e-2}

#: the closed-loop reference of platform robots (symdyn.check.closed_loop) solves each leg's loop
#: closure to this (m per m of leg, and rad); a closure it cannot bring below
#: ``CLOSED_LOOP_UNREACHABLE`` is out of reach.  It treats a matrix as singular where the
#: reciprocal of its condition number is below the generated code's pivot tolerance (PIVOT_RTOL)
CLOSED_LOOP_CLOSURE = 1e-13
CLOSED_LOOP_UNREACHABLE = 1e-8


def pivot_rtol(arithmetic: str) -> float:
    """The relative pivot tolerance of code computing in ``arithmetic`` (``double`` or ``float``)."""
    try:
        return PIVOT_RTOL[arithmetic]
    except KeyError:
        raise ValueError(f"no pivot tolerance for {arithmetic!r} arithmetic (double or float)") from None
