"""The floor of the comparison: a policy that draws a uniformly random admissible action.

With masks and a generous step bound, chance alone finishes some tasks: an agent's success
rate means something only next to this one's. Policy kind ``random`` (reference
``admissible``); it needs no torch.
"""

from __future__ import annotations

import hashlib
from typing import Any

import gymnasium as gym
import numpy as np

from vlb_gym.core.env import PrimitiveEnv

from .wrappers import admissible_actions

REFERENCE = "admissible"
STREAM = 0x52414E44  # spawn key of its draws, apart from the env's and a sampled agent's


class RandomAdmissible:
    """Uniform over the admissible actions of the env (the flat ``MultiDiscrete`` layout of
    :func:`~.wrappers.admissible_actions`), with a generator seeded from each episode's seed;
    it never finishes by itself."""

    def __init__(self, env: gym.Env):
        if not isinstance(env.unwrapped, PrimitiveEnv) or \
                not isinstance(env.action_space, gym.spaces.MultiDiscrete):
            raise ValueError("a random admissible policy needs a PrimitiveEnv with a "
                             "MultiDiscrete action space")
        self.env = env
        self.nvec = tuple(int(n) for n in env.action_space.nvec)
        self.rng = np.random.default_rng(STREAM)

    def reset(self, seed: int | None = None) -> None:
        self.rng = np.random.default_rng([STREAM, 0 if seed is None else seed])

    def predict(self, observation: Any, state: Any = None, episode_start: Any = None,
                deterministic: bool = True) -> tuple[np.ndarray, None]:
        choices = np.flatnonzero(admissible_actions(self.env.unwrapped))
        flat = int(choices[self.rng.integers(choices.size)])
        return np.array(np.unravel_index(flat, self.nvec), dtype=np.int64), None


class RandomLoader:
    """Policy kind ``random``: the only reference is ``admissible``."""

    runs_code = False
    replay_options = None  # vlb replay names behaviors and agents only

    def load(self, ref, env: gym.Env) -> RandomAdmissible:
        if ref.ref != REFERENCE:
            raise ValueError(f"unknown random policy {ref.ref!r}; the one there is: {REFERENCE}")
        return RandomAdmissible(env)

    def files(self, ref, policy: RandomAdmissible) -> list:
        return []

    def content(self, ref, policy: RandomAdmissible) -> dict[str, Any]:
        return {"sha256": hashlib.sha256(f"random:{REFERENCE}:{STREAM}".encode()).hexdigest()}

    def trained_env(self, ref) -> None:
        return None
