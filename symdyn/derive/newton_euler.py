"""Recursive Newton-Euler equations (Table 3.2 of the notes), symbolic, for both DH conventions.

Every vector is expressed in the frame of its own link (frame i), as in the efficient form of
the recursion.  With ``T_i = Pre_i Joint_i(q_i) Post_i`` (see :mod:`symdyn.derive.kinematics`):

- ``R_i`` is the rotation of ``^{i-1}T_i``; ``z_i`` the joint axis in frame i (constant);
- ``r1_i`` is the vector from O_{i-1} to the joint point J_i in frame i-1 (zero for standard DH),
  ``r2_i`` the vector from J_i to O_i in frame i (zero for modified DH; it is p*_i of the notes);
- ``s_i`` is the centre of mass of link i in frame i (s-bar_i of the notes).

Forward recursion (i = 1..n), revolute joint::

    omega_i    = R_i^T omega_{i-1} + z_i qd_i
    omegad_i   = R_i^T omegad_{i-1} + (R_i^T omega_{i-1}) x z_i qd_i + z_i qdd_i
    vd_i       = R_i^T (vd_{i-1} + omegad_{i-1} x r1_i + omega_{i-1} x (omega_{i-1} x r1_i))
                 + omegad_i x r2_i + omega_i x (omega_i x r2_i)

prismatic joint (p*_i = R_i^T times the translation of ^{i-1}T_i)::

    omega_i = R_i^T omega_{i-1};  omegad_i = R_i^T omegad_{i-1}
    vd_i    = R_i^T vd_{i-1} + omegad_i x p*_i + omega_i x (omega_i x p*_i)
              + 2 omega_i x (z_i qd_i) + z_i qdd_i

then ``abar_i = omegad_i x s_i + omega_i x (omega_i x s_i) + vd_i``, with ``vd_0 = -g`` (gravity
enters as an upward acceleration of the base, the usual initial condition).  Backward
recursion (i = n..1), forces and moments about O_i in frame i::

    F_i = m_i abar_i
    N_i = I_i omegad_i + omega_i x (I_i omega_i)
    f_i = F_i + R_{i+1} f_{i+1}
    n_i = N_i + s_i x F_i + R_{i+1} n_{i+1} + p_{i+1} x (R_{i+1} f_{i+1})
    tau_i = z_i . (n_i + r2_i x f_i)   (revolute)      tau_i = z_i . f_i   (prismatic)

where ``p_{i+1}`` is the position of O_{i+1} in frame i.  Viscous damping b_i qd_i, armature and
Coulomb friction are added by :mod:`symdyn.derive.equations`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import sympy as sp

from .chain import Chain
from .spatial import cross_nonzero
from ..model.outputs import PARAMETERS_PER_LINK as PER_LINK


@dataclass
class LinkState:
    """Intermediate quantities of one link for one recursion (all in frame i)."""

    omega: sp.Matrix
    omegad: sp.Matrix
    vd: sp.Matrix
    abar: sp.Matrix
    F: sp.Matrix
    N: sp.Matrix
    f: sp.Matrix | None = None
    n: sp.Matrix | None = None
    tau: sp.Expr | None = None


def _acceleration_operator(b, omega: sp.Matrix, omegad: sp.Matrix, hint: str) -> sp.Matrix | None:
    """``U = [omegad x] + [omega x]^2`` (3x3, 1/s^2), so that ``U p = omegad x p + omega x
    (omega x p)`` for any vector p fixed in the link: the acceleration of a point at p relative
    to the frame origin (Khalil's U_j).  Built from the six products omega_a omega_b, each
    further point costs one 3x3 product (9 multiplications) instead of three cross products
    (18).  None when the link neither turns nor accelerates."""
    if omega.is_zero_matrix and omegad.is_zero_matrix:
        return None
    wx, wy, wz = omega
    ax, ay, az = omegad
    xx, yy, zz = (b.define(f"{hint}_{k}{k}", w * w) for k, w in zip("xyz", omega))
    xy = b.define(f"{hint}_xy", wx * wy)
    xz = b.define(f"{hint}_xz", wx * wz)
    yz = b.define(f"{hint}_yz", wy * wz)
    return b.matrix(hint, sp.Matrix([[-(yy + zz), xy - az, xz + ay],
                                     [xy + az, -(xx + zz), yz - ax],
                                     [xz - ay, yz + ax, -(xx + yy)]]))


def _point_acceleration(U: sp.Matrix | None, omega: sp.Matrix, omegad: sp.Matrix, p: sp.Matrix) -> sp.Matrix:
    """``omegad x p + omega x (omega x p)``, as ``U p`` when U is given."""
    if p.is_zero_matrix or (omega.is_zero_matrix and omegad.is_zero_matrix):
        return sp.zeros(3, 1)
    if U is not None:
        return (U * p).applyfunc(sp.expand)
    return cross_nonzero(omegad, p) + cross_nonzero(omega, cross_nonzero(omega, p))


def _relative_acceleration(b, U: sp.Matrix | None, omega: sp.Matrix, omegad: sp.Matrix, p: sp.Matrix,
                           name: str) -> sp.Matrix:
    """``omegad x p + omega x (omega x p)`` of a point p of the link: ``U p`` when the link has
    U, else the table's cross products with ``omega x p`` named ``name`` (the printouts show
    it)."""
    if U is None and not p.is_zero_matrix:
        wp = b.vector(name, cross_nonzero(omega, p))
        return cross_nonzero(omegad, p) + cross_nonzero(omega, wp)
    return _point_acceleration(U, omega, omegad, p)


@dataclass(frozen=True)
class _LinkFrame:
    """What the recursion needs of link i, in the frame it runs in (see :func:`_link_frames`)."""

    pose: sp.Matrix  # 4x4 pose of this frame in the previous link's frame
    pre: sp.Matrix  # 4x4 constant part before the joint's motion
    post: sp.Matrix  # 4x4 constant part after it
    com: sp.Matrix  # centre of mass (m)
    inertia: sp.Matrix  # 3x3 about the centre of mass (kg m^2)

    @property
    def axis(self) -> sp.Matrix:
        """z_i: the joint axis in this frame (3x1, unit)."""
        return self.post[:3, :3].T * sp.Matrix([0, 0, 1])

    @property
    def r2(self) -> sp.Matrix:
        """r2_i: from the joint point to this frame's origin, in this frame (m)."""
        return self.post[:3, :3].T * self.post[:3, 3]


def _link_frames(chain: Chain, joint_frames: bool) -> list[_LinkFrame]:
    """Per link: the link frame i of the DH table (``joint_frames`` False), or its joint frame
    ``J_i`` (z along the joint axis through the joint point; the pose of J_i in J_{i-1} is
    ``Post_{i-1} Pre_i Joint_i(q_i)``), in which the axis is e_z and the point to the next joint
    has no part along the link's own post transform: for standard DH tables this saves the
    products with the twist's sine and cosine at every ``z qd``, ``z qdd`` and torque.  COM and
    inertia are moved into the chosen frame once, as constants."""
    frames = []
    for i, link in enumerate(chain.robot.links):
        geo = chain.geometry[i]
        pre, post = sp.Matrix(geo.pre), sp.Matrix(geo.post)
        com, inertia = sp.Matrix(link.com), sp.Matrix(link.inertia_matrix)
        if not joint_frames:
            frames.append(_LinkFrame(chain.transforms[i], pre, post, com, inertia))
            continue
        if chain.parents[i] >= 0:
            pre = sp.Matrix(chain.geometry[chain.parents[i]].post) * pre
        R, t = post[:3, :3], post[:3, 3]
        frames.append(_LinkFrame((pre * chain.motions[i]).applyfunc(sp.expand), pre.applyfunc(sp.expand), sp.eye(4),
                                 (R * com + t).applyfunc(sp.expand), (R * inertia * R.T).applyfunc(sp.expand)))
    return frames


def recursion(chain: Chain, qd: Sequence[sp.Expr], qdd: Sequence[sp.Expr],
              gravity: sp.Matrix, tag: str, parameters: Sequence[sp.Expr] | None = None,
              textbook: bool = False, joint_frames: bool | None = None,
              base_wrench: list | None = None, base_motion: list | None = None) -> list[LinkState]:
    """Run Table 3.2 for the given joint rates/accelerations and gravity vector (base frame).

    Returns each link's state; ``state.tau`` is the joint force without friction or armature.
    ``tag`` names the intermediate symbols of this run (shared sub-results are reused).
    ``parameters``: instead of the links' mass, centre of mass and inertia, standard parameters
    (13 per link, :mod:`symdyn.derive.regressor`: m, first moment MS = m s, inertia J about
    O_i): then ``F_i = m_i vd_i + omegad_i x MS_i + omega_i x (omega_i x MS_i)`` and
    ``N_i = J_i omegad_i + omega_i x (J_i omega_i) + MS_i x vd_i`` about O_i (Khalil's form, in
    which a link may have a first moment without a mass), and ``n_i`` has no ``s_i x F_i``;
    ``abar`` is then the origin's acceleration ``vd_i``.

    Each ``omegad x p + omega x (omega x p)`` term (a point fixed in a link: the next joint, the
    frame origin, the centre of mass) is computed as ``U_i p`` with Khalil's matrix ``U_i``
    (:func:`_acceleration_operator`), which costs fewer operations; ``textbook=True`` writes
    the cross products as the table does (the derivation printouts).

    ``joint_frames`` (default: unless ``textbook`` or ``parameters``) runs the recursion in
    the joint frames J_i instead of the link frames (:func:`_link_frames`); the torques are the
    same, the link states are then in J_i.

    A floating base (``chain.robot.floating``): ``qd`` and ``qdd`` hold the base's 6 entries
    first (Pinocchio's free-flyer: linear then angular velocity of the base in its own frame, and
    their rates, the spatial acceleration), then the joints'; the base starts the recursion with
    that motion (its origin's classical acceleration ``a + omega x v - g``), its own inertia
    (``base_inertia``) takes part, and ``base_wrench`` (a list) receives ``(f, n)``: the force
    and the moment about the base origin (base frame) that move the base as asked, the base's
    rows of the generalized forces; ``base_motion`` (a list) receives the base's ``(omega,
    omegad, vd)``, the motion the links start from (base frame).
    """
    b = chain.builder
    robot = chain.robot
    omega = sp.zeros(3, 1)
    omegad = sp.zeros(3, 1)
    vd = -sp.Matrix(gravity)
    base_qd, base_qdd = chain.base_part(qd), chain.base_part(qdd)
    qd, qdd = chain.joint_part(qd), chain.joint_part(qdd)
    U = None
    if robot.floating:
        omega, omegad = sp.Matrix(base_qd[3:]), sp.Matrix(base_qdd[3:])
        vd = b.vector(f"vd0{tag}", sp.Matrix(base_qdd[:3]) + cross_nonzero(omega, sp.Matrix(base_qd[:3])) + vd)
        U = None if textbook else _acceleration_operator(b, omega, omegad, f"U0{tag}")
    if joint_frames is None:
        joint_frames = not textbook and parameters is None
    frames = _link_frames(chain, joint_frames)
    states: list[LinkState] = []
    base_state = (omega, omegad, vd, U)
    if base_motion is not None:
        base_motion.extend((omega, omegad, vd))
    moving: list[tuple] = []  # per link: (omega, omegad, vd, U) in its frame, for its children
    for i, link in enumerate(robot.links):
        k = i + 1
        # the state of the link this one hangs on (U: None in the textbook form, or at rest)
        omega, omegad, vd, U = base_state if chain.parents[i] < 0 else moving[chain.parents[i]]
        omega_i, omegad_i, vd_i, U = _link_motion(b, link, frames[i], (omega, omegad, vd, U), qd[i], qdd[i], k, tag,
                                                  textbook)
        abar, F, N = _link_forces(b, U, omega_i, omegad_i, vd_i, link, frames[i], parameters, i, f"{k}{tag}")
        states.append(LinkState(omega_i, omegad_i, vd_i, abar, F, N))
        moving.append((omega_i, omegad_i, vd_i, U))

    joint_moments = _backward(b, chain, frames, states, parameters, tag, textbook)
    if robot.floating:
        wrench = _floating_base_wrench(b, chain, frames, states, joint_moments, base_state, tag, textbook)
        if base_wrench is not None:
            base_wrench.extend(wrench)
    return states


def _link_motion(b, link, frame: "_LinkFrame", parent: tuple, qd_i, qdd_i, number: int, tag: str,
                 textbook: bool) -> tuple:
    """``(omega_i, omegad_i, vd_i, U_i)`` of link ``number`` (1-based, in its frame) from the
    ``parent`` link's ``(omega, omegad, vd, U)`` and its joint's rate and acceleration (the
    forward lines of Table 3.2); intermediate symbols are named with the number and ``tag``."""
    omega, omegad, vd, U = parent
    hint = f"{number}{tag}"
    T = frame.pose
    R = T[:3, :3]
    Rt = R.T
    z = frame.axis
    if link.is_revolute:
        w_rot = b.vector(f"Rw{hint}", Rt * omega)
        omega_i = b.vector(f"w{hint}", w_rot + z * qd_i)
        omegad_i = b.vector(f"wd{hint}", Rt * omegad + cross_nonzero(w_rot, z * qd_i) + z * qdd_i)
        r1 = frame.pre[:3, 3]
        r2 = frame.r2
        a_joint = vd + _point_acceleration(U, omega, omegad, r1)
        if not (r1.is_zero_matrix or (omega.is_zero_matrix and omegad.is_zero_matrix)):
            a_joint = b.vector(f"aJ{hint}", a_joint)
        U = None if textbook else _acceleration_operator(b, omega_i, omegad_i, f"U{hint}")
        relative = _relative_acceleration(b, U, omega_i, omegad_i, r2, f"wr{hint}")
        vd_i = b.vector(f"vd{hint}", Rt * a_joint + relative)
    else:
        omega_i = b.vector(f"w{hint}", Rt * omega)
        omegad_i = b.vector(f"wd{hint}", Rt * omegad)
        p_star = b.vector(f"p{number}", Rt * T[:3, 3])
        U = None if textbook else _acceleration_operator(b, omega_i, omegad_i, f"U{hint}")
        relative = _relative_acceleration(b, U, omega_i, omegad_i, p_star, f"wp{hint}")
        vd_i = b.vector(f"vd{hint}", Rt * vd + relative
                        + 2 * cross_nonzero(omega_i, z * qd_i) + z * qdd_i)
    return omega_i, omegad_i, vd_i, U


def _link_forces(b, U, omega_i, omegad_i, vd_i, link, frame: "_LinkFrame", parameters, i: int, hint: str) -> tuple:
    """``(abar, F, N)`` of link ``i``: from its mass, centre of mass and inertia, or from its
    standard parameters (Khalil's form: F and N about O_i, abar the origin's acceleration)."""
    if parameters is None:
        abar, F, N = _body_forces(b, U, omega_i, omegad_i, vd_i, link.mass, frame.com, frame.inertia, hint)
    else:
        m, mx, my, mz, ixx, ixy, iyy, ixz, iyz, izz = parameters[PER_LINK * i:PER_LINK * i + 10]
        moment = sp.Matrix([mx, my, mz])
        inertia = sp.Matrix([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        relative = _relative_acceleration(b, U, omega_i, omegad_i, moment, f"wm{hint}")
        abar = vd_i
        F = b.vector(f"F{hint}", m * vd_i + relative)
        Iw = b.vector(f"Iw{hint}", inertia * omega_i)
        N = b.vector(f"N{hint}", inertia * omegad_i + cross_nonzero(omega_i, Iw)
                     + cross_nonzero(moment, vd_i))
    return abar, F, N


def _backward(b, chain: Chain, frames, states, parameters, tag: str, textbook: bool) -> dict:
    """The backward lines of Table 3.2: each link's f_i, n_i and tau_i set on its state, tip to
    base; returns each revolute link's moment about its joint point (for a floating base's wrench)."""
    robot = chain.robot
    # n_c + r2_c x f_c: link c's moment about its joint point (revolute joints), per link
    joint_moments: dict[int, sp.Matrix] = {}
    for i in reversed(range(len(robot.links))):
        k = i + 1
        st = states[i]
        link = robot.links[i]
        s = frames[i].com if parameters is None else sp.zeros(3, 1)  # N_i is about O_i then
        f_children, moment_children = _children_wrench(b, frames, states, joint_moments, chain.children(i),
                                                       f"{k}{tag}", textbook)
        st.f = b.vector(f"f{k}{tag}", st.F + f_children)
        st.n = b.vector(f"n{k}{tag}", st.N + cross_nonzero(s, st.F) + moment_children)
        z = frames[i].axis
        if link.is_revolute:
            r2 = frames[i].r2
            moment = st.n + cross_nonzero(r2, st.f)
            if chain.parents[i] >= 0 and not textbook and not r2.is_zero_matrix:
                moment = b.vector(f"nJ{k}{tag}", moment)
            joint_moments[i] = moment
            st.tau = b.define(f"tau{k}{tag}", (z.T * moment)[0])
        else:
            st.tau = b.define(f"tau{k}{tag}", (z.T * st.f)[0])
    return joint_moments


def _body_forces(b, U, omega: sp.Matrix, omegad: sp.Matrix, vd: sp.Matrix, mass, com: sp.Matrix, inertia: sp.Matrix,
                 hint: str) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """``(abar, F, N)`` of one body moving with (omega, omegad) and origin acceleration ``vd``:
    the centre of mass's acceleration ``abar = vd + omegad x s + omega x (omega x s)``, the
    force ``F = m abar`` and the moment about the centre of mass ``N = I omegad + omega x I
    omega``; named ``a{hint}``, ``F{hint}``, ``Iw{hint}``, ``N{hint}``."""
    relative = _relative_acceleration(b, U, omega, omegad, com, f"ws{hint}")
    abar = b.vector(f"a{hint}", relative + vd)
    F = b.vector(f"F{hint}", mass * abar)
    Iw = b.vector(f"Iw{hint}", inertia * omega)
    N = b.vector(f"N{hint}", inertia * omegad + cross_nonzero(omega, Iw))
    return abar, F, N


def _floating_base_wrench(b, chain: Chain, frames, states, joint_moments, base_state, tag: str, textbook: bool):
    """``(f, n)`` on a floating base: its own ``m (a + U c)`` and ``I_c omegad + omega x I_c omega
    + c x F`` (about its origin), and what the links on it take from it; base frame."""
    omega, omegad, vd, U = base_state
    body = chain.robot.base_inertia
    com = sp.Matrix(body.com)
    _, F, N = _body_forces(b, U, omega, omegad, vd, body.mass, com, sp.Matrix(body.inertia_matrix), f"0{tag}")
    f_children, moment_children = _children_wrench(b, frames, states, joint_moments, chain.children(-1),
                                                   f"0{tag}", textbook)
    return (b.vector(f"f0{tag}", F + f_children),
            b.vector(f"n0{tag}", N + cross_nonzero(com, F) + moment_children))


def _children_wrench(b, frames: list[_LinkFrame], states: list[LinkState], joint_moments: dict, children,
                     hint: str, textbook: bool) -> tuple[sp.Matrix, sp.Matrix]:
    """The force and the moment (about this link's origin) that the links hanging on it exert
    on it, in its frame: ``sum_c R_c f_c`` and ``sum_c R_c n_c + p_c x (R_c f_c)`` over its
    children c (zero for a leaf; one term on a serial chain).  ``R_c f_c`` is named
    ``Rf{hint}`` (``Rf{hint}_{c}`` with several children)."""
    f_sum, moment_sum = sp.zeros(3, 1), sp.zeros(3, 1)
    for c in children:
        T = frames[c].pose
        name = f"Rf{hint}" if len(children) == 1 else f"Rf{hint}_{c + 1}"
        f_rot = b.vector(name, T[:3, :3] * states[c].f)
        if c in joint_moments and not textbook:
            # p_c = r1_c + R_c r2_c for a revolute joint, so R n + p x (R f) = R (n + r2 x f) +
            # r1 x (R f): the joint moment link c's torque already needed, and no product with
            # q_c's sine and cosine
            moment = T[:3, :3] * joint_moments[c] + cross_nonzero(frames[c].pre[:3, 3], f_rot)
        else:
            moment = T[:3, :3] * states[c].n + cross_nonzero(T[:3, 3], f_rot)
        f_sum, moment_sum = f_sum + f_rot, moment_sum + moment
    return f_sum, moment_sum


def joint_forces(chain: Chain, qd, qdd, gravity, tag: str, parameters=None) -> sp.Matrix:
    """Column of joint forces/torques (n x 1) of one recursion, without friction and armature
    (``parameters``: standard parameters instead of the links' own, see :func:`recursion`)."""
    base: list = []
    states = recursion(chain, qd, qdd, gravity, tag, parameters, base_wrench=base)
    return sp.Matrix([*(e for part in base for e in part), *(st.tau for st in states)])
