"""The restricted expression language of behavior files.

Behavior files are data, never code: where a behavior needs a decision function, it writes a small
Python-syntax *expression* that composes whitelisted helpers. An expression is parsed with
:mod:`ast` and checked before anything runs:

* only the node types in :data:`ALLOWED_NODES` (no attributes, lambdas, imports, f-strings,
  assignments, ``**`` or bit operations);
* only names the caller declares (helpers, builtins, variables, functions) or comprehension
  targets; no name may start with ``_``;
* calls only to declared callables, by plain name, with positional arguments;
* bounded size: source length, node count, constants and comprehension depth are capped;
* ``%`` is numeric modulo only (no string formatting).

A checked expression is compiled once and evaluated with empty ``__builtins__`` under a
:class:`Budget` that counts *work*, not items: every comprehension item and every call of a
behavior function is charged the size of the code it runs, every operation that builds or
compares sequences is charged the elements it touches (nested ones included), list-returning
helpers are charged their result's length; every list, tuple or string an operation builds holds
at most :data:`MAX_SIZE` elements, every integer it computes stays below :data:`MAX_INT_RESULT` in
magnitude, and ``round`` takes at most :data:`MAX_ROUND_DIGITS` digits. Exceeding any limit
raises :class:`EvaluationLimitError` (a ``ValueError``): the episode fails with that reason, and
the process never hangs or runs out of memory.
"""

from __future__ import annotations

import ast
import inspect
import numbers
import warnings
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

MAX_SOURCE_CHARS = 2000
MAX_NODES = 400
MAX_GENERATORS = 3
MAX_INT = 10**9  # largest constant
MAX_STR = 200  # longest string constant
MAX_SIZE = 10_000  # elements in a list/tuple/string an operation builds (nested ones counted)
MAX_WORK = 1_000_000  # work units per top-level evaluation
MAX_CALLS = 10_000  # calls of behavior functions per top-level evaluation
MAX_INT_RESULT = 2**63  # magnitude bound of computed integers
MAX_ROUND_DIGITS = 20
#: Kept for existing callers: comprehension sources are bounded by the same size.
MAX_SEQUENCE = MAX_SIZE

ALLOWED_NODES: tuple[type[ast.AST], ...] = (
    ast.Expression, ast.BoolOp, ast.And, ast.Or, ast.BinOp, ast.Add, ast.Sub, ast.Mult, ast.Div,
    ast.FloorDiv, ast.Mod, ast.UnaryOp, ast.Not, ast.USub, ast.UAdd, ast.Compare, ast.Eq,
    ast.NotEq, ast.Lt, ast.LtE, ast.Gt, ast.GtE, ast.In, ast.NotIn, ast.IfExp, ast.Call,
    ast.Constant, ast.Name, ast.Load, ast.Store, ast.List, ast.Tuple, ast.Subscript, ast.Slice,
    ast.ListComp, ast.GeneratorExp, ast.comprehension,
)

#: Builtins every expression may call (bounded versions, bound to a :class:`Budget`).
BUILTINS = frozenset({"len", "min", "max", "any", "all", "abs", "round", "int", "float", "bool",
                      "sorted", "sum", "argmax", "argmin"})


class ExpressionError(ValueError):
    """An expression is malformed, forbidden or too large; the message says why and where."""


class EvaluationLimitError(ValueError):
    """An evaluation exceeded a limit of its :class:`Budget`; the message names the limit."""


_SEQUENCES = (list, tuple, str)


def _size(value: Any, limit: int = MAX_WORK) -> int:
    """Elements in ``value``, nested lists/tuples and characters of strings counted (what comparing
    or sorting it can cost); counting stops once it passes ``limit``, so asking costs at most
    ``limit`` steps even for nested lists that share their elements."""
    kind = type(value)
    if kind is str:
        return len(value)
    if kind is not list and kind is not tuple:
        return value.size if kind is np.ndarray else 1
    total, stack = 0, [value]
    while stack:
        items = stack.pop()
        total += len(items)
        if total > limit:
            return total
        for item in items:
            kind = type(item)
            if kind is list or kind is tuple:
                stack.append(item)
            elif kind is str:
                total += len(item)
            elif kind is np.ndarray:
                total += item.size
    return total


class Budget:
    """The work and size limits of one top-level evaluation, shared by the functions it calls.

    Its methods are what checked code calls (under private ``__`` names) and the bounded builtins.
    """

    __slots__ = ("work", "calls", "memo")

    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        self.work = MAX_WORK
        self.calls = MAX_CALLS
        self.memo: dict[Callable[[], Any], Any] = {}

    def once(self, fn: Callable[[], Any]) -> Callable[[], Any]:
        """A behavior function of no arguments, computed at most once per top-level evaluation
        and then recalled: expressions have no side effects, so nothing in one evaluation can
        change its value. (A recalled value is not charged again: its work is not done again.)"""
        def recalled() -> Any:
            memo = self.memo
            if fn in memo:
                return memo[fn]
            value = memo[fn] = fn()
            return value
        return recalled

    def charge(self, units: int) -> None:
        self.work -= units
        if self.work < 0:
            raise EvaluationLimitError(f"evaluation exceeded its budget of {MAX_WORK} work units")

    def sized(self, value: Any) -> Any:
        """A list or tuple just built, checked against MAX_SIZE and charged its length."""
        if len(value) > MAX_SIZE:
            raise EvaluationLimitError(f"a sequence of more than {MAX_SIZE} elements was built")
        self.charge(len(value))
        return value

    def integer(self, value: Any) -> Any:
        if type(value) is int and not -MAX_INT_RESULT < value < MAX_INT_RESULT:
            raise EvaluationLimitError("an integer of magnitude >= 2**63 was computed")
        return value

    def call(self, weight: int) -> None:
        """Entry of a behavior function whose body has ``weight`` syntax nodes."""
        self.calls -= 1
        if self.calls < 0:
            raise EvaluationLimitError(f"evaluation made more than {MAX_CALLS} function calls")
        self.charge(weight)

    def items(self, iterable: Iterable[Any], weight: int = 1) -> list[Any]:
        """A comprehension source as a list of at most MAX_SIZE items, each charged ``weight``
        (the size of the code that runs per item)."""
        if type(iterable) is list and len(iterable) <= MAX_SIZE:  # the common case, no copy
            items = iterable
        else:
            if isinstance(iterable, (*_SEQUENCES, range)) and len(iterable) > MAX_SIZE:
                raise EvaluationLimitError(f"comprehension over {len(iterable)} items exceeds "
                                           f"{MAX_SIZE}")
            items = []
            for item in iterable:
                items.append(item)
                if len(items) > MAX_SIZE:
                    raise EvaluationLimitError(f"comprehension source exceeds {MAX_SIZE} items")
        self.charge(len(items) * weight)
        return items

    def operand(self, value: Any) -> Any:
        """A comparison operand, charged its size (what comparing it can cost)."""
        kind = type(value)
        if kind is list or kind is tuple or kind is str or kind is np.ndarray:
            self.charge(_size(value))
        return value

    # -- arithmetic --------------------------------------------------------------------------
    def _building(self, length: int) -> None:
        if length > MAX_SIZE:
            raise EvaluationLimitError(f"a sequence of more than {MAX_SIZE} elements would be "
                                       "built")
        self.charge(length)

    def add(self, left: Any, right: Any) -> Any:
        if isinstance(left, _SEQUENCES) and isinstance(right, _SEQUENCES):
            self._building(len(left) + len(right))
            return left + right
        return self.numeric(left + right)

    def mul(self, left: Any, right: Any) -> Any:
        for seq, times in ((left, right), (right, left)):
            if isinstance(seq, _SEQUENCES) and isinstance(times, numbers.Integral):
                self._building(len(seq) * max(int(times), 0))
                return left * right
        return self.numeric(left * right)

    def mod(self, left: Any, right: Any) -> Any:
        if isinstance(left, (str, bytes)):
            raise EvaluationLimitError("'%' is numeric modulo only; strings cannot be formatted")
        return self.numeric(left % right)

    def sub(self, left: Any, right: Any) -> Any:
        return self.numeric(left - right)

    def truediv(self, left: Any, right: Any) -> Any:
        return self.numeric(left / right)

    def floordiv(self, left: Any, right: Any) -> Any:
        return self.numeric(left // right)

    def numeric(self, value: Any) -> Any:
        if type(value) is np.ndarray:
            self._building(value.size)
            return value
        return self.integer(value)

    def slice(self, value: Any, lower: Any, upper: Any, step: Any) -> Any:
        result = value[lower:upper:step]
        self.charge(len(result))
        return result

    # -- bounded builtins ----------------------------------------------------------------------
    def _values(self, args: tuple[Any, ...], name: str) -> list[Any]:
        """The values ``name`` looks at: its arguments, or the items of its one iterable."""
        values = self.items(args[0]) if len(args) == 1 else list(args)
        self.charge(_size(values))
        return values

    def min(self, *args: Any) -> Any:
        return min(self._values(args, "min"))

    def max(self, *args: Any) -> Any:
        return max(self._values(args, "max"))

    def sorted(self, iterable: Iterable[Any]) -> list[Any]:
        values = self._values((iterable,), "sorted")
        self.charge(len(values) * max(1, len(values).bit_length()))
        return sorted(values)

    def any(self, iterable: Iterable[Any]) -> bool:
        return any(self.items(iterable))

    def all(self, iterable: Iterable[Any]) -> bool:
        return all(self.items(iterable))

    def sum(self, iterable: Iterable[Any], start: Any = 0) -> Any:
        """``sum`` of numbers only (adding lists with ``sum`` is quadratic)."""
        if not isinstance(start, numbers.Number):
            raise ValueError("sum() adds numbers only")
        total = start
        for value in self.items(iterable):
            if not isinstance(value, numbers.Number):
                raise ValueError(f"sum() adds numbers only, got {type(value).__name__}")
            total += value
        return self.integer(total)

    def argmax(self, values: Iterable[Any]) -> int:
        """Index of the first maximum of a non-empty sequence."""
        values = self._values((values,), "argmax")
        if not values:
            raise ValueError("argmax() of an empty sequence")
        return values.index(max(values))

    def argmin(self, values: Iterable[Any]) -> int:
        """Index of the first minimum of a non-empty sequence."""
        values = self._values((values,), "argmin")
        if not values:
            raise ValueError("argmin() of an empty sequence")
        return values.index(min(values))

    def round(self, number: Any, digits: Any = None) -> Any:
        if digits is not None and not (isinstance(digits, numbers.Integral)
                                       and abs(int(digits)) <= MAX_ROUND_DIGITS):
            raise EvaluationLimitError(f"round() takes at most {MAX_ROUND_DIGITS} digits")
        return self.integer(round(number) if digits is None else round(number, digits))

    def int(self, *args: Any) -> int:
        if args and isinstance(args[0], str):
            self.charge(len(args[0]))
        return self.integer(int(*args))

    def float(self, *args: Any) -> float:
        if args and isinstance(args[0], str):
            self.charge(len(args[0]))
        return float(*args)

    def builtins(self) -> dict[str, Callable[..., Any]]:
        """The whitelisted builtins, bounded by this budget."""
        return {"len": len, "abs": abs, "bool": bool, "min": self.min, "max": self.max,
                "any": self.any, "all": self.all, "round": self.round, "int": self.int,
                "float": self.float, "sorted": self.sorted, "sum": self.sum,
                "argmax": self.argmax, "argmin": self.argmin}

    def charging(self, helpers: Mapping[str, Callable[..., Any]]
                 ) -> dict[str, Callable[..., Any]]:
        """``helpers`` with the list-returning ones (by return annotation) charged their
        result's length; the others return fixed-size values and are passed through."""
        out = {}
        for name, fn in helpers.items():
            returns = str(inspect.signature(fn).return_annotation)
            out[name] = self._charged(fn) if returns.startswith(("list", "List")) else fn
        return out

    def _charged(self, fn: Callable[..., Any]) -> Callable[..., Any]:
        def charged(*args: Any) -> Any:
            result = fn(*args)
            self.work -= len(result)  # charge(), inlined: helpers are called in hot loops
            if self.work < 0:
                self.charge(0)
            return result
        return charged


_BINOPS = {ast.Add: "__add", ast.Sub: "__sub", ast.Mult: "__mul", ast.Div: "__truediv",
           ast.FloorDiv: "__floordiv", ast.Mod: "__mod"}
_SCALAR_COMPARE = (ast.Eq, ast.NotEq, ast.Lt, ast.LtE, ast.Gt, ast.GtE)


def _nodes(node: ast.AST) -> int:
    return sum(1 for _ in ast.walk(node))


def _call(name: str, *args: ast.expr) -> ast.Call:
    return ast.Call(ast.Name(name, ast.Load()), list(args), [])


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

    def visit_BinOp(self, node: ast.BinOp) -> None:
        if isinstance(node.op, ast.Mod) and isinstance(node.left, ast.Constant) \
                and isinstance(node.left.value, str):
            self.fail(node, "'%' is numeric modulo only; strings cannot be formatted")
        self.generic_visit(node)

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
    """Route every operation that can cost more than a constant through the :class:`Budget`:
    comprehension sources (charged per item), arithmetic, comparisons of non-constant operands,
    slices, list/tuple displays and list comprehension results."""

    def visit_ListComp(self, node: ast.ListComp) -> ast.AST:
        weight = _nodes(node)
        self.generic_visit(node)
        for gen in node.generators:
            gen.iter = _call("__items", gen.iter, ast.Constant(weight))
        return _call("__sized", node)

    def visit_GeneratorExp(self, node: ast.GeneratorExp) -> ast.AST:
        weight = _nodes(node)
        self.generic_visit(node)
        for gen in node.generators:
            gen.iter = _call("__items", gen.iter, ast.Constant(weight))
        return node

    def visit_BinOp(self, node: ast.BinOp) -> ast.AST:
        self.generic_visit(node)
        return _call(_BINOPS[type(node.op)], node.left, node.right)

    def visit_Compare(self, node: ast.Compare) -> ast.AST:
        operands = [node.left, *node.comparators]
        constants = sum(isinstance(o, ast.Constant) for o in operands)
        self.generic_visit(node)
        if constants == len(operands) - 1 and all(isinstance(op, _SCALAR_COMPARE)
                                                  for op in node.ops):
            return node  # costs at most the size of a constant
        node.left = self._operand(node.left)
        node.comparators = [self._operand(o) for o in node.comparators]
        return node

    @staticmethod
    def _operand(node: ast.expr) -> ast.expr:
        return node if isinstance(node, ast.Constant) else _call("__operand", node)

    def visit_Subscript(self, node: ast.Subscript) -> ast.AST:
        self.generic_visit(node)
        if not isinstance(node.slice, ast.Slice):
            return node
        bounds = [b if b is not None else ast.Constant(None)
                  for b in (node.slice.lower, node.slice.upper, node.slice.step)]
        return _call("__slice", node.value, *bounds)

    def _display(self, node: ast.List | ast.Tuple) -> ast.AST:
        self.generic_visit(node)
        if isinstance(node.ctx, ast.Store) or all(isinstance(e, ast.Constant) for e in node.elts):
            return node
        return _call("__sized", node)

    visit_List = _display
    visit_Tuple = _display


class Expression:
    """A checked, compiled expression; call :meth:`evaluate` with a namespace. ``args`` are the
    parameters of a function expression (None: a plain expression)."""

    __slots__ = ("source", "where", "code", "names", "args")

    def __init__(self, source: str, names: Mapping[str, int | None], where: str = "expression",
                 args: tuple[str, ...] | None = None):
        if not isinstance(source, str):
            raise ExpressionError(f"{where}: expected an expression string, got "
                                  f"{type(source).__name__}")
        if len(source) > MAX_SOURCE_CHARS:
            raise ExpressionError(f"{where}: expression longer than {MAX_SOURCE_CHARS} characters")
        try:
            with warnings.catch_warnings():  # e.g. "'int' object is not subscriptable": it fails
                warnings.simplefilter("ignore", SyntaxWarning)  # at run time, with its reason
                tree = ast.parse(source.strip(), mode="eval")
        except SyntaxError as exc:
            raise ExpressionError(f"{where}: syntax error in {source!r:.80}: {exc.msg} "
                                  f"(column {exc.offset})") from None
        except (RecursionError, MemoryError):
            raise ExpressionError(f"{where}: expression nested too deeply") from None
        if _nodes(tree) > MAX_NODES:
            raise ExpressionError(f"{where}: expression has more than {MAX_NODES} syntax nodes")
        _Checker(names, where).visit(tree)
        self.names = frozenset(n.id for n in ast.walk(tree) if isinstance(n, ast.Name))
        weight = _nodes(tree)
        tree = _Guard().visit(tree)
        if args is not None:  # a function: ``lambda *args: __call(weight) or body``, built here
            signature = ast.arguments(posonlyargs=[], args=[ast.arg(a) for a in args],
                                      kwonlyargs=[], kw_defaults=[], defaults=[])
            body = ast.BoolOp(ast.Or(), [_call("__call", ast.Constant(weight)), tree.body])
            tree = ast.Expression(ast.Lambda(signature, body))
        tree = ast.fix_missing_locations(tree)
        self.source = source
        self.where = where
        self.args = args
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", SyntaxWarning)
                self.code = compile(tree, f"<{where}>", "eval")
        except (RecursionError, MemoryError):
            raise ExpressionError(f"{where}: expression nested too deeply") from None

    def evaluate(self, namespace: dict[str, Any]) -> Any:
        """Evaluate in ``namespace`` (made by :func:`guard_namespace`); a function expression
        evaluates to a Python function whose globals are ``namespace``. Each call starts a new
        budget; functions called from it share that budget."""
        namespace["__budget"].reset()
        return eval(self.code, namespace)  # noqa: S307 - checked against the whitelist above

    def __repr__(self) -> str:
        return f"Expression({self.source!r})"


def guard_namespace(values: Mapping[str, Any], budget: Budget | None = None) -> dict[str, Any]:
    """A globals dict for :meth:`Expression.evaluate`: no Python builtins, the budget's guards and
    bounded builtins, and ``values``. Namespaces that share ``budget`` share its limits."""
    budget = budget or Budget()
    namespace: dict[str, Any] = {
        "__builtins__": {}, "__budget": budget, "__items": budget.items, "__sized": budget.sized,
        "__operand": budget.operand, "__call": budget.call, "__slice": budget.slice,
        "__add": budget.add, "__sub": budget.sub, "__mul": budget.mul, "__mod": budget.mod,
        "__truediv": budget.truediv, "__floordiv": budget.floordiv}
    namespace.update(budget.builtins())
    namespace.update(values)
    return namespace
