"""Search for a behavior whose campaign certifies a promise, then certify it on fresh seeds.

:func:`search` walks an env's :mod:`~vlb_gym.abstractor.sketches` space (fewest phases first)
with the confirmed promise attached to every candidate. Each candidate is compiled (the
package's own checks) and *screened*: up to ``screen_episodes`` episodes of campaign seed
:data:`SCREEN_SEED`, stopped at the first one whose rho_B is -1 (a certificate or the promise
failed). The first candidate that passes screening is *certified*: a fixed-N campaign on fresh
seeds (root seed ``CERTIFY_SEED + attempt``), never the screening seeds, since the winner was
chosen on those. A candidate that fails certification sends the search on, at most
``attempts`` times; the confidence reported is that of the whole procedure: with ``attempts``
certification tests of N episodes each, a behavior below 1 - eps passes one with probability at
most ``attempts * (1 - eps)**N`` (a union bound), so N is chosen to make that at most ``delta``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

from vlb_gym.core.library import BehaviorLibrary, compile_spec
from vlb_gym.core.runtime import BehaviorPolicy
from vlb_gym.core.spec import BehaviorSpecError, Promise, spec_from_data
from vlb_gym.envs.modules import make_primitive_env
from vlb_gym.verify.campaign import episode_seed
from vlb_gym.verify.episode import EpisodeResult, run_episode
from vlb_gym.wrappers.robustness import RobustnessWrapper

from .sketches import SPACES, Candidate, candidates, numbers

SCREEN_SEED = 0
CERTIFY_SEED = 1_000_003
EPSILON = 0.05
DELTA = 0.01
ATTEMPTS = 3
SCREEN_EPISODES = 30
MAX_CANDIDATES = 20_000
MAX_FAILURES_KEPT = 5


def certification_episodes(epsilon: float = EPSILON, delta: float = DELTA,
                           attempts: int = ATTEMPTS) -> int:
    """The least N with ``attempts * (1 - epsilon)**N <= delta``."""
    return math.ceil(math.log(delta / attempts) / math.log(1 - epsilon))


@dataclass
class Certification:
    """A fixed-N campaign of a chosen candidate on fresh seeds."""

    seed: int
    episodes: list[EpisodeResult]

    @property
    def successes(self) -> int:
        return sum(e.success for e in self.episodes)

    @property
    def passed(self) -> bool:
        return self.successes == len(self.episodes)


@dataclass
class SearchResult:
    """What :func:`search` found: the certified candidate (None if none), its certification,
    the procedure's confidence, how many candidates were tried, and the first failures seen
    (candidate label, what happened) for feedback."""

    candidate: Candidate | None
    certification: Certification | None
    confidence: float
    tried: int
    seconds: float
    failures: list[tuple[str, str]] = field(default_factory=list)
    certifications: list[tuple[str, int, int]] = field(default_factory=list)


class Screen:
    """Runs candidates on one env (made once) with a promise attached."""

    def __init__(self, env_id: str, library: BehaviorLibrary | None = None,
                 env_kwargs: dict[str, Any] | None = None):
        self.env = RobustnessWrapper(make_primitive_env(env_id, env_kwargs or {}))
        self.library = library or BehaviorLibrary(shipped=False)

    def compile(self, candidate: Candidate, promise: Promise) -> BehaviorPolicy:
        spec = spec_from_data({**candidate.document, "promise": promise.model_dump()},
                              "<candidate>")
        compiled = compile_spec(spec, self.env, "<candidate>", None, self.library,
                                names_only=True)
        return BehaviorPolicy(compiled, self.env.unwrapped)

    def run(self, policy: BehaviorPolicy, seed: int, episodes: int, stop: bool = True
            ) -> list[EpisodeResult]:
        results = []
        for index in range(episodes):
            result = run_episode(self.env, policy, episode_seed(seed, index), index)
            results.append(result)
            if stop and not result.success:
                break
        return results

    def close(self) -> None:
        self.env.close()


def find(env_id: str, request: str, promise: Promise, screen: Screen, name: str = "synthesized",
         screen_episodes: int = SCREEN_EPISODES, max_candidates: int = MAX_CANDIDATES,
         time_limit: float = 120.0, skip: frozenset[str] = frozenset()) -> SearchResult:
    """The first candidate of ``env_id``'s space (fewest phases first; keys in ``skip`` left
    out) that keeps ``promise`` and every certificate on the screening episodes; not yet
    certified."""
    if env_id not in SPACES:
        raise ValueError(f"{env_id} has no search space; known: {', '.join(SPACES)}")
    started = time.perf_counter()
    counts = numbers(request, promise.expr, promise.description)
    space = candidates(SPACES[env_id], env_id, name, request.strip()[:300], counts)
    result = SearchResult(None, None, 0.0, 0, 0.0)
    for candidate in space:
        if result.tried >= max_candidates or time.perf_counter() - started > time_limit:
            break
        if candidate.key in skip:
            continue
        result.tried += 1
        if passes(screen, candidate, promise, screen_episodes, result):
            result.candidate = candidate
            break
    result.seconds = time.perf_counter() - started
    return result


def passes(screen: Screen, candidate: Candidate, promise: Promise, episodes: int,
           notes: SearchResult | None = None) -> bool:
    """Whether ``candidate`` with ``promise`` attached keeps everything on the screening
    episodes (why not is noted in ``notes``)."""
    try:
        policy = screen.compile(candidate, promise)
    except BehaviorSpecError as exc:
        if notes is not None:
            _note(notes, candidate, f"does not compile: {exc}")
        return False
    ran = screen.run(policy, SCREEN_SEED, episodes)
    if not ran[-1].success and notes is not None:
        _note(notes, candidate, ran[-1].reason or "rho_B = -1")
    return ran[-1].success


def certify(screen: Screen, candidate: Candidate, promise: Promise, attempt: int,
            epsilon: float = EPSILON, delta: float = DELTA, attempts: int = ATTEMPTS
            ) -> Certification:
    """Certification campaign number ``attempt`` (0-based) of ``candidate``: fresh seeds,
    :func:`certification_episodes` episodes, none stopped early."""
    seed = CERTIFY_SEED + attempt
    policy = screen.compile(candidate, promise)
    return Certification(seed, screen.run(policy, seed,
                                          certification_episodes(epsilon, delta, attempts),
                                          stop=False))


def procedure_confidence(epsilon: float = EPSILON, delta: float = DELTA,
                         attempts: int = ATTEMPTS) -> float:
    """The confidence of a behavior that passed one of up to ``attempts`` certifications."""
    return 1 - attempts * (1 - epsilon) ** certification_episodes(epsilon, delta, attempts)


def search(env_id: str, request: str, promise: Promise, name: str = "synthesized",
           screen_episodes: int = SCREEN_EPISODES, attempts: int = ATTEMPTS,
           time_limit: float = 120.0, library: BehaviorLibrary | None = None) -> SearchResult:
    """Find and certify: the first candidates that pass screening are certified in turn, up to
    ``attempts`` of them (see the module's docstring)."""
    started = time.perf_counter()
    screen = Screen(env_id, library)
    tried, failures, skip = 0, [], set()
    certifications: list[tuple[str, int, int]] = []
    try:
        while len(certifications) < attempts:
            left = time_limit - (time.perf_counter() - started)
            found = find(env_id, request, promise, screen, name, screen_episodes,
                         time_limit=max(left, 0.0), skip=frozenset(skip))
            tried += found.tried
            failures = failures or found.failures
            if found.candidate is None:
                break
            skip.add(found.candidate.key)
            cert = certify(screen, found.candidate, promise, len(certifications),
                           attempts=attempts)
            certifications.append((found.candidate.label, cert.successes, len(cert.episodes)))
            if cert.passed:
                return SearchResult(found.candidate, cert, procedure_confidence(attempts=attempts),
                                    tried, time.perf_counter() - started, failures,
                                    certifications)
    finally:
        screen.close()
    return SearchResult(None, None, 0.0, tried, time.perf_counter() - started, failures,
                        certifications)


def _note(result: SearchResult, candidate: Candidate, why: str) -> None:
    if len(result.failures) < MAX_FAILURES_KEPT:
        result.failures.append((candidate.label, why))
