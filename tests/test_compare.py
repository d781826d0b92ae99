"""Paired comparisons (``vlb compare``): the tests against independent computations, their error
rates under continuous monitoring, the pairing, the store, and the command line."""

from __future__ import annotations

import itertools
from pathlib import Path
import json
import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vlb_gym.cli import main
from vlb_gym.verify import paired, paired_methods
from vlb_gym.verify.campaign import CampaignConfig, episode_seed, run_campaign
from vlb_gym.verify.comparison import Comparison, ComparisonConfig, report_from_store
from vlb_gym.verify.paired import PairCounts
from vlb_gym.verify.store import CampaignStore, ComparisonStore

GRID = "VLB-GridExplore-v0"
SHORT = {"max_episode_steps": 10}  # explore_until_goal then fails about 6 times in 10


def trinomial(n: int, a: int, b: int, p_a: float, p_b: float) -> float:
    """P[a_only = a, b_only = b] for n pairs, from the multinomial formula."""
    rest = 1.0 - p_a - p_b
    return (math.comb(n, a) * math.comb(n - a, b) * p_a ** a * p_b ** b
            * rest ** (n - a - b))


# ------------------------------------------------------------------------------- statistics


@pytest.mark.parametrize("a_only, b_only", [(0, 0), (3, 12), (12, 3), (5, 5), (0, 9)])
def test_mcnemar_is_the_binomial_tail_of_the_discordant_pairs(a_only, b_only):
    m = a_only + b_only
    expected = sum(math.comb(m, k) for k in range(b_only, m + 1)) / 2 ** m if m else 1.0
    assert paired.mcnemar_p(PairCounts(50, a_only, b_only, 7)) == pytest.approx(expected,
                                                                                  rel=1e-12)


def test_the_tail_of_the_difference_is_the_trinomial_sum():
    n, d0 = 12, -0.1
    for s in (0.15, 0.4, 0.9):
        p_b, p_a = (s + d0) / 2, (s - d0) / 2
        for t in (-3, 0, 2, 5):
            expected = sum(trinomial(n, a, b, p_a, p_b)
                           for a in range(n + 1) for b in range(n + 1 - a) if b - a >= t)
            got = paired._tails(n, t, np.array([d0]), np.array([s]))[0]
            assert got == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("n, margin", [(20, 0.1), (30, 0.05)])
def test_the_unconditional_test_holds_its_level_everywhere_in_the_null(n, margin):
    """The exact size of 'reject when the p-value <= alpha', summed over every outcome, at
    points of the null's boundary and inside it."""
    alpha, d0 = 0.05, -margin
    rejected = [(a, b) for a in range(n + 1) for b in range(n + 1 - a)
                if paired.unconditional_p(PairCounts(n - a - b, a, b, 0), d0) <= alpha]
    assert rejected  # the test can reject at all
    worst = 0.0
    for p_a in np.linspace(margin, 0.95, 24):
        for shift in (0.0, 0.05, 0.2):  # on the boundary, then inside the null
            p_b = p_a + d0 - shift
            if p_b < 0 or p_a + p_b > 1:
                continue
            worst = max(worst, sum(trinomial(n, a, b, p_a, p_b) for a, b in rejected))
    assert worst <= alpha


def test_mcnemar_holds_its_level_exactly():
    n, alpha = 25, 0.05
    rejected = [(a, b) for a in range(n + 1) for b in range(n + 1 - a)
                if paired.mcnemar_p(PairCounts(n - a - b, a, b, 0)) <= alpha]
    for p in np.linspace(0.01, 0.5, 20):  # P[only A] = P[only B] = p
        assert sum(trinomial(n, a, b, p, p) for a, b in rejected) <= alpha


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 30), st.integers(0, 30), st.integers(0, 30),
       st.floats(-0.9, 0.9), st.floats(0.0, 0.05))
def test_the_wealth_falls_as_the_null_value_rises(a_only, b_only, concordant, d0, step):
    counts = PairCounts(concordant, a_only, b_only, 0)
    assert paired.log_wealth(counts, d0 + step, "below") <= \
        paired.log_wealth(counts, d0, "below") + 1e-12
    assert paired.log_wealth(counts, d0 + step, "above") >= \
        paired.log_wealth(counts, d0, "above") - 1e-12


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 40), st.integers(0, 40), st.integers(0, 200))
def test_intervals_hold_the_estimate_and_the_sequential_is_the_wider(a_only, b_only, both):
    counts = PairCounts(both, a_only, b_only, 3)
    estimate = (b_only - a_only) / counts.n
    low, high = paired.anytime_bounds(counts, 0.05)
    assert -1 <= low <= estimate <= high <= 1
    threshold = -math.log(0.05)
    assert paired.log_wealth(counts, low + 1e-5, "below") < threshold  # just inside: kept
    if low > -1 + 1e-5:
        assert paired.log_wealth(counts, low - 1e-5, "below") >= threshold


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 30), st.integers(0, 80), st.integers(0, 150))
def test_the_fixed_n_interval_holds_the_estimate(a_only, b_only, both):
    counts = PairCounts(both, a_only, b_only, 2)
    low, high = paired.unconditional_bounds(counts, 0.05)
    estimate = (b_only - a_only) / counts.n
    assert -1 <= low <= estimate + 1e-4 and estimate - 1e-4 <= high <= 1


def test_the_unconditional_p_value_grows_with_the_null_value():
    counts = PairCounts(127, 0, 73, 0)
    values = [paired.unconditional_p(counts, d0) for d0 in np.linspace(-0.5, 0.9, 15)]
    assert values == sorted(values)
    low, high = paired.unconditional_bounds(counts, 0.05)
    assert low < 73 / 200 < high


@pytest.mark.parametrize("probabilities, margin", [
    ((0.80, 0.05, 0.05, 0.10), 0.0),   # superiority, equal and rarely discordant
    ((0.40, 0.25, 0.25, 0.10), 0.0),   # superiority, often discordant
    ((0.90, 0.06, 0.01, 0.03), 0.05),  # non-inferiority on the boundary P_B = P_A - 0.05
])
def test_wrong_decisions_stay_below_alpha_under_continuous_monitoring(probabilities, margin):
    """10^4 paired streams at the null, the test looking after every pair, 1,000 pairs each:
    'shown' is wrong there, and so is 'refuted' (the truth is on the boundary)."""
    alpha = 0.05
    decisions, _ = paired.simulate(probabilities, margin, alpha, 10_000, 1000,
                                   np.random.default_rng(7))
    assert (decisions == 1).mean() <= alpha
    assert (decisions == -1).mean() <= alpha


def test_the_simulation_decides_as_the_method_does():
    rng = np.random.default_rng(3)
    outcomes = rng.choice(4, size=(40, 300), p=[0.7, 0.05, 0.2, 0.05])
    decisions, stops = paired.simulate((0, 0, 0, 0), 0.0, 0.05, 40, 300, outcomes=outcomes)
    for row, decision, stop in zip(outcomes, decisions, stops):
        method = paired_methods.SequentialPairs(0.0, 0.05, 300)
        method.feed(((kind in (0, 1)), (kind in (0, 2))) for kind in row)
        assert method.counts.n == stop
        assert {"shown": 1, "refuted": -1, None: 0}[method.decision] == decision


def test_a_sequential_plan_that_cannot_decide_says_so():
    method = paired_methods.SequentialPairs(0.0, 0.05, 5)
    assert method.earliest_decision() > 5
    assert "nothing can be shown" in method.caveats()[0]
    assert paired_methods.SequentialPairs(0.0, 0.05, 100).caveats() == []


@pytest.mark.parametrize("margin, alpha, pairs", [(-0.1, 0.05, 10), (1.0, 0.05, 10),
                                                 (0.1, 0.0, 10), (0.1, 0.05, 0),
                                                 (0.0, 0.5, 10), (0.0, 0.6, 10)])
def test_bad_settings_are_refused(margin, alpha, pairs):
    with pytest.raises(ValueError):
        paired_methods.FixedPairs(margin, alpha, pairs)


@given(margin=st.floats(1e-9, 0.999, allow_nan=False))
def test_the_claim_states_the_margin_exactly_as_given(margin):
    """Rounded, a margin would state another claim (0.01234561 shown as 0.0123456 claims
    more): the words carry the number that round-trips to it."""
    words = paired.claim_words(margin)
    shown = re.search(r"P_A - (\S+)\)", words).group(1)
    assert float(shown) == margin


def test_cli_alpha_of_one_half_or_more_is_one_error_line(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["compare", GRID, "explore_until_goal", "explore_until_goal", "--pairs", "5",
              "--alpha", "0.6"])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and "0.6 is not below 0.5" in err
    assert len(err.strip().splitlines()) == 1


# ------------------------------------------------------------------------------- comparisons


def test_pairs_share_their_reset_seeds_and_each_side_is_its_own_campaign():
    config = ComparisonConfig(GRID, "explore_until_goal", "explore_until_goal", 40, seed=3,
                              b_env_kwargs=SHORT)
    with Comparison(config) as comparison:
        pairs = list(comparison.pairs())
        report = comparison.run()
    assert [(p.a.seed, p.b.seed) for p in pairs] == [(episode_seed(3, i),) * 2
                                                     for i in range(40)]
    alone = run_campaign(CampaignConfig(GRID, "explore_until_goal", 40, seed=3,
                                        env_kwargs=SHORT))
    assert report["b"]["successes"] == alone["successes"]
    assert report["a"]["successes"] == 40
    counts = report["counts"]
    assert counts["a_only"] == 40 - alone["successes"] and counts["b_only"] == 0
    assert [d["index"] for d in report["discordant_pairs"]] == \
        [e["index"] for e in alone["failed_episodes"]]
    assert report["decision"] == "refuted" and report["p_value"] == 1.0  # B is worse
    low, high = report["interval"]
    assert low <= report["difference"] <= high < 0


def test_a_sequential_comparison_is_the_same_on_every_backend():
    config = ComparisonConfig(GRID, "explore_until_goal", "explore_until_goal", 400,
                              a_env_kwargs=SHORT, method="sequential")
    reports = []
    for workers in (1, 2):
        with Comparison(config) as comparison:
            reports.append(comparison.run(workers))
    one, two = reports
    assert one["decision"] == two["decision"] == "shown"  # B (no step bound) is better
    assert one["pairs"] == two["pairs"] == one["stopped_at"] < 400
    assert one["counts"] == two["counts"] and one["interval"] == two["interval"]
    assert one["discordant_pairs"] == two["discordant_pairs"]


def test_a_stored_comparison_resumes_to_the_uninterrupted_report(tmp_path):
    config = ComparisonConfig(GRID, "explore_until_goal", "explore_until_goal", 30,
                              b_env_kwargs=SHORT)
    with Comparison(config) as comparison:
        whole = comparison.run()
        store = ComparisonStore(tmp_path / "c.db")
        store.start(comparison.plan)
        for pair in itertools.islice(comparison.pairs(), 12):  # killed after 12 pairs
            store.add(pair)
        store.close()
        store = ComparisonStore(tmp_path / "c.db")
        resumed = comparison.run(store=store)
        store.close()
    reader = ComparisonStore(tmp_path / "c.db", readonly=True)
    rebuilt = report_from_store(reader)
    reader.close()
    keys = ("counts", "interval", "p_value", "decision", "discordant_pairs", "a", "b")
    for report in (resumed, rebuilt):
        assert {k: report[k] for k in keys} == {k: whole[k] for k in keys}


def test_a_store_of_one_kind_is_never_read_as_the_other(tmp_path):
    with Comparison(ComparisonConfig(GRID, "explore_until_goal", "explore_until_goal",
                                     3)) as comparison:
        store = ComparisonStore(tmp_path / "c.db")
        comparison.run(store=store)
        store.close()
    with pytest.raises(ValueError, match="not a vlb-gym campaign store .it is a comparison"):
        CampaignStore(tmp_path / "c.db")
    run_campaign(CampaignConfig(GRID, "explore_until_goal", 3),
                 store=(campaign := CampaignStore(tmp_path / "v.db")))
    campaign.close()
    with pytest.raises(ValueError, match="not a vlb-gym comparison store .it is a campaign"):
        ComparisonStore(tmp_path / "v.db")


# ------------------------------------------------------------------------------- the command


@pytest.mark.parametrize("margin", ["0", "0.05"])
def test_a_fixed_n_refutation_states_what_was_shown_with_its_own_p_value(capsys, margin):
    """B far worse than A: the line says B is shown less reliable, with the mirrored test's
    p-value (tiny), not the claim's (near 1)."""
    assert main(["compare", GRID, "explore_until_goal", "explore_until_goal", "--pairs", "30",
                 "--b-env-kwarg", "max_episode_steps=10", "--margin", margin, "--quiet"]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if "REFUTED" in x)
    assert line.startswith("  REFUTED: B is less reliable than A") and "is shown" in line
    assert ("by more than 0.05 (P_B < P_A - 0.05)" in line) == (margin != "0")
    shown_p = float(re.search(r"mirrored, p = ([0-9.e-]+)", line).group(1))
    assert shown_p <= 0.05 and "refuting: B is" in line


def test_vlb_compare_writes_its_report_and_vlb_report_reads_the_store(tmp_path, capsys):
    args = ["compare", GRID, "explore_until_goal", "explore_until_goal", "--sequential",
            "--b-env-kwarg", "max_episode_steps=10", "--store", str(tmp_path / "c.db"),
            "--report", str(tmp_path / "c.json"), "--quiet"]
    assert main(args) == 0
    out = capsys.readouterr()
    assert "REFUTED after" in out.out and "B is less reliable than A" in out.out
    assert "replay B's failure: vlb replay VLB-GridExplore-v0 --behavior explore_until_goal" \
        in out.out
    assert "A and B run on different envs" in out.err
    report = json.loads((tmp_path / "c.json").read_text())
    assert report["decision"] == "refuted" and report["counts"]["b_only"] == 0
    assert main(["report", str(tmp_path / "c.db"), "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["counts"] == report["counts"] and again["interval"] == report["interval"]
    assert main(args) == 0  # decided already: the store answers, no pair runs again
    assert "resuming" in capsys.readouterr().err


def one_line_error(capsys, *words):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("vlb compare: error: "), err
    for word in words:
        assert word in err, err


@pytest.mark.parametrize("extra, message", [
    ([], "--pairs (or --sequential)"),
    (["--pairs", "5", "--sequential"], "exclude each other"),
    (["--pairs", "5", "--max-pairs", "9"], "--max-pairs needs --sequential"),
    (["--pairs", "5", "--a-sample"], "--a-sample draws a trained agent's actions"),
    (["--pairs", "5", "--b-env-kwarg", "nope"], "expected NAME=VALUE"),
])
def test_bad_command_lines_are_one_line_errors(extra, message, capsys):
    assert main(["compare", GRID, "explore_until_goal", "explore_until_goal", *extra]) == 2
    one_line_error(capsys, message)


def test_an_unknown_side_is_named_as_given(capsys):
    assert main(["compare", GRID, "explore_until_goal", "no_such_one", "--pairs", "3"]) == 2
    one_line_error(capsys, "no_such_one")


@pytest.mark.parametrize("margin", ["1", "-0.1", "x"])
def test_a_bad_margin_is_refused(margin, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["compare", GRID, "a", "b", "--pairs", "3", "--margin", margin])
    assert exit_.value.code == 2


def test_a_behavior_against_a_trained_agent(tmp_path, capsys):
    from vlb_gym.baselines.configs import TASKS
    from vlb_gym.baselines.train import train

    agent = train(TASKS["find_goal"], "maskable_ppo", tmp_path, budgets=(128,), n_envs=1)[0]
    assert main(["compare", "VLB-GridExplore-FindGoal-v0", "explore_until_goal", str(agent),
                 "--pairs", "30", "--margin", "0.1", "--report", str(tmp_path / "r.json"),
                 "--quiet"]) == 0
    report = json.loads((tmp_path / "r.json").read_text())
    assert report["b"]["policy"]["kind"] == "sb3"
    assert report["a"]["successes"] == 30  # the graph finds a goal every time
    assert report["b"]["env_kwargs"] == {"max_episode_steps": 200}  # the agent's training env
    assert report["decision"] in ("not shown", "refuted")
    assert report["counts"]["a_only"] == 30 - report["b"]["successes"]


# ------------------------------------------------------------------------------- review round


@pytest.mark.parametrize("margin", [0.0, 0.1])
def test_mirrored_pairs_give_mirrored_verdicts(margin):
    for n, a_only, b_only in [(5, 0, 4), (8, 1, 6), (13, 0, 5), (20, 5, 13), (20, 0, 6)]:
        counts = PairCounts(n - a_only - b_only, a_only, b_only, 0)
        mirror = PairCounts(n - a_only - b_only, b_only, a_only, 0)
        one, other = (paired_methods.FixedPairs(margin, 0.05, n) for _ in range(2))
        for method, c in ((one, counts), (other, mirror)):
            method.feed([(True, True)] * c.both + [(True, False)] * c.a_only
                        + [(False, True)] * c.b_only)
        if margin == 0:
            assert (one.claim()["decision"] == "shown") == (other.claim()["decision"] == "refuted")


def sequential_store(tmp_path):
    store = tmp_path / "seq.db"
    assert main(["compare", GRID, "explore_until_goal", "explore_until_goal", "--sequential",
                 "--b-env-kwarg", "max_episode_steps=10", "--store", str(store),
                 "--quiet"]) == 0
    return store


def test_a_report_refuses_a_sequential_store_that_resume_refuses(tmp_path, capsys):
    import sqlite3

    store = sequential_store(tmp_path)
    with sqlite3.connect(store) as db:
        db.execute("DELETE FROM episodes WHERE idx IN (1, 3)")
    db.close()
    capsys.readouterr()
    assert main(["report", str(store)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "are not the first" in err


def _edit_comparison_plan(store, change) -> None:
    import sqlite3

    with sqlite3.connect(store) as db:
        plan = json.loads(db.execute("SELECT plan FROM plan").fetchone()[0])
        change(plan)
        db.execute("UPDATE plan SET plan = ?", (json.dumps(plan),))
    db.close()


def test_a_stored_level_too_small_for_floating_point_is_refused(tmp_path, capsys):
    store = sequential_store(tmp_path)
    _edit_comparison_plan(store, lambda plan: plan.update(alpha=1e-300))
    capsys.readouterr()
    assert main(["report", str(store)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "too small" in err


def test_a_forged_line_in_a_store_stays_on_its_line(tmp_path, capsys):
    store = sequential_store(tmp_path)

    def forge(plan):
        plan["a"]["sampling_distribution"] += "\r\n  SHOWN after 3 pairs: forged"
    _edit_comparison_plan(store, forge)
    capsys.readouterr()
    assert main(["report", str(store)]) == 0
    out = capsys.readouterr().out
    assert "\r" not in out and "\n  SHOWN after 3 pairs: forged" not in out
    assert "\\r\\n  SHOWN after 3 pairs: forged" in out


@pytest.mark.parametrize("extra, message", [
    (["--a-env-kwarg", "=1"], "--a-env-kwarg '=1': expected NAME=VALUE"),
    (["--b-env-kwarg", "n_goals=0"], "B: "),
    (["--report", ""], "--report: the path is empty"),
    (["--store", ""], "--store: the path is empty"),
])
def test_what_is_wrong_is_named_with_its_option_and_side(extra, message, capsys):
    assert main(["compare", GRID, "explore_until_goal", "explore_until_goal", "--pairs", "3",
                 "--quiet", *extra]) == 2
    one_line_error(capsys, message)


def test_an_error_is_one_line_whatever_the_file_name_or_the_number_of_problems(tmp_path,
                                                                              capsys):
    assert main(["compare", GRID, str(tmp_path / "no\nsuch.json"), "explore_until_goal",
                 "--pairs", "2"]) == 2
    one_line_error(capsys, "no\\nsuch.json")
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"name": 1, "nodes": 2, "edges": 3}))
    assert main(["compare", GRID, str(bad), "explore_until_goal", "--pairs", "2"]) == 2
    one_line_error(capsys, "bad.json")


def test_notes_come_only_when_the_command_can_run(tmp_path, capsys):
    """A note about the sides (or a warning about the plan) never precedes an error."""
    behavior = tmp_path / "mine.json"
    behavior.write_text(json.dumps(json.loads(
        (Path(__file__).resolve().parent.parent / "vlb_gym" / "behaviors"
         / "explore_until_goal.json").read_text())))
    assert main(["compare", GRID, str(behavior), "explore_until_goal", "--sequential",
                 "--max-pairs", "3", "--b-env-kwarg", "action_noise=0.5",
                 "--report", str(behavior)]) == 2
    one_line_error(capsys, "is an input of this command")


def test_a_store_of_the_first_comparison_format_is_read_and_resumed(tmp_path, capsys):
    """Stores written before each side's plan was a whole campaign plan (the sides held only
    what they are run on) are read, reported and resumed alike."""
    store = sequential_store(tmp_path)
    capsys.readouterr()
    assert main(["report", str(store), "--json"]) == 0
    before = json.loads(capsys.readouterr().out)

    def first_format(plan):
        for side in ("a", "b"):
            for key in ("env_id", "episodes", "epsilon", "delta", "seed", "method"):
                del plan[side][key]
    _edit_comparison_plan(store, first_format)
    assert main(["report", str(store), "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    for key in ("pairs", "counts", "decision", "a", "b", "discordant_pairs"):
        assert again[key] == before[key], key
    assert main(["compare", GRID, "explore_until_goal", "explore_until_goal", "--sequential",
                 "--b-env-kwarg", "max_episode_steps=10", "--store", str(store),
                 "--quiet"]) == 0  # the same plan: resumed


@pytest.mark.parametrize("change", [lambda p: p["a"].update(episodes=1),
                                    lambda p: p["b"].update(seed=p["seed"] + 1),
                                    lambda p: p["a"].update(env_id="Other-v0"),
                                    lambda p: p["b"].update(method="sequential")])
def test_a_side_that_is_not_the_comparisons_is_refused(tmp_path, capsys, change):
    store = sequential_store(tmp_path)
    _edit_comparison_plan(store, change)
    capsys.readouterr()
    assert main(["report", str(store)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "the stored plan is not valid" in err, err


@pytest.mark.parametrize("n", [2500, 6000])
def test_the_truncated_sum_bounds_the_whole_one_from_above_and_closely(n, monkeypatch):
    """Above WHOLE_SUM_PAIRS the exact test's tail sums only the discordant counts that carry
    mass and adds the rest as if each gave the tail: never below the whole sum, within 3e-13."""
    s = np.linspace(0.05, 0.09, 50)
    d = np.minimum(0.01, s)
    for t in (-30, 0, 25, 60):
        monkeypatch.setattr(paired, "WHOLE_SUM_PAIRS", 10 ** 9)
        whole = paired._tails(n, t, d, s)
        monkeypatch.setattr(paired, "WHOLE_SUM_PAIRS", 2000)
        truncated = paired._tails(n, t, d, s)
        assert (truncated >= whole - 1e-14).all() and (truncated - whole).max() <= 3e-13


def test_an_interval_of_80000_pairs_is_computed_and_holds_the_observed_difference():
    counts = PairCounts(both=70_000, a_only=1_300, b_only=1_700, neither=7_000)
    low, high = paired.unconditional_bounds(counts, 0.05)
    assert low < (1_700 - 1_300) / 80_000 < high and high - low < 0.005
