"""Running one episode of any policy under the robustness wrapper."""

from __future__ import annotations

import time
import traceback
from collections.abc import Callable
from typing import Any

import numpy as np

from vlb_gym.core.runtime import failure_cause
from vlb_gym.envs.modules import make_primitive_env
from vlb_gym.wrappers.loop import PolicyEpisode
from vlb_gym.wrappers.robustness import RobustnessWrapper, certificate_cause

from .policies import Policy, policy_loader
from .records import CampaignConfig, EpisodeResult, Step, episode_seed


_NUMBERS = (int, float, bool)
_NUMBER_TYPES = frozenset(_NUMBERS)


def _plain(value: Any) -> Any:
    """``value`` as plain JSON data (numpy scalars and arrays, tuples -> lists)."""
    kind = type(value)
    if kind in _NUMBERS or value is None or kind is str:
        return value
    if kind is tuple and _NUMBER_TYPES.issuperset(map(type, value)):  # most parameters
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
            now = time.perf_counter()  # the callback's time is no step's
        last = now

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
