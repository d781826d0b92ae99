"""Prompts of the behavior generalizer, built from the environment itself.

The templates are versioned files in ``prompts/<version>/``; the primitive list, the helper
signatures and the behavior library are generated from the live environment and library, never
hand-copied. ``v1`` shows the request schema and every library behavior's whole document; ``v2``
is compact -- the graph's rules, one worked example per environment
(``prompts/v2/examples/ENV_ID.json``, else the environment's first library behavior) and the
library as names and descriptions -- at well under half of ``v1``'s tokens (see
``benchmarks/prompt_tokens.py``): on a CPU, prompt processing dominates a request. ``v3`` (the
default) adds the rules small models broke in the certified-synthesis evaluation (a new name,
no declarations that shadow helpers, loops by edges rather than copied nodes) and shows the
first of its examples that the library allows: one that composes a library behavior with a
loop where the library has it.

:func:`request_schema` is the grammar-friendly behavior schema of
:mod:`vlb_gym.abstractor.grammar` with this request's primitive and behavior names as enums, for
backends that enforce structured output (and shown in the prompt).
"""

from __future__ import annotations

import inspect
import json
from dataclasses import dataclass
from importlib import resources
from string import Template
from typing import Any

import gymnasium as gym

from vlb_gym.core.expressions import BUILTINS
from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.core.spec import BehaviorSpecError

from .backends import Message
from .grammar import grammar_schema

PROMPT_VERSIONS = ("v1", "v2", "v3")
PROMPT_VERSION = "v3"


def _template(name: str, version: str) -> Template:
    if version not in PROMPT_VERSIONS:
        raise ValueError(f"unknown prompt version {version!r}; known: {', '.join(PROMPT_VERSIONS)}")
    path = resources.files("vlb_gym.abstractor") / "prompts" / version / f"{name}.md"
    return Template(path.read_text())


def _example(env_id: str, behaviors: list[dict[str, Any]], version: str
             ) -> dict[str, Any] | None:
    """The worked example of ``env_id``'s prompt: the first of those shipped for ``version``
    (``prompts/<version>/examples/ENV_ID.json``: one document in v2, a list in order of
    preference from v3) whose behavior nodes are all in this library; else the env's first
    library behavior; else none."""
    path = resources.files("vlb_gym.abstractor") / "prompts" / version / "examples" \
        / f"{env_id}.json"
    if path.is_file():
        shipped = json.loads(path.read_text())
        available = {b["name"] for b in behaviors}
        return next((doc for doc in (shipped if isinstance(shipped, list) else [shipped])
                     if {n["behavior"] for n in doc["nodes"] if "behavior" in n} <= available),
                    None)
    return behaviors[0]["document"] if behaviors else None


def space_text(space: gym.Space) -> str:
    """A short description of a parameter space, e.g. ``integers in [0, 10) x [0, 10)``
    (bounds rounded to 3 significant digits)."""
    if isinstance(space, gym.spaces.Box) and len(space.shape) == 1:
        return f"{space.shape[0]} numbers in " + " x ".join(
            f"[{lo:.3g}, {hi:.3g}]" for lo, hi in zip(space.low, space.high))
    if isinstance(space, gym.spaces.MultiDiscrete) and space.nvec.ndim == 1:
        return "integers in " + " x ".join(f"[0, {n})" for n in space.nvec.tolist())
    if isinstance(space, gym.spaces.Discrete):
        return f"an integer in [{space.start}, {space.start + space.n})"
    return str(space)


@dataclass(frozen=True)
class PromptContext:
    """What a prompt says about one environment and library."""

    env_id: str
    primitives: dict[str, dict[str, str]]  # name -> description, parameter space
    helpers: dict[str, str]  # signature -> description
    helper_notes: str  # what the helpers' types mean
    behaviors: list[dict[str, Any]]  # name, description, document
    uses: tuple[str, ...]
    skipped: dict[str, str]  # library behaviors that do not load -> why

    @classmethod
    def build(cls, env: gym.Env, library: BehaviorLibrary, uses: tuple[str, ...] = ()
              ) -> PromptContext:
        interface = env.unwrapped
        env_id = interface.env_id or env.spec.id
        primitives = {name: {"description": p.description, "parameters": str(p.param_space),
                             "brief": space_text(p.param_space)}
                      for name, p in interface.primitives.items()}
        specs, skipped = library.load_all()
        for use in uses:
            if use in skipped:
                raise BehaviorSpecError(f"--uses {use}: {skipped[use]}")
            if use not in specs:
                raise BehaviorSpecError(f"--uses: unknown behavior {use!r}; known: "
                                        f"{', '.join(specs)}")
        behaviors = []
        for name, spec in specs.items():
            if spec.env in (None, env_id):
                behaviors.append({"name": name, "description": spec.description,
                                  "document": spec.model_dump(by_alias=True,
                                                              exclude_defaults=True,
                                                              exclude={"format"})})
        helpers = interface.make_helpers()
        notes = " ".join((inspect.getdoc(type(helpers)) or "").split("\n\n", 1)[-1].split())
        return cls(env_id, primitives, helpers.describe(), notes, behaviors, tuple(uses), skipped)


def request_schema(context: PromptContext) -> dict[str, Any]:
    """The request schema (see :mod:`vlb_gym.abstractor.grammar`) for this context: its env, its
    primitives and its library behaviors as enums."""
    return grammar_schema(context.env_id, context.primitives,
                          [b["name"] for b in context.behaviors])


def build_messages(description: str, context: PromptContext, info: str = "",
                   version: str = PROMPT_VERSION) -> list[Message]:
    """The system and user messages for one request (the paper's s, I, D and B), the task last so
    that requests of one context share their longest prefix (a local model's cache reuses it)."""
    system = _template("system", version).substitute(builtins=", ".join(sorted(BUILTINS)))
    helpers = "\n".join([f"- {sig}: {doc}" for sig, doc in context.helpers.items()]
                        + [context.helper_notes])
    if version == "v1":
        primitives = "\n".join(f"- {name}: {p['description']} Parameter space: "
                               f"{p['parameters']}." for name, p in context.primitives.items())
        fields = {"behaviors": "\n".join(
            f"- {b['name']}{_USES if b['name'] in context.uses else ''}: {b['description']}\n"
            f"  {json.dumps(b['document'])}" for b in context.behaviors) or "(none)",
            "schema": json.dumps(request_schema(context))}
    else:
        example = _example(context.env_id, context.behaviors, version)
        primitives = "\n".join(f"- {name}: {p['description']} Space: {p['brief']}."
                               for name, p in context.primitives.items())
        fields = {"library": "\n".join(
            f"- {b['name']}{_USES if b['name'] in context.uses else ''}: {b['description']}"
            for b in context.behaviors) or "(none)",
            "example": json.dumps(example) if example else "(none)"}
    task = {"info": info.strip() or "(none)", "description": description.strip()}
    user = _template("user", version).safe_substitute(
        env_id=context.env_id, primitives=primitives, helpers=helpers, **fields, **task)
    if version in ("v1", "v2"):
        return [{"role": "system", "content": system}, {"role": "user", "content": user}]
    # v3: the worked example is a solved request of its own, a turn before the task
    ask = _template("task", version)
    if example is None:
        return [{"role": "system", "content": system},
                {"role": "user", "content": f"{user}\n{ask.substitute(task)}"}]
    shown = {"info": "(none)", "description": example["description"]}
    return [{"role": "system", "content": system},
            {"role": "user", "content": f"{user}\n{ask.substitute(shown)}"},
            {"role": "assistant", "content": json.dumps(example)},
            {"role": "user", "content": ask.substitute(task)}]


_USES = " (the user asks you to build on it)"


def repair_message(error: BehaviorSpecError) -> Message:
    """The feedback sent back to the model after a reply failed validation."""
    return {"role": "user", "content": (
        f"That behavior was rejected by the {error.layer} check:\n{error}\n"
        "Reply with the corrected JSON document only.")}
