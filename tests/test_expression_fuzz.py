"""Property-based fuzzing of the expression language (Hypothesis).

Random expressions over the whole grammar -- arithmetic, comparisons, comprehensions, slices,
displays, every bounded builtin, the grid env's real helpers bound to a real observation, and a
chain of behavior functions that double their calls -- seeded with the review's payloads (huge
constants, repetitions, nested membership tests, ``round`` digits). Every case must be refused at
load (ExpressionError) or evaluate, successfully or with an exception, within a memory bound, the
budgets ending any long evaluation (the test's timeout would catch one that hangs; no assertion
on time, which a loaded machine stretches): nothing an expression says can hang or exhaust the
process.
"""

from __future__ import annotations

import time
import tracemalloc

import gymnasium as gym
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from vlb_gym.core.budget import Budget
from vlb_gym.core.expressions import BUILTINS, Expression, ExpressionError, guard_namespace

EXAMPLES = 3000
PEAK_BYTES = 64 * 2**20
CHAIN = 16  # f0 ... f15, each calling the previous one twice

VALUES = {"x": 7, "big": 10**9, "xs": list(range(100)), "s": "hello", "long": "ab" * 100,
          "grid": [[1, 2, 3], [4, 5, 6]], "cells": [(i, j) for i in range(10) for j in range(10)]}
HELPERS = {"explored": 0, "adjacent": 1, "label": 1, "goal_found": 0, "goal_cell": 0,
           "current_cell": 0}
ARITY = {**{name: None for name in BUILTINS}, **HELPERS,
         **{f"f{k}": 0 for k in range(CHAIN)}, **{name: -1 for name in VALUES}}

atoms = st.one_of(
    st.integers(-10**9, 10**9).map(str),
    st.sampled_from(["0", "1", "-1", "2", "10000", "1000000000", "0.5", "1e9", "True", "None",
                     "''", "'ab'", "'" + "z" * 200 + "'", "'%d'"]),
    st.sampled_from(sorted(VALUES)),
    st.sampled_from(["explored()", "adjacent(current_cell())", "label((0, 0))", "goal_found()",
                     "goal_cell()", "current_cell()", "f15()", "f8()"]),
    st.sampled_from(["v", "w"]),  # comprehension targets (unknown outside one: refused at load)
)


def extend(inner: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    pair = st.tuples(inner, inner)
    return st.one_of(
        st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "//", "%"]), inner)
        .map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        st.tuples(inner, st.sampled_from(["==", "!=", "<", "<=", ">", ">=", "in", "not in"]),
                  inner).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        st.tuples(inner, st.sampled_from(["and", "or"]), inner)
        .map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        inner.map(lambda e: f"(not {e})"),
        inner.map(lambda e: f"(-{e})"),
        st.tuples(inner, inner, inner).map(lambda t: f"({t[0]} if {t[1]} else {t[2]})"),
        st.tuples(st.sampled_from(sorted(BUILTINS)), inner).map(lambda t: f"{t[0]}({t[1]})"),
        st.tuples(st.sampled_from(["min", "max", "round", "sum", "int"]), pair)
        .map(lambda t: f"{t[0]}({t[1][0]}, {t[1][1]})"),
        st.tuples(st.sampled_from(["label", "adjacent"]), inner).map(lambda t: f"{t[0]}({t[1]})"),
        pair.map(lambda p: f"{p[0]}[{p[1]}]"),
        st.tuples(inner, st.sampled_from(["", "1", "-1", "big"]),
                  st.sampled_from(["", "2", "-1"])).map(lambda t: f"{t[0]}[{t[1]}:{t[2]}]"),
        st.lists(inner, max_size=4).map(lambda es: "[" + ", ".join(es) + "]"),
        st.lists(inner, min_size=2, max_size=3).map(lambda es: "(" + ", ".join(es) + ")"),
        st.tuples(inner, inner).map(lambda t: f"[{t[0]} for v in {t[1]}]"),
        st.tuples(inner, inner, inner).map(lambda t: f"[{t[0]} for v in {t[1]} for w in {t[2]}]"),
        st.tuples(inner, inner, inner).map(lambda t: f"sum({t[0]} for v in {t[1]} if {t[2]})"),
        st.tuples(inner, st.sampled_from(["10000", "9999", "100", "big", "x"]))
        .map(lambda t: f"([{t[0]}] * {t[1]})"),
    )


expressions = st.one_of(
    st.recursive(atoms, extend, max_leaves=12),
    st.sampled_from([  # the review's payloads, as seeds the generated cases vary around
        "round(5, -1000000000)",
        "[[0]*10000 in [[0]*9999+[1]]*10000 for a in [0]*10000 for b in [0]*19]",
        "[s * 10000 for v in xs for w in xs]",
        "sorted([[v] * 100 for v in [0] * 10000])",
        "f15() + f15()",
        "len([f8() for v in xs])",
        "[cells * 100 for v in xs for w in xs]",
    ]),
)


@pytest.fixture(scope="module")
def namespace():
    """Real grid helpers bound to a real observation, the values above and the function chain."""
    env = gym.make("VLB-GridExplore-v0")
    obs, _ = env.reset(seed=0)
    helpers = env.unwrapped.make_helpers()
    helpers.bind(obs)
    env.close()
    budget = Budget()
    ns = guard_namespace({**VALUES, **budget.charging(helpers.functions())}, budget)
    ns["f0"] = Expression("1", {}, "f0", args=()).evaluate(ns)
    for k in range(1, CHAIN):
        ns[f"f{k}"] = Expression(f"f{k - 1}() + f{k - 1}()", {f"f{k - 1}": 0}, f"f{k}",
                                 args=()).evaluate(ns)
    return ns


@pytest.mark.timeout(600)
@settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(source=expressions)
def test_every_expression_is_refused_or_bounded(namespace, source):
    try:
        expression = Expression(source, ARITY, "fuzz")
    except ExpressionError:
        event("refused at load")
        return
    tracemalloc.start()
    started = time.process_time()  # CPU time: what the expression costs, not the machine's load
    try:
        expression.evaluate(namespace)
        event("evaluated")
    except Exception as exc:  # noqa: BLE001 - a failed evaluation is a failed episode: fine
        event(f"failed: {type(exc).__name__}")
    finally:
        seconds = time.process_time() - started
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
    event(f"CPU time {'>' if seconds > 0.1 else '<'} 0.1 s")  # a statistic, not an assertion
    assert peak < PEAK_BYTES, f"{source!r} allocated {peak / 2**20:.0f} MiB"
