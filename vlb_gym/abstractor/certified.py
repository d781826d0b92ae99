"""Certified synthesis, intent first: promises, a consensus behavior, confirmation, certification.

:func:`synthesize_certified` runs the whole pipeline for one request:

1. the model writes the promise ``drafts`` times, each time shown other worked examples of the
   env's bank (:func:`~vlb_gym.abstractor.intent.draft_promise`); a draft whose expression does
   not check is asked again once with the error, out of the conversation;
2. for each distinct promise, :func:`~vlb_gym.abstractor.search.find` looks for the smallest
   behavior of the env's search space that keeps it on the screening episodes;
3. *consensus*: every behavior found is screened against every promise, and the behaviors are
   ranked by the promises they keep, each weighing 1/(k+1) for the draft k that first wrote it
   (a small model's mistakes differ from draft to draft, so what several drafts agree on is more
   likely what the user meant, and the first draft, shown the nearest examples, counts most).
   The best behavior is paired with the earliest promise it keeps;
4. ``confirm`` shows that promise to the user (the CLI prints it in words and asks; ``--yes``
   accepts), since a promise that certifies is only as good as its wording;
5. the behavior is certified against it on fresh seeds
   (:func:`~vlb_gym.abstractor.search.certify`); if it fails, the next behavior in the ranking,
   up to :data:`~vlb_gym.abstractor.search.ATTEMPTS` certifications, whose union bound the
   confidence accounts for.

The result says honestly what it got: a certified behavior with its promise, or the promises
tried and why none certified. The transcript records every request, reply, search and score.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.core.spec import Promise
from vlb_gym.envs.modules import make_primitive_env

from .backends import ChatBackend
from .intent import draft_promise
from .search import (ATTEMPTS, SCREEN_EPISODES, Screen, SearchResult, certify, find, passes,
                     procedure_confidence)
from .sketches import Candidate

DRAFTS = 4
ROUNDS_PER_DRAFT = 2


@dataclass
class CertifiedSynthesis:
    """What the pipeline got: the confirmed ``promise`` and certified ``document`` (None where
    it got none), the last search, whether the user declined, and the transcript."""

    request: str
    promise: Promise | None
    document: dict[str, Any] | None
    search: SearchResult | None
    declined: bool
    transcript: dict[str, Any]

    @property
    def certified(self) -> bool:
        return self.document is not None


def _find_record(result: SearchResult) -> dict[str, Any]:
    return {"candidate": result.candidate.label if result.candidate else None,
            "tried": result.tried, "seconds": round(result.seconds, 2),
            "failures": result.failures}


def synthesize_certified(env_id: str, request: str, backend: ChatBackend,
                         confirm: Callable[[Promise], bool] = lambda promise: True,
                         name: str = "synthesized", drafts: int = DRAFTS,
                         time_limit: float = 600.0,
                         library: BehaviorLibrary | None = None,
                         budgets: Sequence[int] | None = None) -> CertifiedSynthesis:
    """Run the pipeline (see the module's docstring) for ``request`` on ``env_id``.

    The searches share ``time_limit``; ``budgets`` instead bounds each search, in order, by a
    number of candidates and not by time (a replay passes the counts a transcript recorded, so
    that it tries the same candidates on any machine)."""
    started = time.perf_counter()
    env = make_primitive_env(env_id, {})
    interface = env.unwrapped
    transcript: dict[str, Any] = {"env_id": env_id, "request": request, "backend": backend.name,
                                  "pipeline": "intent-first", "drafts": [], "finds": [],
                                  "consensus": [], "certifications": []}
    promises: list[Promise] = []
    weights: list[float] = []  # of each promise: 1 / (k + 1) for the draft k that wrote it first
    for k in range(drafts):
        draft = draft_promise(request, interface, backend, ROUNDS_PER_DRAFT, attempt=k)
        transcript["drafts"].append({"rounds": draft.rounds, "promise": draft.promise
                                     and draft.promise.model_dump()})
        if draft.promise is not None and draft.promise.expr not in {p.expr for p in promises}:
            promises.append(draft.promise)
            weights.append(1 / (k + 1))
        if draft.rounds[-1]["layer"] == "backend":
            break
    env.close()
    screen = Screen(env_id, library)
    try:
        found: list[tuple[Candidate, list[int]]] = []
        per_promise = time_limit / max(len(promises), 1) / 2
        for k, promise in enumerate(promises):
            if budgets is None:
                result = find(env_id, request, promise, screen, name, time_limit=per_promise)
            else:
                result = find(env_id, request, promise, screen, name, time_limit=math.inf,
                              max_candidates=budgets[k] if k < len(budgets) else 0)
            transcript["finds"].append({"promise": promise.expr, **_find_record(result)})
            if result.candidate is not None and all(
                    c.key != result.candidate.key for c, _ in found):
                found.append((result.candidate, []))
        for candidate, kept in found:
            kept += [i for i, p in enumerate(promises) if passes(screen, candidate, p,
                                                                  SCREEN_EPISODES)]
            transcript["consensus"].append({"candidate": candidate.label, "keeps": kept})
        ranked = sorted((f for f in found if f[1]),
                        key=lambda f: (-sum(weights[i] for i in f[1]), f[1][0]))
        for attempt, (candidate, kept) in enumerate(ranked[:ATTEMPTS]):
            promise = promises[kept[0]]
            if not confirm(promise):
                transcript["declined"] = promise.model_dump()
                return _ended(request, promise, None, None, True, transcript, started)
            cert = certify(screen, candidate, promise, attempt)
            transcript["certifications"].append(
                {"candidate": candidate.label, "promise": promise.expr, "seed": cert.seed,
                 "successes": cert.successes, "episodes": len(cert.episodes)})
            if cert.passed:
                result = SearchResult(candidate, cert, procedure_confidence(), len(found), 0.0)
                document = {**candidate.document, "promise": promise.model_dump()}
                return _ended(request, promise, document, result, False, transcript, started)
    finally:
        screen.close()
    return _ended(request, promises[0] if promises else None, None, None, False, transcript,
                  started)


def _ended(request: str, promise: Promise | None, document: dict[str, Any] | None,
           result: SearchResult | None, declined: bool, transcript: dict[str, Any],
           started: float) -> CertifiedSynthesis:
    transcript["seconds"] = round(time.perf_counter() - started, 1)
    if result is not None:
        result.seconds = transcript["seconds"]
    return CertifiedSynthesis(request, promise, document, result, declined, transcript)
