"""Verification campaigns: N i.i.d. episodes -> a probabilistic guarantee.

One pipeline: a :class:`CampaignConfig` names the campaign; :class:`Campaign` prepares it once
(the env made and checked, the policy loaded and checked, the plan made: what a store records
first); its episodes run on a backend (:mod:`.backends`) and land, one
:class:`~.episode.EpisodeResult` each, in the caller's hands, the store and the JSONL export; a
:class:`~.report.Report` is built from the plan and the records alone.

Episode ``i`` of a campaign with seed ``s`` resets the environment with the ``i``-th child of
``numpy.random.SeedSequence(s)`` (as ``SeedSequence(s).spawn(N)[i]`` would give), so results do
not depend on the backend, the number of workers or the order in which episodes finish.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import importlib
import json
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, TypeVar

import numpy as np

from vlb_gym.envs.modules import make_primitive_env
from vlb_gym.wrappers.robustness import RobustnessWrapper

from . import backends
from .episode import EpisodeResult, Policy, run_episode
from .inputs import Inputs, ShippedRunner, capture, versions
from .methods import Method, method_named
from .policies import policy_loader
from .ray_connect import RayOptions
from .records import CampaignConfig, Plan, plan_from_json
from .report import Report
from .store import CampaignStore, StoreError


class Indexed(Protocol):
    """A result of the run of one index (an episode, a pair of episodes)."""

    @property
    def index(self) -> int: ...


class Decides(Protocol):
    """What :func:`feed_until_decided` asks of a statistical method."""

    name: str
    stops_early: bool

    @property
    def decided(self) -> bool: ...


def episode_seed(campaign_seed: int, index: int) -> int:
    """The reset seed of episode ``index``: the index-th spawned child of the campaign's seed."""
    child = np.random.SeedSequence(campaign_seed, spawn_key=(index,))
    return int(child.generate_state(1, dtype=np.uint64)[0])


def build(config: CampaignConfig, render_mode: str | None = None
          ) -> tuple[RobustnessWrapper, Policy]:
    """The wrapped environment (made and checked) and the policy, loaded by its kind's loader."""
    kwargs = config.env_kwargs if render_mode is None else {**config.env_kwargs,
                                                            "render_mode": render_mode}
    env = RobustnessWrapper(make_primitive_env(config.env_id, kwargs, config.env_modules))
    return env, policy_loader(config.policy.kind).load(config.policy, env)


def episode_runner(config: CampaignConfig,
                   built: tuple[RobustnessWrapper, Policy] | None = None
                   ) -> Callable[[int], EpisodeResult]:
    """What runs episode ``index`` of the campaign, on ``built`` (made now if not given): each
    worker of a backend calls this once."""
    env, policy = built or build(config)

    def run(index: int) -> EpisodeResult:
        return run_episode(env, policy, episode_seed(config.seed, index), index,
                           config.stop_on_failure)
    return run


class Campaign:
    """A campaign prepared once: the env made and reset, the policy loaded (a bad behavior file or
    agent fails here, before any episode), the env the policy was trained on checked, and the
    :attr:`plan` made. Close it when done (or use it as a context manager)."""

    def __init__(self, config: CampaignConfig):
        loader = policy_loader(config.policy.kind)
        trained = loader.trained_env(config.policy)
        if trained is not None:  # an agent runs on the env it was trained on
            env_id, kwargs = trained
            if env_id != config.env_id:
                raise ValueError(f"{config.policy.ref} was trained on {env_id}, "
                                 f"not {config.env_id}")
            config = dataclasses.replace(config, env_kwargs={**kwargs, **config.env_kwargs})
        self.config = config
        self.env, self.policy = build(config)
        self.files = loader.files(config.policy, self.policy)  # the user's inputs
        content = loader.content(config.policy, self.policy)
        self.plan: Plan = plan_from_json(json.dumps({  # as stored: tuples are lists
            **dataclasses.asdict(config), "content_sha256": content.pop("sha256"),
            "policy_content": content,
            "sampling_distribution": self.env.unwrapped.sampling_distribution(),
            "versions": versions()}))
        self.inputs: Inputs = capture(config, self.files, self.plan)  # what workers build from

    def __enter__(self) -> Campaign:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self.env.close()

    def episodes(self, indices: Sequence[int] | None = None, workers: int = 1,
                 backend: str = "process", ray: RayOptions | None = None
                 ) -> Iterator[EpisodeResult]:
        """Stream the results of ``indices`` (default: all N) as they finish, in index order on
        one worker. Closing the generator stops the workers."""
        indices = range(self.config.episodes) if indices is None else indices
        return run_where(ShippedRunner(self.config, self.inputs, episode_runner),
                         functools.partial(episode_runner, self.config, (self.env, self.policy)),
                         indices, workers, backend, ray, self.env.unwrapped.preload)

    def method(self) -> Method:
        """A fresh instance of the campaign's statistical method."""
        config = self.config
        return method_named(config.method)(config.epsilon, config.delta, config.episodes)

    def run(self, workers: int = 1, on_episode: Callable[[EpisodeResult], None] | None = None,
            store: CampaignStore | None = None, backend: str = "process",
            ray: RayOptions | None = None) -> Report:
        """Run the campaign and return its report; ``on_episode`` sees each result as it lands.

        Episodes run until the statistical method (:mod:`~vlb_gym.verify.methods`) has
        decided: all N for a fixed-N campaign; for a sequential one, episodes 0, 1, 2, ...
        until its anytime-valid test certifies or refutes ``P[success] >= 1 - epsilon`` at
        level ``delta``, or N (the cap) ran. A method that may stop early sees episodes in
        index order: with workers, results arrive unordered and it decides on the ordered
        prefix, so the decision, the stopping time and the episodes counted are the same
        whatever the backend and worker count; ``on_episode`` then sees exactly those
        episodes, in index order, and episodes that workers finished past the stopping time
        are discarded.

        With a ``store``, the plan is recorded first (or checked against the stored one), every
        episode is stored as it finishes (for a method that stops early, the prefix it saw),
        the episodes already stored are not run again, and the report is built from the
        store's episodes and this run's.
        """
        if _in_process(workers, backend):  # the env's slow imports, before the clock starts
            preload(self.env.unwrapped.preload)  # (workers get them from the forkserver)
        started = time.perf_counter()
        method = self.method()
        results: list[EpisodeResult] = []
        if store is not None:
            store.start(self.plan)
            stored = self.stored(store)
            results = stored[:method.feed(r.success for r in stored)]
        resumed = len(results)
        consumers = [f for f in (store.add if store is not None else None, on_episode) if f]
        if not method.decided:
            todo = Remaining(self.config.episodes, frozenset(r.index for r in results))
            results += self._feed(method, todo, workers, backend, ray, consumers)
        return Report.build(self.plan, results, time.perf_counter() - started, workers, backend,
                            None if store is None else str(store.path), len(results) - resumed)

    def open_store(self, path: str | Path) -> CampaignStore:
        """The store at ``path``, holding this campaign (see :func:`open_store`)."""
        return open_store(CampaignStore, path, self)

    def stored(self, store: CampaignStore) -> list[EpisodeResult]:
        """The episodes ``store`` holds, checked against what the method needs (StoreError):
        a method that stops early saw its episodes in index order, so they are 0..k-1."""
        return stored_prefix(store, method_named(self.config.method))

    def _feed(self, method: Method, todo: Remaining, workers: int, backend: str,
              ray: RayOptions | None, consumers: list[Callable[[EpisodeResult], None]]
              ) -> list[EpisodeResult]:
        def take(result: EpisodeResult) -> None:
            method.observe(result.success)
            for consume in consumers:
                consume(result)

        return feed_until_decided(self.episodes(todo, workers, backend, ray), method,
                                  todo, take, lightened)


R = TypeVar("R", bound=Indexed)


@dataclass(frozen=True)
class Remaining:
    """The indices ``0 .. total - 1`` not in ``done`` (a subset of them), in order, listed as
    they are taken: a campaign's memory does not grow with its N."""

    total: int
    done: frozenset[int] = frozenset()

    def __iter__(self) -> Iterator[int]:
        return (i for i in range(self.total) if i not in self.done)

    @property
    def size(self) -> int:
        """How many (a Python integer: ``len()`` cannot pass 2**63 - 1)."""
        return self.total - len(self.done)

    def __len__(self) -> int:
        return self.size


def lightened(result: EpisodeResult) -> EpisodeResult:
    """What a campaign keeps of a finished episode for its report: a success without its steps
    and start (the store and the export have them), a failure whole."""
    if not result.success:
        return result
    return dataclasses.replace(result, steps=(), start={})


def run_where(setup: Callable[[], Callable[[int], R]],
              setup_here: Callable[[], Callable[[int], R]], indices: Sequence[int],
              workers: int, backend: str, ray: RayOptions | None,
              env_preload: Sequence[str]) -> Iterator[R]:
    """Stream ``runner(i)`` for ``indices`` from the backend: ``setup_here`` (which reuses
    what this process built) when they run in this process, ``setup`` in each worker."""
    if not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be a positive integer (got {workers!r})")
    if _in_process(workers, backend):
        return backends.run_indices(setup_here, indices, backend="serial")
    return backends.run_indices(setup, indices, backend=backend, workers=workers,
                                ray=ray,
                                preload=["vlb_gym.verify.campaign", *env_preload])


def feed_until_decided(stream: Iterator[R], method: Decides, todo: Iterable[int],
                       take: Callable[[R], None], keep: Callable[[R], R] = lambda r: r
                       ) -> list[R]:
    """Hand the results of ``stream`` (of episodes ``todo``) to ``take`` until ``method`` has
    decided: as they finish, or in index order (``todo``'s) if it may stop early; what
    ``keep`` keeps of the results taken. Closes the stream (stopping the workers) when the
    method decided early."""
    used: list[R] = []
    waiting: dict[int, R] = {}
    order = iter(todo)
    following = next(order, None)

    def use(result: R) -> None:
        take(result)
        used.append(keep(result))

    try:
        for result in stream:
            if not method.stops_early:
                use(result)
                continue
            waiting[result.index] = result
            while not method.decided and following in waiting:
                use(waiting.pop(following))
                following = next(order, None)
            if method.decided:
                break
    finally:
        stream.close()
    return used


S = TypeVar("S", bound=CampaignStore)


def open_store(kind: type[S], path: str | Path, prepared: Any) -> S:
    """The store of ``kind`` at ``path`` (made if missing, locked for this process), holding
    the plan of ``prepared`` (a campaign or a comparison), recorded now if the store is new:
    StoreError if it holds another plan, or records the method cannot use."""
    store = kind(path)
    try:
        store.start(prepared.plan)
        prepared.stored(store)
    except BaseException:
        store.close()
        raise
    return store


def stored_prefix(store: CampaignStore, method: Decides) -> list[Any]:
    """The records ``store`` holds, checked against what ``method`` needs (StoreError): a
    method that stops early saw them in index order, so they are 0..k-1."""
    stored = store.results()
    if method.stops_early and [r.index for r in stored] != list(range(len(stored))):
        raise StoreError(f"{store.path}: the stored episodes are not the first "
                         f"{len(stored)} of the campaign, which its {method.name} test "
                         "needs in order: the store was edited or damaged")
    return stored


def preload(modules: Sequence[str]) -> None:
    """Import ``modules``, skipping any that cannot be imported, as the forkserver does: they are
    a speed-up the env does without (the grid's compiled navigate needs the extra ``fast``)."""
    for module in modules:
        with contextlib.suppress(ImportError):
            importlib.import_module(module)


def _in_process(workers: int, backend: str) -> bool:
    """Whether a campaign's episodes run in this process."""
    return backend == "serial" or (backend == "process" and workers == 1)


def run_campaign(config: CampaignConfig, workers: int = 1,
                 on_episode: Callable[[EpisodeResult], None] | None = None,
                 store: CampaignStore | None = None, backend: str = "process") -> Report:
    """Prepare and run a campaign (see :meth:`Campaign.run`)."""
    with Campaign(config) as campaign:
        return campaign.run(workers, on_episode, store, backend)


def report_from_store(store: CampaignStore) -> Report:
    """The report of the campaign in ``store``, rebuilt from the store alone (complete or not:
    ``episodes`` is the number stored). The store does not record how the campaign ran
    (workers, backend): those are None, and the time is the sum of the episodes' own seconds."""
    return report_and_records(store)[0]


def report_and_records(store: CampaignStore) -> tuple[Report, Plan, list[EpisodeResult]]:
    """:func:`report_from_store`, with the plan and the records it was built from (read once:
    a campaign may be adding records meanwhile)."""
    plan = store.plan()
    if plan is None:
        raise StoreError(f"{store.path}: the store holds no campaign yet")
    results = stored_prefix(store, method_named(plan.method))
    if not results:
        raise StoreError(f"{store.path}: no episode is stored yet")
    return (Report.build(plan, results, sum(r.seconds for r in results), None, None,
                         str(store.path)), plan, results)
