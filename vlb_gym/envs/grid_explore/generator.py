"""Sampling of start/environment pairs uniformly from the allowable space (paper eq. allowable_space).

A pair ``(x, d)`` is allowable when the start cell is empty (neither obstacle nor goal) and at least
one goal is reachable from it through free cells. Rejection sampling from the product of

* ``d``: ``n_obstacles`` obstacle cells and ``n_goals`` goal cells, a uniformly random subset, and
* ``x``: a position uniform on ``[-h, h]^2`` with all labels unexplored,

restricted to allowable pairs is exactly the uniform distribution on the allowable space.
"""

from __future__ import annotations

import numpy as np

from .planner import _neighbours, padded_blocked
from .types import EMPTY, GOAL, OBSTACLE, UNEXPLORED, GridState, cell_of

MAX_TRIES = 10_000


def free_components(truth: np.ndarray) -> np.ndarray:
    """4-connected components of the non-obstacle cells, numbered 1, 2, ... in the order of
    their first cell in flat-index order (``scipy.ndimage.label``'s numbering); 0 marks
    obstacles. Plain Python: as fast as ndimage on these grids, and a process that samples
    grids need not import scipy.ndimage (0.2 s)."""
    size = truth.shape[0]  # grids are square
    free = (truth.ravel() != OBSTACLE).tolist()
    neighbours = _neighbours(size)
    labels = [0] * (size * size)
    count = 0
    for first, is_free in enumerate(free):
        if not is_free or labels[first]:
            continue
        count += 1
        labels[first] = count
        stack = [first]
        while stack:
            for k in neighbours[stack.pop()]:
                if free[k] and not labels[k]:
                    labels[k] = count
                    stack.append(k)
    return np.array(labels, dtype=np.int32).reshape(size, size)


def is_allowable(truth: np.ndarray, component: np.ndarray, cell: tuple[int, int]) -> bool:
    """Start cell empty and some goal in the same free component."""
    if truth[cell] != EMPTY:
        return False
    return bool(np.any(component[truth == GOAL] == component[cell]))


def check_fits(size: int, n_obstacles: int, n_goals: int) -> None:
    """Raise ``ValueError`` unless the obstacles and goals leave a free cell to start in."""
    if n_obstacles + n_goals >= size * size:
        raise ValueError(f"{n_obstacles} obstacles and {n_goals} goals do not fit a "
                         f"{size}x{size} grid with a free start cell")


def sample_state(rng: np.random.Generator, size: int, n_obstacles: int, n_goals: int) -> GridState:
    """Draw ``(x, d)`` uniformly from the allowable space."""
    check_fits(size, n_obstacles, n_goals)
    half = size / 2
    for _ in range(MAX_TRIES):
        chosen = rng.choice(size * size, n_obstacles + n_goals, replace=False)
        truth = np.full(size * size, EMPTY, dtype=np.int8)
        truth[chosen[:n_obstacles]] = OBSTACLE
        truth[chosen[n_obstacles:]] = GOAL
        truth = truth.reshape(size, size)
        position = rng.uniform(-half, half, size=2)
        cell = cell_of(position, size)
        if truth[cell] != EMPTY:  # is_allowable's first test, before the costlier labelling
            continue
        component = free_components(truth)
        if is_allowable(truth, component, cell):
            labels = np.full((size, size), UNEXPLORED, dtype=np.int8)
            blocked = padded_blocked(truth != OBSTACLE)
            return GridState(truth, labels, position, cell, component, blocked)
    raise ValueError(f"no allowable start/environment pair found in {MAX_TRIES} draws "
                     f"(size={size}, obstacles={n_obstacles}, goals={n_goals}): too crowded")
