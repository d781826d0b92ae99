"""Arm kinematics and motion: damped-least-squares IK on a site, and joint-space moves executed
through the position actuators while the physics runs."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from .scene import Scene

IK_ITERATIONS = 200
IK_POS_TOL = 1e-3  # m
IK_ROT_TOL = 1e-2  # rad
IK_DAMPING = 0.02


class IKFailure(RuntimeError):
    """No joint configuration reaches the pose within tolerance (out of reach or at a limit)."""


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Rotation matrix of extrinsic x-y-z (roll, pitch, yaw) angles: Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr, cp, sp, cy, sy = (np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch),
                              np.cos(yaw), np.sin(yaw))
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def rotation_error(current: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Axis-angle vector (world frame) rotating ``current`` onto ``target``."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, (target @ current.T).ravel())
    velocity = np.empty(3)
    mujoco.mju_quat2Vel(velocity, quat, 1.0)
    return velocity


def angle_between(a: np.ndarray, b: np.ndarray) -> float:
    """The rotation angle (rad) between two rotation matrices."""
    return float(np.linalg.norm(rotation_error(a, b)))


@dataclass
class Kinematics:
    """IK for one site, on a scratch MjData so the simulation is untouched."""

    scene: Scene
    site: str

    def __post_init__(self) -> None:
        self.data = mujoco.MjData(self.scene.model)
        self.site_id = self.scene.model.site(self.site).id
        self.low = self.scene.model.jnt_range[:6, 0]
        self.high = self.scene.model.jnt_range[:6, 1]
        self._jacp = np.zeros((3, self.scene.model.nv))
        self._jacr = np.zeros((3, self.scene.model.nv))

    def forward(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Site position and rotation matrix at arm configuration ``q``."""
        self.data.qpos[self.scene.arm_qpos] = q
        mujoco.mj_kinematics(self.scene.model, self.data)
        return (self.data.site_xpos[self.site_id].copy(),
                self.data.site_xmat[self.site_id].reshape(3, 3).copy())

    def solve(self, pos: np.ndarray, rot: np.ndarray, seed: np.ndarray) -> np.ndarray:
        """Joint angles putting the site at ``pos`` with orientation ``rot``, near ``seed``."""
        q = np.array(seed, dtype=float)
        dof = self.scene.arm_dof
        for _ in range(IK_ITERATIONS):
            cur_pos, cur_rot = self.forward(q)
            err = np.concatenate([pos - cur_pos, rotation_error(cur_rot, rot)])
            if np.linalg.norm(err[:3]) < IK_POS_TOL and np.linalg.norm(err[3:]) < IK_ROT_TOL:
                return q
            mujoco.mj_comPos(self.scene.model, self.data)  # mj_jac needs the com-based dofs
            mujoco.mj_jacSite(self.scene.model, self.data, self._jacp, self._jacr, self.site_id)
            jac = np.vstack([self._jacp[:, dof], self._jacr[:, dof]])
            step = jac.T @ np.linalg.solve(jac @ jac.T + IK_DAMPING**2 * np.eye(6), err)
            scale = max(1.0, np.abs(step).max() / 0.3)  # at most 0.3 rad per iteration
            q = np.clip(q + step / scale, self.low, self.high)
        cur_pos, cur_rot = self.forward(q)
        raise IKFailure(f"pose {np.round(pos, 3).tolist()} not reached: position error "
                        f"{np.linalg.norm(pos - cur_pos) * 1000:.1f} mm, orientation error "
                        f"{np.degrees(angle_between(cur_rot, rot)):.1f} deg")


def smoothstep(n: int) -> np.ndarray:
    """``n`` fractions from 0 (excluded) to 1 with zero velocity at both ends."""
    s = np.arange(1, n + 1) / n
    return s * s * (3 - 2 * s)


def matrix_rpy(rot: np.ndarray) -> np.ndarray:
    """(roll, pitch, yaw) with ``rpy_matrix(*rpy) == rot`` (pitch in [-pi/2, pi/2])."""
    pitch = -np.arcsin(np.clip(rot[2, 0], -1.0, 1.0))
    roll = np.arctan2(rot[2, 1], rot[2, 2])
    yaw = np.arctan2(rot[1, 0], rot[0, 0])
    return np.array([roll, pitch, yaw])
