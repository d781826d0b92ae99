"""Tests for the restricted expression language (vlb_gym.core.expressions)."""

from __future__ import annotations

import itertools

import pytest

from vlb_gym.core.budget import MAX_SIZE, MAX_WORK, Budget
from vlb_gym.core.expressions import BUILTINS, Expression, ExpressionError, guard_namespace
from vlb_gym.core.helpers import Helpers, helper

WHERE = "behavior.json: nodes.n1.guard"

#: Declared names: all builtins with any arity, plain values, fixed-arity helpers.
NAMES: dict[str, int | None] = {
    **{name: None for name in BUILTINS},
    "x": -1, "xs": -1, "s": -1, "flag": -1, "grid": -1,
    "double": 1, "add": 2, "nothing": 0,
}

VALUES = {
    "x": 7, "xs": [3, 1, 4, 1, 5, 9, 2, 6], "s": "hello", "flag": True,
    "grid": [[1, 2, 3], [4, 5, 6]],
    "double": lambda v: 2 * v, "add": lambda a, b: a + b, "nothing": lambda: None,
}


def run(source: str, names=None, values=None, args=None):
    expr = Expression(source, NAMES if names is None else names, WHERE, args=args)
    return expr.evaluate(guard_namespace(VALUES if values is None else values))


# --------------------------------------------------------------------------- valid expressions


@pytest.mark.parametrize("source,expected", [
    # arithmetic
    ("1 + 2 * 3", 7),
    ("(1 + 2) * 3", 9),
    ("x - 10", -3),
    ("x / 2", 3.5),
    ("x // 2", 3),
    ("x % 4", 3),
    ("-x + +3", -4),
    ("2.5 * 4", 10.0),
    # comparisons
    ("x > 5", True),
    ("1 < x <= 7", True),
    ("x == 7 and x != 8", True),
    ("3 in xs", True),
    ("7 not in xs", True),
    ("s == 'hello'", True),
    # boolean logic
    ("flag and not x > 10", True),
    ("not flag or x < 0", False),
    ("x > 100 or x", 7),
    # conditional expressions
    ("'big' if x > 5 else 'small'", "big"),
    ("'big' if x > 50 else 'small'", "small"),
    # comprehensions and generators
    ("[v * 2 for v in xs if v > 3]", [8, 10, 18, 12]),
    ("[v for row in grid for v in row if v % 2 == 0]", [2, 4, 6]),
    ("[(i, v) for i, v in [(0, 'a'), (1, 'b')]]", [(0, "a"), (1, "b")]),
    ("sum(v for v in xs)", 31),
    ("sum(v * v for v in xs if v < 3)", 1 + 1 + 4),
    ("any(v > 8 for v in xs)", True),
    ("all(v > 0 for v in xs)", True),
    ("[[v + 1 for v in row] for row in grid]", [[2, 3, 4], [5, 6, 7]]),
    # literals, subscripts, slices
    ("(1, 'a', None, True)", (1, "a", None, True)),
    ("[1, [2, 3], ()]", [1, [2, 3], ()]),
    ("xs[0]", 3),
    ("xs[-1]", 6),
    ("xs[1:4]", [1, 4, 1]),
    ("xs[::2]", [3, 4, 5, 2]),
    ("xs[::-1][0]", 6),
    ("grid[1][2]", 6),
    ("s[1:3]", "el"),
    # builtins and helpers
    ("len(xs)", 8),
    ("max(xs) - min(xs)", 8),
    ("abs(-x)", 7),
    ("round(2.675, 1)", 2.7),
    ("int('12') + int(float('2.5'))", 14),
    ("bool(0)", False),
    ("sorted(xs)[:3]", [1, 1, 2]),
    ("double(x)", 14),
    ("add(double(1), 3)", 5),
    ("nothing() == None", True),
    ("argmax(xs)", 5),
    ("argmin(xs)", 1),
    ("argmax([2, 5, 5, 1])", 1),  # first maximum
    ("argmin([4, 0, 3, 0])", 1),  # first minimum
    ("[0] * 10", [0] * 10),
    ("3 * 'ab'", "ababab"),
    ("x * 3", 21),
])
def test_valid_expressions_evaluate(source, expected):
    assert run(source) == expected


def test_multiline_source_and_surrounding_whitespace():
    assert run("  (x +\n 1)\n ") == 8


def test_names_attribute_lists_referenced_names():
    expr = Expression("double(x) + sum(v for v in xs)", NAMES, WHERE)
    assert {"double", "x", "sum", "v", "xs"} <= expr.names
    assert "add" not in expr.names


def test_expression_is_reusable_with_different_namespaces():
    expr = Expression("double(x) + 1", {"double": 1, "x": -1}, WHERE)
    assert expr.evaluate(guard_namespace({"double": lambda v: 2 * v, "x": 1})) == 3
    assert expr.evaluate(guard_namespace({"double": lambda v: 3 * v, "x": 2})) == 7
    assert repr(expr) == "Expression('double(x) + 1')"


def test_function_expression_is_callable():
    expr = Expression("x * 2 + offset", {"x": -1, "offset": -1}, WHERE, args=("x",))
    fn = expr.evaluate(guard_namespace({"offset": 1}))
    assert callable(fn)
    assert fn(3) == 7
    assert fn(10) == 21


def test_function_expression_several_args_and_helpers():
    names = {"a": -1, "b": -1, "argmax": 1, "len": 1}
    expr = Expression("argmax([a, b]) * 10 + len([v for v in [a, b] if v])",
                      names, WHERE, args=("a", "b"))
    fn = expr.evaluate(guard_namespace({}))
    assert fn(1, 5) == 12
    assert fn(0, -1) == 1


def test_function_expression_can_call_another_function():
    ns = guard_namespace({})
    ns["inc"] = Expression("n + 1", {"n": -1}, WHERE, args=("n",)).evaluate(ns)
    twice = Expression("inc(inc(n))", {"n": -1, "inc": 1}, WHERE, args=("n",)).evaluate(ns)
    assert twice(5) == 7


def test_once_computes_a_function_once_per_evaluation_and_again_after():
    budget, calls = Budget(), []

    def fn():
        calls.append(1)
        if len(calls) == 3:
            raise ValueError("third")
        return len(calls)

    once = budget.once(fn)
    assert (once(), once()) == (1, 1) and len(calls) == 1
    budget.reset()  # the next top-level evaluation
    assert once() == 2
    budget.reset()
    with pytest.raises(ValueError, match="third"):
        once()
    assert once() == 4  # a raise is not remembered


def test_argmax_argmin_empty_sequence_raise():
    with pytest.raises(ValueError, match="argmax"):
        run("argmax([])")
    with pytest.raises(ValueError, match="argmin"):
        run("argmin([])")


def test_builtins_whitelist_contents():
    assert set(BUILTINS) == {"len", "min", "max", "sum", "any", "all", "abs", "round", "int",
                             "float", "bool", "sorted", "argmax", "argmin"}
    for dangerous in ("eval", "exec", "open", "getattr", "__import__", "print", "type",
                      "compile", "globals", "vars", "setattr", "range", "iter", "next"):
        assert dangerous not in BUILTINS


# --------------------------------------------------------------------------- rejected expressions

LONG_STRING = "'" + "a" * 201 + "'"
LONG_SOURCE = "x" + " + x" * 600  # > 2000 characters
MANY_NODES = "1+" * 300 + "1"  # < 2000 characters, > 400 nodes
FOUR_LOOPS = "[1 for a in xs for b in xs for c in xs for d in xs]"
FOUR_LOOPS_SPLIT = "sum(a for a in xs) + len([b for b in xs for c in xs for d in xs])"


@pytest.mark.parametrize("source,fragment", [
    ("__import__('os')", "not a whitelisted function"),
    ("().__class__", "forbidden syntax: Attribute"),
    ("x.y", "forbidden syntax: Attribute"),
    ("xs.append(1)", "only helpers called by plain name"),
    ("(lambda: 1)()", "only helpers called by plain name"),
    ("lambda: 1", "forbidden syntax: Lambda"),
    ("open('f')", "not a whitelisted function"),
    ("eval('1')", "not a whitelisted function"),
    ("exec('1')", "not a whitelisted function"),
    ("getattr(x, 'y')", "not a whitelisted function"),
    ("print(1)", "not a whitelisted function"),
    ("2 ** 10", "forbidden syntax: Pow"),
    ("1 << 5", "forbidden syntax: LShift"),
    ("1 >> 5", "forbidden syntax: RShift"),
    ("x & 1", "forbidden syntax: BitAnd"),
    ("x | 1", "forbidden syntax: BitOr"),
    ("x ^ 1", "forbidden syntax: BitXor"),
    ("~x", "forbidden syntax: Invert"),
    ("f'{x}'", "forbidden syntax: JoinedStr"),
    ("(y := 1)", "forbidden syntax: NamedExpr"),
    ("{v: 1 for v in xs}", "forbidden syntax: DictComp"),
    ("{v for v in xs}", "forbidden syntax: SetComp"),
    ("{1: 2}", "forbidden syntax: Dict"),
    ("{1, 2}", "forbidden syntax: Set"),
    ("[*xs]", "forbidden syntax: Starred"),
    ("x is None", "forbidden syntax: Is"),
    ("x @ x", "forbidden syntax: MatMult"),
    ("await x", "forbidden syntax: Await"),
    ("_x", "name '_x' is forbidden"),
    ("x + __builtins__", "name '__builtins__' is forbidden"),
    ("[_v for _v in xs]", "is forbidden"),
    ("__bounded(xs)", "not a whitelisted function"),
    ("len(x=1)", "only plain positional arguments"),
    ("len(*xs)", "only plain positional arguments"),
    ("x(1)", "'x' is a value, not a function"),
    ("double(1, 2)", "double() takes 1 argument(s), 2 given"),
    ("double()", "double() takes 1 argument(s), 0 given"),
    ("add(1)", "add() takes 2 argument(s), 1 given"),
    ("nothing(1)", "nothing() takes 0 argument(s), 1 given"),
    ("100000000000000000000", "is not allowed"),
    ("-100000000000000000000", "is not allowed"),
    ("1000000001", "is not allowed"),
    ("1e300", "is not allowed"),
    ("1j", "is not allowed"),
    ("b'x'", "is not allowed"),
    ("...", "is not allowed"),
    (LONG_STRING, "is not allowed"),
    (LONG_SOURCE, "longer than 2000 characters"),
    (MANY_NODES, "more than 400 syntax nodes"),
    (FOUR_LOOPS, "more than 3 comprehension loops"),
    (FOUR_LOOPS_SPLIT, "more than 3 comprehension loops"),
    ("1 +", "syntax error"),
    ("", "syntax error"),
    ("x = 1", "syntax error"),
    ("import os", "syntax error"),
    ("[f(1) for f in xs]", "call to 'f', which is not a whitelisted function"),
    ("[len(v) for len in xs]", "call to 'len', which is not a whitelisted function"),
    ("[v for (v, (a, b)) in xs]", "comprehension targets must be plain names"),
    ("[v for v.y in xs]", "comprehension targets must be plain names"),
    ("print", "unknown name 'print'"),
    ("undefined + 1", "unknown name 'undefined'"),
    ("[v for v in xs] + [v]", "unknown name 'v'"),  # comprehension variable does not leak
    ("[a for a in b for b in grid]", "unknown name 'b'"),  # later target not visible earlier
])
def test_rejected_at_construction(source, fragment):
    with pytest.raises(ExpressionError) as info:
        Expression(source, NAMES, WHERE)
    message = str(info.value)
    assert message.startswith(WHERE + ": "), message
    assert fragment in message, message


def test_sanity_of_rejection_fixtures():
    assert len(LONG_SOURCE) > 2000
    assert len(MANY_NODES) <= 2000
    assert len(LONG_STRING) - 2 == 201
    # the 3-loop limit itself is allowed
    assert run("len([1 for a in xs for b in xs for c in xs])") == 8 ** 3
    # a 200-char string and 10**9 are allowed
    assert run("'" + "a" * 200 + "'") == "a" * 200
    assert run("1000000000 + 0.5") == 1_000_000_000.5


@pytest.mark.parametrize("source", [5, None, b"1 + 1", ["x"]])
def test_non_string_source_rejected(source):
    with pytest.raises(ExpressionError, match=r"^" + WHERE + ": expected an expression string"):
        Expression(source, NAMES, WHERE)


def test_default_where_prefix():
    with pytest.raises(ExpressionError, match=r"^expression: unknown name 'nope'"):
        Expression("nope", {})


def test_error_reports_column():
    with pytest.raises(ExpressionError, match=r"unknown name 'nope' \(column 5\)"):
        Expression("x + nope", {"x": -1}, WHERE)


def test_expression_error_is_value_error():
    assert issubclass(ExpressionError, ValueError)


def test_undeclared_helper_not_callable_even_if_in_namespace():
    with pytest.raises(ExpressionError, match="not a whitelisted function"):
        Expression("double(1)", {"x": -1}, WHERE)


# --------------------------------------------------------------------------- runtime bounds


@pytest.mark.parametrize("source", [
    "[0] * 100000",
    "100000 * [0]",
    "(0,) * 10001",
    "'ab' * 5001",
    "[1, 2] * 5001",
    "[[0] * 10000 for v in [1]][0] * 2",
])
def test_sequence_repetition_limit(source):
    with pytest.raises(ValueError, match="more than 10000 elements"):
        run(source)


def test_sequence_repetition_at_limit_is_allowed():
    assert run("[0] * 10000") == [0] * MAX_SIZE
    assert run("len('ab' * 5000)") == MAX_SIZE


@pytest.mark.parametrize("source", [
    "[v for v in big()]",
    "sum(v for v in big())",
    "any(v < 0 for v in big())",
    "[v for v in small() for w in big()]",
    "[v for v in tup()]",
    "[c for c in text()]",
])
def test_comprehension_source_limit(source):
    names = {**NAMES, "big": 0, "small": 0, "tup": 0, "text": 0}
    values = {**VALUES,
              "big": lambda: list(range(MAX_SIZE + 1)),
              "small": lambda: [1, 2],
              "tup": lambda: tuple(range(MAX_SIZE + 1)),
              "text": lambda: "a" * (MAX_SIZE + 1)}
    with pytest.raises(ValueError, match="exceeds"):
        run(source, names, values)


def _long_iterator():
    """An iterator far longer than MAX_SIZE that fails loudly if fully consumed."""
    for i in itertools.count():
        if i > 5 * MAX_SIZE:
            raise AssertionError("comprehension source was not bounded")
        yield i


@pytest.mark.parametrize("source", ["any(v < 0 for v in forever())",
                                    "[v for v in forever()]"])
def test_comprehension_over_long_iterator_is_stopped(source):
    names = {**NAMES, "forever": 0}
    values = {**VALUES, "forever": _long_iterator}
    with pytest.raises(ValueError, match="comprehension source exceeds"):
        run(source, names, values)


def test_comprehension_source_at_limit_is_allowed():
    names = {**NAMES, "big": 0, "gen": 0}
    values = {**VALUES, "big": lambda: list(range(MAX_SIZE)),
              "gen": lambda: iter(range(MAX_SIZE))}
    assert run("sum(v for v in big())", names, values) == sum(range(MAX_SIZE))
    assert run("len([v for v in gen()])", names, values) == MAX_SIZE


def test_runtime_limits_apply_inside_function_expressions():
    fn = Expression("[0] * n", {"n": -1}, WHERE, args=("n",)).evaluate(guard_namespace({}))
    assert fn(3) == [0, 0, 0]
    with pytest.raises(ValueError, match="more than 10000 elements"):
        fn(MAX_SIZE + 1)
    total = Expression("sum(v for v in seq)", {"seq": -1, "sum": None}, WHERE,
                       args=("seq",)).evaluate(guard_namespace({}))
    assert total([1, 2, 3]) == 6
    with pytest.raises(ValueError, match="exceeds"):
        total(list(range(MAX_SIZE + 1)))


# --------------------------------------------------------------------------- no builtins


def test_guard_namespace_has_empty_builtins():
    ns = guard_namespace({"x": 1})
    assert ns["__builtins__"] == {}
    assert ns["x"] == 1
    assert "print" not in ns and "open" not in ns and "__import__" not in ns


def test_guard_namespace_adds_private_guards_and_bounded_builtins():
    # every other name guard_namespace adds starts with "_", so no expression can reference it
    ns = guard_namespace({})
    assert "__builtins__" in ns and len(ns) >= 2
    assert all(k.startswith("_") for k in ns if k not in BUILTINS)
    assert BUILTINS <= set(ns)


@pytest.mark.parametrize("source", ["print", "print(1)", "open", "__builtins__"])
def test_print_and_friends_unreachable(source):
    with pytest.raises(ExpressionError):
        Expression(source, NAMES, WHERE)


def test_evaluation_has_no_builtins_even_if_name_declared():
    """Declaring a name does not provide it: with empty __builtins__, `print` is not found."""
    expr = Expression("print(1)", {"print": None}, WHERE)
    with pytest.raises(NameError):
        expr.evaluate(guard_namespace({}))


# -- hardening found in review: numpy counts, total comprehension work, list sums --------------

def _evaluate(source, **values):
    names = {**{k: None for k in BUILTINS},
             **{k: (-1 if not callable(v) else None) for k, v in values.items()}}
    return Expression(source, names, "review").evaluate(guard_namespace(values))


def test_repetition_limit_applies_to_numpy_integers():
    import numpy as np
    with pytest.raises(ValueError, match="more than 10000 elements"):
        _evaluate("[0] * n", n=np.int64(10**6))


def test_nested_comprehensions_share_one_work_budget():
    big = [[0] * 10_000 for _ in range(30)]
    with pytest.raises(ValueError, match="budget of 1000000 work units"):
        _evaluate("len([1 for x in big for y in x if y])", big=big)
    assert _evaluate("len([1 for x in big for y in x if not y])", big=big[:1]) == 10_000


def test_sum_adds_numbers_only():
    with pytest.raises(ValueError, match="adds numbers only"):
        _evaluate("sum(big, [])", big=[[1], [2]])
    with pytest.raises(ValueError, match="adds numbers only"):
        _evaluate("sum(big)", big=[[1], [2]])
    assert _evaluate("sum([1, 2.5])") == 3.5


class _Lists(Helpers):
    def bind(self, observation):
        """No observation: the lists depend on the argument alone."""

    @helper
    def cells(self, k: int) -> list[int]:
        return [k - 1, k + 1]

    @helper(at_most=2)
    def around(self, k: int) -> list[int]:
        return [k - 1, k + 1]


def test_list_helpers_are_charged_their_length_unless_declared_short():
    budget = Budget()
    ns = guard_namespace(budget.charging(_Lists().functions()), budget)
    names = {**dict.fromkeys(BUILTINS), "cells": 1, "around": 1}

    def work(source: str) -> int:
        Expression(source, names, WHERE).evaluate(ns)
        return MAX_WORK - budget.work

    assert (work("cells(3)"), work("around(3)")) == (2, 0)
    assert work("len([k for k in cells(3)])") == work("len([k for k in around(3)])") + 2 > 2
