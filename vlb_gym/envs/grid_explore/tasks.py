"""Task rewards and termination for RL on the exploration grid (``gym.make(..., task=...)``).

Rewards never enter rho_B: the robustness wrapper scores certificates and finishing only. With a
task the episode *terminates* when the task is done, and that is what "finished" means for a
policy that has no graph:

* ``find_goal``: terminates on the step that first labels a goal cell (+1);
* ``find_goal_and_oscillate``: after a goal is found (+1), each navigation that arrives at a goal
  cell (when heading to a goal) or at the start cell (when heading home) completes a leg (+0.5);
  terminates after 10 legs, i.e. 5 round trips ending at the start.

Every step costs 0.01 and every failed certificate 0.1 more.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .types import GOAL, GridState

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
