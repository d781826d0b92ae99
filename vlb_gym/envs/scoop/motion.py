"""Executing arm motions in the running simulation through the joints' position actuators."""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import numpy as np

from .kinematics import Kinematics, smoothstep
from .scene import Scene


def tool_rotation(heading: float, pitch: float) -> np.ndarray:
    """Scoop orientation: tool axis (handle -> tip) pointing along ``heading`` (rad, in the
    plane) and ``pitch`` below the horizontal; the tray's opening faces up at pitch 0."""
    h = np.array([np.cos(heading), np.sin(heading), 0.0])
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cos(pitch) * h - np.sin(pitch) * z
    opening = np.sin(pitch) * h + np.cos(pitch) * z
    return np.column_stack([opening, np.cross(axis, opening), axis])


class ArmDriver:
    """Moves the arm by interpolating actuator set-points while stepping the physics."""

    def __init__(self, scene: Scene, data: mujoco.MjData,
                 on_frame: Callable[[], None] | None = None, frame_every: int = 0):
        self.scene, self.data = scene, data
        self.model = scene.model
        self.scoop = Kinematics(scene, "scoop")
        self.flange = Kinematics(scene, "flange")
        self.on_frame, self.frame_every = on_frame, frame_every
        self.steps = 0

    @property
    def q(self) -> np.ndarray:
        return self.data.qpos[self.scene.arm_qpos].copy()

    def step(self, n: int = 1) -> None:
        for _ in range(n):
            mujoco.mj_step(self.model, self.data)
            self.steps += 1
            if self.on_frame and self.frame_every and self.steps % self.frame_every == 0:
                self.on_frame()

    def move_joints(self, target: np.ndarray, seconds: float) -> None:
        """Smoothly move the set-points from where they are to ``target`` over ``seconds``."""
        start = self.data.ctrl[:6].copy()
        for s in smoothstep(max(1, int(round(seconds / self.model.opt.timestep)))):
            self.data.ctrl[:6] = start + s * (target - start)
            self.step()

    def settle(self, seconds: float) -> None:
        self.step(int(round(seconds / self.model.opt.timestep)))

    def move_scoop(self, path: list[tuple[np.ndarray, np.ndarray]], seconds: float) -> np.ndarray:
        """Follow scoop-site poses ``(pos, rot)`` in order, ``seconds`` in all; returns the last
        joint target. Raises IKFailure if a pose is out of reach."""
        seed = self.data.ctrl[:6].copy()
        targets = []
        for pos, rot in path:
            seed = self.scoop.solve(pos, rot, seed)
            targets.append(seed)
        for target in targets:
            self.move_joints(target, seconds / len(targets))
        return targets[-1]
