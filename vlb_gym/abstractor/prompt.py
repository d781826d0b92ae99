"""Prompts of the behavior generalizer, built from the environment itself.

The templates are versioned files in ``prompts/<version>/``; the primitive list, the helper
signatures and the behavior library are generated from the live environment and library, never
hand-copied. :func:`request_schema` is the grammar-friendly behavior schema of
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

PROMPT_VERSION = "v1"


def _template(name: str, version: str) -> Template:
    path = resources.files("vlb_gym.abstractor") / "prompts" / version / f"{name}.md"
    return Template(path.read_text())


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
        env_id = getattr(interface, "env_id", None) or env.spec.id
        primitives = {name: {"description": p.description, "parameters": str(p.param_space)}
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
                                                              exclude_defaults=True)})
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
    """The system and user messages for one request (the paper's s, I, D and B)."""
    primitives = "\n".join(f"- {name}: {p['description']} Parameter space: {p['parameters']}."
                           for name, p in context.primitives.items())
    helpers = "\n".join([f"- {sig}: {doc}" for sig, doc in context.helpers.items()]
                        + [context.helper_notes])
    behaviors = "\n".join(
        f"- {b['name']}{' (the user asks you to build on it)' if b['name'] in context.uses else ''}"
        f": {b['description']}\n  {json.dumps(b['document'])}" for b in context.behaviors
    ) or "(none)"
    system = _template("system", version).substitute(builtins=", ".join(sorted(BUILTINS)))
    user = _template("user", version).substitute(
        env_id=context.env_id, primitives=primitives, helpers=helpers,
        info=info.strip() or "(none)", behaviors=behaviors,
        schema=json.dumps(request_schema(context)), description=description.strip())
    return [{"role": "system", "content": system}, {"role": "user", "content": user}]


def repair_message(error: BehaviorSpecError) -> Message:
    """The feedback sent back to the model after a reply failed validation."""
    return {"role": "user", "content": (
        f"That behavior was rejected by the {error.layer} check:\n{error}\n"
        "Reply with the corrected JSON document only.")}
