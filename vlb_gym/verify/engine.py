"""The campaign engine: one run loop, one store and resume path, one report-from-store path, for
every kind of study whose unit is run by index (an episode for a :class:`~.campaign.Campaign`,
a pair of episodes for a :class:`~.comparison.Comparison`).

A kind of study is a subclass of :class:`Study` that says what its unit is: how the units of
some indices run on a backend (:meth:`Study.units`), what its statistical method observes of a
unit (:meth:`Study.outcome`), its method from its plan, its report from its plan and units, and
the store kind that keeps it. :meth:`Study.run` runs units until the method has decided, storing
and resuming the same way for every kind; :meth:`Study.from_store` rebuilds a report from a
store alone.
"""

from __future__ import annotations

import abc
import contextlib
import importlib
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Generic, Protocol, TypeVar

from . import backends
from .methods import Decider
from .ray_connect import RayOptions
from .records import EpisodeResult
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


R = TypeVar("R", bound=Indexed)
Rep = TypeVar("Rep")  # a kind of study's report


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


def feed_until_decided(stream: Iterator[R], method: Decides, todo: Iterable[int],
                       take: Callable[[R], None], keep: Callable[[R], R] = lambda r: r
                       ) -> list[R]:
    """Hand the results of ``stream`` (of units ``todo``) to ``take`` until ``method`` has
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


def in_process(workers: int, backend: str) -> bool:
    """Whether a study's units run in this process."""
    return backend == "serial" or (backend == "process" and workers == 1)


def run_where(setup: Callable[[], Callable[[int], R]],
              setup_here: Callable[[], Callable[[int], R]], indices: Sequence[int],
              workers: int, backend: str, ray: RayOptions | None,
              env_preload: Sequence[str]) -> Iterator[R]:
    """Stream ``runner(i)`` for ``indices`` from the backend: ``setup_here`` (which reuses
    what this process built) when they run in this process, ``setup`` in each worker."""
    if not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be a positive integer (got {workers!r})")
    if in_process(workers, backend):
        return backends.run_indices(setup_here, indices, backend="serial")
    return backends.run_indices(setup, indices, backend=backend, workers=workers,
                                ray=ray,
                                preload=["vlb_gym.verify.campaign", *env_preload])


class Study(abc.ABC, Generic[R, Rep]):
    """A study prepared once (its :attr:`plan` made, its inputs checked) whose units ``R`` run by
    index until its statistical method has decided. Subclasses say what a unit is; the run loop,
    the store and resume rules and the report from a store are this class's, for every kind."""

    plan: Any
    #: the store kind that keeps this kind of study
    store_kind: ClassVar[type[CampaignStore]]
    #: what one unit is called in messages ("episode", "pair")
    unit: ClassVar[str]

    # -- what a kind of study says ---------------------------------------------------------------
    @classmethod
    @abc.abstractmethod
    def method_of(cls, plan: Any) -> Decider:
        """A fresh instance of the statistical method ``plan`` names, with its parameters."""

    @staticmethod
    @abc.abstractmethod
    def outcome(result: R) -> Any:
        """What the method observes of one unit (a success; a pair of successes)."""

    @staticmethod
    @abc.abstractmethod
    def seconds(result: R) -> float:
        """The unit's own wall time (what a report from a store counts as the study's time)."""

    @classmethod
    @abc.abstractmethod
    def report(cls, plan: Any, results: Sequence[R], seconds: float, workers: int | None,
               backend: str | None, store: str | None = None, ran: int | None = None) -> Rep:
        """The report of ``plan`` from ``results`` (``ran`` of them run now, the others
        resumed); ``workers`` and ``backend`` None for a report rebuilt from a store."""

    @abc.abstractmethod
    def units(self, indices: Sequence[int] | None = None, workers: int = 1,
              backend: str = "process", ray: RayOptions | None = None) -> Iterator[R]:
        """Stream the units of ``indices`` (default: all planned) as they finish."""

    @property
    @abc.abstractmethod
    def planned(self) -> int:
        """How many units the plan allows (all of them, or the cap of a method that stops
        early)."""

    @property
    @abc.abstractmethod
    def preloads(self) -> Sequence[str]:
        """Modules the envs import slowly, imported before the clock starts."""

    @staticmethod
    def lightened(result: R) -> R:
        """What the run keeps of a finished unit for its report (the store has it whole)."""
        return result

    # -- the engine ------------------------------------------------------------------------------
    def method(self) -> Decider:
        """A fresh instance of the study's statistical method."""
        return self.method_of(self.plan)

    def run(self, workers: int = 1, on_result: Callable[[R], None] | None = None,
            store: CampaignStore | None = None, backend: str = "process",
            ray: RayOptions | None = None) -> Rep:
        """Run the study and return its report; ``on_result`` sees each unit as it lands.

        Units run until the statistical method (:mod:`~vlb_gym.verify.methods`) has
        decided: all N for a fixed-N method; for a sequential one, units 0, 1, 2, ...
        until its anytime-valid test decides, or N (the cap) ran. A method that may stop
        early sees units in index order: with workers, results arrive unordered and it decides
        on the ordered prefix, so the decision, the stopping time and the units counted are the
        same whatever the backend and worker count; ``on_result`` then sees exactly those
        units, in index order, and units that workers finished past the stopping time are
        discarded.

        With a ``store``, the plan is recorded first (or checked against the stored one), every
        unit is stored as it finishes (for a method that stops early, the prefix it saw), the
        units already stored are not run again, and the report is built from the store's units
        and this run's.
        """
        if in_process(workers, backend):  # the envs' slow imports, before the clock starts
            preload(self.preloads)  # (workers get them from the forkserver)
        started = time.perf_counter()
        method = self.method()
        results: list[R] = []
        if store is not None:
            store.start(self.plan)
            stored = self.stored(store)
            results = stored[:method.feed(self.outcome(r) for r in stored)]
        resumed = len(results)
        consumers = [f for f in (store.add if store is not None else None, on_result) if f]

        def take(result: R) -> None:
            method.observe(self.outcome(result))
            for consume in consumers:
                consume(result)

        if not method.decided:
            todo = Remaining(self.planned, frozenset(r.index for r in results))
            results += feed_until_decided(self.units(todo, workers, backend, ray), method,
                                          todo, take, self.lightened)
        return self.report(self.plan, results, time.perf_counter() - started, workers, backend,
                           None if store is None else str(store.path), len(results) - resumed)

    def stored(self, store: CampaignStore) -> list[R]:
        """The units ``store`` holds, checked against what the method needs (StoreError)."""
        return stored_prefix(store, self.method())

    def open_store(self, path: str | Path) -> Any:
        """The store at ``path`` (made if missing, locked for this process), holding this
        study's plan, recorded now if the store is new: StoreError if it holds another plan,
        or records the method cannot use."""
        store = self.store_kind(path)
        try:
            store.start(self.plan)
            self.stored(store)
        except BaseException:
            store.close()
            raise
        return store

    @classmethod
    def from_store(cls, store: CampaignStore) -> tuple[Rep, Any, list[R]]:
        """The report of the study ``store`` holds, rebuilt from the store alone (complete or
        not), with the plan and the units it was built from (read once: a study may be adding
        units meanwhile). The store does not record how the study ran (workers, backend): those
        are None, and the time is the sum of the units' own."""
        plan = store.plan()
        if plan is None:
            raise StoreError(f"{store.path}: the store holds no {store.what.split()[0]} yet")
        results = stored_prefix(store, cls.method_of(plan))
        if not results:
            raise StoreError(f"{store.path}: no {cls.unit} is stored yet")
        return (cls.report(plan, results, sum(cls.seconds(r) for r in results), None, None,
                           str(store.path)), plan, results)


class EpisodeStudy(Study[EpisodeResult, Rep]):
    """A study whose unit is one episode (a campaign): its method observes the episode's
    success."""

    unit = "episode"

    @staticmethod
    def outcome(result: EpisodeResult) -> bool:
        return result.success

    @staticmethod
    def seconds(result: EpisodeResult) -> float:
        return result.seconds
