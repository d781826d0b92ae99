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

from vlb_gym.core.formats import CURRENT

from .methods import method_named
from .records import EpisodeResult, Plan


def one_line(text: str) -> str:
    """``text`` as one line of a summary: the line breaks and carriage returns in it (from a
    store, a file name) escaped, so that no input can forge or overwrite a line."""
    return text.replace("\r", "\\r").replace("\n", "\\n")


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


def replay_command(policy: Mapping[str, Any], env_id: str, env_kwargs: Mapping[str, Any],
                   env_modules: Sequence[str], seed: int) -> str | None:
    """The ``vlb replay`` command that re-runs ``policy`` from reset seed ``seed`` (None for a
    policy kind ``vlb replay`` cannot name, or whose package is not installed here)."""
    from .policies import policy_loader

    try:
        option = getattr(policy_loader(policy["kind"]), "replay_options", None)
    except (ValueError, ImportError):
        return None
    if option is None:
        return None
    words = ["vlb", "replay", env_id, *option, shown_path(policy["ref"]), "--seed", str(seed)]
    for key, value in env_kwargs.items():
        words += ["--env-kwarg", f"{key}={json.dumps(value)}"]
    for module in env_modules:
        words += ["--env-module", module]
    return shlex.join(words)


def where_listed(report_path: str | None, store: str | None) -> str:
    """Where a summary's left-out items are all listed: the report written, else the store's
    report, else how to ask for one."""
    if report_path:
        return f"listed in {report_path}"
    if store:
        return f"listed by: vlb report {shlex.quote(shown_path(store))} --json"
    return "(--report FILE lists them all)"


class JsonReport(Mapping[str, Any]):
    """A report as a read-only mapping of its JSON keys; ``store`` is the path of the store it
    was run with or rebuilt from, if any."""

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
        """The report as strict JSON (a number that is not finite would be ``Infinity``,
        which JSON does not have: it is refused, never written)."""
        return json.dumps(self._data, indent=2, allow_nan=False) + "\n"


class Report(JsonReport):
    """A campaign's report: its JSON keys (those docs/verify.md lists), with
    :meth:`summary` in words and :meth:`replay_command` for any episode (naming the store,
    if it has one).
    """

    # -- building -----------------------------------------------------------------------------
    @classmethod
    def build(cls, plan: Plan, results: Sequence[EpisodeResult], seconds: float,
              workers: int | None, backend: str | None = "process", store: str | None = None,
              ran: int | None = None) -> Report:
        """The report of the campaign of ``plan`` from its episode ``results`` (complete or not:
        ``episodes`` counts those its method used; ``planned_episodes`` is N), its claim made by
        the plan's statistical method (:mod:`.methods`). ``ran`` episodes (default: all) took
        ``seconds``, the others were resumed from a store. A report rebuilt from a store knows
        no ``workers`` or ``backend`` (None); its ``seconds`` are the episodes' own."""
        method = method_named(plan.method)(plan.epsilon, plan.delta, plan.episodes)
        results = sorted(results, key=lambda r: r.index)
        results = results[:method.feed(r.success for r in results)]
        n, failures = len(results), method.failures
        recorded = plan.to_dict()
        data = {
            "format": CURRENT["report"],
            "env_id": plan.env_id,
            "behavior": plan.policy.ref,
            "policy": recorded["policy"],
            "mode": method.name,
            "episodes": n,
            "planned_episodes": plan.episodes,
            "successes": n - failures,
            "failures": failures,
            "epsilon": plan.epsilon,
            "delta": plan.delta,
            "seed": plan.seed,
            **method.claim(),
            "sampling_distribution": plan.sampling_distribution,
            "env_kwargs": recorded["env_kwargs"],
            "env_modules": recorded["env_modules"],
            "content_sha256": plan.content_sha256,
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

    # -- words ----------------------------------------------------------------------------------
    def replay_command(self, index: int, seed: int) -> str | None:
        """The command that re-runs episode ``index`` (reset seed ``seed``) step by step (None
        for a policy kind of its own, which ``vlb replay`` cannot name, outside a store)."""
        if self.store:
            return f"vlb replay {shlex.quote(self.store)} --episode {index}"
        return replay_command(self["policy"], self["env_id"], self["env_kwargs"],
                              self["env_modules"], seed)

    def summary(self, report_path: str | None = None) -> str:
        """The outcome of the campaign in words, as ``vlb verify`` prints it."""
        lines = self._head() + method_named(self["mode"]).lines(self)
        lines.append(f"  holds for: {self['sampling_distribution']}")
        lines += self._failure_lines(report_path)
        if report_path:
            lines.append(f"  report: {report_path}")
        return "\n".join(one_line(line) for line in lines)

    def _head(self) -> list[str]:
        rate = self["episodes_per_second"]
        speed = (f", {rate:.0f} episodes/s" if rate and rate >= 100 else
                 f", {rate:.3g} episodes/s" if rate else "")
        early = method_named(self["mode"]).stops_early
        mode = (f"{self['mode']}, {self['episodes']} episodes (at most "
                f"{self['planned_episodes']}; " if early else f"{self['episodes']} episodes (")
        how = (f"{self['workers']} worker(s), {self['wall_seconds']:.1f} s"
               if self["workers"] is not None else
               f"from the store: the episodes' own time {self['wall_seconds']:.1f} s")
        lines = [f"{self['env_id']} / {shown_path(self['behavior'])}: {mode}seed {self['seed']}, "
                 f"{how}{speed})"]
        if not self["complete"]:
            most = "at most " if early else ""
            lines.append(f"  INCOMPLETE: {self['episodes']} of {most}{self['planned_episodes']} "
                         "episodes stored; the figures below are for those (resume with the same "
                         "vlb verify command and --store)")
        lines.append(f"  successes {self['successes']}/{self['episodes']}, "
                     f"failures {self['failures']}")
        return lines

    def _failure_lines(self, report_path: str | None) -> list[str]:
        lines = [f"  failures by cause: {group['count']} x {group['cause']} (e.g. episode "
                 f"{group['episodes'][0]}, seed {group['seeds'][0]})"
                 for group in self["failures_by_cause"]]
        failed = self["failed_episodes"]
        for item in failed[:5]:
            lines.append(f"  failed episode {item['index']} (seed {item['seed']}): "
                         f"{item['reason']}")
        if len(failed) > 5:
            more = len(failed) - 5
            lines.append(f"  ... {more} more failed episode{'s' if more > 1 else ''} "
                         f"{where_listed(report_path, self.store)}")
        command = failed and self.replay_command(failed[0]["index"], failed[0]["seed"])
        if command:
            lines.append(f"  replay one: {command}")
        return lines
