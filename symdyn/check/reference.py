"""High-precision reference dynamics: an independent recursive Newton-Euler in mpmath.

Nothing here uses symdyn's derivations, kinematics or expressions: the robot's numbers are read
from its description and the equations are evaluated with mpmath at ``digits`` significant
digits (50 by default) by a Newton-Euler recursion written in the *base* frame (symdyn's own is
written in the link frames), with moments about each link frame's origin:

- forward: for body i with frame origin P_i, joint axis z_i through the point p_i (world),
  revolute: ``omega_i = omega_{i-1} + z_i qd_i``,
  ``omegadot_i = omegadot_{i-1} + omega_{i-1} x z_i qd_i + z_i qdd_i``; the axis point is
  shared by both bodies, so ``a(P_i) = a(p_i) + omegadot_i x (P_i - p_i) + omega_i x (omega_i x
  (P_i - p_i))`` with ``a(p_i)`` from body i-1; prismatic: the angular terms are inherited and
  ``a(P_i)`` gains ``z_i qdd_i + 2 omega_{i-1} x z_i qd_i``;
- centre of mass ``a(c_i)``, ``F_i = m_i a(c_i)``, ``N_i = I_i^w omegadot_i + omega_i x
  (I_i^w omega_i)`` with ``I_i^w = R_i I_i R_i^T``; ``a(P_0) = -g``;
- backward: ``f_i = F_i + f_{i+1}``, ``n_i = N_i + (c_i - P_i) x F_i + n_{i+1} + (P_{i+1} - P_i)
  x f_{i+1}``; revolute ``tau_i = z_i . (n_i + (P_i - p_i) x f_i)``, prismatic ``z_i . f_i``.

D comes from unit accelerations, h from zero acceleration without gravity, C by polarization
(h is quadratic in qd, so ``C e_k = (h(qd + e_k) - h(qd - e_k)) / 4`` exactly), forward dynamics
by an LU solve at the same precision.  All results are returned as Python floats (numpy
arrays) in symdyn's notation (see :mod:`symdyn.derive.equations`).
"""

from __future__ import annotations

from typing import Mapping

import mpmath
import numpy as np
import sympy as sp

from ..model.robot import Robot


class MpReference:
    """Reference values of one robot (numbers substituted for its parameters with ``values``)."""

    def __init__(self, robot: Robot, values: Mapping | None = None, digits: int = 50):
        self.ctx = mpmath.mp.clone()
        self.ctx.dps = digits
        if values:
            robot = robot.substitute(values)
        robot = robot.with_nominal_values()
        if robot.parameters:
            names = ", ".join(s.name for s in robot.parameters)
            raise ValueError(f"give values for the parameters {names}")
        self.robot = robot
        self.n = robot.dof
        mpf = self._mpf
        self.links = []
        for link in robot.links:
            xx, yy, zz, xy, xz, yz = (mpf(c) for c in link.inertia)
            self.links.append({
                "revolute": link.is_revolute, "a": mpf(link.a), "alpha": mpf(link.alpha),
                "d": mpf(link.d), "theta": mpf(link.theta), "mass": mpf(link.mass),
                "com": self.ctx.matrix([mpf(c) for c in link.com]),
                "inertia": self.ctx.matrix([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]),
                "armature": mpf(link.armature), "damping": mpf(link.damping), "coulomb": mpf(link.coulomb),
                "origin": (None if link.origin is None else
                           self.ctx.matrix([[mpf(link.origin.matrix()[r, c]) for c in range(4)] for r in range(4)])),
                "axis": None if link.axis is None else self.ctx.matrix([mpf(c) for c in link.axis]),
                "fixed": (self.ctx.eye(4) if link.fixed is None else
                          self.ctx.matrix([[mpf(link.fixed[4 * r + c]) for c in range(4)] for r in range(4)])),
            })
        self.g_vector = self.ctx.matrix([mpf(g) for g in robot.base_gravity])
        self.base = self.ctx.matrix([[mpf(robot.base_matrix()[r, c]) for c in range(4)] for r in range(4)])
        self.tool = self.ctx.matrix([[mpf(robot.tool_matrix()[r, c]) for c in range(4)] for r in range(4)])

    def _mp(self, v):
        """An input number as mpf, exactly (floats and float32 convert without rounding)."""
        return v if isinstance(v, self.ctx.mpf) else self.ctx.mpf(float(v))

    def _mpf(self, value):
        return self.ctx.mpf(str(sp.N(sp.sympify(value), self.ctx.dps + 10)))

    # 4x4 homogeneous transforms in mpmath
    def _rot_z(self, angle):
        c, s = self.ctx.cos(angle), self.ctx.sin(angle)
        return self.ctx.matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])

    def _rot_x(self, angle):
        c, s = self.ctx.cos(angle), self.ctx.sin(angle)
        return self.ctx.matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])

    def _rotation(self, axis, angle):
        """Rotation by ``angle`` about the unit ``axis`` (Rodrigues), 4x4."""
        ctx = self.ctx
        c, s = ctx.cos(angle), ctx.sin(angle)
        x, y, z = axis[0], axis[1], axis[2]
        t = 1 - c
        return ctx.matrix([[c + x * x * t, x * y * t - z * s, x * z * t + y * s, 0],
                           [y * x * t + z * s, c + y * y * t, y * z * t - x * s, 0],
                           [z * x * t - y * s, z * y * t + x * s, c + z * z * t, 0],
                           [0, 0, 0, 1]])

    def _trans(self, x=0, y=0, z=0):
        return self.ctx.matrix([[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]])

    def _frames(self, q):
        """World poses of each joint frame (z = joint axis) and each link frame."""
        joints, links = [], []
        parents = self.robot.parent_indices
        for k, row in enumerate(self.links):
            current = self.ctx.eye(4) if parents[k] < 0 else links[parents[k]]
            angle = row["theta"] + (q[k] if row["revolute"] else 0)
            offset = row["d"] + (0 if row["revolute"] else q[k])
            current = current * row["fixed"]
            if self.robot.convention == "general":
                frame = current * row["origin"]
                axis = frame[0:3, 0:3] * row["axis"]
                if row["revolute"]:
                    link = frame * self._rotation(row["axis"], q[k])
                else:
                    link = frame * self._trans(*(row["axis"] * q[k]))
                joint = self.ctx.eye(4)  # only its axis (column 2) and point (column 3) are used
                for r in range(3):
                    joint[r, 2], joint[r, 3] = axis[r], frame[r, 3]
            elif self.robot.convention == "standard":
                joint = current * self._rot_z(angle) * self._trans(z=offset)
                link = joint * self._trans(x=row["a"]) * self._rot_x(row["alpha"])
            else:
                joint = current * self._rot_x(row["alpha"]) * self._trans(x=row["a"]) * self._rot_z(angle) * self._trans(z=offset)
                link = joint
            joints.append(joint)
            links.append(link)
        return joints, links

    @staticmethod
    def _col(T, c):
        return T[0:3, c]

    def _cross(self, a, b):
        return self.ctx.matrix([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])

    def _dot(self, a, b):
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

    def _motion(self, q, qd, qdd, gravity=True):
        """The forward pass: ``(joints, links, data, moving)`` with per link ``data`` (axis,
        axis point, origin, centre of mass from the origin, F = m a_c, N about the centre of
        mass) and ``moving`` (omega, omegad, the origin's acceleration, the origin), base axes."""
        ctx = self.ctx
        joints, links = self._frames(q)
        zero = ctx.matrix([0, 0, 0])
        base = (zero, zero, -self.g_vector if gravity else zero, zero)
        parents = self.robot.parent_indices
        cross = self._cross
        data, moving = [], []
        for k, row in enumerate(self.links):
            # the parent body's angular velocity and acceleration, and its origin's acceleration
            omega, omegad, accel, previous_origin = base if parents[k] < 0 else moving[parents[k]]
            z = self._col(joints[k], 2)
            axis_point = self._col(joints[k], 3)
            origin = self._col(links[k], 3)
            R = links[k][0:3, 0:3]
            if row["revolute"]:
                r = axis_point - previous_origin
                a_axis = accel + cross(omegad, r) + cross(omega, cross(omega, r))
                omega_new = omega + z * qd[k]
                omegad_new = omegad + cross(omega, z * qd[k]) + z * qdd[k]
                s = origin - axis_point
                accel_new = a_axis + cross(omegad_new, s) + cross(omega_new, cross(omega_new, s))
            else:
                r = origin - previous_origin
                accel_new = (accel + cross(omegad, r) + cross(omega, cross(omega, r))
                             + z * qdd[k] + 2 * cross(omega, z * qd[k]))
                omega_new, omegad_new = omega, omegad
            com = R * row["com"]  # from the link origin, world axes
            a_com = accel_new + cross(omegad_new, com) + cross(omega_new, cross(omega_new, com))
            inertia = R * row["inertia"] * R.T
            F = row["mass"] * a_com
            N = inertia * omegad_new + cross(omega_new, inertia * omega_new)
            data.append((z, axis_point, origin, com, F, N))
            moving.append((omega_new, omegad_new, accel_new, origin))
        return joints, links, data, moving

    def rigid(self, q, qd, qdd, gravity=True):
        """Joint forces of the rigid bodies (no armature, no friction), mpmath values."""
        ctx = self.ctx
        q, qd, qdd = ([self._mp(v) for v in x] for x in (q, qd, qdd))
        _, _, data, _ = self._motion(q, qd, qdd, gravity)
        cross = self._cross
        tau = [ctx.mpf(0)] * self.n
        wrench = [None] * self.n  # (force, moment about the link origin) each body gets from its joint
        for k in reversed(range(self.n)):
            z, axis_point, origin, com, F, N = data[k]
            force, moment = F, N + cross(com, F)
            for c in self.robot.children(k):  # what the bodies hanging on this one take from it
                force_c, moment_c = wrench[c]
                force = force + force_c
                moment = moment + moment_c + cross(data[c][2] - origin, force_c)
            if self.links[k]["revolute"]:
                tau[k] = self._dot(z, moment + cross(origin - axis_point, force))
            else:
                tau[k] = self._dot(z, force)
            wrench[k] = (force, moment)
        return tau

    def _friction(self, qd, qdd=None):
        out = []
        for k, row in enumerate(self.links):
            v = self._mp(qd[k])
            term = row["damping"] * v + row["coulomb"] * self.ctx.sign(v)
            if qdd is not None:
                term += row["armature"] * self._mp(qdd[k])
            out.append(term)
        return out

    @staticmethod
    def _floats(values):
        return np.array([float(v) for v in values])

    def inverse_dynamics(self, q, qd, qdd):
        rigid = self.rigid(q, qd, qdd)
        return self._floats([a + b for a, b in zip(rigid, self._friction(qd, qdd))])

    def _mass_matrix_mp(self, q):
        zero = [0.0] * self.n
        columns = []
        for j in range(self.n):
            unit = [1.0 if k == j else 0.0 for k in range(self.n)]
            columns.append(self.rigid(q, zero, unit, gravity=False))
        return self.ctx.matrix([[columns[j][i] for j in range(self.n)] for i in range(self.n)])

    def mass_matrix(self, q):
        D = self._mass_matrix_mp(q)
        return np.array([[float(D[i, j]) for j in range(self.n)] for i in range(self.n)])

    def gravity(self, q):
        zero = [0.0] * self.n
        return self._floats(self.rigid(q, zero, zero))

    def kinetic_energy(self, q, qd):
        """``sum_i 1/2 (m_i |v_ci|^2 + omega_i . I_i omega_i + armature_i qd_i^2)`` over the bodies
        and rotors (one entry, J): the forward pass at zero rates and accelerations ``qd`` without
        gravity gives each body's velocities in its acceleration slots (linear in qdd there)."""
        ctx, zero = self.ctx, [0.0] * self.n
        _, _, data, moving = self._motion([self._mp(v) for v in q], zero, [self._mp(v) for v in qd], gravity=False)
        energy = ctx.mpf(0)
        for row, (_, _, _, com, _, spin), (_, omega, velocity, _) in zip(self.links, data, moving):
            v_com = velocity + self._cross(omega, com)
            energy += (row["mass"] * self._dot(v_com, v_com) + self._dot(omega, spin)) / 2
        energy += sum(row["armature"] * self._mp(v) ** 2 for row, v in zip(self.links, qd)) / 2
        return self._floats([energy])

    def _central(self, function, point, j):
        """d function / d point_j by central differences at the reference's precision."""
        step = self.ctx.mpf(10) ** (-(self.ctx.dps * 2 // 5))
        up = [v + step if k == j else v for k, v in enumerate(point)]
        down = [v - step if k == j else v for k, v in enumerate(point)]
        return [(a - b) / (2 * step) for a, b in zip(function(up), function(down))]

    def _jacobian(self, function, point):
        """d function / d point (n x n floats: row i = output i, column j = point_j) by central
        differences at the reference's precision."""
        columns = [self._central(function, point, j) for j in range(self.n)]
        return np.array([[float(columns[j][i]) for j in range(self.n)] for i in range(self.n)])

    def inverse_dynamics_dq(self, q, qd, qdd):
        q, qd, qdd = ([self._mp(v) for v in x] for x in (q, qd, qdd))
        return self._jacobian(lambda x: self.rigid(x, qd, qdd), q)

    def inverse_dynamics_dqd(self, q, qd, qdd):
        q, qd, qdd = ([self._mp(v) for v in x] for x in (q, qd, qdd))
        damping = [float(row["damping"]) for row in self.links]
        return self._jacobian(lambda x: self.rigid(q, x, qdd), qd) + np.diag(damping)

    def gravity_derivative(self, q):
        """dc/dq by central differences at the reference's precision (step 1e-20 at 50 digits:
        the truncation error, about 1e-40, is far below double's resolution)."""
        zero = [self.ctx.mpf(0)] * self.n
        return self._jacobian(lambda x: self.rigid(x, zero, zero), [self._mp(v) for v in q])

    def coriolis(self, q, qd):
        return self._floats(self.rigid(q, qd, [0.0] * self.n, gravity=False))

    def coriolis_matrix(self, q, qd):
        n = self.n
        C = np.zeros((n, n))
        base = [self._mp(v) for v in qd]
        for k in range(n):
            plus = [v + (1 if j == k else 0) for j, v in enumerate(base)]
            minus = [v - (1 if j == k else 0) for j, v in enumerate(base)]
            hp = self.rigid(q, plus, [0.0] * n, gravity=False)
            hm = self.rigid(q, minus, [0.0] * n, gravity=False)
            for i in range(n):
                C[i, k] = float((hp[i] - hm[i]) / 4)
        return C

    def _mass_with_armature(self, q):
        M = self._mass_matrix_mp(q)
        for k in range(self.n):
            M[k, k] += self.links[k]["armature"]
        return M

    def _forward_mp(self, q, qd, tau):
        """qdd (mpmath values) solving M qdd = tau - bias - friction by LU at the reference's precision."""
        n = self.n
        bias = self.rigid(q, qd, [0.0] * n)
        friction = self._friction(qd)
        rhs = self.ctx.matrix([self._mp(tau[k]) - bias[k] - friction[k] for k in range(n)])
        return list(self.ctx.lu_solve(self._mass_with_armature(q), rhs))

    def forward_dynamics(self, q, qd, tau):
        return self._floats(self._forward_mp(q, qd, tau))

    def mass_matrix_inverse(self, q):
        Minv = self.ctx.inverse(self._mass_with_armature(q))
        return np.array([[float(Minv[i, j]) for j in range(self.n)] for i in range(self.n)])

    def forward_dynamics_dq(self, q, qd, tau):
        """dqdd/dq by central differences of forward dynamics at the reference's precision (not
        by the implicit function theorem symdyn's code uses)."""
        q, qd, tau = ([self._mp(v) for v in x] for x in (q, qd, tau))
        return self._jacobian(lambda x: self._forward_mp(x, qd, tau), q)

    def forward_dynamics_dqd(self, q, qd, tau):
        q, qd, tau = ([self._mp(v) for v in x] for x in (q, qd, tau))
        return self._jacobian(lambda x: self._forward_mp(q, x, tau), qd)

    # Kinematics of the tool frame, world axes (base placement * chain * tool)
    def _tool_pose(self, q):
        joints, links = self._frames([self._mp(v) for v in q])
        return joints, links, self.base * links[-1] * self.tool

    def forward_kinematics(self, q):
        pose = self._tool_pose(q)[2]
        return np.array([[float(pose[r, c]) for c in range(4)] for r in range(4)])

    def jacobian(self, q):
        joints, links, _ = self._tool_pose(q)
        Jv, Jw = self._point_jacobian(joints, self._col(links[-1] * self.tool, 3), self.n - 1)
        R = self.base[0:3, 0:3]
        return np.array([[float(x) for x in row] for row in (R * Jv).tolist() + (R * Jw).tolist()])

    def jacobian_dot_qd(self, q, qd):
        """Classical acceleration of the tool origin and angular acceleration at qdd = 0: the
        forward pass of velocities and accelerations in base axes, then rotated to the world."""
        return self._bias_of_points(q, qd, [(self.n - 1, self.tool)])

    def _bias_of_points(self, q, qd, points) -> np.ndarray:
        """J-dot qd of frames fixed in links (``points``: (link, 4x4 pose in its frame), link -1
        the base), stacked: each origin's classical acceleration and the angular acceleration at
        qdd = 0, world axes."""
        q, qd = [self._mp(v) for v in q], [self._mp(v) for v in qd]
        _, links, _, moving = self._motion(q, qd, [self.ctx.mpf(0)] * self.n, gravity=False)
        R, cross, out = self.base[0:3, 0:3], self._cross, []
        for link, local in points:
            if link < 0:  # fixed to the fixed base
                out.extend([0.0] * 6)
                continue
            omega, omegad, accel, origin = moving[link]
            r = self._col(links[link] * local, 3) - origin
            linear = accel + cross(omegad, r) + cross(omega, cross(omega, r))
            out.extend(self._floats(list(R * linear) + list(R * omegad)))
        return np.array(out)

    # Frames and the centre of mass (a fixed base: world = base placement * base frame)
    def _path(self, link: int) -> tuple:
        return ((link,) + self.robot.ancestors(link)) if link >= 0 else ()

    def _point_jacobian(self, joints, point, link: int):
        """(J_v, J_omega) of a point fixed in ``link``, base axes, 3 x n mpmath matrices each."""
        Jv, Jw = self.ctx.zeros(3, self.n), self.ctx.zeros(3, self.n)
        for j in self._path(link):
            z, axis_point = self._col(joints[j], 2), self._col(joints[j], 3)
            linear = self._cross(z, point - axis_point) if self.links[j]["revolute"] else z
            for r in range(3):
                Jv[r, j] = linear[r]
                Jw[r, j] = z[r] if self.links[j]["revolute"] else 0
        return Jv, Jw

    def _frame_matrix(self, frame):
        return self.ctx.matrix([[self._mpf(frame.matrix()[r, c]) for c in range(4)] for r in range(4)])

    def _frame_placements(self, q):
        joints, links = self._frames([self._mp(v) for v in q])
        return joints, [(links[f.link] if f.link >= 0 else self.ctx.eye(4)) * self._frame_matrix(f)
                        for f in self.robot.frames]

    def frame_poses(self, q):
        _, poses = self._frame_placements(q)
        return np.vstack([np.array([[float((self.base * T)[r, c]) for c in range(4)] for r in range(4)])
                          for T in poses])

    def frame_jacobians(self, q):
        joints, poses = self._frame_placements(q)
        R = self.base[0:3, 0:3]
        blocks = []
        for frame, T in zip(self.robot.frames, poses):
            Jv, Jw = self._point_jacobian(joints, self._col(T, 3), frame.link)
            blocks.append(np.array([[float(x) for x in row] for row in (R * Jv).tolist() + (R * Jw).tolist()]))
        return np.vstack(blocks)

    def frame_jacobian_dot_v(self, q, qd):
        return self._bias_of_points(q, qd, [(f.link, self._frame_matrix(f)) for f in self.robot.frames])

    def _mass_data(self, q):
        """(joints, per link (mass, centre of mass, inertia about it), total mass, centre of mass), base frame."""
        joints, links = self._frames([self._mp(v) for v in q])
        bodies = []
        for row, T in zip(self.links, links):
            R = T[0:3, 0:3]
            bodies.append((row["mass"], self._col(T, 3) + R * row["com"], R * row["inertia"] * R.T))
        total = sum((m for m, _, _ in bodies), self.ctx.mpf(0))
        com = sum((m * c for m, c, _ in bodies), self.ctx.matrix([0, 0, 0])) / total
        return joints, bodies, total, com

    def center_of_mass(self, q):
        _, _, _, com = self._mass_data(q)
        return self._floats(list(self.base[0:3, 0:3] * com + self._col(self.base, 3)))

    def _momentum_matrix(self, q):
        joints, bodies, total, com = self._mass_data(q)
        linear, angular = self.ctx.zeros(3, self.n), self.ctx.zeros(3, self.n)
        for k, (m, c, inertia) in enumerate(bodies):
            Jv, Jw = self._point_jacobian(joints, c, k)
            linear += m * Jv
            offset = c - com
            skew = self.ctx.matrix([[0, -offset[2], offset[1]], [offset[2], 0, -offset[0]], [-offset[1], offset[0], 0]])
            angular += inertia * Jw + m * skew * Jv
        R = self.base[0:3, 0:3]
        return R * linear, R * angular, total

    def center_of_mass_jacobian(self, q):
        linear, _, total = self._momentum_matrix(q)
        return np.array([[float(x / total) for x in row] for row in linear.tolist()])

    def centroidal_momentum_matrix(self, q):
        linear, angular, _ = self._momentum_matrix(q)
        return np.array([[float(x) for x in row] for row in linear.tolist() + angular.tolist()])

    def _momentum_rates(self, q, qd):
        q, qd = [self._mp(v) for v in q], [self._mp(v) for v in qd]
        _, _, data, _ = self._motion(q, qd, [self.ctx.mpf(0)] * self.n, gravity=False)
        _, bodies, total, com = self._mass_data(q)
        force, moment = self.ctx.matrix([0, 0, 0]), self.ctx.matrix([0, 0, 0])
        for (_, _, origin, offset, F, N) in data:
            force += F
            moment += N + self._cross(origin + offset - com, F)
        R = self.base[0:3, 0:3]
        return R * force, R * moment, total

    def center_of_mass_bias(self, q, qd):
        force, _, total = self._momentum_rates(q, qd)
        return self._floats(list(force / total))

    def centroidal_bias(self, q, qd):
        force, moment, _ = self._momentum_rates(q, qd)
        return self._floats(list(force) + list(moment))

    def condition_number(self, q) -> float:
        """2-norm condition number of D + diag(armature) at q."""
        D = self.mass_matrix(q) + np.diag([float(row["armature"]) for row in self.links])
        return float(np.linalg.cond(D))
