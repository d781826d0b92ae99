"""rho_B, episodes and campaigns: finished / unfinished / failed episodes, workers, replays."""

from __future__ import annotations

import json

import gymnasium as gym
import numpy as np
import pytest
from scipy.stats import beta, binom

from vlb_gym import RobustnessWrapper, load_behavior
from vlb_gym.wrappers.robustness import behavior_robustness
from vlb_gym.verify import Campaign, CampaignConfig, episode_seed, run_campaign, run_episode

from .conftest import EXAMPLES

REPORT_KEYS = {"env_id", "behavior", "episodes", "successes", "failures", "epsilon", "confidence",
               "delta", "lower_bound", "seed", "sampling_distribution", "failed_episodes"}


class Scripted:
    """A policy that plays fixed actions, then finishes (None) or raises."""

    def __init__(self, actions, then=None):
        self.actions, self.then = actions, then

    def reset(self, seed=None):
        self.left = list(self.actions)

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        if self.left:
            action = self.left.pop(0)
            return (action(obs) if callable(action) else np.asarray(action)), None
        if self.then is not None:
            raise self.then
        return None, None


def sense_here(obs):
    return np.array([0, *np.floor(obs["position"] + 5).astype(int)])


def test_robustness_function():
    assert behavior_robustness(True, [True, True]) == 1
    assert behavior_robustness(True, []) == 1
    assert behavior_robustness(True, [True, False]) == -1
    assert behavior_robustness(False, [True]) == -1


def test_finished_episode_scores_plus_one(grid_env):
    result = run_episode(grid_env, Scripted([sense_here]), seed=0)
    assert (result.rho, result.finished, result.primitives, result.reason) == (1, True, 1, None)


def test_failed_certificate_scores_minus_one(grid_env):
    wrong = lambda obs: sense_here(obs) ^ np.array([0, 1, 0])  # a neighbouring cell  # noqa: E731
    result = run_episode(grid_env, Scripted([sense_here, wrong, sense_here]), seed=0,
                         stop_on_failure=False)
    assert result.rho == -1 and result.finished and result.failed_certificates == 1
    assert "step 2: sense" in result.reason and "not admissible" in result.reason
    stopped = run_episode(grid_env, Scripted([sense_here, wrong, sense_here]), seed=0)
    assert stopped.rho == -1 and stopped.primitives == 2 and not stopped.finished


def test_unfinished_episode_is_truncated_to_minus_one():
    env = RobustnessWrapper(gym.make("VLB-GridExplore-v0", max_episode_steps=3))
    result = run_episode(env, Scripted([sense_here] * 10), seed=0)
    assert result.rho == -1 and not result.finished and result.primitives == 3
    assert "truncated" in result.reason


def test_policy_exception_fails_the_episode_not_the_caller(grid_env):
    result = run_episode(grid_env, Scripted([sense_here], then=KeyError("boom")), seed=0)
    assert result.rho == -1 and "KeyError" in result.reason and "boom" in result.reason


def chained_interrupt() -> SystemError:
    """What a C extension raises when Ctrl-C arrives while it calls back into Python."""
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as interrupt:
            raise SystemError("returned a result with an exception set") from interrupt
    except SystemError as exc:
        return exc


def test_ctrl_c_inside_a_c_extension_interrupts_instead_of_failing_the_episode(grid_env):
    """Seen with Numba: Ctrl-C during a compiled navigate came back as a SystemError, and the
    campaign stored it as a failed episode and went on."""
    with pytest.raises(KeyboardInterrupt):
        run_episode(grid_env, Scripted([sense_here], then=chained_interrupt()), seed=0)


def test_a_system_error_of_its_own_still_fails_only_the_episode(grid_env):
    result = run_episode(grid_env, Scripted([sense_here], then=SystemError("bad")), seed=0)
    assert result.rho == -1 and "SystemError: bad" in result.reason


def test_an_error_raised_while_handling_an_interrupt_is_the_episodes_failure(grid_env):
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt:
            raise ValueError("cleanup failed") from None
    except ValueError as exc:
        error = exc
    result = run_episode(grid_env, Scripted([sense_here], then=error), seed=0)
    assert result.rho == -1 and "ValueError: cleanup failed" in result.reason


def test_wrapper_writes_rho_into_info_on_termination(grid_env):
    env = RobustnessWrapper(gym.make("VLB-GridExplore-v0", max_episode_steps=2))
    obs, _ = env.reset(seed=1)
    _, _, _, truncated, info = env.step(sense_here(obs))
    assert not truncated and "rho_B" not in info
    _, _, _, truncated, info = env.step(sense_here(obs))
    assert truncated and info["rho_B"] == -1 and info["primitives"] == 2
    with pytest.raises(RuntimeError, match="episode has ended"):
        env.step(sense_here(obs))


def test_episode_seeds_are_spawned_children():
    children = np.random.SeedSequence(7).spawn(5)
    expected = [int(c.generate_state(1, dtype=np.uint64)[0]) for c in children]
    assert [episode_seed(7, i) for i in range(5)] == expected
    assert len({episode_seed(0, i) for i in range(5000)}) == 5000


def test_results_do_not_depend_on_workers():
    config = CampaignConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", 24, seed=3,
                            env_kwargs={"action_noise": 2.0})
    with Campaign(config) as campaign:
        one = sorted(campaign.episodes(workers=1), key=lambda r: r.index)
        two = sorted(campaign.episodes(workers=2), key=lambda r: r.index)
    assert [r.outcome() for r in one] == [r.outcome() for r in two]
    assert any(not r.success for r in one) and any(r.success for r in one)


def test_paper_campaign_100_episodes():
    report = run_campaign(CampaignConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", 100,
                                         epsilon=0.05))
    assert REPORT_KEYS <= report.keys()
    assert (report["successes"], report["failures"]) == (100, 0)
    assert round(report["confidence"], 3) == 0.994
    assert report["lower_bound"] == pytest.approx(0.05 ** (1 / 100))
    assert "uniform over the allowable space" in report["sampling_distribution"]


def test_wrong_behavior_gets_failure_tolerant_bound_and_replayable_seeds():
    config = CampaignConfig("VLB-GridExplore-v0", str(EXAMPLES / "fixed_cell.json"), 60,
                            epsilon=0.5, delta=0.1, seed=11)
    report = run_campaign(config)
    n, k = report["episodes"], report["failures"]
    assert 0 < k < n
    assert report["confidence"] == pytest.approx(1 - binom.cdf(k, n, 0.5))
    assert report["lower_bound"] == pytest.approx(beta.ppf(0.1, n - k, k + 1))
    assert len(report["failed_episodes"]) == k
    env = RobustnessWrapper(gym.make("VLB-GridExplore-v0"))
    policy = load_behavior(config.policy.ref, env)
    for failed in report["failed_episodes"][:5]:
        assert failed["seed"] == episode_seed(11, failed["index"])
        replay = run_episode(env, policy, failed["seed"])
        assert replay.rho == -1 and replay.reason == failed["reason"]
        assert "(4, 4)" in replay.reason


def test_campaign_config_rejects_bad_values():
    for kwargs, word in [({"episodes": 0}, "episodes"), ({"epsilon": 1.0}, "epsilon"),
                         ({"delta": 0}, "delta"), ({"seed": -1}, "seed")]:
        base = dict(env_id="VLB-GridExplore-v0", policy="explore_until_goal", episodes=5)
        with pytest.raises(ValueError, match=word):
            CampaignConfig(**{**base, **kwargs})


def _causes(report):
    return {group["cause"]: group["count"] for group in report["failures_by_cause"]}


def test_failures_are_grouped_by_cause_with_replayable_seeds():
    report = run_campaign(CampaignConfig("VLB-GridExplore-v0", str(EXAMPLES / "fixed_cell.json"),
                                         100))
    assert _causes(report) == {"navigate: inadmissible parameter": report["failures"]}
    failed_seeds = {item["seed"] for item in report["failed_episodes"]}
    assert set(report["failures_by_cause"][0]["seeds"]) <= failed_seeds
    noisy = run_campaign(CampaignConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", 100,
                                        env_kwargs={"action_noise": 1.0,
                                                    "max_episode_steps": 25}))
    causes = _causes(noisy)
    assert causes["step bound"] > 0 and causes["navigate: controller failed"] > 0
    assert sum(causes.values()) == noisy["failures"]
    assert [g["count"] for g in noisy["failures_by_cause"]] == sorted(causes.values(),
                                                                      reverse=True)


@pytest.mark.parametrize("guard, cause", [
    ("round(5, -1000000000) > 0", "evaluation budget exceeded"),
    ("[1][5] > 0", "behavior runtime error"),
])
def test_behavior_failures_have_their_own_causes(guard, cause, write_behavior):
    from .conftest import explore_doc

    doc = explore_doc()
    doc["edges"][0]["guard"] = guard
    report = run_campaign(CampaignConfig("VLB-GridExplore-v0", str(write_behavior(doc)), 3))
    assert _causes(report) == {cause: 3}


def test_a_failed_part_of_the_scoop_certificate_is_named():
    report = run_campaign(CampaignConfig("VLB-Scoop-v0", "scoop_repeatedly", 1,
                                         env_kwargs={"delivered_threshold_g": 5000.0}))
    assert _causes(report) == {"scoop: certificate (delivered)": 1}


def test_an_episode_capped_in_primitives_stops_unfinished():
    env = RobustnessWrapper(gym.make("VLB-GridExplore-v0"))
    policy = load_behavior("find_goal_and_oscillate", env)
    capped = run_episode(env, policy, 3, max_primitives=3)
    assert (capped.primitives, capped.finished, capped.rho) == (3, False, -1)
    assert capped.cause == "primitive limit" and capped.error is None
    whole = run_episode(env, policy, 3)
    assert whole.finished and whole.primitives > 3
    exactly = run_episode(env, policy, 3, max_primitives=whole.primitives)
    assert exactly.finished and exactly.rho == 1  # finishing on the cap is finishing
    with pytest.raises(ValueError, match="max_primitives"):
        run_episode(env, policy, 3, max_primitives=-1)
    assert [s["param"] for s in whole.steps[:3]] == [s["param"] for s in capped.steps]


def test_the_dry_run_accepts_failed_certificates_and_refuses_errors(tmp_path):
    from vlb_gym.abstractor.validate import dry_run
    from vlb_gym.core.library import compile_for
    from vlb_gym.core.spec import BehaviorSpecError

    env = gym.make("VLB-GridExplore-v0")
    dry_run(compile_for(str(EXAMPLES / "fixed_cell.json"), env), env)  # fails, but is valid
    doc = json.loads((EXAMPLES / "fixed_cell.json").read_text())
    doc["edges"] = [{**edge, "guard": "1 / (len(explored()) - len(explored())) > 0"}
                    for edge in doc["edges"]]
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(BehaviorSpecError, match=r"^dry run from reset seed 0, before primitive "
                                                r"2: .*ZeroDivisionError") as err:
        dry_run(compile_for(str(path), env), env)
    assert err.value.layer == "dry-run"


def test_the_failures_left_out_of_a_summary_say_where_they_are_listed(tmp_path, capsys):
    from vlb_gym.cli import main

    args = ["verify", "VLB-GridExplore-v0", "--behavior",
            str(EXAMPLES / "sense_promises_goal.json"),
            "--episodes", "20", "--epsilon", "0.1"]
    for extra, where in (([], "(--report FILE lists them all)"),
                         (["--store", str(tmp_path / "s.db")], "listed by: vlb report "),
                         (["--report", str(tmp_path / "r.json")], f"listed in {tmp_path}")):
        assert main(args + extra) == 0
        line = next(x for x in capsys.readouterr().out.splitlines() if "more failed" in x)
        assert where in line and "in the report" not in line
