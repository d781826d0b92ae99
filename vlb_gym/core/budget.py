"""The budget of one expression evaluation: work and size limits, charged as it runs.

An evaluation is charged *work*, not items (see :mod:`.expressions`); every list, tuple or string
an operation builds holds at most :data:`MAX_SIZE` elements, every integer it computes stays below
:data:`MAX_INT_RESULT` in magnitude, ``round`` takes at most :data:`MAX_ROUND_DIGITS` digits, and
behavior functions are called at most :data:`MAX_CALLS` times. The evaluations of one step share
:data:`MAX_STEP_WORK`, those of one episode :data:`MAX_EPISODE_WORK` (settled as each evaluation
starts: at most one evaluation's work beyond them). Exceeding any limit raises
:class:`EvaluationLimitError`.
"""

from __future__ import annotations

import inspect
import numbers
from functools import lru_cache
from itertools import chain
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from .errors import UserError
from .helpers import AT_MOST

MAX_SIZE = 10_000  # elements in a list/tuple/string an operation builds (nested ones counted)
MAX_WORK = 1_000_000  # work units per top-level evaluation
MAX_CALLS = 10_000  # calls of behavior functions per top-level evaluation
MAX_INT_RESULT = 2**63  # magnitude bound of computed integers
MAX_ROUND_DIGITS = 20
MAX_STEP_WORK = 5 * MAX_WORK  # work units of every evaluation choosing one action together
MAX_EPISODE_WORK = 100 * MAX_WORK  # ... of one episode (and of a dry run's episodes together)


@lru_cache(maxsize=4096)
def _charged_by_length(function: Callable[..., Any]) -> bool:
    """Whether ``function``'s calls are charged their result's length: it says it returns a
    list (its return annotation) and declares no constant most length (:func:`~.helpers.helper`'s
    ``at_most``), read once."""
    return (str(inspect.signature(function).return_annotation).startswith(("list", "List"))
            and getattr(function, AT_MOST, None) is None)


@lru_cache(maxsize=4096)
def _parameters(function: Callable[..., Any]) -> int:
    """How many parameters ``function`` has (a method's ``self`` included), read once."""
    return len(inspect.signature(function).parameters)


class EvaluationLimitError(UserError, ValueError):
    """An evaluation exceeded a limit of its :class:`Budget`; the message names the limit."""


_SEQUENCES = (list, tuple, str)
_NESTED = frozenset({list, tuple, str, np.ndarray})


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
        if len(items) > 8:  # a long list: its items' types at C speed (cells: tuples of ints)
            kinds = set(map(type, items))
            if kinds.isdisjoint(_NESTED):
                continue
            if len(kinds) == 1 and tuple in kinds:  # tuples alike: walk them as one list
                if total + sum(map(len, items)) > limit:
                    return limit + 1
                stack.append(list(chain.from_iterable(items)))
                continue
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

    __slots__ = ("work", "calls", "memo", "step", "episode")

    def __init__(self) -> None:
        self.step = self.episode = 0  # work of the step and of the episode so far
        self.work = MAX_WORK
        self.memo: dict[Callable[[], Any], Any] = {}
        self.reset()

    def new_episode(self) -> None:
        """An episode begins: its account (and its first step's) starts from zero."""
        self.work, self.step, self.episode = MAX_WORK, 0, 0

    @property
    def episode_spent(self) -> int:
        """The episode's work so far, the evaluation running (or last run) included."""
        return self.episode + MAX_WORK - max(self.work, -1)

    def new_step(self) -> None:
        """A step (one action chosen) begins: its account starts from zero."""
        self._settle()
        self.step = 0

    def reset(self) -> None:
        """A top-level evaluation begins: the last one's work goes on the step's and the
        episode's accounts, which raise once they are spent (at most one evaluation's work
        beyond them, as each evaluation is bounded by its own budget)."""
        if self.work != MAX_WORK:  # the last evaluation did work (else nothing to settle)
            self._settle()
        self.calls = MAX_CALLS
        if self.memo:
            self.memo = {}

    def _settle(self) -> None:
        work = self.work
        used = MAX_WORK - (work if work > -1 else -1)
        self.work = MAX_WORK
        self.step += used
        self.episode += used
        if self.step > MAX_STEP_WORK:
            raise EvaluationLimitError(f"the evaluations of one step exceeded their budget of "
                                       f"{MAX_STEP_WORK} work units")
        if self.episode > MAX_EPISODE_WORK:
            raise EvaluationLimitError(f"the evaluations of one episode exceeded their budget "
                                       f"of {MAX_EPISODE_WORK} work units")

    def once(self, fn: Callable[[], Any]) -> Callable[[], Any]:
        """A function of no arguments, computed at most once per top-level evaluation and then
        recalled: expressions have no side effects, so nothing in one evaluation can
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
        length = len(value)
        if length > MAX_SIZE:
            raise EvaluationLimitError(f"a sequence of more than {MAX_SIZE} elements was built")
        self.work -= length  # charge(), inlined here and below: the hot accounting
        if self.work < 0:
            self.charge(0)
        return value

    def integer(self, value: Any) -> Any:
        if type(value) is int and not -MAX_INT_RESULT < value < MAX_INT_RESULT:
            raise EvaluationLimitError("an integer of magnitude >= 2**63 was computed")
        return value

    def call(self, weight: int) -> None:
        """Entry of a behavior function whose body has ``weight`` syntax nodes."""
        self.calls -= 1
        self.work -= weight
        if self.calls < 0:
            raise EvaluationLimitError(f"evaluation made more than {MAX_CALLS} function calls")
        if self.work < 0:
            self.charge(0)

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
        self.work -= len(items) * weight
        if self.work < 0:
            self.charge(0)
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
        result's length (the others return fixed-size values, as do those declaring
        ``at_most``), and those of no arguments
        computed once per top-level evaluation (:meth:`once`: the observation or episode
        they read stays the same while an expression is evaluated)."""
        out = {}
        for name, fn in helpers.items():
            function = getattr(fn, "__func__", fn)
            out[name] = self._charged(fn) if _charged_by_length(function) else fn
            if _parameters(function) == (1 if function is not fn else 0):
                out[name] = self.once(out[name])
        return out

    def _charged(self, fn: Callable[..., Any]) -> Callable[..., Any]:
        def charged(*args: Any) -> Any:
            result = fn(*args)
            self.work -= len(result)  # charge(), inlined: helpers are called in hot loops
            if self.work < 0:
                self.charge(0)
            return result
        return charged
