"""Sample-complexity bounds from N i.i.d. episodes with k failures.

* :func:`confidence` -- Theorem 1/2 and Corollary 1 of the paper, extended to k failures: the
  confidence that ``P[success] >= 1 - eps`` is ``P[Binomial(N, eps) > k] = 1 - binom.cdf(k, N, eps)``
  (``1 - (1 - eps)**N`` for k = 0).
* :func:`lower_bound` -- the one-sided Clopper-Pearson lower confidence bound on ``P[success]`` at
  level ``1 - delta``: ``beta.ppf(delta, N - k, k + 1)`` (``delta**(1/N)`` for k = 0).
* :func:`min_episodes` -- the least N whose confidence reaches the target with at most k failures
  (``ceil(log(delta) / log(1 - eps))`` for k = 0), for any eps: N may exceed 2**63.
* :func:`rounded` (and :func:`floor_str`, :func:`ceil_str`, :func:`one_minus_str`) -- numbers
  for guarantees stated in words, written so that they never claim more than was computed.

The two statements are dual: with ``delta = 1 - confidence(N, k, eps)`` the lower bound equals
``1 - eps``. N must be fixed before the campaign; adding episodes until the bound passes is not a
valid certificate.
"""

from __future__ import annotations

import math
import numbers
import sys
from collections.abc import Callable
from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal, localcontext
from fractions import Fraction


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
    return _tail(n, k, epsilon, upper=True)


def miss_probability(n: int, k: int, epsilon: float) -> float:
    """``1 - confidence(n, k, epsilon)``, computed directly (``P[Binomial(n, eps) <= k]``): the
    probability of at most k failures were P[success] exactly 1 - eps; it stays exact where the
    confidence rounds to 1.0."""
    return _tail(n, k, epsilon, upper=False)


def _tail(n: int, k: int, epsilon: float, upper: bool) -> float:
    """``P[Binomial(n, eps) > k]`` (``upper``) or ``P[Binomial(n, eps) <= k]``, each computed
    directly so that neither is one minus a rounded other."""
    _check(n, k)
    _check_probability("epsilon", epsilon)
    if k == 0:  # n * log1p(-eps) exactly, rounded once: n may exceed the float range
        log_none = float(int(n) * Fraction(math.log1p(-epsilon)))
        return -math.expm1(log_none) if upper else math.exp(log_none)
    if n > sys.float_info.max:
        raise ValueError(f"more than {sys.float_info.max:.3g} episodes: beyond floating point")
    from scipy.stats import binom  # here, not at the top: it takes 0.4 s to import (campaign
    # workers and the CLI import this module; a campaign without failures never needs scipy)
    tail = binom.sf if upper else binom.cdf
    # scipy takes floats, which past 2**53 are not every integer: n rounded down and k up
    # understate the confidence and overstate the miss probability, never the other way
    return float(tail(_float(k, up=True), _float(n, up=False), epsilon))


def _float(count: int, up: bool) -> float:
    """``count`` as the nearest float above it (``up``) or below it."""
    near = float(count)
    if near == count or (near > count) == up:
        return near
    return math.nextafter(near, math.inf if up else 0.0)


def lower_bound(n: int, k: int, delta: float) -> float:
    """One-sided Clopper-Pearson lower bound on P[success] at confidence level 1 - delta."""
    _check(n, k)
    _check_probability("delta", delta)
    if k == n:
        return 0.0
    if k == 0:
        return delta ** (1.0 / n)
    from scipy.stats import beta  # imported here: see confidence()
    return float(beta.ppf(delta, n - k, k + 1))


def min_episodes(epsilon: float, target_confidence: float, failures: int = 0) -> int:
    """Least N such that N episodes with ``failures`` failures give ``target_confidence``.

    That is ``confidence(N, failures, epsilon) >= target_confidence > confidence(N - 1, ...)``.
    For no failures the closed form, computed exactly from the two logarithms, lands on N or next
    to it; with failures an exponential search brackets N. Both finish with a binary search, which
    also crosses the stretches where consecutive huge N have the same floating-point confidence.
    """
    _check_probability("epsilon", epsilon)
    _check_probability("confidence", target_confidence)
    if not _integer(failures) or failures < 0:
        raise ValueError(f"failures must be a non-negative integer (got {failures!r})")

    allowed = _complement(target_confidence)

    def reaches(n: int) -> bool:
        if failures == 0 or target_confidence <= 0.5:  # (no failures: from one logarithm)
            return confidence(n, failures, epsilon) >= target_confidence
        # the miss probability, computed directly, against 1 - target: scipy's confidence
        # near 1 has no digits left to tell N from a much smaller one
        return miss_probability(n, failures, epsilon) <= allowed

    if failures == 0:
        guess = math.ceil(Fraction(math.log1p(-target_confidence)) / Fraction(math.log1p(-epsilon)))
        return _least(reaches, guess, 1)
    return _least(reaches, failures + 1, failures + 1)


def _complement(probability: float) -> float:
    """``1 - probability`` as the largest float not above the exact difference."""
    exact = 1 - Fraction(probability)
    below = float(exact)
    return below if Fraction(below) <= exact else math.nextafter(below, 0.0)


def _least(reaches: Callable[[int], bool], guess: int, lowest: int) -> int:
    """Least n >= lowest with ``reaches(n)``, for ``reaches`` false up to some n, then true;
    the search starts at ``guess`` and steps out from it in doubling strides."""
    guess, step = max(guess, lowest), 1
    if reaches(guess):
        high, low = guess, guess - 1
        while low >= lowest and reaches(low):
            high, step = low, step * 2
            low = high - step
        low = max(low, lowest - 1)  # not reached, or below the range
    else:
        low, high = guess, guess + 1
        while not reaches(high):
            low, step = high, step * 2
            high = low + step
    while high - low > 1:
        mid = (low + high) // 2
        if reaches(mid):
            high = mid
        else:
            low = mid
    return high


def rounded(x: float, digits: int, up: bool = False, percent: bool = False) -> str:
    """``x`` with ``digits`` decimals (of a percentage with ``percent``), rounded down, or up
    with ``up``, exactly: the decimal rounded is the shortest that reads back as ``x`` (the
    float 0.99 prints ``0.99000``). Every figure vlb-gym prints goes through this function, on
    the side where it claims less: lower bounds, confidences and success rates down; upper
    bounds, p-values, failure rates and eps up."""
    value = Decimal(repr(float(x)))
    if percent:
        value = value.scaleb(2)
    text = str(value.quantize(Decimal(1).scaleb(-digits),
                              rounding=ROUND_CEILING if up else ROUND_FLOOR))
    return text + ("%" if percent else "")


def floor_str(x: float, digits: int = 5) -> str:
    """A probability in words, with ``digits`` decimals, rounded down so that it never claims more
    than the number: 0.9499958 is ``0.94999``, not ``0.95000``. The confidences and bounds of a
    finite campaign are below 1, so a value that rounded up to 1.0 prints as ``0.99999``."""
    return rounded(min(x, math.nextafter(1.0, 0.0)), digits)


def ceil_str(x: float, digits: int = 5) -> str:
    """An upper bound in words, rounded up (never below the number)."""
    return rounded(x, digits, up=True)


def one_minus_str(p: float) -> str:
    """``1 - p`` in decimal, exactly as ``p`` is written: ``0.95`` for 0.05, ``0.9999999`` for
    1e-7 (where ``f"{1 - p:g}"`` would claim ``1``)."""
    written = Decimal(repr(p))
    with localcontext() as context:
        context.prec = 30 - written.adjusted()  # enough digits to be exact
        return format(Decimal(1) - written, "f")
