"""Paired comparisons of two behaviors or agents: the same reset seeds, one test of ``d = P_B -
P_A`` (:mod:`.paired`).

A :class:`ComparisonConfig` names A and B (policy references, each with its own env kwargs
added to the shared ones), the margin, the level and the method. :class:`Comparison` prepares
the two sides as campaigns (each env made and checked, each policy loaded, an agent on the env
it was trained on) and makes the plan; pair ``i`` runs episode ``i`` of A and episode ``i`` of B,
both reset with the campaign seed's ``i``-th child (:func:`~.records.episode_seed`), run by the
engine as campaigns are (:class:`~.engine.Study`: backends, store and resume). The report
(:class:`ComparisonReport`) is built from the plan and the pairs alone.
"""

from __future__ import annotations

import dataclasses
import functools
import platform
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

from vlb_gym.core.formats import CURRENT

from .campaign import Campaign, CampaignConfig, episode_runner, lightened
from .engine import Study, run_where
from .episode import EpisodeResult
from .inputs import ShippedRunner
from .paired import claim_words
from .paired_methods import PairedMethod, paired_method_named
from .ray_connect import RayOptions
from .records import ComparisonConfig, ComparisonPlan, PairResult, Plan
from .report import (JsonReport, failures_by_cause, one_line, replay_command, shown_path,
                     where_listed)
from .store import CampaignStore, ComparisonStore


def _side(config: ComparisonConfig, name: str) -> Campaign:
    """Side ``name`` prepared; a ValueError says which side it is about."""
    try:
        return Campaign(config.side(name))
    except ValueError as exc:
        raise ValueError(f"{name.upper()}: {exc}") from None


def pair_runner(a: CampaignConfig, b: CampaignConfig, built: tuple[Any, Any] | None = None
                ) -> Callable[[int], PairResult]:
    """What runs pair ``index``: episode ``index`` of each side (each worker calls it once)."""
    run_a = episode_runner(a, built[0] if built else None)
    run_b = episode_runner(b, built[1] if built else None)
    return lambda index: PairResult(index, run_a(index), run_b(index))


@dataclass(frozen=True)
class ShippedPair:
    """A backend's ``setup`` for pairs: both sides built from their shipped inputs."""

    a: ShippedRunner
    b: ShippedRunner

    def __call__(self) -> Callable[[int], PairResult]:
        return pair_runner(self.a.config, self.b.config, (self.a.build(), self.b.build()))


class Comparison(Study[PairResult, "ComparisonReport"]):
    """A comparison prepared once: both sides' campaigns (a bad file or agent fails here, before
    any pair) and the :attr:`plan`; its unit is a pair, run by the engine
    (:class:`~.engine.Study`). Close it when done (or use it as a context manager)."""

    store_kind: ClassVar[type[CampaignStore]] = ComparisonStore
    unit = "pair"

    def __init__(self, config: ComparisonConfig):
        self.config = config
        self.sides: tuple[Campaign, Campaign] = (_side(config, "a"),)  # type: ignore
        try:
            self.sides = (self.sides[0], _side(config, "b"))
        except BaseException:
            self.sides[0].close()
            raise
        self.files = [path for side in self.sides for path in side.files]
        self.plan = ComparisonPlan(config.env_id, self.sides[0].plan, self.sides[1].plan,
                                   config.pairs, config.margin, config.alpha, config.seed,
                                   config.method)

    def __enter__(self) -> Comparison:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        for side in self.sides:
            side.close()

    def differences(self) -> list[str]:
        """What differs between the sides' envs: their pairs share reset seeds, not the env
        (the kwargs, else the sampling distribution)."""
        a, b = (side.plan for side in self.sides)
        if a.env_kwargs != b.env_kwargs:
            return [f"env kwargs: A {a.env_kwargs!r}, B {b.env_kwargs!r}"]
        if a.sampling_distribution != b.sampling_distribution:
            return ["sampling distributions (see the report)"]
        return []

    def pairs(self, indices: Sequence[int] | None = None, workers: int = 1,
              backend: str = "process", ray: RayOptions | None = None
              ) -> Iterator[PairResult]:
        """Stream the pairs ``indices`` (default: all) as they finish."""
        a, b = self.sides
        indices = range(self.config.pairs) if indices is None else indices
        built = ((a.env, a.policy), (b.env, b.policy))
        shipped = ShippedPair(*(ShippedRunner(side.config, side.inputs, episode_runner)
                                for side in self.sides))
        return run_where(shipped, functools.partial(pair_runner, a.config, b.config, built),
                         indices, workers, backend, ray, self.preloads)

    units = pairs

    @property
    def planned(self) -> int:
        return self.config.pairs

    @property
    def preloads(self) -> Sequence[str]:
        return [module for side in self.sides for module in side.preloads]

    @classmethod
    def method_of(cls, plan: ComparisonPlan) -> PairedMethod:
        return paired_method_named(plan.method)(plan.margin, plan.alpha, plan.pairs)

    @staticmethod
    def outcome(result: PairResult) -> tuple[bool, bool]:
        return result.a.success, result.b.success

    @staticmethod
    def seconds(result: PairResult) -> float:
        return result.a.seconds + result.b.seconds

    @staticmethod
    def lightened(result: PairResult) -> PairResult:
        return PairResult(result.index, lightened(result.a), lightened(result.b))

    @classmethod
    def report(cls, plan: ComparisonPlan, results: Sequence[PairResult], seconds: float,
               workers: int | None, backend: str | None, store: str | None = None,
               ran: int | None = None) -> ComparisonReport:
        return ComparisonReport.build(plan, results, seconds, workers, backend, store, ran)


def _side_summary(plan: Plan, episodes: list[EpisodeResult]) -> dict[str, Any]:
    successes = sum(r.success for r in episodes)
    recorded = plan.to_dict()
    return {**{key: recorded[key] for key in ("policy", "env_kwargs", "env_modules",
                                              "sampling_distribution", "content_sha256")},
            "successes": successes,
            "failures": len(episodes) - successes,
            "mean_primitives": (sum(r.primitives for r in episodes) / len(episodes))
            if episodes else 0.0,
            "failures_by_cause": failures_by_cause(episodes)}


class ComparisonReport(JsonReport):
    """A comparison's report: its JSON keys, with :meth:`summary` in words."""

    @classmethod
    def build(cls, plan: ComparisonPlan, results: Sequence[PairResult], seconds: float,
              workers: int | None, backend: str | None = "process", store: str | None = None,
              ran: int | None = None) -> ComparisonReport:
        """The report of the comparison of ``plan`` from its ``results`` (those its method
        used, in index order)."""
        method = paired_method_named(plan.method)(plan.margin, plan.alpha, plan.pairs)
        results = sorted(results, key=lambda r: r.index)
        results = results[:method.feed((r.a.success, r.b.success) for r in results)]
        counts = method.counts
        n = counts.n
        data = {
            "format": CURRENT["report"], "env_id": plan.env_id, "mode": method.name, "pairs": n,
            "planned_pairs": plan.pairs, "seed": plan.seed, "margin": plan.margin,
            "alpha": plan.alpha, "claim": claim_words(plan.margin),
            "a": _side_summary(plan.a, [r.a for r in results]),
            "b": _side_summary(plan.b, [r.b for r in results]),
            "counts": dataclasses.asdict(counts),
            "difference": (counts.b_only - counts.a_only) / n if n else 0.0,
            **method.claim(),
            "discordant_pairs": [{"index": r.index, "seed": r.a.seed,
                                  "succeeded": "a" if r.a.success else "b"}
                                 for r in results if r.a.success != r.b.success],
            "sampling_distribution": plan.a.sampling_distribution,
            "wall_seconds": seconds,
            "pairs_per_second": (n if ran is None else ran) / seconds if seconds > 0 else None,
            "workers": workers, "backend": backend,
            "machine": f"{platform.machine()} {platform.system()}, Python "
                       f"{platform.python_version()}" if workers is not None else None,
        }
        return cls(data, store)

    def replay_command(self, side: str, seed: int) -> str | None:
        """The command that re-runs side ``side``'s episode with reset seed ``seed``."""
        plan = self[side]
        return replay_command(plan["policy"], self["env_id"], plan["env_kwargs"],
                              plan["env_modules"], seed)

    def summary(self, report_path: str | None = None) -> str:
        """The outcome in words, as ``vlb compare`` prints it."""
        counts, n = self["counts"], self["pairs"]
        early = paired_method_named(self["mode"]).stops_early
        most = f"at most {self['planned_pairs']}; " if early else ""
        how = (f"{self['workers']} worker(s), {self['wall_seconds']:.1f} s"
               if self["workers"] is not None else
               f"from the store: the episodes' own time {self['wall_seconds']:.1f} s")
        a, b = self["a"], self["b"]
        lines = [f"{self['env_id']}: A = {shown_path(a['policy']['ref'])}, B = "
                 f"{shown_path(b['policy']['ref'])}: {self['mode']}, {n} pairs ({most}seed "
                 f"{self['seed']}, {how})"]
        if not self["complete"]:
            lines.append(f"  INCOMPLETE: {n} of {'at most ' if early else ''}"
                         f"{self['planned_pairs']} pairs stored (resume with the same vlb "
                         "compare command and --store)")
        lines += [f"  A succeeded {a['successes']}/{n}, B {b['successes']}/{n}; pairs: both "
                  f"{counts['both']}, only A {counts['a_only']}, only B {counts['b_only']}, "
                  f"neither {counts['neither']}"]
        lines += paired_method_named(self["mode"]).lines(self)
        lines.append(f"  holds for: {self['sampling_distribution']}")
        if b["sampling_distribution"] != self["sampling_distribution"]:
            lines[-1] = f"  holds for A: {self['sampling_distribution']}"
            lines.append(f"  holds for B: {b['sampling_distribution']}")
        differ = self["discordant_pairs"]
        for item in differ[:5]:
            failed = "b" if item["succeeded"] == "a" else "a"
            command = self.replay_command(failed, item["seed"])
            lines.append(f"  pair {item['index']} (seed {item['seed']}): only "
                         f"{item['succeeded'].upper()} succeeded"
                         + (f"; replay {failed.upper()}'s failure: {command}" if command else ""))
        if len(differ) > 5:
            lines.append(f"  ... {len(differ) - 5} more discordant pairs "
                         f"{where_listed(report_path, self.store)}")
        if report_path:
            lines.append(f"  report: {report_path}")
        return "\n".join(one_line(line) for line in lines)


def report_from_store(store: ComparisonStore) -> ComparisonReport:
    """The report of the comparison in ``store``, rebuilt from the store alone (see
    :meth:`~.engine.Study.from_store`)."""
    return Comparison.from_store(store)[0]
