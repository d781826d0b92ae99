"""The restricted expression language of behavior files.

Behavior files are data, never code: where a behavior needs a decision function, it writes a small
Python-syntax *expression* that composes whitelisted helpers. An expression is parsed with
:mod:`ast` and checked before anything runs:

* only the node types in :data:`ALLOWED_NODES` (no attributes, lambdas, imports, f-strings,
  assignments, ``**`` or bit operations);
* only names the caller declares (helpers, builtins, variables, functions) or comprehension
  targets; no name may start with ``_``;
* calls only to declared callables, by plain name, with positional arguments;
* bounded size: source length, node count, constants and comprehension depth are capped, and at run
  time every comprehension source and every ``*`` on a sequence is checked against
  :data:`MAX_SEQUENCE`.

A checked expression is compiled once and evaluated with empty ``__builtins__``.
"""

from __future__ import annotations

import ast
import numbers
from collections.abc import Callable, Iterable, Mapping
from typing import Any

MAX_SOURCE_CHARS = 2000
MAX_NODES = 400
MAX_GENERATORS = 3
MAX_SEQUENCE = 10_000
MAX_ITEMS = 200_000  # comprehension items per top-level evaluation, all loops together
MAX_INT = 10**9
MAX_STR = 200

ALLOWED_NODES: tuple[type[ast.AST], ...] = (
    ast.Expression, ast.BoolOp, ast.And, ast.Or, ast.BinOp, ast.Add, ast.Sub, ast.Mult, ast.Div,
    ast.FloorDiv, ast.Mod, ast.UnaryOp, ast.Not, ast.USub, ast.UAdd, ast.Compare, ast.Eq,
    ast.NotEq, ast.Lt, ast.LtE, ast.Gt, ast.GtE, ast.In, ast.NotIn, ast.IfExp, ast.Call,
    ast.Constant, ast.Name, ast.Load, ast.Store, ast.List, ast.Tuple, ast.Subscript, ast.Slice,
    ast.ListComp, ast.GeneratorExp, ast.comprehension,
)


class ExpressionError(ValueError):
    """An expression is malformed, forbidden or too large; the message says why and where."""


def _argmax(values: Iterable[Any]) -> int:
    """Index of the first maximum of a non-empty sequence."""
    values = list(values)
    if not values:
        raise ValueError("argmax() of an empty sequence")
    return values.index(max(values))


def _argmin(values: Iterable[Any]) -> int:
    """Index of the first minimum of a non-empty sequence."""
    values = list(values)
    if not values:
        raise ValueError("argmin() of an empty sequence")
    return values.index(min(values))




def _sum(values: Iterable[Any], start: Any = 0) -> Any:
    """``sum`` of numbers only (adding lists with ``sum`` is quadratic and unbounded)."""
    if not isinstance(start, numbers.Number):
        raise ValueError("sum() adds numbers only")
    total = start
    for value in values:
        if not isinstance(value, numbers.Number):
            raise ValueError(f"sum() adds numbers only, got {type(value).__name__}")
        total += value
    return total


class _Budget:
    """Counts comprehension items over one top-level evaluation, all nested loops together."""

    __slots__ = ("left",)

    def __init__(self) -> None:
        self.left = MAX_ITEMS

    def bounded(self, iterable: Iterable[Any]) -> list[Any]:
        """Materialise a comprehension source, refusing anything longer than MAX_SEQUENCE and
        any evaluation that iterates more than MAX_ITEMS items in all."""
        if type(iterable) is list and len(iterable) <= MAX_SEQUENCE:  # the common case, no copy
            items = iterable
        else:
            if isinstance(iterable, (list, tuple, str, range)) and len(iterable) > MAX_SEQUENCE:
                raise ValueError(f"comprehension over {len(iterable)} items exceeds "
                                 f"{MAX_SEQUENCE}")
            items = []
            for item in iterable:
                items.append(item)
                if len(items) > MAX_SEQUENCE:
                    raise ValueError(f"comprehension source exceeds {MAX_SEQUENCE} items")
        self.left -= len(items)
        if self.left < 0:
            raise ValueError(f"expression iterates over more than {MAX_ITEMS} items in all")
        return items


def _mul(left: Any, right: Any) -> Any:
    """``left * right`` that refuses to build sequences longer than MAX_SEQUENCE."""
    for seq, times in ((left, right), (right, left)):
        if isinstance(seq, (list, tuple, str)) and isinstance(times, numbers.Integral):
            if len(seq) * int(times) > MAX_SEQUENCE:
                raise ValueError(f"sequence repetition would exceed {MAX_SEQUENCE} items")
    return left * right




#: Pure, bounded builtins every expression may call.
BUILTINS: dict[str, Callable[..., Any]] = {
    "len": len, "min": min, "max": max, "any": any, "all": all, "abs": abs,
    "round": round, "int": int, "float": float, "bool": bool, "sorted": sorted, "sum": _sum,
    "argmax": _argmax, "argmin": _argmin,
}


class _Checker(ast.NodeVisitor):
    def __init__(self, names: Mapping[str, int | None], where: str):
        self.names = names  # name -> arity for callables (None: any), -1 for plain values
        self.where = where
        self.scopes: list[set[str]] = []
        self.generators = 0

    def fail(self, node: ast.AST, message: str) -> None:
        col = getattr(node, "col_offset", None)
        at = f" (column {col + 1})" if col is not None else ""
        raise ExpressionError(f"{self.where}: {message}{at}")

    def generic_visit(self, node: ast.AST) -> None:
        if not isinstance(node, ALLOWED_NODES):
            self.fail(node, f"forbidden syntax: {type(node).__name__}")
        super().generic_visit(node)

    def visit_Constant(self, node: ast.Constant) -> None:
        value = node.value
        if isinstance(value, bool) or value is None:
            return
        if isinstance(value, int) and abs(value) <= MAX_INT:
            return
        if isinstance(value, float) and abs(value) <= MAX_INT:
            return
        if isinstance(value, str) and len(value) <= MAX_STR:
            return
        self.fail(node, f"constant {value!r:.40} is not allowed (numbers up to {MAX_INT}, "
                        f"strings up to {MAX_STR} characters)")

    def _bound(self, name: str) -> bool:
        return any(name in scope for scope in self.scopes)

    def visit_Name(self, node: ast.Name) -> None:
        if node.id.startswith("_"):
            self.fail(node, f"name {node.id!r} is forbidden (names may not start with '_')")
        if isinstance(node.ctx, ast.Store):
            return
        if not self._bound(node.id) and node.id not in self.names:
            self.fail(node, f"unknown name {node.id!r}")

    def visit_Call(self, node: ast.Call) -> None:
        if not isinstance(node.func, ast.Name):
            self.fail(node, "only helpers called by plain name are allowed")
        name = node.func.id
        if name.startswith("_") or self._bound(name) or name not in self.names:
            self.fail(node, f"call to {name!r}, which is not a whitelisted function")
        arity = self.names[name]
        if arity == -1:
            self.fail(node, f"{name!r} is a value, not a function")
        if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
            self.fail(node, f"call to {name!r}: only plain positional arguments are allowed")
        if arity is not None and len(node.args) != arity:
            self.fail(node, f"{name}() takes {arity} argument(s), {len(node.args)} given")
        for arg in node.args:
            self.visit(arg)

    def _comprehension(self, node: ast.ListComp | ast.GeneratorExp) -> None:
        self.generators += len(node.generators)
        if self.generators > MAX_GENERATORS:
            self.fail(node, f"more than {MAX_GENERATORS} comprehension loops in one expression")
        scope: set[str] = set()
        for gen in node.generators:
            if gen.is_async:
                self.fail(node, "async comprehensions are forbidden")
            self.visit(gen.iter)
            targets = gen.target.elts if isinstance(gen.target, ast.Tuple) else [gen.target]
            for target in targets:
                if not isinstance(target, ast.Name):
                    self.fail(node, "comprehension targets must be plain names")
                self.visit(target)
                scope.add(target.id)
            self.scopes.append(scope)
            for cond in gen.ifs:
                self.visit(cond)
        self.visit(node.elt)
        del self.scopes[-len(node.generators):]

    visit_ListComp = _comprehension
    visit_GeneratorExp = _comprehension


class _Guard(ast.NodeTransformer):
    """Wrap comprehension sources in ``__bounded`` and ``*`` in ``__mul``."""

    def visit_comprehension(self, node: ast.comprehension) -> ast.comprehension:
        self.generic_visit(node)
        node.iter = ast.Call(ast.Name("__bounded", ast.Load()), [node.iter], [])
        return node

    def visit_BinOp(self, node: ast.BinOp) -> ast.AST:
        self.generic_visit(node)
        if isinstance(node.op, ast.Mult):
            return ast.Call(ast.Name("__mul", ast.Load()), [node.left, node.right], [])
        return node


class Expression:
    """A checked, compiled expression; call :meth:`evaluate` with a namespace."""

    __slots__ = ("source", "where", "code", "names")

    def __init__(self, source: str, names: Mapping[str, int | None], where: str = "expression",
                 args: tuple[str, ...] | None = None):
        if not isinstance(source, str):
            raise ExpressionError(f"{where}: expected an expression string, got {type(source).__name__}")
        if len(source) > MAX_SOURCE_CHARS:
            raise ExpressionError(f"{where}: expression longer than {MAX_SOURCE_CHARS} characters")
        try:
            tree = ast.parse(source.strip(), mode="eval")
        except SyntaxError as exc:
            raise ExpressionError(f"{where}: syntax error in {source!r}: {exc.msg} "
                                  f"(column {exc.offset})") from None
        if sum(1 for _ in ast.walk(tree)) > MAX_NODES:
            raise ExpressionError(f"{where}: expression has more than {MAX_NODES} syntax nodes")
        _Checker(names, where).visit(tree)
        self.names = frozenset(n.id for n in ast.walk(tree) if isinstance(n, ast.Name))
        tree = _Guard().visit(tree)
        if args is not None:  # a function: compile ``lambda *args: body`` (built here, never written by users)
            signature = ast.arguments(posonlyargs=[], args=[ast.arg(a) for a in args],
                                      kwonlyargs=[], kw_defaults=[], defaults=[])
            tree = ast.Expression(ast.Lambda(signature, tree.body))
        tree = ast.fix_missing_locations(tree)
        self.source = source
        self.where = where
        self.code = compile(tree, f"<{where}>", "eval")

    def evaluate(self, namespace: dict[str, Any]) -> Any:
        """Evaluate in ``namespace`` (made by :func:`guard_namespace`); a function expression
        evaluates to a Python function whose globals are ``namespace``. Each call starts a new
        item budget; functions called from it share that budget."""
        namespace["__budget"].left = MAX_ITEMS
        return eval(self.code, namespace)  # noqa: S307 - checked against the whitelist above

    def __repr__(self) -> str:
        return f"Expression({self.source!r})"


def guard_namespace(values: Mapping[str, Any]) -> dict[str, Any]:
    """A globals dict for :meth:`Expression.evaluate`: no builtins, the guards, and ``values``."""
    budget = _Budget()
    namespace: dict[str, Any] = {"__builtins__": {}, "__budget": budget,
                                 "__bounded": budget.bounded, "__mul": _mul}
    namespace.update(values)
    return namespace
