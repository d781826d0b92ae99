"""Where a campaign's episodes run (placeholder until the backends branch lands)."""

from __future__ import annotations

import multiprocessing as mp
import signal
from collections.abc import Callable, Iterator, Sequence
from typing import Any, TypeVar

T = TypeVar("T")
BACKENDS = ("serial", "process")
_RUNNER: Any = None


def _init(setup: Callable[[], Callable[[int], Any]]) -> None:
    global _RUNNER
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        _RUNNER = setup()
    except Exception as exc:
        _RUNNER = exc


def _run(index: int) -> Any:
    if isinstance(_RUNNER, Exception):
        raise _RUNNER
    return _RUNNER(index)


def run_indices(setup: Callable[[], Callable[[int], T]], indices: Sequence[int], *,
                backend: str = "process", workers: int = 1, ray_address: str | None = None,
                preload: Sequence[str] = ()) -> Iterator[T]:
    if backend == "serial" or workers == 1:
        runner = setup()
        for i in indices:
            yield runner(i)
        return
    chunk = max(1, min(64, len(indices) // (workers * 16)))
    context = mp.get_context("forkserver")
    context.set_forkserver_preload(list(preload))
    with context.Pool(workers, initializer=_init, initargs=(setup,)) as pool:
        yield from pool.imap_unordered(_run, indices, chunksize=chunk)
