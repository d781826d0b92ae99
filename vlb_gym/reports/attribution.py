"""Which behavior graphs a report draws, and how often each node's certificate failed.

A failed step (``certificate`` false) counts against its ``node`` (a node id of the main
behavior, ``sub/node`` in sub-behavior ``sub``); a step with no node (or,
for stores written before episodes kept their steps, a failed episode whose cause names a
primitive) counts against every node running that primitive, and such counts are marked
approximate. A sub-behavior node totals the nodes of the behavior it names.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import PurePath
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from vlb_gym.verify.records import Plan


@dataclass
class NodeStats:
    """Steps run at a node, how many of their certificates failed and why (the steps'
    causes: inadmissible parameter, controller failed, certificate), and their wall time."""

    runs: int = 0
    failed: int = 0
    approximate: bool = False  # attributed by primitive: the node was not recorded
    causes: Counter[str] = field(default_factory=Counter)
    timed: int = 0  # steps that recorded their time (stores of format 2 on)
    seconds: float = 0.0

    def count(self, step: Mapping[str, Any]) -> None:
        """Add one recorded step."""
        self.runs += 1 if step.get("counted", True) else 0
        if step.get("certificate") is False:
            self.failed += 1
            self.causes[str(step.get("cause") or "certificate")] += 1
        seconds = step.get("seconds")
        if isinstance(seconds, (int, float)):
            self.timed += 1
            self.seconds += seconds

    def add(self, other: NodeStats) -> None:
        self.runs += other.runs
        self.failed += other.failed
        self.approximate = self.approximate or other.approximate
        self.causes.update(other.causes)
        self.timed += other.timed
        self.seconds += other.seconds

    @property
    def mean_seconds(self) -> float | None:
        """A step's mean wall time, None when no step recorded one."""
        return self.seconds / self.timed if self.timed else None

    def as_dict(self) -> dict[str, Any]:
        """The statistics as JSON data (``failures``: failed certificates by cause)."""
        return {"runs": self.runs, "failed": self.failed,
                "failure_rate": self.failed / self.runs if self.runs else None,
                "failures": dict(self.causes.most_common()),
                "mean_seconds": self.mean_seconds, "approximate": self.approximate}


def plan_behaviors(plan: Plan) -> dict[str, dict[str, Any]]:
    """The behavior specs a campaign plan records, by source (none for a trained agent)."""
    return dict(plan.policy_content.get("behaviors") or {})


def is_agent(report: Mapping[str, Any]) -> bool:
    """Whether the campaign verified a trained agent rather than a behavior graph."""
    return report["policy"]["kind"] != "behavior"


def _stem(ref: str) -> str:
    return PurePath(ref).stem if ref.endswith(".json") else PurePath(ref).name


def resolve(ref: str, specs: Mapping[str, dict[str, Any]]) -> str | None:
    """The key of ``specs`` that a behavior reference (name or path) names, if any."""
    if ref in specs:
        return ref
    for key, spec in specs.items():
        if spec.get("name") == ref or _stem(key) == _stem(ref) or spec.get("name") == _stem(ref):
            return key
    return None


def child_ref(node: Mapping[str, Any]) -> str | None:
    """The behavior a sub-behavior node names, or None for a primitive node."""
    ref = node.get("behavior")
    return ref if isinstance(ref, str) else None


def behavior_order(main: str, specs: Mapping[str, dict[str, Any]]) -> list[str]:
    """Keys of ``specs``: the main behavior first, then its sub-behaviors breadth-first, then any
    others the plan holds."""
    first = resolve(main, specs)
    order: list[str] = []
    queue = [first] if first is not None else []
    while queue:
        key = queue.pop(0)
        if key in order:
            continue
        order.append(key)
        for node in specs[key].get("nodes", []):
            ref = child_ref(node)
            found = resolve(ref, specs) if ref else None
            if found is not None and found not in order:
                queue.append(found)
    return order + sorted(key for key in specs if key not in order)


def known_primitives(specs: Mapping[str, dict[str, Any]]) -> set[str]:
    return {node["primitive"] for spec in specs.values() for node in spec.get("nodes", [])
            if isinstance(node.get("primitive"), str)}


def steps_of(episodes: list[dict[str, Any]], primitives: set[str]) -> list[dict[str, Any]]:
    """Every recorded step; without any, one failed pseudo-step per failed episode whose cause
    starts with a known primitive (``"navigate: controller failed"``)."""
    steps = [step for episode in episodes for step in (episode.get("steps") or [])
             if isinstance(step, dict)]
    if steps:
        return steps
    pseudo = []
    for episode in episodes:
        cause = episode.get("cause") or ""
        primitive = cause.split(":", 1)[0]
        if episode.get("rho", 1) < 0 and ":" in cause and primitive in primitives:
            pseudo.append({"primitive": primitive, "node": None, "certificate": False,
                           "counted": False})
    return pseudo


def node_stats(specs: Mapping[str, dict[str, Any]], episodes: list[dict[str, Any]],
               main: str) -> dict[str, dict[str, NodeStats]]:
    """``{behavior key: {node id: NodeStats}}`` for every node of every behavior in ``specs``;
    ``main`` is the key of the behavior the campaign ran."""
    by_node: dict[tuple[str, str, str], NodeStats] = {}
    by_primitive: dict[str, NodeStats] = {}
    for step in steps_of(episodes, known_primitives(specs)):
        primitive, node = str(step.get("primitive")), step.get("node")
        if node is None:
            stats = by_primitive.setdefault(primitive, NodeStats(approximate=True))
        else:
            behavior, _, node_id = str(node).rpartition("/")
            stats = by_node.setdefault((behavior, node_id, primitive), NodeStats())
        stats.count(step)

    result: dict[str, dict[str, NodeStats]] = {}

    def of(key: str, visiting: frozenset[str]) -> dict[str, NodeStats]:
        if key in result:
            return result[key]
        table: dict[str, NodeStats] = {}
        behavior = "" if key == main else str(specs[key].get("name", key))
        for node in specs[key].get("nodes", []):
            node_id, stats = str(node.get("id")), NodeStats()
            ref = child_ref(node)
            if ref is not None:
                child = resolve(ref, specs)
                if child is not None and child not in visiting:
                    for sub in of(child, visiting | {child}).values():
                        stats.add(sub)
            else:
                primitive = str(node.get("primitive"))
                stats.add(by_node.get((behavior, node_id, primitive), NodeStats()))
                stats.add(by_primitive.get(primitive, NodeStats()))
            table[node_id] = stats
        result[key] = table
        return table

    for key in specs:
        of(key, frozenset({key}))
    return result


def failures_by_primitive(episodes: list[dict[str, Any]]) -> dict[str, NodeStats]:
    """Steps and failed certificates per primitive (recorded steps only)."""
    table: dict[str, NodeStats] = {}
    for episode in episodes:
        for step in episode.get("steps") or []:
            table.setdefault(str(step.get("primitive")), NodeStats()).count(step)
    return table


def node_rows(plan: Plan, episodes: list[dict[str, Any]], behavior: str
              ) -> list[dict[str, Any]]:
    """Every node's statistics (:meth:`NodeStats.as_dict`) as the report's graph counts them,
    ``node`` named as steps name it (``sub/node`` in a sub-behavior), the main behavior first;
    empty for a trained agent."""
    specs = plan_behaviors(plan)
    order = behavior_order(behavior, specs)
    return rows_of(specs, order, node_stats(specs, episodes, order[0])) if order else []


def rows_of(specs: Mapping[str, dict[str, Any]], order: list[str],
            stats: Mapping[str, Mapping[str, NodeStats]]) -> list[dict[str, Any]]:
    """:func:`node_rows` of statistics already counted (``order``: :func:`behavior_order`)."""
    rows = []
    for key in order:
        prefix = "" if key == order[0] else str(specs[key].get("name", key)) + "/"
        for node in specs[key].get("nodes", []):
            node_id = str(node.get("id"))
            rows.append({"node": prefix + node_id, "primitive": node.get("primitive"),
                         "behavior": child_ref(node),
                         **stats[key].get(node_id, NodeStats()).as_dict()})
    return rows
