"""A promise read as the agent can know it: decision expressions the search tries first.

A promise speaks of what happened (the true map, the steps run); a behavior decides on what it
observes. The env's :attr:`~vlb_gym.core.search_space.SearchSpace.beliefs` say what the agent
believes of each outcome helper (``is_goal(x)`` -> ``label(x) == 'goal'``); :func:`readings`
rewrites a promise through them, part by part (a part that names an outcome helper the env
gives no belief for is left out: of ``A and B`` the reading is ``A``'s), twice: with the place
where the behavior ends read as *here* ("would the promise hold if I stopped now?": a stopping
condition) and as a bound variable ``c`` ("would it hold if I ended in c?": a filter for where to
go). Every sub-expression of the readings is offered to the search at the cost of one name,
with the constants the promise and the request name (numbers, cells, lists of cells).
"""

from __future__ import annotations

import ast
import copy
import re
from collections.abc import Mapping
from typing import Any

from vlb_gym.core.expressions import BUILTINS
from vlb_gym.core.search_space import SearchSpace

TARGET = "TARGET"
MAX_READINGS = 60
_NUMBER_WORDS = {"once": 1, "one": 1, "twice": 2, "two": 2, "three": 3, "thrice": 3,
                 "four": 4, "five": 5, "six": 6, "seven": 7, "eight": 8, "nine": 9, "ten": 10}


def numbers(*texts: str) -> list[int]:
    """The counts named in ``texts`` (digits and number words up to ten), in [1, 100]."""
    found: set[int] = set()
    for text in texts:
        words = re.findall(r"[a-z]+|\d+", text.lower())
        found |= {int(w) for w in words if w.isdigit() and 1 <= int(w) <= 100}
        found |= {_NUMBER_WORDS[w] for w in words if w in _NUMBER_WORDS}
    return sorted(found)


def literals(expr: str) -> list[Any]:
    """The constant numbers, tuples and lists written in the expression ``expr``."""
    try:
        tree = ast.parse(expr, mode="eval")
    except SyntaxError:
        return []
    out: list[Any] = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.Tuple, ast.List, ast.Constant)):
            try:
                value = ast.literal_eval(node)
            except (ValueError, SyntaxError, TypeError):
                continue
            if not isinstance(value, (bool, str, float)) and value is not None:
                out.append(value)
    return out


class _Reader(ast.NodeTransformer):
    """Rewrites outcome helper calls into beliefs; None where a part cannot be read."""

    def __init__(self, beliefs: Mapping[str, str], outcome: set[str]):
        self.beliefs = beliefs
        self.outcome = outcome

    def read(self, node: ast.AST) -> ast.AST | None:
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) \
                and node.func.id in self.outcome:
            template = self.beliefs.get(node.func.id)
            if template is None:
                return None
            args = [self.read(a) for a in node.args]
            if any(a is None for a in args):
                return None
            text = template.format(*[f"({ast.unparse(a)})" for a in args])
            return ast.parse(text, mode="eval").body
        if isinstance(node, ast.BoolOp):
            values = [v for v in (self.read(v) for v in node.values) if v is not None]
            if not values:
                return None
            return values[0] if len(values) == 1 else ast.BoolOp(node.op, values)
        fields = {}
        for name, value in ast.iter_fields(node):
            if isinstance(value, ast.AST):
                read = self.read(value)
                if read is None:
                    return None
                fields[name] = read
            elif isinstance(value, list):
                items = []
                for item in value:
                    read = self.read(item) if isinstance(item, ast.AST) else item
                    if read is None:
                        return None
                    items.append(read)
                fields[name] = items
            else:
                fields[name] = value
        return type(node)(**fields)


class _Inliner(ast.NodeTransformer):
    """Names a comprehension binds to one value (``for s in [start_cell()]``, a promise's way
    of saying "let") replaced by that value: ``all(P for s in [X])`` is ``P`` with ``X`` for
    ``s``, so its parts can be read as decision expressions."""

    def visit_Call(self, node: ast.Call) -> ast.AST:
        self.generic_visit(node)
        if isinstance(node.func, ast.Name) and node.func.id in ("all", "any") \
                and len(node.args) == 1 and isinstance(node.args[0], ast.List) \
                and len(node.args[0].elts) == 1:
            return node.args[0].elts[0]
        return node

    def _comprehension(self, node: ast.AST) -> ast.AST:
        self.generic_visit(node)
        kept = []
        targets = {n.id for g in node.generators for n in ast.walk(g.target)
                   if isinstance(n, ast.Name)}
        for index, generator in enumerate(node.generators):
            value = _single(generator)
            if value is None or targets & {n.id for n in ast.walk(value)
                                           if isinstance(n, ast.Name)}:
                kept.append(generator)
                continue
            for later in node.generators[index + 1:]:
                _substitute(later, generator.target.id, value)
            _substitute_in(node, generator.target.id, value)
        node.generators = kept
        if kept:
            return node
        if isinstance(node, ast.SetComp):  # one value: a collection of it
            return ast.Set([node.elt])
        return ast.List([node.elt], ast.Load())

    visit_ListComp = visit_GeneratorExp = visit_SetComp = _comprehension


def _single(generator: ast.comprehension) -> ast.expr | None:
    """The one value ``generator`` binds its name to, or None."""
    if isinstance(generator.target, ast.Name) and not generator.ifs \
            and not generator.is_async and isinstance(generator.iter, (ast.List, ast.Tuple)) \
            and len(generator.iter.elts) == 1:
        return generator.iter.elts[0]
    return None


def _substitute(node: ast.AST, name: str, value: ast.expr) -> None:
    """Every load of ``name`` under ``node`` replaced by a copy of ``value``."""
    for parent in ast.walk(node):
        for field, child in ast.iter_fields(parent):
            if isinstance(child, ast.Name) and child.id == name and isinstance(child.ctx, ast.Load):
                setattr(parent, field, copy.deepcopy(value))
            elif isinstance(child, list):
                for k, item in enumerate(child):
                    if isinstance(item, ast.Name) and item.id == name \
                            and isinstance(item.ctx, ast.Load):
                        child[k] = copy.deepcopy(value)


def _substitute_in(node: ast.AST, name: str, value: ast.expr) -> None:
    """``name`` replaced in a comprehension's element (wrapped so the root can be replaced)."""
    holder = ast.Expression(body=node.elt)
    _substitute(holder, name, value)
    node.elt = holder.body


def _inlined(tree: ast.Expression) -> ast.Expression:
    return ast.fix_missing_locations(_Inliner().visit(tree))


def _renamed(tree: ast.AST, avoid: set[str]) -> ast.AST:
    """Comprehension variables renamed p0, p1, ... (away from the search's bound names)."""
    names = {t.id for gen in ast.walk(tree) if isinstance(gen, ast.comprehension)
             for t in ast.walk(gen.target) if isinstance(t, ast.Name)}
    mapping = {name: f"p{k}" for k, name in enumerate(sorted(names))}
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and node.id in mapping:
            node.id = mapping[node.id]
    return tree


def readings(promise: str, space: SearchSpace, outcome: set[str], decision: set[str],
             variable: str = "c") -> list[tuple[str, bool]]:
    """Decision expressions read from ``promise`` (see the module's docstring): each as
    (text, whether it uses ``variable``), largest first, each once. ``outcome`` are the env's
    outcome helper names, ``decision`` the names a decision expression may use."""
    if not space.beliefs or space.here is None:
        return []
    try:
        tree = _renamed(_inlined(ast.parse(promise, mode="eval")).body, {variable})
    except SyntaxError:
        return []
    read = _Reader(space.beliefs, outcome).read(tree)
    if read is None:
        return []
    text = ast.unparse(read)
    known = decision | set(BUILTINS) | {m.name for m in space.memory}
    out: dict[str, bool] = {}
    for target, bound in ((space.here[1], False), (variable, True)):
        whole = ast.parse(text.replace(TARGET, target), mode="eval").body
        for node in ast.walk(whole):
            if not isinstance(node, ast.expr) or isinstance(
                    node, (ast.Name, ast.Constant, ast.Slice, ast.GeneratorExp)):
                continue
            free = _free_names(node)
            if not free <= known | ({variable} if bound else set()):
                continue
            uses = variable in free
            if uses == bound:
                out.setdefault(ast.unparse(node), uses)
    return list(out.items())[:MAX_READINGS]


def _free_names(node: ast.AST) -> set[str]:
    """Names used in ``node`` and not bound by a comprehension inside it."""
    bound = {t.id for gen in ast.walk(node) if isinstance(gen, ast.comprehension)
             for t in ast.walk(gen.target) if isinstance(t, ast.Name)}
    used = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)
            and isinstance(n.ctx, ast.Load)}
    return used - bound
