"""Typed expressions of an env's decision language, enumerated cheapest first, each meaning once.

:class:`Vocabulary` reads an env's decision helpers (their annotations give each a typed
signature), its :class:`~vlb_gym.core.search_space.SearchSpace` (named types, memory,
constants) and the constants of a request and its promise, and :func:`bank` enumerates the
expressions they make -- helper calls, ``L[0]``, ``L[-1]``, ``len(L)``, comparisons, ``in``,
``not``/``and``/``or``, filters ``[c for c in L if P]``, ``any``/``all``, and the element of a
list that makes a score least or greatest -- by increasing cost, bottom-up.

*Observational equivalence*: every expression is evaluated on a set of decision contexts
(:class:`Context`: observations the env produced, with memory values); of the expressions
that give the same values on every context, only the cheapest is kept, and one that fails on
every context is dropped. Expressions of a bound variable (``c`` in a filter, ``n`` inside
it) are compared on contexts paired with values of that variable.

Kinds are strings: ``int``, ``bool``, ``str:a|b|c`` (a closed set of strings), the env's
named types (``cell``) and ``list[KIND]``.
"""

from __future__ import annotations

import ast
import typing
import warnings
from functools import lru_cache
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Literal

from vlb_gym.core.expressions import BUILTINS, MAX_GENERATORS, MAX_SOURCE_CHARS
from vlb_gym.core.helpers import ONE_OF, Helpers
from vlb_gym.core.search_space import SearchSpace

BOUND = ("c", "n")  # names of bound variables, by depth
MAX_COST = 9
MAX_KEPT = 480  # expressions kept per kind and binding (all the grid's cells of cost <= 6)
_FAILED = object()


def kind_of(hint: Any, named: Mapping[str, Any], values: tuple[str, ...] | None = None
            ) -> str | None:
    """The kind of a type annotation (None: not one the search uses); ``X | None`` is X."""
    if values is not None:
        return "str:" + "|".join(values)
    if hint is bool:
        return "bool"
    if hint is int:
        return "int"
    origin = typing.get_origin(hint)
    if origin is Literal and all(isinstance(a, str) for a in typing.get_args(hint)):
        return "str:" + "|".join(typing.get_args(hint))
    if origin in (typing.Union, getattr(__import__("types"), "UnionType", None)):
        args = [a for a in typing.get_args(hint) if a is not type(None)]
        return kind_of(args[0], named) if len(args) == 1 else None
    if origin is list:
        (item,) = typing.get_args(hint) or (None,)
        inner = kind_of(item, named)
        return None if inner is None else f"list[{inner}]"
    for name, named_hint in named.items():
        if hint == named_hint:
            return name
    return None


def item_kind(kind: str) -> str | None:
    return kind[5:-1] if kind.startswith("list[") else None


def conforms(value: Any, kind: str, named: Mapping[str, Any]) -> bool:
    """Whether a constant ``value`` (from a promise or request) is of ``kind``."""
    if kind == "int":
        return type(value) is int
    if kind.startswith("str:"):
        return isinstance(value, str) and value in kind[4:].split("|")
    inner = item_kind(kind)
    if inner is not None:
        return isinstance(value, list) and bool(value) and all(
            conforms(v, inner, named) for v in value)
    hint = named.get(kind)
    if hint is None or typing.get_origin(hint) is not tuple:
        return False
    args = typing.get_args(hint)
    if len(args) == 2 and args[1] is Ellipsis:
        args = (args[0],) * (len(value) if isinstance(value, tuple) else 0)
    return isinstance(value, tuple) and len(value) == len(args) and all(
        isinstance(v, a) and not isinstance(v, bool) for v, a in zip(value, args))


@dataclass(frozen=True)
class Term:
    """An expression ``text`` of ``kind`` that costs ``cost``; ``bound`` is the depth of the
    bound variables it may use (0: none)."""

    text: str
    kind: str
    cost: int
    bound: int = 0
    reading: bool = False  # read from the promise (kept whatever it means on the contexts)


@dataclass
class Context:
    """A decision context: the helpers bound to an observation, and the memory's values."""

    namespace: dict[str, Any]


@dataclass
class Vocabulary:
    """What expressions are made of: typed helper signatures, memory variables, constants and
    the costs of using each (``cheap`` names and constants cost less)."""

    helpers: dict[str, tuple[tuple[str, ...], str]]  # name -> (parameter kinds, result kind)
    variables: dict[str, str]  # memory: name -> kind
    constants: list[tuple[str, str]]  # (kind, text)
    cheap: frozenset[str] = frozenset()  # helper names and constant texts worth trying first
    fragments: list[tuple[str, str, int]] = field(default_factory=list)  # (kind, text, depth)
    each: set[str] = field(default_factory=set)  # lists of places a promise's "all" speaks of
    visits: frozenset[str] = frozenset()  # memory lists a chosen parameter is added to

    @classmethod
    def of(cls, helpers: Helpers, space: SearchSpace) -> Vocabulary:
        """The vocabulary of ``helpers`` (an env's) and ``space``."""
        typed: dict[str, tuple[tuple[str, ...], str]] = {}
        constants: list[tuple[str, str]] = list(space.constants)
        for name, fn in helpers.functions().items():
            hints = typing.get_type_hints(fn)
            required, optional = _parameters(fn)
            result = kind_of(hints.get("return"), space.types, getattr(fn, ONE_OF, None))
            forms = {name: required}
            if optional:
                forms[f"{name}:{len(optional)}"] = required + optional
            for form, params in forms.items():
                kinds = tuple(kind_of(hints.get(p), space.types) for p in params)
                if result is None or None in kinds:
                    continue
                typed[form] = (kinds, result)
                for kind in (*kinds, result):
                    if kind.startswith("str:"):
                        constants += [(kind, repr(v)) for v in kind[4:].split("|")]
        constants += [("int", str(k)) for k in range(4)]
        chosen = {p.primitive for p in space.parameters if p.kind is not None}
        visits = frozenset(m.name for m in space.memory  # every parameter chosen, added
                           if any(primitive in chosen and update.replace(" ", "") ==
                                  f"{m.name}+[PARAM]" for primitive, update in m.updates))
        return cls(typed, {m.name: m.kind for m in space.memory},
                   list(dict.fromkeys(constants)), visits=visits)


def _parameters(fn: Callable[..., Any]) -> tuple[list[str], list[str]]:
    """The names of ``fn``'s required and optional parameters."""
    import inspect

    params = list(inspect.signature(fn).parameters.values())
    return ([p.name for p in params if p.default is p.empty],
            [p.name for p in params if p.default is not p.empty])


def call_name(form: str) -> str:
    """The helper a signature form (``name`` or ``name:optional``) calls."""
    return form.split(":", 1)[0]


def _key(value: Any) -> Any:
    """A hashable form of a value (lists as tuples)."""
    if isinstance(value, (list, tuple)):
        return tuple(_key(v) for v in value)
    return value


class Bank:
    """Terms by kind and binding depth, cheapest first, each meaning once on the contexts."""

    def __init__(self, vocabulary: Vocabulary, contexts: list[Context], max_cost: int = MAX_COST,
                 max_kept: int = MAX_KEPT):
        self.vocabulary = vocabulary
        self.contexts = contexts
        self.max_cost = max_cost
        self.max_kept = max_kept
        self.terms: dict[tuple[str, int], list[Term]] = {}
        self._by_cost: dict[tuple[str, int, int], list[Term]] = {}
        self._seen: dict[tuple[str, int], set[Any]] = {}
        self._texts: dict[tuple[str, int], set[str]] = {}
        self._samples: dict[str, list[list[Any]]] = {}  # kind -> per context, values to bind
        self._code: dict[str, Any] = {}

    # -- evaluation on the contexts ------------------------------------------------------------
    def _values(self, text: str, bound: int, kind: str) -> tuple[Any, ...] | None:
        code = self._code.get(text)
        if code is None:
            with warnings.catch_warnings():  # "'int' object is not subscriptable" for a
                warnings.simplefilter("ignore", SyntaxWarning)  # constant: it fails below
                code = self._code[text] = compile(text, "<term>", "eval")
        out: list[Any] = []
        for pairs in self._bindings(bound, kind, text):
            for namespace in pairs:
                try:
                    out.append(_key(eval(code, namespace)))  # noqa: S307 - our own terms
                except Exception:  # noqa: BLE001 - a term that fails here is a value too
                    out.append(_FAILED)
        if all(v is _FAILED for v in out):
            return None
        return tuple(out)

    def _bindings(self, bound: int, kind: str, text: str) -> Iterator[list[dict[str, Any]]]:
        for index, context in enumerate(self.contexts):
            if bound == 0:
                yield [context.namespace]
                continue
            pairs = [dict(context.namespace)]
            for depth in range(bound):
                values = self._binder_values(self._binder_kind[depth], index)
                pairs = [{**p, BOUND[depth]: v} for p in pairs for v in values] or pairs
            yield pairs

    def _binder_values(self, kind: str, index: int) -> list[Any]:
        per_context = self._samples.get(kind)
        return per_context[index] if per_context else []

    # -- keeping terms -------------------------------------------------------------------------
    def add(self, term: Term, protected: bool = False, anyway: bool = False) -> bool:
        """Keep ``term`` if the package's expression checker accepts it and it means
        something new on the contexts (``protected``, a reading of the promise, or ``anyway``:
        whatever it means) and there is room."""
        key = (term.kind, term.bound)
        kept = self.terms.setdefault(key, [])
        texts = self._texts.setdefault(key, set())
        if len(kept) >= self.max_kept or term.text in texts or not self._checks(term.text):
            return False  # (a protected text, kept at its least cost, is kept once)
        values = self._values(term.text, term.bound, term.kind)
        seen = self._seen.setdefault(key, set())
        if not (protected or anyway) and (values is None or values in seen):
            return False
        seen.add(values)
        texts.add(term.text)
        term = replace(term, reading=True) if protected else term
        kept.append(term)
        self._by_cost.setdefault((term.kind, term.bound, term.cost), []).append(term)
        return True

    def _checks(self, text: str) -> bool:
        """Whether ``text`` stays within the expression language's limits (comprehension
        loops and length; the rest of the package's checks run on every expression a
        candidate uses)."""
        return text.count(" for ") <= MAX_GENERATORS and len(text) <= MAX_SOURCE_CHARS

    def of(self, kind: str, bound: int = 0, cost: int | None = None) -> list[Term]:
        """The terms of ``kind`` usable at binding depth ``bound`` (those of fewer bound
        variables too), of exactly ``cost`` where given."""
        out: list[Term] = []
        for depth in range(bound + 1):
            if cost is None:
                out += self.terms.get((kind, depth), ())
            else:
                out += self._by_cost.get((kind, depth, cost), ())
        return out

    # -- enumeration ---------------------------------------------------------------------------
    def build(self, binders: tuple[str, ...] = ()) -> Bank:
        """Enumerate up to ``max_cost``; ``binders`` are the kinds of bound variables by depth
        (e.g. ``("cell", "cell")``): terms of depth d may use the first d of them."""
        self._binder_kind = binders
        v = self.vocabulary
        for depth, kind in enumerate(binders):
            if kind not in self._samples:
                self._samples[kind] = self._sample(kind)
        self._protected = {text for _, text, _ in v.fragments}
        self._anyway: set[str] = set()
        for cost in range(1, self.max_cost + 1):
            for depth in range(len(binders) + 1):
                for term in self._level(cost, depth):
                    self.add(term, protected=term.text in self._protected,
                             anyway=term.text in self._anyway)
        return self

    def _sample(self, kind: str) -> list[list[Any]]:
        """Per context, a few values of ``kind`` to bind (from the helpers' lists)."""
        return [samples(self.vocabulary, context, kind) for context in self.contexts]

    def _level(self, cost: int, depth: int) -> Iterator[Term]:
        """Every term of ``cost`` at binding ``depth`` (its children already kept)."""
        v = self.vocabulary
        if cost == 1:
            if depth > 0:
                yield Term(BOUND[depth - 1], self._binder_kind[depth - 1], 1, depth)
                yield from (Term(text, kind, 1, d) for kind, text, d in v.fragments
                            if d == depth)
                return
            for name, (params, result) in v.helpers.items():
                if not params and name in v.cheap:
                    yield Term(f"{call_name(name)}()", result, 1)
            for name, kind in v.variables.items():
                yield Term(name, kind, 1)
            yield from (Term(text, kind, 1) for kind, text, d in v.fragments if d == 0)
            for kind, text in v.constants:
                if text in v.cheap or kind == "int" or kind.startswith("str:"):
                    yield Term(text, kind, 1)
            return
        if cost == 2 and depth == 0:
            yield from self._seeking()
            yield from self._unvisited()
        if cost == 2 and depth == 0:
            for name, (params, result) in v.helpers.items():
                if not params and name not in v.cheap:
                    yield Term(f"{call_name(name)}()", result, 2)
            for kind, text in v.constants:
                if not (text in v.cheap or kind == "int" or kind.startswith("str:")):
                    yield Term(text, kind, 2)
        yield from self._calls(cost, depth)
        yield from self._list_forms(cost, depth)
        yield from self._logic(cost, depth)

    def _seeking(self) -> Iterator[Term]:
        """What seeking a place the promise would hold at needs, at a discount: the list of
        such places among each cheapest list (``[c for c in L if P]``, P a reading of the
        promise with ``c`` where the behavior ends), and whether it is empty."""
        if not self._binder_kind:
            return
        var, kind = BOUND[0], self._binder_kind[0]
        for xs in self.of(f"list[{kind}]", 0, 1):
            for fragment_kind, text, depth in self.vocabulary.fragments:
                if depth != 1 or fragment_kind != "bool" or xs.text == text:
                    continue
                found = f"[{var} for {var} in {_source(xs.text)} if {_wrap(text)}]"
                self._protected |= {found, f"len({found}) == 0", f"len({found}) > 0"}
                yield Term(found, f"list[{kind}]", 2)
                yield Term(f"len({found}) == 0", "bool", 2)
                yield Term(f"len({found}) > 0", "bool", 2)

    def _unvisited(self) -> Iterator[Term]:
        """What visiting each of some places once needs, at a discount: each cheapest list
        less what a memory list holds that a chosen parameter is added to (``[c for c in L
        if c not in M]``, M the cells moved to: "the goals not yet visited"; not the cells
        sensed from, where the parameter is fixed), kept whatever it means on the contexts
        (their short rollouts seldom tell it from ``L``)."""
        if not self._binder_kind:
            return
        var, kind = BOUND[0], self._binder_kind[0]
        for memory, memory_kind in self.vocabulary.variables.items():
            if memory not in self.vocabulary.visits or memory_kind != f"list[{kind}]":
                continue
            for xs in self.of(memory_kind, 0, 1):
                if memory in xs.text:
                    continue
                text = f"[{var} for {var} in {_source(xs.text)} if {var} not in {memory}]"
                self._protected.add(text)
                yield Term(text, memory_kind, 2)

    def _split(self, total: int, kinds: tuple[str, ...], depth: int) -> Iterator[tuple[Term, ...]]:
        """Tuples of terms of ``kinds`` whose costs sum to ``total``."""
        if not kinds:
            if total == 0:
                yield ()
            return
        first, rest = kinds[0], kinds[1:]
        for c in range(1, total - len(rest) + 1):
            heads = self.of(first, depth, c)
            if not heads:
                continue
            for tail in self._split(total - c, rest, depth):
                for head in heads:
                    yield (head, *tail)

    def _calls(self, cost: int, depth: int) -> Iterator[Term]:
        for name, (params, result) in self.vocabulary.helpers.items():
            if not params:
                continue
            own = 1 if call_name(name) in self.vocabulary.cheap else 2
            for args in self._split(cost - own, params, depth):
                if max(a.bound for a in args) == depth:
                    yield Term(f"{call_name(name)}({', '.join(a.text for a in args)})", result,
                               cost, depth)

    def _list_forms(self, cost: int, depth: int) -> Iterator[Term]:
        lists = [k for (k, _) in self.terms if item_kind(k)]
        for kind in dict.fromkeys(lists):
            item = item_kind(kind)
            for xs in self.of(kind, depth, cost - 1):
                if xs.bound != depth:
                    continue
                if xs.text in self._protected and _comprehension(xs.text):
                    self._anyway.add(f"{_wrap(xs.text)}[0]")  # what a loop over it moves to
                yield Term(f"{_wrap(xs.text)}[0]", item, cost, depth)
                yield Term(f"{_wrap(xs.text)}[-1]", item, cost, depth)
                yield Term(f"len({xs.text})", "int", cost, depth)
            if depth + 1 >= len(BOUND) or self._binder_kind[depth:depth + 1] != (item,):
                continue
            var = BOUND[depth]
            for c in range(1, cost - 1):
                for xs in self.of(kind, depth, c):
                    for pred in self.of("bool", depth + 1, cost - 1 - c):
                        if pred.bound != depth + 1 or max(xs.bound, pred.bound - 1) != depth:
                            continue
                        body = f"{var} for {var} in {_source(xs.text)} if {_wrap(pred.text)}"
                        yield Term(f"[{body}]", kind, cost, depth)
                    if cost - 1 - c < 1:
                        continue
                    for pred in self.of("bool", depth + 1, cost - 2 - c):
                        if pred.bound == depth + 1 and xs.bound == depth:
                            for quantifier in ("any", "all"):
                                yield Term(f"{quantifier}({_wrap(pred.text)} for {var} in "
                                           f"{_source(xs.text)})",
                                           "bool", cost, depth)
                    for score in self.of("int", depth + 1, cost - 2 - c):
                        if score.bound == depth + 1 and xs.bound == depth and depth == 0:
                            for pick in ("argmin", "argmax"):
                                yield Term(f"{_wrap(xs.text)}[{pick}([{score.text} for {var} "
                                           f"in {_source(xs.text)}])]", item, cost, depth)

    def _logic(self, cost: int, depth: int) -> Iterator[Term]:
        if len(self.terms.get(("bool", depth), ())) >= self.max_kept:
            return  # (no room: none would be kept)
        kinds = [k for (k, _) in self.terms if k != "bool"]
        for kind in dict.fromkeys(kinds):
            ordered = kind == "int"
            for a, b in self._pairs(kind, kind, cost - 1, depth):
                if a.text >= b.text and not ordered:
                    continue
                x, y = _wrap(a.text), _wrap(b.text)
                yield Term(f"{x} == {y}", "bool", cost, depth)
                yield Term(f"{x} != {y}", "bool", cost, depth)
                if ordered:
                    yield Term(f"{x} < {y}", "bool", cost, depth)
            item = item_kind(kind)
            if item is not None:
                for a, xs in self._pairs(item, kind, cost - 1, depth):
                    x, y = _wrap(a.text), _wrap(xs.text)
                    yield Term(f"{x} in {y}", "bool", cost, depth)
                    yield Term(f"{x} not in {y}", "bool", cost, depth)
        for b in self.of("bool", depth, cost - 1):
            if b.bound == depth and not b.text.startswith("not "):
                text = negation(b.text)
                if b.reading:
                    self._protected.add(text)
                yield Term(text, "bool", cost, depth)
        for a, b in self._pairs("bool", "bool", cost - 1, depth):
            if a.text < b.text:
                yield Term(f"{_wrap(a.text)} and {_wrap(b.text)}", "bool", cost, depth)
                yield Term(f"{_wrap(a.text)} or {_wrap(b.text)}", "bool", cost, depth)

    def _pairs(self, first: str, second: str, total: int, depth: int
               ) -> Iterator[tuple[Term, Term]]:
        for c in range(1, total):
            for a in self.of(first, depth, c):
                for b in self.of(second, depth, total - c):
                    if max(a.bound, b.bound) == depth:
                        yield a, b


def samples(vocabulary: Vocabulary, context: Context, kind: str, most: int = 3) -> list[Any]:
    """A few values of ``kind`` in ``context``: spread over what its helpers of no argument
    return (values, or lists of values)."""
    values: list[Any] = []
    for name, (params, result) in vocabulary.helpers.items():
        if params or result not in (kind, f"list[{kind}]"):
            continue
        try:
            value = context.namespace[call_name(name)]()
        except Exception:  # noqa: BLE001 - a helper that fails here offers nothing
            continue
        values += value if isinstance(value, list) else [value]
    unique = list(dict.fromkeys(v for v in values if v is not None))
    step = max(1, len(unique) // most)
    return unique[::step][:most]


def infer_kind(text: str, found: list[Context], named: Mapping[str, Any],
               binder: str | None = None, vocabulary: Vocabulary | None = None) -> str | None:
    """The kind of the expression ``text`` from its values on ``found`` (with ``c`` bound to
    values of ``binder``), or None where they say nothing usable (every value fails, or lists
    that are always empty)."""
    try:
        code = compile(text, "<reading>", "eval")
    except SyntaxError:
        return None
    kinds: set[str] = set()
    for context in found:
        bindings = [context.namespace]
        if binder is not None and vocabulary is not None:
            bindings = [{**context.namespace, BOUND[0]: v}
                        for v in samples(vocabulary, context, binder)]
        for namespace in bindings:
            try:
                value = eval(code, namespace)  # noqa: S307 - a reading of the promise
            except Exception:  # noqa: BLE001
                continue
            kind = _kind_of_value(value, named)
            if kind is None:
                return None
            if kind != "list[]":
                kinds.add(kind)
    return kinds.pop() if len(kinds) == 1 else None


def _kind_of_value(value: Any, named: Mapping[str, Any]) -> str | None:
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "int"
    if isinstance(value, list):
        if not value:
            return "list[]"
        inner = {_kind_of_value(v, named) for v in value}
        return f"list[{inner.pop()}]" if len(inner) == 1 and None not in inner else None
    for name in named:
        if conforms(value, name, named):
            return name
    return None


@lru_cache(maxsize=1 << 16)
def _shape(text: str) -> type[ast.expr] | None:
    """The kind of node ``text`` parses to (None: it does not parse), parsed once per text."""
    try:
        return type(ast.parse(text, mode="eval").body)
    except SyntaxError:
        return None


def _source(text: str) -> str:
    """``text`` parenthesized where it cannot be a comprehension's source as it is (a
    conditional expression, a lambda)."""
    return f"({text})" if _shape(text) in (None, ast.IfExp, ast.Lambda) else text


def _comprehension(text: str) -> bool:
    """Whether ``text`` is a list comprehension (whose first element changes as a loop over it
    moves on; a list display's ``[x][0]`` is only ``x``)."""
    return _shape(text) is ast.ListComp


def negation(text: str) -> str:
    """``not text``, ``text`` parenthesized where it is an operation."""
    return f"not {_wrap(text)}"


_OPERATIONS = (None, ast.BoolOp, ast.Compare, ast.IfExp, ast.UnaryOp, ast.BinOp, ast.Lambda)


def _wrap(text: str) -> str:
    """``text`` parenthesized where it is an operation, to embed it in another."""
    return f"({text})" if _shape(text) in _OPERATIONS else text


def builtins_namespace() -> dict[str, Any]:
    """Python's versions of the whitelisted builtins, for evaluating the search's own terms."""
    def argmax(values: Iterable[Any]) -> int:
        values = list(values)
        return values.index(max(values))

    def argmin(values: Iterable[Any]) -> int:
        values = list(values)
        return values.index(min(values))

    import builtins as py

    out = {name: getattr(py, name) for name in BUILTINS if hasattr(py, name)}
    out.update(argmax=argmax, argmin=argmin, __builtins__={})
    return out


def contexts(env: Any, space: SearchSpace, seeds: list[int], steps: int = 48,
             keep: tuple[int, ...] = (0, 1, 3, 8, 20, 48)) -> list[Context]:
    """Decision contexts from short random rollouts of ``env`` (a PrimitiveEnv, unwrapped) on
    ``seeds``: each step runs a random primitive with a random admissible parameter (the fixed
    one where the space fixes it); the observation after each step in ``keep`` is a context,
    with the memory's values along the rollout (a settable one's: its initial value half-way
    through the rollout so far, a moment the behavior chose to remember). The rollouts run
    ``space.context_steps``
    primitives in all (at most ``steps`` each); once those are spent, a rollout gives its reset
    observation only."""
    import numpy as np

    out: list[Context] = []
    left = space.context_steps
    for seed in seeds:
        rng = np.random.default_rng(seed)
        observation, _ = env.reset(seed=seed)
        memory = _memory_start(env, space, observation)
        marks = [{m.name: memory[m.name] for m in space.memory if m.settable}]
        for step in range(steps + 1):
            if step in keep:
                out.append(Context({**builtins_namespace(), **_bound(env, observation),
                                    **memory, **marks[step // 2]}))
            if step == steps or left <= 0:
                break
            choice = _random_action(env, space, observation, rng)
            if choice is None:
                break
            primitive, param = choice
            left -= 1
            observation, _, _, _, info = env.step(env.encode_action(primitive, param))
            if not info["certificate"]:
                break
            _memory_update(env, space, memory, primitive, param, observation)
            if marks[0]:
                start = _memory_start(env, space, observation)
                marks.append({name: start[name] for name in marks[0]})
    return out


def _bound(env: Any, observation: Any) -> dict[str, Any]:
    """The helpers bound to ``observation``; those of no argument computed once (a context
    does not change)."""
    helpers = env.make_helpers()
    helpers.bind(observation)
    out = {}
    for name, fn in helpers.functions().items():
        try:
            value = fn()
        except TypeError:  # takes arguments
            out[name] = fn
            continue
        except Exception:  # noqa: BLE001 - fails here: it fails when called
            out[name] = fn
            continue
        out[name] = _constant(fn, value)
    return out


def _constant(fn: Callable[..., Any], value: Any) -> Callable[..., Any]:
    """``fn`` with its no-argument call answered by ``value``."""
    def recalled(*args: Any) -> Any:
        return fn(*args) if args else value
    return recalled


def _evaluate(text: str, namespace: dict[str, Any]) -> Any:
    return eval(compile(text, "<memory>", "eval"), namespace)  # noqa: S307 - the env's own


def _memory_start(env: Any, space: SearchSpace, observation: Any) -> dict[str, Any]:
    namespace = {**builtins_namespace(), **_bound(env, observation)}
    return {m.name: _evaluate(m.initial, namespace) for m in space.memory}


def _memory_update(env: Any, space: SearchSpace, memory: dict[str, Any], primitive: str,
                   param: Any, observation: Any) -> None:
    namespace = {**builtins_namespace(), **_bound(env, observation), **memory, "PARAM": param}
    for m in space.memory:
        for name, update in m.updates:
            if name == primitive:
                memory[m.name] = _evaluate(update, {**namespace, **memory})


def _random_action(env: Any, space: SearchSpace, observation: Any, rng: Any
                   ) -> tuple[str, Any] | None:
    """A random primitive and an admissible parameter for it (None if none is found)."""
    import numpy as np
    from gymnasium import spaces as gym_spaces

    parameters = list(space.parameters)
    for _ in range(8):
        parameter = parameters[int(rng.integers(len(parameters)))]
        primitive = env.primitives[parameter.primitive]
        if parameter.kind is None:
            namespace = {**builtins_namespace(), **_bound(env, observation)}
            return parameter.primitive, _evaluate(parameter.fixed[0], namespace)
        if isinstance(primitive.param_space, gym_spaces.MultiDiscrete):
            mask = primitive.admissible_mask(env.state)
            choices = np.argwhere(mask)
            if len(choices):
                pick = choices[int(rng.integers(len(choices)))]
                return parameter.primitive, tuple(int(v) for v in pick)
        for kind, text in space.constants:
            if kind == parameter.kind:
                return parameter.primitive, _evaluate(text, builtins_namespace())
    return None
