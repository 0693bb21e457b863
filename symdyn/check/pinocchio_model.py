"""Build a Pinocchio model from a robot, to cross-check symdyn (requires the ``pin`` package).

This module deliberately shares no kinematics code with the derivations: the DH transforms are
written again here with plain numpy, so that a mistake in one shows up as a mismatch.

Pinocchio frames: joint k's frame is where the joint's motion (Rz or Tz) happens.

- standard DH ``A_k = Rz(theta_k + q_k) Tz(d_k) Tx(a_k) Rx(alpha_k)``: the joint frame is DH
  frame k-1; the joint placement is the previous link's constant part and link k's inertia (given
  in DH frame k) is placed by ``Tz(d) Tx(a) Rx(alpha)`` (with ``Rz(theta)`` for prismatic joints).
- modified DH ``T_k = Rx(alpha_{k-1}) Tx(a_{k-1}) Rz(theta_k + q_k) Tz(d_k)``: the joint frame is
  DH frame k (up to the revolute offset theta), the inertia sits in it directly.
- general (origin O_k, unit axis a_k): the joint frame is O_k, the joint is Pinocchio's
  revolute/prismatic joint about the unaligned axis a_k, and the inertia sits in the joint frame.

The robot's ``base`` placement is the placement of the first joint in Pinocchio's world (gravity
stays in world axes), and a frame ``tool`` on the last joint is the robot's tool frame.

A revolute offset theta becomes part of the joint placement (a rotation about the joint axis),
so q = 0 means the same pose in both codes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np
import sympy as sp

from ..model.outputs import ALL_OUTPUTS
from ..model.robot import Robot
from .states import state_arguments


def _rx(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def _t(x=0.0, y=0.0, z=0.0) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out


def _value(expr, what: str) -> float:
    try:
        return float(expr)
    except TypeError:
        raise ValueError(f"{what} is symbolic ({expr}); substitute numbers first "
                         "(Robot.substitute) or pass them as values=") from None


def numeric_links(robot: Robot) -> list[dict]:
    """Every link's fields as floats (raises ValueError if anything is still symbolic)."""
    rows = []
    for k, link in enumerate(robot.links):
        tag = f"link {k + 1} ('{link.name}')"
        rows.append({
            "revolute": link.is_revolute,
            "a": _value(link.a, f"{tag} a"), "alpha": _value(link.alpha, f"{tag} alpha"),
            "d": _value(link.d, f"{tag} d"), "theta": _value(link.theta, f"{tag} theta"),
            "mass": _value(link.mass, f"{tag} mass"),
            "com": np.array([_value(c, f"{tag} com") for c in link.com]),
            "inertia": np.array([_value(c, f"{tag} inertia") for c in link.inertia]),
            "armature": _value(link.armature, f"{tag} armature"),
            "damping": _value(link.damping, f"{tag} damping"),
            "coulomb": _value(link.coulomb, f"{tag} coulomb"),
            "fixed": (np.eye(4) if link.fixed is None else
                      np.array([_value(c, f"{tag} fixed") for c in link.fixed]).reshape(4, 4)),
            "origin": (None if link.origin is None else
                       np.array([_value(c, f"{tag} origin") for c in link.origin.matrix()]).reshape(4, 4)),
            "axis": None if link.axis is None else np.array([_value(c, f"{tag} axis") for c in link.axis]),
        })
    return rows


def build_model(robot: Robot, values: Mapping | None = None):
    """A ``pinocchio.Model`` of the robot (revolute joints RZ, prismatic PZ).

    ``values`` substitutes numbers for runtime parameters and free symbols first (by symbol or
    name).  The model's ``armature`` is set from the robot, so ``crba`` returns
    ``D + diag(armature)`` and ``rnea`` includes ``armature * qdd``; Pinocchio has no viscous or
    Coulomb friction in ``rnea``: add ``damping * qd + coulomb * sign(qd)`` yourself.
    Returns ``(model, info)`` where info holds the numeric damping and coulomb vectors.
    """
    import pinocchio as pin

    if values:
        robot = robot.substitute(values)
    links = numeric_links(robot)
    model = pin.Model()
    model.name = robot.name
    model.gravity.linear = np.array([_value(g, "gravity") for g in robot.gravity])
    root, base_rows = 0, []
    if robot.floating:  # Pinocchio's free-flyer carrying the base body
        root = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "root_joint")
        model.addJointFrame(root, -1)
        body = robot.base_inertia
        xx, yy, zz, xy, xz, yz = (_value(c, "base_body inertia") for c in body.inertia)
        model.appendBodyToJoint(root, pin.Inertia(_value(body.mass, "base_body mass"),
                                                  np.array([_value(c, "base_body com") for c in body.com]),
                                                  np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])),
                                pin.SE3.Identity())
        base_rows = [0.0] * 6
    placed: list = []  # per link: (its joint id, the pose of its link frame in that joint's frame)
    parent, body = _add_chain(model, robot, links, parent=root, placed=placed)
    order = depth_first(robot)
    model.armature = np.array(base_rows + [links[k]["armature"] for k in order])
    tool = body @ np.array([_value(c, "tool") for c in robot.tool_matrix()]).reshape(4, 4)
    model.addFrame(pin.Frame("tool", parent, pin.SE3(tool[:3, :3].copy(), tool[:3, 3].copy()),
                             pin.FrameType.OP_FRAME))
    for frame in robot.frames:  # the frame functions' frames, by name
        local = np.array([_value(c, f"frame {frame.name}") for c in frame.matrix()]).reshape(4, 4)
        if frame.link >= 0:
            joint, at = placed[frame.link]
        else:  # on the base: the floating base's joint, or the world at the base placement
            joint, at = root, np.eye(4) if robot.floating else np.array(
                [_value(c, "base") for c in robot.base_matrix()]).reshape(4, 4)
        pose = at @ local
        model.addFrame(pin.Frame(f"frame_{frame.name}", joint, pin.SE3(pose[:3, :3].copy(), pose[:3, 3].copy()),
                                 pin.FrameType.OP_FRAME))
    for contact in robot.contacts:  # the contact set again, its kind in the name (the harness's constraintDynamics)
        frame = model.frames[model.getFrameId(f"frame_{robot.frames[contact.frame].name}")]
        model.addFrame(pin.Frame(f"contact{contact.kind}_{robot.frames[contact.frame].name}", frame.parentJoint,
                                 frame.placement, pin.FrameType.OP_FRAME))
    info = {"damping": np.array(base_rows + [links[k]["damping"] for k in order]),
            "last_body": body,  # pose of the last link frame in its joint frame
            "coulomb": np.array(base_rows + [links[k]["coulomb"] for k in order]),
            "order": order}  # the links in the model's joint order
    return model, info


def _add_chain(model, robot: Robot, links: list[dict], parent: int = 0, prefix: str = "", placed: list | None = None):
    """Add the robot's joints and link inertias to ``model`` below joint ``parent`` (the robot's
    base placement relative to it); returns ``(last joint id, pose of the last link frame in
    that joint's frame)``; ``placed`` (a list) receives each link's pair."""
    import pinocchio as pin

    # constant transform from the parent joint frame to this joint frame (the first: the base)
    base = np.array([_value(c, "base") for c in robot.base_matrix()]).reshape(4, 4)
    root = parent
    after: dict[int, np.ndarray] = {}  # per link: the transform from its joint frame to its children's
    ids: dict[int, int] = {}
    body = np.eye(4)
    if placed is not None:
        placed[:] = [None] * len(links)
    for k in depth_first(robot):  # Pinocchio's algorithms need each subtree's joints contiguous
        row = links[k]
        up = robot.parent_indices[k]
        parent, placement = (root, base) if up < 0 else (ids[up], after[up])
        placement = placement @ row["fixed"]
        if robot.convention == "general":
            joint_placement = placement @ row["origin"]
            body = np.eye(4)
            next_placement = np.eye(4)
        elif robot.convention == "standard":
            joint_placement = placement
            if row["revolute"]:
                joint_placement = joint_placement @ _rz(row["theta"])
                body = _t(z=row["d"]) @ _t(x=row["a"]) @ _rx(row["alpha"])
            else:
                body = _rz(row["theta"]) @ _t(z=row["d"]) @ _t(x=row["a"]) @ _rx(row["alpha"])
            next_placement = body
        else:
            joint_placement = placement @ _rx(row["alpha"]) @ _t(x=row["a"]) @ _rz(row["theta"]) @ _t(z=row["d"])
            body = np.eye(4)
            next_placement = np.eye(4)
        if robot.convention == "general":
            x, y, z = row["axis"]
            joint = (pin.JointModelRevoluteUnaligned(x, y, z) if row["revolute"]
                     else pin.JointModelPrismaticUnaligned(x, y, z))
        else:
            joint = pin.JointModelRZ() if row["revolute"] else pin.JointModelPZ()
        se3 = pin.SE3(joint_placement[:3, :3].copy(), joint_placement[:3, 3].copy())
        joint_id = model.addJoint(parent, joint, se3, f"{prefix}joint{k + 1}")
        model.addJointFrame(joint_id, -1)  # frames: needed by buildReducedModel and friends
        xx, yy, zz, xy, xz, yz = row["inertia"]
        inertia_com = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        link_inertia = pin.Inertia(row["mass"], row["com"].copy(), inertia_com)
        body_se3 = pin.SE3(body[:3, :3].copy(), body[:3, 3].copy())
        model.appendBodyToJoint(joint_id, body_se3.act(link_inertia), pin.SE3.Identity())
        ids[k] = joint_id
        after[k] = next_placement
        if placed is not None:
            placed[k] = (joint_id, body)
    return (ids[len(links) - 1] if links else root), body


def depth_first(robot: Robot) -> list[int]:
    """The links in the order Pinocchio's model takes them: each subtree's joints contiguous
    (depth first, children in file order); the file's order for a chain, and for any tree whose
    file lists each subtree in one piece."""
    order: list[int] = []
    stack = list(reversed(robot.children(-1)))
    while stack:
        k = stack.pop()
        order.append(k)
        stack.extend(reversed(robot.children(k)))
    return order


def build_closed_loop_model(robot, armature: float = 0.0):
    """Pinocchio's closed-loop model of a platform robot (:class:`symdyn.model.parallel.ParallelRobot`),
    built independently of symdyn's parallel derivation: the platform a free-flying body (joint
    ``platform``, its frame P), each leg a chain of Pinocchio joints from the world
    (``legN_joint1`` ...), and one 6D loop-closure constraint per leg between the leg's last link
    frame and its attachment frame on the platform (LOCAL).  Returns ``(model, constraint models,
    info)``; info: each leg's joint ids, velocity indices and actuated velocity index, and the
    viscous and Coulomb friction coefficients of every velocity (``damping``, ``coulomb``: the
    legs' links', zero for the platform; :func:`closed_loop_friction`).  The model's armature is
    the legs' links' armature; ``armature`` (kg m^2 or kg) is added on every leg joint: Pinocchio's constraint solver factorizes
    the joint-space mass matrix, which massless links (a spherical pair's or a universal joint's
    crosses) leave singular; 1e-9 changes the flight simulator's accelerations by about 5e-12."""
    import pinocchio as pin

    model = pin.Model()
    model.name = robot.name
    model.gravity.linear = np.array([_value(g, "gravity") for g in robot.gravity])
    platform = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "platform")
    plat = robot.platform
    model.appendBodyToJoint(platform, pin.Inertia(_value(plat.mass, "platform mass"),
                                                  np.array([_value(c, "platform com") for c in plat.com]),
                                                  np.array(plat.inertia_matrix, dtype=float)), pin.SE3.Identity())
    constraints, legs = [], []
    armatures, damping, coulomb = [np.zeros(6)], [np.zeros(6)], [np.zeros(6)]
    for leg in robot.legs:
        links = numeric_links(leg.chain)
        armatures.append([row["armature"] for row in links])
        damping.append([row["damping"] for row in links])
        coulomb.append([row["coulomb"] for row in links])
        first = model.njoints
        last, body = _add_chain(model, leg.chain, links, 0, f"{leg.name}_")
        attachment = np.array(leg.attachment.matrix(), dtype=float)
        constraints.append(pin.RigidConstraintModel(
            pin.ContactType.CONTACT_6D, model, last, pin.SE3(body[:3, :3].copy(), body[:3, 3].copy()),
            platform, pin.SE3(attachment[:3, :3].copy(), attachment[:3, 3].copy()), pin.ReferenceFrame.LOCAL))
        ids = list(range(first, last + 1))
        legs.append({"joints": ids, "v": [model.joints[j].idx_v for j in ids],
                     "q": [model.joints[j].idx_q for j in ids],
                     "actuated_v": model.joints[ids[leg.actuated]].idx_v, "last": last, "body": body})
    model.armature = np.concatenate(armatures) + np.concatenate([np.zeros(6), np.full(model.nv - 6, float(armature))])
    return model, constraints, {"platform": platform, "legs": legs, "damping": np.concatenate(damping),
                                "coulomb": np.concatenate(coulomb)}


# closed loops (platform robots) --------------------------------------------------------------
# Pinocchio's side of a platform state: the tree's q, v, a from the platform's pose, twist and
# twist rate and the legs' joint values (symdyn.check.parallel_reference), and the closed-loop
# inverse and forward dynamics from rnea, the constraint Jacobian and the constrained equations.

def pinocchio_state(model, info, ref, p, R, twist, twist_rate, legs):
    """Pinocchio's q, v, a for the platform state and the legs' joint positions, rates and
    accelerations.  The free flyer's v and a are LOCAL and spatial: the platform's classical
    [omega_dot; c_ddot] (world, at the mass centre) is converted."""
    import pinocchio as pin
    q, v, a = np.zeros(model.nq), np.zeros(model.nv), np.zeros(model.nv)
    q[:3] = p
    q[3:7] = pin.Quaternion(R).coeffs()
    c = R @ ref.com
    omega, c_dot = twist[:3], twist[3:]
    v_origin = c_dot - np.cross(omega, c)
    v[:3], v[3:6] = R.T @ v_origin, R.T @ omega
    if twist_rate is not None:
        omega_dot, c_ddot = twist_rate[:3], twist_rate[3:]
        a_origin = c_ddot - np.cross(omega_dot, c) - np.cross(omega, np.cross(omega, c))
        a[:3] = R.T @ a_origin - np.cross(v[3:6], v[:3])
        a[3:6] = R.T @ omega_dot
    for leg, state in zip(info["legs"], legs):
        q[leg["q"]] = state.theta
        v[leg["v"]] = state.theta_dot
        if state.theta_ddot is not None:
            a[leg["v"]] = state.theta_ddot
    return q, v, a


def closure_mismatch(model, data, models, q, v, a):
    """The largest difference between the two sides of the loop closures: placements, and the
    spatial velocities and accelerations in the closure frame."""
    import pinocchio as pin
    pin.forwardKinematics(model, data, q, v, a)
    worst = [0.0, 0.0, 0.0]
    for cm in models:
        oM1 = data.oMi[cm.joint1_id] * cm.joint1_placement
        oM2 = data.oMi[cm.joint2_id] * cm.joint2_placement
        relative = oM1.inverse() * oM2
        worst[0] = max(worst[0], np.abs(oM1.homogeneous - oM2.homogeneous).max())
        for k, motion in ((1, data.v), (2, data.a)):
            side1 = cm.joint1_placement.actInv(motion[cm.joint1_id])
            side2 = relative.act(cm.joint2_placement.actInv(motion[cm.joint2_id]))
            worst[k] = max(worst[k], np.abs(side1.vector - side2.vector).max())
    return worst


def closure_accelerations(model, data, models, q, v, a):
    """The closures' relative spatial accelerations (side 1 minus side 2, in the closure frame),
    stacked: zero for accelerations that keep the loops closed."""
    import pinocchio as pin
    pin.forwardKinematics(model, data, q, v, a)
    out = []
    for cm in models:
        relative = (data.oMi[cm.joint1_id] * cm.joint1_placement).inverse() * \
            (data.oMi[cm.joint2_id] * cm.joint2_placement)
        side1 = cm.joint1_placement.actInv(data.a[cm.joint1_id])
        side2 = relative.act(cm.joint2_placement.actInv(data.a[cm.joint2_id]))
        out.append((side1 - side2).vector)
    return np.concatenate(out)


def actuation_matrix(model, info):
    S = np.zeros((model.nv, 6))
    for k, leg in enumerate(info["legs"]):
        S[leg["actuated_v"], k] = 1.0
    return S


def closed_loop_friction(info, v):
    """The legs' joint friction at the tree's velocities v (viscous plus Coulomb, zero for the
    platform): the torques it takes beyond rnea's."""
    return info["damping"] * v + info["coulomb"] * np.sign(v)


def pinocchio_inverse_dynamics(model, data, models, datas, info, q, v, a):
    """Actuator forces from rnea of the open tree (plus the legs' joint friction) and the
    constraint Jacobian (rnea = Jc^T lambda + S phi: 42 equations, 36 + 6 unknowns)."""
    import pinocchio as pin
    tau_tree = pin.rnea(model, data, q, v, a) + closed_loop_friction(info, v)
    pin.computeJointJacobians(model, data, q)
    Jc = pin.getConstraintsJacobian(model, data, models, datas)
    return np.linalg.solve(np.hstack([Jc.T, actuation_matrix(model, info)]), tau_tree)[-6:]


def pinocchio_forward_dynamics(model, data, models, info, q, v, phi):
    """The tree's accelerations a under actuator forces phi from the constrained equations
    M a + nle + friction = S phi + Jc^T lambda, Jc a + gamma = 0 (gamma: the closures'
    acceleration at a = 0, Jc's columns from unit accelerations at v = 0: exact, and free of
    the cancellation against gamma that large velocities would bring)."""
    import pinocchio as pin
    nv, nc = model.nv, 6 * len(models)
    M = pin.crba(model, data, q)
    M = mirror_upper(M)
    nle = pin.nonLinearEffects(model, data, q, v) + closed_loop_friction(info, v)
    gamma = closure_accelerations(model, data, models, q, v, np.zeros(nv))
    Jc = np.column_stack([closure_accelerations(model, data, models, q, np.zeros(nv), unit) for unit in np.eye(nv)])
    kkt = np.block([[M, -Jc.T], [Jc, np.zeros((nc, nc))]])
    return np.linalg.solve(kkt, np.concatenate([actuation_matrix(model, info) @ phi - nle, -gamma]))[:nv]


def free_flyer_twist_rate(R, com, twist, a):
    """The platform's classical [omega_dot; c_ddot] (world, at the mass centre) from the free
    flyer's LOCAL spatial acceleration a[:6] (inverse of the conversion in pinocchio_state)."""
    omega, c_dot = twist[:3], twist[3:]
    c = R @ com
    v_origin = c_dot - np.cross(omega, c)
    v_local, w_local = R.T @ v_origin, R.T @ omega
    omega_dot = R @ a[3:6]
    a_origin = R @ (a[:3] + np.cross(w_local, v_local))
    c_ddot = a_origin + np.cross(omega_dot, c) + np.cross(omega, np.cross(omega, c))
    return np.concatenate([omega_dot, c_ddot])


def normalized_error(mine, ref, floor: float = 0.0, row_floor: float = 0.0) -> float:
    """The error measure used everywhere symdyn is compared with a reference.

    Arrays of shape (states, n) or (states, n, m).  For each joint (row) j: the largest
    ``|mine - ref|`` over states (and columns) divided by the RMS over states of joint j's
    reference; a joint whose reference is (numerically) zero everywhere is divided by the RMS
    of the whole output instead, and no divisor is below ``floor`` (in the output's units: an
    output that is zero up to rounding, such as the Coriolis forces of bodies that each turn
    about one fixed axis, is then measured against the floor, not against its own rounding
    noise) nor below ``row_floor`` times the RMS of the whole output (a row far smaller than
    the others carries the rounding of the large ones: :data:`symdyn.model.tolerances.ROW_FLOOR`).
    Returns the worst joint's value; ``inf`` when either array holds a NaN or an infinity
    anywhere (a non-finite output is always a failure, never dropped by ``max``).
    """
    mine = np.asarray(mine, dtype=float)
    ref = np.asarray(ref, dtype=float)
    if mine.shape != ref.shape or not (np.all(np.isfinite(mine)) and np.all(np.isfinite(ref))):
        return float("inf")
    states, n = ref.shape[:2]
    with np.errstate(over="ignore", invalid="ignore"):
        diff = np.abs(mine - ref).reshape(states, n, -1)  # inf where the difference overflows: a failure
    refs = ref.reshape(states, n, -1)
    overall = _rms(refs) or 1.0
    worst = 0.0
    for j in range(n):
        rms = _rms(refs[:, j, :])
        divisor = max(rms if rms > 1e-9 * overall else overall, floor, row_floor * overall)
        worst = max(worst, float(np.max(diff[:, j, :])) / divisor)
    return worst if np.isfinite(worst) else float("inf")


def _rms(values) -> float:
    """Root mean square without overflow or underflow (scaled by the largest magnitude): the
    RMS of values near 1e200 is near 1e200, not infinity."""
    values = np.asarray(values, dtype=float)
    scale = float(np.max(np.abs(values))) if values.size else 0.0
    if scale == 0.0:
        return 0.0
    return scale * float(np.sqrt(np.mean((values / scale) ** 2)))


def compare(mine, reference, states, functions, p=None, floor: float | dict = 0.0,
            row_floor: float = 0.0) -> dict[str, float]:
    """The normalized error (:func:`normalized_error`, with ``floor``: one for every function,
    or each function's, and ``row_floor``) of each named function of ``mine`` against the same
    function of ``reference``, over ``states`` (each ``[q, qd, qdd, tau]``).

    Both take the function's inputs in symdyn's order (:data:`symdyn.model.outputs.OUTPUT_INPUTS`,
    drawn from each state by :func:`symdyn.check.states.state_arguments`);
    ``p`` (runtime parameters) is passed to ``mine`` only, when given.
    """
    extra = [] if p is None else [p]
    contact_rows = sum(len(held.axes) for held in getattr(reference, "contact_set", ()))
    errors = {}
    for name in functions:
        values, refs = [], []
        for state in states:
            args = state_arguments(name, state, contact_rows)
            value = np.asarray(getattr(mine, name)(*args, *extra), dtype=float)
            ref = np.asarray(getattr(reference, name)(*args), dtype=float)
            if value.shape != ref.shape and value.squeeze().shape == ref.squeeze().shape:
                value = value.reshape(ref.shape)  # (one column: a vector on one side, a matrix on the other)
            values.append(value)
            refs.append(ref)
        errors[name] = normalized_error(values, refs, floor.get(name, 0.0) if isinstance(floor, dict) else floor,
                                        row_floor)
    return errors


def mirror_upper(matrix) -> np.ndarray:
    """A symmetric matrix from its upper triangle (Pinocchio's crba and computeMinverse fill only
    that)."""
    matrix = np.asarray(matrix)
    return np.triu(matrix) + np.triu(matrix, 1).T


class ConfigurationSpaceReference:
    """Pinocchio's values of the configuration-space functions (integrate, difference and their
    Jacobians) on symdyn's configurations: its Lie group SE(3) x R^n of a floating base with n
    joints (``pinocchio.liegroups``, whose free-flyer and revolute joints a model's ``integrate``
    composes), R^n of a fixed base, each joint one coordinate as symdyn's (a continuous joint's
    angle, not Pinocchio's (cos, sin)).  A quaternion is normalized first (symdyn takes any
    scale; Pinocchio asks for a unit one).  Subclasses set :attr:`configuration_layout`."""

    #: (floating base, joints) of symdyn's configuration
    configuration_layout: tuple[bool, int] = (False, 0)

    @property
    def lie_group(self):
        import pinocchio as pin
        floating, joints = self.configuration_layout
        if not floating:
            return pin.liegroups.Rn(joints)
        return pin.liegroups.SE3() * pin.liegroups.Rn(joints) if joints else pin.liegroups.SE3()

    def _unit(self, q) -> np.ndarray:
        q = np.array(q, dtype=float)
        if self.configuration_layout[0]:
            q[3:7] = q[3:7] / np.linalg.norm(q[3:7] / np.max(np.abs(q[3:7]))) / np.max(np.abs(q[3:7]))
        return q

    def integrate(self, q, v):
        return self.lie_group.integrate(self._unit(q), np.asarray(v, dtype=float))

    def integrate_dq(self, v):
        group = self.lie_group
        return group.dIntegrate_dq(group.neutral, np.asarray(v, dtype=float))

    def integrate_dv(self, v):
        group = self.lie_group
        return group.dIntegrate_dv(group.neutral, np.asarray(v, dtype=float))

    def difference(self, q, q1):
        return self.lie_group.difference(self._unit(q), self._unit(q1))

    def difference_dq0(self, q, q1):
        import pinocchio as pin
        return self.lie_group.dDifference(self._unit(q), self._unit(q1), pin.ARG0)

    def difference_dq1(self, q, q1):
        import pinocchio as pin
        return self.lie_group.dDifference(self._unit(q), self._unit(q1), pin.ARG1)


class ContactReference:
    """Pinocchio's values of the contact dynamics (``contact_accelerations``, ``contact_forces``)
    from its rigid-body quantities: ``M = D + diag(armature)`` (``system_matrix``), the
    free-motion bias ``rnea(q, qd, 0)`` plus friction (``inverse_dynamics``), the contact frames'
    LOCAL_WORLD_ALIGNED Jacobians (``frame_jacobians``) and classical accelerations at zero
    accelerations (``frame_jacobian_dot_v``; a sole's drift its spatial acceleration, the classical
    minus omega x v, as ``constraintDynamics`` holds a 6D contact), and the KKT system solved as a
    dense matrix by numpy: nothing of symdyn's derivation.  tests/derive/test_contact.py checks this
    against Pinocchio's ``constraintDynamics`` itself (whose ``lambda_c`` are these forces).
    :attr:`contact_set` (:class:`HeldContact` s) is set by :func:`reduced`; a Baumgarte correction
    adds ``kd v + kp (p - reference)`` to a point's drift, ``kd v - kp X log6(M^-1 M_ref)`` to a
    sole's (Pinocchio's ``corrector`` with one gain on every axis, its ``log6``:
    tests/derive/test_contact_kinds.py checks it against constraintDynamics too)."""

    contact_set: tuple = ()
    #: the coordinates contact inverse dynamics gives no force (a floating base's six), set by :func:`reduced`
    unactuated: tuple = ()

    def _contact_jacobian(self, q) -> np.ndarray:
        """The contacts' rows of their frames' Jacobians (NC x N): a point's 3 linear, a sole's 6."""
        J_all = np.asarray(self.frame_jacobians(q))
        return np.vstack([J_all[[6 * held.frame + a for a in held.axes]] for held in self.contact_set])

    def _rows_and_drift(self, q, qd, sole_logs: bool = True):
        """``(J, gamma)``: the contacts' rows (:meth:`_contact_jacobian`) and their drift J-dot qd,
        a point's classical acceleration at qdd = 0, a sole's spatial one (the classical minus
        omega x v, as constraintDynamics holds a 6D contact)."""
        J, drift_all = self._contact_jacobian(q), np.asarray(self.frame_jacobian_dot_v(q, qd))
        qd = np.asarray(qd, dtype=float)
        gamma, at = [], 0
        poses = np.asarray(self.frame_poses(q)) if any(held.kp or held.kd for held in self.contact_set) else None
        for held in self.contact_set:
            frame, kind = held.frame, held.kind
            drift = np.array(drift_all[6 * frame:6 * frame + 6])
            if kind == "6d":
                velocity = J[at:at + 6] @ qd
                drift[:3] -= np.cross(velocity[3:], velocity[:3])
            count = len(held.axes)
            drift = drift[list(held.axes)]
            if held.kp or held.kd:
                drift += held.kd * (J[at:at + count] @ qd)
                if held.kind != "6d" or sole_logs:
                    drift += held.kp * self._placement_error(held, poses)
            gamma.append(drift)
            at += count
        return J, np.concatenate(gamma)

    def _sole_log_derivative(self, q) -> np.ndarray:
        """The derivative by q (NC x N, along q (+) dv) of the corrected soles' terms
        ``-kp X log6(M^-1 M_ref)`` (zero rows elsewhere), from Pinocchio's ``Jlog6``: the frame
        moving by its world-aligned motion delta (its Jacobian's columns: J6) turns X by
        [delta_ang]x and M^-1 M_ref = Y by exp(-X^T delta) on the left, so the term changes by
        ``kp [[e_lin]x; [e_ang]x] delta_ang + kp X Jlog6(Y) Ad(Y^-1) X^T delta`` (e = X log6(Y))."""
        import pinocchio as pin
        poses, J_all = np.asarray(self.frame_poses(q)), np.asarray(self.frame_jacobians(q))
        rows, at = [], 0
        for held in self.contact_set:
            block = np.zeros((len(held.axes), J_all.shape[1]))
            if held.kind == "6d" and held.kp:
                pose = poses[4 * held.frame:4 * held.frame + 4]
                R = pose[:3, :3]
                X = np.kron(np.eye(2), R)
                Y = pin.SE3(R.copy(), pose[:3, 3].copy()).actInv(
                    pin.SE3(pin.rpy.rpyToMatrix(*held.reference[3:]), np.asarray(held.reference[:3], dtype=float)))
                xi = pin.log6(Y)
                e_lin, e_ang = R @ xi.linear, R @ xi.angular
                J6 = J_all[6 * held.frame:6 * held.frame + 6]
                turn = np.vstack([pin.skew(e_lin), pin.skew(e_ang)]) @ J6[3:]
                block = held.kp * (turn + X @ pin.Jlog6(Y) @ Y.inverse().action @ X.T @ J6)
            rows.append(block)
            at += len(held.axes)
        return np.vstack(rows)

    def _sole_log(self, held, poses):
        """Pinocchio's ``log6(M^-1 M_ref)`` of a corrected sole (M its frame's placement)."""
        import pinocchio as pin
        pose = poses[4 * held.frame:4 * held.frame + 4]
        reference = pin.SE3(pin.rpy.rpyToMatrix(*held.reference[3:]), np.asarray(held.reference[:3], dtype=float))
        return pin.log6(pin.SE3(pose[:3, :3].copy(), pose[:3, 3].copy()).actInv(reference))

    def _placement_error(self, held, poses) -> np.ndarray:
        """A corrected contact's placement error, world-aligned, on its axes: a point's ``p -
        reference``; a sole's ``-X log6(M^-1 M_ref)`` (Pinocchio's ``log6``, X = diag(R, R))."""
        pose = poses[4 * held.frame:4 * held.frame + 4]
        if held.kind != "6d":
            return (pose[:3, 3] - np.asarray(held.reference))[list(held.axes)]
        xi = self._sole_log(held, poses)
        R = pose[:3, :3]
        return -np.concatenate([R @ xi.linear, R @ xi.angular])

    def _constrained(self, q, qd, tau):
        J, gamma = self._rows_and_drift(q, qd)
        qd = np.asarray(qd, dtype=float)
        M = np.asarray(self.system_matrix(q))
        bias = np.asarray(self.inverse_dynamics(q, qd, np.zeros(len(qd))))
        n, m = M.shape[0], len(gamma)
        system = np.block([[M, J.T], [J, np.zeros((m, m))]])
        solution = np.linalg.solve(system, np.concatenate([np.asarray(tau, dtype=float) - bias, -gamma]))
        return solution[:n], -solution[n:]  # [M J^T; J 0][qdd; -lambda] = [tau - b; -gamma]

    def _applied(self, q, f):
        """J^T f: the external forces at the contacts as generalized forces."""
        return self._contact_jacobian(q).T @ np.asarray(f, dtype=float)

    def inverse_dynamics_ext(self, q, qd, qdd, f):
        return np.asarray(self.inverse_dynamics(q, qd, qdd)) - self._applied(q, f)

    def forward_dynamics_ext(self, q, qd, tau, f):
        bias = np.asarray(self.inverse_dynamics(q, qd, np.zeros(len(qd))))
        return np.linalg.solve(np.asarray(self.system_matrix(q)), np.asarray(tau, dtype=float) + self._applied(q, f) - bias)

    def _impact(self, q, qd, restitution):
        """(qd_plus, impulse) of [M J^T; J 0][qd+; -impulse] = [M qd; -e J qd] (impulseDynamics)."""
        J, qd = self._contact_jacobian(q), np.asarray(qd, dtype=float)
        M = np.asarray(self.system_matrix(q))
        n, m = M.shape[0], J.shape[0]
        system = np.block([[M, J.T], [J, np.zeros((m, m))]])
        e = float(np.asarray(restitution).reshape(-1)[0])
        solution = np.linalg.solve(system, np.concatenate([M @ qd, -e * (J @ qd)]))
        return solution[:n], -solution[n:]

    def impulse_velocities(self, q, qd, restitution):
        return self._impact(q, qd, restitution)[0]

    def impulse_forces(self, q, qd, restitution):
        return self._impact(q, qd, restitution)[1]

    def contact_accelerations(self, q, qd, tau):
        return self._constrained(q, qd, tau)[0]

    def contact_forces(self, q, qd, tau):
        return self._constrained(q, qd, tau)[1]

    #: the step and weights of the 8th-order central difference the constraint terms' derivatives
    #: by q are taken with (truncation ~ h^8 / 630 of the 9th derivative, rounding ~ 1e-16 / h of the
    #: values): against computeConstraintDynamicsDerivatives on Solo-12, 1.8e-11 with the 6th order
    #: at h = 1e-3, 1.5e-12 with this; fuzz case 0 (a mimic joint at 1.66 times its leader's rate,
    #: the step divided by that) 1.5e-11 at h = 5e-2, 3e-13 at this
    _STEP = 2.5e-2
    _STENCIL = ((1, 4 / 5), (2, -1 / 5), (3, 4 / 105), (4, -1 / 280))
    #: the largest rate of a joint per unit coordinate rate (a mimic joint's multiplier; 1 without)
    _rate_scale = 1.0

    def _constraint_terms(self, q, qd, qdd, force):
        """``(J^T lambda, J qdd + gamma)``: the constraints' generalized force at fixed ``force``
        (world-aligned axes) and the contacts' accelerations (a point's classical, a sole's
        spatial) at ``qdd``, from Pinocchio's frame Jacobians and accelerations; a corrected
        sole's log term left out (:meth:`_sole_log_derivative` differentiates it: log6 jumps at a
        half turn, and a difference quotient near it loses its digits)."""
        J, gamma = self._rows_and_drift(q, qd, sole_logs=False)
        return J.T @ force, J @ qdd + gamma

    def _contact_derivatives(self, q, qd, tau):
        """``(dqdd/dq, dqdd/dqd, dqdd/dtau, dlambda/dq, dlambda/dqd, dlambda/dtau)``: the implicit
        function theorem on ``F1 = ID - J^T lambda - tau``, ``F2 = J qdd + gamma`` at the
        solution, ``[M J^T; J 0][dqdd; -dlambda] = -[dF1; dF2]``, with Pinocchio's RNEA
        derivatives for ID, and the constraint terms (:meth:`_constraint_terms`, Pinocchio's
        values) differentiated by an 8th-order central difference along q (+) h e_j (exact in qd:
        they are linear and quadratic in it); lambda is held in the world's axes."""
        qdd, force = self._constrained(q, qd, tau)
        qd = np.asarray(qd, dtype=float)
        M, J = np.asarray(self.system_matrix(q)), self._contact_jacobian(q)
        n, m = M.shape[0], J.shape[0]
        dF1_q = np.array(self.inverse_dynamics_dq(q, qd, qdd), dtype=float)
        dF1_qd = np.array(self.inverse_dynamics_dqd(q, qd, qdd), dtype=float)
        dF2_q, dF2_qd = np.zeros((m, n)), np.zeros((m, n))
        h = self._STEP / self._rate_scale  # (a mimic joint turning m times as fast: h / m, the same truncation)
        for j in range(n):
            step = np.zeros(n)
            for k, weight in self._STENCIL:
                step[j] = k * h
                ahead = self._constraint_terms(self.integrate(q, step), qd, qdd, force)
                behind = self._constraint_terms(self.integrate(q, -step), qd, qdd, force)
                dF1_q[:, j] -= weight * (ahead[0] - behind[0]) / h
                dF2_q[:, j] += weight * (ahead[1] - behind[1]) / h
            rate = np.zeros(n)
            rate[j] = 1.0
            ahead, behind = self._constraint_terms(q, qd + rate, qdd, force), self._constraint_terms(q, qd - rate, qdd, force)
            dF2_qd[:, j] = (ahead[1] - behind[1]) / 2
        system = np.block([[M, J.T], [J, np.zeros((m, m))]])
        if any(held.kind == "6d" and held.kp for held in self.contact_set):
            dF2_q += self._sole_log_derivative(q)
        solved = [-np.linalg.solve(system, np.vstack([a, b])) for a, b in ((dF1_q, dF2_q), (dF1_qd, dF2_qd))]
        inverse = np.linalg.inv(system)
        dq, dqd = solved
        dlambda_dq = -dq[n:]
        return dq[:n], dqd[:n], inverse[:n, :n], dlambda_dq, -dqd[n:], -inverse[n:, :n]

    def _contact_inverse(self, q, qd, qdd):
        """``(tau, lambda)`` of the contact inverse dynamics: lambda the least-norm solution of
        J_u^T lambda = ID_u over the unactuated coordinates (:attr:`unactuated`; numpy's lstsq of
        the underdetermined system, by the SVD), tau = ID - J^T lambda with those rows zero; ID is
        Pinocchio's rnea plus friction."""
        tau = np.array(self.inverse_dynamics(q, qd, qdd), dtype=float)
        J = self._contact_jacobian(q)
        rows = list(self.unactuated)
        force = np.linalg.lstsq(J[:, rows].T, tau[rows], rcond=None)[0] if rows else np.zeros(J.shape[0])
        tau -= J.T @ force
        tau[rows] = 0.0
        return tau, force

    def contact_inverse_pivot_ratio(self, q) -> float:
        """The smallest pivot R_kk^2 of the QR of the contacts' unactuated columns J_u relative
        to its column's squared norm (1 for orthogonal columns, 0 where the contacts cannot push
        the base in every direction): what the generated code checks."""
        rows = list(self.unactuated)
        if not rows:
            return 1.0
        columns = self._contact_jacobian(q)[:, rows]
        R = np.linalg.qr(columns, mode="r")
        norms = np.sum(columns ** 2, axis=0)
        return float(np.min(np.diag(R) ** 2 / np.where(norms > 0, norms, 1.0))) if columns.shape[0] >= len(rows) else 0.0

    def contact_inverse_torques(self, q, qd, qdd):
        return self._contact_inverse(q, qd, qdd)[0]

    def contact_inverse_forces(self, q, qd, qdd):
        return self._contact_inverse(q, qd, qdd)[1]

    def contact_accelerations_dq(self, q, qd, tau):
        return self._contact_derivatives(q, qd, tau)[0]

    def contact_accelerations_dqd(self, q, qd, tau):
        return self._contact_derivatives(q, qd, tau)[1]

    def contact_accelerations_dtau(self, q, qd, tau):
        return self._contact_derivatives(q, qd, tau)[2]

    def contact_forces_dq(self, q, qd, tau):
        return self._contact_derivatives(q, qd, tau)[3]

    def contact_forces_dqd(self, q, qd, tau):
        return self._contact_derivatives(q, qd, tau)[4]

    def contact_forces_dtau(self, q, qd, tau):
        return self._contact_derivatives(q, qd, tau)[5]


class PinocchioReference(ContactReference, ConfigurationSpaceReference):
    """Pinocchio's values of symdyn's quantities for a robot (numbers substituted for its
    parameters with ``values``), in symdyn's notation: ``mass_matrix`` excludes armature,
    ``inverse_dynamics`` and ``forward_dynamics`` include viscous and Coulomb friction."""

    def __init__(self, robot: Robot, values: Mapping | None = None):
        import pinocchio as pin
        self.pin = pin
        self.model, info = build_model(robot, values)
        self.data = self.model.createData()
        self.configuration_layout = (robot.floating, robot.dof)
        self.damping, self.coulomb = info["damping"], info["coulomb"]
        self.armature = np.array(self.model.armature)
        #: the robot's links in the model's joint order (a tree listed with a subtree in two
        #: pieces is reordered: :func:`reduced` then maps the values back)
        self.order = info["order"]
        self.actuated = list(robot.actuated_joints)
        base = np.array([_value(c, "base") for c in robot.base_matrix()]).reshape(4, 4)
        self.world_to_base = pin.SE3(base[:3, :3].copy(), base[:3, 3].copy()).inverse()
        self.task_rows = tuple(robot.task_rows)

    def mass_matrix(self, q):
        M = self.pin.crba(self.model, self.data, q)
        return mirror_upper(M) - np.diag(self.armature)

    def system_matrix(self, q):
        """M = D + diag(armature), what forward dynamics solves with."""
        return mirror_upper(self.pin.crba(self.model, self.data, q))

    def gravity(self, q):
        return self.pin.computeGeneralizedGravity(self.model, self.data, q).copy()

    def _rnea_derivatives(self, q, qd, qdd):
        dq, dv, _ = self.pin.computeRNEADerivatives(self.model, self.data, q, qd, qdd)
        return np.array(dq).copy(), np.array(dv).copy()

    def inverse_dynamics_dq(self, q, qd, qdd):
        return self._rnea_derivatives(q, qd, qdd)[0]

    def inverse_dynamics_dqd(self, q, qd, qdd):
        return self._rnea_derivatives(q, qd, qdd)[1] + np.diag(self.damping)

    def gravity_derivative(self, q):
        return np.array(self.pin.computeGeneralizedGravityDerivatives(self.model, self.data, q)).copy()

    def mass_matrix_inverse(self, q):
        return mirror_upper(self.pin.computeMinverse(self.model, self.data, q))

    def _aba_derivatives(self, q, qd, tau):
        """Pinocchio's computeABADerivatives at the torques less friction: ``(dqdd/dq,
        dqdd/dv at those torques, M^-1)``."""
        found = self.pin.computeABADerivatives(self.model, self.data, q, qd, tau - self.friction(qd))
        dq, dv, Minv = (np.array(x).copy() for x in found)
        return dq, dv, mirror_upper(Minv)

    def forward_dynamics_dq(self, q, qd, tau):
        return self._aba_derivatives(q, qd, tau)[0]

    def forward_dynamics_dqd(self, q, qd, tau):
        """dqdd/dqd with viscous friction: the torques less damping qd depend on qd too."""
        _, dv, Minv = self._aba_derivatives(q, qd, tau)
        return dv - Minv @ np.diag(self.damping)

    def coriolis(self, q, qd):
        gravity = self.pin.computeGeneralizedGravity(self.model, self.data, q).copy()
        return self.pin.nonLinearEffects(self.model, self.data, q, qd).copy() - gravity

    def coriolis_matrix(self, q, qd):
        return self.pin.computeCoriolisMatrix(self.model, self.data, q, qd).copy()

    def kinetic_energy(self, q, qd):
        """The bodies' and the rotors' kinetic energy (J), one entry: Pinocchio's sum over the
        bodies (``computeKineticEnergy`` of the model without armature) plus ``armature . qd^2 / 2``
        (Pinocchio 4.1's own sum leaves out the armature of its unaligned revolute joints)."""
        if not hasattr(self, "_bodies_only"):
            model = self.model.copy()
            model.armature = np.zeros(model.nv)
            self._bodies_only = (model, model.createData())
        model, data = self._bodies_only
        qd = np.asarray(qd, dtype=float)
        return np.array([self.pin.computeKineticEnergy(model, data, q, qd) + 0.5 * float(self.armature @ (qd * qd))])

    def friction(self, qd):
        return self.damping * qd + self.coulomb * np.sign(qd)

    def inverse_dynamics(self, q, qd, qdd):
        return self.pin.rnea(self.model, self.data, q, qd, qdd).copy() + self.friction(qd)

    def forward_dynamics(self, q, qd, tau):
        return self.pin.aba(self.model, self.data, q, qd, tau - self.friction(qd)).copy()

    # the frames' kinematics (world axes at each frame's origin: LOCAL_WORLD_ALIGNED), stacked
    def _frame_ids(self):
        """The model's frames of the frame functions, in their order (build_model names them
        ``frame_NAME``)."""
        return [k for k, f in enumerate(self.model.frames) if f.name.startswith("frame_")]

    def frame_poses(self, q):
        self.pin.framesForwardKinematics(self.model, self.data, q)
        return np.vstack([self.data.oMf[i].homogeneous for i in self._frame_ids()])

    def frame_jacobians(self, q):
        self.pin.computeJointJacobians(self.model, self.data, q)
        self.pin.updateFramePlacements(self.model, self.data)
        return np.vstack([np.asarray(self.pin.getFrameJacobian(self.model, self.data, i, self.pin.LOCAL_WORLD_ALIGNED))
                          .reshape(6, self.model.nv) for i in self._frame_ids()])  # (one joint: a 6-vector)

    def frame_jacobian_dot_v(self, q, qd):
        self.pin.forwardKinematics(self.model, self.data, q, qd, np.zeros(self.model.nv))
        self.pin.updateFramePlacements(self.model, self.data)
        return np.concatenate([self.pin.getFrameClassicalAcceleration(self.model, self.data, i,
                                                                       self.pin.LOCAL_WORLD_ALIGNED).vector
                               for i in self._frame_ids()])

    # the whole robot's centre of mass and centroidal momentum (world axes; Pinocchio's
    # functions of the same names, each on its own)
    def center_of_mass(self, q):
        return self.pin.centerOfMass(self.model, self.data, q).copy()

    def center_of_mass_jacobian(self, q):
        return self.pin.jacobianCenterOfMass(self.model, self.data, q).copy()

    def center_of_mass_bias(self, q, qd):
        self.pin.centerOfMass(self.model, self.data, q, qd, np.zeros(self.model.nv))
        return self.data.acom[0].copy()

    def centroidal_momentum_matrix(self, q):
        return self.pin.ccrba(self.model, self.data, q, np.zeros(self.model.nv)).copy()

    def centroidal_bias(self, q, qd):
        return self.pin.computeCentroidalMomentumTimeVariation(self.model, self.data, q, qd,
                                                               np.zeros(self.model.nv)).vector.copy()

    def base_wrench(self, q, qd, tau_actuated):
        """The wrench ``[n; f]`` the base exerts on body 1 (moment about the base origin first,
        base axes) when the actuated joints apply ``tau_actuated`` and the passive ones nothing:
        ``aba``, then ``rnea`` at that acceleration, then ``data.f[1]`` (joint 1's frame) moved
        to the base frame."""
        tau = np.zeros(self.model.nv)
        tau[self.actuated] = tau_actuated
        qdd = PinocchioReference.forward_dynamics(self, q, qd, tau)  # q as Pinocchio takes it
        self.pin.rnea(self.model, self.data, q, qd, qdd)
        self.pin.forwardKinematics(self.model, self.data, q)
        force = self.world_to_base.act(self.data.oMi[1].act(self.data.f[1]))
        return np.concatenate([force.angular, force.linear])

    #: functions computed from the others (so taking q as the others do, not wrapped again)
    COMPOSED = ("reaction_map",)

    def reaction_map(self, q, qd):
        """``[k0 | D]`` (6, 1 + actuated joints) from :meth:`base_wrench` at zero and at unit
        actuated torques (the wrench is affine in them)."""
        k0 = self.base_wrench(q, qd, np.zeros(len(self.actuated)))
        columns = [self.base_wrench(q, qd, unit) - k0 for unit in np.eye(len(self.actuated))]
        return np.column_stack([k0, *columns])

    @property
    def tool_frame(self) -> int:
        return self.model.getFrameId("tool", self.pin.FrameType.OP_FRAME)

    def forward_kinematics(self, q):
        self.pin.framesForwardKinematics(self.model, self.data, q)
        return self.data.oMf[self.tool_frame].homogeneous.copy()

    def jacobian(self, q):
        self.pin.computeJointJacobians(self.model, self.data, q)
        self.pin.updateFramePlacements(self.model, self.data)
        J = self.pin.getFrameJacobian(self.model, self.data, self.tool_frame,
                                      self.pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        return np.array(J).reshape(6, self.model.nv)  # 6 x 1 for one joint (Pinocchio gives a vector)

    def jacobian_dot_qd(self, q, qd):
        self.pin.forwardKinematics(self.model, self.data, q, qd, np.zeros(self.model.nv))
        self.pin.updateFramePlacements(self.model, self.data)
        acc = self.pin.getFrameClassicalAcceleration(self.model, self.data, self.tool_frame,
                                                     self.pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        return np.concatenate([acc.linear, acc.angular])

    #: the rows of the tool Jacobian the task-space references use (the robot's task)
    task_rows: tuple = (0, 1, 2, 3, 4, 5)

    def _task_inverse_terms(self, q):
        """``(M^-1, J_s, J_s M^-1 J_s^T)`` at q: ``computeMinverse`` (armature included, upper
        triangle mirrored) and the task rows of the LOCAL_WORLD_ALIGNED tool Jacobian."""
        Minv = PinocchioReference.mass_matrix_inverse(self, q)
        J = PinocchioReference.jacobian(self, q)[list(self.task_rows), :]
        return Minv, J, J @ Minv @ J.T

    def _task_terms(self, q):
        """``(M^-1, J_s, Lambda)`` at q, Lambda the inverse of ``J_s M^-1 J_s^T``."""
        Minv, J, A = self._task_inverse_terms(q)
        return Minv, J, np.linalg.inv(A)

    def task_pivot_ratio(self, q) -> float:
        """The smallest pivot of the LDL^T of ``J_s M^-1 J_s^T`` relative to its diagonal entry
        (1 for an ideally conditioned task, 0 at a singularity): what the generated code checks."""
        A = PinocchioReference._task_inverse_terms(self, q)[2]
        try:
            return float(np.min(np.diag(np.linalg.cholesky(A)) ** 2 / np.diag(A)))
        except np.linalg.LinAlgError:
            return 0.0

    def task_mass_matrix(self, q):
        return self._task_terms(q)[2]

    def task_gravity(self, q):
        Minv, J, Lambda = self._task_terms(q)
        return Lambda @ J @ Minv @ PinocchioReference.gravity(self, q)

    def task_bias(self, q, qd):
        Minv, J, Lambda = self._task_terms(q)
        h = PinocchioReference.coriolis(self, q, qd)
        return Lambda @ (J @ Minv @ h - PinocchioReference.jacobian_dot_qd(self, q, qd)[list(self.task_rows)])

    def task_inverse(self, q):
        Minv, J, Lambda = self._task_terms(q)
        return Minv @ J.T @ Lambda


class UrdfReference(PinocchioReference):
    """Pinocchio's values for the chain of a URDF file, from Pinocchio's own URDF parser
    (``buildModelFromUrdf``): an independent reading of the file, to check symdyn's.

    The chain runs from the root to the link ``tip``; joints off it are locked at their neutral
    position (``buildReducedModel``), as symdyn merges them.  Continuous joints (Pinocchio's
    (cos, sin) configuration) take symdyn's angle.  ``tool``: the link whose frame is the tool
    (default ``tip``).  Viscous and Coulomb friction come from the file's ``<dynamics>``.
    """

    def __init__(self, path: str, tip: str | None = None, tool: str | None = None,
                 quarter_turns: float | None = None, floating_base: bool = False, frames=None):
        import pinocchio as pin
        self.pin = pin
        self.floating = floating_base
        text, renamed = _pinocchio_urdf(str(path), quarter_turns)
        self._frame_names = [renamed.get(name, name) for name in frames or ()]  # URDF links, by name
        root = [pin.JointModelFreeFlyer()] if floating_base else []
        full = pin.buildModelFromXML(text, *root) if text is not None else pin.buildModelFromUrdf(str(path), *root)
        if floating_base or (tip is None and _whole_tree(str(path))):  # the whole tree, as symdyn reads it
            self._whole(full)
            return
        if tip is None:  # the only leaf link, or the end of the one chain of moving joints
            tip = _only_leaf(str(path))
        body = pin.FrameType.BODY  # links by name and type
        if not full.existFrame(renamed.get(tip, tip), body):
            raise ValueError(f"no link {tip!r} in {path}")
        joint = full.frames[full.getFrameId(renamed.get(tip, tip), body)].parentJoint
        chain = []
        while joint > 0:
            chain.append(joint)
            joint = full.parents[joint]
        chain.reverse()
        locked = [j for j in range(1, full.njoints) if j not in chain]
        self.model = pin.buildReducedModel(full, locked, pin.neutral(full)) if locked else full
        names = [full.names[j] for j in chain]
        if list(self.model.names)[1:] != names:
            raise ValueError(f"reduced model joints {list(self.model.names)[1:]} differ from the chain {names}")
        self.data = self.model.createData()
        self.continuous = [self.model.joints[j].nq == 2 for j in range(1, self.model.njoints)]
        self.damping = np.array(self.model.damping, dtype=float)
        self.coulomb = np.array(self.model.friction, dtype=float)
        self.armature = np.array(self.model.armature, dtype=float)
        self._tool = self.model.getFrameId(renamed.get(tool or tip, tool or tip), body)
        self.actuated = list(range(self.model.nv))  # URDF joints are all actuated
        self.world_to_base = pin.SE3.Identity()  # symdyn's base frame is the root link's

    def _whole(self, model) -> None:
        """Compare with Pinocchio's model of the whole file (a tree: no tool frame)."""
        self.model = model
        self.data = model.createData()
        self.continuous = [model.joints[j].nq == 2 for j in range(1, model.njoints)]
        self.damping = np.array(model.damping, dtype=float)
        self.coulomb = np.array(model.friction, dtype=float)
        self.armature = np.array(model.armature, dtype=float)
        self._tool = None
        self.actuated = list(range(model.nv))
        self.world_to_base = self.pin.SE3.Identity()
        self.joint_names = list(model.names)[2 if self.floating else 1:]
        if self.floating:
            self.continuous = self.continuous[1:]

    @property
    def configuration_layout(self) -> tuple[bool, int]:
        return self.floating, len(self.continuous)

    @property
    def tool_frame(self) -> int:
        return self._tool

    def _frame_ids(self):
        """The URDF links asked for as frames, Pinocchio's body frames of those names."""
        return [self.model.getFrameId(name, self.pin.FrameType.BODY) for name in self._frame_names]

    def configuration(self, q) -> np.ndarray:
        """Pinocchio's configuration vector for symdyn's joint angles ``q`` (a floating base's 7
        coordinates first, as they are)."""
        q = np.asarray(q, dtype=float)
        out = list(q[:7]) if self.floating else []
        for value, continuous in zip(q[7:] if self.floating else q, self.continuous):
            out.extend([np.cos(value), np.sin(value)] if continuous else [value])
        return np.array(out)


def _pinocchio_urdf(path: str, tolerance: float | None) -> tuple[str | None, dict[str, str]]:
    """The URDF text of ``path`` as Pinocchio's parser should read it, and the links renamed;
    ``(None, {})`` when the file can be read as it is.

    With ``tolerance``, every rpy angle within it of a multiple of pi/2 is written as that
    multiple to full double precision (how symdyn reads it by default).  A link named as a joint
    (ANYmal's ``LF_HAA``) is renamed ``NAME__link``: Pinocchio's ``buildReducedModel`` looks
    frames up by name alone and fails on the pair."""
    import xml.etree.ElementTree as ET  # a file symdyn has already read (and checked) itself
    tree = ET.parse(path)
    root = tree.getroot()
    changed = False
    for origin in root.iter("origin") if tolerance else ():
        rpy = origin.get("rpy")
        if rpy is None:
            continue
        values = []
        for text in rpy.split():
            value = float(text)
            k = round(value / (np.pi / 2))
            values.append(repr(k * np.pi / 2) if abs(value - k * np.pi / 2) <= tolerance else text)
        origin.set("rpy", " ".join(values))
        changed = True
    joints = {joint.get("name") for joint in root.iter("joint")}
    names = joints | {link.get("name") for link in root.iter("link")}
    renamed: dict[str, str] = {}
    for link in root.findall("link"):
        name = link.get("name")
        if name in joints:
            new = name + "__link"
            while new in names:
                new += "_"
            names.add(new)
            renamed[name] = new
            link.set("name", new)
    for joint in root.findall("joint"):
        for end in (joint.find("parent"), joint.find("child")):
            if end is not None and end.get("link") in renamed:
                end.set("link", renamed[end.get("link")])
    if not changed and not renamed:
        return None, {}
    return ET.tostring(root, encoding="unicode"), renamed


def _whole_tree(path: str) -> bool:
    from ..model.urdf import reads_as_tree
    with open(path, encoding="utf-8") as handle:
        return reads_as_tree(handle.read(), path)


def _only_leaf(path: str) -> str:
    """The tip symdyn's reading takes when none is given (symdyn.model.urdf.default_tip): the
    chain compared is the one symdyn generated; the model itself is Pinocchio's own reading."""
    from ..model.urdf import default_tip
    with open(path, encoding="utf-8") as handle:
        return default_tip(handle.read(), path)


def _configured(method):
    def wrapped(self, q, *rest):
        return method(self, self.configuration(q), *rest)
    wrapped.__name__ = method.__name__
    return wrapped


for _name in (*ALL_OUTPUTS, "base_wrench", "task_pivot_ratio", "system_matrix"):  # every reference function, q as the URDF reader orders it
    if _name in vars(PinocchioReference) and _name not in PinocchioReference.COMPOSED:
        setattr(UrdfReference, _name, _configured(getattr(PinocchioReference, _name)))


class MimicReduction(ContactReference, ConfigurationSpaceReference):
    """Reference values of a robot with mimic joints, from a reference of the same robot whose
    every joint has its own coordinate (``full``: a :class:`PinocchioReference` or a
    :class:`UrdfReference`, both built with every link's joint free): the mimic's position is
    ``multiplier * q_leader + offset`` and its rate ``G v`` (G: NV_links x NV, a 1 for each
    joint's own coordinate, the multiplier for a mimic's leader), so that the dynamics of the
    coordinates are the projections ``M = G^T M_full G``, ``tau = G^T tau_full(q_full, G v, G a)``
    (the principle of virtual work), the Jacobians ``J_full G``, and forward dynamics and the
    inverse mass matrix solve with ``G^T (M_full + armature) G``.  Pinocchio's own mimic joints
    (``mimic=True``) do not run ``aba`` or the derivatives, and its ``computeCoriolisMatrix``
    with them gives a C with ``C v`` different from ``nonLinearEffects - g`` (Pinocchio 4.1, the
    Panda's hand: 1.9e-2 N): hence this projection of the full model, which every algorithm
    supports."""

    def __init__(self, full, robot: Robot):
        self.full = full
        self.floating = robot.floating
        self.configuration_layout = (robot.floating, robot.dof)
        base = 6 if robot.floating else 0
        order = getattr(full, "order", None) or list(range(len(robot.links)))  # the full model's joints
        self.G = np.zeros((base + len(robot.links), base + robot.dof))
        self.G[:base, :base] = np.eye(base)
        self.offset = np.zeros(len(robot.links))
        for row, i in enumerate(order):
            k, m = robot.link_coordinates[i]
            self.G[base + row, base + k] = float(m)
            link = robot.links[i]
            self.offset[row] = 0.0 if link.mimic is None else float(link.mimic.offset)
        self.base = base
        self._rate_scale = max(1.0, float(np.max(np.abs(self.G))))

    def _q(self, q):
        q = np.asarray(q, dtype=float)
        head = 7 if self.floating else 0
        joints = self.G[self.base:, self.base:] @ q[head:] + self.offset
        return np.concatenate([q[:head], joints])

    def _v(self, v):
        return self.G @ np.asarray(v, dtype=float)

    def _both(self, matrix):
        return self.G.T @ matrix @ self.G

    def mass_matrix(self, q):
        return self._both(self.full.mass_matrix(self._q(q)))

    def system_matrix(self, q):
        """G^T (M_full + diag(armature)) G."""
        return self._both(self.full.mass_matrix(self._q(q)) + np.diag(self.full.armature))

    def gravity(self, q):
        return self.G.T @ self.full.gravity(self._q(q))

    def coriolis(self, q, qd):
        return self.G.T @ self.full.coriolis(self._q(q), self._v(qd))

    def coriolis_matrix(self, q, qd):
        return self._both(self.full.coriolis_matrix(self._q(q), self._v(qd)))

    def kinetic_energy(self, q, qd):
        return self.full.kinetic_energy(self._q(q), self._v(qd))

    def inverse_dynamics(self, q, qd, qdd):
        return self.G.T @ self.full.inverse_dynamics(self._q(q), self._v(qd), self._v(qdd))

    def forward_dynamics(self, q, qd, tau):
        bias = self.inverse_dynamics(q, qd, np.zeros(len(qd)))  # h + c + friction
        return np.linalg.solve(self.system_matrix(q), np.asarray(tau, dtype=float) - bias)

    def inverse_dynamics_dq(self, q, qd, qdd):
        return self._both(self.full.inverse_dynamics_dq(self._q(q), self._v(qd), self._v(qdd)))

    def inverse_dynamics_dqd(self, q, qd, qdd):
        return self._both(self.full.inverse_dynamics_dqd(self._q(q), self._v(qd), self._v(qdd)))

    def gravity_derivative(self, q):
        return self._both(self.full.gravity_derivative(self._q(q)))

    def mass_matrix_inverse(self, q):
        return np.linalg.inv(self.system_matrix(q))

    def _forward_derivative(self, inverse_derivative, q, qd, tau):
        """-M^-1 d tau/dx at the accelerations forward dynamics gives (the implicit function theorem)."""
        qdd = self.forward_dynamics(q, qd, tau)
        return -np.linalg.solve(self.system_matrix(q), inverse_derivative(q, qd, qdd))

    def forward_dynamics_dq(self, q, qd, tau):
        return self._forward_derivative(self.inverse_dynamics_dq, q, qd, tau)

    def forward_dynamics_dqd(self, q, qd, tau):
        return self._forward_derivative(self.inverse_dynamics_dqd, q, qd, tau)

    def frame_poses(self, q):
        return self.full.frame_poses(self._q(q))

    def frame_jacobians(self, q):
        return self.full.frame_jacobians(self._q(q)) @ self.G

    def frame_jacobian_dot_v(self, q, qd):
        return self.full.frame_jacobian_dot_v(self._q(q), self._v(qd))

    def center_of_mass(self, q):
        return self.full.center_of_mass(self._q(q))

    def center_of_mass_jacobian(self, q):
        return self.full.center_of_mass_jacobian(self._q(q)) @ self.G

    def center_of_mass_bias(self, q, qd):
        return self.full.center_of_mass_bias(self._q(q), self._v(qd))

    def centroidal_momentum_matrix(self, q):
        return self.full.centroidal_momentum_matrix(self._q(q)) @ self.G

    def centroidal_bias(self, q, qd):
        return self.full.centroidal_bias(self._q(q), self._v(qd))


@dataclass(frozen=True)
class HeldContact:
    """A contact of the reference in numbers: its frame's index, kind and Baumgarte correction
    (``kp``, ``kd``; ``reference``: a point's 3 numbers, a sole's 6, or None)."""

    frame: int
    kind: str
    kp: float = 0.0
    kd: float = 0.0
    reference: tuple | None = None

    @property
    def axes(self) -> tuple[int, ...]:
        """The rows of the frame's Jacobian held (0-2 linear, 3-5 angular)."""
        from ..model.robot import CONTACT_AXES
        return CONTACT_AXES[self.kind]


def held_contacts(robot: Robot, values: Mapping | None = None) -> tuple:
    """The robot's contacts as :class:`HeldContact` s, ``values`` (symbol -> number)
    substituted for the runtime parameters their corrections name."""
    mapping = {sp.Symbol(k, real=True) if isinstance(k, str) else k: v for k, v in (values or {}).items()}
    mapping.update({s: v for s, v in zip(robot.parameters, robot.nominal) if v is not None and s not in mapping})

    def number(e) -> float:
        return float(sp.sympify(e).xreplace(mapping))
    return tuple(HeldContact(c.frame, c.kind, number(c.kp), number(c.kd),
                             None if c.reference is None else tuple(number(e) for e in c.reference))
                 for c in getattr(robot, "contacts", ()))


def reduced(reference, robot: Robot, values: Mapping | None = None):
    """``reference`` itself, or its :class:`MimicReduction` for a robot with mimic joints, or
    whose model takes the links in another order (a tree listed with a subtree in two pieces);
    ``values``: the runtime parameters' numbers (the contacts' corrections may name them)."""
    order = getattr(reference, "order", None)
    reordered = order is not None and list(order) != list(range(len(robot.links)))
    out = MimicReduction(reference, robot) if robot.mimics or reordered else reference
    out.contact_set = held_contacts(robot, values)
    out.unactuated = tuple(range(6 if robot.floating else 0))
    return out
