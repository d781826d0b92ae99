"""Pairs used by ``vlb compare --sequential`` against a fixed-N McNemar plan of equal power.

Paired Bernoulli outcomes, vectorised (no environment): each scenario gives the probabilities
of (both succeed, only A, only B, neither). STREAMS sequential comparisons (superiority, margin
0, alpha 0.05, capped at 5000 pairs) are simulated with :func:`vlb_gym.verify.paired.simulate`;
"fixed N, equal power" is the least N whose one-sided McNemar exact test at level 0.05 shows
``P_B > P_A`` with at least the probability the sequential test did (at most 0.99), that power
computed exactly (the discordant count is Binomial(N, P[only A] + P[only B]); given it, "only B"
is binomial). The last column is 1 - (mean pairs of the sequential test) / (that N). A second
table caps the sequential test where its power is 0.90 (the least cap, to 2%, found by
bisection) and compares it with the fixed-N plan of power 0.90.

    python benchmarks/paired_power.py
"""

from __future__ import annotations

import time

import numpy as np
from scipy.stats import binom

from vlb_gym.verify import paired

ALPHA, STREAMS, CAP, SEED = 0.05, 10_000, 5000, 1
SCENARIOS = {  # both, only A, only B, neither
    "A 0.90, B 0.97 (correlated)": (0.89, 0.01, 0.08, 0.02),
    "A 0.80, B 0.90": (0.75, 0.05, 0.15, 0.05),
    "A 0.95, B 0.98": (0.94, 0.01, 0.04, 0.01),
    "A 0.70, B 0.95": (0.68, 0.02, 0.27, 0.03),
    "A = B = 0.95 (null)": (0.92, 0.03, 0.03, 0.02),
}


def mcnemar_power(n: int, a_only: float, b_only: float) -> float:
    """The exact probability that McNemar's one-sided exact test at ALPHA rejects, n pairs."""
    m = np.arange(n + 1)
    # the least k with P[Bin(m, 1/2) >= k] <= ALPHA, for every m at once
    k = binom.isf(ALPHA, m, 0.5) + 1
    while True:
        too_big = binom.sf(k - 2, m, 0.5) <= ALPHA  # k - 1 rejects as well
        if not too_big.any():
            break
        k = np.where(too_big, k - 1, k)
    s = a_only + b_only
    return float(np.sum(binom.pmf(m, n, s) * binom.sf(k - 1, m, b_only / s)))


def equal_power_n(a_only: float, b_only: float, power: float) -> int:
    power = min(power, 0.99)
    low, high = 1, 2
    while mcnemar_power(high, a_only, b_only) < power:
        low, high = high, high * 2
    while high - low > 1:  # the power is not monotone in n for tiny n: bisection is close
        middle = (low + high) // 2
        low, high = (low, middle) if mcnemar_power(middle, a_only, b_only) >= power \
            else (middle, high)
    return high


def cap_for_power(probabilities, power: float, rng) -> tuple[int, np.ndarray, np.ndarray]:
    """The least cap (to 2%) at which the capped sequential test shows the claim with
    probability >= ``power``, with that cap's decisions and stops."""
    low, high = 1, 64
    while True:
        decisions, stops = paired.simulate(probabilities, 0.0, ALPHA, STREAMS, high, rng)
        if (decisions == 1).mean() >= power:
            break
        low, high = high, high * 2
    found = (high, decisions, stops)
    while high - low > max(1, high // 50):
        middle = (low + high) // 2
        decisions, stops = paired.simulate(probabilities, 0.0, ALPHA, STREAMS, middle, rng)
        if (decisions == 1).mean() >= power:
            high, found = middle, (middle, decisions, stops)
        else:
            low = middle
    return found


def main() -> None:
    rng = np.random.default_rng(SEED)
    print(f"superiority, alpha {ALPHA}, {STREAMS} streams per scenario, cap {CAP} pairs")
    print("| scenario | shown | refuted | mean pairs | median pairs | fixed N, equal power "
          "| pairs saved |")
    print("|---|---|---|---|---|---|---|")
    started = time.perf_counter()
    for name, probabilities in SCENARIOS.items():
        decisions, stops = paired.simulate(probabilities, 0.0, ALPHA, STREAMS, CAP, rng)
        shown = float((decisions == 1).mean())
        _, a_only, b_only, _ = probabilities
        if b_only > a_only:
            n = equal_power_n(a_only, b_only, shown)
            saved = f"{1 - stops.mean() / n:.0%}"
        else:
            n, saved = "-", "- (no effect to detect)"
        print(f"| {name} | {shown:.3f} | {(decisions == -1).mean():.3f} | {stops.mean():.1f} "
              f"| {np.median(stops):.0f} | {n} | {saved} |")
    print("\npower 0.90: the sequential test capped where it shows the claim with probability "
          ">= 0.90, against the fixed-N McNemar plan of power 0.90")
    print("| scenario | cap | shown | mean pairs | fixed N, power 0.90 | pairs saved |")
    print("|---|---|---|---|---|---|")
    for name, probabilities in SCENARIOS.items():
        _, a_only, b_only, _ = probabilities
        if b_only <= a_only:
            continue
        cap, decisions, stops = cap_for_power(probabilities, 0.90, rng)
        n = equal_power_n(a_only, b_only, 0.90)
        print(f"| {name} | {cap} | {(decisions == 1).mean():.3f} | {stops.mean():.1f} | {n} "
              f"| {1 - stops.mean() / n:.0%} |")
    print(f"({time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
