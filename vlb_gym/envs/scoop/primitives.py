"""The scoop primitive P^r of the paper's Sec. V-B."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from gymnasium import spaces

from vlb_gym.core.primitive import MotionPrimitive

from .controller import DepthCamera, grains_in_box, run_scoop
from .kinematics import IKFailure, Kinematics, angle_between, rpy_matrix
from .scene import (DONOR_OUTER, DONOR_WALL, GRAIN_MASS, RECEIVER_HALF, RECEIVER_OUTER,
                    RECEIVER_WALL)
from .types import ScoopState

POSITION_TOL = 0.01  # m: radius of the terminal ball around the sensing position
ORIENTATION_TOL = np.radians(3.0)  # rad: and around the sensing orientation
IMAGE_MARGIN = 0.03  # fraction of the image a container corner must stay inside
POSE_LOW = np.array([-1.0, -1.0, 0.0, -np.pi, -np.pi, -np.pi], dtype=np.float32)
POSE_HIGH = np.array([1.0, 1.0, 1.2, np.pi, np.pi, np.pi], dtype=np.float32)


def container_corners(pose: np.ndarray, half: float, top: float) -> np.ndarray:
    """The 8 outer corners of a container at (x, y, yaw)."""
    c, s = np.cos(pose[2]), np.sin(pose[2])
    out = []
    for dx in (-half, half):
        for dy in (-half, half):
            for z in (0.0, top):
                out.append([pose[0] + c * dx - s * dy, pose[1] + s * dx + c * dy, z])
    return np.array(out)


@dataclass(frozen=True)
class ScoopRegion:
    """R(xi, d): the flange back within a ball around xi, and at least ``threshold_g`` delivered."""

    pose: np.ndarray
    threshold_g: float

    def violations(self, state: ScoopState) -> dict[str, str]:
        """Which parts of the region the state misses: ``pose`` and/or ``delivered`` (the mass of
        the grains in the receiver now)."""
        pos, rot = state.flange_pose
        out = {}
        distance = float(np.linalg.norm(pos - self.pose[:3]))
        angle = angle_between(rot, rpy_matrix(*self.pose[3:]))
        if distance > POSITION_TOL or angle > ORIENTATION_TOL:
            out["pose"] = (f"end pose off by {distance * 1000:.1f} mm and "
                           f"{np.degrees(angle):.1f} deg")
        delivered = delivered_mass(state)
        if delivered < self.threshold_g:
            out["delivered"] = f"delivered {delivered:.1f} g < {self.threshold_g:g} g"
        return out


def delivered_mass(state: ScoopState) -> float:
    """Grams of sand in the receiver."""
    grains = state.data.qpos[state.scene.grain_qpos[:, :3]]
    inside = grains_in_box(grains, state.env.receiver, RECEIVER_HALF, RECEIVER_WALL)
    return float(inside.sum()) * GRAIN_MASS * 1000


class Scoop(MotionPrimitive[ScoopState]):
    """Move to the sensing pose, locate the containers in a depth image, scoop, dump, return."""

    name = "scoop"
    region_parts = ("pose", "delivered")

    def __init__(self, threshold_g: float):
        self.param_space = spaces.Box(POSE_LOW, POSE_HIGH, dtype=np.float32)
        self.threshold_g = threshold_g
        self.description = (
            "Scooping: from the sensing pose (flange x, y, z in m and roll, pitch, yaw in rad, "
            "robot base frame) the wrist depth camera locates the donor and receiver; the arm "
            "scoops granular media from the donor, dumps it into the receiver and returns to the "
            "sensing pose. Admissible when the pose is reachable and both containers are in the "
            "camera's view.")
        self._kinematics: dict[int, Kinematics] = {}
        self._cameras: dict[int, DepthCamera] = {}

    def kinematics(self, state: ScoopState) -> Kinematics:
        key = id(state.scene)
        if key not in self._kinematics:
            self._kinematics[key] = Kinematics(state.scene, "flange")
        return self._kinematics[key]

    def camera(self, state: ScoopState) -> DepthCamera:
        key = id(state.scene)
        if key not in self._cameras:
            self._cameras[key] = DepthCamera(state.scene)
        return self._cameras[key]

    def inadmissible_reason(self, state: ScoopState, param: Any) -> str | None:
        """None if the pose is in A(x, d), else the reason (judged with the true d)."""
        pose = np.asarray(param, dtype=float)
        kin = self.kinematics(state)
        try:
            q = kin.solve(pose[:3], rpy_matrix(*pose[3:]), state.data.qpos[state.scene.arm_qpos])
        except IKFailure as exc:
            return f"not reachable: {exc}"
        model, data = state.scene.model, kin.data
        kin.forward(q)
        mujoco.mj_camlight(model, data)
        cam = model.camera("wrist").id
        height, width = 240, 320
        focal = 0.5 * height / np.tan(np.radians(model.cam_fovy[cam]) / 2)
        for name, pose_d, half, top in (("donor", state.env.donor, DONOR_OUTER, DONOR_WALL),
                                        ("receiver", state.env.receiver, RECEIVER_OUTER,
                                         RECEIVER_WALL)):
            local = (container_corners(pose_d, half, top) - data.cam_xpos[cam]) \
                @ data.cam_xmat[cam].reshape(3, 3)
            depth = -local[:, 2]
            if np.any(depth <= 0.05):
                return f"the {name} is behind the camera"
            u = local[:, 0] * focal / depth / width + 0.5
            v = -local[:, 1] * focal / depth / height + 0.5
            if np.any((u < IMAGE_MARGIN) | (u > 1 - IMAGE_MARGIN) | (v < IMAGE_MARGIN)
                      | (v > 1 - IMAGE_MARGIN)):
                return f"the {name} is not fully in the camera's view"
        return None

    def admissible(self, state: ScoopState, param: Any) -> bool:
        return self.inadmissible_reason(state, param) is None

    def terminal_region(self, state: ScoopState, param: np.ndarray) -> ScoopRegion:
        return ScoopRegion(np.asarray(param, dtype=float), self.threshold_g)

    def run(self, state: ScoopState, param: Any, rng: np.random.Generator) -> dict[str, Any]:
        started = state.data.time
        measured = run_scoop(state, np.asarray(param, dtype=float), self.camera(state))
        details: dict[str, Any] = {"mass_scooped": measured.scooped,
                                   "mass_delivered": measured.delivered,
                                   "mass_spilled": measured.spilled}
        if measured.estimate is not None:
            est = measured.estimate
            details["perceived"] = {
                "donor": [*est.donor.center.round(4).tolist(), round(float(est.donor.yaw), 4)],
                "receiver": [*est.receiver.center.round(4).tolist(),
                             round(float(est.receiver.yaw), 4)],
                "bed_height": round(est.bed_height, 4)}
        details["sim_seconds"] = round(state.data.time - started, 3)
        return details

    def close(self) -> None:
        for camera in self._cameras.values():
            camera.close()
        self._cameras.clear()
