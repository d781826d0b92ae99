"""Tests for vlb_gym.verify.bounds against independent scipy / exact computations."""

from __future__ import annotations

import math
from decimal import Decimal, localcontext
from fractions import Fraction

import pytest
from scipy.stats import beta, binom

from vlb_gym.verify.bounds import confidence, lower_bound, min_episodes

NS = [1, 2, 5, 20, 59, 100, 500, 2000]
KS = [0, 1, 3, 10]
EPSILONS = [1e-4, 0.01, 0.05, 0.3, 0.9]
DELTAS = [1e-6, 0.01, 0.05, 0.5, 0.95]

GRID_NKE = [(n, k, e) for n in NS for k in KS for e in EPSILONS if k <= n]
GRID_NKD = [(n, k, d) for n in NS for k in KS for d in DELTAS if k <= n]


# --------------------------------------------------------------------------- confidence


@pytest.mark.parametrize("n,k,eps", GRID_NKE)
def test_confidence_matches_scipy(n, k, eps):
    expected = 1.0 - binom.cdf(k, n, eps)
    assert confidence(n, k, eps) == pytest.approx(expected, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("n,k,eps", [(1, 0, 0.05), (5, 1, 0.3), (20, 3, 0.05), (59, 0, 0.05),
                                     (100, 10, 0.05), (100, 1, 0.01), (500, 3, 0.01),
                                     (10, 9, 0.9), (7, 7, 0.5)])
def test_confidence_matches_exact_rational(n, k, eps):
    """1 - sum_{i<=k} C(n,i) eps^i (1-eps)^(n-i), computed exactly with fractions."""
    e = Fraction(eps)
    cdf = sum(math.comb(n, i) * e**i * (1 - e) ** (n - i) for i in range(k + 1))
    expected = float(1 - cdf)
    assert confidence(n, k, eps) == pytest.approx(expected, rel=1e-12, abs=1e-15)


def test_confidence_paper_figures():
    assert round(confidence(100, 0, 0.05), 5) == 0.99408
    assert round(confidence(59, 0, 0.05), 5) == 0.95151
    assert confidence(59, 0, 0.05) >= 0.95 > confidence(58, 0, 0.05)


def test_confidence_all_failures_is_zero():
    # P[Binomial(n, eps) > n] = 0
    assert confidence(10, 10, 0.5) == 0.0


def test_confidence_tiny_epsilon_keeps_precision():
    # 1 - (1 - eps)**n for tiny eps must not cancel to 0 (expm1/log1p path)
    assert confidence(1, 0, 1e-15) == pytest.approx(1e-15, rel=1e-9)
    assert confidence(3, 0, 1e-12) == pytest.approx(3e-12, rel=1e-9)


@pytest.mark.parametrize("k,eps", [(0, 0.05), (2, 0.05), (5, 0.01), (1, 0.3)])
def test_confidence_increases_with_n(k, eps):
    values = [confidence(n, k, eps) for n in range(max(k, 1), 121)]
    assert all(0.0 <= v <= 1.0 for v in values)
    pairs = list(zip(values, values[1:]))
    assert all(b >= a for a, b in pairs)
    # strictly increasing until the value saturates at 1 in floating point
    assert all(b > a for a, b in pairs if b < 1.0 - 1e-12)
    assert values[-1] > values[0]


@pytest.mark.parametrize("n,eps", [(50, 0.1), (100, 0.05), (10, 0.5)])
def test_confidence_decreases_with_k(n, eps):
    values = [confidence(n, k, eps) for k in range(n + 1)]
    assert all(b < a for a, b in zip(values, values[1:]) if a > 0.0)
    assert values[-1] == 0.0


# --------------------------------------------------------------------------- lower_bound


@pytest.mark.parametrize("n,k,delta", GRID_NKD)
def test_lower_bound_matches_scipy(n, k, delta):
    if k == n:
        expected = 0.0
    elif k == 0:
        expected = delta ** (1.0 / n)
    else:
        expected = beta.ppf(delta, n - k, k + 1)
    assert lower_bound(n, k, delta) == pytest.approx(expected, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("n,k,delta", [(n, k, d) for n, k, d in GRID_NKD if k < n])
def test_lower_bound_defining_property(n, k, delta):
    """Clopper-Pearson: P[Binomial(n, lb) >= n - k] = delta."""
    lb = lower_bound(n, k, delta)
    assert 0.0 < lb < 1.0
    assert binom.sf(n - k - 1, n, lb) == pytest.approx(delta, rel=1e-8, abs=1e-8)


@pytest.mark.parametrize("n", [1, 10, 100])
def test_lower_bound_all_failures_is_zero(n):
    assert lower_bound(n, n, 0.05) == 0.0


def test_lower_bound_monotone():
    # more failures -> lower bound; more episodes (same k) -> higher bound; larger delta -> higher
    lbs_k = [lower_bound(100, k, 0.05) for k in range(101)]
    assert all(b < a for a, b in zip(lbs_k, lbs_k[1:]))
    lbs_n = [lower_bound(n, 2, 0.05) for n in range(3, 200)]
    assert all(b > a for a, b in zip(lbs_n, lbs_n[1:]))
    lbs_d = [lower_bound(50, 3, d) for d in (1e-6, 1e-3, 0.05, 0.5, 0.9)]
    assert all(b > a for a, b in zip(lbs_d, lbs_d[1:]))


# --------------------------------------------------------------------------- duality

DUAL_GRID = [(n, k, e) for n in (10, 59, 100, 300, 1000) for k in (0, 1, 5, 20)
             for e in (0.01, 0.05, 0.1, 0.3)
             if k < n and 1e-4 <= binom.cdf(k, n, e) <= 1 - 1e-4]


def test_duality_grid_is_not_empty():
    assert len(DUAL_GRID) >= 20


@pytest.mark.parametrize("n,k,eps", DUAL_GRID)
def test_duality(n, k, eps):
    delta = 1.0 - confidence(n, k, eps)
    assert lower_bound(n, k, delta) == pytest.approx(1.0 - eps, rel=1e-8, abs=1e-9)


# --------------------------------------------------------------------------- min_episodes


def test_min_episodes_paper_figure():
    assert min_episodes(0.05, 0.95) == 59
    assert min_episodes(0.05, 0.95, 0) == 59


@pytest.mark.parametrize("eps", [0.001, 0.01, 0.03, 0.05, 0.1, 0.25, 0.5])
@pytest.mark.parametrize("conf", [0.1, 0.5, 0.8, 0.9, 0.95, 0.99, 0.999, 0.999999])
def test_min_episodes_zero_failures_formula(eps, conf):
    delta = 1.0 - conf
    expected = math.ceil(math.log(delta) / math.log(1.0 - eps))
    n = min_episodes(eps, conf)
    assert isinstance(n, int)
    assert n == expected
    assert confidence(n, 0, eps) >= conf
    assert n == 1 or confidence(n - 1, 0, eps) < conf


@pytest.mark.parametrize("eps", [0.01, 0.05, 0.2])
@pytest.mark.parametrize("conf", [0.5, 0.9, 0.95, 0.99, 0.999])
@pytest.mark.parametrize("k", [1, 2, 5, 10])
def test_min_episodes_with_failures_is_minimal(eps, conf, k):
    n = min_episodes(eps, conf, k)
    assert isinstance(n, int)
    assert n > k
    assert confidence(n, k, eps) >= conf
    assert confidence(n - 1, k, eps) < conf


@pytest.mark.parametrize("eps,conf,k", [(0.05, 0.95, 1), (0.05, 0.95, 3), (0.1, 0.99, 2),
                                        (0.2, 0.5, 5), (0.3, 0.999, 4)])
def test_min_episodes_with_failures_brute_force(eps, conf, k):
    """Linear scan with scipy only (independent of the package)."""
    n = k + 1
    while binom.sf(k, n, eps) < conf:
        n += 1
    assert min_episodes(eps, conf, k) == n


def test_min_episodes_known_values():
    # P[Bin(n, 0.05) > 1] >= 0.95 first at n = 93 (standard success-run table)
    assert min_episodes(0.05, 0.95, 1) == 93
    # eps=0.5, conf=0.75: 1 - 0.5**2 = 0.75 exactly
    assert min_episodes(0.5, 0.75) == 2


def exact_miss(n: int, k: int, eps: float) -> Decimal:
    """P[Binomial(n, eps) <= k] to 60 digits, eps taken exactly as the float it is."""
    with localcontext() as context:
        context.prec = 60
        e = Decimal(eps)
        term = (1 - e) ** n
        total = term
        for j in range(k):
            term = term * (n - j) / (j + 1) * e / (1 - e)
            total += term
        return total


@pytest.mark.parametrize("eps, conf, k", [
    (0.5, 0.999999999999, 40), (1e-3, 1 - 1e-15, 200), (1e-10, 0.99, 1), (1e-10, 0.999999, 5),
    (0.05, 1 - 1e-14, 0), (0.2, 0.999999999999999, 3)])
def test_min_episodes_is_exact_where_the_confidence_has_no_digits_left(eps, conf, k):
    """Against 60-digit arithmetic: N keeps the miss probability within 1 - confidence, and
    N - 1 does not (a confidence near 1 compared as a float once printed N short)."""
    n = min_episodes(eps, conf, k)
    allowed = 1 - Decimal(conf)
    assert exact_miss(n, k, eps) <= allowed < exact_miss(n - 1, k, eps)


def test_min_episodes_increases_with_failures():
    ns = [min_episodes(0.05, 0.95, k) for k in range(8)]
    assert all(b > a for a, b in zip(ns, ns[1:]))


# --------------------------------------------------------------------------- bad inputs


@pytest.mark.parametrize("call,match", [
    (lambda: confidence(0, 0, 0.05), "episodes"),
    (lambda: confidence(-3, 0, 0.05), "episodes"),
    (lambda: confidence(5.0, 0, 0.05), "episodes"),
    (lambda: confidence(10, 11, 0.05), "failures"),
    (lambda: confidence(10, -1, 0.05), "failures"),
    (lambda: confidence(10, 1.0, 0.05), "failures"),
    (lambda: confidence(10, 0, 0.0), "epsilon"),
    (lambda: confidence(10, 0, 1.0), "epsilon"),
    (lambda: confidence(10, 0, 1.5), "epsilon"),
    (lambda: confidence(10, 0, -0.1), "epsilon"),
    (lambda: confidence(10, 0, float("nan")), "epsilon"),
    (lambda: lower_bound(0, 0, 0.05), "episodes"),
    (lambda: lower_bound(10.5, 0, 0.05), "episodes"),
    (lambda: lower_bound(10, 11, 0.05), "failures"),
    (lambda: lower_bound(10, -1, 0.05), "failures"),
    (lambda: lower_bound(10, 0, 0.0), "delta"),
    (lambda: lower_bound(10, 0, 1.0), "delta"),
    (lambda: lower_bound(10, 0, 1.5), "delta"),
    (lambda: min_episodes(0.0, 0.95), "epsilon"),
    (lambda: min_episodes(1.0, 0.95), "epsilon"),
    (lambda: min_episodes(1.5, 0.95), "epsilon"),
    (lambda: min_episodes(0.05, 1.0), "confidence"),
    (lambda: min_episodes(0.05, 0.0), "confidence"),
    (lambda: min_episodes(0.05, 0.95, -1), "failures"),
    (lambda: min_episodes(0.05, 0.95, 1.5), "failures"),
])
def test_bad_inputs_raise_value_error(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_counts_accept_numpy_integers_and_refuse_booleans():
    import numpy as np

    assert confidence(np.int64(100), np.int64(0), 0.05) == pytest.approx(0.99408, abs=1e-5)
    with pytest.raises(ValueError, match="episodes"):
        confidence(True, 0, 0.5)
    with pytest.raises(ValueError, match="failures"):
        lower_bound(10, False, 0.05)
