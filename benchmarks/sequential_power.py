"""Error rates and stopping times of ``vlb verify --sequential`` against the fixed-N plan.

Bernoulli(p) behaviors, vectorised (no environment): for each p, RUNS independent sequential
campaigns capped at the default 20 x 59 = 1180 episodes (eps = delta = 0.05). "fixed N, equal
power" is the least N whose fixed-N Clopper-Pearson campaign (certify when the failures are at most
the largest k with ``bounds.confidence(N, k, eps) >= 1 - delta``) certifies with at least the
probability the sequential test certified with, at that p (at most 0.99: a certification rate of
1.000 over the runs is read as 0.99).

    python benchmarks/sequential_power.py
"""

from __future__ import annotations

import time

import numpy as np
from scipy.stats import binom

from vlb_gym.verify import bounds
from vlb_gym.verify.sequential import default_max_episodes, simulate

EPS, DELTA, RUNS, SEED = 0.05, 0.05, 4000, 1


def allowed_failures(n: int) -> int:
    """Largest k with confidence(n, k, eps) >= 1 - delta; -1 if none."""
    k = -1
    while k + 1 < n and bounds.confidence(n, k + 1, EPS) >= 1 - DELTA:
        k += 1
    return k


def fixed_n_equal_power(p: float, power: float) -> int | None:
    k = -1
    for n in range(1, 20000):
        while k + 1 < n and bounds.confidence(n, k + 1, EPS) >= 1 - DELTA:
            k += 1
        if k >= 0 and binom.cdf(k, n, 1 - p) >= power:
            return n
    return None


def main() -> None:
    cap = default_max_episodes(EPS, DELTA)
    plan = bounds.min_episodes(EPS, 1 - DELTA, 0)
    print(f"eps = delta = {EPS}, {RUNS} runs per p, cap {cap}, fixed-N plan (0 failures) {plan}")
    print("p      certified  refuted  undecided  mean episodes  (when decided)  "
          "fixed N, equal power")
    started = time.perf_counter()
    for p in (0.90, 0.93, 0.94, 0.95, 0.96, 0.97, 0.98, 0.99, 1.0):
        decisions, stops = simulate(p, EPS, DELTA, RUNS, cap, np.random.default_rng(SEED))
        cert, ref = (decisions == 1).mean(), (decisions == -1).mean()
        fixed = "(claim false)" if p < 1 - EPS else (
            fixed_n_equal_power(p, min(cert, 0.99)) if cert > 0 else "-")
        decided = stops[decisions != 0].mean() if (decisions != 0).any() else float("nan")
        print(f"{p:.2f}   {cert:.3f}      {ref:.3f}    {1 - cert - ref:.3f}      "
              f"{stops.mean():7.1f}        {decided:7.1f}         {fixed}")
    print(f"({time.perf_counter() - started:.1f} s)")


if __name__ == "__main__":
    main()
