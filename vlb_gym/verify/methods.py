"""Statistical methods: how a campaign's episodes become a claim about ``P[success]``.

A campaign tests ``P[success] >= 1 - epsilon`` at level ``delta``. A :class:`Method` sees the
episodes' outcomes (in index order when it may stop early), says when it has decided, and gives
the report's claim: its keys and its words. A campaign's plan names its method (``"fixed-N"``
or ``"sequential"``). Every method, of campaigns and of comparisons (:mod:`.paired_methods`),
is in one registry (:data:`REGISTRY`, by the unit it observes and its name): a new method is one
class marked :func:`register` and nothing else changes: the engine, the store, the report and
the CLI ask the method, never the name.

* :class:`FixedN`: N fixed before the campaign, every episode run; the binomial tail gives the
  confidence and Clopper-Pearson the lower bound (:mod:`.bounds`).
* :class:`Sequential`: episodes until the anytime-valid test of :mod:`.sequential` certifies or
  refutes the claim, N at most.
"""

from __future__ import annotations

import abc
import math
from collections.abc import Iterable, Mapping
from typing import Any, ClassVar, TypeVar

from vlb_gym.core.document import Block, Cell, Inline, Paragraph, Strong

from . import bounds, sequential


class Decider(abc.ABC):
    """What every statistical method is, of campaigns and of comparisons alike: it observes
    outcomes one by one (in index order when it may stop early), says when it has decided, and
    gives the report's claim, in keys and in words."""

    name: ClassVar[str]
    #: what one outcome is of: ``"episode"`` (a campaign's) or ``"pair"`` (a comparison's)
    unit: ClassVar[str]
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

    @staticmethod
    def paragraphs(report: Mapping[str, Any], where: list[Inline]) -> list[Block]:
        """The claim of ``report`` as the report folder's paragraphs, ``where`` saying of what
        and for which distribution; by default the claim's statement."""
        return [Paragraph([*where, ": ", str(report["statement"]), "."])]

    @staticmethod
    def rows(report: Mapping[str, Any]) -> list[list[Cell]]:
        """The rows the method adds to the report folder's table of numbers (its own keys)."""
        return []


D = TypeVar("D", bound=type[Decider])

REGISTRY: dict[str, dict[str, type[Decider]]] = {"episode": {}, "pair": {}}
"""Every statistical method: ``REGISTRY[unit][name]``, the unit it observes (``"episode"``,
``"pair"``) and the name a plan gives."""


def register(method: D) -> D:
    """Make ``method`` (a :class:`Decider` subclass with its ``unit`` and ``name``) one a plan
    can name; a class decorator."""
    REGISTRY[method.unit][method.name] = method
    return method


def method_named(name: str, unit: str = "episode") -> Any:
    """The method of ``unit`` called ``name``; ValueError naming the known ones otherwise."""
    known = REGISTRY[unit]
    try:
        return known[name]
    except KeyError:
        raise ValueError(f"unknown statistical method {name!r} (known: "
                         f"{', '.join(known)})") from None


def not_complete(planned: int, units: str, verdict: str) -> str:
    """The line a method prints for a run that stopped before its ``planned`` units."""
    return (f"  no {verdict} until all {planned} {units} ran: the ones stored finished first "
            "(failures can end sooner)")


class Method(Decider):
    """A statistical method for one campaign of at most ``episodes`` episodes; an outcome is
    an episode's success. Its claim has at least ``complete``, ``confidence``,
    ``lower_bound`` and ``statement``."""

    unit = "episode"

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


@register
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
            return [not_complete(report["planned_episodes"], "episodes", "guarantee")
                    + ", so their figures are not printed"]
        return [f"  {_at_least(report['epsilon'])} with confidence "
                f"{bounds.floor_str(report['confidence'])}",
                f"  P[success] >= {bounds.floor_str(report['lower_bound'])} at confidence level "
                f"{bounds.one_minus_str(report['delta'])} (one-sided Clopper-Pearson)"]

    @staticmethod
    def paragraphs(report: Mapping[str, Any], where: list[Inline]) -> list[Block]:
        if not report["complete"]:  # a part of a fixed-N campaign certifies nothing
            return [Paragraph([Strong("No guarantee: "), str(report["statement"]), "."])]
        claim = bounds.one_minus_str(report["epsilon"])
        level = bounds.one_minus_str(report["delta"])
        conf, low, delta = report["confidence"], report["lower_bound"], report["delta"]
        return [
            Paragraph([*where, " succeeds with probability at least ", Strong(claim),
                       ", with confidence ", Strong(bounds.floor_str(conf)), "."]),
            Paragraph(["At confidence level ", Strong(level), " (delta = ", f"{delta:g}",
                       "), its probability of success is at least ",
                       Strong(bounds.floor_str(low)),
                       f" (one-sided Clopper–Pearson lower bound from N = {report['episodes']} "
                       f"episodes with k = {report['failures']} failures)."]),
            Paragraph(["Target confidence ", level, ": ",
                       Strong("met" if conf >= 1.0 - delta else "not met"),
                       ". N was fixed before the campaign; bounds are rounded down; the guarantee "
                       "holds for this sampling distribution only."])]


@register
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

    @staticmethod
    def paragraphs(report: Mapping[str, Any], where: list[Inline]) -> list[Block]:
        claim = bounds.one_minus_str(report["epsilon"])
        level = bounds.one_minus_str(report["delta"])
        decision = str(report.get("decision", "undecided"))
        low, high = report["lower_bound"], report.get("upper_bound", 1.0)
        stopped = report.get("stopped_at")
        stop_words = (f"stopped after {stopped} episodes" if stopped is not None else
                      "no decision within the cap of "
                      f"{report.get('max_episodes', report['episodes'])} episodes")
        verb = {"certified": [" succeeds with probability at least ", Strong(claim),
                              ": certified"],
                "refuted": [" succeeds with probability below ", Strong(claim), ": refuted"]}
        blocks: list[Block] = [
            Paragraph([*where, *verb.get(decision, [
                " has no certified probability of success at ", Strong(claim),
                ": undecided, nothing is certified"]),
                       f" at level {level} by an anytime-valid sequential test ({stop_words})."]),
            Paragraph(["Decision: ", Strong(decision), ". Anytime-valid confidence interval at "
                       f"level {level}, simultaneously for all n: P[success] in [",
                       Strong(bounds.floor_str(low)), ", ", Strong(bounds.ceil_str(high)),
                       "]; confidence in the claim: ",
                       Strong(bounds.floor_str(report["confidence"])), "."]),
            Paragraph(["Test: ", str(report.get("test", "?")), ". Guarantee: ",
                       str(report.get("guarantee", "?"))])]
        fixed = report.get("fixed_n_description") or {}
        if fixed:
            blocks.append(Paragraph([
                "Clopper–Pearson figures of these episodes, for description only: confidence ",
                bounds.floor_str(fixed.get("confidence", 0.0)), ", lower bound ",
                bounds.floor_str(fixed.get("lower_bound", 0.0)), ". ",
                str(fixed.get("note", ""))]))
        return blocks

    @staticmethod
    def rows(report: Mapping[str, Any]) -> list[list[Cell]]:
        return [["upper bound on P[success] (anytime-valid)",
                 bounds.ceil_str(report.get("upper_bound", 1.0))],
                ["decision", str(report.get("decision"))],
                ["stopped at", str(report.get("stopped_at"))],
                ["cap (max episodes)", str(report.get("max_episodes"))]]


def _binomial(n: int, failures: int, epsilon: float, delta: float) -> tuple[float, float]:
    """The fixed-N confidence in the claim and the Clopper-Pearson lower bound (0 with no
    episodes)."""
    if not n:
        return 0.0, 0.0
    return bounds.confidence(n, failures, epsilon), bounds.lower_bound(n, failures, delta)


def _at_least(epsilon: float) -> str:
    return f"P[success] >= {bounds.one_minus_str(epsilon)}"


METHODS: dict[str, type[Method]] = REGISTRY["episode"]  # type: ignore[assignment]
"""The methods of campaigns, by the name a campaign's plan gives."""
