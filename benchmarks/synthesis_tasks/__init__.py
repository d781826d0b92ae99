"""Tasks of the certified-synthesis evaluation on ``VLB-GridExplore-v0``.

A :class:`Task` is what a user asks a language model for, in words, with a
hand-written reference behavior and a ``check`` that decides from the ground truth
whether an episode did the task. :func:`evaluate` runs a behavior through the
package's own campaign machinery (default env kwargs) and counts the episodes that
are verified (rho_B = +1) and those that also did the task.

Words of the descriptions, as the checks read them: a cell is *known* when the
agent's label of it is not 'unexplored'; *reachable* when it lies in the start
cell's free component of the true map; exploring is *exhausted* when every reachable
cell and every cell next to one is known; moves are the ``navigate`` steps, and
round trips are read from their parameters (sensing in between does not count).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE, UNEXPLORED, GridState
from vlb_gym.verify.bounds import confidence
from vlb_gym.verify.campaign import CampaignConfig, build, episode_seed
from vlb_gym.verify.episode import EpisodeResult, run_episode
from vlb_gym.verify.policies import PolicyRef

ENV_ID = "VLB-GridExplore-v0"
EPSILON = 0.05
REFERENCES = Path(__file__).resolve().parent / "references"
MAX_REASONS = 5

Cell = tuple[int, int]
Check = Callable[[GridState, EpisodeResult], str | None]


@dataclass(frozen=True)
class Task:
    """One natural-language task, its reference behavior and its success check."""

    name: str
    description: str  # what the user types, in plain words
    difficulty: int  # 1 easy .. 3 hard
    library: bool  # whether the shipped behaviors may be used as sub-behaviors
    reference: Path
    check: Check  # None when the episode did the task, else why not


@dataclass(frozen=True)
class TaskOutcome:
    """What :func:`evaluate` counted. ``confidence``: that P[rho_B = +1] >= 0.95,
    from the verified count; ``task_confidence``: the same from task_done;
    ``failures``: the first (episode index, reason) pairs."""

    task: str
    behavior: str
    episodes: int
    verified: int
    task_done: int
    confidence: float
    task_confidence: float
    failures: tuple[tuple[int, str], ...]


# --- ground truth ------------------------------------------------------------------

def _cell(param: object) -> Cell:
    i, j = param  # type: ignore[misc]
    return int(i), int(j)


def _moves(result: EpisodeResult) -> list[Cell]:
    return [_cell(s["param"]) for s in result.steps if s["primitive"] == "navigate"]


def _neighbours(state: GridState, cell: Cell) -> list[Cell]:
    i, j = cell
    return [(a, b) for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1))
            if 0 <= a < state.size and 0 <= b < state.size]


def _reachable(state: GridState) -> np.ndarray:
    """Cells of the start cell's free component in the true map."""
    return state.component == state.component[state.start_cell]


def _exhausted(state: GridState) -> bool:
    """Whether every reachable cell and every cell next to one is known."""
    reach = _reachable(state)
    near = reach.copy()
    near[1:] |= reach[:-1]
    near[:-1] |= reach[1:]
    near[:, 1:] |= reach[:, :-1]
    near[:, :-1] |= reach[:, 1:]
    return bool((state.labels[near] != UNEXPLORED).all())


def _known(state: GridState) -> int:
    return int((state.labels != UNEXPLORED).sum())


def _at_start(state: GridState) -> str | None:
    if state.cell != state.start_cell:
        return f"ended in cell {state.cell}, not the start cell {state.start_cell}"
    return None


# --- checks ------------------------------------------------------------------------

def check_sense_once(state: GridState, result: EpisodeResult) -> str | None:
    names = [s["primitive"] for s in result.steps]
    return None if names == ["sense"] else f"ran {names}, not one sense"


def check_go_to_goal(state: GridState, result: EpisodeResult) -> str | None:
    if state.truth[state.cell] != GOAL:
        return f"ended in cell {state.cell}, which is not a goal"
    return None


def check_return_home(state: GridState, result: EpisodeResult) -> str | None:
    if not (state.labels == GOAL).any():
        return "no goal was found"
    return _at_start(state)


def check_explore_until_goal(state: GridState, result: EpisodeResult) -> str | None:
    """A goal was found and the last step is the sense that first revealed one."""
    for index, step in enumerate(result.steps):
        if step["primitive"] == "sense":
            cell = _cell(step["param"])
            if any(state.truth[c] == GOAL for c in [cell, *_neighbours(state, cell)]):
                extra = len(result.steps) - index - 1
                return f"{extra} step(s) after finding a goal" if extra else None
    return "no goal was found"


def round_trips(n: int) -> Check:
    """A check: from the first move onto a goal on, the moves are exactly
    [that goal, start] * n, ending at the start."""

    def check(state: GridState, result: EpisodeResult) -> str | None:
        moves = _moves(result)
        first = next((k for k, c in enumerate(moves) if state.truth[c] == GOAL), None)
        if first is None:
            return "never moved onto a goal"
        tail, want = moves[first:], [moves[first], state.start_cell] * n
        if tail != want:
            return f"moves from the goal on were {tail}, not {n} x {want[:2]}"
        return _at_start(state)
    return check


def check_goal_sense_home(state: GridState, result: EpisodeResult) -> str | None:
    if not any(s["primitive"] == "sense" and state.truth[_cell(s["param"])] == GOAL
               for s in result.steps):
        return "never sensed on a goal"
    return _at_start(state)


def known_at_least(n: int) -> Check:
    """A check: at least ``n`` cells known, or exploring exhausted."""

    def check(state: GridState, result: EpisodeResult) -> str | None:
        if _known(state) >= n or _exhausted(state):
            return None
        return f"only {_known(state)} cells known, and more could be found"
    return check


def obstacles_at_least(n: int) -> Check:
    """A check: at least ``n`` obstacles known, or exploring exhausted."""

    def check(state: GridState, result: EpisodeResult) -> str | None:
        found = int((state.labels == OBSTACLE).sum())
        if found >= n or _exhausted(state):
            return None
        return f"only {found} obstacles found, and more could be found"
    return check


def patrol(n: int) -> Check:
    """A check: the moves are exactly [spot, start] * n, the spot a free cell next to
    the start."""

    def check(state: GridState, result: EpisodeResult) -> str | None:
        moves, home = _moves(result), state.start_cell
        spot = moves[0] if moves else home
        if (spot not in _neighbours(state, home) or state.truth[spot] == OBSTACLE
                or moves != [spot, home] * n):
            return f"moves were {moves}, not {n} round trips to a free neighbour"
        return _at_start(state)
    return check


def check_explore_all(state: GridState, result: EpisodeResult) -> str | None:
    if _exhausted(state):
        return None
    return f"only {_known(state)} cells known, and more could be found"


def check_explore_all_return_home(state: GridState,
                                  result: EpisodeResult) -> str | None:
    return check_explore_all(state, result) or _at_start(state)


def check_visit_all_goals(state: GridState, result: EpisodeResult) -> str | None:
    goals = {_cell(c) for c in np.argwhere(_reachable(state) & (state.truth == GOAL))}
    missed = sorted(goals - set(_moves(result)))
    return f"never moved onto reachable goal(s) {missed}" if missed else None


# --- the suite ---------------------------------------------------------------------

def _task(name: str, difficulty: int, library: bool, check: Check,
          *description: str) -> Task:
    return Task(name, "".join(description), difficulty, library,
                REFERENCES / f"{name}.json", check)


_EXHAUSTED = ("You may also stop once every cell you can reach, and every cell next "
              "to one, is known, since then nothing more can be found.")
_TRIPS = ("ending at your starting cell. Make no other moves after first moving "
          "onto the goal.")

TASKS: tuple[Task, ...] = (
    _task("sense_once", 1, False, check_sense_once,
          "Sense your surroundings once from where you stand, then stop without "
          "moving."),
    _task("go_to_goal", 1, True, check_go_to_goal,
          "Search the grid until you find a goal, then move onto that goal and stop "
          "there."),
    _task("return_home", 1, True, check_return_home,
          "Search the grid until you find a goal, then go back to the cell you started "
          "in and stop there."),
    _task("explore_until_goal", 2, False, check_explore_until_goal,
          "Explore the grid, moving and sensing, until you have found a goal. Stop as "
          "soon as one is found: the sensing that first reveals a goal must be your "
          "last action."),
    _task("two_round_trips", 2, True, round_trips(2),
          "Find a goal, then move back and forth between that goal and the cell you "
          "started in: 2 round trips (goal, start, goal, start), ", _TRIPS),
    _task("find_goal_and_oscillate", 2, True, round_trips(5),
          "Find a goal, then move back and forth between that goal and the cell you "
          "started in 5 times: 5 round trips (goal, start, goal, start, ...), ",
          _TRIPS),
    _task("goal_sense_home", 2, True, check_goal_sense_home,
          "Find a goal, move onto it and sense there, then go back to the cell you "
          "started in and stop."),
    _task("explore_20_cells", 2, False, known_at_least(20),
          "Explore until you know what at least 20 cells of the grid contain (empty, "
          "obstacle or goal), then stop. ", _EXHAUSTED),
    _task("find_3_obstacles", 2, False, obstacles_at_least(3),
          "Explore until you have found at least 3 obstacles, then stop. ", _EXHAUSTED),
    _task("patrol_neighbour", 2, False, patrol(3),
          "Pick one cell next to your starting cell (left, right, up or down) that is "
          "not an obstacle and go back and forth between the two: 3 round trips (that "
          "cell, start, that cell, start, that cell, start), ending at your starting "
          "cell. Make no other moves."),
    _task("explore_all", 3, False, check_explore_all,
          "Explore everything you can reach from your starting cell: keep going until "
          "you know what every reachable cell and every cell next to a reachable cell "
          "contains, then stop."),
    _task("explore_all_return_home", 3, False, check_explore_all_return_home,
          "Explore everything you can reach from your starting cell until you know "
          "what every reachable cell and every cell next to a reachable cell contains, "
          "then go back to the cell you started in and stop."),
    _task("visit_all_goals", 3, False, check_visit_all_goals,
          "Move onto every goal that can be reached from your starting cell, ending a "
          "move on each of them, then stop. Goals walled off from you do not count."),
)


def task_named(name: str) -> Task:
    """The task called ``name`` (KeyError if none)."""
    for task in TASKS:
        if task.name == name:
            return task
    raise KeyError(f"no task {name!r} (tasks: {', '.join(t.name for t in TASKS)})")


def evaluate(task: Task, behavior: str | Path, episodes: int = 100, seed: int = 0,
             library_dir: Path | None = None) -> TaskOutcome:
    """Run ``behavior`` for episodes 0..episodes-1 of the campaign with ``seed`` and
    count those verified and those that also did ``task``.

    ``behavior`` is a .json path or a library name; names, its sub-behaviors' too,
    resolve in ``library_dir`` (default: the user's library). A behavior that does
    not load raises ValueError."""
    library = None if library_dir is None else str(library_dir)
    config = CampaignConfig(ENV_ID, PolicyRef("behavior", str(behavior), library),
                            episodes, epsilon=EPSILON, seed=seed)
    env, policy = build(config)
    verified = done = 0
    failures: list[tuple[int, str]] = []
    try:
        for i in range(episodes):
            result = run_episode(env, policy, episode_seed(seed, i), i,
                                 config.stop_on_failure)
            reason = result.reason or "rho_B = -1"
            if result.success:
                verified += 1
                reason = task.check(env.unwrapped.state, result)
                done += reason is None
            if reason is not None and len(failures) < MAX_REASONS:
                failures.append((i, reason))
    finally:
        env.close()
    return TaskOutcome(task.name, str(behavior), episodes, verified, done,
                       confidence(episodes, episodes - verified, EPSILON),
                       confidence(episodes, episodes - done, EPSILON), tuple(failures))
