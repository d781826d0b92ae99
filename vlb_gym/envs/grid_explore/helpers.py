"""Decision helpers of the exploration study: the paper's E1-E3 plus small accessors.

Cells are ``(i, j)`` tuples; lists of cells are in flat-index order ``i * size + j``. Helpers read
only the observation: the agent's labels and position.
"""

from __future__ import annotations

from typing import Any

from vlb_gym.core.helpers import Helpers, helper

from .planner import _neighbours
from .types import GOAL, LABEL_NAMES, UNEXPLORED, cell_of

Cell = tuple[int, int]


class GridHelpers(Helpers):
    """Helpers for ``VLB-GridExplore-v0`` observations.

    A Cell is a tuple (i, j) of ints with 0 <= i, j < size (10 by default); i indexes x, j indexes
    y, and (i + 1, j) is the cell to the right of (i, j). Lists of cells are in flat-index order
    i * size + j. Primitive parameters are cells.
    """

    def __init__(self, size: int):
        self.size = size
        self._cells = [divmod(k, size) for k in range(size * size)]
        self._flat = {cell: k for k, cell in enumerate(self._cells)}
        self._adjacent = [[self._cells[m] for m in ms] for ms in _neighbours(size)]
        self._labels: list[int] = []
        self._here: Cell = (0, 0)

    def bind(self, observation: dict[str, Any]) -> None:
        self._labels = observation["labels"].tolist()
        self._here = cell_of(observation["position"], self.size)

    def _index(self, cell: Any, fn: str) -> int:
        if type(cell) is tuple:  # fast path: a well-formed cell tuple
            k = self._flat.get(cell)
            if k is not None:
                return k
        try:
            i, j = cell
        except (TypeError, ValueError):
            raise ValueError(f"{fn}(): {cell!r} is not a cell (i, j)") from None
        if not (isinstance(i, int) and isinstance(j, int) and 0 <= i < self.size
                and 0 <= j < self.size):
            raise ValueError(f"{fn}(): {cell!r} is not a cell of the {self.size}x{self.size} grid")
        return i * self.size + j

    @helper
    def explored(self) -> list[Cell]:
        """E1: all cells whose label is not 'unexplored', in flat-index order."""
        return [self._cells[k] for k, lab in enumerate(self._labels) if lab != UNEXPLORED]

    @helper
    def adjacent(self, cell: Cell | None = None) -> list[Cell]:
        """E2: the cells 4-adjacent to ``cell`` (default: the agent's cell), inside the grid."""
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
    def label(self, cell: Cell) -> str:
        """The agent's label of ``cell``: 'empty', 'obstacle', 'unexplored' or 'goal'."""
        k = self._flat.get(cell) if type(cell) is tuple else None  # inlined fast path (hot)
        return LABEL_NAMES[self._labels[self._index(cell, "label") if k is None else k]]
