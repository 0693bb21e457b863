"""Centre of mass and centroidal momentum of a whole robot (serial chain, tree or floating base),
symbolic.

World axes throughout, as Pinocchio's ``centerOfMass``, ``jacobianCenterOfMass``, ``ccrba`` and
``computeCentroidalMomentumTimeVariation``:

- ``center_of_mass``: c = sum(m_i c_i) / m, 3 (m), the links' and a floating base's bodies;
- ``center_of_mass_jacobian``: J_c, 3 x nv, c-dot = J_c v;
- ``center_of_mass_bias``: J_c-dot v, 3: the centre of mass's acceleration at zero joint (and
  base) accelerations;
- ``centroidal_momentum_matrix``: A_G, 6 x nv (Orin's), h_G = A_G v: linear momentum m c-dot,
  then the angular momentum about the centre of mass (rows 0-2 linear, 3-5 angular);
- ``centroidal_bias``: A_G-dot v, 6: the rate of h_G at zero accelerations.

How.  Everything is formed in the base frame (the fixed base's, or the floating base's own) and
turned into world axes at the end (one 3x3 rotation; translation does not change momenta about
the centre of mass).  Each link's pose in the base frame is composed once along the tree.  The
columns of A_G come from the *subtree* of each joint taken as one body: its mass m_j, first
moment h_j = sum m c and rotational inertia J_j about the base origin (sums over the subtree, so
each link's own terms are added once to each of its ancestors' sums).  For a unit rate of a
revolute joint with axis k through p: linear momentum ``k x (h_j - m_j p)`` and angular momentum
about the base origin ``J_j k - h_j x (k x p)``; prismatic: ``m_j k`` and ``h_j x k``.  The
angular momentum about the centre of mass G is that about the origin minus ``G x`` the linear
one.  The rates come from the Newton-Euler forward recursion at zero accelerations and zero
gravity (each link's ``F_i = m_i a_i`` and ``N_i``, the same quantities as the Coriolis vector's):
``m c-ddot = sum F_i`` and ``h_G-dot (angular) = sum (c_i - G) x F_i + N_i``.
"""

from __future__ import annotations

import sympy as sp

from ..model.errors import SymdynError
from ..model.outputs import CENTROIDAL_OUTPUTS  # noqa: F401 (the outputs this module derives)
from .chain import Chain
from .composite import composite_inertias, unit_momentum, whole_robot_inertia
from .newton_euler import recursion
from .poses import tree_poses, world_placement
from .spatial import named_vector


def _rotate(b, hint: str, R: sp.Matrix, v: sp.Matrix) -> sp.Matrix:
    return v if R == sp.eye(3) else named_vector(b, hint, R * v)


def centroidal_quantities(chain: Chain, wanted) -> dict[str, sp.Matrix]:
    """The requested outputs (names from :data:`CENTROIDAL_OUTPUTS`) of ``chain``'s robot."""
    robot, b = chain.robot, chain.builder
    links = robot.links
    base = robot.base_inertia if robot.floating else None
    total = sp.expand(sum((link.mass for link in links), base.mass if base is not None else sp.S.Zero))
    if total == 0:
        raise SymdynError(f"{robot.source or robot.name}: the centre of mass and the centroidal momentum need a "
                          "robot with mass (every link's mass is zero)")
    frames, poses = tree_poses(chain)
    # the first moment of every body about the base origin (base frame)
    first = sp.Matrix(base.com) * base.mass if base is not None else sp.zeros(3, 1)
    for i, link in enumerate(links):
        R, p = poses[i][:3, :3], poses[i][:3, 3]
        first += link.mass * (R * sp.Matrix(link.com) + p)
    R_w, p_w = world_placement(chain)
    first = named_vector(b, "hG", first)
    com_base = named_vector(b, "Gb", first / total)
    result: dict[str, sp.Matrix] = {}
    if "center_of_mass" in wanted:
        result["center_of_mass"] = (R_w * com_base + p_w).applyfunc(sp.expand)
    if {"center_of_mass_jacobian", "centroidal_momentum_matrix"} & set(wanted):
        A = _momentum_matrix(chain, frames, first, com_base)
        if R_w != sp.eye(3):  # into world axes, from the named base-frame entries
            A = sp.Matrix(6, A.shape[1], lambda r, c: b.define(f"AGb_{r}_{c}", A[r, c]))
            A = sp.Matrix.vstack(R_w * A[:3, :], R_w * A[3:, :]).applyfunc(sp.expand)
        if "centroidal_momentum_matrix" in wanted:
            result["centroidal_momentum_matrix"] = A
        if "center_of_mass_jacobian" in wanted:
            result["center_of_mass_jacobian"] = (A[:3, :] / total).applyfunc(sp.expand)
    if {"center_of_mass_bias", "centroidal_bias"} & set(wanted):
        force, moment = _momentum_rates(chain, poses, com_base)
        force, moment = _rotate(b, "dhGf", R_w, force), _rotate(b, "dhGn", R_w, moment)
        if "centroidal_bias" in wanted:
            result["centroidal_bias"] = sp.Matrix.vstack(force, moment)
        if "center_of_mass_bias" in wanted:
            result["center_of_mass_bias"] = (force / total).applyfunc(sp.expand)
    return result


def _momentum_matrix(chain: Chain, frames, first: sp.Matrix, com: sp.Matrix) -> sp.Matrix:
    """A_G in the base frame, 6 x nv (linear rows first, angular momentum about ``com``): each
    joint's column is its subtree's momentum for a unit rate (the composite-rigid-body
    quantities of the mass matrix, in the joint's frame) moved into the base frame."""
    robot, b = chain.robot, chain.builder
    composite = composite_inertias(chain)
    columns = []
    if robot.floating:
        whole = whole_robot_inertia(chain, composite)
        for a in range(3):  # the base's linear velocity: every body moves along e_a
            e = sp.eye(3)[:, a]
            columns.append((whole.mass * e, whole.first_moment.cross(e)))
        for a in range(3):  # its angular velocity about the base origin
            e = sp.eye(3)[:, a]
            columns.append((e.cross(whole.first_moment), whole.rotational * e))
    for j, link in enumerate(robot.links):
        R, p = frames[j][:3, :3], frames[j][:3, 3]  # joint frame J_j in the base frame
        force, moment = unit_momentum(composite[j], link.is_revolute)
        linear = named_vector(b, f"AGf{j + 1}", R * force)
        columns.append((linear, R * moment + p.cross(linear)))
    A = sp.zeros(6, len(columns))
    for col, (linear, angular) in enumerate(columns):
        A[:3, col] = linear.applyfunc(sp.expand)
        if robot.floating and col < 3:
            continue  # translating every body moves no mass about the centre of mass: exactly zero
        A[3:, col] = (angular - com.cross(linear)).applyfunc(sp.expand)
    return A


def _momentum_rates(chain: Chain, poses, com: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
    """(m c-ddot, the angular momentum's rate about ``com``) at zero accelerations, base frame."""
    robot, b = chain.robot, chain.builder
    zero = [sp.S.Zero] * len(chain.qd)
    motion: list = []
    states = recursion(chain, chain.qd, zero, sp.zeros(3, 1), "h", joint_frames=False, base_motion=motion)
    force, moment = sp.zeros(3, 1), sp.zeros(3, 1)
    for i, st in enumerate(states):
        R, p = poses[i][:3, :3], poses[i][:3, 3]
        F = named_vector(b, f"Fb{i + 1}", R * st.F)
        c = R * sp.Matrix(robot.links[i].com) + p
        force += F
        moment += R * st.N + (c - com).cross(F)
    if robot.floating:  # the base's own body, moving as the recursion starts
        body = robot.base_inertia
        omega, omegad, vd = motion
        s, inertia = sp.Matrix(body.com), sp.Matrix(body.inertia_matrix)
        F = named_vector(b, "Fb0", body.mass * (vd + omegad.cross(s) + omega.cross(omega.cross(s))))
        force += F
        moment += inertia * omegad + omega.cross(inertia * omega) + (s - com).cross(F)
    return named_vector(b, "dhGfb", force), named_vector(b, "dhGnb", moment)
