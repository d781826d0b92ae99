"""Flattening ``MultiDiscrete`` actions to ``Discrete`` (for DQN-style agents and action masking)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium import spaces


class FlatActions(gym.ActionWrapper):
    """``Discrete(prod(nvec))`` over a ``MultiDiscrete`` env, in C order; masks pass through."""

    def __init__(self, env: gym.Env):
        if not isinstance(env.action_space, spaces.MultiDiscrete):
            raise TypeError(f"FlatActions needs a MultiDiscrete action space, not "
                            f"{env.action_space}")
        super().__init__(env)
        self.nvec = tuple(int(n) for n in env.action_space.nvec)
        self.action_space = spaces.Discrete(int(np.prod(self.nvec)))

    def action(self, action: int) -> np.ndarray:
        return np.array(np.unravel_index(int(action), self.nvec), dtype=np.int64)

    def action_masks(self) -> np.ndarray:
        return self.env.unwrapped.action_masks()
