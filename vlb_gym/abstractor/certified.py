"""Certified synthesis, intent first: a promise, its least witness, a search, a certificate.

:func:`certify_promise` is the pipeline for one promise (an expert's ``--promise``, or the one
the model's drafts agree on):

1. the promise is tried on the env's least behaviors (stop at once, sense here, ...) on the
   screening episodes (:meth:`~vlb_gym.abstractor.search.Search.witnesses`): one that keeps it
   is shown with the promise when ``confirm`` asks the user ("a behavior that keeps this
   promise: ... Is that what you meant?");
2. the search finds the cheapest behavior that keeps it on the screening episodes (a root seed
   drawn afresh), re-run through the package's runtime;
3. the behavior is certified by a fixed-N campaign on fresh seeds
   (:mod:`~vlb_gym.abstractor.certify`); one that fails sends the search on with the time it
   has left (``time_limit`` bounds the search, not the campaigns: a scoop's certification
   takes minutes), up to :data:`~vlb_gym.abstractor.certify.ATTEMPTS` certifications, whose
   union bound the confidence accounts for. The document saved carries its certificate.

:func:`synthesize_certified` puts a language model first: it writes the promise ``drafts``
times, each shown other worked examples of the env's bank
(:func:`~vlb_gym.abstractor.intent.draft_promise`); a draft that a least behavior keeps is sent
back once with that behavior (the request may ask for more); the search runs for each distinct
promise, every behavior found is screened against every promise, and the behavior kept by the
promises of most weight (1/(k+1) for each draft k that wrote it; drafts no least behavior
keeps count double; among equals, the one that comes nearer the promises it does not keep,
then the cheaper) is certified against the tightest promise it keeps (kept by the fewest of
the behaviors found). A promise whose behavior would still keep it after one more step of a
least behavior does not say when to stop: where the env's judge can tell what held before a
behavior's last step, the same promise kept *as soon as* it holds is searched too and counts
for its draft in its place (the loose form alone, half).

Randomness is recorded: the transcript holds the seeds of the screening and certification
campaigns and how many programs each search built, so that a replay (``seeds`` and
``budgets`` from the transcript) tries the same programs and runs the same episodes.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.core.spec import Certificate, Promise

from .backends import ChatBackend
from .certify import ATTEMPTS, Certification, certify
from .intent import draft_promise
from .search import Found, Search, fresh_seed

DRAFTS = 4
ROUNDS_PER_DRAFT = 2
TIME_LIMIT = 240.0

Confirm = Callable[[Promise, list[str]], bool]


@dataclass
class Seeds:
    """The root seeds a run uses: fresh from the OS unless given (a replay, a test)."""

    screen: list[int] = field(default_factory=list)
    certify: list[int] = field(default_factory=list)

    def next_screen(self, k: int) -> int:
        while len(self.screen) <= k:
            self.screen.append(fresh_seed())
        return self.screen[k]

    def next_certify(self, k: int) -> int:
        while len(self.certify) <= k:
            self.certify.append(fresh_seed())
        return self.certify[k]


@dataclass
class CertifiedSynthesis:
    """What the pipeline got: the confirmed ``promise``, the certified ``document`` (with its
    certificate; None where it got none), the behavior in words, whether the user declined,
    and the transcript."""

    request: str
    promise: Promise | None
    document: dict[str, Any] | None
    words: str | None
    declined: bool
    transcript: dict[str, Any]
    witnesses: list[str] = field(default_factory=list)

    @property
    def certified(self) -> bool:
        return self.document is not None

    @property
    def certificate(self) -> Certificate | None:
        return None if self.document is None else Certificate(**self.document["certificate"])


def _transcript(env_id: str, request: str, pipeline: str, backend: str) -> dict[str, Any]:
    return {"env_id": env_id, "request": request, "backend": backend, "pipeline": pipeline,
            "drafts": [], "finds": [], "consensus": [], "certifications": [], "seeds": {}}


def _find_record(promise: Promise, search: Search, found: Found | None) -> dict[str, Any]:
    tally = search.tally
    return {"promise": promise.expr, "as_soon_as": promise.as_soon_as,
            "screen_seed": search.screen_seed,
            "program": found.program.words() if found else None,
            "built": tally.built, "distinct": tally.distinct, "judged": tally.judged,
            "seconds": round(tally.seconds, 2), "failures": tally.failures[:3]}


class _Certifier:
    """Searches and certifications of one request, sharing its seeds, budgets and
    transcript."""

    def __init__(self, env_id: str, request: str, name: str, transcript: dict[str, Any],
                 seeds: Seeds, budgets: Sequence[int] | None, env_kwargs: dict[str, Any],
                 workers: int, library: BehaviorLibrary | None):
        self.env_id, self.request, self.name = env_id, request, name
        self.transcript, self.seeds, self.budgets = transcript, seeds, budgets
        self.env_kwargs, self.workers, self.library = env_kwargs, workers, library
        self.searches: list[Search] = []
        self.interface: Any = None

    def search(self, promise: Promise) -> Search:
        k = len(self.searches)
        search = Search(self.env_id, promise, self.request, self.env_kwargs,
                        self.seeds.next_screen(k), library=self.library, name=self.name)
        self.searches.append(search)
        return search

    def find(self, search: Search, time_limit: float, skip: frozenset[str] = frozenset()
             ) -> Found | None:
        k = len(self.transcript["finds"])
        if self.budgets is None:
            found = search.find(time_limit, skip=skip)
        else:
            budget = self.budgets[k] if k < len(self.budgets) else 0
            found = search.find(float("inf"), max_programs=budget, skip=skip)
        self.transcript["finds"].append(_find_record(search.promise, search, found))
        return found

    def certify(self, search: Search, found: Found) -> tuple[dict[str, Any], Certification]:
        document = search.document(found, self.name, self.request.strip()[:300])
        why = search.rescreen(document)
        attempt = len(self.transcript["certifications"])
        seed = self.seeds.next_certify(attempt)
        record: dict[str, Any] = {"program": found.program.words(),
                                  "promise": search.promise.expr,
                                  "as_soon_as": search.promise.as_soon_as, "seed": seed}
        self.transcript["certifications"].append(record)
        if why is not None:  # the runtime and the search disagree: not certified, and said
            record.update(successes=0, episodes=0, rescreen=why)
            return document, None  # type: ignore[return-value]
        certification = certify(self.env_id, document, seed, self.env_kwargs,
                                workers=self.workers)
        record.update(successes=certification.successes, episodes=certification.episodes)
        if not certification.passed:  # what it failed on, the search now screens
            record["learned"] = certification.failed_seeds
            search.learn(certification.failed_seeds)
        return document, certification

    def close(self) -> None:
        for search in self.searches:
            search.close()


def certify_promise(env_id: str, request: str, promise: Promise, confirm: Confirm,
                    name: str = "synthesized", time_limit: float = TIME_LIMIT,
                    seeds: Seeds | None = None, budgets: Sequence[int] | None = None,
                    env_kwargs: dict[str, Any] | None = None, workers: int = 1,
                    library: BehaviorLibrary | None = None) -> CertifiedSynthesis:
    """The pipeline for one promise (see the module's docstring); programs may run the
    behaviors of ``library`` as a whole."""
    started = time.perf_counter()
    transcript = _transcript(env_id, request, "promise", "none")
    run = _Certifier(env_id, request, name, transcript, seeds or Seeds(), budgets,
                     dict(env_kwargs or {}), workers, library)
    try:
        search = run.search(promise)
        witnesses = search.witnesses()
        transcript["witnesses"] = witnesses
        if not confirm(promise, witnesses):
            transcript["declined"] = promise.model_dump()
            return _ended(request, promise, None, None, True, transcript, started, witnesses)
        skip: set[str] = set()
        while len(transcript["certifications"]) < ATTEMPTS:
            left = time_limit - search.tally.seconds  # the search's time: not the campaigns'
            found = run.find(search, max(left, 0.0), frozenset(skip))
            if found is None:
                break
            skip.add(found.program.words())
            document, certification = run.certify(search, found)
            if certification is not None and certification.passed:
                document["certificate"] = certification.certificate.model_dump()
                return _ended(request, promise, document, found.program.words(), False,
                              transcript, started, witnesses)
    finally:
        transcript["seeds"] = {"screen": run.seeds.screen, "certify": run.seeds.certify}
        run.close()
    return _ended(request, promise, None, None, False, transcript, started, witnesses)


def synthesize_certified(env_id: str, request: str, backend: ChatBackend, confirm: Confirm,
                         name: str = "synthesized", drafts: int = DRAFTS,
                         time_limit: float = TIME_LIMIT, seeds: Seeds | None = None,
                         budgets: Sequence[int] | None = None,
                         env_kwargs: dict[str, Any] | None = None, workers: int = 1,
                         library: BehaviorLibrary | None = None) -> CertifiedSynthesis:
    """The model-first pipeline (see the module's docstring)."""
    started = time.perf_counter()
    transcript = _transcript(env_id, request, "intent-first", backend.name)
    run = _Certifier(env_id, request, name, transcript, seeds or Seeds(), budgets,
                     dict(env_kwargs or {}), workers, library)
    try:
        promises, weights, kept = _drafts(run, backend, drafts)
        found: list[tuple[Found, Search]] = []
        tightened: dict[int, int] = {}  # a promise's index -> its as-soon-as form's
        per_promise = time_limit / 2 / max(len(promises), 1)
        for promise in list(promises):
            search = next(s for s in run.searches if s.promise == promise)
            result = run.find(search, per_promise)
            if result is None:
                continue
            if all(result.program != f.program for f, _ in found):
                found.append((result, search))
            tight = _as_soon_as(run, search, result)
            if tight is not None:
                tightened[promises.index(promise)] = len(promises)
                promises.append(tight.promise)
                weights.append(weights[promises.index(promise)])
                kept.append(tight.witnesses())
                tighter = run.find(tight, per_promise)
                if tighter is not None and all(tighter.program != f.program for f, _ in found):
                    found.append((tighter, tight))
        ranked = []
        keepers = [0] * len(run.searches)  # how many behaviors found keep each promise
        for result, search in found:
            grades = [other.grade(result.program) for other in run.searches]
            keeps = [k for k, (keep, _) in enumerate(grades) if keep]
            transcript["consensus"].append({"program": result.program.words(), "keeps": keeps})
            for k in keeps:
                keepers[k] += 1
            if keeps:
                score = sum(_weight(k, keeps, weights, kept, tightened) for k in keeps)
                near = sum(weights[k] * close for k, (keep, close) in enumerate(grades)
                           if not keep)  # how near it comes to the promises it does not keep
                ranked.append((-score, -near, result.cost, result, keeps))
        ranked.sort(key=lambda r: r[:3])
        declined: list[int] = []  # promises (their searches' indices) the user declined
        for *_, result, keeps in ranked:
            keeps = sorted(keeps, key=lambda k: (  # the tightest first
                keepers[k], not run.searches[k].promise.as_soon_as, k))
            if len(transcript["certifications"]) >= ATTEMPTS:
                break
            first = None  # the earliest promise it keeps that the user confirms
            for k in keeps:
                if k in declined:
                    continue
                if confirm(run.searches[k].promise, kept[k]):
                    first = k
                    break
                declined.append(k)  # a declined promise gives way to the next
            if first is None:
                continue
            search = run.searches[first]
            document, certification = run.certify(search, result)
            if certification is not None and certification.passed:
                document["certificate"] = certification.certificate.model_dump()
                return _ended(request, search.promise, document, result.program.words(),
                              False, transcript, started, kept[first])
        if declined and not transcript["certifications"]:
            promise = run.searches[declined[0]].promise
            transcript["declined"] = promise.model_dump()
            return _ended(request, promise, None, None, True, transcript, started,
                          kept[declined[0]])
        promise = promises[0] if promises else None
        return _ended(request, promise, None, None, False, transcript, started,
                      kept[0] if kept else [])
    finally:
        transcript["seeds"] = {"screen": run.seeds.screen, "certify": run.seeds.certify}
        run.close()


def _drafts(run: _Certifier, backend: ChatBackend, drafts: int
            ) -> tuple[list[Promise], list[float], list[list[str]]]:
    """The distinct promises the model wrote, their weights, and the least behaviors keeping
    each (a draft kept by one is asked again once, with it)."""
    promises: list[Promise] = []
    weights: list[float] = []
    kept: list[list[str]] = []
    transcript = run.transcript
    for k in range(drafts):
        interface = _interface(run)
        draft = draft_promise(run.request, interface, backend, ROUNDS_PER_DRAFT, attempt=k)
        record: dict[str, Any] = {"rounds": draft.rounds,
                                  "promise": draft.promise and draft.promise.model_dump()}
        transcript["drafts"].append(record)
        promise = draft.promise
        if promise is not None and promise.expr in [p.expr for p in promises]:
            weights[[p.expr for p in promises].index(promise.expr)] += 1 / (k + 1)  # agreement
        elif promise is not None:
            search = run.search(promise)
            witnesses = search.witnesses()
            if witnesses:
                again = draft_promise(run.request, interface, backend, 1, attempt=k,
                                      rejected=(promise.expr, _too_weak(witnesses[0])))
                record["witnessed"] = {"witnesses": witnesses, "rounds": again.rounds,
                                       "promise": again.promise and again.promise.model_dump()}
                if again.promise is not None and again.promise.expr not in {
                        p.expr for p in promises} | {promise.expr}:
                    stronger = run.search(again.promise)
                    if not stronger.witnesses():
                        run.searches.remove(search)
                        search.close()
                        search, promise, witnesses = stronger, again.promise, []
                    else:
                        run.searches.remove(stronger)
                        stronger.close()
            promises.append(promise)
            weights.append(1 / (k + 1))
            kept.append(witnesses)
        if draft.rounds[-1]["layer"] == "backend":
            break
    return promises, weights, kept


def _weight(k: int, keeps: list[int], weights: list[float], kept: list[list[str]],
            tightened: dict[int, int]) -> float:
    """What keeping promise ``k`` adds to a behavior's score (it keeps ``keeps``): the
    promise's weight, doubled if no least behavior keeps it; a draft whose as-soon-as form was
    searched counts once, through that form, and half when only its loose form is kept."""
    weight = weights[k] * (1 if kept[k] else 2)
    if k not in tightened:
        return weight
    return 0.0 if tightened[k] in keeps else weight / 2


def _as_soon_as(run: _Certifier, search: Search, found: Found) -> Search | None:
    """The search for ``search``'s promise kept as soon as it holds, when ``found`` keeps it
    and still would after one more step of a least behavior (the promise does not say when to
    stop) and the env can judge that; else None."""
    promise = search.promise
    if promise.as_soon_as or not search.interface.make_judge().rewinds:
        return None
    overrun = search.overrun(found.program)
    if overrun is None:
        return None
    run.transcript.setdefault("overruns", []).append(
        {"promise": promise.expr, "program": found.program.words(), "then": overrun})
    return run.search(promise.model_copy(update={"as_soon_as": True}))


def _too_weak(witness: str) -> str:
    return (f"a behavior that only does this keeps it: {witness}. If the task asks for more "
            "than that, the promise must fail for such a behavior: say what the task asks.")


def _interface(run: _Certifier) -> Any:
    """The env the model's promises are checked against (made once)."""
    if run.interface is None:
        from vlb_gym.envs.modules import make_primitive_env

        run.interface = make_primitive_env(run.env_id, run.env_kwargs).unwrapped
    return run.interface


def _ended(request: str, promise: Promise | None, document: dict[str, Any] | None,
           words: str | None, declined: bool, transcript: dict[str, Any], started: float,
           witnesses: list[str]) -> CertifiedSynthesis:
    transcript["seconds"] = round(time.perf_counter() - started, 1)
    return CertifiedSynthesis(request, promise, document, words, declined, transcript,
                              witnesses)
