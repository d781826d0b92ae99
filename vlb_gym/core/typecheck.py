"""A small, conservative type check of behavior expressions: meaning errors caught before running.

Helpers declare their types with ordinary annotations (``def label(self, cell: Cell) -> str``);
a helper whose string result is one of a closed set of values says so with
``@helper(one_of=(...))``. :func:`check` infers simple types over an already whitelisted
expression -- int, float, bool, None, str (with its possible values when known), tuple,
``list[T]`` -- and refuses only what cannot be right:

* comparing a closed-set string with something that is not a string (``label(c) == 2``), or
  testing it for equality/membership with a string outside the set (``label(c) == 'wall'``);
* calling a helper or builtin with a number of arguments it cannot take;
* passing a helper an argument of an obviously wrong type (a number where it takes a cell, a
  string where it takes a number, ...);
* ordering values that have no order between them (``known_cells() > 3``, a cell against a
  number, anything against None);
* summing a list of what is not a number (``sum(moves())``, a list of cells);
* ``bool()`` of a generator (always True); a generator is a *generator*, never a condition.

Whatever it cannot infer is *unknown* and accepted: behavior variables (``set`` may change them)
and function arguments are unknown, unions (``Cell | None``) are unknown, and so is any
annotation it does not understand.
"""

from __future__ import annotations

import ast
from collections.abc import Mapping
from typing import Any

from .expressions import ExpressionError
from .signatures import (BOOL, BUILTIN_SIGNATURES, FLOAT, INT, NONE, NUMBERS, STR, TUPLE,
                         Signature, Type, Unknown)

GENERATOR = Type("generator")  # ``(x for x in xs)``: only any, all, sum, min, max ... take one


class TypeCheckError(ExpressionError):
    """An expression cannot be right; the message names the place and says why."""


def _join(a: Type | None, b: Type | None) -> Type | None:
    """The type of a value that is either an ``a`` or a ``b``."""
    if a is None or b is None:
        return Unknown
    if a == b:
        return a
    if a.kind == b.kind == "str":
        if a.values is None or b.values is None:
            return STR
        return Type("str", tuple(dict.fromkeys((*a.values, *b.values))))
    if a.kind == b.kind == "list":
        return Type("list", item=_join(a.item, b.item))
    if a.kind == b.kind:
        return Type(a.kind)
    return Unknown


def _quoted(values: tuple[str, ...]) -> str:
    return ", ".join(repr(v) for v in values)


def _constant(node: ast.expr) -> Any:
    """The value of a constant node (including ``-2``), or raise LookupError."""
    if isinstance(node, ast.Constant):
        return node.value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)) \
            and isinstance(node.operand, ast.Constant) \
            and isinstance(node.operand.value, (int, float)):
        return ast.literal_eval(node)
    raise LookupError


def _accepts(param: Type | None, arg: Type | None) -> bool:
    """Whether a parameter of type ``param`` can obviously not take an ``arg`` (False)."""
    if param is None or arg is None:
        return True
    if param.kind in ("int", "float"):
        return arg.kind in NUMBERS
    if param.kind in ("tuple", "list"):  # sequences: a cell may be written as a list
        return arg.kind in ("tuple", "list")
    if param.kind == "str":
        return arg.kind == "str"
    return True


def _a(t: Type) -> str:
    """A type named with its article: 'an int', 'a tuple', 'None'."""
    name = t.describe()
    return name if t.kind == "none" else ("an " if name[0] in "aeiou" else "a ") + name


_SEQUENCES = ("str", "list", "tuple")
_SYMBOLS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.FloorDiv: "//",
            ast.Mod: "%", ast.Pow: "**"}


class _Inference:
    def __init__(self, signatures: Mapping[str, Signature], where: str):
        self.signatures = signatures
        self.where = where
        self.scopes: list[dict[str, Type | None]] = []

    def fail(self, node: ast.AST, message: str) -> None:
        col = getattr(node, "col_offset", None)
        at = f" (column {col + 1})" if col is not None else ""
        raise TypeCheckError(f"{self.where}: {message}{at}")

    def infer(self, node: ast.AST) -> Type | None:
        method = getattr(self, f"_{type(node).__name__}", None)
        if method is None:
            for child in ast.iter_child_nodes(node):
                self.infer(child)
            return Unknown
        return method(node)

    def _Expression(self, node: ast.Expression) -> Type | None:
        return self.infer(node.body)

    def _Constant(self, node: ast.Constant) -> Type | None:
        value = node.value
        if isinstance(value, bool):
            return BOOL
        if isinstance(value, int):
            return INT
        if isinstance(value, float):
            return FLOAT
        if isinstance(value, str):
            return Type("str", (value,))
        if value is None:
            return NONE
        return Unknown

    def _Name(self, node: ast.Name) -> Type | None:
        for scope in reversed(self.scopes):
            if node.id in scope:
                return scope[node.id]
        return Unknown  # variables and function arguments: ``set`` and callers decide

    def _UnaryOp(self, node: ast.UnaryOp) -> Type | None:
        operand = self.infer(node.operand)
        if isinstance(node.op, ast.Not):
            return BOOL
        if operand is not None and operand.kind in ("int", "float"):
            return operand
        return Unknown

    def _BinOp(self, node: ast.BinOp) -> Type | None:
        left, right = self.infer(node.left), self.infer(node.right)
        if left is None or right is None:
            return Unknown
        self._operands(node, left, right)
        numeric = ("int", "float")
        if left.kind in numeric and right.kind in numeric:
            if isinstance(node.op, ast.Div) or FLOAT in (left, right):
                return FLOAT
            return INT
        if isinstance(node.op, ast.Add) and left.kind == right.kind == "str":
            return STR
        if isinstance(node.op, ast.Add) and left.kind == right.kind == "list":
            return Type("list", item=_join(left.item, right.item))
        return Unknown

    def _operands(self, node: ast.BinOp, left: Type, right: Type) -> None:
        """A type error where Python would raise one for these operand kinds (numbers with
        numbers; ``+`` joins two of one sequence kind; ``*`` repeats a sequence a whole number
        of times)."""
        if left.kind in NUMBERS and right.kind in NUMBERS:
            return
        if isinstance(node.op, ast.Add) and left.kind == right.kind and left.kind in _SEQUENCES:
            return
        if isinstance(node.op, ast.Mult) and any(
                a.kind in _SEQUENCES and b.kind in ("int", "bool")
                for a, b in ((left, right), (right, left))):
            return
        symbol = _SYMBOLS.get(type(node.op), type(node.op).__name__)
        self.fail(node, f"{ast.unparse(node)!r} applies {symbol!r} to {_a(left)} and "
                        f"{_a(right)}, which fails whenever it runs")

    def _BoolOp(self, node: ast.BoolOp) -> Type | None:
        types = [self.infer(v) for v in node.values]
        out = types[0]
        for t in types[1:]:
            out = _join(out, t)
        return out

    def _IfExp(self, node: ast.IfExp) -> Type | None:
        self.infer(node.test)
        return _join(self.infer(node.body), self.infer(node.orelse))

    def _List(self, node: ast.List | ast.Tuple) -> Type | None:
        items = [self.infer(e) for e in node.elts]
        if isinstance(node, ast.Tuple):
            return TUPLE
        item = items[0] if items else Unknown
        for t in items[1:]:
            item = _join(item, t)
        return Type("list", item=item)

    _Tuple = _List

    def _Subscript(self, node: ast.Subscript) -> Type | None:
        value = self.infer(node.value)
        self.infer(node.slice)
        if value is None:
            return Unknown
        if isinstance(node.slice, ast.Slice):
            return value if value.kind in ("list", "tuple") else (STR if value.kind == "str"
                                                                  else Unknown)
        if value.kind == "list":
            return value.item
        if value.kind == "str":
            return STR
        return Unknown

    def _comprehension(self, node: ast.ListComp | ast.GeneratorExp) -> Type | None:
        scope: dict[str, Type | None] = {}
        self.scopes.append(scope)
        try:
            for gen in node.generators:
                source = self.infer(gen.iter)
                item = source.item if source is not None and source.kind == "list" else Unknown
                if isinstance(gen.target, ast.Name):
                    scope[gen.target.id] = item
                else:  # tuple unpacking: the parts are unknown
                    for target in gen.target.elts:
                        scope[target.id] = Unknown
                for cond in gen.ifs:
                    self.infer(cond)
            item = self.infer(node.elt)
        finally:
            self.scopes.pop()
        return Type("list", item=item) if isinstance(node, ast.ListComp) else GENERATOR

    _ListComp = _GeneratorExp = _comprehension

    def _Call(self, node: ast.Call) -> Type | None:
        args = [self.infer(a) for a in node.args]
        name = node.func.id if isinstance(node.func, ast.Name) else None
        if name is None or any(name in scope for scope in self.scopes):
            return Unknown
        sig = self.signatures.get(name)
        if sig is None:
            return Unknown
        if name == "bool" and args and args[0] is not None and args[0].kind == "generator":
            self.fail(node, "bool() of a generator is always True: write any(...) or all(...)")
        given = len(node.args)
        if given < sig.min_args or (sig.max_args is not None and given > sig.max_args):
            if sig.max_args is None:
                takes = f"at least {sig.min_args}"
            elif sig.min_args == sig.max_args:
                takes = str(sig.min_args)
            else:
                takes = f"{sig.min_args} to {sig.max_args}"
            self.fail(node, f"{name}() takes {takes} argument(s), {given} given")
        for i, (param, arg, arg_node) in enumerate(zip(sig.params, args, node.args)):
            if not _accepts(param, arg):
                self.fail(arg_node, f"{name}() argument {i + 1} is a {param.describe()}; "
                                    f"given {arg.describe()} {ast.unparse(arg_node)}")
        if sig.returns is not None:
            return sig.returns
        first = args[0] if args else None
        if name == "sum" and first is not None and first.kind == "list" \
                and first.item is not None and first.item.kind not in NUMBERS:
            self.fail(node, f"sum() adds numbers; {ast.unparse(node.args[0])} is a list of "
                            f"{first.item.describe()}")
        return self._builtin(name, args)

    @staticmethod
    def _builtin(name: str, args: list[Type | None]) -> Type | None:
        if not args or name not in BUILTIN_SIGNATURES:
            return Unknown
        first = args[0]
        if name == "sorted" and first is not None and first.kind == "list":
            return first
        if name in ("min", "max"):
            if len(args) == 1:
                return first.item if first is not None and first.kind == "list" else Unknown
            out = first
            for t in args[1:]:
                out = _join(out, t)
            return out
        if name == "abs" and first is not None and first.kind in ("int", "float"):
            return first

        if name == "round" and len(args) == 1:
            return INT
        return Unknown

    def _Compare(self, node: ast.Compare) -> Type | None:
        operands = [node.left, *node.comparators]
        types = [self.infer(o) for o in operands]
        for op, (ln, lt), (rn, rt) in zip(node.ops, zip(operands, types),
                                          zip(operands[1:], types[1:])):
            if isinstance(op, (ast.In, ast.NotIn)):
                self._membership(ln, lt, rn)
            else:
                self._compare(ln, lt, rn, rt, isinstance(op, (ast.Eq, ast.NotEq)))
                self._compare(rn, rt, ln, lt, isinstance(op, (ast.Eq, ast.NotEq)))
                if isinstance(op, (ast.Lt, ast.LtE, ast.Gt, ast.GtE)):
                    self._order(node, ln, lt, rn, rt)
        return BOOL

    def _order(self, node: ast.Compare, left: ast.expr, lt: Type | None, right: ast.expr,
               rt: Type | None) -> None:
        """``<``-like comparisons hold only between numbers, or values of one sequence kind."""
        for side, t in ((left, lt), (right, rt)):
            if t is not None and t.kind == "none":
                self.fail(node, f"{ast.unparse(side)} is None, which has no order")
        group = {k: "number" for k in NUMBERS}
        if lt is not None and rt is not None and \
                group.get(lt.kind, lt.kind) != group.get(rt.kind, rt.kind):
            self.fail(node, f"{ast.unparse(left)} ({lt.describe()}) and {ast.unparse(right)} "
                            f"({rt.describe()}) have no order")

    def _closed(self, node: ast.expr, t: Type | None) -> str | None:
        """How to say that ``node`` is one of a closed set of strings, or None if it is not."""
        if t is None or t.kind != "str" or t.values is None or isinstance(node, ast.Constant):
            return None
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) \
                and node.func.id in self.signatures:
            return f"{node.func.id}() returns one of {_quoted(t.values)}"
        return f"{ast.unparse(node)} is one of {_quoted(t.values)}"

    def _compare(self, node: ast.expr, t: Type | None, other: ast.expr, other_t: Type | None,
                 equality: bool) -> None:
        closed = self._closed(node, t)
        if closed is None or other_t is None:
            return
        try:
            value = _constant(other)
        except LookupError:
            value = None
            shown = ast.unparse(other)
        else:
            shown = repr(value)
        if other_t.kind == "none":
            self.fail(node, f"{closed}; compared with None")
        if other_t.kind != "str":
            self.fail(node, f"{closed}; compared with {other_t.describe()} {shown}")
        if equality and isinstance(value, str) and value not in t.values:
            self.fail(node, f"{closed}; compared with {value!r}, which it never is")

    def _membership(self, node: ast.expr, t: Type | None, container: ast.expr) -> None:
        closed = self._closed(node, t)
        if closed is None or not isinstance(container, (ast.List, ast.Tuple, ast.Set)):
            return
        for element in container.elts:
            try:
                value = _constant(element)
            except LookupError:
                continue
            if not isinstance(value, str):
                self.fail(node, f"{closed}; tested against {type(value).__name__} {value!r}")
            if value not in t.values:
                self.fail(node, f"{closed}; tested against {value!r}, which it never is")


def check(source: str, signatures: Mapping[str, Signature], where: str = "expression"
          ) -> Type | None:
    """Type-check ``source`` (already accepted by :class:`vlb_gym.core.expressions.Expression`)
    given the signatures of the callables it may use; return its inferred type (None: unknown).
    Raises :class:`TypeCheckError` for what cannot be right."""
    tree = ast.parse(source.strip(), mode="eval")
    return _Inference(signatures, where).infer(tree)
