"""``VLB-Integrator-v0``, the paper's introductory example: a single integrator moves between
adjacent cells of an obstacle-free grid. ``docs/new_env.md`` builds this file piece by piece;
importing it registers the env."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from vlb_gym.core.env import PrimitiveEnv
from vlb_gym.core.helpers import Helpers, helper
from vlb_gym.core.primitive import MotionPrimitive
from vlb_gym.envs import arguments

Cell = tuple[int, int]
GAIN, DT, EULER_STEPS = 5.0, 0.1, 6  # u = GAIN * (centre - x); each Euler step halves the error


def cell_of(position: np.ndarray, size: int) -> Cell:
    """The cell (i, j) containing ``position``: cell (i, j) covers [i, i+1) x [j, j+1)."""
    i, j = np.clip(np.floor(position), 0, size - 1).astype(int).tolist()
    return (i, j)


@dataclass
class IntegratorState:
    """The joint state (x, d): the agent's position x and the goal cell d."""

    size: int
    position: np.ndarray
    goal: Cell


@dataclass(frozen=True)
class InCell:
    """R(xi, d) of ``move``: the states whose position lies in ``cell``."""

    cell: Cell

    def violations(self, state: IntegratorState) -> dict[str, str]:
        here = cell_of(state.position, state.size)
        return {} if here == self.cell else {"cell": f"ended in {here}, not in {self.cell}"}


class Move(MotionPrimitive[IntegratorState]):
    """P = (Xi, A, U, R): Xi every cell, A the cells 4-adjacent to the agent's, U integrates
    x' = u, u = GAIN (c - x), towards the target's centre c, R the target cell."""

    name = "move"
    description = ("Move to a cell 4-adjacent to the agent's cell (left, right, down or up). "
                   "Parameter: the target cell (i, j).")

    def __init__(self, size: int):
        self.param_space = spaces.MultiDiscrete([size, size])  # Xi: every cell

    def inadmissible_reason(self, state: IntegratorState, param: Cell) -> str | None:
        (i, j), (a, b) = cell_of(state.position, state.size), param
        if abs(a - i) + abs(b - j) == 1:
            return None
        return f"cell {tuple(param)} is not 4-adjacent to the agent's cell {(i, j)}"

    def admissible(self, state: IntegratorState, param: Cell) -> bool:
        return self.inadmissible_reason(state, param) is None

    def terminal_region(self, state: IntegratorState, param: Cell) -> InCell:
        return InCell(tuple(param))

    def run(self, state: IntegratorState, param: Cell, rng: np.random.Generator) -> dict:
        centre = np.asarray(param, dtype=float) + 0.5
        for _ in range(EULER_STEPS):
            state.position = state.position + DT * GAIN * (centre - state.position)
        return {"error": float(np.abs(centre - state.position).max())}


class IntegratorHelpers(Helpers):
    """Helpers for ``VLB-Integrator-v0`` observations.

    A Cell is a tuple (i, j) of ints, 0 <= i, j < size (5 by default); (i + 1, j) is the cell
    right of (i, j), (i, j + 1) the one above it. The ``move`` primitive takes a Cell.
    """

    def __init__(self, size: int):
        self.size = size
        self._here, self._goal = (0, 0), (0, 0)  # the agent's cell and the goal cell

    def bind(self, observation: dict[str, np.ndarray]) -> None:
        self._here = cell_of(observation["position"], self.size)
        self._goal = (int(observation["goal"][0]), int(observation["goal"][1]))

    def _cell(self, value: Any, fn: str) -> Cell:
        if type(value) is tuple and len(value) == 2 and all(
                type(v) is int and 0 <= v < self.size for v in value):
            return value
        raise ValueError(f"{fn}(): {value!r} is not a cell of the {self.size}x{self.size} grid")

    @helper
    def current_cell(self) -> Cell:
        """The cell the agent occupies."""
        return self._here

    @helper
    def goal_cell(self) -> Cell:
        """The goal cell."""
        return self._goal

    @helper
    def adjacent(self, cell: Cell) -> list[Cell]:
        """The cells 4-adjacent to ``cell``, inside the grid."""
        i, j = self._cell(cell, "adjacent")
        near = ((i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1))
        return [(a, b) for a, b in near if 0 <= a < self.size and 0 <= b < self.size]

    @helper
    def distance(self, a: Cell, b: Cell) -> int:
        """The number of moves from cell ``a`` to cell ``b`` (Manhattan distance)."""
        (i, j), (k, m) = self._cell(a, "distance"), self._cell(b, "distance")
        return abs(i - k) + abs(j - m)


class IntegratorEnv(PrimitiveEnv[IntegratorState]):
    """A single-integrator agent moves between adjacent cells of an obstacle-free grid.

    ## Description
    A ``size x size`` grid (default 5x5) on ``[0, size]^2``, cell ``(i, j)`` covering
    ``[i, i+1) x [j, j+1)``. ``x`` is the agent's position, ``d`` a goal cell (the paper has no
    ``d``; a goal gives behaviors something to reach). One primitive, :class:`Move`: to a cell
    4-adjacent to the agent's (not its own), certified when the agent ends in that cell.

    ## Action Space
    ``MultiDiscrete([size, size])``: the target cell ``(i, j)`` of ``move``.

    ## Observation Space
    ``Dict`` with ``"position"``: ``Box(0, size, (2,), float64)`` and ``"goal"``:
    ``MultiDiscrete([size, size])``, the goal cell.

    ## Rewards
    0: behaviors are scored by rho_B (:class:`vlb_gym.RobustnessWrapper`), not by rewards.

    ## Starting State
    The position uniform on ``[0, size]^2``; the goal uniform over the other cells.

    ## Episode End
    Never terminates by itself (the behavior decides); truncated after 50 primitives.

    ## Info
    ``primitive``, ``param``, ``admissible``, ``certificate`` (and ``reason`` when it failed),
    and ``error``, the final distance to the cell's centre (max-norm), when ``move`` ran.

    ## Arguments
    ``size=5``: an integer from 2 to 20 (else ``TypeError`` or ``ValueError``). No render modes.
    """

    env_id = "VLB-Integrator-v0"

    def __init__(self, render_mode: str | None = None, size: int = 5):
        self.size = arguments.integer("size", size, 2, 20)
        position = spaces.Box(0.0, self.size, shape=(2,), dtype=np.float64)
        goal = spaces.MultiDiscrete([self.size, self.size])
        super().__init__([Move(self.size)], spaces.Dict(position=position, goal=goal), render_mode)

    def sample_state(self) -> IntegratorState:
        position = self.np_random.uniform(0.0, self.size, size=2)
        start = cell_of(position, self.size)
        others = [cell for cell in np.ndindex(self.size, self.size) if cell != start]
        goal = others[self.np_random.integers(len(others))]
        return IntegratorState(self.size, position, goal)

    def observation(self) -> dict[str, np.ndarray]:
        return {"position": self.state.position.copy(), "goal": np.array(self.state.goal)}

    def make_helpers(self) -> IntegratorHelpers:
        return IntegratorHelpers(self.size)

    def sampling_distribution(self) -> str:
        n = self.size
        return (f"position uniform on [0, {n}]^2, goal cell uniform over the other {n * n - 1} "
                f"cells of the {n}x{n} grid; deterministic dynamics")


if "VLB-Integrator-v0" not in gym.registry:
    gym.register(id="VLB-Integrator-v0", entry_point=f"{__name__}:IntegratorEnv",
                 max_episode_steps=50)
