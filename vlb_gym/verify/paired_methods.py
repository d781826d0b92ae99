"""The statistical methods of paired comparisons: how the pairs of a comparison become its
decision (the statistics are :mod:`.paired`'s).

:class:`PairedMethod` has the shape of a campaign's :class:`~.methods.Method`, fed
``(a_success, b_success)``, and registered beside it (:data:`~.methods.REGISTRY`, unit
``"pair"``); :data:`PAIRED_METHODS` maps the names a comparison's plan gives (``"fixed-N"``,
``"sequential"``) to the classes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from . import bounds
from .methods import REGISTRY, Decider, method_named, not_complete, register
from .paired import (BETS, SEQUENTIAL_TEST, PairCounts, anytime_bounds, check_alpha, check_margin,
                     claim_words, log_wealth, mcnemar_p, refuted_words, unconditional_bounds,
                     unconditional_p)


class PairedMethod(Decider):
    """A statistical method for a comparison of at most ``pairs`` pairs, testing ``d <=
    -margin`` at level ``alpha``; an outcome is a pair's ``(a_success, b_success)``. Its claim
    has at least ``complete``, ``decision`` (``"shown"``, ``"refuted"``, ``"not shown"`` or
    ``"undecided"``), ``interval`` and ``statement``."""

    unit = "pair"

    def __init__(self, margin: float, alpha: float, pairs: int):
        check_margin(margin)
        check_alpha(alpha)
        if not isinstance(pairs, int) or isinstance(pairs, bool) or pairs < 1:
            raise ValueError(f"pairs must be a positive integer (got {pairs!r})")
        self.margin, self.alpha, self.pairs = margin, alpha, pairs
        self.counts = PairCounts()

    def _count(self, outcome: tuple[bool, bool]) -> None:
        self.counts = self.counts.add(*outcome)


@register
class FixedPairs(PairedMethod):
    """``pairs`` fixed in advance, all run; McNemar's exact test (margin 0) or the exact
    unconditional test (margin > 0)."""

    name = "fixed-N"
    stops_early = False

    @property
    def decided(self) -> bool:
        return self.counts.n >= self.pairs

    def claim(self) -> dict[str, Any]:
        counts, margin, alpha = self.counts, self.margin, self.alpha
        complete = counts.n == self.pairs
        mirror = PairCounts(counts.both, counts.b_only, counts.a_only, counts.neither)
        if margin == 0:  # the mirror test decides "refuted": mirrored data, mirrored verdicts
            test, p = "McNemar's exact test (one-sided)", mcnemar_p(counts)
            against = mcnemar_p(mirror)
        else:
            test = "exact unconditional test of b_only - a_only (one-sided)"
            p = unconditional_p(counts, -margin)
            against = unconditional_p(mirror, margin)
        low, high = unconditional_bounds(counts, alpha) if counts.n else (-1.0, 1.0)
        decision = "shown" if p <= alpha else "refuted" if against <= alpha else "not shown"
        if not complete:
            decision = "incomplete"
        statement = (f"{claim_words(margin)}: {decision} at level {alpha!r} ({test}, "
                     f"p = {bounds.ceil_str(p)})")
        if decision == "refuted":  # what was shown is the mirror claim, with its own p-value
            statement = (f"{refuted_words(margin)}: shown at level {alpha!r} ({test}, mirrored, "
                         f"p = {bounds.ceil_str(against)}), refuting: {claim_words(margin)}")
        if not complete:
            statement = (f"no decision: {counts.n} of the {self.pairs} pairs fixed in advance "
                         "ran, and which ones finished first is not random")
        note = f"each bound at level {bounds.one_minus_str(alpha)} (the exact unconditional test " \
            "inverted)"
        if margin == 0:
            note += ("; the decision is McNemar's, conditional on the discordant pairs, and may "
                     "differ from the interval's at the edge")
        return {"complete": complete, "test": test, "p_value": p, "p_value_against": against,
                "decision": decision, "interval": [low, high], "interval_note": note,
                "statement": statement}

    @staticmethod
    def lines(report: Mapping[str, Any]) -> list[str]:
        if not report["complete"]:
            return [not_complete(report["planned_pairs"], "pairs", "decision")]
        low, high = report["interval"]
        if report["decision"] == "refuted":
            head = (f"  REFUTED: {refuted_words(report['margin'])} is shown, at level "
                    f"{report['alpha']!r} ({report['test']}, mirrored, p = "
                    f"{bounds.ceil_str(report['p_value_against'])}), refuting: "
                    f"{report['claim']}")
        else:
            verdict = {"shown": "SHOWN", "not shown": "NOT SHOWN"}[report["decision"]]
            head = (f"  {verdict}: {report['claim']}, at level {report['alpha']!r} "
                    f"({report['test']}, p = {bounds.ceil_str(report['p_value'])})")
        return [head,
                f"  P_B - P_A in [{bounds.floor_str(low, 4)}, {bounds.ceil_str(high, 4)}]: "
                f"{report['interval_note']}"]


@register
class SequentialPairs(PairedMethod):
    """Pairs until the betting test decides, ``pairs`` (the cap) at most."""

    name = "sequential"
    stops_early = True

    def __init__(self, margin: float, alpha: float, pairs: int):
        super().__init__(margin, alpha, pairs)
        self.decision: str | None = None
        self.stopped_at: int | None = None

    def _count(self, outcome: tuple[bool, bool]) -> None:
        super()._count(outcome)
        threshold = -math.log(self.alpha)
        if log_wealth(self.counts, -self.margin, "below") >= threshold:
            self.decision = "shown"
        elif log_wealth(self.counts, -self.margin, "above") >= threshold:
            self.decision = "refuted"
        if self.decision:
            self.stopped_at = self.counts.n

    @property
    def decided(self) -> bool:
        return self.decision is not None or self.counts.n >= self.pairs

    def earliest_decision(self) -> int:
        """The fewest pairs after which the test can show the claim (every pair "only B")."""
        threshold, n = -math.log(self.alpha), 0
        while True:
            n += 1
            if log_wealth(PairCounts(b_only=n), -self.margin, "below") >= threshold:
                return n

    def caveats(self) -> list[str]:
        earliest = self.earliest_decision()
        if earliest > self.pairs:
            return [f"with at most {self.pairs} pairs nothing can be shown: the test cannot "
                    f"decide before pair {earliest} (raise --max-pairs)"]
        return []

    def claim(self) -> dict[str, Any]:
        low, high = anytime_bounds(self.counts, self.alpha)
        decision = self.decision or "undecided"
        return {"complete": self.decided, "test": SEQUENTIAL_TEST, "bets": list(BETS),
                "decision": decision, "stopped_at": self.stopped_at, "max_pairs": self.pairs,
                "log_wealth": {"for": log_wealth(self.counts, -self.margin, "below"),
                               "against": log_wealth(self.counts, -self.margin, "above")},
                "interval": [low, high],
                "interval_note": f"anytime-valid, each bound at level "
                                 f"{bounds.one_minus_str(self.alpha)} for every n at once",
                "statement": f"{claim_words(self.margin)}: {decision} at level {self.alpha!r}, "
                             f"anytime-valid ({SEQUENTIAL_TEST}), after {self.counts.n} pairs"}

    @staticmethod
    def lines(report: Mapping[str, Any]) -> list[str]:
        decision, alpha = report["decision"], report["alpha"]
        if decision == "shown":
            head = (f"  SHOWN after {report['stopped_at']} pairs: {report['claim']}, at level "
                    f"{alpha!r}, valid however often the test looked")
        elif decision == "refuted":
            head = (f"  REFUTED after {report['stopped_at']} pairs: "
                    f"{refuted_words(report['margin'])}, at level {alpha!r}, valid however "
                    "often the test looked")
        elif not report["complete"]:
            head = (f"  UNDECIDED so far, after {report['pairs']} pairs: the comparison was "
                    "interrupted; nothing is shown")
        else:
            head = (f"  UNDECIDED after {report['pairs']} pairs (the cap, --max-pairs): nothing "
                    f"is shown. A rerun with another seed is a new test: each may be wrong with "
                    f"probability {alpha!r}, so r tests together up to r x {alpha!r}")
        low, high = report["interval"]
        return [head,
                f"  anytime-valid: P_B - P_A in [{bounds.floor_str(low, 4)}, "
                f"{bounds.ceil_str(high, 4)}], each bound at confidence level "
                f"{bounds.one_minus_str(alpha)}, simultaneously for every number of pairs",
                f"  test: {report['test']}"]


PAIRED_METHODS: dict[str, type[PairedMethod]] = REGISTRY["pair"]  # type: ignore[assignment]
"""The methods of comparisons, by the name a comparison's plan gives."""


def paired_method_named(name: str) -> type[PairedMethod]:
    """The comparison method called ``name`` (:func:`~.methods.method_named` of pairs)."""
    return method_named(name, "pair")
