"""Held-out tasks, fifteenth set: written before the next change of the synthesizer, run once after
it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout15/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (exploring that stops once four known free
cells make a 2-by-2 square; a walk towards the nearest edge of the grid the start is not on;
exploring that stops with the first move that ends four or more steps from where it began; a walk
along the row away from the one blocked side, up with neither side blocked, none with both; a
search that checks in at home once if its first five senses show no goal; exploring for two more
senses for every obstacle next to the start, then home; a search that goes onto the goal, senses
there and steps on past it; a search that drops in at home before going onto a goal nearer the
start than the agent; a search that goes onto the goal and back to where the middle sense was
taken; once a goal is in view, back to where a sense last showed a new obstacle; once a goal is in
view, onto the known free cell nearest the mean of the places sensed from; a search that backs out
of cramped cells to where it sensed before) and two scooping tasks (one to four scoops that leave
within 25 g of 45 g a scoop in the receiver; one to five scoops scoring at least 35, the grams
delivered less the square of the grams spilled over 10). Each has a reference behavior
(``references/``), a ground-truth ``check`` and a faithful ``promise`` over the env's outcome
helpers, so that the search can be measured apart from the model. They were written on 2026-12-07
blind: without reading the search's code and without running the synthesizer on them; the first run
of the search on them is the evaluation, reported beside the development figures.

Close relatives of earlier tasks: to_nearest_edge of heldout5's toward_far_side (a walk towards a
side the start's position picks; here the nearest of four edges, ties and the edges the start is on
included); away_from_row_block of heldout6's step_away_from_obstacle and heldout8's row_to_junction
(a row walk whose way the first sense picks); check_in_after_five of heldout14's three_look_rounds
and heldout6's hub_search (trips home within a search; here one, after a count); looks_per_obstacle
of heldout8's free_count_straight_walk (a count at the start sets a length; here of the exploring,
before going home); scoop_on_pace of heldout11's gentle_scoops and heldout7's
two_to_four_scoops_25g_each (bounds that grow with the scoops; here both sides of a pace);
squared_spill_score of heldout14's scoop_points and heldout13's scoop_credits (spills that cost;
here their square). The others are of families the earlier sets have (stops on a rule while
exploring, a move chosen once a goal is in view, a place remembered while searching) with rules
none of them has: first_long_move is nearest to heldout7's twelve_steps_travelled,
free_square_known to heldout8's two_touching_obstacles, middle_look_return to heldout10's
back_to_second_look, centre_of_search to heldout12's meeting_point, last_new_obstacle_spot to
heldout6's first_crowded_look, retreat_on_crowd to heldout13's report_each_goal, overshoot_goal to
heldout13's retreat_from_goal and home_first_if_nearer to heldout11's goal_above_or_home.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a cell is
*blocked* when it is an obstacle or outside the grid; an edge of the grid is i cells away (left),
9 - i (right), j (bottom) or 9 - j (top), and the start is *on* an edge 0 cells away; a sense labels
its cell and the four around it (it *shows* them; a goal *comes into view* with the first sense
that shows it); the obstacles *next to* a cell are those among its four neighbours inside the grid
(the grid's edge does not count), and a cell other than the start with CRAMPED (3) or more of them
is *cramped*; a sense shows a *new* obstacle when no earlier sense showed it; a move's *length* is
the distance from the cell it began in (the start or where the move before ended) to the cell it
ended in; the *middle* of n senses is the ((n + 1) // 2)-th; the cell *beyond* a goal g seen from p
is 2 g - p; the *distance* of two cells, or of a cell and the mean of the places sensed from,
counts steps along rows and columns (|di| + |dj|), obstacles ignored, and *nearest* by it. The
start cell always has a free neighbour (a goal is reachable from it and it holds none); the
references only move onto cells they know, so none ever stood on a goal when it first came into
view. The promises' language allows three comprehension loops in one expression, all of them
counted together, and 400 syntax nodes (away_from_row_block's promise has 392): where a promise
needs indices it writes them out (first_long_move's, last_new_obstacle_spot's and
retreat_on_crowd's read up to 100 moves or senses, where the references never made more than 41, 53
and 55); where a move may follow the sense after which nothing more was to be found, that it was
not so before is read from the senses, as in heldout14 (the last sense showed a cell no earlier
sense showed: looks_per_obstacle), and where the sense is the last step from
``known_before_last()`` (free_square_known, first_long_move); where senses and moves alternate,
each sense is where the move before it ended, as the navigate certificates say
(check_in_after_five, middle_look_return, retreat_on_crowd, overshoot_goal's sense on the goal);
away_from_row_block picks the way it walks from a list of four by 2 if the left cell is blocked
plus 1 if the right one is; to_nearest_edge counts an edge the start is on as 10 away;
centre_of_search adds up the i (times 10000) and the j of the places sensed from in one number,
compares n times the distances, and reads the nearest cell as the first of the known free cells
sorted by that and by a tag that puts the cell the agent stands in, then the cell it went to, first
among equals (as heldout14); last_new_obstacle_spot reads the places that showed a new obstacle as
a list after the goal sense's own cell, whose last element must be where the agent ends. A goal
next to the agent is always one step nearer the start than the agent or one step farther, never as
near, so home_first_if_nearer's "not nearer" is "farther". The scooping checks weigh the grains at
the end, as ``delivered()`` and ``spilled()`` do: those in the receiver, and those outside the
receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all; on those 3,600 episodes every one
of the twelve promises was also judged against every reference, and its verdict equalled its
check's on all. On those episodes the tasks' branches came up: exploring stopped after the 2nd
sense 181 times, the 3rd 45, the 4th or 5th 42 and later 32 (up to the 24th), nothing more to find
first in 2 of them, a goal in the square 59; the start on an edge 97 times (in a corner 3), the
nearest other edge 1 to 4 cells away 108, 89, 67 and 33 times, ties 55, walks of 0 to 5 moves 90,
116, 63, 25, 5 and 1 times, ended by the edge 141 times and by an obstacle 69; the first long move
of 4 to 11 steps 126, 63, 46, 35, 16, 6, 3 and 2 times, the 4th to the 41st move, nothing more to
find first 3; the start's left cell blocked alone 71 times (walking right), its right cell alone 74
(walking left), by an obstacle 105 and the edge 40, neither 127 (walking up, 53 of them blocked at
once), both 28, the walks ended by an obstacle 160 times and by the edge 59; a goal in view within
five senses 112 times (from the start 41) and later 188 (so a check-in; up to the 54th sense); 0,
1, 2 and 3 obstacles next to the start 86, 132, 65 and 17 times (back home 214), nothing more to
find first never; the cell beyond the goal stepped onto 192 times, off the grid 33, an obstacle 75
(two goals in view 6); a drop in at home 54 times, straight onto the goal 246; the middle sense the
start 68 times; back to where a new obstacle was last seen 171 times (1 to 10 steps away), staying
because the goal sense showed one 110 and because no sense showed an obstacle 19; onto the cell
nearest the mean 232 times (1 to 8 steps away), staying 68 (all with a goal in view within two
senses); backing out of cramped cells once in 41 searches, twice 14, three times 2 and four times 1
(none in 242). Faithfulness on behaviors that do not do the tasks: every grid promise was judged
against 49 near misses of the references (thresholds, counts and indices one off, other directions,
rules or places to go, the grid's edge not taken as blocked or taken as an edge to head for, a
condition dropped or changed, a missing sense, unknown cells taken for free) and 15 other ways of
doing the tasks (another explorer, another choice among ties or goals, and four variants first
written as near misses that do the tasks: check_in_after_five's trips home after every fifth sense
and retreat_on_crowd's backing out of cells with two obstacles, or of the start too, add moves the
tasks leave free, and home_first_if_nearer's "at most as near" never meets an equal distance) on
episodes 0-99 of seeds 0 and 1 (12,709 judged episodes for each promise, 91 lost: 83 where
free_square_known's empty-only near miss read a label off the grid, 8 where retreat_on_crowd's
start-counts way shuttled to the 500-step limit): the near misses kept their own task's promise on
4,633 of their 9,717 and the other ways on all their 2,992; one near miss did its task on every one
of these episodes and kept its promise there: centre_of_search's nearest by the larger of |di| and
|dj| (the cell holding the mean, when it is known free, is the nearest by both); against the 182
grid references of the development and earlier held-out sets on episodes 0-49 of seed 0 (9,100
judged episodes for each promise, none lost); and against 3 trivial behaviors (stop at once, judged
on the reset; sense once; navigate onto the cell it stands in) on episodes 0-99 of seeds 0 and 1:
on every judged episode the promise's verdict equalled the check's. Keep rates of the trivial
behaviors: stopping at once and navigating onto the cell it stands in keep no promise on any
episode; sensing once keeps none but to_nearest_edge's (62 of 200: the cell towards the nearest
edge blocked), away_from_row_block's (57: both cells beside the start blocked, or neither and the
cell above blocked), looks_per_obstacle's (59: no obstacle next to the start),
last_new_obstacle_spot's and centre_of_search's (29 each: a goal in view from the start, where the
first sense is the goal sense, the place of a new obstacle, if any, the start, and the mean the
start), where the task asks for the one sense. The logic of the held-out folder tests
(tests/test_synthesis_eval.py's satisfiable-faithful-checkable test, and tests/test_certified.py's
readings of every promise and its bank test) pointed at this folder passed. The scooping references
(one and three scoops from the default sensing pose) were run on episodes 0-19 of seed 0 only
(seconds an episode) and kept their promises and did their tasks on all 20: one scoop delivered
29.4 to 56.5 g (20 to 70 g allowed: margin 9.4); three scoops delivered 83.7 to 144.8 g and spilled
0.0 to 24.9 g, for scores of 46.8 to 133.5 (35 needed: margin 11.8). Other counts on those episodes
(five scoops on episodes 0-9 only), both promises judged and the checks agreeing on every one: one
scoop kept squared_spill_score's promise on 15; two scoops (58.8 to 97.3 g delivered, up to 22.6 g
spilled) kept scoop_on_pace's on 16 and squared_spill_score's on 19; three kept scoop_on_pace's on
13; four (101.8 to 185.5 g, up to 31.7 g spilled) kept scoop_on_pace's on 9 and
squared_spill_score's on all 20; five kept squared_spill_score's on all 10 and scoop_on_pace's on
none."""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (goal_sense as _goal_sense,
                                        ALTERNATE as _ALTERNATE, FINAL as _F, FRESH as _FRESH,
                                        LAST_SENSE as _L, MOVE as _MOVE, NEW_LAST as _NEW_LAST,
                                        ONLY_MOVES as _ONLY_MOVES, ONTO_GOAL as _ONTO_GOAL,
                                        START as _S, START_I as _S0, START_J as _S1, STAY as _STAY,
                                        cell, distance, distance_text, exhausted,
                                        first_reaching, free_cell, goals_shown, grams_in_receiver,
                                        grams_spilled, held_out_task, indices, known_after,
                                        label_sensed, obstacles_beside, onto, onto_goal_seen,
                                        same_steps, scoops, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
LEFT, RIGHT, DOWN, UP = (-1, 0), (1, 0), (0, -1), (0, 1)
LONG = 4  # steps from where it began that make a move long (first_long_move)
CHECK_IN = 5  # the sense after which check_in_after_five goes home if no goal is in view
LOOKS = 2  # more senses for every obstacle next to the start (looks_per_obstacle)
CRAMPED = 3  # obstacles next to a cell that make it cramped (retreat_on_crowd)


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


def _alternating(steps, index) -> str | None:
    """None if the steps up to ``index`` are a sense first, then a move and a sense in turn."""
    for t, (kind, _) in enumerate(steps[:index + 1]):
        if kind != ("sense" if t % 2 == 0 else "navigate"):
            return f"step {t + 1} was a {kind}: a sense first and after every move, and no " \
                   "other sense"
    return None


def _edge_gap(state, c, step) -> int:
    """How many cells lie between ``c`` and the grid's edge in the direction ``step``."""
    top = state.size - 1
    return {LEFT: c[0], RIGHT: top - c[0], DOWN: c[1], UP: top - c[1]}[step]


def _square_known(state, known) -> bool:
    """Some four known free cells form a 2-by-2 square."""
    free = known & (state.truth != OBSTACLE)
    return bool((free[:-1, :-1] & free[1:, :-1] & free[:-1, 1:] & free[1:, 1:]).any())


# --- checks -------------------------------------------------------------------------------

def check_free_square_known(state, result):
    """Exploring stops with the first sense after which four known free cells form a 2-by-2
    square, or nothing more is to be found."""
    index = first_reaching(state, result,
                           lambda known: _square_known(state, known) or exhausted(state, known))
    if index is None:
        return "never knew a 2-by-2 square of free cells and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_to_nearest_edge(state, result):
    """A sense, then a walk towards an edge of the grid fewest cells away among those the start
    is not on, a sense after every move, while the next cell that way is inside the grid and
    free."""
    home = state.start_cell
    ways = [s for s in (LEFT, RIGHT, DOWN, UP) if _edge_gap(state, home, s) > 0]
    near = min(_edge_gap(state, home, s) for s in ways)
    plans = [[("sense", home)] + _walk(state, home, s) for s in ways
             if _edge_gap(state, home, s) == near]
    steps = steps_of(result)
    return None if steps in plans else same_steps(steps, plans[0])


def check_away_from_row_block(state, result):
    """A sense; if exactly one of the cells left and right of the start is blocked (an obstacle
    or off the grid), a walk the other way along the row; if neither is, a walk up; each with a
    sense after every move, while the next cell is inside the grid and free; if both are blocked,
    nothing more."""
    home = state.start_cell
    left = not free_cell(state, step_by(home, LEFT))
    right = not free_cell(state, step_by(home, RIGHT))
    plan = [("sense", home)]
    if not (left and right):
        plan += _walk(state, home, RIGHT if left else LEFT if right else UP)
    return same_steps(steps_of(result), plan)


def check_first_long_move(state, result):
    """Exploring stops with the first move that ends LONG or more steps from the cell it began
    in, or with the sense after which nothing more is to be found, whichever comes first."""
    steps, here = steps_of(result), state.start_cell
    known = _unknown(state)
    for index, (kind, c) in enumerate(steps):
        if kind == "navigate":
            far, here = distance(here, c) >= LONG, c
            if far:
                return same_steps(steps[index + 1:], [])
            continue
        label_sensed(state, known, (kind, c))
        if exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return "stopped before a long move and before everything was known"


def check_check_in_after_five(state, result):
    """A sense first, then a move and a sense in turn up to the sense that first shows a goal;
    if that came after the CHECK_IN-th sense, the move after the CHECK_IN-th went to the start;
    then one move onto a goal that sense showed (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    why = _alternating(steps, index)
    if why is not None:
        return why
    back = steps[2 * CHECK_IN - 1] if index // 2 + 1 > CHECK_IN else None
    if back is not None and back[1] != state.start_cell:
        return f"move {CHECK_IN} went to {back[1]}, not back to the start"
    return onto_goal_seen(state, steps, index)


def check_looks_per_obstacle(state, result):
    """A sense at the start; exploring stops with the sense that makes LOOKS more senses for each
    obstacle next to the start, or with the sense after which nothing more is to be found; then
    one move onto the start (nothing if the agent stands on it)."""
    steps, home = steps_of(result), state.start_cell
    if steps[:1] != [("sense", home)]:
        return f"began with {steps[:1]}, not a sense"
    need = 1 + LOOKS * obstacles_beside(state, home)
    known, senses = _unknown(state), 0
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] != "sense":
            continue
        senses += 1
        if senses == need or exhausted(state, known):
            return onto(steps[index + 1:], step[1], [home], "after the last sense")
    return f"stopped after {senses} of {need} senses, before everything was known"


def check_overshoot_goal(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed and a sense there,
    then one move onto the cell beyond that goal, away from the cell it was seen from, if that
    cell is inside the grid and free (nothing at all if the agent stands on a goal)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, rest = steps[index][1], steps[index + 1:]
    if state.truth[here] == GOAL:
        return same_steps(rest, [])
    plans = []
    for g in goals_shown(state, here):
        beyond = (2 * g[0] - here[0], 2 * g[1] - here[1])
        plans.append([("navigate", g), ("sense", g)]
                     + ([("navigate", beyond)] if free_cell(state, beyond) else []))
    return None if rest in plans else same_steps(rest, plans[0])


def check_home_first_if_nearer(state, result):
    """After the sense that first shows a goal: a move onto the start if the goal gone to is
    nearer the start than the agent, then one move onto that goal, one the sense showed (nothing
    if the agent stands on a goal)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    home = state.start_cell
    here, rest = steps[index][1], steps[index + 1:]
    if state.truth[here] == GOAL:
        return same_steps(rest, [])
    plans = [([("navigate", home)] if distance(g, home) < distance(here, home) else [])
             + [("navigate", g)] for g in goals_shown(state, here)]
    return None if rest in plans else same_steps(rest, plans[0])


def check_middle_look_return(state, result):
    """A sense first, then a move and a sense in turn up to the sense that first shows a goal;
    then one move onto a goal it showed (none if the agent stands on one) and one onto the cell
    of the middle sense, the ((n + 1) // 2)-th of n (none if the agent stands there)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    why = _alternating(steps, index)
    if why is not None:
        return why
    middle = steps[2 * (index // 2 // 2)][1]
    here, rest = steps[index][1], steps[index + 1:]
    goals = [here] if state.truth[here] == GOAL else goals_shown(state, here)
    plans = [([] if g == here else [("navigate", g)])
             + ([] if g == middle else [("navigate", middle)]) for g in goals]
    return None if rest in plans else same_steps(rest, plans[0])


def check_last_new_obstacle_spot(state, result):
    """After the sense that first shows a goal: one move onto the cell of the last sense (up to
    that one) that showed an obstacle no earlier sense had; nothing if that is where the agent
    stands, or if no sense showed an obstacle."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    known, spot = _unknown(state), None
    for kind, c in steps[:index + 1]:
        before = int((known & (state.truth == OBSTACLE)).sum())
        label_sensed(state, known, (kind, c))
        if int((known & (state.truth == OBSTACLE)).sum()) > before:
            spot = c
    here = steps[index][1]
    return onto(steps[index + 1:], here, [spot or here], "after the goal came into view")


def check_centre_of_search(state, result):
    """After the sense that first shows a goal: one move onto a known free cell nearest (along
    rows and columns) to the mean of the cells sensed from, up to that sense (nothing if the agent
    stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    senses = [c for kind, c in steps[:index + 1] if kind == "sense"]
    n, si, sj = len(senses), sum(c[0] for c in senses), sum(c[1] for c in senses)
    known = known_after(state, result.steps[:index + 1])
    free = [cell(x) for x in zip(*(known & (state.truth != OBSTACLE)).nonzero())]

    def score(c):  # n times the distance from c to the mean
        return abs(n * c[0] - si) + abs(n * c[1] - sj)
    best = min(score(c) for c in free)
    return onto(steps[index + 1:], steps[index][1], [c for c in free if score(c) == best],
                "after the goal came into view")


def check_retreat_on_crowd(state, result):
    """A sense first, then a move and a sense in turn up to the sense that first shows a goal;
    after each earlier sense taken on a cramped cell (not the start, with CRAMPED or more
    obstacles next to it) the move goes to the cell of the sense before it; then one move onto a
    goal the goal sense showed (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    why = _alternating(steps, index)
    if why is not None:
        return why
    for t in range(2, index, 2):
        c = steps[t][1]
        if c != state.start_cell and obstacles_beside(state, c) >= CRAMPED \
                and steps[t + 1][1] != steps[t - 2][1]:
            return f"step {t + 2} went to {steps[t + 1][1]}, not back from cramped {c} to " \
                   f"{steps[t - 2][1]}"
    return onto_goal_seen(state, steps, index)


PACE, PACE_SLACK = 45, 25  # grams a scoop; grams either side allowed (scoop_on_pace)
SQUARE_SPILL, SQUARE_SCORE = 10, 35  # the spill's square is divided by; the score needed


def check_scoop_on_pace(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass = grams_in_receiver(state)
    return None if abs(mass - PACE * n) <= PACE_SLACK else \
        f"{mass:.1f} g delivered after {n} scoop(s), not within {PACE_SLACK} g of {PACE * n}"


def check_squared_spill_score(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    score = mass - spilled * spilled / SQUARE_SPILL
    return None if score >= SQUARE_SCORE else \
        f"score {score:.1f}: {mass:.1f} g delivered, {spilled:.1f} g spilled, {n} scoop(s)"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_K10, _K100 = indices(10), indices(100)


def _d(a: str, b: str = _S) -> str:
    return distance_text(a, b)


def _square(known: str) -> str:
    """Some cell of ``known`` and the cells right of it, above it and above-right of it are in
    ``known`` and free."""
    others = ["(c[0] + 1, c[1])", "(c[0], c[1] + 1)", "(c[0] + 1, c[1] + 1)"]
    return f"any({' and '.join(f'{x} in {known}' for x in others)} and " \
           f"{' and '.join(f'not is_obstacle({x})' for x in others)} for c in {known} if not " \
           f"is_obstacle(c))"


def _row_blocked(i: str) -> str:
    """The cell of column ``i`` in the start's row is off the grid or an obstacle."""
    return f"(not 0 <= {i} <= 9 or is_obstacle(({i}, {_S1})))"


def _gap(g: str) -> str:
    """The cells between the start and an edge, ``g``, or 10 if the start is on that edge."""
    return f"({g} if {g} > 0 else 10)"


def _blocked(i: str, j: str) -> str:
    """The cell (i, j) is off the grid or an obstacle."""
    return f"(not (0 <= {i} <= 9 and 0 <= {j} <= 9) or is_obstacle(({i}, {j})))"


_LEFT_BLOCKED, _RIGHT_BLOCKED = _row_blocked(f"{_S0} - 1"), _row_blocked(f"{_S0} + 1")
# the way away_from_row_block walks: up with neither side blocked, left with the right one
# blocked, right with the left one, none (0, 0) with both
_AWAY = f"[(0, 1), (-1, 0), (1, 0), (0, 0)][(2 if {_LEFT_BLOCKED} else 0) + (1 if " \
        f"{_RIGHT_BLOCKED} else 0)]"
_LEN_K = _d("([start_cell()] + moves())[k]", "moves()[k]")  # the length of the move k
_LEN_LAST = _d("([start_cell()] + moves())[-2]", "moves()[-1]")
_BEFORE_GOAL, _ON_GOAL = "sensed()[-2]", "sensed()[-1]"  # overshoot_goal: the goal sense; on it
_BEYOND_I, _BEYOND_J = f"2 * {_ON_GOAL}[0] - {_BEFORE_GOAL}[0]", f"2 * {_ON_GOAL}[1] - " \
                                                                   f"{_BEFORE_GOAL}[1]"
_MIDDLE = "sensed()[(len(sensed()) - 1) // 2]"
# the senses (up to the last) that showed an obstacle no earlier sense had shown
_NEW_OBSTACLE_SPOTS = f"[sensed()[k] for k in {_K100}[:len(sensed())] if any(is_obstacle(x) and " \
                      f"not any(x in neighbours(s) for s in sensed()[:k]) for x in " \
                      f"neighbours(sensed()[k]))]"
# n times the distance from c to the mean of the n cells sensed from, T the sums of their i
# (T // 10000) and of their j (T % 10000)
_OFF_MEAN = "abs(len(sensed()) * c[0] - T // 10000) + abs(len(sensed()) * c[1] - T % 10000)"
_OBSTACLES_AT_START = f"len([x for x in neighbours({_S}) if is_obstacle(x)])"

TASKS = [
    _task("free_square_known", 1, check_free_square_known,
          "Explore, moving and sensing, until you know four free cells (empty cells or goals) "
          "that make up a 2-by-2 square: two cells side by side in a row and the two cells "
          "right above them. Stop right after the sense that completes such a square. If "
          "there is nothing more to find before that, stop right after the sense that leaves "
          "nothing more to find.",
          f"primitives()[-1:] == ['sense'] and not {_square('known_before_last()')} and "
          f"({_square('known_cells()')} or (explored_all() and {_FRESH}))"),
    _task("to_nearest_edge", 1, check_to_nearest_edge,
          "Head for the nearest edge of the grid that you are not already on. Sense where "
          "you start. Of the four edges, pick the one fewest cells away from you -- the left "
          "edge is i cells away, the right one 9 - i, the bottom one j and the top one 9 - j; "
          "leave out any edge you stand on (0 cells away), and take any of the nearest if "
          "several are equally near -- and walk straight towards it, one cell at a time, "
          "sensing after every move, while the next cell that way is inside the grid and free. "
          "Stop when it is not.",
          f"any(primitives() == ['sense'] + ['navigate', 'sense'] * R and moves() == [({_S0} + "
          f"a * k, {_S1} + b * k) for k in {_K10}[1:R + 1]] and "
          f"{_blocked(f'{_S0} + a * (R + 1)', f'{_S1} + b * (R + 1)')} for a, b, e in [(-1, 0, "
          f"{_S0}), (1, 0, 9 - {_S0}), (0, -1, {_S1}), (0, 1, 9 - {_S1})] if e == "
          f"min({_gap(_S0)}, {_gap(_S1)}, {_gap(f'9 - {_S0}')}, {_gap(f'9 - {_S1}')}) for R in "
          f"{_K10})"),
    _task("first_long_move", 1, check_first_long_move,
          f"Explore, moving and sensing, and stop as soon as you make a long trip: right after "
          f"the first move that ends {LONG} or more steps away from the cell it started from "
          f"(counting steps along rows and columns, ignoring obstacles). If there is nothing "
          f"more to find before that, stop right after the sense that leaves nothing more to "
          f"find.",
          f"all({_LEN_K} < {LONG} for k in {_K100}[:len(moves()) - (1 if primitives()[-1:] == "
          f"['navigate'] else 0)]) and ((primitives()[-1:] == ['navigate'] and not "
          f"explored_all() and {_LEN_LAST} >= {LONG}) or (primitives()[-1:] == ['sense'] and "
          f"explored_all() and {_FRESH}))"),
    _task("away_from_row_block", 2, check_away_from_row_block,
          "Sense once where you start and look at the two cells beside you in your row: the "
          "one to your left (i - 1) and the one to your right (i + 1). Call a cell blocked if "
          "it is an obstacle or lies outside the grid. If exactly one of the two is blocked, "
          "walk away from it along your row; if neither is, walk up (j + 1) instead; walk one "
          "cell at a time, sensing after every move, while the next cell that way is inside "
          "the grid and free, and stop when it is not. If both cells beside you are blocked, "
          "do not move: stop after that first sense.",
          f"(primitives() == ['sense'] and {_LEFT_BLOCKED} and {_RIGHT_BLOCKED}) or "
          f"any(primitives() == ['sense'] + ['navigate', 'sense'] * R and moves() == [({_S0} + "
          f"a * k, {_S1} + b * k) for k in {_K10}[1:R + 1]] and "
          f"{_blocked(f'{_S0} + a * (R + 1)', f'{_S1} + b * (R + 1)')} for a, b in [{_AWAY}] "
          f"for R in {_K10})"),
    _task("check_in_after_five", 2, check_check_in_after_five,
          f"Search for a goal, sensing where you start and after every move, and at no other "
          f"time. Check in at home once on the way: if none of your first {CHECK_IN} senses "
          f"has shown you a goal, make your next move straight back to your starting cell, "
          f"sense there as after any move, and then carry on searching. As soon as a sense "
          f"shows you a goal, go onto it with one move and stop (onto any of them if that sense "
          f"showed several; if you are standing on one, just stop).",
          f"{_ONTO_GOAL} and {_ALTERNATE} and (len(sensed()) <= {CHECK_IN} or "
          f"sensed()[{CHECK_IN}] == {_S})"),
    _task("looks_per_obstacle", 2, check_looks_per_obstacle,
          f"The more crowded your start, the longer you look around. Sense where you start and "
          f"count the obstacles on the cells right next to you (the grid's edge does not "
          f"count). Then explore, moving and sensing, until you have taken {LOOKS} more senses "
          f"for every one of those obstacles (none if there are none; after a first sense that "
          f"shows three obstacles, six more). Then go straight back to your starting cell with "
          f"one move and stop (if you are standing on it, just stop). If there is nothing more "
          f"to find before you have taken all those senses, go back right after the sense that "
          f"leaves nothing more to find.",
          f"primitives()[:1] == ['sense'] and {LOOKS} * {_OBSTACLES_AT_START} + 1 - "
          f"len(sensed()) in ([0] if not explored_all() else {_K10}) and (not explored_all() "
          f"or {_NEW_LAST}) and (({_STAY} and {_L} == {_S}) or ({_MOVE} and {_L} != {_S} and "
          f"{_F} == {_S}))"),
    _task("overshoot_goal", 2, check_overshoot_goal,
          "Search for a goal and run through it. Explore until a sense shows you a goal, go "
          "onto it with one move (onto any of them if that sense showed several) and sense "
          "there. Then take one more step the same way, onto the cell just beyond the goal -- "
          "on the far side of the goal from the cell you saw it from -- if that cell is inside "
          "the grid and free, and stop there without sensing; if it is not, stop on the goal. "
          "If you are standing on a goal when you first see one, just stop.",
          f"goal_found() and ((steps_after_goal() == 0 and is_goal({_L})) or "
          f"(steps_after_goal() in [2, 3] and primitives()[len(primitives()) - "
          f"steps_after_goal():] == ['navigate', 'sense', 'navigate'][:steps_after_goal()] and "
          f"not is_goal({_BEFORE_GOAL}) and is_goal({_ON_GOAL}) and {_ON_GOAL} in "
          f"neighbours({_BEFORE_GOAL}) and steps_after_goal() == (2 if "
          f"{_blocked(_BEYOND_I, _BEYOND_J)} else 3) and (steps_after_goal() == 2 or {_F} == "
          f"({_BEYOND_I}, {_BEYOND_J}))))"),
    _task("home_first_if_nearer", 2, check_home_first_if_nearer,
          "Explore until a sense shows you a goal, then go onto it -- but if that goal is "
          "nearer to your starting cell than you are (counting steps along rows and columns, "
          "ignoring obstacles), drop in at home on the way: go straight back to your starting "
          "cell with one move, then onto the goal with one more. If the goal is not nearer, go "
          "straight onto it with one move. Stop on the goal (if that sense showed several "
          "goals, do this for any one of them; if you are standing on a goal, just stop).",
          f"goal_found() and ((steps_after_goal() == 0 and is_goal({_L})) or (not "
          f"is_goal({_L}) and is_goal({_F}) and {_F} in neighbours({_L}) and {_ONLY_MOVES} and "
          f"moves_after_goal() == ([{_S}, {_F}] if {_d(_F)} < {_d(_L)} else [{_F}])))"),
    _task("middle_look_return", 2, check_middle_look_return,
          "Search for a goal, sensing where you start and after every move, and at no other "
          "time. As soon as a sense shows you a goal, go onto it with one move (onto any of "
          "them if that sense showed several; skip this if you are standing on one). Then go "
          "back with one move to where you took the middle sense of your search: counting your "
          "senses up to and including the one that showed you the goal, the middle one of 5 is "
          "the 3rd, of 6 the 3rd, of 7 the 4th, and of 1 or 2 the 1st. Stop there (skip that "
          "move if you are already there).",
          f"goal_found() and {_ALTERNATE} and {_ONLY_MOVES} and all(is_goal(G) and G in "
          f"[{_L}] + neighbours({_L}) and moves_after_goal() == ([] if G == {_L} else [G]) + "
          f"([] if G == M else [M]) for G in [{_L} if is_goal({_L}) else (moves_after_goal() + "
          f"[{_L}])[0]] for M in [{_MIDDLE}])"),
    _task("last_new_obstacle_spot", 3, check_last_new_obstacle_spot,
          "Search for a goal, keeping track of where you were when you last discovered an "
          "obstacle: the place you sensed from the last time a sense showed you an obstacle "
          "that none of your earlier senses had shown you. As soon as a sense shows you a goal, "
          "do not go to the goal: go back to that place with one move and stop (if that very "
          "sense showed you a new obstacle, or you are standing on that place, just stop). If "
          "none of your senses has shown you an obstacle, just stop.",
          f"goal_found() and steps_after_goal() == (0 if {_F} == {_L} else 1) and "
          f"primitives()[-1:] == (['sense'] if {_F} == {_L} else ['navigate']) and ([{_L}] + "
          f"{_NEW_OBSTACLE_SPOTS})[-1] == {_F}"),
    _task("centre_of_search", 3, check_centre_of_search,
          "Search for a goal, then go to the middle of the area you searched. Explore until a "
          "sense shows you a goal, but do not go to it. Instead take the average position of "
          "all the places you sensed from, that last one included (the average of their i and "
          "the average of their j), and go with one move to the cell you know to be free that "
          "is nearest to that point, counting steps along rows and columns (any of them if "
          "several are equally near; if you are standing on one, just stop).",
          f"goal_found() and steps_after_goal() == (0 if {_F} == {_L} else 1) and "
          f"primitives()[-1:] == (['sense'] if {_F} == {_L} else ['navigate']) and "
          f"all(sorted([({_OFF_MEAN}, 0 if c == {_L} else 1 if c == {_F} else 2) for c in "
          f"known_cells() if not is_obstacle(c)])[0][1] == (0 if {_F} == {_L} else 1) for T in "
          f"[sum([10000 * s[0] + s[1] for s in sensed()])])"),
    _task("retreat_on_crowd", 3, check_retreat_on_crowd,
          f"Search for a goal, sensing where you start and after every move, and at no other "
          f"time, backing out of cramped spots. Whenever a sense taken anywhere but your "
          f"starting cell shows you {CRAMPED} or more obstacles on the cells right next to you "
          f"(the grid's edge does not count), your next move must take you straight back to "
          f"the place where you took the sense before that one. As soon as a sense shows you a "
          f"goal, go onto it with one move and stop (onto any of them if that sense showed "
          f"several; if you are standing on one, just stop).",
          f"{_ONTO_GOAL} and {_ALTERNATE} and all(moves()[k] == sensed()[k - 1] for k in "
          f"{_K100}[1:len(sensed()) - 1] if sensed()[k] != {_S} and len([x for x in "
          f"neighbours(sensed()[k]) if is_obstacle(x)]) >= {CRAMPED})"),
    _task("scoop_on_pace", 2, check_scoop_on_pace,
          f"Keep a steady pace: scoop one to four times, then stop, so that the receiver ends "
          f"up holding within {PACE_SLACK} grams of {PACE} grams of grains for every scoop you "
          f"made -- {PACE - PACE_SLACK} to {PACE + PACE_SLACK} g after one scoop, "
          f"{2 * PACE - PACE_SLACK} to {2 * PACE + PACE_SLACK} g after two, "
          f"{3 * PACE - PACE_SLACK} to {3 * PACE + PACE_SLACK} g after three, "
          f"{4 * PACE - PACE_SLACK} to {4 * PACE + PACE_SLACK} g after four.",
          f"scoops() >= 1 and scoops() <= 4 and abs(delivered() - {PACE} * scoops()) <= "
          f"{PACE_SLACK}", SCOOP),
    _task("squared_spill_score", 2, check_squared_spill_score,
          f"Scoop one to five times, then stop, with a score of at least {SQUARE_SCORE}. Your "
          f"score is the grams of grains in the receiver less a penalty for spilling that "
          f"grows fast: the square of the grams spilled outside the containers, divided by "
          f"{SQUARE_SPILL} (5 g spilled costs 2.5 points, 20 g costs 40).",
          f"scoops() >= 1 and scoops() <= 5 and delivered() - spilled() * spilled() / "
          f"{SQUARE_SPILL} >= {SQUARE_SCORE}", SCOOP),
]
