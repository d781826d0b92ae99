"""What an environment tells the behavior synthesizer about itself: :class:`SearchSpace`.

The synthesizer (:mod:`vlb_gym.abstractor`) searches the behavior language itself -- graphs of
the env's primitives whose parameters and guards are expressions over its decision helpers --
and holds no table of its own about any env. An env that can be synthesized for returns a
:class:`SearchSpace` from :meth:`~vlb_gym.core.env.PrimitiveEnv.search_space`, saying:

* ``types``: the names of the value types its helpers' annotations use (``{"cell":
  tuple[int, int]}``), so that helper signatures become typed productions of a grammar;
  ``int``, ``bool``, ``str`` with a closed set of values (a ``Literal`` annotation or
  ``@helper(one_of=...)``) and lists of any of them are known without saying;
* ``parameters``: how each primitive is parametrised: by any expression of a type, or by fixed
  expressions only (a primitive whose one admissible parameter is known);
* ``constants``: expressions of a type worth trying (a pose that sees the containers);
* ``memory``: variables every searched behavior keeps, with their initial value and how a
  primitive updates them (where the agent started, where it has been); a *settable* one a
  behavior may also set, between two statements, to any expression of its kind (a mark: the
  goal in view when exploring stopped, remembered while the agent looks further);
* ``witnesses``: the least behaviors of the env, in words, against which a promise is tried
  before any search (a promise they keep asks for nothing);
* ``beliefs``: for an outcome helper a promise may use, what the agent believes of it, as a
  decision expression (``"is_goal": "label({0}) == 'goal'"``, ``{0}`` its first argument;
  ``TARGET`` stands for where the behavior ends: ``here``'s expression when the promise is
  read as "if I stopped now", a bound variable when read as "if I ended there"). The search
  reads a promise through them and tries the decision expressions it gets first;
* ``common``: the decision helpers and memory behaviors of the env use most (a prior: those
  helpers cost less; memory not named here is searched only where a reading of the promise
  reads it);
* ``here``: the kind and expression of where the agent is now (``("cell",
  "current_cell()")``), what ``TARGET`` is when read now;
* ``synonyms``: other words a request may use for a value of a helper's closed set of strings
  (``{"above": "up"}``), read as that value;
* ``screening``: episodes a candidate runs before it may be certified (fewer where an episode
  costs seconds of simulation); ``max_steps``: primitives a searched behavior may run in an
  episode (a candidate that runs longer is not pursued; certification uses the env's own
  bound); ``context_steps``: random primitives the rollouts that make the grammar's decision
  contexts run in all (a count, never a time, so that a search is the same on a loaded machine).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class Parameter:
    """How searched behaviors parametrise ``primitive``: by expressions of type ``kind``, or,
    where ``kind`` is None, by the ``fixed`` expressions only; never by an ``idle`` one (a
    parameter with which the primitive does nothing, such as moving to where the agent is).
    ``feasible``, where given, is a decision expression (``{0}`` the parameter) that holds
    when the primitive can succeed with that parameter (``is_free({0})``: a cell it can move
    onto): the guard of "do it while (or if) it can be done"."""

    primitive: str
    kind: str | None = None
    fixed: tuple[str, ...] = ()
    idle: tuple[str, ...] = ()
    feasible: str | None = None


@dataclass(frozen=True)
class Memory:
    """A variable every searched behavior keeps: its ``kind``, its ``initial`` expression, and
    for a primitive, how running it updates the variable (an expression in which ``PARAM``
    stands for the parameter just chosen). A ``settable`` one a behavior may also set to any
    expression of its kind between two statements."""

    name: str
    kind: str
    initial: str
    updates: tuple[tuple[str, str], ...] = ()
    description: str = ""
    settable: bool = False


@dataclass(frozen=True)
class Witness:
    """One of an env's least behaviors: ``words`` for the user, and its steps as (primitive,
    parameter expression) pairs; no steps is the behavior that stops at once. Where ``most`` > 1
    the steps done again, up to ``most`` times in all, are least behaviors too (staying put,
    over and over), ``again`` their words with ``{times}`` for the count."""

    words: str
    steps: tuple[tuple[str, str], ...] = ()
    most: int = 1
    again: str = ""

    def repeated(self) -> list[tuple[str, tuple[tuple[str, str], ...]]]:
        """(words, steps) of this behavior done once, then again, up to ``most`` times."""
        return [(self.words if times == 1 else self.again.format(times=times),
                 self.steps * times) for times in range(1, max(self.most, 1) + 1)]


def name_pattern(name: str) -> str:
    """A pattern of ``name`` as a whole name (not inside another, nor a string's words)."""
    return rf"(?<![\w']){re.escape(name)}(?![\w'])"


def mentions(text: str, name: str) -> bool:
    """Whether the expression ``text`` reads the name ``name``."""
    return re.search(name_pattern(name), text) is not None


@dataclass(frozen=True)
class SearchSpace:
    """An env's declaration for the behavior synthesizer (see the module's docstring)."""

    types: dict[str, Any]
    parameters: tuple[Parameter, ...]
    constants: tuple[tuple[str, str], ...] = ()
    memory: tuple[Memory, ...] = ()
    witnesses: tuple[Witness, ...] = (Witness("stop at once, doing nothing"),)
    beliefs: dict[str, str] = field(default_factory=dict)
    common: tuple[str, ...] = ()
    here: tuple[str, str] | None = None
    synonyms: dict[str, str] = field(default_factory=dict)
    screening: int = 30
    max_steps: int | None = None
    context_steps: int = 6 * 48

    def memory_read(self, text: str) -> set[str]:
        """The names of the memory ``text`` reads, with the memory their initial values and
        updates read (a behavior that reads them keeps those too)."""
        kept: set[str] = set()
        while True:
            more = {m.name for m in self.memory if mentions(text, m.name)} - kept
            if not more:
                return kept
            kept |= more
            text = " ".join(f"{m.initial} {' '.join(u for _, u in m.updates)}"
                            for m in self.memory if m.name in more)
