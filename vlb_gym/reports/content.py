"""What a campaign report says, section by section, as a :class:`~.document.Document`."""

from __future__ import annotations

import json
import shlex
from typing import Any

import numpy as np

from vlb_gym.core.document import (Block, Code, Document, Figure, Gallery, Heading, Inline,
                                   Paragraph, Preformatted, Strong, Table, short)
from vlb_gym.core.env import FrameKey
from vlb_gym.verify import bounds
from vlb_gym.verify.methods import method_named
from vlb_gym.verify.records import Plan

from . import attribution, graph, plots
from .png import encode_png, pick, thumbnail

MAX_FAILED_ROWS = 25
MAX_TRACEBACKS = 3
MAX_FRAMES = 6
MAX_GRAPHS = 12  # behavior graphs drawn in one report
MAX_NODE_ROWS = 60  # rows of the node table in report.md/html
MATPLOTLIB_MISSING = ("no picture (matplotlib, a dependency of vlb-gym, is missing: pip install "
                      "matplotlib)")


def joined(parts: list[Inline], separator: str = ", ") -> list[Inline]:
    """``parts`` with ``separator`` between them."""
    out: list[Inline] = []
    for part in parts:
        out += [separator, part] if out else [part]
    return out


def subject(report: dict[str, Any]) -> list[Inline]:
    """"the behavior NAME" or "the trained agent PATH"."""
    what = "the trained agent " if attribution.is_agent(report) else "the behavior "
    return [what, Strong(str(report.get("behavior", "?")))]


def claim_blocks(report: dict[str, Any]) -> list[Block]:
    """Section 1: the guarantee in words, bounds rounded down, as the campaign's statistical
    method states it (its ``paragraphs``)."""
    where: list[Inline] = ["For start/environment pairs drawn from the sampling distribution (",
                           str(report.get("sampling_distribution", "not recorded")), "), ",
                           *subject(report)]
    blocks: list[Block] = [Heading(2, "The claim"),
                           *method_named(report["mode"]).paragraphs(report, where)]
    n, planned = report["episodes"], report.get("planned_episodes")
    if planned is not None and planned != n:
        blocks.append(Paragraph([Strong("Incomplete campaign: "),
                                 f"{n} of {planned} planned episodes were stored; the figures "
                                 "describe those only."]))
    return blocks


def numbers_table(report: dict[str, Any]) -> list[Block]:
    """Section 2: the numbers."""
    rate = report.get("episodes_per_second")
    rows: list[list[Any]] = [
        ["episodes N", str(report["episodes"])],
        ["successes", str(report["successes"])],
        ["failures k", str(report["failures"])],
        ["eps (claim P[success] >= 1 - eps)", f"{report['epsilon']:g}"],
        ["confidence in the claim", bounds.floor_str(report["confidence"])],
        ["delta (level 1 - delta)", f"{report['delta']:g}"],
        ["lower bound on P[success] at level 1 - delta", bounds.floor_str(report["lower_bound"])],
    ]
    rows += method_named(report["mode"]).rows(report)
    rows += [
        ["seed", Code(str(report.get("seed")))],
        ["wall time (s)", f"{report.get('wall_seconds', 0.0):.2f}"],
        ["episodes / s", f"{rate:.1f}" if isinstance(rate, (int, float)) else "-"],
        ["mean primitives per episode", f"{report.get('mean_primitives', 0.0):.2f}"],
    ]
    return [Heading(2, "The numbers"), Table(["quantity", "value"], rows, numeric=(1,))]


def replay(store_path: str | None, index: int | None) -> Inline:
    """The command that replays episode ``index`` of the campaign stored at ``store_path``."""
    if store_path is None or index is None:
        return "-"
    return Code(f"vlb replay {shlex.quote(store_path)} --episode {index}")


def failure_blocks(report: dict[str, Any], episodes: list[dict[str, Any]],
                   store_path: str | None) -> list[Block]:
    """Section 3: failures by cause, the failed episodes, an example's last steps, tracebacks."""
    blocks: list[Block] = [Heading(2, "Failures by cause")]
    groups = report.get("failures_by_cause") or []
    if not groups:
        return blocks + [Paragraph(["No episode failed."])]
    failed = [e for e in episodes if e.get("rho", 1) < 0] or report.get("failed_episodes", [])
    index_of = {e.get("seed"): e.get("index") for e in failed}
    first_of: dict[str, dict[str, Any]] = {}
    for episode in failed:
        first_of.setdefault(episode.get("cause") or "unknown", episode)
    headers = ["cause", "count", "share", "example seeds", "example reason"]
    if store_path is not None:
        headers.append("replay an example")
    rows = []
    total = max(report.get("episodes", 1), 1)
    for group in groups:
        cause = str(group.get("cause"))
        seeds = group.get("seeds", [])
        example = first_of.get(cause, {})
        index = example.get("index", index_of.get(seeds[0]) if seeds else None)
        row = [cause, str(group.get("count")), bounds.rounded(group.get("count", 0) / total, 1, up=True, percent=True),
               joined([Code(str(s)) for s in seeds]),
               short(example.get("reason") or "", 160)]
        if store_path is not None:
            row.append(replay(store_path, index))
        rows.append(row)
    blocks.append(Table(headers, rows, numeric=(1, 2)))

    shown = failed[:MAX_FAILED_ROWS]
    blocks.append(Heading(3, f"Failed episodes ({len(failed)}"
                             + (f", first {len(shown)} shown)" if len(shown) < len(failed) else ")")))
    with_start = any("start" in e for e in shown)
    head = ["episode", "seed", "cause", "reason"] + (["start"] if with_start else [])
    table = []
    for episode in shown:
        row = [str(episode.get("index")), Code(str(episode.get("seed"))),
               str(episode.get("cause") or "unknown"), short(episode.get("reason") or "", 200)]
        if with_start:
            start = episode.get("start")
            row.append(Code(short(json.dumps(start, sort_keys=True, default=str), 120))
                       if start is not None else "-")
        table.append(row)
    blocks.append(Table(head, table, numeric=(0,)))

    example = next((e for e in failed if e.get("steps")), None)
    if example is not None:
        steps = example["steps"]
        last = steps[-15:]
        blocks += [Heading(3, f"Last steps of failed episode {example.get('index')}"),
                   Table(["step", "node", "primitive", "param", "certificate", "reason"],
                         [[str(len(steps) - len(last) + i + 1), str(s.get("node") or "-"),
                           str(s.get("primitive")), Code(short(json.dumps(s.get("param"),
                                                                          default=str), 60)),
                           "held" if s.get("certificate") else "FAILED",
                           short(s.get("reason") or "", 120)] for i, s in enumerate(last)],
                         numeric=(0,))]
    errors = [e for e in failed if e.get("error")][:MAX_TRACEBACKS]
    for episode in errors:
        blocks.append(Preformatted(str(episode["error"]),
                                   f"Traceback of episode {episode.get('index')}"))
    return blocks


def graph_blocks(report: dict[str, Any], plan: Plan,
                 episodes: list[dict[str, Any]]) -> list[Block]:
    """Section 4: the behavior graph and its sub-behaviors, coloured by failed certificates."""
    blocks: list[Block] = [Heading(2, "The behavior graph")]
    if attribution.is_agent(report):
        return blocks + [Paragraph(["A trained RL agent (", Code(str(report.get("behavior"))),
                                    ") was verified, not a behavior graph: there is no graph to "
                                    "draw."])] + primitive_table(episodes)
    specs = attribution.plan_behaviors(plan)
    order = attribution.behavior_order(str(report.get("behavior", "")), specs)
    if not order:
        return blocks + [Paragraph(["The plan holds no behavior specs: no picture."])]
    stats = attribution.node_stats(specs, episodes, order[0])
    approximate = any(s.approximate for table in stats.values() for s in table.values())
    blocks.append(Paragraph([
        "Nodes are coloured by the share of their steps whose certificate failed (pale green: "
        "none; yellow, 0.1% or less, to red, all: a log scale); labels give failed / steps run "
        "at the node",
        "; ~ marks counts attributed by primitive because the node was not recorded"
        if approximate else "",
        ". Double outline: terminal node; box: sub-behavior (its count totals its nodes); edge "
        "labels: guards (truncated); the dot marks the start node."]))
    if len(order) > MAX_GRAPHS:  # a plan may list thousands: a report draws what it shows
        blocks.append(Paragraph([f"The plan lists {len(order)} behaviors: the first "
                                 f"{MAX_GRAPHS} are drawn ({order[0]} and its sub-behaviors "
                                 "in order)."]))
    for i, key in enumerate(order[:MAX_GRAPHS]):
        spec = specs[key]
        role = "main behavior" if i == 0 else "sub-behavior"
        title = f"{role}: {spec.get('name', key)}"
        try:
            png, how = graph.behavior_png(spec, stats.get(key, {}), title)
        except graph.PictureUnavailable as exc:
            blocks.append(Paragraph([f"{title}: {exc}"]))
            continue
        blocks.append(Figure(f"graph-{i}.png", png, f"graph of the {title}",
                             f"{title} ({key}), drawn with {how}"))
        blocks += promise_blocks(spec, episodes)
    blocks += node_table(attribution.rows_of(specs, order, stats))
    no_certificate = [e for e in episodes
                      if e.get("rho", 1) < 0 and not e.get("failed_certificates")]
    if no_certificate:
        causes = sorted({str(e.get("cause") or "unknown") for e in no_certificate})
        blocks.append(Paragraph([f"{len(no_certificate)} failed episode(s) ended without a "
                                 "failed certificate (", "; ".join(causes),
                                 "): they are not on the graph."]))
    return blocks + primitive_table(episodes)


def node_table(rows: list[dict[str, Any]]) -> list[Block]:
    """Each node's steps, failed certificates by kind and mean step time (the first
    :data:`MAX_NODE_ROWS`; report.json holds them all)."""
    if not rows:
        return []
    shown = rows[:MAX_NODE_ROWS]
    more = ([Paragraph([f"The first {MAX_NODE_ROWS} of {len(rows)} nodes; report.json lists "
                        "them all."])] if len(rows) > MAX_NODE_ROWS else [])
    return [Paragraph(["Each node's steps, the certificates that failed there by kind, and the "
                       "mean wall time of a step (the policy's decision and the env's step)."]),
            Table(["node", "what it runs", "steps", "failed", "failure rate", "failures by kind",
                   "mean step time"],
                  [[row["node"], str(row["primitive"] or f"behavior {row['behavior']}"),
                    str(row["runs"]), str(row["failed"]),
                    bounds.rounded(row["failure_rate"], 2, up=True, percent=True)
                    if row["failure_rate"] is not None else "-",
                    "; ".join(f"{cause}: {count}" for cause, count in row["failures"].items())
                    or "-",
                    f"{1000 * row['mean_seconds']:.2f} ms" if row["mean_seconds"] is not None
                    else "-"] for row in shown], numeric=(2, 3, 4, 6)), *more]


def promise_blocks(spec: dict[str, Any], episodes: list[dict[str, Any]]) -> list[Block]:
    """The behavior's promise in words and as judged, and how many episodes broke it."""
    promise = spec.get("promise")
    if not isinstance(promise, dict):
        return []
    name = str(spec.get("name", "?"))
    broken = sum(1 for e in episodes if e.get("cause") == f"{name}: promise")
    return [Paragraph([f"Promise of {name}: ", Strong(str(promise.get("description") or "")),
                       " (judged as ", Code(str(promise.get("expr", ""))), "); broken in ",
                       Strong(str(broken)), f" of {len(episodes)} episode(s)."])]


def primitive_table(episodes: list[dict[str, Any]]) -> list[Block]:
    table = attribution.failures_by_primitive(episodes)
    if not table:
        return []
    return [Table(["primitive", "steps", "failed certificates", "failure rate"],
                  [[name, str(s.runs), str(s.failed), bounds.rounded(s.failed / s.runs, 2, up=True, percent=True)]
                   for name, s in sorted(table.items())], numeric=(1, 2, 3))]


def chart_blocks(report: dict[str, Any], episodes: list[dict[str, Any]]) -> list[Block]:
    """Sections 5 and 6: confidence against eps; rho_B and primitives per episode."""
    blocks: list[Block] = [Heading(2, "Confidence against eps")]
    n, k = report["episodes"], report["failures"]
    note = "fixed-N formula, description only" if method_named(report["mode"]).stops_early \
        else ""
    try:
        blocks.append(Figure("confidence.png",
                             plots.confidence_png(n, k, report["epsilon"], report["delta"], note),
                             "confidence against eps",
                             f"1 - binom.cdf(k, N, eps) for N = {n}, k = {k}; the dotted lines "
                             "mark the campaign's eps and 1 - delta; where the curve crosses "
                             "1 - delta, eps equals 1 minus the Clopper–Pearson lower bound."
                             + (" The number of episodes was not fixed in advance: this curve "
                                "is no guarantee." if note else "")))
    except ImportError:
        blocks.append(Paragraph([MATPLOTLIB_MISSING]))
    blocks.append(Heading(2, "Episodes"))
    if not episodes:
        return blocks + [Paragraph(["No episode records were given."])]
    try:
        blocks.append(Figure("episodes.png", plots.episodes_png(episodes),
                             "rho_B and primitives per episode",
                             "rho_B and the number of primitives of every episode, by index "
                             "(failures in red), and a histogram of primitives per episode."))
    except ImportError:
        blocks.append(Paragraph([MATPLOTLIB_MISSING]))
    seconds = [e.get("seconds", 0.0) for e in episodes]
    blocks.append(Paragraph([f"Primitives per episode: mean "
                             f"{np.mean([e.get('primitives', 0) for e in episodes]):.2f}, max "
                             f"{max(e.get('primitives', 0) for e in episodes)}; seconds per "
                             f"episode: median {np.median(seconds):.4f}, max {max(seconds):.4f}."]))
    return blocks


def frame_blocks(frames: dict[str, list[np.ndarray]] | None, key: FrameKey | None = None
                 ) -> list[Block]:
    """Section 7: a few frames of the episodes given, the last of each always (where a failed
    episode failed); with the env's ``key``, a legend of its colours and, on a grid, the cells'
    indices along each frame's edges."""
    if not frames:
        return []
    blocks: list[Block] = [Heading(2, "Frames")]
    if key is not None and key.colours:
        blocks.append(Gallery("What the colours show", [Figure(
            "frames-legend.png", plots.legend_png(key.colours),
            "; ".join(label for label, _ in key.colours), "legend")]))
    for g, (label, images) in enumerate(frames.items()):
        chosen = pick(len(images), MAX_FRAMES)
        figures = [Figure(f"frames-{g}-{j}.png", _frame_png(images[j], key),
                          f"{label}, frame {j + 1} of {len(images)}"
                          + (" (the last: where it ended)" if j == len(images) - 1 else ""),
                          f"frame {j + 1}")
                   for j in chosen]
        blocks.append(Gallery(str(label), figures) if figures else
                      Paragraph([f"{label}: no frames."]))
    return blocks


def _frame_png(image: np.ndarray, key: FrameKey | None) -> bytes:
    if key is not None and key.cells:
        return plots.frame_png(image, key.cells)
    return encode_png(thumbnail(image))


def provenance_blocks(report: dict[str, Any], plan: Plan) -> list[Block]:
    """Section 8: what ran, where, from which files."""
    def js(value: Any) -> Code:
        return Code(json.dumps(value, sort_keys=True, default=str))

    rows: list[list[Any]] = [
        ["environment", Code(plan.env_id)],
        ["environment kwargs", js(plan.env_kwargs)],
        ["environment modules", js(plan.env_modules)],
        ["trained agent" if attribution.is_agent(report) else "behavior",
         Code(str(report.get("behavior")))],
        ["content sha256", Code(plan.content_sha256)],
        ["root seed", Code(str(report.get("seed")))],
        ["stop on first failure", str(plan.stop_on_failure)],
        ["sampling distribution", str(report.get("sampling_distribution", "not recorded"))],
    ]
    rows += [[f"version: {name}", Code(str(version))]
             for name, version in sorted(plan.versions.items())]
    if report.get("machine"):
        workers = report.get("workers")
        rows.append(["machine", report["machine"] if workers is None
                     else f"{report['machine']}, {workers} worker(s)"])
    return [Heading(2, "Provenance"), Table(["item", "value"], rows)]


def build_document(report: dict[str, Any], episodes: list[dict[str, Any]], plan: Plan,
                   frames: dict[str, list[np.ndarray]] | None = None,
                   store_path: str | None = None, key: FrameKey | None = None) -> Document:
    """The whole report (``key``: how to read the frames, see :func:`frame_blocks`)."""
    episodes = sorted(episodes, key=lambda e: e.get("index", 0))
    document = Document(f"Verification report: {report.get('behavior')} on "
                        f"{report.get('env_id')}")
    document.add(*claim_blocks(report), *numbers_table(report),
                 *failure_blocks(report, episodes, store_path),
                 *graph_blocks(report, plan, episodes), *chart_blocks(report, episodes),
                 *frame_blocks(frames, key), *provenance_blocks(report, plan))
    return document
