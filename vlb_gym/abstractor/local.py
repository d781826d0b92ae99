"""A language model in-process: a GGUF file decoded by llama.cpp (llama-cpp-python, extra ``llm``).

:class:`LocalBackend` loads the model once and answers each request with the request schema
compiled into a grammar (:mod:`vlb_gym.abstractor.grammar`), so every reply is a JSON document of
the behavior's shape by construction and the repair loop only meets meaning errors (references,
graph, expressions, the dry run). Tokens are streamed to a ``progress`` callback, so a slow CPU
model is visibly working. Requests that share a prefix with the previous one (the same prompt,
a repair round) reuse llama.cpp's evaluated tokens, which is most of the prompt processing.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .backends import ModelError, Message, unrepeated

GGUF_MAGIC = b"GGUF"
DEFAULT_CONTEXT = 8192
"""Context window in tokens: the compact prompt (about 1,000 tokens) and three rounds of replies
and repairs fit with room to spare."""
DEFAULT_MAX_TOKENS = 1500
"""Tokens per reply; a behavior document of the paper's size is 250-500."""
DEFAULT_TIMEOUT = 1800.0
"""Seconds per reply: a 1.5B model on two CPU cores generates 3-10 tokens/s."""


@dataclass(frozen=True)
class Decoding:
    """Where one request stands: its number (1 for the first), the prompt's length in tokens
    (known once the first token is out), tokens generated, seconds since the request began, the
    seconds the prompt took (None before the first token) and whether the reply is complete. The
    callback is called once when a request begins (no tokens yet), after every token and once at
    the end."""

    request: int
    prompt_tokens: int | None
    tokens: int
    seconds: float
    prompt_seconds: float | None
    done: bool = False


def check_model_file(path: str | Path) -> Path:
    """``path`` as a readable GGUF file, or ValueError saying what it is instead."""
    path = Path(path)
    try:
        with path.open("rb") as handle:
            magic = handle.read(4)
    except IsADirectoryError:
        raise ValueError(f"--model-path {path}: a directory, not a GGUF model file") from None
    except OSError as exc:
        raise ValueError(f"--model-path {path}: {exc.strerror or exc}") from None
    if magic != GGUF_MAGIC:
        raise ValueError(f"--model-path {path}: not a GGUF model file (it does not start with "
                         f"'GGUF')")
    return path


class LocalBackend:
    """Chat completions from a GGUF model loaded in this process (llama-cpp-python).

    The chat template is the model's own (from the GGUF metadata). ``temperature`` 0 is greedy
    decoding; otherwise ``seed`` makes sampling repeatable. ``timeout`` bounds one reply's
    generation (prompt processing cannot be interrupted; it is reported once done). ``usage``
    keeps one record per request: prompt and reply tokens, seconds, the reason generation
    stopped.
    """

    dialect = "grammar"
    """Recorded in transcripts as the structured output used."""

    def __init__(self, model_path: str | Path, context: int = DEFAULT_CONTEXT,
                 threads: int | None = None, max_tokens: int = DEFAULT_MAX_TOKENS,
                 temperature: float = 0.0, seed: int = 0, timeout: float = DEFAULT_TIMEOUT,
                 progress: Callable[[Decoding], None] | None = None):
        path = check_model_file(model_path)
        if context < 512 or max_tokens < 1 or timeout <= 0 or temperature < 0:
            raise ValueError("context must be at least 512 tokens, max_tokens and timeout "
                             "positive, temperature at least 0")
        try:
            from llama_cpp import Llama
        except ImportError:
            raise ValueError("--model-path needs llama-cpp-python: pip install 'vlb-gym[llm]' "
                             "(it compiles llama.cpp, 15-30 minutes on two cores)") from None
        try:
            self.llm = Llama(model_path=str(path), n_ctx=context, seed=seed, verbose=False,
                             n_threads=threads or os.cpu_count() or 1)
        except (ValueError, RuntimeError) as exc:
            raise ValueError(f"--model-path {path}: llama.cpp could not load it ({exc})") from None
        self.path, self.max_tokens, self.timeout = path, max_tokens, timeout
        self.temperature, self.seed = temperature, seed
        self.progress = progress
        self.name = f"{path.name} (local, llama.cpp)"
        self.usage: list[dict[str, Any]] = []
        self.probe_log: list[dict[str, str]] = []  # nothing to probe: llama.cpp takes grammars
        self._grammars: dict[str, Any] = {}

    def grammar(self, schema: dict[str, Any]) -> Any:
        """``schema`` compiled by llama.cpp into a grammar (kept for the next request)."""
        from llama_cpp import LlamaGrammar

        key = json.dumps(schema)  # as it is: the grammar writes properties in this order
        if key not in self._grammars:
            try:
                self._grammars[key] = LlamaGrammar.from_json_schema(key, verbose=False)
            except (ValueError, RuntimeError) as exc:
                raise ModelError(f"llama.cpp could not compile the request schema into a "
                                   f"grammar: {exc}") from None
        return self._grammars[key]

    def complete(self, messages: Sequence[Message], schema: dict[str, Any] | None = None) -> str:
        """One reply. A reply identical to an earlier assistant turn -- a reply the repair loop
        rejected (greedy decoding repeats itself through repair rounds) or the prompt's worked
        example, copied -- is drawn again (:func:`~vlb_gym.abstractor.backends.unrepeated`:
        at least at ``RESAMPLE_TEMPERATURE`` with a new seed, up to ``RESAMPLES`` times);
        ``usage`` records each draw, a repeated one marked ``repeated``."""
        earlier = {m["content"] for m in messages if m["role"] == "assistant"}

        def draw(temperature: float, seed: int | None) -> str:
            reply = self._decode(messages, schema, temperature, self.seed if seed is None
                                 else seed)
            if reply in earlier:
                self.usage[-1]["repeated"] = True
            return reply

        return unrepeated(draw, messages, self.temperature, self.seed)

    def _decode(self, messages: Sequence[Message], schema: dict[str, Any] | None,
                temperature: float, seed: int) -> str:
        request = len(self.usage) + 1
        grammar = self.grammar(schema) if schema is not None else None
        started = time.perf_counter()
        pieces: list[str] = []
        tokens, prompt_tokens, prompt_seconds, finish = 0, None, None, None
        if self.progress is not None:
            self.progress(Decoding(request, None, 0, 0.0, None))
        stream = self.llm.create_chat_completion(
            messages=list(messages), grammar=grammar, temperature=temperature,
            max_tokens=self.max_tokens, seed=seed, stream=True)
        try:
            for chunk in stream:
                choice = chunk["choices"][0]
                finish = choice.get("finish_reason") or finish
                text = choice.get("delta", {}).get("content")
                if not text:
                    continue
                now = time.perf_counter() - started
                if prompt_seconds is None:
                    prompt_seconds, prompt_tokens = now, self.llm.n_tokens - 1
                pieces.append(text)
                tokens += 1
                if self.progress is not None:
                    self.progress(Decoding(request, prompt_tokens, tokens, now, prompt_seconds))
                if now > self.timeout:
                    finish = "timeout"
                    break
        finally:
            stream.close()
        seconds = time.perf_counter() - started
        if self.progress is not None:
            self.progress(Decoding(request, prompt_tokens, tokens, seconds, prompt_seconds, True))
        self.usage.append({"request": request, "prompt_tokens": prompt_tokens,
                           "reply_tokens": tokens, "prompt_seconds": prompt_seconds,
                           "seconds": round(seconds, 3), "finish": finish,
                           "temperature": temperature, "seed": seed})
        if finish == "timeout":
            raise ModelError(f"no complete reply within --timeout {self.timeout:g} s "
                               f"({tokens} tokens generated)")
        return "".join(pieces)
