"""Pinocchio's closed-loop values of every function a platform robot's generated C provides, and
the status each returns (``symdyn verify`` and ``symdyn bench`` of ``kind: parallel`` files).

The model is :func:`symdyn.check.pinocchio_model.build_closed_loop_model`: the platform a
free-flying body, each leg a chain of Pinocchio joints from the world, one 6D loop closure per
leg.  Everything here comes from Pinocchio's algorithms on that model, nothing from symdyn's
platform derivation:

- the legs' joint positions: Gauss-Newton on each closure's placement error (``log6``, the leg's
  joint Jacobian), followed from the home configuration (the branch the generated code takes) to
  the pose in small steps;
- rates and accelerations: the closures' relative spatial acceleration
  (:func:`~symdyn.check.pinocchio_model.closure_accelerations`, exact and affine in the tree's
  accelerations) gives the constraint Jacobian Jc; each leg's joint rates and accelerations solve
  its 6x6 block given the platform's;
- ``K`` (q_dot = K t) from those rates, ``T = K^-1``, ``L_J``; the mass matrix in actuated
  coordinates ``G^T crba G`` with ``G`` the tree's velocity per unit actuated rate; inverse
  dynamics from ``rnea`` and the constraint Jacobian, forward dynamics from the constrained
  equations (:func:`~symdyn.check.pinocchio_model.pinocchio_inverse_dynamics`,
  :func:`~symdyn.check.pinocchio_model.pinocchio_forward_dynamics`).

Statuses (the generated functions' codes, :data:`symdyn.derive.parallel.STATUS`): UNREACHABLE
where the quaternion is zero or a closure cannot be solved; LEG_SINGULAR where a leg's block of
Jc is singular; SINGULAR where K is (inverse dynamics, M, T, L_J), for forward dynamics where the
platform's generalized inertia ``G_t^T crba G_t`` (twist coordinates) is; NOT_FINITE where a
result is not finite in the generated code's scalar type.  Singular means a reciprocal condition
number below the generated code's pivot tolerance for its precision.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..derive.parallel import FUNCTIONS, STATUS, home_pose
from ..derive.spatial import skew_numeric
from ..model.parallel import ParallelRobot
from ..model.tolerances import CLOSED_LOOP_CLOSURE, CLOSED_LOOP_UNREACHABLE, pivot_rtol
from .pinocchio_model import (build_closed_loop_model, closure_accelerations, free_flyer_twist_rate,
                              pinocchio_forward_dynamics, pinocchio_inverse_dynamics)

#: random platform states about the home pose: positions within this fraction of the legs' length
#: scale (the mean distance from the home pose's origin to the legs' bases), angles within TILT
REACH = 0.05
TILT = 0.1  # rad
#: ranges of the random twists (rad/s, m/s) and twist rates (rad/s^2, m/s^2)
TWIST, TWIST_RATE = 0.5, 1.0


class PlatformStatus(Exception):
    """A state at which a function returns a nonzero status: ``code`` (a name of
    :data:`~symdyn.derive.parallel.STATUS`), ``legs`` (the legs, from 0, that cause it)."""

    def __init__(self, code: str, legs=()):
        super().__init__(code)
        self.code, self.legs = code, tuple(legs)


@dataclass
class Kinematics:
    """The closed loop at one pose: the tree's configuration ``q``, the platform's rotation
    ``R``, Jc (closure rows leg by leg, the tree's velocities as columns), ``G`` (the tree's
    velocity per unit twist t, nv x 6), ``rates`` (each leg's joint rates per unit twist) and
    ``K`` (q_dot = K t)."""

    q: np.ndarray
    R: np.ndarray
    jc: np.ndarray
    G: np.ndarray
    rates: list
    K: np.ndarray


def rotation_of(quat) -> np.ndarray:
    """The rotation of a quaternion (x, y, z, w), normalized (PlatformStatus 'unreachable' for a
    zero or non-finite one)."""
    quat = np.asarray(quat, dtype=float)
    scale = float(np.sum(np.abs(quat)))
    if not (np.isfinite(scale) and scale > 0):
        raise PlatformStatus("unreachable")
    x, y, z, w = quat / scale
    s = 2 / (x * x + y * y + z * z + w * w)
    return np.array([[1 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w)],
                     [s * (x * y + z * w), 1 - s * (x * x + z * z), s * (y * z - x * w)],
                     [s * (x * z - y * w), s * (y * z + x * w), 1 - s * (x * x + y * y)]])


def pose_vector(p, R) -> np.ndarray:
    """``[p; quaternion (x, y, z, w)]`` (7), the generated functions' pose argument."""
    import pinocchio as pin
    return np.concatenate([np.asarray(p, dtype=float), pin.Quaternion(np.asarray(R, dtype=float)).coeffs()])


def rcond(matrix) -> float:
    """The reciprocal of the 2-norm condition number (0 for a singular or non-finite matrix)."""
    matrix = np.asarray(matrix, dtype=float)
    if not np.all(np.isfinite(matrix)):
        return 0.0
    sigma = np.linalg.svd(matrix, compute_uv=False)
    return float(sigma[-1] / sigma[0]) if sigma[0] > 0 else 0.0


def platform_states(position, reach: float, tilt: float, count: int, seed: int, rotation=None):
    """Seeded random platform states ``(p, R, twist, twist_rate)`` about the pose (``position``,
    ``rotation``, default level): p within ``reach`` (m) of it per axis, R turned by roll, pitch
    and yaw within ``tilt`` (rad), twists in [-0.5, 0.5], twist rates in [-1, 1]."""
    import pinocchio as pin
    rng = np.random.default_rng(seed)
    base = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
    for _ in range(count):
        p = np.asarray(position, dtype=float) + rng.uniform(-reach, reach, 3)
        R = pin.rpy.rpyToMatrix(*rng.uniform(-tilt, tilt, 3)) @ base
        yield p, R, rng.uniform(-TWIST, TWIST, 6), rng.uniform(-TWIST_RATE, TWIST_RATE, 6)


class ClosedLoopReference:
    """Pinocchio's values of a platform robot's generated functions (module docstring).  Each
    function takes the generated function's inputs (``pose`` 7, ``twist`` 6, ``twist_rate`` or
    ``phi`` 6) and returns ``(status, outputs...)`` as
    :class:`symdyn.check.cbuild.CompiledPlatform` does (zeros where the status is nonzero).
    ``precision`` of the code compared with: its pivot tolerance and the range of its scalar type
    decide SINGULAR and NOT_FINITE."""

    def __init__(self, robot: ParallelRobot, precision: str = "double"):
        import pinocchio as pin
        self.pin = pin
        if any(leg.home is None for leg in robot.legs):
            raise ValueError(f"{robot.source or robot.name}: the closed-loop reference starts from the legs' 'home'")
        self.robot = robot
        self.model, constraints, self.info = build_closed_loop_model(robot)
        self.data = self.model.createData()
        self.models, self.datas = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
        for cm in constraints:
            self.models.append(cm)
            self.datas.append(cm.createData())
        self.legs = self.info["legs"]
        self.attachments = [pin.SE3(np.array(leg.attachment.matrix(), dtype=float)) for leg in robot.legs]
        self.ends = [pin.SE3(leg["body"][:3, :3].copy(), leg["body"][:3, 3].copy()) for leg in self.legs]
        self.com = np.array([float(c) for c in robot.platform.com])
        self.actuated_v = [leg["actuated_v"] for leg in self.legs]
        self.revolute = np.array([leg.actuated_link.is_revolute for leg in robot.legs])
        self.rtol = pivot_rtol("float" if precision == "float" else "double")
        self.limit = float(np.finfo(np.float32 if precision == "float" else np.float64).max)
        home = np.array(home_pose(robot))
        self.home_position, self.home_rotation = home[:3], rotation_of(home[3:])
        self.home_q = pin.neutral(self.model)
        self.home_q[:7] = home
        for leg, info in zip(robot.legs, self.legs):
            self.home_q[info["q"]] = [float(v) for v in leg.home]
        bases = [np.array(leg.chain.base_matrix(), dtype=float)[:3, 3] for leg in robot.legs]
        #: the legs' length scale (m): the mean distance from the home pose's origin to their bases
        self.length = float(np.mean([np.linalg.norm(b - self.home_position) for b in bases])) or 1.0
        self._cache: tuple | None = None

    # states ------------------------------------------------------------------------------------
    def random_states(self, count: int, seed: int = 0):
        """Seeded states about the home pose (:func:`platform_states`, positions within
        :data:`REACH` of :attr:`length`, angles within :data:`TILT`)."""
        return platform_states(self.home_position, REACH * self.length, TILT, count, seed, self.home_rotation)

    # kinematics --------------------------------------------------------------------------------
    def _close_leg(self, q, k, target) -> float:
        """Solve leg k's closure in ``q`` (in place) for its end frame at ``target``; returns the
        remaining error (m per :attr:`length`, rad)."""
        pin, info = self.pin, self.legs[k]
        size, polished = np.inf, False
        for _ in range(60):
            pin.forwardKinematics(self.model, self.data, q)
            end = self.data.oMi[info["last"]] * self.ends[k]
            err = pin.log6(end.actInv(target)).vector
            size = max(float(np.abs(err[:3]).max()) / self.length, float(np.abs(err[3:]).max()))
            if not size > CLOSED_LOOP_CLOSURE:  # closed (NaN: not converging)
                if polished or size != size:
                    break
                polished = True  # one step more: Gauss-Newton converges quadratically, to rounding
            jac = pin.computeJointJacobian(self.model, self.data, q, info["last"])[:, info["v"]]
            step = np.linalg.lstsq(self.ends[k].inverse().toActionMatrix() @ jac, err, rcond=1e-13)[0]
            step *= min(1.0, 0.3 / max(float(np.abs(step).max()), 1e-300))  # at most 0.3 rad (m) a step
            q[info["q"]] += step
        return size

    def _close_loops(self, p, R, start, direct: bool = False):
        """The tree's configuration at platform pose (p, R), followed from ``start`` (a
        configuration, its platform pose included) in steps of at most a tenth of the length
        scale and 0.2 rad (``direct``: in one step); PlatformStatus 'unreachable' naming the legs
        that cannot close."""
        pin = self.pin
        q = start.copy()
        p0, R0 = q[:3].copy(), rotation_of(q[3:7])
        turn = pin.log3(R0.T @ R)
        steps = 1 if direct else int(np.ceil(max(np.linalg.norm(p - p0) / (0.1 * self.length),
                                                 np.linalg.norm(turn) / 0.2, 1.0)))
        for s in range(1, steps + 1):
            good = q.copy()
            p_s, R_s = (p, R) if s == steps else (p0 + (p - p0) * s / steps, R0 @ pin.exp3(turn * s / steps))
            q[:7] = pose_vector(p_s, R_s)
            pose = pin.SE3(R_s, p_s)
            sizes = [self._close_leg(q, k, pose * self.attachments[k]) for k in range(len(self.legs))]
            failed = [k for k, size in enumerate(sizes) if not size <= CLOSED_LOOP_UNREACHABLE]
            if failed and s < steps:  # a detour out of reach: try the pose itself from the last closed one
                return self._close_loops(p, R, good, direct=True)
            if failed:
                raise PlatformStatus("unreachable", failed)
        return q

    def kinematics(self, pose, start=None) -> Kinematics:
        """The closed loop at ``pose`` (followed from ``start``, default the home configuration);
        PlatformStatus 'unreachable' or 'leg_singular' (naming the legs) where it has none."""
        pose = np.asarray(pose, dtype=float)
        key = pose.tobytes()
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        R = rotation_of(pose[3:])
        if not np.all(np.isfinite(pose[:3])):
            raise PlatformStatus("unreachable")
        q = self._close_loops(pose[:3], R, self.home_q if start is None else start)
        nv = self.model.nv
        zero = np.zeros(nv)
        jc = np.column_stack([closure_accelerations(self.model, self.data, self.models, q, zero, unit)
                              for unit in np.eye(nv)])
        singular = [k for k, leg in enumerate(self.legs) if rcond(jc[6 * k:6 * k + 6][:, leg["v"]]) < self.rtol]
        if singular:
            raise PlatformStatus("leg_singular", singular)
        c = R @ self.com
        P = np.zeros((6, 6))  # the free flyer's LOCAL [v; w] per unit twist [omega; c_dot]
        P[:3, :3], P[:3, 3:], P[3:, :3] = R.T @ skew_numeric(c), R.T, R.T
        G = np.zeros((nv, 6))
        G[:6] = P
        rates = []
        for k, leg in enumerate(self.legs):
            block = jc[6 * k:6 * k + 6]
            rate = -np.linalg.solve(block[:, leg["v"]], block[:, :6] @ P)
            G[leg["v"]] = rate
            rates.append(rate)
        K = np.array([rate[self.robot.legs[k].actuated] for k, rate in enumerate(rates)])
        found = Kinematics(q, R, jc, G, rates, K)
        self._cache = (key, found)
        return found

    def tree_state(self, pose, twist, twist_rate=None):
        """Pinocchio's ``(q, v, a)`` of the tree at a platform state (``a`` None without
        ``twist_rate``): the legs' accelerations close the loops at the platform's."""
        kin = self.kinematics(pose)
        twist = np.asarray(twist, dtype=float)
        v = kin.G @ twist
        if twist_rate is None:
            return kin.q, v, None
        omega, rate = twist[:3], np.asarray(twist_rate, dtype=float)
        c = kin.R @ self.com
        a = np.zeros(self.model.nv)
        a_origin = rate[3:] - np.cross(rate[:3], c) - np.cross(omega, np.cross(omega, c))
        a[:3] = kin.R.T @ a_origin - np.cross(v[3:6], v[:3])
        a[3:6] = kin.R.T @ rate[:3]
        gamma = closure_accelerations(self.model, self.data, self.models, kin.q, v, a)
        for k, leg in enumerate(self.legs):
            a[leg["v"]] = -np.linalg.solve(kin.jc[6 * k:6 * k + 6][:, leg["v"]], gamma[6 * k:6 * k + 6])
        return kin.q, v, a

    def _twist_map(self, kin: Kinematics) -> np.ndarray:
        if rcond(kin.K) < self.rtol:
            raise PlatformStatus("singular")
        return np.linalg.inv(kin.K)

    def _mass(self, q) -> np.ndarray:
        M = self.pin.crba(self.model, self.data, q)
        return np.triu(M) + np.triu(M, 1).T

    # the generated functions -------------------------------------------------------------------
    def inverse_dynamics(self, pose, twist, twist_rate):
        return self._call("inverse_dynamics", pose, twist, twist_rate)

    def forward_dynamics(self, pose, twist, phi):
        return self._call("forward_dynamics", pose, twist, phi)

    def mass_matrix(self, pose):
        return self._call("mass_matrix", pose)

    def twist_map(self, pose):
        return self._call("twist_map", pose)

    def leg_rate_maps(self, pose):
        return self._call("leg_rate_maps", pose)

    def inverse_kinematics(self, pose, twist):
        return self._call("inverse_kinematics", pose, twist)

    def _call(self, name, *args):
        _, outputs, _ = FUNCTIONS[name]
        try:
            with np.errstate(all="ignore"):
                values = [np.asarray(x, dtype=float) for x in self._evaluate(name, *args)]
                if not all(np.all(np.isfinite(x)) and np.all(np.abs(x) <= self.limit) for x in values):
                    raise PlatformStatus("not_finite")
        except (PlatformStatus, np.linalg.LinAlgError) as status:
            code = status.code if isinstance(status, PlatformStatus) else "singular"  # an exactly singular solve
            return (STATUS[code], *[np.zeros((rows, cols)) if cols > 1 else np.zeros(rows) for _, rows, cols in outputs])
        return (0, *values)

    def _evaluate(self, name, pose, *rest):
        kin = self.kinematics(pose)
        if name == "twist_map":
            return [self._twist_map(kin)]
        if name == "leg_rate_maps":
            T = self._twist_map(kin)
            return [np.vstack([rate @ T for rate in kin.rates])]
        if name == "mass_matrix":
            G = kin.G @ self._twist_map(kin)
            return [G.T @ self._mass(kin.q) @ G]
        if name == "inverse_kinematics":
            angles = np.array([kin.q[leg["q"][robot_leg.actuated]] for leg, robot_leg in zip(self.legs, self.robot.legs)])
            angles = np.where(self.revolute, np.mod(angles + np.pi, 2 * np.pi) - np.pi, angles)
            return [angles, kin.K @ np.asarray(rest[0], dtype=float)]
        if name == "inverse_dynamics":
            self._twist_map(kin)  # SINGULAR where K is
            q, v, a = self.tree_state(pose, *rest)
            return [pinocchio_inverse_dynamics(self.model, self.data, self.models, self.datas, self.info, q, v, a)]
        twist, phi = (np.asarray(x, dtype=float) for x in rest)
        if rcond(kin.G.T @ self._mass(kin.q) @ kin.G) < self.rtol:
            raise PlatformStatus("singular")
        q, v, _ = self.tree_state(pose, twist)
        a = pinocchio_forward_dynamics(self.model, self.data, self.models, self.info, q, v, phi)
        return [free_flyer_twist_rate(kin.R, self.com, twist, a), a[self.actuated_v]]
