"""Held-out tasks, fourteenth set: written before the next change of the synthesizer, run once
after it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout14/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (exploring that stops once the cells known
span six columns; exploring that stops at the first sense taken on a cell squeezed between two
obstacles, along its row or its column; exploring that stops once the senses taken outnumber the
obstacles known; exploring that stops at the second of two senses in a row that show no obstacle;
exploring that stops at the first sense that shows an empty cell, an obstacle and a goal at once; a
walk up to the wall above the start, then along its underside to the right; once a goal is in view,
onto the empty cell next to it that is nearest the start; after exploring, to whichever is nearer,
the start or the nearest goal; a search in rounds of three looks with a trip home after each round;
a search that, once a goal is in view, takes as many senses again before going onto a goal;
exploring that stops at the fifth sense taken farther from the start than every earlier one; a
search that always goes to the nearest known free cell never stood in) and two scooping tasks (one
to five scoops that score at least 30 points, a point a gram delivered, less a point a gram spilled
and 10 a scoop; one to four scoops that deliver at least 40 g and at least 12 g times the square of
the number of scoops). Each has a reference behavior (``references/``), a ground-truth ``check`` and
a faithful ``promise`` over the env's outcome helpers, so that the search can be measured apart from
the model. They were written on 2026-12-07 blind: without reading the search's code and without
running the synthesizer on them; the first run of the search on them is the evaluation, reported
beside the development figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal) and *empty* when it holds neither an obstacle nor a goal; *known* when the agent's
label of it is not 'unexplored'; *reachable* when it lies in the start cell's free component;
*nothing more to find* when every reachable cell and every cell next to one is known; *up* is j + 1,
*down* j - 1, *right* i + 1, *left* i - 1; a *column* is the cells of one i, and the known cells
*span* the columns from the smallest i of a known cell to the largest, both counted; a sense labels
its cell and the four around it (it *shows* them; a goal *comes into view* with the first sense that
shows it); the cells *next to* a cell are its four neighbours inside the grid, and the obstacles
next to it are those among them (the grid's edge does not count); a sense *shows no obstacle* when
no cell next to its cell holds one (its own cell never does); a cell is *squeezed* when the two
cells beside it along its row, or the two along its column, are inside the grid and obstacles; two
senses are *in a row* when no other sense comes between them (a move may); a cell *stood in* is the
start or one a move ended in; a *round* is three moves, each followed by a sense, and then a move
onto the start; a sense sets a *record* when its cell is farther from the start than the cell of
every earlier sense (the first sense sets none); the *wall above* is the obstacle that ends the walk
up, and the walk along its underside goes right while the cell above the agent is an obstacle and
the cell to its right is free; the *distance* of two cells, and *nearest*, count steps along rows
and columns (|di| + |dj|), obstacles ignored. The start cell always has a free neighbour (a goal is
reachable from it and it holds none); the references only move onto cells they know, so none ever
stood on a goal when it first came into view. The promises' language allows three comprehension
loops in one expression, all of them counted together, and 400 syntax nodes: where a promise needs
indices it writes them out (obstacle_rate_stop's, clear_streak's, all_kinds_look's and
outward_records' promises read up to 100 senses, nearest_new_cell_search's up to 80, where the
references never made more than 61 and 66); where a rule must hold at the last sense and at no
earlier one, the promise counts in one sum the senses where it held, the last once and each earlier
one twice, and compares that one number (clear_streak, all_kinds_look; outward_records counts its
records twice and the last sense once more if it set one); the span of the known map is read from
the first and the last known cell, since lists of cells are in flat-index order (i * 10 + j); where
senses and moves alternate, each sense is where the move before it ended, as the navigate
certificates say (double_the_search, nearest_new_cell_search); a nearest cell is read as the first
of the candidates sorted by distance and by a tag that puts the cell the agent stands in, then the
cell it went to, first among equals (homeward_side_of_goal, nearest_new_cell_search). The scooping
checks weigh the grains at the end, as ``delivered()`` and ``spilled()`` do: those in the receiver,
and those outside the receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all. On those episodes the tasks'
branches came up: the known cells spanning six columns after 4 to 34 senses (within 5 senses 103,
after 20 or more 94), nothing more to find first 3; a squeezed cell sensed from 298 times (along its
row 135, along its column 163; the start 40), after up to 42 senses, nothing more to find first 2;
the senses outnumbering the obstacles after 1 to 17 senses (at the first, with no obstacle next to
the start, 86; at the second 53, the third 39, later 122, nothing more to find first in 2 of them);
two clear looks in a row 287 times, after up to 61 senses (under 10: 112), nothing more to find
first 13; a look of all three kinds 297 times (after passing over earlier senses that showed a goal
113, taken on a goal 65), nothing more to find first 3; the walk up of 0 to 8 moves 106, 57, 49, 42,
17, 20, 4, 4 and 1 times, ended by the top edge 89 and by an obstacle 211, the walk right of 0 to 4
moves 153, 127, 18, 1 and 1 times; the empty cell nearest the start next to the goal the agent's own
cell 276 times and another one 24 (one such cell known 227, two 73; the goal in view from the start
41; two goals in view 6); after exploring, to a goal 215 and to the start 85 times (equally near 13,
standing there already 17; 1, 2 and 3 reachable goals 21, 61 and 218 times); 0 to 17 rounds before
the goal came into view (none 99, in view from the start 41; one 43, two 22, three to five 75, six
or more 61), up to 53 senses; the first goal sense the 1st to the 11th 41, 27, 18, 13, 13, 12, 18,
11, 1, 10 and 10 times and later 126, the count doubled 266 times and nothing more to find first 34,
ending on a goal it stood on 32; the fifth record, or nothing more to find first (4 times, with 2 to
4 records), after 5 to 20 senses (the sixth 149, the seventh to ninth 99, later 51); the nearest new
cell search seeing a goal from the start 41 times and after up to 66 senses (under 10: 155, 40 or
more 13). Faithfulness on behaviors that do not do the tasks: every grid promise was judged against
73 near misses of the references (thresholds and counts one off, other directions, rules or places
to go, the grid's edge taken for an obstacle, a condition dropped or changed, one sense late, a
missing or extra sense or move, cells not yet known taken for free) and 13 other ways of doing the
tasks (another explorer, another choice among ties or goals) on episodes 0-99 of seeds 0 and 1
(17,189 judged episodes for each promise, 11 lost where a near miss moved onto an unknown obstacle:
the near misses kept their own task's promise on 4,841 of their 14,589 and the other ways on all
their 2,600; three near misses did their task on every one of these episodes and kept its promise
there: all_kinds_look's goal and obstacle without the empty cell, the agent's own cell being one;
map_six_wide's count of distinct columns, the known columns having no gap; homeward_side_of_goal's
free rather than empty cells, no goal next to a goal being nearer the start), against the 12
references of this set, the 12 grid references of heldout13 and the 158 of the development and
earlier held-out sets on episodes 0-49 of seed 0 (9,100 judged episodes for each promise), and
against 3 trivial behaviors (stop at once, judged on the reset; sense once; navigate onto the cell
it stands in) on episodes 0-99 of seeds 0 and 1: on every judged episode the promise's verdict
equalled the check's. Keep rates of the trivial behaviors: stopping at once and navigating onto the
cell it stands in keep no promise on any episode; sensing once keeps none but obstacle_rate_stop's
(59 of 200: no obstacle next to the start), follow_wall_above's (29: the cell above the start an
obstacle and the cell to its right blocked, or the start in the top row), homeward_side_of_goal's
(29: a goal next to the start, which is then the nearest empty cell), squeezed_stop's (21: the start
squeezed) and all_kinds_look's (16: the first look shows all three kinds), where the task asks for
the one sense. The logic of the held-out folder tests (tests/test_synthesis_eval.py's
satisfiable-faithful-checkable test, and tests/test_certified.py's readings of every promise and its
bank test) pointed at this folder passed. The scooping references (four and two scoops from the
default sensing pose) were run on episodes 0-19 of seed 0 only (3 to 9 s an episode) and kept their
promises and did their tasks on all 20: four scoops delivered 101.8 to 185.5 g and spilled 0.0 to
31.7 g, for 41.4 to 131.9 points (30 needed: margin 11.4); two scoops delivered 58.8 to 97.3 g (48 g
needed: margin 10.8). Other counts on episodes 0-9 (both promises judged, the checks agreeing on
every one): one scoop (33.9 to 54.3 g) kept scoop_points' promise on 5 and rising_bar's on 7; two
scoops kept scoop_points' on 8; three (88.2 to 133.5 g) kept scoop_points' on all 10 and
rising_bar's on 5; four and five kept scoop_points' on all 10 and rising_bar's on none."""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (ALTERNATE as _ALTERNATE, FINAL as _F, FRESH as _FRESH,
                                        LAST_SENSE as _L, MOVE as _MOVE, NEW_LAST as _NEW_LAST,
                                        ONTO_GOAL as _ONTO_GOAL_SHORT, START as _S, START_I as _S0,
                                        START_J as _S1, STAY as _STAY, cell, distance,
                                        distance_text, exhausted, first_goal_sense, first_reaching,
                                        free_cell, goals_shown, grams_in_receiver, grams_spilled,
                                        held_out_task, indices, known_after, label_sensed,
                                        neighbours, obstacles_beside, on_grid, onto, onto_goal_seen,
                                        reachable, same_steps, scoops, sensed_cells, step_by,
                                        steps_of)
from vlb_gym.envs.grid_explore.types import EMPTY, GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, UP = (1, 0), (0, 1)
WIDE = 6  # columns the known map must span (map_six_wide)
RECORDS = 5  # records of distance from the start that end outward_records
ROUND = 3  # senses of a round of three_look_rounds


def _unknown(state):
    """A boolean grid of the cells' knowledge before any step: nothing known."""
    return state.truth != state.truth


def _stops_at_sense(state, result, stop) -> str | None:
    """Exploring stops with the first sense after which ``stop(step, known)`` holds or nothing
    more is to be found (``stop`` sees every sense in turn, with the cells known after it)."""
    steps = steps_of(result)
    known = _unknown(state)
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] != "sense":
            continue
        if stop(step[1], known) or exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return "stopped before the rule's sense and before everything was known"


def _span(known) -> int:
    """How many columns the known cells span, from the leftmost to the rightmost (0: none)."""
    columns = known.any(axis=1).nonzero()[0]
    return int(columns[-1] - columns[0] + 1) if len(columns) else 0


def _squeezed(state, c) -> bool:
    """``c`` has obstacles on both sides along its row, or along its column (the grid's edge is
    no obstacle)."""
    i, j = c
    return any(on_grid(state, a) and on_grid(state, b) and state.truth[a] == OBSTACLE
               and state.truth[b] == OBSTACLE
               for a, b in (((i - 1, j), (i + 1, j)), ((i, j - 1), (i, j + 1))))


# --- checks -------------------------------------------------------------------------------

def check_map_six_wide(state, result):
    """Exploring stops with the first sense after which the known cells span WIDE columns, or
    nothing more is to be found."""
    index = first_reaching(state, result,
                           lambda known: _span(known) >= WIDE or exhausted(state, known))
    if index is None:
        return f"the known cells never spanned {WIDE} columns and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_squeezed_stop(state, result):
    """Exploring stops with the first sense taken on a cell with obstacles on both sides along
    its row or its column, or with the sense after which nothing more is to be found."""
    return _stops_at_sense(state, result, lambda here, known: _squeezed(state, here))


def check_obstacle_rate_stop(state, result):
    """Exploring stops with the first sense after which the senses taken outnumber the obstacles
    known, or nothing more is to be found."""
    counted = []

    def stop(here, known):
        counted.append(here)
        return len(counted) > int((known & (state.truth == OBSTACLE)).sum())
    return _stops_at_sense(state, result, stop)


def check_clear_streak(state, result):
    """Exploring stops with the second of two senses in a row that show no obstacle, or with the
    sense after which nothing more is to be found."""
    last = []  # whether each sense so far showed no obstacle

    def stop(here, known):
        last.append(obstacles_beside(state, here) == 0)
        return last[-2:] == [True, True]
    return _stops_at_sense(state, result, stop)


def check_all_kinds_look(state, result):
    """Exploring stops with the first sense that shows an empty cell, an obstacle and a goal,
    or with the sense after which nothing more is to be found."""
    return _stops_at_sense(state, result, lambda here, known: {
        int(state.truth[c]) for c in sensed_cells(state, here)} == {EMPTY, OBSTACLE, GOAL})


def check_follow_wall_above(state, result):
    """Sense; walk up, each move followed by a sense, while the cell above is inside the grid
    and free; if an obstacle (not the edge) stopped it, walk right the same way while the cell
    above the agent is an obstacle and the cell to its right inside the grid and free."""
    here = state.start_cell
    plan = [("sense", here)]
    while free_cell(state, step_by(here, UP)):
        here = step_by(here, UP)
        plan += [("navigate", here), ("sense", here)]
    if on_grid(state, step_by(here, UP)):
        while state.truth[step_by(here, UP)] == OBSTACLE and free_cell(state, step_by(here,
                                                                                     RIGHT)):
            here = step_by(here, RIGHT)
            plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_homeward_side_of_goal(state, result):
    """After the sense that first shows a goal: one move onto an empty cell next to a goal it
    showed, known by then, that is as near the start as any such cell next to that goal
    (nothing if the agent stands on one; nothing if that goal has none)."""
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    steps, home = steps_of(result), state.start_cell
    here, rest = steps[index][1], steps[index + 1:]
    known = known_after(state, result.steps[:index + 1])
    why = None
    for goal in goals_shown(state, here):
        near = [n for n in neighbours(state, goal) if known[n] and state.truth[n] == EMPTY]
        best = min((distance(n, home) for n in near), default=None)
        targets = [n for n in near if distance(n, home) == best] or [here]
        why = onto(rest, here, targets, "after the goal came into view")
        if why is None:
            return None
    return why


def check_nearer_of_home_and_goal(state, result):
    """Nothing more to find at the end; after the last sense, one move onto the start or onto a
    goal nearest the agent, whichever is nearer (the start if equally near), or nothing if the
    agent stands on it."""
    if not exhausted(state):
        return "stopped before everything was known"
    steps, home = steps_of(result), state.start_cell
    senses = [k for k, (kind, _) in enumerate(steps) if kind == "sense"]
    if not senses:
        return "never sensed"
    here = steps[senses[-1]][1]
    goals = [cell(c) for c in zip(*(reachable(state) & (state.truth == GOAL)).nonzero())]
    near = min(distance(here, g) for g in goals)
    targets = [g for g in goals if distance(here, g) == near] \
        if near < distance(here, home) else [home]
    return onto(steps[senses[-1] + 1:], here, targets, "after the last sense")


def check_three_look_rounds(state, result):
    """A sense at the start, then rounds of ROUND moves each followed by a sense and a move onto
    the start, up to the sense that first shows a goal; then one move onto a goal it showed
    (nothing if the agent stands on one)."""
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    steps, home = steps_of(result), state.start_cell
    block = ["navigate", "sense"] * ROUND + ["navigate"]
    for t, (kind, c) in enumerate(steps[:index + 1]):
        want = "sense" if t == 0 else block[(t - 1) % len(block)]
        if kind != want:
            return f"step {t + 1} was a {kind}, not a {want}"
        if t > 0 and (t - 1) % len(block) == len(block) - 1 and c != home:
            return f"step {t + 1} went to {c}, not back to the start after a round"
    return onto_goal_seen(state, steps, index)


def check_double_the_search(state, result):
    """A sense first, then a move and a sense in turn; exploring stops with the sense that
    doubles the count of senses up to the one that first showed a goal, or with the sense after
    which nothing more is to be found if that comes first; then one move onto a known goal
    (nothing if the agent stands on a goal)."""
    steps = steps_of(result)
    known = _unknown(state)
    senses, need = 0, None
    for index, (kind, c) in enumerate(steps):
        if kind != ("sense" if index % 2 == 0 else "navigate"):
            return f"step {index + 1} was a {kind}: a sense first and after every move, and " \
                   "no other sense"
        if kind == "navigate":
            continue
        senses += 1
        label_sensed(state, known, (kind, c))
        if need is None and goals_shown(state, c):
            need = 2 * senses
        if need is not None and (senses >= need or exhausted(state, known)):
            goals = [cell(g) for g in zip(*(known & (state.truth == GOAL)).nonzero())]
            return onto(steps[index + 1:], c, goals, "after the last sense")
    return "stopped before the search was doubled or everything was known"


def check_outward_records(state, result):
    """Exploring stops with the RECORDS-th sense taken farther from the start than every earlier
    sense (the first sense is no record), or with the sense after which nothing more is to be
    found."""
    home, best, records = state.start_cell, [], []

    def stop(here, known):
        d = distance(here, home)
        if best and d > max(best):
            records.append(here)
        best.append(d)
        return len(records) == RECORDS
    return _stops_at_sense(state, result, stop)


def check_nearest_new_cell_search(state, result):
    """A sense at the start, then a move and a sense in turn up to the sense that first shows a
    goal, each move onto a known free cell never stood in, as near the agent as any such cell;
    then one move onto a goal that sense showed (nothing if the agent stands on one)."""
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    steps = steps_of(result)
    known, stood = _unknown(state), [state.start_cell]
    for t, (kind, c) in enumerate(steps[:index + 1]):
        if kind != ("sense" if t % 2 == 0 else "navigate"):
            return f"step {t + 1} was a {kind}: a sense first and after every move, and no " \
                   "other sense"
        if kind == "sense":
            label_sensed(state, known, (kind, c))
            continue
        here = stood[-1]
        new = [cell(x) for x in zip(*(known & (state.truth != OBSTACLE)).nonzero())
               if cell(x) not in stood]
        near = min((distance(here, x) for x in new), default=None)
        if c not in new or distance(here, c) != near:
            return f"step {t + 1} went to {c}, not to one of the nearest known free cells " \
                   f"never stood in {[x for x in new if distance(here, x) == near][:6]}"
        stood.append(c)
    return onto_goal_seen(state, steps, index)


POINTS, POINT_SPILL, POINT_SCOOP = 30, 1, 10  # points needed; lost a gram spilled; lost a scoop
BAR, BAR_FLOOR = 12, 40  # grams a squared scoop; grams delivered in any case


def check_scoop_points(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    points = mass - POINT_SPILL * spilled - POINT_SCOOP * n  # POINT_SPILL: 1, as the promise reads
    return None if points >= POINTS else \
        f"{points:.1f} points: {mass:.1f} g delivered, {spilled:.1f} g spilled, {n} scoops"


def check_rising_bar(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass = grams_in_receiver(state)
    return None if mass >= BAR_FLOOR and mass >= BAR * n * n else \
        f"{mass:.1f} g delivered after {n} scoops"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
# nothing more was to be found before the last sense (it labelled something, or it is not so now)
_NOT_BEFORE = f"({_FRESH} or not explored_all())"
# a list's value allowed where the last sense is the rule's (1) or, with nothing more to find
# after it and not before, none was (0)
_RULE_OR_ALL = f"([0, 1] if explored_all() and {_FRESH} else [1] if not explored_all() else [])"
# after the sense that first shows a goal: nothing on a goal, else one move onto one it showed
_ONTO_GOAL = f"((steps_after_goal() == 0 and is_goal({_L})) or (steps_after_goal() == 1 and " \
             f"primitives()[-1] == 'navigate' and not is_goal({_L}) and is_goal({_F}) and " \
             f"{_F} in neighbours({_L})))"
# a sense after every move and nowhere else: the steps up to the last sense
_TURNS = "primitives()[:2 * len(sensed()) - 1] == ['sense'] + ['navigate', 'sense'] * " \
         "(len(sensed()) - 1) and sensed()[1:] == moves()[:len(sensed()) - 1]"
_K10, _K20, _K80, _K100 = indices(10), indices(20), indices(80), indices(100)
_NEAR_C = distance_text("sensed()[k]", "c")  # from where the sense k was taken to c


def _d(a: str, b: str = _S) -> str:
    return distance_text(a, b)


def _squeezed_text(c: str) -> str:
    """The cell ``c`` has obstacles on both sides along its row or its column."""
    return f"((0 < {c}[0] < 9 and is_obstacle(({c}[0] - 1, {c}[1])) and is_obstacle(({c}[0] + " \
           f"1, {c}[1]))) or (0 < {c}[1] < 9 and is_obstacle(({c}[0], {c}[1] - 1)) and " \
           f"is_obstacle(({c}[0], {c}[1] + 1))))"


def _clear(k: str) -> str:
    """The sense ``k`` (an index of sensed()) shows no obstacle."""
    return f"not any(is_obstacle(x) for x in neighbours(sensed()[{k}]))"


# the sense k's five cells as a number: 1 an obstacle, 10 an empty cell, 100 a goal; T all three
_KINDS = "sum([1 if is_obstacle(x) else 100 if is_goal(x) else 10 for x in [sensed()[k]] + " \
         "neighbours(sensed()[k])])"
_ALL_KINDS = "T % 10 > 0 and T // 10 % 10 > 0 and T >= 100"
# the first sense that shows a goal (an index of sensed(), with _TURNS)
_F_GOAL = "((len(primitives()) - 1 - steps_after_goal()) // 2)"
_ROUNDS = "max(0, (len(sensed()) - 2) // 3)"  # rounds completed (home trips) before the goal sense
# the values of _RECORDS allowed when nothing more was to be found after the last sense and not
# before: r records, L = 1 if the last sense set one, r - L < RECORDS
_RECORDS_ALL = str(sorted({2 * r + last for r in range(RECORDS + 1) for last in (0, 1)
                           if r - last <= RECORDS - 1 and r >= last}))
# the senses that set a record of distance from the start, 2 each and 3 for the last sense
_RECORDS = f"sum([(3 if k == len(sensed()) - 1 else 2) for k in {_K100}[1:len(sensed())] if " \
           f"all({_d('sensed()[k]')} > {_d('s')} for s in sensed()[:k])])"

TASKS = [
    _task("map_six_wide", 1, check_map_six_wide,
          f"Explore, moving and sensing, until the cells you know span at least {WIDE} "
          f"columns: counting from the leftmost column (smallest i) in which you know some cell "
          f"to the rightmost one, both included, there must be {WIDE} or more. Stop right after "
          f"the sense that achieves this. If there is nothing more to find before that, stop "
          f"right after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and (len(known_before_last()) == 0 or "
          f"known_before_last()[-1][0] - known_before_last()[0][0] < {WIDE - 1}) and "
          f"(known_cells()[-1][0] - known_cells()[0][0] >= {WIDE - 1} or (explored_all() and "
          f"{_FRESH}))"),
    _task("squeezed_stop", 1, check_squeezed_stop,
          "Explore, moving and sensing, until you sense from a cell squeezed between two "
          "obstacles: one with an obstacle on both of its sides along its row (left and right) "
          "or along its column (above and below); the grid's edge does not count as an "
          "obstacle. Stop right after the first sense taken on such a cell (your starting cell "
          "counts). If there is nothing more to find before that, stop right after the sense "
          "that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and not any({_squeezed_text('c')} for c in "
          f"sensed()[:-1]) and (({_squeezed_text(_L)} and {_NOT_BEFORE}) or (explored_all() and "
          f"{_FRESH}))"),
    _task("obstacle_rate_stop", 2, check_obstacle_rate_stop,
          "Explore, moving and sensing, for as long as your senses keep turning up obstacles: "
          "stop right after the first sense after which the senses you have taken outnumber "
          "the obstacles you know (count every sense, your first one included, and every "
          "different obstacle any of them showed you). If there is nothing more to find before "
          "that, stop right after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and all(len([o for o in known_obstacles() if any(o in "
          f"neighbours(s) for s in sensed()[:k + 1])]) > k for k in {_K100}[:len(sensed()) - "
          f"1]) and ((len(sensed()) > len(known_obstacles()) and {_NOT_BEFORE}) or "
          f"(explored_all() and {_FRESH}))"),
    _task("clear_streak", 2, check_clear_streak,
          "Explore, moving and sensing, and stop right after the second of two senses in a row "
          "that both show you no obstacle at all (none on the cells right next to the cell you "
          "sense from): two senses one right after the other, with no other sense between "
          "them. If there is nothing more to find before that, stop right after the sense that "
          "leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and sum([(2 if k < len(sensed()) - 2 else 1) for k "
          f"in {_K100}[:len(sensed()) - 1] if {_clear('k')} and {_clear('k + 1')}]) in "
          f"{_RULE_OR_ALL}"),
    _task("all_kinds_look", 2, check_all_kinds_look,
          "Explore, moving and sensing, until a single sense shows you all three kinds of cell "
          "at once: an empty cell, an obstacle and a goal, each on the cell you sense from or "
          "on a cell right next to it. Stop right after that sense. If there is nothing more to "
          "find before that, stop right after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and sum([(2 if k < len(sensed()) - 1 else 1) for k "
          f"in {_K100}[:len(sensed())] for T in [{_KINDS}] if {_ALL_KINDS}]) in {_RULE_OR_ALL}"),
    _task("follow_wall_above", 2, check_follow_wall_above,
          "Find the wall above you and follow it. Sense, then walk up (j + 1) one cell at a "
          "time, sensing after every move, while the cell above you is inside the grid and "
          "free. If what stops you is an obstacle (not the top edge of the grid), follow it to "
          "the right: step right (i + 1) one cell at a time, sensing after every move, as long "
          "as the cell above you is an obstacle and the cell to your right is inside the grid "
          "and free. Stop when you cannot go on.",
          f"any(primitives() == ['sense'] + ['navigate', 'sense'] * (U + R) and moves() == "
          f"[({_S0}, {_S1} + k) if k <= U else ({_S0} + k - U, {_S1} + U) for k in "
          f"{_K20}[1:U + R + 1] if k <= U or ({_S1} + U < 9 and is_obstacle(({_S0} + k - U - 1, "
          f"{_S1} + U + 1)))] "
          f"and ((R == 0 and {_S1} + U == 9) or ({_S1} + U < 9 and is_obstacle(({_S0}, {_S1} + "
          f"U + 1)) and ({_S0} + R == 9 or is_obstacle(({_S0} + R + 1, {_S1} + U)) or not "
          f"is_obstacle(({_S0} + R, {_S1} + U + 1))))) for U in {_K10}[:10 - {_S1}] for R in "
          f"{_K10}[:10 - {_S0}])"),
    _task("homeward_side_of_goal", 2, check_homeward_side_of_goal,
          "Explore until a sense shows you a goal. Do not step onto it: go with one move onto "
          "the empty cell right next to that goal that is nearest to your starting cell "
          "(counting steps along rows and columns, ignoring obstacles), choosing among the "
          "cells next to the goal that you know to be empty by then -- any of them if several "
          "are equally near. If you are standing on one of those nearest cells, or the goal has "
          "no such cell next to it, just stop. If that sense showed you several goals, do this "
          "for any one of them.",
          f"goal_found() and primitives()[len(primitives()) - steps_after_goal():] == ([] if "
          f"{_F} == {_L} else ['navigate']) and any(sorted([({_d('c')}, (0 if c == {_L} else 2) "
          f"+ (0 if c == {_F} else 1)) for c in neighbours(g) if not is_obstacle(c) and not "
          f"is_goal(c) and any(c == s or c in neighbours(s) for s in sensed())] + [(1000, "
          f"0)])[0] in [({_d(_F)}, 0 if {_F} == {_L} else 2), (1000, 0 if {_F} == {_L} else 4)] "
          f"for g in [{_L}] + neighbours({_L}) if is_goal(g))"),
    _task("nearer_of_home_and_goal", 2, check_nearer_of_home_and_goal,
          "Explore until there is nothing more to find. Then, from where you stand, go with one "
          "move to whichever is nearer: your starting cell, or the goal nearest to you "
          "(counting steps along rows and columns, ignoring obstacles; any nearest goal if "
          "several are equally near). Go to your starting cell if it is as near as that goal. "
          "If you are already standing there, just stop.",
          f"explored_all() and sensed()[-1:] != [] and all(({_STAY} and {_L} in T) or ({_MOVE} "
          f"and {_F} in T and {_L} not in T) for T in [[c for c in [{_S}] + reachable_goals() "
          f"if (c == {_S} or {_d(_L, 'c')} < {_d(_L)}) and all({_d(_L, 'c')} <= {_d(_L, 'h')} "
          f"for h in reachable_goals())]])"),
    _task("three_look_rounds", 2, check_three_look_rounds,
          "Search for a goal in rounds, coming home after each. Sense where you start. Then "
          "explore in rounds: in each round make three moves, each followed by a sense, and "
          "then go straight back to your starting cell with one move, without sensing there, "
          "before the next round begins. As soon as a sense shows you a goal, go onto it with "
          "one move and stop (onto any of them if that sense showed several; if you are "
          "standing on one, just stop).",
          f"goal_found() and {_ONTO_GOAL} and primitives()[:len(primitives()) - "
          f"steps_after_goal()] == ['sense'] + (['navigate', 'sense'] * 3 + ['navigate']) * "
          f"{_ROUNDS} + ['navigate', 'sense'] * (len(sensed()) - 1 - 3 * {_ROUNDS}) and "
          f"moves()[3::4][:{_ROUNDS}] == [{_S}] * {_ROUNDS}"),
    _task("double_the_search", 3, check_double_the_search,
          "Search for a goal, then look around for as long again before you go to one. Sense "
          "where you start and after every move, and at no other time. Count your senses up to "
          "and including the one that first shows you a goal; then keep exploring until you "
          "have taken that many senses again (after a first goal sense that was your fifth, "
          "stop after your tenth), and go with one move onto a goal you know and stop (any of "
          "them; if you are standing on a goal, just stop). If there is nothing more to find "
          "before you have taken all those senses, do this right after the sense that leaves "
          "nothing more to find.",
          f"goal_found() and {_TURNS} and primitives()[2 * len(sensed()) - 1:] in [[], "
          f"['navigate']] and (len(primitives()) - 1 - steps_after_goal()) % 2 == 0 and "
          f"all(len(sensed()) <= 2 * f + 2 and ((len(sensed()) == 2 * f + 2 and not "
          f"explored_all()) or ({_NEW_LAST} and (len(sensed()) == 2 * f + 2 or explored_all()))) "
          f"for f in [{_F_GOAL}]) and (({_STAY} and is_goal({_L})) or ({_MOVE} and "
          f"is_goal({_F}) and {_F} in known_cells() and not is_goal({_L})))"),
    _task("outward_records", 3, check_outward_records,
          "Explore, moving and sensing, pushing outwards: note how far from your starting cell "
          "each of your senses is taken (steps along rows and columns, ignoring obstacles). A "
          "sense sets a new record when it is taken farther from your start than every earlier "
          "sense (your first sense only sets the first distance; it is no record). Stop right "
          "after the sense that sets the fifth record. If there is nothing more to find before "
          "that, stop right after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and {_RECORDS} in ({_RECORDS_ALL} if explored_all() "
          f"and {_FRESH} else [{2 * RECORDS + 1}] if not explored_all() else [])"),
    _task("nearest_new_cell_search", 3, check_nearest_new_cell_search,
          "Search for a goal by always going to the nearest place you have not been. Sense "
          "where you start. Then, until a sense shows you a goal, move onto the cell nearest "
          "to where you stand (counting steps along rows and columns, ignoring obstacles) among "
          "the cells you know to be free and have never stood in (your starting cell counts as "
          "stood in), any of them if several are equally near, and sense there. As soon as a "
          "sense shows you a goal, go onto it with one move and stop (onto any of them if that "
          "sense showed several; if you are standing on one, just stop).",
          f"{_ONTO_GOAL_SHORT} and {_ALTERNATE} and all((moves()[k] in neighbours(sensed()[k]) "
          f"and moves()[k] not in sensed()[:k + 1]) or not min([({_NEAR_C}, c != moves()[k]) for "
          f"p in sensed()[:k + 1] for c in neighbours(p) if not is_obstacle(c) and c not in "
          f"sensed()[:k + 1]] + [(99, True)])[1] for k in {_K80}[:len(sensed()) - 1])"),
    _task("scoop_points", 2, check_scoop_points,
          f"Play for points. Each gram of grains you get into the receiver wins a point, each "
          f"gram you spill outside the containers loses a point, and each scoop costs "
          f"{POINT_SCOOP} points. Scoop one to five times, then stop, with at least {POINTS} "
          f"points.",
          f"scoops() >= 1 and scoops() <= 5 and delivered() - spilled() - {POINT_SCOOP} * "
          f"scoops() >= {POINTS}", SCOOP),
    _task("rising_bar", 2, check_rising_bar,
          f"Scoop one to four times, then stop, with at least {BAR_FLOOR} grams of grains in the "
          f"receiver -- and the more scoops you make, the higher the bar: the receiver must "
          f"also hold at least {BAR} grams times the square of the number of scoops "
          f"({BAR} g after one scoop, {4 * BAR} after two, {9 * BAR} after three, {16 * BAR} "
          f"after four).",
          f"scoops() >= 1 and scoops() <= 4 and delivered() >= {BAR_FLOOR} and delivered() >= "
          f"{BAR} * scoops() * scoops()", SCOOP),
]
