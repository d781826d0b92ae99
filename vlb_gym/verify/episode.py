"""Running one episode of any policy under the robustness wrapper."""

from __future__ import annotations

import time
import traceback
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any, Protocol

import numpy as np

from vlb_gym.core.runtime import failure_cause
from vlb_gym.wrappers import RobustnessWrapper


class Policy(Protocol):
    """What campaigns run: a behavior graph or (later) an adapted RL agent.

    ``predict`` returns ``(action, state)``; an action of None means the policy has finished.
    """

    def reset(self) -> None: ...

    def predict(self, observation: Any, state: Any = None, episode_start: Any = None,
                deterministic: bool = True) -> tuple[np.ndarray | None, Any]: ...


@dataclass(frozen=True)
class EpisodeResult:
    """One episode's outcome: rho_B and enough to replay it (``seed``)."""

    index: int
    seed: int
    rho: int
    finished: bool
    primitives: int
    failed_certificates: int
    reason: str | None
    seconds: float
    cause: str | None = None  # the failure's class, for grouping (see failure_cause)

    @property
    def success(self) -> bool:
        return self.rho > 0

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def run_episode(env: RobustnessWrapper, policy: Policy, seed: int, index: int = 0,
                stop_on_failure: bool = True,
                on_step: Callable[[dict[str, Any]], None] | None = None) -> EpisodeResult:
    """Run ``policy`` from ``env.reset(seed=seed)`` until it finishes or the episode ends.

    Any exception from the policy or the environment fails this episode (rho_B = -1, with the
    reason) instead of propagating. With ``stop_on_failure`` the episode stops at the first failed
    certificate, since rho_B is then already -1. ``on_step`` is called with None after the
    reset and with every step's info after the step.
    """
    started = time.perf_counter()
    try:
        obs, _ = env.reset(seed=seed)
        policy.reset()
        if on_step is not None:
            on_step(None)
        while env.summary is None:
            action, _ = policy.predict(obs)
            if action is None:
                env.end(finished=True)
                break
            obs, _, _, _, info = env.step(action)
            if on_step is not None:
                on_step(info)
            if stop_on_failure and env.failed:
                env.end(finished=False)
    except Exception as exc:  # an episode's failure, never the campaign's end
        frame = traceback.extract_tb(exc.__traceback__)[-1]
        env.end(finished=False, reason=f"{type(exc).__name__}: {exc} "
                                       f"({frame.filename.rsplit('/', 1)[-1]}:{frame.lineno})",
                cause=failure_cause(exc))
    summary = env.summary
    return EpisodeResult(index, int(seed), summary["rho_B"], summary["finished"],
                         summary["primitives"], summary["failed_certificates"],
                         summary["failure_reason"], time.perf_counter() - started,
                         summary["failure_cause"])

