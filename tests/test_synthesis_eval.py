"""The committed real-model transcripts of the certified-synthesis evaluation replay, offline, to
the outcome the live run recorded (benchmarks/results/synthesis)."""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.synthesis_eval import replay, tables  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results" / "synthesis"
EPISODES = 10


@pytest.fixture(scope="module")
def replayed():
    from benchmarks.synthesis_tasks import TASKS
    return replay(RESULTS, list(TASKS), EPISODES)


def test_every_live_sample_replays_round_by_round(replayed):
    """``replay`` exits when a round's error differs; here the outcomes are held to the CSV of
    the live run."""
    with (RESULTS / "results.csv").open() as handle:
        live = {(r["model"], r["task"], int(r["sample"])): r for r in csv.DictReader(handle)}
    assert len(replayed) == len(live) > 0
    for sample in replayed:
        row = live[(sample.model, sample.task, sample.sample)]
        assert (sample.valid, sample.rounds, sample.layers) == \
            (row["valid"] == "True", int(row["rounds"]), row["layers"])
        assert sample.reply_tokens == int(row["reply_tokens"]) > 0
        if sample.valid and int(row["done"]) == int(row["episodes"]):
            assert sample.done == EPISODES  # certified at 100 episodes: done on the first 10
        if sample.valid and int(row["verified"]) == 0:
            assert sample.verified == 0


def test_the_table_counts_what_the_samples_say(replayed):
    table = tables(replayed, EPISODES)
    for model in {s.model for s in replayed}:
        mine = [s for s in replayed if s.model == model]
        valid = sum(s.valid for s in mine) / len(mine)
        assert f"| {model} | {len(mine)} | {valid:.0%} |" in table
