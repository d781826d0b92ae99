"""Intent first: a language model turns the user's request into a promise, before any graph.

The promise (:mod:`vlb_gym.core.promise`) is what a synthesized behavior is certified against,
so it is written, checked and shown to the user first. The model sees the env's outcome helpers
and the few worked examples of the env's bank (``intents/ENV_ID.json``: requests with their
promises, none of them an evaluation task) nearest to the request; its reply is a JSON object
``{"description", "expr"}`` under the :func:`~vlb_gym.abstractor.grammar.promise_schema`. A
reply whose expression does not check is not kept in the conversation: the next request is the
same prompt with the rejected expression and its error stated in the task's turn, so the model
is not shown its own mistake as an example to repeat.
"""

from __future__ import annotations

import json
import math
import re
from collections import Counter
from dataclasses import dataclass
from importlib import resources
from typing import Any

from vlb_gym.core.env import PrimitiveEnv
from vlb_gym.core.promise import check_promise
from vlb_gym.core.spec import BehaviorSpecError, Promise, validated

from .backends import ModelError, ChatBackend, Message
from .grammar import promise_schema

EXAMPLES_SHOWN = 4
_WORD = re.compile(r"[a-z]+|\d+")

SYSTEM = (
    "You turn a robot task into its promise: the condition that must hold once the behavior has "
    "finished, judged by the environment from what really happened. Reply with one JSON object "
    '{"description": ..., "expr": ...} only. "expr" is a Python expression over the outcome '
    "helpers below and the builtins len, min, max, any, all, abs, sum, sorted, int, float, bool "
    "(comprehensions, comparisons, and/or/not, subscripts and slices are allowed; no other "
    'names, no attributes, no "is"). It must state exactly what the task asks: every '
    "requirement, and nothing the task does not ask. \"description\" says the same in plain "
    "words, for the user to confirm.")


@dataclass(frozen=True)
class Example:
    """A worked example: a request and its promise."""

    request: str
    promise: Promise


def bank(env_id: str) -> list[Example]:
    """The env's worked examples (none if it ships no bank)."""
    path = resources.files("vlb_gym.abstractor") / "intents" / f"{env_id}.json"
    if not path.is_file():
        return []
    return [Example(e["request"], Promise(**e["promise"])) for e in json.loads(path.read_text())]


def _words(text: str) -> Counter[str]:
    return Counter(_WORD.findall(text.lower()))


def nearest(request: str, examples: list[Example], k: int = EXAMPLES_SHOWN, skip: int = 0
            ) -> list[Example]:
    """The ``k`` examples whose requests are nearest ``request`` (cosine of word counts weighted
    by inverse document frequency over the bank), after the ``skip`` nearest, nearest last: the
    one most like the task stands next to it. (A later round skips some, so that it is asked
    with other examples and does not repeat itself.)"""
    if not examples:
        return []
    documents = [_words(e.request) for e in examples]
    weight = {w: math.log((1 + len(documents)) / (1 + sum(w in d for d in documents))) + 1
              for d in documents for w in d}

    def vector(words: Counter[str]) -> dict[str, float]:
        return {w: n * weight.get(w, 1.0) for w, n in words.items()}

    def cosine(a: dict[str, float], b: dict[str, float]) -> float:
        dot = sum(v * b.get(w, 0.0) for w, v in a.items())
        norm = math.sqrt(sum(v * v for v in a.values()) * sum(v * v for v in b.values()))
        return dot / norm if norm else 0.0

    query = vector(_words(request))
    scored = sorted(range(len(examples)),
                    key=lambda i: (cosine(query, vector(documents[i])), -i), reverse=True)
    chosen = scored[skip:skip + k] if skip + k <= len(scored) else scored[-k:]
    return [examples[i] for i in reversed(chosen)]


def _reply(promise: Promise) -> str:
    return json.dumps({"description": promise.description, "expr": promise.expr})


def promise_messages(request: str, interface: PrimitiveEnv, examples: list[Example],
                     rejected: tuple[str, str] | None = None) -> list[Message]:
    """The conversation asking for ``request``'s promise: the outcome helpers, the examples as
    solved turns, then the task (with the last rejected expression and why, if any)."""
    judge = interface.make_judge()
    if judge is None:
        raise BehaviorSpecError(f"{interface.env_id}: offers no outcome helpers to promise with")
    helpers = "\n".join(f"- {sig}: {doc}" for sig, doc in judge.describe().items())
    notes = " ".join(judge.__doc__.split("\n\n", 1)[-1].split()) if judge.__doc__ else ""
    messages: list[Message] = [{"role": "system", "content": (
        f"{SYSTEM}\n\nEnvironment: {interface.env_id}\nOutcome helpers:\n{helpers}\n{notes}")}]
    for example in examples:
        messages += [{"role": "user", "content": f"Task: {example.request}"},
                     {"role": "assistant", "content": _reply(example.promise)}]
    task = f"Task: {request.strip()}"
    if rejected is not None:
        task += (f"\n(An earlier answer, {rejected[0]!r}, was rejected: {rejected[1]} "
                 "Write a correct one.)")
    return messages + [{"role": "user", "content": task}]


def parse_promise(reply: str, interface: PrimitiveEnv) -> Promise:
    """A model's reply as a checked promise; BehaviorSpecError saying what is wrong."""
    try:
        data = json.loads(reply)
    except (json.JSONDecodeError, TypeError):
        raise BehaviorSpecError("the reply is not a JSON object", "json") from None
    if not isinstance(data, dict) or not isinstance(data.get("expr"), str) \
            or not isinstance(data.get("description", ""), str):
        raise BehaviorSpecError('the reply is not {"description": TEXT, "expr": EXPRESSION}',
                                "schema")
    promise = validated(Promise, {"expr": data["expr"],
                                  "description": data.get("description", "")},
                        "the reply", "promise")
    check_promise(promise.expr, interface, "promise")
    return promise


@dataclass
class Draft:
    """The promise a model wrote for a request (None if every round was rejected), and how."""

    promise: Promise | None
    rounds: list[dict[str, Any]]


def draft_promise(request: str, interface: PrimitiveEnv, backend: ChatBackend,
                  max_rounds: int = 3, rejected: tuple[str, str] | None = None,
                  attempt: int = 0) -> Draft:
    """Ask ``backend`` for the promise of ``request``, up to ``max_rounds`` times; each round
    after the first is asked with other worked examples and the rejected answer's error.
    ``rejected`` (an earlier promise and what went wrong with it) and ``attempt`` (how many
    drafts came before) let a caller ask again after a promise no behavior could keep."""
    examples = bank(interface.env_id)
    rounds: list[dict[str, Any]] = []
    for number in range(1, max_rounds + 1):
        shown = nearest(request, examples, skip=attempt + number - 1)
        messages = promise_messages(request, interface, shown, rejected)
        try:
            reply = backend.complete(messages, promise_schema())
        except ModelError as exc:
            rounds.append({"round": number, "reply": None, "error": str(exc),
                           "layer": "backend"})
            return Draft(None, rounds)
        record: dict[str, Any] = {"round": number, "examples": [e.request for e in shown],
                                  "reply": reply, "error": None, "layer": None}
        rounds.append(record)
        try:
            return Draft(parse_promise(reply, interface), rounds)
        except BehaviorSpecError as exc:
            record.update(error=str(exc), layer=exc.layer)
            text = reply if len(reply) <= 300 else reply[:297] + "..."
            rejected = (text, str(exc))
    return Draft(None, rounds)
