"""Held-out tasks, sixth set: written before the next change of the synthesizer, run once after.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout6/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (a step straight away from an obstacle
next to the start, or else onto any free neighbour; a step along the roomier of the row and the
column; a look from the cell above that decides a return; a tour of the start's free neighbours
in a given order; a walk round a small square; a search that stops after three senses showing no
obstacle; a stop on a tally of obstacles in the start's column; a goal taken only if it was seen
within four moves, else home; a climb that keeps getting farther from the start; a search that
comes home after every look; after exploring, the first place away from the start where a sense
showed two obstacles next to it; a stop on entering a fourth row) and two scooping tasks (one
bounding the number of scoops beside the grams delivered, one bounding the grams spilled by a
fraction of those delivered). Each has a reference behavior (``references/``), a ground-truth
``check`` and a faithful ``promise`` over the env's outcome helpers, so that the search can be
measured apart from the model. They were written on 2026-12-06 without running the synthesizer
on them; the first run of the search on them is the evaluation, reported beside the development
figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and
every cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a
*row* is the cells of one j, a *column* those of one i; a sense labels its cell and the four
around it (a goal is *in sight* when it is among them; a sense *shows no obstacle* when none of
them is one); the obstacles *next to* a cell are those among its four neighbours inside the grid
(the grid's edge does not count); a cell *stood in* is the start cell or one a move ended in;
the *distance* of two cells counts steps along rows and columns (|di| + |dj|), obstacles
ignored. The start cell always has a free neighbour (a goal is reachable from it and it holds
none). The scooping checks weigh the grains at the end, as ``delivered()`` and ``spilled()`` do:
those in the receiver, and those outside the receiver, the donor and the spoon's tray. The
scooping references, run with ``evaluate`` on episodes 0-19 of seed 0 before the set was fixed,
kept their promises and did their tasks on all 20: three scoops left 88.2 to 140.2 g in the
receiver (the bound is 70 g; one scoop alone left 33.9 to 58.8 g), two scoops delivered 61.1 to
104.0 g and spilled 0 to 15.8 g, each episode delivering at least 4.1 times what it spilled (the
bound is 3 times).
"""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (distance, exhausted, first_goal_sense, first_reaching,
                                        free_cell, free_neighbours, grams_in_receiver,
                                        grams_spilled, held_out_task, moves, neighbours, same_steps,
                                        scoops, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP, DOWN = (1, 0), (-1, 0), (0, 1), (0, -1)


def _obstacles_beside(state, c) -> list[tuple[int, int]]:
    return [n for n in neighbours(state, c) if state.truth[n] == OBSTACLE]


def _clear(state, c) -> bool:
    """Whether a sense at ``c`` shows no obstacle."""
    return not any(state.truth[x] == OBSTACLE for x in [c, *neighbours(state, c)])


def _sensing_line(state, result) -> str | None:
    """None if the episode is a sense at the start, then moves each followed by a sense where it
    ended."""
    steps = steps_of(result)
    want = [("sense", state.start_cell)] + [x for c in moves(result)
                                            for x in (("navigate", c), ("sense", c))]
    return same_steps(steps, want)


def _sense(state, known, step) -> None:
    if step[0] == "sense":
        for n in [step[1], *neighbours(state, step[1])]:
            known[n] = True



# --- checks -------------------------------------------------------------------------------

def check_step_away_from_obstacle(state, result):
    """One sense; then one move: onto a free cell across the start from an obstacle next to it
    if there is one, else onto any free cell next to the start."""
    home, steps = state.start_cell, steps_of(result)
    away = [(2 * home[0] - o[0], 2 * home[1] - o[1]) for o in _obstacles_beside(state, home)]
    away = [c for c in away if free_cell(state, c)]
    targets = away or free_neighbours(state, home)
    if len(steps) == 2 and steps[0] == ("sense", home) and steps[1][0] == "navigate" \
            and steps[1][1] in targets:
        return None
    return f"ran {steps[:4]}; the cells across from an obstacle: {away}"


def check_roomier_axis_step(state, result):
    """One sense; a move onto a free cell left or right of the start if at least as many of
    those two are free as of the two above and below, else onto a free one above or below."""
    home, steps = state.start_cell, steps_of(result)
    row = [n for n in free_neighbours(state, home) if n[1] == home[1]]
    column = [n for n in free_neighbours(state, home) if n[0] == home[0]]
    side = row if len(row) >= len(column) else column
    if len(steps) == 2 and steps[0] == ("sense", home) and steps[1][0] == "navigate" \
            and steps[1][1] in side:
        return None
    return f"ran {steps[:4]}; free in the row {row}, in the column {column}"


def check_up_peek_retreat(state, result):
    """One sense; if the cell above the start is inside the grid and free, a move onto it and a
    sense there, then a move back onto the start if the cell above that is outside the grid or
    an obstacle; else nothing after the first sense."""
    home, steps = state.start_cell, steps_of(result)
    up = step_by(home, UP)
    if not free_cell(state, up):
        return same_steps(steps, [("sense", home)])
    want = [("sense", home), ("navigate", up), ("sense", up)]
    if not free_cell(state, step_by(up, UP)):
        want.append(("navigate", home))
    return same_steps(steps, want)


def check_ordered_neighbour_tour(state, result):
    """One sense; then one move onto each free cell next to the start, in the order right, up,
    left, down; nothing else."""
    home = state.start_cell
    tour = [c for c in (step_by(home, step) for step in (RIGHT, UP, LEFT, DOWN)) if free_cell(state, c)]
    return same_steps(steps_of(result), [("sense", home)] + [("navigate", c) for c in tour])


def check_little_square(state, result):
    """Sense; then right, up, left, down (back onto the start), sensing after every move, while
    the next cell of that pattern is inside the grid and free."""
    here, plan = state.start_cell, [("sense", state.start_cell)]
    for step in (RIGHT, UP, LEFT, DOWN):
        if not free_cell(state, step_by(here, step)):
            break
        here = step_by(here, step)
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_three_clear_looks(state, result):
    """Exploring stops with the third sense that showed no obstacle, or with the sense after
    which nothing more is to be found, whichever comes first."""
    steps = steps_of(result)
    known = state.truth != state.truth  # nothing known before the first step
    clear = 0
    for index, step in enumerate(steps):
        _sense(state, known, step)
        if step[0] != "sense":
            continue
        clear += _clear(state, step[1])
        if clear == 3 or exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return f"{clear} sense(s) showed no obstacle and more could be found"


def check_two_obstacles_in_start_column(state, result):
    """Exploring stops with the sense after which two obstacles in the start's column are known,
    or nothing more is to be found, whichever comes first."""
    column = state.start_cell[0]

    def enough(known):
        return int((known & (state.truth == OBSTACLE))[column].sum()) >= 2 or \
            exhausted(state, known)
    index = first_reaching(state, result, enough)
    if index is None:
        return "neither two obstacles known in the start's column nor everything explored"
    return same_steps(steps_of(result)[index + 1:], [])


def check_quick_find_or_home(state, result):
    """Once a goal is in sight: one move, onto a goal if at most four moves came before that
    sense, else onto the start; nothing else."""
    steps, found = steps_of(result), first_goal_sense(state, result)
    if found is None:
        return "no goal was found"
    before = sum(kind == "navigate" for kind, _ in steps[:found])
    rest = steps[found + 1:]
    if before > 4:
        return same_steps(rest, [("navigate", state.start_cell)])
    if len(rest) == 1 and rest[0][0] == "navigate" and state.truth[rest[0][1]] == GOAL:
        return None
    return f"found a goal after {before} move(s), then ran {rest[:3]}"


def check_climb_away_from_start(state, result):
    """Sense; then moves, each onto a free cell next to the last one farther from the start and
    followed by a sense there, until no free cell next to the agent is farther."""
    home = state.start_cell
    wrong = _sensing_line(state, result)
    if wrong:
        return wrong
    stood = [home, *moves(result)]
    for before, after in zip(stood, stood[1:]):
        if after not in neighbours(state, before) or \
                distance(after, home) != distance(before, home) + 1:
            return f"moved from {before} to {after}, not one step farther from {home}"
    here = stood[-1]
    farther = [n for n in free_neighbours(state, here) if distance(n, home) > distance(here, home)]
    return f"stopped in {here} beside {farther}, farther from the start" if farther else None


def check_hub_search(state, result):
    """A sense at the start; then rounds of a move onto a cell other than the start, a sense
    there and a move back onto the start, until a sense has shown a goal; nothing after it (and
    the move home that follows it)."""
    home, steps = state.start_cell, steps_of(result)
    if steps[:1] != [("sense", home)] or (len(steps) - 1) % 3:
        return f"ran {steps[:7]}: not a sense at the start and rounds of three"
    for k in range(1, len(steps), 3):
        spot = steps[k][1]
        if spot == home or steps[k:k + 3] != [("navigate", spot), ("sense", spot),
                                              ("navigate", home)]:
            return f"a round ran {steps[k:k + 3]}"
    found = first_goal_sense(state, result)
    if found is not None and found == max(len(steps) - 2, 0):
        return None
    return f"a goal first in sight at step {found}; the episode has {len(steps)} steps"


def check_first_crowded_look(state, result):
    """Nothing more to find; ends on the first cell other than the start sensed from with two or
    more obstacles next to it, or on the start if there is none."""
    if not exhausted(state):
        return "stopped before everything was known"
    spots = [c for kind, c in steps_of(result) if kind == "sense"]
    crowded = [c for c in spots
               if c != state.start_cell and len(_obstacles_beside(state, c)) >= 2]
    want = (crowded + [state.start_cell])[0]
    return None if state.cell == want else f"ended in {state.cell}, not {want}"


def check_four_rows_visited(state, result):
    """Exploring stops with the move after which the cells stood in cover four rows, or with the
    sense after which nothing more is to be found, whichever comes first."""
    steps = steps_of(result)
    known = state.truth != state.truth
    rows = {state.start_cell[1]}
    for index, step in enumerate(steps):
        _sense(state, known, step)
        if step[0] == "navigate":
            rows.add(step[1][1])
        if len(rows) >= 4 or (step[0] == "sense" and exhausted(state, known)):
            return same_steps(steps[index + 1:], [])
    return f"stood in rows {sorted(rows)} and more could be found"


def check_at_most_three_scoops_70g(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 3:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass = grams_in_receiver(state)
    return None if mass >= 70 else f"{mass:.1f} g in the receiver"


def check_two_scoops_threefold_clean(state, result):
    n = len(scoops(result))
    if len(result.steps) != 2 or n != 2:
        return f"{n} scoop(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if mass >= 3 * spilled else f"{mass:.1f} g delivered, {spilled:.1f} g spilled"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)


_LINE = "primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and " \
        "sensed() == [start_cell()] + moves()"
_S0, _S1 = "start_cell()[0]", "start_cell()[1]"
_K = "[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17]"  # no range()
_D = "(abs({0}[0] - start_cell()[0]) + abs({0}[1] - start_cell()[1]))"  # from the start
_FRESH = "len(known_before_last()) < len(known_cells())"  # the last step labelled something
_SQUARE = f"[({_S0} + 1, {_S1}), ({_S0} + 1, {_S1} + 1), ({_S0}, {_S1} + 1), ({_S0}, {_S1})]"
_TOUR = "[n for n in [(s[0] + 1, s[1]), (s[0], s[1] + 1), (s[0] - 1, s[1]), (s[0], s[1] - 1)] " \
        "if n in neighbours(s) and not is_obstacle(n)]"

TASKS = [
    _task("step_away_from_obstacle", 1, check_step_away_from_obstacle,
          "Sense once. If one of the cells next to you is an obstacle, step directly away from "
          "it: move onto the cell on the opposite side of you, as long as that cell is inside "
          "the grid and not an obstacle (with several obstacles around you, any one that "
          "leaves such a cell will do). If no obstacle allows this, step onto any free cell "
          "next to you instead. Then stop.",
          "all(sensed() == [s] and primitives() == ['sense', 'navigate'] and (moves()[0] in ops "
          "if ops else moves()[0] in neighbours(s) and not is_obstacle(moves()[0])) for s in "
          "[start_cell()] for ops in "
          "[[(2 * s[0] - n[0], 2 * s[1] - n[1]) for n in neighbours(s) if is_obstacle(n) and "
          "(2 * s[0] - n[0], 2 * s[1] - n[1]) in neighbours(s) and not is_obstacle((2 * s[0] - "
          "n[0], 2 * s[1] - n[1]))]])"),
    _task("roomier_axis_step", 1, check_roomier_axis_step,
          "Take one look around. Count how many of the two cells beside you in your row (left "
          "and right) are free, and how many of the two in your column (above and below). "
          "Step onto a free cell along whichever of the two has more free cells, and along "
          "your row if the counts are the same. Then stop.",
          "all(sensed() == [s] and primitives() == ['sense', 'navigate'] and moves()[0] in "
          "neighbours(s) and not is_obstacle(moves()[0]) and (moves()[0][1] == s[1] if d >= 0 "
          "else moves()[0][0] == s[0]) for s in [start_cell()] for d in [sum([1 if n[1] == s[1] "
          "else -1 for n in neighbours(s) if not is_obstacle(n)])])"),
    _task("up_peek_retreat", 2, check_up_peek_retreat,
          "Sense where you start. If the cell just above you (j + 1) is inside the grid and "
          "free, climb onto it and sense again. If that second look shows the next cell up is "
          "an obstacle, or there is no next cell because you reached the top edge, go back "
          "down to your starting cell; otherwise stay where you are. If you could not climb at "
          "all, stop after the first sense.",
          "all(sensed()[:1] == [s] and ((primitives() == ['sense', 'navigate', 'sense'] + "
          "['navigate'] * b and moves() == [u] + [s] * b and sensed() == [s, u] and b == (1 if "
          "u[1] == 9 or is_obstacle((u[0], u[1] + 1)) else 0)) if s[1] < 9 and not "
          "is_obstacle(u) else primitives() == ['sense']) for s in [start_cell()] for u in "
          "[(s[0], s[1] + 1)] for b in [len(moves()) - 1])"),
    _task("ordered_neighbour_tour", 2, check_ordered_neighbour_tour,
          "Sense once at your starting cell. Then visit the cells around your start in this "
          "order: the one to the right (i + 1), the one above (j + 1), the one to the left "
          "(i - 1), the one below (j - 1). Move straight from each to the next, without "
          "sensing, and skip any that is an obstacle or off the grid. Stop on the last one "
          "you visit.",
          f"all(primitives() == ['sense'] + ['navigate'] * len(f) and sensed() == [s] and "
          f"moves() == f for s in [start_cell()] for f in [{_TOUR}])"),
    _task("little_square", 2, check_little_square,
          "Sense, then walk a small square: one cell right (i + 1), one cell up (j + 1), one "
          "cell left (i - 1) and one cell down (j - 1), which brings you back to your start. "
          "Sense after each of these moves. If the next move of the square would leave the "
          "grid or run into an obstacle, stop where you are instead.",
          f"{_LINE} and moves() == {_SQUARE}[:len(moves())] and (len(moves()) == 4 or all(c[0] "
          f"> 9 or c[1] > 9 or is_obstacle(c) for c in [{_SQUARE}[len(moves())]]))"),
    _task("three_clear_looks", 2, check_three_clear_looks,
          "Explore, sensing after every move, and keep count of the senses that show no "
          "obstacle at all, neither on your cell nor on any cell next to it. Stop right after "
          "the third such sense. If there is nothing more to find before that, stop right "
          "after the sense that leaves nothing more to find.",
          f"all(primitives()[-1] == 'sense' and ((sum(f) == 3 and f[-1] == 1 and ({_FRESH} or "
          f"not explored_all())) or (sum(f) < 3 and explored_all() and {_FRESH})) for f in [[0 "
          f"if any(is_obstacle(x) for x in neighbours(c)) else 1 for c in sensed()]])"),
    _task("two_obstacles_in_start_column", 2, check_two_obstacles_in_start_column,
          "Explore until you have discovered two obstacles in the column you started in (cells "
          "with the same i as your starting cell), and stop right after the sense that reveals "
          "the second of them. If there is nothing more to find before that, stop once there "
          "is nothing more to find.",
          f"primitives()[-1] == 'sense' and {_FRESH} and (len([c for c in known_obstacles() if "
          f"c[0] == {_S0}]) >= 2 or explored_all()) and len([c for c in known_before_last() if "
          f"c[0] == {_S0} and is_obstacle(c)]) < 2"),
    _task("quick_find_or_home", 2, check_quick_find_or_home,
          "Search for a goal. If a sense shows you one after no more than four moves, step "
          "onto that goal and stop. If it took you more than four moves to see a goal, do not "
          "go to it: head straight back to your starting cell with one move and stop there.",
          "steps_after_goal() == 1 and primitives()[-1] == 'navigate' and (is_goal(final_cell()) "
          "if len(moves()) <= 5 else final_cell() == start_cell())"),
    _task("climb_away_from_start", 3, check_climb_away_from_start,
          "Sense, then keep stepping to a free cell right next to you that is farther from "
          "your starting cell than where you stand (counting steps along rows and columns), "
          "any one of them if several are, sensing after every step. Stop when none of the "
          "cells next to you is both free and farther away.",
          f"{_LINE} and all(sensed()[k + 1] in neighbours(sensed()[k]) and "
          f"{_D.format('sensed()[k + 1]')} == {_D.format('sensed()[k]')} + 1 for k in "
          f"{_K}[:len(moves())]) and not any(not is_obstacle(n) and {_D.format('n')} > "
          f"{_D.format('final_cell()')} for n in neighbours(final_cell()))"),
    _task("hub_search", 3, check_hub_search,
          "Search for a goal, treating your starting cell as a hub: sense at the start, then "
          "repeatedly go out to some other cell, sense there, and come straight back to the "
          "start. Keep doing rounds like this until one of your senses has shown you a goal, "
          "and finish at your starting cell.",
          "goal_found() and primitives() == ['sense'] + ['navigate', 'sense', 'navigate'] * "
          "(len(moves()) // 2) and sensed() == [start_cell()] + moves()[0::2] and all(c == "
          "start_cell() for c in moves()[1::2]) and start_cell() not in moves()[0::2] and "
          "steps_after_goal() == (1 if moves() else 0)"),
    _task("first_crowded_look", 3, check_first_crowded_look,
          "Explore until there is nothing more to find. Remember the first place you sensed "
          "from, other than your starting cell, that had obstacles on two or more of the cells "
          "right next to it; once the exploring is over, go back there and stop. If no such "
          "place came up, go back to your starting cell.",
          "explored_all() and final_cell() == ([c for c in sensed() if c != start_cell() and "
          "len([n for n in neighbours(c) if is_obstacle(n)]) >= 2] + [start_cell()])[0]"),
    _task("four_rows_visited", 3, check_four_rows_visited,
          "Explore, and stop the moment a move puts you in a fourth different row, that is "
          "once the cells you have stood in, your start included, cover four different values "
          "of j. If there is nothing more to find before that, stop right after the sense that "
          "leaves nothing more to find.",
          f"all(len([r for r in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9] if r in js]) in ([4] if "
          f"primitives()[-1] == 'navigate' else [1, 2, 3]) and ((primitives()[-1] == 'navigate' "
          f"and not explored_all() and js[-1] not in js[:-1]) or (primitives()[-1] == 'sense' "
          f"and explored_all() and {_FRESH})) for js in [[c[1] for c in [start_cell()] + "
          f"moves()]])"),
    _task("at_most_three_scoops_70g", 2, check_at_most_three_scoops_70g,
          "Get at least 70 grams of grains into the receiver using no more than three scoops "
          "(at least one), then stop.", "scoops() >= 1 and scoops() <= 3 and delivered() >= 70",
          SCOOP),
    _task("two_scoops_threefold_clean", 2, check_two_scoops_threefold_clean,
          "Scoop two times. The grains you deliver into the receiver must weigh at least three "
          "times as much as the grains you spill outside the containers.",
          "scoops() == 2 and delivered() >= 3 * spilled()", SCOOP),
]
