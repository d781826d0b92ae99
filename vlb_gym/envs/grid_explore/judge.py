"""Outcome helpers of the exploration study: what a behavior's promise is written with.

They read the true map and the steps the behavior ran (a :class:`~vlb_gym.core.promise.Episode`),
so a promise can say what the behavior did, not only what the agent believes.
"""

from __future__ import annotations

from dataclasses import replace
from functools import cached_property

import numpy as np

from vlb_gym.core.helpers import Judge, helper
from vlb_gym.core.promise import Episode

from .helpers import Cell, cell_index
from .planner import _neighbours
from .types import GOAL, OBSTACLE, UNEXPLORED, GridState


class GridJudge(Judge):
    """Outcome helpers for ``VLB-GridExplore-v0`` promises.

    Cells are tuples (i, j) as for the decision helpers; lists of cells are in flat-index order
    unless they are steps (moves, sensed), which are in the order the behavior ran them. A cell
    is known when the agent's label of it is not 'unexplored'; reachable when it lies in the free
    component of the cell the behavior started in.
    """

    def __init__(self, size: int):
        self.size = size
        self._cells = [divmod(k, size) for k in range(size * size)]
        self._adjacent = [[self._cells[m] for m in ms] for ms in _neighbours(size)]
        self._state: GridState | None = None
        self._episode = Episode(None, [], {})
        self._start: Cell = (0, 0)

    def bind(self, episode: Episode) -> None:
        self._state = episode.state
        self._episode = episode
        for read in ("_steps", "_goal_known"):  # the last episode's, read when first asked
            self.__dict__.pop(read, None)
        entry = episode.entry
        self._start = tuple(entry["cell"] if "cell" in entry else entry["start_cell"])

    @cached_property
    def _steps(self) -> list[tuple[str, Cell]]:
        """Each step's primitive and parameter cell, in order."""
        return [(s["primitive"], tuple(map(int, s["param"]))) for s in self._episode.steps]

    @cached_property
    def _goal_known(self) -> list[bool]:
        """Whether a goal was known before the first step and after each."""
        episode = self._episode
        return [bool(episode.entry.get("goal_found", False))] + \
            [bool(s["goal_found"]) for s in episode.steps]

    @property
    def _truth(self) -> np.ndarray:
        return self._state.truth.ravel()

    @helper
    def start_cell(self) -> Cell:
        """The cell the agent was in when the behavior began."""
        return self._start

    @helper
    def final_cell(self) -> Cell:
        """The cell the agent is in now that the behavior has finished."""
        return self._state.cell

    @helper
    def moves(self) -> list[Cell]:
        """The target cells of the behavior's navigate steps, in the order it ran them."""
        return [cell for name, cell in self._steps if name == "navigate"]

    @helper
    def sensed(self) -> list[Cell]:
        """The cells where the behavior ran sense, in order."""
        return [cell for name, cell in self._steps if name == "sense"]

    @helper
    def primitives(self) -> list[str]:
        """The names of the primitives the behavior ran, in order ('sense' or 'navigate')."""
        return [name for name, _ in self._steps]

    @helper
    def known_cells(self) -> list[Cell]:
        """The cells the agent knows now (labelled empty, obstacle or goal)."""
        labels = self._state.labels.ravel().tolist()
        return [cell for cell, lab in zip(self._cells, labels) if lab != UNEXPLORED]

    @helper
    def known_before_last(self) -> list[Cell]:
        """The cells the agent knew before the behavior's last step: those it knows now, less
        those its last step sensed that none of its earlier steps did (with known_cells(): was
        the last step the first after which something held, "as soon as"?)."""
        fresh = self._fresh()
        return [c for c in self.known_cells() if c not in fresh]

    def _fresh(self) -> set[Cell]:
        """The cells the last step labelled: those a last sense labels that no earlier step
        of the behavior sensed (a cell known before the behavior began and first sensed by it
        in its last step counts as fresh)."""
        if not self._steps or self._steps[-1][0] != "sense":
            return set()
        earlier = set()
        for name, cell in self._steps[:-1]:
            if name == "sense":
                earlier.update(self._sensed(cell))
        return set(self._sensed(self._steps[-1][1])) - earlier

    def _sensed(self, cell: Cell) -> list[Cell]:
        """The cells a sense at ``cell`` labels: it and its neighbours."""
        return [cell, *self._adjacent[cell_index(cell, self.size, "sense")]]

    def rewind(self, episode: Episode) -> Episode:
        """The episode before its last step: the agent in the cell it was in then, the cells
        that step labelled unlabelled again (see :meth:`known_before_last`), the truth as it
        is."""
        self.bind(episode)
        state = episode.state
        labels = state.labels.copy()
        for i, j in self._fresh():
            labels[i, j] = UNEXPLORED
        before = episode.steps[-2] if len(episode.steps) > 1 else episode.entry
        i, j = before["cell"] if "cell" in before else before["start_cell"]
        half = self.size / 2
        earlier = replace(state, labels=labels, goal_found=bool((labels == GOAL).any()),
                          position=np.array([i - half + 0.5, j - half + 0.5]))
        return Episode(earlier, episode.steps[:-1], episode.entry)

    @helper
    def known_obstacles(self) -> list[Cell]:
        """The cells the agent has labelled 'obstacle'."""
        labels = self._state.labels.ravel().tolist()
        return [cell for cell, lab in zip(self._cells, labels) if lab == OBSTACLE]

    @helper
    def goal_found(self) -> bool:
        """Whether the agent has labelled some cell 'goal'."""
        return bool((self._state.labels == GOAL).any())

    @helper
    def steps_after_goal(self) -> int:
        """How many primitives the behavior ran after the one that first revealed a goal: 0 if
        its last step did, -1 if no goal is known (the number of its steps if one was known
        before it began)."""
        if not self._goal_known[-1]:
            return -1
        return len(self._goal_known) - 1 - self._goal_known.index(True)

    @helper
    def moves_after_goal(self) -> list[Cell]:
        """The target cells of the navigate steps the behavior ran after the step that first
        revealed a goal, in order (empty if no goal is known)."""
        after = self.steps_after_goal()
        if after <= 0:
            return []
        return [cell for name, cell in self._steps[-after:] if name == "navigate"]

    @helper
    def is_goal(self, cell: Cell) -> bool:
        """Whether ``cell`` truly holds a goal."""
        return bool(self._truth[cell_index(cell, self.size, "is_goal")] == GOAL)

    @helper
    def is_obstacle(self, cell: Cell) -> bool:
        """Whether ``cell`` truly holds an obstacle."""
        return bool(self._truth[cell_index(cell, self.size, "is_obstacle")] == OBSTACLE)

    @helper
    def reachable_cells(self) -> list[Cell]:
        """The cells reachable from the start cell (its free component), in flat-index order."""
        return [self._cells[k] for k in np.flatnonzero(self._reachable().ravel()).tolist()]

    @helper
    def reachable_goals(self) -> list[Cell]:
        """The goals reachable from the start cell, in flat-index order."""
        reach = self._reachable().ravel() & (self._truth == GOAL)
        return [self._cells[k] for k in np.flatnonzero(reach).tolist()]

    @helper
    def explored_all(self) -> bool:
        """Whether every reachable cell, and every cell next to a reachable one, is known:
        nothing more can be found."""
        reach = self._reachable()
        near = reach.copy()
        near[1:] |= reach[:-1]
        near[:-1] |= reach[1:]
        near[:, 1:] |= reach[:, :-1]
        near[:, :-1] |= reach[:, 1:]
        return bool((self._state.labels[near] != UNEXPLORED).all())

    @helper(at_most=4)
    def neighbours(self, cell: Cell) -> list[Cell]:
        """The cells 4-adjacent to ``cell``, inside the grid."""
        return self._adjacent[cell_index(cell, self.size, "neighbours")]

    def _reachable(self) -> np.ndarray:
        component = self._state.component
        return component == component[self._start]

    def summary(self) -> str:
        moves, sensed = self.moves(), self.sensed()
        final = self.final_cell()
        tail = f", last moves {moves[-4:]}" if moves else ""
        return (f"began in {self._start}, ended in {final}"
                f"{' (a goal)' if self.is_goal(final) else ''}; {len(moves)} move(s){tail}, "
                f"{len(sensed)} sense(s); {len(self.known_cells())} cells known, "
                f"{len(self.known_obstacles())} obstacle(s) known, goal "
                f"{'found' if self.goal_found() else 'not found'}, everything reachable "
                f"{'explored' if self.explored_all() else 'not explored'}")
