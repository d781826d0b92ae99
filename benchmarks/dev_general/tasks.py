"""Development tasks of the kinds the generalizing search is for (not the held-out ones).

    python benchmarks/synthesis_eval.py --tasks benchmarks/dev_general/tasks.py --promises

Directions until blocked, counters, a conditional on what was found, nearest and farthest,
memory of where the agent stood, cells with a property found by exploring. The search was
developed looking at these (and at the 13 tasks of ``benchmarks.synthesis_tasks``); the
held-out set (``benchmarks/heldout2``) was written before and not looked at. Words as in
``benchmarks/heldout2/tasks.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.synthesis_tasks import Task, cell, exhausted, first_goal_sense, neighbours
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE, UNEXPLORED

REFERENCES = Path(__file__).resolve().parent / "references"


def _steps(result):
    return [(s["primitive"], cell(s["param"])) for s in result.steps]


def _free(state, c) -> bool:
    return state.truth[c] != OBSTACLE


def _known(state):
    return [cell(c) for c in np.argwhere(state.labels != UNEXPLORED)]


def _line(state, start, step, limit=None):
    here, plan = start, [("sense", start)]
    while limit is None or len(plan) // 2 < limit:
        nxt = (here[0] + step[0], here[1] + step[1])
        if not (0 <= nxt[0] < state.size and 0 <= nxt[1] < state.size) or not _free(state, nxt):
            break
        plan += [("navigate", nxt), ("sense", nxt)]
        here = nxt
    return plan


def check_west_until_blocked(state, result):
    want = _line(state, state.start_cell, (-1, 0))
    return None if _steps(result) == want else f"ran {_steps(result)[:8]}"


def check_up_two_or_blocked(state, result):
    want = _line(state, state.start_cell, (0, 1), limit=2)
    return None if _steps(result) in (want, want[:-1]) else f"ran {_steps(result)[:8]}"


def check_goal_beside_start_or_home(state, result):
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal was found"
    rest, home = _steps(result)[index + 1:], state.start_cell
    goals = [n for n in neighbours(state, home) if state.truth[n] == GOAL
             and state.labels[n] == GOAL]
    ok = (len(rest) == 1 and rest[0][1] in goals) if goals else (
        rest in ([("navigate", home)], []) and state.cell == home)
    return None if ok else f"after finding a goal it ran {rest[:3]}"


def check_farthest_goal(state, result):
    home, final = state.start_cell, state.cell
    goals = [c for c in _known(state) if state.truth[c] == GOAL]
    if state.truth[final] != GOAL:
        return "did not end on a goal"
    if len(goals) < 2 and not exhausted(state):
        return "fewer than two goals known"
    far = max(abs(g[0] - home[0]) + abs(g[1] - home[1]) for g in goals)
    return None if abs(final[0] - home[0]) + abs(final[1] - home[1]) == far else "not farthest"


def check_back_one_after_ten(state, result):
    steps = _steps(result)
    if len(_known(state)) < 10 or len(steps) < 2 or steps[-2][0] != "sense":
        return f"ran {steps[-3:]}"
    moves = [c for p, c in steps if p == "navigate"]
    before = moves[-3] if len(moves) >= 3 else state.start_cell
    return None if state.cell == before else f"ended in {state.cell}, not {before}"


def check_border_cell(state, result):
    final = state.cell
    if final[0] in (0, 9) or final[1] in (0, 9):
        return None
    reach = state.component == state.component[state.start_cell]
    border = [c for c in np.argwhere(reach) if c[0] in (0, 9) or c[1] in (0, 9)]
    return None if not border and exhausted(state) else f"ended in {final}"


def check_most_free_neighbours(state, result):
    known = _known(state)
    if len(known) < 15 and not exhausted(state):
        return "fewer than 15 cells known"

    def count(c):
        return sum(1 for n in neighbours(state, c) if n in known and _free(state, n))
    free = [c for c in known if _free(state, c)]
    if state.cell not in free or count(state.cell) < max(count(c) for c in free):
        return f"ended in {state.cell}, which has {count(state.cell)} known free neighbours"
    return None


def _task(name, difficulty, check, description, promise):
    return Task(name, description, difficulty, False, REFERENCES / f"{name}.json", check, promise)


_L = "(final_cell()[0] - 1, final_cell()[1])"
_U = "(final_cell()[0], final_cell()[1] + 1)"
_KF = "len([n for n in neighbours({x}) if n in known_cells() and not is_obstacle(n)])"

TASKS = [
    _task("west_until_blocked", 2, check_west_until_blocked,
          "Walk left (decreasing i) one cell at a time, sensing before each step, until the "
          "cell to your left is an obstacle or outside the grid; stop there.",
          "primitives() == ['sense', 'navigate'] * len(moves()) + ['sense'] and "
          "moves() == [(c[0] - 1, c[1]) for c in sensed()[:-1]] and "
          f"(final_cell()[0] == 0 or is_obstacle({_L}))"),
    _task("up_two_or_blocked", 2, check_up_two_or_blocked,
          "Move up (increasing j) at most two cells, one at a time, sensing before each move; "
          "stop early when the cell above you is an obstacle or outside the grid.",
          "len(moves()) <= 2 and primitives()[:2 * len(moves())] == ['sense', 'navigate'] * "
          "len(moves()) and primitives()[2 * len(moves()):] in [[], ['sense']] and "
          "moves() == [(c[0], c[1] + 1) for c in sensed()[:len(moves())]] and "
          f"(len(moves()) == 2 or final_cell()[1] == 9 or is_obstacle({_U}))"),
    _task("goal_beside_start_or_home", 3, check_goal_beside_start_or_home,
          "Explore until you find a goal. If that goal is right next to the cell you started "
          "in, step onto it; otherwise go back to your starting cell. Then stop.",
          "goal_found() and steps_after_goal() <= 1 and (is_goal(final_cell()) if any(is_goal(n) "
          "and n in known_cells() for n in neighbours(start_cell())) else final_cell() == "
          "start_cell())"),
    _task("farthest_goal", 3, check_farthest_goal,
          "Explore until you know two goals (or nothing more can be found), then go to the "
          "known goal farthest from your starting cell, counting steps along rows and columns.",
          "is_goal(final_cell()) and (len([g for g in known_cells() if is_goal(g)]) >= 2 or "
          "explored_all()) and all(abs(g[0] - start_cell()[0]) + abs(g[1] - start_cell()[1]) <= "
          "abs(final_cell()[0] - start_cell()[0]) + abs(final_cell()[1] - start_cell()[1]) "
          "for g in known_cells() if is_goal(g))"),
    _task("back_one_after_ten", 3, check_back_one_after_ten,
          "Explore until at least 10 cells are known, then go back to the cell you were in "
          "before your last move, and stop.",
          "len(known_cells()) >= 10 and primitives()[-2:] == ['sense', 'navigate'] and "
          "final_cell() == (moves()[-3] if len(moves()) >= 3 else start_cell())"),
    _task("border_cell", 3, check_border_cell,
          "Get to a free cell on the border of the grid (i or j is 0 or 9), exploring as "
          "needed, and stop there; if no border cell can be reached, stop once nothing more "
          "can be found.",
          "final_cell()[0] in [0, 9] or final_cell()[1] in [0, 9] or (explored_all() and not "
          "any(c[0] in [0, 9] or c[1] in [0, 9] for c in reachable_cells()))"),
    _task("most_free_neighbours", 3, check_most_free_neighbours,
          "Explore until at least 15 cells are known (or nothing more can be found), then go to "
          "the known free cell with the most known free neighbours, and stop.",
          "(len(known_cells()) >= 15 or explored_all()) and final_cell() in known_cells() and "
          f"not is_obstacle(final_cell()) and all({_KF.format(x='c')} <= "
          f"{_KF.format(x='final_cell()')} for c in known_cells() if not is_obstacle(c))"),
]
