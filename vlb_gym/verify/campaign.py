"""Verification campaigns: N i.i.d. episodes -> a probabilistic guarantee.

Episode ``i`` of a campaign with seed ``s`` resets the environment with the ``i``-th child of
``numpy.random.SeedSequence(s)`` (as ``SeedSequence(s).spawn(N)[i]`` would give), so results do
not depend on the number of workers or on the order in which episodes finish.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import multiprocessing as mp
import platform
import signal
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import vlb_gym
from vlb_gym.core.compiler import CompiledBehavior
from vlb_gym.core.library import load_behavior, spec_json
from vlb_gym.envs.modules import import_env_module
from vlb_gym.wrappers import RobustnessWrapper

from . import bounds, sequential
from .episode import EpisodeResult, Policy, run_episode
from .store import CampaignStore, StoreError


@dataclass(frozen=True)
class CampaignConfig:
    """Everything that defines a campaign; N is fixed before it starts."""

    env_id: str
    behavior: str
    episodes: int
    epsilon: float = 0.05
    delta: float = 0.05
    seed: int = 0
    env_kwargs: dict[str, Any] = field(default_factory=dict)
    stop_on_failure: bool = True
    policy: bool = False  # ``behavior`` is the path of a trained agent (extra ``rl``)
    env_modules: tuple[str, ...] = ()  # modules that register the env (imported in workers too)

    def __post_init__(self) -> None:
        if not isinstance(self.episodes, int) or self.episodes < 1:
            raise ValueError(f"episodes must be a positive integer (got {self.episodes!r})")
        for name in ("epsilon", "delta"):
            value = getattr(self, name)
            if not 0 < value < 1:
                raise ValueError(f"{name} must lie strictly between 0 and 1 (got {value!r})")
        if not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"seed must be a non-negative integer (got {self.seed!r})")


def episode_seed(campaign_seed: int, index: int) -> int:
    """The reset seed of episode ``index``: the index-th spawned child of the campaign's seed."""
    child = np.random.SeedSequence(campaign_seed, spawn_key=(index,))
    return int(child.generate_state(1, dtype=np.uint64)[0])


def build(config: CampaignConfig) -> tuple[RobustnessWrapper, Policy]:
    """The wrapped environment and the policy (compiled behavior or trained agent)."""
    for module in config.env_modules:
        import_env_module(module)
    env = RobustnessWrapper(gym.make(config.env_id, **config.env_kwargs))
    if config.policy:
        from vlb_gym.baselines.train import SB3Policy
        return env, SB3Policy(config.behavior, env)
    return env, load_behavior(config.behavior, env)


_WORKER: tuple[CampaignConfig, RobustnessWrapper, Policy] | Exception | None = None


def _init_worker(config: CampaignConfig) -> None:
    global _WORKER
    # Ctrl-C reaches the whole process group: the parent handles it and terminates the pool
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        _WORKER = (config, *build(config))
    except Exception as exc:  # raised from the first task: a Pool restarts failing initializers
        _WORKER = exc


def _run_index(index: int) -> EpisodeResult:
    if isinstance(_WORKER, Exception):
        raise _WORKER
    config, env, policy = _WORKER
    return run_episode(env, policy, episode_seed(config.seed, index), index,
                       config.stop_on_failure)


def iter_episodes(config: CampaignConfig, workers: int = 1,
                  indices: list[int] | None = None) -> Iterator[EpisodeResult]:
    """Stream episode results as they finish (in index order for one worker); ``indices``
    (default: all N) are the episodes to run, e.g. those a resumed store lacks.

    Worker processes ignore SIGINT: a Ctrl-C raises ``KeyboardInterrupt`` in the caller only, and
    closing or leaving this generator terminates the pool.
    """
    if not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be a positive integer (got {workers!r})")
    indices = range(config.episodes) if indices is None else indices
    env, policy = build(config)  # also checks the behavior before any worker starts
    if workers == 1:
        for i in indices:
            yield run_episode(env, policy, episode_seed(config.seed, i), i, config.stop_on_failure)
        return
    env.close()
    chunk = max(1, min(64, len(indices) // (workers * 16)))
    # forkserver: workers fork from a clean server process, never from this one, which may hold
    # threads or a GL context (a forked EGL context deadlocks); vlb_gym is preloaded there so
    # workers start fast. Scripts that run campaigns with workers need a __main__ guard.
    if "forkserver" in mp.get_all_start_methods():
        context = mp.get_context("forkserver")
        context.set_forkserver_preload(["vlb_gym.verify.campaign"])
    else:
        context = mp.get_context("spawn")
    with context.Pool(workers, initializer=_init_worker, initargs=(config,)) as pool:
        yield from pool.imap_unordered(_run_index, indices, chunksize=chunk)


def sampling_distribution(config: CampaignConfig) -> str:
    """Words for the distribution the guarantee holds under (the env's own description)."""
    env = gym.make(config.env_id, **config.env_kwargs)
    text = env.unwrapped.sampling_distribution()
    env.close()
    return text


def failures_by_cause(results: list[EpisodeResult], examples: int = 3) -> list[dict[str, Any]]:
    """Failed episodes grouped by cause (which primitive's certificate or which part of it,
    inadmissible parameters, controller failures, behavior runtime errors, the evaluation budget,
    the step bound), most frequent first, each with a few example reset seeds for replays."""
    groups: dict[str, list[EpisodeResult]] = {}
    for result in sorted(results, key=lambda r: r.index):
        if not result.success:
            groups.setdefault(result.cause or "unknown", []).append(result)
    return [{"cause": cause, "count": len(failed), "seeds": [r.seed for r in failed[:examples]]}
            for cause, failed in sorted(groups.items(), key=lambda item: -len(item[1]))]


def build_report(config: CampaignConfig, results: list[EpisodeResult], seconds: float,
                 workers: int, distribution: str | None = None) -> dict[str, Any]:
    """The JSON report of a finished campaign (keys per ARCHITECTURE.md, plus context);
    ``distribution`` is the sampling distribution in words (asked of the env if not given)."""
    results = sorted(results, key=lambda r: r.index)
    n = len(results)
    failures = sum(not r.success for r in results)
    conf = bounds.confidence(n, failures, config.epsilon)
    low = bounds.lower_bound(n, failures, config.delta)
    distribution = distribution or sampling_distribution(config)
    return {
        "env_id": config.env_id,
        "behavior": config.behavior,
        "policy": config.policy,
        "episodes": n,
        "successes": n - failures,
        "failures": failures,
        "epsilon": config.epsilon,
        "confidence": conf,
        "delta": config.delta,
        "lower_bound": low,
        "seed": config.seed,
        "statement": (f"P[success] >= {bounds.one_minus_str(config.epsilon)} with confidence "
                      f"{bounds.floor_str(conf)}; P[success] >= {bounds.floor_str(low)} at "
                      f"confidence level {bounds.one_minus_str(config.delta)} "
                      "(one-sided Clopper-Pearson)"),
        "sampling_distribution": distribution,
        "env_kwargs": config.env_kwargs,
        "env_modules": list(config.env_modules),
        "failed_episodes": [{"index": r.index, "seed": r.seed, "reason": r.reason,
                             "cause": r.cause} for r in results if not r.success],
        "failures_by_cause": failures_by_cause(results),
        "mean_primitives": float(np.mean([r.primitives for r in results])),
        "wall_seconds": seconds,
        "episodes_per_second": n / seconds if seconds > 0 else None,
        "workers": workers,
        "machine": f"{platform.machine()} {platform.system()}, {mp.cpu_count()} cpus, "
                   f"Python {platform.python_version()}",
    }


def run_campaign(config: CampaignConfig, workers: int = 1,
                 on_episode: Callable[[EpisodeResult], None] | None = None,
                 store: CampaignStore | None = None,
                 plan: dict[str, Any] | None = None) -> dict[str, Any]:
    """Run all N episodes and return the report; ``on_episode`` sees each result as it lands.

    With a ``store``, the plan (``plan``, if the caller made it already with
    :func:`campaign_plan`) is recorded first (or checked against the stored one), every
    episode is stored as it finishes, the episodes already stored are not run again, and the
    report is built from the store.
    """
    started = time.perf_counter()
    if store is None:
        results = []
        for result in iter_episodes(config, workers):
            results.append(result)
            if on_episode is not None:
                on_episode(result)
        return build_report(config, results, time.perf_counter() - started, workers)
    plan = plan or campaign_plan(config)
    store.start(plan)
    done = store.done()
    todo = [i for i in range(config.episodes) if i not in done]
    if todo:
        for result in iter_episodes(config, workers, todo):
            store.add(result)
            if on_episode is not None:
                on_episode(result)
    return build_report(config, store.results(), time.perf_counter() - started, workers,
                        plan["sampling_distribution"])


def campaign_plan(config: CampaignConfig) -> dict[str, Any]:
    """What defines a campaign, as stored first in its store: the config, a digest of the
    behavior (its whole tree of files) or of the agent, the sampling distribution, versions."""
    digest = hashlib.sha256()
    if config.policy:
        path = Path(config.behavior)
        digest.update((path if path.suffix == ".zip" else path.with_suffix(".zip")).read_bytes())
    else:
        env, policy = build(config)
        env.close()
        for behavior in _behavior_tree(policy.behavior):
            digest.update(spec_json(behavior.spec).encode())
    plan = {**dataclasses.asdict(config), "content_sha256": digest.hexdigest(),
            "sampling_distribution": sampling_distribution(config),
            "versions": {"vlb_gym": vlb_gym.__version__, "gymnasium": gym.__version__,
                         "numpy": np.__version__, "python": platform.python_version()}}
    return json.loads(json.dumps(plan))  # as stored: tuples become lists


def _behavior_tree(behavior: CompiledBehavior) -> list[CompiledBehavior]:
    """A compiled behavior and its sub-behaviors, each once, in a fixed order."""
    seen: dict[str, CompiledBehavior] = {}
    stack = [behavior]
    while stack:
        current = stack.pop()
        if current.source not in seen:
            seen[current.source] = current
            stack.extend(n.child for n in current.nodes.values() if n.child is not None)
    return [seen[source] for source in sorted(seen)]


def report_from_store(store: CampaignStore) -> dict[str, Any]:
    """The report of the campaign in ``store``, rebuilt from the store alone (complete or not:
    ``episodes`` is the number stored). Timing is the sum of the episodes' own seconds."""
    plan = store.plan()
    if plan is None:
        raise StoreError(f"{store.path}: the store holds no campaign yet")
    names = {f.name for f in dataclasses.fields(CampaignConfig)}
    config = CampaignConfig(**{k: (tuple(v) if k == "env_modules" else v)
                               for k, v in plan.items() if k in names})
    results = store.results()
    if not results:
        raise StoreError(f"{store.path}: no episode is stored yet")
    report = build_report(config, results, sum(r.seconds for r in results), 1,
                          plan["sampling_distribution"])
    report["planned_episodes"] = config.episodes
    return report


def run_sequential(config: CampaignConfig, max_episodes: int | None = None, workers: int = 1,
                   on_episode: Callable[[EpisodeResult], None] | None = None) -> dict[str, Any]:
    """A sequential campaign (``vlb verify --sequential``): episodes 0, 1, 2, ... until the
    anytime-valid test of :mod:`vlb_gym.verify.sequential` certifies or refutes
    ``P[success] >= 1 - config.epsilon`` at level ``config.delta``, or ``max_episodes`` ran
    (default :func:`~vlb_gym.verify.sequential.default_max_episodes`); ``config.episodes`` is
    ignored. The test sees episodes in index order: with workers, results arrive unordered and
    the test decides on the ordered prefix, so the decision, the stopping time and the episodes
    counted are the same whatever the worker count; ``on_episode`` sees exactly those episodes,
    in index order. Episodes that workers finished past the stopping time are discarded.
    """
    if max_episodes is None:
        max_episodes = sequential.default_max_episodes(config.epsilon, config.delta)
    if not isinstance(max_episodes, int) or max_episodes < 1:
        raise ValueError(f"max_episodes must be a positive integer (got {max_episodes!r})")
    capped = dataclasses.replace(config, episodes=max_episodes)
    test = sequential.SequentialTest(config.epsilon, config.delta)
    started = time.perf_counter()
    used: list[EpisodeResult] = []
    waiting: dict[int, EpisodeResult] = {}
    stream = iter_episodes(capped, workers)
    try:
        for result in stream:
            waiting[result.index] = result
            while test.decision is None and len(used) in waiting:
                ready = waiting.pop(len(used))
                used.append(ready)
                if on_episode is not None:
                    on_episode(ready)
                test.update(ready.success)
            if test.decision is not None:
                break
    finally:
        stream.close()  # terminates the pool when the test stopped early
    seconds = time.perf_counter() - started
    report = build_report(capped, used, seconds, workers)
    low, high = test.bounds()
    decision = test.decision or "undecided"
    eps, delta = bounds.one_minus_str(config.epsilon), bounds.one_minus_str(config.delta)
    words = {
        "certified": f"certified: P[success] >= {eps} at level {delta}, anytime-valid "
                     f"(stopped after {test.n} episodes)",
        "refuted": f"refuted: P[success] < {eps} at level {delta}, anytime-valid "
                   f"(stopped after {test.n} episodes)",
        "undecided": f"undecided after {test.n} episodes (the cap): nothing is certified",
    }[decision]
    fixed = {"confidence": report["confidence"], "lower_bound": report["lower_bound"],
             "note": "Clopper-Pearson figures of the episodes run, for description only: the "
                     "number of episodes was not fixed in advance, so they are no guarantee"}
    report.update({
        "mode": "sequential",
        "test": sequential.TEST_NAME,
        "prior": list(sequential.prior(config.epsilon)),
        "guarantee": sequential.guarantee(config.epsilon, config.delta),
        "decision": decision,
        "stopped_at": test.stopped_at,
        "max_episodes": max_episodes,
        "fixed_n_plan": bounds.min_episodes(config.epsilon, 1.0 - config.delta, 0),
        # the fixed-N keys, with their anytime-valid meaning in this mode
        "confidence": test.confidence(),
        "lower_bound": low,
        "upper_bound": high,
        "statement": (f"{words}; P[success] in [{bounds.floor_str(low)}, "
                      f"{_ceil_str(high)}] at confidence level {delta}, simultaneously for all "
                      f"n ({sequential.TEST_NAME})"),
        "fixed_n_description": fixed,
    })
    return report


def _ceil_str(x: float, digits: int = 5) -> str:
    """An upper bound in words, rounded up (never below the number)."""
    from decimal import ROUND_CEILING, Decimal
    return str(Decimal(repr(x)).quantize(Decimal(1).scaleb(-digits), rounding=ROUND_CEILING))
