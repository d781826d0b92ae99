"""Statistical methods: how a campaign's episodes become a claim about ``P[success]``.

A campaign tests ``P[success] >= 1 - epsilon`` at level ``delta``. A :class:`Method` sees the
episodes' outcomes (in index order when it may stop early), says when it has decided, and gives
the report's claim: its keys and its words. A campaign's plan names its method (``"fixed-N"``
or ``"sequential"``); :data:`METHODS` maps the names to the classes, so a new method is one
class here and nothing else changes: the campaign, the store, the report and the CLI ask the
method, never the name.

* :class:`FixedN`: N fixed before the campaign, every episode run; the binomial tail gives the
  confidence and Clopper-Pearson the lower bound (:mod:`.bounds`).
* :class:`Sequential`: episodes until the anytime-valid test of :mod:`.sequential` certifies or
  refutes the claim, N at most.
"""

from __future__ import annotations

import abc
import math
from collections.abc import Iterable, Mapping
from typing import Any, ClassVar

from . import bounds, sequential


class Decider(abc.ABC):
    """What every statistical method is, of campaigns and of comparisons alike: it observes
    outcomes one by one (in index order when it may stop early), says when it has decided, and
    gives the report's claim, in keys and in words."""

    name: ClassVar[str]
    #: whether it may decide before the last outcome: it is then fed outcomes in index order
    #: (whatever order workers finish them in), and those past its decision are dropped
    stops_early: ClassVar[bool]

    def observe(self, outcome: Any) -> None:
        """One more outcome (refused once the method has decided)."""
        if self.decided:
            raise RuntimeError(f"{self.name}: the method has decided already")
        self._count(outcome)

    @abc.abstractmethod
    def _count(self, outcome: Any) -> None:
        """Take ``outcome`` into the method's counts."""

    def feed(self, outcomes: Iterable[Any]) -> int:
        """Observe ``outcomes`` (in index order) until the method decides; how many it used."""
        used = 0
        for outcome in outcomes:
            if self.decided:
                break
            self.observe(outcome)
            used += 1
        return used

    @property
    @abc.abstractmethod
    def decided(self) -> bool:
        """Whether the run may stop now."""

    def caveats(self) -> list[str]:
        """What to tell the user before the run (a plan that cannot reach a decision, say);
        none by default."""
        return []

    @abc.abstractmethod
    def claim(self) -> dict[str, Any]:
        """The report's keys for the claim (``complete`` and ``statement`` at least)."""

    @staticmethod
    @abc.abstractmethod
    def lines(report: Mapping[str, Any]) -> list[str]:
        """The claim of ``report`` in words, as the command prints it."""


class Method(Decider):
    """A statistical method for one campaign of at most ``episodes`` episodes; an outcome is
    an episode's success. Its claim has at least ``complete``, ``confidence``,
    ``lower_bound`` and ``statement``."""

    def __init__(self, epsilon: float, delta: float, episodes: int):
        bounds._check_probability("epsilon", epsilon)
        bounds._check_probability("delta", delta)
        if not isinstance(episodes, int) or isinstance(episodes, bool) or episodes < 1:
            raise ValueError(f"episodes must be a positive integer (got {episodes!r})")
        self.epsilon, self.delta, self.episodes = epsilon, delta, episodes
        self.successes = self.failures = 0

    @classmethod
    @abc.abstractmethod
    def default_episodes(cls, epsilon: float, delta: float) -> int:
        """N when the campaign names none."""

    @property
    def n(self) -> int:
        return self.successes + self.failures

    def _count(self, success: bool) -> None:
        if success:
            self.successes += 1
        else:
            self.failures += 1


class FixedN(Method):
    """N fixed in advance; every episode counts."""

    name = "fixed-N"
    stops_early = False

    @classmethod
    def default_episodes(cls, epsilon: float, delta: float) -> int:
        return bounds.min_episodes(epsilon, 1.0 - delta, 0)

    @property
    def decided(self) -> bool:
        return self.n >= self.episodes

    def claim(self) -> dict[str, Any]:
        eps, delta = self.epsilon, self.delta
        conf, low = _binomial(self.n, self.failures, eps, delta)
        complete = self.n == self.episodes
        statement = (f"{_at_least(eps)} with confidence {bounds.floor_str(conf)}; "
                     f"P[success] >= {bounds.floor_str(low)} at confidence level "
                     f"{bounds.one_minus_str(delta)} (one-sided Clopper-Pearson)")
        if not complete:
            statement = (f"no guarantee: {self.n} of the {self.episodes} episodes fixed in "
                         "advance ran, and which ones finished first is not random")
        return {"complete": complete, "confidence": conf, "lower_bound": low,
                "miss_probability": bounds.miss_probability(self.n, self.failures, eps)
                if self.n else 1.0,
                "statement": statement}

    @staticmethod
    def lines(report: Mapping[str, Any]) -> list[str]:
        if not report["complete"]:  # the figures of a part would read as a guarantee
            return [f"  no guarantee until all {report['planned_episodes']} episodes ran: the "
                    "ones stored finished first (failures can end sooner), so their figures "
                    "are not printed"]
        return [f"  {_at_least(report['epsilon'])} with confidence "
                f"{bounds.floor_str(report['confidence'])}",
                f"  P[success] >= {bounds.floor_str(report['lower_bound'])} at confidence level "
                f"{bounds.one_minus_str(report['delta'])} (one-sided Clopper-Pearson)"]


class Sequential(Method):
    """Until the anytime-valid test decides, N (the cap) at most."""

    name = "sequential"
    stops_early = True

    def __init__(self, epsilon: float, delta: float, episodes: int):
        super().__init__(epsilon, delta, episodes)
        self.test = sequential.SequentialTest(epsilon, delta)

    @classmethod
    def default_episodes(cls, epsilon: float, delta: float) -> int:
        return sequential.default_max_episodes(epsilon, delta)

    def _count(self, success: bool) -> None:
        super()._count(success)
        self.test.update(success)

    def earliest_certification(self) -> int:
        """The first episode at which the test can certify: after that many successes and no
        failure (``log M_n(1 - eps)`` grows with n along that path; doubling, then
        bisection)."""
        a, b = sequential.prior(self.epsilon)
        p0, threshold = 1.0 - self.epsilon, -math.log(self.delta)

        def certifies(n: int) -> bool:
            return sequential.log_mixture(n, 0, p0, a, b) >= threshold

        high = 1
        while not certifies(high):
            high *= 2
        low = high // 2  # certifies(low) is False (or low is 0)
        while high - low > 1:
            middle = (low + high) // 2
            low, high = (low, middle) if certifies(middle) else (middle, high)
        return high

    def caveats(self) -> list[str]:
        earliest = self.earliest_certification()
        if earliest > self.episodes:
            return [f"with at most {self.episodes} episodes nothing can be certified: the test "
                    f"cannot certify before episode {earliest} (raise --max-episodes)"]
        return []

    @property
    def decided(self) -> bool:
        return self.test.decision is not None or self.n >= self.episodes

    def claim(self) -> dict[str, Any]:
        test, eps, delta = self.test, self.epsilon, self.delta
        low, high = test.bounds()
        decision = test.decision or "undecided"
        p0, level = bounds.one_minus_str(eps), bounds.one_minus_str(delta)
        words = {
            "certified": f"certified: P[success] >= {p0} at level {level}, anytime-valid "
                         f"(stopped after {test.n} episodes)",
            "refuted": f"refuted: P[success] < {p0} at level {level}, anytime-valid "
                       f"(stopped after {test.n} episodes)",
            "undecided": f"undecided after {test.n} episodes (the cap): nothing is certified",
        }[decision]
        conf, low_n = _binomial(self.n, self.failures, eps, delta)
        return {
            "complete": self.decided,  # a stored campaign may stop before its test decided
            "test": sequential.TEST_NAME,
            "prior": list(sequential.prior(eps)),
            "guarantee": sequential.guarantee(eps, delta),
            "decision": decision,
            "stopped_at": test.stopped_at,
            "max_episodes": self.episodes,
            "fixed_n_plan": FixedN.default_episodes(eps, delta),
            # the fixed-N keys, with their anytime-valid meaning in this mode
            "confidence": test.confidence(),
            "miss_probability": min(1.0, math.exp(-test.best_log_evidence)),
            "lower_bound": low,
            "upper_bound": high,
            "statement": f"{words}; P[success] in [{bounds.floor_str(low)}, "
                         f"{bounds.ceil_str(high)}] at confidence level {level}, "
                         f"simultaneously for all n ({sequential.TEST_NAME})",
            "fixed_n_description": {
                "confidence": conf, "lower_bound": low_n,
                "note": "Clopper-Pearson figures of the episodes run, for description only: the "
                        "number of episodes was not fixed in advance, so they are no guarantee"},
        }

    @staticmethod
    def lines(report: Mapping[str, Any]) -> list[str]:
        p0 = bounds.one_minus_str(report["epsilon"])
        level = bounds.one_minus_str(report["delta"])
        a, b = report["prior"]
        decision, stopped = report["decision"], report["stopped_at"]
        if decision == "certified":
            head = (f"  CERTIFIED after {stopped} episodes: P[success] >= {p0} at confidence "
                    f"level {level}, valid however often the test looked")
        elif decision == "refuted":
            head = (f"  REFUTED after {stopped} episodes: P[success] < {p0} at confidence "
                    f"level {level}, valid however often the test looked")
        elif not report["complete"]:
            head = (f"  UNDECIDED so far, after {report['episodes']} episodes: the campaign was "
                    "interrupted; nothing is certified")
        else:
            head = (f"  UNDECIDED after {report['episodes']} episodes (the cap, --max-episodes): "
                    f"neither P[success] >= {p0} nor its negation is established; nothing is "
                    "certified. A rerun with another seed is a new test: each may be wrong with "
                    f"probability {report['delta']:g}, so r tests together up to r x "
                    f"{report['delta']:g}")
        return [
            head,
            f"  anytime-valid: P[success] in [{bounds.floor_str(report['lower_bound'])}, "
            f"{bounds.ceil_str(report['upper_bound'])}] at confidence level {level}, "
            "simultaneously for every number of episodes",
            f"  test: {report['test']}, mixing prior Beta({a:g}, {b:g}); Ville's inequality: the "
            f"true P[success] leaves the interval at some n with probability <= "
            f"{report['delta']:g}",
            f"  fixed-N plan for comparison: {report['fixed_n_plan']} episodes with no failure "
            "('vlb plan')",
        ]


def _binomial(n: int, failures: int, epsilon: float, delta: float) -> tuple[float, float]:
    """The fixed-N confidence in the claim and the Clopper-Pearson lower bound (0 with no
    episodes)."""
    if not n:
        return 0.0, 0.0
    return bounds.confidence(n, failures, epsilon), bounds.lower_bound(n, failures, delta)


def _at_least(epsilon: float) -> str:
    return f"P[success] >= {bounds.one_minus_str(epsilon)}"


METHODS: dict[str, type[Method]] = {m.name: m for m in (FixedN, Sequential)}
"""Every statistical method, by the name a campaign's plan gives."""


def method_named(name: str) -> type[Method]:
    """The method called ``name``; ValueError naming the known ones otherwise."""
    try:
        return METHODS[name]
    except KeyError:
        raise ValueError(f"unknown statistical method {name!r} (known: "
                         f"{', '.join(METHODS)})") from None
