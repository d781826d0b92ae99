"""Sampling d: container placements around set-points and a settled pile (the distribution pi).

Container x and y: set-point plus Gaussian noise (``placement_noise`` m, default 0.02), yaw: Gaussian
(``yaw_noise_deg``, default 8 deg), each truncated at 2.5 standard deviations and independent.
Sand: grain count uniform over the shipped levels (230, 260, 290 grains, 0.52-0.66 kg), pile style
uniform over flat / tilted / heaped, and one of two settled variants of each.
"""

from __future__ import annotations

import mujoco
import numpy as np

from . import piles
from .scene import Scene, yaw_quat
from .types import PILE_STYLES, Environment

DONOR_SETPOINT = np.array([0.5, -0.2, 0.0])
RECEIVER_SETPOINT = np.array([0.5, 0.2, 0.0])
TRUNCATE = 2.5


def _noisy(rng: np.random.Generator, setpoint: np.ndarray, xy: float, yaw_deg: float
           ) -> np.ndarray:
    scale = np.array([xy, xy, np.radians(yaw_deg)])
    return setpoint + np.clip(rng.normal(0.0, 1.0, 3), -TRUNCATE, TRUNCATE) * scale


def sample_environment(rng: np.random.Generator, grain_counts: tuple[int, ...],
                       placement_noise: float, yaw_noise_deg: float) -> Environment:
    return Environment(
        donor=_noisy(rng, DONOR_SETPOINT, placement_noise, yaw_noise_deg),
        receiver=_noisy(rng, RECEIVER_SETPOINT, placement_noise, yaw_noise_deg),
        n_grains=int(rng.choice(grain_counts)),
        pile_style=str(rng.choice(PILE_STYLES)),
        pile_variant=int(rng.integers(piles.VARIANTS)))


def place(scene: Scene, data: mujoco.MjData, env: Environment, arm_q: np.ndarray) -> None:
    """Put the containers (into ``scene``'s model: see :meth:`Scene.own_copy`), the settled pile
    (moved rigidly with the donor) and the arm at rest; every grain starts awake."""
    scene.place_container(scene.donor_body, *env.donor)
    scene.place_container(scene.receiver_body, *env.receiver)
    mujoco.mj_resetData(scene.model, data)
    pile = piles.pile(env.pile_style, env.n_grains, env.pile_variant)
    c, s = np.cos(env.donor[2]), np.sin(env.donor[2])
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    data.qpos[scene.grain_qpos[:, :3]] = pile[:, :3] @ rot.T + [env.donor[0], env.donor[1], 0.0]
    turned = np.empty(4)
    yaw = yaw_quat(env.donor[2])
    for k, quat in enumerate(pile[:, 3:]):
        mujoco.mju_mulQuat(turned, yaw, quat)
        data.qpos[scene.grain_qpos[k, 3:]] = turned
    data.qpos[scene.arm_qpos] = arm_q
    data.ctrl[:6] = arm_q
    mujoco.mj_forward(scene.model, data)
