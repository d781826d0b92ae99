"""Matplotlib charts of a campaign (Agg canvas, no pyplot state): confidence against eps, and
rho_B and primitives per episode. matplotlib is imported on first use (extra ``rl``)."""

from __future__ import annotations

import io
import math
from typing import Any

import numpy as np

from vlb_gym.verify import bounds

DPI = 100


def figure(width: float, height: float) -> Any:
    """A matplotlib Figure on an Agg canvas; ImportError when matplotlib is missing."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def png_of(fig: Any) -> bytes:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    return buffer.getvalue()


def epsilon_grid(n: int, k: int, epsilon: float, points: int = 160) -> np.ndarray:
    """Log-spaced eps values around where the confidence rises, the campaign's eps included."""
    low = max(1e-6, min(epsilon / 10.0, 0.1 / n))
    high = min(0.999, max(0.5, 3.0 * epsilon, 2.0 * (k + 1) / n))
    return np.unique(np.append(np.geomspace(low, high, points), epsilon))


def confidence_png(n: int, k: int, epsilon: float, delta: float, note: str = "") -> bytes:
    """Confidence that P[success] >= 1 - eps against eps, for N episodes with k failures; the
    campaign's eps and the 1 - delta level are marked, as is the eps where they meet."""
    grid = epsilon_grid(n, k, epsilon)
    curve = [bounds.confidence(n, k, float(e)) for e in grid]
    fig = figure(7.0, 3.6)
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(grid, curve, color="#1f4e9c", lw=2, label=f"N = {n}, k = {k} failures")
    if k:
        ax.plot(grid, [bounds.confidence(n, 0, float(e)) for e in grid], color="#999999",
                lw=1, ls="--", label=f"N = {n}, no failures (for comparison)")
    level = 1.0 - delta
    ax.axhline(level, color="#c0392b", lw=1, ls=":", label=f"1 - delta = {bounds.one_minus_str(delta)}")
    conf = bounds.confidence(n, k, epsilon)
    ax.axvline(epsilon, color="#2e7d32", lw=1, ls=":")
    ax.plot([epsilon], [conf], "o", color="#2e7d32",
            label=f"eps = {epsilon:g}: confidence {bounds.floor_str(conf)}")
    meet = 1.0 - bounds.lower_bound(n, k, delta)
    if grid[0] <= meet <= grid[-1]:
        ax.plot([meet], [level], "s", color="#c0392b", ms=5,
                label=f"eps = 1 - lower bound = {bounds.ceil_str(meet, 4)}")
    ax.set_xscale("log")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel("eps (claim: P[success] >= 1 - eps)")
    ax.set_ylabel("confidence")
    ax.set_title("Confidence in P[success] >= 1 - eps" + (f" ({note})" if note else ""),
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=7, loc="lower right")
    return png_of(fig)


def episodes_png(episodes: list[dict[str, Any]]) -> bytes:
    """rho_B and primitives per episode over the episode index (failures in red), and a
    histogram of primitives per episode."""
    index = np.array([e.get("index", i) for i, e in enumerate(episodes)], dtype=float)
    rho = np.array([1 if e.get("rho", 1) > 0 else -1 for e in episodes])
    prims = np.array([e.get("primitives", 0) for e in episodes], dtype=float)
    failed = rho < 0
    fig = figure(7.0, 5.6)
    grid = fig.add_gridspec(2, 2, height_ratios=[1, 1.4])
    strip = fig.add_subplot(grid[0, :])
    scatter = fig.add_subplot(grid[1, 0])
    hist = fig.add_subplot(grid[1, 1])
    small = len(episodes) <= 400
    strip.vlines(index[~failed], 0, 1, color="#2e7d32", lw=1 if small else 0.3)
    strip.vlines(index[failed], -1, 0, color="#c0392b", lw=1.5 if small else 0.5)
    strip.axhline(0, color="black", lw=0.5)
    strip.set_yticks([-1, 1])
    strip.set_ylim(-1.2, 1.2)
    strip.set_ylabel("rho_B")
    strip.set_xlabel("episode index")
    strip.set_title(f"rho_B per episode: {int((~failed).sum())} successes (+1), "
                    f"{int(failed.sum())} failures (-1)", fontsize=9)
    size = 14 if small else 4
    scatter.scatter(index[~failed], prims[~failed], s=size, color="#2e7d32", label="success")
    scatter.scatter(index[failed], prims[failed], s=size * 1.6, color="#c0392b", marker="x",
                    label="failure")
    scatter.set_xlabel("episode index")
    scatter.set_ylabel("primitives")
    scatter.set_title("primitives per episode", fontsize=9)
    scatter.legend(fontsize=7)
    top = int(prims.max()) if prims.size else 1
    bins = (np.arange(0, top + 2) - 0.5 if top <= 25 else
            min(30, max(8, 2 * int(math.sqrt(len(prims))))))
    hist.hist([prims[~failed], prims[failed]], bins=bins, stacked=True,
              color=["#2e7d32", "#c0392b"], label=["success", "failure"])
    hist.set_xlabel("primitives per episode")
    hist.set_ylabel("episodes")
    hist.set_title("histogram", fontsize=9)
    hist.legend(fontsize=7)
    return png_of(fig)


def frame_png(image: np.ndarray, cells: int) -> bytes:
    """A frame of a grid of ``cells`` per side with the cells' indices along its edges (``i``
    below, ``j`` on the left, counted from the bottom-left cell)."""
    fig = figure(2.6, 2.6)
    ax = fig.add_subplot()
    ax.imshow(image, extent=(0, cells, 0, cells), interpolation="nearest")
    ticks = np.arange(cells) + 0.5
    step = max(1, math.ceil(cells / 10))  # at most about ten labels a side
    ax.set_xticks(ticks[::step], [str(k) for k in range(0, cells, step)], fontsize=7)
    ax.set_yticks(ticks[::step], [str(k) for k in range(0, cells, step)], fontsize=7)
    ax.set_xlabel("i", fontsize=8, labelpad=1)
    ax.set_ylabel("j", fontsize=8, labelpad=1, rotation=0)
    ax.tick_params(length=0, pad=1)
    return png_of(fig)


def legend_png(colours: tuple[tuple[str, tuple[int, int, int]], ...]) -> bytes:
    """The colours of an env's frames and what each shows, as a legend."""
    from matplotlib.patches import Patch

    fig = figure(6.0, 0.35 + 0.22 * math.ceil(len(colours) / 3))
    handles = [Patch(facecolor=np.array(rgb) / 255, edgecolor="0.5", label=label)
               for label, rgb in colours]
    fig.legend(handles=handles, loc="center", ncols=3, fontsize=8, frameon=False)
    return png_of(fig)
