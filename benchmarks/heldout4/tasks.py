"""Held-out tasks, fourth set: written before the next change of the synthesizer, run once after.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout4/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (staying put or stepping off depending
on how many obstacles one sense showed, a step toward the centre of the grid, a fixed number of
moves onto fresh cells, a second look from next door when no goal is in sight, a walk right and
then all the way back left, a walk up that stops on a tally of obstacles, a return to the first
cell moved to after a goal, a walk right from the goal found, one goal or else home after
exploring everything, the neighbour with the fewest obstacles after visiting them all, a tour of
every goal after exploring, the place where a sense showed the most obstacles) and two scooping
tasks. Each has a reference behavior (``references/``), a ground-truth ``check`` and a faithful
``promise`` over the env's outcome helpers, so that the search can be measured apart from the
model. They were written on 2026-12-05 without running the synthesizer on them; the first run of
the search on them is the evaluation, reported beside the development figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and
every cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a
sense labels its cell and the four around it; the obstacles *next to* a cell are those among its
four neighbours inside the grid (the grid's edge does not count). The start cell always has a
free neighbour (a goal is reachable from it and it holds none). The scooping check weighs the
grains in the receiver at the end, as ``delivered()`` does since the judge was fixed (it used to
add up each scoop's weighing of the receiver's contents, counting early grains again; the
tasks were not changed: three scoops of the reference left 88 to 140 g there in ten episodes).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.synthesis_tasks import (cell, exhausted, first_goal_sense, first_reaching,
                                        free_cell, free_neighbours, grams_in_receiver,
                                        held_out_task, moves, neighbours, reachable, same_steps,
                                        scoops, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP = (1, 0), (-1, 0), (0, 1)


def _obstacles_beside(state, c) -> int:
    return sum(state.truth[n] == OBSTACLE for n in neighbours(state, c))


def _revealed(state, c) -> list[tuple[int, int]]:
    return [x for x in [c, *neighbours(state, c)] if state.truth[x] == GOAL]


def _goals(state) -> list[tuple[int, int]]:
    """The reachable goals, in (i, j) order."""
    return sorted(cell(c) for c in np.argwhere(reachable(state) & (state.truth == GOAL)))


def _walk(state, start, step):
    """Sense at ``start``, then one move by ``step`` while the next cell is free, sensing after
    every move; the plan and the cell it ends in."""
    here, plan = start, [("sense", start)]
    while free_cell(state, step_by(here, step)):
        here = step_by(here, step)
        plan += [("navigate", here), ("sense", here)]
    return plan, here


def _centre(c) -> int:
    """Twice the distance of ``c`` from the centre of the grid, (4.5, 4.5), along rows and
    columns: an integer."""
    return abs(2 * c[0] - 9) + abs(2 * c[1] - 9)


# --- checks -------------------------------------------------------------------------------

def check_crowded_stay_else_step(state, result):
    """One sense; no move if obstacles are next to the start on two or more sides, else one
    move onto a free cell next to the start."""
    home, steps = state.start_cell, steps_of(result)
    if _obstacles_beside(state, home) >= 2:
        return same_steps(steps, [("sense", home)])
    if len(steps) == 2 and steps[0] == ("sense", home) and steps[1][0] == "navigate" \
            and steps[1][1] in free_neighbours(state, home):
        return None
    return f"ran {steps[:4]}; {_obstacles_beside(state, home)} obstacle(s) next to the start"


def check_centre_neighbour(state, result):
    """One sense, then one move onto a free cell next to the start nearest the centre."""
    home, steps = state.start_cell, steps_of(result)
    free = free_neighbours(state, home)
    best = min(_centre(n) for n in free)
    if len(steps) == 2 and steps[0] == ("sense", home) and steps[1][0] == "navigate" \
            and steps[1][1] in free and _centre(steps[1][1]) == best:
        return None
    return f"ran {steps[:4]}; the free neighbours: {free}"


def check_four_fresh_cells(state, result):
    """Sense; then moves, each onto a cell not stood in before and followed by a sense there:
    four, or fewer only if nothing more can be found."""
    home, steps, targets = state.start_cell, steps_of(result), moves(result)
    if steps != [("sense", home)] + [x for c in targets for x in (("navigate", c), ("sense", c))]:
        return f"ran {steps[:10]}: not a sense first and after every move"
    if len(targets) > 4 or any(c in [home, *targets[:k]] for k, c in enumerate(targets)):
        return f"moved to {targets}"
    if len(targets) < 4 and not exhausted(state):
        return f"stopped after {len(targets)} move(s) with more to find"
    return None


def check_peek_again_if_no_goal(state, result):
    """One sense; if it showed a goal, nothing more; else a move onto a free cell next to the
    start and a sense there."""
    home, steps = state.start_cell, steps_of(result)
    if _revealed(state, home):
        return same_steps(steps, [("sense", home)])
    if len(steps) == 3 and steps[0] == ("sense", home) and steps[1][0] == "navigate" \
            and steps[1][1] in free_neighbours(state, home) and steps[2] == ("sense", steps[1][1]):
        return None
    return f"ran {steps[:4]}; no goal in sight of the start"


def check_sweep_row(state, result):
    """Sense; right while free, then left while free (back past the start), sensing after
    every move."""
    plan, end = _walk(state, state.start_cell, RIGHT)
    more, _ = _walk(state, end, LEFT)
    return same_steps(steps_of(result), plan + more[1:])


def check_up_until_three_obstacles(state, result):
    """Sense; up while the cell above is free and fewer than three obstacles are known, sensing
    after every move."""
    here = state.start_cell
    plan, known = [("sense", here)], set()
    while True:
        known |= {c for c in [here, *neighbours(state, here)] if state.truth[c] == OBSTACLE}
        if len(known) >= 3 or not free_cell(state, step_by(here, UP)):
            break
        here = step_by(here, UP)
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_goal_then_first_step(state, result):
    """Once a goal is revealed: a move onto a goal, then a move back to the first cell moved to
    (none if the move onto the goal was the first)."""
    steps, found = steps_of(result), first_goal_sense(state, result)
    if found is None:
        return "no goal was found"
    before = [c for kind, c in steps[:found] if kind == "navigate"]
    rest = steps[found + 1:]
    if not rest or rest[0][0] != "navigate" or state.truth[rest[0][1]] != GOAL:
        return f"after finding a goal it ran {rest[:3]}"
    return same_steps(rest, [rest[0]] + [("navigate", c) for c in before[:1]])


def check_goal_then_right_walk(state, result):
    """Once a goal is revealed: a move onto a goal, a sense there, then right while free,
    sensing after every move."""
    steps, found = steps_of(result), first_goal_sense(state, result)
    if found is None:
        return "no goal was found"
    rest = steps[found + 1:]
    if not rest or rest[0][0] != "navigate" or state.truth[rest[0][1]] != GOAL:
        return f"after finding a goal it ran {rest[:3]}"
    plan, _ = _walk(state, rest[0][1], RIGHT)
    return same_steps(rest, [rest[0]] + plan)


def check_lone_goal_or_home(state, result):
    """Nothing more to find; ends on the goal if exactly one is reachable, else at the start."""
    if not exhausted(state):
        return "stopped before everything was known"
    goals = _goals(state)
    want = goals[0] if len(goals) == 1 else state.start_cell
    return None if state.cell == want else f"ended in {state.cell}, not {want} ({goals})"


def check_calmest_neighbour(state, result):
    """A sense at the start first; a sense at every free cell next to the start; ends on one of
    those with the fewest obstacles next to it."""
    home, steps = state.start_cell, steps_of(result)
    free = free_neighbours(state, home)
    count = {n: _obstacles_beside(state, n) for n in free}
    if not steps or steps[0] != ("sense", home):
        return f"ran {steps[:2]}, not a sense at the start first"
    missed = [n for n in free if ("sense", n) not in steps]
    if missed:
        return f"never sensed at {missed}"
    if state.cell in count and count[state.cell] == min(count.values()):
        return None
    return f"ended in {state.cell}; obstacles next to the free neighbours: {count}"


def check_explore_then_goal_tour(state, result):
    """Once nothing more is to be found: only moves, one onto each reachable goal (any order),
    then one onto the start."""
    home = state.start_cell
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    rest = steps_of(result)[index + 1:]
    targets = [c for _, c in rest]
    if not rest or any(kind != "navigate" for kind, _ in rest) or targets[-1] != home \
            or sorted(targets[:-1]) != _goals(state):
        return f"after exploring it ran {rest[:8]}; the goals: {_goals(state)}"
    return None


def check_most_obstacles_spot(state, result):
    """Nothing more to find; ends on a cell it sensed from whose obstacles next to it are the
    most of all the cells it sensed from."""
    if not exhausted(state):
        return "stopped before everything was known"
    spots = [c for kind, c in steps_of(result) if kind == "sense"]
    most = max(_obstacles_beside(state, c) for c in spots)
    if state.cell in spots and _obstacles_beside(state, state.cell) == most:
        return None
    return f"ended in {state.cell}; the most obstacles a sense showed: {most}"


def check_five_scoops(state, result):
    n = len(scoops(result))
    return None if n == 5 and len(result.steps) == 5 else f"{n} scoop(s)"


def check_three_scoops_60g(state, result):
    n = len(scoops(result))
    if len(result.steps) != 3 or n != 3:
        return f"{n} scoop(s)"
    mass = grams_in_receiver(state)
    return None if mass >= 60 else f"{mass:.1f} g in the receiver"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)


_LINE = "primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and " \
        "sensed() == [start_cell()] + moves()"
_N = "[1, 2, 3, 4, 5, 6, 7, 8, 9]"  # the promises' language has no range()
_S0, _S1 = "start_cell()[0]", "start_cell()[1]"
_R = "((len(moves()) + final_cell()[0] - start_cell()[0]) // 2)"  # right moves, then left
_OBS = "len([m for m in neighbours({0}) if is_obstacle(m)])"  # obstacles next to a cell
_D = "abs(2 * {0}[0] - 9) + abs(2 * {0}[1] - 9)"  # twice the distance from the centre

TASKS = [
    _task("crowded_stay_else_step", 1, check_crowded_stay_else_step,
          "Sense once where you stand. If that shows obstacles on two or more of the cells "
          "next to you, stay where you are. Otherwise step onto any one of the free cells "
          "next to you. Then stop.",
          "all(sensed() == [s] and ((primitives() == ['sense']) if len(obs) >= 2 else "
          "(primitives() == ['sense', 'navigate'] and moves()[0] in neighbours(s) and not "
          "is_obstacle(moves()[0]))) for s in [start_cell()] for obs in [[n for n in "
          "neighbours(s) if is_obstacle(n)]])"),
    _task("centre_neighbour", 1, check_centre_neighbour,
          "Sense once, then move onto whichever free cell next to you is closest to the centre "
          "of the grid, the point (4.5, 4.5): the one with the smallest |i - 4.5| + |j - 4.5| "
          "(any of them if several tie). Then stop.",
          f"primitives() == ['sense', 'navigate'] and sensed() == [start_cell()] and moves()[0] "
          f"in neighbours(start_cell()) and not is_obstacle(moves()[0]) and "
          f"all({_D.format('moves()[0]')} <= {_D.format('n')} for n in neighbours(start_cell()) "
          f"if not is_obstacle(n))"),
    _task("four_fresh_cells", 1, check_four_fresh_cells,
          "Sense where you are, then make four moves, each onto a cell you have never stood in "
          "before, sensing right after each move, and stop after the fourth. Make fewer moves "
          "only if there is nothing more to find: every cell you can reach, and every cell next "
          "to one, is already known.",
          f"{_LINE} and len(moves()) <= 4 and all(moves()[k] not in [start_cell()] + "
          f"moves()[:k] for k in [0, 1, 2, 3][:len(moves())]) and (len(moves()) == 4 or "
          f"explored_all())"),
    _task("peek_again_if_no_goal", 1, check_peek_again_if_no_goal,
          "Sense once where you stand. If that shows a goal (on your cell or next to it), stop "
          "there without moving. If it shows no goal, step onto a free cell next to you, sense "
          "once more from there, and stop.",
          "primitives()[:1] == ['sense'] and sensed()[:1] == [start_cell()] and "
          "((primitives() == ['sense']) if any(is_goal(c) for c in [start_cell()] + "
          "neighbours(start_cell())) else (primitives() == ['sense', 'navigate', 'sense'] and "
          "moves()[0] in neighbours(start_cell()) and not is_obstacle(moves()[0]) and "
          "sensed()[1] == moves()[0]))"),
    _task("sweep_row", 2, check_sweep_row,
          "Sense where you are. Walk right (increasing i) one cell at a time while the next "
          "cell to the right is inside the grid and free. Then turn around and walk left "
          "(decreasing i) one cell at a time, back past your starting cell, while the next cell "
          "to the left is inside the grid and free. Sense after every single move, and stop "
          "when you cannot go left any more.",
          f"{_LINE} and moves() == [({_S0} + n, {_S1}) for n in {_N}][:{_R}] + [({_S0} + {_R} "
          f"- n, {_S1}) for n in {_N}][:len(moves()) - {_R}] and ({_S0} + {_R} == 9 or "
          f"is_obstacle(({_S0} + {_R} + 1, {_S1}))) and (final_cell()[0] == 0 or "
          "is_obstacle((final_cell()[0] - 1, final_cell()[1])))"),
    _task("up_until_three_obstacles", 2, check_up_until_three_obstacles,
          "Sense, then walk up (increasing j) one cell at a time, sensing after every move. "
          "Keep a tally of the distinct obstacles your senses have shown you so far, and stop "
          "as soon as it reaches three, or when the cell above you is outside the grid or an "
          "obstacle.",
          f"{_LINE} and moves() == [({_S0}, {_S1} + n) for n in {_N}][:len(moves())] and "
          "(len(known_obstacles()) >= 3 or final_cell()[1] == 9 or is_obstacle((final_cell()[0], "
          "final_cell()[1] + 1))) and len([c for c in known_before_last() if is_obstacle(c)]) < 3"),
    _task("goal_then_first_step", 2, check_goal_then_first_step,
          "Explore until you find a goal, and move onto it. Then go back to the cell that your "
          "very first move took you to, and stop there. If your very first move was the one "
          "onto the goal, just stop on the goal.",
          "(steps_after_goal() == 1 and primitives()[-1] == 'navigate' and len(moves()) == 1 "
          "and is_goal(moves()[0])) or (steps_after_goal() == 2 and primitives()[-2:] == "
          "['navigate', 'navigate'] and len(moves()) >= 3 and is_goal(moves()[-2]) and "
          "moves()[-1] == moves()[0])"),
    _task("goal_then_right_walk", 2, check_goal_then_right_walk,
          "Explore until you find a goal, move onto it and sense there. Then, starting from the "
          "goal, walk right (increasing i) one cell at a time while the next cell to the right "
          "is inside the grid and free, sensing after every move, and stop when you cannot go "
          "further right.",
          "steps_after_goal() >= 2 and all(steps_after_goal() == 2 * w and "
          "primitives()[-2 * w:] == ['navigate', 'sense'] * w and is_goal(g) and "
          "moves()[-w:] == [(g[0] + n, g[1]) for n in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]][:w] and "
          "sensed()[-w:] == moves()[-w:] and (final_cell()[0] == 9 or "
          "is_obstacle((final_cell()[0] + 1, final_cell()[1]))) for w in "
          "[steps_after_goal() // 2] for g in [moves()[-w]])"),
    _task("lone_goal_or_home", 2, check_lone_goal_or_home,
          "Explore everything you can reach, until there is nothing more to find. If that turned "
          "up exactly one goal, finish standing on that goal; if it turned up two or more, "
          "finish back at your starting cell.",
          "explored_all() and final_cell() == (reachable_goals()[0] if len(reachable_goals()) "
          "== 1 else start_cell())"),
    _task("calmest_neighbour", 3, check_calmest_neighbour,
          "Sense at your starting cell first. Then visit every free cell next to your start and "
          "sense once while standing on each. Finish standing on the one of those neighbouring "
          "cells that has the fewest obstacles directly next to it (the grid's edge does not "
          "count; any of them if several tie).",
          f"primitives()[:1] == ['sense'] and sensed()[:1] == [start_cell()] and final_cell() "
          f"in neighbours(start_cell()) and not is_obstacle(final_cell()) and all(is_obstacle(n) "
          f"or (n in sensed() and {_OBS.format('final_cell()')} <= {_OBS.format('n')}) for n in "
          f"neighbours(start_cell()))"),
    _task("explore_then_goal_tour", 3, check_explore_then_goal_tour,
          "First explore until you know every cell you can reach and every cell next to one. "
          "Then visit each goal you found with one move onto it, in any order, and finish with "
          "one move back to your starting cell. After the exploring, make no other moves and "
          "do not sense again.",
          "all(explored_all() and primitives()[-k - 2:] == ['sense'] + ['navigate'] * (k + 1) "
          "and sorted(moves()[-k - 1:-1]) == reachable_goals() and moves()[-1] == start_cell() "
          "and any(all(x not in [d] + neighbours(d) for d in sensed()[:-1]) for x in "
          "[sensed()[-1]] + neighbours(sensed()[-1])) for k in [len(reachable_goals())])"),
    _task("most_obstacles_spot", 3, check_most_obstacles_spot,
          "Explore everything you can reach, noting for each place you sense from how many "
          "obstacles are directly next to it (the grid's edge does not count). When there is "
          "nothing more to find, go back to a place you sensed from where that number was the "
          "largest (any of them if several tie), and stop there.",
          f"explored_all() and final_cell() in sensed() and all({_OBS.format('final_cell()')} "
          f">= {_OBS.format('c')} for c in sensed())"),
    _task("five_scoops", 1, check_five_scoops,
          "Scoop five times, one right after another, and stop after the fifth scoop.",
          "scoops() == 5", SCOOP),
    _task("three_scoops_60g", 2, check_three_scoops_60g,
          "Scoop exactly three times, so that the three scoops together put at least 60 grams "
          "of grains into the receiver.", "scoops() == 3 and delivered() >= 60", SCOOP),
]
