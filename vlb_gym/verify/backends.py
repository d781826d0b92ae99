"""Where a campaign's episodes run: in this process, in worker processes, or on Ray actors.

:func:`run_indices` knows nothing of episodes: ``setup`` is a picklable callable that every
worker calls once to build its runner, and ``runner(i)`` is computed for every index, each
result yielded exactly once, so results do not depend on the backend or the worker count.

Worker processes that die mid-task (SIGKILL, the out-of-memory killer) are replaced and their
unfinished work runs again on the replacement; an index whose run kills its worker
``max_deaths`` times raises :class:`RuntimeError` naming it. Work goes out in chunks (a small
list of indices per message) with a bounded number in flight.
"""

from __future__ import annotations

import collections
import contextlib
import gc
import multiprocessing as mp
import multiprocessing.connection
import os
import pickle
import signal
import sys
import tempfile
import traceback
from collections.abc import Callable, Iterable, Iterator, Sequence, Sized
from typing import TYPE_CHECKING, Any, TypeVar

from vlb_gym.core.errors import UserError

from .chunks import ChunkQueue, count

if TYPE_CHECKING:
    from .ray_connect import RayOptions

T = TypeVar("T")

Backend = Callable[..., Iterator[Any]]
"""What runs a study's indices: ``backend(setup, indices, workers, preload, max_deaths, ray)``
yields ``runner(i)`` for every ``i`` of ``indices`` as they finish, each worker building
``runner = setup()`` once (see :func:`run_indices`)."""

BACKENDS: dict[str, Backend] = {}
"""Every backend, by the name ``--backend`` takes."""


def register_backend(name: str) -> Callable[[Backend], Backend]:
    """Make the decorated :data:`Backend` one a campaign can run on as ``name``."""
    def add(backend: Backend) -> Backend:
        BACKENDS[name] = backend
        return backend
    return add

MAX_DEATHS = 3  # an index whose run killed its worker this many times fails the campaign
IN_FLIGHT = 2  # chunks queued per worker: the next one is there when the current one ends
_WORKER_NAME = "vlb-worker:"  # process name prefix; the rest is the guard-report file

GUARD_MESSAGE = (
    "a campaign with worker processes was started while {main} was being imported by a worker "
    "process: the script runs it at module level, so every worker would run it again. A script "
    "that runs campaigns with workers needs an `if __name__ == '__main__':` guard around that "
    "code (see the multiprocessing docs, 'Safe importing of main module')")


class BackendError(UserError, RuntimeError):
    """A backend cannot run the work as asked (a cluster out of reach or out of workers,
    inputs that differ on a worker); the message is one line for the user."""


class RemoteTraceback(Exception):
    """The traceback of an exception raised in a worker (set as that exception's cause)."""

    def __str__(self) -> str:
        return self.args[0] if self.args else ""


@contextlib.contextmanager
def gc_paused() -> Iterator[None]:
    """Hold the cyclic garbage collector back while a block runs (unpickling a chunk of
    results): each result is dozens of small containers, and collections triggered while the
    parent's heap grows by thousands of them cost it 60-120 us per result, 7-13x the unpickling
    itself, taken from the cores the workers run on. Nothing is lost: the collector runs as
    usual afterwards. A collector the caller disabled stays disabled (one thread: campaigns
    run the backend on one)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def freeze_setup() -> None:
    """In a worker, once its runner is built: move everything alive (the modules, the env, the
    policy) to the collector's permanent generation, so that the collections its episodes
    trigger walk only what the episodes allocate, not the whole heap (for process workers,
    forked from the forkserver, this also leaves its copy-on-write pages shared). 5-9% more grid
    episodes per second on 2 workers. The price is bounded: what the set-up left alive is never
    collected, even if it later becomes cyclic garbage (it lives as long as the worker anyway)."""
    gc.freeze()


def start_forkserver(preload: Sequence[str]) -> None:
    """Start the forkserver that ``process`` workers fork from now, importing ``preload`` in it
    while the caller goes on: ``vlb verify`` calls it first, so that the server's imports run
    beside its own instead of after them (0.5 s sooner to the first episode of a 2-worker grid
    campaign). The server keeps this preload for every later campaign of the process; nothing
    happens where there is no forkserver or one is running already."""
    context = _context()
    if context.get_start_method() != "forkserver":
        return
    from multiprocessing import forkserver

    context.set_forkserver_preload(list(preload))
    with safe_import_path():
        forkserver.ensure_running()


def check_main_guard() -> None:
    """Raise :class:`RuntimeError` if this process is a multiprocessing worker still importing
    the main script (a script without an ``if __name__ == '__main__':`` guard that starts a
    campaign at module level); that worker's parent gets the same error."""
    if not getattr(mp.current_process(), "_inheriting", False):
        return
    main = getattr(sys.modules.get("__mp_main__"), "__file__", None)
    message = GUARD_MESSAGE.format(main=main or "the main module")
    name = mp.current_process().name
    if name.startswith(_WORKER_NAME):  # one of ours: tell the parent why this worker dies
        try:
            with open(name[len(_WORKER_NAME):], "w") as report:
                report.write(message)
        except OSError:
            pass
    raise RuntimeError(message)


def run_indices(setup: Callable[[], Callable[[int], T]], indices: Sequence[int], *,
                backend: str = "process", workers: int = 1, ray: RayOptions | None = None,
                preload: Sequence[str] = (), max_deaths: int = MAX_DEATHS) -> Iterator[T]:
    """Yield ``runner(i)`` for every ``i`` in ``indices`` as they finish (in order for
    ``serial`` and for one ``process`` worker), where each worker builds ``runner = setup()``
    once.

    - ``serial``: ``setup()`` and every run in this process.
    - ``process``: ``workers`` processes from a forkserver (spawn where there is none) that
      imports ``preload`` once; they ignore SIGINT, so Ctrl-C raises ``KeyboardInterrupt`` in
      the caller only. A script that uses it needs an ``if __name__ == '__main__':`` guard
      (without one, a clear :class:`RuntimeError` says so).
    - ``ray``: ``workers`` Ray actors (at most one per free CPU), on the Ray this process is
      connected to, else as ``ray`` says (:class:`~.ray_connect.RayOptions`: a cluster's
      address, or a private local instance started and stopped here); needs the extra
      ``vlb-gym[ray]``. A cluster out of reach or out of CPUs is a :class:`BackendError`.

    An exception from ``setup`` or from a run is raised here as itself (the worker's traceback
    as its cause). A worker that dies mid-run is replaced and the run repeated; an index whose
    run killed ``max_deaths`` workers raises :class:`RuntimeError`. Closing or leaving the
    generator stops the workers.
    """
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {', '.join(BACKENDS)} (got {backend!r})")
    if not isinstance(workers, int) or isinstance(workers, bool) or workers < 1:
        raise ValueError(f"workers must be a positive integer (got {workers!r})")
    if not isinstance(max_deaths, int) or max_deaths < 1:
        raise ValueError(f"max_deaths must be a positive integer (got {max_deaths!r})")
    check_main_guard()
    if not isinstance(indices, Sized):  # a generator: listed once
        indices = list(indices)
    return BACKENDS[backend](setup, indices, workers, tuple(preload), max_deaths, ray)


@register_backend("serial")
def _on_serial(setup: Callable[[], Callable[[int], T]], indices: Sequence[int], workers: int,
               preload: tuple[str, ...], max_deaths: int, ray: RayOptions | None
               ) -> Iterator[T]:
    return _serial(setup, indices)


@register_backend("process")
def _on_processes(setup: Callable[[], Callable[[int], T]], indices: Sequence[int], workers: int,
                  preload: tuple[str, ...], max_deaths: int, ray: RayOptions | None
                  ) -> Iterator[T]:
    return _process(setup, indices, workers, preload, max_deaths)


@register_backend("ray")
def _on_ray(setup: Callable[[], Callable[[int], T]], indices: Sequence[int], workers: int,
            preload: tuple[str, ...], max_deaths: int, ray: RayOptions | None) -> Iterator[T]:
    from .ray_backend import run_on_ray  # Ray's imports only for Ray
    from .ray_connect import RayOptions

    return run_on_ray(setup, indices, workers, ray or RayOptions(), max_deaths)


def _serial(setup: Callable[[], Callable[[int], T]], indices: Iterable[int]) -> Iterator[T]:
    runner = setup()
    for i in indices:
        yield runner(i)


# ---------------------------------------------------------------------------------- processes


def _context() -> Any:
    if "forkserver" in mp.get_all_start_methods():
        return mp.get_context("forkserver")
    return mp.get_context("spawn")


@contextlib.contextmanager
def safe_import_path() -> Iterator[None]:
    """While worker interpreters start (a forkserver, spawned processes): Python's safe-path
    mode for them (``PYTHONSAFEPATH``, Python 3.11+), so that the folder a command runs in is
    not put first on their import path -- a ``random.py`` or ``signal.py`` among the files where
    a campaign runs is never imported; their path is then the parent's own. This process's
    environment is as it was afterwards."""
    saved = os.environ.get("PYTHONSAFEPATH")
    os.environ["PYTHONSAFEPATH"] = "1"
    try:
        yield
    finally:
        if saved is None:
            os.environ.pop("PYTHONSAFEPATH", None)
        else:
            os.environ["PYTHONSAFEPATH"] = saved


def _portable(exc: BaseException) -> BaseException:
    """``exc`` if it pickles, else a RuntimeError that describes it."""
    try:
        pickle.loads(pickle.dumps(exc))
        return exc
    except Exception:
        return RuntimeError(f"{type(exc).__qualname__}: {exc} (the exception does not pickle)")


WORKER_THREAD_VARIABLES = ("OMP_NUM_THREADS", "MKL_NUM_THREADS")


def one_core_each() -> None:
    """Size the thread pools of libraries a worker loads later (OpenMP and MKL: torch's, for
    trained agents) to one thread, unless the user set them: a worker runs one episode at a
    time, and pools sized to the machine in every worker oversubscribe the cores; spinning
    OpenMP threads then made a 2-worker campaign of an SB3 agent 80x slower than 1 worker."""
    for name in WORKER_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")


def _worker_main(conn: Any, current: Any, setup: Callable[[], Callable[[int], Any]]) -> None:
    """A worker process: build the runner, then run the chunks that arrive until None.

    Messages to the parent: ``("started",)``, then ``("ok", results)`` per chunk, or
    ``("error", exception, traceback text)`` (after which the parent stops everything).
    ``current`` holds the index being run (-1 between chunks): a dead worker's culprit.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is for the parent, which stops us
    one_core_each()
    conn.send(("started",))
    try:
        runner = setup()
    except Exception as exc:
        conn.send(("error", _portable(exc), traceback.format_exc()))
        return
    freeze_setup()
    while True:
        chunk = conn.recv()
        if chunk is None:
            return
        try:
            results = []
            for i in chunk:
                current.value = i
                results.append(runner(i))
            current.value = -1
            conn.send(("ok", results))
        except Exception as exc:
            conn.send(("error", _portable(exc), traceback.format_exc()))
            return


class _Worker:
    """The parent's handle on one worker process and the chunks sent to it (oldest first)."""

    def __init__(self, context: Any, setup: Callable[[], Any], report: str) -> None:
        self.conn, child = context.Pipe()
        self.current = context.RawValue("q", -1)
        self.report = report
        self.process = context.Process(target=_worker_main, args=(child, self.current, setup),
                                       name=_WORKER_NAME + report, daemon=True)
        with safe_import_path():  # (the forkserver, if this starts it)
            self.process.start()
        child.close()
        self.started = False
        self.chunks: collections.deque[list[int]] = collections.deque()

    def finish(self) -> None:
        """Ask the worker to exit once its queue is done (it may be gone already)."""
        with contextlib.suppress(OSError):
            self.conn.send(None)

    def stop(self, wait: float) -> None:
        """Wait up to ``wait`` seconds for a worker asked to :meth:`finish`, or terminate it
        now (``wait`` 0); reap it either way."""
        if wait > 0:
            self.process.join(wait)
        if self.process.is_alive():
            self.process.terminate()
            self.process.join(2)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.conn.close()
        self.process.close()


def _process(setup: Callable[[], Callable[[int], T]], indices: Sequence[int], workers: int,
             preload: tuple[str, ...], max_deaths: int) -> Iterator[T]:
    context = _context()
    if preload and context.get_start_method() == "forkserver":
        context.set_forkserver_preload(list(preload))
    todo = ChunkQueue(indices, count(indices), workers)
    deaths: collections.Counter[int] = collections.Counter()
    idle_deaths = 0  # deaths in a row outside any run (during setup, or killed while idle)
    remaining = count(indices)
    folder = tempfile.mkdtemp(prefix="vlb-workers-")
    pool: list[_Worker] = []
    finished = False

    numbers = iter(range(1 << 62))

    def start() -> _Worker:
        worker = _Worker(context, setup, os.path.join(folder, f"{next(numbers)}.guard"))
        pool.append(worker)
        return worker

    def feed(worker: _Worker) -> None:
        while todo and len(worker.chunks) < IN_FLIGHT:
            chunk = todo.popleft()
            try:
                worker.conn.send(chunk)
            except OSError:  # it has exited (a failed setup is quick): the loop reads why
                todo.appendleft(chunk)
                return
            worker.chunks.append(chunk)

    def died(worker: _Worker) -> None:
        nonlocal idle_deaths
        worker.process.join(5)
        code = worker.process.exitcode
        culprit = worker.current.value if worker.chunks else -1
        how = (f"signal {signal.Signals(-code).name}" if code is not None and code < 0
               else f"exit code {code}")
        if not worker.started:
            message = None
            if os.path.exists(worker.report):
                with open(worker.report) as report:
                    message = report.read()
            if message:
                raise RuntimeError(message)
            if code is not None and code > 0:
                raise RuntimeError(
                    f"a worker process failed to start ({how}; its traceback is on stderr): "
                    "the setup callable must be importable by name in a fresh interpreter, and "
                    "a script that runs campaigns with workers needs an `if __name__ == "
                    "'__main__':` guard")
        todo.extendleft(reversed(worker.chunks))  # first in line again, in their order
        worker.chunks.clear()
        pool.remove(worker)
        worker.stop(0)
        if culprit >= 0:
            idle_deaths = 0
            deaths[culprit] += 1
            if deaths[culprit] >= max_deaths:
                raise RuntimeError(
                    f"index {culprit}: its run killed the worker process {deaths[culprit]} "
                    f"times (last: {how}), so it is not tried again; the runner kills or "
                    "crashes its process (out of memory, a crash in native code, os._exit)")
        else:
            idle_deaths += 1
            if idle_deaths >= max_deaths * max(workers, 2):
                raise RuntimeError(
                    f"worker processes keep dying outside any run ({idle_deaths} in a row, "
                    f"last: {how}): during setup, or killed from outside")
        if remaining:  # a worker that died after its last results needs no replacement
            feed(start())

    try:
        for _ in range(min(workers, remaining)):
            feed(start())
        while remaining:
            ready = mp.connection.wait([w.conn for w in pool] + [w.process.sentinel
                                                                  for w in pool])
            for worker in list(pool):
                if worker.conn not in ready and worker.process.sentinel not in ready:
                    continue
                alive = True
                while alive and worker.conn.poll():
                    try:
                        with gc_paused():
                            message = worker.conn.recv()
                    except (EOFError, OSError):
                        alive = False
                        break
                    if message[0] == "started":
                        worker.started = True
                    elif message[0] == "error":
                        _, exc, text = message
                        raise exc from RemoteTraceback(text)
                    else:
                        chunk = worker.chunks.popleft()
                        remaining -= len(chunk)
                        idle_deaths = 0
                        feed(worker)
                        yield from message[1]
                if not alive or worker.process.sentinel in ready:
                    died(worker)
        finished = True
    finally:
        if finished:  # all at once: each exit takes milliseconds (a big heap to unmap)
            for worker in pool:
                worker.finish()
        for worker in pool:
            worker.stop(5 if finished else 0)
        for name in os.listdir(folder):
            os.unlink(os.path.join(folder, name))
        os.rmdir(folder)
