"""Checks every registered vlb-gym environment passes, in the style of dm_control's suite tests."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import vlb_gym

ENV_IDS = list(vlb_gym.ENV_IDS)
BUILTIN_SPACES = (gym.spaces.Box, gym.spaces.Discrete, gym.spaces.MultiDiscrete,
                  gym.spaces.MultiBinary, gym.spaces.Dict)


def rollout(env: gym.Env, seed: int, steps: int = 8):
    """Observations, rewards and infos under actions sampled from a seeded action space."""
    obs, info = env.reset(seed=seed)
    env.action_space.seed(seed)
    trace = [(obs, info)]
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        trace.append((obs, reward, terminated, truncated, info))
        if terminated or truncated:
            break
    return trace


def same(a, b) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return np.array_equal(a, b)
    return a == b


@pytest.mark.parametrize("env_id", ENV_IDS)
class TestEveryEnv:
    def test_registered_with_module_prefix(self, env_id):
        env = gym.make(f"vlb_gym:{env_id}")
        assert env.spec.id == env_id
        env.close()

    def test_check_env(self, env_id):
        # Nothing skipped. On VLB-Scoop-v0 check_env's random sensing poses are almost all
        # unreachable or blind, so few whole scoops run here; tests/test_scoop.py runs real ones.
        check_env(gym.make(env_id).unwrapped, skip_render_check=False)

    def test_builtin_spaces_and_metadata(self, env_id):
        env = gym.make(env_id)
        for space in (env.action_space, env.observation_space):
            assert isinstance(space, BUILTIN_SPACES)
        if isinstance(env.observation_space, gym.spaces.Dict):
            assert all(isinstance(s, BUILTIN_SPACES) for s in env.observation_space.values())
        assert "rgb_array" in env.metadata["render_modes"]
        assert env.metadata["render_fps"] > 0

    def test_deterministic_for_a_seed(self, env_id):
        a, b = gym.make(env_id), gym.make(env_id)
        assert same(rollout(a, 123), rollout(b, 123))
        assert not same(rollout(a, 1)[0], rollout(b, 2)[0])

    def test_step_info_contract(self, env_id):
        for step in rollout(gym.make(env_id), 7)[1:]:
            info = step[-1]
            assert {"primitive", "param", "admissible", "certificate"} <= info.keys()
            assert isinstance(info["admissible"], bool) and isinstance(info["certificate"], bool)
            if not info["admissible"]:
                assert info["certificate"] is False and info["reason"]

    def test_action_outside_space_raises(self, env_id):
        env = gym.make(env_id)
        env.reset(seed=0)
        bad = np.asarray(env.action_space.sample()) + 1000
        with pytest.raises(ValueError, match="not in the action space"):
            env.step(bad)

    def test_render_rgb_array(self, env_id):
        env = gym.make(env_id, render_mode="rgb_array")
        env.reset(seed=0)
        frame = env.render()
        assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
        assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 3  # a picture, not a blank

    def test_unknown_render_mode_rejected(self, env_id):
        with pytest.raises(ValueError, match="render_mode"):
            gym.make(env_id, render_mode="human-ish")

    @pytest.mark.parametrize("mode", ["sync", "async"])
    def test_make_vec(self, env_id, mode):
        envs = gym.make_vec(env_id, num_envs=2, vectorization_mode=mode)
        try:
            obs, _ = envs.reset(seed=5)
            envs.action_space.seed(5)
            obs2, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())
            assert envs.observation_space.contains(obs2)
            assert rewards.shape == (2,) and "certificate" in infos
        finally:
            envs.close()
