"""Each contestant of the comparison against the task's hand-written graph on the same reset
seeds: rows keep their failed episodes, so episode ``i`` of one pairs with episode ``i`` of the
other, and the fixed-N paired method of ``vlb compare`` (McNemar's exact test, each way:
:class:`~vlb_gym.verify.paired_methods.FixedPairs`) says what the pairs support."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from vlb_gym.verify.bounds import ceil_str
from vlb_gym.verify.paired_methods import FixedPairs

from .configs import DELTA

if TYPE_CHECKING:
    from .compare import Row


def paired(graph: Row, row: Row) -> dict:
    """``row`` against the task's hand-written ``graph`` on the same reset seeds (episode ``i``
    of each): the discordant pairs and McNemar's exact one-sided test each way, at level
    :data:`DELTA`; ``verdict`` says what the pairs support."""
    if (graph.episodes, graph.task) != (row.episodes, row.task):
        raise ValueError(f"{row.contestant} and {graph.contestant} did not run the same episodes")
    graph_failed, row_failed = set(graph.failed), set(row.failed)
    only_graph, only_row = len(row_failed - graph_failed), len(graph_failed - row_failed)
    test = FixedPairs(0.0, DELTA, row.episodes)  # A: the graph, B: the contestant
    test.feed((i not in graph_failed, i not in row_failed) for i in range(row.episodes))
    claim = test.claim()
    row_better, graph_better = claim["p_value"], claim["p_value_against"]
    if graph_better <= DELTA:
        verdict = f"graph more reliable (p = {ceil_str(graph_better, 3)})"
    elif row_better <= DELTA:
        verdict = f"{row.contestant} more reliable (p = {ceil_str(row_better, 3)})"
    else:
        verdict = "no difference shown"
    return {"only_graph": only_graph, "only_contestant": only_row, "graph_better_p": graph_better,
            "contestant_better_p": row_better, "verdict": verdict}


def support(rows: list[Row]) -> list[str]:
    """What the data support, per task and contestant at its largest training budget: on how
    many seeds the paired test shows the graph (or the contestant) more reliable."""
    lines = []
    for task, graph, mine in pairable(rows):
        for contestant in dict.fromkeys(r.contestant for r in mine):
            runs = [r for r in mine if r.contestant == contestant]
            steps = max((r.train_steps or 0) for r in runs)
            runs = [r for r in runs if (r.train_steps or 0) == steps]
            tests = [paired(graph, r) for r in runs]
            worse = sum(t["graph_better_p"] <= DELTA for t in tests)
            better = sum(t["contestant_better_p"] <= DELTA for t in tests)
            at = f" at {steps} steps" if steps else ""
            seeds = f"{len(runs)} seed(s)" if runs[0].seed is not None else "its one run"
            lines.append(f"- {task}: {contestant}{at}, {seeds}: the graph is shown more "
                         f"reliable on {worse}, {contestant} on {better}, no difference shown on "
                         f"{len(runs) - worse - better}")
    return lines


def pairable(rows: list[Row]) -> Iterator[tuple[str, Row, list[Row]]]:
    """Per task: its graph's row and the other rows that know their failed episodes (rows
    written before they kept them do not)."""
    known = [r for r in rows if len(r.failed) == r.episodes - r.successes]
    for task in dict.fromkeys(r.task for r in known):
        mine = [r for r in known if r.task == task]
        graph = next((r for r in mine if r.kind == "graph"), None)
        if graph is not None:
            yield task, graph, [r for r in mine if r.kind != "graph"]
