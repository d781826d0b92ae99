"""Aggregates across seeds against hand-computed cases, and the episodes needed to certify
against a brute-force scan of the binomial tail (scipy), independent of ``vlb plan``."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import binom

from vlb_gym.baselines.stats import aggregate, episodes_to_certify, iqm


def test_iqm_is_the_mean_of_the_middle_half():
    assert iqm([8, 1, 7, 2, 6, 3, 5, 4]) == pytest.approx((3 + 4 + 5 + 6) / 4)
    assert iqm([0.1, 0.9, 0.2, 0.8]) == pytest.approx((0.2 + 0.8) / 2)
    assert iqm([0.3, 0.6, 0.9]) == pytest.approx(0.6)  # a quarter of 3 runs trims none
    with pytest.raises(ValueError, match="no scores"):
        iqm([])


def test_the_bootstrap_interval_brackets_the_iqm_and_is_repeatable():
    scores = [0.62, 0.71, 0.74, 0.80, 0.93]
    one, two = aggregate(scores, seed=3), aggregate(scores, seed=3)
    assert one == two and one.runs == 5
    assert min(scores) <= one.low <= one.iqm <= one.high <= max(scores)
    assert one.iqm == pytest.approx(np.mean([0.71, 0.74, 0.80]))
    assert one.high - one.low > 0
    same = aggregate([0.97, 0.97, 0.97])
    assert (same.iqm, same.low, same.high) == pytest.approx((0.97, 0.97, 0.97))


def brute_force(rate: float, epsilon: float = 0.05, confidence: float = 0.95,
                limit: int = 4000) -> int:
    """The least N with P[Bin(N, eps) > floor(rate N)] >= confidence, by scanning N."""
    n = np.arange(1, limit + 1)
    reached = binom.sf(np.floor(rate * n), n, epsilon) >= confidence
    assert reached.any()
    return int(n[np.argmax(reached)])


@pytest.mark.parametrize("rate, expected", [(0.0, 59), (0.02, 93), (0.03, 260)])
def test_episodes_to_certify_hand_cases(rate, expected):
    assert episodes_to_certify(rate) == expected == brute_force(rate)


@settings(max_examples=40, deadline=None)
@given(rate=st.floats(0.0, 0.04), epsilon=st.sampled_from([0.05, 0.1]),
       confidence=st.sampled_from([0.9, 0.95, 0.99]))
def test_episodes_to_certify_equals_the_brute_force_scan(rate, epsilon, confidence):
    assert episodes_to_certify(rate, epsilon, confidence) == \
        brute_force(rate, epsilon, confidence, limit=12_000)


def test_a_rate_at_or_above_epsilon_never_certifies():
    assert episodes_to_certify(0.05) == math.inf == episodes_to_certify(0.3)
    with pytest.raises(ValueError, match="failure_rate must lie in"):
        episodes_to_certify(-0.1)
