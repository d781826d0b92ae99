"""Wrappers for RL: flattened actions and masks of admissible actions, for any PrimitiveEnv."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium import spaces


from vlb_gym.core.env import PrimitiveEnv


def admissible_actions(env: PrimitiveEnv) -> np.ndarray:
    """The admissible actions now, flat in C order over the ``MultiDiscrete`` action space (as
    :class:`FlatActions` numbers them): each primitive's own ``admissible_mask``, judged with the
    true state as admissibility is. Needs the base class's action layout."""
    masks = [primitive.admissible_mask(env.state).ravel() for primitive in env.primitive_order]
    mask = masks[0] if len(masks) == 1 else np.concatenate(masks)
    if not isinstance(env.action_space, spaces.MultiDiscrete) or \
            mask.size != int(np.prod(env.action_space.nvec)):
        raise TypeError(f"{type(env).__name__}: masks need PrimitiveEnv's MultiDiscrete action "
                        "layout")
    return mask


class ActionMasks(gym.Wrapper):
    """Adds ``action_masks()`` (sb3-contrib's MaskablePPO calls it): :func:`admissible_actions`
    of the env inside, flat in C order (put it outside :class:`FlatActions`)."""

    def action_masks(self) -> np.ndarray:
        return admissible_actions(self.env.unwrapped)


class FlatActions(gym.ActionWrapper):
    """``Discrete(prod(nvec))`` over a ``MultiDiscrete`` env, in C order."""

    def __init__(self, env: gym.Env):
        if not isinstance(env.action_space, spaces.MultiDiscrete):
            raise TypeError(f"FlatActions needs a MultiDiscrete action space, not "
                            f"{env.action_space}")
        super().__init__(env)
        self.nvec = tuple(int(n) for n in env.action_space.nvec)
        self.action_space = spaces.Discrete(int(np.prod(self.nvec)))

    def action(self, action: int) -> np.ndarray:
        return np.array(np.unravel_index(int(action), self.nvec), dtype=np.int64)
