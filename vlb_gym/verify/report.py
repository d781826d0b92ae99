"""The report of a campaign: one object owns its JSON, its summary in words and its replay hints.

A report is built from the campaign's plan and its episode records alone (as a store holds
them), so a report rebuilt from a store equals the one the campaign printed.
"""

from __future__ import annotations

import json
import multiprocessing as mp
import os
import platform
import shlex
from collections.abc import Iterator, Mapping, Sequence
from typing import Any

from . import bounds, sequential
from .episode import EpisodeResult


def shown_path(ref: str) -> str:
    """A policy reference as printed: a file below the working directory relative to it."""
    if not os.path.isabs(ref):
        return ref
    relative = os.path.relpath(ref)
    return ref if relative.startswith("..") else relative


def failures_by_cause(results: Sequence[EpisodeResult], examples: int = 3) -> list[dict[str, Any]]:
    """Failed episodes grouped by cause (which primitive's certificate or which part of it,
    inadmissible parameters, controller failures, behavior runtime errors, the evaluation budget,
    the step bound), most frequent first, each with a few example episodes for replays."""
    groups: dict[str, list[EpisodeResult]] = {}
    for result in results:
        if not result.success:
            groups.setdefault(result.cause or "unknown", []).append(result)
    return [{"cause": cause, "count": len(failed), "seeds": [r.seed for r in failed[:examples]],
             "episodes": [r.index for r in failed[:examples]]}
            for cause, failed in sorted(groups.items(), key=lambda item: -len(item[1]))]


_REPLAY_OPTIONS = {"behavior": ["--behavior"], "sb3": ["--policy"],  # what 'vlb replay' takes
                   "sb3_sampled": ["--sample", "--policy"]}


class Report(Mapping[str, Any]):
    """A campaign's report: a read-only mapping of its JSON keys (those of ARCHITECTURE.md and
    more), with :meth:`summary` in words and :meth:`replay_command` for any episode.

    ``store`` is the path of the campaign's store, if it has one: replay hints then name it.
    """

    def __init__(self, data: dict[str, Any], store: str | None = None):
        self._data = data
        self.store = store

    def __getitem__(self, key: str) -> Any:
        return self._data[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def to_json(self) -> str:
        return json.dumps(self._data, indent=2) + "\n"

    # -- building -----------------------------------------------------------------------------
    @classmethod
    def fixed_n(cls, plan: dict[str, Any], results: Sequence[EpisodeResult], seconds: float,
                workers: int | None, backend: str | None = "process", store: str | None = None,
                ran: int | None = None) -> Report:
        """The report of a fixed-N campaign (complete or not: ``episodes`` counts ``results``;
        ``planned_episodes`` is N); ``ran`` episodes (default: all) took ``seconds``, the
        others were resumed from a store. A report rebuilt from a store knows no ``workers``
        or ``backend`` (None); its ``seconds`` are the episodes' own."""
        results = sorted(results, key=lambda r: r.index)
        n = len(results)
        failures = sum(not r.success for r in results)
        eps, delta = plan["epsilon"], plan["delta"]
        conf = bounds.confidence(n, failures, eps) if n else 0.0
        low = bounds.lower_bound(n, failures, delta) if n else 0.0
        data = {
            "env_id": plan["env_id"],
            "behavior": plan["policy"]["ref"],
            "policy": plan["policy"],
            "mode": "fixed-N",
            "episodes": n,
            "planned_episodes": plan["episodes"],
            "complete": n == plan["episodes"],
            "successes": n - failures,
            "failures": failures,
            "epsilon": eps,
            "confidence": conf,
            "delta": delta,
            "lower_bound": low,
            "seed": plan["seed"],
            "statement": (f"P[success] >= {bounds.one_minus_str(eps)} with confidence "
                          f"{bounds.floor_str(conf)}; P[success] >= {bounds.floor_str(low)} at "
                          f"confidence level {bounds.one_minus_str(delta)} "
                          "(one-sided Clopper-Pearson)"),
            "sampling_distribution": plan["sampling_distribution"],
            "env_kwargs": plan["env_kwargs"],
            "env_modules": plan["env_modules"],
            "content_sha256": plan["content_sha256"],
            "failed_episodes": [{"index": r.index, "seed": r.seed, "reason": r.reason,
                                 "cause": r.cause} for r in results if not r.success],
            "failures_by_cause": failures_by_cause(results),
            "mean_primitives": (sum(r.primitives for r in results) / n) if n else 0.0,
            "wall_seconds": seconds,
            "episodes_per_second": (n if ran is None else ran) / seconds if seconds > 0 else None,
            "workers": workers,
            "backend": backend,
            "machine": f"{platform.machine()} {platform.system()}, {mp.cpu_count()} cpus, "
                       f"Python {platform.python_version()}" if workers is not None else None,
        }
        return cls(data, store)

    @classmethod
    def sequential(cls, plan: dict[str, Any], results: Sequence[EpisodeResult],
                   test: sequential.SequentialTest, max_episodes: int, seconds: float,
                   workers: int | None, backend: str | None = "process", store: str | None = None,
                   ran: int | None = None) -> Report:
        """The report of a sequential campaign stopped by ``test`` (or by the cap)."""
        base = cls.fixed_n(plan, results, seconds, workers, backend, ran=ran)._data
        eps, delta = plan["epsilon"], plan["delta"]
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
        fixed = {"confidence": base["confidence"], "lower_bound": base["lower_bound"],
                 "note": "Clopper-Pearson figures of the episodes run, for description only: "
                         "the number of episodes was not fixed in advance, so they are no "
                         "guarantee"}
        base.update({
            "mode": "sequential",
            "planned_episodes": max_episodes,
            # a stored campaign may have been interrupted before its test decided
            "complete": test.decision is not None or len(results) >= max_episodes,
            "test": sequential.TEST_NAME,
            "prior": list(sequential.prior(eps)),
            "guarantee": sequential.guarantee(eps, delta),
            "decision": decision,
            "stopped_at": test.stopped_at,
            "max_episodes": max_episodes,
            "fixed_n_plan": bounds.min_episodes(eps, 1.0 - delta, 0),
            # the fixed-N keys, with their anytime-valid meaning in this mode
            "confidence": test.confidence(),
            "lower_bound": low,
            "upper_bound": high,
            "statement": (f"{words}; P[success] in [{bounds.floor_str(low)}, "
                          f"{bounds.ceil_str(high)}] at confidence level {level}, "
                          "simultaneously for all n "
                          f"({sequential.TEST_NAME})"),
            "fixed_n_description": fixed,
        })
        return cls(base, store)

    # -- words ----------------------------------------------------------------------------------
    def replay_command(self, index: int, seed: int) -> str | None:
        """The command that re-runs episode ``index`` (reset seed ``seed``) step by step (None
        for a policy kind of its own, which ``vlb replay`` cannot name, outside a store)."""
        if self.store:
            return f"vlb replay {shlex.quote(self.store)} --episode {index}"
        policy = self["policy"]
        option = _REPLAY_OPTIONS.get(policy["kind"])
        if option is None:
            return None
        words = ["vlb", "replay", self["env_id"], *option, shown_path(policy["ref"]), "--seed",
                 str(seed)]
        for key, value in self["env_kwargs"].items():
            words += ["--env-kwarg", f"{key}={json.dumps(value)}"]
        for module in self["env_modules"]:
            words += ["--env-module", module]
        return shlex.join(words)

    def summary(self, report_path: str | None = None) -> str:
        """The outcome of the campaign in words, as ``vlb verify`` prints it."""
        lines = self._head()
        if self["mode"] == "sequential":
            lines += self._sequential_lines()
        else:
            lines += [
                f"  P[success] >= {bounds.one_minus_str(self['epsilon'])} with confidence "
                f"{bounds.floor_str(self['confidence'])}",
                f"  P[success] >= {bounds.floor_str(self['lower_bound'])} at confidence level "
                f"{bounds.one_minus_str(self['delta'])} (one-sided Clopper-Pearson)",
            ]
        lines.append(f"  holds for: {self['sampling_distribution']}")
        lines += self._failure_lines()
        if report_path:
            lines.append(f"  report: {report_path}")
        return "\n".join(lines)

    def _head(self) -> list[str]:
        rate = self["episodes_per_second"]
        speed = (f", {rate:.0f} episodes/s" if rate and rate >= 100 else
                 f", {rate:.3g} episodes/s" if rate else "")
        mode = (f"sequential, {self['episodes']} episodes (at most {self['max_episodes']}; "
                if self["mode"] == "sequential" else f"{self['episodes']} episodes (")
        how = (f"{self['workers']} worker(s), {self['wall_seconds']:.1f} s"
               if self["workers"] is not None else
               f"from the store: the episodes' own time {self['wall_seconds']:.1f} s")
        lines = [f"{self['env_id']} / {shown_path(self['behavior'])}: {mode}seed {self['seed']}, "
                 f"{how}{speed})"]
        if not self["complete"]:
            most = "at most " if self["mode"] == "sequential" else ""
            lines.append(f"  INCOMPLETE: {self['episodes']} of {most}{self['planned_episodes']} "
                         "episodes stored; the figures below are for those (resume with the same "
                         "vlb verify command and --store)")
        lines.append(f"  successes {self['successes']}/{self['episodes']}, "
                     f"failures {self['failures']}")
        return lines

    def _sequential_lines(self) -> list[str]:
        p0 = bounds.one_minus_str(self["epsilon"])
        level = bounds.one_minus_str(self["delta"])
        a, b = self["prior"]
        decision = self["decision"]
        if decision == "certified":
            lines = [f"  CERTIFIED after {self['stopped_at']} episodes: P[success] >= {p0} at "
                     f"confidence level {level}, valid however often the test looked"]
        elif decision == "refuted":
            lines = [f"  REFUTED after {self['stopped_at']} episodes: P[success] < {p0} at "
                     f"confidence level {level}, valid however often the test looked"]
        elif not self["complete"]:
            lines = [f"  UNDECIDED so far, after {self['episodes']} episodes: the campaign was "
                     "interrupted; nothing is certified"]
        else:
            lines = [f"  UNDECIDED after {self['episodes']} episodes (the cap, --max-episodes): "
                     f"neither P[success] >= {p0} nor its negation is established; nothing is "
                     "certified"]
        return lines + [
            f"  anytime-valid: P[success] in [{bounds.floor_str(self['lower_bound'])}, "
            f"{bounds.ceil_str(self['upper_bound'])}] at confidence level {level}, "
            "simultaneously for every number of episodes",
            f"  test: {self['test']}, mixing prior Beta({a:g}, {b:g}); Ville's inequality: the "
            f"true P[success] leaves the interval at some n with probability <= "
            f"{self['delta']:g}",
            f"  fixed-N plan for comparison: {self['fixed_n_plan']} episodes with no failure "
            "('vlb plan')",
        ]

    def _failure_lines(self) -> list[str]:
        lines = [f"  failures by cause: {group['count']} x {group['cause']} (e.g. episode "
                 f"{group['episodes'][0]}, seed {group['seeds'][0]})"
                 for group in self["failures_by_cause"]]
        failed = self["failed_episodes"]
        for item in failed[:5]:
            lines.append(f"  failed episode {item['index']} (seed {item['seed']}): "
                         f"{item['reason']}")
        if len(failed) > 5:
            lines.append(f"  ... {len(failed) - 5} more failed episodes in the report")
        command = failed and self.replay_command(failed[0]["index"], failed[0]["seed"])
        if command:
            lines.append(f"  replay one: {command}")
        return lines
