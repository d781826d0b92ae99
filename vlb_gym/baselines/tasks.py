"""Tasks for RL on the exploration grid: :class:`GridTask` adds rewards, termination and the
observation keys a memoryless policy needs. Each task is an env id of its own
(``gym.make("VLB-GridExplore-FindGoal-v0")``, see ``vlb_gym.RL_TASKS``); ``VLB-GridExplore-v0``
itself has no task.

Rewards never enter rho_B: the robustness wrapper scores certificates and finishing only. With a
task the episode *terminates* when the task is done, and that is what "finished" means for a
policy that has no graph:

* ``find_goal``: terminates on the step that first labels a goal cell (+1);
* ``find_goal_and_oscillate``: after a goal is found (+1), each navigation that arrives at a goal
  cell (when heading to a goal) or at the start cell (when heading home) completes a leg (+0.5);
  terminates after 10 legs, i.e. 5 round trips ending at the start.

Every step costs 0.01 and every failed certificate 0.1 more. With ``find_goal_and_oscillate`` the
observation also holds ``start`` (the start cell) and ``legs`` (legs completed).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from vlb_gym.envs.grid_explore import GridExploreEnv
from vlb_gym.envs.grid_explore.types import GOAL, UNEXPLORED, GridState

TASKS = ("find_goal", "find_goal_and_oscillate")
STEP_COST = 0.01
FAILED_CERTIFICATE = 0.1
GOAL_FOUND = 1.0
LEG = 0.5
LEGS = 10


@dataclass
class TaskTracker:
    """Progress of one episode on ``task``; :meth:`update` gives (reward, terminated)."""

    task: str
    goal_found: bool = False
    legs: int = 0

    def update(self, state: GridState, info: dict[str, Any]) -> tuple[float, bool]:
        reward = -STEP_COST - (0.0 if info["certificate"] else FAILED_CERTIFICATE)
        if not self.goal_found:
            if info["goal_found"]:  # the env's step already looked for goal labels
                self.goal_found = True
                return reward + GOAL_FOUND, self.task == "find_goal"
            return reward, False
        if self.task == "find_goal_and_oscillate" and info["primitive"] == "navigate" \
                and info["certificate"]:
            heading_home = self.legs % 2 == 1
            arrived = state.cell == state.start_cell if heading_home \
                else state.truth[state.cell] == GOAL
            if arrived:
                self.legs += 1
                reward += LEG
        return reward, self.legs >= LEGS


class GridTask(gym.Wrapper):
    """A task on ``VLB-GridExplore-v0``: the reward and termination of :class:`TaskTracker`, and
    for ``find_goal_and_oscillate`` the ``start`` and ``legs`` observation keys."""

    def __init__(self, env: gym.Env, task: str):
        if task not in TASKS:
            raise ValueError(f"task={task!r} is not one of {TASKS}")
        super().__init__(env)
        self.task = task
        self.tracker = TaskTracker(task)
        if task == "find_goal_and_oscillate":
            size = env.unwrapped.size
            self.observation_space = spaces.Dict({**env.observation_space.spaces,
                                                  "start": spaces.MultiDiscrete([size, size]),
                                                  "legs": spaces.Discrete(LEGS + 1)})

    def reset(self, **kwargs: Any):
        obs, info = self.env.reset(**kwargs)
        self.tracker = TaskTracker(self.task)
        return self._observation(obs), info

    def step(self, action: Any):
        obs, _, terminated, truncated, info = self.env.step(action)
        reward, done = self.tracker.update(self.env.unwrapped.state, info)
        return self._observation(obs), reward, terminated or done, truncated, info

    def _observation(self, obs: dict[str, np.ndarray]) -> dict[str, Any]:
        if self.task != "find_goal_and_oscillate":
            return obs
        start = np.array(self.env.unwrapped.state.start_cell, dtype=np.int64)
        return {**obs, "start": start, "legs": self.tracker.legs}


def find_goal(**kwargs: Any) -> gym.Env:
    """The entry point of ``VLB-GridExplore-FindGoal-v0``: the grid (``kwargs`` as
    :class:`GridExploreEnv` takes them) with the ``find_goal`` task."""
    return GridTask(GridExploreEnv(**kwargs), "find_goal")


def find_goal_and_oscillate(**kwargs: Any) -> gym.Env:
    """The entry point of ``VLB-GridExplore-FindGoalAndOscillate-v0``."""
    return GridTask(GridExploreEnv(**kwargs), "find_goal_and_oscillate")


class ExplorationBonus(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """Reward shaping for training only: ``bonus`` per cell newly labelled by a step (counted
    from the observation's labels), added to the task's reward. It never enters rho_B: the
    verifier builds its own env, without this wrapper, and scores certificates and finishing.
    Over an episode the shaping adds ``bonus`` x (cells known at the end - cells known after
    reset)."""

    def __init__(self, env: gym.Env, bonus: float = 0.02):
        if not (isinstance(bonus, (int, float)) and 0 <= bonus <= 1):
            raise ValueError(f"bonus must be a number in [0, 1], not {bonus!r}")
        gym.utils.RecordConstructorArgs.__init__(self, bonus=bonus)
        super().__init__(env)
        self.bonus = float(bonus)
        self._known = 0

    @staticmethod
    def known(obs: dict[str, Any]) -> int:
        """Cells whose label is not 'unexplored'."""
        return int((np.asarray(obs["labels"]) != UNEXPLORED).sum())

    def reset(self, **kwargs: Any):
        obs, info = self.env.reset(**kwargs)
        self._known = self.known(obs)
        return obs, info

    def step(self, action: Any):
        obs, reward, terminated, truncated, info = self.env.step(action)
        known = self.known(obs)
        reward += self.bonus * (known - self._known)
        self._known = known
        return obs, reward, terminated, truncated, info
