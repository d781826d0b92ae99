"""Per-episode overhead of each backend of :func:`vlb_gym.verify.backends.run_indices` on the
grid campaign (explore_until_goal on VLB-GridExplore-v0): the bare serial runner (setup and a
plain loop in this process), the serial backend, the process backend with 1 and 2 workers next
to a reference ``multiprocessing.Pool`` with ``imap_unordered`` (campaigns before the backends
module, same forkserver, preload and chunking), and Ray with 2 actors (the Ray instance is
started once, outside the timings). Runs are interleaved; figures are medians.

Usage: python benchmarks/backend_overhead.py [--repeats 5] [--episodes 2000] [--no-ray]
"""

from __future__ import annotations

import argparse
import functools
import logging
import multiprocessing as mp
import os
import platform
import signal
import statistics
import time
from collections.abc import Callable
from typing import Any

from vlb_gym.verify.backends import run_indices
from vlb_gym.verify.chunks import chunk_size
from vlb_gym.verify.campaign import CampaignConfig, episode_runner

PRELOAD = ["vlb_gym.verify.campaign"]


_RUNNER: Any = None


def _pool_init(setup: Callable[[], Callable[[int], Any]]) -> None:
    global _RUNNER
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _RUNNER = setup()


def _pool_run(i: int) -> Any:
    return _RUNNER(i)


def reference_pool(setup: Callable[[], Callable[[int], Any]], indices: list[int],
                   workers: int) -> list[Any]:
    """What campaigns did before the backends module: Pool + imap_unordered."""
    context = mp.get_context("forkserver")
    context.set_forkserver_preload(PRELOAD)
    with context.Pool(workers, initializer=_pool_init, initargs=(setup,)) as pool:
        return list(pool.imap_unordered(_pool_run, indices,
                                        chunksize=chunk_size(len(indices), workers)))


def bare(setup: Callable[[], Callable[[int], Any]], indices: list[int]) -> list[Any]:
    runner = setup()
    return [runner(i) for i in indices]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--episodes", type=int, default=2000)
    parser.add_argument("--no-ray", action="store_true")
    args = parser.parse_args()
    print(f"machine: {platform.machine()}, {os.cpu_count()} cpus, Python "
          f"{platform.python_version()}")
    config = CampaignConfig("VLB-GridExplore-v0", "explore_until_goal", args.episodes)
    setup = functools.partial(episode_runner, config)
    indices = list(range(args.episodes))
    runs: dict[str, Callable[[], list[Any]]] = {
        "bare serial runner": lambda: bare(setup, indices),
        "serial backend": lambda: list(run_indices(setup, indices, backend="serial")),
        "Pool imap_unordered, 1 worker": lambda: reference_pool(setup, indices, 1),
        "process backend, 1 worker": lambda: list(run_indices(
            setup, indices, backend="process", workers=1, preload=PRELOAD)),
        "Pool imap_unordered, 2 workers": lambda: reference_pool(setup, indices, 2),
        "process backend, 2 workers": lambda: list(run_indices(
            setup, indices, backend="process", workers=2, preload=PRELOAD)),
    }
    if not args.no_ray:
        import ray

        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False,
                 logging_level=logging.ERROR)
        runs["ray backend, 2 actors"] = lambda: list(run_indices(setup, indices, backend="ray",
                                                                 workers=2))
    reference = sorted((r.to_dict() for r in bare(setup, indices)), key=lambda r: r["index"])
    for record in reference:
        del record["seconds"]
    times: dict[str, list[float]] = {name: [] for name in runs}
    for _ in range(args.repeats):
        for name, run in runs.items():
            started = time.perf_counter()
            results = run()
            times[name].append(time.perf_counter() - started)
            records = sorted((r.to_dict() for r in results), key=lambda r: r["index"])
            for record in records:
                del record["seconds"]
            assert records == reference, name  # the same episodes, each once
    medians = {name: statistics.median(t) for name, t in times.items()}
    serial = medians["bare serial runner"]
    print(f"{args.episodes} episodes, median of {args.repeats} interleaved runs (setup and "
          "worker start included):")
    for name, seconds in medians.items():
        workers = 2 if "2" in name else 1
        extra = 1e6 * (seconds - serial / workers) / args.episodes
        line = (f"  {name:32s} {seconds:6.2f} s  {1e3 * seconds / args.episodes:5.2f} ms/episode"
                f"  {extra:+6.0f} us/episode over bare serial/{workers}")
        pool = {"process backend, 1 worker": "Pool imap_unordered, 1 worker",
                "process backend, 2 workers": "Pool imap_unordered, 2 workers"}.get(name)
        if pool:
            line += f"  ({100 * (seconds / medians[pool] - 1):+.1f}% vs Pool)"
        print(line)
    if not args.no_ray:
        ray.shutdown()


if __name__ == "__main__":
    main()
