"""Writing a campaign's report folder: report.json, report.md (+ figures/) and report.html."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from vlb_gym.core.env import FrameKey
from vlb_gym.core.files import write_atomic

from . import html, markdown
from vlb_gym.verify.records import Plan

from .attribution import node_rows
from .content import build_document


def report_data(report: dict[str, Any], episodes: list[dict[str, Any]], plan: Plan
                ) -> dict[str, Any]:
    """What report.json holds: the report's keys and ``nodes``, each node's statistics
    (:func:`~.attribution.node_rows`: steps, failed certificates by cause, mean step time)."""
    return {**dict(report), "nodes": node_rows(plan, episodes, str(report.get("behavior", "")))}


def write_report_dir(out_dir: Path, report: dict[str, Any], episodes: list[dict[str, Any]],
                     plan: Plan, frames: dict[str, list[np.ndarray]] | None = None,
                     store_path: str | None = None, key: FrameKey | None = None
                     ) -> list[Path]:
    """Write the report of a finished campaign into ``out_dir`` and return the files written.

    ``report`` is a :class:`~vlb_gym.verify.report.Report` (or its JSON), ``episodes`` one
    :meth:`~vlb_gym.verify.episode.EpisodeResult.to_dict` per episode, ``plan`` the campaign
    plan (its ``policy_content.behaviors``, ``{source: behavior spec}``, give the graph pictures), ``frames`` optional
    ``{label: [RGB arrays]}`` (``key``: the env's :class:`~vlb_gym.core.env.FrameKey`, for
    their legend and cell indices) and ``store_path`` the campaign store, for replay commands
    (omitted when None). report.html needs nothing but itself; report.md shows the PNG files
    in ``figures/``. Every file is written atomically.
    """
    out_dir = Path(out_dir)
    document = build_document(report, episodes, plan, frames, store_path, key)
    written: list[Path] = []

    def put(path: Path, content: str | bytes) -> None:
        write_atomic(path, content)
        written.append(path)

    put(out_dir / "report.json",
        json.dumps(report_data(report, episodes, plan), indent=2, default=str) + "\n")
    for fig in document.figures():
        put(out_dir / markdown.FIGURE_DIR / fig.name, fig.png)
    put(out_dir / "report.md", markdown.render(document))
    put(out_dir / "report.html", html.render(document))
    return written
