"""Running one episode of any policy under the robustness wrapper."""

from __future__ import annotations

import time
import traceback
from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from vlb_gym.core.runtime import failure_cause
from vlb_gym.wrappers.loop import PolicyEpisode
from vlb_gym.wrappers.robustness import RobustnessWrapper, certificate_cause

from .records import EpisodeResult, Step


class Policy(Protocol):
    """What campaigns run: a behavior graph or a trained agent.

    ``predict`` returns ``(action, state)``; an action of None means the policy has finished. A
    behavior graph's state is the node that chose the action (a string, recorded with the step);
    an agent's is its recurrent state or None. ``reset`` gets the episode's reset seed: a policy
    that draws its actions seeds its own generator from it, so that episodes stay independent
    and each replays exactly.
    """

    def reset(self, seed: int | None = None) -> None: ...

    def predict(self, observation: Any, state: Any = None, episode_start: Any = None,
                deterministic: bool = True) -> tuple[np.ndarray | None, Any]: ...


_NUMBERS = (int, float, bool)


def _plain(value: Any) -> Any:
    """``value`` as plain JSON data (numpy scalars and arrays, tuples -> lists)."""
    kind = type(value)
    if kind in _NUMBERS or value is None or kind is str:
        return value
    if kind is tuple and all(type(v) in _NUMBERS for v in value):  # most parameters
        return list(value)
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def step_record(info: dict[str, Any], node: str | None, seconds: float) -> Step:
    """The stored record of one step's ``info`` that took ``seconds``."""
    held = bool(info["certificate"])
    return {"primitive": info["primitive"], "node": node, "param": _plain(info["param"]),
            "certificate": held,
            "reason": None if held else str(info.get("reason", "certificate failed")),
            "cause": None if held else certificate_cause(info), "seconds": seconds}


def interrupted(exc: BaseException) -> bool:
    """Whether ``exc`` is a KeyboardInterrupt in disguise: C extensions (Numba's compiled code
    among them) turn one raised while they call back into Python into a SystemError whose cause
    it is. Only that pattern: an error raised on purpose while handling an interrupt is the
    episode's failure."""
    return isinstance(exc, SystemError) and isinstance(exc.__cause__, KeyboardInterrupt)


def run_episode(env: RobustnessWrapper, policy: Policy, seed: int, index: int = 0,
                stop_on_failure: bool = True,
                on_step: Callable[[dict[str, Any] | None], None] | None = None,
                max_primitives: int | None = None) -> EpisodeResult:
    """Run ``policy`` from ``env.reset(seed=seed)`` until the episode ends
    (:class:`~vlb_gym.wrappers.loop.PolicyEpisode`: the policy finished, the env ended it, or,
    with ``max_primitives``, that many primitives ran: the episode then did not finish).

    Any exception from the policy or the environment fails this episode (rho_B = -1, with the
    reason) instead of propagating, except one a KeyboardInterrupt caused (:func:`interrupted`),
    which raises KeyboardInterrupt. With ``stop_on_failure`` the episode stops at the first failed
    certificate, since rho_B is then already -1. ``on_step`` is called with None after the
    reset and with every step's info after the step.
    """
    episode = PolicyEpisode(env, policy, stop_on_failure, max_primitives)
    started = last = time.perf_counter()
    steps: list[Step] = []
    start: dict[str, Any] = {}
    error = None

    def begin(info: dict[str, Any]) -> None:
        nonlocal last
        start.update(_plain(info))  # the sampled start, as reset reported it
        if on_step is not None:
            on_step(None)
        last = time.perf_counter()

    def record(info: dict[str, Any], state: Any) -> None:
        nonlocal last
        now = time.perf_counter()
        steps.append(step_record(info, state if isinstance(state, str) else None, now - last))
        if on_step is not None:
            on_step(info)
        last = time.perf_counter()

    try:
        episode.reset(seed=seed, on_reset=begin)
        while episode.action is not None:
            episode.step(record)
    except Exception as exc:  # an episode's failure, never the campaign's end
        if interrupted(exc):  # Ctrl-C, not a failure: never stored as one
            raise KeyboardInterrupt from exc
        frame = traceback.extract_tb(exc.__traceback__)[-1]
        error = "".join(traceback.format_exception(exc))[-_MAX_TRACEBACK:]
        env.end(finished=False, reason=f"{type(exc).__name__}: {exc} "
                                       f"({frame.filename.rsplit('/', 1)[-1]}:{frame.lineno})",
                cause=failure_cause(exc))
    summary = env.summary
    return EpisodeResult(index, int(seed), summary["rho_B"], summary["finished"],
                         summary["primitives"], summary["failed_certificates"],
                         summary["failure_reason"], time.perf_counter() - started,
                         summary["failure_cause"], tuple(steps), start, error)


_MAX_TRACEBACK = 8000  # characters of a traceback kept (its end: where it was raised)

