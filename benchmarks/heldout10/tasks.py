"""Held-out tasks, tenth set: written before the next change of the synthesizer, run once after.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout10/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (one step towards the diagonal i = j, none
on it; a step onto a neighbour, a look there, and back unless two more free cells are next to it; a
step, a look, and a step turned right of the first; a walk right, then to the goal that came into
view first, else home; exploring that stops with the first move back into the start's row after a
move out of it; once a goal is in view, to whichever of the start and the first move's cell is
nearer to it; a walk up that stops on the second cell with a free cell to its right; after five
senses, back to where the second was taken; once a goal is in view, to a known free cell as nearly
halfway between the start and it as any; a walk up, then right, down and left, turning clockwise
when blocked; a walk down then left, retraced cell by cell to the start; up to eight moves onto
cells never stood in, each the nearest to the start) and two scooping tasks (one to five scoops
with a charge of 15 g a scoop taken off the grams delivered; two scoops that take a bound of grams
out of the donor, delivered and spilled together). Each has a reference behavior (``references/``),
a ground-truth ``check`` and a faithful ``promise`` over the env's outcome helpers, so that the
search can be measured apart from the model. They were written on 2026-12-06 blind: without reading
the search's code and without running the synthesizer on them; the first run of the search on them
is the evaluation, reported beside the development figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and every
cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a *row* is the
cells of one j; a sense labels its cell and the four around it (it *shows* them; a goal *comes into
view* with the first sense that shows it); the cells *next to* a cell are its four neighbours
inside the grid; a cell *stood in* is the start cell or one a move ended in; the *distance* of two
cells counts steps along rows and columns (|di| + |dj|), obstacles ignored; the *diagonal* is the
cells with i = j, and a cell is nearer to it when |i - j| is smaller; *turning right* of a move
(di, dj) is the direction (dj, -di), *clockwise* is up, right, down, left; the *halfway gap* of a
cell is |its distance to the start - its distance to the goal|. The start cell always has a free
neighbour (a goal is reachable from it and it holds none). The promises' language allows three
comprehension loops in one expression and 400 syntax nodes: where a promise needs indices 0..n - 1
they are written out, and walks are bounded by what the grid allows (back_in_start_row's promise
reads the first 100 moves, which no episode comes near). The scooping checks weigh the grains at
the end, as ``delivered()`` and ``spilled()`` do: those in the receiver, and those outside the
receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``'s counting, each reference with its task's
promise): every grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds
0, 1 and 2), the promise's verdict equal to the check's on all. On those episodes the tasks'
branches came up: the start on the diagonal 30 times, a step towards it 244, both nearer cells
blocked 26; back from the neighbour 100, staying 200; the turned step 197, none 103 (first steps
right 198, left 74, up 25, down 3); the walk right with no move 102, with 5 or more moves 22, then
onto the goal first in view 58, already on it 11, home 135, no move and no goal 96; the first move
back into the start's row 288 (after 2 to 62 moves), nothing more to find first 12; a goal in view
before any move 41, then to the first move's cell 159, to the start 73, already on the nearer one
27 (a tie never came up: a first move onto a neighbour of the start is one step nearer to or
farther from the goal); the walk up stopped by the second opening 93, by a blocked cell after
moving 101, with no move 106, up to 6 moves; the fifth sense 300 times (nothing more to find before
it, and standing on the second sense's cell then, never came up for the reference: its exploring
never comes back so soon); the halfway cell reached with a move 197, the cell sensed from already
one 103 (a goal in view at the first sense 41); the clockwise walk with 1, 2, 3 and 4 legs that
moved 15, 76, 139 and 70 times, 1 to 24 moves; the walk down and left with no move 30, with a leg
left 199, up to 13 moves out and as many back; the walk near home 8 moves 159, fewer (stuck) 141.
Faithfulness on behaviors that do not do the tasks: every grid promise was judged against the
behaviors written for it (62 near misses -- other directions, turns, thresholds, counts, orders or
places to go back to, a missing or extra sense or move, one step late -- and 8 other ways of doing
the tasks, other choices where a task allows any) on episodes 0-99 of seeds 0 and 1 (14,000 judged
episodes), against the other 11 references of this set and the 122 grid references of the
development and earlier held-out sets on episodes 0-49 of seed 0 (79,800 judged episodes), and
against 3 trivial behaviors (stop at once, sense once, navigate onto the cell it stands in) on
episodes 0-99 of seeds 0 and 1: on every judged episode the promise's verdict equalled the check's.
Keep rates of the trivial behaviors: stopping at once and navigating onto the cell it stands in
keep no promise on any episode; sensing once keeps none but toward_diagonal's (38 of 200: on the
diagonal, or both nearer cells blocked), right_walk_then_first_goal's (60: the cell to the right
blocked and no goal in view), nearer_of_start_and_first_step's and halfway_cell's (29 each: a goal
next to the start, in view before any move, where every halfway gap is odd and the start's, 1, is
least), up_until_second_opening's (70: the cell above blocked) and down_left_retrace's (20: below
and left blocked), where the task asks for the one sense. The scooping references (four and two
scoops from the default sensing pose), run on episodes 0-19 of seed 0, kept their promises and did
their tasks on all 20: four scoops left 101.8 to 185.5 g in the receiver (the bound is 30 g after
60 g of charges: 90 g) and two scoops delivered 58.8 to 97.3 g and spilled 0 to 22.6 g, 65.6 to
108.6 g out of the donor (the bound is 55 g). One scoop (episodes 0-7) delivered 33.9 to 54.3 g,
keeping scoop_fee's promise on 5 (it needs 45 g) and never moved_out_of_donor's; two scoops
(episodes 0-9) kept scoop_fee's (61.1 g at least, 60 g needed; 58.8 g once in episodes 0-19); three
scoops (episodes 0-3) kept no moved_out_of_donor promise and five (episodes 0-2) kept scoop_fee's;
the check agreed on every judged episode.
"""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (cell, distance, exhausted, first_goal_sense, free_cell,
                                        free_neighbours, grams_in_receiver, grams_spilled,
                                        held_out_task, indices, label_sensed, same_steps, scoops,
                                        sensed_cells, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP, DOWN = (1, 0), (-1, 0), (0, 1), (0, -1)




def _walk_plan(state, here, way):
    """From ``here``, the (move, sense) steps of a walk ``way`` while the next cell is inside the
    grid and free, and the cell it ends in."""
    plan = []
    while free_cell(state, step_by(here, way)):
        here = step_by(here, way)
        plan += [("navigate", here), ("sense", here)]
    return plan, here


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

def check_toward_diagonal(state, result):
    """One sense; then one move onto a free cell next to the start with a smaller |i - j| than
    the start's if there is one (none on the diagonal), else nothing more."""
    home, steps = state.start_cell, steps_of(result)
    targets = [n for n in free_neighbours(state, home)
               if abs(n[0] - n[1]) < abs(home[0] - home[1])]
    if steps[:1] == [("sense", home)] and (
            (not targets and len(steps) == 1)
            or (targets and len(steps) == 2 and steps[1][0] == "navigate"
                and steps[1][1] in targets)):
        return None
    return f"ran {steps[:4]}, not a sense and then a move onto one of {targets}"


def check_open_spot_or_back(state, result):
    """Sense, a move onto a free cell next to the start, a sense there; then a move back onto
    the start unless that cell has two or more free cells next to it besides the start."""
    steps = steps_of(result)
    spot, why = _peek(state, steps)
    if spot is None:
        return why
    others = [n for n in free_neighbours(state, spot) if n != state.start_cell]
    rest = [] if len(others) >= 2 else [("navigate", state.start_cell)]
    return same_steps(steps[3:], rest)


def check_step_then_turn_right(state, result):
    """Sense, a move onto a free cell next to the start, a sense there; then a move onto the
    cell to the right of that move's heading ((di, dj) turned to (dj, -di)) if it is inside the
    grid and free."""
    steps = steps_of(result)
    spot, why = _peek(state, steps)
    if spot is None:
        return why
    di, dj = spot[0] - state.start_cell[0], spot[1] - state.start_cell[1]
    turn = step_by(spot, (dj, -di))
    return same_steps(steps[3:], [("navigate", turn)] if free_cell(state, turn) else [])


def check_right_walk_then_first_goal(state, result):
    """Sense; right while free, each move followed by a sense; then, if some sense of the walk
    showed a goal, a move onto one of the goals the first such sense showed (nothing if the
    agent stands on one); if none did, a move onto the start if the walk moved."""
    home, steps = state.start_cell, steps_of(result)
    walk, end = _walk_plan(state, home, RIGHT)
    plan = [("sense", home)] + walk
    if steps[:len(plan)] != plan:
        return same_steps(steps, plan)
    rest = steps[len(plan):]
    first = []
    for kind, c in plan:
        if kind == "sense":
            first = [n for n in sensed_cells(state, c) if state.truth[n] == GOAL]
            if first:
                break
    if not first:
        return same_steps(rest, [("navigate", home)] if end != home else [])
    if end in first:
        return same_steps(rest, [])
    if len(rest) == 1 and rest[0][0] == "navigate" and rest[0][1] in first:
        return None
    return f"after the walk ran {rest[:4]}, not one move onto one of {first}"


def check_back_in_start_row(state, result):
    """Exploring stops with the first move that ends in the start's row after an earlier move
    ended outside it, or with the sense after which nothing more is to be found, whichever
    comes first."""
    steps, row = steps_of(result), state.start_cell[1]
    known = state.truth != state.truth
    out = False
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] == "navigate":
            if step[1][1] == row and out:
                return same_steps(steps[index + 1:], [])
            out = out or step[1][1] != row
        elif exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return "never back in the start's row after leaving it, and more could be found"


def check_nearer_of_start_and_first_step(state, result):
    """After the sense that first shows a goal: nothing if no move came before it; else one
    move onto the start or the first move's cell, whichever is nearer to a goal that sense
    showed (the start on a tie), or nothing if the agent stands on that cell."""
    steps, home = steps_of(result), state.start_cell
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    here, rest = steps[index][1], steps[index + 1:]
    earlier = [c for kind, c in steps[:index] if kind == "navigate"]
    if not earlier:
        return same_steps(rest, [])
    first = earlier[0]
    picks = {home if distance(home, g) <= distance(first, g) else first
             for g in sensed_cells(state, here) if state.truth[g] == GOAL}
    if (rest == [] and here in picks) or (len(rest) == 1 and rest[0][0] == "navigate"
                                          and rest[0][1] in picks and here not in picks):
        return None
    return f"after the goal came into view ran {rest[:4]}, not one move onto one of {picks}"


def check_up_until_second_opening(state, result):
    """Sense; up while free, each move followed by a sense, stopping after the sense on the
    second cell moved onto whose right neighbour is inside the grid and free."""
    here = state.start_cell
    plan, openings = [("sense", here)], 0
    while free_cell(state, step_by(here, UP)) and openings < 2:
        here = step_by(here, UP)
        plan += [("navigate", here), ("sense", here)]
        openings += free_cell(state, step_by(here, RIGHT))
    return same_steps(steps_of(result), plan)


def check_back_to_second_look(state, result):
    """Exploring stops with the fifth sense, or with the sense after which nothing more is to
    be found, whichever comes first; then one move onto the cell of the second sense, or
    nothing if the agent stands on it."""
    steps = steps_of(result)
    known = state.truth != state.truth
    looks: list[tuple[int, int]] = []
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] != "sense":
            continue
        looks.append(step[1])
        if len(looks) == 5 or exhausted(state, known):
            if len(looks) < 2:
                return "stopped exploring before a second sense"
            want = [] if step[1] == looks[1] else [("navigate", looks[1])]
            return same_steps(steps[index + 1:], want)
    return "fewer than five senses, and more could be found"


def check_halfway_cell(state, result):
    """After the sense that first shows a goal: one move onto a known free cell whose
    |distance to the start - distance to a goal that sense showed| is the least among the
    known free cells, or nothing if the agent stands on such a cell."""
    steps, home = steps_of(result), state.start_cell
    index = first_goal_sense(state, result)
    if index is None:
        return "no goal seen"
    known = state.truth != state.truth
    for step in steps[:index + 1]:
        label_sensed(state, known, step)
    here, rest = steps[index][1], steps[index + 1:]
    spots = [cell(c) for c in zip(*(known & (state.truth != OBSTACLE)).nonzero())]
    for goal in (g for g in sensed_cells(state, here) if state.truth[g] == GOAL):
        gap = {c: abs(distance(c, home) - distance(c, goal)) for c in spots}
        best = min(gap.values())
        if gap[here] == best:
            if rest == []:
                return None
        elif len(rest) == 1 and rest[0][0] == "navigate" and gap.get(rest[0][1]) == best:
            return None
    return f"after the goal came into view ran {rest[:4]}, not a move onto a halfway cell"


def check_three_turn_walk(state, result):
    """Sense; then four walks, up, right, down and left, each from where the last ended and
    while the next cell is inside the grid and free, each move followed by a sense."""
    here = state.start_cell
    plan = [("sense", here)]
    for way in (UP, RIGHT, DOWN, LEFT):
        walk, here = _walk_plan(state, here, way)
        plan += walk
    return same_steps(steps_of(result), plan)


def check_down_left_retrace(state, result):
    """Sense; down while free, then left while free, each move followed by a sense; then one
    move onto each cell stood in before, in reverse order, ending on the start."""
    home = state.start_cell
    down, bottom = _walk_plan(state, home, DOWN)
    left, _ = _walk_plan(state, bottom, LEFT)
    out = down + left
    stood = [home] + [c for kind, c in out if kind == "navigate"]
    plan = [("sense", home)] + out + [("navigate", c) for c in reversed(stood[:-1])]
    return same_steps(steps_of(result), plan)


def check_hug_home_walk(state, result):
    """Sense; then, up to 8 times, a move onto the free cell next to the agent it has not
    stood in that is nearest to the start (ties: up, right, down, left) and a sense there;
    fewer moves only when no such cell is next to it."""
    here = state.start_cell
    plan, stood = [("sense", here)], [here]
    while len(stood) < 9:
        fresh = [(distance(c, state.start_cell), t, c) for t, c in
                 enumerate((step_by(here, UP), step_by(here, RIGHT), step_by(here, DOWN),
                            step_by(here, LEFT))) if free_cell(state, c) and c not in stood]
        if not fresh:
            break
        here = min(fresh)[2]
        stood.append(here)
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


FEE, NET = 15, 30  # grams charged for every scoop; grams that must be left after the charges
MOVED = 55  # grams two scoops must take out of the donor (into the receiver or spilled)


def check_scoop_fee(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 1 <= n <= 5:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass = grams_in_receiver(state)
    return None if mass - FEE * n >= NET else f"{mass:.1f} g in the receiver after {n} scoops"


def check_moved_out_of_donor(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or n != 2:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if mass + spilled >= MOVED else f"{mass:.1f} g delivered, {spilled:.1f} g spilled"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)




# The promises' language allows at most 3 comprehension loops in one expression: these are
# written to stay within that.
_S, _S0, _S1 = "start_cell()", "start_cell()[0]", "start_cell()[1]"
_N = "[1, 2, 3, 4, 5, 6, 7, 8, 9]"
_LINE = "primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and " \
        "sensed() == [start_cell()] + moves()"
_FRESH = "len(known_before_last()) < len(known_cells())"  # the last step labelled something
_M0 = "moves()[0]"
_PEEK = "primitives()[:3] == ['sense', 'navigate', 'sense'] and sensed() == [start_cell(), " \
        "moves()[0]] and moves()[0] in neighbours(start_cell()) and not " \
        "is_obstacle(moves()[0]) and len(primitives()) == 2 + len(moves())"
_K = "(len(sensed()) - 1)"  # moves followed by a sense, in a walk that senses after each
_L = "sensed()[-1]"  # where the last sense was taken


def _open(x: str, of: str = _S) -> str:
    """``x``, a cell next to ``of`` or off the grid, is inside the grid and free."""
    return f"({x} in neighbours({of}) and not is_obstacle({x}))"


def _dist(a: str, b: str) -> str:
    return f"(abs({a}[0] - {b}[0]) + abs({a}[1] - {b}[1]))"


def _up_shut(p: str) -> str:
    return f"({p}[1] == 9 or is_obstacle(({p}[0], {p}[1] + 1)))"


def _down_shut(p: str) -> str:
    return f"({p}[1] == 0 or is_obstacle(({p}[0], {p}[1] - 1)))"


def _right_shut(p: str) -> str:
    return f"({p}[0] == 9 or is_obstacle(({p}[0] + 1, {p}[1])))"


def _left_shut(p: str) -> str:
    return f"({p}[0] == 0 or is_obstacle(({p}[0] - 1, {p}[1])))"


def _seen_at(c: str, a: str = _S0, b: str = _S1) -> str:
    """The index of the first sense of a walk right from (a, b), sensing after every move, that
    shows ``c`` (a cell it shows)."""
    return f"max(0, {c}[0] - {a} - 1 + abs({c}[1] - {b}))"


def _gap(c: str) -> str:
    """|distance from ``c`` to the start - distance from ``c`` to the goal g|."""
    return f"abs({_dist(c, _S)} - {_dist(c, 'g')})"


# the direction of move k - 1 in a walk that senses after every move, for a move of one cell: 0
# up, 1 right, 2 down, 3 left (3 * di + dj is 1, 3, -1 or -3); 0 before the first move
_WAS = "([3, 9, 2, 9, 0, 9, 1][(3 * (sensed()[k][0] - sensed()[k - 1][0]) + sensed()[k][1] - " \
       "sensed()[k - 1][1] + 3) % 7] if k > 0 else 0)"
_Q = "sensed()[k]"  # where the agent stood before move k, in a walk that senses after every move
_OPENING = "({m}[0] < 9 and not is_obstacle(({m}[0] + 1, {m}[1])))"
_FRESH_LOOK = f"any(all({_dist('c', 'd')} > 1 for d in sensed()[:-1]) for c in [{_L}] + " \
              f"neighbours({_L}))"  # the last sense showed a cell no earlier sense did
_HUG = f"[({_dist('c', _S)}, t, c) for t, c in [(0, ({_Q}[0], {_Q}[1] + 1)), (1, ({_Q}[0] + 1, " \
       f"{_Q}[1])), (2, ({_Q}[0], {_Q}[1] - 1)), (3, ({_Q}[0] - 1, {_Q}[1]))] if " \
       f"{_open('c', _Q)} and c not in sensed()[:k + 1]]"

TASKS = [
    _task("toward_diagonal", 1, check_toward_diagonal,
          "Sense once where you start. If your starting cell lies on the grid's diagonal, where "
          "i equals j, stay there. Otherwise take one step towards the diagonal: onto a free "
          "cell next to you where the difference between i and j is smaller than at your "
          "start -- to your left (i - 1) or down (j - 1) if your i is the larger, to your right "
          "(i + 1) or up (j + 1) if your j is the larger. If neither of those two cells is "
          "inside the grid and free, stay where you are. Then stop.",
          f"primitives()[:1] == ['sense'] and sensed() == [{_S}] and len(primitives()) == 1 + "
          f"len(moves()) and all(moves() == [] if T == [] else (len(moves()) == 1 and {_M0} in "
          f"T) for T in [[c for c in neighbours({_S}) if not is_obstacle(c) and abs(c[0] - "
          f"c[1]) < abs({_S0} - {_S1})]])"),
    _task("open_spot_or_back", 1, check_open_spot_or_back,
          "Sense where you start, step onto any free cell next to you and sense again. If the "
          "cell you now stand on has at least two free cells right next to it besides your "
          "starting cell, stay there; otherwise go straight back to your starting cell with "
          "one move. Then stop.",
          f"{_PEEK} and moves()[1:] == ([] if len([c for c in neighbours({_M0}) if c != {_S} and "
          f"not is_obstacle(c)]) >= 2 else [{_S}])"),
    _task("step_then_turn_right", 1, check_step_then_turn_right,
          "Sense, step onto any free cell next to you and sense again. Then turn to your right, "
          "relative to the step you just made, and take one more step that way if that cell is "
          "inside the grid and free: after a step up (j + 1) your right is i + 1, after a step "
          "right (i + 1) it is j - 1, after a step down (j - 1) it is i - 1, and after a step "
          "left (i - 1) it is j + 1. If that cell is outside the grid or an obstacle, stay "
          "where you are. Then stop.",
          f"{_PEEK} and all(moves()[1:] == ([b] if {_open('b', _M0)} else []) for b in "
          f"[({_M0}[0] + {_M0}[1] - {_S1}, {_M0}[1] - {_M0}[0] + {_S0})])"),
    _task("right_walk_then_first_goal", 2, check_right_walk_then_first_goal,
          "Sense, then walk right (i + 1) one cell at a time, sensing after every move, while "
          "the cell to your right is inside the grid and free. When you cannot go on, think "
          "back: if any of your senses showed you a goal (on the cell you sensed from or one "
          "next to it), go with one move onto the goal that came into view first (any of them "
          "if that sense showed several) and stop -- if you are standing on it already, just "
          "stop. If no sense showed a goal, go straight back to your starting cell with one "
          "move and stop (if you never moved, just stop).",
          f"sensed()[-1:] != [] and all(primitives() == ['sense'] + ['navigate', 'sense'] * K "
          f"+ ['navigate'] * (len(moves()) - K) and sensed() == [(a, b)] + moves()[:K] and "
          f"moves()[:K] == [(a + n, b) for n in {_N}][:K] and {_right_shut('E')} and "
          f"((moves()[K:] == ([(a, b)] if K > 0 else [])) if G == [] else ((moves()[K:] == []) if "
          f"(min(G)[0], E) in G else (len(moves()) == K + 1 and (min(G)[0], moves()[-1]) in G))) "
          f"for a, b, K, E, G in [({_S0}, {_S1}, len(sensed()) - 1, {_L}, [({_seen_at('g')}, g) "
          f"for g in known_cells() if is_goal(g)])])"),
    _task("back_in_start_row", 2, check_back_in_start_row,
          "Explore, moving and sensing, and stop as soon as a move brings you back into the "
          "row you started in (a cell whose j is that of your starting cell) after an earlier "
          "move had ended outside it: that move is your last action. If there is nothing more "
          "to find before that happens, stop right after the sense that leaves nothing more to "
          "find.",
          f"all((primitives()[-1:] == ['navigate'] and not explored_all() and R[:1] == "
          f"[len(moves()) - 1]) or (primitives()[-1:] == ['sense'] and explored_all() and "
          f"{_FRESH} and R == []) for R in [[k for k in {indices(100)}[:len(moves())] if "
          f"moves()[k][1] == {_S1} and any(m[1] != {_S1} for m in moves()[:k])]])"),
    _task("nearer_of_start_and_first_step", 2, check_nearer_of_start_and_first_step,
          "Explore until a sense shows you a goal, but do not go to the goal. Instead compare "
          "two places: your starting cell and the cell your very first move took you to. Go "
          "with one move to whichever of the two is nearer to that goal, counting steps along "
          "rows and columns and ignoring obstacles (your starting cell if they are equally "
          "near; if that sense showed several goals, measure to any one of them), and stop; if "
          "you are standing on it already, just stop. If the goal came into view before you "
          "had moved at all, stop right there.",
          f"goal_found() and sensed()[-1:] != [] and any((steps_after_goal() == 0 and (moves() "
          f"== [] or t == {_L})) or (steps_after_goal() == 1 and primitives()[-1] == 'navigate' "
          f"and len(moves()) >= 2 and moves()[-1] == t and t != {_L}) for g in [{_L}] + "
          f"neighbours({_L}) if is_goal(g) for t in [{_S} if {_dist(_S, 'g')} <= "
          f"{_dist('(moves() + [start_cell()])[0]', 'g')} else (moves() + [start_cell()])[0]])"),
    _task("up_until_second_opening", 2, check_up_until_second_opening,
          "Sense, then walk up (j + 1) one cell at a time, sensing after every move, while the "
          "cell above you is inside the grid and free. Keep count of the cells you move onto "
          "that have a free cell directly to their right (i + 1), and stop right after the "
          "sense on the second of them. If the cell above you is outside the grid or an "
          "obstacle before that, stop there.",
          f"{_LINE} and moves() == [({_S0}, {_S1} + n) for n in {_N}][:len(moves())] and "
          f"len([m for m in moves()[:-1] if {_OPENING.format(m='m')}]) < 2 and (len([m for m in "
          f"moves() if {_OPENING.format(m='m')}]) == 2 or {_up_shut(_L)})"),
    _task("back_to_second_look", 2, check_back_to_second_look,
          "Explore, moving and sensing, until you have sensed five times. Then go back with one "
          "move to the cell where you took your second sense, and stop there (if you are "
          "standing on it, just stop). If there is nothing more to find before your fifth "
          "sense, go back there in the same way right after the sense that leaves nothing more "
          "to find.",
          f"len(sensed()) >= 2 and len(sensed()) <= 5 and ((len(sensed()) == 5 and not "
          f"explored_all()) or (explored_all() and {_FRESH_LOOK})) and ((primitives()[-1] == "
          f"'sense' and {_L} == sensed()[1]) or (primitives()[-2:] == ['sense', 'navigate'] and "
          f"moves()[-1] == sensed()[1] and {_L} != sensed()[1]))"),
    _task("halfway_cell", 3, check_halfway_cell,
          "Explore until a sense shows you a goal. Then go with one move to a cell you know to "
          "be free that lies as nearly as possible halfway between your starting cell and that "
          "goal: the difference between its distance to your start and its distance to the "
          "goal (counting steps along rows and columns, ignoring obstacles) must be as small "
          "as for any free cell you know (any of them if several tie; if that sense showed "
          "several goals, measure to any one of them). Stop there; if the cell you stand on is "
          "already such a cell, just stop.",
          f"goal_found() and sensed()[-1:] != [] and any(steps_after_goal() == (0 if {_gap(_L)} "
          f"== b else 1) and {_gap('final_cell()')} == b and (steps_after_goal() == 0 or "
          f"(primitives()[-1] == 'navigate' and final_cell() in known_cells() and not "
          f"is_obstacle(final_cell()))) for g in [{_L}] + neighbours({_L}) if is_goal(g) for b in "
          f"[min([{_gap('c')} for c in known_cells() if not is_obstacle(c)])])"),
    _task("three_turn_walk", 3, check_three_turn_walk,
          "Walk with clockwise turns. Sense, then walk up (j + 1) one cell at a time, sensing "
          "after every move, while the cell ahead of you is inside the grid and free. When it "
          "is not, turn clockwise -- from up to right (i + 1), from right to down (j - 1), from "
          "down to left (i - 1) -- and walk on the same way in the new direction; if the new "
          "direction is blocked at once, turn again. Stop when the cell ahead is outside the "
          "grid or an obstacle while you are heading left: a fourth turn is never made.",
          f"{_LINE} and len(moves()) <= 36 and all([c for c in [(q[0], q[1] + 1), (q[0] + 1, "
          f"q[1]), (q[0], q[1] - 1), (q[0] - 1, q[1])][P:] if c in neighbours(q) and not "
          f"is_obstacle(c)][:1] == moves()[k:k + 1] for k in {indices(37)}[:len(moves()) + 1] for q, "
          f"P in [({_Q}, {_WAS})])"),
    _task("down_left_retrace", 3, check_down_left_retrace,
          "Sense, then walk down (j - 1) one cell at a time while the cell below you is inside "
          "the grid and free, and from where that walk ends walk left (i - 1) the same way "
          "while the cell to your left is inside the grid and free, sensing after every move "
          "of both walks. Then come back the way you went: move back onto each cell you stood "
          "in, in reverse order, one move per cell and without sensing, ending with a move "
          "onto your starting cell (if you never moved, just stop).",
          f"primitives() == ['sense'] + ['navigate', 'sense'] * {_K} + ['navigate'] * {_K} and "
          f"{_K} <= 18 and sensed() == [{_S}] + moves()[:{_K}] and moves()[{_K}:] == "
          f"sensed()[:-1][::-1] and all((q[0] == {_S0} and moves()[k] == (q[0], q[1] - 1)) or "
          f"(moves()[k] == (q[0] - 1, q[1]) and (q[0] < {_S0} or {_down_shut('q')})) for k in "
          f"{indices(19)}[:{_K}] for q in [sensed()[k]]) and {_left_shut(_L)} and ({_L}[0] < {_S0} "
          f"or {_down_shut(_L)})"),
    _task("hug_home_walk", 3, check_hug_home_walk,
          "Stay close to home while you look around. Sense, then make up to eight moves, "
          "sensing after every move, each onto a free cell right next to you where you have "
          "never stood (your starting cell counts as stood in). Of those cells always take the "
          "one nearest to your starting cell, counting steps along rows and columns and "
          "ignoring obstacles; if several are equally near, the first of up (j + 1), right "
          "(i + 1), down (j - 1) and left (i - 1). Stop after the eighth move, or earlier when "
          "every free cell next to you is one you have stood in.",
          f"{_LINE} and len(moves()) <= 8 and all((P != [] and moves()[k] == min(P)[2]) if k < "
          f"len(moves()) else (len(moves()) == 8 or P == []) for k in {indices(9)}[:len(moves()) + "
          f"1] for P in [{_HUG}])"),
    _task("scoop_fee", 2, check_scoop_fee,
          f"Every scoop costs {FEE} grams. Scoop at least once and at most five times, then "
          f"stop, so that the grams of grains in the receiver, less {FEE} grams for every scoop "
          f"you made, come to at least {NET}.",
          f"scoops() >= 1 and scoops() <= 5 and delivered() - {FEE} * scoops() >= {NET}", SCOOP),
    _task("moved_out_of_donor", 1, check_moved_out_of_donor,
          f"Scoop exactly twice, then stop. Together the two scoops must take at least {MOVED} "
          f"grams of grains out of the donor for good: count what ends up in the receiver and "
          f"what is spilled outside both containers.",
          f"scoops() == 2 and delivered() + spilled() >= {MOVED}", SCOOP),
]
