"""Sequential verification that stays valid under continuous monitoring.

The test: Robbins' beta-binomial mixture confidence sequence for a Bernoulli success probability
(H. Robbins, "Statistical methods related to the law of the iterated logarithm", Ann. Math.
Statist. 41, 1970; S. R. Howard, A. Ramdas, J. McAuliffe, J. Sekhon, "Time-uniform, nonparametric,
nonasymptotic confidence sequences", Ann. Statist. 49, 2021, section 3). After ``n`` episodes with
``S`` successes and ``F = n - S`` failures, for each candidate success probability ``p``::

    M_n(p) = integral of  theta**S (1 - theta)**F / (p**S (1 - p)**F)  over theta ~ Beta(a, b)
           = B(a + S, b + F) / B(a, b) / (p**S (1 - p)**F)

is, under i.i.d. episodes with success probability ``p``, a nonnegative martingale with
``M_0 = 1`` (a mixture of likelihood ratios). Ville's inequality gives
``P[M_n(p) >= 1/delta for some n] <= delta``, so the set ``C_n = {p : M_n(p) < 1/delta}`` is a
confidence sequence: **with probability >= 1 - delta, simultaneously for all n, p lies in
C_n = (L_n, U_n)**; hence stopping whenever one likes, at a time chosen by looking at the data, is
valid. ``log M_n(p)`` is convex in ``p`` and at most 0 at the maximum-likelihood estimate ``S/n``,
so ``C_n`` is an interval around ``S/n``.

Decisions on the claim ``P[success] >= 1 - eps`` (``p0 = 1 - eps``):

* **certified** as soon as ``L_n >= p0`` (``S/n > p0`` and ``M_n(p0) >= 1/delta``);
* **refuted** as soon as ``U_n <= p0`` (``S/n < p0`` and ``M_n(p0) >= 1/delta``);
* **undecided** when neither happened within ``max_episodes`` (default
  :data:`MAX_EPISODES_FACTOR` times the fixed-N plan for zero failures). When ``p`` is close to
  ``p0`` the test may need a great many episodes; there is no indifference region, the cap is
  what ends it. An undecided campaign certifies nothing.

Whatever ``p``, the probability that the decision is wrong (certified while ``p < p0``, or
refuted while ``p >= p0``) is at most ``delta``: both need ``p`` outside some ``C_n``.
The mixing prior is fixed before the campaign from eps alone: ``Beta(c (1 - eps), c eps)`` with
``c =`` :data:`PRIOR_STRENGTH` (prior mean ``1 - eps``, the boundary of the claim; prior sample
size 10). Everything is computed exactly in log space (``scipy.special.betaln``); no Monte Carlo.

Power against the fixed-N plan (``benchmarks/sequential_power.py``: eps = delta = 0.05, 4000
Bernoulli runs per p, cap 1180 = 20 x 59 episodes; "fixed N, equal power" is the least N whose
fixed-N Clopper-Pearson campaign certifies at that p at least as often as the sequential test did,
at most 0.99 of the time)::

    p     certified refuted undecided  mean episodes (when decided)  fixed N, equal power
    0.90  0.000     0.999   0.001        242.1        241.2          (claim false)
    0.93  0.003     0.479   0.518        908.7        617.7          (claim false)
    0.94  0.009     0.093   0.897       1111.6        514.2          (claim false)
    0.95  0.025     0.009   0.966       1146.4        185.1          59
    0.96  0.157     0.001   0.843       1067.9        466.2          208
    0.97  0.716     0.000   0.284        735.5        559.0          482
    0.98  0.998     0.000   0.002        327.3        325.2          554
    0.99  1.000     0.000   0.000        154.1        154.1          234
    1.00  1.000     0.000   0.000         81.0         81.0          59 (vlb plan, 0 failures)

Wrong decisions (certified for p < 0.95, refuted for p >= 0.95) stay far below delta. Mixtures
pay for anytime validity: a behavior that never fails needs 81 episodes instead of 59, and near
the boundary (p = 0.96, 0.97) the capped test is undecided often; for p well above 1 - eps with
failures (0.98, 0.99) it needs far fewer episodes than a fixed-N plan that certifies as often, and
a clearly bad behavior is refuted early.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from . import bounds

PRIOR_STRENGTH = 10.0
"""``a + b`` of the mixing prior ``Beta(a, b)``, whose mean is ``1 - eps``."""

MAX_EPISODES_FACTOR = 20
"""Default cap: this many times the fixed-N plan ``min_episodes(eps, 1 - delta, 0)``."""

TEST_NAME = "Robbins beta-binomial mixture confidence sequence"


def prior(epsilon: float) -> tuple[float, float]:
    """The mixing prior ``Beta(a, b)`` on the success probability, fixed by eps alone."""
    bounds._check_probability("epsilon", epsilon)
    return PRIOR_STRENGTH * (1.0 - epsilon), PRIOR_STRENGTH * epsilon


def default_max_episodes(epsilon: float, delta: float) -> int:
    """The default cap on a sequential campaign (20 x the fixed-N plan with no failures)."""
    return MAX_EPISODES_FACTOR * bounds.min_episodes(epsilon, 1.0 - delta, 0)


def log_mixture(successes: int, failures: int, p: float, a: float, b: float) -> float:
    """``log M_n(p)``: the log of the beta-binomial mixture likelihood ratio against ``p``."""
    from scipy.special import betaln  # here: scipy.special takes 0.1 s to import, and
    # fixed-N campaigns (whose workers and CLI import this module) never call it

    s, f = successes, failures
    value = betaln(a + s, b + f) - betaln(a, b)
    if s:
        value -= s * math.log(p) if p > 0 else -math.inf
    if f:
        value -= f * math.log1p(-p) if p < 1 else -math.inf
    return float(value)


def confidence_sequence(successes: int, failures: int, delta: float, a: float,
                        b: float) -> tuple[float, float]:
    """``(L_n, U_n)``: the ends of ``{p : M_n(p) < 1/delta}``, rounded outwards (each end is a
    float at which ``M_n >= 1/delta``, or 0 and 1)."""
    n = successes + failures
    if n == 0:
        return 0.0, 1.0
    from scipy.optimize import brentq  # here: it takes 0.25 s to import, and workers import us
    threshold = -math.log(delta)
    mle = successes / n

    def g(p: float) -> float:
        return log_mixture(successes, failures, p, a, b) - threshold

    low, tiny = 0.0, 5e-324
    if successes and g(tiny) >= 0:
        low = brentq(g, tiny, mle, xtol=1e-300, rtol=1e-15, maxiter=500)
        while low > 0 and g(low) < 0:  # outwards: the bound never claims more than computed
            low = math.nextafter(low, 0.0)
    high, top = 1.0, math.nextafter(1.0, 0.0)
    if failures and g(top) >= 0:
        high = brentq(g, mle, top, xtol=1e-300, rtol=1e-15, maxiter=500)
        while high < 1 and g(high) < 0:
            high = math.nextafter(high, 1.0)
    return low, high


@dataclass
class SequentialTest:
    """The test of ``P[success] >= 1 - epsilon`` at level ``delta``, fed one episode at a time in
    index order. ``decision`` is None until the claim is certified or refuted."""

    epsilon: float
    delta: float
    successes: int = 0
    failures: int = 0
    decision: str | None = None
    stopped_at: int | None = None
    best_log_evidence: float = -math.inf  # max over n with S/n > p0 of log M_n(p0)

    def __post_init__(self) -> None:
        bounds._check_probability("epsilon", self.epsilon)
        bounds._check_probability("delta", self.delta)
        self.a, self.b = prior(self.epsilon)
        self.threshold = -math.log(self.delta)

    @property
    def n(self) -> int:
        return self.successes + self.failures

    def log_evidence(self) -> float:
        """``log M_n(1 - eps)``."""
        return log_mixture(self.successes, self.failures, 1.0 - self.epsilon, self.a, self.b)

    def update(self, success: bool) -> str | None:
        """Add one episode; return the decision once there is one (then stop feeding)."""
        if self.decision is not None:
            raise RuntimeError(f"the test has decided already ({self.decision})")
        if success:
            self.successes += 1
        else:
            self.failures += 1
        p0, n = 1.0 - self.epsilon, self.n
        evidence = self.log_evidence()
        above = self.successes > p0 * n
        if above:
            self.best_log_evidence = max(self.best_log_evidence, evidence)
        if evidence >= self.threshold and self.successes != p0 * n:
            self.decision = "certified" if above else "refuted"
            self.stopped_at = n
        return self.decision

    def bounds(self) -> tuple[float, float]:
        """The anytime-valid confidence interval ``(L_n, U_n)`` now."""
        return confidence_sequence(self.successes, self.failures, self.delta, self.a, self.b)

    def confidence(self) -> float:
        """Anytime-valid confidence in the claim: ``1 - 1 / max M_m(1 - eps)`` over the times
        ``m`` so far with ``S_m/m > 1 - eps`` (0 if none). Under any ``p < 1 - eps`` it reaches
        ``1 - alpha`` at some time with probability at most ``alpha``, by Ville's inequality,
        since there ``M_m(1 - eps) <= M_m(p)``."""
        if self.best_log_evidence <= 0:
            return 0.0
        return -math.expm1(-self.best_log_evidence)


def guarantee(epsilon: float, delta: float) -> str:
    """The test and its guarantee in words."""
    a, b = prior(epsilon)
    return (f"{TEST_NAME} (Robbins 1970; Howard et al. 2021), mixing prior Beta({a:g}, {b:g}): "
            f"with probability >= {bounds.one_minus_str(delta)}, simultaneously for all n, "
            "P[success] lies in [L_n, U_n], so stopping at any data-dependent time is valid; "
            f"the claim is certified when L_n >= {bounds.one_minus_str(epsilon)} and refuted when "
            f"U_n <= {bounds.one_minus_str(epsilon)}; either decision is wrong with probability "
            f"<= {delta:g}")


def simulate(p: float, epsilon: float, delta: float, runs: int, max_episodes: int,
             rng) -> tuple[object, object]:
    """Run the test on ``runs`` i.i.d. Bernoulli(``p``) streams at once (numpy, vectorised).

    Returns ``(decisions, stops)``: arrays with +1 (certified), -1 (refuted) or 0 (undecided),
    and the number of episodes each run used. The same decision rule as :class:`SequentialTest`.
    """
    import numpy as np
    from scipy.special import betaln

    a, b = prior(epsilon)
    p0, threshold = 1.0 - epsilon, -math.log(delta)
    decisions = np.zeros(runs, dtype=int)
    stops = np.full(runs, max_episodes)
    successes = np.zeros(runs, dtype=np.int64)
    open_ = np.arange(runs)
    block, start = 256, 0
    while start < max_episodes and open_.size:
        width = min(block, max_episodes - start)
        draws = rng.random((open_.size, width)) < p
        s = successes[open_, None] + np.cumsum(draws, axis=1)
        n = start + 1 + np.arange(width)
        f = n - s
        log_m = (betaln(a + s, b + f) - betaln(a, b) - s * math.log(p0) - f * math.log1p(-p0))
        hit = (log_m >= threshold) & (s != p0 * n)
        done = hit.any(axis=1)
        first = hit.argmax(axis=1)
        rows = open_[done]
        stops[rows] = n[first[done]]
        decisions[rows] = np.where(s[done, first[done]] > p0 * n[first[done]], 1, -1)
        successes[open_] = s[:, -1]
        open_ = open_[~done]
        start += width
    return decisions, stops
