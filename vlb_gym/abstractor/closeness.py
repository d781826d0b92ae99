"""How close an episode came to keeping a promise: a score in [0, 1], 1 exactly when it holds.

The search orders what it tries by cost, less a reward for prefixes that come closer to the
promise (:mod:`~vlb_gym.abstractor.search`). A promise is a condition, true or false; its
*closeness* grades it along its own structure, as quantitative semantics grade temporal logic
formulas: ``a and b`` scores the mean of its parts, ``a or b`` the best, ``x if c else y`` the
branch its condition takes; ``==`` between sequences scores the share of their common prefix
(so two of four round trips done is halfway), between numbers ``1 / (1 + |a - b|)``, and so
do ``<``, ``<=``, ``>``, ``>=`` when they fail (``a < b`` failing where ``a == b`` scores 1/2:
less than 1, or ``not`` would turn a failing ``9 < 9`` into a part that fails). Anything else
(a call, ``in``, a comprehension, a chained comparison) scores 1 if it holds, else 0; a part
that raises scores 0. Every part is a checked expression of the outcome helpers, evaluated
under the judging budget.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Mapping
from typing import Any

from vlb_gym.core.expressions import Expression

_ORDER = (ast.Lt, ast.LtE, ast.Gt, ast.GtE)


class Closeness:
    """The closeness of one promise (see the module's docstring); ``names`` are those the
    promise may use (outcome helpers and builtins, with arities)."""

    def __init__(self, promise: str, names: Mapping[str, int | None]):
        self.names = dict(names)
        self._expressions: dict[str, Expression] = {}
        self._score = self._compile(ast.parse(promise, mode="eval").body)

    def __call__(self, namespace: dict[str, Any]) -> float:
        return self._score(namespace)

    def _value(self, node: ast.expr) -> Callable[[dict[str, Any]], Any]:
        text = ast.unparse(node)
        expression = self._expressions.get(text)
        if expression is None:
            expression = self._expressions[text] = Expression(text, self.names, "promise")
        return expression.evaluate

    def _compile(self, node: ast.expr) -> Callable[[dict[str, Any]], float]:
        if isinstance(node, ast.BoolOp):
            parts = [self._compile(v) for v in node.values]
            if isinstance(node.op, ast.And):
                return lambda ns: sum(p(ns) for p in parts) / len(parts)
            return lambda ns: max(p(ns) for p in parts)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
            inner = self._compile(node.operand)
            return lambda ns: 1.0 - float(inner(ns) == 1.0)
        if isinstance(node, ast.IfExp):
            test, body, orelse = (self._truth(node.test), self._compile(node.body),
                                  self._compile(node.orelse))
            return lambda ns: body(ns) if test(ns) else orelse(ns)
        if isinstance(node, ast.Compare) and len(node.ops) == 1 and isinstance(
                node.ops[0], (ast.Eq, *_ORDER)):
            left, right = self._value(node.left), self._value(node.comparators[0])
            holds = self._truth(node)
            return lambda ns: _compared(holds, left, right, ns)
        truth = self._truth(node)
        return lambda ns: float(truth(ns))

    def _truth(self, node: ast.expr) -> Callable[[dict[str, Any]], bool]:
        value = self._value(node)

        def holds(namespace: dict[str, Any]) -> bool:
            try:
                return bool(value(namespace))
            except Exception:  # noqa: BLE001 - a part that raises does not hold
                return False
        return holds


def _compared(holds: Callable[[dict[str, Any]], bool], left: Callable[..., Any],
              right: Callable[..., Any], namespace: dict[str, Any]) -> float:
    if holds(namespace):
        return 1.0
    try:
        a, b = left(namespace), right(namespace)
    except Exception:  # noqa: BLE001 - a side that raises is far
        return 0.0
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        common = 0
        for x, y in zip(a, b):
            if x != y:
                break
            common += 1
        return common / max(len(a), len(b), 1)
    numbers = (int, float)
    if isinstance(a, numbers) and isinstance(b, numbers) and not isinstance(a, bool) \
            and not isinstance(b, bool):
        far = abs(a - b)  # (0 where ``a < b`` fails at a == b; tiny between close floats)
        return 1.0 / (1.0 + far) if 1.0 + far > 1.0 else 0.5
    return 0.0
