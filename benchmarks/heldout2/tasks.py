"""Held-out tasks of the generalizing search: written before the search was changed, run once.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout2/tasks.py --list

Twelve grid tasks of kinds the development set has none of (conditionals on what a sensing
showed, moves in a direction until blocked, dead ends, reachable corners, the nearer of two
goals, stepping back, memory of what was visited, nearest and farthest) and three scooping
tasks. Each has a reference behavior (``references/``), a ground-truth ``check`` and a faithful
``promise``: what an expert would write, over the env's outcome helpers, so that the search can
be measured apart from the model. Nothing of the search was written while looking at how it
fared on these; the results of their one run go outside the repository and are quoted in the
docs beside the development figures.

Words as the checks read them: a cell is *free* when it holds no obstacle (empty or a goal);
*known* when the agent's label of it is not 'unexplored'; *reachable* when it lies in the start
cell's free component; the *distance* of two cells counts steps along rows and columns
(|di| + |dj|), obstacles ignored; *up* is j + 1, *down* j - 1, *right* i + 1. A scoop's mass is
what its step measured (``mass_delivered``, grams).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.synthesis_tasks import (cell, exhausted, first_goal_sense, grams_in_receiver,
                                        held_out_task, moves, neighbours, reachable, scoops)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE, UNEXPLORED

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
CORNERS = [(0, 0), (0, 9), (9, 0), (9, 9)]


def _steps(result) -> list[tuple[str, tuple[int, int]]]:
    return [(s["primitive"], cell(s["param"])) for s in result.steps]


def _free(state, c) -> bool:
    return state.truth[c] != OBSTACLE


def _distance(a, b) -> int:
    return abs(a[0] - b[0]) + abs(a[1] - b[1])


def _known(state) -> list[tuple[int, int]]:
    return [cell(c) for c in np.argwhere(state.labels != UNEXPLORED)]


def _dead_end(state, c) -> bool:
    return _free(state, c) and sum(_free(state, n) for n in neighbours(state, c)) == 1


def _line(state, start, step, limit=None) -> list[tuple[str, tuple[int, int]]]:
    """Sense, then step by ``step`` while the next cell is inside the grid and free (at most
    ``limit`` steps), sensing after every step."""
    here, plan = start, [("sense", start)]
    while limit is None or len(plan) // 2 < limit:
        nxt = (here[0] + step[0], here[1] + step[1])
        if not (0 <= nxt[0] < state.size and 0 <= nxt[1] < state.size) or not _free(state, nxt):
            break
        plan += [("navigate", nxt), ("sense", nxt)]
        here = nxt
    return plan


# --- checks -------------------------------------------------------------------------------

def check_sense_goal_or_stay(state, result):
    """One sense at the start; then one move onto a goal if the sense showed one, else none."""
    home, steps = state.start_cell, _steps(result)
    seen = [n for n in neighbours(state, home) if state.truth[n] == GOAL]
    if steps[:1] != [("sense", home)]:
        return f"did not begin with a sense at the start: {steps[:3]}"
    rest = steps[1:]
    if seen:
        ok = len(rest) == 1 and rest[0][0] == "navigate" and state.truth[rest[0][1]] == GOAL
    else:
        ok = rest == []
    return None if ok else f"goal beside the start: {bool(seen)}; then it ran {rest[:4]}"


def check_east_until_blocked(state, result):
    """Exactly: sense, then step right while the next cell is in the grid and free, sensing
    after each step."""
    want = _line(state, state.start_cell, (1, 0))
    steps = _steps(result)
    return None if steps == want else f"ran {steps[:8]}, not {want[:8]}"


def check_step_back_after_goal(state, result):
    """Once a goal is revealed: onto a goal, then back to the cell it was in, and stop."""
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal was found"
    rest = _steps(result)[index + 1:]
    here = _steps(result)[index][1]
    if len(rest) == 2 and rest[0][0] == rest[1][0] == "navigate" \
            and state.truth[rest[0][1]] == GOAL and rest[1][1] == here:
        return None
    return f"after finding a goal in {here} it ran {rest[:4]}"


def check_nearer_goal(state, result):
    """Ends on a known goal no farther from the start than any known goal, with two goals
    known or nothing more to find."""
    home, final = state.start_cell, state.cell
    goals = [c for c in _known(state) if state.truth[c] == GOAL]
    if state.truth[final] != GOAL:
        return f"ended in {final}, not on a goal"
    if len(goals) < 2 and not exhausted(state):
        return f"only {len(goals)} goal(s) known and more could be found"
    if any(_distance(g, home) < _distance(final, home) for g in goals):
        return f"ended on {final}, but a known goal is nearer the start {home}"
    return None


def check_dead_end(state, result):
    """Ends on a dead end, or none is reachable and everything that can be found is known."""
    if _dead_end(state, state.cell):
        return None
    if exhausted(state) and not any(_dead_end(state, cell(c))
                                    for c in np.argwhere(reachable(state))):
        return None
    return f"ended in {state.cell}, not a dead end"


def check_reachable_corner(state, result):
    """Ends on a corner, or no corner is reachable and everything that can be found is known."""
    if state.cell in CORNERS:
        return None
    reach = reachable(state)
    if exhausted(state) and not any(reach[c] for c in CORNERS):
        return None
    return f"ended in {state.cell}, not a corner"


def check_visit_two_goals(state, result):
    """Moved onto two different goals and ended on the second (onto the only one, with
    everything explored, when one goal is reachable)."""
    goals = {cell(c) for c in np.argwhere(reachable(state) & (state.truth == GOAL))}
    visited = {c for c in moves(result) if c in goals}
    if len(goals) >= 2:
        ok = len(visited) >= 2 and state.truth[state.cell] == GOAL
    else:
        ok = visited == goals and exhausted(state)
    return None if ok else f"visited goals {sorted(visited)} of {sorted(goals)}"


def check_north_and_back(state, result):
    """One sense; onto the cell above and back if it is in the grid and free, else no move."""
    home, steps = state.start_cell, _steps(result)
    up = (home[0], home[1] + 1)
    if up[1] < state.size and _free(state, up):
        want = [("sense", home), ("navigate", up), ("navigate", home)]
    else:
        want = [("sense", home)]
    return None if steps == want else f"ran {steps[:5]}, not {want}"


def check_farthest_known_cell(state, result):
    """At least 12 cells known (or nothing more to find), ends on the known free cell
    farthest from the start."""
    home, final = state.start_cell, state.cell
    known = _known(state)
    if len(known) < 12 and not exhausted(state):
        return f"only {len(known)} cells known"
    best = max(_distance(c, home) for c in known if _free(state, c))
    if final not in known or _distance(final, home) < best:
        return f"ended {_distance(final, home)} from the start; a known free cell is {best} away"
    return None


def check_beside_goal(state, result):
    """Never moved onto a goal; ends on a free cell next to a goal."""
    if any(state.truth[c] == GOAL for c in moves(result)):
        return "moved onto a goal"
    final = state.cell
    if state.truth[final] == GOAL or not any(state.truth[n] == GOAL
                                             for n in neighbours(state, final)):
        return f"ended in {final}, not beside a goal"
    return None


def check_down_three_or_blocked(state, result):
    """Sense, then step down while the cell below is in the grid and free, at most three
    steps, sensing before each step (a last sense after the third step is allowed)."""
    want = _line(state, state.start_cell, (0, -1), limit=3)
    steps = _steps(result)
    return None if steps in (want, want[:-1]) else f"ran {steps[:9]}, not {want}"


def check_sense_free_neighbours(state, result):
    """A sense at the start; each free neighbour of the start visited once, sensed there, and
    the start again after each; ends at the start."""
    home, steps = state.start_cell, _steps(result)
    free = sorted(n for n in neighbours(state, home) if _free(state, n))
    if steps[:1] != [("sense", home)]:
        return f"did not begin with a sense at the start: {steps[:3]}"
    rest, visits = steps[1:], []
    while rest[:1] and rest[0][0] == "navigate" and rest[0][1] != home:
        spot = rest[0][1]
        if rest[1:3] != [("sense", spot), ("navigate", home)]:
            return f"at {spot} it ran {rest[1:3]}, not a sense then back to the start"
        visits.append(spot)
        rest = rest[3:]
    if rest or sorted(visits) != free:
        return f"visited {visits} then ran {rest[:3]}; the free neighbours are {free}"
    return None


def check_scoop_twice(state, result):
    n = len(scoops(result))
    return None if n == 2 and len(result.steps) == 2 else f"{n} scoop(s)"


def check_one_good_scoop(state, result):
    n = len(scoops(result))
    if len(result.steps) != 1 or n != 1:
        return f"{n} scoop(s)"
    mass = grams_in_receiver(state)
    return None if mass >= 20 else f"{mass:.1f} g in the receiver"


def check_three_scoops(state, result):
    n = len(scoops(result))
    return None if n == 3 and len(result.steps) == 3 else f"{n} scoop(s)"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)


_UP = "(start_cell()[0], start_cell()[1] + 1)"
_D = "abs({a}[0] - start_cell()[0]) + abs({a}[1] - start_cell()[1])"

TASKS = [
    _task("sense_goal_or_stay", 1, check_sense_goal_or_stay,
          "Sense once where you stand. If that shows a goal right next to you, step onto the "
          "goal and stop; if it shows none, stop where you are without moving.",
          "sensed() == [start_cell()] and (primitives() == ['sense', 'navigate'] and "
          "is_goal(final_cell()) if any(is_goal(c) for c in neighbours(start_cell())) else "
          "primitives() == ['sense'])"),
    _task("east_until_blocked", 2, check_east_until_blocked,
          "Go right (increasing i) one cell at a time, sensing before every step so you know "
          "what is next to you, and stop as soon as the next cell to the right is an obstacle "
          "or outside the grid.",
          "primitives() == ['sense', 'navigate'] * len(moves()) + ['sense'] and "
          "moves() == [(c[0] + 1, c[1]) for c in sensed()[:-1]] and "
          "(final_cell()[0] == 9 or is_obstacle((final_cell()[0] + 1, final_cell()[1])))"),
    _task("step_back_after_goal", 2, check_step_back_after_goal,
          "Explore until you find a goal, then move onto it. After that, step back to the cell "
          "you were in just before moving onto the goal, and stop there.",
          "steps_after_goal() == 2 and len(moves()) >= 2 and is_goal(moves()[-2]) and "
          "final_cell() == (moves()[-3] if len(moves()) >= 3 else start_cell())"),
    _task("nearer_goal", 3, check_nearer_goal,
          "Explore until you have found two goals, or until there is nothing more to find. "
          "Then go to the goal you found that is nearest to your starting cell (fewest steps "
          "along rows and columns) and stop on it.",
          "is_goal(final_cell()) and (len([g for g in known_cells() if is_goal(g)]) >= 2 or "
          f"explored_all()) and all({_D.format(a='final_cell()')} <= {_D.format(a='g')} "
          "for g in known_cells() if is_goal(g))"),
    _task("dead_end", 3, check_dead_end,
          "Find a dead end -- a free cell with an obstacle or the grid's edge on three of its "
          "four sides -- exploring as much as you need, then go to it and stop. If no dead end "
          "can be reached, stop once there is nothing more to find.",
          "len([n for n in neighbours(final_cell()) if not is_obstacle(n)]) == 1 or "
          "(explored_all() and not any(len([n for n in neighbours(c) if not is_obstacle(n)]) "
          "== 1 for c in reachable_cells()))"),
    _task("reachable_corner", 3, check_reachable_corner,
          "Get to one of the four corner cells of the grid, (0, 0), (0, 9), (9, 0) or (9, 9), "
          "exploring as much as you need to find one you can reach, and stop on it. If no "
          "corner can be reached, stop once there is nothing more to find.",
          "final_cell() in [(0, 0), (0, 9), (9, 0), (9, 9)] or (explored_all() and not any(c "
          "in reachable_cells() for c in [(0, 0), (0, 9), (9, 0), (9, 9)]))"),
    _task("visit_two_goals", 3, check_visit_two_goals,
          "Step onto two different goals, one after the other, exploring as needed, and stop "
          "on the second. If only one goal can be reached, step onto it and stop once there "
          "is nothing more to find.",
          "len([g for g in reachable_goals() if g in moves()]) >= min(2, len(reachable_goals()))"
          " and (is_goal(final_cell()) if len(reachable_goals()) >= 2 else explored_all())"),
    _task("north_and_back", 2, check_north_and_back,
          "Sense where you are. If the cell directly above you (j + 1) is inside the grid and "
          "not an obstacle, step onto it and then come back to your starting cell; otherwise do "
          "not move at all. Then stop.",
          f"primitives()[0] == 'sense' and len(sensed()) == 1 and (moves() == [{_UP}, "
          f"start_cell()] if start_cell()[1] < 9 and not is_obstacle({_UP}) else moves() == [])"),
    _task("farthest_known_cell", 3, check_farthest_known_cell,
          "Explore until you know what at least 12 cells contain, or until there is nothing "
          "more to find. Then go to the known free cell that is farthest from your starting "
          "cell (most steps along rows and columns) and stop there.",
          "(len(known_cells()) >= 12 or explored_all()) and final_cell() in known_cells() and "
          f"all({_D.format(a='c')} <= {_D.format(a='final_cell()')} for c in known_cells() if "
          "not is_obstacle(c))"),
    _task("beside_goal", 2, check_beside_goal,
          "Find a goal but never step onto one: stop on a free cell right next to a goal.",
          "goal_found() and not is_goal(final_cell()) and any(is_goal(n) for n in "
          "neighbours(final_cell())) and not any(is_goal(c) for c in moves())"),
    _task("down_three_or_blocked", 2, check_down_three_or_blocked,
          "Move down (decreasing j) one cell at a time, sensing before each move to know the "
          "cell below is free. Make at most three moves: stop after the third, or earlier as "
          "soon as the cell below you is an obstacle or outside the grid.",
          "len(moves()) <= 3 and primitives()[:2 * len(moves())] == ['sense', 'navigate'] * "
          "len(moves()) and primitives()[2 * len(moves()):] in [[], ['sense']] and "
          "moves() == [(c[0], c[1] - 1) for c in sensed()[:len(moves())]] and "
          "(len(moves()) == 3 or final_cell()[1] == 0 or "
          "is_obstacle((final_cell()[0], final_cell()[1] - 1)))"),
    _task("sense_free_neighbours", 3, check_sense_free_neighbours,
          "Sense at your starting cell. Then visit each free cell next to your start, one at a "
          "time: go there, sense, and come back to the start before the next. Finish at the "
          "start once every free neighbour has been visited.",
          "primitives()[0] == 'sense' and sensed()[0] == start_cell() and "
          "final_cell() == start_cell() and all(c == start_cell() for c in moves()[1::2]) and "
          "sorted(moves()[0::2]) == sorted([n for n in neighbours(start_cell()) if not "
          "is_obstacle(n)]) and all(c in sensed() for c in moves()[0::2])"),
    _task("scoop_twice", 1, check_scoop_twice, "Scoop two times in a row, then stop.",
          "scoops() == 2", SCOOP),
    _task("one_good_scoop", 1, check_one_good_scoop,
          "Scoop just once, getting at least 20 grams of grains into the receiver.",
          "scoops() == 1 and delivered() >= 20", SCOOP),
    _task("three_scoops", 2, check_three_scoops, "Scoop three times, then stop.",
          "scoops() == 3", SCOOP),
]
