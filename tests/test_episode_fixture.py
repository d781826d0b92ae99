"""The shipped behaviors give the episode records stored before the env and runtime rewrites
(``tests/fixtures/episodes.json``, recorded with ``python -m tests.fixtures.episodes``)."""

from __future__ import annotations

import json

import pytest

from .fixtures.episodes import CASES, PATH, record

STORED = json.loads(PATH.read_text())


@pytest.mark.parametrize("case", sorted(CASES))
def test_episode_records_are_unchanged(case):
    assert record(case) == STORED[case]


def test_the_fixture_covers_successes_and_failures():
    rhos = {case: {episode["rho"] for episode in STORED[case]} for case in CASES}
    assert rhos["grid/find_goal_and_oscillate"] == {1} and rhos["scoop/scoop_repeatedly"] == {1}
    assert rhos["grid/fixed_cell"] == {1, -1} and rhos["scoop/scoop_looks_away"] == {-1}
