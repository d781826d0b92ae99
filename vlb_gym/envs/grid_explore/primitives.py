"""The two primitives of the exploration study (paper Sec. V-A): ``sense`` and ``navigate``."""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass
from functools import lru_cache
from types import ModuleType
from typing import Any

import numpy as np
from gymnasium import spaces

from vlb_gym.core.primitive import ControllerFailure, MotionPrimitive

from . import planner
from .types import GOAL, OBSTACLE, GridState

Cell = tuple[int, int]


@lru_cache(maxsize=4096)
def sensed_cells(size: int, cell: Cell) -> tuple[np.ndarray, np.ndarray]:
    """Index arrays of ``cell`` and its in-grid 4-neighbours."""
    i, j = cell
    cand = [(i, j), (i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)]
    keep = [(a, b) for a, b in cand if 0 <= a < size and 0 <= b < size]
    return np.array([a for a, _ in keep]), np.array([b for _, b in keep])


@lru_cache(maxsize=1)
def controller() -> ModuleType:
    """The navigate controller's functions: :mod:`.compiled` when Numba is installed (extra
    ``fast``), else the plain :mod:`.planner`; both give the same numbers."""
    try:
        from . import compiled
    except ImportError:
        return planner
    return compiled


def controller_modules() -> tuple[str, ...]:
    """What :func:`controller` imports on first use, without importing it: the compiled module
    (and Numba) where Numba is installed, else scipy.signal for the plain one (what campaigns
    import before their clock starts)."""
    if importlib.util.find_spec("numba") is not None:
        return (f"{__package__}.compiled",)
    return ("scipy.signal",)


def cost_to_go(state: GridState, target: Cell) -> np.ndarray:
    """Cached optimal cost-to-go to ``target`` in the true environment."""
    key = target[0] * state.size + target[1]
    dist = state.distances.get(key)
    if dist is None:
        dist = state.distances[key] = controller().cost_to_go(state.truth != OBSTACLE, target)
    return dist


@dataclass(frozen=True)
class LabelsMatch:
    """R of ``sense``: states whose labels at ``cells`` equal the true ones."""

    cells: tuple[np.ndarray, np.ndarray]

    def violations(self, state: GridState) -> dict[str, str]:
        if (state.labels[self.cells] == state.truth[self.cells]).all():
            return {}
        return {"labels": "the sensed labels differ from the true ones"}


@dataclass(frozen=True)
class InCell:
    """R of ``navigate``: states whose position lies in the square of ``cell``."""

    cell: Cell

    def violations(self, state: GridState) -> dict[str, str]:
        half = state.size / 2
        x, y = state.position.tolist()
        i, j = self.cell
        if i - half <= x < i - half + 1 and j - half <= y < j - half + 1:
            return {}
        return {"cell": f"final position ({x:.2f}, {y:.2f}) outside the target cell {self.cell}"}


class Sense(MotionPrimitive[GridState]):
    """P1: set the labels of the current cell and its 4 neighbours to the true ones."""

    name = "sense"

    def __init__(self, size: int):
        self.param_space = spaces.MultiDiscrete([size, size])
        self.description = ("Label update: the labels of the agent's current cell and its four "
                            "adjacent cells become the true ones. Parameter: the cell the agent "
                            "occupies (the only admissible one).")

    def admissible(self, state: GridState, param: Cell) -> bool:
        return tuple(param) == state.cell

    def admissible_mask(self, state: GridState) -> np.ndarray:
        mask = np.zeros((state.size, state.size), dtype=bool)
        mask[state.cell] = True
        return mask

    def terminal_region(self, state: GridState, param: Cell) -> LabelsMatch:
        return LabelsMatch(sensed_cells(state.size, param))

    def run(self, state: GridState, param: Cell, rng: np.random.Generator) -> dict[str, Any]:
        cells = sensed_cells(state.size, param)
        sensed = state.truth[cells]
        state.labels[cells] = sensed
        state.goal_found = state.goal_found or bool((sensed == GOAL).any())
        return {}


class Navigate(MotionPrimitive[GridState]):
    """P2: steer the agent to a target cell around obstacles (MDP plan + PD tracking)."""

    name = "navigate"

    def __init__(self, size: int, action_noise: float):
        self.param_space = spaces.MultiDiscrete([size, size])
        self.action_noise = action_noise
        self.description = ("Navigation: steers the agent to the target cell while avoiding "
                            "obstacles, with an MDP planner tracked by a PD controller. Parameter: "
                            "the target cell; admissible when it is reachable.")

    def admissible(self, state: GridState, param: Cell) -> bool:
        target = tuple(param)
        return bool(state.component[target] != 0
                    and state.component[target] == state.component[state.cell])

    def admissible_mask(self, state: GridState) -> np.ndarray:
        return state.component == state.component[state.cell]  # the agent's cell is free

    def terminal_region(self, state: GridState, param: Cell) -> InCell:
        return InCell(tuple(param))

    def run(self, state: GridState, param: Cell, rng: np.random.Generator) -> dict[str, Any]:
        kernels = controller()
        waypoints = kernels.waypoints(cost_to_go(state, tuple(param)), state.cell)
        noise = None
        if self.action_noise > 0:
            shape = (kernels.steps(state.position, waypoints), 2)
            noise = rng.normal(0.0, planner.DT * self.action_noise, size=shape)
        trajectory, hit = kernels.rollout(state.position, waypoints, noise, state.blocked)
        if hit < 0:
            state.trail.append(trajectory)
            state.position = trajectory[-1]
            return {}
        state.trail.append(trajectory[:hit])
        if hit:
            state.position = trajectory[hit - 1]
        point = trajectory[hit]
        if np.all(np.abs(point) < state.size / 2):
            raise ControllerFailure(f"collided with an obstacle in cell {state.cell_of(point)}")
        raise ControllerFailure("collided with the grid's edge")
