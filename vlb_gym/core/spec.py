"""The behavior file format: a JSON document validated by pydantic (schema in ``vlb_gym/schema``).

A behavior ``B = (N, E, S, T)`` (the paper's Definition 2) is written as::

    {
      "name": "explore_until_goal",
      "variables": {"home": "current_cell()"},          # behavior-local, initial-value expressions
      "functions": {"E4": {"args": [], "expr": "..."}},  # new decision functions, as expressions
      "nodes": [{"id": "sense", "primitive": "sense"},   # N: primitives or whole sub-behaviors
                {"id": "explore", "behavior": "explore_until_goal"}],
      "edges": [{"from": "sense", "to": "go", "guard": "not goal_found()", "param": "E4()",
                 "set": {"trips": "trips + 1"}}],        # E: first edge whose guard holds is taken
      "start": {"node": "sense", "param": "current_cell()"},   # S
      "terminals": ["sense"],                            # T
      "promise": {"expr": "goal_found()",                # what holds when it finishes
                  "description": "a goal has been found"}
    }

Every string that is evaluated is an expression of :mod:`vlb_gym.core.expressions`. The
``promise`` is judged by the environment, over the episode (see :mod:`vlb_gym.core.promise`): it
names only the environment's outcome helpers, never the behavior's own variables.
"""

from __future__ import annotations

import difflib
import json
import typing
import unicodedata
from pathlib import Path
from typing import Annotated, Any

from pydantic import (AfterValidator, BaseModel, ConfigDict, Field, StringConstraints,
                      ValidationError, model_validator)

from .errors import UserError
from .files import InputFileError, load_json
from .formats import FormatError, check_format
from .names import IDENTIFIER_PATTERN, MAX_NAME_LENGTH

Identifier = Annotated[str, StringConstraints(pattern=IDENTIFIER_PATTERN,
                                              max_length=MAX_NAME_LENGTH)]
ExpressionText = Annotated[str, StringConstraints(min_length=1, max_length=2000)]

_UNPRINTABLE = ("Cc", "Cf", "Zl", "Zp")  # controls, format (bidi overrides), line breaks


def _one_line(text: str) -> str:
    """``text`` if it is one line of printable text: what a terminal shows as written."""
    for at, char in enumerate(text, 1):
        if unicodedata.category(char) in _UNPRINTABLE:
            raise ValueError(f"character U+{ord(char):04X} at position {at} is not printable; "
                             "text here is one line of printable characters")
    return text


def text(max_length: int, min_length: int | None = None) -> Any:
    """The type of a description or name shown to people: one printable line, bounded."""
    return Annotated[str, StringConstraints(min_length=min_length, max_length=max_length),
                     AfterValidator(_one_line),
                     Field(json_schema_extra={"pattern": "^[^\\u0000-\\u001f\\u007f-\\u009f]*$"})]


Description = text(2000)

SCHEMA_PATH = Path(__file__).resolve().parent.parent / "schema" / "behavior.schema.json"


MAX_FUNCTIONS = 32
MAX_VARIABLES = 64
MAX_ERRORS_SHOWN = 5


class BehaviorSpecError(UserError, ValueError):
    """A behavior file is invalid; the message names the file and the place, ``layer`` the check."""

    def __init__(self, message: str, layer: str = "references"):
        super().__init__(message)
        self.layer = layer


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", populate_by_name=True, frozen=True)


class Node(_Model):
    """A node of the graph: exactly one of a primitive name or a sub-behavior name/file."""

    id: Identifier
    primitive: Identifier | None = None
    behavior: text(500, min_length=1) | None = None
    description: Description = ""

    @model_validator(mode="after")
    def _one_kind(self) -> "Node":
        if (self.primitive is None) == (self.behavior is None):
            raise ValueError("a node names exactly one of 'primitive' or 'behavior'")
        return self


class Edge(_Model):
    """A directed edge; ``param`` chooses the next primitive's parameter."""

    source: Identifier = Field(alias="from")
    to: Identifier
    guard: ExpressionText = "True"
    param: ExpressionText | None = None
    set: dict[Identifier, ExpressionText] = Field(default_factory=dict)
    description: Description = ""


class Start(_Model):
    """The start function S: first node and, for a primitive, its parameter."""

    node: Identifier
    param: ExpressionText | None = None


class Function(_Model):
    """A named decision function composed from helpers (e.g. the paper's E4)."""

    args: list[Identifier] = Field(default_factory=list, max_length=8)
    expr: ExpressionText
    description: Description = ""


class Promise(_Model):
    """What the behavior promises holds when it finishes: an expression over the env's outcome
    helpers (the final state and the steps the behavior ran), and the same in plain words.
    With ``as_soon_as`` it also promises to stop as soon as the expression holds: it did not
    hold before the behavior's last step (judged where the env's judge can rewind a step)."""

    expr: ExpressionText
    description: text(500) = ""
    as_soon_as: bool = False


class Certificate(_Model):
    """What certified a behavior: a fixed-N campaign on ``env`` (with ``env_kwargs``), root seed
    ``seed``, whose ``successes`` of ``episodes`` kept every certificate and ``promise`` (kept
    as soon as it held, with ``as_soon_as``). It
    gives P[success] >= 1 - ``epsilon`` with ``confidence`` (over the ``attempts`` certification
    campaigns of the search that found it: a union bound). ``content_sha256`` is the digest of
    the behavior's content without this certificate, ``vlb_gym`` the version that ran it:
    ``vlb verify ENV --behavior FILE --episodes N --seed S`` runs the same episodes again."""

    promise: ExpressionText
    as_soon_as: bool = False
    env: text(200)
    env_kwargs: dict[Identifier, Any] = Field(default_factory=dict, max_length=32)
    seed: int = Field(ge=0, lt=2**63)
    episodes: int = Field(ge=1, le=10**9)
    successes: int = Field(ge=0, le=10**9)
    epsilon: float = Field(gt=0, lt=1)
    confidence: float = Field(ge=0, le=1)
    attempts: int = Field(1, ge=1, le=1000)
    content_sha256: Annotated[str, StringConstraints(pattern="^[0-9a-f]{64}$")]
    vlb_gym: text(40)


class BehaviorSpec(_Model):
    """A whole behavior file."""

    name: Identifier
    description: Description = ""
    env: text(200) | None = Field(None, description="environment id the behavior is written for")
    variables: dict[Identifier, ExpressionText] = Field(default_factory=dict,
                                                        max_length=MAX_VARIABLES)
    functions: dict[Identifier, Function] = Field(default_factory=dict, max_length=MAX_FUNCTIONS)
    nodes: list[Node] = Field(min_length=1, max_length=256)
    edges: list[Edge] = Field(default_factory=list, max_length=1024)
    start: Start
    terminals: list[Identifier] = Field(min_length=1)
    promise: Promise | None = None
    certificate: Certificate | None = None
    format: int | None = Field(None, ge=1, description="the file's format version (written by "
                               "vlb-gym; none: 1, the files written before versions)")


def _place(loc: tuple[Any, ...]) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(document)"


def parse_spec(text: str | bytes, source: str = "<behavior>") -> BehaviorSpec:
    """Parse and schema-check a behavior document; errors name ``source`` and the place."""
    try:
        data = load_json(text, source)
    except json.JSONDecodeError as exc:
        raise BehaviorSpecError(f"{source}: line {exc.lineno} column {exc.colno}: "
                                f"invalid JSON: {exc.msg}", "json") from None
    except UnicodeDecodeError:
        raise BehaviorSpecError(f"{source}: not UTF-8 text", "json") from None
    except InputFileError as exc:
        raise BehaviorSpecError(str(exc), "json") from None
    return spec_from_data(data, source)


def spec_from_data(data: Any, source: str = "<behavior>") -> BehaviorSpec:
    """Schema-check an already decoded behavior document (of a format this package reads)."""
    if isinstance(data, dict) and "format" in data:
        try:
            check_format("behavior", data["format"], f"{source}: format")
        except FormatError as exc:
            raise BehaviorSpecError(str(exc), "schema") from None
    return validated(BehaviorSpec, data, source)


def validated(model: type[_Model], data: Any, source: str, prefix: str = "") -> Any:
    """``data`` as a ``model``; BehaviorSpecError (layer schema) naming ``source`` and each
    place (after ``prefix``) if it is not one."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        errors = exc.errors()
        lines = [f"{source}: {_place((prefix, *err['loc']) if prefix else err['loc'])}: "
                 f"{err['msg']}{_suggestion(model, err)}" for err in errors[:MAX_ERRORS_SHOWN]]
        if len(errors) > MAX_ERRORS_SHOWN:
            lines.append(f"{source}: ... and {len(errors) - MAX_ERRORS_SHOWN} more problems")
        raise BehaviorSpecError("\n".join(lines), "schema") from None


def _suggestion(model: type[BaseModel], error: Any) -> str:
    """For a key the schema does not know, the nearest one it does at that place."""
    if error["type"] != "extra_forbidden" or not error["loc"]:
        return ""
    here: Any = model
    a_key = False  # the next part is a key of a dict field
    for part in error["loc"][:-1]:
        if isinstance(part, int) or a_key:
            a_key = False
            continue
        field = next((f for n, f in here.model_fields.items() if part in (n, f.alias)), None)
        here = _model_in(field.annotation) if field is not None else None
        if here is None:
            return ""
        a_key = typing.get_origin(field.annotation) is dict
    known = [name for n, f in here.model_fields.items() for name in (f.alias or n,)]
    near = difflib.get_close_matches(str(error["loc"][-1]), known, n=1, cutoff=0.6)
    return f" (did you mean {near[0]!r}?)" if near else f" (known here: {', '.join(known)})"


def _model_in(annotation: Any) -> type[BaseModel] | None:
    """The model class inside ``annotation`` (``list[Node]``, ``Promise | None``, ...)."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for inner in typing.get_args(annotation):
        found = _model_in(inner)
        if found is not None:
            return found
    return None


def json_schema() -> dict[str, Any]:
    """The JSON Schema of behavior files (the one shipped at ``SCHEMA_PATH``)."""
    schema = BehaviorSpec.model_json_schema(by_alias=True)
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["$id"] = "https://vlb-gym.invalid/behavior.schema.json"
    return schema
