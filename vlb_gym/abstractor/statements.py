"""The statements of searched programs, by cost, from a bank of typed terms.

An act costs 1 plus its parameter's term (a fixed parameter costs nothing more); a conditional
3 plus its guard and its acts; a loop 2 plus its guard and its acts, plus 1 for a limit (a
loop without a guard must pick its first act from a list, which ends it, or have a limit). A
guard costs its term, plus :data:`GUARD` unless it is a reading of the promise: conditions
the promise suggests come first. A loop guarded by its first act itself -- "while it can be
done" (the parameter's ``feasible`` expression: the cell to move onto is free) -- costs 1 plus
its acts, as a loop over a list does, and a conditional "if it can be done" or "if it does
something" (its parameter is not an idle one: go to the start unless there) 2 plus its acts:
moving in a direction until blocked is as plain a request as there is. Such a loop ended
early, "until" a condition the promise reads at cost 1 holds (a goal has come into sight),
costs 1 more. So does a loop over a list (1 plus its acts) ended early by any condition of
cost 1 ("explore until a goal is in sight"), and 1 more again after at most ``k`` rounds, ``k``
a number the request or promise gives ("but give up after five moves"). Ending the behavior
where a guard holds ("if the first look shows an obstacle, stop there") costs :data:`STOP`
plus the guard. Bodies hold one to :data:`MAX_BODY` acts. A library behavior, run whole, is a
statement of cost :data:`USE`; setting a settable memory variable to a term of its kind
("remember the goal in view now"), :data:`SET` plus the term (the search sets one once, right
after a loop). :meth:`Statements.at` lists those of one cost, computed once and capped at
:data:`MAX_PER_COST`.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Any

from vlb_gym.core.search_space import Parameter, SearchSpace

from .programs import (Act, If, Loop, Set, Statement, Stop, Use, _list_of, _mentions,
                       after_a_move, conjunction)
from .terms import Bank, Term, negation

MAX_BODY = 3
MAX_PER_COST = 40_000
GUARD = 2  # what a guard that is not a reading of the promise costs more
USE = 2  # what running a library behavior costs
SET = 1  # what setting a memory variable costs, besides its value
STOP = 2  # what ending the behavior where a guard holds costs, besides the guard


class Statements:
    """The statements of one search (see the module's docstring)."""

    def __init__(self, bank: Bank, space: SearchSpace, limits: list[int],
                 behaviors: list[str] | None = None):
        self.bank = bank
        self.behaviors = sorted(behaviors or [])
        self.space = space
        self.limits = sorted({k for k in limits if 1 <= k <= 20})
        self._acts: dict[int, list[Act]] = {}
        self._bodies: dict[tuple[int, int], list[tuple[Act, ...]]] = {}
        self._statements: dict[int, list[Statement]] = {}
        self._fixed = {Act(p.primitive, text) for p in space.parameters for text in p.fixed}
        self._parameter = {p.primitive: p for p in space.parameters}

    def acts(self, cost: int) -> list[Act]:
        """Acts of exactly ``cost``."""
        if cost not in self._acts:
            out: list[Act] = []
            for parameter in self.space.parameters:
                if parameter.kind is None:
                    if cost == 1:
                        out += [Act(parameter.primitive, text) for text in parameter.fixed]
                    continue
                out += [Act(parameter.primitive, t.text)
                        for t in self._parameters(parameter, cost - 1)]
            self._acts[cost] = out
        return self._acts[cost]

    def _parameters(self, parameter: Parameter, cost: int | None = None) -> list[Term]:
        """The terms ``parameter``'s primitive may take (of ``cost``, or any): its kind's,
        but none with which the primitive would do nothing."""
        return [t for t in self.bank.of(parameter.kind, 0, cost) if t.text not in parameter.idle]

    def bodies(self, cost: int, length: int) -> list[tuple[Act, ...]]:
        """Sequences of ``length`` acts of total ``cost``."""
        key = (cost, length)
        if key not in self._bodies:
            if length == 1:
                out = [(a,) for a in self.acts(cost)]
            else:
                out = []
                for c in range(1, cost - length + 2):
                    for head in self.acts(c):
                        out += [(head, *tail) for tail in self.bodies(cost - c, length - 1)
                                if not (head == tail[0] and head in self._fixed)]
                        if len(out) > MAX_PER_COST:
                            break
            self._bodies[key] = out[:MAX_PER_COST]
        return self._bodies[key]

    def at(self, cost: int) -> list[Statement]:
        """Statements of exactly ``cost`` (at most MAX_PER_COST of them)."""
        if cost not in self._statements:
            out: list[Statement] = []
            for statement in self._generate(cost):
                out.append(statement)
                if len(out) >= MAX_PER_COST:
                    break
            self._statements[cost] = out
        return self._statements[cost]

    def firsts(self, cost: int) -> list[Statement]:
        """What a program may begin with, of exactly ``cost``: an act, or a library
        behavior (cost :data:`USE`)."""
        return [*self.acts(cost), *(Use(b) for b in self.behaviors if cost == USE)]

    def _generate(self, cost: int) -> Iterator[Statement]:
        """Loops and conditionals guarded by their first act (the plainest of a cost), acts,
        library behaviors, settings, ends where a guard holds, then the other loops and conditionals with bodies of each length in
        turn (one of each length at a time: where :data:`MAX_PER_COST` cuts, no
        length of body is cut whole)."""
        yield from self._idioms(cost)
        yield from self.acts(cost)
        if cost == USE:
            yield from (Use(b) for b in self.behaviors)
        yield from self.sets(cost)
        yield from (Stop(guard) for guard in self.guards(cost - STOP))
        families = [self._compound(cost, length) for length in range(1, MAX_BODY + 1)]
        while families:
            for family in list(families):
                statement = next(family, None)
                if statement is None:
                    families.remove(family)
                else:
                    yield statement

    def sets(self, cost: int) -> list[Set]:
        """Settings of ``cost`` of the settable memory variables: to a term of their kind that
        is not a memory variable (whose value it would copy) nor reads the variable set."""
        memory = {m.name for m in self.space.memory}
        return [Set(m.name, t.text) for m in self.space.memory if m.settable
                for t in self.bank.of(m.kind, 0, cost - SET)
                if t.text not in memory and not _mentions(t.text, m.name)]

    def _idioms(self, cost: int) -> list[Statement]:
        """Loops and conditionals of ``cost`` guarded by their first act itself: while it can
        be done (and, costing 1 more, until a condition read from the promise holds), while
        the list it picks from lasts until a condition of cost 1 holds (and, 1 more, at most
        ``k`` times), with bodies of each length; then if it can be done, if it does something;
        those whose bodies choose fewer parameters first (a move and a sense before two
        moves)."""
        out: list[Statement] = []
        cheapest = self.bank.of("bool", 0, 1)
        stops = [negation(t.text) for t in cheapest if t.reading]
        ends = [negation(t.text) for t in cheapest]
        for length in range(1, MAX_BODY + 1):
            bodies = self.bodies(cost - 1, length) if cost - 1 >= length else []
            out += [Loop(g, b) for b in bodies if (g := self.feasible(b[0]))]
            bodies = self.bodies(cost - 2, length) if cost - 2 >= length else []
            out += [Loop(conjunction([g, stop]), b) for b in bodies
                    if (g := self.feasible(b[0])) for stop in stops]
            out += [Loop(end, b) for b in bodies if _list_of(b[0].param) for end in ends]
            bodies = self.bodies(cost - 3, length) if cost - 3 >= length and length <= 2 else []
            out += [Loop(end, b, k) for b in bodies if _list_of(b[0].param) for end in ends
                    for k in self.limits]
        for length in range(1, 3):
            bodies = self.bodies(cost - 2, length) if cost - 2 >= length else []
            out += [If(g, b) for b in bodies for g in self.own_guards(b[0])]
        return sorted(out, key=lambda s: sum(a not in self._fixed for a in s.body))

    def _compound(self, cost: int, length: int) -> Iterator[Statement]:
        """Loops and conditionals of ``cost`` whose bodies hold ``length`` acts (but those of
        :meth:`_idioms`)."""
        for body_cost in range(length, cost):
            bodies = self.bodies(body_cost, length)
            if not bodies:
                continue
            rest = cost - body_cost
            if rest == 1:  # a loop over a list, ended by it
                yield from (Loop("True", b) for b in bodies if _list_of(b[0].param))
            if rest == 3 and length <= 2:
                yield from (Loop("True", b, k) for k in self.limits for b in bodies)
            for guard in self.guards(rest - 2):
                yield from (Loop(guard, b) for b in bodies)
            if length <= 2:
                for guard in self.guards(rest - 3):
                    yield from (If(guard, b) for b in bodies)

    def completions(self) -> list[Statement]:
        """Statements to try at once after every prefix: acts whose parameter is read from the
        promise (a place the promise would hold at, the first of the places it would, a memory
        variable the promise's readings name: where the behavior began, the first of the places,
        where the promise counts them, else a memory it may end at: "onto a goal in view, else
        home"), each also as "if it does something" (go to the start unless there; but one that
        filters by where the promise would hold after the move: the move there counts); one
        that picks from the places an ``all`` of the promise speaks of first as a loop over them
        ("each goal not yet moved onto": on episodes where one is left it acts as the single
        act, and of programs that act alike the first built is kept)."""
        out: list[Statement] = []
        read = " ".join(text for _, text, _ in self.bank.vocabulary.fragments)
        named = {m.name for m in self.space.memory if re.search(rf"\b{m.name}\b", read)}
        for parameter in self.space.parameters:
            if parameter.kind is None:
                continue
            fallbacks = [m.name for m in self.space.memory if m.kind == parameter.kind
                         and self._ends_at(m.name)]
            for term in self._parameters(parameter):
                first = term.text.endswith("[0]") and _reads(self.bank, term)
                if term.reading or term.text in named or first:
                    texts = [term.text]
                    if first and self._counted(listed := _list_of(term.text)):
                        texts += [f"({listed} + [{m}])[0]" for m in fallbacks]
                    for text in texts:
                        act = Act(parameter.primitive, text)
                        each = [Loop("True", (act,))] if _list_of(text) in \
                            self.bank.vocabulary.each else []
                        unless = [If(g, (act,)) for g in [self.acting(act)]
                                  if g and not after_a_move(text)]  # (a move there counts)
                        out += [*each, act, *unless]
        return out

    def _counted(self, listed: str) -> bool:
        """Whether a reading of the promise counts the list ``listed`` (``len(L) > 0``: the
        promise tells apart the cases where it is empty and where it is not)."""
        return any(text.startswith(f"len({listed}) ")
                   for _, text, _ in self.bank.vocabulary.fragments)

    def _ends_at(self, name: str) -> bool:
        """Whether a reading of the promise is "here is the memory ``name``" (it may end there:
        where the behavior began, in one of its cases)."""
        here = self.space.here[1] if self.space.here else None
        return here is not None and any(
            text in (f"{here} == {name}", f"{name} == {here}")
            for _, text, _ in self.bank.vocabulary.fragments)

    def feasible(self, act: Act) -> str | None:
        """The guard "``act`` can be done" (its parameter's ``feasible`` expression), if its
        primitive declares one and ``act``'s parameter is not fixed."""
        parameter = self._parameter.get(act.primitive)
        if parameter is None or parameter.feasible is None or act in self._fixed:
            return None
        return parameter.feasible.format(act.param)

    def acting(self, act: Act) -> str | None:
        """The guard "``act`` does something": its parameter is none of the idle ones (go to
        the start unless there), if its primitive has idle ones."""
        parameter = self._parameter.get(act.primitive)
        if parameter is None or not parameter.idle or act in self._fixed:
            return None
        return " and ".join(f"{act.param} != {text}" for text in parameter.idle)

    def own_guards(self, act: Act) -> list[str]:
        """Guards read from ``act`` itself: it can be done; it does something."""
        return [g for g in (self.feasible(act), self.acting(act)) if g]

    def guards(self, cost: int) -> list[str]:
        """Guards of exactly ``cost`` (see the module's docstring)."""
        if cost < 1:
            return []
        readings = [t.text for t in self.bank.of("bool", 0, cost) if t.reading]
        return readings + [t.text for t in self.bank.of("bool", 0, cost - GUARD)
                           if not t.reading]


def _reads(bank: Bank, term: Any) -> bool:
    """Whether ``term`` picks the first of a list read from the promise."""
    inner = term.text[:-3]
    return any(t.reading and t.text.strip("()") == inner.strip("()")
               for t in bank.of(f"list[{term.kind}]", 0))
