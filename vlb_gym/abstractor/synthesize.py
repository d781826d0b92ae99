"""Algorithm 1 of the paper: ask the abstractor for a behavior the library lacks, validate it,
feed validation errors back for repair (a bounded number of rounds), and only then add it to B."""

from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import gymnasium as gym

from vlb_gym.core.compiler import CompiledBehavior
from vlb_gym.core.files import write_atomic
from vlb_gym.core.library import BehaviorLibrary, compile_for, spec_json
from vlb_gym.core.errors import UserError
from vlb_gym.core.spec import BehaviorSpecError

from .backends import ModelError, ChatBackend
from .prompt import PROMPT_VERSION, PromptContext, build_messages, repair_message, request_schema
from .validate import validate_reply


class SynthesisError(UserError, RuntimeError):
    """No valid behavior came back within the allowed rounds; ``transcript`` says what happened."""

    def __init__(self, message: str, transcript: dict[str, Any]):
        super().__init__(message)
        self.transcript = transcript


@dataclass
class Synthesis:
    """A validated behavior and the transcript of how it was obtained."""

    compiled: CompiledBehavior
    transcript: dict[str, Any]
    from_library: bool = False
    rounds: int = field(init=False)

    def __post_init__(self) -> None:
        self.rounds = len(self.transcript["rounds"])


def synthesize(env_id: str, description: str, backend: ChatBackend,
               library: BehaviorLibrary | None = None, info: str = "",
               uses: tuple[str, ...] = (), name: str | None = None,
               max_rounds: int = 3, prompt_version: str = PROMPT_VERSION) -> Synthesis:
    """One pass of Algorithm 1 for the desired behavior ``description`` (the paper's s) with the
    extra information ``info`` (I), asked with the prompt templates ``prompt_version``. A
    ``name`` already in the library is returned as it is."""
    if max_rounds < 1:
        raise ValueError(f"max_rounds must be at least 1 (got {max_rounds})")
    library = library or BehaviorLibrary()
    env = gym.make(env_id)
    transcript: dict[str, Any] = {
        "env_id": env_id, "description": description, "info": info, "uses": list(uses),
        "name": name, "backend": backend.name, "prompt_version": prompt_version,
        "started": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "rounds": []}
    if name is not None and name in library:
        return Synthesis(compile_for(name, env, library), transcript, from_library=True)
    context = PromptContext.build(env, library, uses)
    transcript["skipped_library_behaviors"] = context.skipped
    messages = build_messages(description, context, info, prompt_version)
    schema = request_schema(context)
    transcript["messages"] = list(messages)
    error: BehaviorSpecError | None = None
    usage = backend.usage  # a local model's draws: tokens and seconds
    for round_number in range(1, max_rounds + 1):
        drawn = len(usage)
        try:
            reply = backend.complete(messages, schema)
        except ModelError as exc:
            _note_structured_output(transcript, backend)
            transcript["rounds"].append({"round": round_number, "reply": None,
                                         "error": str(exc), "layer": "backend"})
            cause = (f"{error} (the {error.layer} check); then " if error is not None else "")
            raise SynthesisError(f"{cause}the language model failed: {exc}", transcript) from None
        _note_structured_output(transcript, backend)
        record = {"round": round_number, "reply": reply, "error": None, "layer": None}
        if usage:
            record["usage"] = usage[drawn:]
        transcript["rounds"].append(record)
        try:
            compiled = validate_reply(reply, env, library, name, f"reply {round_number}")
        except BehaviorSpecError as exc:
            error = exc
            record.update(error=str(exc), layer=exc.layer)
            repair = repair_message(exc)
            messages += [{"role": "assistant", "content": reply}, repair]
            record["repair"] = repair["content"]
            continue
        return Synthesis(compiled, transcript)
    raise SynthesisError(f"no valid behavior after {max_rounds} round(s); the last reply failed "
                         f"the {error.layer} check: {error}", transcript)


def _note_structured_output(transcript: dict[str, Any], backend: ChatBackend) -> None:
    """Record the structured-output dialect an HTTP backend used (and, if it probed, what each
    probe got)."""
    if backend.dialect is not None:
        transcript["structured_output"] = backend.dialect
        if backend.probe_log:
            transcript["structured_output_probe"] = list(backend.probe_log)


def save(synthesis: Synthesis, library: BehaviorLibrary, out: Path | None = None,
         overwrite: bool = False) -> Path:
    """Add the behavior to the library (or write it to ``out``), with its transcript beside it."""
    spec = synthesis.compiled.spec
    if out is None:
        path = library.save(spec, overwrite)
    else:
        if out.exists() and not overwrite:
            raise BehaviorSpecError(f"{out}: exists already (use --force to replace it)")
        write_atomic(out, spec_json(spec))
        path = out
    save_transcript(synthesis.transcript, path.with_suffix(".transcript.json"))
    return path


def save_transcript(transcript: dict[str, Any], path: Path) -> Path:
    write_atomic(path, json.dumps(transcript, indent=2) + "\n")
    return path
