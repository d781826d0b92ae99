"""The closeness of a promise (abstractor.closeness): a score in [0, 1] that is 1 exactly when
the promise holds, over random conditions of integer variables, lists and their combinations
(Hypothesis), judged against Python's own truth of the same text."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vlb_gym.abstractor.closeness import Closeness
from vlb_gym.core.expressions import guard_namespace

NAMES = {"w": None, "x": None, "y": None, "z": None, "xs": None, "ys": None, "len": 1}
ORDER = ["<", "<=", ">", ">=", "==", "!="]

atoms = st.one_of(
    st.builds(lambda a, op, b: f"{a} {op} {b}", st.sampled_from(["x", "y", "z", "x + 1"]),
              st.sampled_from(ORDER), st.sampled_from(["x", "y", "z", "0", "9", "y - 1"])),
    st.builds(lambda a, op, b: f"{a} {op} {b}", st.sampled_from(["xs", "ys", "xs[:1]"]),
              st.sampled_from(["==", "!="]), st.sampled_from(["xs", "ys", "[0, 1]"])),
    st.builds(lambda a, b: f"{a} in {b}", st.sampled_from(["x", "y"]),
              st.sampled_from(["xs", "ys"])),
    st.builds(lambda op: f"w {op} 60", st.sampled_from(ORDER)),  # close floats (grams)
    st.sampled_from(["True", "False", "len(xs) < len(ys)"]))


def _combine(parts: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    return st.one_of(
        st.builds(lambda a, b: f"({a}) and ({b})", parts, parts),
        st.builds(lambda a, b: f"({a}) or ({b})", parts, parts),
        st.builds(lambda a: f"not ({a})", parts),
        st.builds(lambda a, c, b: f"({a}) if ({c}) else ({b})", parts, parts, parts))


conditions = st.recursive(atoms, _combine, max_leaves=8)
values = st.fixed_dictionaries({
    "w": st.sampled_from([60.0, 60.0 + 1e-17, 60 + 1e-12, 59.9999999999999, 61.5]),
    "x": st.integers(-3, 12), "y": st.integers(-3, 12), "z": st.integers(-3, 12),
    "xs": st.lists(st.integers(0, 3), max_size=4), "ys": st.lists(st.integers(0, 3), max_size=4)})


@settings(max_examples=400, deadline=None)
@given(conditions, values)
def test_closeness_is_one_exactly_when_the_condition_holds(condition, bound):
    score = Closeness(condition, NAMES)(guard_namespace(bound))
    assert 0.0 <= score <= 1.0
    assert (score == 1.0) == bool(eval(condition, {"len": len}, dict(bound)))  # noqa: S307


@pytest.mark.parametrize("condition, expected", [
    ("not (x < 9)", 1.0),  # "x < 9" fails at x == 9 (scoring 1/2): its negation holds
    ("x < 9", 0.5), ("x >= 10", 0.5), ("x == 11", 1 / 3), ("xs == [1, 2, 3, 4]", 0.5),
    ("x == 9 and xs == [1, 2]", 1.0), ("x < 9 or x == 8", 0.5),
    ("(x < 9) and (xs == [1])", 0.5 * 0.5 + 0.5 * 0.5)])
def test_closeness_grades_along_the_promise(condition, expected):
    bound = guard_namespace({"x": 9, "y": 0, "z": 0, "xs": [1, 2], "ys": []})
    assert Closeness(condition, NAMES)(bound) == pytest.approx(expected)


@pytest.mark.parametrize("w", [float("inf"), float("-inf"), float("nan"), 10**30, -10**30])
@pytest.mark.parametrize("condition", ["w < 60", "w == 60", "not (w >= 60)", "w > 60"])
def test_closeness_of_extreme_values_stays_a_score_that_is_one_only_when_it_holds(w, condition):
    score = Closeness(condition, NAMES)(guard_namespace({"w": w}))
    assert 0.0 <= score <= 1.0
    assert (score == 1.0) == bool(eval(condition, {}, {"w": w}))  # noqa: S307
