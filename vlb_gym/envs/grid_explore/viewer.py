"""Top-down RGB pictures of the exploration world, drawn with numpy (no pygame).

As in the paper's Fig. 3: obstacles black, goals green, the explored region gold, the start cell
outlined in blue, the agent a blue disc; the agent's trajectories are drawn as a thin blue trail.
The cell a failed step was sent to (a navigate's goal or a sense's cell) is outlined and crossed
in red.
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
FAILED = (220, 30, 30)


def render_rgb(state: GridState, cell_px: int = CELL_PX,
               failed_cell: tuple[int, int] | None = None) -> np.ndarray:
    """An ``(size * cell_px, size * cell_px, 3)`` uint8 image; image rows run from +y down to -y.
    ``failed_cell``: the cell a failed step was sent to, outlined and crossed in red."""
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
    _outline(image, state.start_cell, size, cell_px, AGENT)
    (row,), (col,) = to_px(state.position[None])
    rr, cc = np.ogrid[:size * cell_px, :size * cell_px]
    image[(rr - row) ** 2 + (cc - col) ** 2 <= (cell_px * 0.3) ** 2] = AGENT
    if failed_cell is not None and all(0 <= k < size for k in failed_cell):
        top, left = _outline(image, failed_cell, size, cell_px, FAILED, width=3)
        diagonal = np.arange(cell_px // 4, cell_px - cell_px // 4)
        for thick in (0, 1):
            image[top + diagonal, left + diagonal + thick] = FAILED
            image[top + diagonal, left + cell_px - 1 - diagonal - thick] = FAILED
    return image


def _outline(image: np.ndarray, cell: tuple[int, int], size: int, cell_px: int,
             colour: tuple[int, int, int], width: int = 2) -> tuple[int, int]:
    """Outline ``cell`` in ``colour``, ``width`` pixels inside its edge; its top-left pixel."""
    i, j = cell
    top, left = (size - 1 - j) * cell_px, i * cell_px
    for offset in range(1, width + 1):
        image[top + offset, left:left + cell_px] = colour
        image[top + cell_px - offset, left:left + cell_px] = colour
        image[top:top + cell_px, left + offset] = colour
        image[top:top + cell_px, left + cell_px - offset] = colour
    return top, left
