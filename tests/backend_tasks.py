"""Setups for tests/test_backends.py: module-level, so worker processes import them by name."""

from __future__ import annotations

import functools
import gc
import os
import signal
import time
from pathlib import Path

from vlb_gym.verify.campaign import CampaignConfig, episode_runner


def _square(i: int) -> tuple[int, int]:
    return i, i * i


def squares():
    """runner(i) = (i, i*i)."""
    return _square


def _threads(i: int) -> tuple[int, dict[str, str | None]]:
    import torch  # loaded after the worker started, as a trained agent's policy loads it

    return i, {"OMP_NUM_THREADS": os.environ.get("OMP_NUM_THREADS"),
               "torch": str(torch.get_num_threads())}


def thread_pools():
    """runner(i) = (i, the worker's OpenMP setting and torch's intra-op threads)."""
    return _threads


def _collector(built: list[int], i: int) -> tuple[int, dict[str, int]]:
    return i, {"built": built[0], "frozen": gc.get_freeze_count()}


def collector_state():
    """runner(i) = (i, how many objects were alive when the runner was built and how many the
    collector holds frozen)."""
    return functools.partial(_collector, [len(gc.get_objects())])


class SetupError(Exception):
    pass


def failing_setup():
    raise SetupError("no runner today")


def _die_once(marker: str, victim: int, i: int) -> tuple[int, int]:
    if i == victim and not os.path.exists(marker):
        Path(marker).write_text(str(os.getpid()))
        os.kill(os.getpid(), signal.SIGKILL)
    return i, i * i


def dies_once(marker: str, victim: int = 7):
    """Kills its own process the first time it sees ``victim`` (``marker`` records it)."""
    return functools.partial(_die_once, marker, victim)


def _die_always(victim: int, i: int) -> tuple[int, int]:
    if i == victim:
        os.kill(os.getpid(), signal.SIGKILL)
    return i, i * i


def dies_always(victim: int = 7):
    return functools.partial(_die_always, victim)


def _slow(i: int) -> tuple[int, int]:
    time.sleep(0.05)
    return i, os.getpid()


def slow():
    """runner(i) = (i, pid) after 50 ms."""
    return _slow


def campaign(config: CampaignConfig):
    """The runner a campaign's workers build: the env and the policy once, then episodes."""
    return episode_runner(config)


class RunError(Exception):
    pass


def _slow_then_fail(i: int) -> tuple[int, int]:
    if i == 30:
        raise RunError(f"index {i} failed")
    return _slow(i)


def slow_then_fail():
    """Like :func:`slow`, but the run of index 30 raises RunError."""
    return _slow_then_fail
