"""The ``ray`` backend of :func:`~vlb_gym.verify.backends.run_indices`: one Ray actor per
worker, each building its runner once; chunks of indices in flight per actor, a dead actor's
unfinished chunks run again elsewhere."""

from __future__ import annotations

import collections
import contextlib
import logging
import signal
import threading
from collections.abc import Callable, Iterator, Sequence
from typing import Any, TypeVar

from .backends import IN_FLIGHT, RemoteTraceback, freeze_setup, gc_paused, one_core_each
from .chunks import ChunkQueue

T = TypeVar("T")


class _RayRunner:
    """A Ray actor's state: the runner (or the exception ``setup`` raised)."""

    def __init__(self, setup: Callable[[], Callable[[int], Any]]) -> None:
        self.runner: Callable[[int], Any] | None = None
        self.error: Exception | None = None
        one_core_each()  # Ray sizes them to the actor's one CPU already, unless told otherwise
        try:
            self.runner = setup()
        except Exception as exc:  # raised from the first chunk, as itself
            self.error = exc
        freeze_setup()

    def run(self, chunk: list[int]) -> list[Any]:
        if self.error is not None:
            raise self.error
        return [self.runner(i) for i in chunk]


def _import_ray() -> Any:
    try:
        import ray
    except ImportError as exc:
        raise ImportError("the ray backend needs Ray: install vlb-gym[ray]") from exc
    return ray


_DEAD_ACTOR_WAIT = 30.0  # seconds to wait for a dead actor's finished results


@contextlib.contextmanager
def _sigint_held() -> Iterator[None]:
    """Hold SIGINT back (in the main thread) until the block is done; a Ctrl-C meanwhile is
    delivered, as KeyboardInterrupt, when it ends."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def run_on_ray(setup: Callable[[], Callable[[int], T]], indices: Sequence[int], workers: int,
         address: str | None, max_deaths: int) -> Iterator[T]:
    ray = _import_ray()
    from ray.exceptions import (GetTimeoutError, RayActorError, RayTaskError,
                                WorkerCrashedError)

    started = False
    todo = ChunkQueue(indices, len(indices), workers)
    deaths: collections.Counter[int] = collections.Counter()
    actors: dict[Any, collections.deque] = {}  # actor -> its (ref, chunk)s, oldest first
    owner: dict[Any, Any] = {}  # ref -> actor
    remaining = len(indices)

    suspects: set[int] = set()  # indices of chunks an actor died with

    def alone(chunk: list[int]) -> bool:
        """Whether ``chunk`` runs alone on its actor: a suspect, retried so that a death can
        be pinned on it (the replies of an actor's finished chunks may die with it)."""
        return len(chunk) == 1 and chunk[0] in suspects

    def feed(actor: Any) -> None:
        queue = actors[actor]
        while todo and len(queue) < IN_FLIGHT:
            if queue and (alone(todo[0]) or alone(queue[-1][1])):
                break
            chunk = todo.popleft()
            ref = actor.run.remote(chunk)
            actors[actor].append((ref, chunk))
            owner[ref] = actor

    def start() -> None:
        actor = actor_class.remote(setup_ref)
        actors[actor] = collections.deque()
        feed(actor)

    def died(actor: Any, error: BaseException) -> list[tuple[list[int], list[Any]]]:
        """Replace a dead actor; return the chunks it finished before dying, with their results
        (not yet yielded: ray.wait may report the death first)."""
        sent = actors.pop(actor)
        for ref, _ in sent:
            owner.pop(ref, None)
        finished, unfinished = [], []
        for ref, chunk in sent:
            if not unfinished:
                try:  # a dead actor's refs resolve soon: to results it sent, or to its death
                    finished.append((chunk, ray.get(ref, timeout=_DEAD_ACTOR_WAIT)))
                    continue
                except (RayActorError, WorkerCrashedError, GetTimeoutError):
                    pass  # the actor died before finishing it (or had not run it)
            unfinished.append(chunk)
        ray.kill(actor, no_restart=True)
        if len(unfinished) == 1 and alone(unfinished[0]):  # it ran alone: it is the culprit
            (index,) = unfinished[0]
            deaths[index] += 1
            if deaths[index] >= max_deaths:
                raise RuntimeError(
                    f"index {index}: its run killed the Ray actor's worker process "
                    f"{deaths[index]} times, so it is not tried again ({error})")
            todo.appendleft([index])
        else:  # one of these was running: each is retried alone to find which
            suspects.update(i for chunk in unfinished for i in chunk)
            todo.extendleft([i] for chunk in reversed(unfinished) for i in reversed(chunk))
        start()
        return finished

    try:
        if not ray.is_initialized():
            options: dict[str, Any] = {"address": address, "include_dashboard": False,
                                       "log_to_driver": False, "logging_level": logging.ERROR}
            if address is None:
                options["num_cpus"] = workers
            # Ctrl-C during Ray's start-up can leave it half started (seen: lost interrupts,
            # crashes); it is held back until Ray is up, then stops the campaign as usual
            with _sigint_held():
                ray.init(**options)
                started = True
        actor_class = ray.remote(num_cpus=1, max_restarts=0, max_task_retries=0)(_RayRunner)
        setup_ref = ray.put(setup)
        for _ in range(min(workers, remaining)):
            start()
        while remaining:
            done, _ = ray.wait(list(owner), num_returns=1)
            for ref in done:
                actor = owner.get(ref)
                if actor is None:  # its actor died already
                    continue
                try:
                    with gc_paused():
                        results = ray.get(ref)
                except (RayActorError, WorkerCrashedError) as error:
                    for chunk, results in died(actor, error):
                        remaining -= len(chunk)
                        yield from results
                    continue
                except RayTaskError as error:
                    cause = getattr(error, "cause", None)
                    if isinstance(cause, BaseException):
                        raise cause from RemoteTraceback(str(error))
                    raise
                del owner[ref]
                _, chunk = actors[actor].popleft()
                remaining -= len(chunk)
                feed(actor)
                yield from results
    finally:
        for actor in actors:
            ray.kill(actor, no_restart=True)
        if started:
            ray.shutdown()
