"""The episode loop: one code path for when a policy's episode ends, whoever drives it.

Campaigns and the dry run loop over :class:`PolicyEpisode` in
:func:`vlb_gym.verify.episode.run_episode`; :class:`~.behavior.BehaviorFinished` hands its
steps to one, so that a standard Gymnasium loop sees the episodes a campaign scores.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from vlb_gym.core.runtime import failure_cause

from .robustness import RobustnessWrapper


class PolicyEpisode:
    """Episodes of ``policy`` scored by ``robustness``, a primitive at a time, reset and stepped
    through ``env`` (default: ``robustness`` itself; a wrapper around it, e.g. a step bound).

    After :meth:`reset` and after each :meth:`step`, :attr:`action` is the policy's next action
    (and :attr:`state` the state it returned), or None once the episode has ended, rho_B then
    in ``robustness.summary``. The episode ends when

    * the policy finishes (its action is None): finished;
    * with ``stop_on_failure``, a certificate or a promise has failed (rho_B is -1 already);
    * ``max_primitives`` primitives ran: not finished (cause ``"primitive limit"``);
    * the policy raises one of ``caught``: not finished, the exception the reason;
    * the environment ends it, or a wrapper outside ``robustness`` does (terminated is
      finished, truncated is not: :meth:`RobustnessWrapper.ended_by`).

    Any other exception propagates, to the caller's loop.
    """

    def __init__(self, robustness: RobustnessWrapper, policy: Any, stop_on_failure: bool = True,
                 max_primitives: int | None = None,
                 caught: tuple[type[Exception], ...] = (), env: Any = None):
        if max_primitives is not None and (not isinstance(max_primitives, int)
                                           or max_primitives < 0):
            raise ValueError(f"max_primitives must be a non-negative integer "
                             f"(got {max_primitives!r})")
        self.robustness, self.policy = robustness, policy
        self.env = robustness if env is None else env
        self.stop_on_failure, self.max_primitives, self.caught = (stop_on_failure,
                                                                   max_primitives, caught)
        self.action: Any = None
        self.state: Any = None
        self.primitives = 0

    @property
    def ended(self) -> bool:
        return self.robustness.summary is not None

    def reset(self, seed: int | None = None, options: dict[str, Any] | None = None,
              on_reset: Callable[[dict[str, Any]], None] | None = None
              ) -> tuple[Any, dict[str, Any]]:
        """Reset the env (``on_reset`` sees its info) and the policy (with the episode's seed),
        and ask for the first action."""
        self.action, self.state, self.primitives = None, None, 0
        obs, info = self.env.reset(seed=seed, options=options)
        if on_reset is not None:
            on_reset(info)
        self.policy.reset(seed=seed)
        self._decide(obs)
        return obs, info

    def step(self, on_step: Callable[[dict[str, Any], Any], None] | None = None
             ) -> tuple[Any, Any, bool, bool, dict[str, Any]]:
        """Apply :attr:`action`; ``on_step`` sees the step's info and the state that chose the
        action before the policy is asked for the next one."""
        if self.action is None:
            raise RuntimeError("the episode has ended (rho_B is recorded); call reset()")
        state = self.state
        obs, reward, terminated, truncated, info = self.env.step(self.action)
        self.primitives += 1
        self.action = None
        if on_step is not None:
            on_step(info, state)
        if terminated or truncated:  # also by a wrapper outside the robustness wrapper
            info = {**info, **self.robustness.ended_by(terminated, truncated)}
        if self.stop_on_failure and self.robustness.failed:
            info = {**info, **self.robustness.end(finished=False)}
        elif not self.ended:
            self._decide(obs)
        return obs, reward, terminated, truncated, info

    def _decide(self, obs: Any) -> None:
        scored = self.robustness
        try:
            action, self.state = scored.act(self.policy, obs)
        except self.caught as exc:
            scored.end(False, f"{type(exc).__name__}: {exc}", failure_cause(exc))
            return
        if action is None:
            scored.end(finished=True)
        elif self.stop_on_failure and scored.failed:  # a sub-behavior broke its promise
            scored.end(finished=False)
        elif self.max_primitives is not None and self.primitives >= self.max_primitives:
            scored.end(False, f"stopped after {self.max_primitives} primitives",
                       "primitive limit")
        else:
            self.action = action
