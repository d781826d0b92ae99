"""A wrapper that scores every episode with the behavior robustness rho_B."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import gymnasium as gym

from vlb_gym.core.primitive import Failure
from vlb_gym.core.runtime import BehaviorPolicy
from vlb_gym.core.promise import Claim, Judging


def behavior_robustness(finished: bool, certificates: Iterable[bool]) -> int:
    """rho_B (the paper's eq. behavior_robustness): +1 iff the behavior finished and every
    certificate held (vacuously for none), else -1."""
    return 1 if finished and all(certificates) else -1


class RobustnessWrapper(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """Collects each step's certificate and writes rho_B into ``info`` when the episode ends.

    Works for any policy. The episode ends, and ``info`` gains the keys of :meth:`end`, when

    * the environment terminates (the task says it is finished: ``finished=True``),
    * it is truncated (``finished=False``), or
    * the caller calls :meth:`end` -- a behavior graph does so when it reaches a terminal node
      with no edge to take (``finished=True``), a runner when the policy raised (``False``).

    rho_B is +1 iff the behavior finished, every certificate held and every promise judged
    (:meth:`judge`) held, else -1: an inadmissible parameter, a failed controller, a broken
    promise, a runtime error in the behavior and running past the step bound all give -1.
    """

    def __init__(self, env: gym.Env):
        gym.utils.RecordConstructorArgs.__init__(self)
        super().__init__(env)
        self.certificates: list[bool] = []
        self.history: list[dict[str, Any]] = []  # every step's info, for replays
        self.promises: list[bool] = []
        self._reset_info: dict[str, Any] = {}
        self.first_failure: str | None = None
        self.first_cause: str | None = None
        self.summary: dict[str, Any] | None = None
        self._judging: Judging | None = None  # made at the first promise

    def reset(self, **kwargs: Any):
        self.certificates = []
        self.history = []
        self.promises = []
        self.first_failure = None
        self.first_cause = None
        self.summary = None
        if self._judging is not None:
            self._judging.new_episode()
        obs, self._reset_info = self.env.reset(**kwargs)
        return obs, self._reset_info

    def step(self, action: Any):
        if self.summary is not None:
            raise RuntimeError("the episode has ended (rho_B is recorded); call reset()")
        obs, reward, terminated, truncated, info = self.env.step(action)
        certificate = bool(info["certificate"])
        self.certificates.append(certificate)
        self.history.append(info)
        if not certificate and self.first_failure is None:
            self.first_failure = (f"step {len(self.certificates)}: {info['primitive']} "
                                  f"{info['param']}: {info.get('reason', 'certificate failed')}")
            self.first_cause = certificate_cause(info)
        if terminated or truncated:
            info = {**info, **self.ended_by(terminated, truncated)}
        return obs, reward, terminated, truncated, info

    def ended_by(self, terminated: bool, truncated: bool) -> dict[str, Any]:
        """The episode's summary if the env ended it (here or in a wrapper outside this one):
        terminated is finished, truncated is not (the step bound); else nothing."""
        if not (terminated or truncated):
            return {}
        bound = f"truncated: step bound reached after {len(self.certificates)} primitives"
        return self.end(terminated, None if terminated else bound,
                        None if terminated else "step bound")

    def act(self, policy: Any, observation: Any) -> tuple[Any, Any]:
        """``policy.predict(observation)``: the next action (None once it has finished) and the
        policy's state; a behavior's sub-behaviors (or itself) that have just finished hand
        their promises to :meth:`judge`. The decision step of the episode loop,
        :class:`~vlb_gym.wrappers.loop.PolicyEpisode`."""
        action, state = policy.predict(observation)
        if isinstance(policy, BehaviorPolicy):
            self.judge(policy.claims())
        return action, state

    def judge(self, claims: Iterable[Claim]) -> None:
        """Judge the promises of behaviors that have just finished, with the true state and
        the steps each ran; a broken one fails the episode like a failed certificate (cause
        ``"<behavior>: promise"``)."""
        for claim in claims:
            if self._judging is None:
                self._judging = Judging(self.env.unwrapped)
                self._judging.new_episode()
            problem = self._judging(claim, self.history, self._reset_info)
            self.promises.append(problem is None)
            if problem is not None and self.first_failure is None:
                self.first_failure = f"after step {len(self.history)}: {problem}"
                self.first_cause = f"{claim.behavior}: promise"

    @property
    def failed(self) -> bool:
        """Whether some certificate has already failed (rho_B will be -1)."""
        return self.first_failure is not None

    def end(self, finished: bool, reason: str | None = None,
            cause: str | None = None) -> dict[str, Any]:
        """End the episode; return (and keep in :attr:`summary`) rho_B and how it came about:
        ``failure_reason`` in words and ``failure_cause``, its class (see
        :func:`certificate_cause`; ``cause`` names it when the episode ends for another reason,
        e.g. ``"step bound"`` or ``"behavior runtime error"``)."""
        if self.summary is not None:
            return self.summary
        rho = behavior_robustness(finished, [*self.certificates, *self.promises])
        if rho < 0:  # the first failed certificate is the root cause when there is one
            reason = self.first_failure or reason or "behavior did not finish"
            cause = self.first_cause or cause or "did not finish"
        self.summary = {"rho_B": rho, "finished": bool(finished),
                        "primitives": len(self.certificates),
                        "failed_certificates": self.certificates.count(False),
                        "failure_reason": reason if rho < 0 else None,
                        "failure_cause": cause if rho < 0 else None}
        return self.summary


def certificate_cause(info: dict[str, Any]) -> str:
    """The class of a failed step, for grouping failures: ``"<primitive>: inadmissible
    parameter"``, ``"<primitive>: controller failed"`` or ``"<primitive>: certificate"`` with the
    failed parts of the terminal region in parentheses (e.g. ``"scoop: certificate (delivered)"``)."""
    primitive, failure = info["primitive"], info.get("failure")
    if failure == Failure.INADMISSIBLE:
        return f"{primitive}: inadmissible parameter"
    if failure == Failure.CONTROLLER:
        return f"{primitive}: controller failed"
    parts = [part for part, held in info.get("certificates", {}).items() if not held]
    return f"{primitive}: certificate" + (f" ({', '.join(parts)})" if parts else "")
