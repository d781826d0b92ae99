"""A compiled behavior as a standard policy: SB3's ``evaluate_policy`` and Gymnasium vector loops
give the episodes of this package's own runner (``run_episode``) for the same reset seeds."""

from __future__ import annotations

import warnings
from pathlib import Path
from functools import partial

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from stable_baselines3.common.evaluation import evaluate_policy
from stable_baselines3.common.monitor import Monitor
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

from vlb_gym.core.library import load_behavior
from vlb_gym.verify import run_episode
from vlb_gym.wrappers import BehaviorAgent, BehaviorFinished, RobustnessWrapper

from .conftest import EXAMPLES

GRID = "VLB-GridExplore-v0"
BEHAVIOR = "find_goal_and_oscillate"
FIXED_CELL = str(EXAMPLES / "fixed_cell.json")
pytestmark = pytest.mark.timeout(60)


class Reseed(gym.Wrapper):
    """Seeds every reset, autoresets included, from ``seeds``: episodes replayable one by one."""

    def __init__(self, env: gym.Env, seeds: list[int]):
        super().__init__(env)
        self.seeds = iter(seeds)

    def reset(self, *, seed=None, options=None):
        return self.env.reset(seed=next(self.seeds), options=options)


def seeds_of(index: int) -> list[int]:
    """Reset seeds of vector-env index ``index``, one per episode (plenty)."""
    return [1000 * index + k for k in range(100)]


def make_env(behavior: str, seeds: list[int], **kwargs) -> gym.Env:
    return BehaviorFinished(RobustnessWrapper(Reseed(gym.make(GRID, **kwargs), seeds)), behavior)


def reference(behavior: str, seed: int, **kwargs) -> dict:
    """``run_episode``'s verdict on one episode, in the final-info keys of the wrappers."""
    env = RobustnessWrapper(gym.make(GRID, **kwargs))
    result = run_episode(env, load_behavior(behavior, env), seed, stop_on_failure=False)
    return {"rho_B": result.rho, "finished": result.finished, "primitives": result.primitives}


def evaluate(behavior: str, vec_env_class=DummyVecEnv, n_envs: int = 2, **kwargs):
    """``evaluate_policy`` of the agent on ``n_envs`` envs: its lengths and, per episode, the
    reset seed and the final info."""
    factories = [partial(lambda i: Monitor(make_env(behavior, seeds_of(i))), i)
                 for i in range(n_envs)]
    vec_env = vec_env_class(factories, **kwargs)
    episodes, counts = [], [0] * n_envs

    def record(local_vars, _):
        if local_vars["done"]:
            i = local_vars["i"]
            episodes.append((seeds_of(i)[counts[i]], local_vars["info"]))
            counts[i] += 1

    agent = BehaviorAgent(behavior, gym.make(GRID))
    _, lengths = evaluate_policy(agent, vec_env, n_eval_episodes=10, callback=record,
                                 return_episode_rewards=True)
    vec_env.close()
    return lengths, episodes


@pytest.mark.parametrize("vec_env_class, kwargs", [
    (DummyVecEnv, {}), (SubprocVecEnv, {"start_method": "fork"})], ids=["dummy", "subproc"])
def test_evaluate_policy_runs_a_shipped_behavior_like_run_episode(vec_env_class, kwargs):
    lengths, episodes = evaluate(BEHAVIOR, vec_env_class, **kwargs)
    assert len(lengths) == len(episodes) == 10
    for length, (seed, info) in zip(lengths, episodes):
        assert not info["TimeLimit.truncated"]  # so the episode ended by termination
        assert info["rho_B"] == 1 and info["finished"]
        assert length == info["primitives"] == reference(BEHAVIOR, seed)["primitives"]


def run_vector(envs: gym.vector.VectorEnv, agent: BehaviorAgent, episodes: int
               ) -> list[tuple[int, bool, dict]]:
    """Drive ``envs`` (next-step autoreset) with batched predictions until ``episodes`` ended:
    (env index, terminated, final rho_B/finished/primitives) per episode, in order per index."""
    keys = ("rho_B", "finished", "primitives")
    obs, _ = envs.reset()
    starts = np.ones(envs.num_envs, dtype=bool)
    autoreset = np.zeros(envs.num_envs, dtype=bool)
    ended = []
    while len(ended) < episodes:
        actions, _ = agent.predict(obs, episode_start=starts)
        assert actions.shape == (envs.num_envs, *envs.single_action_space.shape)
        obs, _, terminated, truncated, infos = envs.step(actions)
        assert infos["on_behavior"][infos["_on_behavior"]].all()  # agent and wrappers agree
        starts = autoreset  # where the step reset the env, obs is the first of an episode
        autoreset = terminated | truncated
        ended += [(int(i), bool(terminated[i]), {k: infos[k][i].item() for k in keys})
                  for i in np.flatnonzero(autoreset)]
    envs.close()
    return ended


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_vector_env_loop_gives_run_episodes_results(mode):
    env_fns = [partial(make_env, BEHAVIOR, seeds_of(i)) for i in range(3)]
    vector = gym.vector.SyncVectorEnv if mode == "sync" else gym.vector.AsyncVectorEnv
    ended = run_vector(vector(env_fns), BehaviorAgent(BEHAVIOR, gym.make(GRID)), 9)
    counts = [0, 0, 0]
    for i, terminated, final in ended:
        assert terminated and final == reference(BEHAVIOR, seeds_of(i)[counts[i]])
        counts[i] += 1


def test_unbatched_predict_equals_batched_predict():
    envs = gym.make_vec(GRID, num_envs=3, vectorization_mode="sync", wrappers=[
        RobustnessWrapper, partial(BehaviorFinished, behavior=BEHAVIOR)])
    env = gym.make(GRID)
    batched = BehaviorAgent(BEHAVIOR, env)
    single = [BehaviorAgent(BEHAVIOR, env) for _ in range(3)]
    obs, _ = envs.reset(seed=7)
    starts, autoreset = np.ones(3, dtype=bool), np.zeros(3, dtype=bool)
    for _ in range(30):
        actions, state = batched.predict(obs, episode_start=starts)
        assert state is None
        for i, agent in enumerate(single):
            action, _ = agent.predict({k: v[i] for k, v in obs.items()}, episode_start=starts[i])
            assert action.shape == env.action_space.shape and np.array_equal(action, actions[i])
        obs, _, terminated, truncated, _ = envs.step(actions)
        starts, autoreset = autoreset, terminated | truncated
    envs.close()
    with pytest.raises(ValueError, match="batch"):
        batched.predict({"position": np.zeros((2, 2)), "labels": np.zeros((3, 100))})


def test_failing_behavior_scores_minus_one_and_raises_nothing():
    lengths, episodes = evaluate(FIXED_CELL)
    for length, (seed, info) in zip(lengths, episodes):
        expected = reference(FIXED_CELL, seed)
        assert length == 2 and not info["TimeLimit.truncated"]  # sense, navigate, finished
        assert {k: info[k] for k in expected} == expected
    assert {info["rho_B"] for _, info in episodes} == {1, -1}


@pytest.mark.parametrize("start, edge, primitives", [
    ("current_cell()", "(current_cell()[0] + 10, 0)", 1),  # fails after the first step
    ("(current_cell()[0] + 10, 0)", "current_cell()", 0),  # fails at the reset
])
def test_behavior_runtime_error_truncates_the_episode(write_behavior, start, edge, primitives):
    doc = {"name": "off_grid", "env": GRID, "nodes": [{"id": "sense", "primitive": "sense"},
                                                      {"id": "go", "primitive": "navigate"}],
           "start": {"node": "sense", "param": start},
           "edges": [{"from": "sense", "to": "go", "param": edge}], "terminals": ["go"]}
    path = str(write_behavior(doc))
    lengths, episodes = evaluate(path)
    for length, (seed, info) in zip(lengths, episodes):
        assert info["TimeLimit.truncated"] and length == max(primitives, 1)
        assert info["rho_B"] == -1 and not info["finished"] and info["primitives"] == primitives
        assert info["failure_reason"].startswith("BehaviorRuntimeError: ")
        assert reference(path, seed) == {"rho_B": -1, "finished": False,
                                         "primitives": primitives}


def test_step_bound_ends_the_episode_unfinished():
    env = make_env(BEHAVIOR, seeds_of(0), max_episode_steps=5)
    agent = BehaviorAgent(BEHAVIOR, env)
    obs, _ = env.reset()
    for _ in range(5):
        obs, _, terminated, truncated, info = env.step(agent.predict(obs)[0])
    assert truncated and not terminated and info["on_behavior"]
    assert {k: info[k] for k in ("rho_B", "finished", "primitives")} == reference(
        BEHAVIOR, seeds_of(0)[0], max_episode_steps=5) == {"rho_B": -1, "finished": False,
                                                           "primitives": 5}
    with pytest.raises(RuntimeError, match="ended"):
        env.step(agent.predict(obs)[0])


def test_after_another_action_the_wrapper_stands_aside():
    env = make_env(BEHAVIOR, seeds_of(0), max_episode_steps=30)
    agent = BehaviorAgent(BEHAVIOR, env)
    obs, _ = env.reset()
    obs, _, _, _, info = env.step(agent.predict(obs, episode_start=True)[0])
    assert info["on_behavior"] and info["primitive"] == "sense"
    obs, _, _, _, info = env.step(np.array([0, *info["cell"]]))  # the behavior would navigate
    assert not info["on_behavior"] and info["primitive"] == "sense" and info["certificate"]
    steps = 2
    while "rho_B" not in info:  # the agent's copy goes on, the wrapper's has stopped
        obs, _, terminated, truncated, info = env.step(agent.predict(obs)[0])
        assert not info["on_behavior"]
        steps += 1
    assert steps == 30 and truncated and not terminated and info["rho_B"] == -1
    assert info["failure_reason"] == "truncated: step bound reached after 30 primitives"


def test_robustness_is_added_when_missing_and_env_checker_passes():
    env = BehaviorFinished(gym.make(GRID), BEHAVIOR)
    assert isinstance(env.env, RobustnessWrapper) and env.robustness is env.env
    assert env.spec.additional_wrappers[-1].kwargs == {"behavior": BEHAVIOR}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # the close check remakes the env from env.spec: RobustnessWrapper records no arguments
        check_env(env, skip_render_check=True, skip_close_check=True)
    # check_env steps random actions: the wrapper stands aside, they are applied as they are
    assert [str(w.message) for w in caught if "unwrapped" not in str(w.message)] == []


def test_the_documented_evaluate_policy_example_runs_and_reads_rho(capsys):
    readme = (Path(__file__).resolve().parent.parent / "docs" / "python.md").read_text()
    block = next(b for b in readme.split("```python\n")[1:] if "evaluate_policy(agent" in b)
    scope: dict = {}
    exec(block.split("```")[0], scope)  # noqa: S102 - the page's own example
    assert len(scope["rho"]) == 10 and set(scope["rho"]) <= {1, -1}
    assert capsys.readouterr().out.startswith("10 episodes, rho_B: [")


class Counting(gym.Wrapper):
    """Counts the resets and steps that reach it."""

    def __init__(self, env: gym.Env):
        super().__init__(env)
        self.resets = self.steps = 0

    def reset(self, **kwargs):
        self.resets += 1
        return self.env.reset(**kwargs)

    def step(self, action):
        self.steps += 1
        return self.env.step(action)


def test_the_wrappers_between_it_and_the_robustness_wrapper_see_every_step():
    """An env that contains a RobustnessWrapper keeps its own wrappers around it: a step bound
    outside it still ends the episode, and a wrapper between sees the resets and steps."""
    counting = Counting(RobustnessWrapper(gym.make(GRID)))
    env = BehaviorFinished(gym.wrappers.TimeLimit(counting, max_episode_steps=3), BEHAVIOR)
    agent = BehaviorAgent(BEHAVIOR, env)
    obs, _ = env.reset(seed=0)
    steps, terminated, truncated = 0, False, False
    while not (terminated or truncated):
        obs, _, terminated, truncated, info = env.step(agent.predict(obs)[0])
        steps += 1
    assert (steps, truncated, info["on_behavior"]) == (3, True, True)
    assert (counting.resets, counting.steps) == (1, 3)
    assert info["rho_B"] == -1 and not info["finished"]
