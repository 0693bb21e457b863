"""Shared 3D and spatial (6D) vector algebra of the derivations, symbolic or numeric.

One place for the small operations every recursion uses (Featherstone's notation: a spatial
motion vector is ``[omega; v]``, a force vector ``[n; f]``, angular part first):

- :func:`skew`, :func:`cross`, :func:`cross3`, :func:`dot3`, :func:`cross_nonzero` on 3-vectors
  (SymPy matrices, lists, or anything indexable; the results are written component by component,
  so they work on numbers and expressions alike);
- :func:`cross_motion` (``v x m``), :func:`cross_force` (``v x* f``), :func:`motion_transform`
  and :func:`spatial_inertia` on spatial quantities; :func:`quaternion_rotation`; :func:`named_symmetric` and
  :func:`named_pose` name a symmetric matrix's upper triangle, a pose's entries, in a program;
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


def quaternion_rotation(builder, x, y, z, w, hint: str = "qn_k") -> sp.Matrix:
    """The rotation of the quaternion (x, y, z, w) divided by its norm (any nonzero quaternion;
    q and -q give the same): ``I + 2 k [...]`` with ``k = 1 / (x^2 + y^2 + z^2 + w^2)`` named
    ``hint`` in the program ``builder``, 3x3."""
    k = builder.define(hint, 2 / (x * x + y * y + z * z + w * w), force=True)
    return sp.Matrix([[1 - k * (y * y + z * z), k * (x * y - z * w), k * (x * z + y * w)],
                      [k * (x * y + z * w), 1 - k * (x * x + z * z), k * (y * z - x * w)],
                      [k * (x * z - y * w), k * (y * z + x * w), 1 - k * (x * x + y * y)]])


def cross_motion(v: sp.Matrix, m: sp.Matrix) -> sp.Matrix:
    """``v x m`` of spatial motion vectors (6 x 1): ``[w x m_w; w x m_v + u x m_w]``."""
    w, u = v[:3, 0], v[3:, 0]
    return sp.Matrix.vstack(w.cross(m[:3, 0]), w.cross(m[3:, 0]) + u.cross(m[:3, 0]))


def cross_force(v: sp.Matrix, f: sp.Matrix) -> sp.Matrix:
    """``v x* f`` of a motion vector and a force vector (6 x 1): ``[w x n + u x f; w x f]``."""
    w, u = v[:3, 0], v[3:, 0]
    return sp.Matrix.vstack(w.cross(f[:3, 0]) + u.cross(f[3:, 0]), w.cross(f[3:, 0]))


def named_symmetric(builder, hint: str, M: sp.Matrix) -> sp.Matrix:
    """The symmetric square ``M`` (3 x 3 or 6 x 6) with its upper triangle named in
    ``builder`` (a :class:`~symdyn.derive.program.ProgramBuilder`) as ``{hint}_{r}{c}``, each
    entry expanded, the lower triangle mirrored."""
    size = M.rows
    out = sp.zeros(size, size)
    for r in range(size):
        for c in range(r, size):
            out[r, c] = out[c, r] = builder.define(f"{hint}_{r}{c}", sp.expand(M[r, c]))
    return out


def named_vector(builder, hint: str, exprs) -> sp.Matrix:
    """A column of ``exprs``, each expanded and named in ``builder`` as ``{hint}_{k}``
    (entries that fold to numbers stay numbers)."""
    return builder.vector(hint, [sp.expand(e) for e in exprs])


def named_pose(builder, hint: str, pose: sp.Matrix) -> sp.Matrix:
    """``pose`` (4 x 4 homogeneous) with its top three rows named in ``builder`` as
    ``{hint}_{r}{c}``, each entry expanded (entries that fold to numbers stay numbers)."""
    return sp.Matrix.vstack(builder.matrix(hint, pose[:3, :].applyfunc(sp.expand)), sp.Matrix([[0, 0, 0, 1]]))


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


# ---------------------------------------------------------------------------------------------
# Staged transforms: a placement applied as its rotation and its translation, each stage named
# ---------------------------------------------------------------------------------------------

class Placement:
    """The pose of a frame B in a frame A as a rotation ``R`` (3 x 3, B's axes in A) and a
    translation ``p`` (3 x 1, B's origin in A); its motion transform is ``motion_transform``'s
    ``X = [R^T 0; 0 R^T] [1 0; -p x 1]``.

    The functions below apply X (or X^T) in stages, naming each stage's entries with ``name(hint,
    expressions) -> expressions``, so that a product costs what the structure of R and p allows
    (Featherstone, Rigid Body Dynamics Algorithms, section 2.8 and table A.1): zeros and numbers
    fold, a rotation about z touches 2 x 2 blocks, a translation along z few entries."""

    def __init__(self, pose: sp.Matrix):
        self.R = sp.Matrix(pose[:3, :3]).applyfunc(sp.expand)
        self.p = sp.Matrix(pose[:3, 3]).applyfunc(sp.expand)
        self.rotates = self.R != sp.eye(3)
        self.translates = not self.p.is_zero_matrix

    def matrix(self) -> sp.Matrix:
        """``X`` (6 x 6), for consumers that want it whole."""
        return motion_transform(sp.Matrix(sp.BlockMatrix([[self.R, self.p], [sp.zeros(1, 3), sp.ones(1, 1)]])))


def _stage(name, hint: str, exprs) -> sp.Matrix:
    return sp.Matrix(list(name(hint, [sp.expand(e) for e in exprs])))


def apply_motion(placement: Placement, v: sp.Matrix, name, hint: str) -> sp.Matrix:
    """``X v``: a motion vector ``[omega; v]`` of frame A in frame B (6 x 1)."""
    w, lin = sp.Matrix(v[:3, :]), sp.Matrix(v[3:, :])
    if placement.translates:
        lin = _stage(name, f"{hint}t", lin - cross_nonzero(placement.p, w))
    if placement.rotates:
        Rt = placement.R.T
        w, lin = _stage(name, f"{hint}w", Rt * w), _stage(name, f"{hint}r", Rt * lin)
    return sp.Matrix.vstack(w, lin)


def apply_force_back(placement: Placement, f: sp.Matrix, name, hint: str) -> sp.Matrix:
    """``X^T f``: a force ``[n; f]`` of frame B in frame A (moment about A's origin)."""
    moment, force = sp.Matrix(f[:3, :]), sp.Matrix(f[3:, :])
    if placement.rotates:
        moment = _stage(name, f"{hint}n", placement.R * moment)
        force = _stage(name, f"{hint}f", placement.R * force)
    if placement.translates:
        moment = moment + cross_nonzero(placement.p, force)
    return sp.Matrix.vstack(moment, force)


def _symmetric_stage(name, hint: str, M: sp.Matrix) -> sp.Matrix:
    """``M`` (symmetric 6 x 6) with its upper triangle named (21 entries)."""
    pairs = [(r, c) for r in range(6) for c in range(r, 6)]
    values = list(name(hint, [sp.expand(M[r, c]) for r, c in pairs]))
    out = sp.zeros(6, 6)
    for (r, c), value in zip(pairs, values):
        out[r, c] = out[c, r] = value
    return out


def apply_inertia_back(placement: Placement, M: sp.Matrix, name, hint: str) -> sp.Matrix:
    """``X^T M X``: a symmetric spatial inertia (6 x 6) of frame B in frame A.  The rotation
    turns each 3 x 3 block (``R M_ij R^T``, by way of ``M_ij R^T``), the translation adds
    ``[P B21 - Y P, Y; -B22 P, 0]`` with ``P = p x`` and ``Y = B12 + P B22``."""
    B = sp.Matrix(M)
    if placement.rotates:
        R = placement.R
        blocks = {}
        for (r, c) in ((0, 0), (0, 3), (3, 3)):
            half = _stage(name, f"{hint}h{r}{c}", B[r:r + 3, c:c + 3] * R.T)
            blocks[r, c] = R * half.reshape(3, 3)
        B = sp.Matrix(sp.BlockMatrix([[blocks[0, 0], blocks[0, 3]], [blocks[0, 3].T, blocks[3, 3]]]))
        B = _symmetric_stage(name, f"{hint}b", B)
    if placement.translates:
        P = skew(placement.p)
        B11, B12, B22 = B[:3, :3], B[:3, 3:], B[3:, 3:]
        Y = _stage(name, f"{hint}y", B12 + P * B22).reshape(3, 3)
        top_left = B11 + P * B12.T - Y * P
        B = sp.Matrix(sp.BlockMatrix([[top_left, Y], [Y.T, B22]]))
    return B
