"""Shared 3D and spatial (6D) vector algebra of the derivations, symbolic or numeric.

One place for the small operations every recursion uses (Featherstone's notation: a spatial
motion vector is ``[omega; v]``, a force vector ``[n; f]``, angular part first):

- :func:`skew`, :func:`cross`, :func:`cross3`, :func:`dot3`, :func:`cross_nonzero` on 3-vectors
  (SymPy matrices, lists, or anything indexable; the results are written component by component,
  so they work on numbers and expressions alike);
- :func:`cross_motion` (``v x m``), :func:`cross_force` (``v x* f``), :func:`motion_transform`
  and :func:`spatial_inertia` on spatial quantities;
- :func:`skew_numeric`, the numpy form of :func:`skew`.

The independent references in :mod:`symdyn.check` keep their own arithmetic on purpose.
"""

from __future__ import annotations

import numpy as np
import sympy as sp


def skew(v) -> sp.Matrix:
    """``[v x]`` (3 x 3): ``skew(v) * w == v x w``."""
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def skew_numeric(v) -> np.ndarray:
    """``[v x]`` as a numpy array of floats."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def cross3(a, b) -> list:
    """``a x b`` as a list of three components."""
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def cross(a, b) -> sp.Matrix:
    """``a x b`` as a 3 x 1 SymPy matrix."""
    return sp.Matrix(cross3(a, b))


def dot3(a, b):
    """``a . b`` of two 3-vectors."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross_nonzero(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """``a x b`` (SymPy 3 x 1), skipping the products when either is identically zero."""
    if a.is_zero_matrix or b.is_zero_matrix:
        return sp.zeros(3, 1)
    return a.cross(b)


def cross_motion(v: sp.Matrix, m: sp.Matrix) -> sp.Matrix:
    """``v x m`` of spatial motion vectors (6 x 1): ``[w x m_w; w x m_v + u x m_w]``."""
    w, u = v[:3, 0], v[3:, 0]
    return sp.Matrix.vstack(w.cross(m[:3, 0]), w.cross(m[3:, 0]) + u.cross(m[:3, 0]))


def cross_force(v: sp.Matrix, f: sp.Matrix) -> sp.Matrix:
    """``v x* f`` of a motion vector and a force vector (6 x 1): ``[w x n + u x f; w x f]``."""
    w, u = v[:3, 0], v[3:, 0]
    return sp.Matrix.vstack(w.cross(f[:3, 0]) + u.cross(f[3:, 0]), w.cross(f[3:, 0]))


def motion_transform(pose: sp.Matrix) -> sp.Matrix:
    """``X`` (6 x 6) mapping motion vectors of frame A to frame B, ``pose`` = B in A (4 x 4)."""
    R, p = pose[:3, :3], pose[:3, 3]
    X = sp.zeros(6, 6)
    X[:3, :3] = R.T
    X[3:, 3:] = R.T
    X[3:, :3] = -R.T * skew(p)
    return X


def spatial_inertia(mass, com: sp.Matrix, inertia_com: sp.Matrix) -> sp.Matrix:
    """The 6 x 6 spatial inertia about a frame's origin of a body of ``mass`` (kg) with centre of
    mass ``com`` (m) and inertia ``inertia_com`` (kg m^2, 3 x 3) about it, both in that frame."""
    cx = skew(com)
    I = sp.zeros(6, 6)
    I[:3, :3] = inertia_com - mass * cx * cx
    I[:3, 3:] = mass * cx
    I[3:, :3] = -mass * cx
    I[3:, 3:] = mass * sp.eye(3)
    return I
