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

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

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
Check = Callable[[Any, EpisodeResult], str | None]  # (the env's state, the episode record)


@dataclass(frozen=True)
class Task:
    """One natural-language task, its reference behavior and its success check; ``promise``,
    where given, is a faithful promise an expert would write for it (an expression over the
    env's outcome helpers), so that the search can be evaluated apart from the model; ``env_id``
    the environment it is asked on; ``trivial_ok``: the task asks for no more than one of the
    env's least behaviors does (sense once and stop), as a user says with ``--trivial-ok``."""

    name: str
    description: str  # what the user types, in plain words
    difficulty: int  # 1 easy .. 3 hard
    library: bool  # whether the shipped behaviors may be used as sub-behaviors
    reference: Path
    check: Check  # None when the episode did the task, else why not
    promise: str | None = None
    env_id: str = ENV_ID
    trivial_ok: bool = False


@dataclass(frozen=True)
class TaskOutcome:
    """What :func:`evaluate` counted. ``verified``: rho_B = +1 (every certificate and, where
    the behavior has one, its promise held); ``task_done``: verified and the task's check
    passed; ``judged``: episodes whose certificates all held, so the promise was judged;
    ``faithful``: those where the promise's verdict equals the check's; ``confidence``: that
    P[rho_B = +1] >= 0.95, from the verified count; ``task_confidence``: the same from
    task_done; ``failures``: the first (episode index, reason) pairs."""

    task: str
    behavior: str
    episodes: int
    verified: int
    task_done: int
    confidence: float
    task_confidence: float
    failures: tuple[tuple[int, str], ...]
    judged: int = 0
    faithful: int = 0


# --- ground truth (public: external task files use these) -------------------------

def cell(param: object) -> Cell:
    """A step's parameter as a cell."""
    i, j = param  # type: ignore[misc]
    return int(i), int(j)


def moves(result: EpisodeResult) -> list[Cell]:
    """The target cells of the episode's navigate steps, in order."""
    return [cell(s["param"]) for s in result.steps if s["primitive"] == "navigate"]


def neighbours(state: GridState, c: Cell) -> list[Cell]:
    """The cells 4-adjacent to ``c`` inside the grid."""
    i, j = c
    return [(a, b) for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1))
            if 0 <= a < state.size and 0 <= b < state.size]


def on_grid(state: GridState, c: Cell) -> bool:
    return 0 <= c[0] < state.size and 0 <= c[1] < state.size


def free_cell(state: GridState, c: Cell) -> bool:
    """``c`` is on the grid and holds no obstacle (empty or a goal)."""
    return on_grid(state, c) and state.truth[c] != OBSTACLE


def free_neighbours(state: GridState, c: Cell) -> list[Cell]:
    return [n for n in neighbours(state, c) if free_cell(state, n)]


def obstacles_beside(state: GridState, c: Cell) -> int:
    """How many obstacles are next to ``c`` (the grid's edge does not count)."""
    return sum(state.truth[n] == OBSTACLE for n in neighbours(state, c))


def sensed_cells(state: GridState, c: Cell) -> list[Cell]:
    """The cells a sense at ``c`` labels: ``c`` and the cells next to it."""
    return [c, *neighbours(state, c)]


def step_by(c: Cell, step: tuple[int, int]) -> Cell:
    return c[0] + step[0], c[1] + step[1]


def distance(a: Cell, b: Cell) -> int:
    """Steps along rows and columns, obstacles ignored: |di| + |dj|."""
    return abs(a[0] - b[0]) + abs(a[1] - b[1])


def steps_of(result: EpisodeResult) -> list[tuple[str, Cell]]:
    """Each step of the episode as (primitive, cell)."""
    return _plan(result.steps)


def same_steps(steps: list, want: list) -> str | None:
    """None if ``steps`` are ``want``, else what ran instead (the first ten of each)."""
    return None if steps == want else f"ran {steps[:10]}, not {want[:10]}"


def label_sensed(state: GridState, known: np.ndarray, step: tuple[str, Cell]) -> int:
    """Mark what a sense step labels in ``known``; return how many cells it labelled that no
    earlier sense had (0 for a move)."""
    if step[0] != "sense":
        return 0
    fresh = [n for n in sensed_cells(state, step[1]) if not known[n]]
    for n in fresh:
        known[n] = True
    return len(fresh)


def goals_shown(state: GridState, here: Cell) -> list[Cell]:
    """The goals a sense at ``here`` shows."""
    return [g for g in sensed_cells(state, here) if state.truth[g] == GOAL]


def onto(rest: list, here: Cell, targets: list, what: str) -> str | None:
    """None if the steps ``rest`` are nothing (the agent stands in ``here``, one of
    ``targets``) or one move onto one of ``targets`` (it does not); else why not."""
    if here in targets:
        return same_steps(rest, [])
    if len(rest) == 1 and rest[0][0] == "navigate" and rest[0][1] in targets:
        return None
    return f"{what} ran {rest[:4]}, not one move onto one of {targets[:6]}"


def onto_goal_seen(state: GridState, steps: list, index: int) -> str | None:
    """:func:`onto` after step ``index``, the sense that first showed a goal: the steps after
    it are nothing (the agent stands on a goal) or one move onto a goal that sense showed."""
    here = steps[index][1]
    return onto(steps[index + 1:], here, goals_shown(state, here), "after the goal came into view")


def distance_text(a: str, b: str) -> str:
    """A promise's text of :func:`distance` between the cells the texts ``a`` and ``b`` name."""
    return f"(abs({a}[0] - {b}[0]) + abs({a}[1] - {b}[1]))"


def indices(n: int) -> str:
    """The list [0, 1, ..., n - 1] written out (the promises' language has no range())."""
    return "[" + ", ".join(str(k) for k in range(n)) + "]"


# Parts of held-out promises (the judge's outcome language) that several sets write alike.
START, START_I, START_J = "start_cell()", "start_cell()[0]", "start_cell()[1]"
LAST_SENSE, FINAL = "sensed()[-1]", "final_cell()"  # where the last sense was; where it ended
# after the last sense: nothing, or one move (the last sense is then the step before it)
STAY = "primitives()[-1] == 'sense'"
MOVE = "primitives()[-2:] == ['sense', 'navigate']"
FRESH = "len(known_before_last()) < len(known_cells())"  # the last step labelled something
# a sense first, then a move and a sense in turn (each sense where the move before it ended, as
# the certificates say), up to the last sense
ALTERNATE = "primitives()[:2 * len(sensed()) - 1] == ['sense'] + ['navigate', 'sense'] * " \
            "(len(sensed()) - 1)"
# after the sense that first shows a goal: nothing on a goal, else one move onto one it showed
# (the agent ends on a goal, the cell of the goal sense with no step after it if that cell is a
# goal, else one next to it with the one step after it: a sense moves nothing)
ONTO_GOAL = f"steps_after_goal() == (0 if is_goal({LAST_SENSE}) else 1) and is_goal({FINAL}) " \
            f"and {FINAL} in [{LAST_SENSE}] + neighbours({LAST_SENSE})"
# after the last sense only moves, so that the last sense is the one that first showed a goal
ONLY_MOVES = "primitives()[len(primitives()) - steps_after_goal():] == ['navigate'] * " \
             "steps_after_goal()"
# the last sense showed a cell no earlier sense showed (then nothing more was to be found
# before it), read from the senses where a move may follow it
NEW_LAST = f"any(not any(x == s or x in neighbours(s) for s in sensed()[:-1]) for x in " \
           f"[{LAST_SENSE}] + neighbours({LAST_SENSE}))"


def held_out_task(references: Path) -> Callable[..., Task]:
    """The task maker of a held-out set whose references lie in ``references``: ``(name,
    difficulty, check, description, promise, env_id)``, the reference ``<name>.json``, no library
    behaviors."""
    def task(name: str, difficulty: int, check: Check, description: str, promise: str,
             env_id: str = ENV_ID) -> Task:
        return Task(name, description, difficulty, False, references / f"{name}.json", check,
                    promise, env_id)
    return task


def reachable(state: GridState) -> np.ndarray:
    """Cells of the start cell's free component in the true map (a boolean grid)."""
    return state.component == state.component[state.start_cell]


def _sense(state: GridState, known: np.ndarray, step: dict) -> None:
    if step["primitive"] == "sense":
        c = cell(step["param"])
        for n in [c, *neighbours(state, c)]:
            known[n] = True


def known_after(state: GridState, steps: Sequence[dict]) -> np.ndarray:
    """The cells known after ``steps`` from the reset (sense labels its cell and the four
    around it), as a boolean grid."""
    known = np.zeros_like(state.truth, dtype=bool)
    for step in steps:
        _sense(state, known, step)
    return known


def exhausted(state: GridState, known: np.ndarray | None = None) -> bool:
    """Whether every reachable cell and every cell next to one is known (``known``: a
    boolean grid; default: the agent's final labels)."""
    known = state.labels != UNEXPLORED if known is None else known
    reach = reachable(state)
    near = reach.copy()
    near[1:] |= reach[:-1]
    near[:-1] |= reach[1:]
    near[:, 1:] |= reach[:, :-1]
    near[:, :-1] |= reach[:, 1:]
    return bool(known[near].all())


def scoops(result: EpisodeResult) -> list[dict]:
    """The scoop steps of an episode (the held-out sets' scooping checks)."""
    return [s for s in result.steps if s["primitive"] == "scoop"]


def grams_in_receiver(state: Any) -> float:
    """Grams of grains in a scoop state's receiver now, counted from the simulation."""
    from vlb_gym.envs.scoop.controller import RECEIVER_HALF, RECEIVER_WALL, grains_in_box
    from vlb_gym.envs.scoop.scene import GRAIN_MASS

    positions = state.data.qpos[state.scene.grain_qpos[:, :3]]
    inside = grains_in_box(positions, state.env.receiver, RECEIVER_HALF, RECEIVER_WALL)
    return float(inside.sum()) * GRAIN_MASS * 1000


def grams_spilled(state: Any) -> float:
    """Grams of grains outside the receiver, the donor and the spoon's tray now, counted from
    the simulation as the scoop primitive counts them after each scoop."""
    from vlb_gym.envs.scoop.controller import grains_in_box, grains_in_scoop
    from vlb_gym.envs.scoop.scene import (DONOR_HALF, DONOR_WALL, GRAIN_MASS, RECEIVER_HALF,
                                          RECEIVER_WALL)

    positions = state.data.qpos[state.scene.grain_qpos[:, :3]]
    delivered = grains_in_box(positions, state.env.receiver, RECEIVER_HALF, RECEIVER_WALL)
    kept = grains_in_box(positions, state.env.donor, DONOR_HALF, DONOR_WALL)
    tray = grains_in_scoop(positions, state.data, state.scene.model.site("scoop").id)
    return float((~(delivered | kept | tray)).sum()) * GRAIN_MASS * 1000


def at_start(state: GridState) -> str | None:
    """None if the agent ended in its start cell, else where it ended."""
    if state.cell != state.start_cell:
        return f"ended in cell {state.cell}, not the start cell {state.start_cell}"
    return None


def first_goal_sense(state: GridState, result: EpisodeResult) -> int | None:
    """The index of the step whose sense first revealed a goal (None: none did)."""
    for index, step in enumerate(result.steps):
        if step["primitive"] == "sense":
            c = cell(step["param"])
            if any(state.truth[n] == GOAL for n in [c, *neighbours(state, c)]):
                return index
    return None


def goal_sense(state: GridState, result: EpisodeResult) -> tuple[list, int | None]:
    """The steps of the episode and the index of the sense that first showed a goal (None if
    none did)."""
    return steps_of(result), first_goal_sense(state, result)


def any_plan(rest: list, plans: list[list]) -> str | None:
    """None if ``rest`` is one of ``plans``, else what ran instead of the first."""
    return None if rest in plans else same_steps(rest, plans[0])


def first_reaching(state: GridState, result: EpisodeResult,
                   reached: Callable[[np.ndarray], bool]) -> int | None:
    """The index of the first step after which ``reached(known cells)`` holds."""
    known = np.zeros_like(state.truth, dtype=bool)
    for index, step in enumerate(result.steps):
        _sense(state, known, step)
        if step["primitive"] == "sense" and reached(known):
            return index
    return None


def _plan(steps: Sequence[dict]) -> list[tuple[str, Cell]]:
    return [(s["primitive"], cell(s["param"])) for s in steps]


def _then(state: GridState, result: EpisodeResult, index: int | None, what: str,
          allowed: Callable[[list[tuple[str, Cell]]], bool]) -> str | None:
    """A check's verdict: ``what`` must have happened (at step ``index``) and the steps
    after it must be ``allowed``."""
    if index is None:
        return f"{what} never happened"
    rest = _plan(result.steps[index + 1:])
    return None if allowed(rest) else f"after {what} (step {index + 1}) it ran {rest[:6]}"


# --- checks ------------------------------------------------------------------------

def check_sense_once(state: GridState, result: EpisodeResult) -> str | None:
    names = [s["primitive"] for s in result.steps]
    return None if names == ["sense"] else f"ran {names}, not one sense"


def check_go_to_goal(state: GridState, result: EpisodeResult) -> str | None:
    """Once a goal is revealed, one move, onto a goal, and nothing else."""
    return _then(state, result, first_goal_sense(state, result), "finding a goal",
                 lambda rest: len(rest) == 1 and rest[0][0] == "navigate"
                 and state.truth[rest[0][1]] == GOAL)


def check_return_home(state: GridState, result: EpisodeResult) -> str | None:
    """Once a goal is revealed, straight back to the start (no move if already there)."""
    home = state.start_cell
    return _then(state, result, first_goal_sense(state, result), "finding a goal",
                 lambda rest: rest == [("navigate", home)]
                 or (rest == [] and state.cell == home))


def check_explore_until_goal(state: GridState, result: EpisodeResult) -> str | None:
    """A goal was found and the last step is the sense that first revealed one."""
    return _then(state, result, first_goal_sense(state, result), "finding a goal",
                 lambda rest: rest == [])


def round_trips(n: int) -> Check:
    """A check: once a goal is revealed, the moves are exactly [goal, start] * n (the same
    goal each time), ending at the start."""

    def check(state: GridState, result: EpisodeResult) -> str | None:
        found = first_goal_sense(state, result)
        if found is None:
            return "no goal was found"
        tail = [c for name, c in _plan(result.steps[found + 1:]) if name == "navigate"]
        if not tail or state.truth[tail[0]] != GOAL:
            return f"the first move after finding a goal was not onto a goal: {tail[:2]}"
        want = [tail[0], state.start_cell] * n
        if tail != want:
            return f"moves after finding a goal were {tail[:12]}, not {n} x {want[:2]}"
        return at_start(state)
    return check


def check_goal_sense_home(state: GridState, result: EpisodeResult) -> str | None:
    """Once a goal is revealed: onto a goal, sense there, back to the start, nothing else."""
    home = state.start_cell
    return _then(state, result, first_goal_sense(state, result), "finding a goal",
                 lambda rest: len(rest) == 3 and rest[0][0] == "navigate"
                 and state.truth[rest[0][1]] == GOAL and rest[1] == ("sense", rest[0][1])
                 and rest[2] == ("navigate", home))


def _stops_when(what: str, enough: Callable[[GridState, np.ndarray], bool]) -> Check:
    """A check: exploring stops with the sense after which ``enough`` (or exhaustion) first
    holds."""

    def check(state: GridState, result: EpisodeResult) -> str | None:
        index = first_reaching(state, result,
                               lambda known: enough(state, known) or exhausted(state, known))
        return _then(state, result, index, what, lambda rest: rest == [])
    return check


def known_at_least(n: int) -> Check:
    """A check: stops as soon as at least ``n`` cells are known, or exploring is exhausted."""
    return _stops_when(f"knowing {n} cells", lambda state, known: int(known.sum()) >= n)


def obstacles_at_least(n: int) -> Check:
    """A check: stops as soon as at least ``n`` obstacles are known, or exploring is
    exhausted."""
    return _stops_when(f"finding {n} obstacles",
                       lambda state, known: int((known & (state.truth == OBSTACLE)).sum()) >= n)


def patrol(n: int) -> Check:
    """A check: the moves are exactly [spot, start] * n, the spot a free cell next to
    the start."""

    def check(state: GridState, result: EpisodeResult) -> str | None:
        route, home = moves(result), state.start_cell
        spot = route[0] if route else home
        if (spot not in neighbours(state, home) or state.truth[spot] == OBSTACLE
                or route != [spot, home] * n):
            return f"moves were {route}, not {n} round trips to a free neighbour"
        return at_start(state)
    return check


check_explore_all = _stops_when("exploring everything", lambda state, known: False)


def check_explore_all_return_home(state: GridState,
                                  result: EpisodeResult) -> str | None:
    """Exploring stops when exhausted, then straight back to the start."""
    home = state.start_cell
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    return _then(state, result, index, "exploring everything",
                 lambda rest: rest == [("navigate", home)]
                 or (rest == [] and state.cell == home))


def check_visit_all_goals(state: GridState, result: EpisodeResult) -> str | None:
    """Every reachable goal is moved onto (a behavior cannot know it has found them all
    before exploring everything, so what follows is free)."""
    goals = {cell(c) for c in np.argwhere(reachable(state) & (state.truth == GOAL))}
    missed = sorted(goals - set(moves(result)))
    return f"never moved onto reachable goal(s) {missed}" if missed else None


# --- the suite ---------------------------------------------------------------------

def _task(name: str, difficulty: int, library: bool, check: Check,
          *description: str) -> Task:
    return Task(name, "".join(description), difficulty, library,
                REFERENCES / f"{name}.json", check, PROMISES[name],
                trivial_ok=name == "sense_once")


def _trips(n: int) -> str:
    return (f"len(moves_after_goal()) == {2 * n} and is_goal(moves_after_goal()[0]) and "
            f"moves_after_goal() == [moves_after_goal()[0], start_cell()] * {n}")


#: A faithful promise of each task: what an expert would write (the search's own figure is
#: measured with these, apart from the model's).
PROMISES = {
    "sense_once": "primitives() == ['sense']",
    "go_to_goal": "steps_after_goal() == 1 and primitives()[-1] == 'navigate' and "
                  "is_goal(final_cell())",
    "return_home": "goal_found() and steps_after_goal() <= 1 and final_cell() == start_cell() "
                   "and (steps_after_goal() == 0 or primitives()[-1] == 'navigate')",
    "explore_until_goal": "goal_found() and steps_after_goal() == 0",
    "two_round_trips": _trips(2),
    "find_goal_and_oscillate": _trips(5),
    "goal_sense_home": "steps_after_goal() == 3 and primitives()[-3:] == ['navigate', 'sense', "
                       "'navigate'] and is_goal(moves()[-2]) and sensed()[-1] == moves()[-2] "
                       "and final_cell() == start_cell()",
    "explore_20_cells": "(len(known_cells()) >= 20 or explored_all()) and "
                        "primitives()[-1] == 'sense' and len(known_before_last()) < 20",
    "find_3_obstacles": "(len(known_obstacles()) >= 3 or explored_all()) and "
                        "primitives()[-1] == 'sense' and "
                        "len([c for c in known_before_last() if is_obstacle(c)]) < 3",
    "patrol_neighbour": "len(moves()) == 6 and moves()[0] in neighbours(start_cell()) and "
                        "moves() == [moves()[0], start_cell()] * 3",
    "explore_all": "explored_all() and primitives()[-1] == 'sense'",
    "explore_all_return_home": "explored_all() and final_cell() == start_cell() and "
                               "primitives()[-1] == 'navigate'",
    "visit_all_goals": "all(g in moves() for g in reachable_goals())",
}


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
    config = CampaignConfig(task.env_id, PolicyRef("behavior", str(behavior), library),
                            episodes, epsilon=EPSILON, seed=seed)
    env, policy = build(config)
    verified = done = judged = faithful = 0
    failures: list[tuple[int, str]] = []
    try:
        for i in range(episodes):
            result = run_episode(env, policy, episode_seed(seed, i), i,
                                 config.stop_on_failure)
            reason = result.reason or "rho_B = -1"
            promise_failed = (result.cause or "").endswith(": promise")
            if result.success or promise_failed:
                judged += 1
                verdict = task.check(env.unwrapped.state, result)
                faithful += (verdict is None) == result.success
                if result.success:
                    verified += 1
                    done += verdict is None
                    reason = verdict
            if reason is not None and len(failures) < MAX_REASONS:
                failures.append((i, reason))
    finally:
        env.close()
    return TaskOutcome(task.name, str(behavior), episodes, verified, done,
                       confidence(episodes, episodes - verified, EPSILON),
                       confidence(episodes, episodes - done, EPSILON), tuple(failures),
                       judged, faithful)
