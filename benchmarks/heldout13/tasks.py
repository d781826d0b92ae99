"""Held-out tasks, thirteenth set: written before the next change of the synthesizer, run once
after it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout13/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (a goal search made only if the first look
shows no obstacle next to the start, else one sense; a tour of the eight cells round the start,
clockwise from the one above, skipping those not known to be free by then, and home; a passage
followed while it offers exactly one way on; once a goal is in view, a walk straight away from it;
exploring that stops once the four straight lines out of the start are known up to their first
obstacles; a walk down and back up the start's column, then onto the middle of that stretch; after
exploring, onto a vantage point from which one sense shows two goals, else home; a search that goes
home if five obstacles come into view before a goal; exploring that stops once a goal and every cell
next to it are known, then home; exploring on a battery of 20 units, home once the units used and
the way home reach 20; a trip home after every sense that shows a new goal; after exploring, onto
the goal that the most senses showed) and two scooping tasks (at least 70 g delivered for at most
100 credits, 20 a scoop and 1 a gram spilled; one to five scoops that deliver at least 45 g and
spill at most 45 g less 5 g for every scoop). Each has a reference behavior (``references/``), a
ground-truth ``check`` and a faithful ``promise`` over the env's outcome helpers, so that the search
can be measured apart from the model. They were written on 2026-12-06 blind: without reading the
search's code and without running the synthesizer on them; the first run of the search on them is
the evaluation, reported beside the development figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a *column* is
the cells of one i; a sense labels its cell and the four around it (it *shows* them; a goal *comes
into view*, or is *seen*, with the first sense that shows it, and a goal is *new* to a sense that no
earlier sense showed it to); the cells *next to* a cell are its four neighbours inside the grid, and
the obstacles next to it are those among them (the grid's edge does not count); the eight cells
*round* the start are those next to it and the four diagonal to it, and one is *known to be free*
when an earlier sense showed it free; a cell *stood in* is the start or one a move ended in; a *way
on* is a free cell next to the agent that it has not stood in; the *straight lines* out of the start
run up, right, down and left to the grid's edge, and each is wanted up to and including its first
obstacle; the *stretch* of the column walk is its cells from the lowest stood in to the highest, and
its *middle* the lower of its two middle cells when it has an even number; a *vantage point* is a
reachable cell whose sense would show two or more goals (on it or next to it); the *distance* of two
cells, and a move's *length*, count steps along rows and columns (|di| + |dj|), obstacles ignored.
The start cell always has a free neighbour (a goal is reachable from it and it holds none); the
references only move onto cells they know, so none ever stood on a goal when it first came into
view. The promises' language allows three comprehension loops in one expression, all of them counted
together, and 400 syntax nodes: where a promise needs indices it writes them out (battery_return's
promise reads up to 20 senses, all the battery allows; follow_passage's up to 90 moves, more than a
passage can have; report_each_goal's up to 100 senses, where its reference never made more than 69);
a diagonal cell of the ring is known when its turn comes exactly when the cell before it on the ring
(for the last, that one or the first) is free and so was visited, and a free cell next to a
reachable one is reachable, so ring_around_start's and retreat_from_goal's promises read *free* from
``reachable_cells()``; where a promise needs what was known before the last sense while a move may
follow it, it reads the cells the earlier senses showed (goal_before_clutter,
scout_goal_surroundings). The scooping checks weigh the grains at the end, as ``delivered()`` and
``spilled()`` do: those in the receiver, and those outside the receiver, the donor and the spoon's
tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all. On those episodes the tasks'
branches came up: an obstacle next to the start and one sense 214, a clear first look 86 (a goal in
view from the start 16, found by searching 70); the ring with 1 to 8 of its cells visited 9, 35, 50,
70, 52, 46, 29 and 9 times, 0 to 4 of them diagonal 26, 105, 90, 68 and 11 times; the passage
followed for 0 to 5 moves after the first step 210, 65, 17, 4, 3 and 1 times, ending at a dead end
19, at a fork 281; the walk away from the goal of 0 to 8 moves 97, 73, 59, 25, 16, 18, 9, 2 and 1
times (a goal in view from the start 41, several goals in that sense 6); the four lines known after
1 to 61 senses (within 4 senses 26, after 30 or more 173), at the sense that left nothing more to
find 17; the column's stretch of 1 cell (no move) 41 and of 2 to 10 cells 38, 40, 47, 41, 31, 30,
12, 12 and 8 times (no move down 106); no vantage point and home 237, one 20, two 41, three or more
2, the point a goal 35, stood on already 2; a goal before five obstacles 137 (from the start 41; the
count reaching five at that same sense 14), five obstacles first and home 163 (a sense showing
several at once: six 28, seven 3); a goal's surroundings completed by a sense on the goal 281,
elsewhere 19, after up to 53 senses; the battery's reserve reached after 6 to 10 senses 5, 6, 273,
13 and 1 times, nothing more to find first 2; 0 to 3 trips home to report a goal 3, 25, 92 and 180
times (a goal in view from the start 41), the last sense showing a new goal and a move home after it
8, up to 69 senses; the reachable goals 1, 2 and 3 21, 61 and 218 times, two or three goals shown by
the most senses 112, the goal stood on already 1. Faithfulness on behaviors that do not do the
tasks: every grid promise was judged against 78 near misses of the references (other directions,
orders, rules or places to go, counts one off, thresholds one off, a missing or extra sense or move,
one sense late, stopping early, cells not yet known taken for free) and 11 other ways of doing the
tasks (another explorer, another first step or choice among ties) on episodes 0-99 of seeds 0 and 1
(17,578 judged episodes for each promise: the near misses kept their own task's promise on 5,674 of
their 15,378 and the other ways on all their 2,200), against the 12 references of this set and the
158 grid references of the development and earlier held-out sets (heldout12's included) on episodes
0-49 of seed 0 (8,500 judged episodes for each promise), and against 3 trivial behaviors (stop at
once, judged on the reset; sense once; navigate onto the cell it stands in) on episodes 0-99 of
seeds 0 and 1: on every judged episode the promise's verdict equalled the check's. Keep rates of the
trivial behaviors: stopping at once and navigating onto the cell it stands in keep no promise on any
episode; sensing once keeps none but clear_start_search's (141 of 200: an obstacle next to the
start), column_midpoint's (26: the cells above and below blocked), retreat_from_goal's (8: a goal
next to the start and the cell on the far side blocked) and four_ray_lengths' (2: the start so near
the edges that its first sense shows every line to its first obstacle or the edge), where the task
asks for the one sense. The scooping references (three and two scoops from the default sensing pose)
were run on episodes 0-19 of seed 0 only (3 to 10 s an episode) and kept their promises and did
their tasks on all 20: three scoops delivered 83.7 to 144.8 g (70 g needed: margin 13.7 g) and
spilled 0.0 to 24.9 g (at most 84.9 of the 100 credits spent); two scoops delivered 58.8 to 97.3 g
(45 g needed: margin 13.8 g) and spilled 0.0 to 22.6 g (35 g allowed: margin 12.4 g). Near misses
and other counts on episodes 0-9 (and 0-19 for the references' counts): one scoop (33.9 to 54.3 g)
kept no scoop_credits promise and shrinking_spill_allowance's on 6 of 10 (45 g delivered); two
scoops kept scoop_credits' on 16 of 20 (under 70 g on 4); three scoops kept
shrinking_spill_allowance's on all 20; four scoops (104.0 to 171.9 g, 6.8 to 31.7 g spilled) kept
scoop_credits' on 4 and shrinking_spill_allowance's on 8; five scoops (124.4 to 196.8 g, 6.8 to
36.2 g spilled) kept scoop_credits' on none and shrinking_spill_allowance's on 2; the check agreed
on every judged episode.
"""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (cell, distance, distance_text, exhausted, first_goal_sense,
                                        first_reaching, free_cell, free_neighbours, goals_shown,
                                        grams_in_receiver, grams_spilled, held_out_task, indices,
                                        label_sensed, obstacles_beside, on_grid, onto,
                                        onto_goal_seen, reachable, same_steps, scoops, sensed_cells,
                                        step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP, DOWN = (1, 0), (-1, 0), (0, 1), (0, -1)
RING = (UP, (1, 1), RIGHT, (1, -1), DOWN, (-1, -1), LEFT, (-1, 1))  # clockwise from above
CLUTTER = 5  # obstacles shown before any goal that make goal_before_clutter give up
BATTERY = 20  # units of battery_return




def _after_exploring(state, steps, targets) -> str | None:
    """Nothing more to find at the end; after the last sense, nothing if its cell is one of
    ``targets``, else one move onto one of them."""
    if not exhausted(state):
        return "stopped before everything was known"
    senses = [k for k, (kind, _) in enumerate(steps) if kind == "sense"]
    if not senses:
        return "never sensed"
    here = steps[senses[-1]][1]
    return onto(steps[senses[-1] + 1:], here, targets, "after the last sense")


def _unknown(state):
    """A boolean grid of the cells' knowledge before any step: nothing known."""
    return state.truth != state.truth


# --- checks -------------------------------------------------------------------------------

def check_clear_start_search(state, result):
    """A sense on the start first; if an obstacle is next to the start, nothing more; else,
    after the sense that first shows a goal, one move onto a goal it showed (nothing if the
    agent stands on one)."""
    steps, home = steps_of(result), state.start_cell
    if steps[:1] != [("sense", home)]:
        return f"ran {steps[:2]}, not a sense where it started first"
    if obstacles_beside(state, home):
        return same_steps(steps, [("sense", home)])
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    return onto_goal_seen(state, steps, index)


def check_ring_around_start(state, result):
    """Sense; then, for the eight cells around the start clockwise from the one above, a move
    onto it and a sense there if it is inside the grid, free and known by then; then a move
    onto the start if the agent moved."""
    home = state.start_cell
    known = _unknown(state)
    plan = [("sense", home)]
    label_sensed(state, known, plan[0])
    for way in RING:
        c = step_by(home, way)
        if on_grid(state, c) and known[c] and state.truth[c] != OBSTACLE:
            plan += [("navigate", c), ("sense", c)]
            label_sensed(state, known, plan[-1])
    if len(plan) > 1:
        plan.append(("navigate", home))
    return same_steps(steps_of(result), plan)


def check_follow_passage(state, result):
    """Sense, a move onto a free cell next to the start, a sense there; then, while exactly one
    free cell next to the agent is one it has not stood in, a move onto it and a sense."""
    steps, home = steps_of(result), state.start_cell
    if len(steps) < 3 or steps[0] != ("sense", home) or steps[1][0] != "navigate" \
            or steps[1][1] not in free_neighbours(state, home) \
            or steps[2] != ("sense", steps[1][1]):
        return f"ran {steps[:4]}, not a sense, a move onto a free cell next to the start and " \
               "a sense there"
    here = steps[1][1]
    plan, stood = steps[:3], [home, here]
    while True:
        new = [n for n in free_neighbours(state, here) if n not in stood]
        if len(new) != 1:
            break
        here = new[0]
        stood.append(here)
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps, plan)


def check_retreat_from_goal(state, result):
    """After the sense that first shows a goal: nothing if the agent stands on a goal; else a
    walk straight away from a goal it showed (the way from the goal to the agent's cell), each
    move followed by a sense, while the next cell that way is inside the grid and free."""
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    steps = steps_of(result)
    here, rest = steps[index][1], steps[index + 1:]
    if state.truth[here] == GOAL:
        return same_steps(rest, [])
    for goal in goals_shown(state, here):
        way, c, plan = (here[0] - goal[0], here[1] - goal[1]), here, []
        while free_cell(state, step_by(c, way)):
            c = step_by(c, way)
            plan += [("navigate", c), ("sense", c)]
        if rest == plan:
            return None
    return f"after the goal came into view ran {rest[:4]}, not a walk straight away from it"


def _rays(state) -> list:
    """The cells on the four straight lines out of the start, up to and including the first
    obstacle on each (to the grid's edge where there is none)."""
    home, cells = state.start_cell, []
    for way in (UP, RIGHT, DOWN, LEFT):
        c = step_by(home, way)
        while on_grid(state, c):
            cells.append(c)
            if state.truth[c] == OBSTACLE:
                break
            c = step_by(c, way)
    return cells


def check_four_ray_lengths(state, result):
    """Exploring stops with the first sense after which every cell of the four lines is
    known."""
    need = _rays(state)
    index = first_reaching(state, result, lambda known: all(known[c] for c in need))
    if index is None:
        return "the four lines out of the start were never all known"
    return same_steps(steps_of(result)[index + 1:], [])


def check_column_midpoint(state, result):
    """Sense; walk down, each move followed by a sense, while the cell below is inside the grid
    and free; then walk up the same way while the cell above is; then one move onto the lower
    middle cell of the stretch from the lowest cell to the highest (nothing if the agent is on
    it)."""
    here = state.start_cell
    plan = [("sense", here)]
    for way in (DOWN, UP):
        while free_cell(state, step_by(here, way)):
            here = step_by(here, way)
            plan += [("navigate", here), ("sense", here)]
        if way == DOWN:
            low = here
    middle = (here[0], (low[1] + here[1]) // 2)
    if middle != here:
        plan.append(("navigate", middle))
    return same_steps(steps_of(result), plan)


def check_two_goal_vantage(state, result):
    """Nothing more to find at the end; after the last sense, one move onto a reachable cell
    whose sense would show two or more goals (nothing if the agent stands on one), or onto the
    start if there is no such cell (nothing if the agent stands on it)."""
    reach = reachable(state)
    spots = [c for c in (cell(c) for c in zip(*reach.nonzero()))
             if len(goals_shown(state, c)) >= 2]
    return _after_exploring(state, steps_of(result), spots or [state.start_cell])


def check_goal_before_clutter(state, result):
    """At the first sense that shows a goal: one move onto a goal it showed (nothing if the
    agent stands on one); at the first sense before that after which CLUTTER obstacles are
    known: one move onto the start (nothing if the agent stands on it)."""
    steps, home = steps_of(result), state.start_cell
    known = _unknown(state)
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] != "sense":
            continue
        here, rest = step[1], steps[index + 1:]
        goals = goals_shown(state, here)
        if goals:
            return onto(rest, here, goals, "after the goal came into view")
        if int((known & (state.truth == OBSTACLE)).sum()) >= CLUTTER:
            return onto(rest, here, [home], f"after the {CLUTTER}th obstacle came into view")
    return "no goal seen, and too few obstacles to give up"


def check_scout_goal_surroundings(state, result):
    """Exploring stops with the first sense after which some goal and every cell next to it
    are known, then one move onto the start (nothing if the agent stands on it)."""
    steps, home = steps_of(result), state.start_cell
    goals = [cell(c) for c in zip(*(state.truth == GOAL).nonzero())]
    known = _unknown(state)
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] == "sense" and any(all(known[c] for c in sensed_cells(state, g))
                                      for g in goals):
            return onto(steps[index + 1:], step[1], [home],
                         "after a goal's surroundings were known")
    return "no goal and its surroundings were ever all known"


def check_battery_return(state, result):
    """A sense first, then a move and a sense in turn; at each sense one unit used, at each
    move its length; exploring stops with the first sense after which nothing more is to be
    found (then nothing more), or after which the units used and the distance home come to
    BATTERY (then one move onto the start, nothing if the agent stands on it)."""
    steps, home = steps_of(result), state.start_cell
    known = _unknown(state)
    used, here = 0, home
    for index, (kind, c) in enumerate(steps):
        if kind != ("sense" if index % 2 == 0 else "navigate"):
            return f"step {index + 1} was a {kind}: a sense first and after every move, and " \
                   "no other sense"
        if kind == "navigate":
            used, here = used + distance(here, c), c
            continue
        used += 1
        label_sensed(state, known, (kind, c))
        rest = steps[index + 1:]
        if exhausted(state, known):
            return same_steps(rest, [])
        if used + distance(here, home) >= BATTERY:
            return onto(rest, here, [home], "once the reserve was reached")
    return "the exploring ended before the reserve was reached or everything was known"


def check_report_each_goal(state, result):
    """A sense first, then a move and a sense in turn; after each sense away from the start
    that shows a goal no earlier sense showed, the next move onto the start; exploring stops
    with the first sense after which nothing more is to be found, then nothing, or one move
    onto the start if that sense showed a new goal away from it."""
    steps, home = steps_of(result), state.start_cell
    known, seen = _unknown(state), set()
    for index, (kind, c) in enumerate(steps):
        if kind != ("sense" if index % 2 == 0 else "navigate"):
            return f"step {index + 1} was a {kind}: a sense first and after every move, and " \
                   "no other sense"
        if kind == "navigate":
            continue
        label_sensed(state, known, (kind, c))
        new = [g for g in goals_shown(state, c) if g not in seen]
        seen.update(new)
        rest = steps[index + 1:]
        report = [("navigate", home)] if new and c != home else []
        if exhausted(state, known):
            return same_steps(rest, report)
        if report and rest[:1] != report:
            return f"after a new goal came into view at step {index + 1} ran {rest[:2]}, not " \
                   "a move back to the start"
    return "stopped before everything was known"


def check_most_sighted_goal(state, result):
    """Nothing more to find at the end; after the last sense, one move onto a goal shown by as
    many of the senses as any goal (nothing if the agent stands on one)."""
    steps = steps_of(result)
    counts: dict = {}
    for kind, here in steps:
        if kind == "sense":
            for g in goals_shown(state, here):
                counts[g] = counts.get(g, 0) + 1
    most = max(counts.values(), default=0)
    return _after_exploring(state, steps, [g for g, n in counts.items() if n == most])


CREDITS, CREDIT_SCOOP, CREDIT_LEAST = 100, 20, 70  # credits in all; per scoop; grams delivered
ALLOWANCE, ALLOWANCE_STEP, ALLOWANCE_LEAST = 45, 5, 45  # spill allowed: 45 g less 5 g a scoop


def check_scoop_credits(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or n < 1:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if mass >= CREDIT_LEAST and CREDIT_SCOOP * n + spilled <= CREDITS else \
        f"{mass:.1f} g delivered, {spilled:.1f} g spilled after {n} scoops"


def check_shrinking_spill_allowance(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if mass >= ALLOWANCE_LEAST and spilled <= ALLOWANCE - ALLOWANCE_STEP * n else \
        f"{mass:.1f} g delivered, {spilled:.1f} g spilled after {n} scoops"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_S, _S0, _S1 = "start_cell()", "start_cell()[0]", "start_cell()[1]"
_L, _F = "sensed()[-1]", "final_cell()"  # where the last sense was taken; where it ended
_P = "([start_cell()] + moves())"  # the cells stood in: the start, then each move's
# after the last sense: nothing, or one move (the last sense is then the step before it)
_STAY = "primitives()[-1] == 'sense'"
_MOVE = "primitives()[-2:] == ['sense', 'navigate']"
_FRESH = "len(known_before_last()) < len(known_cells())"  # the last step labelled something
_HOME = f"(({_L} == {_S} and {_STAY}) or ({_L} != {_S} and {_MOVE} and {_F} == {_S}))"
# after the sense that first shows a goal: nothing on a goal, else one move onto one it showed
_ONTO_GOAL = f"((steps_after_goal() == 0 and is_goal({_L})) or (steps_after_goal() == 1 and " \
             f"primitives()[-1] == 'navigate' and not is_goal({_L}) and is_goal({_F}) and " \
             f"{_F} in neighbours({_L})))"
# a sense after every move and nowhere else: the steps up to the last sense
_TURNS = "primitives()[:2 * len(sensed()) - 1] == ['sense'] + ['navigate', 'sense'] * " \
         "(len(sensed()) - 1) and sensed()[1:] == moves()[:len(sensed()) - 1]"
_K10, _K20, _K100 = indices(10), indices(20), indices(100)



def _on(x: str) -> str:
    """The cell ``x`` (possibly off the grid) is inside it."""
    return f"(0 <= {x}[0] <= 9 and 0 <= {x}[1] <= 9)"


def _shows(k: str, g: str) -> str:
    """The sense ``k`` (an index of sensed()) shows the cell ``g``."""
    return f"({g} == sensed()[{k}] or {g} in neighbours(sensed()[{k}]))"


# the eight cells around the start, clockwise from the one above; a free diagonal one is known
# (and reachable) when the one before it, or for the last the first too, is free
_RING = f"[({_S0} + a, {_S1} + b) for a, b in [(0, 1), (1, 1), (1, 0), (1, -1), (0, -1), " \
        f"(-1, -1), (-1, 0), (-1, 1)]]"
_RING_SEEN = f"[R[m] for m in {indices(8)} if R[m] in reachable_cells() and (m % 2 == 0 or " \
             f"R[m - 1] in reachable_cells() or (m == 7 and R[0] in reachable_cells()))]"
_N = "(steps_after_goal() // 2)"  # moves of the walk away from the goal
_AWAY = f"(Q[0] + ({_N} + 1) * (Q[0] - g[0]), Q[1] + ({_N} + 1) * (Q[1] - g[1]))"
_RAY = f"({_S0} + (x % 9 + 1) * [0, 1, 0, -1][x // 9], {_S1} + (x % 9 + 1) * [1, 0, -1, 0]" \
       f"[x // 9])"
_RAY_BEFORE = f"({_S0} + m * [0, 1, 0, -1][x // 9], {_S1} + m * [1, 0, -1, 0][x // 9])"
_BEFORE = "any(o == s or o in neighbours(s) for s in sensed()[:-1])"  # o shown before the last
_USED = f"k + 1 + sum([{distance_text('sensed()[m]', 'sensed()[m + 1]')} for m in {_K20}[:k]]) + " \
        f"{distance_text('sensed()[k]', _S)}"  # units used after the sense k, and the way home
_FIRST_SEEN = f"[min([k for k in {_K100}[:len(sensed())] if {_shows('k', 'g')}] + [1000]) " \
              f"for g in reachable_goals()]"  # each reachable goal's first sense (1000: none)
_N_LAST = "(len(sensed()) - 1)"
_AFTER = "(len(primitives()) - 2 * len(sensed()) + 1)"  # steps after the last sense (with _TURNS)

TASKS = [
    _task("clear_start_search", 1, check_clear_start_search,
          "Sense once where you start. If that first look shows no obstacle on any of the "
          "cells right next to you, search for a goal: explore, moving and sensing, and as "
          "soon as a sense shows you a goal, go onto it with one move and stop (onto any of "
          "them if that sense showed several; if you are standing on one, just stop). If your "
          "first look shows an obstacle next to you, stop right there without moving.",
          f"primitives()[:1] == ['sense'] and ((primitives() == ['sense']) if any(is_obstacle(c) "
          f"for c in neighbours({_S})) else (goal_found() and {_ONTO_GOAL}))"),
    _task("ring_around_start", 1, check_ring_around_start,
          "Circle your starting cell. Sense where you start, then go round the eight cells "
          "that surround it -- the four right next to it and the four diagonal to it -- "
          "clockwise from the cell above you: above (j + 1), above-right, right (i + 1), "
          "below-right, below (j - 1), below-left, left (i - 1), above-left. Go onto each with "
          "one move and sense there, but skip any you do not know to be free when you come to "
          "it (outside the grid, an obstacle, or not yet shown by one of your senses). After "
          "the last of the eight, go straight back to your starting cell with one move (if you "
          "skipped all eight, just stop).",
          f"all(sensed() == [{_S}] + {_RING_SEEN} for R in [{_RING}]) and moves() == "
          f"sensed()[1:] + [{_S}][:len(sensed()) - 1] and primitives() == ['sense'] + "
          f"['navigate', 'sense'] * (len(sensed()) - 1) + ['navigate'] * min(1, len(sensed()) - "
          f"1)"),
    _task("follow_passage", 2, check_follow_passage,
          "Follow the passage you are in. Sense where you start, step onto any free cell right "
          "next to you and sense there. Then keep going while there is exactly one way on: if "
          "exactly one of the cells right next to you is free and is not a cell you have stood "
          "in before (your starting cell counts as stood in), step onto it and sense there. "
          "Stop as soon as there is no such cell, or there are two or more of them.",
          f"len(moves()) >= 1 and len(moves()) <= 90 and primitives() == ['sense'] + "
          f"['navigate', 'sense'] * len(moves()) and sensed() == [{_S}] + moves() and moves()[0] "
          f"in neighbours({_S}) and not is_obstacle(moves()[0]) and all((W == [{_P}[k + 1]]) if "
          f"k < len(moves()) else len(W) != 1 for k in {_K100}[1:len(moves()) + 1] for W in "
          f"[[n for n in neighbours({_P}[k]) if not is_obstacle(n) and n not in {_P}[:k + 1]]])"),
    _task("retreat_from_goal", 2, check_retreat_from_goal,
          "Explore until a sense shows you a goal. Do not go to it: back away from it in a "
          "straight line, in the direction from the goal to the cell you sensed it from (if "
          "the goal is right above you, that is down). Walk that way one cell at a time, "
          "sensing after every move, for as long as the next cell that way is inside the grid "
          "and free, and stop when it is not. If that sense showed several goals, back away "
          "from any one of them; if you are standing on a goal, just stop.",
          f"goal_found() and steps_after_goal() % 2 == 0 and primitives()[len(primitives()) - "
          f"steps_after_goal():] == ['navigate', 'sense'] * {_N} and all((steps_after_goal() == "
          f"0) if is_goal(Q) else any(moves_after_goal() == [(Q[0] + k * (Q[0] - g[0]), Q[1] + k "
          f"* (Q[1] - g[1])) for k in {_K10}[1:{_N} + 1]] and {_AWAY} not in reachable_cells() "
          f"for g in neighbours(Q) if is_goal(g)) for Q in [sensed()[len(sensed()) - 1 - {_N}]])"),
    _task("four_ray_lengths", 2, check_four_ray_lengths,
          "Find out how far you could go in a straight line from your start in each of the "
          "four directions. Explore, moving and sensing, until you know every cell on the four "
          "straight lines out of your starting cell -- up (j + 1), right (i + 1), down (j - 1) "
          "and left (i - 1) -- up to and including the first obstacle on each line (a line "
          "with no obstacle must be known all the way to the grid's edge). Stop right after "
          "the sense that completes this.",
          f"primitives()[-1:] == ['sense'] and min([(1 if C in known_cells() else 0) + (1 if C "
          f"in known_before_last() else 0) for x in {indices(36)} for C in [{_RAY}] if "
          f"{_on('C')} and not any(is_obstacle("
          f"{_RAY_BEFORE}) for m in {_K10}[1:x % 9 + 1])]) == 1"),
    _task("column_midpoint", 2, check_column_midpoint,
          "Find the middle of the free stretch of your column. Sense, then walk down (j - 1) "
          "one cell at a time, sensing after every move, while the cell below you is inside "
          "the grid and free. Then walk back up (j + 1) the same way, past your starting cell, "
          "sensing after every move (on cells you sensed before too), while the cell above you "
          "is inside the grid and free. The cells from the lowest to the highest you stood in "
          "make the stretch: finish with one move onto its middle cell -- the lower of the two "
          "middle cells if the stretch has an even number of cells -- and stop (if you are "
          "standing on it, just stop).",
          f"any(primitives() == ['sense'] + ['navigate', 'sense'] * (D + U) + ['navigate'] * "
          f"min(1, U) and moves() == [({_S0}, {_S1} - k) if k <= D else ({_S0}, {_S1} - 2 * D + "
          f"k) for k in {_K20}[1:D + U + 1]] + [({_S0}, {_S1} - D + U // 2)] * min(1, U) and "
          f"({_S1} - D == 0 or is_obstacle(({_S0}, {_S1} - D - 1))) and ({_S1} - D + U == 9 or "
          f"is_obstacle(({_S0}, {_S1} - D + U + 1))) for D in {_K10} for U in {_K10})"),
    _task("two_goal_vantage", 2, check_two_goal_vantage,
          "Explore until there is nothing more to find. Then go with one move to a vantage "
          "point and stop: a cell you can reach from which a single sense would show you two "
          "or more goals (on that cell itself or on the cells right next to it; a goal with "
          "another goal right next to it counts), any of them if there are several. If you "
          "are already standing on one, just stop. If there is no such cell, go back to your "
          "starting cell instead (if you are on it, just stop).",
          f"explored_all() and sensed()[-1:] != [] and all((({_STAY} and {_L} in V) or "
          f"({_MOVE} and {_F} in V and {_L} not in V)) if V != [] else {_HOME} for V in [[c for "
          f"c in reachable_cells() if len([g for g in [c] + neighbours(c) if is_goal(g)]) >= "
          f"2]])"),
    _task("goal_before_clutter", 2, check_goal_before_clutter,
          f"Search for a goal, but give up if the place is too cluttered. Explore, moving and "
          f"sensing. As soon as a sense shows you a goal, go onto it with one move and stop "
          f"(onto any of them if that sense showed several; if you are standing on one, just "
          f"stop). But if your senses have shown you {CLUTTER} different obstacles in all before "
          f"any goal has come into view, stop exploring right after the sense that brings the "
          f"count to {CLUTTER} and go straight back to your starting cell with one move (if you "
          f"are on it, just stop). A sense that shows you a goal and brings the count to "
          f"{CLUTTER} at once counts as finding the goal.",
          f"sensed()[-1:] != [] and len([o for o in known_obstacles() if {_BEFORE}]) < {CLUTTER} "
          f"and ({_ONTO_GOAL} if goal_found() else (len(known_obstacles()) >= {CLUTTER} and "
          f"{_HOME}))"),
    _task("scout_goal_surroundings", 2, check_scout_goal_surroundings,
          "Scout out a goal's surroundings and report back. Explore, moving and sensing, until "
          "you know what some goal and every cell right next to it hold: the goal's own cell "
          "and all of its neighbours inside the grid. Stop exploring right after the sense that "
          "first completes this for a goal, and go straight back to your starting cell with one "
          "move (if you are on it, just stop).",
          f"sensed()[-1:] != [] and max([min([(1 if o in known_cells() else 0) + (1 if {_BEFORE} "
          f"else 0) for o in [g] + neighbours(g)]) for g in reachable_goals()]) == 1 and "
          f"{_HOME}"),
    _task("battery_return", 3, check_battery_return,
          f"Explore on a battery of {BATTERY} units. Each sense uses 1 unit, and each move uses "
          f"1 unit for every step of its length (steps along rows and columns from where it "
          f"starts to where it ends, obstacles ignored). Sense where you start and after every "
          f"move, and at no other time. Keep a reserve for the way home: right after the first "
          f"sense after which the units used so far plus the length of the way home from where "
          f"you stand (in steps along rows and columns) come to {BATTERY} or more, stop "
          f"exploring and go straight back to your starting cell with one move (if you are on "
          f"it, just stop). But if a sense leaves nothing more to find before that, or at that "
          f"same sense, stop right after it where you are.",
          f"len(sensed()) <= {BATTERY} and {_TURNS} and [k for k in {_K20}[:len(sensed())] if "
          f"{_USED} >= {BATTERY}][:1] in ([[], [{_N_LAST}]] if explored_all() else "
          f"[[{_N_LAST}]]) and (({_STAY} and {_FRESH}) if explored_all() else {_HOME})"),
    _task("report_each_goal", 3, check_report_each_goal,
          "Report every goal you find back at your starting cell. Explore, sensing where you "
          "start and after every move, and at no other time. Whenever a sense shows you a goal "
          "that none of your senses had shown before, your next move must take you straight "
          "back to your starting cell (unless that sense was taken there), where you sense "
          "again and carry on exploring. Stop right after the sense that leaves nothing more "
          "to find -- but if that sense showed you a new goal away from your starting cell, "
          "first go back to your starting cell with one move, and stop there.",
          f"len(sensed()) <= 100 and explored_all() and {_TURNS} and max([(0 if f >= {_N_LAST} "
          f"or sensed()[f] == {_S} or sensed()[f + 1] == {_S} else 1000) + (1 if f == {_N_LAST} "
          f"and sensed()[f] != {_S} else 0) for f in {_FIRST_SEEN}]) == {_AFTER} and ({_FRESH} if "
          f"{_AFTER} == 0 else {_F} == {_S})"),
    _task("most_sighted_goal", 3, check_most_sighted_goal,
          "Explore until there is nothing more to find, keeping count of how many of your "
          "senses have shown you each goal (on the cell you sensed from or right next to it). "
          "Then go with one move onto the goal the most of your senses showed you (any of them "
          "if several tie) and stop; if you are standing on it, just stop.",
          f"explored_all() and sensed()[-1:] != [] and all(({_STAY} and (X[-1][0], {_L}) in X) "
          f"or ({_MOVE} and (X[-1][0], {_F}) in X and (X[-1][0], {_L}) not in X) for X in "
          f"[sorted([(len([s for s in sensed() if g == s or g in neighbours(s)]), g) for g in "
          f"reachable_goals()])])"),
    _task("scoop_credits", 2, check_scoop_credits,
          f"You have {CREDITS} credits to spend. Every scoop costs {CREDIT_SCOOP} credits and "
          f"every gram of grains you spill outside the containers costs 1 credit. Scoop at "
          f"least once, get at least {CREDIT_LEAST} grams of grains into the receiver, and stop "
          f"having spent no more than your {CREDITS} credits.",
          f"scoops() >= 1 and delivered() >= {CREDIT_LEAST} and {CREDIT_SCOOP} * scoops() + "
          f"spilled() <= {CREDITS}", SCOOP),
    _task("shrinking_spill_allowance", 2, check_shrinking_spill_allowance,
          f"Scoop one to five times, then stop, with at least {ALLOWANCE_LEAST} grams of grains "
          f"in the receiver. The more scoops you make, the less you may spill outside the "
          f"containers in all: at most {ALLOWANCE - ALLOWANCE_STEP} grams after one scoop, "
          f"{ALLOWANCE - 2 * ALLOWANCE_STEP} after two, {ALLOWANCE - 3 * ALLOWANCE_STEP} after "
          f"three, {ALLOWANCE - 4 * ALLOWANCE_STEP} after four and "
          f"{ALLOWANCE - 5 * ALLOWANCE_STEP} after five ({ALLOWANCE} grams less "
          f"{ALLOWANCE_STEP} for every scoop).",
          f"scoops() >= 1 and scoops() <= 5 and delivered() >= {ALLOWANCE_LEAST} and spilled() "
          f"<= {ALLOWANCE} - {ALLOWANCE_STEP} * scoops()", SCOOP),
]
