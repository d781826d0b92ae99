"""A promise read as the agent can know it: decision expressions the search tries first.

A promise speaks of what happened (the true map, the steps run); a behavior decides on what it
observes. The env's :attr:`~vlb_gym.core.search_space.SearchSpace.beliefs` say what the agent
believes of each outcome helper (``is_goal(x)`` -> ``label(x) == 'goal'``); :func:`readings`
rewrites a promise through them, part by part (a part that names an outcome helper the env
gives no belief for is left out: of ``A and B`` the reading is ``A``'s; where a whole cannot
be read, as ``X if C else known_before_last() == [...]``, its largest parts that can are, ``C``
and ``X``), twice: with the place where the behavior ends read as *here* ("would the promise
hold if I stopped now?": a stopping condition) and as a bound variable ``c`` ("would it hold if
I ended in c?": a filter for where to go); :func:`after_moving` reads it once more as it would
be after one more move to ``c`` (the steps and moves it counts one more). A comprehension over
a few values written out (``[E for K in [known_before_last(), known_cells()]]``) is read at
each value it can be. Every sub-expression of the readings is offered to the search at the cost
of one name, with the constants the promise and the request name (numbers, cells, lists of
cells). A place the promise says is the least or greatest of a list's elements by some score
(the nearest, the one with the fewest obstacles next to it: :func:`extremes`) is read as the
expression that picks it, so that going there costs one name too, and so are the places a
quantifier speaks of (:func:`witnesses`: of ``any``, where it holds; of ``all``, where it does
not).
"""

from __future__ import annotations

import ast
import copy
import re
from collections.abc import Iterator, Mapping
from typing import Any

from vlb_gym.core.expressions import BUILTINS
from vlb_gym.core.search_space import SearchSpace

TARGET = "TARGET"
MAX_READINGS = 60
MAX_CASES = 5  # a promise and the readable cases of its conditionals
MAX_EACH = 4  # values of a comprehension over a list written out, each read on its own
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


def _written_out(generator: ast.comprehension) -> list[ast.expr]:
    """The values ``generator`` binds its name to where they are written out (``for K in [A,
    B]``, no filter), else none."""
    if isinstance(generator.target, ast.Name) and not generator.ifs \
            and not generator.is_async and isinstance(generator.iter, (ast.List, ast.Tuple)):
        return generator.iter.elts
    return []


def _single(generator: ast.comprehension) -> ast.expr | None:
    """The one value ``generator`` binds its name to, or None."""
    values = _written_out(generator)
    return values[0] if len(values) == 1 else None


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


def _instance(general: ast.AST, particular: ast.AST, name: str, found: list[ast.AST]) -> bool:
    """Whether ``particular`` is ``general`` with one expression (collected in ``found``, every
    occurrence the same) written where ``general`` says ``name``."""
    if isinstance(general, ast.Name) and general.id == name:
        found.append(particular)
        return ast.dump(particular) == ast.dump(found[0])
    if type(general) is not type(particular):
        return False
    for field, value in ast.iter_fields(general):
        other = getattr(particular, field, None)
        if isinstance(value, ast.AST):
            if not isinstance(other, ast.AST) or not _instance(value, other, name, found):
                return False
        elif isinstance(value, list):
            if not isinstance(other, list) or len(other) != len(value) or not all(
                    _instance(v, o, name, found) if isinstance(v, ast.AST) else v == o
                    for v, o in zip(value, other)):
                return False
        elif value != other:
            return False
    return True


def _score(general: ast.expr, particular: ast.expr, name: str) -> ast.expr | None:
    """Where ``particular`` is the score ``general`` (which uses ``name``) of one element: that
    element (the expression written for ``name``), or None."""
    found: list[ast.AST] = []
    if _instance(general, particular, name, found) and found and name not in {
            n.id for n in ast.walk(particular) if isinstance(n, ast.Name)}:
        return found[0]
    return None


_LEAST = {ast.Lt: "argmin", ast.LtE: "argmin", ast.Gt: "argmax", ast.GtE: "argmax"}
_OPPOSITE = {"argmin": "argmax", "argmax": "argmin"}
Extreme = tuple[str, ast.expr, ast.expr, list[ast.expr]]  # end, score, place, conditions


def _extreme(elt: ast.expr, name: str) -> Extreme | None:
    """Of a quantified ``all(elt for name in ...)``: which end (argmin, argmax) of which score
    of ``name`` the promise's place (``final_cell()``) is at, and the conditions under which
    ``elt`` asks it (``is_obstacle(n) or K(x) <= K(n)``: where ``n`` is not an obstacle);
    None if it says no such thing."""
    if isinstance(elt, ast.BoolOp):
        hits = [(v, e) for v in elt.values if (e := _extreme(v, name)) is not None]
        if len(hits) != 1:
            return None
        value, (end, score, place, conditions) = hits[0]
        if isinstance(elt.op, ast.Or):  # the comparison where no other part holds
            conditions = conditions + [ast.UnaryOp(ast.Not(), v) for v in elt.values
                                       if v is not value]
        return end, score, place, conditions  # (and: the comparison among other demands)
    if not (isinstance(elt, ast.Compare) and len(elt.ops) == 1
            and type(elt.ops[0]) in _LEAST):
        return None
    left, right, end = elt.left, elt.comparators[0], _LEAST[type(elt.ops[0])]
    if (place := _score(right, left, name)) is not None:
        return end, right, place, []
    if (place := _score(left, right, name)) is not None:
        return _OPPOSITE[end], left, place, []
    return None


def _generator(node: ast.AST) -> ast.comprehension | None:
    """The one generator of a generator expression (or a list comprehension) over a plain
    name, or None."""
    if isinstance(node, (ast.GeneratorExp, ast.ListComp)) and len(node.generators) == 1 \
            and isinstance(node.generators[0].target, ast.Name):
        return node.generators[0]
    return None


# a place compared with min or max of the scores is at that end when it is no more than the
# least (no less than the greatest): (min or max, whether min/max is on the left) -> operators
_BOUNDING = {("min", False): (ast.Eq, ast.LtE), ("min", True): (ast.Eq, ast.GtE),
             ("max", False): (ast.Eq, ast.GtE), ("max", True): (ast.Eq, ast.LtE)}


def _quantified(node: ast.AST) -> tuple[ast.comprehension, Extreme | None] | None:
    """A generator and what :func:`_extreme` reads of it, where ``node`` is
    ``all(... for n in L if P)`` or bounds a score by ``min``/``max`` of the scores of ``L``'s
    elements (``K(x) == min(K(n) for n in L if P)``, ``K(x) <= min(...)``); None where it is
    neither."""
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) \
            and node.func.id == "all" and len(node.args) == 1 and not node.keywords \
            and (generator := _generator(node.args[0])) is not None:
        return generator, _extreme(node.args[0].elt, generator.target.id)
    if not (isinstance(node, ast.Compare) and len(node.ops) == 1):
        return None
    for one, other, first in ((node.left, node.comparators[0], True),
                              (node.comparators[0], node.left, False)):
        if isinstance(one, ast.Call) and isinstance(one.func, ast.Name) \
                and one.func.id in ("min", "max") and len(one.args) == 1 \
                and isinstance(node.ops[0], _BOUNDING[one.func.id, first]) \
                and (generator := _generator(one.args[0])) is not None \
                and (place := _score(one.args[0].elt, other, generator.target.id)) is not None:
            end = "argmin" if one.func.id == "min" else "argmax"
            return generator, (end, one.args[0].elt, place, [])
    return None


def _positive(node: ast.expr) -> Iterator[ast.expr]:
    """``node`` and the parts of it the promise asks to hold where it holds (of ``and``/``or``,
    of both branches of ``x if c else y``; not under ``not``, in a test or an argument)."""
    yield node
    if isinstance(node, ast.BoolOp):
        for value in node.values:
            yield from _positive(value)
    elif isinstance(node, ast.IfExp):
        yield from _positive(node.body)
        yield from _positive(node.orelse)


def _mentions(node: ast.AST, part: ast.AST) -> bool:
    return any(ast.dump(n) == ast.dump(part) for n in ast.walk(node))


def extremes(tree: ast.expr) -> list[ast.expr]:
    """The places a promise says are the least or greatest by some score of a list's
    elements (``all(K(x) <= K(n) for n in L if P)``, either way round, or ``K(x) ==
    min(K(n) for n in L if P)``: x makes K least among L's elements that keep P), each as the
    expression picking it: ``[n for n in L if P][argmin([K(n) for n in L if P])]``. A condition
    that names x itself (``if n != x``: the others, for a strict comparison) is left out."""
    out = []
    for node in _positive(tree):
        quantified = _quantified(node)
        if quantified is None or quantified[1] is None:
            continue
        generator, (end, score, place, conditions) = quantified
        name = generator.target.id
        conditions = [c for c in [*generator.ifs, *conditions] if not _mentions(c, place)]
        if conditions:
            test = conditions[0] if len(conditions) == 1 else ast.BoolOp(ast.And(), conditions)
            among = ast.ListComp(ast.Name(name, ast.Load()), [ast.comprehension(
                ast.Name(name, ast.Store()), copy.deepcopy(generator.iter), [test], 0)])
        else:
            among = copy.deepcopy(generator.iter)
        scores = ast.ListComp(copy.deepcopy(score), [ast.comprehension(
            ast.Name(name, ast.Store()), copy.deepcopy(generator.iter),
            [copy.deepcopy(c) for c in conditions], 0)])
        pick = ast.Call(ast.Name(end, ast.Load()), [scores], [])
        out.append(ast.fix_missing_locations(ast.Subscript(among, pick, ast.Load())))
    return out


def _parsed(promise: str, space: SearchSpace, outcome: set[str], variable: str
            ) -> tuple[ast.expr, _Reader] | None:
    """``promise``'s tree (a "let" inlined, its comprehension names away from ``variable``) and
    the reader of ``space``'s beliefs; None where the space has none or the text is no
    expression."""
    if not space.beliefs or space.here is None:
        return None
    try:
        tree = _renamed(_inlined(ast.parse(promise, mode="eval")).body, {variable})
    except SyntaxError:
        return None
    return tree, _Reader(space.beliefs, outcome)


def readings(promise: str, space: SearchSpace, outcome: set[str], decision: set[str],
             variable: str = "c", each: set[str] | None = None) -> list[tuple[str, bool]]:
    """Decision expressions read from ``promise`` (see the module's docstring): each as
    (text, whether it uses ``variable``), largest first, each once. ``outcome`` are the env's
    outcome helper names, ``decision`` the names a decision expression may use; ``each``,
    where given, gets the readings that list the places an ``all`` speaks of (every one to be
    seen to)."""
    parsed = _parsed(promise, space, outcome, variable)
    if parsed is None:
        return []
    tree, reader = parsed
    known = decision | set(BUILTINS) | {m.name for m in space.memory}
    out: dict[str, bool] = {}
    for extreme in extremes(tree):
        picked = reader.read(extreme)
        if picked is not None and _free_names(picked) <= known:
            out.setdefault(ast.unparse(picked), False)
    texts = list(dict.fromkeys(ast.unparse(part) for case in _cases(reader, tree)
                               for part in _readable(reader, case)))
    for target, bound in ((space.here[1], False), (variable, True)):
        for node in (node for text in texts for node in ast.walk(
                ast.parse(text.replace(TARGET, target), mode="eval").body)):
            if not isinstance(node, ast.expr) or isinstance(
                    node, (ast.Name, ast.Constant, ast.Slice, ast.GeneratorExp)):
                continue
            for part in (node, *witnesses(node)):
                free = _free_names(part)
                if free <= known | ({variable} if bound else set()) \
                        and (variable in free) == bound:
                    out.setdefault(ast.unparse(part), bound)
                    if each is not None and part is not node and node.func.id == "all":
                        each.add(ast.unparse(part))
    return list(out.items())[:MAX_READINGS]


def after_moving(promise: str, space: SearchSpace, outcome: set[str], decision: set[str],
                 variable: str = "c") -> list[str]:
    """The promise (its first case that can be read) read as "would it hold if one more act
    moved the agent to ``variable`` now, and the behavior ended there?", for each primitive
    whose parameter is of the space's first kind: where the behavior ends and where the agent
    is read as ``variable``, and the memory that act updates as it would be updated (the steps
    and the moves a promise counts are one more). Only where that changes the reading; a
    parameter that filters by one is chosen before the updates."""
    parsed = _parsed(promise, space, outcome, variable)
    if parsed is None or space.here is None:
        return []
    tree, reader = parsed
    read = next((r for case in _cases(reader, tree) if (r := reader.read(case)) is not None),
                None)
    if read is None:
        return []
    text = ast.unparse(read).replace(TARGET, variable)
    known = decision | set(BUILTINS) | {m.name for m in space.memory} | {variable}
    here = ast.dump(ast.parse(space.here[1], mode="eval").body)
    kind = next(iter(space.types), None)
    out: list[str] = []
    for parameter in (p for p in space.parameters if p.kind == kind):
        values = {m.name: ast.parse(f"({update})".replace("PARAM", variable), mode="eval").body
                  for m in space.memory for name, update in m.updates
                  if name == parameter.primitive}
        moved = _Moving(values, here, variable).visit(ast.parse(text, mode="eval").body)
        after = ast.unparse(ast.fix_missing_locations(moved))
        if after != text and after not in out and _free_names(moved) <= known:
            out.append(after)
    return out


class _Moving(ast.NodeTransformer):
    """Loads of the memory names ``values`` names replaced by their values, and the
    expression of where the agent is (``here``, dumped) by ``variable``, all at once."""

    def __init__(self, values: dict[str, ast.expr], here: str, variable: str):
        self.values, self.here, self.variable = values, here, variable

    def visit_Name(self, node: ast.Name) -> ast.expr:
        if isinstance(node.ctx, ast.Load) and node.id in self.values:
            return copy.deepcopy(self.values[node.id])
        return node

    def visit_Call(self, node: ast.Call) -> ast.expr:
        if ast.dump(node) == self.here:
            return ast.Name(self.variable, ast.Load())
        return self.generic_visit(node)


def witnesses(node: ast.expr) -> list[ast.expr]:
    """Of ``any(E for x in L if P)``, the list of its witnesses ``[x for x in L if P and
    E]`` (the places that would make it hold: a place to go to); of ``all(...)``, of those
    that break it, ``[x for x in L if P and not E]`` (the places left to be seen to)."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
            and node.func.id in ("any", "all") and len(node.args) == 1 and not node.keywords
            and (generator := _generator(node.args[0])) is not None):
        return []
    test = copy.deepcopy(node.args[0].elt)
    if node.func.id == "all":
        test = _negation(test)
    test = ast.BoolOp(ast.And(), [*copy.deepcopy(generator.ifs), test]) if generator.ifs else test
    name = generator.target.id
    return [ast.fix_missing_locations(ast.ListComp(ast.Name(name, ast.Load()), [
        ast.comprehension(ast.Name(name, ast.Store()), copy.deepcopy(generator.iter), [test],
                          0)]))]


def _negation(test: ast.expr) -> ast.expr:
    """``not test``; of ``x in L``, ``x not in L`` (and the other way round)."""
    flipped = {ast.In: ast.NotIn, ast.NotIn: ast.In}
    if isinstance(test, ast.Compare) and len(test.ops) == 1 and type(test.ops[0]) in flipped:
        return ast.Compare(test.left, [flipped[type(test.ops[0])]()], test.comparators)
    return ast.UnaryOp(ast.Not(), test)


def _cases(reader: _Reader, tree: ast.expr) -> list[ast.expr]:
    """``tree``, then the trees where an ``X if C else Y`` that cannot be read whole is replaced
    by a branch that can be read: both where only ``C`` cannot (the steps decide it: each is a
    way to keep the promise), the other where one of ``X``, ``Y`` cannot (the case the agent
    can know of); outermost first, at most :data:`MAX_CASES` trees."""
    cases = [tree]
    for node in cases:  # (each case appended is split in its turn)
        nodes = list(ast.walk(node))
        split = next(((k, branches) for k, n in enumerate(nodes) if isinstance(n, ast.IfExp)
                      and reader.read(n) is None
                      and (branches := [b for b in ("body", "orelse")
                                        if reader.read(getattr(n, b)) is not None])), None)
        for branch in split[1] if split else ():
            if len(cases) >= MAX_CASES:
                return cases
            holder = ast.Expression(body=copy.deepcopy(node))
            conditional = list(ast.walk(holder.body))[split[0]]
            _replace(holder, conditional, getattr(conditional, branch))
            cases.append(holder.body)
    return cases


def _replace(root: ast.AST, old: ast.AST, new: ast.AST) -> None:
    """The node ``old`` under ``root`` replaced by ``new``."""
    for parent in ast.walk(root):
        for field, child in ast.iter_fields(parent):
            if child is old:
                setattr(parent, field, new)
            elif isinstance(child, list) and any(item is old for item in child):
                child[[item is old for item in child].index(True)] = new


def _readable(reader: _Reader, node: ast.AST) -> list[ast.AST]:
    """``node`` read through the beliefs or, where it cannot be read whole (``X if C else
    known_before_last() == [...]``: no belief reads what was known before), the largest parts
    of it that can (``C``, ``X``), outermost first; so are the parts of those an
    ``and``/``or`` left out."""
    read = reader.read(node)
    if read is None:
        return [part for each in _at_each(node) for part in _readable(reader, each)] \
            + [part for child in ast.iter_child_nodes(node)
                if isinstance(child, ast.expr) and not isinstance(child, ast.Slice)
                for part in _readable(reader, child)]
    dropped = [v for v in node.values if reader.read(v) is None] \
        if isinstance(node, ast.BoolOp) else []  # (left out of the reading of and/or)
    return [read, *(part for value in dropped for part in _readable(reader, value))]


def _at_each(node: ast.AST) -> list[ast.expr]:
    """Of a comprehension over a list of a few values written out (``[E for K in [A, B]]``, a
    promise's way of saying "for each of A and B"), ``E`` at each value, ``A`` then ``B``: the
    ones that can be read are readings even where another cannot (``known_before_last()``).
    Not where ``E`` holds such a comprehension itself: nested, the copies would multiply."""
    if not _each(node) or any(_each(n) for n in ast.walk(node.elt)):
        return []
    out = []
    for value in _each(node):
        holder = ast.Expression(body=copy.deepcopy(node.elt))
        _substitute(holder, node.generators[0].target.id, value)
        out.append(ast.fix_missing_locations(holder.body))
    return out


def _each(node: ast.AST) -> list[ast.expr]:
    """The 2 to :data:`MAX_EACH` values written out that ``node``, a comprehension of one
    generator, binds its name to; else none."""
    if not isinstance(node, (ast.ListComp, ast.GeneratorExp, ast.SetComp)) \
            or len(node.generators) != 1:
        return []
    values = _written_out(node.generators[0])
    return values if 2 <= len(values) <= MAX_EACH else []


def _free_names(node: ast.AST) -> set[str]:
    """Names used in ``node`` and not bound by a comprehension inside it."""
    bound = {t.id for gen in ast.walk(node) if isinstance(gen, ast.comprehension)
             for t in ast.walk(gen.target) if isinstance(t, ast.Name)}
    used = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)
            and isinstance(n.ctx, ast.Load)}
    return used - bound
