"""RL baselines: task rewards, masks, SB3 compatibility, and train -> save -> load -> verify."""

from __future__ import annotations

import json
import shlex

import gymnasium as gym
import numpy as np
import pytest
from scipy.stats import beta, binom

from vlb_gym import RobustnessWrapper, load_behavior
from vlb_gym.baselines.configs import TASKS
from vlb_gym.baselines.train import make_env, train
from vlb_gym.baselines.wrappers import ActionMasks, FlatActions
from vlb_gym.cli import main
from vlb_gym.baselines.configs import TASK_IDS
from vlb_gym.baselines.tasks import LEGS, GridTask
from vlb_gym.baselines.train import policy_env_kwargs
from vlb_gym.envs.grid_explore import GridExploreEnv
from vlb_gym.envs.modules import EnvSetupError, make_primitive_env
from vlb_gym.verify import Campaign, CampaignConfig, PolicyRef, run_campaign, run_episode

GRID = "VLB-GridExplore-v0"
FIND_GOAL = TASK_IDS["find_goal"]


@pytest.mark.parametrize("task", sorted(TASKS))
def test_sb3_check_env_accepts_every_task(task):
    from stable_baselines3.common.env_checker import check_env

    check_env(gym.make(TASKS[task].task_id, **TASKS[task].env_kwargs))
    check_env(make_env(TASKS[task].task_id, TASKS[task].env_kwargs))


@pytest.mark.parametrize("seed", range(6))
def test_flat_actions_and_masks_match_admissibility(seed):
    flat = FlatActions(gym.make(FIND_GOAL, size=6 + seed, n_obstacles=4 * seed))
    env = ActionMasks(flat)
    env.reset(seed=seed)
    base, n = env.unwrapped, flat.action_space.n
    for _ in range(3):  # states along a random admissible walk
        mask = env.action_masks()
        assert mask.shape == (n,) and n == 2 * base.size ** 2
        for index in range(n):
            kind, i, j = flat.action(index)
            assert index == kind * base.size ** 2 + i * base.size + j
            primitive = base.primitive_order[kind]
            assert mask[index] == primitive.admissible(base.state, (int(i), int(j)))
        env.step(int(np.flatnonzero(mask)[-1]))


@pytest.mark.parametrize("task, behavior", [("find_goal", "explore_until_goal"),
                                            ("find_goal_and_oscillate", "find_goal_and_oscillate")])
def test_tasks_terminate_when_the_graph_finishes(task, behavior):
    env = RobustnessWrapper(gym.make(TASK_IDS[task]))
    policy = load_behavior(behavior, env)
    for seed in range(10):
        rewards = []
        result = run_episode(env, policy, seed, stop_on_failure=False,
                             on_step=lambda info: info and rewards.append(info))
        assert result.rho == 1 and result.finished
        assert not policy.finished  # the env ended the episode on the graph's last primitive
        assert policy.predict(env.unwrapped.observation())[0] is None
        if task == "find_goal_and_oscillate":
            assert env.get_wrapper_attr("tracker").legs == LEGS


def test_task_rewards_follow_the_documented_scheme():
    env = gym.make(TASK_IDS["find_goal_and_oscillate"])
    policy = load_behavior("find_goal_and_oscillate", RobustnessWrapper(env))
    obs, _ = env.reset(seed=3)
    total, steps = 0.0, 0
    while True:
        action, _ = policy.predict(obs)
        obs, reward, terminated, truncated, info = env.step(action)
        total, steps = total + reward, steps + 1
        if terminated:
            break
    assert total == pytest.approx(1.0 + 0.5 * LEGS - 0.01 * steps)
    assert obs["legs"] == LEGS and tuple(obs["start"]) == env.unwrapped.state.start_cell


def test_unknown_task_is_rejected():
    with pytest.raises(ValueError, match="task='explore' is not one of"):
        GridTask(gym.make(GRID), "explore")


def test_the_env_has_no_task_kwarg_and_the_tasks_are_ids_of_their_own():
    with pytest.raises(EnvSetupError, match="task"):  # no kwarg changes what finished means
        make_primitive_env(GRID, {"task": "find_goal"})
    for task, env_id in TASK_IDS.items():
        env = gym.make(env_id)
        assert isinstance(env.unwrapped, GridExploreEnv) and env.get_wrapper_attr("task") == task
    assert not isinstance(gym.make(GRID).env, GridTask)


def test_an_agent_saved_with_a_task_kwarg_loads_on_the_tasks_id(tmp_path):
    saved = train(TASKS["find_goal"], "ppo", tmp_path, budgets=(128,), n_envs=1)[0]
    meta_path = saved.with_suffix(".json")
    meta = json.loads(meta_path.read_text())
    assert meta["env_id"] == FIND_GOAL and "task" not in meta["env_kwargs"]
    meta_path.write_text(json.dumps({**meta, "env_id": GRID,
                                     "env_kwargs": {**meta["env_kwargs"], "task": "find_goal"}}))
    assert policy_env_kwargs(saved) == (FIND_GOAL, meta["env_kwargs"])
    meta_path.write_text(json.dumps({**meta, "env_kwargs": {"task": "explore"}}))
    with pytest.raises(ValueError, match=r"env_kwargs.task: unknown task 'explore'"):
        policy_env_kwargs(saved)


@pytest.mark.parametrize("algorithm", ["ppo", "maskable_ppo", "a2c"])
def test_train_save_load_verify_round_trip(algorithm, tmp_path):
    saved = train(TASKS["find_goal"], algorithm, tmp_path, budgets=(256,), n_envs=2)
    assert len(saved) == 1 and saved[0].exists()
    meta = json.loads(saved[0].with_suffix(".json").read_text())
    assert meta["algorithm"] == algorithm and meta["steps"] >= 256
    config = CampaignConfig(FIND_GOAL, PolicyRef("sb3", str(saved[0])), 12, seed=5)
    with Campaign(config) as campaign:  # the agent's training env kwargs apply
        assert campaign.config.env_kwargs == meta["env_kwargs"]
        results = sorted(campaign.episodes(), key=lambda r: r.index)
    report = run_campaign(config)
    k = sum(not r.success for r in results)
    assert report["failures"] == k and report["successes"] == 12 - k
    assert report["confidence"] == pytest.approx(1 - binom.cdf(k, 12, 0.05))
    expected = 0.0 if k == 12 else beta.ppf(0.05, 12 - k, k + 1)
    assert report["lower_bound"] == pytest.approx(expected)
    assert all(r.reason for r in results if not r.success)  # failures explained, no crash


def test_cli_verify_policy_and_mismatch(tmp_path, capsys):
    saved = train(TASKS["find_goal"], "ppo", tmp_path, budgets=(128,), n_envs=1)[0]
    assert main(["verify", FIND_GOAL, "--policy", str(saved), "--episodes", "5",
                 "--epsilon", "0.1", "--report", str(tmp_path / "r.json")]) == 0
    report = json.loads((tmp_path / "r.json").read_text())
    assert report["policy"] == {"kind": "sb3", "ref": str(saved.resolve()), "library": None}
    assert report["episodes"] == 5
    assert report["env_id"] == FIND_GOAL and "task" not in report["env_kwargs"]
    assert main(["verify", "VLB-Scoop-v0", "--policy", str(saved), "--episodes", "5",
                 "--epsilon", "0.1"]) == 2
    assert f"was trained on {FIND_GOAL}" in capsys.readouterr().err
    assert main(["verify", GRID, "--policy", str(tmp_path / "none.zip"), "--episodes", "5",
                 "--epsilon", "0.1"]) == 2


@pytest.mark.parametrize("task", sorted(TASKS))
def test_an_image_agent_with_the_bonus_round_trips_through_the_cli(task, tmp_path, capsys):
    """vlb baseline train --observation image --bonus -> saved agent -> vlb verify --policy:
    the verifier rebuilds the agent's pictures from the plain env's observations, and its
    actions are the trained model's own on the training env's images."""
    assert main(["baseline", "train", GRID, "--task", task, "--algo", "maskable_ppo",
                 "--observation", "image", "--bonus", "0.02", "--budgets", "128",
                 "--n-envs", "1", "--seed", "3", "--out", str(tmp_path)]) == 0
    saved = tmp_path / f"{task}_maskable_ppo-image-bonus0p02-s3_128.zip"
    meta = json.loads(saved.with_suffix(".json").read_text())
    assert (meta["observation"], meta["bonus"], meta["seed"]) == ("image", 0.02, 3)
    assert main(["verify", TASKS[task].task_id, "--policy", str(saved), "--episodes", "4",
                 "--epsilon", "0.1", "--report", str(tmp_path / "r.json")]) == 0
    assert json.loads((tmp_path / "r.json").read_text())["episodes"] == 4

    from vlb_gym.baselines.train import SB3Policy
    trained = make_env(TASKS[task].task_id, TASKS[task].env_kwargs, "image", 0.02)
    plain = gym.make(TASKS[task].task_id, **TASKS[task].env_kwargs)
    policy = SB3Policy(saved, plain)
    for seed in range(2):
        image, _ = trained.reset(seed=seed)
        obs, _ = plain.reset(seed=seed)
        policy.reset()
        for _ in range(5):
            action, _ = policy.predict(obs)
            expected, _ = policy.model.predict(image, deterministic=True,
                                               action_masks=trained.action_masks())
            assert tuple(action) == tuple(trained.env.action(int(expected)))  # FlatActions
            image, *_, done, cut, _ = trained.step(int(expected))
            obs, *_ = plain.step(action)
            if done or cut:
                break


@pytest.mark.parametrize("args, message", [
    (["--observation", "pixels"], "invalid choice: 'pixels'"),
    (["--bonus", "2"], "2 must lie between 0 and 1"),
    (["--bonus", "x"], "'x' is not a number")])
def test_bad_representation_options_are_usage_errors(args, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["baseline", "train", GRID, "--task", "find_goal", "--algo", "ppo", *args])
    assert exit_.value.code == 2 and message in capsys.readouterr().err


def test_policy_campaigns_replay(tmp_path, capsys):
    """A --policy campaign's replay hint names --policy, and its stored episodes replay."""
    saved = train(TASKS["find_goal"], "ppo", tmp_path, budgets=(128,), n_envs=1)[0]
    assert main(["verify", FIND_GOAL, "--policy", str(saved), "--episodes", "4", "--epsilon", "0.1",
                 "--quiet"]) == 0
    out = capsys.readouterr().out
    assert f"replay one: vlb replay {FIND_GOAL} --policy " in out
    hint = shlex.split(out.split("replay one: ")[1].splitlines()[0])
    assert main(hint[1:]) == 0
    assert "rho_B = -1" in capsys.readouterr().out  # untrained: fails, as the campaign said
    store = tmp_path / "agent.db"
    assert main(["verify", FIND_GOAL, "--policy", str(saved), "--episodes", "4", "--epsilon", "0.1",
                 "--quiet", "--store", str(store)]) == 0
    capsys.readouterr()
    assert main(["replay", str(store), "--episode", "2"]) == 2  # the store names a pickle
    assert f"name it again to trust it: --policy {saved.resolve()}" in capsys.readouterr().err
    assert main(["replay", str(store), "--episode", "2", "--policy", str(saved)]) == 0
    out = capsys.readouterr().out
    assert "reproduces the stored record" in out and "[node" not in out  # an agent: no nodes


def test_comparison_benchmark_at_small_scale_and_its_reuse(tmp_path, capsys):
    args = ["bench", "compare", "--out", str(tmp_path), "--episodes", "6", "--budgets", "128",
            "--agents", "maskable_ppo:image:0.02", "--seeds", "2", "--n-envs", "1",
            "--tasks", "find_goal"]
    assert main(args + ["--jobs", "2"]) == 0  # the two seeds train in two processes at once
    first = capsys.readouterr().out
    assert first.count("find_goal: trained maskable_ppo-image-bonus0.02 seed") == 2
    rows = json.loads((tmp_path / "compare.json").read_text())
    manifest = sorted(json.loads((tmp_path / "agents" / "manifest.json").read_text()),
                      key=lambda m: m["seed"])
    assert [(m["seed"], m["budget"]) for m in manifest] == [(0, 128), (1, 128)]
    assert all(m["steps_per_second"] > 0 and m["observation"] == "image" for m in manifest)
    agent = "maskable_ppo-image-bonus0.02"
    assert [(r["kind"], r["contestant"], r["seed"], r["train_steps"]) for r in rows] == [
        ("graph", "explore_until_goal", None, None),
        ("synthesized graph", "explore_for_goal", None, None),
        ("random", "uniform admissible", None, None),
        *[("rl", f"{agent} {how}", m["seed"], m["steps"]) for m in manifest
          for how in ("greedy", "sampled")]]
    graphs = [r for r in rows if "graph" in r["kind"]]
    assert all(r["successes"] == 6 for r in graphs)  # same seeds, the graphs never fail
    assert all(r["episodes_to_certify"] == 59 for r in graphs)  # no failures: vlb plan's 59
    for r in rows:  # an agent's rate is its own failures over N
        rate = 1 - r["successes"] / 6
        assert (r["episodes_to_certify"] == float("inf")) == (rate >= 0.05)
    table = (tmp_path / "compare.md").read_text()
    for how in ("greedy", "sampled"):
        assert f"| find_goal | {agent} {how} | rl | {manifest[0]['steps']} | 2 |" in table
    assert (tmp_path / "compare.png").stat().st_size > 1000
    assert (tmp_path / "compare.csv").read_text().count("\n") == 1 + len(rows)
    assert (tmp_path / "behaviors" / "goal_and_back.json").exists()
    assert "What the data support" in table and "{platform" not in table
    for r in rows[1:]:  # the graph never fails: every failure of the others is "only graph"
        assert len(r["failed"]) == 6 - r["successes"]
        assert f"| {r['seed'] if r['seed'] is not None else '-'} | {6 - r['successes']} | 0 |" \
            in table

    assert all("/" not in m["path"] for m in manifest)  # names beside the manifest
    assert main(args + ["--reuse"]) == 0  # the same agents, verified again, no training
    assert "trained" not in capsys.readouterr().out
    again = json.loads((tmp_path / "compare.json").read_text())
    assert [(r["successes"], r["train_steps"]) for r in again] == \
        [(r["successes"], r["train_steps"]) for r in rows]


@pytest.mark.parametrize("manifest, message", [
    ("{", "the agents' manifest is not JSON"),
    ('{"a": 1}', "is not a JSON list"),
    ("[1]", "entry 0 is not an object"),
    ('[{"task": "find_goal"}]', "entry 0 needs 'agent'"),
    ('[{"task": "find_goal", "agent": "ppo", "seed": true, "budget": 1, "path": "x.zip", '
     '"steps": 1, "wall_seconds": 1}]', "entry 0 needs 'seed'"),
    ('[{"task": "find_goal", "agent": "ppo", "seed": 0, "budget": 1, "path": "/etc/x.zip", '
     '"steps": 1, "wall_seconds": 1}]', "is not the file name of an agent beside the manifest"),
    ("[" * 1000 + "]" * 1000, "nested deeper"),
])
def test_a_bad_manifest_is_a_usage_error_before_any_training(manifest, message, tmp_path,
                                                              capsys):
    (tmp_path / "agents").mkdir()
    (tmp_path / "agents" / "manifest.json").write_text(manifest)
    assert main(["bench", "compare", "--out", str(tmp_path), "--reuse", "--tasks",
                 "find_goal"]) == 2
    captured = capsys.readouterr()
    assert message in captured.err and "manifest.json" in captured.err
    assert "graph" not in captured.out  # refused before anything ran


@pytest.mark.parametrize("spec, message", [
    ("dqn", "ALGO one of"), ("ppo:pixels", "observation must be one of"),
    ("ppo:flat:x", "the bonus is not a number"), ("ppo:image:3", "between 0 and 1"),
    ("ppo:image:0.1:9", "expected ALGO[:OBSERVATION[:BONUS]]"),
    ("a2c:spatial", "the spatial policy needs action masks: use maskable_ppo")])
def test_bad_agent_specs_are_usage_errors(spec, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["bench", "compare", "--agents", spec])
    assert exit_.value.code == 2 and message in capsys.readouterr().err


def test_a_sampled_agent_draws_from_its_distribution_seeded_per_episode(tmp_path):
    """--sample: the draws follow the model's masked probabilities (chi-square against them),
    are admissible, repeat for an episode's seed and differ between seeds."""
    from scipy.stats import chisquare
    import torch

    from vlb_gym.baselines.train import SB3Policy

    saved = train(TASKS["find_goal"], "maskable_ppo", tmp_path, budgets=(128,), n_envs=1,
                  observation="spatial")[0]
    env = gym.make(FIND_GOAL, **TASKS["find_goal"].env_kwargs)
    policy = SB3Policy(saved, env, sample=True)
    obs, _ = env.reset(seed=4)
    policy.reset(seed=11)
    draws = np.array([np.ravel_multi_index(tuple(policy.predict(obs)[0]), (2, 10, 10))
                      for _ in range(4000)])
    imager = policy.imager
    masks = ActionMasks(FlatActions(env)).action_masks()
    with torch.no_grad():
        probs = policy.model.policy.get_distribution(
            policy.model.policy.obs_to_tensor(imager(obs))[0],
            action_masks=masks).distribution.probs[0].double().numpy()
    assert masks[draws].all()
    support = np.flatnonzero(probs > 0)
    counts = np.bincount(draws, minlength=probs.size)[support]
    assert chisquare(counts, probs[support] / probs[support].sum() * counts.sum()).pvalue > 1e-4

    def episode(seed):
        obs, _ = env.reset(seed=4)
        policy.reset(seed=seed)
        return [tuple(policy.predict(obs)[0]) for _ in range(30)]

    assert episode(5) == episode(5) and episode(5) != episode(6)


def test_a_sampled_campaign_replays_from_its_store_and_its_hint(tmp_path, capsys):
    saved = train(TASKS["find_goal"], "maskable_ppo", tmp_path, budgets=(128,), n_envs=1,
                  observation="spatial")[0]
    assert main(["verify", FIND_GOAL, "--policy", str(saved), "--sample", "--episodes", "6",
                 "--epsilon", "0.1", "--report", str(tmp_path / "r.json")]) == 0
    out = capsys.readouterr().out
    report = json.loads((tmp_path / "r.json").read_text())
    assert report["policy"]["kind"] == "sb3_sampled"
    if report["failures"]:  # its hint replays it, drawing the same actions
        hint = shlex.split(out.split("replay one: ")[1].splitlines()[0])
        assert hint[3:5] == ["--sample", "--policy"]
        assert main(hint[1:]) == 0
        assert "rho_B = -1" in capsys.readouterr().out
    store = tmp_path / "sampled.db"
    assert main(["verify", FIND_GOAL, "--policy", str(saved), "--sample", "--episodes", "6",
                 "--epsilon", "0.1", "--store", str(store), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["replay", str(store), "--episode", "3", "--policy", str(saved)]) == 0
    assert "reproduces the stored record" in capsys.readouterr().out
    assert main(["replay", str(store), "--episode", "3", "--policy", str(saved),
                 "--sample"]) == 2
    assert main(["verify", GRID, "--behavior", "explore_until_goal", "--sample", "--episodes",
                 "3", "--epsilon", "0.1"]) == 2
    assert "--sample draws a trained agent's actions: it needs --policy" in \
        capsys.readouterr().err


def test_the_random_floor_draws_uniformly_among_admissible_actions():
    """Policy kind ``random``: each draw admissible, uniform over the admissible set
    (chi-square), the same for an episode's seed, and a campaign runs it."""
    from scipy.stats import chisquare

    from vlb_gym.baselines.random_policy import RandomLoader
    from vlb_gym.baselines.wrappers import admissible_actions

    env = gym.make(FIND_GOAL)
    policy = RandomLoader().load(PolicyRef("random", "admissible"), env)
    env.reset(seed=2)
    policy.reset(seed=9)
    admissible = np.flatnonzero(admissible_actions(env.unwrapped))
    draws = [int(np.ravel_multi_index(tuple(policy.predict(None)[0]), (2, 10, 10)))
             for _ in range(3000)]
    assert set(draws) <= set(admissible)
    counts = np.bincount(draws, minlength=200)[admissible]
    assert chisquare(counts).pvalue > 1e-4
    policy.reset(seed=9)
    again = [int(np.ravel_multi_index(tuple(policy.predict(None)[0]), (2, 10, 10)))
             for _ in range(3000)]
    assert again == draws
    with pytest.raises(ValueError, match="unknown random policy 'uniform'"):
        RandomLoader().load(PolicyRef("random", "uniform"), env)
    report = run_campaign(CampaignConfig(FIND_GOAL, PolicyRef("random", "admissible"), 20, seed=1,
                                         env_kwargs=TASKS["find_goal"].env_kwargs))
    assert report["episodes"] == 20 and report["mean_primitives"] > 19  # the graph needs 19


def test_rows_pair_up_on_their_failed_episodes():
    from vlb_gym.baselines.compare import Row
    from vlb_gym.baselines.pairing import paired, support

    def row(contestant, kind, failed, seed=None):
        return Row("find_goal", contestant, kind, seed, 100, 100 - len(failed), 0.9, 0.9, 59,
                   19.0, None, None, None, 1.0, tuple(failed))

    graph = row("g", "graph", [3, 50])
    worse = row("w", "rl", range(40, 60), seed=0)  # 19 failures the graph has not, 1 shared
    test = paired(graph, worse)
    assert (test["only_graph"], test["only_contestant"]) == (19, 1)
    assert test["graph_better_p"] == pytest.approx(21 / 2 ** 20, rel=1e-9)  # P[Bin(20,.5)>=19]
    assert test["verdict"].startswith("graph more reliable")
    same = paired(graph, row("s", "rl", [3, 50], seed=1))
    assert same["verdict"] == "no difference shown" and same["graph_better_p"] == 1.0
    lines = support([graph, worse, row("w", "rl", [3], seed=1)])
    assert lines == ["- find_goal: w, 2 seed(s): the graph is shown more reliable on 1, w on 0, "
                     "no difference shown on 1"]
    legacy = row("old", "rl", [], seed=0)
    legacy = Row(*[getattr(legacy, f) for f in ("task", "contestant", "kind", "seed",
                                                "episodes")], 90, *[0.9, 0.9, 59, 19.0, None,
                                                                    None, None, 1.0])
    assert support([graph, legacy]) == []  # no failed episodes recorded: nothing to pair


def test_the_comparison_table_rounds_bounds_down():
    from vlb_gym.baselines.compare import Row, markdown

    row = Row("find_goal", "x", "graph", None, 100, 99, 0.96292, 0.99969, 59, 19.0, None,
              None, None, 1.0)
    table = markdown([row], 100, 0)
    assert "| 0.962 | 0.999 |" in table and "0.963" not in table
