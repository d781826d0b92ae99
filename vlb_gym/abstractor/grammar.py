"""The schema sent with a request: a behavior schema that grammar compilers accept.

Servers that enforce structured output (llama.cpp and llama-cpp-python, Ollama, vLLM's
xgrammar/outlines, OpenAI) compile the schema into a grammar. The validation schema
(``vlb_gym/schema/behavior.schema.json``) is not fit for that: ``maxLength: 2000`` on every
expression string becomes a repetition of 2,000 in the grammar, enough to make llama.cpp give up
("number of rules that are going to be repeated multiplied by the new repetition exceeds sane
defaults"), and ``maxItems: 1024`` or ``patternProperties`` fare no better. So the request
schema keeps the shape of a behavior document and drops the limits:

* the top level is fixed and all of it required, in the order a behavior is read: ``name``,
  ``description``, ``env`` (a constant), ``variables`` and ``functions`` (empty objects when
  unused), ``nodes``, ``edges``, ``start``, ``terminals`` (a promise is written apart, first: :func:`promise_schema`). Grammar compilers write required
  properties first, in their order, then the optional ones: with ``variables`` optional, a
  constrained model could only declare them after the edges that use them, and small models
  then leave them out. Every object of fixed shape has ``additionalProperties: false``;
* a node is either a primitive node (``id``, ``primitive``) or, when the library has behaviors,
  a behavior node (``id``, ``behavior``): never both, never neither; primitive names and library
  behavior names are enums, as the env and the library are known when the request is made;
* expression strings have no ``maxLength``; descriptions have ``MAX_STRING_LENGTH`` and the
  node and edge lists ``MAX_GRAPH_ITEMS``, small bounds that grammar compilers handle and that
  stop a model from rambling in prose or unrolling a loop into copies of nodes until its token
  budget cuts the reply off (both seen with real models); names keep their pattern (no length);
* maps (``variables``, ``functions``, an edge's ``set``) are ``additionalProperties: SCHEMA``
  rather than ``patternProperties``.

The full validation (lengths, counts, references, the graph, expressions, a dry run) stays in
:mod:`vlb_gym.abstractor.validate`; this schema only keeps a constrained decoder on the right
shape.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from vlb_gym.core.names import IDENTIFIER_PATTERN

MAX_STRING_LENGTH = 300
"""The ``maxLength`` of descriptions, the longest in the request schema (a task description
copied into the behavior's fits)."""
MAX_GRAPH_ITEMS = 16
"""The ``maxItems`` of nodes and edges, the largest in the request schema."""


def _name() -> dict[str, Any]:
    return {"type": "string", "pattern": IDENTIFIER_PATTERN}


def _expression() -> dict[str, Any]:
    return {"type": "string", "minLength": 1}


def _text() -> dict[str, Any]:
    return {"type": "string", "maxLength": MAX_STRING_LENGTH}


def _optional(schema: dict[str, Any]) -> dict[str, Any]:
    return {"anyOf": [schema, {"type": "null"}]}


def grammar_schema(env_id: str, primitives: Iterable[str], behaviors: Iterable[str] = ()
                   ) -> dict[str, Any]:
    """The request schema for behaviors of ``env_id`` over ``primitives`` that may use the
    library behaviors ``behaviors`` as sub-behavior nodes."""
    behavior_names = sorted(set(behaviors))
    primitive_node = {
        "type": "object",
        "description": "A node that runs one motion primitive.",
        "properties": {"id": _name(), "primitive": {"enum": sorted(primitives)},
                       "description": _text()},
        "required": ["id", "primitive"],
        "additionalProperties": False}
    node: dict[str, Any] = primitive_node
    if behavior_names:
        node = {"anyOf": [primitive_node, {
            "type": "object",
            "description": "A node that runs a whole library behavior.",
            "properties": {"id": _name(), "behavior": {"enum": behavior_names},
                           "description": _text()},
            "required": ["id", "behavior"],
            "additionalProperties": False}]}
    edge = {
        "type": "object",
        "description": "A directed edge, taken when its guard holds; param is the parameter of "
                       "the next node's primitive, set updates variables.",
        "properties": {
            "from": _name(),
            "to": _name(),
            "guard": _expression(),
            "param": _optional(_expression()),
            "set": {"type": "object", "additionalProperties": _expression()},
            "description": _text()},
        "required": ["from", "to"],
        "additionalProperties": False}
    start = {
        "type": "object",
        "description": "The first node and, for a primitive, its parameter.",
        "properties": {"node": _name(), "param": _optional(_expression())},
        "required": ["node"],
        "additionalProperties": False}
    function = {
        "type": "object",
        "description": "A decision function: an expression over its args and the helpers.",
        "properties": {
            "args": {"type": "array", "items": _name(), "maxItems": 8},
            "expr": _expression(),
            "description": _text()},
        "required": ["args", "expr"],
        "additionalProperties": False}
    return {
        "type": "object",
        "properties": {
            "name": _name(),
            "description": _text(),
            "env": {"const": env_id},
            "variables": {"type": "object", "additionalProperties": _expression()},
            "functions": {"type": "object", "additionalProperties": {"$ref": "#/$defs/Function"}},
            "nodes": {"type": "array", "items": {"$ref": "#/$defs/Node"}, "minItems": 1,
                      "maxItems": MAX_GRAPH_ITEMS},
            "edges": {"type": "array", "items": {"$ref": "#/$defs/Edge"},
                      "maxItems": MAX_GRAPH_ITEMS},
            "start": {"$ref": "#/$defs/Start"},
            "terminals": {"type": "array", "items": _name(), "minItems": 1}},
        "required": ["name", "description", "env", "variables", "functions", "nodes", "edges",
                     "start", "terminals"],
        "additionalProperties": False,
        "$defs": {"Node": node, "Edge": edge, "Start": start, "Function": function}}


def promise_schema() -> dict[str, Any]:
    """The schema of a promise: its expression over the env's outcome helpers, and the same in
    words (what the user confirms)."""
    return {"type": "object",
            "description": "What holds when the behavior finishes, judged from the episode.",
            "properties": {"description": _text(), "expr": _expression()},
            "required": ["description", "expr"],
            "additionalProperties": False}
