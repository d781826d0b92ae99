"""Held-out tasks, eighteenth set: written before the next change of the synthesizer, run once
after it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout18/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (after exploring, onto the reachable cell of
the start's column farthest from the start; exploring that stops once 13 cells of the start's
quarter of the grid are known; a walk up, then back to its narrowest cell, the one with the most
obstacles beside it in its row; after exploring, a tour of the goals from the lowest to the highest,
then home; once a goal is in view, onto it if it lies beside the agent in its row, else home; after
exploring, onto the reachable cell with an obstacle right above it nearest the start, else home;
after exploring, back to where the sense that first showed a goal was taken; exploring that stops
with the fourth move of three or more steps; exploring that stops once a free cell six or more steps
from the start is known; once a goal is in view, back to the lowest place sensed from, then onto the
goal; once a goal is in view, home if more than half of the senses showed an obstacle next to the
agent, else onto the goal; a walk right, then a walk up, and home if the walk up was the longer) and
two scooping tasks (one to five scoops that leave 50 to 150 g in the receiver with at most 30 g
spilled; two to four scoops scoring at least 30, the grams delivered less twice the grams spilled).
Each has a reference behavior (``references/``), a ground-truth ``check`` and a faithful ``promise``
over the env's outcome helpers, so that the search can be measured apart from the model. They were
written on 2026-12-07 blind: without reading the search's code and without running the synthesizer
on them; the first run of the search on them is the evaluation, reported beside the development
figures.

Close relatives of earlier tasks: column_far_end of heldout5's lowest_reachable_cell and
heldout2's farthest_known_cell (a reachable or known cell picked by a comparison after exploring;
here along the start's column, either way); home_quarter_mapped of the development
explore_20_cells (a count of known cells) and heldout17's four_quarters_sensed (the grid's
quarters; here the cells known in the start's own quarter); narrowest_on_climb of heldout13's
column_midpoint (a walk in the start's column, then back onto one of its cells) and heldout4's
most_obstacles_spot (back to the place with the most obstacles next to it; here beside it in its
row, among the walk's cells); goals_low_to_high_home of heldout9's nearest_first_goal_tour and
heldout16's farthest_first_goal_tour (ordered tours after exploring; here by row, and home after)
and heldout4's explore_then_goal_tour; row_goal_else_home of heldout11's goal_above_or_home and
heldout16's clutter_turns_home (goal or home on where the goal lies or what the sense showed;
here whether it lies beside the agent in its row); nearest_shelter of heldout8's clearest_cell
and heldout17's centre_park (a reachable cell picked after exploring) and heldout16's
right_until_ledge (an obstacle next to a cell; there below); first_sighting_spot of heldout3's
first_goal_after_all (the first goal, after exploring; here the place it was first seen from)
and heldout10's back_to_second_look; fourth_long_trip of heldout15's first_long_move (there the
first long move) and heldout7's twelve_steps_travelled (lengths of moves added up);
six_out_sighted of heldout7's five_out_then_home (there a move ending five steps out) and
heldout14's outward_records; lowest_look_then_goal of heldout16's highest_look_after_goal (back to
a place sensed from picked by its row; here the lowest, and the goal after it) and heldout17's
wandered_home_first (a stop on the way to the goal); cluttered_search_home of heldout16's
clutter_turns_home (there the goal sense alone) and heldout16's third_obstacle_look (a count of
senses that show an obstacle); longer_climb_home of heldout3's up_then_right (two walks in a row)
and heldout9's longer_arm (two walks compared) and heldout16's short_walk_home (home on a walk's
length); fill_window of heldout15's scoop_on_pace (a window on the grams delivered; there for
every scoop) and heldout12's clean_or_plenty (a spill limit); double_spill_penalty of heldout14's
scoop_points (points for grams delivered, less for grams spilled; here spilling costs double and
scoops nothing).

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a cell is
*blocked* when it is an obstacle or outside the grid; a cell's *row* is the cells with its j, its
*column* those with its i; the *lowest* places have the smallest j; the *quarters* of the grid are
cut between i = 4 and i = 5 and between j = 4 and j = 5, each of 25 cells; a sense labels its cell
and the four around it (it *shows* them; a goal *comes into view* with the first sense that shows
it); the obstacles *next to* a cell are those among its four neighbours inside the grid (the grid's
edge does not count), and a sense *shows an obstacle* when its cell has one next to it (its own cell
never holds one); the obstacles *beside* a cell in its row are those on the cells left and right of
it; a cell has an obstacle *right above* it when the cell up from it is an obstacle (the top edge is
not one); the *distance* of two cells counts steps along rows and columns (|di| + |dj|), obstacles
ignored, and a move's *length* is the distance from the cell it began in to the cell it ended in (a
*long trip* when 3 or more); a walk's *moves* are the navigate steps it made. The start cell always
has a free neighbour (a goal is reachable from it and it holds none); the references only move onto
cells they know, so none ever stood on a goal when it first came into view, and a known free cell
is always reachable (it is the sensed-from cell or next to it). The promises' language allows three
comprehension loops in one expression, all of them counted together, and 400 syntax nodes
(nearest_shelter's promise has 337): where the steps after the goal sense may be moves only, the
goal sense is read as the last sense (``_HOME``, ``_ONTO_GOAL``, ``_ONLY_MOVES``); where exploring
ends on a sense after which nothing more was to be found, that it was not so before is read from
``known_before_last()`` (home_quarter_mapped, six_out_sighted, fourth_long_trip) or, where moves
follow it, from the senses (the last sense showed a cell no earlier sense showed: column_far_end,
goals_low_to_high_home, nearest_shelter, first_sighting_spot, as in heldout14);
home_quarter_mapped and six_out_sighted read, before the last step and after it, whether the
known cells hold what ends the exploring, and ask for [False, True], or [False, False] with nothing
more to find; first_sighting_spot finds the sense that first showed a goal as the one whose count
among the senses is that of the senses up to the step ``steps_after_goal()`` counts from;
fourth_long_trip counts the long trips among the moves (each from the cell the one before ended
in, the first from the start; up to 100 moves, and no judged episode made more than 72) and asks
for 4 with the last move one of them, or fewer with nothing more to find; narrowest_on_climb
reads the walk as the senses in the start's column, one a cell, and the walk's cells' counts as a
list in the order of the walk; longer_climb_home reads the walk right's length R, and the walk
up's as the senses less R + 1; a promise whose target is a choice among ties lets the agent stay
only where the cell it stands in is as good as the target, and move only where that cell is
strictly worse (nearer the start for column_far_end, farther for nearest_shelter, fewer obstacles
beside it for narrowest_on_climb, higher for lowest_look_then_goal; nearest_shelter reads it among
the reachable cells, the cell of the last sense being one of them). The scooping checks weigh the
grains at the end, as ``delivered()`` and ``spilled()`` do: those in the receiver, and those
outside the receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all; on those 3,600 episodes every one of
the twelve promises was also judged against every reference (each reference run once an episode,
every promise judged on the run as ``evaluate`` judges it), and its verdict equalled its check's on
all. On those episodes the tasks' branches came up: a move onto the column's farthest cell 284
times, staying on it 16; 13 cells of the start's quarter known after 4 to 50 senses 293 times (4 to
8 senses 149), nothing more to find first 7 (after 5 to 52 senses); walks up of 0 to 8 moves 106,
57, 49, 42, 17, 20, 4, 4 and 1 times, back onto a narrower cell 87, staying at the walk's end 213;
tours of 1, 2 and 3 goals 21, 61 and 218 times, in an order other than the goals' i-then-j order
183, the last sense on a goal 17; onto a goal beside the agent in its row 160 times, home 121,
staying at the start 19 (a goal in view from the start, not beside it in its row); a move onto the
nearest sheltered cell 294 times, staying on one 4, no sheltered cell reachable and home 2; back to
where the goal was first seen from 300 times (never already there); the fourth long trip after 7
to 49 moves 292 times, nothing more to find first 8 (after 4 to 24 moves); a free cell six steps
out known after 6 to 29 senses 295 times, nothing more to find first 5 (after 5 to 12 senses); back
to the lowest place, then onto the goal, 144 times, straight onto the goal from a lowest place 156
(41 of them seen from the start); home from a cluttered search 219 times, staying at the start 25,
onto the goal 56; walks right of 0 to 8 moves 102, 89, 48, 21, 18, 8, 11, 2 and 1 times and walks up
of 0 to 8 moves 108, 68, 47, 34, 22, 12, 6, 2 and 1, home after the longer walk up 125, no move
home 175 (29 of them walks up as long as the walk right, 26 with no move at all). Faithfulness on
behaviors that do not do the tasks: every grid promise was judged against 79 near misses of the
references (thresholds and counts one off, other directions, rows, columns, sides or quarters,
other measures or places to go, the start, the grid's edge or the goal sense counted or left out,
a return, a goal or the fallback dropped or added, an extra sense or move, a move where the agent
should stay) and 22 other ways of doing the tasks (another explorer, another choice among ties,
a count or comparison written another way) on episodes 0-99 of seeds 0 and 1 (20,200 judged
episodes for each promise, none lost): the near misses kept their own task's promise on 5,751 of
their 15,800 judged episodes and the other ways on all their 4,400; three near misses did their
task on every one of these episodes and kept its promise there (column_far_end's and
nearest_shelter's move when the agent stands on a target that is not the first of several, which
never happened there; narrowest_on_climb's with the grid's edge counted as an obstacle, which adds
the same to every cell of a walk in one column); against the 218 grid references of the
development and earlier held-out sets on episodes 0-49 of seed 0 (10,900 judged episodes for each
promise, none lost); and against 3 trivial behaviors (stop at once, judged on the reset; sense
once; navigate onto the cell it stands in) on episodes 0-99 of seeds 0 and 1: on every judged
episode the promise's verdict equalled the check's. Keep rates of the trivial behaviors: stopping
at once and navigating onto the cell it stands in keep no promise on any episode; sensing once
keeps none but narrowest_on_climb's (70 of 200: the cell above the start blocked),
row_goal_else_home's (11: a goal in view from the start, not beside it in its row),
cluttered_search_home's (16: a goal and an obstacle in view from the start) and
longer_climb_home's (15: the cells right of and above the start blocked), where the task asks for
the one sense. The held-out folder tests (tests/test_synthesis_eval.py's
satisfiable-faithful-checkable test) pointed at this folder passed. The scooping references (two
and three scoops from the default sensing pose) were run on episodes 0-9 of seed 0 only (seconds
an episode) and kept their promises and did their tasks on all 10: two scoops delivered 61.1 to
97.3 g and spilled 4.5 to 22.6 g (50 g needed: margin 11.1 g; 30 g spilled at most: margin 7.4 g);
three scoops delivered 88.2 to 133.5 g and spilled 4.5 to 24.9 g, for scores of 47.5 to 110.8 (30
needed: margin 17.5). Both promises were judged on both references and the checks agreed on every
one: three scoops kept fill_window's on all 10, two scoops double_spill_penalty's on 9 (a score of
29.4 on the other)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.synthesis_tasks import (goal_sense as _goal_sense, any_plan as _any_plan,
                                        FINAL as _F, FRESH as _FRESH, LAST_SENSE as _L,
                                        NEW_LAST as _NEW_LAST, ONLY_MOVES as _ONLY_MOVES,
                                        ONTO_GOAL as _ONTO_GOAL, START as _S, START_I as _S0,
                                        START_J as _S1, cell, distance, distance_text, exhausted,
                                        first_goal_sense, first_reaching, free_cell, goals_shown,
                                        grams_in_receiver, grams_spilled, held_out_task, indices,
                                        label_sensed, obstacles_beside, onto, onto_goal_seen,
                                        reachable, same_steps, scoops, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
LEFT, RIGHT, DOWN, UP = (-1, 0), (1, 0), (0, -1), (0, 1)
HALF = 5  # a cell is in the right half when i >= HALF, the top half when j >= HALF
QUARTER_KNOWN = 13  # cells of the start's quarter known that end home_quarter_mapped
LONG, TRIPS = 3, 4  # steps that make a move a long trip; long trips that end fourth_long_trip
SIGHT = 6  # steps from the start of the free cell that ends six_out_sighted


def _unknown(state):
    """A boolean grid of the cells' knowledge before any step: nothing known."""
    return state.truth != state.truth


def _walk(state, here, step) -> list:
    """The steps of a walk from ``here`` in the direction ``step``: a move and a sense while the
    next cell that way is inside the grid and free."""
    plan = []
    while free_cell(state, step_by(here, step)):
        here = step_by(here, step)
        plan += [("navigate", here), ("sense", here)]
    return plan


def _reachable_cells(state) -> list:
    return [cell(x) for x in zip(*reachable(state).nonzero())]


def _beside_in_row(state, c) -> int:
    """How many of the cells left and right of ``c`` are obstacles (the grid's edge does not
    count)."""
    return sum(0 <= c[0] + s[0] <= 9 and state.truth[step_by(c, s)] == OBSTACLE
               for s in (LEFT, RIGHT))


# --- checks -------------------------------------------------------------------------------

def check_column_far_end(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then one move
    onto a reachable cell of the start's column farthest from the start (nothing if the agent
    stands on one)."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    steps, home = steps_of(result), state.start_cell
    column = [c for c in _reachable_cells(state) if c[0] == home[0]]
    far = max(abs(c[1] - home[1]) for c in column)
    return onto(steps[index + 1:], steps[index][1],
                [c for c in column if abs(c[1] - home[1]) == far], "after exploring")


def check_home_quarter_mapped(state, result):
    """Exploring stops with the first sense after which QUARTER_KNOWN cells of the start's
    quarter of the grid are known, or nothing more is to be found."""
    i, j = np.indices(state.truth.shape)
    a, b = state.start_cell
    mine = ((i >= HALF) == (a >= HALF)) & ((j >= HALF) == (b >= HALF))
    index = first_reaching(state, result, lambda known: int(known[mine].sum()) >= QUARTER_KNOWN
                           or exhausted(state, known))
    if index is None:
        return f"never knew {QUARTER_KNOWN} cells of the start's quarter, and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_narrowest_on_climb(state, result):
    """A sense, then a walk up, a sense after every move, while the next cell is inside the grid
    and free; then one move onto a cell of the walk (the start included) with the most
    obstacles left and right of it (nothing if the agent stands on one)."""
    home = state.start_cell
    walk = [("sense", home)] + _walk(state, home, UP)
    steps = steps_of(result)
    if steps[:len(walk)] != walk:
        return f"began {steps[:8]}, not the walk up {walk[:8]}"
    cells = [c for kind, c in walk if kind == "sense"]
    most = max(_beside_in_row(state, c) for c in cells)
    return onto(steps[len(walk):], cells[-1],
                [c for c in cells if _beside_in_row(state, c) == most], "after the walk")


def check_goals_low_to_high_home(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then only moves:
    onto each reachable goal once, in order of j, smallest first, then onto the start."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    rest, home = steps_of(result)[index + 1:], state.start_cell
    goals = sorted(cell(x) for x in zip(*(reachable(state) & (state.truth == GOAL)).nonzero()))
    tour = [c for kind, c in rest if kind == "navigate"]
    if len(tour) != len(rest) or len(tour) != len(goals) + 1 or tour[-1] != home \
            or sorted(tour[:-1]) != goals:
        return f"after exploring ran {rest[:6]}, not one move onto each of the goals {goals} " \
               f"and one home"
    rows = [c[1] for c in tour[:-1]]
    return None if rows == sorted(rows) else \
        f"visited the goals {tour[:-1]} in rows {rows}, not lowest first"


def check_row_goal_else_home(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed left or right of
    the agent if there is one; else one move onto the start (nothing if the agent is there)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here = steps[index][1]
    beside = [g for g in goals_shown(state, here) if g[1] == here[1] and g != here]
    if beside:
        return onto(steps[index + 1:], here, beside, "after a goal came into view in the row")
    return onto(steps[index + 1:], here, [state.start_cell], "after a goal out of the row")


def check_nearest_shelter(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then one move
    onto a reachable cell with an obstacle right above it nearest the start (nothing if the
    agent stands on one), or, with none reachable, onto the start (nothing if the agent is
    there)."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    steps, home = steps_of(result), state.start_cell
    sheltered = [c for c in _reachable_cells(state)
                 if c[1] < 9 and state.truth[c[0], c[1] + 1] == OBSTACLE]
    if sheltered:
        near = min(distance(c, home) for c in sheltered)
        targets = [c for c in sheltered if distance(c, home) == near]
    else:
        targets = [home]
    return onto(steps[index + 1:], steps[index][1], targets, "after exploring")


def check_first_sighting_spot(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then one move
    onto the cell of the sense that first showed a goal (nothing if the agent is there)."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    steps = steps_of(result)
    spot = steps[first_goal_sense(state, result)][1]
    return onto(steps[index + 1:], steps[index][1], [spot], "after exploring")


def check_fourth_long_trip(state, result):
    """Exploring stops with the TRIPS-th move of LONG or more steps, or with the sense after
    which nothing more is to be found, whichever comes first."""
    steps, known, here, trips = steps_of(result), _unknown(state), state.start_cell, 0
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] == "navigate":
            trips += distance(step[1], here) >= LONG
            here = step[1]
            if trips >= TRIPS:
                return same_steps(steps[index + 1:], [])
        elif exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return f"stopped after {trips} long trip(s), before everything was known"


def check_six_out_sighted(state, result):
    """Exploring stops with the first sense after which a free cell SIGHT or more steps from
    the start is known, or nothing more is to be found."""
    a, b = state.start_cell
    i, j = np.indices(state.truth.shape)
    far = (np.abs(i - a) + np.abs(j - b) >= SIGHT) & (state.truth != OBSTACLE)
    index = first_reaching(state, result, lambda known: bool((known & far).any())
                           or exhausted(state, known))
    if index is None:
        return f"never knew a free cell {SIGHT} steps out, and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_lowest_look_then_goal(state, result):
    """After the sense that first shows a goal (nothing if the agent stands on a goal): one
    move onto a cell sensed from (up to that sense) with the smallest j, none if the agent
    stands on one, then one move onto a goal that sense showed."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, rest = steps[index][1], steps[index + 1:]
    if state.truth[here] == GOAL:
        return same_steps(rest, [])
    senses = [c for kind, c in steps[:index + 1] if kind == "sense"]
    low = min(c[1] for c in senses)
    lows = [c for c in senses if c[1] == low]
    via = [[]] if here in lows else [[("navigate", w)] for w in lows]
    return _any_plan(rest, [v + [("navigate", g)] for v in via
                            for g in goals_shown(state, here)])


def check_cluttered_search_home(state, result):
    """After the sense that first shows a goal: if more than half of the senses up to it
    showed an obstacle next to their cell, one move onto the start (nothing if the agent is
    there); else one move onto a goal it showed (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    senses = [c for kind, c in steps[:index + 1] if kind == "sense"]
    cluttered = sum(obstacles_beside(state, c) > 0 for c in senses)
    if 2 * cluttered > len(senses):
        return onto(steps[index + 1:], steps[index][1], [state.start_cell],
                    f"after {cluttered} of {len(senses)} senses showed an obstacle")
    return onto_goal_seen(state, steps, index)


def check_longer_climb_home(state, result):
    """A sense, a walk right, then from its end a walk up, each a sense after every move while
    the next cell is inside the grid and free; then one move onto the start if the walk up made
    more moves than the walk right."""
    home = state.start_cell
    right = _walk(state, home, RIGHT)
    end = right[-1][1] if right else home
    up = _walk(state, end, UP)
    back = [("navigate", home)] if len(up) > len(right) else []
    return same_steps(steps_of(result), [("sense", home)] + right + up + back)


LOW, HIGH, SPILL_CAP = 50, 150, 30  # grams in the receiver, least and most; grams spilled, most
PENALTY = 30  # the score needed, grams delivered less twice the grams spilled


def check_fill_window(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    if not LOW <= mass <= HIGH or spilled > SPILL_CAP:
        return f"{mass:.1f} g delivered and {spilled:.1f} g spilled in {n} scoop(s)"
    return None


def check_double_spill_penalty(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    score = mass - 2 * spilled
    return None if score >= PENALTY else \
        f"score {score:.1f}: {mass:.1f} g delivered, {spilled:.1f} g spilled, {n} scoop(s)"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_K10, _K20, _K100 = indices(10), indices(20), indices(100)


def _d(a: str, b: str = _S) -> str:
    return distance_text(a, b)


def _blocked(i: str, j: str) -> str:
    """The cell (i, j) is off the grid or an obstacle."""
    return f"(not (0 <= {i} <= 9 and 0 <= {j} <= 9) or is_obstacle(({i}, {j})))"


def _mine(c: str) -> str:
    """The cell ``c`` lies in the start's quarter of the grid."""
    return f"(({c}[0] >= {HALF}) == ({_S0} >= {HALF}) and ({c}[1] >= {HALF}) == ({_S1} >= " \
           f"{HALF}))"


def _row_obstacles(c: str) -> str:
    """How many of the cells left and right of ``c`` are obstacles (no loop)."""
    return f"((1 if {c}[0] > 0 and is_obstacle(({c}[0] - 1, {c}[1])) else 0) + (1 if {c}[0] < 9 " \
           f"and is_obstacle(({c}[0] + 1, {c}[1])) else 0))"


def _shelter(c: str) -> str:
    """The cell ``c`` has an obstacle right above it (no loop)."""
    return f"({c}[1] < 9 and is_obstacle(({c}[0], {c}[1] + 1)))"


# the cell of the sense that first showed a goal: as many senses in as there are senses among
# the steps up to the goal's
_SIGHTING = "sensed()[len([p for p in primitives()[:len(primitives()) - steps_after_goal()] if " \
            "p == 'sense']) - 1]"
_NG = "len(reachable_goals())"
_HOME = f"{_F} == {_S} and steps_after_goal() == (0 if {_L} == {_S} else 1) and " \
        f"primitives()[-1:] == (['sense'] if {_L} == {_S} else ['navigate'])"
_CLUTTERED = "2 * len([s for s in sensed() if any(is_obstacle(x) for x in neighbours(s))]) > " \
             "len(sensed())"

TASKS = [
    _task("column_far_end", 2, check_column_far_end,
          "Explore, moving and sensing, until there is nothing more to find. Then go with one "
          "move to the cell of your starting column (the cells whose i is that of your starting "
          "cell) that you can reach and that lies farthest from your starting cell, up or down, "
          "and stop there (any of them if several are equally far; if you are standing on one, "
          "just stop).",
          f"explored_all() and {_NEW_LAST} and {_F}[0] == {_S0} and all(abs(c[1] - {_S1}) <= "
          f"abs({_F}[1] - {_S1}) for c in reachable_cells() if c[0] == {_S0}) and "
          f"(primitives()[-1:] == ['sense'] or (primitives()[-2:] == ['sense', 'navigate'] and "
          f"({_L}[0] != {_S0} or abs({_L}[1] - {_S1}) < abs({_F}[1] - {_S1}))))"),
    _task("home_quarter_mapped", 1, check_home_quarter_mapped,
          f"Explore, moving and sensing, until you know what at least {QUARTER_KNOWN} of the 25 "
          f"cells in your own quarter of the grid hold -- the quarter your starting cell lies "
          f"in, the grid being cut into quarters between i = 4 and i = 5 and between j = 4 and "
          f"j = 5 -- and stop right after the sense that brings you to {QUARTER_KNOWN}. If "
          f"there is nothing more to find before that, stop right after the sense that leaves "
          f"nothing more to find.",
          f"primitives()[-1:] == ['sense'] and [len([c for c in K if {_mine('c')}]) >= "
          f"{QUARTER_KNOWN} for K in [known_before_last(), known_cells()]] in [[False, True]] + "
          f"([[False, False]] if explored_all() and {_FRESH} else [])"),
    _task("narrowest_on_climb", 2, check_narrowest_on_climb,
          "Sense where you start, then walk up (j + 1), one cell at a time, sensing after every "
          "move, while the next cell up is inside the grid and free. Then go back with one move "
          "to the narrowest cell of that walk, your starting cell included: the one with the "
          "most obstacles right beside it in its row, on the cells to its left (i - 1) and to "
          "its right (i + 1); the grid's edge does not count. Stop there (any of them if "
          "several tie; if you are standing on one of them, just stop).",
          f"primitives() == ['sense'] + ['navigate', 'sense'] * (len(sensed()) - 1) + ([] if "
          f"{_F} == {_L} else ['navigate']) and sensed() == [({_S0}, {_S1} + k) for k in "
          f"{_K10}[:len(sensed())]] and {_blocked(_S0, f'{_S1} + len(sensed())')} and {_F} in "
          f"sensed() and all(W[{_F}[1] - {_S1}] == max(W) and ({_F} == {_L} or W[-1] < max(W)) "
          f"for W in [[{_row_obstacles('s')} for s in sensed()]])"),
    _task("goals_low_to_high_home", 3, check_goals_low_to_high_home,
          "Explore, moving and sensing, until there is nothing more to find. Then visit every "
          "goal you can reach, moving onto each exactly once, from the lowest to the highest: "
          "in order of j, smallest first (goals in the same row in any order). Then go straight "
          "back to your starting cell with one move and stop there. After the exploring, make "
          "no other moves and do not sense again; a goal you are standing on when the exploring "
          "ends still gets its move in its turn.",
          f"explored_all() and {_NEW_LAST} and primitives()[len(primitives()) - {_NG} - 2:] == "
          f"['sense'] + ['navigate'] * ({_NG} + 1) and sorted(moves()[len(moves()) - {_NG} - "
          f"1:-1]) == reachable_goals() and moves()[-1] == {_S} and all(moves()[k - {_NG} - "
          f"1][1] <= moves()[k - {_NG}][1] for k in {_K10}[:{_NG} - 1])"),
    _task("row_goal_else_home", 2, check_row_goal_else_home,
          "Search for a goal. When a sense first shows you one, look where it lies: if that "
          "sense showed a goal right beside you in your row -- on the cell to your left (i - 1) "
          "or to your right (i + 1) -- go onto it with one move and stop (onto either if both "
          "are goals). In every other case leave the goal alone and go straight back to your "
          "starting cell with one move, and stop there (if you are there, just stop).",
          f"goal_found() and all(((steps_after_goal() == 1 and primitives()[-1:] == "
          f"['navigate'] and {_F} in G) if len(G) > 0 else ({_HOME})) for G in [[x for x in "
          f"neighbours({_L}) if x[1] == {_L}[1] and is_goal(x)]])"),
    _task("nearest_shelter", 2, check_nearest_shelter,
          "Explore, moving and sensing, until there is nothing more to find. Then take shelter: "
          "go with one move to the cell you can reach that has an obstacle right above it (on "
          "the cell j + 1; the grid's top edge does not count) and that is nearest to your "
          "starting cell, counting steps along rows and columns and ignoring obstacles (any of "
          "them if several are equally near; if you are standing on one, just stop). If you can "
          "reach no such cell, go straight back to your starting cell with one move instead (if "
          "you are there, just stop).",
          f"explored_all() and {_NEW_LAST} and ({_shelter(_F)} or {_F} == {_S}) and all(not "
          f"{_shelter('c')} or ({_shelter(_F)} and {_d('c')} - {_d(_F)} >= (0 if c != {_L} or "
          f"{_F} == {_L} else 1)) for c in reachable_cells()) and (primitives()[-1:] == ['sense'] "
          f"or (primitives()[-2:] == ['sense', 'navigate'] and {_L} != {_F}))"),
    _task("first_sighting_spot", 2, check_first_sighting_spot,
          "Explore, moving and sensing, until there is nothing more to find. Then go back with "
          "one move to the place where you took the sense that first showed you a goal, and "
          "stop there (if you are standing there, just stop).",
          f"explored_all() and {_NEW_LAST} and {_F} == {_SIGHTING} and (primitives()[-1:] == "
          f"['sense'] if {_F} == {_L} else primitives()[-2:] == ['sense', 'navigate'])"),
    _task("fourth_long_trip", 2, check_fourth_long_trip,
          f"Explore, moving and sensing, and count your long trips: moves that end {LONG} or "
          f"more steps away from the cell they started from, counting steps along rows and "
          f"columns and ignoring obstacles. Stop right after your {TRIPS}th long trip: that "
          f"move is your last action. If there is nothing more to find before that, stop right "
          f"after the sense that leaves nothing more to find.",
          f"all((primitives()[-1:] == ['navigate'] and not explored_all() and "
          f"{_d('P[-1]', 'P[-2]')} >= {LONG} and C == {TRIPS}) or (primitives()[-1:] == "
          f"['sense'] and explored_all() and {_FRESH} and C < {TRIPS}) for P in [[{_S}] + "
          f"moves()] for C in [len([k for k in {_K100}[:len(moves())] if "
          f"{_d('P[k + 1]', 'P[k]')} >= {LONG}])])"),
    _task("six_out_sighted", 1, check_six_out_sighted,
          f"Explore, moving and sensing, until you know of a free cell (empty or a goal) that "
          f"lies {SIGHT} or more steps from your starting cell, counting steps along rows and "
          f"columns and ignoring obstacles. Stop right after the sense that first shows you "
          f"one. If there is nothing more to find before that, stop right after the sense that "
          f"leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and [any({_d('c')} >= {SIGHT} and not is_obstacle(c) "
          f"for c in K) for K in [known_before_last(), known_cells()]] in [[False, True]] + "
          f"([[False, False]] if explored_all() and {_FRESH} else [])"),
    _task("lowest_look_then_goal", 3, check_lowest_look_then_goal,
          "Search for a goal. As soon as a sense shows you one, do not go straight to it: first "
          "go back with one move to the lowest of the places you have sensed from -- the one "
          "with the smallest j, counting that last sense too (any of them if several are "
          "equally low; skip this move if you are standing on one of them) -- and then go onto "
          "the goal with one more move (onto any of them if that sense showed several) and stop "
          "there. If you are standing on a goal when you first see one, just stop.",
          f"goal_found() and {_ONLY_MOVES} and (steps_after_goal() == 0 if is_goal({_L}) else "
          f"(is_goal({_F}) and {_F} in neighbours({_L}) and all(({_L}[1] == J and "
          f"moves_after_goal() == [{_F}]) or ({_L}[1] != J and len(moves_after_goal()) == 2 and "
          f"moves_after_goal()[1] == {_F} and moves_after_goal()[0] in sensed() and "
          f"moves_after_goal()[0][1] == J) for J in [min([s[1] for s in sensed()])])))"),
    _task("cluttered_search_home", 2, check_cluttered_search_home,
          "Search for a goal. As soon as a sense shows you one, look back over all your senses, "
          "that one included, and count those that showed you an obstacle on a cell right next "
          "to where you sensed (the grid's edge does not count; a sense taken again in the same "
          "place counts again). If more than half of your senses did, the area is too "
          "cluttered: leave the goal and go straight back to your starting cell with one move "
          "and stop (if you are there, just stop). Otherwise go onto the goal with one move and "
          "stop (onto any of them if that sense showed several; if you are standing on one, "
          "just stop).",
          f"goal_found() and (({_HOME}) if {_CLUTTERED} else ({_ONTO_GOAL}))"),
    _task("longer_climb_home", 2, check_longer_climb_home,
          "Sense where you start, then walk right (i + 1), one cell at a time, sensing after "
          "every move, while the next cell to the right is inside the grid and free. From where "
          "that walk ends, walk up (j + 1) the same way, sensing after every move, while the "
          "next cell up is inside the grid and free. Then, if the walk up made more moves than "
          "the walk right, go straight back to your starting cell with one move and stop there; "
          "otherwise stop where the walk up ended.",
          f"any(U >= 0 and primitives() == ['sense'] + ['navigate', 'sense'] * (R + U) + "
          f"(['navigate'] if U > R else []) and moves() == [({_S0} + min(k, R), {_S1} + max(0, "
          f"k - R)) for k in {_K20}[1:R + U + 1]] + ([{_S}] if U > R else []) and "
          f"{_blocked(f'{_S0} + R + 1', _S1)} and {_blocked(f'{_S0} + R', f'{_S1} + U + 1')} "
          f"for R in {_K10} for U in [len(sensed()) - 1 - R])"),
    _task("fill_window", 2, check_fill_window,
          f"Scoop one to five times, then stop, so that the receiver ends up holding between "
          f"{LOW} and {HIGH} g of grains (both included) and no more than {SPILL_CAP} g of "
          f"grains is spilled outside the containers.",
          f"scoops() >= 1 and scoops() <= 5 and delivered() >= {LOW} and delivered() <= {HIGH} "
          f"and spilled() <= {SPILL_CAP}", SCOOP),
    _task("double_spill_penalty", 2, check_double_spill_penalty,
          f"Scoop two to four times, then stop, with a score of at least {PENALTY}: every gram "
          f"of grains in the receiver earns a point, and every gram spilled outside the "
          f"containers costs two points.",
          f"scoops() >= 2 and scoops() <= 4 and delivered() - 2 * spilled() >= {PENALTY}",
          SCOOP),
]
