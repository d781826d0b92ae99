"""Statistics of the comparison: aggregates across training seeds and the cost of certifying.

Across RL seeds, the interquartile mean (IQM, the 25% trimmed mean, as the ``rliable`` library
and Agarwal et al., "Deep RL at the Edge of the Statistical Precipice", 2021, recommend) with a
percentile bootstrap confidence interval over runs (with one task, rliable's stratified bootstrap
is this bootstrap). Computed with scipy, the package's core dependency: rliable 1.2 pins
``arch < 8``, which does not import under pandas 3.

:func:`episodes_to_certify` turns a failure rate into what a user must pay to certify
P[success] >= 1 - eps at a confidence: the least N at which a fixed-N campaign certifies with a
stated probability (90% by default), computed exactly from the binomial. Given a rate measured on
a few episodes it treats that rate as the true one: the rate's own uncertainty is not counted.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats

from vlb_gym.verify.bounds import min_episodes, rounded

TRIM = 0.25
CERTIFY_PROBABILITY = 0.9
"""How sure a user wants to be that a campaign of the stated N certifies."""
MAX_EPISODES = 1_000_000
"""The scan of :func:`episodes_to_certify` stops here."""
_BLOCK = 4096


def iqm(scores: Sequence[float]) -> float:
    """The interquartile mean: the mean of the middle half (25% trimmed at each end)."""
    values = np.asarray(scores, dtype=float)
    if values.size == 0:
        raise ValueError("no scores")
    return float(stats.trim_mean(values, TRIM))


BOOTSTRAP_COVERAGE_10 = 0.93
"""How often the nominal 95% percentile-bootstrap interval of the IQM covered the true IQM with
10 seeds (1,000 simulated sets of normal seeds; ``tests/test_rl_stats.py`` checks it)."""

MIN_SEEDS_FOR_INTERVAL = 10
"""Below this many seeds no interval is shown: a percentile bootstrap of 3 runs has 10 distinct
resamples, its 95% interval is the runs' range, and for normal seeds it covered the true IQM
76% of the time (93% with 10 seeds; 1,000 simulated sets each)."""


def describe(scores: Sequence[float]) -> str:
    """Scores across seeds in words that claim no more than they hold: the IQM where 25%
    trimming removes a run at each end (else the mean, which it then is), with its 95%
    bootstrap interval from :data:`MIN_SEEDS_FOR_INTERVAL` seeds on, else every seed's value."""
    values = sorted(float(s) for s in scores)
    if len(values) == 1:  # one campaign (a graph): its rate
        return rounded(values[0], 2)
    centre = f"{'IQM' if int(TRIM * len(values)) > 0 else 'mean'} {rounded(iqm(values), 2)}"
    if len(values) >= MIN_SEEDS_FOR_INTERVAL:
        agg = aggregate(values)
        return f"{centre} [{rounded(agg.low, 2)}, {rounded(agg.high, 2, up=True)}]"
    return f"{centre}; seeds " + ", ".join(rounded(v, 2) for v in values)


@dataclass(frozen=True)
class Aggregate:
    """IQM of per-seed scores with a bootstrap interval (``low``, ``high``)."""

    iqm: float
    low: float
    high: float
    runs: int


def aggregate(scores: Sequence[float], confidence: float = 0.95, resamples: int = 10_000,
              seed: int = 0) -> Aggregate:
    """IQM of ``scores`` (one per training seed) with a percentile bootstrap interval at
    ``confidence`` (``resamples`` resamples of the runs, seeded). Equal scores, a single run
    included, give a zero-width interval."""
    values = np.asarray(scores, dtype=float)
    centre = iqm(values)
    if np.ptp(values) == 0:
        return Aggregate(centre, centre, centre, values.size)
    result = stats.bootstrap((values,), lambda x, axis: stats.trim_mean(x, TRIM, axis=axis),
                             confidence_level=confidence, n_resamples=resamples,
                             method="percentile", random_state=np.random.default_rng(seed))
    interval = result.confidence_interval
    return Aggregate(centre, float(interval.low), float(interval.high), values.size)


def episodes_to_certify(failure_rate: float, epsilon: float = 0.05, confidence: float = 0.95,
                        probability: float = CERTIFY_PROBABILITY) -> float:
    """The least N at which a campaign of N episodes, each failing independently with
    probability ``failure_rate``, certifies P[success] >= 1 - ``epsilon`` at ``confidence``
    with probability at least ``probability``; ``math.inf`` when none does within
    :data:`MAX_EPISODES` (a rate of ``epsilon`` or more never does).

    With ``k*(N)`` the most failures that still certify at N (the largest k with
    ``binom.sf(k, N, eps) >= confidence``), a campaign certifies with probability
    ``binom.cdf(k*(N), N, rate)``, which is not monotone in N (it drops each time N grows
    without ``k*`` growing): the answer is the first N where it reaches ``probability``."""
    if not 0 <= failure_rate <= 1:
        raise ValueError(f"failure_rate must lie in [0, 1] (got {failure_rate!r})")
    for name, value in (("epsilon", epsilon), ("confidence", confidence)):
        if not 0 < value < 1:
            raise ValueError(f"{name} must lie strictly between 0 and 1 (got {value!r})")
    if not 0 < probability < 1:
        raise ValueError(f"probability must lie strictly between 0 and 1 (got {probability!r})")
    if failure_rate >= epsilon:
        return math.inf
    q = 1.0 - confidence
    first = min_episodes(epsilon, confidence, 0)
    for start in range(first, MAX_EPISODES + 1, _BLOCK):
        n = np.arange(start, min(start + _BLOCK, MAX_EPISODES + 1), dtype=float)
        least = stats.binom.ppf(q, n, epsilon)  # the smallest k with cdf(k) >= q
        most = np.where(stats.binom.cdf(least, n, epsilon) <= q, least, least - 1)
        certifies = np.where(most >= 0, stats.binom.cdf(most, n, failure_rate), 0.0)
        hit = certifies >= probability
        if hit.any():
            return int(n[np.argmax(hit)])
    return math.inf