"""``VLB-GridExplore-v0``: the paper's 10x10 exploration study (Sec. V-A)."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from vlb_gym.core.primitive import MotionPrimitive, execute
from vlb_gym.envs import arguments

from .generator import check_fits, sample_state
from .helpers import GridHelpers
from .primitives import Navigate, Sense
from .tasks import LEGS, TASKS, TaskTracker
from .types import GOAL, GridState, Label
from .viewer import render_rgb

MAX_SIZE = 64  # bounds memory and planning time: size**2 cells, labels and actions
MAX_ACTION_NOISE = 100.0  # cells/s: 5 cells per 20 Hz step, far past any useful disturbance


class GridExploreEnv(gym.Env):
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
    0 without a ``task``: the environment exists to verify behaviors, whose robustness rho_B is
    computed by :class:`vlb_gym.RobustnessWrapper` from the certificates, not from rewards. With
    ``task="find_goal"`` or ``"find_goal_and_oscillate"`` a task-aligned reward for RL (see
    :mod:`.tasks`); it never changes rho_B.

    ## Starting State
    ``(x, d)`` drawn uniformly from the allowable space: obstacles and goals a uniform random
    subset of cells, the position uniform on the grid, accepted when its cell is empty (no
    obstacle, no goal) and some goal is reachable from it. All labels start unexplored.

    ## Episode End
    Without a task the environment never terminates by itself: a behavior decides when it has
    finished. With a task it terminates when the task is done. Episodes are truncated after
    ``max_episode_steps`` primitives (500 when made with ``gym.make``).

    ## Info
    Every step: ``primitive``, ``param``, ``admissible``, ``certificate`` (and ``reason`` when the
    certificate failed), plus ``cell`` (the agent's cell) and ``goal_found``. ``reset`` returns
    ``start_cell``.

    ## Arguments
    ``gym.make("VLB-GridExplore-v0", render_mode=None, size=10, n_obstacles=30, n_goals=3,
    action_noise=0.0, task=None)``: ``size`` an integer from 2 to 64, the counts integers that
    leave a free start cell, ``action_noise`` a number from 0 to 100; otherwise ``TypeError`` or
    ``ValueError``. With ``task="find_goal_and_oscillate"`` the observation also holds ``start``
    (the start cell) and ``legs`` (legs completed). ``action_noise`` (cells/s) is the standard
    deviation of a Gaussian velocity disturbance on the integrator: the paper's non-deterministic
    case (Corollary 1).
    ``render_mode="rgb_array"`` renders a top-down picture (see :mod:`.viewer`).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 4}
    env_id = "VLB-GridExplore-v0"

    def __init__(self, render_mode: str | None = None, size: int = 10, n_obstacles: int = 30,
                 n_goals: int = 3, action_noise: float = 0.0, task: str | None = None):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode={render_mode!r} is not supported; "
                             f"use one of {self.metadata['render_modes']} or None")
        size = arguments.integer("size", size, 2, MAX_SIZE)
        n_obstacles = arguments.integer("n_obstacles", n_obstacles, 0)
        n_goals = arguments.integer("n_goals", n_goals, 1)
        check_fits(size, n_obstacles, n_goals)
        action_noise = arguments.real("action_noise", action_noise, 0.0, MAX_ACTION_NOISE)
        if task is not None and task not in TASKS:
            raise ValueError(f"task={task!r} is not one of {TASKS} (or None)")
        self.task = task
        self._tracker: TaskTracker | None = None
        self.render_mode = render_mode
        self.size, self.n_obstacles, self.n_goals = size, n_obstacles, n_goals
        self.action_noise = action_noise
        half = size / 2
        self.action_space = spaces.MultiDiscrete([2, size, size])
        observations = {
            "position": spaces.Box(-half, half, shape=(2,), dtype=np.float64),
            "labels": spaces.MultiDiscrete(np.full(size * size, len(Label))),
        }
        if task == "find_goal_and_oscillate":  # what a memoryless policy needs to oscillate
            observations["start"] = spaces.MultiDiscrete([size, size])
            observations["legs"] = spaces.Discrete(LEGS + 1)
        self.observation_space = spaces.Dict(observations)
        sense, navigate = Sense(size), Navigate(size, self.action_noise)
        self.primitives: dict[str, MotionPrimitive[GridState]] = {"sense": sense,
                                                                  "navigate": navigate}
        self._by_index = (sense, navigate)
        self._state: GridState | None = None

    # -- the behavior interface -------------------------------------------------------------
    def make_helpers(self) -> GridHelpers:
        """Fresh helpers (E1-E3) reading this environment's observations."""
        return GridHelpers(self.size)

    def encode_action(self, primitive: str, param: Any) -> np.ndarray:
        """The action running ``primitive`` with parameter cell ``param``."""
        kind = ("sense", "navigate").index(primitive)
        try:
            i, j = param
        except (TypeError, ValueError):
            raise ValueError(f"{primitive} parameter {param!r} is not a cell (i, j)") from None
        if not (isinstance(i, (int, np.integer)) and isinstance(j, (int, np.integer))
                and 0 <= i < self.size and 0 <= j < self.size):
            raise ValueError(f"{primitive} parameter {param!r} is not a cell of the "
                             f"{self.size}x{self.size} grid")
        return np.array([kind, i, j], dtype=np.int64)

    # -- gymnasium API -------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        self._state = sample_state(self.np_random, self.size, self.n_obstacles, self.n_goals)
        self._tracker = TaskTracker(self.task) if self.task else None
        return self._observation(), {"start_cell": self._state.start_cell}

    def step(self, action: Any):
        if self._state is None:
            raise RuntimeError("call reset() before step()")
        array = np.asarray(action)
        if array.shape != (3,) or array.dtype.kind not in "iu":
            raise ValueError(f"action {action!r} is not in the action space {self.action_space}: "
                             "expected an integer array [primitive (0 sense, 1 navigate), i, j]")
        kind, i, j = array.tolist()
        if not (0 <= kind < 2 and 0 <= i < self.size and 0 <= j < self.size):
            raise ValueError(f"action {action!r} is not in the action space {self.action_space}: "
                             f"primitive must be 0 (sense) or 1 (navigate) and 0 <= i, j < "
                             f"{self.size}")
        outcome = execute(self._by_index[kind], self._state, (i, j), self.np_random)
        info = outcome.as_info()
        info["cell"] = self._state.cell
        info["goal_found"] = bool(np.any(self._state.labels == GOAL))
        reward, terminated = 0.0, False
        if self._tracker is not None:
            reward, terminated = self._tracker.update(self._state, info)
        return self._observation(), reward, terminated, False, info

    def action_masks(self) -> np.ndarray:
        """Admissible actions of the flattened action space ``kind * size**2 + i * size + j``
        (judged with the true map, as admissibility is): for sb3-contrib's MaskablePPO."""
        state = self.state
        sense = np.zeros(self.size * self.size, dtype=bool)
        sense[state.cell[0] * self.size + state.cell[1]] = True
        navigate = (state.component == state.component[state.cell]).ravel()
        return np.concatenate([sense, navigate])

    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        if self._state is None:
            raise RuntimeError("call reset() before render()")
        return render_rgb(self._state)

    def sampling_distribution(self) -> str:
        """The distribution reset() samples from, in words: what a guarantee holds for."""
        half = self.size / 2
        dynamics = ("deterministic dynamics (Theorem 2)" if self.action_noise == 0 else
                    f"Gaussian velocity disturbance sigma={self.action_noise:g} cells/s "
                    "(non-deterministic, Corollary 1)")
        return (f"uniform over the allowable space of a {self.size}x{self.size} grid: "
                f"{self.n_obstacles} obstacles and {self.n_goals} goals on distinct uniformly "
                f"random cells, start position uniform on [{-half:g}, {half:g}]^2, accepted when "
                f"its cell is empty and some goal is reachable from it; {dynamics}"
                + (f"; task {self.task} (finished = the task terminated)" if self.task else ""))

    @property
    def state(self) -> GridState:
        """The joint state (x, d); for analysis and tests, not for policies."""
        if self._state is None:
            raise RuntimeError("call reset() first")
        return self._state

    def _observation(self) -> dict[str, np.ndarray]:
        obs = {"position": self._state.position.copy(),
               "labels": self._state.labels.ravel().astype(np.int64)}
        if self.task == "find_goal_and_oscillate":
            obs["start"] = np.array(self._state.start_cell, dtype=np.int64)
            obs["legs"] = self._tracker.legs
        return obs
