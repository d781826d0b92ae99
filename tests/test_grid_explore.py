"""VLB-GridExplore-v0: the world's invariants, the primitives' certificates, planner and controller."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from vlb_gym.core.helpers import AT_MOST
from vlb_gym.core.primitive import Failure
from vlb_gym.envs.grid_explore import GridExploreEnv, planner
from vlb_gym.envs.grid_explore.generator import free_components
from vlb_gym.envs.grid_explore.helpers import GridHelpers
from vlb_gym.envs.grid_explore.judge import GridJudge
from vlb_gym.envs.grid_explore.types import EMPTY, GOAL, OBSTACLE, UNEXPLORED, cell_of
from vlb_gym.wrappers.robustness import certificate_cause

SENSE, NAVIGATE = 0, 1


def reachable_from(truth: np.ndarray, cell) -> np.ndarray:
    """Independent reachability: flood fill with scipy's binary propagation."""
    seed = np.zeros_like(truth, dtype=bool)
    seed[cell] = True
    return ndimage.binary_propagation(seed, mask=truth != OBSTACLE)


@pytest.fixture
def env():
    return GridExploreEnv()


def test_reset_samples_the_allowable_space(env):
    starts = set()
    for seed in range(300):
        obs, info = env.reset(seed=seed)
        s = env.state
        assert (s.truth == OBSTACLE).sum() == 30 and (s.truth == GOAL).sum() == 3
        assert s.truth[s.start_cell] == EMPTY
        assert reachable_from(s.truth, s.start_cell)[s.truth == GOAL].any()
        assert (obs["labels"] == UNEXPLORED).all()
        assert cell_of(obs["position"], 10) == s.start_cell == info["start_cell"]
        starts.add(s.start_cell)
    assert len(starts) > 50  # start cells spread over the grid


def test_cell_geometry_follows_the_paper():
    assert cell_of(np.array([-4.5, -3.5]), 10) == (0, 1)
    assert cell_of(np.array([-5.0, -5.0]), 10) == (0, 0)
    assert cell_of(np.array([4.999, 0.0]), 10) == (9, 5)


def sense_action(env):
    return np.array([SENSE, *env.state.cell])


def test_sense_certificate_and_labels(env):
    obs, _ = env.reset(seed=1)
    i, j = env.state.cell
    obs, reward, terminated, truncated, info = env.step(sense_action(env))
    assert info["admissible"] and info["certificate"] and info["primitive"] == "sense"
    labels = obs["labels"].reshape(10, 10)
    for a, b in [(i, j), (i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)]:
        if 0 <= a < 10 and 0 <= b < 10:
            assert labels[a, b] == env.state.truth[a, b]
    assert (labels != UNEXPLORED).sum() <= 5
    assert reward == 0.0 and not terminated and not truncated


def test_sense_elsewhere_is_not_admissible_and_changes_nothing(env):
    obs, _ = env.reset(seed=2)
    i, j = env.state.cell
    other = ((i + 3) % 10, j)
    obs2, _, _, _, info = env.step(np.array([SENSE, *other]))
    assert not info["admissible"] and not info["certificate"] and "not admissible" in info["reason"]
    assert info["failure"] == Failure.INADMISSIBLE == "inadmissible"
    assert np.array_equal(obs["labels"], obs2["labels"])


def test_navigate_reaches_reachable_cells(env):
    for seed in range(20):
        env.reset(seed=seed)
        truth = env.state.truth
        reach = reachable_from(truth, env.state.cell)
        targets = np.argwhere(reach)
        target = tuple(targets[seed % len(targets)])
        _, _, _, _, info = env.step(np.array([NAVIGATE, *target]))
        assert info["admissible"] and info["certificate"], info
        assert "failure" not in info and "reason" not in info
        assert env.state.cell == target


def test_navigate_to_obstacle_or_unreachable_is_not_admissible(env):
    env.reset(seed=4)
    before = env.state.position.copy()
    reach = reachable_from(env.state.truth, env.state.cell)
    for target in map(tuple, np.argwhere(~reach)):
        _, _, _, _, info = env.step(np.array([NAVIGATE, *target]))
        assert not info["admissible"] and not info["certificate"]
    assert np.array_equal(env.state.position, before)


def test_process_noise_makes_certificates_fail_sometimes():
    env = GridExploreEnv(action_noise=3.0)
    outcomes = []
    for seed in range(40):
        env.reset(seed=seed)
        reach = np.argwhere(reachable_from(env.state.truth, env.state.cell))
        target = tuple(reach[np.argmax(np.abs(reach - env.state.cell).sum(axis=1))])
        outcomes.append(env.step(np.array([NAVIGATE, *target]))[4])
    failed = [o for o in outcomes if not o["certificate"]]
    assert 0 < len(failed) < len(outcomes)
    assert all(o["admissible"] for o in outcomes)
    assert any("collided" in o["reason"] for o in failed)
    # a collision is the controller's failure; missing the target cell is the region's
    assert {o["failure"] for o in failed} <= {"controller", "region"}
    assert all((o["failure"] == "controller") == o["reason"].startswith("controller failed")
               for o in failed)
    assert {certificate_cause(o) for o in failed} <= {"navigate: controller failed",
                                                      "navigate: certificate"}


def test_noise_free_navigation_never_touches_obstacles(env):
    """The PD lag cuts corners by less than a quarter cell: no trajectory enters a blocked cell."""
    for seed in range(30):
        env.reset(seed=seed)
        reach = np.argwhere(reachable_from(env.state.truth, env.state.cell))
        for target in reach[:: max(1, len(reach) // 6)]:
            info = env.step(np.array([NAVIGATE, *target]))[4]
            assert info["certificate"], info
        for trajectory in env.state.trail:
            cells = np.floor(trajectory + 5).astype(int)
            assert (env.state.truth[cells[:, 0], cells[:, 1]] != OBSTACLE).all()


def value_iteration(passable: np.ndarray, target) -> np.ndarray:
    """Plain synchronous value iteration on the grid MDP (cost 1 per move), independent of BFS."""
    big = 10**6
    value = np.full(passable.shape, big, dtype=np.int64)
    value[target] = 0
    while True:
        padded = np.pad(value, 1, constant_values=big)
        best = np.minimum.reduce([padded[2:, 1:-1], padded[:-2, 1:-1],
                                  padded[1:-1, 2:], padded[1:-1, :-2]])
        new = np.where(passable, np.minimum(value, best + 1), big)
        new[target] = 0 if passable[target] else big
        new = np.minimum(new, big)
        if np.array_equal(new, value):
            return value
        value = new


@pytest.mark.parametrize("seed", range(10))
def test_cost_to_go_is_the_value_iteration_fixed_point(seed):
    rng = np.random.default_rng(seed)
    passable = rng.random((10, 10)) > 0.3
    target = tuple(np.argwhere(passable)[0])
    expected = value_iteration(passable, target)
    got = planner.cost_to_go(passable, target).astype(np.int64)
    got[got == planner.UNREACHABLE] = 10**6
    assert np.array_equal(got, expected)
    start = tuple(np.argwhere(expected == expected[expected < 10**6].max())[0])
    path = planner.greedy_path(planner.cost_to_go(passable, target), start)
    assert len(path) == expected[start] + 1 and path[-1] == target
    assert all(abs(a[0] - b[0]) + abs(a[1] - b[1]) == 1 for a, b in zip(path, path[1:]))


def test_tracking_filter_matches_the_pd_loop():
    """The lfilter closed form equals stepping p += dt (KP e + KD (e - e_prev) / dt + noise)."""
    rng = np.random.default_rng(0)
    start = np.array([-4.2, 1.3])
    ref = planner.reference(start, np.array([[-3.5, 1.5], [-2.5, 1.5], [-2.5, 2.5]]))
    noise = rng.normal(0, planner.DT * 0.7, size=ref.shape)
    got = planner.track(start, ref, noise)
    p, e_prev = start.copy(), ref[0] - start
    for k in range(len(ref)):
        e = ref[k] - p
        u = planner.KP * e + planner.KD * (e - e_prev) / planner.DT
        p = p + planner.DT * u + noise[k]
        e_prev = e
        assert np.allclose(got[k], p, atol=1e-9)
    assert np.linalg.norm(got[-1] - [-2.5, 2.5]) < 0.05  # settles on the target centre


def test_constructor_arguments_are_checked():
    with pytest.raises(ValueError, match="action_noise"):
        GridExploreEnv(action_noise=-1)
    with pytest.raises(ValueError, match="size"):
        GridExploreEnv(size=1)
    with pytest.raises(ValueError, match="do not fit"):
        GridExploreEnv(size=3, n_obstacles=8, n_goals=1).reset(seed=0)


def test_render_shows_the_world():
    env = gym.make("VLB-GridExplore-v0", render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (320, 320, 3)
    dark = (frame.reshape(-1, 3) == (20, 20, 20)).all(axis=1).sum()
    assert dark > 30 * (32 - 1) ** 2 * 0.9  # 30 obstacle squares


def test_goal_found_in_info_equals_the_labels():
    env = gym.make("VLB-GridExplore-v0", n_goals=6)
    for seed in range(5):
        env.reset(seed=seed)
        env.action_space.seed(seed)
        for _ in range(40):
            state = env.unwrapped.state
            action = np.array([0, *state.cell]) if env.action_space.sample()[0] == 0 else \
                env.action_space.sample()
            info = env.step(action)[4]
            assert info["goal_found"] == bool((env.unwrapped.state.labels == 3).any())


@settings(max_examples=300, deadline=None)
@given(size=st.integers(1, 16), density=st.floats(0, 1), seed=st.integers(0, 2**32 - 1))
def test_free_components_number_them_as_scipy_does(size, density, seed):
    truth = np.where(np.random.default_rng(seed).random((size, size)) < density, OBSTACLE,
                     EMPTY).astype(np.int8)
    expected = ndimage.label(truth != OBSTACLE, structure=ndimage.generate_binary_structure(2, 1))
    got = free_components(truth)
    assert got.dtype == np.int32 and np.array_equal(got, expected[0])


@pytest.mark.parametrize("size", [2, 3, 10, 17])
def test_neighbour_helpers_keep_their_declared_most_length(size):
    helpers, judge = GridHelpers(size), GridJudge(size)
    bound = {fn: getattr(fn, AT_MOST) for fn in (*helpers.functions().values(),
                                                   *judge.functions().values())
             if getattr(fn, AT_MOST, None) is not None}
    assert {fn.__name__ for fn in bound} == {"adjacent", "neighbours"}
    for cell in np.ndindex(size, size):
        cell = tuple(map(int, cell))
        assert len(helpers.adjacent(cell)) <= bound[helpers.adjacent]
        assert len(judge.neighbours(cell)) <= bound[judge.neighbours]
