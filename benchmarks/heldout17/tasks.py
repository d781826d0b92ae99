"""Held-out tasks, seventeenth set: written before the next change of the synthesizer, run once
after it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout17/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (exploring that stops once senses have been
taken in all four quarters of the grid; exploring that stops once an obstacle is known somewhere in
the start's row and one somewhere in its column; a walk right that turns up into the first opening
above it; a walk up, then a search from where it ended, cut short by a goal seen on the walk; once
a goal is in view, onto it, a sense, and a trip out to each free cell next to it and back; after
exploring, a delivery trip from the start to every reachable goal; once a goal is in view, home
first if more moves were made than the goal is steps from the start, then onto it; once a goal is
in view, onto it and home if it is five or more steps from the start; once a goal is in view,
onto it, a sense, and home if two or more obstacles are next to it; once a goal is in view, back
to the place sensed from with the most free cells next to it; after exploring, onto the reachable
cell nearest the grid's centre; once a goal is in view, onto it if that sense showed more empty
cells than obstacles, else back to where the sense before it was taken) and two scooping tasks
(two to five scoops that net at least 18 g a scoop, delivered less spilled; one to four scoops
with a haul of at least 60, the grams delivered times the share of the grains moved that landed).
Each has a reference behavior (``references/``), a ground-truth ``check`` and a faithful
``promise`` over the env's outcome helpers, so that the search can be measured apart from the
model. They were written on 2026-12-07 blind: without reading the search's code and without
running the synthesizer on them; the first run of the search on them is the evaluation, reported
beside the development figures.

Close relatives of earlier tasks: four_quarters_sensed of heldout6's four_rows_visited and
heldout12's both_sides_then_home (stops on where the agent has been; here a sense in each quarter)
and heldout14's map_six_wide; row_and_column_obstacle of heldout6's two_obstacles_in_start_column,
heldout9's start_row_known and heldout13's four_ray_lengths (the start's row and column; here an
obstacle anywhere along each, not the first one out of the start); right_then_up_at_opening of
heldout10's up_until_second_opening and heldout8's row_to_junction (a walk that stops on what lies
beside it; here it turns there and walks on) and heldout3's up_then_right (two walks in a row);
up_then_search of heldout3's down_until_goal_or_blocked and heldout10's right_walk_then_first_goal
(a walk that a goal in view cuts short; here a search follows it); goal_petal_tour of heldout6's
ordered_neighbour_tour (the start's neighbours, in a given order), heldout11's goal_shuttle and
heldout13's scout_goal_surroundings; goal_deliveries of heldout4's explore_then_goal_tour and
heldout9's nearest_first_goal_tour (tours after exploring; here home between goals) and heldout6's
hub_search; wandered_home_first of heldout15's home_first_if_nearer (home on the way to the goal;
there when the goal is nearer the start than the agent) and heldout6's quick_find_or_home (moves
counted before a goal is seen); far_goal_comes_home of heldout7's distant_goal (goals by their
distance from the start) and the development goal_sense_home; goal_inspection of heldout16's
clutter_turns_home (home on obstacles a sense showed; there the goal sense's) and heldout8's
goal_chain (a sense on the goal decides what follows); best_view_return of heldout4's
most_obstacles_spot, heldout16's highest_look_after_goal and heldout5's goal_then_farthest_look
(back to a place sensed from, picked by a comparison; here the most free cells next to it);
centre_park of heldout4's centre_neighbour (the centre of the grid; there one step from the start)
and heldout15's centre_of_search; roomy_goal_or_back of heldout16's clutter_turns_home and
heldout12's obstacle_parity_goal (goal or not on what was seen; here a count of empty cells against
obstacles) and heldout11's lookback_three (back to where the agent was); net_yield_per_scoop of
heldout7's three_scoops_net_gain (grams delivered less spilled; here for every scoop) and
heldout15's scoop_on_pace; landed_weighted_haul of heldout16's landed_share (the share of what was
moved that landed; here it weighs the grams delivered) and heldout14's scoop_points.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a cell is
*blocked* when it is an obstacle or outside the grid; a cell's *row* is the cells with its j, its
*column* those with its i; the *quarters* of the grid are bottom-left (i <= 4, j <= 4), top-left
(i <= 4, j >= 5), bottom-right (i >= 5, j <= 4) and top-right (i >= 5, j >= 5); a sense labels its
cell and the four around it (it *shows* them; a goal *comes into view* with the first sense that
shows it); the cells *next to* a cell are its four neighbours inside the grid (the grid's edge
does not count), so its *free cells next to it* are those of them that are free; the *distance*
of two cells counts steps along rows and columns (|di| + |dj|), obstacles ignored, and the
distance to the centre (4.5, 4.5) is |i - 4.5| + |j - 4.5| (the checks and promises use twice it,
|2 i - 9| + |2 j - 9|); a walk's *moves* are the navigate steps it made. The start cell always has
a free neighbour (a goal is reachable from it and it holds none); the references only move onto
cells they know, so none ever stood on a goal when it first came into view, and a known free cell
is always reachable (it is the sensed-from cell or next to it). The promises' language allows
three comprehension loops in one expression, all of them counted together, and 400 syntax nodes
(right_then_up_at_opening's promise has 344): where the steps after the goal sense may be moves
only, the goal sense is read as the last sense (``_STAY_OR_ONE``, ``_ONTO_GOAL``, ``_ONLY_MOVES``);
where a sense on the goal may follow it (goal_petal_tour, goal_inspection), whether one does
(a sense among the steps after the goal sense, or two or more steps after it) says whether the goal
sense is the last sense or the one before; the moves made before the goal sense are all the moves
less those after it (wandered_home_first); where exploring ends on a sense after which nothing more
was to be found, that it was not so before is read from ``known_before_last()``
(four_quarters_sensed, row_and_column_obstacle) or, where moves follow it, from the senses (the
last sense showed a cell no earlier sense showed: goal_deliveries, centre_park, as in heldout14);
four_quarters_sensed lists the quarters of the senses before the last once and asks the last to
make four of them, or, with nothing more to find, fewer; row_and_column_obstacle reads, before
the last step and after it, whether the known obstacles in the start's row and column (a row one
counted True, a column one False) hold both kinds, and asks for [False, True], or [False, False]
with nothing more to find; right_then_up_at_opening reads the walk right's length R from the
moves (the moves are R cells right, then up) and the walk's cells from the start and the moves;
up_then_search reads the walk as the first 2 R + 1 steps, cut short by the goal sense if that is
sense R, else ended by a blocked cell; a promise whose target is a choice among ties lets the agent
stay only where the cell it stands in is as good as the target, and move only where that cell is
strictly worse (best_view_return compares (free cells next to it, 1 for the goal sense's own cell
else 0) and takes the largest); goal_deliveries' trips are the last 2 n moves (n the reachable
goals): every other one onto the start, the others onto the goals, each once. The scooping checks
weigh the grains at the end, as ``delivered()`` and ``spilled()`` do: those in the receiver, and
those outside the receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all; on those 3,600 episodes every one of
the twelve promises was also judged against every reference (each reference run once an episode,
every promise judged on the run as ``evaluate`` judges it), and its verdict equalled its check's on
all. On those episodes the tasks' branches came up: exploring stopped on the fourth quarter 278
times (after 7 to 51 senses), with nothing more to find first 22; an obstacle in the start's row and
one in its column known after the first sense 59 times, the 2nd to 5th 72 and later 155 (up to the
57th), nothing more to find first 14 (after 41 to 61 senses); no move right 102 times, walks right
that turned up 143 (at the first cell moved into 128 times, the 2nd to 4th 15; walks up of 1 to 7
moves) and walks right blocked with no opening 55; a goal in view on the walk up 70 times (26 from
the start), after it 230 (after walks of 0 to 7 moves 98, 45, 34, 30, 10, 10, 1 and 2 times); trips
out from the goal to 1, 2, 3 and 4 free cells 23, 90, 122 and 65 times; deliveries to 1, 2 and 3
reachable goals 21, 61 and 218 times; home first 167 times, straight onto the goal 133 (0 to 52
moves before the goal sense); home from a goal 5 or more steps away 161 times, staying on a nearer
one 139; home from a goal with two or more obstacles next to it 68 times, staying 232; moving back
to the place with the most free cells 163 times, staying 137; parking with one move 297 times,
staying 3 (on one of the four middle cells 280 times); onto a goal after a roomy goal sense 257
times (33 seen from the start), back to the place before a crowded one 35, staying after a crowded
first sense 8. Faithfulness on behaviors that do not do the tasks: every grid promise was judged
against 61 near misses of the references (thresholds one off, other directions, quarters or rows,
measures, metrics or places to go, the start or the grid's edge counted, a condition or a return
dropped, a sense late, missing or extra, a move extra or missing, unknown cells taken for free) and
20 other ways of doing the tasks (another explorer, another choice among ties or goals, another
order of the deliveries) on episodes 0-99 of seeds 0 and 1 (16,200 judged episodes for each promise,
none lost): the near misses kept their own task's promise on 5,917 of their 12,200 judged episodes
and the other ways on all their 4,000; one near miss did its task on every one of these episodes and
kept its promise there (centre_park's move when the agent stands on a cell as near the centre as the
target, which never happened there); against the 219 grid references of the development and earlier
held-out sets on episodes 0-49 of seed 0 (10,950 judged episodes for each promise, none lost); and
against 3 trivial behaviors (stop at once, judged on the reset; sense once; navigate onto the cell
it stands in) on episodes 0-99 of seeds 0 and 1: on every judged episode the promise's verdict
equalled the check's. Keep rates of the trivial behaviors: stopping at once and navigating onto the
cell it stands in keep no promise on any episode; sensing once keeps none but
row_and_column_obstacle's (36 of 200: obstacles next to the start in its row and its column),
right_then_up_at_opening's (64: the cell right of the start blocked), best_view_return's (29: a goal
in view from the start, the only place sensed from) and roomy_goal_or_back's (5: a crowded goal
sense from the start, the first sense), where the task asks for the one sense. The held-out folder
tests (tests/test_synthesis_eval.py's satisfiable-faithful-checkable test, and
tests/test_certified.py's readings of every promise and its bank test) pointed at this folder
passed. The scooping references (two and three scoops from the default sensing pose) were run on
episodes 0-9 of seed 0 only (seconds an episode) and kept their promises and did their tasks on all
10; on episodes 0-7, where the grams were recorded, two scoops delivered 61.1 to 97.3 g and spilled
4.5 to 22.6 g, netting 24.85 to 43.0 g a scoop (18 needed: margin 6.85 g a scoop); three scoops
delivered 88.2 to 133.5 g and spilled 4.5 to 24.9 g, for hauls of 79.2 to 123.1 (60 needed: margin
19.2). The thresholds were set from these figures and from heldout16's (two scoops over episodes
0-19 delivered at least 58.8 g and spilled at most 22.6 g, so a net of at least 36.2 g, 18.1 g a
scoop); a dock-from-below task first written in wandered_home_first's place was dropped: the cell
below a goal was known to be free when the goal came into view on only 12 of 200 episodes. Both
promises were judged on both references on episodes 0-7, and the checks agreed on every one: three
scoops kept net_yield_per_scoop's on all 8, two scoops landed_weighted_haul's on 6 (hauls of 52.1
and 56.9 on the others)."""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (goal_sense as _goal_sense, any_plan as _any_plan,
                                        FINAL as _F, FRESH as _FRESH, LAST_SENSE as _L,
                                        NEW_LAST as _NEW_LAST, ONLY_MOVES as _ONLY_MOVES,
                                        ONTO_GOAL as _ONTO_GOAL, START as _S, START_I as _S0,
                                        START_J as _S1, cell, distance, distance_text, exhausted,
                                        first_reaching, free_cell,
                                        free_neighbours, goals_shown, grams_in_receiver,
                                        grams_spilled, held_out_task, indices, label_sensed,
                                        obstacles_beside, onto, onto_goal_seen, reachable,
                                        same_steps, scoops, sensed_cells, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import EMPTY, GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
LEFT, RIGHT, DOWN, UP = (-1, 0), (1, 0), (0, -1), (0, 1)
HALF = 5  # a cell is in the right half when i >= HALF, the top half when j >= HALF
FAR = 5  # steps from the start that make a goal far (far_goal_comes_home)
CROWDED_GOAL = 2  # obstacles next to a goal that send goal_inspection home


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


def _quarter(c) -> int:
    """The quarter of the grid ``c`` lies in: 0 bottom-left, 1 top-left, 2 bottom-right, 3
    top-right."""
    return 2 * (c[0] >= HALF) + (c[1] >= HALF)


def _off_centre(c) -> int:
    """Twice the distance from ``c`` to the grid's centre (4.5, 4.5), along rows and columns."""
    return abs(2 * c[0] - 9) + abs(2 * c[1] - 9)


# --- checks -------------------------------------------------------------------------------

def check_four_quarters_sensed(state, result):
    """Exploring stops with the first sense after which the senses have been taken in all four
    quarters of the grid, or nothing more is to be found."""
    steps, known, quarters = steps_of(result), _unknown(state), set()
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] != "sense":
            continue
        quarters.add(_quarter(step[1]))
        if len(quarters) == 4 or exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return f"stopped having sensed in {len(quarters)} quarter(s), before everything was known"


def check_row_and_column_obstacle(state, result):
    """Exploring stops with the first sense after which an obstacle in the start's row and an
    obstacle in the start's column are known, or nothing more is to be found."""
    i, j = state.start_cell

    def both(known):
        seen = known & (state.truth == OBSTACLE)
        return bool(seen[:, j].any() and seen[i, :].any())
    index = first_reaching(state, result, lambda known: both(known) or exhausted(state, known))
    if index is None:
        return "never knew an obstacle in both the start's row and column, and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_right_then_up_at_opening(state, result):
    """A sense, then a walk right, a sense after every move, while the next cell is inside the
    grid and free, up to the first cell moved into whose upper neighbour is free; from there a
    walk up, a sense after every move, while the next cell is inside the grid and free."""
    home = state.start_cell
    plan, here = [("sense", home)], home
    while free_cell(state, step_by(here, RIGHT)):
        here = step_by(here, RIGHT)
        plan += [("navigate", here), ("sense", here)]
        if free_cell(state, step_by(here, UP)):
            plan += _walk(state, here, UP)
            break
    return same_steps(steps_of(result), plan)


def check_up_then_search(state, result):
    """A sense, then a walk up, a sense after every move, while the next cell is inside the grid
    and free, cut short by the first sense that shows a goal; after a whole walk any search; then
    one move onto a goal the first goal sense showed (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    home = state.start_cell
    walk = [("sense", home)] + _walk(state, home, UP)
    seen = [t for t, (kind, c) in enumerate(walk) if kind == "sense" and goals_shown(state, c)]
    want = walk[:seen[0] + 1] if seen else walk
    if steps[:len(want)] != want:
        return f"began {steps[:8]}, not the walk up {want[:8]}"
    return onto_goal_seen(state, steps, index)


def check_goal_petal_tour(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed and a sense there
    (neither if the agent stands on one); then, for each free cell next to that goal, once each
    in any order, a move onto it and a move back onto the goal, and nothing else."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, rest = steps[index][1], steps[index + 1:]
    if state.truth[here] == GOAL:
        goal, tour = here, rest
    else:
        goal = rest[0][1] if rest else None
        if goal not in goals_shown(state, here) or rest[:2] != [("navigate", goal),
                                                               ("sense", goal)]:
            return f"after the goal came into view ran {rest[:3]}, not a move onto a goal it " \
                   f"showed and a sense there"
        tour = rest[2:]
    petals = sorted(free_neighbours(state, goal))
    visits = tour[0::2]
    if len(tour) != 2 * len(petals) or tour[1::2] != [("navigate", goal)] * len(petals) \
            or any(kind != "navigate" for kind, _ in visits) \
            or sorted(c for _, c in visits) != petals:
        return f"from goal {goal} ran {tour[:8]}, not out to each of {petals} and back"
    return None


def check_goal_deliveries(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then only moves:
    onto each reachable goal once, in any order, each followed by a move onto the start."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    rest, home = steps_of(result)[index + 1:], state.start_cell
    goals = sorted(cell(x) for x in zip(*(reachable(state) & (state.truth == GOAL)).nonzero()))
    if [kind for kind, _ in rest] != ["navigate"] * (2 * len(goals)) \
            or [c for _, c in rest[1::2]] != [home] * len(goals) \
            or sorted(c for _, c in rest[0::2]) != goals:
        return f"after exploring ran {rest[:8]}, not a trip from {home} to each of the goals " \
               f"{goals}"
    return None


def check_wandered_home_first(state, result):
    """After the sense that first shows a goal: a move onto the start if more moves came before
    that sense than a goal it showed is steps from the start (none if the agent stands on the
    start), then a move onto that goal (nothing at all if the agent stands on a goal)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, rest, home = steps[index][1], steps[index + 1:], state.start_cell
    if state.truth[here] == GOAL:
        return same_steps(rest, [])
    made = sum(kind == "navigate" for kind, _ in steps[:index])
    plans = [([("navigate", home)] if made > distance(g, home) and here != home else [])
             + [("navigate", g)] for g in goals_shown(state, here)]
    return _any_plan(rest, plans)


def check_far_goal_comes_home(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed (none if the
    agent stands on one), then one move onto the start if that goal is FAR or more steps from
    it."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, home = steps[index][1], state.start_cell
    goals = [here] if state.truth[here] == GOAL else goals_shown(state, here)
    plans = [([] if g == here else [("navigate", g)])
             + ([("navigate", home)] if distance(g, home) >= FAR else []) for g in goals]
    return _any_plan(steps[index + 1:], plans)


def check_goal_inspection(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed and a sense there
    (neither if the agent stands on one), then one move onto the start if that goal has
    CROWDED_GOAL or more obstacles next to it."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, home = steps[index][1], state.start_cell
    goals = [here] if state.truth[here] == GOAL else goals_shown(state, here)
    plans = [([] if g == here else [("navigate", g), ("sense", g)])
             + ([("navigate", home)] if obstacles_beside(state, g) >= CROWDED_GOAL else [])
             for g in goals]
    return _any_plan(steps[index + 1:], plans)


def check_best_view_return(state, result):
    """After the sense that first shows a goal: one move onto a cell sensed from (up to that
    sense) with the most free cells next to it (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    senses = [c for kind, c in steps[:index + 1] if kind == "sense"]
    room = {c: len(free_neighbours(state, c)) for c in senses}
    top = max(room.values())
    return onto(steps[index + 1:], steps[index][1], [c for c in senses if room[c] == top],
                "after the goal came into view")


def check_centre_park(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then one move
    onto a reachable cell nearest the grid's centre (nothing if the agent stands on one)."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    steps = steps_of(result)
    free = [cell(x) for x in zip(*reachable(state).nonzero())]
    best = min(_off_centre(c) for c in free)
    return onto(steps[index + 1:], steps[index][1],
                [c for c in free if _off_centre(c) == best], "after exploring")


def check_roomy_goal_or_back(state, result):
    """After the sense that first shows a goal: if it showed more empty cells than obstacles
    (its own cell and those next to it), one move onto a goal it showed (nothing if the agent
    stands on one); else one move onto the cell of the sense before it (nothing if the agent
    stands there or there was none)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here = steps[index][1]
    shown = [int(state.truth[c]) for c in sensed_cells(state, here)]
    if shown.count(EMPTY) > shown.count(OBSTACLE):
        return onto_goal_seen(state, steps, index)
    before = [c for kind, c in steps[:index] if kind == "sense"]
    return onto(steps[index + 1:], here, before[-1:] or [here], "after a crowded goal sense")


NET = 18  # grams a scoop must net on average, delivered less spilled (net_yield_per_scoop)
HAUL = 60  # the landed-weighted haul needed (landed_weighted_haul)


def check_net_yield_per_scoop(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if mass - spilled >= NET * n else \
        f"{mass:.1f} g delivered and {spilled:.1f} g spilled in {n} scoop(s): net " \
        f"{(mass - spilled) / n:.1f} g a scoop"


def check_landed_weighted_haul(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    haul = mass * mass / (mass + spilled) if mass > 0 else 0.0
    return None if haul >= HAUL else \
        f"haul {haul:.1f}: {mass:.1f} g delivered, {spilled:.1f} g spilled, {n} scoop(s)"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_K10, _K20 = indices(10), indices(20)


def _d(a: str, b: str = _S) -> str:
    return distance_text(a, b)


def _blocked(i: str, j: str) -> str:
    """The cell (i, j) is off the grid or an obstacle."""
    return f"(not (0 <= {i} <= 9 and 0 <= {j} <= 9) or is_obstacle(({i}, {j})))"


def _top_blocked(c: str) -> str:
    """The cell above the cell ``c`` is off the grid or an obstacle."""
    return f"({c}[1] == 9 or is_obstacle(({c}[0], {c}[1] + 1)))"


def _right_blocked(c: str) -> str:
    """The cell right of the cell ``c`` is off the grid or an obstacle."""
    return f"({c}[0] == 9 or is_obstacle(({c}[0] + 1, {c}[1])))"


def _quarter_text(c: str) -> str:
    return f"((2 if {c}[0] >= {HALF} else 0) + (1 if {c}[1] >= {HALF} else 0))"


def _free_count(c: str) -> str:
    """How many free cells are next to ``c`` (one loop)."""
    return f"len([x for x in neighbours({c}) if not is_obstacle(x)])"


def _centre_text(c: str) -> str:
    return f"(abs(2 * {c}[0] - 9) + abs(2 * {c}[1] - 9))"


# after the last sense: nothing if the agent ends where it sensed, else one move (the last sense
# is then the one before it, the sense that first showed a goal)
_STAY_OR_ONE = f"steps_after_goal() == (0 if {_F} == {_L} else 1) and primitives()[-1:] == " \
               f"(['sense'] if {_F} == {_L} else ['navigate'])"
_AFTER = "primitives()[len(primitives()) - steps_after_goal():]"  # the steps after the goal sense
_NG = "len(reachable_goals())"
_PATH = f"([{_S}] + moves())"  # the start, then the cells moved to
_EMPTY_SHOWN = f"len([x for x in [{_L}] + neighbours({_L}) if not is_obstacle(x) and not " \
               f"is_goal(x)])"
_OBSTACLES_SHOWN = f"len([x for x in neighbours({_L}) if is_obstacle(x)])"

TASKS = [
    _task("four_quarters_sensed", 2, check_four_quarters_sensed,
          "Explore, moving and sensing, until you have sensed from at least one cell in each of "
          "the four quarters of the grid: bottom-left (i at most 4, j at most 4), bottom-right "
          "(i at least 5, j at most 4), top-left (i at most 4, j at least 5) and top-right (i "
          "at least 5, j at least 5); your first sense counts for the quarter you start in. "
          "Stop right after the sense that completes the four. If there is nothing more to "
          "find before that, stop right after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and (not explored_all() or {_FRESH}) and all(len(C) + "
          f"(0 if {_quarter_text(_L)} in C else 1) in ([4] if {_quarter_text(_L)} not in C else "
          f"[]) + ([1, 2, 3] if explored_all() else []) for C in [[q for q in [0, 1, 2, 3] if "
          f"any({_quarter_text('s')} == q for s in sensed()[:-1])]])"),
    _task("row_and_column_obstacle", 1, check_row_and_column_obstacle,
          "Explore, moving and sensing, until you know of an obstacle somewhere in your "
          "starting row (a cell with the same j as your starting cell) and of an obstacle "
          "somewhere in your starting column (a cell with the same i), near or far. Stop right "
          "after the sense that first gives you both. If there is nothing more to find before "
          "that, stop right after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and [0 < sum(B) < len(B) for B in [[c[1] == {_S1} for "
          f"c in K if is_obstacle(c) and (c[0] == {_S0} or c[1] == {_S1})] for K in "
          f"[known_before_last(), known_cells()]]] in [[False, True]] + ([[False, False]] if "
          f"explored_all() and {_FRESH} else [])"),
    _task("right_then_up_at_opening", 2, check_right_then_up_at_opening,
          "Sense where you start, then walk right (i + 1), one cell at a time, sensing after "
          "every move, while the next cell to the right is inside the grid and free. As soon as "
          "you move into a cell whose upper neighbour (j + 1) is inside the grid and free, turn "
          "there and walk up instead, one cell at a time, sensing after every move, while the "
          "next cell up is inside the grid and free, and stop when it is not. Your starting "
          "cell does not count as a place to turn. If the walk right is blocked before you "
          "reach such a cell, stop there.",
          f"any(R <= len(moves()) and primitives() == ['sense'] + ['navigate', 'sense'] * "
          f"len(moves()) and moves() == [({_S0} + min(k, R), {_S1} + max(0, k - R)) for k in "
          f"{_K20}[1:len(moves()) + 1]] and all({_top_blocked('c')} for c in {_PATH}[1:R]) and "
          f"((len(moves()) > R and {_top_blocked(_F)}) if R > 0 and not "
          f"{_top_blocked(f'{_PATH}[R]')} else (len(moves()) == R and {_right_blocked(_F)})) "
          f"for R in {_K10})"),
    _task("up_then_search", 2, check_up_then_search,
          "Sense where you start, then walk up (j + 1), one cell at a time, sensing after every "
          "move, while the next cell up is inside the grid and free. From where that walk "
          "ends, search for a goal, moving and sensing as you like. As soon as a sense shows "
          "you a goal -- on the walk or after it -- go onto it with one move and stop (onto any "
          "of them if that sense showed several; if you are standing on one, just stop).",
          f"goal_found() and {_ONTO_GOAL} and any(primitives()[:2 * R + 1] == ['sense'] + "
          f"['navigate', 'sense'] * R and moves()[:R] == [({_S0}, {_S1} + k) for k in "
          f"{_K10}[1:R + 1]] and (len(sensed()) == R + 1 or (len(sensed()) > R + 1 and "
          f"{_blocked(_S0, f'{_S1} + R + 1')})) for R in {_K10})"),
    _task("goal_petal_tour", 3, check_goal_petal_tour,
          "Search for a goal. As soon as a sense shows you one, go onto it with one move and "
          "sense there (onto any of them if that sense showed several; if you are standing on "
          "one, skip the move and the sense). Then visit every free cell right next to that "
          "goal -- empty cells and goals alike, inside the grid -- each exactly once, in any "
          "order, going back onto the goal after each visit: one move out and one move back "
          "each time, and no more senses. Stop on the goal.",
          f"goal_found() and is_goal({_F}) and sensed()[-1:] == [{_F}] and all({_AFTER} == "
          f"['navigate', 'sense'][:2 * O] + ['navigate'] * (2 * len(N)) and "
          f"moves_after_goal()[:O] == [{_F}][:O] and sorted(moves_after_goal()[O::2]) == "
          f"sorted(N) and moves_after_goal()[O + 1::2] == [{_F}] * len(N) and (O == 0 or "
          f"({_F} in neighbours(sensed()[-2]) and not is_goal(sensed()[-2]))) for O in [1 if "
          f"'sense' in {_AFTER} else 0] for N in [[x for x in neighbours({_F}) if not "
          f"is_obstacle(x)]])"),
    _task("goal_deliveries", 3, check_goal_deliveries,
          "Explore, moving and sensing, until there is nothing more to find. Then, from "
          "wherever you are, make a delivery trip to every goal you can reach: go onto the goal "
          "with one move, then straight back to your starting cell with one more, goal after "
          "goal, each goal exactly once and in any order, ending on your starting cell. After "
          "the exploring, make no other moves and do not sense again; a goal you are standing "
          "on when the exploring ends still gets its move in its turn.",
          f"explored_all() and primitives()[len(primitives()) - 2 * {_NG} - 1:] == ['sense'] + "
          f"['navigate'] * (2 * {_NG}) and {_NEW_LAST} and sorted(moves()[len(moves()) - 2 * "
          f"{_NG}::2]) == reachable_goals() and moves()[len(moves()) - 2 * {_NG} + 1::2] == "
          f"[{_S}] * {_NG}"),
    _task("wandered_home_first", 2, check_wandered_home_first,
          "Search for a goal. As soon as a sense shows you one, compare the number of moves you "
          "have made so far with that goal's distance from your starting cell, counting steps "
          "along rows and columns and ignoring obstacles. If you have made more moves than "
          "that, your search wandered: go straight back to your starting cell with one move "
          "(skip this move if you are standing on it), then onto the goal with one more. If "
          "you have made no more moves than that, go straight onto the goal with one move. Stop "
          "on the goal (if that sense showed several goals, do this for any one of them, "
          "measuring that one's distance; if you are standing on a goal, just stop).",
          f"goal_found() and {_ONLY_MOVES} and is_goal({_F}) and ({_F} == {_L}) == "
          f"is_goal({_L}) and ({_F} == {_L} or {_F} in neighbours({_L})) and "
          f"moves_after_goal() == ([] if {_F} == {_L} else ([{_S}] if len(moves()) - "
          f"len(moves_after_goal()) > {_d(_F)} and {_L} != {_S} else []) + [{_F}])"),
    _task("far_goal_comes_home", 2, check_far_goal_comes_home,
          f"Search for a goal. As soon as a sense shows you one, go onto it with one move (onto "
          f"any of them if that sense showed several; if you are standing on one, skip the "
          f"move). Then, if that goal is {FAR} or more steps from your starting cell, counting "
          f"steps along rows and columns and ignoring obstacles, go straight back to your "
          f"starting cell with one more move and stop there; if it is nearer than that, stop "
          f"on the goal.",
          f"goal_found() and {_ONLY_MOVES} and all(is_goal(G) and G in [{_L}] + "
          f"neighbours({_L}) and moves_after_goal() == ([] if G == {_L} else [G]) + ([{_S}] if "
          f"{_d('G')} >= {FAR} else []) for G in [{_L} if is_goal({_L}) else "
          f"(moves_after_goal() + [{_L}])[0]])"),
    _task("goal_inspection", 2, check_goal_inspection,
          f"Search for a goal. As soon as a sense shows you one, go onto it with one move and "
          f"sense there (onto any of them if that sense showed several; if you are standing on "
          f"one, skip the move and the sense). If the goal has {CROWDED_GOAL} or more "
          f"obstacles on the cells right next to it (the grid's edge does not count), it is "
          f"too cramped: go straight back to your starting cell with one move and stop there. "
          f"Otherwise stop on the goal.",
          f"goal_found() and is_goal({_L}) and all({_AFTER} == ['navigate', 'sense'][:2 * O] + "
          f"(['navigate'] if H else []) and moves_after_goal() == [{_L}][:O] + ([{_S}] if H "
          f"else []) and (O == 0 or ({_L} in neighbours(sensed()[-2]) and not "
          f"is_goal(sensed()[-2]))) for O in [1 if steps_after_goal() >= 2 else 0] for H in "
          f"[len([x for x in neighbours({_L}) if is_obstacle(x)]) >= {CROWDED_GOAL}])"),
    _task("best_view_return", 3, check_best_view_return,
          "Search for a goal, noting for each place you sense from how many free cells lie "
          "right next to it (empty cells or goals inside the grid; obstacles and the grid's "
          "edge do not count). As soon as a sense shows you a goal, do not go to the goal: go "
          "back with one move to a place you have sensed from -- that last one included -- "
          "with the most free cells next to it, and stop there (any of them if several tie; if "
          "you are standing on one of them, just stop).",
          f"goal_found() and {_STAY_OR_ONE} and {_F} in sensed() and sorted([({_free_count('s')}, "
          f"1 if s == {_L} else 0) for s in sensed()])[-1] == ({_free_count(_F)}, 1 if {_F} == "
          f"{_L} else 0)"),
    _task("centre_park", 2, check_centre_park,
          "Explore, moving and sensing, until there is nothing more to find. Then park as near "
          "the middle of the grid as you can: go with one move to the free cell you can reach "
          "that is nearest to the grid's centre point (4.5, 4.5), the one with the smallest "
          "|i - 4.5| + |j - 4.5|, and stop there (any of them if several tie; if you are "
          "standing on one, just stop).",
          f"explored_all() and {_NEW_LAST} and {_F} in reachable_cells() and "
          f"all({_centre_text('c')} >= {_centre_text(_F)} for c in reachable_cells()) and "
          f"(primitives()[-1:] == ['sense'] or (primitives()[-2:] == ['sense', 'navigate'] and "
          f"{_centre_text(_L)} > {_centre_text(_F)}))"),
    _task("roomy_goal_or_back", 2, check_roomy_goal_or_back,
          "Search for a goal. As soon as a sense shows you one, count what that sense showed on "
          "your own cell and the cells right next to it: the empty cells (goals count as "
          "neither) and the obstacles. If it showed more empty cells than obstacles, go onto "
          "the goal with one move and stop (onto any of them if it showed several; if you are "
          "standing on one, just stop). Otherwise do not go to the goal: go back with one move "
          "to the place where you took the sense before that one and stop there (if that was "
          "your first sense, or you took the one before it in the same place, just stop).",
          f"goal_found() and ({_ONTO_GOAL} if {_EMPTY_SHOWN} > {_OBSTACLES_SHOWN} else "
          f"({_STAY_OR_ONE} and {_F} == ([{_L}] + sensed()[:-1])[-1]))"),
    _task("net_yield_per_scoop", 2, check_net_yield_per_scoop,
          f"Scoop two to five times, then stop, so that on average every scoop nets at least "
          f"{NET} g: the grams of grains in the receiver less the grams spilled outside the "
          f"containers must come to at least {NET} g for every scoop you made.",
          f"scoops() >= 2 and scoops() <= 5 and delivered() - spilled() >= {NET} * scoops()",
          SCOOP),
    _task("landed_weighted_haul", 2, check_landed_weighted_haul,
          f"Scoop one to four times, then stop, with a haul of at least {HAUL}. Your haul is "
          f"the grams of grains in the receiver, multiplied by the share of the grains you "
          f"moved that landed there: the grams in the receiver divided by the grams in the "
          f"receiver and spilled outside the containers together (a haul of 0 if nothing was "
          f"moved).",
          f"scoops() >= 1 and scoops() <= 4 and delivered() > 0 and delivered() * delivered() "
          f">= {HAUL} * (delivered() + spilled())", SCOOP),
]
