"""Types of the scooping world: the sampled environment d and the joint state (x, d)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np

from .scene import Scene

PILE_STYLES = ("flat", "tilted", "heaped")


@dataclass(frozen=True)
class Environment:
    """d: container poses (x, y, yaw in the robot base frame) and the pile in the donor."""

    donor: np.ndarray  # (3,) x, y, yaw
    receiver: np.ndarray  # (3,)
    n_grains: int
    pile_style: str
    pile_variant: int


@dataclass
class ScoopState:
    """The simulation (x: arm and grains, d: containers), and the env's filming hook."""

    scene: Scene
    data: mujoco.MjData
    env: Environment
    on_frame: Callable[[], None] | None = None  # called every ``frame_every`` physics steps
    frame_every: int = 0

    @property
    def flange_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Flange position and rotation matrix (the end-effector pose x)."""
        site = self.scene.model.site("flange").id
        return self.data.site_xpos[site].copy(), self.data.site_xmat[site].reshape(3, 3).copy()
