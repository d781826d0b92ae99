"""Held-out tasks, twentieth set: written before the next change of the synthesizer, run once
after it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout20/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (exploring that stops once two known goals
share a row or a column; exploring that stops once a known goal has a known obstacle next to it; a
walk left that backs out of its end if that is a dead end; a walk in the first of up, left, down and
right that is free from the start, chosen once; a trip onto the corner of the grid farthest from the
start, exploring as needed, and straight home from it; after exploring, onto the reachable goal that
comes second by distance from the start; once a goal is in view, home if more obstacles are next to
the place it was seen from than next to the start, else onto the goal; a search that only counts
goals in the start's quarter of the grid, else home; after exploring, onto the reachable dead end
farthest from the start, then home; after exploring, onto the reachable cell no move has ended on
nearest the start; onto the far end of the longest of the four straight runs of free cells out of
the start, exploring as needed; after exploring, as many round trips between the start and the goal
nearest it as there are reachable goals) and two scooping tasks (one to six scoops with a tally of
at least 75, the grams delivered less a toll of 20 for every scoop after the third; two to five
scoops that leave at least 40 g in the receiver and spill no more than half of the grams delivered
beyond 40 g). Each has a reference behavior (``references/``), a ground-truth ``check`` and a
faithful ``promise`` over the env's outcome helpers, so that the search can be measured apart from
the model. They were written on 2026-12-07 blind: without reading the search's code and without
running the synthesizer on them; the first run of the search on them is the evaluation, reported
beside the development figures.

Close relatives of earlier tasks: goals_share_line of heldout12's aligned_goal (a goal in line with
the start; here two goals in line with each other) and heldout19's wall_of_three and heldout8's
two_touching_obstacles (exploring until the known cells hold a shape); goal_by_obstacle_known of
heldout14's all_kinds_look (a goal and an obstacle shown by one sense; here next to each other,
known by any senses) and heldout13's scout_goal_surroundings; left_walk_dead_end_back of heldout9's
left_wall_return (a walk left and what ends it), heldout2's dead_end (a cell blocked on three sides)
and heldout2's step_back_after_goal (a step back); first_free_way_run of heldout9's
priority_walk_until_repeat and heldout7's up_else_right_climb (directions by preference; there
chosen at every step, here once) and heldout2's east_until_blocked; far_corner_and_back of
heldout2's reachable_corner (a corner, exploring as needed; here the far one, and home from it) and
heldout19's corner_patrol; second_nearest_goal of heldout2's nearer_goal and the development
farthest_goal (dev_general; goals picked by their distance from the start; here the second in
order); goal_look_busier_home of heldout16's clutter_turns_home and heldout18's
cluttered_search_home (home or the goal on the obstacles a sense showed; here compared with the
first sense's) and heldout11's home_like_spot (the start's count of obstacles as a yardstick);
own_quarter_goal of heldout12's aligned_goal and heldout7's distant_goal (only some goals count;
here those of the start's quarter) and heldout18's home_quarter_mapped (the start's quarter);
farthest_dead_end_home of heldout2's dead_end and heldout18's nearest_shelter (a reachable cell
picked by a property and a distance after exploring; here the farthest dead end, and home after it);
nearest_unstood_cell of heldout10's hug_home_walk and heldout7's no_backtrack_search (cells never
stood in; there walked onto one by one) and heldout17's centre_park; longest_straight_run of
heldout13's four_ray_lengths (the four straight lines out of the start; there explored) and
heldout9's longer_arm (two arms of the row compared, walked); trips_per_goal_found of heldout9's
obstacle_count_round_trips (round trips counted by what was found; there obstacles next to the
start) and heldout17's goal_deliveries and the development two_round_trips; scoop_toll_after_three
of heldout10's scoop_fee (grams charged for scoops; here only after the third) and heldout19's
shrinking_multiplier; surplus_spill_allowance of heldout19's spill_grace and heldout6's
two_scoops_threefold_clean (a spill allowance that grows with the grams delivered; here with those
beyond a floor).

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a cell is
*blocked* when it is an obstacle or outside the grid; a cell's *row* is the cells with its j, its
*column* those with its i; a *dead end* is a free cell blocked on three of its four sides (it has
exactly one free cell next to it); the *quarters* of the grid are cut between i = 4 and i = 5 and
between j = 4 and j = 5; the grid's *corners* are (0, 0), (0, 9), (9, 0) and (9, 9), and the one
*farthest* from a start (i, j) is (9 if i <= 4 else 0, 9 if j <= 4 else 0), never a tie; the
*straight runs* out of the start are its free cells up, down, left and right of it up to the first
blocked cell, a run's *length* its number of cells and its *far end* its last (every run of the
longest has at least one cell: the start always has a free neighbour); the agent *stood on* a cell
when a move ended on it (its start included); a sense labels its cell and the four around it (it
*shows* them; a goal *comes into view* with the first sense that shows it); the obstacles *next to*
a cell are those among its four neighbours inside the grid (the grid's edge does not count); the
*distance* of two cells counts steps along rows and columns (|di| + |dj|), obstacles ignored. The
start cell always has a free neighbour (a goal is reachable from it and it holds none); the
references only move onto cells they know, so none ever stood on a goal when it first came into
view, and a known free cell is always reachable (it is the sensed-from cell or next to it). The
promises' language allows three comprehension loops in one expression, all of them counted together,
and 400 syntax nodes (longest_straight_run's promise has 391): where exploring ends on a sense after
which something held, that it did not before is read from ``known_before_last()`` (goals_share_line,
goal_by_obstacle_known: whether the known cells hold it before the last step and after it, [False,
True], or [False, False] with nothing more to find); where moves follow the sense that left nothing
more to find, that nothing more was to be found before it is read from the senses with one loop (the
last sense showed a cell x that no earlier sense was taken on, nor on a cell next to x:
second_nearest_goal, nearest_unstood_cell, trips_per_goal_found), and farthest_dead_end_home asks
only that nothing more was to be found at the end and reads its moves after the last sense (a sense
more after the exploring does no harm, as its task says); where the steps after the goal sense may
be moves only, the goal sense is read as the last sense (goal_look_busier_home, own_quarter_goal);
left_walk_dead_end_back and first_free_way_run read the walk from the senses or the moves, as
heldout19's down_then_sidestep does; far_corner_and_back reads the first move onto the corner as the
move before the last, with no earlier move onto it; nearest_unstood_cell reads the cells stood on as
the start and the moves but the last (where the last move is not the one after the exploring, the
reading errs only where the verdict is the same either way); farthest_dead_end_home tells a dead end
among the reachable cells by its free neighbours and the one it visited by the reachable cells next
to it; longest_straight_run asks of the final cell, on the start's row or column at a distance D of
at least 1, that in every direction a blocked cell lies within D + 1 steps of the start and in its
own direction none within D; trips_per_goal_found reads the goal of the round trips as the move
before the last; a promise whose target is a choice among ties lets the agent stay only where the
cell it stands in is as good as the target, and move only where that cell is strictly worse
(second_nearest_goal; far_corner_and_back, farthest_dead_end_home and trips_per_goal_found always
move, as their tasks say). The scooping checks weigh the grains at the end, as ``delivered()`` and
``spilled()`` do: those in the receiver, and those outside the receiver, the donor and the spoon's
tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all; on those 3,600 episodes every one of
the twelve promises was also judged against every reference (each reference run once an episode,
every promise judged on the run as ``evaluate`` judges it), and its verdict equalled its check's on
all. On those episodes the tasks' branches came up: two goals in line known after 2 to 61 senses 132
times, nothing more to find first 168 (after 5 to 66 senses); a goal beside an obstacle known after
2 to 60 senses 284 times, nothing more to find first 16; walks left of 0 to 9 moves, backing out of
a dead end 32 times (18 of them from the start), staying 268; walks up 194 times, left 76, down 22
and right 8, of 1 to 8 moves; onto the far corner and home 155 times, the corner out of reach and
home after 5 to 65 senses 145; the second nearest of 3, 2 and 1 reachable goals 218, 61 and 21
times, staying on it 6; home from a busier goal sense 61 times, onto the goal 239 (41 of them seen
from the start); onto a goal of the start's quarter 163 times, home 137; onto the farthest dead end
and home 300 times; onto the nearest cell never stood on 294 times, home 6; onto the end of a
longest run of 1 to 9 cells 30, 52, 64, 53, 49, 31, 13, 7 and 1 times; 3, 2 and 1 round trips 218,
61 and 21 times. Faithfulness on behaviors that do not do the tasks: every grid promise was judged
against 77 near misses of the references (conditions, comparisons, counts and thresholds one off or
turned round, other directions, orders, corners, quarters, halves, metrics or measuring points, the
grid's edge or the start counted or left out, a fallback, a return, a sense, a move or a trip
dropped or added, an explorer that stops too early or too late, a walk that stops short or
re-chooses its direction) and 21 other ways of doing the tasks (other explorers, another choice
among ties, a direction or a count written another way, exploring more than needed, a sense more
after the exploring where the task allows it) on episodes 0-99 of seeds 0 and 1 (19,585 judged
episodes for each promise; 15 of one near miss's 200 were lost to its own failed certificates): the
near misses kept their own task's promise on 6,577 of their 15,385 judged episodes and the other
ways on all their 4,200; one near miss did its task on every one of these episodes and kept its
promise there (farthest_dead_end_home's with the start counted as a dead end, which differs only
where the start is the only reachable dead end, which never happened there); against the 242 grid
references of the development and earlier held-out sets on episodes 0-49 of seed 0 (12,100 judged
episodes for each promise, none lost); and against 25 trivial behaviors (stop at once, judged on the
reset; sense where it stands 1 to 12 times; navigate onto the cell it stands in 1 to 12 times) on
episodes 0-99 of seeds 0 and 1 (5,000 judged episodes for each promise): on every judged episode the
promise's verdict equalled the check's. Keep rates of the trivial behaviors: none keeps any promise
on any episode but sensing once, which keeps left_walk_dead_end_back's (54 of 200: the cell left of
the start blocked, and the start no dead end), where the task asks for the one sense. The held-out
folder tests (tests/test_synthesis_eval.py's satisfiable-faithful-checkable test, and
tests/test_certified.py's readings of every promise and its bank test) pointed at this folder
passed. The scooping references (three and four scoops from the default sensing pose) were run on
episodes 0-9 of seed 0 only (seconds an episode) and kept their promises and did their tasks on all
10: three scoops delivered 88.2 to 133.5 g, free of toll (75 needed: margin 13.2); four scoops
delivered 104.0 to 171.9 g and spilled 6.8 to 31.7 g, at least 9.4 g under the allowance. The
thresholds were set from these figures and from one to five scoops on the same episodes (the same as
heldout17's to heldout19's): surplus_spill_allowance first asked for 60 g and half of the grams
beyond them, which four scoops missed on one of the 10 (0.6 g over), and was set to 40 g before the
set was fixed. Both promises were judged on one to five scoops and the checks agreed on every one:
one scoop (33.9 to 54.3 g) kept neither; two scoops kept scoop_toll_after_three's on 6 and
surplus_spill_allowance's on 7; three, four and five scoops kept both on all 10 (tallies of 84.0 and
84.4 at least after four and five)."""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (goal_sense as _goal_sense, any_plan as _any_plan,
                                        FINAL as _F, FRESH as _FRESH, LAST_SENSE as _L,
                                        ONTO_GOAL as _ONTO_GOAL, START as _S, START_I as _S0,
                                        START_J as _S1, cell, distance, distance_text, exhausted,
                                        first_reaching, free_cell, free_neighbours, goals_shown,
                                        grams_in_receiver, grams_spilled, held_out_task, indices,
                                        neighbours as _neighbours, obstacles_beside, onto,
                                        onto_goal_seen, reachable, same_steps, scoops, step_by,
                                        steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
LEFT, RIGHT, DOWN, UP = (-1, 0), (1, 0), (0, -1), (0, 1)
HALF = 5  # a cell is in the right half when i >= HALF, the top half when j >= HALF


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


def _reachable_goals(state) -> list:
    return [cell(x) for x in zip(*(reachable(state) & (state.truth == GOAL)).nonzero())]


def _known_goals(state, known) -> list:
    """The goals among the cells ``known`` (a boolean grid), in flat-index order."""
    return [cell(x) for x in zip(*(known & (state.truth == GOAL)).nonzero())]


def _dead_end(state, c) -> bool:
    """``c`` is free and has an obstacle or the grid's edge on three of its four sides."""
    return free_cell(state, c) and len(free_neighbours(state, c)) == 1


def _after_exhausted(state, result):
    """The steps, the index of the sense after which nothing more was to be found (None if
    none), and the steps after it."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    steps = steps_of(result)
    return steps, index, ([] if index is None else steps[index + 1:])


# --- checks -------------------------------------------------------------------------------

def check_goals_share_line(state, result):
    """Exploring stops with the first sense after which two known goals share a row or a
    column, or nothing more is to be found."""
    def in_line(known):
        goals = _known_goals(state, known)
        return any(a != b and (a[0] == b[0] or a[1] == b[1]) for a in goals for b in goals)
    index = first_reaching(state, result, lambda known: in_line(known) or exhausted(state, known))
    if index is None:
        return "never knew two goals in line, and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_goal_by_obstacle_known(state, result):
    """Exploring stops with the first sense after which a known goal has a known obstacle
    next to it, or nothing more is to be found."""
    def pair(known):
        seen = known & (state.truth == OBSTACLE)
        return any(any(seen[n] for n in _neighbours(state, g))
                   for g in _known_goals(state, known))
    index = first_reaching(state, result, lambda known: pair(known) or exhausted(state, known))
    if index is None:
        return "never knew a goal beside an obstacle, and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_left_walk_dead_end_back(state, result):
    """A sense, then a walk left, a sense after every move, while the next cell is inside the
    grid and free; then, if the walk's end has one free neighbour, a move onto it."""
    home = state.start_cell
    plan = [("sense", home)] + _walk(state, home, LEFT)
    way = free_neighbours(state, plan[-1][1])
    if len(way) == 1:
        plan.append(("navigate", way[0]))
    return same_steps(steps_of(result), plan)


def check_first_free_way_run(state, result):
    """A sense, then a walk, a sense after every move, in the first of up, left, down and right
    whose next cell from the start is free, while the next cell that way is inside the grid and
    free."""
    home = state.start_cell
    way = next(s for s in (UP, LEFT, DOWN, RIGHT) if free_cell(state, step_by(home, s)))
    return same_steps(steps_of(result), [("sense", home)] + _walk(state, home, way))


def check_far_corner_and_back(state, result):
    """If the corner farthest from the start is reachable: the first move that ends on it is
    followed by one move onto the start and nothing else; if not, nothing more is to be found
    at the end and the agent is on the start."""
    home = state.start_cell
    corner = (9 if home[0] <= 4 else 0, 9 if home[1] <= 4 else 0)
    if reachable(state)[corner]:
        steps = steps_of(result)
        if ("navigate", corner) not in steps:
            return f"never moved onto the far corner {corner}"
        first = steps.index(("navigate", corner))
        return same_steps(steps[first + 1:], [("navigate", home)])
    if not exhausted(state):
        return "the far corner is out of reach, and more could be found"
    return None if state.cell == home else f"ended in {state.cell}, not the start {home}"


def check_second_nearest_goal(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then one move
    onto a reachable goal as far from the start as the second in the goals' order by distance
    (the only one if there is one; nothing if the agent stands on one)."""
    steps, index, rest = _after_exhausted(state, result)
    if index is None:
        return "stopped before everything was known"
    home, goals = state.start_cell, _reachable_goals(state)
    ranks = sorted(distance(g, home) for g in goals)
    want = ranks[min(1, len(ranks) - 1)]
    return onto(rest, steps[index][1], [g for g in goals if distance(g, home) == want],
                "after exploring")


def check_goal_look_busier_home(state, result):
    """A sense on the start first; after the sense that first shows a goal: if more obstacles
    are next to its cell than next to the start, one move onto the start (nothing if the agent
    is there), else one move onto a goal it showed (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    home = state.start_cell
    if steps[:1] != [("sense", home)]:
        return f"began {steps[:1]}, not a sense on the start"
    here = steps[index][1]
    if obstacles_beside(state, here) > obstacles_beside(state, home):
        return onto(steps[index + 1:], here, [home], "after a goal came into view")
    return onto_goal_seen(state, steps, index)


def _mine(home, c) -> bool:
    """``c`` lies in the quarter of the grid ``home`` lies in."""
    return (c[0] >= HALF) == (home[0] >= HALF) and (c[1] >= HALF) == (home[1] >= HALF)


def check_own_quarter_goal(state, result):
    """After the first sense that shows a goal in the start's quarter, one move onto such a
    goal it showed (nothing if the agent stands on one); if no sense shows one, nothing more to
    be found at the end and, after the last sense, one move onto the start (nothing if the
    agent is there)."""
    steps, home = steps_of(result), state.start_cell
    last = None
    for index, (kind, here) in enumerate(steps):
        if kind != "sense":
            continue
        last = index
        ours = [g for g in goals_shown(state, here) if _mine(home, g)]
        if ours:
            return onto(steps[index + 1:], here, ours, "after a goal of the quarter came into view")
    if not exhausted(state):
        return "no goal of the start's quarter seen, and more could be found"
    if last is None:
        return "never sensed"
    return onto(steps[last + 1:], steps[last][1], [home], "after the last sense")


def check_farthest_dead_end_home(state, result):
    """Nothing more to be found at the end; after the last sense, one move onto a reachable
    dead end other than the start farthest from the start, and one onto the start (with no such
    dead end, only the move onto the start)."""
    if not exhausted(state):
        return "stopped before everything was known"
    steps = steps_of(result)
    senses = [k for k, (kind, _) in enumerate(steps) if kind == "sense"]
    rest = steps[senses[-1] + 1:]
    home = state.start_cell
    ends = [c for c in _reachable_cells(state) if c != home and _dead_end(state, c)]
    if not ends:
        return same_steps(rest, [("navigate", home)])
    far = max(distance(c, home) for c in ends)
    return _any_plan(rest, [[("navigate", c), ("navigate", home)] for c in ends
                            if distance(c, home) == far])


def check_nearest_unstood_cell(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then one move
    onto a reachable cell no move had ended on (nor the start) nearest the start; with none,
    one move onto the start (nothing if the agent is there)."""
    steps, index, rest = _after_exhausted(state, result)
    if index is None:
        return "stopped before everything was known"
    home = state.start_cell
    stood = {home} | {c for kind, c in steps[:index + 1] if kind == "navigate"}
    fresh = [c for c in _reachable_cells(state) if c not in stood]
    if fresh:
        near = min(distance(c, home) for c in fresh)
        targets = [c for c in fresh if distance(c, home) == near]
    else:
        targets = [home]
    return onto(rest, steps[index][1], targets, "after exploring")


def check_longest_straight_run(state, result):
    """Ends on the far end of a longest of the four straight runs of free cells out of the
    start (up, down, left, right; each ends before the first obstacle or the grid's edge)."""
    home, ends = state.start_cell, []
    for way in (UP, DOWN, LEFT, RIGHT):
        here, n = home, 0
        while free_cell(state, step_by(here, way)):
            here, n = step_by(here, way), n + 1
        ends.append((n, here))
    best = max(n for n, _ in ends)
    targets = [c for n, c in ends if n == best]
    return None if state.cell in targets else f"ended in {state.cell}, not one of {targets}"


def check_trips_per_goal_found(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then only moves:
    onto a reachable goal nearest the start and onto the start, as many times as there are
    reachable goals."""
    steps, index, rest = _after_exhausted(state, result)
    if index is None:
        return "stopped before everything was known"
    home, goals = state.start_cell, _reachable_goals(state)
    near = min(distance(g, home) for g in goals)
    return _any_plan(rest, [[("navigate", g), ("navigate", home)] * len(goals) for g in goals
                            if distance(g, home) == near])


TOLL_FREE, TOLL, TOLL_LEAST = 3, 20, 75  # free scoops; grams charged each later one; tally needed
SURPLUS_BASE, SURPLUS_SHARE = 40, 2  # grams delivered at least; spill <= surplus / SURPLUS_SHARE


def check_scoop_toll_after_three(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 6:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass = grams_in_receiver(state)
    tally = mass - TOLL * max(0, n - TOLL_FREE)
    return None if tally >= TOLL_LEAST else \
        f"tally {tally:.1f}: {mass:.1f} g delivered in {n} scoop(s)"


def check_surplus_spill_allowance(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    if mass < SURPLUS_BASE or spilled > (mass - SURPLUS_BASE) / SURPLUS_SHARE:
        return f"{mass:.1f} g delivered and {spilled:.1f} g spilled in {n} scoop(s)"
    return None


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_K10, _K11 = indices(10), indices(11)
_DIRS = "[(0, 1), (0, -1), (1, 0), (-1, 0)]"
_WAYS = "[(0, 1), (-1, 0), (0, -1), (1, 0)]"  # up, left, down, right
# left_walk_dead_end_back: the free cells among those right of, above and below the walk's end
# (i - W, j), whose left is blocked
_SIDES = "((0 if i - W == 9 or is_obstacle((i - W + 1, j)) else 1) + (0 if j == 9 or " \
         "is_obstacle((i - W, j + 1)) else 1) + (0 if j == 0 or is_obstacle((i - W, j - 1)) else " \
         "1))"


def _d(a: str, b: str = _S) -> str:
    return distance_text(a, b)


def _blocked(i: str, j: str) -> str:
    """The cell (i, j) is off the grid or an obstacle."""
    return f"(not (0 <= {i} <= 9 and 0 <= {j} <= 9) or is_obstacle(({i}, {j})))"


def _free_count(c: str) -> str:
    """How many of the four cells next to ``c`` are inside the grid and free (no loop)."""
    return f"((1 if {c}[0] > 0 and not is_obstacle(({c}[0] - 1, {c}[1])) else 0) + (1 if {c}[0] " \
           f"< 9 and not is_obstacle(({c}[0] + 1, {c}[1])) else 0) + (1 if {c}[1] > 0 and not " \
           f"is_obstacle(({c}[0], {c}[1] - 1)) else 0) + (1 if {c}[1] < 9 and not " \
           f"is_obstacle(({c}[0], {c}[1] + 1)) else 0))"


def _obstacles_next(c: str) -> str:
    return f"len([x for x in neighbours({c}) if is_obstacle(x)])"


def _quarter_goal(c: str) -> str:
    """The cell ``c`` is a goal in the start's quarter of the grid."""
    return f"(is_goal({c}) and ({c}[0] // {HALF}, {c}[1] // {HALF}) == ({_S0} // {HALF}, " \
           f"{_S1} // {HALF}))"


_E = "sensed()[:-1]"  # the senses before the last
# the last sense showed a cell no earlier sense showed (then nothing more was to be found before
# it), read from the senses where moves may follow it, with one loop: a cell x is shown by a
# sense on x or on a cell next to it
_NEW_LAST = f"any(not (x in {_E} or (x[0] + 1, x[1]) in {_E} or (x[0] - 1, x[1]) in {_E} or " \
            f"(x[0], x[1] + 1) in {_E} or (x[0], x[1] - 1) in {_E}) for x in [{_L}] + " \
            f"neighbours({_L}))"
_STAY, _MOVE = "primitives()[-1:] == ['sense']", "primitives()[-2:] == ['sense', 'navigate']"
# after the last sense: nothing if it was taken on the start, else one move onto the start
_HOME_AFTER = f"(({_L} == {_S} and {_STAY}) or ({_L} != {_S} and {_MOVE} and {_F} == {_S}))"
_HOME = f"{_F} == {_S} and steps_after_goal() == (0 if {_L} == {_S} else 1) and " \
        f"primitives()[-1:] == (['sense'] if {_L} == {_S} else ['navigate'])"
_FAR_CORNER = f"(9 if {_S0} <= 4 else 0, 9 if {_S1} <= 4 else 0)"
_DF = _d(_F)  # the final cell's distance from the start
_W = "moves()[-2]"  # farthest_dead_end_home: the dead end visited
# longest_straight_run: (i, j) the start, (x, y) the final cell; the k-th cell out of the start by
# (a, b) is blocked; the final cell's distance from the start
_RUN_STOP, _DXY = _blocked("i + a * k", "j + b * k"), "abs(x - i + y - j)"  # on an axis


def _dead_in_reach(c: str) -> str:
    """The reachable cell ``c`` has exactly one reachable cell next to it (no loop)."""
    return " + ".join(f"(1 if ({x}, {y}) in reachable_cells() else 0)" for x, y in
                      ((f"{c}[0] - 1", f"{c}[1]"), (f"{c}[0] + 1", f"{c}[1]"),
                       (f"{c}[0]", f"{c}[1] - 1"), (f"{c}[0]", f"{c}[1] + 1"))) + " == 1"

TASKS = [
    _task("goals_share_line", 1, check_goals_share_line,
          "Explore, moving and sensing, until you know of two goals that lie in line with each "
          "other: in the same row (the same j) or in the same column (the same i), however far "
          "apart. Stop right after the sense that first shows you such a pair. If there is "
          "nothing more to find before that, stop right after the sense that leaves nothing "
          "more to find.",
          f"primitives()[-1:] == ['sense'] and [any(is_goal(a) and any(is_goal(b) and b != a and "
          f"(b[0] == a[0] or b[1] == a[1]) for b in K) for a in K) for K in [known_before_last(), "
          f"known_cells()]] in [[False, True]] + ([[False, False]] if explored_all() and "
          f"{_FRESH} else [])"),
    _task("left_walk_dead_end_back", 2, check_left_walk_dead_end_back,
          "Sense where you start, then walk left (i - 1), one cell at a time, sensing after "
          "every move, while the next cell to the left is inside the grid and free. Then look "
          "at the cell where the walk ended: if it is a dead end -- an obstacle or the grid's "
          "edge on three of its four sides -- back out of it with one move onto its only free "
          "neighbour and stop there without sensing. Otherwise stop where the walk ended.",
          "any(W >= 0 and primitives() == ['sense'] + ['navigate', 'sense'] * W + ['navigate'] * "
          f"E and moves()[:W] == [(i - k, j) for k in {_K10}[1:W + 1]] and "
          f"{_blocked('i - W - 1', 'j')} and ({_SIDES} == 1) == (E == 1) and (E == 0 or "
          f"(moves()[-1] in neighbours((i - W, j)) and not is_obstacle(moves()[-1]))) for E in "
          f"[0, 1] for W, i, j in [(len(sensed()) - 1, {_S0}, {_S1})])"),
    _task("first_free_way_run", 1, check_first_free_way_run,
          "Sense where you start. Then choose one direction: the first of up (j + 1), left "
          "(i - 1), down (j - 1) and right (i + 1), in that order, in which the cell next to "
          "your start is inside the grid and free. Walk that way, one cell at a time, sensing "
          "after every move, while the next cell that way is inside the grid and free, and stop "
          "where the walk ends.",
          "any(W >= 1 and primitives() == ['sense'] + ['navigate', 'sense'] * W and moves() == "
          f"[(i + a * k, j + b * k) for k in {_K10}[1:W + 1]] and "
          f"{_blocked('i + a * (W + 1)', 'j + b * (W + 1)')} and (b == 1 or "
          f"({_blocked('i', 'j + 1')} and (a == -1 or ({_blocked('i - 1', 'j')} and (b == -1 or "
          f"{_blocked('i', 'j - 1')}))))) for a, b, W, i, j in [(a, b, len(moves()), {_S0}, "
          f"{_S1}) for a, b in {_WAYS}])"),
    _task("far_corner_and_back", 2, check_far_corner_and_back,
          "Touch the far corner of the grid and come back: of the four corner cells (0, 0), "
          "(0, 9), (9, 0) and (9, 9), head for the one farthest from your starting cell, "
          "counting steps along rows and columns, and explore as much as you need to get onto "
          "it. As soon as a move puts you on that corner, go straight back to your starting "
          "cell with one move and stop there. If that corner cannot be reached, go back to your "
          "starting cell once there is nothing more to find, and stop there.",
          f"all((C not in moves()[:-2] and moves()[-2:] == [C, {_S}] and primitives()[-2:] == "
          f"['navigate', 'navigate']) if C in reachable_cells() else (explored_all() and {_F} "
          f"== {_S}) for C in [{_FAR_CORNER}])"),
    _task("second_nearest_goal", 2, check_second_nearest_goal,
          "Explore, moving and sensing, until there is nothing more to find. Then order the "
          "goals you can reach by their distance from your starting cell, nearest first, "
          "counting steps along rows and columns and ignoring obstacles, and go with one move "
          "onto the goal that comes second (goals equally far may come in either order, so any "
          "goal as far as the second one will do; if you can reach only one goal, go onto that "
          "one). If you are standing on such a goal, just stop.",
          f"explored_all() and {_NEW_LAST} and all(is_goal({_F}) and {_F} in reachable_goals() "
          f"and {_DF} == T and ({_STAY} or ({_MOVE} and not (is_goal({_L}) and {_d(_L)} == "
          f"T))) for T in [sorted([{_d('g')} for g in reachable_goals()])[min(1, "
          f"len(reachable_goals()) - 1)]])"),
    _task("goal_look_busier_home", 2, check_goal_look_busier_home,
          "Sense where you start and count the obstacles on the cells right next to your "
          "starting cell (the grid's edge does not count). Then search for a goal. When a sense "
          "first shows you one, count the obstacles right next to the place you took that "
          "sense from in the same way. If there are more there than at your start, leave the "
          "goal and go straight back to your starting cell with one move, and stop (if you are "
          "there, just stop). Otherwise go onto the goal with one move and stop (onto any of "
          "them if that sense showed several; if you are standing on one, just stop).",
          f"primitives()[:1] == ['sense'] and goal_found() and (({_HOME}) if "
          f"{_obstacles_next(_L)} > {_obstacles_next(_S)} else ({_ONTO_GOAL}))"),
    _task("own_quarter_goal", 2, check_own_quarter_goal,
          "Look for a goal in your own quarter of the grid: the quarter your starting cell lies "
          "in, the grid being cut into quarters between i = 4 and i = 5 and between j = 4 and "
          "j = 5. Goals in the other quarters do not count. Explore, moving and sensing, and as "
          "soon as a sense shows you a goal in your quarter, go onto it with one move and stop "
          "(onto any of them if that sense showed several; if you are standing on one, just "
          "stop). If there is nothing more to find and you never saw one, go straight back to "
          "your starting cell with one move and stop (if you are there, just stop).",
          f"(not any({_quarter_goal('c')} for s in sensed()[:-1] for c in [s] + neighbours(s)) "
          f"and ({_STAY} if {_quarter_goal(_L)} else ({_MOVE} and {_F} in neighbours({_L}) and "
          f"{_quarter_goal(_F)}))) or (explored_all() and not "
          f"any({_quarter_goal('g')} for g in reachable_goals()) and {_HOME_AFTER})"),
    _task("farthest_dead_end_home", 3, check_farthest_dead_end_home,
          "Explore, moving and sensing, until there is nothing more to find (a sense more after "
          "that changes nothing and does no harm). Then, without sensing again, visit the "
          "dead end you can reach that lies farthest from your starting cell -- a free cell "
          "with an obstacle or the grid's edge on three of its four sides; your starting cell "
          "does not count -- counting steps along rows and columns and ignoring obstacles (any "
          "of them if several are equally far): go onto it with one move, then straight back "
          "to your starting cell with one more, and stop. If you can reach no such dead end, "
          "just go straight back to your starting cell with one move. A dead end you are "
          "standing on when the exploring ends still gets its move.",
          f"explored_all() and moves()[-1:] == [{_S}] and all((primitives()[-3:] == ['sense', "
          f"'navigate', 'navigate'] and {_dead_in_reach(_W)} and {_d(_W)} == max(D)) if len(D) > "
          f"0 else {_MOVE} for D in [[{_d('c')} for c in reachable_cells() if c != {_S} and "
          f"len([x for x in neighbours(c) if not is_obstacle(x)]) == 1]])"),
    _task("nearest_unstood_cell", 2, check_nearest_unstood_cell,
          "Explore, moving and sensing, until there is nothing more to find. Then go with one "
          "move to the cell you can reach where none of your moves has ended yet (your "
          "starting cell counts as one you have stood on) that is nearest to your starting "
          "cell, counting steps along rows and columns and ignoring obstacles (any of them if "
          "several are equally near). If your moves have ended on every cell you can reach, go "
          "straight back to your starting cell with one move instead (if you are there, just "
          "stop).",
          f"explored_all() and {_NEW_LAST} and all(({_MOVE} and {_F} not in [{_S}] + "
          f"moves()[:-1] and {_DF} == min(U)) if len(U) > 0 else {_HOME_AFTER} for U in "
          f"[[{_d('c')} for c in reachable_cells() if c not in [{_S}] + moves()[:-1]]])"),
    _task("longest_straight_run", 3, check_longest_straight_run,
          "Find the longest straight run out of your starting cell. From your start, look "
          "along the four straight lines up (j + 1), down (j - 1), left (i - 1) and right "
          "(i + 1): each runs over free cells until the first obstacle or the grid's edge. "
          "Explore as much as you need to know how long each of them is, then go to the far "
          "end of the longest one -- its last free cell -- and stop there (any of them if "
          "several are equally long).",
          f"all((x == i or y == j) and {_DXY} >= 1 and any({_RUN_STOP} for k in "
          f"{_K11}[1:{_DXY} + 2]) and ((x, y) != (i + a * {_DXY}, j + b * {_DXY}) or not "
          f"any({_RUN_STOP} for k in {_K10}[1:{_DXY} + 1])) for a, b, i, j, x, y in [" +
          ", ".join(f"({a}, {b}) + {_S} + {_F}" for a, b in ((0, 1), (0, -1), (1, 0), (-1, 0)))
          + "])"),
    _task("trips_per_goal_found", 3, check_trips_per_goal_found,
          "Explore, moving and sensing, until there is nothing more to find, and count the "
          "goals you can reach. Then shuttle between the goal nearest to your starting cell "
          "(counting steps along rows and columns and ignoring obstacles; any of them if "
          "several are equally near) and your starting cell, as many times as you counted "
          "goals: onto the goal, back to your start, onto the goal, back to your start, and so "
          "on, one move each, ending on your start. After the exploring, make no other moves "
          "and do not sense again; a goal you are standing on when the exploring ends still "
          "gets its first move.",
          f"explored_all() and {_NEW_LAST} and len(moves()) >= 2 and all(is_goal(G) and "
          f"all({_d('g')} >= {_d('G')} for g in reachable_goals()) and primitives()[len("
          f"primitives()) - 2 * N - 1:] == ['sense'] + ['navigate'] * (2 * N) and "
          f"moves()[len(moves()) - 2 * N:] == [G, {_S}] * N for G, N in [(moves()[-2], "
          f"len(reachable_goals()))])"),
    _task("goal_by_obstacle_known", 1, check_goal_by_obstacle_known,
          "Explore, moving and sensing, until you know of a goal with an obstacle right next to "
          "it, on one of the four cells beside it (left, right, above or below). Stop right "
          "after the sense that first shows you such a goal and obstacle together. If there is "
          "nothing more to find before that, stop right after the sense that leaves nothing "
          "more to find.",
          "primitives()[-1:] == ['sense'] and [any(is_goal(c) and any(x in K and is_obstacle(x) "
          "for x in neighbours(c)) for c in K) for K in [known_before_last(), known_cells()]] in "
          f"[[False, True]] + ([[False, False]] if explored_all() and {_FRESH} else [])"),
    _task("scoop_toll_after_three", 2, check_scoop_toll_after_three,
          f"Scoop one to six times, then stop, with a tally of at least {TOLL_LEAST}: the grams "
          f"of grains in the receiver, less a toll of {TOLL} for every scoop after the "
          f"{TOLL_FREE}rd (the first {TOLL_FREE} scoops are free).",
          f"scoops() >= 1 and scoops() <= 6 and delivered() - {TOLL} * (scoops() - {TOLL_FREE} "
          f"if scoops() > {TOLL_FREE} else 0) >= {TOLL_LEAST}", SCOOP),
    _task("surplus_spill_allowance", 2, check_surplus_spill_allowance,
          f"Scoop two to five times, then stop, leaving at least {SURPLUS_BASE} g of grains in "
          f"the receiver, and spilling no more outside the containers than half of what the "
          f"receiver holds beyond {SURPLUS_BASE} g.",
          f"scoops() >= 2 and scoops() <= 5 and delivered() >= {SURPLUS_BASE} and spilled() <= "
          f"(delivered() - {SURPLUS_BASE}) / {SURPLUS_SHARE}", SCOOP),
]
