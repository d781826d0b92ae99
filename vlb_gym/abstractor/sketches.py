"""The space the synthesizer searches: behaviors composed of a few generic phases.

A candidate is a sequence of :class:`Phase` s chained into one behavior document (each phase's
exit node leads to the next phase's entry; the last phase's exit is the terminal). The phases are
what a robot of the env does in general, not answers to particular tasks: for the grid, sense
here, explore (the paper's E4 frontier rule) until a stopping rule holds or nothing more can be
found, go to a place (and sense there), shuttle between two places k times, visit every known
goal. Counts come from the numbers in the request and its promise. :func:`candidates` yields the
documents smallest first, each structurally distinct document once.
"""

from __future__ import annotations

import itertools
import json
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

MAX_PHASES = 3
_NUMBER_WORDS = {"once": 1, "one": 1, "twice": 2, "two": 2, "three": 3, "four": 4, "five": 5,
                 "six": 6, "seven": 7, "eight": 8, "nine": 9, "ten": 10}


@dataclass(frozen=True)
class Edge:
    source: str
    to: str
    guard: str = "True"
    param: str | None = None
    set: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True)
class Phase:
    """A small graph with one entry and one exit: ``nodes`` (id -> primitive), ``edges``
    inside it (tried before the exit, so their guards must fail once the phase is done),
    ``entry`` (node, param) and ``exit`` (the node where it ends); ``variables`` and
    ``functions`` it declares (shared names must mean the same in every phase)."""

    label: str
    nodes: tuple[tuple[str, str], ...]
    entry: tuple[str, str | None]
    exit: str
    edges: tuple[Edge, ...] = ()
    variables: tuple[tuple[str, str], ...] = ()
    functions: tuple[tuple[str, str], ...] = ()
    kind: str = field(default="", compare=False)


def numbers(*texts: str) -> list[int]:
    """The counts named in ``texts`` (digits and number words up to ten), in [1, 100]."""
    found: set[int] = set()
    for text in texts:
        words = re.findall(r"[a-z]+|\d+", text.lower())
        found |= {int(w) for w in words if w.isdigit() and 1 <= int(w) <= 100}
        found |= {_NUMBER_WORDS[w] for w in words if w in _NUMBER_WORDS}
    return sorted(found)


def compose(phases: tuple[Phase, ...], name: str, description: str, env_id: str,
            base_variables: dict[str, str]) -> dict[str, Any]:
    """The behavior document that runs ``phases`` in order (ids made unique per phase)."""
    variables = dict(base_variables)
    functions: dict[str, dict[str, Any]] = {}
    nodes, edges = [], []
    for k, phase in enumerate(phases):
        def rename(text: str, k: int = k) -> str:
            return _rename(text, k)

        for node_id, primitive in phase.nodes:
            nodes.append({"id": f"{node_id}_{k}", "primitive": primitive})
        variables.update({rename(v): rename(e) for v, e in phase.variables})
        for fn, expr in phase.functions:
            functions[fn] = {"args": [], "expr": expr}
        for edge in phase.edges:
            edges.append(_edge(f"{edge.source}_{k}", f"{edge.to}_{k}", rename(edge.guard),
                               edge.param and rename(edge.param),
                               {rename(v): rename(e) for v, e in edge.set}))
        if k + 1 < len(phases):
            following = phases[k + 1]
            edges.append(_edge(f"{phase.exit}_{k}", f"{following.entry[0]}_{k + 1}", "True",
                               following.entry[1] and _rename(following.entry[1], k + 1), {}))
    first = phases[0]
    document = {"name": name, "description": description, "env": env_id,
                "variables": variables, "functions": functions, "nodes": nodes,
                "edges": edges,
                "start": {"node": f"{first.entry[0]}_0",
                          **({"param": _rename(first.entry[1], 0)} if first.entry[1] else {})},
                "terminals": [f"{phases[-1].exit}_{len(phases) - 1}"]}
    return document


def _rename(text: str, k: int) -> str:
    """``text`` with the phase's own names (``$name``) made ``name_k``."""
    return re.sub(r"\$(\w+)", rf"\g<1>_{k}", text)


def _edge(source: str, to: str, guard: str, param: str | None, assignments: dict[str, str]
          ) -> dict[str, Any]:
    edge: dict[str, Any] = {"from": source, "to": to}
    if guard != "True":
        edge["guard"] = guard
    if param is not None:
        edge["param"] = param
    if assignments:
        edge["set"] = assignments
    return edge


@dataclass(frozen=True)
class Candidate:
    """One document of the search space and the phases it was made from, in words."""

    label: str
    document: dict[str, Any]
    phases: int = field(default=1, compare=False)

    @property
    def key(self) -> str:
        """The document's structure (its name and description left out): equal keys, one
        candidate."""
        body = {k: v for k, v in self.document.items() if k not in ("name", "description")}
        return json.dumps(body, sort_keys=True)


PhaseMenu = Callable[[list[int]], list[Phase]]


@dataclass(frozen=True)
class Space:
    """An env's search space: its phase menu (given the counts in the request), the
    variables every candidate starts with, and which phase may not follow which."""

    menu: PhaseMenu
    variables: dict[str, str]
    follows: Callable[[Phase, Phase], bool] = lambda before, after: before != after


def candidates(space: Space, env_id: str, name: str, description: str, counts: list[int],
               max_phases: int = MAX_PHASES) -> Iterator[Candidate]:
    """Every composition of up to ``max_phases`` phases, fewest phases first, each distinct
    document once."""
    menu = space.menu(counts)
    seen: set[str] = set()
    for length in range(1, max_phases + 1):
        for phases in itertools.product(menu, repeat=length):
            if not all(space.follows(a, b) for a, b in zip(phases, phases[1:])):
                continue
            candidate = Candidate(" -> ".join(p.label for p in phases),
                                  compose(phases, name, description, env_id, space.variables),
                                  len(phases))
            if candidate.key not in seen:
                seen.add(candidate.key)
                yield candidate


# --- VLB-GridExplore-v0 -----------------------------------------------------------------------

_GRID_FUNCTIONS = (
    ("open_cells", "[c for c in explored() if label(c) != 'obstacle' and "
                   "len([n for n in adjacent(c) if label(n) == 'unexplored']) > 0]"),
    ("next_cell", "open_cells()[argmax([len([n for n in adjacent(c) if label(n) == "
                  "'unexplored']) for c in open_cells()])]"),
)
_KNOWN_GOALS = ("known_goals", "[c for c in explored() if label(c) == 'goal']")
_BESIDE_HOME = ("beside_home", "[c for c in adjacent(home) if label(c) == 'empty' or "
                               "label(c) == 'goal'][0]")


def _explore(label: str, stop: str) -> Phase:
    return Phase(label, (("look", "sense"), ("go", "navigate")), ("look", "current_cell()"),
                 "look", (Edge("look", "go", f"not ({stop}) and len(open_cells()) > 0",
                               "next_cell()"), Edge("go", "look", param="current_cell()")),
                 functions=_GRID_FUNCTIONS, kind="explore")


def _places() -> list[tuple[str, str, tuple[tuple[str, str], ...]]]:
    return [("the found goal", "goal_cell()", ()), ("the start", "home", ()),
            ("a free cell beside the start", "beside_home()", (_BESIDE_HOME,))]


def grid_menu(counts: list[int]) -> list[Phase]:
    """The grid's phases for the counts ``counts``."""
    menu = [Phase("sense here", (("look", "sense"),), ("look", "current_cell()"), "look",
                  kind="sense"),
            _explore("explore until a goal is found", "goal_found()"),
            _explore("explore everything reachable", "False")]
    for n in counts:
        menu += [_explore(f"explore until {n} cells are known", f"len(explored()) >= {n}"),
                 _explore(f"explore until {n} obstacles are known",
                          f"len([c for c in explored() if label(c) == 'obstacle']) >= {n}")]
    for words, cell, functions in _places():
        menu.append(Phase(f"go to {words}", (("go", "navigate"),), ("go", cell), "go",
                          functions=functions, kind="go"))
        menu.append(Phase(f"go to {words} and sense", (("go", "navigate"), ("look", "sense")),
                          ("go", cell), "look", (Edge("go", "look", param="current_cell()"),),
                          functions=functions, kind="go"))
    for (a_words, a, a_fns), (b_words, b, b_fns) in itertools.permutations(_places(), 2):
        if "home" not in (a, b):
            continue
        for k in sorted({1, *counts}):
            if k > 20:
                continue
            menu.append(Phase(
                f"{k} round trip(s) {a_words} -> {b_words}",
                (("there", "navigate"), ("back", "navigate")), ("there", a), "back",
                (Edge("there", "back", param=b, set=(("$trips", "$trips + 1"),)),
                 Edge("back", "there", f"$trips < {k}", a)),
                variables=(("$trips", "0"),), functions=(*a_fns, *b_fns), kind="shuttle"))
    menu.append(Phase("visit every known goal", (("go", "navigate"),),
                      ("go", "known_goals()[0]"), "go",
                      (Edge("go", "go", "$visited < len(known_goals())",
                            "known_goals()[$visited - 1]", (("$visited", "$visited + 1"),)),),
                      variables=(("$visited", "1"),), functions=(_KNOWN_GOALS,), kind="visit"))
    return menu


def _grid_follows(before: Phase, after: Phase) -> bool:
    """Pairs that add nothing are skipped: a phase twice, two explorations, sensing twice."""
    if before == after or (before.kind == after.kind == "explore"):
        return False
    return not (after.kind == "sense" and before.exit == "look")


GRID = Space(grid_menu, {"home": "current_cell()"}, _grid_follows)


# --- VLB-Scoop-v0 -----------------------------------------------------------------------------

_POSE = "(0.5, 0.075, 0.55, 3.14159, -0.35, 1.5708)"


def scoop_menu(counts: list[int]) -> list[Phase]:
    """Scoop k times from the default sensing pose."""
    return [Phase(f"scoop {k} time(s)", (("scoop", "scoop"),), ("scoop", _POSE), "scoop",
                  (Edge("scoop", "scoop", f"$scoops < {k}", _POSE,
                        (("$scoops", "$scoops + 1"),)),),
                  variables=(("$scoops", "1"),), kind="scoop")
            for k in sorted({1, *counts}) if k <= 10]


SCOOP = Space(scoop_menu, {}, lambda before, after: False)

SPACES: dict[str, Space] = {"VLB-GridExplore-v0": GRID, "VLB-Scoop-v0": SCOOP}
"""The search space of each env that has one."""
