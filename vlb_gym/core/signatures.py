"""The types the type check infers, and the signatures of the callables an expression may use:
helpers declare theirs with ordinary annotations (``def label(self, cell: Cell) -> str``, and
``@helper(one_of=(...))`` for a string from a closed set), builtins have theirs here."""

from __future__ import annotations

import inspect
import typing
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from .helpers import ONE_OF


@dataclass(frozen=True)
class Type:
    """A known type: ``kind`` is int, float, bool, none, str, tuple or list. ``values`` is the
    closed set of a str (None: any string); ``item`` the element type of a list (None: unknown)."""

    kind: str
    values: tuple[str, ...] | None = None
    item: Type | None = None

    def describe(self) -> str:
        return {"none": "None"}.get(self.kind, self.kind)


INT, FLOAT, BOOL, NONE, STR, TUPLE = (Type(k) for k in ("int", "float", "bool", "none", "str",
                                                        "tuple"))
Unknown = None  # the type of what cannot be inferred
NUMBERS = ("int", "float", "bool")  # the kinds that are numbers


@dataclass(frozen=True)
class Signature:
    """What a callable takes and gives: ``min_args``..``max_args`` positional arguments (max None:
    any number), the known parameter types, and the return type."""

    min_args: int
    max_args: int | None
    params: tuple[Type | None, ...] = ()
    returns: Type | None = Unknown


def _from_hint(hint: Any, values: tuple[str, ...] | None = None) -> Type | None:
    if hint is int:
        return INT
    if hint is float:
        return FLOAT
    if hint is bool:
        return BOOL
    if hint is str:
        return Type("str", values)
    if hint is type(None):
        return NONE
    origin = typing.get_origin(hint)
    if hint is tuple or origin is tuple:
        return TUPLE
    if hint is list or origin is list:
        args = typing.get_args(hint)
        return Type("list", item=_from_hint(args[0]) if len(args) == 1 else Unknown)
    return Unknown


def signature(fn: Callable[..., Any]) -> Signature:
    """The signature of a helper, from its annotations (unknown where they say nothing usable)."""
    try:
        params = list(inspect.signature(fn).parameters.values())
    except (TypeError, ValueError):
        return Signature(0, None)
    try:
        hints = typing.get_type_hints(fn)
    except Exception:  # noqa: BLE001 - an annotation we cannot resolve is simply unknown
        hints = {}
    if any(p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD) for p in params):
        return Signature(0, None, returns=_from_hint(hints.get("return"), _one_of(fn)))
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    required = sum(1 for p in positional if p.default is p.empty)
    return Signature(required, len(positional),
                     tuple(_from_hint(hints.get(p.name)) for p in positional),
                     _from_hint(hints.get("return"), _one_of(fn)))


def _one_of(fn: Callable[..., Any]) -> tuple[str, ...] | None:
    values = getattr(fn, ONE_OF, None)
    return tuple(values) if values is not None else None


def helper_signatures(functions: Mapping[str, Callable[..., Any]]) -> dict[str, Signature]:
    return {name: signature(fn) for name, fn in functions.items()}


#: The whitelisted builtins: how many arguments each takes; return types where fixed.
BUILTIN_SIGNATURES: dict[str, Signature] = {
    "len": Signature(1, 1, returns=INT), "abs": Signature(1, 1), "any": Signature(1, 1, returns=BOOL),
    "all": Signature(1, 1, returns=BOOL), "bool": Signature(0, 1, returns=BOOL),
    "int": Signature(0, 2, returns=INT), "float": Signature(0, 1, returns=FLOAT),
    "round": Signature(1, 2), "sorted": Signature(1, 1), "sum": Signature(1, 2),
    "argmax": Signature(1, 1, returns=INT), "argmin": Signature(1, 1, returns=INT),
    "min": Signature(1, None), "max": Signature(1, None),
}
