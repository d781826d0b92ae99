"""The scoop controller U: sense, plan from the depth image, scoop, transfer, dump, return.

Every motion is executed by the simulated arm (IK targets interpolated through the position
actuators while the physics runs); nothing is teleported. The plan uses only what perception
estimated from the wrist camera's depth image and the robot's own kinematics.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from vlb_gym.core.primitive import ControllerFailure

from . import gl
from .kinematics import IKFailure, rpy_matrix
from .motion import ArmDriver, tool_rotation
from .perception import Estimate, PerceptionFailure, depth_to_points, locate_containers
from .scene import (DONOR_HALF, DONOR_WALL, FLOOR, GRAIN_MASS, GRAIN_RADIUS, RECEIVER_HALF,
                    RECEIVER_WALL, Scene)
from .types import ScoopState

TIP = 0.045  # m from the scoop site (tray centre) to the tip along the tool axis
CAMERA_SIZE = (240, 320)  # depth image rows, columns
LIFT = 0.28  # m: scoop height while carrying (keeps the wrist camera clear of the walls)
DUMP = 0.13  # m: scoop height while pouring


class DepthCamera:
    """Depth images from the wrist camera, and the world points they show."""

    def __init__(self, scene: Scene):
        self.model = scene.model
        self.camera = scene.model.camera("wrist").id
        self.renderer = gl.renderer(scene.model, *CAMERA_SIZE)
        self.renderer.enable_depth_rendering()

    def depth(self, data: mujoco.MjData) -> np.ndarray:
        self.renderer.update_scene(data, camera=self.camera)
        return self.renderer.render().copy()

    def points(self, data: mujoco.MjData) -> np.ndarray:
        return depth_to_points(self.depth(data), self.model.cam_fovy[self.camera],
                               data.cam_xpos[self.camera],
                               data.cam_xmat[self.camera].reshape(3, 3))

    def close(self) -> None:
        self.renderer.close()


def grains_in_box(positions: np.ndarray, center: np.ndarray, half: float, top: float
                  ) -> np.ndarray:
    """Mask of grains inside a container's interior (centre x, y, yaw) below ``top``."""
    c, s = np.cos(center[2]), np.sin(center[2])
    rel = (positions[:, :2] - center[:2]) @ np.array([[c, -s], [s, c]])
    return np.all(np.abs(rel) < half, axis=1) & (positions[:, 2] < top + GRAIN_RADIUS)


def grains_in_scoop(positions: np.ndarray, data: mujoco.MjData, site: int) -> np.ndarray:
    """Mask of grains resting in the scoop's tray."""
    rel = (positions - data.site_xpos[site]) @ data.site_xmat[site].reshape(3, 3)
    return ((np.abs(rel[:, 1]) < 0.035) & (np.abs(rel[:, 2]) < TIP + 0.005)
            & (rel[:, 0] > -0.02) & (rel[:, 0] < 0.03))


@dataclass(frozen=True)
class Measured:
    """What a scoop did, in grams, plus the perception estimate it acted on."""

    scooped: float
    delivered: float
    spilled: float
    estimate: Estimate | None


def _heading(estimate: Estimate) -> float:
    """Drag direction: the donor side axis closest to the direction of the receiver."""
    to_receiver = estimate.receiver.center - estimate.donor.center
    target = np.arctan2(to_receiver[1], to_receiver[0])
    axes = estimate.donor.yaw + np.arange(4) * np.pi / 2
    return float(axes[np.argmin(np.abs(np.angle(np.exp(1j * (axes - target)))))])


def run_scoop(state: ScoopState, pose: np.ndarray, camera: DepthCamera) -> Measured:
    """Run the whole scoop from the sensing pose ``pose`` = (x, y, z, roll, pitch, yaw) of the
    flange. Raises ControllerFailure when it cannot go on (unreachable pose, perception failed)."""
    scene, data = state.scene, state.data
    driver = ArmDriver(scene, data, state.on_frame, state.frame_every)
    scoop_site = scene.model.site("scoop").id
    grains = lambda: data.qpos[scene.grain_qpos[:, :3]]  # noqa: E731
    try:
        sense_q = driver.flange.solve(pose[:3], rpy_matrix(*pose[3:]), driver.q)
    except IKFailure as exc:
        raise ControllerFailure(f"sensing pose unreachable: {exc}") from None
    driver.move_joints(sense_q, 1.2)
    driver.settle(0.2)
    try:
        estimate = locate_containers(camera.points(data))
    except PerceptionFailure as exc:
        raise ControllerFailure(f"perception: {exc}") from None
    heading = _heading(estimate)
    h = np.array([np.cos(heading), np.sin(heading), 0.0])
    bed_top = max(estimate.bed_height + GRAIN_RADIUS, FLOOR + 2 * GRAIN_RADIUS)
    tip_z = max(bed_top - 0.018, FLOOR + 0.008)
    centre = np.array([*estimate.donor.center, 0.0])
    start, end = centre - 0.015 * h, centre + 0.035 * h

    def tip(point: np.ndarray, pitch_deg: float) -> tuple[np.ndarray, np.ndarray]:
        rot = tool_rotation(heading, np.radians(pitch_deg))
        return point - TIP * rot[:, 2], rot

    def site(point: np.ndarray, pitch_deg: float) -> tuple[np.ndarray, np.ndarray]:
        return point, tool_rotation(heading, np.radians(pitch_deg))

    above_receiver = np.array([*estimate.receiver.center, 0.0]) - 0.035 * h
    try:
        driver.move_scoop([tip(start + [0, 0, bed_top + 0.06], 60)], 0.8)
        driver.move_scoop([tip(start + [0, 0, tip_z], 60)], 0.5)
        driver.move_scoop([tip(start + f * (end - start) + [0, 0, tip_z], 60 - 30 * f)
                           for f in np.linspace(0.125, 1, 8)], 0.9)
        driver.move_scoop([tip(end + [0, 0, tip_z + 0.025 * f], 30 - 30 * f)
                           for f in np.linspace(0.2, 1, 5)], 0.6)
        driver.move_scoop([tip(end + [0, 0, tip_z + 0.025 + 0.06 * f], -15 * f)
                           for f in np.linspace(0.25, 1, 4)], 0.5)
        lifted = data.site_xpos[scoop_site].copy()
        driver.move_scoop([site(lifted * [1, 1, 0] + [0, 0, LIFT], -15)], 0.6)
        scooped = int(grains_in_scoop(grains(), data, scoop_site).sum())
        driver.move_scoop([site(lifted * (1 - f) * [1, 1, 0] + above_receiver * f
                                + [0, 0, LIFT - 0.04 * f], -15)
                           for f in np.linspace(0.1, 1, 10)], 1.0)
        driver.move_scoop([site(above_receiver + [0, 0, DUMP], -15)], 0.5)
        driver.move_scoop([site(above_receiver + [0, 0, DUMP], a)
                           for a in np.linspace(-15, 100, 12)[1:]], 1.4)
        driver.settle(0.4)
        driver.move_scoop([site(above_receiver + [0, 0, DUMP + 0.12 * f], 100 - 115 * f)
                           for f in np.linspace(0.2, 1, 5)], 0.8)
    except IKFailure as exc:
        raise ControllerFailure(f"scoop motion unreachable: {exc}") from None
    driver.move_joints(sense_q, 1.0)
    driver.settle(0.3)
    env = state.env
    positions = grains()
    delivered = grains_in_box(positions, env.receiver, RECEIVER_HALF, RECEIVER_WALL)
    kept = grains_in_box(positions, env.donor, DONOR_HALF, DONOR_WALL)
    in_scoop = grains_in_scoop(positions, data, scoop_site)
    return Measured(scooped * GRAIN_MASS * 1000, float(delivered.sum()) * GRAIN_MASS * 1000,
                    float((~(delivered | kept | in_scoop)).sum()) * GRAIN_MASS * 1000, estimate)
