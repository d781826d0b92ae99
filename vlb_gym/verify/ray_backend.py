"""The ``ray`` backend of :func:`~vlb_gym.verify.backends.run_indices`: one Ray actor per
worker (at most one per free CPU of the cluster), each building its runner once; chunks go to
an actor once it has started, a few in flight each.

An actor that dies is told apart by its node: when the node died with it, its unfinished chunks
run again on the others (never counted against an index) and a replacement starts only where a
CPU is free; when the node lives on, the actor's process crashed, and the chunks are retried
index by index to find the one that killed it (``max_deaths`` deaths end the run). An actor
that cannot start within :attr:`~.ray_connect.RayOptions.stall` seconds is given up; with no
other actor alive the run ends with :class:`~.ray_connect.ClusterError`.
"""

from __future__ import annotations

import collections
import os
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

from .backends import IN_FLIGHT, RemoteTraceback, freeze_setup, gc_paused, one_core_each
from .chunks import ChunkQueue, count
from .ray_connect import NOTES, ClusterError, RayOptions, error_line, session

T = TypeVar("T")

_DEAD_ACTOR_WAIT = 30.0  # seconds to wait for a dead actor's finished results
_NODE_SETTLE = 5.0  # seconds a dead actor's node has to be declared dead (it may be dying)
_POLL = 1.0  # seconds between looks at actors that have not started
_RELEASE_WAIT = 5.0  # seconds to wait for the CPUs of killed actors to show free


class _RayRunner:
    """A Ray actor's state: the runner (or the exception ``setup`` raised)."""

    def __init__(self, setup: Callable[[], Callable[[int], Any]]) -> None:
        self.runner: Callable[[int], Any] | None = None
        self.error: Exception | None = None
        one_core_each()  # Ray sizes them to the actor's one CPU already, unless told otherwise
        try:
            self.runner = setup()
        except Exception as exc:  # raised from ready(), as itself
            self.error = exc
        freeze_setup()

    def ready(self) -> str:
        """The id of the node this actor runs on, once its runner is built."""
        if self.error is not None:
            raise self.error
        import ray

        return ray.get_runtime_context().get_node_id()

    def run(self, chunk: list[int]) -> list[Any]:
        return [self.runner(i) for i in chunk]


@dataclass(eq=False)
class _Actor:
    handle: Any
    started: float
    node: str | None = None  # known once it is ready
    sent: collections.deque = field(default_factory=collections.deque)  # (ref, chunk)s


def local_cpus() -> int:
    """CPUs this process may run on (a local instance gets no more)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (
        os.cpu_count() or 1)


def run_on_ray(setup: Callable[[], Callable[[int], T]], indices: Sequence[int], workers: int,
               options: RayOptions, max_deaths: int) -> Iterator[T]:
    with session(options, min(workers, count(indices), local_cpus())) as ray:
        yield from _Run(ray, setup, indices, workers, options, max_deaths).results()


class _Run:
    """One run's actors, the chunks they hold and the deaths seen."""

    def __init__(self, ray: Any, setup: Callable[[], Any], indices: Sequence[int], workers: int,
                 options: RayOptions, max_deaths: int) -> None:
        self.ray, self.options, self.max_deaths = ray, options, max_deaths
        self.remaining = count(indices)
        free = self.free_cpus()
        self.workers = max(1, min(workers, free, self.remaining))
        if self.remaining and free < 1:
            NOTES.warning(f"the Ray cluster has no free CPU now ({self.total_cpus()} in all): "
                          f"waiting up to {options.stall:.0f} s for one")
        elif self.workers < min(workers, self.remaining):
            NOTES.warning(f"--workers {workers} reduced to {self.workers} (the Ray cluster "
                          f"has {free} free CPU(s))")
        self.todo = ChunkQueue(indices, count(indices), max(self.workers, 1))
        self.actors: list[_Actor] = []
        self.owner: dict[Any, _Actor] = {}  # a chunk's ref -> its actor
        self.pending: dict[Any, _Actor] = {}  # an actor's ready() ref -> the actor
        self.deaths: collections.Counter[int] = collections.Counter()
        self.suspects: set[int] = set()  # indices of chunks an actor died with
        self.idle_deaths = 0  # deaths in a row before any chunk (in setup, say)
        self.lost_nodes: set[str] = set()
        self.actor_class = ray.remote(num_cpus=1, max_restarts=0,
                                      max_task_retries=0)(_RayRunner)
        self.setup_ref = ray.put(setup)

    def free_cpus(self) -> int:
        return int(self.ray.available_resources().get("CPU", 0))

    def total_cpus(self) -> int:
        return int(self.ray.cluster_resources().get("CPU", 0))

    def alive_nodes(self) -> set[str]:
        return {node["NodeID"] for node in self.ray.nodes() if node["Alive"]}

    def node_lost(self, node: str | None) -> bool:
        """Whether ``node`` (a dead actor's) is gone: its workers often die before Ray declares
        the node dead, so a node still listed alive is given a few seconds to settle."""
        if node is None:
            return False
        deadline = time.monotonic() + _NODE_SETTLE
        while node in self.alive_nodes():
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.25)
        return True

    def alone(self, chunk: list[int]) -> bool:
        """Whether ``chunk`` runs alone on its actor: a suspect, retried so that a death can
        be pinned on it (the replies of an actor's finished chunks may die with it)."""
        return len(chunk) == 1 and chunk[0] in self.suspects

    def start(self) -> None:
        actor = _Actor(self.actor_class.remote(self.setup_ref), time.monotonic())
        self.actors.append(actor)
        self.pending[actor.handle.ready.remote()] = actor

    def feed(self, actor: _Actor) -> None:
        while self.todo and len(actor.sent) < IN_FLIGHT:
            if actor.sent and (self.alone(self.todo[0]) or self.alone(actor.sent[-1][1])):
                break
            chunk = self.todo.popleft()
            ref = actor.handle.run.remote(chunk)
            actor.sent.append((ref, chunk))
            self.owner[ref] = actor

    def drop(self, actor: _Actor) -> None:
        self.actors.remove(actor)
        for ref, _ in actor.sent:
            self.owner.pop(ref, None)
        for ref in [r for r, a in self.pending.items() if a is actor]:
            del self.pending[ref]
        self.ray.kill(actor.handle, no_restart=True)

    def results(self) -> Iterator[Any]:
        from ray.exceptions import RayActorError, RayTaskError, WorkerCrashedError

        try:
            for _ in range(self.workers):
                self.start()
            while self.remaining:
                for actor in self.actors:  # chunks given back (a dead actor's) go out at once
                    if actor.node is not None:
                        self.feed(actor)
                if not self.owner and not self.pending:
                    raise RuntimeError(f"{self.remaining} indices left and nothing to wait for "
                                       "(a bug of the ray backend)")
                done, _ = self.ray.wait([*self.owner, *self.pending], num_returns=1,
                                        timeout=_POLL)
                if not done:
                    self.give_up_unstarted()
                    continue
                (ref,) = done
                actor = self.pending.pop(ref, None) or self.owner.pop(ref, None)
                if actor is None:  # its actor died already
                    continue
                try:
                    with gc_paused():
                        value = self.ray.get(ref)
                except (RayActorError, WorkerCrashedError) as error:
                    for chunk, results in self.died(actor, error):
                        self.remaining -= len(chunk)
                        yield from results
                    continue
                except RayTaskError as error:
                    cause = error.cause
                    if isinstance(cause, BaseException):
                        raise cause from RemoteTraceback(str(error))
                    raise
                if actor.node is None:  # ready() answered: it has started
                    actor.node = value
                    NOTES.debug(f"an actor started on node {value}")
                    self.feed(actor)
                    continue
                _, chunk = actor.sent.popleft()
                self.remaining -= len(chunk)
                self.idle_deaths = 0
                self.feed(actor)
                yield from value
        finally:
            self.release()

    def release(self) -> None:
        """Kill every actor, and wait (a few seconds at most) until the cluster shows their
        CPUs free again: Ray frees them asynchronously, and a campaign started right after
        would otherwise find the cluster short."""
        placed = sum(actor.node is not None for actor in self.actors)
        target = min(self.free_cpus() + placed, self.total_cpus())
        for actor in list(self.actors):
            self.drop(actor)
        deadline = time.monotonic() + _RELEASE_WAIT
        while placed and self.free_cpus() < target and time.monotonic() < deadline:
            time.sleep(0.05)

    def give_up_unstarted(self) -> None:
        """Drop actors that did not start within the stall bound; ClusterError if none is
        left."""
        now = time.monotonic()
        late = [a for a in self.pending.values() if now - a.started > self.options.stall]
        for actor in late:
            self.drop(actor)
        if late and not self.actors:
            raise ClusterError(
                f"no Ray actor could start within {self.options.stall:.0f} s, so the campaign "
                f"cannot go on: the cluster has {self.free_cpus()} free CPU(s) of "
                f"{self.total_cpus()}, each actor needs 1 (lost nodes: {len(self.lost_nodes)})")
        if late:
            NOTES.warning(f"{len(late)} Ray actor(s) could not start within "
                          f"{self.options.stall:.0f} s; their work goes to the "
                          f"{len(self.actors)} running")

    def died(self, actor: _Actor, error: BaseException) -> list[tuple[list[int], list[Any]]]:
        """Account for a dead actor and replace it where it can be; return the chunks it
        finished before dying, with their results (ray.wait may report the death first)."""
        from ray.exceptions import GetTimeoutError, RayActorError, WorkerCrashedError

        finished, unfinished = [], []
        for ref, chunk in actor.sent:
            if not unfinished:
                try:  # a dead actor's refs resolve soon: to results it sent, or to its death
                    finished.append((chunk, self.ray.get(ref, timeout=_DEAD_ACTOR_WAIT)))
                    continue
                except (RayActorError, WorkerCrashedError, GetTimeoutError):
                    pass  # the actor died before finishing it (or had not run it)
            unfinished.append(chunk)
        self.drop(actor)
        node_lost = self.node_lost(actor.node)
        NOTES.debug(f"an actor on node {actor.node} died (node lost: {node_lost}, "
                    f"{len(finished)} chunk(s) finished, {len(unfinished)} not): "
                    f"{error_line(error, last=True)}")
        if node_lost:  # not the episodes' doing: they run again elsewhere, uncounted
            self.todo.extendleft(reversed(unfinished))
            if actor.node not in self.lost_nodes:
                self.lost_nodes.add(actor.node)
                NOTES.warning(f"lost a Ray node ({actor.node[:12]}): its episodes run again "
                              "on the other actors")
        elif actor.node is None:
            if isinstance(error, RayActorError) and error.actor_init_failed:
                raise ClusterError(f"a Ray actor could not be created ({error_line(error, last=True)}): "
                                   "every node needs the vlb-gym (and the extras) of this "
                                   "machine installed, in the same versions")
            self.idle_deaths += 1
            if self.idle_deaths >= self.max_deaths * max(self.workers, 2):
                raise RuntimeError(f"Ray actors keep dying before they start "
                                   f"({self.idle_deaths} in a row; last: {error})")
        else:
            self.blame(unfinished, error)
        if not node_lost or not self.actors or self.free_cpus() >= 1:
            self.start()
        return finished

    def blame(self, unfinished: list[list[int]], error: BaseException) -> None:
        """Requeue a crashed actor's chunks: a suspect that ran alone is the culprit."""
        if len(unfinished) == 1 and self.alone(unfinished[0]):
            (index,) = unfinished[0]
            self.deaths[index] += 1
            if self.deaths[index] >= self.max_deaths:
                raise RuntimeError(
                    f"index {index}: its run killed the Ray actor's worker process "
                    f"{self.deaths[index]} times, so it is not tried again ({error})")
            self.todo.appendleft([index])
        else:  # one of these was running: each is retried alone to find which
            self.suspects.update(i for chunk in unfinished for i in chunk)
            self.todo.extendleft([i] for chunk in reversed(unfinished) for i in reversed(chunk))
