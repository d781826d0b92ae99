"""Held-out tasks, twenty-first set: written before the next change of the synthesizer, run once
after it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout21/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (a walk right while free whose end is a
base: everything explored from there, then back to it; after exploring, back to where the longest
move ended; after exploring, home if fewer than 60 free cells are known, else onto the goal
nearest the start; a goal in the first look fetched (onto it, then home), else everything explored
and home; after exploring, a sweep of the start's row, left to right, then home; three leaps, each
onto the known free cell farthest from the start, and a sense; a peek above, then below, the start
for a goal, back home after each; onto the cell opposite the start through the grid's centre,
exploring as needed, else home once it is known that it cannot be reached; once a goal is in view,
onto it and then onto the known free border cell nearest it, else home; onto a crossroads with four
free neighbours, exploring as needed; a step onto a free neighbour, on straight that way while free,
then home; once a goal is in view, onto it, a sense, and off it onto its free neighbour farthest
from the start) and two scooping tasks (two to five scoops ending with at least 3 tokens, a token
for every full 20 g in the receiver less one for every full 15 g spilled; one to four scoops that
leave at least 50 g in the receiver and spill no more than the larger of 20 g and a quarter of
the grams in it). Each has a reference behavior (``references/``), a ground-truth ``check`` and a
faithful ``promise`` over the env's outcome helpers, so that the search can be measured apart from
the model. They were written blind: without reading the search's code, without running the
synthesizer on them and without reading the twentieth set; the first run of the search on them is
the evaluation, reported beside the development figures.

Close relatives of earlier tasks: right_end_base of heldout5's goal_base_explore_rest (a base,
everything explored, back to the base; there the first goal) and heldout17's up_then_search (a walk
while free, then a search from its end) and the development explore_all_return_home;
longest_move_revisit of heldout18's fourth_long_trip and heldout15's first_long_move (moves measured
by their length) and heldout18's first_sighting_spot and heldout10's back_to_second_look (back to a
remembered place after exploring); small_area_home_else_goal of heldout4's lone_goal_or_home (a
count after exploring picks the end) and heldout2's nearer_goal (the goal nearest the start);
first_look_fetch_or_map of heldout2's sense_goal_or_stay and heldout13's clear_start_search (a
choice on what the first look shows) and the development two_round_trips (onto a goal and home);
start_row_sweep_home of heldout4's sweep_row and heldout9's start_row_known (the start's row) and
heldout18's goals_low_to_high_home (a tour in a fixed order after exploring, then home);
three_far_leaps of heldout2's farthest_known_cell (one move to the known free cell farthest from the
start; here three, each followed by a sense) and heldout6's climb_away_from_start; peek_up_and_down
of heldout4's peek_again_if_no_goal and heldout6's up_peek_retreat (a peek and a choice on what it
showed) and heldout2's north_and_back; cross_grid_mirror of heldout19's knight_jump and heldout8's
four_in_line (a cell defined from the start, exploring as needed) and heldout16's
goal_mirror_through_start (a mirror image; there through the start); goal_to_edge of heldout19's
border_goal_or_home and the development border_cell (the grid's border) and heldout14's
homeward_side_of_goal (a cell picked near the goal); open_crossroads of heldout2's dead_end and
heldout3's touching_obstacle (a cell of a kind, exploring as needed; here four free sides) and
heldout8's row_to_junction (three free sides, on a walk); straight_run_home of heldout7's
straight_two_steps (on the way the first step went; there one more step) and heldout3's
right_then_home (a walk while free, then home); goal_far_side_step of heldout14's
homeward_side_of_goal (the goal's neighbour nearest the start, without stepping onto the goal) and
heldout15's overshoot_goal and heldout17's goal_petal_tour (onto the goal, a sense, then off it);
scoop_tokens of heldout14's scoop_points and heldout18's double_spill_penalty (grams delivered less
grams spilled, weighted; here counted in whole units); spill_cap_or_quarter of heldout19's
spill_grace and heldout6's two_scoops_threefold_clean (a spill allowed by the grams delivered; here
the larger of a fixed one and a share).

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known (then the free cells known are the reachable ones); *up* is j + 1, *down*
j - 1, *right* i + 1, *left* i - 1; a cell is *blocked* when it is an obstacle or outside the grid;
a cell's *row* is the cells with its j; the grid's *border* is the cells whose i or j is 0 or 9; a
*crossroads* is a cell whose four neighbours lie inside the grid and are free; a sense labels its
cell and the four next to it (it *shows* them; a goal *comes into view* with the first sense that
shows it); the *distance* of two cells counts steps along rows and columns (|di| + |dj|), obstacles
ignored, and a move's *length* is the distance from the cell it began in to the one it ended in.
The start cell always has a free neighbour (a goal is reachable from it and it holds none); the
references only move onto cells they know, so none ever stood on a goal when it first came into
view, and a known free cell is always reachable (it is the sensed-from cell or next to it). The
promises' language allows three comprehension loops in one expression, all of them counted
together, and 400 syntax nodes (right_end_base's promise has 398): where exploring ends on a sense
that moves may follow, that nothing more was to be found before it is read from the senses (the
last sense showed a cell no earlier sense showed), with two loops where there is room and with one
where there is not (each of the five cells the last sense showed tested against the earlier senses
written out: right_end_base, first_look_fetch_or_map, start_row_sweep_home); a pick among the
moves or the known cells is read from the last of a sorted list of tuples, where a flag sorts the
cell the agent ends in after its equals (longest_move_revisit: the length of each move with
whether it ended where the last sense was and where the agent ends, so that a longest move's end
where the agent stood is stayed on; three_far_leaps: the distance from the start of each free cell
the senses up to a leap showed, with whether it is the leap's target; goal_to_edge: the first of
the known free border cells sorted by their distance from the goal and whether they are not where
the agent ends, after a last entry (100, the agent does not end on the start) that is first only
where none is known); goal_to_edge reads the goal sense as the last sense, the steps after it being
moves only, and goal_far_side_step as the last sense or the one before it (a sense on the goal);
peek_up_and_down reads the peeks as the senses after the first, each with a move before it and one
after it, the cells peeked into being the free ones above and below the start in that order, cut
short after a peek that showed a goal; straight_run_home reads the run's step from its first move;
cross_grid_mirror, like the reaching tasks of the earlier sets, judges only where the agent ends
and what it knows then. The scooping checks weigh the grains at the end, as ``delivered()`` and
``spilled()`` do: those in the receiver, and those outside the receiver, the donor and the spoon's
tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all; on those 3,600 episodes every one of
the twelve promises was also judged against every reference (each reference run once an episode,
every promise judged on the run as ``evaluate`` judges it), and its verdict equalled its check's on
all. On those episodes the tasks' branches came up: walks right of 0 to 8 moves 102, 89, 48, 21, 18,
8, 11, 2 and 1 times, exploring always going on past the walk's end (5 to 66 senses in all) and a
move back to the base at the end; longest moves of 2 to 14 steps, a move back to one's end 285
times, staying on one 15; home with a move 70 times (fewer than 60 free cells), onto the goal
nearest the start 227, staying on one 3; a goal in the first look fetched 41 times, everything
explored and home 259; rows of 1 to 10 reachable cells swept 1, 6, 14, 9, 40, 66, 66, 57, 35 and 6
times; one, two and three leaps 6, 31 and 263 times; onto a goal in the first look 41 times, no peek
to take 36, one peek 24 times onto a goal and 105 back home, two peeks 8 times onto a goal (the
second) and 86 home; onto the opposite cell 178 times, home once it was known to be an obstacle 91
and once there was nothing more to find 31 (after 2 to 57 senses); staying on a goal on the border
92 times, a move to the border 152, home 56 (no free border cell known 47, the start the nearest 9);
onto a crossroads after 2 to 34 senses 300 times (none reachable never came up); runs of 1 to 8
cells 95, 73, 60, 27, 26, 11, 5 and 3 times; off the goal onto an empty cell 288 times and onto
another goal 12. Faithfulness on behaviors that do not do the tasks: every grid promise was judged
against 80 near misses of the references (thresholds and counts one off, other directions, sides,
cells, rows, columns, metrics or orders, the start counted or left out, a return dropped, added or
made another way, a sense added or dropped, the fallback or one branch of a choice dropped or
swapped, a move where the agent should stay) and 21 other ways of doing the tasks (other explorers,
other choices among ties or goals in view) on episodes 0-99 of seeds 0 and 1 (20,183 judged episodes
for each promise, 17 not judged: a near miss of cross_grid_mirror that aims off the grid): the near
misses kept their own task's promise on 6,458 of their 15,983 judged episodes and the other ways on
all their 4,200; three near misses did their task on every one of these episodes and kept their
promise there (open_crossroads' crossroads with only empty sides and its fallback home, which differ
only where a crossroads has a goal beside it or none is reachable, and three_far_leaps' farthest
cells by straight-line distance, which were always farthest by steps too); against the 242 grid
references of the development and earlier held-out sets up to the nineteenth on episodes 0-49 of
seed 0 (12,100 judged episodes for each promise); and against 25 trivial behaviors (stop at once,
judged on the reset; sense where it stands once and 2 to 12 times; navigate onto the cell it stands
in 1 to 12 times) on episodes 0-99 of seeds 0 and 1 (5,000 judged episodes for each promise): on
every judged episode the promise's verdict equalled the check's. Keep rates of the trivial
behaviors: none keeps any promise on any episode but sensing once, which keeps peek_up_and_down's
(22 of 200: no goal in the first look and the cells above and below the start blocked), where the
task asks for the one sense. The held-out folder tests (tests/test_synthesis_eval.py's
satisfiable-faithful-checkable test, and tests/test_certified.py's readings of every promise and its
bank test) pointed at this folder passed. The scooping references (three and two scoops from the
default sensing pose) were run on episodes 0-9 of seed 0 only (seconds an episode) and kept their
promises and did their tasks on all 10: three scoops delivered 88.2 to 140.2 g and spilled 4.5 to
20.4 g, for 3 to 7 tokens (3 needed; the two episodes with 3 had 88.2 and 99.5 g delivered, 80 g
being the fourth token's bar, and 20.4 and 15.8 g spilled, 30 g the second cost's); two scoops
delivered 61.1 to 104.0 g (50 needed: margin 11.1 g) and spilled 2.3 to 15.8 g, at least 4.2 g under
the allowance. Both promises were judged on both references and the checks agreed on every one:
three scoops kept spill_cap_or_quarter's on all 10, two scoops scoop_tokens' on 9 (65.6 g delivered
and 15.8 g spilled, for 2 tokens, on the other)."""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (goal_sense as _goal_sense, any_plan as _any_plan,
                                        FINAL as _F, LAST_SENSE as _L, NEW_LAST as _NEW_LAST,
                                        ONLY_MOVES as _ONLY_MOVES,
                                        START as _S, START_I as _S0, START_J as _S1, cell,
                                        distance, distance_text, exhausted, first_reaching,
                                        free_cell, goals_shown, grams_in_receiver, grams_spilled,
                                        held_out_task, indices, known_after, label_sensed,
                                        neighbours, onto, reachable, same_steps, scoops, step_by,
                                        steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE, UNEXPLORED

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
LEFT, RIGHT, DOWN, UP = (-1, 0), (1, 0), (0, -1), (0, 1)
SMALL_AREA = 60  # free cells known (all the reachable ones) below which the agent goes home
LEAPS = 3  # the leaps of three_far_leaps


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
    """The reachable cells, in flat-index order."""
    return [cell(x) for x in zip(*reachable(state).nonzero())]


def _on_border(c) -> bool:
    return c[0] in (0, 9) or c[1] in (0, 9)


def _exhausting(state, result):
    """The index of the sense after which nothing more was to be found (None: never)."""
    return first_reaching(state, result, lambda known: exhausted(state, known))


# --- checks -------------------------------------------------------------------------------

def check_right_end_base(state, result):
    """A sense, then a walk right, a sense after every move, while the next cell is inside the
    grid and free; exploring stops with the sense after which nothing more is to be found (the
    walk's last sense if that came during the walk); then one move onto the walk's end (nothing
    if the agent stands on it)."""
    home = state.start_cell
    plan = [("sense", home)] + _walk(state, home, RIGHT)
    steps = steps_of(result)
    if steps[:len(plan)] != plan:
        return f"began with {steps[:6]}, not the walk right {plan[:6]}"
    index = _exhausting(state, result)
    if index is None:
        return "stopped before everything was known"
    index = max(index, len(plan) - 1)
    return onto(steps[index + 1:], steps[index][1], [plan[-1][1]], "after exploring")


def check_longest_move_revisit(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then one move
    onto the cell where a longest of the moves made until then ended (length: steps along rows
    and columns between where the move began and where it ended), nothing if the agent stands
    on one."""
    index = _exhausting(state, result)
    if index is None:
        return "stopped before everything was known"
    steps = steps_of(result)
    path = [state.start_cell] + [c for kind, c in steps[:index] if kind == "navigate"]
    lengths = [distance(a, b) for a, b in zip(path, path[1:])]
    if not lengths:
        return "no move before everything was known"
    ends = [b for b, n in zip(path[1:], lengths) if n == max(lengths)]
    return onto(steps[index + 1:], steps[index][1], ends, "after exploring")


def check_small_area_home_else_goal(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then, with fewer
    than SMALL_AREA reachable cells, one move onto the start; else one move onto a reachable
    goal nearest the start (nothing if the agent stands on the target)."""
    index = _exhausting(state, result)
    if index is None:
        return "stopped before everything was known"
    home, reach = state.start_cell, reachable(state)
    if int(reach.sum()) < SMALL_AREA:
        targets = [home]
    else:
        goals = [cell(x) for x in zip(*(reach & (state.truth == GOAL)).nonzero())]
        near = min(distance(g, home) for g in goals)
        targets = [g for g in goals if distance(g, home) == near]
    steps = steps_of(result)
    return onto(steps[index + 1:], steps[index][1], targets, "after exploring")


def check_first_look_fetch_or_map(state, result):
    """A sense at the start; if it shows a goal, one move onto a goal it showed and one onto the
    start; else exploring stops with the sense after which nothing more is to be found, then
    one move onto the start (nothing if the agent is there)."""
    steps, home = steps_of(result), state.start_cell
    if steps[:1] != [("sense", home)]:
        return f"began with {steps[:1]}, not a sense at the start"
    goals = goals_shown(state, home)
    if goals:
        return _any_plan(steps[1:], [[("navigate", g), ("navigate", home)] for g in goals])
    index = _exhausting(state, result)
    if index is None:
        return "no goal in the first look, and stopped before everything was known"
    return onto(steps[index + 1:], steps[index][1], [home], "after exploring")


def check_start_row_sweep_home(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then only moves:
    onto each reachable cell of the start's row, left to right (the start included), then onto
    the start."""
    index = _exhausting(state, result)
    if index is None:
        return "stopped before everything was known"
    home = state.start_cell
    row = [c for c in _reachable_cells(state) if c[1] == home[1]]  # flat order: smallest i first
    return same_steps(steps_of(result)[index + 1:], [("navigate", c) for c in row + [home]])


def check_three_far_leaps(state, result):
    """A sense at the start; then LEAPS times: if the agent stands on a known free cell
    farthest from the start, nothing more; else one move onto one and a sense there."""
    steps, home = steps_of(result), state.start_cell
    if steps[:1] != [("sense", home)]:
        return f"began with {steps[:1]}, not a sense at the start"
    known = _unknown(state)
    label_sensed(state, known, steps[0])
    here, at = home, 1
    for leap in range(LEAPS):
        free = [cell(x) for x in zip(*(known & (state.truth != OBSTACLE)).nonzero())]
        far = max(distance(c, home) for c in free)
        targets = [c for c in free if distance(c, home) == far]
        if here in targets:
            return same_steps(steps[at:], [])
        pair = steps[at:at + 2]
        if len(pair) != 2 or pair[0][0] != "navigate" or pair[0][1] not in targets \
                or pair[1] != ("sense", pair[0][1]):
            return f"leap {leap + 1} ran {pair}, not a move onto one of {targets[:6]} and a sense"
        here = pair[0][1]
        label_sensed(state, known, pair[1])
        at += 2
    return same_steps(steps[at:], [])


def check_peek_up_and_down(state, result):
    """A sense at the start: a goal in view, one move onto one. Else, for the cell above the
    start, then the cell below, if it is inside the grid and free: a move onto it and a sense;
    a goal in view, one move onto one and nothing more; else a move back onto the start."""
    steps, home = steps_of(result), state.start_cell
    plan = [("sense", home)]
    goals = goals_shown(state, home)
    if goals:
        return _any_plan(steps, [plan + [("navigate", g)] for g in goals])
    for side in (UP, DOWN):
        peek = step_by(home, side)
        if not free_cell(state, peek):
            continue
        plan += [("navigate", peek), ("sense", peek)]
        goals = goals_shown(state, peek)
        if goals:
            return _any_plan(steps, [plan + [("navigate", g)] for g in goals])
        plan += [("navigate", home)]
    return same_steps(steps, plan)


def check_cross_grid_mirror(state, result):
    """Ends on the cell (9 - i, 9 - j) of the start (i, j) if it is reachable; else on the start,
    knowing that cell (an obstacle) or with nothing more to find."""
    home = state.start_cell
    target = (state.size - 1 - home[0], state.size - 1 - home[1])
    if reachable(state)[target]:
        return None if state.cell == target else f"ended in {state.cell}, not {target}"
    if state.cell != home:
        return f"{target} cannot be reached, and it ended in {state.cell}, not the start"
    if state.labels[target] != UNEXPLORED or exhausted(state):
        return None
    return f"ended at the start without knowing that {target} cannot be reached"


def check_goal_to_edge(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed (none if the
    agent stands on one); then one move onto a known free border cell nearest that goal
    (none if the goal is one), or, with none known, onto the start."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, home = steps[index][1], state.start_cell
    known = known_after(state, result.steps[:index + 1]) & (state.truth != OBSTACLE)
    border = [c for c in (cell(x) for x in zip(*known.nonzero())) if _on_border(c)]
    goals = [here] if state.truth[here] == GOAL else goals_shown(state, here)
    plans = []
    for g in goals:
        first = [] if g == here else [("navigate", g)]
        if border:
            near = min(distance(c, g) for c in border)
            plans += [first + ([] if c == g else [("navigate", c)])
                      for c in border if distance(c, g) == near]
        else:
            plans.append(first + [("navigate", home)])
    return _any_plan(steps[index + 1:], plans)


def _crossroads(state, c) -> bool:
    """All four cells next to ``c`` lie inside the grid and are free."""
    return all(free_cell(state, step_by(c, s)) for s in (LEFT, RIGHT, DOWN, UP))


def check_open_crossroads(state, result):
    """Ends on a reachable cell other than the start whose four neighbours lie inside the grid
    and are free; where there is none, nothing more is to be found at the end."""
    home = state.start_cell
    cells = [c for c in _reachable_cells(state) if c != home and _crossroads(state, c)]
    if cells:
        return None if state.cell in cells else f"ended in {state.cell}, not one of {cells[:6]}"
    return None if exhausted(state) else "no crossroads reachable, and more could be found"


def check_straight_run_home(state, result):
    """A sense at the start, a move onto a free neighbour and a sense there; then a walk on the
    same way, a sense after every move, while the next cell is inside the grid and free; then
    one move onto the start."""
    steps, home = steps_of(result), state.start_cell
    if len(steps) < 4 or steps[0] != ("sense", home) or steps[1][0] != "navigate":
        return f"began with {steps[:2]}, not a sense at the start and a move"
    first = steps[1][1]
    side = (first[0] - home[0], first[1] - home[1])
    if side not in (LEFT, RIGHT, DOWN, UP) or not free_cell(state, first):
        return f"the first move went to {first}, not a free cell next to the start"
    plan = [("sense", home), ("navigate", first), ("sense", first)] \
        + _walk(state, first, side) + [("navigate", home)]
    return same_steps(steps, plan)


def check_goal_far_side_step(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed and a sense
    there (neither if the agent stands on one); then one move onto a free cell next to that
    goal farthest from the start."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, home = steps[index][1], state.start_cell
    goals = [here] if state.truth[here] == GOAL else goals_shown(state, here)
    plans = []
    for g in goals:
        free = [n for n in neighbours(state, g) if free_cell(state, n)]
        far = max(distance(n, home) for n in free)
        first = [] if g == here else [("navigate", g), ("sense", g)]
        plans += [first + [("navigate", n)] for n in free if distance(n, home) == far]
    return _any_plan(steps[index + 1:], plans)


TOKEN_GRAMS, TOKEN_SPILL, TOKENS = 20, 15, 3  # a token per full 20 g delivered, less one per
#                                              full 15 g spilled; tokens needed
CAP_LEAST, CAP_GRAMS, CAP_SHARE = 50, 20, 4  # grams delivered, at least; grams spilled allowed:
#                                             the larger of CAP_GRAMS and 1/CAP_SHARE of those


def check_scoop_tokens(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    tokens = mass // TOKEN_GRAMS - spilled // TOKEN_SPILL
    return None if tokens >= TOKENS else \
        f"{tokens:.0f} token(s): {mass:.1f} g delivered and {spilled:.1f} g spilled"


def check_spill_cap_or_quarter(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    if mass < CAP_LEAST or spilled > max(CAP_GRAMS, mass / CAP_SHARE):
        return f"{mass:.1f} g delivered and {spilled:.1f} g spilled in {n} scoop(s)"
    return None


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_K4, _K10, _K100 = indices(4), indices(10), indices(100)


def _d(a: str, b: str = _S) -> str:
    return distance_text(a, b)


def _blocked(i: str, j: str) -> str:
    """The cell (i, j) is off the grid or an obstacle."""
    return f"(not (0 <= {i} <= 9 and 0 <= {j} <= 9) or is_obstacle(({i}, {j})))"


_E = "sensed()[:-1]"
# the last sense showed a cell no earlier sense showed (then nothing more was to be found
# before it): a cell x is shown by a sense at s when s is x or next to it; one loop
_NEW_ONE = f"any(x not in {_E} and (x[0] + 1, x[1]) not in {_E} and (x[0] - 1, x[1]) not in " \
           f"{_E} and (x[0], x[1] + 1) not in {_E} and (x[0], x[1] - 1) not in {_E} for x in " \
           f"[{_L}] + neighbours({_L}))"
# after the last sense: nothing if the agent ends where it sensed, else one move
_STAY_OR_ONE = f"(primitives()[-1:] == ['sense'] if {_F} == {_L} else primitives()[-2:] == " \
               f"['sense', 'navigate'])"
# goal_far_side_step: Q the place of the goal sense, G the goal gone onto
_Q = "(sensed()[-2] if steps_after_goal() == 3 else sensed()[-1])"
# the cell the agent stood in before each move k
_P = f"([{_S}] + moves())"
_UP_CELL, _DOWN_CELL = f"({_S0}, {_S1} + 1)", f"({_S0}, {_S1} - 1)"
# peek_up_and_down: the cells above and below the start that are inside the grid and free
_PEEKS = f"(([{_UP_CELL}] if {_S1} < 9 and not is_obstacle({_UP_CELL}) else []) + " \
         f"([{_DOWN_CELL}] if {_S1} > 0 and not is_obstacle({_DOWN_CELL}) else []))"
_MIRROR = f"(9 - {_S0}, 9 - {_S1})"
# longest_move_revisit: the length of move k (steps along rows and columns)
_MOVE_LENGTH = _d(f"{_P}[k]", "moves()[k]")
# straight_run_home: the step of the first move
_DI, _DJ = f"(moves()[0][0] - {_S0})", f"(moves()[0][1] - {_S1})"


def _border_text(c: str) -> str:
    return f"({c}[0] == 0 or {c}[0] == 9 or {c}[1] == 0 or {c}[1] == 9)"


def _goal_in_view(c: str) -> str:
    return f"any(is_goal(x) for x in [{c}] + neighbours({c}))"


def _crossroads_text(c: str) -> str:
    return f"(0 < {c}[0] < 9 and 0 < {c}[1] < 9 and not any(is_obstacle(x) for x in " \
           f"neighbours({c})))"


TASKS = [
    _task("right_end_base", 2, check_right_end_base,
          "Set up base at the end of your row. Sense where you start, then walk right (i + 1), "
          "one cell at a time, sensing after every move, while the next cell to the right is "
          "inside the grid and free; the cell where that walk ends is your base. From there, "
          "explore, moving and sensing, until there is nothing more to find. Then go back to "
          "your base with one move and stop there (if you are standing on it, just stop). If "
          "there is nothing more to find before the walk ends, finish the walk and stop at its "
          "end.",
          f"explored_all() and any(primitives()[:2 * R + 1] == ['sense'] + ['navigate', 'sense'] "
          f"* R and moves()[:R] == [({_S0} + k, {_S1}) for k in {_K10}[1:R + 1]] and "
          f"{_blocked(f'{_S0} + R + 1', _S1)} and {_F} == ({_S0} + R, {_S1}) and "
          f"(len(sensed()) == R + 1 or {_NEW_ONE}) for R in {_K10}) and {_STAY_OR_ONE}"),
    _task("longest_move_revisit", 2, check_longest_move_revisit,
          "Explore, moving and sensing, until there is nothing more to find. Then go back with "
          "one move to the cell where your longest move ended: the move, of those you made while "
          "exploring, that covered the most steps along rows and columns between the cell it "
          "began in and the cell it ended in, obstacles ignored. Stop there (any of them if "
          "several moves were equally long; if you are standing on one, just stop).",
          f"explored_all() and {_NEW_LAST} and {_STAY_OR_ONE} and sorted([({_MOVE_LENGTH}, "
          f"moves()[k] == {_L}, moves()[k] == {_F}) for k in {_K100}[:len(moves()) - (0 if {_F} == "
          f"{_L} else 1)]])[-1][1:] == ({_F} == {_L}, True)"),
    _task("small_area_home_else_goal", 2, check_small_area_home_else_goal,
          f"Explore, moving and sensing, until there is nothing more to find. Then count the free "
          f"cells you know (empty cells and goals). If there are fewer than {SMALL_AREA}, go "
          f"straight back to your starting cell with one move (if you are there, just stop). "
          f"Otherwise go with one move onto the goal nearest to your starting cell, counting "
          f"steps along rows and columns and ignoring obstacles, and stop there (any of them if "
          f"several are equally near; if you are standing on one, just stop).",
          f"explored_all() and {_NEW_LAST} and {_STAY_OR_ONE} and ({_F} == {_S} if "
          f"len(reachable_cells()) < {SMALL_AREA} else (is_goal({_F}) and all({_d('g')} >= "
          f"{_d(_F)} for g in reachable_goals()) and ({_F} == {_L} or not is_goal({_L}) or "
          f"{_d(_L)} > {_d(_F)})))"),
    _task("first_look_fetch_or_map", 2, check_first_look_fetch_or_map,
          "Sense where you start. If that first look shows you a goal, fetch it: go onto it with "
          "one move (onto any of them if it showed several), then straight back to your starting "
          "cell with one more, and stop. If it shows you no goal, map the area instead: explore, "
          "moving and sensing, until there is nothing more to find, then go straight back to "
          "your starting cell with one move and stop there (if you are there, just stop).",
          f"primitives()[:1] == ['sense'] and sensed()[:1] == [{_S}] and ((primitives() == "
          f"['sense', 'navigate', 'navigate'] and is_goal(moves()[0]) and moves()[0] in "
          f"neighbours({_S}) and moves()[1] == {_S}) if {_goal_in_view(_S)} else (explored_all() "
          f"and {_NEW_ONE} and {_F} == {_S} and {_STAY_OR_ONE}))"),
    _task("start_row_sweep_home", 2, check_start_row_sweep_home,
          "Explore, moving and sensing, until there is nothing more to find. Then, without "
          "sensing again, sweep the row you started in: move onto every cell of that row (the "
          "cells whose j is that of your starting cell) that you can reach, one move each, from "
          "left to right -- smallest i first -- your starting cell included in its place (a cell "
          "you are standing on still gets its move). Then go straight back to your starting cell "
          "with one move and stop there.",
          f"explored_all() and {_NEW_ONE} and all(primitives()[len(primitives()) - len(R) - 2:] "
          f"== ['sense'] + ['navigate'] * (len(R) + 1) and moves()[len(moves()) - len(R) - 1:] == "
          f"R + [{_S}] for R in [[c for c in reachable_cells() if c[1] == {_S1}]])"),
    _task("three_far_leaps", 2, check_three_far_leaps,
          f"Leap outward {LEAPS} times. Sense where you start. Then, {LEAPS} times over: go with "
          f"one move to the free cell you know (empty or a goal) that lies farthest from your "
          f"starting cell, counting steps along rows and columns and ignoring obstacles (any of "
          f"them if several are equally far), and sense there. If you are already standing on "
          f"such a farthest cell when it is time to leap, stop there instead.",
          f"len(moves()) <= {LEAPS} and primitives() == ['sense'] + ['navigate', 'sense'] * "
          f"len(moves()) and all(sorted([({_d('x')}, x == (moves() + [{_F}])[k]) for s in "
          f"sensed()[:k + 1] for x in [s] + neighbours(s) if not is_obstacle(x)])[-1] == "
          f"({_d('(moves() + [final_cell()])[k]')}, True) and (k == len(moves()) or "
          f"{_d(f'{_P}[k]')} < {_d('(moves() + [final_cell()])[k]')}) for k in "
          f"{_K4}[:min(len(moves()) + 1, {LEAPS})])"),
    _task("peek_up_and_down", 2, check_peek_up_and_down,
          "Peek above and below you for a goal. Sense where you start; if that shows you a goal, "
          "go onto it with one move and stop (onto any of them if it showed several). Otherwise "
          "peek up: if the cell above you (j + 1) is inside the grid and free, step onto it and "
          "sense there; if that shows you a goal, go onto it with one move and stop; if not, "
          "step back down onto your starting cell. Then peek down the same way: if the cell "
          "below your starting cell (j - 1) is inside the grid and free, step onto it and sense; "
          "if that shows you a goal, go onto it with one move and stop; if not, step back up "
          "onto your starting cell. If no peek showed you a goal, stop on your starting cell.",
          f"primitives() == ['sense'] + ['navigate', 'sense', 'navigate'] * (len(sensed()) - 1) + "
          f"(['navigate'] if len(sensed()) == 1 and is_goal({_F}) else []) and moves()[:2 * "
          f"len(sensed()) - 2:2] == sensed()[1:] and moves()[1:2 * len(sensed()) - 3:2] == "
          f"[{_S}] * (len(sensed()) - 2) and sensed()[1:] == {_PEEKS}[:len(sensed()) - 1 + (0 if "
          f"is_goal({_F}) else 9)] and not any(is_goal(x) for s in sensed()[:-1] for x in [s] + "
          f"neighbours(s)) and ((is_goal({_F}) and {_F} in neighbours({_L})) if "
          f"{_goal_in_view(_L)} else {_F} == {_S})"),
    _task("cross_grid_mirror", 2, check_cross_grid_mirror,
          "Cross the grid: get to the cell opposite your starting cell through the centre of the "
          "grid, (9 - i, 9 - j) for a start (i, j), exploring as much as you need, and stop on "
          "it. If you find that you cannot get there -- you learn that the cell holds an "
          "obstacle, or there is nothing more to find and you have not been able to reach it -- "
          "go back to your starting cell and stop there instead.",
          f"{_F} == {_MIRROR} or ({_F} == {_S} and {_MIRROR} not in reachable_cells() and "
          f"(explored_all() or {_MIRROR} in known_cells()))"),
    _task("goal_to_edge", 3, check_goal_to_edge,
          "Search for a goal. As soon as a sense shows you one, go onto it with one move (onto "
          "any of them if that sense showed several; if you are standing on one, skip the move). "
          "Then take it to the edge: go with one more move to the free cell you know on the "
          "border of the grid (a cell whose i or j is 0 or 9) that is nearest to that goal, "
          "counting steps along rows and columns and ignoring obstacles, and stop there (any of "
          "them if several are equally near; if the goal itself is on the border, stay on it). "
          "If you know of no free cell on the border, go straight back to your starting cell "
          "with one move instead.",
          f"goal_found() and {_ONLY_MOVES} and all(is_goal(G) and G in [{_L}] + neighbours({_L}) "
          f"and moves_after_goal() == ([] if G == {_L} else [G]) + ([] if {_F} == G else [{_F}]) "
          f"and not sorted([({_d('c', 'G')}, c != {_F}) for c in known_cells() if "
          f"{_border_text('c')} and not is_obstacle(c)] + [(100, {_F} != {_S})])[0][1] for G in "
          f"[{_L} if is_goal({_L}) else (moves_after_goal() + [{_L}])[0]])"),
    _task("open_crossroads", 2, check_open_crossroads,
          "Find an open crossroads and stand on it: a cell other than your starting cell whose "
          "four neighbours -- left (i - 1), right (i + 1), above (j + 1) and below (j - 1) -- "
          "all lie inside the grid and are free (empty or goals). Explore as much as you need, "
          "go to one you can reach and stop there. If no such cell can be reached, stop once "
          "there is nothing more to find.",
          f"({_F} != {_S} and {_crossroads_text(_F)}) or (explored_all() and not any(c != {_S} "
          f"and {_crossroads_text('c')} for c in reachable_cells()))"),
    _task("straight_run_home", 1, check_straight_run_home,
          "Sense where you start, then step onto any free cell right next to you (left, right, "
          "above or below) and sense there. Then keep going straight on the same way, one cell "
          "at a time, sensing after every move, while the next cell that way is inside the grid "
          "and free. When you cannot go on, go straight back to your starting cell with one "
          "move and stop.",
          f"len(moves()) >= 2 and moves()[0] in neighbours({_S}) and primitives() == ['sense'] + "
          f"['navigate', 'sense'] * (len(moves()) - 1) + ['navigate'] and moves() == [({_S0} + k "
          f"* (moves()[0][0] - {_S0}), {_S1} + k * (moves()[0][1] - {_S1})) for k in "
          f"{_K10}[1:len(moves())]] + [{_S}] and "
          f"{_blocked(f'{_S0} + len(moves()) * {_DI}', f'{_S1} + len(moves()) * {_DJ}')}"),
    _task("goal_far_side_step", 2, check_goal_far_side_step,
          "Search for a goal. As soon as a sense shows you one, go onto it with one move and "
          "sense there (onto any of them if that sense showed several; if you are standing on "
          "one, skip the move and the sense). Then step off it on its far side: go with one move "
          "onto the free cell right next to that goal (left, right, above or below; empty or a "
          "goal) that lies farthest from your starting cell, counting steps along rows and "
          "columns, and stop there (any of them if several are equally far).",
          f"goal_found() and all(is_goal(G) and G in [Q] + neighbours(Q) and "
          f"primitives()[len(primitives()) - steps_after_goal():] == (['navigate'] if G == Q "
          f"else ['navigate', 'sense', 'navigate']) and moves_after_goal() == ([] if G == Q else "
          f"[G]) + [{_F}] and {_F} in neighbours(G) and not is_obstacle({_F}) and all({_d('y')} "
          f"<= {_d(_F)} for y in neighbours(G) if not is_obstacle(y)) for Q in [{_Q}] for G in "
          f"[Q if is_goal(Q) else (moves_after_goal() + [Q])[0]])"),
    _task("scoop_tokens", 2, check_scoop_tokens,
          f"Scoop two to five times, then stop, ending with at least {TOKENS} tokens: every full "
          f"{TOKEN_GRAMS} g of grains in the receiver earns a token ({TOKEN_GRAMS * 2 + 5} g earns "
          f"2), "
          f"and every full {TOKEN_SPILL} g of grains spilled outside the containers costs one "
          f"({TOKEN_SPILL + 5} g spilled costs 1).",
          f"scoops() >= 2 and scoops() <= 5 and delivered() // {TOKEN_GRAMS} - spilled() // "
          f"{TOKEN_SPILL} >= {TOKENS}", SCOOP),
    _task("spill_cap_or_quarter", 2, check_spill_cap_or_quarter,
          f"Scoop one to four times, then stop, with at least {CAP_LEAST} g of grains in the "
          f"receiver, spilling no more outside the containers than {CAP_GRAMS} g or a quarter of "
          f"the grams in the receiver, whichever is larger.",
          f"scoops() >= 1 and scoops() <= 4 and delivered() >= {CAP_LEAST} and spilled() <= "
          f"max({CAP_GRAMS}, delivered() / {CAP_SHARE})", SCOOP),
]
