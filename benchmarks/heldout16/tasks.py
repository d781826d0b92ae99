"""Held-out tasks, sixteenth set: written before the next change of the synthesizer, run once after
it.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout16/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (exploring that stops once a corner cell of
the grid is known; a walk right that stops on the first cell with an obstacle right below it;
exploring that stops at the third sense that shows an obstacle next to the agent; once a goal is in
view, home if that same sense showed an obstacle, else onto the goal; once a goal is in view, back
to the first place whose sense showed no obstacle; once a goal is in view, back to the highest
place sensed from; once a goal is in view, onto the known free cell farthest from it; onto the goal,
then onto its mirror image through the start if known free, else home; after exploring, a tour of
the goals farthest from the start first; onto the goal, then a walk along its row away from the
start's column; once a goal is in view, onto a known free cell two steps from it; a walk down that
comes home only if it made fewer than three moves) and two scooping tasks (two to four scoops that
land at least 75% of the grains moved, delivered and spilled together, and at least 50 g; one to
five scoops scoring at least 45, the grams delivered counted up to 100 g less the grams spilled).
Each has a reference behavior (``references/``), a ground-truth ``check`` and a faithful
``promise`` over the env's outcome helpers, so that the search can be measured apart from the
model. They were written on 2026-12-07 blind: without reading the search's code and without running
the synthesizer on them; the first run of the search on them is the evaluation, reported beside the
development figures.

Close relatives of earlier tasks: corner_in_sight_stop of heldout2's reachable_corner (the corners;
there reached, here only known) and heldout8's ten_free_cells_known (a stop on what is known);
right_until_ledge of heldout5's down_until_side_wall and heldout10's up_until_second_opening (a walk
that stops on what lies beside it; here below, and the start does not count); third_obstacle_look
of heldout6's three_clear_looks (a count of senses; here of those that show an obstacle) and the
development find_3_obstacles (obstacles, not senses); clutter_turns_home of heldout13's
goal_before_clutter and heldout12's obstacle_parity_goal (goal or home on what was seen; here the
goal sense alone); first_clear_look_return of heldout10's back_to_second_look and heldout15's
last_new_obstacle_spot (back to a remembered place; here the first clear one); far_from_goal_cell
of heldout5's goal_then_farthest_look (there from the goal, among the places sensed from; here
without going onto it, among the known free cells) and heldout2's farthest_known_cell (from the
start); goal_mirror_through_start of heldout8's mirror_step (a neighbour mirrored through the start)
and heldout11's home_then_point; farthest_first_goal_tour of heldout9's nearest_first_goal_tour and
heldout4's explore_then_goal_tour (tours after exploring; here farthest from the start first);
onward_from_goal of heldout4's goal_then_right_walk (there always right) and heldout13's
retreat_from_goal (a walk away from the goal; here away from the start's column);
two_steps_off_goal of heldout2's beside_goal (next to a goal) and heldout10's halfway_cell;
short_walk_home of heldout9's left_wall_return (home on how the walk ended; here on its length) and
heldout2's down_three_or_blocked; landed_share of heldout12's spill_under_average_scoop and
heldout8's low_spill_per_scoop (spill against delivery; here a share of what was moved);
capped_credit of heldout14's scoop_points and heldout8's capped_fill (points for grams, and a top;
here grams past the top earn nothing, and cost nothing). highest_look_after_goal is of the family
of heldout5's goal_then_farthest_look (back to a place sensed from, picked by a comparison) with a
rule none of them has.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a cell is
*blocked* when it is an obstacle or outside the grid; the *corners* are (0, 0), (0, 9), (9, 0) and
(9, 9); a sense labels its cell and the four around it (it *shows* them; a goal *comes into view*
with the first sense that shows it); the obstacles *next to* a cell are those among its four
neighbours inside the grid (the grid's edge does not count), and a sense *shows an obstacle* when
its cell has one next to it (its own cell never holds one); a cell has an obstacle *right below* it
when the cell down from it is an obstacle (the bottom edge is not one); the *highest* places have
the largest j; the *distance* of two cells counts steps along rows and columns (|di| + |dj|),
obstacles ignored, and *farthest* by it; the *mirror image* of a goal (i, j) through the start
(a, b) is (2 a - i, 2 b - j); a walk's *moves* are the navigate steps it made. The start cell
always has a free neighbour (a goal is reachable from it and it holds none); the references only
move onto cells they know, so none ever stood on a goal when it first came into view. The
promises' language allows three comprehension loops in one expression, all of them counted
together, and 400 syntax nodes (onward_from_goal's promise has 385): where the steps after the
goal sense may be moves only, the goal sense is read as the last sense (``_STAY_OR_ONE``,
``_ONTO_GOAL``, ``_ONLY_MOVES``); where they are a move and a sense in turn (onward_from_goal), the
goal sense is the sense as many senses before the last as there are pairs of steps after it, and
the walk's cells are those from the goal to where the agent ends; where exploring ends on a sense
after which nothing more was to be found, that it was not so before is read from
``known_before_last()`` (corner_in_sight_stop, third_obstacle_look) or, where moves follow it, from
the senses (the last sense showed a cell no earlier sense showed: farthest_first_goal_tour, as in
heldout14); third_obstacle_look counts the senses that showed an obstacle once and asks that count
to be 3 (if the last sense showed one) or, with nothing more to find, less; a promise whose target
is a choice among ties lets the agent stay only where the cell it stands in is as good as the
target, and move only where that cell is strictly worse (nearer, lower). The scooping checks weigh
the grains at the end, as ``delivered()`` and ``spilled()`` do: those in the receiver, and those
outside the receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all; on those 3,600 episodes every one
of the twelve promises was also judged against every reference, and its verdict equalled its
check's on all. On those episodes the tasks' branches came up: exploring stopped with nothing more
to find 5 times, on a corner the other 295; walks right of 0 to 6 moves 102, 125, 44, 9, 10, 5
and 5 times; exploring stopped at the third sense showing an obstacle after 3 to 12 senses (nothing
more to find first never); home on a cluttered goal sense 187 times (25 of them seen from the
start, staying), onto the goal 113; staying at the first clear place 88 times, moving back to it
212; staying on the highest place 157 times, moving 143; the farthest free cell the agent's own 1
time; the goal's mirror image known free 40 times, home instead 260; the farthest-first tour on
all 300; no walk on from the goal 157 times (the goal in the start's column, or blocked at once),
walks of 1 to 8 moves 55, 40, 23, 9, 9, 4, 2 and 1 times; a known free cell two steps from the
goal 299 times, none 1; walks down of no move 106 times, short walks home 113, walks of three or
more moves 81. Faithfulness on behaviors that do not do the tasks: every grid promise was judged
against 69 near misses of the references (thresholds and counts one off, other directions, corners
or edges, rules or places to go, the grid's edge taken as an obstacle, a missing sense or walk, an
extra move or sense, the exhaustion rule or the check of what is known dropped) and 17 other ways
of doing the tasks (another explorer, another choice among ties or goals, a guard written another
way, and one near miss that does the task: first_clear_look_return's first clear place read from
the senses before the goal sense, then that sense's own place) on episodes 0-99 of seeds 0 and 1
(17,175 judged episodes for each promise, 25 lost: 23 where goal_mirror_through_start's
unknown-mirror near miss went for a cell it could not reach, 2 where corner_in_sight_stop's
exploring without the exhaustion rule ran out of places): the near misses kept their own task's
promise on 6,468 of their 13,775 judged episodes and the other ways on all their 3,400; three near
misses did their task on every one of these episodes and kept its promise there
(corner_in_sight_stop's without the exhaustion rule, where a corner was always known first;
far_from_goal_cell's among empty cells only, where the farthest cell was never a goal;
two_steps_off_goal's home when no cell two steps off is known, which never happened there);
against the 194 grid references of the development and earlier held-out sets on episodes 0-49 of
seed 0 (9,700 judged episodes for each promise, none lost); and against 3 trivial behaviors (stop
at once, judged on the reset; sense once; navigate onto the cell it stands in) on episodes 0-99 of
seeds 0 and 1: on every judged episode the promise's verdict equalled the check's. Keep rates of
the trivial behaviors: stopping at once and navigating onto the cell it stands in keep no promise
on any episode; sensing once keeps none but corner_in_sight_stop's (12 of 200: a corner at or
next to the start), right_until_ledge's (64: the cell right of the start blocked),
short_walk_home's (68: the cell below blocked), clutter_turns_home's (16: a goal and an obstacle in
view from the start),
first_clear_look_return's and highest_look_after_goal's (29 each: a goal in view from the start,
the only place sensed from), far_from_goal_cell's (1) and two_steps_off_goal's (1) (a goal in view
from the start and no known free cell farther from it, or two steps off it), where the task asks
for the one sense. The held-out folder tests (tests/test_synthesis_eval.py's
satisfiable-faithful-checkable test, and tests/test_certified.py's readings of every promise and
its bank test) pointed at this folder passed. The scooping references (two and three scoops from
the default sensing pose) were run on episodes 0-19 of seed 0 only (seconds an episode) and kept
their promises and did their tasks on all 20: two scoops delivered 58.8 to 97.3 g and spilled 0.0
to 22.6 g, landing 78.7% to 100% of what they moved (75% needed: margin 3.7 points; 50 g needed:
margin 8.8 g); three scoops delivered 83.7 to 144.8 g and spilled 0.0 to 24.9 g, for scores of
67.9 to 100.0 (45 needed: margin 22.9). landed_share first asked for 80%, which two scoops kept on
18 of the 20 (78.7% and 79.4% on the others), and was set to 75% before the set was fixed. Both
promises were judged on both references and the checks agreed on every one: two scoops kept
capped_credit's on all 20, three scoops landed_share's (at 80%) on all 20."""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (goal_sense as _goal_sense, any_plan as _any_plan,
                                        FINAL as _F, FRESH as _FRESH, LAST_SENSE as _L,
                                        NEW_LAST as _NEW_LAST, ONLY_MOVES as _ONLY_MOVES,
                                        ONTO_GOAL as _ONTO_GOAL, START as _S, START_I as _S0,
                                        START_J as _S1, cell, distance, distance_text, exhausted,
                                        first_reaching, free_cell, goals_shown,
                                        grams_in_receiver, grams_spilled, held_out_task, indices,
                                        known_after, label_sensed, obstacles_beside, onto,
                                        onto_goal_seen, reachable, same_steps, scoops, step_by,
                                        steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
LEFT, RIGHT, DOWN, UP = (-1, 0), (1, 0), (0, -1), (0, 1)
CORNERS = [(0, 0), (0, 9), (9, 0), (9, 9)]  # the grid's corners (corner_in_sight_stop)
OBSTACLE_LOOKS = 3  # senses showing an obstacle that end third_obstacle_look
SHORT = 3  # a walk of fewer moves is short and goes home (short_walk_home)
OFF_GOAL = 2  # steps from the goal that two_steps_off_goal goes to


def _unknown(state):
    """A boolean grid of the cells' knowledge before any step: nothing known."""
    return state.truth != state.truth


def _walk(state, here, step, stop=lambda c: False) -> list:
    """The steps of a walk from ``here`` in the direction ``step``: a move and a sense while the
    next cell that way is inside the grid and free, ending early on a cell where ``stop`` holds."""
    plan = []
    while free_cell(state, step_by(here, step)):
        here = step_by(here, step)
        plan += [("navigate", here), ("sense", here)]
        if stop(here):
            break
    return plan


def _known_free(state, result, index) -> list:
    """The cells known to be free after the steps up to ``index``."""
    known = known_after(state, result.steps[:index + 1])
    return [cell(x) for x in zip(*(known & (state.truth != OBSTACLE)).nonzero())]


# --- checks -------------------------------------------------------------------------------

def check_corner_in_sight_stop(state, result):
    """Exploring stops with the first sense after which a corner of the grid is known, or
    nothing more is to be found."""
    index = first_reaching(state, result, lambda known: any(known[c] for c in CORNERS)
                           or exhausted(state, known))
    if index is None:
        return "never knew a corner and more could be found"
    return same_steps(steps_of(result)[index + 1:], [])


def check_right_until_ledge(state, result):
    """A sense, then a walk right, a sense after every move, while the next cell is inside the
    grid and free, ending on the first cell moved into with an obstacle right below it."""
    def ledge(c):
        return c[1] > 0 and state.truth[c[0], c[1] - 1] == OBSTACLE
    home = state.start_cell
    return same_steps(steps_of(result), [("sense", home)] + _walk(state, home, RIGHT, ledge))


def check_third_obstacle_look(state, result):
    """Exploring stops with the OBSTACLE_LOOKS-th sense that shows an obstacle next to its
    cell, or with the sense after which nothing more is to be found, whichever comes first."""
    steps, known, looks = steps_of(result), _unknown(state), 0
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] != "sense":
            continue
        looks += obstacles_beside(state, step[1]) > 0
        if looks >= OBSTACLE_LOOKS or exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return f"stopped after {looks} sense(s) showing an obstacle, before everything was known"


def check_clutter_turns_home(state, result):
    """After the sense that first shows a goal: one move onto the start if that sense showed an
    obstacle next to its cell (nothing if the agent is there), else one move onto a goal it
    showed (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here = steps[index][1]
    if obstacles_beside(state, here) > 0:
        return onto(steps[index + 1:], here, [state.start_cell], "after a cluttered goal sense")
    return onto_goal_seen(state, steps, index)


def check_first_clear_look_return(state, result):
    """After the sense that first shows a goal: one move onto the cell of the first sense (up
    to that one) that showed no obstacle next to its cell; nothing if the agent stands there or
    no sense did."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here = steps[index][1]
    clear = [c for kind, c in steps[:index + 1]
             if kind == "sense" and obstacles_beside(state, c) == 0]
    return onto(steps[index + 1:], here, (clear + [here])[:1], "after the goal came into view")


def check_highest_look_after_goal(state, result):
    """After the sense that first shows a goal: one move onto a cell sensed from (up to that
    sense) with the largest j (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    senses = [c for kind, c in steps[:index + 1] if kind == "sense"]
    top = max(c[1] for c in senses)
    return onto(steps[index + 1:], steps[index][1], [c for c in senses if c[1] == top],
                "after the goal came into view")


def check_far_from_goal_cell(state, result):
    """After the sense that first shows a goal: one move onto a cell known to be free then that
    is farthest from a goal that sense showed (nothing if the agent stands on one)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, rest, free = steps[index][1], steps[index + 1:], _known_free(state, result, index)
    why = []
    for g in goals_shown(state, here):
        far = max(distance(c, g) for c in free)
        why.append(onto(rest, here, [c for c in free if distance(c, g) == far],
                        f"after goal {g} came into view"))
    return None if None in why else why[0]


def check_goal_mirror_through_start(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed (none if the
    agent stands on one), then one move onto that goal's mirror image through the start if it
    is inside the grid and was known to be free, else onto the start."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, home = steps[index][1], state.start_cell
    free = _known_free(state, result, index)
    goals = [here] if state.truth[here] == GOAL else goals_shown(state, here)
    plans = []
    for g in goals:
        mirror = (2 * home[0] - g[0], 2 * home[1] - g[1])
        plans.append(([] if g == here else [("navigate", g)])
                     + [("navigate", mirror if mirror in free else home)])
    return _any_plan(steps[index + 1:], plans)


def check_farthest_first_goal_tour(state, result):
    """Exploring stops with the sense after which nothing more is to be found; then only moves,
    onto each reachable goal once, in order of distance from the start, farthest first."""
    index = first_reaching(state, result, lambda known: exhausted(state, known))
    if index is None:
        return "stopped before everything was known"
    rest, home = steps_of(result)[index + 1:], state.start_cell
    goals = sorted(cell(x) for x in zip(*(reachable(state) & (state.truth == GOAL)).nonzero()))
    tour = [c for kind, c in rest if kind == "navigate"]
    if len(tour) != len(rest) or sorted(tour) != goals:
        return f"after exploring ran {rest[:6]}, not one move onto each of the goals {goals}"
    gaps = [distance(c, home) for c in tour]
    return None if gaps == sorted(gaps, reverse=True) else \
        f"visited the goals {tour} at {gaps} steps from the start, not farthest first"


def check_onward_from_goal(state, result):
    """After the sense that first shows a goal: one move onto a goal it showed and a sense there
    (neither if the agent stands on one), then a walk along the goal's row away from the start's
    column, a sense after every move, while the next cell is inside the grid and free (none if
    the goal is in the start's column)."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, home = steps[index][1], state.start_cell
    goals = [here] if state.truth[here] == GOAL else goals_shown(state, here)
    plans = []
    for g in goals:
        way = (g[0] > home[0]) - (g[0] < home[0])
        plans.append(([] if g == here else [("navigate", g), ("sense", g)])
                     + (_walk(state, g, (way, 0)) if way else []))
    return _any_plan(steps[index + 1:], plans)


def check_two_steps_off_goal(state, result):
    """After the sense that first shows a goal: one move onto a cell known to be free then that
    is OFF_GOAL steps from a goal that sense showed; nothing if no such cell is known."""
    steps, index = _goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, rest, free = steps[index][1], steps[index + 1:], _known_free(state, result, index)
    plans = []
    for g in goals_shown(state, here):
        spots = [c for c in free if distance(c, g) == OFF_GOAL]
        plans += [[("navigate", c)] for c in spots] if spots else [[]]
    return _any_plan(rest, plans)


def check_short_walk_home(state, result):
    """A sense, a walk down, a sense after every move, while the next cell is inside the grid
    and free; then, if the walk made 1 to SHORT - 1 moves, one move onto the start."""
    home = state.start_cell
    walk = _walk(state, home, DOWN)
    back = [("navigate", home)] if 0 < len(walk) // 2 < SHORT else []
    return same_steps(steps_of(result), [("sense", home)] + walk + back)


SHARE, SHARE_LEAST = 75, 50  # percent of the grains moved that must land; grams (landed_share)
CAP, CAP_SCORE = 100, 45  # grams that earn points at most; the score needed (capped_credit)


def check_landed_share(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    if mass < SHARE_LEAST or 100 * mass < SHARE * (mass + spilled):
        return f"{mass:.1f} g delivered and {spilled:.1f} g spilled in {n} scoop(s)"
    return None


def check_capped_credit(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    score = min(mass, CAP) - spilled
    return None if score >= CAP_SCORE else \
        f"score {score:.1f}: {mass:.1f} g delivered, {spilled:.1f} g spilled, {n} scoop(s)"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)

# The promises' language allows at most 3 comprehension loops in one expression (all of its
# loops counted together) and 400 syntax nodes: these are written to stay within that.
_K10 = indices(10)


def _d(a: str, b: str = _S) -> str:
    return distance_text(a, b)


def _blocked(i: str, j: str) -> str:
    """The cell (i, j) is off the grid or an obstacle."""
    return f"(not (0 <= {i} <= 9 and 0 <= {j} <= 9) or is_obstacle(({i}, {j})))"


def _shows_obstacle(c: str) -> str:
    """A sense at ``c`` shows an obstacle next to it (one loop)."""
    return f"any(is_obstacle(x) for x in neighbours({c}))"


# after the last sense: nothing if the agent ends where it sensed, else one move (the last sense
# is then the one before it, the sense that first showed a goal)
_STAY_OR_ONE = f"steps_after_goal() == (0 if {_F} == {_L} else 1) and primitives()[-1:] == " \
               f"(['sense'] if {_F} == {_L} else ['navigate'])"
_FREE_KNOWN = f"{_F} in known_cells() and not is_obstacle({_F})"
# onward_from_goal: P the cell of the goal sense (as many senses after it as pairs of steps), G
# the goal walked from, A the way along the row (1 right, -1 left, 0 none); the walk's cells are
# those from G to where the agent ends
_P = "sensed()[-1 - steps_after_goal() // 2]"
_A = f"(1 if G[0] > {_S0} else -1 if G[0] < {_S0} else 0)"
_MIRROR = f"(2 * {_S0} - G[0], 2 * {_S1} - G[1])"
_N = "len(reachable_goals())"

TASKS = [
    _task("corner_in_sight_stop", 1, check_corner_in_sight_stop,
          "Explore, moving and sensing, until you know what is in one of the four corner cells "
          "of the grid, (0, 0), (0, 9), (9, 0) or (9, 9): stop right after the sense that first "
          "shows you a corner. If there is nothing more to find before that, stop right after "
          "the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and not any(c in known_before_last() for c in "
          f"{CORNERS}) and (any(c in known_cells() for c in {CORNERS}) or (explored_all() and "
          f"{_FRESH}))"),
    _task("right_until_ledge", 1, check_right_until_ledge,
          "Sense where you start, then walk to the right (i + 1), one cell at a time, sensing "
          "after every move, while the next cell to the right is inside the grid and free. Stop "
          "early on the first cell you move into that has an obstacle right below it (j - 1; "
          "the grid's bottom edge does not count as an obstacle).",
          f"any(primitives() == ['sense'] + ['navigate', 'sense'] * R and moves() == [({_S0} + "
          f"k, {_S1}) for k in {_K10}[1:R + 1]] and not any({_S1} > 0 and is_obstacle(({_S0} + "
          f"k, {_S1} - 1)) for k in {_K10}[1:R]) and ((R > 0 and {_S1} > 0 and "
          f"is_obstacle(({_S0} + R, {_S1} - 1))) or {_blocked(f'{_S0} + R + 1', _S1)}) for R in "
          f"{_K10})"),
    _task("third_obstacle_look", 1, check_third_obstacle_look,
          f"Explore, moving and sensing, and count the senses that show you an obstacle on a "
          f"cell right next to where you sensed (the grid's edge does not count; a sense taken "
          f"again in the same place counts again). Stop right after the {OBSTACLE_LOOKS}rd such "
          f"sense. If there is nothing more to find before that, stop right after the sense "
          f"that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and (not explored_all() or {_FRESH}) and len([s for s "
          f"in sensed() if {_shows_obstacle('s')}]) in ([{OBSTACLE_LOOKS}] if "
          f"{_shows_obstacle(_L)} else []) + ({indices(OBSTACLE_LOOKS)} if explored_all() else "
          f"[])"),
    _task("clutter_turns_home", 2, check_clutter_turns_home,
          "Search for a goal. When a sense first shows you a goal, look at what else it showed: "
          "if it also showed an obstacle on a cell right next to you (the grid's edge does not "
          "count), give up and go straight back to your starting cell with one move (if you "
          "are there, just stop). Otherwise go onto the goal with one move and stop (onto any "
          "of them if that sense showed several; if you are standing on one, just stop).",
          f"goal_found() and (({_shows_obstacle(_L)} and {_F} == {_S} and steps_after_goal() == "
          f"(0 if {_L} == {_S} else 1) and primitives()[-1:] == (['sense'] if {_L} == {_S} else "
          f"['navigate'])) or (not {_shows_obstacle(_L)} and {_ONTO_GOAL}))"),
    _task("first_clear_look_return", 2, check_first_clear_look_return,
          "Search for a goal, remembering the first place where a sense showed you no obstacle "
          "at all on the cells right next to you (the grid's edge does not count). As soon as a "
          "sense shows you a goal, do not go to the goal: go back to that place with one move "
          "and stop. If you are standing there, or none of your senses so far (that last one "
          "included) was free of obstacles, just stop.",
          f"goal_found() and all({_F} == T and steps_after_goal() == (0 if T == {_L} else 1) and "
          f"primitives()[-1:] == (['sense'] if T == {_L} else ['navigate']) for T in [([s for s "
          f"in sensed() if not {_shows_obstacle('s')}] + [{_L}])[0]])"),
    _task("highest_look_after_goal", 2, check_highest_look_after_goal,
          "Search for a goal. As soon as a sense shows you one, go back with one move to the "
          "highest of the places you have sensed from -- the one with the largest j, counting "
          "that last sense too -- and stop there (any of them if several are equally high; if "
          "you are standing on one of them, just stop).",
          f"goal_found() and {_STAY_OR_ONE} and {_F} in sensed() and all(s[1] <= {_F}[1] for s "
          f"in sensed()) and ({_F} == {_L} or {_L}[1] < {_F}[1])"),
    _task("far_from_goal_cell", 2, check_far_from_goal_cell,
          "Search for a goal, then keep your distance from it. As soon as a sense shows you a "
          "goal, do not go to it: go with one move to the cell you know to be free that is "
          "farthest from that goal, counting steps along rows and columns and ignoring "
          "obstacles (any of them if several are equally far; if that sense showed several "
          "goals, measure from any one of them). If you are standing on such a cell, just stop.",
          f"goal_found() and {_STAY_OR_ONE} and {_FREE_KNOWN} and any(is_goal(G) and "
          f"all({_d('c', 'G')} <= {_d(_F, 'G')} for c in known_cells() if not is_obstacle(c)) "
          f"and ({_F} == {_L} or {_d(_L, 'G')} < {_d(_F, 'G')}) for G in [{_L}] + "
          f"neighbours({_L}))"),
    _task("goal_mirror_through_start", 3, check_goal_mirror_through_start,
          "Search for a goal. As soon as a sense shows you one, go onto it with one move (onto "
          "any of them if that sense showed several; skip this if you are standing on one). "
          "Then go with one move to the goal's mirror image through your starting cell -- the "
          "cell just as far from the start on the opposite side, (2 a - i, 2 b - j) for a start "
          "(a, b) and a goal (i, j) -- if it lies inside the grid and you already know it to be "
          "free; otherwise go straight back to your starting cell. Stop there.",
          f"goal_found() and {_ONLY_MOVES} and all(is_goal(G) and G in [{_L}] + "
          f"neighbours({_L}) and moves_after_goal() == ([] if G == {_L} else [G]) + [M if 0 <= "
          f"M[0] <= 9 and 0 <= M[1] <= 9 and M in known_cells() and not is_obstacle(M) else "
          f"{_S}] for G in [{_L} if is_goal({_L}) else (moves_after_goal() + [{_L}])[0]] for M in "
          f"[{_MIRROR}])"),
    _task("farthest_first_goal_tour", 3, check_farthest_first_goal_tour,
          "Explore, moving and sensing, until there is nothing more to find. Then visit every "
          "goal you can reach, moving onto each exactly once, in order of distance from your "
          "starting cell, farthest first (counting steps along rows and columns and ignoring "
          "obstacles; goals equally far in any order), and stop on the last one. Make no other "
          "moves after the last sense; a goal you are standing on when exploring ends still "
          "gets its move in its turn.",
          f"explored_all() and {_NEW_LAST} and primitives()[len(primitives()) - {_N} - 1:] == "
          f"['sense'] + ['navigate'] * {_N} and sorted(moves()[len(moves()) - {_N}:]) == "
          f"reachable_goals() and all({_d(f'moves()[k - {_N}]')} >= "
          f"{_d(f'moves()[k + 1 - {_N}]')} for k in {_K10}[:{_N} - 1])"),
    _task("onward_from_goal", 3, check_onward_from_goal,
          "Search for a goal. As soon as a sense shows you one, go onto it with one move and "
          "sense there (onto any of them if that sense showed several; if you are standing on "
          "one, skip the move and the sense). Then carry on along the goal's row, away from the "
          "column you started in: to the right (i + 1) if the goal lies right of your starting "
          "cell, to the left (i - 1) if it lies left of it; one cell at a time, sensing after "
          "every move, while the next cell that way is inside the grid and free. If the goal "
          "is in your starting column, stop on it.",
          f"goal_found() and primitives()[len(primitives()) - steps_after_goal():] == "
          f"['navigate', 'sense'] * (steps_after_goal() // 2) and all(is_goal(G) and G in [P] + "
          f"neighbours(P) and {_F}[1] == G[1] and moves_after_goal() == ([] if G == P else "
          f"[G]) + [(G[0] + {_A} * k, G[1]) for k in {_K10}[1:abs({_F}[0] - G[0]) + 1]] and "
          f"({_A} == 0 or "
          f"{_blocked(f'{_F}[0] + {_A}', f'{_F}[1]')}) for P in [{_P}] for G in [P if is_goal(P) "
          f"else (moves_after_goal() + [P])[0]])"),
    _task("two_steps_off_goal", 2, check_two_steps_off_goal,
          f"Search for a goal. As soon as a sense shows you one, do not step onto it: go with "
          f"one move to a cell you know to be free that is exactly {OFF_GOAL} steps from the "
          f"goal, counting steps along rows and columns and ignoring obstacles (any such cell; "
          f"if that sense showed several goals, {OFF_GOAL} steps from any one of them), and "
          f"stop there. If you know no such cell, just stop.",
          f"goal_found() and steps_after_goal() <= 1 and primitives()[-1:] == (['sense'] if "
          f"steps_after_goal() == 0 else ['navigate']) and any(is_goal(G) and (({_FREE_KNOWN} "
          f"and {_d(_F, 'G')} == {OFF_GOAL}) if steps_after_goal() == 1 else not "
          f"any({_d('c', 'G')} == {OFF_GOAL} for c in known_cells() if not is_obstacle(c))) for G "
          f"in [{_L}] + neighbours({_L}))"),
    _task("short_walk_home", 2, check_short_walk_home,
          f"Sense where you start, then walk down (j - 1), one cell at a time, sensing after "
          f"every move, while the next cell down is inside the grid and free. If that walk "
          f"ended after fewer than {SHORT} moves, go straight back to your starting cell with "
          f"one move and stop; if it made {SHORT} or more, stop where it ended. If you could "
          f"not move down at all, just stop.",
          f"any(primitives() == ['sense'] + ['navigate', 'sense'] * R + (['navigate'] if 0 < R "
          f"< {SHORT} else []) and moves() == [({_S0}, {_S1} - k) for k in {_K10}[1:R + 1]] + "
          f"([{_S}] if 0 < R < {SHORT} else []) and {_blocked(_S0, f'{_S1} - R - 1')} for R in "
          f"{_K10})"),
    _task("landed_share", 2, check_landed_share,
          f"Scoop two to four times, then stop, landing most of what you move: of the grains "
          f"that end up in the receiver or spilled outside the containers, together, at least "
          f"{SHARE}% must be in the receiver, and the receiver must hold at least {SHARE_LEAST} "
          f"g.",
          f"scoops() >= 2 and scoops() <= 4 and delivered() >= {SHARE_LEAST} and 100 * "
          f"delivered() >= {SHARE} * (delivered() + spilled())", SCOOP),
    _task("capped_credit", 2, check_capped_credit,
          f"Scoop one to five times, then stop, with a score of at least {CAP_SCORE}. The grams "
          f"of grains in the receiver earn a point each, but only up to {CAP} g (grains beyond "
          f"{CAP} g earn nothing), and every gram spilled outside the containers costs a "
          f"point.",
          f"scoops() >= 1 and scoops() <= 5 and min(delivered(), {CAP}) - spilled() >= "
          f"{CAP_SCORE}", SCOOP),
]
