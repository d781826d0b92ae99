"""The compiled navigate controller (extra ``fast``) against the plain one, bit for bit."""

from __future__ import annotations

import sys

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vlb_gym.envs import grid_explore
from vlb_gym.envs.grid_explore import planner, primitives
from vlb_gym.verify.campaign import Campaign, CampaignConfig, run_campaign

compiled = pytest.importorskip("vlb_gym.envs.grid_explore.compiled")


@st.composite
def navigations(draw):
    """A grid, a reachable start cell and target, a position in the start cell, maybe noise."""
    size = draw(st.integers(2, 16))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    passable = rng.random((size, size)) > draw(st.floats(0.0, 0.5))
    free = np.argwhere(passable)
    if not len(free):
        passable[0, 0] = True
        free = np.argwhere(passable)
    target = tuple(int(v) for v in free[rng.integers(len(free))])
    dist = planner.cost_to_go(passable, target)
    start = tuple(int(v) for v in np.argwhere(dist != planner.UNREACHABLE)[
        rng.integers((dist != planner.UNREACHABLE).sum())])
    corner = np.array(start, dtype=float) - size / 2
    offset = draw(st.one_of(st.just(0.5), st.floats(0.0, 0.999)))  # 0.5: exactly the centre
    position = corner + np.array([offset, draw(st.floats(0.0, 0.999))])
    sigma = draw(st.sampled_from([0.0, 0.1, 1.0, 20.0]))
    return passable, target, start, position, sigma, rng


@settings(max_examples=300, deadline=None)
@given(navigations())
def test_compiled_controller_equals_the_plain_one(case):
    passable, target, start, position, sigma, rng = case
    dist = planner.cost_to_go(passable, target)
    assert np.array_equal(compiled.cost_to_go(passable, target), dist)
    assert compiled.cost_to_go(passable, target).dtype == dist.dtype
    centres = planner.waypoints(dist, start)
    assert np.array_equal(compiled.waypoints(dist, start), centres)
    count = planner.steps(position, centres)
    assert compiled.steps(position, centres) == count
    noise = rng.normal(0.0, planner.DT * sigma, size=(count, 2)) if sigma else None
    blocked = planner.padded_blocked(passable)
    want, want_hit = planner.rollout(position, centres, noise, blocked)
    got, got_hit = compiled.rollout(position, centres, noise, blocked)
    assert np.array_equal(got, want) and got_hit == want_hit


def test_compiled_planner_rejects_unreachable_starts_like_the_plain_one():
    passable = np.ones((3, 3), dtype=bool)
    passable[1, :] = False
    dist = planner.cost_to_go(passable, (0, 0))
    for kernels in (planner, compiled):
        with pytest.raises(ValueError, match=r"cell \(2, 2\) cannot reach the target"):
            kernels.waypoints(dist, (2, 2))
    assert np.array_equal(compiled.cost_to_go(passable, (1, 1)), planner.cost_to_go(
        passable, (1, 1)))  # an obstacle target: unreachable everywhere


def test_compiled_functions_check_what_compiled_code_would_not():
    passable = np.ones((4, 4), dtype=bool)
    for target in ((4, 0), (-1, 2)):
        with pytest.raises(IndexError, match="outside the 4x4 grid"):
            compiled.cost_to_go(passable, target)
        with pytest.raises(IndexError, match="outside the 4x4 grid"):
            compiled.waypoints(planner.cost_to_go(passable, (0, 0)), target)
    centres = np.array([[0.5, 0.5]])
    with pytest.raises(ValueError, match="noise of shape"):
        compiled.rollout(np.zeros(2), centres, np.zeros((1, 2)), planner.padded_blocked(passable))


def trails(kernels, monkeypatch, action_noise: float) -> list:
    """Every episode's trajectories, certificates and final state with ``kernels``."""
    monkeypatch.setattr(primitives, "controller", lambda: kernels)
    env = gym.make("VLB-GridExplore-v0", action_noise=action_noise)
    out = []
    for seed in range(15):
        env.reset(seed=seed)
        env.action_space.seed(seed)
        for _ in range(30):
            state = env.unwrapped.state
            action = env.action_space.sample()
            if action[0] == 0:
                action[1:] = state.cell
            info = env.step(action)[4]
            out.append((info["certificate"], info.get("reason")))
        state = env.unwrapped.state
        out.append((state.position.tolist(), [t.tolist() for t in state.trail],
                    state.labels.tolist()))
    return out


@pytest.mark.parametrize("action_noise", [0.0, 0.8])
def test_env_runs_the_same_episodes_on_either_controller(monkeypatch, action_noise):
    assert trails(compiled, monkeypatch, action_noise) == trails(planner, monkeypatch,
                                                                action_noise)


def test_campaign_episodes_are_the_same_on_either_controller(monkeypatch):
    config = CampaignConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", 40, seed=3)
    runs = []
    for kernels in (compiled, planner):
        monkeypatch.setattr(primitives, "controller", lambda k=kernels: k)
        with Campaign(config) as campaign:
            runs.append([(e.rho, e.outcome()["steps"]) for e in campaign.episodes()])
    assert runs[0] == runs[1]
    assert all(rho == 1 for rho, _ in runs[0])  # the paper's Behavior 2 always verifies


def test_without_numba_navigate_uses_the_plain_controller(monkeypatch):
    monkeypatch.delitem(sys.modules, "vlb_gym.envs.grid_explore.compiled")
    monkeypatch.delattr(grid_explore, "compiled")
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba raises ImportError
    primitives.controller.cache_clear()
    try:
        assert primitives.controller() is planner
        env = gym.make("VLB-GridExplore-v0")
        env.reset(seed=0)
        here = env.unwrapped.state.cell
        assert env.step(np.array([1, *here]))[4]["certificate"]  # navigate to the centre
        assert env.unwrapped.preload == ("scipy.signal",)  # what the plain navigate imports
        # a campaign in process imports the env's preload first: without Numba, it goes on
        report = run_campaign(CampaignConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", 3))
        assert report["successes"] == 3
    finally:
        primitives.controller.cache_clear()  # the next call imports the compiled one again
