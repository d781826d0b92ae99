"""Types of the grid exploration world: labels and the joint state (x, d)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import IntEnum

import numpy as np


class Label(IntEnum):
    """Cell labels, in the paper's order {empty, obstacle, unexplored, goal}."""

    EMPTY = 0
    OBSTACLE = 1
    UNEXPLORED = 2
    GOAL = 3


LABEL_NAMES: tuple[str, ...] = tuple(label.name.lower() for label in Label)
# plain ints for numpy comparisons on hot paths (an IntEnum operand costs numpy ~4 us)
EMPTY, OBSTACLE, UNEXPLORED, GOAL = (int(label) for label in Label)


def cell_of(position: np.ndarray, size: int) -> tuple[int, int]:
    """The cell containing ``position`` (points on the outer boundary clip inward)."""
    half, top = size / 2, size - 1
    x, y = position.tolist()  # Python floats: a third of the time of indexing the array
    i, j = math.floor(x + half), math.floor(y + half)
    return (0 if i < 0 else top if i > top else i, 0 if j < 0 else top if j > top else j)


@dataclass
class GridState:
    """The joint state: ``x`` = (position, agent labels), ``d`` = the true labels.

    Cell ``(i, j)`` covers ``[-h + i, -h + i + 1) x [-h + j, -h + j + 1)`` with ``h = size / 2``;
    ``i`` indexes x and ``j`` indexes y. Arrays are indexed ``[i, j]``; flat index ``i * size + j``.
    """

    truth: np.ndarray  # (size, size) int8, d: EMPTY / OBSTACLE / GOAL
    labels: np.ndarray  # (size, size) int8, the agent's labels (part of x)
    position: np.ndarray  # (2,) float64, the agent's planar position (part of x)
    start_cell: tuple[int, int]
    component: np.ndarray  # (size, size) int32, 4-connected free components of d (0: obstacle)
    blocked: np.ndarray  # (size + 2, size + 2) bool, obstacles and a border for the grid's edge
    distances: dict[int, np.ndarray] = field(default_factory=dict)  # target -> steps-to-go
    goal_found: bool = False  # some label is 'goal' (kept by sense, the only labeller)
    trail: list[np.ndarray] = field(default_factory=list)  # trajectories, for rendering
    _at: tuple[np.ndarray, tuple[int, int]] | None = field(default=None, init=False,
                                                          repr=False, compare=False)

    @property
    def size(self) -> int:
        return self.truth.shape[0]

    @property
    def cell(self) -> tuple[int, int]:
        """The cell the agent occupies (computed once per position: a move assigns a new
        array, never writes into this one)."""
        at = self._at
        if at is None or at[0] is not self.position:
            at = self._at = (self.position, cell_of(self.position, self.size))
        return at[1]

    def cell_of(self, position: np.ndarray) -> tuple[int, int]:
        """The cell containing ``position``."""
        return cell_of(position, self.size)
