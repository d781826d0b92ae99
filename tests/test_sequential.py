"""Sequential verification: the mixture martingale against an independent integral, its decisions
at hand-computed thresholds, error rates by simulation, campaigns and the command line."""

from __future__ import annotations

import json
import math
import sqlite3

import numpy as np
import pytest
from scipy import integrate
from scipy.stats import beta as beta_dist
from scipy.stats import binom

from vlb_gym.cli import main
from vlb_gym.verify import bounds, sequential
from vlb_gym.verify.campaign import CampaignConfig, episode_seed, run_campaign
from vlb_gym.verify.sequential import SequentialTest, confidence_sequence, log_mixture, simulate

from .conftest import EXAMPLES

GRID = "VLB-GridExplore-v0"


def mixture_by_quadrature(s: int, f: int, p: float, a: float, b: float) -> float:
    """M_n(p) = E_{theta ~ Beta(a, b)}[theta^s (1-theta)^f / (p^s (1-p)^f)], integrated."""
    def integrand(theta):
        return beta_dist.pdf(theta, a, b) * math.exp(
            s * math.log(theta / p) + f * (math.log1p(-theta) - math.log1p(-p)))
    value, _ = integrate.quad(integrand, 0, 1, epsabs=0, epsrel=1e-11, limit=200,
                              points=[p, s / (s + f)])
    return value


@pytest.mark.parametrize("s,f,p", [(1, 0, 0.5), (0, 1, 0.95), (3, 2, 0.6), (10, 0, 0.95),
                                   (20, 1, 0.9), (7, 3, 0.95), (40, 0, 0.99)])
def test_mixture_matches_an_independent_integral(s, f, p):
    a, b = sequential.prior(0.05)
    assert math.exp(log_mixture(s, f, p, a, b)) == pytest.approx(
        mixture_by_quadrature(s, f, p, a, b), rel=1e-8)


def test_prior_is_fixed_by_epsilon():
    assert sequential.prior(0.05) == pytest.approx((9.5, 0.5))
    assert sequential.default_max_episodes(0.05, 0.05) == 20 * 59 == 1180


def test_all_successes_certify_at_the_hand_computed_time():
    # B(9.5 + n, 0.5) / B(9.5, 0.5) / 0.95**n >= 20 first at n = 81
    def m(n):
        return mixture_by_quadrature(n, 0, 0.95, 9.5, 0.5)
    assert m(80) < 20 <= m(81)
    test = SequentialTest(0.05, 0.05)
    for n in range(1, 81):
        assert test.update(True) is None, n
    assert test.update(True) == "certified" and test.stopped_at == 81
    low, high = test.bounds()
    assert 0.95 <= low < 0.951 and high == 1.0
    assert 0.95 <= test.confidence() < 0.96
    with pytest.raises(RuntimeError):
        test.update(True)


def test_failures_refute_at_the_hand_computed_time():
    # alternating success/failure: refuted at the first n where M_n(0.95) >= 1/0.05
    stream = [i % 2 == 0 for i in range(100)]
    expected = next(n for n in range(1, 101)
                    if mixture_by_quadrature(sum(stream[:n]), n - sum(stream[:n]), 0.95, 9.5,
                                             0.5) >= 20)
    test = SequentialTest(0.05, 0.05)
    decisions = [test.update(x) for x in stream[:expected]]
    assert decisions[:-1] == [None] * (expected - 1) and decisions[-1] == "refuted"
    assert test.stopped_at == expected and test.bounds()[1] <= 0.95
    assert test.confidence() == 0.0


@pytest.mark.parametrize("s,f", [(1, 0), (0, 3), (5, 5), (14, 6), (81, 0), (300, 9)])
def test_confidence_sequence_ends_are_where_the_mixture_crosses_one_over_delta(s, f):
    a, b = sequential.prior(0.05)
    low, high = confidence_sequence(s, f, 0.05, a, b)
    mle = s / (s + f)
    assert low <= mle <= high
    for end, inside in ((low, math.nextafter(low, 1)), (high, math.nextafter(high, 0))):
        if 0 < end < 1:  # outside (or on) at the end, inside one step in, to 1e-9
            assert log_mixture(s, f, end, a, b) >= math.log(20)
            assert log_mixture(s, f, inside, a, b) == pytest.approx(math.log(20), abs=1e-9)


def reference_run(p: float, seed: int, cap: int) -> tuple[int, int]:
    rng, test, n = np.random.default_rng(seed), SequentialTest(0.05, 0.05), 0
    while n < cap:
        for x in rng.random((1, min(256, cap - n)))[0]:
            n += 1
            if test.update(bool(x < p)):
                return (1 if test.decision == "certified" else -1), n
    return 0, cap


@pytest.mark.parametrize("p", [0.9, 0.95, 0.97])
def test_vectorised_simulation_decides_like_the_test(p):
    for seed in range(10):
        decisions, stops = simulate(p, 0.05, 0.05, 1, 600, np.random.default_rng(seed))
        assert (decisions[0], stops[0]) == reference_run(p, seed, 600)


# p on both sides of 1 - eps = 0.95 (p = 0.95 itself: the claim holds, refuting is the error)
@pytest.mark.parametrize("p", [0.90, 0.93, 0.94, 0.95, 0.97, 0.99, 1.0])
def test_error_rate_stays_within_delta(p):
    eps, delta, runs = 0.05, 0.05, 3000
    decisions, stops = simulate(p, eps, delta, runs, 1180, np.random.default_rng(20240611))
    wrong = int(np.sum(decisions == (1 if p < 1 - eps else -1)))
    # one-sided exact binomial test at level 1e-6 of "error rate <= delta": cannot flake
    assert binom.sf(wrong - 1, runs, delta) > 1e-6, (p, wrong / runs)
    if p == 1.0:
        assert (stops == 81).all() and (decisions == 1).all()
    if p == 0.99:  # far fewer than a fixed-N plan that certifies p = 0.99 as often (254)
        assert (decisions == 1).all() and stops.mean() < 200
    if p == 0.90:
        assert (decisions == -1).mean() > 0.99 and stops.mean() < 300


def test_campaign_certifies_a_behavior_that_never_fails():
    config = CampaignConfig(GRID, "find_goal_and_oscillate", method="sequential")
    seen = []
    report = run_campaign(config, on_episode=seen.append)
    assert report["mode"] == "sequential" and report["decision"] == "certified"
    assert report["stopped_at"] == report["episodes"] == 81 and report["failures"] == 0
    assert [r.index for r in seen] == list(range(81))
    assert [r.seed for r in seen] == [episode_seed(0, i) for i in range(81)]
    assert report["lower_bound"] >= 0.95 and report["confidence"] >= 0.95
    assert report["max_episodes"] == 1180 and report["fixed_n_plan"] == 59
    assert "simultaneously for all n" in report["guarantee"]
    assert report["test"] == sequential.TEST_NAME


def test_campaign_with_workers_decides_on_the_ordered_prefix():
    config = CampaignConfig(GRID, str(EXAMPLES / "fixed_cell.json"), method="sequential")
    one = run_campaign(config, workers=1)
    two = run_campaign(config, workers=2)
    assert one["decision"] == two["decision"] == "refuted"
    for key in ("stopped_at", "episodes", "successes", "failed_episodes", "lower_bound",
                "upper_bound", "confidence"):
        assert one[key] == two[key], key
    assert one["upper_bound"] <= 0.95


def test_campaign_undecided_at_the_cap_certifies_nothing():
    report = run_campaign(CampaignConfig(GRID, "find_goal_and_oscillate", 10,
                                         method="sequential"))
    assert report["decision"] == "undecided" and report["stopped_at"] is None
    assert report["episodes"] == 10 and "nothing is certified" in report["statement"]
    assert report["confidence"] < 0.95 and report["lower_bound"] < 0.95
    assert "no guarantee" in report["fixed_n_description"]["note"]


def test_fixed_n_campaign_never_stops_early():
    report = run_campaign(CampaignConfig(GRID, "find_goal_and_oscillate", 100))
    assert report["episodes"] == 100 and report["mode"] == "fixed-N"


def test_cli_sequential(tmp_path, capsys):
    path = tmp_path / "report.json"
    assert main(["verify", GRID, "--behavior", "find_goal_and_oscillate", "--sequential",
                 "--epsilon", "0.05", "--quiet", "--report", str(path)]) == 0
    out = capsys.readouterr().out
    assert "CERTIFIED after 81 episodes: P[success] >= 0.95 at confidence level 0.95" in out
    assert "Robbins beta-binomial mixture" in out and "Beta(9.5, 0.5)" in out
    low = json.loads(path.read_text())["lower_bound"]
    assert f"P[success] in [{bounds.floor_str(low)}, 1.00000]" in out
    assert main(["verify", GRID, "--behavior", str(EXAMPLES / "fixed_cell.json"),
                 "--sequential", "--epsilon", "0.05", "--quiet"]) == 0
    assert "REFUTED after 20 episodes: P[success] < 0.95" in capsys.readouterr().out
    assert main(["verify", GRID, "--behavior", "find_goal_and_oscillate", "--sequential",
                 "--epsilon", "0.05", "--max-episodes", "5", "--quiet"]) == 0
    assert "UNDECIDED after 5 episodes" in capsys.readouterr().out


@pytest.mark.parametrize("args,words", [
    (["--sequential", "--episodes", "10"], "exclude each other"),
    (["--max-episodes", "10", "--episodes", "10"], "needs --sequential"),
    ([], "--episodes"),
    (["--sequential", "--max-episodes", "0"], "--max-episodes"),
])
def test_cli_sequential_usage_errors(args, words, capsys):
    with pytest.raises(SystemExit) as exit_info:
        code = main(["verify", GRID, "--behavior", "find_goal_and_oscillate", "--epsilon", "0.05",
                     "--quiet", *args])
        raise SystemExit(code)
    assert exit_info.value.code == 2
    assert words in capsys.readouterr().err


def test_a_stored_sequential_campaign_resumes_and_rebuilds_its_report(tmp_path, capsys):
    """A sequential campaign stores the prefix its test saw; an interrupted one (here: its store
    cut back to 30 episodes) resumes where it stopped and ends as an uninterrupted one."""
    store = tmp_path / "seq.db"
    command = ["verify", GRID, "--behavior", "find_goal_and_oscillate", "--sequential",
               "--epsilon", "0.05", "--quiet", "--store", str(store)]
    assert main([*command, "--report", str(tmp_path / "first.json")]) == 0
    first = json.loads((tmp_path / "first.json").read_text())
    assert first["decision"] == "certified" and first["stopped_at"] == 81
    with sqlite3.connect(store) as db:
        assert db.execute("SELECT COUNT(*) FROM episodes").fetchone() == (81,)  # the prefix
        db.execute("DELETE FROM episodes WHERE idx >= 30")
    capsys.readouterr()
    assert main([*command, "--report", str(tmp_path / "resumed.json")]) == 0
    assert "resuming" in capsys.readouterr().err
    resumed = json.loads((tmp_path / "resumed.json").read_text())
    run = ("wall_seconds", "episodes_per_second", "machine")
    assert {k: v for k, v in resumed.items() if k not in run} == \
        {k: v for k, v in first.items() if k not in run}
    assert main(["report", str(store), "--json"]) == 0
    rebuilt = json.loads(capsys.readouterr().out)
    run += ("workers", "backend", "nodes")  # nodes: what the store's steps add
    assert {k: v for k, v in rebuilt.items() if k not in run} == \
        {k: v for k, v in first.items() if k not in run}
    # the same store cannot hold the fixed-N campaign of the same behavior
    assert main(["verify", GRID, "--behavior", "find_goal_and_oscillate", "--episodes", "1180",
                 "--epsilon", "0.05", "--quiet", "--store", str(store)]) == 2
    assert "method: stored 'sequential', now 'fixed-N'" in capsys.readouterr().err
