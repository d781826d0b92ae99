"""Every environment whose entry point makes a :class:`PrimitiveEnv` passes the same checks, in
the shape of dm_control's suite tests.

The environments are found in Gymnasium's registry after ``import vlb_gym`` (``vlb_gym.ENV_IDS``)
and the import of the guide's example (``examples/integrator_env.py``), so an environment
registered later is covered without editing this file; so is every shipped behavior, run on the
environment its file names.
"""

from __future__ import annotations

import importlib
import inspect
import pickle
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.envs.registration import EnvSpec, load_env_creator
from gymnasium.utils.env_checker import check_env

import vlb_gym
from vlb_gym.core.env import PrimitiveEnv
from vlb_gym.core.helpers import Helpers, arity
from vlb_gym.core.library import BehaviorLibrary, load_behavior, shipped_behaviors
from vlb_gym.verify.episode import run_episode
from vlb_gym.wrappers import RobustnessWrapper

from .test_new_env_guide import EXAMPLE_BEHAVIOR, EXAMPLE_ID, import_example

import_example()  # registers VLB-Integrator-v0

BUILTIN_SPACES = (gym.spaces.Box, gym.spaces.Discrete, gym.spaces.MultiDiscrete,
                  gym.spaces.MultiBinary, gym.spaces.Dict)
EPISODES = {"VLB-Scoop-v0": 1}  # a scoop takes seconds; other envs run DEFAULT_EPISODES
DEFAULT_EPISODES = 3


def makes_primitive_env(spec: EnvSpec) -> bool:
    """Whether ``gym.make(spec.id)`` gives a PrimitiveEnv: its entry point is a PrimitiveEnv
    class, or a factory (made once here) that returns one. Gymnasium's own environments are not
    loaded (importing its MuJoCo envs first would pick MuJoCo's OpenGL backend before vlb-gym
    does); entry points that cannot load or make an env without arguments are not ours."""
    entry_point = spec.entry_point
    module = entry_point if isinstance(entry_point, str) else entry_point.__module__
    if module.partition(".")[0] == "gymnasium":
        return False
    try:
        creator = load_env_creator(entry_point) if isinstance(entry_point, str) else entry_point
        if inspect.isclass(creator):
            return issubclass(creator, PrimitiveEnv)
        env = gym.make(spec.id, disable_env_checker=True)
    except Exception:
        return False
    env.close()
    return isinstance(env.unwrapped, PrimitiveEnv)


#: the RL tasks (vlb_gym.RL_TASKS) are wrappers of an env, with the baselines' tests
ENV_IDS = sorted(env_id for env_id, spec in gym.registry.items() if makes_primitive_env(spec)
                 and env_id not in {task for task, _, _ in vlb_gym.RL_TASKS})


def behaviors() -> list[Any]:
    """(env id, behavior, episodes) for every shipped behavior and the guide's example."""
    library = BehaviorLibrary()
    runs = [(library.resolve_name(name)[0].env, name) for name in shipped_behaviors()]
    runs.append((EXAMPLE_ID, str(EXAMPLE_BEHAVIOR)))
    return [pytest.param(env_id, ref, EPISODES.get(env_id, DEFAULT_EPISODES),
                         id=f"{env_id}-{ref.rsplit('/', 1)[-1]}") for env_id, ref in runs]


BEHAVIORS = behaviors()


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


def inadmissible_action(env: PrimitiveEnv, seed: int = 0) -> tuple[np.ndarray, str]:
    """A sampled action whose parameter is not admissible now, and the reason."""
    env.action_space.seed(seed)
    for _ in range(500):
        action = env.action_space.sample()
        primitive, param = env.decode_action(action)
        reason = env.inadmissible_reason(primitive.name, param)
        if reason is not None:
            return action, reason
    raise AssertionError("500 sampled actions were all admissible")


def test_registry_holds_vlb_gym_envs_and_the_example():
    assert set(vlb_gym.ENV_IDS) | {EXAMPLE_ID} <= set(ENV_IDS)


def test_every_behavior_names_a_registered_env_and_every_env_has_one():
    named = [param.values[0] for param in BEHAVIORS]
    assert set(named) <= set(ENV_IDS)
    assert set(ENV_IDS) <= set(named), "ship a behavior for every environment"


@pytest.mark.parametrize("env_id", ENV_IDS)
class TestEveryEnv:
    def test_registered_with_module_prefix(self, env_id):
        entry_point = gym.spec(env_id).entry_point
        module = (entry_point.split(":")[0] if isinstance(entry_point, str)
                  else entry_point.__module__)
        env = gym.make(f"{'vlb_gym' if env_id in vlb_gym.ENV_IDS else module}:{env_id}")
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
        modes = env.metadata["render_modes"]
        assert set(modes) <= {"rgb_array", "depth_array"}
        assert not modes or "rgb_array" in modes  # an env that renders renders pictures
        assert env.metadata["render_fps"] > 0

    def test_primitive_env_contract(self, env_id):
        env = gym.make(env_id).unwrapped
        assert isinstance(env, PrimitiveEnv) and env.env_id == env_id
        assert list(env.primitives) == [p.name for p in env.primitive_order]
        assert all(env.primitives[p.name] is p for p in env.primitive_order)
        first = env.primitive_order[0].param_space
        if len(env.primitive_order) == 1:  # the action is the parameter
            assert env.action_space == first
        else:  # [primitive index, *parameter]
            nvec = [len(env.primitive_order), *np.asarray(first.nvec).ravel()]
            assert env.action_space == gym.spaces.MultiDiscrete(nvec)

    def test_preloaded_modules_import(self, env_id):
        """What a campaign imports before forking its workers exists (a forkserver would skip a
        missing one silently)."""
        for module in gym.make(env_id).unwrapped.preload:
            importlib.import_module(module)

    def test_action_encoding_round_trips(self, env_id):
        env = gym.make(env_id).unwrapped
        env.action_space.seed(0)
        for _ in range(50):
            action = env.action_space.sample()
            primitive, param = env.decode_action(action)
            assert isinstance(param, tuple)
            assert all(type(v) in (int, float) for v in param)  # plain Python numbers
            again = env.encode_action(primitive.name, param)
            assert again.dtype == action.dtype and np.array_equal(again, action)

    def test_state_before_reset_raises(self, env_id):
        env = gym.make(env_id).unwrapped
        with pytest.raises(RuntimeError, match="reset"):
            _ = env.state
        with pytest.raises(RuntimeError, match="reset"):
            env.step(env.action_space.sample())

    def test_sampling_distribution_and_helpers(self, env_id):
        env = gym.make(env_id).unwrapped
        assert isinstance(env.sampling_distribution(), str) and env.sampling_distribution()
        helpers = env.make_helpers()
        assert isinstance(helpers, Helpers) and helpers.functions()
        obs, _ = env.reset(seed=0)
        helpers.bind(obs)
        for fn in helpers.functions().values():  # those without arguments answer now
            if arity(fn) == 0:
                fn()

    def test_deterministic_for_a_seed(self, env_id):
        a, b = gym.make(env_id), gym.make(env_id)
        assert same(rollout(a, 123), rollout(b, 123))
        assert not same(rollout(a, 1)[0], rollout(b, 2)[0])

    def test_step_info_contract(self, env_id):
        for step in rollout(gym.make(env_id), 7)[1:]:
            info = step[-1]
            assert {"primitive", "param", "admissible", "certificate"} <= info.keys()
            assert isinstance(info["admissible"], bool) and isinstance(info["certificate"], bool)
            if not info["certificate"]:
                assert isinstance(info["reason"], str) and info["reason"]

    def test_inadmissible_step_runs_nothing_and_says_why(self, env_id):
        env = gym.make(env_id)
        before, _ = env.reset(seed=0)
        action, reason = inadmissible_action(env.unwrapped)
        after, _, _, _, info = env.step(action)
        assert (info["admissible"], info["certificate"], info["reason"]) == (False, False, reason)
        assert same(before, after)

    def test_action_outside_space_raises(self, env_id):
        env = gym.make(env_id)
        env.reset(seed=0)
        bad = np.asarray(env.action_space.sample()) + 1000
        with pytest.raises(ValueError, match="not in the action space"):
            env.step(bad)

    def test_pickles_fresh_and_reset(self, env_id):
        fresh = pickle.loads(pickle.dumps(gym.make(env_id)))
        fresh.reset(seed=3)
        env = gym.make(env_id)
        obs, _ = env.reset(seed=3)
        clone = pickle.loads(pickle.dumps(env))
        assert same(clone.unwrapped.observation(), obs)
        action = env.action_space.sample()
        assert same(clone.step(action), env.step(action))  # the same state and np_random

    def test_render_modes(self, env_id):
        modes = gym.make(env_id).metadata["render_modes"]
        if not modes:
            with pytest.raises(ValueError, match="render_mode"):
                gym.make(env_id, render_mode="rgb_array")
            with pytest.raises(ValueError, match="render_mode"):
                gym.make(env_id).unwrapped.film(print)
        for mode in modes:
            env = gym.make(env_id, render_mode=mode)
            frames: list[np.ndarray] = []
            env.unwrapped.film(frames.append)
            env.reset(seed=0)
            env.step(inadmissible_action(env.unwrapped)[0])
            env.unwrapped.film(None)
            assert len(frames) >= 2  # after reset and after the primitive
            frame = env.render()
            if mode == "rgb_array":
                assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
                assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 3  # a picture, not a blank
            else:  # depth_array: metres per pixel
                assert frame.ndim == 2 and frame.dtype.kind == "f" and np.isfinite(frame).any()
            env.close()

    def test_unknown_render_mode_rejected(self, env_id):
        with pytest.raises(ValueError, match="render_mode"):
            gym.make(env_id, render_mode="human-ish")

    @pytest.mark.parametrize("mode", ["sync", "async"])
    def test_make_vec(self, env_id, mode):
        envs = gym.make_vec(env_id, num_envs=2, vectorization_mode=mode)
        try:
            envs.reset(seed=5)
            envs.action_space.seed(5)
            obs, rewards, _, _, infos = envs.step(envs.action_space.sample())
            assert envs.observation_space.contains(obs)
            assert rewards.shape == (2,) and "certificate" in infos
        finally:
            envs.close()


@pytest.mark.parametrize(("env_id", "behavior", "episodes"), BEHAVIORS)
def test_behavior_succeeds(env_id, behavior, episodes):
    env = RobustnessWrapper(gym.make(env_id))
    policy = load_behavior(behavior, env)
    try:
        for seed in range(episodes):
            result = run_episode(env, policy, seed)
            assert result.rho == 1, f"seed {seed}: {result.reason}"
    finally:
        env.close()
