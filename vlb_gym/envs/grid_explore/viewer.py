"""Top-down RGB pictures of the exploration world, drawn with numpy (no pygame).

As in the paper's Fig. 3: obstacles black, goals green, the explored region gold, the start cell
outlined in blue, the agent a blue disc; the agent's trajectories are drawn as a thin blue trail.
"""

from __future__ import annotations

import numpy as np

from .types import GridState, Label

CELL_PX = 32
WHITE = (255, 255, 255)
GRID = (200, 200, 200)
OBSTACLE = (20, 20, 20)
GOAL = (40, 170, 70)
EXPLORED = (240, 200, 80)
EXPLORED_GOAL = (30, 130, 50)
AGENT = (30, 90, 220)
TRAIL = (90, 140, 240)


def render_rgb(state: GridState, cell_px: int = CELL_PX) -> np.ndarray:
    """An ``(size * cell_px, size * cell_px, 3)`` uint8 image; image rows run from +y down to -y."""
    size = state.size
    explored = state.labels != Label.UNEXPLORED
    colour = np.empty((size, size, 3), dtype=np.uint8)
    colour[:] = WHITE
    colour[explored] = EXPLORED
    colour[state.truth == Label.GOAL] = GOAL
    colour[explored & (state.truth == Label.GOAL)] = EXPLORED_GOAL
    colour[state.truth == Label.OBSTACLE] = OBSTACLE
    # cells are indexed [i, j] = [x, y]; the image wants [row, col] = [-y, x]
    image = np.repeat(np.repeat(colour.transpose(1, 0, 2)[::-1], cell_px, 0), cell_px, 1)
    image[::cell_px, :] = GRID
    image[:, ::cell_px] = GRID

    def to_px(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        cols = np.clip(((points[:, 0] + size / 2) * cell_px).astype(int), 0, size * cell_px - 1)
        rows = np.clip(((size / 2 - points[:, 1]) * cell_px).astype(int), 0, size * cell_px - 1)
        return rows, cols

    for trajectory in state.trail:
        if len(trajectory):
            image[to_px(trajectory)] = TRAIL
    i, j = state.start_cell
    top, left = (size - 1 - j) * cell_px, i * cell_px
    for offset in (1, 2):
        image[top + offset, left:left + cell_px] = AGENT
        image[top + cell_px - offset, left:left + cell_px] = AGENT
        image[top:top + cell_px, left + offset] = AGENT
        image[top:top + cell_px, left + cell_px - offset] = AGENT
    (row,), (col,) = to_px(state.position[None])
    rr, cc = np.ogrid[:size * cell_px, :size * cell_px]
    image[(rr - row) ** 2 + (cc - col) ** 2 <= (cell_px * 0.3) ** 2] = AGENT
    return image
