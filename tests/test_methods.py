"""The statistical-method interface: fixed-N and sequential are two methods of one interface,
and a third plugs in (here a toy one, registered for the test) without touching the campaign,
the store or the report."""

from __future__ import annotations

import json
import sqlite3
from typing import Any

import pytest
from scipy.stats import beta, binom

from vlb_gym.verify import bounds
from vlb_gym.verify.campaign import CampaignConfig, report_from_store, run_campaign
from vlb_gym.cli import main
from vlb_gym.verify.methods import METHODS, FixedN, Method, Sequential, method_named, register
from vlb_gym.verify.report import Report
from vlb_gym.verify.store import CampaignStore, StoreError

from .conftest import EXAMPLES

GRID = "VLB-GridExplore-v0"
FIXED_CELL = str(EXAMPLES / "fixed_cell.json")  # fails now and then: both outcomes occur


class UntilFailures(Method):
    """A toy method: stop at the second failure; claims nothing beyond the counts."""

    name = "until-2-failures"
    stops_early = True

    @classmethod
    def default_episodes(cls, epsilon: float, delta: float) -> int:
        return 50

    @property
    def decided(self) -> bool:
        return self.failures >= 2 or self.n >= self.episodes

    def claim(self) -> dict[str, Any]:
        return {"complete": self.decided, "confidence": 0.0, "lower_bound": 0.0,
                "statement": f"stopped at failure 2 after {self.n} episodes"}

    @staticmethod
    def lines(report):
        return [f"  TOY: {report['statement']}"]


@pytest.fixture
def toy(monkeypatch):
    monkeypatch.setitem(METHODS, UntilFailures.name, None)  # removed again after the test
    assert register(UntilFailures) is UntilFailures
    return UntilFailures


def test_a_third_method_plugs_in_and_rebuilds_from_its_store(toy, tmp_path, capsys):
    config = CampaignConfig(GRID, FIXED_CELL, method=toy.name)
    assert config.episodes == 50  # the method's default N
    store = CampaignStore(tmp_path / "toy.db")
    try:
        report = run_campaign(config, workers=2, store=store)
    finally:
        store.close()
    assert report["mode"] == toy.name and report["failures"] == 2
    indices = [e["index"] for e in report["failed_episodes"]]
    assert report["episodes"] == indices[-1] + 1  # the ordered prefix up to the 2nd failure
    assert report.summary().splitlines()[2] == f"  TOY: {report['statement']}"
    rebuilt = report_from_store(CampaignStore(tmp_path / "toy.db", readonly=True))
    for key in ("episodes", "failures", "statement", "failed_episodes", "complete"):
        assert rebuilt[key] == report[key], key
    with sqlite3.connect(tmp_path / "toy.db") as db:  # keep the first two: resume the rest
        db.execute("DELETE FROM episodes WHERE idx >= 2")
    store = CampaignStore(tmp_path / "toy.db")
    try:
        resumed = run_campaign(config, store=store)
    finally:
        store.close()
    for key in ("episodes", "failures", "statement", "failed_episodes", "complete"):
        assert resumed[key] == report[key], key
    # the CLI and the report folder speak of it in its own words, told nothing about it
    assert main(["report", str(tmp_path / "toy.db"), "--out", str(tmp_path / "out")]) == 0
    assert report["statement"] in (tmp_path / "out" / "report.md").read_text()
    assert main(["report", str(tmp_path / "toy.db")]) == 0
    assert f"  TOY: {report['statement']}" in capsys.readouterr().out


@pytest.mark.parametrize("n, k", [(59, 0), (100, 3), (7, 7)])
def test_fixed_n_claims_the_binomial_tail_and_clopper_pearson(n, k):
    method = FixedN(0.05, 0.05, n)
    assert method.feed([False] * k + [True] * (n - k)) == n and method.decided
    claim = method.claim()
    assert claim["confidence"] == pytest.approx(1 - binom.cdf(k, n, 0.05))
    assert claim["lower_bound"] == pytest.approx(0.0 if k == n else beta.ppf(0.05, n - k, k + 1))
    assert claim["complete"] and "Clopper-Pearson" in claim["statement"]


def test_sequential_decides_and_stops_taking_episodes():
    method = Sequential(0.05, 0.05, 1000)
    assert method.feed([True] * 500) == 81 and method.decided  # certified at 81 (README)
    assert method.claim()["decision"] == "certified"
    with pytest.raises(RuntimeError, match="decided already"):
        method.observe(True)


def test_unknown_methods_are_refused_by_name():
    with pytest.raises(ValueError, match="unknown statistical method 'bayes'.*fixed-N"):
        method_named("bayes")
    with pytest.raises(ValueError, match="unknown statistical method"):
        CampaignConfig(GRID, FIXED_CELL, 10, method="bayes")


def test_a_store_that_names_an_unknown_method_is_refused(tmp_path):
    path = tmp_path / "s.db"
    store = CampaignStore(path)
    run_campaign(CampaignConfig(GRID, FIXED_CELL, 3), store=store)
    store.close()
    with sqlite3.connect(path) as db:
        plan = json.loads(db.execute("SELECT plan FROM plan").fetchone()[0])
        db.execute("UPDATE plan SET plan = ?", (json.dumps({**plan, "method": "magic"}),))
    with pytest.raises(StoreError, match="stored plan is not valid.*method.*magic"):
        CampaignStore(path, readonly=True).plan()


@pytest.mark.parametrize("legacy, method", [(False, "fixed-N"), (True, "sequential")])
def test_a_store_written_before_methods_had_names_resumes(tmp_path, legacy, method):
    path = tmp_path / "old.db"
    config = CampaignConfig(GRID, FIXED_CELL, 20, method=method)
    store = CampaignStore(path)
    fresh = run_campaign(config, store=store)
    store.close()
    with sqlite3.connect(path) as db:
        plan = json.loads(db.execute("SELECT plan FROM plan").fetchone()[0])
        del plan["method"]
        db.execute("UPDATE plan SET plan = ?", (json.dumps({**plan, "sequential": legacy}),))
    store = CampaignStore(path)
    try:
        again = run_campaign(config, store=store)  # the same plan: resumed, nothing rerun
    finally:
        store.close()
    assert again["mode"] == method and again["episodes"] == fresh["episodes"]
    assert again["statement"] == fresh["statement"]


def test_report_words_come_from_the_method():
    plan_report = Report({"mode": "fixed-N", "epsilon": 0.05, "delta": 0.05, "complete": True,
                          "confidence": 0.951, "lower_bound": 0.9491}, None)
    assert FixedN.lines(plan_report) == [
        "  P[success] >= 0.95 with confidence 0.95100",
        f"  P[success] >= {bounds.floor_str(0.9491)} at confidence level 0.95 "
        "(one-sided Clopper-Pearson)"]


@pytest.mark.parametrize("n, k, eps", [(100, 0, 0.05), (4000, 78, 0.05), (59, 2, 0.1),
                                       (10**6, 0, 0.05)])
def test_the_miss_probability_is_the_exact_complement_and_never_saturates(n, k, eps):
    exact = binom.cdf(k, n, eps)
    assert bounds.miss_probability(n, k, eps) == pytest.approx(exact, rel=1e-9, abs=1e-300)
    claim = FixedN(eps, 0.05, n)
    claim.feed([False] * k + [True] * (n - k))
    assert claim.claim()["miss_probability"] == pytest.approx(exact, rel=1e-9, abs=1e-300)
    if n == 4000:  # the case that printed confidence 1.0 in JSON
        assert 0 < claim.claim()["miss_probability"] < 1e-15


def test_an_incomplete_fixed_n_campaign_prints_no_guarantee():
    method = FixedN(0.05, 0.05, 4000)
    method.feed([True] * 640)
    claim = method.claim()
    assert not claim["complete"] and claim["statement"].startswith("no guarantee")
    report = {"complete": False, "planned_episodes": 4000}
    lines = FixedN.lines(report)
    assert len(lines) == 1 and "no guarantee" in lines[0] and "confidence" not in lines[0]


def test_a_cap_below_the_first_possible_certification_is_said_before_running():
    assert Sequential(0.05, 0.05, 1180).earliest_certification() == 81
    assert Sequential(0.05, 0.05, 1180).caveats() == []
    (caveat,) = Sequential(0.05, 0.05, 70).caveats()
    assert "nothing can be certified" in caveat and "before episode 81" in caveat


def test_vlb_verify_warns_of_a_cap_that_cannot_certify(capsys):
    from vlb_gym.cli import main

    assert main(["verify", GRID, "--behavior", "find_goal_and_oscillate", "--sequential",
                 "--max-episodes", "70", "--epsilon", "0.05", "--quiet"]) == 0
    captured = capsys.readouterr()
    assert "vlb verify: warning: with at most 70 episodes nothing can be certified" in \
        captured.err
    assert "UNDECIDED after 70 episodes" in captured.out
    assert "A rerun with another seed is a new test" in captured.out


def test_a_sequential_store_with_a_gap_is_refused_in_one_line(tmp_path, capsys):
    from vlb_gym.cli import main

    path = tmp_path / "seq.db"
    args = ["verify", GRID, "--behavior", FIXED_CELL, "--sequential", "--epsilon", "0.5",
            "--store", str(path), "--quiet"]
    assert main(args) == 0
    with sqlite3.connect(path) as db:
        db.execute("DELETE FROM episodes WHERE idx = 4")
    capsys.readouterr()
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "are not the first" in err and "Traceback" not in err


def test_the_earliest_certification_is_the_tests_own():
    for eps, delta in ((0.05, 0.05), (0.1, 0.01), (0.01, 0.05)):
        method = Sequential(eps, delta, 10**6)
        n = method.earliest_certification()
        assert method.feed([True] * (n + 5)) == n and method.claim()["decision"] == "certified"


def test_a_tiny_epsilon_caveat_names_a_finite_episode_at_once():
    (caveat,) = Sequential(1e-12, 0.05, 5).caveats()  # by bisection, not a scan of 10^12
    assert int(caveat.split("before episode ")[1].split()[0]) > 10**12
