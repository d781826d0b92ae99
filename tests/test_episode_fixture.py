"""The shipped behaviors give the episode records stored before the env and runtime rewrites
(``tests/fixtures/episodes.json``, recorded with ``python -m tests.fixtures.episodes``).

Everything is compared exactly (reset seeds, primitives, parameters, admissibility, certificates,
reasons, rho_B) except the scooping masses: a pile of grains is chaotic, and the last bits of
floating point that differ between processors (MuJoCo's vectorised paths) move a few grains.
Masses agree within :data:`MASS_BAND_G`.
"""

from __future__ import annotations

import json

import pytest

from vlb_gym.envs.scoop.scene import GRAIN_MASS

from .fixtures.episodes import CASES, PATH, record

STORED = json.loads(PATH.read_text())
MASSES = ("mass_scooped", "mass_delivered", "mass_spilled")
MASS_BAND_G = 6 * GRAIN_MASS * 1000  # six grains: the stored records moved three between CPUs


def _without_masses(episodes: list[dict]) -> tuple[list[dict], list[list[float]]]:
    """The records with the masses taken out, and the masses step by step."""
    plain, masses = [], []
    for episode in episodes:
        steps = []
        for step in episode["steps"]:
            steps.append({k: v for k, v in step.items() if k not in MASSES})
            masses.append([step[k] for k in MASSES if k in step])
        plain.append({**episode, "steps": steps})
    return plain, masses


@pytest.mark.parametrize("case", sorted(CASES))
def test_episode_records_are_unchanged(case):
    got, got_masses = _without_masses(record(case))
    stored, stored_masses = _without_masses(STORED[case])
    assert got == stored
    for mine, theirs in zip(got_masses, stored_masses, strict=True):
        assert len(mine) == len(theirs)
        assert all(abs(a - b) <= MASS_BAND_G for a, b in zip(mine, theirs)), (mine, theirs)


def test_the_fixture_covers_successes_and_failures():
    rhos = {case: {episode["rho"] for episode in STORED[case]} for case in CASES}
    assert rhos["grid/find_goal_and_oscillate"] == {1} and rhos["scoop/scoop_repeatedly"] == {1}
    assert rhos["scoop/scoop_repeatedly_sleeping"] == {1}
    assert rhos["grid/fixed_cell"] == {1, -1} and rhos["scoop/scoop_looks_away"] == {-1}
