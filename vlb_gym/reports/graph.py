"""Pictures of behavior graphs, nodes coloured by the rate of their failed certificates.

Graphviz's ``dot`` draws them when it is on PATH; otherwise networkx lays them out and matplotlib
draws them. Terminal nodes have a double outline, sub-behavior nodes are boxes, edges carry their
guards (truncated) and a dot marks the start node.
"""

from __future__ import annotations

import math
import shutil
import subprocess
from collections.abc import Mapping
from typing import Any

from vlb_gym.core.document import short

from .attribution import NodeStats, child_ref

DOT_TIMEOUT_S = 20.0
NO_FAILURE = "#d9f0d3"
FEW_FAILURES = "#fee08b"
MANY_FAILURES = "#d73027"
SUB_BEHAVIOR_EDGE = "#3b5b92"


class PictureUnavailable(RuntimeError):
    """Neither Graphviz nor matplotlib can draw here; the message says what to install."""


def _mix(a: str, b: str, t: float) -> str:
    ca = [int(a[i:i + 2], 16) for i in (1, 3, 5)]
    cb = [int(b[i:i + 2], 16) for i in (1, 3, 5)]
    return "#" + "".join(f"{round(x + (y - x) * t):02x}" for x, y in zip(ca, cb, strict=True))


RATES = (0.001, 0.01, 0.1, 1.0)  # the colour scale's marks: yellow at 0.1% or less, red at all


def failure_shade(failed: int, runs: int) -> float:
    """Where a node with ``failed`` of ``runs`` certificates failed lies on the colour scale, in
    [0, 1]: by its failure *rate*, on a log scale from 0.1% (0) to 100% (1), so that 33 failures
    in 37,155 runs read as rare; a node whose runs are unknown counts as failing every time."""
    rate = failed / runs if runs else 1.0
    return min(1.0, max(0.0, math.log10(max(rate, RATES[0]) / RATES[0]) / 3))


def failure_colour(failed: int, runs: int) -> str:
    """Fill colour of a node with ``failed`` of ``runs`` certificates failed: pale green for
    none, yellow (0.1% of its runs or fewer) to red (all of them) by :func:`failure_shade`."""
    if failed <= 0:
        return NO_FAILURE
    return _mix(FEW_FAILURES, MANY_FAILURES, failure_shade(failed, runs))


def _rate_words(rate: float) -> str:
    return f"{rate:.1%}".replace(".0%", "%")


def node_label(node: Mapping[str, Any], stats: NodeStats) -> str:
    """Id, what the node runs, and its failures (``~`` where attributed by primitive)."""
    ref = child_ref(node)
    what = f"behavior {short(ref, 28)}" if ref else short(node.get("primitive", "?"), 28)
    approx = "~" if stats.approximate else ""
    count = (f"{approx}{stats.failed}/{stats.runs} failed" if stats.runs
             else f"{approx}{stats.failed} failed")
    return f"{short(node.get('id', '?'), 28)}\n({what})\n{count}"


def _edges(spec: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    edges = []
    for edge in spec.get("edges", []):
        guard = edge.get("guard")
        edges.append((str(edge.get("from")), str(edge.get("to")),
                      short(guard, 28) if guard not in (None, "", True, "True") else ""))
    return edges


def _dot_quote(text: str) -> str:
    """A DOT string literal: no escape sequence of the text survives."""
    text = "".join(ch for ch in text if ch == "\n" or ch >= " ")
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def to_dot(spec: Mapping[str, Any], stats: Mapping[str, NodeStats], title: str) -> str:
    """The DOT text of one behavior graph (nodes renamed n0, n1, ...; labels quoted)."""
    nodes = list(spec.get("nodes", []))
    ids = {str(node.get("id")): f"n{i}" for i, node in enumerate(nodes)}
    terminals = {str(t) for t in spec.get("terminals", [])}
    lines = ["digraph behavior {",
             f'  graph [rankdir=LR, dpi=100, size="9,6", fontname="Helvetica", fontsize=13, '
             f'labelloc=t, label={_dot_quote(title)}, bgcolor=white, nodesep=0.4];',
             '  node [fontname="Helvetica", fontsize=10, style=filled, color="#333333"];',
             '  edge [fontname="Helvetica", fontsize=9, color="#555555"];']
    for node in nodes:
        node_id = str(node.get("id"))
        info = stats.get(node_id, NodeStats())
        shape = "box3d" if child_ref(node) else "ellipse"
        extra = f', color="{SUB_BEHAVIOR_EDGE}", penwidth=2' if child_ref(node) else ""
        if info.failed > 0 and failure_shade(info.failed, info.runs) >= 0.6:
            extra += ", fontcolor=white"  # readable on dark red
        lines.append(f"  {ids[node_id]} [label={_dot_quote(node_label(node, info))}, "
                     f'shape={shape}, fillcolor="{failure_colour(info.failed, info.runs)}", '
                     f"peripheries={2 if node_id in terminals else 1}{extra}];")
    start = spec.get("start") or {}
    if str(start.get("node")) in ids:
        param = start.get("param")
        label = _dot_quote(short(param, 24)) if param is not None else '""'
        lines += ["  start [shape=point, width=0.15, color=black];",
                  f"  start -> {ids[str(start.get('node'))]} [label={label}];"]
    for source, target, guard in _edges(spec):
        for end in (source, target):
            if end not in ids:  # an edge to an unknown node: draw it, do not hide it
                ids[end] = f"n{len(ids)}"
                lines.append(f"  {ids[end]} [label={_dot_quote(short(end, 28) + '?')}, "
                             'shape=octagon, fillcolor="#eeeeee"];')
        lines.append(f"  {ids[source]} -> {ids[target]} [label={_dot_quote(guard)}];")
    lines += ["  subgraph cluster_legend {",
              '    label="legend"; fontsize=10; color="#999999"; style=rounded;',
              '    node [fontsize=9, width=0.3, height=0.3];',
              f'    l0 [label="no failed\\ncertificate", fillcolor="{NO_FAILURE}"];']
    legend = ["l0"]
    for k, rate in enumerate(RATES, 1):
        failed = round(rate * 1000)
        white = ", fontcolor=white" if failure_shade(failed, 1000) >= 0.6 else ""
        lines.append(f'    r{k} [label="{_rate_words(rate)} of runs\\nfailed", '
                     f'fillcolor="{failure_colour(failed, 1000)}"{white}];')
        legend.append(f"r{k}")
    lines += ['    l3 [label="terminal", fillcolor=white, peripheries=2];',
              f'    l4 [label="sub-behavior", shape=box3d, fillcolor=white, '
              f'color="{SUB_BEHAVIOR_EDGE}", penwidth=2];',
              "    " + " -> ".join(legend + ["l3", "l4"]) + " [style=invis];",
              "  }", "}"]
    return "\n".join(lines) + "\n"


def dot_png(dot_text: str, dot: str) -> bytes:
    """Run Graphviz ``dot`` on ``dot_text``; raises on failure or after DOT_TIMEOUT_S."""
    done = subprocess.run([dot, "-Tpng"], input=dot_text.encode(), capture_output=True,
                          timeout=DOT_TIMEOUT_S, check=False)
    if done.returncode != 0 or not done.stdout.startswith(b"\x89PNG"):
        raise RuntimeError(f"dot failed: {done.stderr.decode(errors='replace')[:200]}")
    return done.stdout


def networkx_png(spec: Mapping[str, Any], stats: Mapping[str, NodeStats], title: str) -> bytes:
    """The graph drawn by networkx and matplotlib (layered from the start node)."""
    try:
        from matplotlib.colors import LinearSegmentedColormap, Normalize
        from matplotlib.cm import ScalarMappable
        from matplotlib.lines import Line2D
    except ImportError:
        raise PictureUnavailable("no picture (matplotlib, a dependency of vlb-gym, is missing: "
                                 "pip install matplotlib)") from None
    import networkx as nx

    from .plots import figure, png_of

    nodes = {str(n.get("id")): n for n in spec.get("nodes", [])}
    terminals = {str(t) for t in spec.get("terminals", [])}
    graph = nx.DiGraph()
    graph.add_nodes_from(nodes)
    labels: dict[tuple[str, str], list[str]] = {}
    for source, target, guard in _edges(spec):
        graph.add_edge(source, target)
        if guard:
            labels.setdefault((source, target), []).append(guard)
    start = str((spec.get("start") or {}).get("node"))
    layers = {start: 0} if start in graph else {}
    if layers:
        layers.update(nx.single_source_shortest_path_length(graph, start))
    deepest = max(layers.values(), default=-1)
    for node in graph:
        graph.nodes[node]["layer"] = layers.get(node, deepest + 1)
    pos = nx.multipartite_layout(graph, subset_key="layer") if len(graph) > 1 else {
        n: (0.0, 0.0) for n in graph}

    fig = figure(8.0, 5.0)
    ax = fig.add_subplot(1, 1, 1)
    ax.set_title(title, fontsize=11)
    ax.set_axis_off()
    colour = {n: failure_colour(stats.get(n, NodeStats()).failed, stats.get(n, NodeStats()).runs)
              for n in graph}
    for shape, members in (("o", [n for n in graph if n in nodes and not child_ref(nodes[n])]),
                           ("s", [n for n in graph if n in nodes and child_ref(nodes[n])]),
                           ("8", [n for n in graph if n not in nodes])):
        ring = [n for n in members if n in terminals]
        if ring:  # the outer ring of a terminal node's double outline
            nx.draw_networkx_nodes(graph, pos, nodelist=ring, node_shape=shape, ax=ax,
                                   node_size=4400, node_color="white", edgecolors="#333333",
                                   linewidths=1.2)
        if members:
            nx.draw_networkx_nodes(
                graph, pos, nodelist=members, node_shape=shape, ax=ax, node_size=3400,
                node_color=[colour[n] for n in members], linewidths=2 if shape == "s" else 1.2,
                edgecolors=SUB_BEHAVIOR_EDGE if shape == "s" else "#333333")
    nx.draw_networkx_edges(graph, pos, ax=ax, node_size=4000, arrowsize=14,
                           connectionstyle="arc3,rad=0.15", edge_color="#555555")
    text = {n: (node_label(nodes[n], stats.get(n, NodeStats())) if n in nodes else n + "?")
            for n in graph}
    nx.draw_networkx_labels(graph, pos, labels=text, font_size=7, ax=ax)
    if labels:
        nx.draw_networkx_edge_labels(graph, pos, ax=ax, font_size=7, connectionstyle="arc3,rad=0.15",
                                     edge_labels={e: " | ".join(g) for e, g in labels.items()})
    if start in pos:
        x, y = pos[start]
        ax.annotate("start", xy=(x, y), xytext=(x - 0.5, y + 0.12), fontsize=8,
                    arrowprops={"arrowstyle": "->", "color": "black", "shrinkB": 32})
    xs = [p[0] for p in pos.values()] or [0.0]
    ys = [p[1] for p in pos.values()] or [0.0]
    ax.set_xlim(min(xs) - 0.6, max(xs) + 0.6)
    ax.set_ylim(min(ys) - 0.5, max(ys) + 0.5)
    cmap = LinearSegmentedColormap.from_list("failures", [(0.0, FEW_FAILURES),
                                                          (1.0, MANY_FAILURES)])
    bar = fig.colorbar(ScalarMappable(Normalize(0.0, 1.0), cmap), ax=ax, shrink=0.6,
                       ticks=[failure_shade(round(r * 1000), 1000) for r in RATES])
    bar.ax.set_yticklabels([("<= " if r == RATES[0] else "") + _rate_words(r) for r in RATES])
    bar.set_label("failed certificates, share of the node's runs (green: none)", fontsize=8)
    ax.legend(handles=[
        Line2D([], [], marker="o", ls="", mfc="white", mec="#333333", ms=10, label="primitive"),
        Line2D([], [], marker="s", ls="", mfc="white", mec=SUB_BEHAVIOR_EDGE, mew=2, ms=10,
               label="sub-behavior"),
        Line2D([], [], marker="o", ls="", mfc="white", mec="#333333", ms=13, mew=3,
               label="terminal (double outline)")], loc="lower left", fontsize=7, frameon=True)
    return png_of(fig)


def behavior_png(spec: Mapping[str, Any], stats: Mapping[str, NodeStats], title: str
                 ) -> tuple[bytes, str]:
    """``(png, how)``: the picture and what drew it (``"graphviz"`` or ``"networkx"``)."""
    dot = shutil.which("dot")
    if dot:
        try:
            return dot_png(to_dot(spec, stats, title), dot), "graphviz"
        except (OSError, RuntimeError, subprocess.TimeoutExpired):
            pass  # fall through to the networkx picture
    return networkx_png(spec, stats, title), "networkx"
