"""Structured behaviors -- sequences, conditionals and loops of primitives -- as behavior graphs.

The search (:mod:`vlb_gym.abstractor.search`) enumerates :class:`Program` s: a first
primitive, then statements, each an :class:`Act` (run a primitive with a parameter
expression), an :class:`If` (run its acts when a guard holds), a :class:`Loop` (run its acts
while a guard holds, at most ``limit`` times when it has one), a :class:`Stop` (end here when a
guard holds) or a :class:`Set` (give a settable memory variable a value: remember something
now). :meth:`Program.document` writes the behavior file that does exactly that: one node per
act, edges whose guards, in file order, pick the next act (an end where a guard holds: the
edges past it taken only where it does not), the env's memory variables the program reads
kept on the way (with those their updates read), a set variable assigned on the edges that leave
the point it is set at, and a counter per loop with a limit. Every node is terminal: where no
edge can be taken the behavior has finished, and its promise is judged.

An act whose parameter picks from a list (``L[0]``, ``L[-1]``, ``L[argmin(...)]``) is entered
only when the list is not empty: a loop that moves to the first of a list runs until the list
is exhausted, a statement that would pick from an empty list is skipped, and inside the acts of
a loop or a conditional the behavior ends there.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

from vlb_gym.core.expressions import MAX_GENERATORS, MAX_NODES, MAX_SOURCE_CHARS
from vlb_gym.core.search_space import SearchSpace
from vlb_gym.core.search_space import mentions as _mentions
from vlb_gym.core.search_space import name_pattern as _name

END = "<end>"
CHOSEN = "chosen"  # the variable a parameter that reads updated memory is chosen into
MOVED = "promised_after"  # the functions of a promise read after one more move (chosen first)


@dataclass(frozen=True)
class Act:
    """Use ``primitive`` with the parameter expression ``param``."""

    primitive: str
    param: str

    def words(self) -> str:
        return f"{self.primitive}({self.param})"


@dataclass(frozen=True)
class Use:
    """Use the library behavior ``behavior`` as a whole (a node that is a behavior: its promise
    is judged when it finishes). The memory is not updated by what it runs."""

    behavior: str

    def words(self) -> str:
        return f"use({self.behavior})"


@dataclass(frozen=True)
class If:
    """Use ``body`` when ``guard`` holds."""

    guard: str
    body: tuple[Act, ...]

    def words(self) -> str:
        return f"if {self.guard}: " + "; ".join(a.words() for a in self.body)


@dataclass(frozen=True)
class Loop:
    """Use ``body`` while ``guard`` holds, at most ``limit`` times when given."""

    guard: str
    body: tuple[Act, ...]
    limit: int | None = None

    def words(self) -> str:
        if self.guard == "True":
            head = f"repeat {self.limit} times" if self.limit else "repeat"
        else:
            head = f"while {self.guard}" + (f" (at most {self.limit} times)" if self.limit
                                             else "")
        return f"{head}: " + "; ".join(a.words() for a in self.body)


@dataclass(frozen=True)
class Stop:
    """End the behavior here when ``guard`` holds (what follows runs only where it does not:
    "if the first look shows an obstacle, stop; else search")."""

    guard: str

    def words(self) -> str:
        return f"stop if {self.guard}"


@dataclass(frozen=True)
class Set:
    """Give the settable memory variable ``name`` the value of ``value`` (no primitive runs)."""

    name: str
    value: str

    def words(self) -> str:
        return f"{self.name} = {self.value}"


Statement = Act | Use | If | Loop | Set | Stop


@dataclass(frozen=True)
class Program:
    """A first act, then statements."""

    statements: tuple[Statement, ...]

    def words(self) -> str:
        return "; ".join(s.words() for s in self.statements)

    def document(self, space: SearchSpace, name: str, description: str, env_id: str,
                 functions: dict[str, tuple[tuple[str, ...], str]] | None = None
                 ) -> dict[str, Any]:
        """The behavior file of this program (see the module's docstring); ``functions``
        (name -> its arguments and expression) are those its expressions may call, written
        into the file where they do (or where one written does)."""
        return _Writer(self, space).document(name, description, env_id, functions or {})


@lru_cache(maxsize=65536)
def reads(statement: Statement, names: frozenset[str]) -> bool:
    """Whether ``statement`` reads one of the variables ``names``."""
    words = statement.words()
    return any(_mentions(words, name) for name in names)


def acts(program: tuple[Statement, ...]) -> int:
    """The statements of ``program`` that act (all but its :class:`Set` s and :class:`Stop`
    s)."""
    return sum(not isinstance(s, (Set, Stop)) for s in program)


def memory_updates(space: SearchSpace, primitive: str) -> list[tuple[str, str]]:
    """(memory name, update expression) for each memory running ``primitive`` updates."""
    return [(m.name, update) for m in space.memory for name, update in m.updates
            if name == primitive]


def chosen_first(space: SearchSpace, act: Act) -> bool:
    """Whether ``act``'s parameter is evaluated before its memory updates rather than after: one
    that keeps only what an updated memory does not hold (``c not in path``: "a goal not yet
    stood on"), which after the update would never be the cell it is about to add, where the
    space says where the agent is (to start :data:`CHOSEN` from). Any other reads the memory as
    updated (``path[-2]`` is then the cell before the one moved to, as a promise's
    ``moves()[-2]`` reads it after the move), but one that calls a :data:`MOVED` function (a
    promise read as it would be after this move: the updates are in it)."""
    return space.here is not None and (after_a_move(act.param) or any(
        re.search(rf" not in {re.escape(name)}(?![\w'])", act.param)
        for name, _ in memory_updates(space, act.primitive)))


def after_a_move(param: str) -> bool:
    """Whether the parameter ``param`` calls a :data:`MOVED` function (reads the promise as it
    would be after the move it makes)."""
    return re.search(rf"\b{MOVED}\d*\(", param) is not None


def _ids(k: int, body: tuple[Act, ...]) -> list[str]:
    return [f"s{k}_{j}" for j in range(len(body))]


@lru_cache(maxsize=65536)
def _list_of(param: str) -> str | None:
    """The list a parameter picks from (``L`` of ``L[...]``), or None."""
    try:
        tree = ast.parse(param, mode="eval").body
    except SyntaxError:
        return None
    if isinstance(tree, ast.Subscript) and not isinstance(tree.slice, ast.Slice):
        return ast.unparse(tree.value)
    return None


def _substitute(text: str, name: str, value: str) -> str:
    """``text`` with the name ``name`` replaced by the expression ``value``."""
    return re.sub(_name(name), f"({value})", text)


def conjunction(conditions: list[str]) -> str:
    parts = [c for c in conditions if c != "True"]
    if not parts:
        return "True"
    if len(parts) == 1:
        return parts[0]
    return " and ".join(f"({p})" if _loose(p) else p for p in parts)


@lru_cache(maxsize=65536)
def _loose(text: str) -> bool:
    """Whether ``text`` binds more loosely than ``and`` (an ``or`` or a conditional)."""
    try:
        node = ast.parse(text, mode="eval").body
    except SyntaxError:
        return True
    return isinstance(node, ast.IfExp) or (isinstance(node, ast.BoolOp)
                                           and isinstance(node.op, ast.Or))


def _guard(negated: list[list[str]], conditions: list[str], functions: dict[str, str]) -> str:
    """The guard "none of ``negated`` holds, and ``conditions`` do". Where that breaks a limit
    of the expression language (comprehension loops, syntax nodes, length: conditions checked
    one by one in the search may not fit together), each condition with a comprehension is
    held in a function of the behavior (``functions``: condition -> name, added to) and called
    by name: the language checks each function's expression on its own."""
    def written(name: Any) -> str:
        return conjunction([f"not ({conjunction([name(c) for c in cs])})" for cs in negated]
                           + [name(c) for c in conditions])

    plain = written(lambda c: c)
    if _fits(plain):
        return plain

    def held(condition: str) -> str:
        if not _loops(ast.parse(condition, mode="eval")):
            return condition
        return f"{functions.setdefault(condition, f'condition{len(functions) + 1}')}()"
    return written(held)


def _loops(tree: ast.AST) -> int:
    """The comprehension loops of the expression ``tree``."""
    return sum(len(node.generators) for node in ast.walk(tree)
               if isinstance(node, (ast.ListComp, ast.GeneratorExp)))


def _fits(text: str) -> bool:
    """Whether the expression ``text`` keeps the expression language's limits of size."""
    tree = ast.parse(text, mode="eval")
    return (len(text) <= MAX_SOURCE_CHARS and sum(1 for _ in ast.walk(tree)) <= MAX_NODES
            and _loops(tree) <= MAX_GENERATORS)


class _Writer:
    def __init__(self, program: Program, space: SearchSpace):
        self.statements = program.statements
        self.space = space
        self.settable = {m.name for m in space.memory if m.settable}
        self.kept = {m.name for m in space.memory}  # (until :meth:`document` reads the program)
        first = self.statements[0]
        if not isinstance(first, (Act, Use)):
            raise ValueError("a program begins with an act or a library behavior")
        if isinstance(first, Act) and chosen_first(space, first):
            initial = {m.name: m.initial for m in space.memory}
            param = first.param  # chosen from the memory's initial values
            for name, _ in memory_updates(space, first.primitive):
                param = _substitute(param, name, initial[name])
            self.statements = (Act(first.primitive, param), *self.statements[1:])

    def _node(self, k: int, j: int = 0) -> str:
        return "s0" if k == 0 else f"s{k}_{j}"

    def _acts(self) -> list[tuple[str, Act | Use]]:
        out = [("s0", self.statements[0])]
        for k, statement in enumerate(self.statements[1:], 1):
            if isinstance(statement, (Set, Stop)):
                continue
            body = (statement,) if isinstance(statement, (Act, Use)) else statement.body
            out += [(self._node(k, j), act) for j, act in enumerate(body)]
        return out

    def _enter(self, k: int) -> list[tuple[list[str], list[tuple[str, str]], str]]:
        """Entries (conditions, assignments, node) when the program reaches statement k."""
        if k == len(self.statements):
            return [([], [], END)]
        statement = self.statements[k]
        if isinstance(statement, Set):  # what follows, its guards read before the assignment
            name, value = statement.name, statement.value  # (a later setting of the same
            return [([_substitute(c, name, value) for c in conditions],  # name from it: an
                     [(name, value), *[(n, _substitute(e, name, value) if n == name else e)
                                       for n, e in assignments]], node)  # edge sets a name once)
                    for conditions, assignments, node in self._enter(k + 1)]
        if isinstance(statement, Stop):  # the end first: what follows is taken only where
            return [([statement.guard], [], END)] + self._enter(k + 1)  # it is not
        if isinstance(statement, Use):
            return [([], [], self._node(k))]
        if isinstance(statement, Act):
            skipped = self._enter(k + 1) if _list_of(statement.param) is not None else []
            return [([], [], self._node(k))] + skipped
        if isinstance(statement, If):
            return [([statement.guard], [], self._node(k))] + self._enter(k + 1)
        return self._loop(k)

    def _loop(self, k: int) -> list[tuple[list[str], list[tuple[str, str]], str]]:
        loop = self.statements[k]
        conditions, into, out = [loop.guard], [], []
        if loop.limit is not None:
            counter = f"n{k}"
            conditions.insert(0, f"{counter} < {loop.limit}")
            into, out = [(counter, f"{counter} + 1")], [(counter, "0")]
        exits = [(c, out + s, node) for c, s, node in self._enter(k + 1)]
        return [(conditions, into, self._node(k))] + exits

    def _after(self, k: int, j: int) -> list[tuple[list[str], list[tuple[str, str]], str]]:
        """Entries after act j of statement k."""
        if k == 0:
            return self._enter(1)
        statement = self.statements[k]
        body = (statement,) if isinstance(statement, (Act, Use)) else statement.body
        if j + 1 < len(body):
            return [([], [], self._node(k, j + 1))]
        if isinstance(statement, Loop):
            return self._loop(k)
        return self._enter(k + 1)

    def _before(self, condition: str, assignments: list[tuple[str, str]]) -> str:
        """``condition`` read before ``assignments``: the values of the set variables among
        them in place of their names (a guard is evaluated before its edge assigns)."""
        for name, value in reversed(assignments):
            if name in self.settable:
                condition = _substitute(condition, name, value)
        return condition

    def _updates(self, act: Act | Use) -> list[tuple[str, str]]:
        """The assignments entering ``act``: the memory it updates. A parameter chosen before
        that memory (:func:`chosen_first`) is assigned to :data:`CHOSEN` first (the runtime
        evaluates a node's parameter after its edge's assignments)."""
        if isinstance(act, Use):
            return []
        updates = [(name, update) for name, update in memory_updates(self.space, act.primitive)
                   if name in self.kept]
        if chosen_first(self.space, act):
            return [(CHOSEN, act.param)] + [(name, _substitute(update, "PARAM", CHOSEN))
                                            for name, update in updates]
        return [(name, _substitute(update, "PARAM", act.param)) for name, update in updates]

    def document(self, name: str, description: str, env_id: str,
                 called: dict[str, tuple[tuple[str, ...], str]]) -> dict[str, Any]:
        read = " ".join(s.words() for s in self.statements)
        declared: dict[str, dict[str, Any]] = {}
        for function, (args, text) in reversed(called.items()):  # (later ones call earlier)
            if _mentions(read, function) or any(_mentions(f["expr"], function)
                                                for f in declared.values()):
                declared[function] = {"args": list(args), "expr": text}
        self.kept = self.space.memory_read(" ".join([read, *(f["expr"]
                                                             for f in declared.values())]))
        acts = dict(self._acts())
        edges = []
        functions: dict[str, str] = {}  # condition -> the name of the function that holds it
        for source, act in self._acts():
            k, j = (0, 0) if source == "s0" else map(int, source[1:].split("_"))
            negated: list[list[str]] = []
            for conditions, assignments, target in self._after(k, j):
                if target == END:
                    if not conditions:
                        break
                    negated.append(conditions)
                    continue
                to = acts[target]
                conditions = list(conditions)
                picked = None if isinstance(to, Use) else _list_of(to.param)
                if picked is not None:
                    conditions.append(self._before(f"len({picked}) > 0", assignments))
                edge: dict[str, Any] = {"from": source, "to": target}
                guard = _guard(negated, conditions, functions)
                if guard != "True":
                    edge["guard"] = guard
                sets = dict(assignments + self._updates(to))
                if isinstance(to, Act):
                    edge["param"] = CHOSEN if CHOSEN in sets else to.param
                if sets:
                    edge["set"] = sets
                edges.append(edge)
        first = self.statements[0]
        variables = {}
        for memory in sorted(self.space.memory, key=lambda m: not m.settable):  # set ones
            if memory.name not in self.kept:  # first: the others' initial values may read
                continue  # them (the first act's parameter)
            initial = memory.initial
            for primitive, update in memory.updates:
                if isinstance(first, Act) and primitive == first.primitive:
                    initial = _substitute(_substitute(update, "PARAM", first.param),
                                          memory.name, initial)
            variables[memory.name] = initial
        for k, statement in enumerate(self.statements):
            if isinstance(statement, Loop) and statement.limit is not None:
                variables[f"n{k}"] = "0"
        if any(isinstance(act, Act) and chosen_first(self.space, act) for _, act in self._acts()):
            variables[CHOSEN] = self.space.here[1]  # type: ignore[index]
        declared |= {function: {"args": [], "expr": condition}
                     for condition, function in functions.items()}
        named = {"functions": declared} if declared else {}
        return {"name": name, "description": description, "env": env_id,
                "variables": variables, **named,
                "nodes": [{"id": node, "behavior": act.behavior} if isinstance(act, Use) else
                          {"id": node, "primitive": act.primitive} for node, act in acts.items()],
                "edges": edges,
                "start": {"node": "s0"} if isinstance(first, Use) else {"node": "s0",
                                                                         "param": first.param},
                "terminals": list(acts)}
