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
from vlb_gym.verify import bounds


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
                probability: float = 0.9, limit: int = 6000) -> int:
    """The least N at which P[a campaign of N certifies] >= probability, scanning N one by one
    with the verifier's own confidence (k*: the most failures that still certify)."""
    most = -1
    for n in range(1, limit + 1):
        while most + 1 < n and bounds.confidence(n, most + 1, epsilon) >= confidence:
            most += 1
        if most >= 0 and binom.cdf(most, n, rate) >= probability:
            return n
    raise AssertionError("not within the limit")


@pytest.mark.parametrize("rate, expected", [(0.0, 59), (0.01, 153), (0.02, 311), (0.03, 832)])
def test_episodes_to_certify_hand_cases(rate, expected):
    assert episodes_to_certify(rate) == expected == brute_force(rate)


@settings(max_examples=30, deadline=None)
@given(rate=st.floats(0.0, 0.03), epsilon=st.sampled_from([0.05, 0.1]),
       confidence=st.sampled_from([0.9, 0.95, 0.99]), probability=st.sampled_from([0.5, 0.9]))
def test_episodes_to_certify_equals_the_brute_force_scan(rate, epsilon, confidence,
                                                         probability):
    assert episodes_to_certify(rate, epsilon, confidence, probability) == \
        brute_force(rate, epsilon, confidence, probability)


@pytest.mark.parametrize("rate", [0.01, 0.02, 0.03])
def test_a_campaign_of_that_size_certifies_as_often_as_stated(rate):
    n = episodes_to_certify(rate)
    rng = np.random.default_rng(7)
    failures = rng.binomial(n, rate, size=20_000)
    certified = np.mean([bounds.confidence(n, int(k), 0.05) >= 0.95 for k in failures])
    assert certified >= 0.9 - 3 * math.sqrt(0.9 * 0.1 / 20_000)


def test_a_rate_at_or_above_epsilon_never_certifies():
    assert episodes_to_certify(0.05) == math.inf == episodes_to_certify(0.3)
    with pytest.raises(ValueError, match="failure_rate must lie in"):
        episodes_to_certify(-0.1)


def test_seeds_are_described_as_far_as_they_support():
    from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal

    from vlb_gym.baselines.stats import describe

    def floor(x):
        return str(Decimal(repr(x)).quantize(Decimal("0.01"), rounding=ROUND_FLOOR))

    def ceil(x):
        return str(Decimal(repr(x)).quantize(Decimal("0.01"), rounding=ROUND_CEILING))

    assert describe([0.98]) == "0.98"
    assert describe([0.88, 0.77, 0.82]) == "mean 0.82; seeds 0.77, 0.82, 0.88"  # no interval
    assert describe([0.1, 0.2, 0.3, 0.9]) == "IQM 0.25; seeds 0.10, 0.20, 0.30, 0.90"
    ten = [0.80, 0.82, 0.84, 0.85, 0.86, 0.88, 0.90, 0.91, 0.93, 0.99]
    text = describe(ten)
    agg = aggregate(ten)
    assert text == f"IQM {floor(agg.iqm)} [{floor(agg.low)}, {ceil(agg.high)}]"
    assert describe([0.996, 0.999]) == "mean 0.99; seeds 0.99, 0.99"  # never 1.00 unless 1


def test_the_stated_coverage_of_the_ten_seed_bootstrap():
    """The tables say the nominal 95% interval covered the true IQM 93% of the time with 10
    seeds: 400 simulated sets of normal seeds (the true IQM of a normal is its mean) agree
    within sampling error (a standard error of 1.3 points)."""
    from vlb_gym.baselines.stats import BOOTSTRAP_COVERAGE_10

    rng = np.random.default_rng(0)
    sets = 400
    covered = sum(interval.low <= 0.8 <= interval.high for interval in (
        aggregate(list(rng.normal(0.8, 0.05, 10)), seed=k) for k in range(sets)))
    assert abs(covered / sets - BOOTSTRAP_COVERAGE_10) < 0.04
