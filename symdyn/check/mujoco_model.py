"""MuJoCo's numbers for an MJCF robot, in symdyn's notation: an independent reading of the file
(MuJoCo defines the format) for ``symdyn verify``.

MuJoCo (the ``mujoco`` package, optional) compiles the file itself; its mass matrix
(``mj_fullM``, armature included) and bias forces (``qfrc_bias``) give symdyn's mass matrix, h,
c, inverse and forward dynamics, and its sites' poses the frame poses.  A free joint's
coordinates differ (MuJoCo's qpos has the quaternion w first, its qvel the base's linear velocity
in the world frame): with R the base's rotation and T = diag(R, I), MuJoCo's mass matrix is
T M Tᵀ and its bias, at MuJoCo's zero acceleration, T·ID(q, v, a) with a = (−ω × v_lin, 0, 0).
Everything else (derivatives, Jacobians, centroidal and task-space quantities) comes from the
Pinocchio model of symdyn's reading, as for a robot file; viscous and Coulomb friction are the
reading's.
"""

from __future__ import annotations

import contextlib
import os
import tempfile

import numpy as np

from .pinocchio_model import PinocchioReference, mirror_upper
from .quiet import stderr_silenced


class MujocoUnavailable(Exception):
    """MuJoCo cannot give the reference (not installed, or its compiler refuses the file); the
    message says why, in one line."""


@contextlib.contextmanager
def _in_scratch_folder():
    """Run in a scratch folder: MuJoCo writes its warnings to MUJOCO_LOG.TXT in the current one."""
    here = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="symdyn_mujoco_") as scratch:
        os.chdir(scratch)
        try:
            yield
        finally:
            os.chdir(here)


def compile_mjcf(path: str):
    """MuJoCo's compiled model of the MJCF at ``path`` (raises :class:`MujocoUnavailable`)."""
    try:
        import mujoco
    except ImportError:
        raise MujocoUnavailable("MuJoCo is not installed (pip install mujoco)") from None
    path = os.path.abspath(path)  # (before moving to the scratch folder)
    with _in_scratch_folder(), stderr_silenced():  # (its warnings: settotalmass is deprecated in MuJoCo 4)
        try:
            return mujoco.MjModel.from_xml_path(path)
        except ValueError as exc:  # (its message names the element and line)
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise MujocoUnavailable(f"MuJoCo's compiler refuses the file: {first[:200]}") from None


class MujocoReference(PinocchioReference):
    """symdyn's quantities of an MJCF robot, the dynamics from MuJoCo's compiled model of the file
    (see the module's documentation); ``robot`` is symdyn's reading of it."""

    def __init__(self, robot, path: str, values=None):
        super().__init__(robot, values)
        import mujoco
        self.mujoco = mujoco
        self.mj = compile_mjcf(path)
        self.mj_data = mujoco.MjData(self.mj)
        if self.mj.nv != self.model.nv:
            raise MujocoUnavailable(f"MuJoCo's model has {self.mj.nv} degrees of freedom, symdyn's reading "
                                    f"{self.model.nv}")
        armature = [getattr(self.mj, field, np.zeros(1)) for field in ("tendon_armature", "actuator_armature")]
        if any(np.any(np.asarray(a) != 0) for a in armature):
            raise MujocoUnavailable("the file has tendon or actuator armature, which MuJoCo adds to its mass "
                                    "matrix and symdyn does not model")
        # symdyn's frames: the named sites in MuJoCo's order, but for those of bodies welded to the
        # world under a floating base (not on the robot)
        self.sites = [k for k in range(self.mj.nsite) if mujoco.mj_id2name(self.mj, mujoco.mjtObj.mjOBJ_SITE, k)
                      and not (robot.floating and self.mj.body_weldid[self.mj.site_bodyid[k]] == 0)]
        self.frame_count = len(robot.frames)

    def _forward(self, q, qd):
        """MuJoCo's state at symdyn's (q, qd): mj_forward done; returns T (see the module)."""
        q, qd = np.asarray(q, dtype=float), np.asarray(qd, dtype=float)
        d, T = self.mj_data, np.eye(self.mj.nv)
        if self.configuration_layout[0]:  # a free joint
            R = self.pin.Quaternion(q[6], q[3], q[4], q[5]).normalized().toRotationMatrix()
            d.qpos[:] = np.concatenate([q[:3], [q[6]], q[3:6], q[7:]])
            d.qvel[:] = np.concatenate([R @ qd[:3], qd[3:]])
            T[:3, :3] = R
        else:
            d.qpos[:], d.qvel[:] = q, qd
        self.mujoco.mj_forward(self.mj, d)
        return T

    def _full_mass(self) -> np.ndarray:
        M = np.zeros((self.mj.nv, self.mj.nv))
        if hasattr(self.mj_data, "qM"):  # MuJoCo 3
            self.mujoco.mj_fullM(self.mj, M, self.mj_data.qM)
        else:  # MuJoCo 4
            self.mujoco.mj_fullM(self.mj, self.mj_data, M)
        return M

    def _terms(self, q, qd):
        """``(M with armature, h, c)`` in symdyn's coordinates, from MuJoCo."""
        T = self._forward(q, np.zeros(self.mj.nv))
        Tinv = np.linalg.inv(T)
        M = mirror_upper(Tinv @ self._full_mass() @ Tinv.T)
        c = Tinv @ self.mj_data.qfrc_bias
        T = self._forward(q, qd)
        bias = np.linalg.inv(T) @ self.mj_data.qfrc_bias
        if self.configuration_layout[0]:  # MuJoCo's zero acceleration is a = (-w x v_lin, 0, 0) in symdyn's
            a = np.zeros(self.mj.nv)
            qd = np.asarray(qd, dtype=float)
            a[:3] = -np.cross(qd[3:6], qd[:3])
            bias = bias - M @ a
        return M, bias - c, c

    def system_matrix(self, q):
        return self._terms(q, np.zeros(self.mj.nv))[0]

    def mass_matrix(self, q):
        return self.system_matrix(q) - np.diag(self.armature)

    def gravity(self, q):
        return self._terms(q, np.zeros(self.mj.nv))[2]

    def coriolis(self, q, qd):
        return self._terms(q, qd)[1]

    def inverse_dynamics(self, q, qd, qdd):
        M, h, c = self._terms(q, qd)
        return M @ np.asarray(qdd, dtype=float) + h + c + self.friction(qd)

    def forward_dynamics(self, q, qd, tau):
        M, h, c = self._terms(q, qd)
        return np.linalg.solve(M, np.asarray(tau, dtype=float) - self.friction(qd) - h - c)

    def frame_poses(self, q):
        """The sites' poses in the world from MuJoCo (symdyn's frames are the named sites, in
        order, then the bodies --frames adds, which Pinocchio's model gives)."""
        poses = super().frame_poses(q)
        self._forward(q, np.zeros(self.mj.nv))
        for k, site in enumerate(self.sites[:self.frame_count]):
            pose = np.eye(4)
            pose[:3, :3] = self.mj_data.site_xmat[site].reshape(3, 3)
            pose[:3, 3] = self.mj_data.site_xpos[site]
            poses[4 * k:4 * k + 4] = pose
        return poses
