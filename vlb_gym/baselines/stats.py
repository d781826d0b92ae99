"""Statistics of the comparison: aggregates across training seeds and the cost of certifying.

Across RL seeds, the interquartile mean (IQM, the 25% trimmed mean, as the ``rliable`` library
and Agarwal et al., "Deep RL at the Edge of the Statistical Precipice", 2021, recommend) with a
percentile bootstrap confidence interval over runs (with one task, rliable's stratified bootstrap
is this bootstrap). Computed with scipy, the package's core dependency: rliable 1.2 pins
``arch < 8``, which does not import under pandas 3.

:func:`episodes_to_certify` turns an empirical failure rate into what a user must pay to certify
P[success] >= 1 - eps at a confidence: the least N that certifies when the campaign sees the
failures it should expect. It is ``vlb plan`` with the contestant's own k.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats

from vlb_gym.verify.bounds import min_episodes

TRIM = 0.25
MAX_FAILURES = 2000
"""The scan of :func:`episodes_to_certify` stops here (about 40,000 episodes at eps = 0.05)."""


def iqm(scores: Sequence[float]) -> float:
    """The interquartile mean: the mean of the middle half (25% trimmed at each end)."""
    values = np.asarray(scores, dtype=float)
    if values.size == 0:
        raise ValueError("no scores")
    return float(stats.trim_mean(values, TRIM))


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


def episodes_to_certify(failure_rate: float, epsilon: float = 0.05,
                        confidence: float = 0.95) -> float:
    """The least N whose campaign certifies P[success] >= 1 - ``epsilon`` at ``confidence``
    when it sees ``floor(failure_rate * N)`` failures (what the contestant's rate predicts);
    ``math.inf`` when none does (a rate of ``epsilon`` or more) or the scan passes
    ``MAX_FAILURES`` failures.

    With ``N_k`` the least N certifying with k failures (``vlb plan --failures k``), the answer
    is ``N_k`` for the least k with ``floor(failure_rate * N_k) <= k``: any N certifying with
    its predicted failures k is at least ``N_k``, and ``N_k`` grows with k."""
    if not 0 <= failure_rate <= 1:
        raise ValueError(f"failure_rate must lie in [0, 1] (got {failure_rate!r})")
    if failure_rate >= epsilon:
        return math.inf
    for k in range(MAX_FAILURES + 1):
        n = min_episodes(epsilon, confidence, k)
        if math.floor(failure_rate * n) <= k:
            return n
    return math.inf
