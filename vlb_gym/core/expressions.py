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
:class:`~vlb_gym.core.budget.Budget` that counts *work*, not items: every comprehension item and every call of a
behavior function is charged the size of the code it runs, every operation that builds or
compares sequences is charged the elements it touches (nested ones included), list-returning
helpers are charged their result's length; every list, tuple or string an operation builds holds
at most ``MAX_SIZE`` elements, every integer it computes stays bounded in magnitude, and
``round`` takes a bounded number of digits (:mod:`.budget`). Exceeding any limit raises
``EvaluationLimitError`` (a ``ValueError``): the episode fails with that reason, and
the process never hangs or runs out of memory.
"""

from __future__ import annotations

import ast
import difflib
import warnings
from collections.abc import Mapping
from typing import Any


from .budget import Budget
from .errors import UserError

MAX_SOURCE_CHARS = 2000
MAX_NODES = 400
MAX_GENERATORS = 3
MAX_INT = 10**9  # largest constant
MAX_STR = 200  # longest string constant

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


class ExpressionError(UserError, ValueError):
    """An expression is malformed, forbidden or too large; the message says why and where."""


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

    def _nearest(self, name: str) -> str:
        """The functions that might have been meant: the nearest by spelling, and the env's
        helpers and the behavior's functions (the builtins are documented once for all);
        nothing for a name no one could mean (``__import__``)."""
        if name.startswith("_"):
            return ""
        functions = sorted(n for n, arity in self.names.items()
                           if arity != -1 and not n.startswith("_"))
        near = difflib.get_close_matches(name, functions, n=1, cutoff=0.6)
        helpers = [n for n in functions if n not in BUILTINS]
        return ((f"; did you mean {near[0]!r}?" if near else "")
                + (f" (functions here: {', '.join(helpers)})" if helpers else ""))

    def visit_Call(self, node: ast.Call) -> None:
        if not isinstance(node.func, ast.Name):
            self.fail(node, "only helpers called by plain name are allowed")
        name = node.func.id
        if name.startswith("_") or self._bound(name) or name not in self.names:
            self.fail(node, f"call to {name!r}, which is not a whitelisted function"
                            f"{self._nearest(name)}")
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
        if len(node.generators) == 1:  # no longer than its source, which items() bounded and
            return node  # charged at least one unit per item
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
