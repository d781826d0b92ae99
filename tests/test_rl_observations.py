"""The RL representations of the grid: the label image (against the true state, episode by
episode), the CNN over it, and the exploration bonus (adds up as documented, never touches
rho_B)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from hypothesis import given, settings
from hypothesis import strategies as st

from vlb_gym import RobustnessWrapper
from vlb_gym.baselines.observations import AGENT, FULL, GOAL_FOUND, START, LabelImage
from vlb_gym.baselines.tasks import LEGS, ExplorationBonus
from vlb_gym.baselines.wrappers import admissible_actions
from vlb_gym.envs.grid_explore.types import GOAL, UNEXPLORED

ENV = "VLB-GridExplore-v0"
TASKS = (None, "find_goal", "find_goal_and_oscillate")


def random_admissible(env: gym.Env, rng: np.random.Generator) -> np.ndarray:
    """A uniformly random admissible action of the MultiDiscrete layout."""
    flat = rng.choice(np.flatnonzero(admissible_actions(env.unwrapped)))
    return np.array(np.unravel_index(flat, env.action_space.nvec), dtype=np.int64)


@pytest.mark.filterwarnings("ignore:.*is different from the unwrapped version")
@pytest.mark.parametrize("task", TASKS)
def test_the_label_image_passes_both_env_checkers(task):
    sb3_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    env = LabelImage(ExplorationBonus(gym.make(ENV, task=task) if task else gym.make(ENV)))
    check_env(env, skip_render_check=True)
    with pytest.warns(UserWarning, match="36x36"):  # the reason for GridCNN, and only that
        sb3_checker.check_env(env)
    assert env.observation_space.shape == (7 + (task == "find_goal_and_oscillate"), 10, 10)


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), task=st.sampled_from(TASKS[1:]))
def test_the_label_image_shows_the_true_state(seed, task):
    env = LabelImage(gym.make(ENV, task=task))
    rng = np.random.default_rng(seed)
    image, _ = env.reset(seed=seed)
    for _ in range(12):
        state = env.unwrapped.state
        assert image.dtype == np.uint8 and set(np.unique(image[:GOAL_FOUND + 1])) <= {0, FULL}
        labels = np.argmax(image[:4], axis=0)
        np.testing.assert_array_equal(labels, state.labels)
        assert (image[:4] == FULL).sum(axis=0).min() == 1  # one label per cell
        assert list(zip(*np.nonzero(image[AGENT]))) == [state.cell]
        assert list(zip(*np.nonzero(image[START]))) == [state.start_cell]
        assert (image[GOAL_FOUND] == FULL * bool((state.labels == GOAL).any())).all()
        if task == "find_goal_and_oscillate":
            assert (image[-1] == round(FULL * env.get_wrapper_attr("tracker").legs / LEGS)).all()
        image, _, terminated, truncated, _ = env.step(random_admissible(env, rng))
        if terminated or truncated:
            break


def test_the_label_image_needs_the_grid_observation():
    with pytest.raises(TypeError, match="position and labels"):
        LabelImage(gym.make("VLB-Scoop-v0"))


def test_grid_cnn_keeps_every_cell_and_gives_its_features():
    torch = pytest.importorskip("torch")
    from vlb_gym.baselines.cnn import GridCNN

    env = LabelImage(gym.make(ENV, task="find_goal"))
    cnn = GridCNN(env.observation_space, features_dim=64)
    image, _ = env.reset(seed=0)
    features = cnn(torch.as_tensor(image[None] / 255.0, dtype=torch.float32))
    assert features.shape == (1, 64) and (features >= 0).all()
    assert cnn.net[5].in_features == 32 * 10 * 10  # padding kept the 10x10 map


@pytest.mark.parametrize("bonus", [0.0, 0.02, 0.5])
def test_the_exploration_bonus_adds_up_as_documented_and_never_changes_rho(bonus):
    """The same actions with and without the bonus: rewards differ by exactly bonus x (cells
    known at the end - cells known after reset), counted from the true state here; every
    step's info, the termination and rho_B are the same."""
    rng = np.random.default_rng(7)
    plain = RobustnessWrapper(gym.make(ENV, task="find_goal"))
    shaped = RobustnessWrapper(ExplorationBonus(gym.make(ENV, task="find_goal"), bonus))
    for episode in range(3):
        plain.reset(seed=episode)
        shaped.reset(seed=episode)
        known_start = int((shaped.unwrapped.state.labels != UNEXPLORED).sum())
        totals = [0.0, 0.0]
        while True:
            action = random_admissible(plain, rng)
            *_, r0, t0, u0, i0 = plain.step(action)
            *_, r1, t1, u1, i1 = shaped.step(action)
            totals[0] += r0
            totals[1] += r1
            assert (t0, u0) == (t1, u1) and i0 == i1
            if t0 or u0:
                break
        known_end = int((shaped.unwrapped.state.labels != UNEXPLORED).sum())
        assert totals[1] - totals[0] == pytest.approx(bonus * (known_end - known_start))
        assert plain.summary == shaped.summary and plain.summary["rho_B"] in (-1, 1)


@pytest.mark.parametrize("bonus", [-0.1, 2, "a"])
def test_a_bad_bonus_is_refused(bonus):
    with pytest.raises(ValueError, match="bonus must be a number in"):
        ExplorationBonus(gym.make(ENV, task="find_goal"), bonus)
