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
from vlb_gym.baselines.observations import (AGENT, FULL, GOAL_FOUND, HEADING_HOME, LEGS_DONE,
                                            START, LabelImage)
from vlb_gym.baselines.configs import TASK_IDS
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
    env = LabelImage(ExplorationBonus(gym.make(TASK_IDS.get(task, ENV))))
    check_env(env, skip_render_check=True)
    with pytest.warns(UserWarning, match="36x36"):  # the reason for GridCNN, and only that
        sb3_checker.check_env(env)
    assert env.observation_space.shape == (7 + 2 * (task == "find_goal_and_oscillate"), 10, 10)


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), task=st.sampled_from(TASKS[1:]))
def test_the_label_image_shows_the_true_state(seed, task):
    env = LabelImage(gym.make(TASK_IDS[task]))
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
            legs = env.get_wrapper_attr("tracker").legs
            assert (image[LEGS_DONE] == round(FULL * legs / LEGS)).all()
            assert (image[HEADING_HOME] == FULL * (legs % 2)).all()
        image, _, terminated, truncated, _ = env.step(random_admissible(env, rng))
        if terminated or truncated:
            break


def test_the_label_image_needs_the_grid_observation():
    with pytest.raises(TypeError, match="position and labels"):
        LabelImage(gym.make("VLB-Scoop-v0"))


def test_grid_cnn_keeps_every_cell_and_gives_its_features():
    torch = pytest.importorskip("torch")
    from vlb_gym.baselines.cnn import GridCNN

    env = LabelImage(gym.make(TASK_IDS["find_goal"]))
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
    plain = RobustnessWrapper(gym.make(TASK_IDS["find_goal"]))
    shaped = RobustnessWrapper(ExplorationBonus(gym.make(TASK_IDS["find_goal"]), bonus))
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
        ExplorationBonus(gym.make(TASK_IDS["find_goal"]), bonus)


def _spatial_policy(task: str = "find_goal", **env_options):
    pytest.importorskip("sb3_contrib")
    from vlb_gym.baselines.cnn import SpatialPolicy
    from vlb_gym.baselines.train import make_env

    env = make_env(TASK_IDS[task], env_options, "spatial")
    policy = SpatialPolicy(env.observation_space, env.action_space, lambda _: 3e-4)
    return env, policy


@pytest.mark.parametrize("size", [10, 15])
def test_the_spatial_head_reads_each_action_off_its_own_cell(size):
    """The logit of (primitive, i, j) is the 1x1 convolution of the feature map at (i, j), in
    FlatActions' C order; and it sees only its receptive field: changing the image at cell
    (0, 0) leaves every logit more than 3 cells away (three 3x3 layers) unchanged. A dense head
    over all actions would fail both."""
    import torch

    env, policy = _spatial_policy(size=size, n_obstacles=size * size * 3 // 10)
    assert isinstance(policy.action_net, torch.nn.Identity)
    image, _ = env.reset(seed=1)
    obs = torch.as_tensor(image[None], dtype=torch.float32)
    with torch.no_grad():
        logits = policy.get_distribution(obs).distribution.logits[0]
        features = policy.extract_features(obs).view(1, 32, size, size)
        conv = policy.mlp_extractor.actor
        expected = torch.einsum("pc,bcij->bpij", conv.weight[:, :, 0, 0], features)[0] \
            + conv.bias[:, None, None]
    assert logits.shape == (2 * size * size,)
    torch.testing.assert_close(torch.log_softmax(expected.flatten(), 0), logits)
    changed = obs.clone()
    changed[0, :, 0, 0] = 255 - changed[0, :, 0, 0]
    with torch.no_grad():
        moved = policy.get_distribution(changed).distribution.logits[0]
    shift = (moved - logits).view(2, size, size)  # log-softmax: a common offset
    far = shift[:, 4:, :].flatten().tolist() + shift[:, :4, 4:].flatten().tolist()
    assert max(far) - min(far) < 1e-5
    assert (shift[:, :4, :4] - far[0]).abs().max() > 1e-6  # near cells do change


def test_a_spatial_policy_never_puts_mass_on_an_inadmissible_action():
    import torch

    env, policy = _spatial_policy()
    rng = np.random.default_rng(0)
    image, _ = env.reset(seed=3)
    for _ in range(10):
        masks = env.action_masks()
        with torch.no_grad():
            probs = policy.get_distribution(torch.as_tensor(image[None], dtype=torch.float32),
                                            action_masks=masks).distribution.probs[0].numpy()
        assert probs[~masks].max() == 0 and probs[masks].sum() == pytest.approx(1, abs=1e-5)
        image, _, done, cut, _ = env.step(int(rng.choice(np.flatnonzero(masks))))
        if done or cut:
            break
