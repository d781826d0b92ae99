"""Held-out tasks, eleventh set: written before the next change of the synthesizer, run once after.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout11/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (a step whose direction a count picks,
up, right, down or left for 0, 1, 2 or 3 obstacles next to the start; a fixed manoeuvre round the
cell to the right of the start, up, right and down, given up for home at the first blocked move; a
move onto a free cell the first sense showed and the second did not; a fixed route, up, up, right,
right, down, down, whose blocked steps are skipped; once a goal is in view, onto it only if it lies
above the start's row, else home; once a goal is in view, back to the cell stood in three moves
before; exploring that stops at the first place away from the start with as many obstacles next to
it as the start has; two more moves and senses after a goal comes into view, then onto it; once a
goal is in view, home and one step from there towards it; a walk up that peeks into the cell left
of every cell on the way; a walk right that goes round obstacles over the top; after exploring, a
shuttle between two goals) and two scooping tasks (at least 100 g delivered in at most five scoops
and no more than 50 g for every scoop made; two or three scoops that deliver at least 45 g and take
at most 125 g out of the donor, delivered and spilled together). Each has a reference behavior
(``references/``), a ground-truth ``check`` and a faithful ``promise`` over the env's outcome
helpers, so that the search can be measured apart from the model. They were written on 2026-12-06
blind: without reading the search's code and without running the synthesizer on them; the first
run of the search on them is the evaluation, reported beside the development figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a *row* is the
cells of one j, and a row is *above* another when its j is larger; a sense labels its cell and the
four around it (it *shows* them; a goal *comes into view* with the first sense that shows it); the
cells *next to* a cell are its four neighbours inside the grid, and the obstacles next to it are
those among them (the grid's edge does not count); a cell *stood in* is the start cell or one a
move ended in, and the cell stood in *three moves before* is the one the agent stood in before its
last three moves (the start when it made fewer); the *distance* of two cells counts steps along
rows and columns (|di| + |dj|), obstacles ignored; a step of a route or of a walk is *blocked* when
the cell it leads to is outside the grid or an obstacle. The start cell always has a free neighbour
(a goal is reachable from it and it holds none), so at most three obstacles are next to it. The
promises' language allows three comprehension loops in one expression and 400 syntax nodes: where a
promise needs indices 0..n - 1 it writes them out (route_skip_blocked's promise reads the route's
27 outcomes, how many of its two steps up, right and down were made, from the indices 0..26), and
walks are bounded by what the grid allows (side_peek_walk's promise reads up to 29 moves,
right_around_obstacles' 30 and home_like_spot's 100 senses; the references never made more than 22,
16 and 61). The scooping checks weigh the grains at the end, as ``delivered()`` and ``spilled()``
do: those in the receiver, and those outside the receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all. On those episodes the tasks'
branches came up: 0, 1, 2 and 3 obstacles next to the start 86, 132, 65 and 17 times, the step
taken 198, its cell blocked 102; the manoeuvre with no move (the cell above blocked) 106, given up
for home after one move 72 and after two 40, done 82; another free cell next to the start 271, none
and back 29; the route with 0 to 6 of its steps skipped 20, 43, 103, 65, 44, 14 and 11 times; a
goal in view before any move 41 (every goal task below shares this exploring), then onto a goal
above the start's row 139, home 136, already home with none above 25 (two goals in one sense 6); the
look-back target the start 99 (41 of them standing on it), an earlier cell 201; the start's
obstacle count matched after 1 to 60 moves 298, nothing more to find first 2; after the two more
looks onto the goal 298, already on it 2; home and a step towards the goal 240, the goal in view
from the start and the step taken there (onto the goal, next to the start) 41, home and no free
nearer cell 19; the walk up with 0 to 8 moves up (none 106), 0 to 7 peeks (none 59, one from the
start 201), up to 22 moves; the walk right with 0 to 4 climbs over obstacles (one or more 139),
back down into its own row 44 times, ending at the right edge 105, blocked in its own row 82 and in
the row above 113, up to 16 moves; the shuttle's reachable goals 1, 2 and 3 21, 61 and 218 times,
the last sense on a goal 17. Faithfulness on behaviors that do not do the tasks: every grid promise
was judged against the behaviors written for it (71 near misses -- other directions, routes,
orders, counts, comparisons or places to go back to, a missing or extra sense or move, one step
late -- and 8 other ways of doing the tasks, other explorers or other choices where a task allows
any) on episodes 0-99 of seeds 0 and 1 (15,800 judged episodes), against the other 11 references
of this set and the 134 grid references of the development and earlier held-out sets (heldout10's
included) on episodes 0-49 of seed 0 (87,000 judged episodes), and against 3 trivial behaviors
(stop at once, judged on the reset; sense once; navigate onto the cell it stands in) on episodes
0-99 of seeds 0 and 1: on every judged episode the promise's verdict equalled the check's. Keep
rates of the trivial behaviors: stopping at once and navigating onto the cell it stands in keep no
promise on any episode; sensing once keeps none but obstacle_count_direction's (65 of 200: the
counted direction blocked), up_over_and_down's (70: the cell above blocked), route_skip_blocked's
(6: above, right and below blocked), goal_above_or_home's (19: a goal in view from the start, none
above its row), lookback_three's (29: a goal in view from the start), side_peek_walk's (20: left and
above blocked) and right_around_obstacles' (26: the right edge, or an obstacle on the right and the
cell above blocked), where the task asks for the one sense. The scooping references (five and two
scoops from the default sensing pose) were run on episodes 0-19 of seed 0 only (3 to 8 s an
episode) and kept their promises and did their tasks on all 20: five scoops left 124.4 to 221.7 g
in the receiver (100 to 250 g allowed: margins 24.4 and 28.3 g); two scoops delivered 58.8 to
97.3 g (45 g needed) and took 65.6 to 108.6 g out of the donor (125 g allowed). Near misses on
episodes 0-9: one scoop (33.9 to 54.3 g) kept no spare_the_donor promise; two scoops (61.1 to
97.3 g) kept no gentle_scoops promise; three scoops (88.2 to 133.5 g delivered, 92.7 to 149.3 g
out of the donor) kept gentle_scoops' on 6 and spare_the_donor's on 6; four scoops (104.0 to
171.9 g) kept gentle_scoops' on all 10; the check agreed on every judged episode. The cap of 50 g a
scoop decided no verdict on these runs (two or more scoops never averaged more than 48.7 g a
scoop): it is there for a behavior that fills faster.
"""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (cell, distance, exhausted, first_goal_sense, free_cell,
                                        free_neighbours, grams_in_receiver, grams_spilled,
                                        held_out_task, indices, label_sensed, obstacles_beside,
                                        on_grid, reachable, same_steps, scoops, sensed_cells,
                                        step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP, DOWN = (1, 0), (-1, 0), (0, 1), (0, -1)




def _goal_seen(state, result):
    """The index of the sense that first showed a goal, the cell it was taken in, the goals it
    showed and the steps after it; None (with why) when no sense showed one."""
    steps = steps_of(result)
    index = first_goal_sense(state, result)
    if index is None:
        return None, "no goal seen"
    here = steps[index][1]
    goals = [g for g in sensed_cells(state, here) if state.truth[g] == GOAL]
    return (index, here, goals, steps[index + 1:]), None


def _peek(state, steps):
    """The cell of a (sense, move onto a free cell next to the start, sense there) opening, or
    None (with why) when the steps do not begin so."""
    home = state.start_cell
    if len(steps) < 3 or steps[0] != ("sense", home) or steps[1][0] != "navigate" \
            or steps[1][1] not in free_neighbours(state, home) or steps[2] != ("sense", steps[1][1]):
        return None, f"ran {steps[:4]}, not a sense, a move onto a free cell next to the " \
                     "start and a sense there"
    return steps[1][1], None


# --- checks -------------------------------------------------------------------------------

def check_obstacle_count_direction(state, result):
    """One sense; then one move up, right, down or left for 0, 1, 2 or 3 obstacles next to the
    start, if that cell is inside the grid and free, else nothing more."""
    home = state.start_cell
    way = (UP, RIGHT, DOWN, LEFT)[min(3, obstacles_beside(state, home))]
    target = step_by(home, way)
    plan = [("sense", home)] + ([("navigate", target)] if free_cell(state, target) else [])
    return same_steps(steps_of(result), plan)


def check_up_over_and_down(state, result):
    """Sense; up, right, down, each move followed by a sense, while the next cell is inside the
    grid and free; at the first that is not, a move back onto the start if the agent moved."""
    home = state.start_cell
    plan, here = [("sense", home)], home
    for way in (UP, RIGHT, DOWN):
        nxt = step_by(here, way)
        if not free_cell(state, nxt):
            if here != home:
                plan.append(("navigate", home))
            break
        here = nxt
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_seen_first_only(state, result):
    """Sense, a move onto a free cell next to the start, a sense there; then one move onto
    another free cell next to the start (what the first sense showed and the second did not),
    or onto the start if there is none."""
    steps = steps_of(result)
    spot, why = _peek(state, steps)
    if spot is None:
        return why
    others = [n for n in free_neighbours(state, state.start_cell) if n != spot]
    rest = steps[3:]
    if not others:
        return same_steps(rest, [("navigate", state.start_cell)])
    if len(rest) == 1 and rest[0][0] == "navigate" and rest[0][1] in others:
        return None
    return f"after the two senses ran {rest[:4]}, not one move onto one of {others}"


ROUTE = (UP, UP, RIGHT, RIGHT, DOWN, DOWN)


def check_route_skip_blocked(state, result):
    """Sense; the route up, up, right, right, down, down from the start, each step a move and a
    sense if the cell it leads to is inside the grid and free, skipped if not."""
    here = state.start_cell
    plan = [("sense", here)]
    for way in ROUTE:
        nxt = step_by(here, way)
        if free_cell(state, nxt):
            here = nxt
            plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_goal_above_or_home(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed in a row above
    the start's (nothing if the agent stands on one); if it showed none there, one move onto
    the start (nothing if the agent stands on it)."""
    seen, why = _goal_seen(state, result)
    if seen is None:
        return why
    _, here, goals, rest = seen
    home = state.start_cell
    above = [g for g in goals if g[1] > home[1]]
    if not above:
        return same_steps(rest, [] if here == home else [("navigate", home)])
    if here in above:
        return same_steps(rest, [])
    if len(rest) == 1 and rest[0][0] == "navigate" and rest[0][1] in above:
        return None
    return f"after the goal came into view ran {rest[:4]}, not one move onto one of {above}"


def check_lookback_three(state, result):
    """After the sense that first shows a goal: one move onto the cell stood in three moves
    before (the start if fewer moves came before), or nothing if the agent stands on it."""
    seen, why = _goal_seen(state, result)
    if seen is None:
        return why
    index, here, _, rest = seen
    stood = [state.start_cell] + [c for kind, c in steps_of(result)[:index] if kind == "navigate"]
    target = stood[max(0, len(stood) - 4)]
    return same_steps(rest, [] if here == target else [("navigate", target)])


def check_home_like_spot(state, result):
    """Exploring stops with the first sense away from the start whose cell has as many
    obstacles next to it as the start has, or with the sense after which nothing more is to be
    found, whichever comes first."""
    steps, home = steps_of(result), state.start_cell
    count = obstacles_beside(state, home)
    known = state.truth != state.truth
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] != "sense":
            continue
        if (step[1] != home and obstacles_beside(state, step[1]) == count) or exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return "no sense away from the start matched it, and more could be found"


def check_two_more_looks_then_goal(state, result):
    """After the sense that first shows a goal: a move onto a cell other than the agent's and a
    sense there, twice; then one move onto a goal the first sense showed, or nothing if the
    agent stands on one."""
    seen, why = _goal_seen(state, result)
    if seen is None:
        return why
    _, here, goals, rest = seen
    if len(rest) < 4 or rest[0][0] != "navigate" or rest[0][1] == here \
            or rest[1] != ("sense", rest[0][1]) or rest[2][0] != "navigate" \
            or rest[2][1] == rest[0][1] or rest[3] != ("sense", rest[2][1]):
        return f"after the goal came into view ran {rest[:4]}, not two (move, sense) pairs"
    last, tail = rest[3][1], rest[4:]
    if last in goals:
        return same_steps(tail, [])
    if len(tail) == 1 and tail[0][0] == "navigate" and tail[0][1] in goals:
        return None
    return f"after the two looks ran {tail[:4]}, not one move onto one of {goals}"


def check_home_then_point(state, result):
    """After the sense that first shows a goal: a move onto the start unless the agent stands
    on it; then a move onto a free cell next to the start nearer than the start to a goal that
    sense showed, or nothing if there is no such cell."""
    seen, why = _goal_seen(state, result)
    if seen is None:
        return why
    _, here, goals, rest = seen
    home = state.start_cell
    back = [] if here == home else [("navigate", home)]
    if rest[:len(back)] != back:
        return f"after the goal came into view ran {rest[:4]}, not a move onto the start first"
    tail = rest[len(back):]
    for goal in goals:
        toward = [n for n in free_neighbours(state, home)
                  if distance(n, goal) < distance(home, goal)]
        if (not toward and tail == []) or (len(tail) == 1 and tail[0][0] == "navigate"
                                           and tail[0][1] in toward):
            return None
    return f"at the start ran {tail[:4]}, not a step towards one of {goals}"


def check_side_peek_walk(state, result):
    """Sense; then, on the start and on every cell the walk up reaches: a move onto the cell on
    its left, a sense there and a move back if that cell is free; a move up and a sense there
    if the cell above is inside the grid and free, else the end."""
    here = state.start_cell
    plan = [("sense", here)]
    while True:
        side = step_by(here, LEFT)
        if free_cell(state, side):
            plan += [("navigate", side), ("sense", side), ("navigate", here)]
        if not free_cell(state, step_by(here, UP)):
            break
        here = step_by(here, UP)
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_right_around_obstacles(state, result):
    """Sense; walk right along the start's row, each move followed by a sense; where the cell
    to the right is an obstacle, a move up (if free), then moves right along the row above (at
    least one) until the cell below is free, and a move down onto it; the end where a needed
    cell is outside the grid or an obstacle, or at the right edge in the start's row."""
    here = state.start_cell
    plan, mode = [("sense", here)], "row"  # "row", "up" (just stepped up), "over" (moved right)
    while True:
        right, up, down = step_by(here, RIGHT), step_by(here, UP), step_by(here, DOWN)
        if mode == "row":
            if free_cell(state, right):
                nxt = right
            elif on_grid(state, right) and free_cell(state, up):
                nxt, mode = up, "up"
            else:
                break
        elif mode == "up":
            if not free_cell(state, right):
                break
            nxt, mode = right, "over"
        elif free_cell(state, down):
            nxt, mode = down, "row"
        elif free_cell(state, right):
            nxt = right
        else:
            break
        here = nxt
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_goal_shuttle(state, result):
    """Nothing more to find at the end; after the last sense only moves: four alternating
    between two different reachable goals, the first not the cell of the last sense, if there
    are two or more; else one onto the goal, or nothing if the agent stands on it."""
    steps = steps_of(result)
    if not exhausted(state):
        return "stopped before everything was known"
    senses = [k for k, (kind, _) in enumerate(steps) if kind == "sense"]
    if not senses:
        return "never sensed"
    here, rest = steps[senses[-1]][1], steps[senses[-1] + 1:]
    goals = [cell(c) for c in zip(*(reachable(state) & (state.truth == GOAL)).nonzero())]
    if len(goals) == 1:
        return same_steps(rest, [] if here == goals[0] else [("navigate", goals[0])])
    if len(rest) == 4 and all(kind == "navigate" for kind, _ in rest):
        a, b = rest[0][1], rest[1][1]
        if a != b and a in goals and b in goals and a != here \
                and [c for _, c in rest] == [a, b, a, b]:
            return None
    return f"after the last sense ran {rest[:6]}, not a shuttle between two of {goals}"


GENTLE_LEAST, GENTLE_EACH = 100, 50  # grams in the receiver at least; at most per scoop made
DONOR_LEAST, DONOR_MOST = 45, 125  # grams delivered at least; grams out of the donor at most


def check_gentle_scoops(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass = grams_in_receiver(state)
    return None if GENTLE_LEAST <= mass <= GENTLE_EACH * n else \
        f"{mass:.1f} g in the receiver after {n} scoops"


def check_spare_the_donor(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or n not in (2, 3):
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if mass >= DONOR_LEAST and mass + spilled <= DONOR_MOST else \
        f"{mass:.1f} g delivered, {spilled:.1f} g spilled after {n} scoops"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)




# The promises' language allows at most 3 comprehension loops in one expression: these are
# written to stay within that.
_S, _S0, _S1 = "start_cell()", "start_cell()[0]", "start_cell()[1]"
_LINE = "primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and " \
        "sensed() == [start_cell()] + moves()"
_FRESH = "len(known_before_last()) < len(known_cells())"  # the last step labelled something
_M0 = "moves()[0]"
_PEEK = "primitives()[:3] == ['sense', 'navigate', 'sense'] and sensed() == [start_cell(), " \
        "moves()[0]] and moves()[0] in neighbours(start_cell()) and not " \
        "is_obstacle(moves()[0]) and len(primitives()) == 2 + len(moves())"
_L = "sensed()[-1]"  # where the last sense was taken
_P = "([start_cell()] + moves())"  # the cells stood in: the start, then each move's


def _open(x: str, of: str = _S) -> str:
    """``x``, a cell next to ``of`` or off the grid, is inside the grid and free."""
    return f"({x} in neighbours({of}) and not is_obstacle({x}))"


def _dist(a: str, b: str) -> str:
    return f"(abs({a}[0] - {b}[0]) + abs({a}[1] - {b}[1]))"


def _crowd_of(c: str, o: str = "o") -> str:
    """How many obstacles are next to ``c`` (one comprehension loop, over ``o``)."""
    return f"len([{o} for {o} in neighbours({c}) if is_obstacle({o})])"


def _shut(x: str, y: str, edge: str) -> str:
    """The cell (x, y), one step off a cell of the grid, is outside it (``edge`` says when) or
    an obstacle."""
    return f"({edge} or is_obstacle(({x}, {y})))"


# the route's cells after a moves up, b right and c down from the start (s, t)
_ROUTE = "[(s, t + 1), (s, t + 2)][:a] + [(s + 1, t + a), (s + 2, t + a)][:b] + " \
         "[(s + b, t + a - 1), (s + b, t + a - 2)][:c]"
_QR, _QU, _QD, _QL = "(q[0] + 1, q[1])", "(q[0], q[1] + 1)", "(q[0], q[1] - 1)", "(q[0] - 1, q[1])"
_TOWARD = f"[c for c in neighbours({_S}) if not is_obstacle(c) and {_dist('c', 'g')} < " \
          f"{_dist(_S, 'g')}]"

TASKS = [
    _task("obstacle_count_direction", 1, check_obstacle_count_direction,
          "Sense once where you start and count the obstacles on the cells right next to you "
          "(the grid's edge does not count). Let that count pick your direction: with no "
          "obstacle step up (j + 1), with one step right (i + 1), with two step down (j - 1), "
          "with three or more step left (i - 1). Take that one step if the cell is inside the "
          "grid and free; if it is not, stay where you are. Then stop.",
          f"sensed() == [{_S}] and all(primitives() == ['sense'] + ['navigate'] * len(moves()) "
          f"and moves() == ([c] if {_open('c')} else []) for n in [min(3, {_crowd_of(_S)})] "
          f"for c in [[({_S0}, {_S1} + 1), ({_S0} + 1, {_S1}), ({_S0}, {_S1} - 1), ({_S0} - 1, "
          f"{_S1})][n]])"),
    _task("up_over_and_down", 1, check_up_over_and_down,
          "Go round the cell to your right by way of the cell above it. Sense where you start, "
          "then move up (j + 1), then right (i + 1), then down (j - 1), one cell at a time, "
          "sensing after each move; you end on the cell just right of your start. If the next "
          "of these three moves would take you outside the grid or onto an obstacle, do not "
          "make it: go straight back to your starting cell with one move and stop (if you have "
          "not moved yet, just stop).",
          f"all(primitives() == ['sense'] + ['navigate', 'sense'] * k + ['navigate'] * (1 if 0 "
          f"< k < 3 else 0) and sensed() == [{_S}] + W[:k] and moves() == W[:k] + ([{_S}] if 0 "
          f"< k < 3 else []) and (k == 3 or not {_open('W[k]', 'P[k]')}) for k in [len(sensed()) "
          f"- 1] for W, P in [([({_S0}, {_S1} + 1), ({_S0} + 1, {_S1} + 1), ({_S0} + 1, {_S1})], "
          f"[{_S}, ({_S0}, {_S1} + 1), ({_S0} + 1, {_S1} + 1)])])"),
    _task("seen_first_only", 1, check_seen_first_only,
          "Sense where you start, step onto any free cell next to you and sense again. Then go "
          "with one move to a free cell that your first sense showed you but your second did "
          "not (any of them if there are several), and stop. If there is no such cell, go "
          "straight back to your starting cell and stop.",
          f"{_PEEK} and len(moves()) == 2 and all(moves()[1] in O if O != [] else moves()[1] == "
          f"{_S} for O in [[c for c in neighbours({_S}) if c != {_M0} and not is_obstacle(c)]])"),
    _task("route_skip_blocked", 2, check_route_skip_blocked,
          "Follow a fixed route from your start, one cell per step: up, up, right, right, "
          "down, down (up is j + 1, right i + 1, down j - 1). Sense where you start and after "
          "every move. Before each step of the route, look at the cell it leads to: if that "
          "cell is outside the grid or an obstacle, skip the step and go on with the next one "
          "from where you stand. Stop when the route is done.",
          f"{_LINE} and any(moves() == {_ROUTE} and (a == 2 or "
          f"{_shut('s', 't + a + 1', 't + a == 9')}) and (b == 2 or "
          f"{_shut('s + b + 1', 't + a', 's + b == 9')}) and (c == 2 or "
          f"{_shut('s + b', 't + a - c - 1', 't + a - c == 0')}) for s, t in [{_S}] for a, b, c in "
          f"[(x // 9, x // 3 % 3, x % 3) for x in {indices(27)}])"),
    _task("goal_above_or_home", 2, check_goal_above_or_home,
          "Explore until a sense shows you a goal. If that goal lies in a row above the one "
          "you started in (its j is larger than your starting cell's), go onto it with one "
          "move and stop. If it does not, leave it and go straight back to your starting cell "
          "with one move, and stop. If that sense showed several goals, go onto one above your "
          "starting row if there is one, and go back only if none is. If you are already "
          "standing on the cell you would go to, just stop.",
          f"goal_found() and sensed()[-1:] != [] and all(((steps_after_goal() == 0 and {_L} in "
          f"U) or (steps_after_goal() == 1 and primitives()[-1] == 'navigate' and moves()[-1] in "
          f"U and {_L} not in U)) if U != [] else (steps_after_goal() == (0 if {_L} == {_S} else "
          f"1) and final_cell() == {_S} and ({_L} == {_S} or primitives()[-1] == 'navigate')) "
          f"for U in [[g for g in [{_L}] + neighbours({_L}) if is_goal(g) and g[1] > {_S1}]])"),
    _task("lookback_three", 2, check_lookback_three,
          "Explore until a sense shows you a goal. Do not go to it: back off instead to the "
          "cell you stood in three moves earlier, the cell you were in before your last three "
          "moves, with one move, and stop. If you had made fewer than three moves, go back to "
          "your starting cell instead. If you are already standing on that cell, just stop.",
          f"goal_found() and sensed()[-1:] != [] and all((steps_after_goal() == 0 and t == {_L}) "
          f"or (steps_after_goal() == 1 and primitives()[-1] == 'navigate' and moves()[-1] == t "
          f"and t != {_L}) for t in [{_P}[max(0, len(moves()) - steps_after_goal() - 3)]])"),
    _task("home_like_spot", 2, check_home_like_spot,
          "Note how many obstacles are right next to your starting cell (the grid's edge does "
          "not count). Then explore, moving and sensing, and stop right after the first sense "
          "taken anywhere but your starting cell that shows the same number of obstacles right "
          "next to the cell you sense from. If there is nothing more to find before that "
          "happens, stop right after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and len(sensed()) <= 100 and (not explored_all() or "
          f"{_FRESH}) and [k for k in {indices(100)}[:len(sensed())] if sensed()[k] != {_S} and "
          f"{_crowd_of('sensed()[k]')} == {_crowd_of(_S, 'x')}][:1] in [[len(sensed()) - 1]] + "
          f"([[]] if explored_all() else [])"),
    _task("two_more_looks_then_goal", 2, check_two_more_looks_then_goal,
          "Explore until a sense shows you a goal. Do not go to it yet: first look around a "
          "little more, with two more moves, each onto a free cell other than the one you stand "
          "on, sensing after each. Then go onto that goal -- the one the first sense showed "
          "you, any of them if it showed several -- with one move and stop; if you are "
          "standing on it already, just stop.",
          f"goal_found() and steps_after_goal() in [4, 5] and primitives()[-steps_after_goal():] "
          f"== ['navigate', 'sense', 'navigate', 'sense', 'navigate'][:steps_after_goal()] and "
          f"all(a != L and b != a and any((b == g) if steps_after_goal() == 4 else (moves()[-1] "
          f"== g and b != g) for g in [L] + neighbours(L) if is_goal(g)) for L, a, b in "
          f"[(sensed()[-3], sensed()[-2], sensed()[-1])])"),
    _task("home_then_point", 3, check_home_then_point,
          "Explore until a sense shows you a goal. Do not go to it: go straight back to your "
          "starting cell with one move (unless you are on it), and from there take one step "
          "towards the goal -- onto a free cell next to your start that is nearer to the goal "
          "than your start is, counting steps along rows and columns and ignoring obstacles "
          "(any such cell; if that sense showed several goals, towards any one of them). If no "
          "cell next to your start is both free and nearer, stay on your start. Then stop.",
          f"goal_found() and sensed()[-1:] != [] and steps_after_goal() == "
          f"len(moves_after_goal()) and any(moves_after_goal() == ([] if {_L} == {_S} else "
          f"[{_S}]) + moves()[len(moves()) - len(T[:1]):] and (T == [] or moves()[-1] in T) for "
          f"g in [{_L}] + neighbours({_L}) if is_goal(g) for T in [{_TOWARD}])"),
    _task("side_peek_walk", 3, check_side_peek_walk,
          "Walk up and peek to your left along the way. Sense, then walk up (j + 1) one cell at "
          "a time, sensing after every move, while the cell above you is inside the grid and "
          "free. On every cell of this walk, your starting cell included, peek left before you "
          "go on: if the cell to your left (i - 1) is inside the grid and free, step onto it, "
          "sense there and step straight back, without sensing again, before you move up. "
          "Stop when you cannot go up any further (after the peek from the last cell, if it has "
          "one).",
          f"len(moves()) <= 29 and sensed() == [{_S}] + "
          f"[moves()[k] for k in "
          f"{indices(29)}[:len(moves())] if moves()[k][0] <= {_P}[k][0]] and all(moves()[k:k + 1] == "
          f"([{_QR}] if q[0] < {_S0} else ([{_QL}] if (k == 0 or {_P}[k - 1] != {_QL}) and "
          f"{_open(_QL, 'q')} else ([{_QU}] if {_open(_QU, 'q')} else []))) for k in "
          f"{indices(30)}[:len(moves()) + 1] for q in [{_P}[k]])"),
    _task("right_around_obstacles", 3, check_right_around_obstacles,
          "Walk right along your row, going round obstacles over the top. Sense, then walk "
          "right (i + 1) one cell at a time, sensing after every move. When the cell to your "
          "right is an obstacle, step up (j + 1), then move right along that upper row, at "
          "least one cell and sensing after every move, until the cell below you is free; step "
          "down onto it and carry on walking right in your own row. Stop when a move you need "
          "is blocked by an obstacle or the grid's edge -- the step up, or a move right along "
          "the upper row -- and when you reach the right edge of the grid in your own row.",
          f"{_LINE} and len(moves()) <= 30 and all([c for c in ((([{_QR}, {_QU}] if q[0] < 9 "
          f"else []) if q[1] == {_S1} else ([{_QR}] if sensed()[k - 1][1] < q[1] else [{_QD}, "
          f"{_QR}]))) if {_open('c', 'q')}][:1] == moves()[k:k + 1] for k in "
          f"{indices(31)}[:len(moves()) + 1] for q in [sensed()[k]])"),
    _task("goal_shuttle", 3, check_goal_shuttle,
          "Explore until there is nothing more to find. Then, without sensing again, shuttle "
          "between two of the goals you found: four moves, alternating between the two, the "
          "first onto one you are not standing on, and stop. If you found only one goal, go "
          "onto it with one move and stop (if you are standing on it, just stop).",
          f"sensed()[-1:] != [] and explored_all() and all((len(G) >= 2 and primitives()[-5:] "
          f"== ['sense', 'navigate', 'navigate', 'navigate', 'navigate'] and moves()[-4:] == "
          f"[moves()[-4], moves()[-3]] * 2 and moves()[-4] != moves()[-3] and moves()[-4] in G "
          f"and moves()[-3] in G and moves()[-4] != {_L}) or (G == [{_L}] and "
          f"primitives()[-1] == 'sense') or (len(G) == 1 and G != [{_L}] and primitives()[-2:] "
          f"== ['sense', 'navigate'] and moves()[-1] == G[0]) for G in [reachable_goals()])"),
    _task("gentle_scoops", 2, check_gentle_scoops,
          f"Fill the receiver gently: make at most five scoops, so that it ends up holding at "
          f"least {GENTLE_LEAST} grams of grains but no more than {GENTLE_EACH} grams for every "
          f"scoop you made (at most {2 * GENTLE_EACH} g after two scoops, {3 * GENTLE_EACH} g "
          f"after three, and so on), then stop.",
          f"scoops() >= 1 and scoops() <= 5 and delivered() >= {GENTLE_LEAST} and delivered() "
          f"<= {GENTLE_EACH} * scoops()", SCOOP),
    _task("spare_the_donor", 1, check_spare_the_donor,
          f"Scoop two or three times, then stop. Get at least {DONOR_LEAST} grams of grains "
          f"into the receiver, but take no more than {DONOR_MOST} grams out of the donor in "
          f"all: what ends up in the receiver plus what is spilled outside the containers.",
          f"scoops() >= 2 and scoops() <= 3 and delivered() >= {DONOR_LEAST} and delivered() + "
          f"spilled() <= {DONOR_MOST}", SCOOP),
]
