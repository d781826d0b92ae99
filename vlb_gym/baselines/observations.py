"""The label map as an image: an observation that fits grid tasks, for RL.

:class:`LabelImage` turns ``VLB-GridExplore-v0``'s observation (planar position and flat labels,
plus ``start`` and ``legs`` under the ``find_goal_and_oscillate`` task) into a
``(channels, size, size)`` uint8 image, 0 or 255 (SB3's image convention: its CNN policies scale
by 1/255): one channel per label (empty, obstacle, unexplored, goal), then the agent's cell, the
start cell, a full plane once a goal has been found and, with ``legs``, a plane at
255 x legs / LEGS and a full plane while heading home (an odd number of legs done: the policy is
memoryless, and the direction of travel is not legible from the progress plane's intensity).
Everything comes from the observation the wrapper is given (the start cell, under
``find_goal``, from the first observation of the episode, where the agent stands at reset);
nothing is read from the env's hidden state. :mod:`~.cnn` has the networks that read it.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from vlb_gym.envs.grid_explore.types import GOAL, Label, cell_of

from .tasks import LEGS

LABEL_CHANNELS = len(Label)
AGENT, START, GOAL_FOUND = LABEL_CHANNELS, LABEL_CHANNELS + 1, LABEL_CHANNELS + 2
LEGS_DONE, HEADING_HOME = GOAL_FOUND + 1, GOAL_FOUND + 2
FULL = 255


class LabelImager:
    """The image of each observation of one episode: :meth:`reset` with the episode's first
    observation (it fixes the start cell where no ``start`` key gives it), then call it on
    every observation. Shared by :class:`LabelImage` (training) and a trained agent's policy
    (verification), so both see the same pictures."""

    def __init__(self, space: spaces.Space):
        if not isinstance(space, spaces.Dict) or not {"position", "labels"} <= set(space.spaces):
            raise TypeError(f"a label image needs VLB-GridExplore-v0's observation (position "
                            f"and labels), not {space}")
        self.size = int(round(np.sqrt(len(space["labels"].nvec))))
        self.legs = "legs" in space.spaces
        self.space = spaces.Box(0, 255, (GOAL_FOUND + 1 + 2 * self.legs, self.size, self.size),
                                np.uint8)
        self.start: tuple[int, int] | None = None

    def reset(self, obs: dict[str, Any]) -> None:
        self.start = cell_of(obs["position"], self.size)

    def __call__(self, obs: dict[str, Any]) -> np.ndarray:
        if self.start is None:
            raise RuntimeError("LabelImager: reset() with the episode's first observation first")
        labels = np.asarray(obs["labels"]).reshape(self.size, self.size)
        image = np.zeros(self.space.shape, np.uint8)
        image[:LABEL_CHANNELS] = (labels == np.arange(LABEL_CHANNELS)[:, None, None]) * FULL
        image[(AGENT, *cell_of(obs["position"], self.size))] = FULL
        image[(START, *(tuple(obs["start"]) if "start" in obs else self.start))] = FULL
        image[GOAL_FOUND] = FULL * bool((labels == GOAL).any())
        if self.legs:
            legs = int(obs["legs"])
            image[LEGS_DONE] = round(FULL * legs / LEGS)
            image[HEADING_HOME] = FULL * (legs % 2)
        return image


class LabelImage(gym.ObservationWrapper, gym.utils.RecordConstructorArgs):
    """The label map as an image (see the module's docstring); wrap a ``VLB-GridExplore-v0``
    env, with or without a task, before any action wrapper."""

    def __init__(self, env: gym.Env):
        gym.utils.RecordConstructorArgs.__init__(self)
        super().__init__(env)
        self.imager = LabelImager(env.observation_space)
        self.observation_space = self.imager.space

    def reset(self, **kwargs: Any):
        obs, info = self.env.reset(**kwargs)
        self.imager.reset(obs)
        return self.observation(obs), info

    def observation(self, obs: dict[str, Any]) -> np.ndarray:
        return self.imager(obs)
