"""Decision helpers of the exploration study: the paper's E1-E3 plus small accessors.

Cells are ``(i, j)`` tuples; lists of cells are in flat-index order ``i * size + j``. Helpers read
only the observation: the agent's labels and position.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from vlb_gym.core.helpers import Helpers, brief, helper

from .planner import _neighbours
from .types import GOAL, LABEL_NAMES, OBSTACLE, UNEXPLORED, cell_of

Cell = tuple[int, int]
Direction = Literal["right", "left", "up", "down"]
_STEPS = {"right": (1, 0), "left": (-1, 0), "up": (0, 1), "down": (0, -1)}
_FREE = (LABEL_NAMES.index("empty"), GOAL)


def _integer(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def cell_index(cell: Any, size: int, fn: str) -> int:
    """The flat index of ``cell`` on a ``size`` grid, else ValueError naming helper ``fn``;
    types are checked before anything else (an untrusted value is never hashed)."""
    if type(cell) is tuple and len(cell) == 2:
        i, j = cell
        if type(i) is int and type(j) is int and 0 <= i < size and 0 <= j < size:
            return i * size + j
    if not (isinstance(cell, (tuple, list)) and len(cell) == 2):
        raise ValueError(f"{fn}(): {brief(cell)} is not a cell (i, j)")
    i, j = cell
    if not (_integer(i) and _integer(j) and 0 <= i < size and 0 <= j < size):
        raise ValueError(f"{fn}(): {brief(cell)} is not a cell of the {size}x{size} grid")
    return i * size + j


_MAX_CELLS = 4096 * 100  # cells of the label maps remembered: 4,096 maps of 10x10, 100 of 64x64


@dataclass(slots=True)
class _View:
    """One label map and the lists read from it, computed when first asked for. Helpers return
    these lists shared: expressions cannot change a value (no attributes, no assignment)."""

    labels: list[int]
    explored: list[Cell] | None = None
    frontier: list[Cell] | None = None


class GridHelpers(Helpers):
    """Helpers for ``VLB-GridExplore-v0`` observations.

    A Cell is a tuple (i, j) of ints with 0 <= i, j < size (10 by default); i indexes x, j indexes
    y, and (i + 1, j) is the cell to the right of (i, j). Lists of cells are in flat-index order
    i * size + j. Primitive parameters are cells.
    """

    def __init__(self, size: int):
        self.size = size
        self._cells = [divmod(k, size) for k in range(size * size)]
        self._adjacent_flat = _neighbours(size)
        self._adjacent = [[self._cells[m] for m in ms] for ms in self._adjacent_flat]
        self._labels: list[int] = []
        self._here: Cell = (0, 0)
        self._views: dict[bytes, _View] = {}  # label maps seen (a search revisits them often)
        self._max_views = max(1, _MAX_CELLS // (size * size))
        self._view = _View([])

    def bind(self, observation: dict[str, Any]) -> None:
        labels = observation["labels"]
        key = labels.tobytes()
        view = self._views.get(key)
        if view is None:
            if len(self._views) >= self._max_views:
                self._views.clear()
            view = self._views[key] = _View(labels.tolist())
        self._view, self._labels = view, view.labels
        self._here = cell_of(observation["position"], self.size)

    def _index(self, cell: Any, fn: str) -> int:
        return cell_index(cell, self.size, fn)

    @helper
    def explored(self) -> list[Cell]:
        """E1: all cells whose label is not 'unexplored', in flat-index order."""
        view = self._view
        if view.explored is None:
            view.explored = [cell for cell, lab in zip(self._cells, view.labels)
                             if lab != UNEXPLORED]
        return view.explored

    @helper(at_most=4)
    def adjacent(self, cell: Cell | None = None) -> list[Cell]:
        """E2: the cells 4-adjacent to ``cell`` (default: the agent's cell), inside the grid."""
        if type(cell) is tuple and len(cell) == 2:  # _index's fast path, inlined: a hot call
            i, j = cell
            size = self.size
            if type(i) is int and type(j) is int and 0 <= i < size and 0 <= j < size:
                return self._adjacent[i * size + j]
        return self._adjacent[self._index(self._here if cell is None else cell, "adjacent")]

    @helper
    def goal_found(self) -> bool:
        """E3: whether some cell is labelled 'goal'."""
        return GOAL in self._labels

    @helper
    def goal_cell(self) -> Cell | None:
        """E3: the first cell labelled 'goal', or None if no goal has been found."""
        try:
            return self._cells[self._labels.index(GOAL)]
        except ValueError:
            return None

    @helper
    def current_cell(self) -> Cell:
        """The cell the agent occupies."""
        return self._here

    @helper
    def frontier_cells(self) -> list[Cell]:
        """E4's candidates: the known cells that are not obstacles and have an unexplored
        neighbour (where sensing can still reveal something), in flat-index order."""
        view = self._view
        if view.frontier is None:
            labels, adjacent = view.labels, self._adjacent_flat
            view.frontier = [self._cells[k] for k, lab in enumerate(labels)
                             if lab != UNEXPLORED and lab != OBSTACLE
                             and any(labels[m] == UNEXPLORED for m in adjacent[k])]
        return view.frontier

    @helper
    def manhattan(self, a: Cell, b: Cell) -> int:
        """Steps along rows and columns from ``a`` to ``b``, obstacles ignored: |di| + |dj|."""
        k, m = self._index(a, "manhattan"), self._index(b, "manhattan")
        return abs(k // self.size - m // self.size) + abs(k % self.size - m % self.size)

    @helper
    def beside(self, cell: Cell, direction: Direction) -> Cell | None:
        """The cell next to ``cell`` in ``direction`` ('right': i + 1, 'left': i - 1, 'up':
        j + 1, 'down': j - 1), or None where that is outside the grid."""
        k = self._index(cell, "beside")
        step = _STEPS.get(direction) if type(direction) is str else None
        if step is None:
            raise ValueError(f"beside(): {brief(direction)} is not one of "
                             f"{', '.join(map(repr, _STEPS))}")
        i, j = k // self.size + step[0], k % self.size + step[1]
        return (i, j) if 0 <= i < self.size and 0 <= j < self.size else None

    @helper
    def opposite(self, cell: Cell) -> Cell | None:
        """The cell on the other side of the agent from its neighbour ``cell``:
        ``opposite(path[-2])`` is one more step the way the last move went,
        ``opposite(o)`` the step straight away from the obstacle ``o`` beside the agent. None
        where ``cell`` is not beside the agent or that cell is outside the grid."""
        k, (i, j) = self._index(cell, "opposite"), self._here
        di, dj = i - k // self.size, j - k % self.size
        if abs(di) + abs(dj) != 1:
            return None
        i, j = i + di, j + dj
        return (i, j) if 0 <= i < self.size and 0 <= j < self.size else None

    @helper
    def is_free(self, cell: Cell | None) -> bool:
        """Whether ``cell`` is known to be free: labelled 'empty' or 'goal' (a cell outside the
        grid, or None, is not: nothing can stand there)."""
        size = self.size
        if type(cell) is tuple and len(cell) == 2:  # the hot call: a pair of ints
            i, j = cell
            if type(i) is int and type(j) is int:
                return 0 <= i < size and 0 <= j < size and self._labels[i * size + j] in _FREE
        if cell is None or (isinstance(cell, (tuple, list)) and len(cell) == 2 and all(
                _integer(v) for v in cell) and not all(0 <= v < size for v in cell)):
            return False
        return self._labels[self._index(cell, "is_free")] in _FREE

    @helper(one_of=LABEL_NAMES)
    def label(self, cell: Cell) -> str:
        """The agent's label of ``cell``: 'empty', 'obstacle', 'unexplored' or 'goal'."""
        if type(cell) is tuple and len(cell) == 2:  # _index's fast path, inlined: the hot call
            i, j = cell
            size = self.size
            if type(i) is int and type(j) is int and 0 <= i < size and 0 <= j < size:
                return LABEL_NAMES[self._labels[i * size + j]]
        return LABEL_NAMES[self._labels[self._index(cell, "label")]]
