"""Helper functions that behaviors may call: the paper's E-functions, one set per environment.

Helpers read only the current observation (bound with :meth:`Helpers.bind` before every decision);
the environment, which knows ``d``, judges admissibility and certificates. Subclasses mark their
methods with :func:`helper`; the marked methods, with their signatures and docstrings, are what the
expression checker whitelists and what prompts describe.
"""

from __future__ import annotations

import abc
import inspect
import reprlib
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .promise import Episode

_MARK = "__vlb_helper__"
ONE_OF = "__vlb_one_of__"  # the closed set of values a helper's string result is one of
AT_MOST = "__vlb_at_most__"  # the most items a helper's list result ever has
_BRIEF = reprlib.Repr()
_BRIEF.maxlevel, _BRIEF.maxtuple, _BRIEF.maxlist = 3, 8, 8
_BRIEF.maxstring, _BRIEF.maxother, _BRIEF.maxlong = 60, 60, 40


def brief(value: Any, limit: int = 120) -> str:
    """A short repr of an untrusted value, for error messages: at most ``limit`` characters, in
    bounded work however large or deeply shared ``value`` is."""
    text = _BRIEF.repr(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def helper(fn: Callable[..., Any] | None = None, *, one_of: tuple[str, ...] | None = None,
           at_most: int | None = None) -> Any:
    """Mark a method of a :class:`Helpers` subclass as callable from behavior expressions.

    ``@helper(one_of=(...))`` also declares that the (string) result is always one of these
    values: the type check (:mod:`vlb_gym.core.typecheck`) then refuses comparing it with anything
    else, such as ``label(c) == 2`` or ``label(c) == 'wall'``. ``@helper(at_most=n)`` declares
    that a list result never has more than ``n`` items (e.g. a cell's neighbours): a fixed-size
    value, which the budget does not charge by its length.
    """
    def mark(fn: Callable[..., Any]) -> Callable[..., Any]:
        setattr(fn, _MARK, True)
        if one_of is not None:
            setattr(fn, ONE_OF, tuple(one_of))
        if at_most is not None:
            setattr(fn, AT_MOST, at_most)
        return fn
    return mark if fn is None else mark(fn)


def arity(fn: Callable[..., Any]) -> int | None:
    """The fixed number of positional arguments of ``fn``, or None if it takes a range."""
    params = inspect.signature(fn).parameters.values()
    if any(p.kind is p.VAR_POSITIONAL for p in params):
        return None
    required = sum(1 for p in params if p.default is p.empty)
    return required if required == len(params) else None


class Helpers(abc.ABC):
    """Base class: a named set of decision functions over one observation.

    Helpers run inside a behavior's evaluation budget (:mod:`vlb_gym.core.expressions`), so each
    must cost at most about the size of the observation and reject malformed arguments cheaply:
    check types before using a value (an argument may be a huge list, or a tuple nested 40 deep
    that shares its halves, whose hash or repr never ends), never iterate, hash or print it
    whole (:func:`brief` prints it in bounded time). A helper that returns a list says so in its
    return annotation (``-> list[...]``): the budget then charges each call the list's length,
    unless it declares that the list is never longer than a constant (``@helper(at_most=n)``).
    """

    @abc.abstractmethod
    def bind(self, observation: Any) -> None:
        """Make ``observation`` the one the helpers read."""

    def functions(self) -> dict[str, Callable[..., Any]]:
        """Bound helper methods by name."""
        return {name: getattr(self, name) for name in dir(type(self))
                if getattr(getattr(type(self), name), _MARK, False)}

    def describe(self) -> dict[str, str]:
        """``name(signature)`` -> first docstring paragraph, for documentation and prompts."""
        out = {}
        for name, fn in self.functions().items():
            doc = inspect.getdoc(fn) or ""
            signature = str(inspect.signature(fn)).replace("'", "")
            out[f"{name}{signature}"] = " ".join(doc.split("\n\n")[0].split())
        return out


class Judge(Helpers):
    """Base class: the outcome helpers a behavior's promise is written with.

    Where :class:`Helpers` read an observation, a judge reads a :class:`~vlb_gym.core.promise.
    Episode`: the environment's true state when a behavior finished and the steps that behavior
    ran. The environment, which knows ``d``, judges promises as it judges certificates.
    :meth:`summary` says in a line what the judge saw, for failure reasons and feedback.
    """

    @abc.abstractmethod
    def summary(self) -> str:
        """The bound episode's outcome in a line (where the agent ended, what it did)."""

    def rewind(self, episode: Episode) -> Episode | None:
        """``episode`` as it stood before its last step (it has at least one), for promises
        kept "as soon as" they hold; None where the env cannot say (the default)."""
        return None

    @property
    def rewinds(self) -> bool:
        """Whether this judge can :meth:`rewind` an episode."""
        return type(self).rewind is not Judge.rewind
