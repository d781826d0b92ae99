"""Held-out tasks, nineteenth set: written before the next change of the synthesizer, run once
after it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout19/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (exploring that stops once three obstacles
side by side in a row or a column are known; a cell a knight's move from the start, exploring as
much as needed to reach one; exploring that stops with the third move that ends in a lower row than
it began in; a walk down, then one step to the side, left before right, and a sense there; after
exploring, a patrol of the grid's corners that can be reached, then home; after exploring, onto the
reachable cell farthest from the start as the crow flies; once a goal is in view, onto it and home,
then a search for a second, different goal; once a goal is in view, home and a sense there before
going onto it; exploring that stops once the eight cells around the start are known; once a goal is
in view, onto it, and home if the search took more than six senses; once a goal is in view, onto it
if it lies on the grid's border, else home; exploring until 25 cells are known, then onto the known
goal nearest the agent, else home) and two scooping tasks (one to four scoops scoring at least 160,
the grams delivered times a multiplier of 4 that drops by one with every further scoop; two to five
scoops that leave at least 80 g in the receiver and spill no more than 10 g plus 1 g for every 5 g
delivered). Each has a reference behavior (``references/``), a ground-truth ``check`` and a faithful
``promise`` over the env's outcome helpers, so that the search can be measured apart from the model.
They were written on 2026-12-07 blind: without reading the search's code and without running the
synthesizer on them; the first run of the search on them is the evaluation, reported beside the
development figures.

Close relatives of earlier tasks: wall_of_three of heldout8's two_touching_obstacles and heldout3's
touching_obstacle (obstacles that touch; here three in a straight line) and heldout15's
free_square_known (a shape among the known cells); knight_jump of heldout8's four_in_line and
heldout2's reachable_corner (a cell to get to, exploring as much as needed; here a knight's move
from the start) and heldout9's diagonal_step; third_downhill_move of heldout18's fourth_long_trip
(moves counted by what they do; there their length) and heldout10's back_in_start_row (a stop on the
row a move ends in); down_then_sidestep of heldout3's up_then_right and heldout8's
down_then_edge_left (a walk, then a turn; here a single step) and heldout3's left_or_right (left,
else right); corner_patrol of heldout2's reachable_corner (there one corner, got to) and heldout4's
explore_then_goal_tour and heldout18's goals_low_to_high_home (tours after exploring, then home;
here of the corners); crow_flies_far of heldout2's farthest_known_cell and heldout18's
column_far_end (a cell picked by its distance from the start; here the straight-line distance) and
heldout17's centre_park; second_goal_after_home of heldout2's visit_two_goals and heldout3's
second_goal_or_home (a second goal after the first) and heldout17's goal_deliveries (home between
goals); home_report_then_goal of the first held-out set's home_and_sense (home and a sense there
once a goal is found), the development goal_sense_home (there the goal first) and heldout17's
wandered_home_first (home before the goal; there on a condition); start_ring_known of heldout13's
ring_around_start (the eight cells round the start; there a tour of them), heldout7's square_survey
and heldout13's four_ray_lengths (what is known round the start); long_search_comes_home of
heldout17's far_goal_comes_home (home from the goal; there on its distance) and heldout6's
quick_find_or_home (the search's length; there in moves, and home instead of the goal);
border_goal_or_home of heldout18's row_goal_else_home and heldout11's goal_above_or_home (goal or
home on where the goal lies; here on the border) and the development border_cell (dev_general; the
grid's border); known_cells_nearest_goal of heldout2's farthest_known_cell and the development
most_free_neighbours (dev_general; exploring until a count of known cells, then one move to a picked
cell; here the nearest known goal, else home) and heldout14's nearer_of_home_and_goal;
shrinking_multiplier of heldout14's scoop_points and heldout10's scoop_fee (scoops that cost; here
each shrinks a multiplier of the grams delivered) and heldout17's landed_weighted_haul (a product
with the grams delivered); spill_grace of heldout6's two_scoops_threefold_clean (the spill bounded
by the grams delivered; there a third of them) and heldout13's shrinking_spill_allowance (an
allowance of spill; there shrinking with the scoops, here growing with the grams delivered).

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a cell is
*blocked* when it is an obstacle or outside the grid; a cell's *row* is the cells with its j, its
*column* those with its i; a *lower* row has a smaller j, and a *downhill* move ends in a lower row
than the cell it began in; the grid's *border* is the cells whose i or j is 0 or 9, its *corners*
(0, 0), (0, 9), (9, 0) and (9, 9); the cells *around* a cell are the eight whose i and j each differ
from its by at most 1 (those inside the grid); a *knight's move* from a cell changes one of its i
and j by 2 and the other by 1; a sense labels its cell and the four around it (it *shows* them; a
goal *comes into view* with the first sense that shows it); the *distance* of two cells counts steps
along rows and columns (|di| + |dj|), obstacles ignored, and the distance *as the crow flies* is the
square root of di * di + dj * dj (compared as its square). The start cell always has a free
neighbour (a goal is reachable from it and it holds none); the references only move onto cells they
know, so none ever stood on a goal when it first came into view, and a known free cell is always
reachable (it is the sensed-from cell or next to it). The promises' language allows three
comprehension loops in one expression, all of them counted together, and 400 syntax nodes
(crow_flies_far's promise has 382): where the steps after the goal sense may be moves only, the goal
sense is read as the last sense (long_search_comes_home, border_goal_or_home); where exploring ends
on a sense after which something held, that it did not before is read from ``known_before_last()``
(wall_of_three, start_ring_known: whether the known cells hold it before the last step and after it,
[False, True], or [False, False] with nothing more to find) or, where moves follow it, from the
senses (the last sense showed a cell no earlier sense showed: corner_patrol, crow_flies_far, as in
heldout14; known_cells_nearest_goal counts the cells its earlier senses showed);
home_report_then_goal and second_goal_after_home read the steps after the goal sense from
``steps_after_goal()``, and home_report_then_goal the cell the agent stood in at the goal sense as
the start or the end of the move before it; second_goal_after_home reads the first goal visited as
the first move after the goal sense (a goal the agent stands on still gets its move, as the task
says), and asks that no sense but the last (every sense, where the agent does not end on another
goal) showed a goal other than that one; third_downhill_move counts the downhill moves among the
moves (each from the cell the one before ended in, the first from the start; up to 100 moves, and no
judged episode made more than 72); down_then_sidestep reads the walk as the moves less the side
step, with or without one; a promise whose target is a choice among ties lets the agent stay only
where the cell it stands in is as good as the target, and move only where that cell is strictly
worse (nearer the start for crow_flies_far; for known_cells_nearest_goal the nearest goal is
measured from where the agent stands, so a goal it stands on is the target). The scooping checks
weigh the grains at the end, as ``delivered()`` and ``spilled()`` do: those in the receiver, and
those outside the receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all; on those 3,600 episodes every one of
the twelve promises was also judged against every reference (each reference run once an episode,
every promise judged on the run as ``evaluate`` judges it), and its verdict equalled its check's on
all. On those episodes the tasks' branches came up: a wall of three known after 3 to 62 senses 259
times (3 to 8 senses 63), nothing more to find first 41 (after 5 to 63 senses); onto a knight's move
296 times (after 3 senses 241), none reachable 4; the third downhill move after 3 to 26 moves 299
times, nothing more to find first once (after 4 moves); walks down of 0 to 8 moves 106, 75, 38, 28,
21, 17, 10, 3 and 2 times, then a step left 199, right 76, none 25; patrols of 0 to 4 corners 19,
81, 116, 65 and 19 times (the start a corner 3); a move onto the farthest cell as the crow flies 270
times, staying on one 30; a second goal known back at the start 6 times (the first goal sense showed
two), seen on the search after it 273, none and nothing more to find 21; a report with a move home
259 times, without one 41 (a goal in view from the start); staying on the goal after 1 to 6 senses
124 times, home after 7 to 53 senses 176; the eight cells around the start known after 2 to 58
senses 266 times (2 to 5 senses 68), nothing more to find first 34 (after 5 to 61 senses); onto a
goal on the border 93 times, home 176, staying at the start 31 (a goal off the border in view from
it); 25 cells known 296 times (then onto the nearest known goal 159, staying on it 13, home 124),
nothing more to find first 4 (then onto a goal), after 5 to 16 senses in all. Faithfulness on
behaviors that do not do the tasks: every grid promise was judged against 76 near misses of the
references (thresholds and counts one off, other directions, sides, rows, shapes, cells or metrics,
the agent's cell taken for the start, the start counted or left out, a return, a sense, a side step,
the fallback or the first goal dropped or added, a step late or extra, a move where the agent should
stay, a goal where a corner or a border goal is asked for) and 31 other ways of doing the tasks
(other explorers, another choice among ties, goals or corners, another order of the patrol, a choice
written another way) on episodes 0-99 of seeds 0 and 1 (21,400 judged episodes for each promise,
none lost): the near misses kept their own task's promise on 5,144 of their 15,200 judged episodes
and the other ways on all their 6,200; one near miss did its task on every one of these episodes and
kept its promise there (border_goal_or_home's move onto the first goal in view, which differs only
where one sense shows a goal on the border and one off it, which never happened there); against the
230 grid references of the development and earlier held-out sets on episodes 0-49 of seed 0 (11,500
judged episodes for each promise, none lost); and against 25 trivial behaviors (stop at once, judged
on the reset; sense where it stands once and 2 to 12 times; navigate onto the cell it stands in 1 to
12 times) on episodes 0-99 of seeds 0 and 1 (5,000 judged episodes for each promise): on every
judged episode the promise's verdict equalled the check's. Keep rates of the trivial behaviors: none
keeps any promise on any episode but sensing once, which keeps down_then_sidestep's (4 of 200: the
cells below, left and right of the start blocked) and border_goal_or_home's (20: a goal off the
border in view from the start), where the task asks for the one sense; a first version of
known_cells_nearest_goal that ended the exploring after eight senses was kept by sensing eight times
where the agent stands on 171 of 200 episodes and was replaced by the count of known cells, which no
trivial behavior reaches. The held-out folder tests (tests/test_synthesis_eval.py's
satisfiable-faithful-checkable test, and tests/test_certified.py's readings of every promise and its
bank test) pointed at this folder passed. The scooping references (two and three scoops from the
default sensing pose) were run on episodes 0-9 of seed 0 only (seconds an episode) and kept their
promises and did their tasks on all 10: two scoops delivered 61.1 to 97.3 g, for scores of 183.2 to
291.8 (160 needed: margin 23.2); three scoops delivered 88.2 to 133.5 g (80 needed: margin 8.2 g)
and spilled 4.5 to 24.9 g, at least 7.3 g under the allowance. The thresholds were set from these
figures (the same episodes as heldout17's and heldout18's). Both promises were judged on both
references and the checks agreed on every one: three scoops kept shrinking_multiplier's on all 10
(scores of 176.4 to 266.9), two scoops spill_grace's on 4 (under 80 g delivered on the others)."""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (goal_sense as _goal_sense, any_plan as _any_plan,
                                        FINAL as _F, FRESH as _FRESH, LAST_SENSE as _L,
                                        NEW_LAST as _NEW_LAST, ONLY_MOVES as _ONLY_MOVES,
                                        START as _S, START_I as _S0, START_J as _S1, cell,
                                        distance, distance_text, exhausted, first_reaching,
                                        free_cell, goals_shown, grams_in_receiver, grams_spilled,
                                        held_out_task, indices, known_after, label_sensed, onto,
                                        reachable, same_steps, scoops, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
LEFT, RIGHT, DOWN, UP = (-1, 0), (1, 0), (0, -1), (0, 1)
KNIGHT = ((1, 2), (2, 1), (2, -1), (1, -2), (-1, -2), (-2, -1), (-2, 1), (-1, 2))
CORNERS = ((0, 0), (0, 9), (9, 0), (9, 9))
DOWNHILL = 3  # moves ending in a lower row that end third_downhill_move
LONG_SEARCH = 6  # senses up to the goal sense past which long_search_comes_home goes home
KNOWN = 25  # cells known that end the exploring of known_cells_nearest_goal


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


def _known_goals(state, known) -> list:
    """The goals among the cells ``known`` (a boolean grid), in flat-index order."""
    return [cell(x) for x in zip(*(known & (state.truth == GOAL)).nonzero())]


def _on_border(c) -> bool:
    return c[0] in (0, 9) or c[1] in (0, 9)


def _crow(c, home) -> int:
    """The square of the straight-line distance between the centres of ``c`` and ``home``."""
    return (c[0] - home[0]) ** 2 + (c[1] - home[1]) ** 2


# --- checks -------------------------------------------------------------------------------

def check_wall_of_three(state, result):
    """Exploring stops with the first sense after which three obstacles side by side in a row or
    a column are known, or nothing more is to be found."""
    obstacle = state.truth == OBSTACLE

    def wall(known):
        k = known & obstacle
        return bool((k[:-2, :] & k[1:-1, :] & k[2:, :]).any()
                    or (k[:, :-2] & k[:, 1:-1] & k[:, 2:]).any())
    index = first_reaching(state, result, lambda known: wall(known) or exhausted(state, known))
    if index is None:
        return "never knew three obstacles in a line, and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_knight_jump(state, result):
    """Ends on a reachable cell a knight's move from the start; where there is none, nothing
    more is to be found at the end."""
    home, reach = state.start_cell, reachable(state)
    targets = [c for c in (step_by(home, k) for k in KNIGHT)
               if 0 <= c[0] <= 9 and 0 <= c[1] <= 9 and reach[c]]
    if targets:
        return None if state.cell in targets else f"ended in {state.cell}, not one of {targets}"
    return None if exhausted(state) else "no knight's move reachable, and more could be found"


def check_third_downhill_move(state, result):
    """Exploring stops with the DOWNHILL-th move that ends in a lower row than it began in, or
    with the sense after which nothing more is to be found, whichever comes first."""
    steps, known, here, down = steps_of(result), _unknown(state), state.start_cell, 0
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] == "navigate":
            down += step[1][1] < here[1]
            here = step[1]
            if down >= DOWNHILL:
                return same_steps(steps[index + 1:], [])
        elif exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return f"stopped after {down} downhill move(s), before everything was known"


def check_down_then_sidestep(state, result):
    """A sense, then a walk down, a sense after every move, while the next cell is inside the
    grid and free; then a move onto the cell left of its end if free, else right if free, and a
    sense there."""
    home = state.start_cell
    plan = [("sense", home)] + _walk(state, home, DOWN)
    end = plan[-1][1]
    for side in (LEFT, RIGHT):
        if free_cell(state, step_by(end, side)):
            plan += [("navigate", step_by(end, side)), ("sense", step_by(end, side))]
            break
    return same_steps(steps_of(result), plan)


def check_corner_patrol(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then only moves:
    onto each reachable corner of the grid other than the start once, in any order, then onto
    the start."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    rest, home, reach = steps_of(result)[index + 1:], state.start_cell, reachable(state)
    corners = sorted(c for c in CORNERS if reach[c] and c != home)
    tour = [c for kind, c in rest if kind == "navigate"]
    if len(tour) != len(rest) or len(tour) != len(corners) + 1 or tour[-1] != home \
            or sorted(tour[:-1]) != corners:
        return f"after exploring ran {rest[:6]}, not one move onto each of the corners " \
               f"{corners} and one home"
    return None


def check_crow_flies_far(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then one move
    onto a reachable cell farthest from the start in straight-line distance (nothing if the
    agent stands on one)."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    steps, home = steps_of(result), state.start_cell
    cells = _reachable_cells(state)
    far = max(_crow(c, home) for c in cells)
    return onto(steps[index + 1:], steps[index][1], [c for c in cells if _crow(c, home) == far],
                "after exploring")


def check_second_goal_after_home(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed (the cell the
    agent stands in included), one move onto the start; then, from the first moment a goal
    other than that one is known (at the start, or with a sense), one move onto such a goal
    (nothing if the agent stands on one); if nothing more is to be found first (at the start,
    or with a sense), nothing more."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    home, here, rest = state.start_cell, steps[index][1], steps[index + 1:]
    first = rest[0][1] if rest and rest[0][0] == "navigate" else None
    if first not in goals_shown(state, here) or rest[1:2] != [("navigate", home)]:
        return f"after the goal came into view ran {rest[:2]}, not a move onto a goal it " \
               f"showed and one home"
    known = known_after(state, result.steps[:index + 1])

    def others():
        return [g for g in _known_goals(state, known) if g != first]
    tail = rest[2:]
    if others():
        return onto(tail, home, others(), "back at the start")
    if exhausted(state, known):
        return same_steps(tail, [])
    for t, step in enumerate(tail):
        label_sensed(state, known, step)
        if step[0] != "sense":
            continue
        if others():
            return onto(tail[t + 1:], step[1], others(), "after a second goal came into view")
        if exhausted(state, known):
            return same_steps(tail[t + 1:], [])
    return "no second goal seen, and more could be found"


def check_home_report_then_goal(state, result):
    """After the sense that first shows a goal: one move onto the start (none if the agent is
    there), a sense there, then one move onto a goal the goal sense showed."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, home = steps[index][1], state.start_cell
    back = [] if here == home else [("navigate", home)]
    return _any_plan(steps[index + 1:], [back + [("sense", home), ("navigate", g)]
                                         for g in goals_shown(state, here)])


def check_start_ring_known(state, result):
    """Exploring stops with the first sense after which the eight cells around the start (those
    inside the grid) are known, or nothing more is to be found."""
    a, b = state.start_cell
    ring = _unknown(state)
    ring[max(a - 1, 0):a + 2, max(b - 1, 0):b + 2] = True
    index = first_reaching(state, result, lambda known: bool(known[ring].all())
                           or exhausted(state, known))
    if index is None:
        return "never knew the cells around the start, and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_long_search_comes_home(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed (none if the
    agent stands on one), then one move onto the start if that sense was later than the
    LONG_SEARCH-th."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, home = steps[index][1], state.start_cell
    senses = sum(kind == "sense" for kind, _ in steps[:index + 1])
    goals = [here] if state.truth[here] == GOAL else goals_shown(state, here)
    plans = [([] if g == here else [("navigate", g)])
             + ([("navigate", home)] if senses > LONG_SEARCH else []) for g in goals]
    return _any_plan(steps[index + 1:], plans)


def check_border_goal_or_home(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed on the grid's
    border if there is one (nothing if the agent stands on one); else one move onto the start
    (nothing if the agent is there)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here = steps[index][1]
    edge = [g for g in goals_shown(state, here) if _on_border(g)]
    if edge:
        return onto(steps[index + 1:], here, edge, "after a goal on the border came into view")
    return onto(steps[index + 1:], here, [state.start_cell], "after a goal off the border")


def check_known_cells_nearest_goal(state, result):
    """Exploring stops with the first sense after which KNOWN cells are known, or nothing more
    is to be found; then one move onto a goal known by then nearest the agent (nothing if it
    stands on one), or, with no goal known, onto the start (nothing if the agent is there)."""
    index = first_reaching(state, result, lambda known: int(known.sum()) >= KNOWN
                           or exhausted(state, known))
    if index is None:
        return f"never knew {KNOWN} cells, and more could be found"
    steps = steps_of(result)
    here, goals = steps[index][1], _known_goals(state, known_after(state, result.steps[:index + 1]))
    if goals:
        near = min(distance(g, here) for g in goals)
        targets = [g for g in goals if distance(g, here) == near]
    else:
        targets = [state.start_cell]
    return onto(steps[index + 1:], here, targets, "after exploring")


MULTIPLIER_SCORE = 160  # the score needed, the grams delivered times (5 - scoops)
GRACE_LEAST = 80  # grams delivered, at least
GRACE, GRACE_PER = 10, 5  # grams spilled allowed: GRACE, and 1 g for every GRACE_PER g delivered


def check_shrinking_multiplier(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass = grams_in_receiver(state)
    score = mass * (5 - n)
    return None if score >= MULTIPLIER_SCORE else \
        f"score {score:.1f}: {mass:.1f} g delivered in {n} scoop(s)"


def check_spill_grace(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    if mass < GRACE_LEAST or spilled > GRACE + mass / GRACE_PER:
        return f"{mass:.1f} g delivered and {spilled:.1f} g spilled in {n} scoop(s)"
    return None


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_K10, _K100 = indices(10), indices(100)


def _d(a: str, b: str = _S) -> str:
    return distance_text(a, b)


def _blocked(i: str, j: str) -> str:
    """The cell (i, j) is off the grid or an obstacle."""
    return f"(not (0 <= {i} <= 9 and 0 <= {j} <= 9) or is_obstacle(({i}, {j})))"


def _crow_text(c: str) -> str:
    return f"(({c}[0] - {_S0}) * ({c}[0] - {_S0}) + ({c}[1] - {_S1}) * ({c}[1] - {_S1}))"


def _knight_text(c: str) -> str:
    return f"sorted([abs({c}[0] - {_S0}), abs({c}[1] - {_S1})]) == [1, 2]"


def _line(c: str, K: str, a: int, b: int) -> str:
    """The two cells after ``c`` by the step (a, b) are known (in ``K``) obstacles."""
    one = f"({c}[0] + {a}, {c}[1])" if a else f"({c}[0], {c}[1] + {b})"
    two = f"({c}[0] + {2 * a}, {c}[1])" if a else f"({c}[0], {c}[1] + {2 * b})"
    return f"({one} in {K} and {two} in {K} and is_obstacle({one}) and is_obstacle({two}))"


# the reachable corners of the grid other than the start, in flat-index order
_CORNER_LIST = " + ".join(f"([{c}] if {c} in reachable_cells() and {c} != {_S} else [])"
                          for c in CORNERS)
# the cell the agent stood in when a goal first came into view
_SIGHT_CELL = f"([{_S}] + moves())[len(moves()) - len(moves_after_goal())]"
_AFTER = "primitives()[len(primitives()) - steps_after_goal():]"  # the steps after the goal sense
_HOME = f"{_F} == {_S} and steps_after_goal() == (0 if {_L} == {_S} else 1) and " \
        f"primitives()[-1:] == (['sense'] if {_L} == {_S} else ['navigate'])"
# after the last sense: nothing if the agent ends where it sensed, else one move
_STAY_OR_ONE = f"(primitives()[-1:] == ['sense'] if {_F} == {_L} else primitives()[-2:] == " \
               f"['sense', 'navigate'])"
# down_then_sidestep: the cell left of the walk's end is off the grid or an obstacle
_LEFT_BLOCKED = f"({_S0} == 0 or is_obstacle(({_S0} - 1, {_S1} - D)))"
_BORDER = "(x[0] == 0 or x[0] == 9 or x[1] == 0 or x[1] == 9)"
# second_goal_after_home: G the first goal visited, L the last sense, Y: the agent ends on
# another goal
_Y = f"(is_goal({_F}) and {_F} != G)"

TASKS = [
    _task("wall_of_three", 1, check_wall_of_three,
          "Explore, moving and sensing, until you know of a wall of three: three obstacles side "
          "by side in a straight line, on three cells next to one another in a row (the same "
          "j) or in a column (the same i). Stop right after the sense that first shows you such "
          "a line complete. If there is nothing more to find before that, stop right after the "
          "sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and [any(is_obstacle(c) and ({_line('c', 'K', 1, 0)} "
          f"or {_line('c', 'K', 0, 1)}) for c in K) for K in [known_before_last(), "
          f"known_cells()]] in [[False, True]] + ([[False, False]] if explored_all() and "
          f"{_FRESH} else [])"),
    _task("knight_jump", 2, check_knight_jump,
          "Get to a cell a knight's move away from your starting cell, as in chess: two cells "
          "along your row and one along your column, or two along your column and one along "
          "your row -- (i + 2, j + 1), (i + 2, j - 1), (i - 2, j + 1), (i - 2, j - 1), (i + 1, "
          "j + 2), (i + 1, j - 2), (i - 1, j + 2) or (i - 1, j - 2). Explore as much as you need "
          "to find one you can reach, and stop on it. If none of them can be reached, stop once "
          "there is nothing more to find.",
          f"{_knight_text(_F)} or (explored_all() and not any({_knight_text('c')} for c in "
          f"reachable_cells()))"),
    _task("third_downhill_move", 2, check_third_downhill_move,
          f"Explore, moving and sensing, and count your downhill moves: moves that end in a "
          f"lower row than the one they started from (a smaller j). Stop right after your "
          f"{DOWNHILL}rd downhill move: that move is your last action. If there is nothing "
          f"more to find before that, stop right after the sense that leaves nothing more to "
          f"find.",
          f"all((primitives()[-1:] == ['navigate'] and not explored_all() and P[-1][1] < "
          f"P[-2][1] and C == {DOWNHILL}) or (primitives()[-1:] == ['sense'] and explored_all() "
          f"and {_FRESH} and C < {DOWNHILL}) for P in [[{_S}] + moves()] for C in [len([k for k "
          f"in {_K100}[:len(moves())] if P[k + 1][1] < P[k][1]])])"),
    _task("down_then_sidestep", 1, check_down_then_sidestep,
          "Sense where you start, then walk down (j - 1), one cell at a time, sensing after "
          "every move, while the next cell down is inside the grid and free. Where that walk "
          "ends, take one step to the side and sense there: onto the cell to your left (i - 1) "
          "if it is inside the grid and free, otherwise onto the cell to your right (i + 1) if "
          "it is. If neither is, stop where the walk ended.",
          f"any(D >= 0 and primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and "
          f"moves()[:D] == [({_S0}, {_S1} - k) for k in {_K10}[1:D + 1]] and ({_S1} - D == 0 or "
          f"is_obstacle(({_S0}, {_S1} - D - 1))) and ((E == 1 and moves()[-1:] == [({_S0} - 1, "
          f"{_S1} - D) if not {_LEFT_BLOCKED} else ({_S0} + 1, {_S1} - D)]) or (E == 0 and "
          f"{_LEFT_BLOCKED} and ({_S0} == 9 or is_obstacle(({_S0} + 1, {_S1} - D))))) for E in "
          f"[0, 1] for D in [len(moves()) - E])"),
    _task("corner_patrol", 3, check_corner_patrol,
          "Explore, moving and sensing, until there is nothing more to find. Then patrol the "
          "corners: visit every corner cell of the grid -- (0, 0), (0, 9), (9, 0) and (9, 9) -- "
          "that you can reach, other than your starting cell, moving onto each exactly once, in "
          "any order. Then go straight back to your starting cell with one move and stop there. "
          "After the exploring, make no other moves and do not sense again; a corner you are "
          "standing on when the exploring ends still gets its move in its turn.",
          f"explored_all() and {_NEW_LAST} and all(primitives()[len(primitives()) - len(C) - 2:] "
          f"== ['sense'] + ['navigate'] * (len(C) + 1) and sorted(moves()[len(moves()) - len(C) "
          f"- 1:-1]) == C and moves()[-1:] == [{_S}] for C in [{_CORNER_LIST}])"),
    _task("crow_flies_far", 2, check_crow_flies_far,
          "Explore, moving and sensing, until there is nothing more to find. Then go with one "
          "move to the cell you can reach that lies farthest from your starting cell as the crow "
          "flies: by the straight-line distance between the cells' centres, the square root of "
          "(di * di + dj * dj), obstacles ignored. Stop there (any of them if several are "
          "equally far; if you are standing on one, just stop).",
          f"explored_all() and {_NEW_LAST} and all({_crow_text('c')} <= {_crow_text(_F)} for c "
          f"in reachable_cells()) and (primitives()[-1:] == ['sense'] or (primitives()[-2:] == "
          f"['sense', 'navigate'] and {_crow_text(_L)} < {_crow_text(_F)}))"),
    _task("second_goal_after_home", 3, check_second_goal_after_home,
          "Fetch two goals, checking in at home in between. Search for a goal. As soon as a "
          "sense shows you one, go onto it with one move (onto any of them if that sense showed "
          "several; a goal you are standing on still gets its move), then straight back to "
          "your starting cell with one more. Then search on for a second goal, a different one: "
          "as soon as you know of a goal other than the one you visited -- it may have come into "
          "view with the first -- go onto it with one move and stop there (if a sense shows you "
          "one while you are standing on it, just stop). If there is nothing more to find before "
          "you know of one, stop: right after the sense that leaves nothing more to find, or "
          "back on your starting cell if there was nothing more to find when you got there.",
          f"goal_found() and all(is_goal(G) and moves_after_goal()[:2] == [G, {_S}] and "
          f"{_AFTER}[:2] == ['navigate', 'navigate'] and all(not any(is_goal(x) and x != G for x "
          f"in [s] + neighbours(s)) for s in sensed()[:len(sensed()) - (1 if {_Y} else 0)]) and "
          f"(({_F} in [L] + neighbours(L) and ({_F} == L) == (is_goal(L) and L != G) and "
          f"(primitives()[-1:] == ['sense'] if {_F} == L else (primitives()[-2:] == ['sense', "
          f"'navigate'] or (steps_after_goal() == 3 and G in [L] + neighbours(L))))) if {_Y} "
          f"else (explored_all() and ((primitives()[-1:] == ['sense'] and {_FRESH}) or "
          f"steps_after_goal() == 2))) for G, L in [((moves_after_goal() + [{_S}])[0], "
          f"{_L})])"),
    _task("home_report_then_goal", 2, check_home_report_then_goal,
          "Search for a goal. As soon as a sense shows you one, do not go to it yet: first "
          "report at home -- go straight back to your starting cell with one move (skip this "
          "move if you are standing on it) and sense there. Then go onto the goal with one move "
          "(onto any of them if the sense that first showed you a goal showed several) and stop "
          "on it.",
          f"goal_found() and all({_AFTER} == (['navigate'] if C != {_S} else []) + ['sense', "
          f"'navigate'] and moves_after_goal() == ([{_S}] if C != {_S} else []) + [{_F}] and "
          f"sensed()[-1] == {_S} and is_goal({_F}) and {_F} in [C] + neighbours(C) for C in "
          f"[{_SIGHT_CELL}])"),
    _task("start_ring_known", 1, check_start_ring_known,
          "Explore, moving and sensing, until you know what all eight cells around your starting "
          "cell hold: the four right next to it and the four diagonal to it (those of them that "
          "lie inside the grid). Stop right after the sense that completes them. If there is "
          "nothing more to find before that, stop right after the sense that leaves nothing more "
          "to find.",
          f"primitives()[-1:] == ['sense'] and [all(x in K for n in [{_S}] + neighbours({_S}) "
          f"for x in neighbours(n) if abs(x[0] - {_S0}) <= 1 and abs(x[1] - {_S1}) <= 1) for K "
          f"in [known_before_last(), known_cells()]] in [[False, True]] + ([[False, False]] if "
          f"explored_all() and {_FRESH} else [])"),
    _task("long_search_comes_home", 2, check_long_search_comes_home,
          f"Search for a goal. As soon as a sense shows you one, go onto it with one move (onto "
          f"any of them if that sense showed several; if you are standing on one, skip the "
          f"move). Then, if finding it took you more than {LONG_SEARCH} senses -- that sense "
          f"was your {LONG_SEARCH + 1}th or later, your first sense included -- go straight back "
          f"to your starting cell with one more move and stop there; otherwise stop on the "
          f"goal.",
          f"goal_found() and {_ONLY_MOVES} and all(is_goal(G) and G in [{_L}] + "
          f"neighbours({_L}) and moves_after_goal() == ([] if G == {_L} else [G]) + ([{_S}] if "
          f"len(sensed()) > {LONG_SEARCH} else []) for G in [{_L} if is_goal({_L}) else "
          f"(moves_after_goal() + [{_L}])[0]])"),
    _task("border_goal_or_home", 2, check_border_goal_or_home,
          "Search for a goal. When a sense first shows you one, look where it lies: if that "
          "sense showed a goal on the border of the grid (a cell whose i or j is 0 or 9), go "
          "onto it with one move and stop (onto any of them if it showed several; if you are "
          "standing on one, just stop). Otherwise leave the goal alone and go straight back to "
          "your starting cell with one move, and stop there (if you are there, just stop).",
          f"goal_found() and all(((steps_after_goal() == 0 if {_L} in G else (steps_after_goal() "
          f"== 1 and primitives()[-1:] == ['navigate'])) and {_F} in G) if len(G) > 0 else "
          f"({_HOME}) for G in [[x for x in [{_L}] + neighbours({_L}) if is_goal(x) and "
          f"{_BORDER}]])"),
    _task("known_cells_nearest_goal", 3, check_known_cells_nearest_goal,
          f"Explore, moving and sensing, until you know what at least {KNOWN} cells of the grid "
          f"hold, or until there is nothing more to find if that comes first. Then go with one "
          f"move onto the goal you know of that is nearest to where you stand, counting steps "
          f"along rows and columns and ignoring obstacles (any of them if several are equally "
          f"near; if you are standing on one, just stop). If you know of no goal, go straight "
          f"back to your starting cell with one move instead (if you are there, just stop).",
          f"len([x for x in known_cells() if any(x == s or x in neighbours(s) for s in "
          f"sensed()[:-1])]) < min({KNOWN}, len(known_cells())) and (len(known_cells()) >= "
          f"{KNOWN} or explored_all()) and {_STAY_OR_ONE} and ((is_goal({_F}) and {_F} in "
          f"known_cells() and all({_d('g', _L)} >= {_d(_F, _L)} for g in known_cells() if "
          f"is_goal(g))) if goal_found() else {_F} == {_S})"),
    _task("shrinking_multiplier", 2, check_shrinking_multiplier,
          f"Scoop one to four times, then stop, with a score of at least {MULTIPLIER_SCORE}: "
          f"the grams of grains in the receiver times a multiplier that shrinks with every "
          f"scoop, 4 after one scoop, 3 after two, 2 after three and 1 after four.",
          f"scoops() >= 1 and scoops() <= 4 and delivered() * (5 - scoops()) >= "
          f"{MULTIPLIER_SCORE}", SCOOP),
    _task("spill_grace", 2, check_spill_grace,
          f"Scoop two to five times, then stop, leaving at least {GRACE_LEAST} g of grains in "
          f"the receiver and spilling no more outside the containers than {GRACE} g plus 1 g "
          f"for every {GRACE_PER} g in the receiver.",
          f"scoops() >= 2 and scoops() <= 5 and delivered() >= {GRACE_LEAST} and spilled() <= "
          f"{GRACE} + delivered() / {GRACE_PER}", SCOOP),
]
