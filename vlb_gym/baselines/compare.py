"""The comparison benchmark: graphs (hand-written and synthesized) and RL agents, verified on the
same env, task, sampling distribution, seeds, rho_B and bounds.

For each task it writes ``<out>/compare.md`` (a Markdown table) and ``<out>/compare.png`` (lower
bound vs training steps for the agents, graphs as horizontal lines), plus ``compare.json``.
"""

from __future__ import annotations

import json
import platform
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.verify.campaign import CampaignConfig, run_campaign
from vlb_gym.verify.policies import PolicyRef
from vlb_gym.verify.report import Report

from .configs import ALGORITHMS, SYNTHESES, TASKS, TaskConfig

EPSILON = 0.05
DELTA = 0.05


@dataclass
class Row:
    task: str
    contestant: str
    kind: str  # graph, synthesized graph, rl
    episodes: int
    successes: int
    lower_bound: float
    confidence: float
    mean_primitives: float
    train_steps: int | None
    train_seconds: float | None
    verify_seconds: float


def _verify(task: TaskConfig, policy: PolicyRef, episodes: int, seed: int,
            workers: int) -> Report:
    kwargs = {} if policy.kind == "sb3" else task.env_kwargs  # an agent brings its own
    return run_campaign(CampaignConfig(task.env_id, policy, episodes, EPSILON, DELTA, seed,
                                       kwargs), workers)


def _row(task: TaskConfig, name: str, kind: str, report: dict, steps: int | None = None,
         train_seconds: float | None = None) -> Row:
    return Row(task.task, name, kind, report["episodes"], report["successes"],
               report["lower_bound"], report["confidence"], report["mean_primitives"], steps,
               train_seconds, report["wall_seconds"])


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


def compare(out: Path, tasks: tuple[str, ...] = tuple(TASKS), episodes: int = 100,
            seed: int = 0, algorithms: tuple[str, ...] = ALGORITHMS,
            budgets: tuple[int, ...] | None = None, n_envs: int = 4, workers: int = 1,
            log=print) -> list[Row]:
    from .train import train

    out.mkdir(parents=True, exist_ok=True)
    rows: list[Row] = []
    # the synthesized behaviors (and their transcripts) are kept with the results; campaigns,
    # worker processes included, resolve behavior names in that library
    library = BehaviorLibrary(out / "behaviors")
    synthesized_graphs(library)
    for name in tasks:
        task = TASKS[name]
        for behavior, kind in ((task.graph, "graph"), (task.synthesized, "synthesized graph")):
            ref = PolicyRef("behavior", behavior, str(library.directory))
            report = _verify(task, ref, episodes, seed, workers)
            rows.append(_row(task, behavior, kind, report))
            log(f"{name}: {kind} {behavior}: {report['successes']}/{episodes}")
        for algorithm in algorithms:
            started = time.perf_counter()
            checkpoints = train(task, algorithm, out / "agents", seed=seed, n_envs=n_envs,
                                budgets=budgets, tensorboard=out / "tensorboard")
            log(f"{name}: trained {algorithm} in {time.perf_counter() - started:.0f} s")
            for path in checkpoints:
                meta = json.loads(path.with_suffix(".json").read_text())
                report = _verify(task, PolicyRef("sb3", str(path)), episodes, seed, workers)
                rows.append(_row(task, algorithm, "rl", report, meta["steps"],
                                 meta["wall_seconds"]))
                log(f"{name}: {algorithm} @ {meta['steps']} steps: "
                    f"{report['successes']}/{episodes}")
    (out / "compare.json").write_text(json.dumps([asdict(r) for r in rows], indent=2) + "\n")
    (out / "compare.md").write_text(markdown(rows, episodes, seed))
    plot(rows, out / "compare.png")
    return rows


def markdown(rows: list[Row], episodes: int, seed: int) -> str:
    lines = [f"N = {episodes} episodes per contestant, the same reset seeds (campaign seed "
             f"{seed}); eps = {EPSILON}, lower bound at confidence {1 - DELTA:g} (one-sided "
             f"Clopper-Pearson). Machine: {platform.machine()}, Python "
             f"{platform.python_version()}.", "",
             "| task | contestant | kind | successes | lower bound | confidence (eps 0.05) | "
             "mean primitives | training steps | training s | verification s |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(
            f"| {r.task} | {r.contestant} | {r.kind} | {r.successes}/{r.episodes} | "
            f"{r.lower_bound:.3f} | {r.confidence:.3f} | {r.mean_primitives:.1f} | "
            f"{r.train_steps if r.train_steps is not None else '-'} | "
            f"{f'{r.train_seconds:.0f}' if r.train_seconds is not None else '-'} | "
            f"{r.verify_seconds:.1f} |")
    return "\n".join(lines) + "\n"


def plot(rows: list[Row], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tasks = sorted({r.task for r in rows}, key=[r.task for r in rows].index)
    fig, axes = plt.subplots(1, len(tasks), figsize=(6 * len(tasks), 4), squeeze=False)
    for ax, task in zip(axes[0], tasks):
        mine = [r for r in rows if r.task == task]
        for algorithm in sorted({r.contestant for r in mine if r.kind == "rl"}):
            points = sorted((r.train_steps, r.lower_bound) for r in mine
                            if r.kind == "rl" and r.contestant == algorithm)
            ax.plot(*zip(*points), marker="o", label=algorithm)
        for r, style in zip([r for r in mine if r.kind != "rl"], ("--", ":")):
            ax.axhline(r.lower_bound, linestyle=style, color="k", label=f"{r.contestant} "
                       f"({r.kind})")
        ax.set(title=task, xlabel="training environment steps",
               ylabel=f"lower bound on P[success] ({1 - DELTA:g})", ylim=(-0.02, 1.02))
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
