"""``VLB-GridExplore-v0``: the paper's 10x10 exploration study (Sec. V-A)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from vlb_gym.core.env import FrameKey, PrimitiveEnv
from vlb_gym.core.primitive import Outcome
from vlb_gym.core.search_space import Memory, Parameter, SearchSpace, Witness
from vlb_gym.envs import arguments

from . import viewer
from .generator import check_fits, sample_state
from .helpers import Cell, GridHelpers
from .judge import GridJudge
from .primitives import Navigate, Sense, controller_modules
from .types import GridState, Label
from .viewer import render_rgb

MAX_SIZE = 64  # bounds memory and planning time: size**2 cells, labels and actions
MAX_ACTION_NOISE = 100.0  # cells/s: 5 cells per 20 Hz step, far past any useful disturbance
STAY_PUT = 12  # a least behavior that stays put is tried done up to this many times (the counts
#                a request names: five round trips are ten moves)


class GridExploreEnv(PrimitiveEnv[GridState]):
    """A single-integrator agent explores a grid with obstacles for goals, one primitive per step.

    ## Description
    The world is a ``size x size`` grid (default 10x10) on ``[-size/2, size/2]^2``; cell ``(i, j)``
    covers ``[-5 + i, -4 + i) x [-5 + j, -4 + j)`` for the default size, so ``i`` indexes x and
    ``j`` indexes y. This matches the paper's example "position [-4.5, -3.5] lies in cell (0, 1)";
    its other example, "R((2, 2)) = [-2, -1]^2", is off by one under any consistent indexing and
    is not followed. The environment ``d`` places ``n_obstacles`` obstacles (default 30) and
    ``n_goals`` goals (default 3) on distinct cells. The agent's state ``x`` is its position and
    its label for every cell, one of {empty, obstacle, unexplored, goal}.

    Two motion primitives act on it (Definition 1 of the paper):

    * ``sense`` (P1): the labels of the agent's cell and its 4 neighbours become the true ones.
      Admissible parameter: the agent's current cell. Certificate: those labels are now correct.
    * ``navigate`` (P2): an MDP planner (optimal cost-to-go on the grid) tracked by a PD controller
      on the single-integrator dynamics, simulated at 20 Hz. Admissible parameters: cells reachable
      in the true environment. Certificate: the final position lies in the target cell. Touching
      an obstacle or the grid's edge stops the agent there and fails the certificate.

    ## Action Space
    ``MultiDiscrete([2, size, size])``: ``[primitive, i, j]`` with primitive 0 = ``sense``,
    1 = ``navigate`` and ``(i, j)`` its parameter cell. An action outside this space raises
    ``ValueError``; an in-space parameter that is not admissible runs nothing and records a false
    certificate.

    ## Observation Space
    ``Dict`` with ``"position"``: ``Box(-size/2, size/2, (2,), float64)``, the agent's position, and
    ``"labels"``: ``MultiDiscrete([4] * size**2)``, the agent's labels in flat order ``i * size + j``
    (0 empty, 1 obstacle, 2 unexplored, 3 goal).

    ## Rewards
    0: the environment exists to verify behaviors, whose robustness rho_B is computed by
    :class:`vlb_gym.RobustnessWrapper` from the certificates, not from rewards. The RL tasks
    on this env are ids of their own (``VLB-GridExplore-FindGoal-v0``,
    ``VLB-GridExplore-FindGoalAndOscillate-v0``; :mod:`vlb_gym.baselines.tasks`).

    ## Starting State
    ``(x, d)`` drawn uniformly from the allowable space: obstacles and goals a uniform random
    subset of cells, the position uniform on the grid, accepted when its cell is empty (no
    obstacle, no goal) and some goal is reachable from it. All labels start unexplored.

    ## Episode End
    The environment never terminates by itself: a behavior decides when it has finished.
    Episodes are truncated after
    ``max_episode_steps`` primitives (500 when made with ``gym.make``).

    ## Info
    Every step: ``primitive``, ``param``, ``admissible``, ``certificate`` (and ``failure`` and
    ``reason`` when the certificate failed: see :class:`vlb_gym.core.Failure`), plus ``cell`` (the agent's cell) and ``goal_found``. ``reset`` returns
    ``start_cell``.

    ## Arguments
    ``gym.make("VLB-GridExplore-v0", render_mode=None, size=10, n_obstacles=30, n_goals=3,
    action_noise=0.0)``: ``size`` an integer from 2 to 64, the counts integers that leave a free
    start cell, ``action_noise`` a number from 0 to 100; otherwise ``TypeError`` or
    ``ValueError``. ``action_noise``
    (cells/s) is the standard deviation of a Gaussian velocity disturbance on the integrator: the
    paper's non-deterministic case (Corollary 1).
    ``render_mode="rgb_array"`` renders a top-down picture (see :mod:`.viewer`).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 4}
    env_id = "VLB-GridExplore-v0"
    @property
    def preload(self) -> tuple[str, ...]:  # type: ignore[override]
        """Numba and the compiled navigate (extra ``fast``), else scipy.signal."""
        return controller_modules()

    def __init__(self, render_mode: str | None = None, size: int = 10, n_obstacles: int = 30,
                 n_goals: int = 3, action_noise: float = 0.0):
        size = arguments.integer("size", size, 2, MAX_SIZE)
        n_obstacles = arguments.integer("n_obstacles", n_obstacles, 0)
        n_goals = arguments.integer("n_goals", n_goals, 1)
        check_fits(size, n_obstacles, n_goals)
        self.size, self.n_obstacles, self.n_goals = size, n_obstacles, n_goals
        self.action_noise = arguments.real("action_noise", action_noise, 0.0, MAX_ACTION_NOISE)
        half = size / 2
        observations = spaces.Dict({
            "position": spaces.Box(-half, half, shape=(2,), dtype=np.float64),
            "labels": spaces.MultiDiscrete(np.full(size * size, len(Label))),
        })
        super().__init__([Sense(size), Navigate(size, self.action_noise)], observations,
                         render_mode)

    def sample_state(self) -> GridState:
        return sample_state(self.np_random, self.size, self.n_obstacles, self.n_goals)

    def observation(self) -> dict[str, np.ndarray]:
        state = self.state
        return {"position": state.position.copy(),
                "labels": state.labels.ravel().astype(np.int64)}

    def make_helpers(self) -> GridHelpers:
        """Fresh helpers (E1-E3) reading this environment's observations."""
        return GridHelpers(self.size)

    def make_judge(self) -> GridJudge:
        """Fresh outcome helpers for promises (the true map and the steps a behavior ran)."""
        return GridJudge(self.size)

    def search_space(self) -> SearchSpace:
        """Cells are the one type; ``sense`` takes the agent's cell, ``navigate`` any cell;
        behaviors remember where they began (``home``), where they have stood (``path``),
        where they sensed from (``sensed_from``: what a promise's ``sensed()`` reads, exact
        after moves that sense nothing), what they did once a goal was known (``since_goal``,
        ``after_goal``: a promise's ``steps_after_goal()`` and ``moves_after_goal()``), the
        primitives they ran (``ran``: a promise's ``primitives()``) and a cell they chose to
        (``mark``)."""
        return SearchSpace(
            types={"cell": Cell},
            parameters=(Parameter("sense", fixed=("current_cell()",)),
                        Parameter("navigate", "cell", idle=("current_cell()",),
                                  feasible="is_free({0})")),
            memory=(Memory("home", "cell", "current_cell()",
                           description="the cell the behavior began in"),
                    Memory("path", "list[cell]", "[current_cell()]",
                           (("navigate", "path + [PARAM]"),),
                           "the cells the agent has stood in: the start, then each cell it "
                           "moved to"),
                    Memory("sensed_from", "list[cell]", "[]",
                           (("sense", "sensed_from + [PARAM]"),),
                           "the cells the agent sensed from, in order"),
                    Memory("since_goal", "int", "0",
                           tuple((name, "since_goal + 1 if goal_found() else 0")
                                 for name in ("sense", "navigate")),
                           "how many primitives ran with a goal already known (those after the "
                           "one that showed the first goal)"),
                    Memory("after_goal", "list[cell]", "[]",
                           (("navigate", "after_goal + [PARAM] if goal_found() else after_goal"),),
                           "the cells moved to with a goal already known, in order"),
                    Memory("ran", "list[str]", "[]",
                           (("sense", "ran + ['sense']"), ("navigate", "ran + ['navigate']")),
                           "the names of the primitives run, in order"),
                    Memory("mark", "cell", "current_cell()",
                           description="a cell the behavior chose to remember (at first, the "
                           "start)", settable=True)),
            witnesses=(Witness("stop at once, doing nothing"),
                       Witness("sense once where it stands and stop",
                               (("sense", "current_cell()"),), STAY_PUT,
                               "sense {times} times where it stands and stop"),
                       Witness("go to the cell where it stands (its start) and stop",
                               (("navigate", "current_cell()"),), STAY_PUT,
                               "go to the cell where it stands (its start) {times} times and "
                               "stop")),
            beliefs={"start_cell": "home", "final_cell": "TARGET", "moves": "path[1:]",
                     "sensed": "sensed_from", "primitives": "ran",
                     "steps_after_goal": "since_goal if goal_found() else -1",
                     "moves_after_goal": "after_goal",
                     "is_goal": "label({0}) == 'goal'", "is_obstacle": "label({0}) == 'obstacle'",
                     "goal_found": "goal_found()", "neighbours": "adjacent({0})",
                     "known_cells": "explored()",
                     "known_obstacles": "[k for k in explored() if label(k) == 'obstacle']",
                     "reachable_cells": "[k for k in explored() if is_free(k)]",
                     "reachable_goals": "[k for k in explored() if label(k) == 'goal']",
                     "explored_all": "len(frontier_cells()) == 0"},
            common=("current_cell", "explored", "frontier_cells", "goal_found", "label",
                    "home", "path", "sensed_from", "mark"),
            here=("cell", "current_cell()"),
            synonyms={"above": "up", "below": "down", "north": "up", "south": "down",
                      "east": "right", "west": "left"}, max_steps=4 * self.size * self.size // 3)

    def save(self) -> tuple[GridState, dict[str, Any]]:
        """A copy of what primitives change (labels, position, what was found, the trail so
        far); the map and its derived arrays, which never change in an episode, are shared."""
        return self._copy(self.state), dict(self.np_random.bit_generator.state)

    def load(self, saved: tuple[GridState, dict[str, Any]]) -> None:
        state, generator = saved
        self._state = self._copy(state)
        self.np_random.bit_generator.state = generator

    @staticmethod
    def _copy(state: GridState) -> GridState:
        return replace(state, labels=state.labels.copy(), position=state.position.copy(),
                       trail=list(state.trail))

    def reset_info(self) -> dict[str, Any]:
        return {"start_cell": self.state.start_cell}

    def step_info(self, outcome: Outcome) -> dict[str, Any]:
        state = self.state
        return {"cell": state.cell, "goal_found": state.goal_found}

    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        return render_rgb(self.state, failed_cell=self._failed_cell())

    def _failed_cell(self) -> tuple[int, int] | None:
        """The cell the last step was sent to, if its certificate failed."""
        outcome = self.last_outcome
        if outcome is None or outcome.certificate:
            return None
        try:  # a behavior may have sent anything: an inadmissible one is not a cell
            i, j = (int(k) for k in outcome.param)
        except (TypeError, ValueError, OverflowError):
            return None
        return i, j

    def frame_key(self) -> FrameKey:
        return FrameKey((("obstacle", viewer.OBSTACLE), ("goal, not yet sensed", viewer.GOAL),
                         ("explored (labelled by sense)", viewer.EXPLORED),
                         ("goal, sensed", viewer.EXPLORED_GOAL),
                         ("agent; outline: start cell", viewer.AGENT),
                         ("trail of the agent's moves", viewer.TRAIL),
                         ("cell a failed step was sent to", viewer.FAILED)), self.size)

    def sampling_distribution(self) -> str:
        half = self.size / 2
        dynamics = ("deterministic dynamics (Theorem 2)" if self.action_noise == 0 else
                    f"Gaussian velocity disturbance sigma={self.action_noise:g} cells/s "
                    "(non-deterministic, Corollary 1)")
        return (f"uniform over the allowable space of a {self.size}x{self.size} grid: "
                f"{self.n_obstacles} obstacles and {self.n_goals} goals on distinct uniformly "
                f"random cells, start position uniform on [{-half:g}, {half:g}]^2, accepted when "
                f"its cell is empty and some goal is reachable from it; {dynamics}")
