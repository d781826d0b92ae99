"""Held-out tasks, twenty-second set: written before the next change of the synthesizer, run once
after it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout22/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (after exploring, onto the reachable goal
nearest to a corner of the grid; exploring that stops once a lone obstacle is known, one with no
obstacle next to it and every cell next to it known; after exploring, a tour of the goals with the
most obstacles next to them first, then home; a walk down that comes home only if it made an odd
number of moves; once a goal is in view, onto it and a sense there, then off it onto its only free
neighbour if it is a dead end; after exploring, back along the last three moves, cell by cell;
exploring that stops with the sense taken on a third cell of the grid's border; after exploring,
onto the reachable cell of the start's row with the fewest obstacles next to it; after exploring,
home if more than twice as many dead ends as goals can be reached, else onto the goal nearest the
start; a walk left, then a walk up from its end, and back to the turn if the walk up moved; once a
goal is in view, home if the moves made outnumber the obstacles known, else onto the goal;
exploring that stops at the first sense taken on a dead end other than the start, then home) and
two scooping tasks (one to five scoops with a net of at least 85, the grams delivered less the
grams spilled beyond a free allowance of 10 g; one to four scoops that leave at least 80 g in the
receiver with the grams spilled times the scoops made at most 100). Each has a reference behavior
(``references/``), a ground-truth ``check`` and a faithful ``promise`` over the env's outcome
helpers, so that the search can be measured apart from the model. They were written on 2026-12-07
blind: without reading the search's code and without running the synthesizer on them; the first run
of the search on them is the evaluation, reported beside the development figures.

Close relatives of earlier tasks: goal_nearest_corner of heldout2's reachable_corner and
heldout20's far_corner_and_back (the grid's corners) and heldout20's second_nearest_goal and
heldout2's nearer_goal (a goal picked by a distance after exploring; here to its nearest corner,
not to the start); lone_obstacle_known of heldout3's touching_obstacle and heldout8's
two_touching_obstacles (obstacles that touch; here one that touches none) and heldout20's
goal_by_obstacle_known and heldout13's scout_goal_surroundings (a cell and the cells next to it
known); crowded_goals_first_tour of heldout18's goals_low_to_high_home and heldout16's
farthest_first_goal_tour (ordered tours of the goals after exploring, then home; here by the
obstacles next to each) and heldout7's least_hemmed_goal (a goal by the obstacles next to it);
down_walk_odd_home of heldout16's short_walk_home and heldout9's left_wall_return (home on how a
walk went; there its length under three, or the edge) and heldout12's obstacle_parity_goal and
heldout9's parity_step (a parity decides); goal_dead_end_backout of heldout17's goal_inspection and
heldout8's goal_chain (onto the goal and a sense there that decides what follows), heldout20's
left_walk_dead_end_back (out of a dead end onto its one free neighbour) and heldout2's
step_back_after_goal; retrace_last_three of heldout3's retrace_to_start and heldout10's
down_left_retrace (cells retraced one by one; there to the start) and heldout11's lookback_three
(there one move back to the cell stood in three moves before); three_border_looks of heldout17's
four_quarters_sensed (stops on where senses were taken), heldout6's three_clear_looks (a count of
senses) and the development border_cell (dev_general; the grid's border); calmest_in_start_row of
heldout4's calmest_neighbour and heldout7's least_hemmed_goal (the fewest obstacles next to a cell)
and heldout18's column_far_end (a reachable cell of the start's column after exploring);
dead_ends_outnumber_home of heldout20's trips_per_goal_found (the reachable goals counted) and
farthest_dead_end_home (reachable dead ends), heldout4's lone_goal_or_home (goal or home after
exploring, on a count) and heldout2's nearer_goal; left_up_corner_return of heldout3's
up_then_right and heldout17's right_then_up_at_opening (two walks in a row), heldout10's
down_left_retrace and back_to_second_look (back to a place the agent was);
search_moves_vs_obstacles of heldout17's wandered_home_first (home or the goal on the moves counted
against the goal's distance), heldout18's cluttered_search_home (home on the obstacles the search
showed) and heldout14's obstacle_rate_stop (senses against obstacles known); dead_end_look_home of
heldout14's squeezed_stop and heldout6's first_crowded_look (exploring that stops at the first
sense taken on a cell of some shape), heldout2's dead_end and heldout20's far_corner_and_back (home
once nothing more is to be found); spill_allowance_net of heldout7's three_scoops_net_gain (grams
delivered less spilled) and heldout19's spill_grace (an allowance of spill); spill_times_scoops of
heldout13's shrinking_spill_allowance and heldout8's low_spill_per_scoop (a spill bound that
tightens with the scoops; here their product).

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a cell's *row*
is the cells with its j; the grid's *border* is the cells with i or j equal to 0 or 9 and its
*corners* are (0, 0), (0, 9), (9, 0) and (9, 9), a cell's distance *to the nearest corner* being
min(i, 9 - i) + min(j, 9 - j); a cell is *blocked* when it is an obstacle or outside the grid; a
*dead end* is a free cell blocked on three of its four sides (it has exactly one free cell next to
it); a *lone obstacle* is one none of whose neighbours inside the grid is an obstacle, known when
it and all of those are known; the agent *stood on* a cell when a move ended on it (its start
included); a sense labels its cell and the four around it (it *shows* them; a goal *comes into
view* with the first sense that shows it; a sense is *taken on* the cell the agent is in); the
obstacles *next to* a cell are those among its four neighbours inside the grid (the grid's edge
does not count); the *distance* of two cells counts steps along rows and columns (|di| + |dj|),
obstacles ignored. The start cell always has a free neighbour (a goal is reachable from it and it
holds none); the references only move onto cells they know, so none ever stood on a goal when it
first came into view, and a known free cell is always reachable (it is the sensed-from cell or next
to it). The promises' language allows three comprehension loops in one expression, all of them
counted together, and 400 syntax nodes (goal_nearest_corner's promise has 378): where exploring
ends on a sense after which something held, that it did not before is read from
``known_before_last()`` (lone_obstacle_known: whether the known cells hold it before the last step
and after it, [False, True], or [False, False] with nothing more to find); where it ends on a count
of the senses (three_border_looks), from the senses less the last and all of them, and whether
nothing more was to be found before the last sense from ``explored_all()`` and whether it labelled
anything (a sense labels only reachable cells and cells next to them, so one that labels something
new leaves something that was not known before it); where moves follow the sense that left nothing
more to find, that nothing more was to be found before it is read from the senses with one loop
(the last sense showed a cell that no earlier sense was taken on, nor on a cell next to it:
goal_nearest_corner, retrace_last_three, and dead_end_look_home, which also reads from it that the
exploring had not ended before its last sense); crowded_goals_first_tour, calmest_in_start_row and
dead_ends_outnumber_home ask only that nothing more was to be found at the end and read their moves
after the last sense (a sense more after the exploring does no harm, as their tasks say);
goal_dead_end_backout reads the goal as the cell of the last sense, and the sense that showed it as
the one before it unless the agent stood on a goal then; search_moves_vs_obstacles reads the goal
sense as the last sense (only moves may follow it) and the moves before it as the moves less
``moves_after_goal()``; retrace_last_three reads how many moves were retraced from the moves in all
(three of six or more, half of fewer, and only where that is the lesser of three and the moves
before it); down_walk_odd_home and left_up_corner_return read their walks from the senses and the
moves, as heldout20's left_walk_dead_end_back does (left_up_corner_return writes the two walks as
one list of cells, the turn after A moves, for each A from 0 to 9); crowded_goals_first_tour reads
the tour as the moves before the last, one for each reachable goal, whose sorted list must be the
reachable goals; a promise whose target is a choice among ties lets the agent stay only where the
cell it stands in is as good as the target, and move only where that cell is strictly worse
(goal_nearest_corner, dead_ends_outnumber_home; calmest_in_start_row lets it stay or move when it
stands on such a cell, as its task says). The scooping checks weigh the grains at the end, as
``delivered()`` and ``spilled()`` do: those in the receiver, and those outside the receiver, the
donor and the spoon's tray.

Validation before the set was fixed (each reference run once an episode without a promise, and
every promise and every check of the set judged on the run as ``evaluate`` judges it, on the
episodes whose certificates all held): every grid reference kept its promise and did its task on
all 300 episodes (0-99 of seeds 0, 1 and 2), and on those 3,600 episodes every one of the twelve
promises was judged against every reference (43,200 judgements), its verdict equal to its check's
on all. On those episodes the tasks' branches came up: the goal nearest a corner of 3, 2 and 1
reachable goals 218, 61 and 21 times, 0 to 8 steps from its corner, staying on it 12; a lone
obstacle known after 2 to 54 senses 294 times, nothing more to find first 6; tours of 3, 2 and 1
goals 218, 61 and 21 times, with a tie in the counts 181, in an order other than the goals'
i-then-j order 143; walks down of 0 to 8 moves (none 106, one 75, two 38), home after an odd one
123; a goal that is a dead end, stepped off 23 times, stayed on 277; three moves retraced all 300
times (fewer than three moves before nothing more was to be found never came up for the reference:
its exploring makes more); a third border sense after 3 to 27 senses 299 times (the start on the
border 97), nothing more to find first once; onto a cell of the start's row with 0, 1 and 2
obstacles next to it 250, 46 and 4 times (onto the start 55), staying 4; home after exploring 190
times, onto the nearest goal 110; walks left of 0 to 9 moves (none 99, one 83) and walks up of 0 to
8 (none 83), back to the turn 217 times; home from the goal sense 180 times (after up to 52 moves),
onto the goal 120 (41 of them seen from the start); home from a dead end other than the start after
2 to 59 senses 299 times, nothing more to find first once. Faithfulness on behaviors that do not do
the tasks: every grid promise was judged against 69 near misses of the references (thresholds,
ratios, parities and counts one off or turned round, other directions, corners, rows or columns,
metrics, shapes or places to go back to, the grid's edge or the start counted or left out, a
return, a sense, a move or a trip dropped or added, an explorer that stops one sense late or runs
on) and 18 other ways of doing the tasks (another explorer, another choice among ties, a parity
read from the place, a back-out onto the cell the goal was seen from, which is the dead end's only
free neighbour, a move where staying would do, a sense more after the exploring where the task
allows it) on episodes 0-99 of seeds 0 and 1 (17,400 judged episodes for each promise, none lost):
the near misses kept their own task's promise on 4,927 of their 13,800 episodes and the other ways
on all their 3,600; against the 254 grid references of the development and earlier held-out sets
(heldout21 left out: not yet evaluated) on episodes 0-49 of seed 0 (12,700 judged episodes for each
promise, none lost); and against 25 trivial behaviors (stop at once, judged on the reset; sense
where it stands 1 to 12 times; navigate onto the cell it stands in 1 to 12 times) on episodes 0-99
of seeds 0 and 1 (5,000 judged episodes for each promise): on every judged episode the promise's
verdict equalled the check's. Keep rates of the trivial behaviors: none keeps any promise on any
episode but sensing once, which keeps down_walk_odd_home's (68 of 200: the cell below the start
blocked) and left_up_corner_return's (20: the cells left of and above the start blocked), where the
tasks ask for the one sense. The held-out folder tests (tests/test_synthesis_eval.py's
satisfiable-faithful-checkable test, and tests/test_certified.py's readings of every promise and
its bank test) pointed at this folder passed. The scooping references (four and three scoops from
the default sensing pose) were run on episodes 0-9 of seed 0 only (seconds an episode) and kept
their promises and did their tasks on all 10: four scoops delivered 104.0 to 171.9 g and spilled
6.8 to 31.7 g, a net of 91.4 at least (85 needed: margin 6.4); three scoops delivered 88.2 to 133.5
g (80 needed) and spilled 4.5 to 24.9 g, 74.6 at most times three (100 allowed). The thresholds
were set from these figures and from one to six scoops on the same episodes. Both promises were
judged on one to six scoops and the checks agreed on every one: one scoop (33.9 to 54.3 g) kept
neither; two scoops kept spill_allowance_net's on 2 and spill_times_scoops' on 4; three scoops
spill_allowance_net's on 9 and spill_times_scoops' on all 10; four scoops spill_allowance_net's on
all 10 and spill_times_scoops' on 8; five scoops spill_allowance_net's on all 10 and
spill_times_scoops' on none (more than four); six scoops neither."""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (goal_sense as _goal_sense,
                                        FINAL as _F, FRESH as _FRESH, LAST_SENSE as _L,
                                        ONLY_MOVES as _ONLY_MOVES, ONTO_GOAL as _ONTO_GOAL,
                                        START as _S, START_I as _S0, START_J as _S1, cell,
                                        distance, distance_text, exhausted, first_reaching,
                                        free_cell, free_neighbours, goals_shown, grams_in_receiver,
                                        grams_spilled, held_out_task, indices, known_after,
                                        neighbours as _neighbours, obstacles_beside, onto,
                                        onto_goal_seen, reachable, same_steps, scoops, step_by,
                                        steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
LEFT, RIGHT, DOWN, UP = (-1, 0), (1, 0), (0, -1), (0, 1)
EDGE = 9  # the last index of a row or a column of the 10x10 grid


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


def _dead_end(state, c) -> bool:
    """``c`` is free and has an obstacle or the grid's edge on three of its four sides."""
    return free_cell(state, c) and len(free_neighbours(state, c)) == 1


def _corner_distance(c) -> int:
    """Steps from ``c`` to the corner of the grid nearest it."""
    return min(c[0], EDGE - c[0]) + min(c[1], EDGE - c[1])


def _border(c) -> bool:
    return c[0] in (0, EDGE) or c[1] in (0, EDGE)


def _after_exhausted(state, result):
    """The steps, the index of the sense after which nothing more was to be found (None if
    none), and the steps after it."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    steps = steps_of(result)
    return steps, index, ([] if index is None else steps[index + 1:])


def _after_last_sense(state, result):
    """The steps, the index of the last sense (None if none) and the steps after it."""
    steps = steps_of(result)
    senses = [k for k, (kind, _) in enumerate(steps) if kind == "sense"]
    if not senses:
        return steps, None, []
    return steps, senses[-1], steps[senses[-1] + 1:]


# --- checks -------------------------------------------------------------------------------

def check_goal_nearest_corner(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then one move
    onto a reachable goal whose distance to its nearest corner is the least (nothing if the
    agent stands on one)."""
    steps, index, rest = _after_exhausted(state, result)
    if index is None:
        return "stopped before everything was known"
    goals = _reachable_goals(state)
    least = min(_corner_distance(g) for g in goals)
    return onto(rest, steps[index][1], [g for g in goals if _corner_distance(g) == least],
                "after exploring")


def check_lone_obstacle_known(state, result):
    """Exploring stops with the first sense after which a known obstacle has every cell next to
    it known and free, or nothing more is to be found."""
    def lone(known):
        return any(known[o] and state.truth[o] == OBSTACLE and
                   all(known[n] and state.truth[n] != OBSTACLE for n in _neighbours(state, o))
                   for o in map(cell, zip(*known.nonzero())))
    index = first_reaching(state, result, lambda known: lone(known) or exhausted(state, known))
    if index is None:
        return "never knew a lone obstacle, and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_crowded_goals_first_tour(state, result):
    """Nothing more to be found at the end; after the last sense only moves: onto every
    reachable goal once, those with more obstacles next to them first, then onto the start."""
    if not exhausted(state):
        return "stopped before everything was known"
    steps, index, rest = _after_last_sense(state, result)
    if index is None:
        return "never sensed"
    home, goals = state.start_cell, _reachable_goals(state)
    tour = [c for kind, c in rest[:-1] if kind == "navigate"]
    counts = [obstacles_beside(state, c) for c in tour]
    if (len(tour) == len(rest) - 1 and sorted(tour) == sorted(goals)
            and counts == sorted(counts, reverse=True) and rest[-1:] == [("navigate", home)]):
        return None
    return f"after the last sense ran {rest[:6]}, not a tour of {goals} most crowded first, " \
           "then home"


def check_down_walk_odd_home(state, result):
    """A sense, then a walk down, a sense after every move, while the next cell is inside the
    grid and free; then one move onto the start if the walk made an odd number of moves."""
    home = state.start_cell
    walk = _walk(state, home, DOWN)
    plan = [("sense", home)] + walk + ([("navigate", home)] if len(walk) // 2 % 2 else [])
    return same_steps(steps_of(result), plan)


def check_goal_dead_end_backout(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed and a sense
    there (nothing if the agent stands on one); then, if that goal has exactly one free cell
    next to it, one move onto that cell."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, rest = steps[index][1], steps[index + 1:]
    if state.truth[here] == GOAL:
        goal, tail = here, rest
    elif (len(rest) >= 2 and rest[0][0] == "navigate" and rest[0][1] in goals_shown(state, here)
          and rest[1] == ("sense", rest[0][1])):
        goal, tail = rest[0][1], rest[2:]
    else:
        return f"after the goal came into view ran {rest[:4]}, not a move onto it and a sense"
    ways = free_neighbours(state, goal)
    return same_steps(tail, [("navigate", ways[0])] if len(ways) == 1 else [])


def check_retrace_last_three(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then only moves:
    back onto the cells stood on before the last three moves (fewer if fewer were made), the
    latest first."""
    steps, index, rest = _after_exhausted(state, result)
    if index is None:
        return "stopped before everything was known"
    stood = [state.start_cell] + [c for kind, c in steps[:index + 1] if kind == "navigate"]
    last = len(stood) - 1
    return same_steps(rest, [("navigate", stood[last - 1 - k]) for k in range(min(3, last))])


def check_three_border_looks(state, result):
    """Exploring stops with the first sense after which senses have been taken on three
    different cells of the grid's border, or nothing more is to be found."""
    known = state.truth != state.truth  # all False
    border: set = set()
    for index, step in enumerate(result.steps):
        if step["primitive"] != "sense":
            continue
        here = cell(step["param"])
        for n in [here, *_neighbours(state, here)]:
            known[n] = True
        if _border(here):
            border.add(here)
        if len(border) >= 3 or exhausted(state, known):
            return same_steps(steps_of(result)[index + 1:], [])
    return "sensed on fewer than three border cells, and more could be found"


def check_calmest_in_start_row(state, result):
    """Nothing more to be found at the end; after the last sense, one move onto a reachable
    cell of the start's row with the fewest obstacles next to it, or nothing if the agent
    stands on one."""
    if not exhausted(state):
        return "stopped before everything was known"
    steps, index, rest = _after_last_sense(state, result)
    if index is None:
        return "never sensed"
    row = [c for c in _reachable_cells(state) if c[1] == state.start_cell[1]]
    least = min(obstacles_beside(state, c) for c in row)
    targets = [c for c in row if obstacles_beside(state, c) == least]
    if (rest == [] and steps[index][1] in targets) or \
            (len(rest) == 1 and rest[0][0] == "navigate" and rest[0][1] in targets):
        return None
    return f"after the last sense ran {rest[:4]}, not an end on one of {targets[:6]}"


def check_dead_ends_outnumber_home(state, result):
    """Nothing more to be found at the end; after the last sense, if more than twice as many
    reachable dead ends (the start included) as reachable goals, one move onto the start
    (nothing if the agent is there), else one move onto a reachable goal nearest the start
    (nothing if the agent stands on one)."""
    if not exhausted(state):
        return "stopped before everything was known"
    steps, index, rest = _after_last_sense(state, result)
    if index is None:
        return "never sensed"
    home, goals = state.start_cell, _reachable_goals(state)
    ends = [c for c in _reachable_cells(state) if _dead_end(state, c)]
    if len(ends) > 2 * len(goals):
        return onto(rest, steps[index][1], [home], "after the last sense")
    near = min(distance(g, home) for g in goals)
    return onto(rest, steps[index][1], [g for g in goals if distance(g, home) == near],
                "after the last sense")


def check_left_up_corner_return(state, result):
    """A sense, a walk left, then a walk up from its end, a sense after every move, each while
    the next cell is inside the grid and free; then, if the walk up moved, one move back onto
    the cell where it began."""
    home = state.start_cell
    plan = [("sense", home)] + _walk(state, home, LEFT)
    turn = plan[-1][1]
    climb = _walk(state, turn, UP)
    plan += climb + ([("navigate", turn)] if climb else [])
    return same_steps(steps_of(result), plan)


def check_search_moves_vs_obstacles(state, result):
    """After the sense that first shows a goal: if more moves came before it than obstacles
    were known after it, one move onto the start (nothing if the agent is there), else one move
    onto a goal it showed (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    moved = sum(kind == "navigate" for kind, _ in steps[:index])
    known = known_after(state, result.steps[:index + 1])
    seen = int((known & (state.truth == OBSTACLE)).sum())
    if moved > seen:
        return onto(steps[index + 1:], steps[index][1], [state.start_cell],
                    "after a goal came into view")
    return onto_goal_seen(state, steps, index)


def check_dead_end_look_home(state, result):
    """Exploring stops with the first sense taken on a dead end other than the start, or after
    which nothing more is to be found; then one move onto the start (nothing if the agent is
    there)."""
    home = state.start_cell
    known = state.truth != state.truth  # all False
    steps = steps_of(result)
    for index, (kind, here) in enumerate(steps):
        if kind != "sense":
            continue
        for n in [here, *_neighbours(state, here)]:
            known[n] = True
        if (here != home and _dead_end(state, here)) or exhausted(state, known):
            return onto(steps[index + 1:], here, [home], "after the exploring")
    return "never sensed on a dead end, and more could be found"


ALLOWANCE, NET_LEAST = 10, 85  # grams spilled free of charge; net grams needed
PRODUCT_MOST, PRODUCT_LEAST = 100, 80  # spilled grams times scoops at most; grams delivered


def check_spill_allowance_net(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    net = mass - max(0.0, spilled - ALLOWANCE)
    return None if net >= NET_LEAST else \
        f"net {net:.1f}: {mass:.1f} g delivered, {spilled:.1f} g spilled in {n} scoop(s)"


def check_spill_times_scoops(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    if mass < PRODUCT_LEAST or spilled * n > PRODUCT_MOST:
        return f"{mass:.1f} g delivered and {spilled:.1f} g spilled in {n} scoop(s)"
    return None


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_K3, _K10, _K19 = indices(3), indices(10), indices(19)
_STAY, _MOVE = "primitives()[-1:] == ['sense']", "primitives()[-2:] == ['sense', 'navigate']"
_E = "sensed()[:-1]"  # the senses before the last
# the last sense showed a cell no earlier sense showed (then nothing more was to be found
# before it), read from the senses where moves may follow it, with one loop: a cell x is shown
# by a sense on x or on a cell next to it
_NEW_LAST = f"any(not (x in {_E} or (x[0] + 1, x[1]) in {_E} or (x[0] - 1, x[1]) in {_E} or " \
            f"(x[0], x[1] + 1) in {_E} or (x[0], x[1] - 1) in {_E}) for x in [{_L}] + " \
            f"neighbours({_L}))"
# after the last sense: nothing if it was taken on the start, else one move onto the start
_HOME_AFTER = f"(({_L} == {_S} and {_STAY}) or ({_L} != {_S} and {_MOVE} and {_F} == {_S}))"
_HOME = f"{_F} == {_S} and steps_after_goal() == (0 if {_L} == {_S} else 1) and " \
        f"primitives()[-1:] == (['sense'] if {_L} == {_S} else ['navigate'])"


def _d(a: str, b: str = _S) -> str:
    return distance_text(a, b)


def _cd(c: str) -> str:
    """The distance of the cell ``c`` to the corner of the grid nearest it."""
    return f"(min({c}[0], 9 - {c}[0]) + min({c}[1], 9 - {c}[1]))"


def _blocked(i: str, j: str) -> str:
    """The cell (i, j) is off the grid or an obstacle."""
    return f"(not (0 <= {i} <= 9 and 0 <= {j} <= 9) or is_obstacle(({i}, {j})))"


def _free_count(c: str) -> str:
    """How many of the four cells next to ``c`` are inside the grid and free (no loop)."""
    return f"((1 if {c}[0] > 0 and not is_obstacle(({c}[0] - 1, {c}[1])) else 0) + (1 if {c}[0] " \
           f"< 9 and not is_obstacle(({c}[0] + 1, {c}[1])) else 0) + (1 if {c}[1] > 0 and not " \
           f"is_obstacle(({c}[0], {c}[1] - 1)) else 0) + (1 if {c}[1] < 9 and not " \
           f"is_obstacle(({c}[0], {c}[1] + 1)) else 0))"


def _obstacle_count(c: str) -> str:
    """How many of the four cells next to ``c`` inside the grid are obstacles (no loop)."""
    return f"((1 if {c}[0] > 0 and is_obstacle(({c}[0] - 1, {c}[1])) else 0) + (1 if {c}[0] < " \
           f"9 and is_obstacle(({c}[0] + 1, {c}[1])) else 0) + (1 if {c}[1] > 0 and " \
           f"is_obstacle(({c}[0], {c}[1] - 1)) else 0) + (1 if {c}[1] < 9 and " \
           f"is_obstacle(({c}[0], {c}[1] + 1)) else 0))"


def _obstacles_next(c: str) -> str:
    return f"len([x for x in neighbours({c}) if is_obstacle(x)])"


def _lone(c: str, k: str) -> str:
    """Every cell next to ``c`` inside the grid is among the cells ``k`` and free (no loop)."""
    return " and ".join(f"({edge} or (({x}, {y}) in {k} and not is_obstacle(({x}, {y}))))"
                        for edge, x, y in ((f"{c}[0] == 0", f"{c}[0] - 1", f"{c}[1]"),
                                           (f"{c}[0] == 9", f"{c}[0] + 1", f"{c}[1]"),
                                           (f"{c}[1] == 0", f"{c}[0]", f"{c}[1] - 1"),
                                           (f"{c}[1] == 9", f"{c}[0]", f"{c}[1] + 1")))


def _border_looks(senses: str) -> str:
    """How many different cells of the grid's border are among the cells ``senses``."""
    return f"len([c for c in reachable_cells() if c in {senses} and (c[0] % 9 == 0 or " \
           f"c[1] % 9 == 0)])"


_NEAREST = f"min([{_d('g')} for g in reachable_goals()])"
# retrace_last_three: the moves retraced, from the number of moves in all (6 or more: three;
# fewer: half of them)
_BACK = "(3 if len(moves()) >= 6 else len(moves()) // 2)"

TASKS = [
    _task("goal_nearest_corner", 2, check_goal_nearest_corner,
          "Explore, moving and sensing, until there is nothing more to find. Then go with one "
          "move onto the goal you can reach that lies nearest to a corner of the grid -- the "
          "corners are (0, 0), (0, 9), (9, 0) and (9, 9), and a goal's distance is to whichever "
          "corner is nearest to it, counting steps along rows and columns (any of them if "
          "several goals are equally near). If you are standing on such a goal, just stop.",
          f"explored_all() and {_NEW_LAST} and all(is_goal({_F}) and {_F} in reachable_goals() "
          f"and {_cd(_F)} == T and ({_STAY} or ({_MOVE} and not (is_goal({_L}) and {_cd(_L)} "
          f"== T))) for T in [min([{_cd('g')} for g in reachable_goals()])])"),
    _task("lone_obstacle_known", 1, check_lone_obstacle_known,
          "Explore, moving and sensing, until you know of a lone obstacle: one with no other "
          "obstacle right next to it (left, right, above or below), where you know what every "
          "one of those cells inside the grid holds. Stop right after the sense that first "
          "lets you know of such an obstacle. If there is nothing more to find before that, "
          "stop right after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and [any(is_obstacle(c) and {_lone('c', 'K')} for c "
          f"in K) for K in [known_before_last(), known_cells()]] in [[False, True]] + "
          f"([[False, False]] if explored_all() and {_FRESH} else [])"),
    _task("crowded_goals_first_tour", 3, check_crowded_goals_first_tour,
          "Explore, moving and sensing, until there is nothing more to find (a sense more after "
          "that changes nothing and does no harm). Then, without sensing again, visit every "
          "goal you can reach, one move onto each, in order of how many obstacles are right "
          "next to it (the grid's edge does not count): the goal with the most first, goals "
          "with equally many in either order. Then go straight back to your starting cell with "
          "one more move and stop. A goal you are standing on when the exploring ends still "
          "gets its move.",
          f"explored_all() and moves()[-1:] == [{_S}] and primitives()[len(primitives()) - "
          f"len(reachable_goals()) - 2:] == ['sense'] + ['navigate'] * (len(reachable_goals()) "
          f"+ 1) and sorted(moves()[-len(reachable_goals()) - 1:-1]) == reachable_goals() and "
          f"all({_obstacles_next('moves()[k - len(reachable_goals()) - 1]')} >= "
          f"{_obstacles_next('moves()[k - len(reachable_goals())]')} for k in "
          f"{_K3}[:len(reachable_goals()) - 1])"),
    _task("down_walk_odd_home", 2, check_down_walk_odd_home,
          "Sense where you start, then walk down (j - 1), one cell at a time, sensing after "
          "every move, while the next cell below is inside the grid and free. If that walk made "
          "an odd number of moves, go straight back to your starting cell with one move and "
          "stop there; if it made an even number (no move at all counts as even), stop where "
          "the walk ended.",
          "any(W >= 0 and primitives() == ['sense'] + ['navigate', 'sense'] * W + ['navigate'] * "
          f"(W % 2) and moves()[:W] == [(i, j - k) for k in {_K10}[1:W + 1]] and "
          f"{_blocked('i', 'j - W - 1')} and (W % 2 == 0 or moves()[-1] == (i, j)) for W, i, j "
          f"in [(len(sensed()) - 1, {_S0}, {_S1})])"),
    _task("goal_dead_end_backout", 2, check_goal_dead_end_backout,
          "Search for a goal. As soon as a sense shows you one, go onto it with one move and "
          "sense there (onto any of them if that sense showed several; if you are already "
          "standing on one, stay there, you have just sensed on it). Then, if that goal is a "
          "dead end -- an obstacle or the grid's edge on three of its four sides -- step off it "
          "with one move onto its only free neighbour and stop there; otherwise stop on the "
          "goal.",
          f"goal_found() and any(is_goal(G) and (E == 1) == ({_free_count('G')} == 1) and "
          f"primitives()[len(primitives()) - 1 - E:] == ['sense'] + ['navigate'] * E and (E == "
          f"0 or ({_F} in neighbours(G) and not is_obstacle({_F}))) and (steps_after_goal() == "
          f"E or (steps_after_goal() == E + 2 and primitives()[len(primitives()) - 3 - E:len("
          f"primitives()) - 1 - E] == ['sense', 'navigate'] and moves()[len(moves()) - 1 - E] "
          f"== G and G in neighbours(sensed()[-2]) and not is_goal(sensed()[-2]))) for E, G in "
          f"[(0, {_L}), (1, {_L})])"),
    _task("retrace_last_three", 2, check_retrace_last_three,
          "Explore, moving and sensing, until there is nothing more to find. Then, without "
          "sensing again, go back along your last three moves, one move for each: first onto "
          "the cell you stood on before your last move, then onto the one you stood on before "
          "that, then onto the one before that (your starting cell is the first cell you stood "
          "on). If you had made fewer than three moves, go back along all of them, ending on "
          "your starting cell.",
          f"explored_all() and {_NEW_LAST} and all(R == min(3, len(moves()) - R) and "
          f"primitives()[len(primitives()) - R - 1:] == ['sense'] + ['navigate'] * R and "
          f"moves()[len(moves()) - R:] == [([{_S}] + moves())[len(moves()) - R - 1 - k] for k "
          f"in {_K3}[:R]] for R in [{_BACK}])"),
    _task("three_border_looks", 1, check_three_border_looks,
          "Explore, moving and sensing, until you have sensed from three different cells on "
          "the grid's border -- the cells with i or j equal to 0 or 9; your starting cell "
          "counts if it lies there. Stop right after the sense taken on the third such cell. If "
          "there is nothing more to find before that, stop right after the sense that leaves "
          "nothing more to find.",
          f"primitives()[-1:] == ['sense'] and {_border_looks(_E)} < 3 and "
          f"({_border_looks('sensed()')} >= 3 or explored_all()) and not (explored_all() and "
          f"not {_FRESH})"),
    _task("calmest_in_start_row", 2, check_calmest_in_start_row,
          "Explore, moving and sensing, until there is nothing more to find (a sense more after "
          "that changes nothing and does no harm). Then, of the cells you can reach in your "
          "starting row (those with the same j as your starting cell, your starting cell "
          "included), end on one with the fewest obstacles right next to it (the grid's edge "
          "does not count; any of them if several have equally few): go onto it with one move "
          "and stop, or, if you are already standing on one, you may also just stop.",
          f"explored_all() and ({_STAY} or {_MOVE}) and {_F} in reachable_cells() and {_F}[1] "
          f"== {_S1} and {_obstacle_count(_F)} == min([{_obstacles_next('c')} for c in "
          f"reachable_cells() if c[1] == {_S1}])"),
    _task("dead_ends_outnumber_home", 3, check_dead_ends_outnumber_home,
          "Explore, moving and sensing, until there is nothing more to find (a sense more after "
          "that changes nothing and does no harm). Then count the dead ends you can reach -- "
          "free cells with an obstacle or the grid's edge on three of their four sides; your "
          "starting cell counts if it is one -- and the goals you can reach. If there are more "
          "than twice as many dead ends as goals, go straight back to your starting cell with "
          "one move and stop "
          "(if you are there, just stop). Otherwise go with one move onto the goal nearest to "
          "your starting cell, counting steps along rows and columns and ignoring obstacles "
          "(any of them if several are equally near), and stop (if you are standing on one, "
          "just stop).",
          f"explored_all() and ({_HOME_AFTER} if len([c for c in reachable_cells() if "
          f"len([x for x in neighbours(c) if not is_obstacle(x)]) == 1]) > 2 * "
          f"len(reachable_goals()) else (is_goal({_F}) and {_F} in reachable_goals() and "
          f"{_d(_F)} == {_NEAREST} and ({_STAY} or ({_MOVE} and not (is_goal({_L}) and "
          f"{_d(_L)} == {_d(_F)})))))"),
    _task("left_up_corner_return", 2, check_left_up_corner_return,
          "Sense where you start, then walk left (i - 1), one cell at a time, sensing after "
          "every move, while the next cell to the left is inside the grid and free. From where "
          "that walk ended, walk up (j + 1) the same way while the next cell above is inside "
          "the grid and free. If the walk up made any move, go straight back with one move to "
          "the cell where you turned (where the walk left ended) and stop there; otherwise stop "
          "where you are.",
          f"any(A <= W and primitives() == ['sense'] + ['navigate', 'sense'] * W + ['navigate'] "
          f"* (1 if W > A else 0) and moves()[:W] == [(i - min(k, A), j + max(0, k - A)) for k "
          f"in {_K19}[1:W + 1]] and {_blocked('i - A - 1', 'j')} and "
          f"{_blocked('i - A', 'j + W - A + 1')} and (W == A or moves()[-1] == (i - A, j)) for "
          f"A in {_K10} for W, i, j in [(len(sensed()) - 1, {_S0}, {_S1})])"),
    _task("search_moves_vs_obstacles", 2, check_search_moves_vs_obstacles,
          "Search for a goal, moving and sensing. When a sense first shows you one, compare the "
          "moves you have made so far with the obstacles you know of: if you have made more "
          "moves than you know obstacles, go straight back to your starting cell with one move "
          "and stop (if you are there, just stop); otherwise go onto the goal with one move and "
          "stop (onto any of them if that sense showed several; if you are standing on one, "
          "just stop).",
          f"goal_found() and {_ONLY_MOVES} and (({_HOME}) if len(moves()) - "
          f"len(moves_after_goal()) > len(known_obstacles()) else ({_ONTO_GOAL}))"),
    _task("dead_end_look_home", 2, check_dead_end_look_home,
          "Explore, moving and sensing, until you sense from a dead end other than your "
          "starting cell -- a cell with an obstacle or the grid's edge on three of its four "
          "sides. Then go straight back to your starting cell with one move and stop. If there "
          "is nothing more to find before that, go straight back to your starting cell with one "
          "move once there is nothing more to find, and stop (if you are there, just stop).",
          f"{_HOME_AFTER} and ({_NEW_LAST} or not explored_all()) and [len([x for x in "
          f"neighbours(s) if not is_obstacle(x)]) == 1 and s != {_S} for s in sensed()] in "
          f"[[False] * (len(sensed()) - 1) + [True]] + ([[False] * len(sensed())] if "
          f"explored_all() else [])"),
    _task("spill_allowance_net", 2, check_spill_allowance_net,
          f"Scoop one to five times, then stop, with a net of at least {NET_LEAST}: the grams "
          f"of grains in the receiver, less the grams spilled outside the containers beyond a "
          f"free allowance of {ALLOWANCE} g (spilling up to {ALLOWANCE} g costs nothing).",
          f"scoops() >= 1 and scoops() <= 5 and delivered() - (spilled() - {ALLOWANCE} if "
          f"spilled() > {ALLOWANCE} else 0) >= {NET_LEAST}", SCOOP),
    _task("spill_times_scoops", 2, check_spill_times_scoops,
          f"Scoop one to four times, then stop, leaving at least {PRODUCT_LEAST} g of grains in "
          f"the receiver, where the grams spilled outside the containers, multiplied by the "
          f"number of scoops you made, come to no more than {PRODUCT_MOST}.",
          f"scoops() >= 1 and scoops() <= 4 and delivered() >= {PRODUCT_LEAST} and spilled() * "
          f"scoops() <= {PRODUCT_MOST}", SCOOP),
]
