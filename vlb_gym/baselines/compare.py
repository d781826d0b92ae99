"""The comparison benchmark: graphs (hand-written and synthesized) and RL agents, verified on the
same env, task, sampling distribution, reset seeds, rho_B and bounds.

Contestants: the task's hand-written graph, its synthesized graph, a uniformly random admissible
policy (the floor: with masks and the step bound, chance alone finishes some episodes), and
every RL configuration
(:class:`AgentSpec`: algorithm, observation, exploration bonus) trained with several seeds and
checkpointed at every budget, each verified as it acts: ``greedy`` (the most likely action,
policy kind ``sb3``) and ``sampled`` (drawn from its distribution, seeded per episode,
``sb3_sampled``). Each is verified on the same N episodes; a row gives successes,
the one-sided Clopper-Pearson lower bound, the confidence at eps, mean primitives and the
**episodes needed to certify** P >= 1 - eps at 95% confidence: the least N at which a campaign
certifies with probability 90% were the row's measured failure rate the true one
(:func:`~.stats.episodes_to_certify`; the rate's own uncertainty is not counted). Across seeds,
the summary describes the success rate as :func:`~.stats.describe` does: an IQM with its
bootstrap interval from 10 seeds on, else the mean and every seed.

Writes ``<out>/compare.md`` (the tables), ``compare.csv`` and ``compare.json`` (one row per
verified contestant), ``compare.png`` (success rate and lower bound against training steps,
IQM and the band between the lowest and highest seed, graphs as horizontal lines), and
``agents/manifest.json``: every trained agent (configuration, seed, budget, steps, wall time,
env steps/s). With ``reuse`` the agents of the manifest whose files exist are verified again
without training.
"""

from __future__ import annotations

import csv
import json
import math
import os
import platform
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass, fields
from multiprocessing import get_context
from pathlib import Path

from vlb_gym.core.files import InputFileError, read_json_file, write_atomic
from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.verify.backends import safe_import_path
from vlb_gym.verify.bounds import floor_str
from vlb_gym.verify.campaign import CampaignConfig, run_campaign
from vlb_gym.verify.policies import PolicyRef

from .configs import (ACTING, DEFAULT_AGENTS, DEFAULT_TASKS, DELTA, SYNTHESES, TASKS,
                      AgentSpec, TaskConfig)
from .pairing import paired, pairable, support
from .stats import (BOOTSTRAP_COVERAGE_10, CERTIFY_PROBABILITY, MIN_SEEDS_FOR_INTERVAL,
                    aggregate, describe, episodes_to_certify)

EPSILON = 0.05
CERTIFY_CONFIDENCE = 0.95
MANIFEST = "manifest.json"


@dataclass
class Row:
    task: str
    contestant: str
    kind: str  # graph, synthesized graph, random, rl
    seed: int | None
    episodes: int
    successes: int
    lower_bound: float
    confidence: float
    episodes_to_certify: float  # math.inf: not certifiable at eps
    mean_primitives: float
    train_steps: int | None
    train_seconds: float | None
    steps_per_second: float | None
    verify_seconds: float
    failed: tuple[int, ...] = ()  # the failed episodes' indices: rows pair up on them

    @property
    def success_rate(self) -> float:
        return self.successes / self.episodes


def verify_agent(task: TaskConfig, policy: PolicyRef, episodes: int, seed: int,
                 workers: int = 1) -> dict:
    """The campaign report of ``policy`` on ``task``: ``episodes`` from campaign ``seed``."""
    kwargs = {} if policy.kind in ACTING.values() else task.env_kwargs  # an agent brings its own
    return run_campaign(CampaignConfig(task.task_id, policy, episodes, EPSILON, DELTA, seed,
                                       kwargs), workers)


def _row(task: TaskConfig, name: str, kind: str, report: dict, meta: dict | None = None
         ) -> Row:
    meta = meta or {}
    rate = report["failures"] / report["episodes"]
    return Row(task.label, name, kind, meta.get("seed"), report["episodes"], report["successes"],
               report["lower_bound"], report["confidence"],
               episodes_to_certify(rate, EPSILON, CERTIFY_CONFIDENCE), report["mean_primitives"],
               meta.get("steps"), meta.get("wall_seconds"), meta.get("steps_per_second"),
               report["wall_seconds"], tuple(e["index"] for e in report["failed_episodes"]))


def synthesized_graphs(library: BehaviorLibrary) -> None:
    """Put the graphs of :data:`~.configs.SYNTHESES` into ``library``, synthesized from the
    paper's requests with the scripted replies (the offline stand-in for a live model)."""
    from vlb_gym.abstractor.backends import ScriptedBackend
    from vlb_gym.abstractor.paper import PAPER, PROMPTS
    from vlb_gym.abstractor.synthesize import save, synthesize

    for item in SYNTHESES:
        backend = ScriptedBackend.from_file(PAPER / f"{item.prompt}.replies.json")
        result = synthesize(item.env_id, PROMPTS[item.prompt], backend, library, uses=item.uses,
                            name=item.name)
        if not result.from_library:
            save(result, library)


_ENTRY = {"task": str, "agent": str, "seed": int, "budget": int, "path": str, "steps": int,
          "wall_seconds": (int, float)}


def load_manifest(path: Path) -> list[dict]:
    """The agents of a manifest written by :func:`compare` (none if there is no file), checked:
    a list of objects with the keys and types of ``_ENTRY``, each ``path`` the file name of an
    agent beside the manifest (a saved agent is a pickle: only what the comparison wrote there
    is loaded), returned as a full path. :class:`InputFileError` naming the file and entry
    otherwise."""
    if not path.is_file():
        return []
    manifest = read_json_file(path, "the agents' manifest", list)
    folder = path.parent
    for i, entry in enumerate(manifest):
        if not isinstance(entry, dict):
            raise InputFileError(f"{path}: entry {i} is not an object")
        for key, kind in _ENTRY.items():
            if not isinstance(entry.get(key), kind) or isinstance(entry.get(key), bool):
                raise InputFileError(f"{path}: entry {i} needs {key!r} "
                                     f"({'a string' if kind is str else 'a number'})")
        name = entry["path"]
        if Path(name).name != name or not name.endswith(".zip"):
            raise InputFileError(f"{path}: entry {i}: {name!r} is not the file name of an agent "
                                 f"beside the manifest")
    return [{**entry, "path": str(folder / entry["path"])} for entry in manifest]


def _trained(manifest: list[dict], task: str, spec: AgentSpec, seed: int,
             budgets: tuple[int, ...]) -> list[dict] | None:
    """The manifest's checkpoints of this run at exactly ``budgets``, if all their files exist."""
    found = {m["budget"]: m for m in manifest
             if (m["task"], m["agent"], m["seed"]) == (task, spec.label, seed)}
    if set(found) != set(budgets) or not all(Path(m["path"]).is_file()
                                             for m in found.values()):
        return None
    return [found[b] for b in budgets]


Run = tuple[str, AgentSpec, int]  # (task, configuration, training seed)


def _train_run(run: Run, agents_dir: Path, n_envs: int, budgets: tuple[int, ...] | None,
               subprocesses: bool) -> tuple[list[dict], float]:
    """Train one run; its checkpoints as manifest entries, and the wall time."""
    from .train import train

    name, spec, run_seed = run
    started = time.perf_counter()
    paths = train(TASKS[name], spec.algorithm, agents_dir, seed=run_seed, n_envs=n_envs,
                  budgets=_budgets(name, budgets), observation=spec.observation,
                  bonus=spec.bonus, subprocesses=subprocesses)
    checkpoints = [{"task": name, "agent": spec.label, "seed": run_seed, "budget": budget,
                    "path": str(path), **asdict(spec),
                    **json.loads(path.with_suffix(".json").read_text())}
                   for budget, path in zip(_budgets(name, budgets), paths)]
    return checkpoints, time.perf_counter() - started


def _share_threads(threads: int) -> None:
    import torch

    torch.set_num_threads(threads)


def _train_runs(runs: list[Run], jobs: int, *args) -> Iterator[tuple[Run, list[dict], float]]:
    """Each run's checkpoints and wall time as it ends: trained here one after another, or with
    ``jobs`` > 1 in as many worker processes (spawned), the CPUs' torch threads shared out."""
    if jobs <= 1 or len(runs) <= 1:
        for run in runs:
            yield run, *_train_run(run, *args)
        return
    threads = max(1, (os.cpu_count() or 1) // jobs)
    with ProcessPoolExecutor(jobs, mp_context=get_context("spawn"), initializer=_share_threads,
                             initargs=(threads,)) as pool:
        with safe_import_path():  # the workers start as the jobs are submitted
            futures = {pool.submit(_train_run, run, *args): run for run in runs}
        for future in as_completed(futures):
            yield futures[future], *future.result()


def _budgets(task: str, budgets: tuple[int, ...] | None) -> tuple[int, ...]:
    return tuple(sorted(budgets or TASKS[task].budgets))


def compare(out: Path, tasks: tuple[str, ...] = DEFAULT_TASKS, episodes: int = 100,
            seed: int = 0, agents: tuple[AgentSpec, ...] = DEFAULT_AGENTS, seeds: int = 3,
            budgets: tuple[int, ...] | None = None, n_envs: int = 4, workers: int = 1,
            subprocesses: bool = False, reuse: bool = False,
            acting: tuple[str, ...] = tuple(ACTING), jobs: int = 1,
            log: Callable[[str], None] = print) -> list[Row]:
    """Train (or, with ``reuse``, reload) every agent of ``agents`` with training seeds
    ``seed .. seed + seeds - 1``, ``jobs`` runs at a time; then verify the graphs and every
    agent, acting in each way of ``acting`` (keys of :data:`ACTING`); write the results to
    ``out``. Verification campaigns all use campaign seed ``seed``."""
    out.mkdir(parents=True, exist_ok=True)
    agents_dir = out / "agents"
    manifest_path = agents_dir / MANIFEST
    manifest = load_manifest(manifest_path) if reuse else []
    runs = [(name, spec, run_seed) for name in tasks for spec in agents
            for run_seed in range(seed, seed + seeds)]
    trained = {run: _trained(manifest, *run, _budgets(run[0], budgets)) if reuse else None
               for run in runs}
    todo = [run for run in runs if trained[run] is None]
    for run, checkpoints, seconds in _train_runs(todo, jobs, agents_dir, n_envs, budgets,
                                                 subprocesses):
        name, spec, run_seed = run
        log(f"{name}: trained {spec.label} seed {run_seed} in {seconds:.0f} s")
        trained[run] = checkpoints
        manifest = [m for m in manifest if (m["task"], m["agent"], m["seed"]) !=
                    (name, spec.label, run_seed)] + checkpoints
        write_atomic(manifest_path, json.dumps(  # paths: names beside it
            [{**m, "path": Path(m["path"]).name} for m in manifest], indent=2) + "\n")
    rows: list[Row] = []
    # the synthesized behaviors (and their transcripts) are kept with the results; campaigns,
    # worker processes included, resolve behavior names in that library
    library = BehaviorLibrary(out / "behaviors")
    synthesized_graphs(library)
    for name in tasks:
        task = TASKS[name]
        for ref, kind in ((PolicyRef("behavior", task.graph, str(library.directory)), "graph"),
                          (PolicyRef("behavior", task.synthesized, str(library.directory)),
                           "synthesized graph"),
                          (PolicyRef("random", "admissible"), "random")):
            contestant = "uniform admissible" if kind == "random" else ref.ref
            rows.append(_row(task, contestant, kind, verify_agent(task, ref, episodes, seed,
                                                                  workers)))
            log(f"{name}: {kind} {contestant}: {rows[-1].successes}/{episodes}")
        for run in [run for run in runs if run[0] == name]:
            _, spec, run_seed = run
            for meta in trained[run]:
                for how in acting:
                    report = verify_agent(task, PolicyRef(ACTING[how], meta["path"]), episodes,
                                          seed, workers)
                    rows.append(_row(task, f"{spec.label} {how}", "rl", report, meta))
                    log(f"{name}: {spec.label} {how}, seed {run_seed} @ {meta['steps']} "
                        f"steps: {report['successes']}/{episodes}")
    write_atomic(out / "compare.json", json.dumps([asdict(r) for r in rows], indent=2) + "\n")
    write_csv(rows, out / "compare.csv")
    write_atomic(out / "compare.md", markdown(rows, episodes, seed))
    plot(rows, out / "compare.png")
    return rows


def write_csv(rows: list[Row], path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, [f.name for f in fields(Row)])
        writer.writeheader()
        writer.writerows({**asdict(r), "failed": " ".join(map(str, r.failed))} for r in rows)


def _number(x: float | None) -> str:
    return "-" if x is None else f"{x:.0f}"


def _certify_text(n: float) -> str:
    return "never (rate >= eps)" if math.isinf(n) else f"{n:,.0f}"


def summary(rows: list[Row]) -> list[dict]:
    """Per task, contestant and training steps: the IQM of the success rate across seeds with
    its bootstrap interval, the median episodes to certify, throughput."""
    groups: dict[tuple, list[Row]] = {}
    for r in rows:
        groups.setdefault((r.task, r.contestant, r.kind, r.train_steps), []).append(r)
    out = []
    for (task, contestant, kind, steps), members in groups.items():
        agg = aggregate([m.success_rate for m in members])
        certify = sorted(m.episodes_to_certify for m in members)
        speeds = [m.steps_per_second for m in members if m.steps_per_second]
        out.append({"task": task, "contestant": contestant, "kind": kind, "steps": steps,
                    "runs": agg.runs, "iqm": agg.iqm, "low": agg.low, "high": agg.high,
                    "text": describe([m.success_rate for m in members]),
                    "best": max(m.successes for m in members), "episodes": members[0].episodes,
                    "certify": certify[(len(certify) - 1) // 2],
                    "steps_per_second": sum(speeds) / len(speeds) if speeds else None})
    return out


def markdown(rows: list[Row], episodes: int, seed: int) -> str:
    lines = [f"N = {episodes} episodes per contestant, the same reset seeds (campaign seed "
             f"{seed}); eps = {EPSILON}, lower bound at confidence {1 - DELTA:g} (one-sided "
             f"Clopper-Pearson); *episodes to certify*: the least N at which a campaign "
             f"certifies P >= {1 - EPSILON:g} at {CERTIFY_CONFIDENCE:.0%} confidence with "
             f"probability {CERTIFY_PROBABILITY:.0%}, were the row's measured failure rate the "
             "true one (its own uncertainty, from the row's episodes, is not counted). "
             f"Machine: {platform.machine()}, Python "
             f"{platform.python_version()}.", "",
             "Across training seeds (the success rate's IQM with a nominal 95% "
             f"percentile-bootstrap interval from {MIN_SEEDS_FOR_INTERVAL} seeds on, which "
             f"covered the true IQM {BOOTSTRAP_COVERAGE_10:.0%} of the time with 10 seeds in "
             "simulation; with fewer, its mean and every seed's value, since a bootstrap of a "
             "few runs covers far less; rates rounded down; episodes to certify: the median "
             "seed's):", "",
             "| task | contestant | kind | training steps | seeds | success rate | "
             "best seed | episodes to certify | env steps/s |",
             "| --- | --- | --- | ---: | ---: | --- | ---: | ---: | ---: |"]
    for s in summary(rows):
        lines.append(
            f"| {s['task']} | {s['contestant']} | {s['kind']} | "
            f"{s['steps'] if s['steps'] is not None else '-'} | {s['runs']} | "
            f"{s['text']} | {s['best']}/{s['episodes']} | "
            f"{_certify_text(s['certify'])} | {_number(s['steps_per_second'])} |")
    lines += ["", "Every contestant:", "",
              "| task | contestant | kind | seed | successes | lower bound | confidence "
              "(eps 0.05) | episodes to certify | mean primitives | training steps | "
              "training s | verification s |",
              "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in rows:
        lines.append(
            f"| {r.task} | {r.contestant} | {r.kind} | "
            f"{r.seed if r.seed is not None else '-'} | {r.successes}/{r.episodes} | "
            f"{floor_str(r.lower_bound, 3)} | {floor_str(r.confidence, 3)} | "
            f"{_certify_text(r.episodes_to_certify)} | "
            f"{r.mean_primitives:.1f} | {r.train_steps if r.train_steps is not None else '-'} | "
            f"{_number(r.train_seconds)} | {r.verify_seconds:.1f} |")
    supported = support(rows)
    if supported:
        lines += ["", "What the data support: each contestant against the task's hand-written "
                  f"graph on the same {episodes} reset seeds (episode i of each pairs up), "
                  f"McNemar's exact test one-sided each way at level {DELTA:g} (the two "
                  f"together a two-sided test at {2 * DELTA:g}), per training seed at the "
                  "largest budget:", "", *supported, "",
                  "Every pair of runs (only graph: episodes the graph finished and the "
                  "contestant failed):", "",
                  "| task | contestant | training steps | seed | only graph | only contestant "
                  "| verdict |", "| --- | --- | ---: | ---: | ---: | ---: | --- |"]
        for task, graph, others in pairable(rows):
            for r in others:
                t = paired(graph, r)
                lines.append(f"| {task} | {r.contestant} | "
                                 f"{r.train_steps if r.train_steps is not None else '-'} | "
                                 f"{r.seed if r.seed is not None else '-'} | {t['only_graph']} "
                                 f"| {t['only_contestant']} | {t['verdict']} |")
    return "\n".join(lines) + "\n"


def plot(rows: list[Row], path: Path) -> None:
    """Per task: success rate and lower bound against training steps (IQM across seeds, band
    from the lowest to the highest seed), the graphs as horizontal lines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from .stats import iqm

    tasks = list(dict.fromkeys(r.task for r in rows))
    fig, axes = plt.subplots(2, len(tasks), figsize=(6 * len(tasks), 7), squeeze=False)
    for column, task in enumerate(tasks):
        mine = [r for r in rows if r.task == task]
        for ax, (value, label) in zip(axes[:, column], (
                (lambda r: r.success_rate, "success rate"),
                (lambda r: r.lower_bound, f"lower bound on P[success] ({1 - DELTA:g})"))):
            for contestant in dict.fromkeys(r.contestant for r in mine if r.kind == "rl"):
                runs = [r for r in mine if r.kind == "rl" and r.contestant == contestant]
                steps = sorted({r.train_steps for r in runs})
                values = [[value(r) for r in runs if r.train_steps == s] for s in steps]
                line, = ax.plot(steps, [iqm(v) for v in values], marker="o", label=contestant)
                ax.fill_between(steps, [min(v) for v in values], [max(v) for v in values],
                                color=line.get_color(), alpha=0.2)
            for r, style in zip([r for r in mine if r.kind != "rl"], ("--", ":", "-.")):
                ax.axhline(value(r), linestyle=style, label=f"{r.contestant} ({r.kind})",
                           color="grey" if r.kind == "random" else "k")
            ax.set(title=task, xlabel="training environment steps", ylabel=label,
                   ylim=(-0.02, 1.02))
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
