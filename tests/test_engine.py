"""The engine: adding a backend or a kind of study is one registration or one subclass, and
campaigns and comparisons run through the same loop (:mod:`vlb_gym.verify.engine`); a method
is one registration too (tests/test_methods.py)."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import Any

import pytest

from vlb_gym.verify import backends
from vlb_gym.verify.campaign import Campaign, CampaignConfig, build, episode_seed
from vlb_gym.verify.comparison import Comparison, ComparisonConfig
from vlb_gym.verify.engine import EpisodeStudy
from vlb_gym.verify.episode import EpisodeResult, run_episode
from vlb_gym.verify.methods import FixedN, Method
from vlb_gym.verify.store import CampaignStore

from .conftest import EXAMPLES

GRID = "VLB-GridExplore-v0"


def _reversed(setup, indices, workers, preload, max_deaths, ray) -> Iterator[Any]:
    """A toy backend: every index in this process, the last first."""
    runner = setup()
    for i in reversed(list(indices)):
        yield runner(i)


@pytest.fixture
def toy_backend():
    assert backends.register_backend("toy-reversed")(_reversed) is _reversed
    yield "toy-reversed"
    del backends.BACKENDS["toy-reversed"]


@pytest.mark.parametrize("method", ["fixed-N", "sequential"])
def test_a_registered_backend_runs_campaigns_and_comparisons(toy_backend, method):
    """Results arrive in reverse order from the toy backend; the engine gives the same reports
    (and, for a method that stops early, the same stopping time) as the serial backend."""
    config = CampaignConfig(GRID, str(EXAMPLES / "fixed_cell.json"), 60, epsilon=0.2,
                            method=method)
    with Campaign(config) as campaign:
        serial, toy = (campaign.run(backend=b) for b in ("serial", "toy-reversed"))
    run = ("wall_seconds", "episodes_per_second", "backend", "workers")
    assert {k: v for k, v in toy.items() if k not in run} == \
        {k: v for k, v in serial.items() if k not in run}
    assert toy["backend"] == "toy-reversed"
    pairs = ComparisonConfig(GRID, "explore_until_goal", str(EXAMPLES / "fixed_cell.json"), 30)
    with Comparison(pairs) as comparison:
        serial, toy = (comparison.run(backend=b) for b in ("serial", "toy-reversed"))
    assert toy["counts"] == serial["counts"] and toy["p_value"] == serial["p_value"]


class FixedSeeds(EpisodeStudy[dict]):
    """A toy kind of study: a behavior on a list of reset seeds given in advance (say, the
    failures of another campaign), judged fixed-N."""

    store_kind = CampaignStore

    def __init__(self, behavior: str, seeds: Sequence[int]):
        self.seeds = list(seeds)
        self.plan = {"method": FixedN.name, "seeds": self.seeds, "behavior": behavior}
        self.config = CampaignConfig(GRID, behavior, len(self.seeds))
        self.built = build(self.config)

    @classmethod
    def method_of(cls, plan: Any) -> Method:
        return FixedN(0.1, 0.05, len(plan["seeds"]))

    @classmethod
    def report(cls, plan, results, seconds, workers, backend, store=None, ran=None) -> Any:
        return {"seeds": [r.seed for r in results], "successes": sum(r.success for r in results)}

    @property
    def planned(self) -> int:
        return len(self.seeds)

    @property
    def preloads(self) -> Sequence[str]:
        return ()

    def units(self, indices=None, workers=1, backend="process", ray=None) -> Iterator[Any]:
        env, policy = self.built
        for i in range(self.planned) if indices is None else indices:
            yield run_episode(env, policy, self.seeds[i], i)


def test_a_kind_of_study_is_one_subclass():
    """The toy kind says what its unit is and nothing else: the engine runs it to its method's
    decision and hands every unit to ``on_result`` and the report."""
    seeds = [episode_seed(0, i) for i in (3, 1, 4, 1, 5)]
    study = FixedSeeds("explore_until_goal", seeds)
    seen: list[EpisodeResult] = []
    report = study.run(on_result=seen.append)
    assert sorted(r.seed for r in seen) == sorted(seeds)
    assert report == {"seeds": seeds, "successes": sum(r.success for r in seen)}
    with Campaign(CampaignConfig(GRID, "explore_until_goal", 6)) as campaign:
        same = {r.seed: r.outcome()["steps"] for r in campaign.episodes()}
    for result in seen:  # the same seed gives the campaign's episode
        if result.seed in same:
            assert result.outcome()["steps"] == same[result.seed]
