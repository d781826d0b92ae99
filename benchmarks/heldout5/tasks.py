"""Held-out tasks, fifth set: written before the next change of the synthesizer, run once after.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout5/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (a step down when one sense showed an
obstacle above, a step left when both sides of the row are free, a walk left until a goal comes
into sight and then onto it, a walk towards the far side of the grid, a walk down until an
obstacle is beside you, a walk down and then half of it back up, a search cut off after five
moves and then home, a stop once a goal and four obstacles are known together, a free cell next
to the goal never stood in, the place sensed from that is farthest from the goal found, the
lowest cell that can be reached, a goal kept as a base while exploring the rest) and two
scooping tasks (one with a bound on the grams spilled). Each has a reference behavior
(``references/``), a ground-truth ``check`` and a faithful ``promise`` over the env's outcome
helpers, so that the search can be measured apart from the model. They were written on
2026-12-05 without running the synthesizer on them; the first run of the search on them is the
evaluation, reported beside the development figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and
every cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a
sense labels its cell and the four around it (a goal is *in sight* when it is among them); the
obstacles *beside* a cell are those directly left or right of it; a cell *stood in* is the start
cell or one a move ended in. The start cell always has a free neighbour (a goal is reachable
from it and it holds none). The scooping checks weigh the grains at the end, as ``delivered()``
and ``spilled()`` do: those in the receiver, and those outside the receiver, the donor and the
spoon's tray. The scooping references, run with ``evaluate`` on episodes 0-19 of seed 0 before
the set was fixed, kept their promises and did their tasks on all 20: two scoops spilled 0 to
15.8 g (the bound is 25 g), four scoops left 106.3 to 178.7 g in the receiver (the bound is
90 g).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.synthesis_tasks import (distance, exhausted, first_goal_sense, first_reaching,
                                        free_cell, free_neighbours, grams_in_receiver,
                                        grams_spilled, held_out_task, moves, neighbours, reachable,
                                        same_steps, scoops, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP, DOWN = (1, 0), (-1, 0), (0, 1), (0, -1)


def _revealed(state, c) -> list[tuple[int, int]]:
    """The goals a sense at ``c`` shows."""
    return [x for x in [c, *neighbours(state, c)] if state.truth[x] == GOAL]


def _walk(state, start, step, stop=lambda here: False):
    """Sense at ``start``, then one move by ``step`` while ``stop(here)`` is false and the next
    cell is free, sensing after every move; the plan and the cell it ends in."""
    here, plan = start, [("sense", start)]
    while not stop(here) and free_cell(state, step_by(here, step)):
        here = step_by(here, step)
        plan += [("navigate", here), ("sense", here)]
    return plan, here


def _side_wall(state, c) -> bool:
    """Whether an obstacle lies directly left or right of ``c`` (inside the grid)."""
    return any(state.truth[n] == OBSTACLE for n in neighbours(state, c) if n[1] == c[1])


def _goal_step(state, rest) -> str | None:
    """None if ``rest`` (the steps after the first sense that showed a goal) begins with a move
    onto a goal."""
    if not rest or rest[0][0] != "navigate" or state.truth[rest[0][1]] != GOAL:
        return f"after finding a goal it ran {rest[:3]}"
    return None



# --- checks -------------------------------------------------------------------------------

def check_shy_of_obstacle_above(state, result):
    """One sense; a move onto the cell below the start if the cell above is an obstacle and the
    one below is free, else no move."""
    home, steps = state.start_cell, steps_of(result)
    above, below = step_by(home, UP), step_by(home, DOWN)
    blocked = above[1] < state.size and state.truth[above] == OBSTACLE
    if blocked and free_cell(state, below):
        return same_steps(steps, [("sense", home), ("navigate", below)])
    return same_steps(steps, [("sense", home)])


def check_left_if_row_open(state, result):
    """One sense; a move onto the cell left of the start if the cells left and right of it are
    both free, else no move."""
    home, steps = state.start_cell, steps_of(result)
    left, right = step_by(home, LEFT), step_by(home, RIGHT)
    if free_cell(state, left) and free_cell(state, right):
        return same_steps(steps, [("sense", home), ("navigate", left)])
    return same_steps(steps, [("sense", home)])


def check_left_to_sighted_goal(state, result):
    """Sense; left while no goal is in sight and the next cell is free, sensing after every
    move; then, if a goal is in sight, one move onto one of those goals."""
    plan, here = _walk(state, state.start_cell, LEFT, lambda c: bool(_revealed(state, c)))
    steps = steps_of(result)
    if not _revealed(state, here):
        return same_steps(steps, plan)
    if steps[:-1] == plan and steps[-1][0] == "navigate" and steps[-1][1] in _revealed(state, here):
        return None
    return f"ran {steps[-6:]}; the goals in sight at {here}: {_revealed(state, here)}"


def check_toward_far_side(state, result):
    """Sense; right while free if the start has i <= 4, else left while free, sensing after
    every move."""
    home = state.start_cell
    plan, _ = _walk(state, home, RIGHT if home[0] <= 4 else LEFT)
    return same_steps(steps_of(result), plan)


def check_down_until_side_wall(state, result):
    """Sense; down while no obstacle is directly left or right and the cell below is free,
    sensing after every move."""
    plan, _ = _walk(state, state.start_cell, DOWN, lambda c: _side_wall(state, c))
    return same_steps(steps_of(result), plan)


def check_down_and_halfway_back(state, result):
    """Sense; down while free (d moves), then d // 2 moves up, sensing after every move."""
    plan, here = _walk(state, state.start_cell, DOWN)
    down = state.start_cell[1] - here[1]
    for _ in range(down // 2):
        here = step_by(here, UP)
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_five_move_search_home(state, result):
    """Sense; moves, each followed by a sense where it ended, until a sense shows a goal for the
    first time or five moves are made; then at most one move, onto the start, ending there."""
    home, steps = state.start_cell, steps_of(result)
    back = 1 if steps and steps[-1][0] == "navigate" else 0
    body, targets = steps[:len(steps) - back], moves(result)[:len(moves(result)) - back]
    if body != [("sense", home)] + [x for c in targets for x in (("navigate", c), ("sense", c))]:
        return f"ran {steps[:10]}: not a sense first and after every move"
    if len(targets) > 5:
        return f"searched with {len(targets)} moves"
    if (back and steps[-1][1] != home) or state.cell != home:
        return f"ended in {state.cell}, not the start {home}"
    found = first_goal_sense(state, result)
    if found == len(body) - 1 or (found is None and len(targets) == 5):
        return None
    return f"stopped searching after {len(targets)} move(s); a goal first in sight at step {found}"


def check_goal_and_four_obstacles(state, result):
    """Exploring stops with the sense after which a goal and four obstacles are known, or
    nothing more is to be found, whichever comes first."""
    def enough(known):
        return bool((known & (state.truth == GOAL)).any()) and \
            int((known & (state.truth == OBSTACLE)).sum()) >= 4 or exhausted(state, known)
    index = first_reaching(state, result, enough)
    if index is None:
        return "neither a goal and four obstacles known nor everything explored"
    return same_steps(steps_of(result)[index + 1:], [])


def check_goal_then_farthest_look(state, result):
    """Once a goal is in sight: a move onto a goal, then a move onto a cell sensed from with the
    greatest |di| + |dj| from that goal; nothing else."""
    steps, found = steps_of(result), first_goal_sense(state, result)
    if found is None:
        return "no goal was found"
    rest = steps[found + 1:]
    wrong = _goal_step(state, rest)
    if wrong:
        return wrong
    goal, spots = rest[0][1], [c for kind, c in steps[:found + 1] if kind == "sense"]
    far = max(distance(goal, c) for c in spots)
    if len(rest) == 2 and rest[1][0] == "navigate" and rest[1][1] in spots \
            and distance(goal, rest[1][1]) == far:
        return None
    return f"after the goal {goal} it ran {rest[1:4]}; sensed from {spots}"


def check_lowest_reachable_cell(state, result):
    """Nothing more to find; ends on a reachable cell with the smallest j."""
    if not exhausted(state):
        return "stopped before everything was known"
    low = min(int(j) for _, j in np.argwhere(reachable(state)))
    here = state.cell
    if reachable(state)[here] and here[1] == low:
        return None
    return f"ended in {here}; the lowest reachable row is j = {low}"


def check_goal_base_explore_rest(state, result):
    """Once a goal is in sight: a move onto a goal; then nothing more to find, and ends on that
    goal."""
    steps, found = steps_of(result), first_goal_sense(state, result)
    if found is None:
        return "no goal was found"
    rest = steps[found + 1:]
    wrong = _goal_step(state, rest)
    if wrong:
        return wrong
    if not exhausted(state):
        return "stopped before everything was known"
    return None if state.cell == rest[0][1] else f"ended in {state.cell}, not {rest[0][1]}"


def check_goal_then_fresh_neighbour(state, result):
    """Once a goal is in sight: a move onto a goal and a sense there; then a move onto a free
    cell next to it never stood in, if there is one, else nothing."""
    steps, found = steps_of(result), first_goal_sense(state, result)
    if found is None:
        return "no goal was found"
    rest = steps[found + 1:]
    wrong = _goal_step(state, rest)
    if wrong:
        return wrong
    goal = rest[0][1]
    stood = [state.start_cell] + [c for kind, c in steps[:found] if kind == "navigate"]
    fresh = [n for n in free_neighbours(state, goal) if n not in stood]
    if rest[1:2] != [("sense", goal)]:
        return f"after moving onto the goal it ran {rest[1:3]}"
    if not fresh:
        return same_steps(rest, rest[:2])
    if len(rest) == 3 and rest[2][0] == "navigate" and rest[2][1] in fresh:
        return None
    return f"after the goal {goal} it ran {rest[2:4]}; the fresh cells next to it: {fresh}"


def check_two_scoops_tidy(state, result):
    n = len(scoops(result))
    if len(result.steps) != 2 or n != 2:
        return f"{n} scoop(s)"
    spilled = grams_spilled(state)
    return None if spilled <= 25 else f"{spilled:.1f} g spilled"


def check_four_scoops_90g(state, result):
    n = len(scoops(result))
    if len(result.steps) != 4 or n != 4:
        return f"{n} scoop(s)"
    mass = grams_in_receiver(state)
    return None if mass >= 90 else f"{mass:.1f} g in the receiver"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)


_LINE = "primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and " \
        "sensed() == [start_cell()] + moves()"
_N = "[1, 2, 3, 4, 5, 6, 7, 8, 9]"  # the promises' language has no range()
_S0, _S1 = "start_cell()[0]", "start_cell()[1]"
_SIDE = "(({0}[0] > 0 and is_obstacle(({0}[0] - 1, {0}[1]))) or ({0}[0] < 9 and " \
        "is_obstacle(({0}[0] + 1, {0}[1]))))"  # an obstacle directly left or right
_FAR = "abs({0}[0] - g[0]) + abs({0}[1] - g[1])"  # steps from the goal g, obstacles ignored
# d moves down and d // 2 up make d + d // 2 moves, so d = (2 * len(moves()) + 2) // 3 (a
# count no d makes gives a d whose moves differ in number: the promise then fails)

TASKS = [
    _task("shy_of_obstacle_above", 1, check_shy_of_obstacle_above,
          "Sense once where you stand. If the cell directly above you (j + 1) turns out to be an "
          "obstacle, move one cell down (j - 1), as long as that cell is inside the grid and "
          "not an obstacle. In every other case do not move. Then stop.",
          f"sensed() == [start_cell()] and ((primitives() == ['sense', 'navigate'] and moves() "
          f"== [({_S0}, {_S1} - 1)]) if {_S1} < 9 and is_obstacle(({_S0}, {_S1} + 1)) and {_S1} "
          f"> 0 and not is_obstacle(({_S0}, {_S1} - 1)) else primitives() == ['sense'])"),
    _task("left_if_row_open", 1, check_left_if_row_open,
          "Look around once. When the cells on both sides of you in your row, to your left "
          "(i - 1) and to your right (i + 1), both lie inside the grid and hold no obstacle, "
          "take one step to the left. Otherwise remain where you are. Then stop.",
          f"sensed() == [start_cell()] and ((primitives() == ['sense', 'navigate'] and moves() "
          f"== [({_S0} - 1, {_S1})]) if {_S0} > 0 and {_S0} < 9 and not is_obstacle(({_S0} - 1, "
          f"{_S1})) and not is_obstacle(({_S0} + 1, {_S1})) else primitives() == ['sense'])"),
    _task("left_to_sighted_goal", 2, check_left_to_sighted_goal,
          "Sense, then head left (decreasing i) one cell at a time, sensing after every move, "
          "until a sense shows you a goal on your cell or right next to it. As soon as you see "
          "one, step onto it and stop. If the cell to your left is outside the grid or an "
          "obstacle before any goal has come into view, stop there instead.",
          f"all(primitives() == ['sense'] + ['navigate', 'sense'] * k + ['navigate'] * g and "
          f"sensed() == [start_cell()] + moves()[:k] and moves()[:k] == [({_S0} - n, {_S1}) "
          f"for n in {_N}][:k] and ((steps_after_goal() == 1 and is_goal(final_cell()) and "
          f"final_cell() in neighbours(sensed()[-1])) if g else (final_cell()[0] == 0 or "
          f"is_obstacle((final_cell()[0] - 1, final_cell()[1])))) for g in [1 if goal_found() "
          f"else 0] for k in [len(moves()) - g])"),
    _task("toward_far_side", 2, check_toward_far_side,
          "Sense where you are. If you start in the left half of the grid (i is 4 or less), walk "
          "right (increasing i); if you start in the right half (i is 5 or more), walk left "
          "(decreasing i). Go one cell at a time, sensing after every move, while the next cell "
          "that way is inside the grid and free, and stop when it is not.",
          f"all({_LINE} and moves() == [({_S0} + d * n, {_S1}) for n in {_N}][:len(moves())] "
          f"and (final_cell()[0] + d < 0 or final_cell()[0] + d > 9 or "
          f"is_obstacle((final_cell()[0] + d, final_cell()[1]))) for d in [1 if {_S0} <= 4 "
          f"else -1])"),
    _task("down_until_side_wall", 2, check_down_until_side_wall,
          "Sense, then go down (decreasing j) one cell at a time, sensing after each move, until "
          "you stand beside an obstacle: one directly to your left (i - 1) or to your right "
          "(i + 1). Also stop if the cell below you is outside the grid or an obstacle.",
          f"{_LINE} and moves() == [({_S0}, {_S1} - n) for n in {_N}][:len(moves())] and not "
          f"any({_SIDE.format('c')} for c in sensed()[:-1]) and ({_SIDE.format('final_cell()')} "
          f"or final_cell()[1] == 0 or is_obstacle((final_cell()[0], final_cell()[1] - 1)))"),
    _task("five_move_search_home", 2, check_five_move_search_home,
          "Search for a goal, but give up after five moves: sense where you are, then keep "
          "moving and sensing again until a sense shows you a goal or you have made five moves "
          "(and sensed after the fifth). Then go straight back to your starting cell with a "
          "single move and stop (if you are already standing on it, you may just stop).",
          "all(primitives() == ['sense'] + ['navigate', 'sense'] * k + ['navigate'] * r and "
          "sensed() == [start_cell()] + moves()[:k] and k <= 5 and final_cell() == start_cell() "
          "and (steps_after_goal() == r or (steps_after_goal() == -1 and k == 5)) for r in [1 if "
          "primitives()[-1] == 'navigate' else 0] for k in [len(moves()) - r])"),
    _task("goal_and_four_obstacles", 2, check_goal_and_four_obstacles,
          "Keep exploring until you have seen at least one goal and, on top of that, at least "
          "four obstacles; stop right after the sense that makes both of these true. If nothing "
          "more can be found before that happens, stop then.",
          "primitives()[-1] == 'sense' and ((goal_found() and len(known_obstacles()) >= 4) or "
          "explored_all()) and len(known_before_last()) < len(known_cells()) and not "
          "(any(is_goal(c) for c in known_before_last()) and len([c for c in known_before_last() "
          "if is_obstacle(c)]) >= 4)"),
    _task("goal_then_fresh_neighbour", 2, check_goal_then_fresh_neighbour,
          "Explore until you find a goal, step onto it and sense there. Then move onto a free "
          "cell next to that goal where you have never been: not your starting cell and not any "
          "cell one of your moves ended in. If there is no such cell, just stop on the goal.",
          "moves_after_goal()[:1] != [] and all(is_goal(a[0]) and len(a) <= 2 and "
          "steps_after_goal() == len(a) + 1 and primitives()[-len(a) - 1:] == ['navigate', "
          "'sense'] + ['navigate'] * (len(a) - 1) and sensed()[-1] == a[0] and ((len(a) == 2 and "
          "a[1] in fresh) if fresh else len(a) == 1) for a in [moves_after_goal()] for fresh in "
          "[[x for x in neighbours(a[0]) if not is_obstacle(x) and x not in [start_cell()] + "
          "moves()[:len(moves()) - len(a)]]])"),
    _task("down_and_halfway_back", 3, check_down_and_halfway_back,
          "Sense, then walk down (decreasing j) one cell at a time while the cell below you is "
          "inside the grid and free, counting your moves. Then walk back up (increasing j) half "
          "as many cells as you went down, rounded down (after 5 moves down, 2 moves up). Sense "
          "after every move, and stop when the climb back is done.",
          f"all({_LINE} and moves() == [({_S0}, {_S1} - n) for n in {_N}][:d] + [({_S0}, {_S1} - "
          f"d + n) for n in {_N}][:d // 2] and ({_S1} - d == 0 or is_obstacle(({_S0}, {_S1} - d "
          f"- 1))) for d in [(2 * len(moves()) + 2) // 3])"),
    _task("goal_then_farthest_look", 3, check_goal_then_farthest_look,
          "Explore until you spot a goal, and move onto it. Then go to whichever of the places "
          "you sensed from is farthest from that goal, counting steps along rows and columns "
          "and ignoring obstacles (any of them if several tie), and stop there.",
          f"steps_after_goal() == 2 and primitives()[-2:] == ['navigate', 'navigate'] and "
          f"all(is_goal(g) and final_cell() in sensed() and all({_FAR.format('final_cell()')} "
          f">= {_FAR.format('c')} for c in sensed()) for g in [moves()[-2]])"),
    _task("lowest_reachable_cell", 3, check_lowest_reachable_cell,
          "Explore until there is nothing more to find. Then travel to the lowest free cell you "
          "are able to reach, the one with the smallest j (any of them if several tie), and "
          "stop there.",
          "explored_all() and final_cell() in reachable_cells() and all(final_cell()[1] <= c[1] "
          "for c in reachable_cells())"),
    _task("goal_base_explore_rest", 3, check_goal_base_explore_rest,
          "Find a goal and step onto it as soon as you see it. Then, using that goal as your "
          "base, carry on exploring until there is nothing more to find, and finish by going "
          "back to that same goal and stopping on it.",
          "steps_after_goal() >= 1 and primitives()[-steps_after_goal()] == 'navigate' and "
          "all(is_goal(g) and explored_all() and final_cell() == g for g in "
          "moves_after_goal()[:1])"),
    _task("two_scoops_tidy", 2, check_two_scoops_tidy,
          "Scoop twice and then stop, without spilling more than 25 grams of grains outside "
          "the two containers.", "scoops() == 2 and spilled() <= 25", SCOOP),
    _task("four_scoops_90g", 2, check_four_scoops_90g,
          "Make four scoops in a row, so that together they put at least 90 grams of grains "
          "into the receiver, then stop.", "scoops() == 4 and delivered() >= 90", SCOOP),
]
