"""Sample-complexity bounds from N i.i.d. episodes with k failures.

* :func:`confidence` -- Theorem 1/2 and Corollary 1 of the paper, extended to k failures: the
  confidence that ``P[success] >= 1 - eps`` is ``P[Binomial(N, eps) > k] = 1 - binom.cdf(k, N, eps)``
  (``1 - (1 - eps)**N`` for k = 0).
* :func:`lower_bound` -- the one-sided Clopper-Pearson lower confidence bound on ``P[success]`` at
  level ``1 - delta``: ``beta.ppf(delta, N - k, k + 1)`` (``delta**(1/N)`` for k = 0).
* :func:`min_episodes` -- the least N whose confidence reaches the target with at most k failures
  (``ceil(log(delta) / log(1 - eps))`` for k = 0).

The two statements are dual: with ``delta = 1 - confidence(N, k, eps)`` the lower bound equals
``1 - eps``. N must be fixed before the campaign; adding episodes until the bound passes is not a
valid certificate.
"""

from __future__ import annotations

import math
import numbers

from scipy.stats import beta, binom


def _integer(value: object) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _check(n: int, k: int) -> None:
    if not _integer(n) or n < 1:
        raise ValueError(f"the number of episodes must be a positive integer (got {n!r})")
    if not _integer(k) or not 0 <= k <= n:
        raise ValueError(f"failures must be an integer in [0, {n}] (got {k!r})")


def _check_probability(name: str, value: float) -> None:
    if not 0 < value < 1:
        raise ValueError(f"{name} must lie strictly between 0 and 1 (got {value!r})")


def confidence(n: int, k: int, epsilon: float) -> float:
    """Confidence that P[success] >= 1 - epsilon after n episodes with k failures."""
    _check(n, k)
    _check_probability("epsilon", epsilon)
    if k == 0:
        return -math.expm1(int(n) * math.log1p(-epsilon))
    return float(binom.sf(k, n, epsilon))


def lower_bound(n: int, k: int, delta: float) -> float:
    """One-sided Clopper-Pearson lower bound on P[success] at confidence level 1 - delta."""
    _check(n, k)
    _check_probability("delta", delta)
    if k == n:
        return 0.0
    if k == 0:
        return delta ** (1.0 / n)
    return float(beta.ppf(delta, n - k, k + 1))


def min_episodes(epsilon: float, target_confidence: float, failures: int = 0) -> int:
    """Least N such that N episodes with ``failures`` failures give ``target_confidence``."""
    _check_probability("epsilon", epsilon)
    _check_probability("confidence", target_confidence)
    if not _integer(failures) or failures < 0:
        raise ValueError(f"failures must be a non-negative integer (got {failures!r})")
    if failures == 0:
        n = math.ceil(math.log1p(-target_confidence) / math.log1p(-epsilon))
        while n > 1 and confidence(n - 1, 0, epsilon) >= target_confidence:  # guard rounding
            n -= 1
        while confidence(n, 0, epsilon) < target_confidence:
            n += 1
        return n
    high = failures + 1
    while confidence(high, failures, epsilon) < target_confidence:
        high *= 2
    low = high // 2  # confidence(low) < target or low <= failures
    while high - low > 1:
        mid = (low + high) // 2
        if mid > failures and confidence(mid, failures, epsilon) >= target_confidence:
            high = mid
        else:
            low = mid
    return high
