"""Held-out tasks, twelfth set: written before the next change of the synthesizer, run once after.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout12/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (probes to the right that reach one cell
further each time, back onto the start after each; a walk down that stops on the first look
showing more obstacles next to its cell than the look before; a walk left that comes home only if
more of its cells have an obstacle right above them than right below; a walk up, then onto the
cell right of the highest cell of the walk that has a free cell there, else home; once a goal is in
view, onto it if the obstacles known are even in number, else home; exploring that stops on a goal
in line with the start, in its row or column, else home when there is nothing more to find;
exploring that stops once two goals have been seen, then onto the one nearer the start; a search
that moves one cell at a time; after exploring, onto the goal that came into view last; after
exploring, onto a meeting point, a cell whose distances to the goals add up to the least; exploring
that stops once it has sensed from both sides of the start's column, then home; once a goal is in
view, to the cell in the goal's column and the start's row if it is known to be free, else home)
and two scooping tasks (two to five scoops that make either a clean job, at least 60 g delivered
with at most 10 g spilled, or a big haul, at least 110 g delivered; two to five scoops that
deliver at least 45 g and spill less in all than the grams delivered divided by the scoops made).
Each has a reference behavior (``references/``), a ground-truth ``check`` and a faithful
``promise`` over the env's outcome helpers, so that the search can be measured apart from the
model. They were written on 2026-12-06 blind: without reading the search's code and without
running the synthesizer on them; the first run of the search on them is the evaluation, reported
beside the development figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a *row* is the
cells of one j, a *column* those of one i; a goal is *in line with* the start when it shares its row
or its column; a sense labels its cell and the four around it (it *shows* them; a goal *comes into
view*, or is *seen*, with the first sense that shows it, and the goals that *came into view last*
are those first shown by the latest sense that first showed any); the cells *next to* a cell are
its four neighbours inside the grid, and the obstacles next to it are those among them (the grid's
edge does not count); the *distance* of two cells counts steps along rows and columns (|di| +
|dj|), obstacles ignored, and a *meeting point* is a reachable cell whose distances to the
reachable goals add up to as little as any reachable cell's; a move *in one step* ends on a cell
next to the one it began in; a cell of a walk is the start or one a move of the walk ended in. The
start cell always has a free neighbour (a goal is reachable from it and it holds none). The
promises' language allows three comprehension loops in one expression, all of them counted
together, and 400 syntax nodes: walks are bounded by what the grid allows (at most 9 moves);
single_step_search's promise reads up to 500 moves (the episode's bound of primitives) through
two loops of ten and fifty indices, last_seen_goal's up to 100 senses (its reference never made
more than 66); where a promise needs the least or greatest of a few values it sorts a list of
tuples (two_goals_nearer_home's, last_seen_goal's and meeting_point's) or of counts
(down_until_more_crowded's: the counts never rise before the last, ``C[:-1] ==
sorted(C[:-1])[::-1]``). The scooping checks weigh the grains at the end, as ``delivered()`` and
``spilled()`` do: those in the receiver, and those outside the receiver, the donor and the spoon's
tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all. On those episodes the tasks'
branches came up: 0 to 8 probes 102, 89, 48, 21, 18, 8, 11, 2 and 1 times; the walk down with no
move (the cell below blocked) 106, stopped on a more crowded cell after 1 to 6 moves 69, 38, 20, 3,
4 and 2 times, blocked after 1 to 6 moves 33, 13, 6, 2, 3 and 1; the walk left with no move 99, 1
to 9 moves 83, 50, 27, 16, 9, 8, 4, 3 and 1, and home after it 52, stayed 149; the walk up with 0 to
8 moves 106, 57, 49, 42, 17, 20, 4, 4 and 1, then onto the cell right of its top cell 206, of a
lower cell 42, home 26, no opening and no move 26; a goal in view before any move 41 (every goal
task below shares this exploring), then an even count and onto the goal 143 (23 of them from the
start), an odd count and home 139, already home 18; a goal in line with the start seen 122 (from
the start 41; in its row 60, in its column 62), none reachable and home after exploring 178; two
goals seen 279 (two new ones in one sense 7), standing on the nearer one 10, only one reachable
goal and onto it 21; the single-step search's moves up to 76 (15.4 on average); the reachable goals
1, 2 and 3 21, 61 and 218 times, the goal that came into view last stood on already 17, two goals
coming into view last together 1; the meeting point a goal 191, stood on already 5, one meeting
point 211, two 16, three or more 73; both sides of the start's column sensed from 242, nothing more
to find first 58; the corner cell of the goal's column and the start's row known to be free 148
(stood on already 26), not yet seen 68, an obstacle 42, the start itself (the goal above or below
it) 42 (already home 19); up to 66 senses. Faithfulness on behaviors that do not do the tasks:
every grid promise was judged against 72 near misses of the references (other directions, sides,
orders, counts, parities, comparisons or cells to go to, a missing or extra sense or move, one step
late, a long move back) and 8 other ways of doing the tasks (another explorer, another order of
steps) on episodes 0-99 of seeds 0 and 1 (15,975 judged episodes for each promise: the near misses
kept their own task's promise on 6,386 of their 14,375 and the other ways on all their 1,600),
against the 12 references of this set and the 146 grid references of the development and earlier
held-out sets (heldout11's included) on episodes 0-49 of seed 0 (7,900 judged episodes for each
promise), and against 3 trivial behaviors (stop at once, judged on the reset; sense once; navigate
onto the cell it stands in) on episodes 0-99 of seeds 0 and 1: on every judged episode the
promise's verdict equalled the check's. Keep rates of the trivial behaviors: stopping at once and
navigating onto the cell it stands in keep no promise on any episode; sensing once keeps none but
widening_probes_right's (64 of 200: the cell on the right blocked), down_until_more_crowded's (68:
the cell below blocked), left_walk_above_below's (66: the cell on the left blocked),
last_opening_right's (15: the cell above blocked and the one on the right too),
obstacle_parity_goal's (12: a goal in view from the start and an odd count) and
goal_column_start_row's (12: a goal in view from the start, above or below it), where the task asks
for the one sense. The scooping references (five and two scoops from the default sensing pose)
were run on episodes 0-19 of seed 0 only (3 to 10 s an episode) and kept their promises and did
their tasks on all 20: five scoops delivered 124.4 to 221.7 g (a big haul needs 110 g: margin
14.4 g) and spilled 0.0 to 38.5 g; two scoops delivered 58.8 to 97.3 g (45 g needed: margin
13.8 g) and spilled 0.0 to 22.6 g, at most 0.54 of the grams delivered divided by the scoops.
Near misses on episodes 0-9 (and 0-19 for the references' counts): one scoop (33.9 to 54.3 g)
kept no promise; two scoops kept clean_or_plenty's on 8 of 20 (a clean job every time); three
scoops (88.2 to 133.5 g) kept it on 6 of 10 (1 clean job, 5 big hauls) and
spill_under_average_scoop's on all 10; four scoops (104.0 to 171.9 g) kept clean_or_plenty's on 9
and spill_under_average_scoop's on all 10; five scoops kept spill_under_average_scoop's on 16 of
20 (on 4 the spill came to at least a fifth of the grams delivered: up to 1.18 times the grams
delivered divided by the scoops); the check agreed on every judged episode.
"""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (distance, distance_text, exhausted, first_goal_sense,
                                        free_cell, goals_shown, grams_in_receiver, grams_spilled,
                                        held_out_task, indices, known_after, neighbours,
                                        obstacles_beside, on_grid, onto, onto_goal_seen, reachable,
                                        same_steps, scoops, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP, DOWN = (1, 0), (-1, 0), (0, 1), (0, -1)




def _last_sense(steps) -> int | None:
    senses = [k for k, (kind, _) in enumerate(steps) if kind == "sense"]
    return senses[-1] if senses else None


def _after_exploring(state, steps, targets_of) -> str | None:
    """Nothing more to find at the end; after the last sense, nothing if its cell is one of
    ``targets_of(here)``, else one move onto one of them."""
    if not exhausted(state):
        return "stopped before everything was known"
    last = _last_sense(steps)
    if last is None:
        return "never sensed"
    here = steps[last][1]
    return onto(steps[last + 1:], here, targets_of(here), "after the last sense")


def _line(state, way, stop=None):
    """Sense; then moves ``way`` one cell at a time while the next cell is inside the grid and
    free, each followed by a sense, until ``stop(cells so far)`` says to stop: the plan and the
    cells stood in."""
    here = state.start_cell
    plan, cells = [("sense", here)], [here]
    while free_cell(state, step_by(here, way)) and not (stop and stop(cells)):
        here = step_by(here, way)
        plan += [("navigate", here), ("sense", here)]
        cells.append(here)
    return plan, cells


def _obstacle(state, c) -> bool:
    return on_grid(state, c) and state.truth[c] == OBSTACLE


# --- checks -------------------------------------------------------------------------------

def check_widening_probes_right(state, result):
    """Sense; then for k = 1, 2, ...: a move onto the cell k to the right of the start, a sense
    there and a move back onto the start, while that cell is inside the grid and free."""
    home = state.start_cell
    plan, k = [("sense", home)], 1
    while free_cell(state, (home[0] + k, home[1])):
        plan += [("navigate", (home[0] + k, home[1])), ("sense", (home[0] + k, home[1])),
                 ("navigate", home)]
        k += 1
    return same_steps(steps_of(result), plan)


def check_down_until_more_crowded(state, result):
    """Sense; walk down, each move followed by a sense, while the cell below is inside the grid
    and free; stop right after the first sense whose cell has more obstacles next to it than
    the cell of the sense before."""
    def crowded(cells):
        return len(cells) > 1 and obstacles_beside(state, cells[-1]) > \
            obstacles_beside(state, cells[-2])
    plan, _ = _line(state, DOWN, crowded)
    return same_steps(steps_of(result), plan)


def check_left_walk_above_below(state, result):
    """Sense; walk left, each move followed by a sense, while the cell on the left is inside the
    grid and free; then a move onto the start if the agent moved and more of the walk's cells
    (the start's included) have an obstacle right above them than right below them."""
    plan, cells = _line(state, LEFT)
    above = sum(_obstacle(state, step_by(c, UP)) for c in cells)
    below = sum(_obstacle(state, step_by(c, DOWN)) for c in cells)
    if above > below and len(cells) > 1:
        plan.append(("navigate", state.start_cell))
    return same_steps(steps_of(result), plan)


def check_last_opening_right(state, result):
    """Sense; walk up, each move followed by a sense, while the cell above is inside the grid
    and free; then one move onto the cell right of the highest cell of the walk (the start
    included) whose right-hand cell is free, or onto the start if there is none (nothing if
    the agent stands there)."""
    plan, cells = _line(state, UP)
    openings = [step_by(c, RIGHT) for c in cells if free_cell(state, step_by(c, RIGHT))]
    target = openings[-1] if openings else state.start_cell
    if target != cells[-1]:
        plan.append(("navigate", target))
    return same_steps(steps_of(result), plan)


def check_obstacle_parity_goal(state, result):
    """After the sense that first shows a goal: if the agent then knows an even number of
    obstacles, one move onto a goal it showed (nothing if the agent stands on one); if an odd
    number, one move onto the start (nothing if the agent stands on it)."""
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    steps = steps_of(result)
    here, rest = steps[index][1], steps[index + 1:]
    known = known_after(state, result.steps[:index + 1])
    if int((known & (state.truth == OBSTACLE)).sum()) % 2 == 0:
        return onto(rest, here, goals_shown(state, here), "after the goal came into view")
    return onto(rest, here, [state.start_cell], "after the goal came into view")


def check_aligned_goal(state, result):
    """Exploring stops with the first sense that shows a goal in the start's row or column,
    then one move onto such a goal it showed (nothing if the agent stands on one); if no sense
    shows one, nothing more to find at the end and, after the last sense, one move onto the
    start (nothing if the agent stands on it)."""
    steps, home = steps_of(result), state.start_cell
    for index, (kind, here) in enumerate(steps):
        if kind != "sense":
            continue
        lined = [g for g in goals_shown(state, here) if home[0] == g[0] or home[1] == g[1]]
        if lined:
            return onto(steps[index + 1:], here, lined, "after the goal came into view")
    return _after_exploring(state, steps, lambda here: [home])


def check_two_goals_nearer_home(state, result):
    """Exploring stops with the first sense after which two goals have been seen, then one move
    onto a goal seen so far that is as near the start as any of them (nothing if the agent
    stands on one); if no sense makes two, nothing more to find at the end and, after the last
    sense, one move onto the goal (nothing if the agent stands on it)."""
    steps, home = steps_of(result), state.start_cell
    seen: list = []
    for index, (kind, here) in enumerate(steps):
        if kind != "sense":
            continue
        seen += [g for g in goals_shown(state, here) if g not in seen]
        if len(seen) >= 2:
            near = min(distance(g, home) for g in seen)
            return onto(steps[index + 1:], here, [g for g in seen if distance(g, home) == near],
                         "after the second goal came into view")
    return _after_exploring(state, steps, lambda here: seen)


def check_single_step_search(state, result):
    """Every move onto a cell next to the one the agent stands in; after the sense that first
    shows a goal, one move onto a goal it showed (nothing if the agent stands on one)."""
    steps, here = steps_of(result), state.start_cell
    for kind, c in steps:
        if kind == "navigate":
            if c not in neighbours(state, here):
                return f"moved from {here} to {c}, not a cell next to it"
            here = c
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    return onto_goal_seen(state, steps, index)


def check_last_seen_goal(state, result):
    """Nothing more to find at the end; after the last sense, one move onto a goal that came
    into view last (no sense after the one that first showed it first showed another goal),
    or nothing if the agent stands on one."""
    steps = steps_of(result)
    first: dict = {}
    for index, (kind, here) in enumerate(steps):
        if kind == "sense":
            for g in goals_shown(state, here):
                first.setdefault(g, index)
    latest = max(first.values(), default=None)
    return _after_exploring(state, steps,
                            lambda here: [g for g, k in first.items() if k == latest])


def check_meeting_point(state, result):
    """Nothing more to find at the end; after the last sense, one move onto a reachable cell
    whose distances to the reachable goals add up to as little as any reachable cell's, or
    nothing if the agent stands on one."""
    reach = reachable(state)
    cells = [(int(i), int(j)) for i, j in zip(*reach.nonzero())]
    goals = [c for c in cells if state.truth[c] == GOAL]
    cost = {c: sum(distance(c, g) for g in goals) for c in cells}
    least = min(cost.values())
    best = [c for c in cells if cost[c] == least]
    return _after_exploring(state, steps_of(result), lambda here: best)


def check_both_sides_then_home(state, result):
    """Exploring stops with the first sense after which the agent has sensed both from a cell
    left of the start's column and from one right of it, then one move onto the start; if no
    sense makes both, nothing more to find at the end and, after the last sense, one move onto
    the start (nothing if the agent stands on it)."""
    steps, home = steps_of(result), state.start_cell
    left = right = False
    for index, (kind, here) in enumerate(steps):
        if kind != "sense":
            continue
        left, right = left or here[0] < home[0], right or here[0] > home[0]
        if left and right:
            return onto(steps[index + 1:], here, [home], "after sensing on both sides")
    return _after_exploring(state, steps, lambda here: [home])


def check_goal_column_start_row(state, result):
    """After the sense that first shows a goal: one move onto the cell in a shown goal's column
    and the start's row if the agent knows that cell is free, else onto the start; nothing
    if the agent stands on the cell it would go to."""
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    steps, home = steps_of(result), state.start_cell
    here, rest = steps[index][1], steps[index + 1:]
    known = known_after(state, result.steps[:index + 1])
    for goal in goals_shown(state, here):
        corner = (goal[0], home[1])
        target = corner if known[corner] and state.truth[corner] != OBSTACLE else home
        if onto(rest, here, [target], "") is None:
            return None
    return f"after the goal came into view ran {rest[:4]}, not the move the goal's column asks"


CLEAN_SPILL, CLEAN_LEAST, PLENTY = 10, 60, 110  # a clean job: grams spilled at most and
# delivered at least; a big haul: grams delivered at least, whatever is spilled
AVERAGE_LEAST = 45  # grams delivered at least (and more than the scoops times the spill)


def check_clean_or_plenty(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if (spilled <= CLEAN_SPILL and mass >= CLEAN_LEAST) or mass >= PLENTY else \
        f"{mass:.1f} g delivered, {spilled:.1f} g spilled after {n} scoops"


def check_spill_under_average_scoop(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if mass >= AVERAGE_LEAST and spilled * n < mass else \
        f"{mass:.1f} g delivered, {spilled:.1f} g spilled after {n} scoops"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)




# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_S, _S0, _S1 = "start_cell()", "start_cell()[0]", "start_cell()[1]"
_L, _F = "sensed()[-1]", "final_cell()"  # where the last sense was taken; where it ended
_LINE = "primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and " \
        "sensed() == [start_cell()] + moves()"
# after the last sense: nothing, or one move (the last sense is then the step before it)
_STAY = "primitives()[-1] == 'sense'"
_MOVE = "primitives()[-2:] == ['sense', 'navigate']"
_K10, _K100 = indices(10), indices(100)



def _blocked(x: str, y: str, edge: str) -> str:
    """The cell (x, y), one step off a cell of the grid, is outside it (``edge`` says when) or
    an obstacle."""
    return f"({edge} or is_obstacle(({x}, {y})))"


def _shows(g: str, k: str) -> str:
    """The sense ``k`` (an index of sensed()) shows the cell ``g``."""
    return f"({g} == sensed()[{k}] or {g} in neighbours(sensed()[{k}]))"


def _home_after_all() -> str:
    """After the last sense: nothing if it was taken on the start, else one move onto it."""
    return f"(({_L} == {_S} and {_STAY}) or ({_L} != {_S} and {_MOVE} and {_F} == {_S}))"


def _aligned(c: str) -> str:
    return f"(is_goal({c}) and ({c}[0] == {_S0} or {c}[1] == {_S1}))"


# for each reachable goal: (not known, its distance to the start, shown by a sense before the
# last, the goal), sorted: the known goals first, the nearest first
_SEEN = f"sorted([(g not in known_cells(), {distance_text('g', _S)}, any(g == s or g in " \
        f"neighbours(s) for s in sensed()[:-1]), g) for g in reachable_goals()])"


def _both(cells: str) -> str:
    """Some of ``cells`` lie left of the start's column and some right of it."""
    return f"sorted({cells})[0][0] < {_S0} < sorted({cells})[-1][0]"


_CROWD = f"[len([o for o in neighbours(sensed()[k]) if is_obstacle(o)]) if sensed()[k] == " \
         f"({_S0}, {_S1} - k) else -1 for k in {_K10}[:len(sensed())]]"
_SIDES = "sum([(1 if c[1] < 9 and is_obstacle((c[0], c[1] + 1)) else 0) - (1 if c[1] > 0 and " \
         "is_obstacle((c[0], c[1] - 1)) else 0) for c in sensed()])"
_OPENING = f"([{_S}] + [(c[0] + 1, c[1]) for c in sensed() if c[0] < 9 and not " \
           f"is_obstacle((c[0] + 1, c[1]))])[-1]"
_P = "([start_cell()] + moves())"  # the cells stood in: the start, then each move's
_CORNER = f"((g[0], {_S1}) if (g[0], {_S1}) in known_cells() and not is_obstacle((g[0], " \
          f"{_S1})) else {_S})"

TASKS = [
    _task("widening_probes_right", 1, check_widening_probes_right,
          "Probe to your right, reaching a little further each time. Sense where you start. "
          "Then go to the cell one to your right (i + 1), sense there and come straight back to "
          "your starting cell; then go to the cell two to your right, sense and come back; then "
          "three, and so on. Stop, back on your starting cell, as soon as the next cell to probe "
          "is outside the grid or an obstacle (if the cell right next to you already is, just "
          "sense and stop).",
          f"primitives() == ['sense'] + ['navigate', 'sense', 'navigate'] * (len(sensed()) - 1) "
          f"and sensed() == [{_S}] + [({_S0} + k, {_S1}) for k in {_K10}[1:len(sensed())]] and "
          f"moves() == [c for k in {_K10}[1:len(sensed())] for c in [({_S0} + k, {_S1}), {_S}]] "
          f"and {_blocked(f'{_S0} + len(sensed())', _S1, f'{_S0} + len(sensed()) == 10')}"),
    _task("down_until_more_crowded", 2, check_down_until_more_crowded,
          "Walk down (j - 1) from where you start, one cell at a time: sense first, then move "
          "down and sense after every move, as long as the cell below you is inside the grid "
          "and free. Count the obstacles right next to each cell you sense from (the grid's "
          "edge does not count). Stop right after the first sense that shows more obstacles "
          "next to your cell than the sense before it showed next to its cell -- or when you "
          "cannot go down any further.",
          f"{_LINE} and len(sensed()) <= 10 and all(-1 not in C and C[:-1] == "
          f"sorted(C[:-1])[::-1] and ((len(C) > 1 and C[-1] > C[-2]) or ((len(C) == 1 or C[-1] "
          f"<= C[-2]) and {_blocked(_S0, f'{_S1} - len(moves()) - 1', f'{_S1} == len(moves())')}"
          f")) for C in [{_CROWD}])"),
    _task("left_walk_above_below", 2, check_left_walk_above_below,
          "Walk left (i - 1) as far as you can: sense, then move left one cell at a time, "
          "sensing after every move, while the cell to your left is inside the grid and free. "
          "Then look back over the cells of your walk, your starting cell included: if more of "
          "them have an obstacle right above them (j + 1) than right below them (j - 1), go "
          "straight back to your starting cell with one move; otherwise stay where you are. "
          "If you could not move at all, just stop.",
          f"sensed() == [({_S0} - k, {_S1}) for k in {_K10}[:len(sensed())]] and "
          f"{_blocked(f'{_S0} - len(sensed())', _S1, f'{_S0} == len(sensed()) - 1')} and "
          f"all(primitives() == ['sense'] + ['navigate', 'sense'] * (len(sensed()) - 1) + "
          f"['navigate'] * b and moves() == sensed()[1:] + [{_S}] * b for b in [1 if "
          f"len(sensed()) > 1 and {_SIDES} > 0 else 0])"),
    _task("last_opening_right", 2, check_last_opening_right,
          "Walk up (j + 1) as far as you can: sense, then move up one cell at a time, sensing "
          "after every move, while the cell above you is inside the grid and free. When you "
          "cannot go up any further, find the highest cell of your walk (your starting cell "
          "included) whose right-hand neighbour (i + 1) is free, and go onto that right-hand "
          "neighbour with one move. If no cell of the walk has a free cell on its right, go back "
          "to your starting cell instead (if you are on it, just stop).",
          f"sensed() == [({_S0}, {_S1} + k) for k in {_K10}[:len(sensed())]] and "
          f"{_blocked(_S0, f'{_S1} + len(sensed())', f'{_S1} + len(sensed()) == 10')} and "
          f"all(primitives() == ['sense'] + ['navigate', 'sense'] * (len(sensed()) - 1) + "
          f"['navigate'] * (1 if T != {_L} else 0) and moves() == sensed()[1:] + [T] * (1 if T "
          f"!= {_L} else 0) for T in [{_OPENING}])"),
    _task("obstacle_parity_goal", 1, check_obstacle_parity_goal,
          "Explore until a sense shows you a goal. Then count the obstacles you know about by "
          "then: if the count is even (zero included), go onto the goal with one move (onto any "
          "of them if that sense showed several); if it is odd, leave the goal and go straight "
          "back to your starting cell with one move. If you are already standing on the cell "
          "you would go to, just stop.",
          f"goal_found() and sensed()[-1:] != [] and (((steps_after_goal() == 0 and "
          f"is_goal({_L})) or (steps_after_goal() == 1 and primitives()[-1] == 'navigate' and "
          f"not is_goal({_L}) and is_goal({_F}) and {_F} in neighbours({_L}))) if "
          f"len(known_obstacles()) % 2 == 0 else ((steps_after_goal() == 0 and {_L} == {_S}) or "
          f"(steps_after_goal() == 1 and primitives()[-1] == 'navigate' and {_L} != {_S} and "
          f"{_F} == {_S})))"),
    _task("aligned_goal", 2, check_aligned_goal,
          "Look for a goal that lies in line with your starting cell: in the same row (same j) "
          "or the same column (same i). Explore, moving and sensing, and as soon as a sense "
          "shows you such a goal, go onto it with one move and stop (if you are standing on it, "
          "just stop). Goals that are not in line with your start do not count. If there is "
          "nothing more to find and you never saw one, go back to your starting cell and stop.",
          f"(not any({_aligned('c')} for s in sensed()[:-1] for c in "
          f"[s] + neighbours(s)) and (({_aligned(_L)} and {_STAY}) or (not {_aligned(_L)} and "
          f"{_MOVE} and {_F} in neighbours({_L}) and {_aligned(_F)}))) or (explored_all() and not "
          f"any({_aligned('g')} for g in reachable_goals()) and {_home_after_all()})"),
    _task("two_goals_nearer_home", 3, check_two_goals_nearer_home,
          "Explore until you have seen two different goals. Stop exploring right then and go, "
          "with one move, onto whichever of the goals you have seen is nearer to your starting "
          "cell, counting steps along rows and columns and ignoring obstacles (either one if "
          "they are equally near; if that last sense showed you two new goals at once, choose "
          "among all the goals you have seen). If you are already standing on it, just stop. "
          "If there turns out to be only one goal you can find -- nothing more to find and "
          "still only one seen -- go onto that one and stop.",
          f"all((len(Y) >= 2 and not Y[1][0] and not sorted([Y[0][2], Y[1][2], len(Y) == 3 and "
          f"Y[-1][2]])[1] and is_goal({_F}) "
          f"and {_F} in known_cells() and {distance_text(_F, _S)} == Y[0][1] and ({_STAY} or "
          f"({_MOVE} and not (is_goal({_L}) and {distance_text(_L, _S)} == Y[0][1])))) or "
          f"(len(Y) == 1 and explored_all() and {_F} == Y[0][3] and ({_STAY} or ({_MOVE} and "
          f"{_L} != {_F}))) for Y in [{_SEEN}])"),
    _task("single_step_search", 3, check_single_step_search,
          "Search for a goal, but move only one cell at a time: every move must end on a cell "
          "right next to (left, right, above or below) the cell you are standing in -- no "
          "longer trips, not even back over cells you know. Sense wherever you like. As soon "
          "as a sense shows you a goal, step onto it and stop (if you are standing on it, just "
          "stop).",
          f"goal_found() and sensed()[-1:] != [] and ((steps_after_goal() == 0 and "
          f"is_goal({_L})) or (steps_after_goal() == 1 and primitives()[-1] == 'navigate' and "
          f"not is_goal({_L}) and is_goal({_F}))) and all({_P}[10 * a + b + 1] in "
          f"neighbours({_P}[10 * a + b]) for a in {indices(50)} for b in {_K10} if 10 * a + b < "
          f"len(moves()))"),
    _task("last_seen_goal", 3, check_last_seen_goal,
          "Explore until there is nothing more to find. Keep track of the order in which the "
          "goals came into view. Then go onto the goal you saw last -- the one whose first "
          "sighting came latest (if a single sense showed two new goals at once and that was "
          "the latest, either of them) -- with one move, and stop. If you are standing on it "
          "already, just stop.",
          f"len(sensed()) <= 100 and explored_all() and all(({_STAY} and (X[-1][0], {_L}) in X) "
          f"or ({_MOVE} and (X[-1][0], {_F}) in X and (X[-1][0], {_L}) not in X) for X in "
          f"[sorted([(min([k for k in {_K100}[:len(sensed())] if {_shows('g', 'k')}]), g) for g "
          f"in reachable_goals()])])"),
    _task("meeting_point", 3, check_meeting_point,
          "Explore until there is nothing more to find. Then go with one move to a meeting "
          "point for the goals: a cell you can reach whose distances to all the goals you can "
          "reach, added up, are as small as any reachable cell's (distances count steps along "
          "rows and columns, ignoring obstacles; any such cell if there are several, a goal "
          "itself included). Stop there. If you are already standing on such a cell, just "
          "stop.",
          f"explored_all() and sensed()[-1:] != [] and all(({_STAY} and (Z[0][0], {_L}) in Z) "
          f"or ({_MOVE} and (Z[0][0], {_F}) in Z and (Z[0][0], {_L}) not in Z) for Z in "
          f"[sorted([(sum([{distance_text('c', 'g')} for g in reachable_goals()]), c) for c in "
          f"reachable_cells()])])"),
    _task("both_sides_then_home", 2, check_both_sides_then_home,
          "Explore until you have sensed from at least one cell to the left of your starting "
          "column (smaller i) and from at least one cell to the right of it (larger i). Stop "
          "exploring right after the sense that completes this and go straight back to your "
          "starting cell with one move. If there is nothing more to find before that happens, "
          "go back to your starting cell then (if you are on it, just stop).",
          f"sensed()[-1:] != [] and {_home_after_all()} and (({_both('sensed()')} and not "
          f"({_both('sensed()[:-1]')})) or (not ({_both('sensed()')}) and explored_all()))"),
    _task("goal_column_start_row", 2, check_goal_column_start_row,
          "Explore until a sense shows you a goal. Do not go onto it. Instead, go with one move "
          "to the cell that is in the goal's column (same i as the goal) and in your starting "
          "row (same j as your starting cell) -- but only if you already know that cell is "
          "free. If you have not seen that cell yet, or it is an obstacle, go back to your "
          "starting cell instead. If that sense showed several goals, go by any one of them. If "
          "you are already standing on the cell you would go to, just stop.",
          f"goal_found() and sensed()[-1:] != [] and any((steps_after_goal() == 0 and {_L} == T) "
          f"or (steps_after_goal() == 1 and primitives()[-1] == 'navigate' and {_L} != T and "
          f"{_F} == T) for g in [{_L}] + neighbours({_L}) if is_goal(g) for T in [{_CORNER}])"),
    _task("clean_or_plenty", 2, check_clean_or_plenty,
          f"Scoop two to five times, then stop. Either do a clean job -- at least {CLEAN_LEAST} "
          f"grams of grains in the receiver with no more than {CLEAN_SPILL} grams spilled "
          f"outside the containers -- or bring a big haul: at least {PLENTY} grams in the "
          f"receiver, however much you spill.",
          f"scoops() >= 2 and scoops() <= 5 and ((spilled() <= {CLEAN_SPILL} and delivered() >= "
          f"{CLEAN_LEAST}) or delivered() >= {PLENTY})", SCOOP),
    _task("spill_under_average_scoop", 2, check_spill_under_average_scoop,
          f"Scoop two to five times, then stop. Get at least {AVERAGE_LEAST} grams of grains "
          f"into the receiver, and spill less, all told, than one of your scoops brought on "
          f"average: the grams spilled outside the containers must be under the grams "
          f"delivered divided by the number of scoops you made.",
          f"scoops() >= 2 and scoops() <= 5 and delivered() >= {AVERAGE_LEAST} and spilled() * "
          f"scoops() < delivered()", SCOOP),
]
