"""Paired comparisons: is behavior (or agent) B at least as reliable as A?

A and B run on the same reset seeds, so episode ``i`` of one pairs with episode ``i`` of the
other. Each pair is one of four kinds (:class:`PairCounts`): both succeeded, only A, only B,
neither. With ``p_A``, ``p_B`` the success probabilities and ``d = p_B - p_A``, every test here
is of the null ``d <= -margin`` against ``d > -margin``:

* ``margin = 0``: **superiority**, "B is more reliable than A";
* ``margin > 0``: **non-inferiority**, "B is at least as reliable as A, up to ``margin``".

Only the discordant pairs (one succeeded, the other failed) carry evidence about ``d`` beyond
the margin; concordant pairs count for non-inferiority (``d = 0`` is inside the claim).

Fixed N (:class:`~.paired_methods.FixedPairs`), all pairs run:

* superiority: **McNemar's exact test**, one-sided: given ``m`` discordant pairs, the number
  where only B succeeded is Binomial(m, 1/2) when ``d = 0`` and smaller when ``d < 0``, so
  ``p = P[Binomial(m, 1/2) >= b_only]``;
* non-inferiority: McNemar's conditioning does not carry a margin on ``d``; the **exact
  unconditional test** of ``T = b_only - a_only`` does: its p-value is the largest
  ``P[T >= t]`` over the null's boundary ``d = -margin`` (where it is largest: moving mass to
  "only B" or away from "only A" raises ``T``), computed exactly from the trinomial for each
  value of the nuisance (the discordance ``P[only A] + P[only B]``) on a grid of
  :data:`NUISANCE_GRID` values, then refined by a bounded scalar search around the best;
* the interval on ``d``: each bound inverts that unconditional test at level ``1 - alpha``
  (one-sided; together a ``1 - 2 alpha`` interval).

Sequential (:class:`~.paired_methods.SequentialPairs`), stopping whenever the evidence suffices:
**testing by betting** (Waudby-Smith and Ramdas, "Estimating means of bounded random variables
by betting", JRSS-B 2024; Shafer, "Testing by betting", JRSS-A 2021). With ``X = B_i - A_i`` in
``{-1, 0, 1}`` (mean ``d``) and a null value ``d0``, the wealth of a bettor who stakes a fixed
fraction ``c`` of the most it can safely stake,
``K_n(c) = prod_i (1 + c (X_i - d0) / (1 + d0))``, is a nonnegative supermartingale under
``d <= d0`` (each factor has mean ``1 + c (d - d0) / (1 + d0) <= 1``), and so is the average
over the fractions :data:`BETS`. Ville's inequality: ``P[sup_n K_n >= 1/alpha] <= alpha``,
however often one looks. B is shown better than ``-margin`` when the wealth against
``d <= -margin`` reaches ``1/alpha``; shown worse (the claim refuted) when the mirror bet
against ``d >= -margin`` does; each is wrong with probability at most ``alpha``. The bets are
fixed in advance, so the wealth depends only on the counts. The anytime-valid interval on ``d``
inverts the two wealths (each bound at ``1 - alpha``, for all n at once).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


BETS = (0.01, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.9)
"""The fractions of the safe stake that the sequential test's bettors stake (its mixture)."""

NUISANCE_GRID = 200
"""Nuisance values the unconditional test's p-value is maximised over before refining."""

BERGER_BOOS_GAMMA = 0.001
"""The part of the unconditional test's level spent on the nuisance's confidence interval."""

SEQUENTIAL_TEST = "testing by betting (fixed-fraction mixture, Ville's inequality)"
DEFAULT_MAX_PAIRS = 5000


@dataclass(frozen=True)
class PairCounts:
    """How many pairs of each kind: ``both`` succeeded, ``a_only``, ``b_only``, ``neither``."""

    both: int = 0
    a_only: int = 0
    b_only: int = 0
    neither: int = 0

    @property
    def n(self) -> int:
        return self.both + self.a_only + self.b_only + self.neither

    @property
    def discordant(self) -> int:
        return self.a_only + self.b_only

    @property
    def a_successes(self) -> int:
        return self.both + self.a_only

    @property
    def b_successes(self) -> int:
        return self.both + self.b_only

    def add(self, a_success: bool, b_success: bool) -> PairCounts:
        key = ("neither", "b_only", "a_only", "both")[2 * bool(a_success) + bool(b_success)]
        return PairCounts(**{**self.__dict__, key: getattr(self, key) + 1})


def check_margin(margin: float) -> None:
    if not isinstance(margin, (int, float)) or isinstance(margin, bool) \
            or not 0 <= margin < 1:
        raise ValueError(f"margin must lie in [0, 1) (got {margin!r})")


def check_alpha(alpha: float) -> None:
    """A comparison's level: in (0, 1/2), where a test is wrong less often than not and its
    two-sided interval (each bound at 1 - alpha) cannot be empty."""
    if not isinstance(alpha, (int, float)) or isinstance(alpha, bool) \
            or not 0 < alpha < 0.5 or 1.0 - alpha == 1.0:
        raise ValueError(f"alpha must lie strictly between 0 and 0.5 (got {alpha!r}): a test "
                         "wrong with probability one half or more shows nothing")


def claim_words(margin: float) -> str:
    """The alternative hypothesis in words (the margin exactly as given: rounded, it would
    state another claim)."""
    if margin == 0:
        return "B is more reliable than A (P_B > P_A)"
    return f"B is at least as reliable as A up to {margin!r} (P_B > P_A - {margin!r})"


def refuted_words(margin: float) -> str:
    """What the mirror test shows when it refutes the claim, in words."""
    if margin == 0:
        return "B is less reliable than A (P_B < P_A)"
    return (f"B is less reliable than A by more than {margin!r} "
            f"(P_B < P_A - {margin!r})")


# ------------------------------------------------------------------------------- fixed N


def mcnemar_p(counts: PairCounts) -> float:
    """McNemar's exact one-sided p-value for ``P_B > P_A``: ``P[Bin(m, 1/2) >= b_only]``."""
    from scipy.stats import binom

    if counts.discordant == 0:
        return 1.0
    return float(binom.sf(counts.b_only - 1, counts.discordant, 0.5))


WHOLE_SUM_PAIRS = 2000  # above this many pairs, the sum over discordant counts is truncated
TRUNCATION = 1e-13  # where: each end leaves out at most this much of M's mass, added back


def _tails(n: int, t: int, d: np.ndarray, s: np.ndarray) -> np.ndarray:
    """``P[b_only - a_only >= t]`` for ``n`` pairs at each discordance ``s`` and difference
    ``d`` (``P[only B] = (s + d) / 2``, ``P[only A] = (s - d) / 2``), exactly: the discordant
    count ``M`` is Binomial(n, s) and, given ``M = m``, ``b_only`` is Binomial(m, (s + d) /
    (2 s)). Above :data:`WHOLE_SUM_PAIRS` pairs the sum runs over the counts ``M`` takes but
    with probability below :data:`TRUNCATION` at each end, and the rest is added as if it gave
    the tail for sure: never less than the exact value, at most 2e-13 more, in time that grows
    with the square root of ``n`` (a report of 80,000 pairs no longer takes minutes)."""
    from scipy.stats import binom

    first, last = 0, n
    if n > WHOLE_SUM_PAIRS:  # the discordant counts the grid's s can give: its extremes' bulk
        first = int(binom.ppf(TRUNCATION, n, float(s.min())))
        last = int(binom.isf(TRUNCATION, n, float(s.max())))
    m = np.arange(first, last + 1)[:, None]
    need = np.ceil((m + t) / 2.0)  # b_only >= (m + t) / 2
    q = np.clip((s + d) / (2 * s), 0.0, 1.0)[None, :]
    inside = (binom.pmf(m, n, s[None, :]) * binom.sf(need - 1, m, q)).sum(axis=0)
    # the counts left out, counted as if each gave the tail for sure: an upper bound, within
    # 2 x TRUNCATION of the exact sum (M is stochastically increasing in s)
    outside = binom.cdf(first - 1, n, s) + binom.sf(last, n, s) if n > WHOLE_SUM_PAIRS else 0.0
    return np.clip(inside + outside, 0, 1)


def unconditional_p(counts: PairCounts, d0: float) -> float:
    """The exact unconditional p-value of the null ``d <= d0`` (``-1 < d0 < 1``) given the
    counts, Berger and Boos' way: ``gamma`` (:data:`BERGER_BOOS_GAMMA`) plus the largest
    ``P[T >= t]`` over the null's points whose discordance ``s`` lies in a ``1 - gamma``
    Clopper-Pearson interval from the observed discordant count. At a given ``s`` the
    difference is at most ``s`` and ``P[T >= t]`` grows with it, so the largest is at
    ``d = min(d0, s)`` (see the module's docstring); valid at every level (R. L. Berger and
    D. D. Boos, "P values maximised over a confidence set for the nuisance parameter", JASA 89,
    1994)."""
    from scipy.optimize import minimize_scalar
    from scipy.stats import beta

    n, t, m = counts.n, counts.b_only - counts.a_only, counts.discordant
    if n == 0:
        return 1.0
    half = BERGER_BOOS_GAMMA / 2
    low = beta.ppf(half, m, n - m + 1) if m > 0 else 0.0
    high = beta.ppf(1 - half, m + 1, n - m) if m < n else 1.0
    low, high = max(low, -d0, 1e-12), min(high, 1.0)  # d >= -s: the null needs s >= -d0
    if low > high:  # no point of the null is in the interval
        return min(1.0, BERGER_BOOS_GAMMA)

    def tails(s: np.ndarray) -> np.ndarray:
        return _tails(n, t, np.minimum(d0, s), s)

    grid = np.linspace(low, high, NUISANCE_GRID)
    values = tails(grid)
    best = int(values.argmax())
    step = (high - low) / (NUISANCE_GRID - 1)
    found = minimize_scalar(lambda s: -float(tails(np.array([s]))[0]),
                            method="bounded", options={"xatol": 1e-9},
                            bounds=(max(low, grid[best] - step), min(high, grid[best] + step)))
    return float(min(1.0, max(values[best], -found.fun) + BERGER_BOOS_GAMMA))


def unconditional_bounds(counts: PairCounts, alpha: float) -> tuple[float, float]:
    """The interval on ``d``: each end inverts the exact unconditional test at level
    ``1 - alpha`` (the least ``d0`` whose null ``d <= d0`` is not rejected, and its mirror)."""
    mirror = PairCounts(counts.both, counts.b_only, counts.a_only, counts.neither)
    return _lowest_kept(counts, alpha), -_lowest_kept(mirror, alpha)


def _lowest_kept(counts: PairCounts, alpha: float) -> float:
    """``inf {d0 : unconditional_p(counts, d0) > alpha}`` (the p-value grows with ``d0``), by
    bisection to 1e-4, rounded down."""
    low, high = -1.0, 1.0
    while high - low > 1e-4:
        middle = (low + high) / 2
        if unconditional_p(counts, middle) > alpha:
            high = middle
        else:
            low = middle
    return max(-1.0, low)


# ------------------------------------------------------------------------------- sequential


def log_wealth(counts: PairCounts, d0: float, against: str = "below") -> float:
    """The log of the mixture wealth against the null ``d <= d0`` (``against="below"``:
    evidence that ``d > d0``) or ``d >= d0`` (``"above"``: evidence that ``d < d0``)."""
    x = np.array([1.0, 0.0, -1.0]) - d0  # only B, concordant, only A
    n = np.array([counts.b_only, counts.both + counts.neither, counts.a_only], dtype=float)
    c = np.array(BETS)[:, None]
    if against == "below":
        factors = 1.0 + c * x / (1.0 + d0)
    elif against == "above":
        factors = 1.0 - c * x / (1.0 - d0)
    else:
        raise ValueError(f"against must be 'below' or 'above' (got {against!r})")
    logs = (np.where(n > 0, n * np.log(factors), 0.0)).sum(axis=1)
    top = logs.max()
    return float(top + math.log(np.exp(logs - top).mean()))


def anytime_bounds(counts: PairCounts, alpha: float) -> tuple[float, float]:
    """The anytime-valid interval on ``d`` after ``counts``: each end at level ``1 - alpha``,
    for every n at once (the wealths inverted by bisection, rounded outwards)."""
    threshold = -math.log(alpha)

    def lowest(side: str, sign: float) -> float:
        # the wealth against d <= d0 falls as d0 grows: the least d0 it does not reject
        low, high = -1.0, 1.0
        while high - low > 1e-6:
            middle = (low + high) / 2
            if log_wealth(counts, sign * middle, side) < threshold:
                high = middle
            else:
                low = middle
        return low

    return max(-1.0, lowest("below", 1.0)), min(1.0, -lowest("above", -1.0))


def simulate(probabilities: tuple[float, float, float, float], margin: float, alpha: float,
             streams: int, max_pairs: int, rng: np.random.Generator | None = None,
             outcomes: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Run the sequential test on ``streams`` i.i.d. paired streams at once (vectorised), with
    ``probabilities`` those of (both, only A, only B, neither), drawn from ``rng``, or on given
    ``outcomes`` (streams x max_pairs, 0 both, 1 only A, 2 only B, 3 neither). Returns
    ``(decisions, stops)``: +1 shown, -1 refuted, 0 undecided, and the pairs each used. The
    rule of :class:`~.paired_methods.SequentialPairs`, on the same wealths."""
    d0, threshold = -margin, -math.log(alpha)
    c = np.array(BETS)[:, None]
    x = np.array([1.0, 0.0, -1.0]) - d0  # columns: only B, concordant, only A
    up, down = np.log1p(c * x / (1.0 + d0)), np.log1p(-c * x / (1.0 - d0))  # bets x columns
    column = np.array([1, 2, 0, 1])  # both, only A, only B, neither -> their column
    cumulative = np.cumsum(probabilities)
    decisions = np.zeros(streams, dtype=int)
    stops = np.full(streams, max_pairs)
    held = np.zeros((streams, 3))
    open_ = np.arange(streams)
    block, start = 256, 0
    while start < max_pairs and open_.size:
        width = min(block, max_pairs - start)
        if outcomes is None:
            kinds = np.searchsorted(cumulative, rng.random((open_.size, width)), side="right")
        else:
            kinds = outcomes[open_, start:start + width]
        counts = held[open_, None, :] + np.cumsum(np.eye(3)[column[kinds.clip(max=3)]], axis=1)
        lw_up, lw_down = _log_mean_exp(counts @ up.T), _log_mean_exp(counts @ down.T)
        shown = lw_up >= threshold
        hit = shown | (lw_down >= threshold)
        done = hit.any(axis=1)
        first = hit.argmax(axis=1)
        rows = open_[done]
        stops[rows] = start + 1 + first[done]
        decisions[rows] = np.where(shown[done, first[done]], 1, -1)
        held[open_] = counts[:, -1, :]
        open_ = open_[~done]
        start += width
    return decisions, stops


def _log_mean_exp(x: np.ndarray) -> np.ndarray:
    top = x.max(axis=-1, keepdims=True)
    return (top + np.log(np.exp(x - top).mean(axis=-1, keepdims=True)))[..., 0]
