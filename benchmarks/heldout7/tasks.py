"""Held-out tasks, seventh set: written before the next change of the synthesizer, run once after.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout7/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (a goal next to the start, else a
sideways step along the row, else one along the column; a step off the grid's border; a second
step that keeps the first step's direction; a return decided by comparing the obstacles two
senses showed; exploring on a leash of 5 steps from the start, then home; a search that ignores
goals nearer than 4 steps; a travel budget of 12 steps summed over the moves; a climb that goes
up whenever it can and right otherwise; mapping the 5x5 square around the start without leaving
it; eight moves of the right-hand rule; after exploring, the goal with the fewest obstacles next
to it; a search that never stands in a cell twice and goes home when stuck) and two scooping
tasks (a range of scoop counts with a bound on the grams per scoop; a bound on the grams
delivered less those spilled, beside a bound on the spill). Each has a reference behavior
(``references/``), a ground-truth ``check`` and a faithful ``promise`` over the env's outcome
helpers, so that the search can be measured apart from the model. They were written on
2026-12-06 blind: without reading the search's code and without running the synthesizer on
them; the first run of the search on them is the evaluation, reported beside the development
figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and
every cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a
*row* is the cells of one j, a *column* those of one i; the *border* is the cells with i or j
equal to 0 or 9; a sense labels its cell and the four around it (a goal is *in sight* when it is
among them); the obstacles *next to* a cell are those among its four neighbours inside the grid
(the grid's edge does not count); a cell *stood in* is the start cell or one a move ended in;
the *distance* of two cells, and a move's *length* (from the cell it began in to the one it
ended in), count steps along rows and columns (|di| + |dj|), obstacles ignored; the *square* is
the cells at most 2 columns and 2 rows from the start; in the right-hand rule the *heading* is
the direction of the last move (up before the first), turning right maps (di, dj) to (dj, -di).
The start cell always has a free neighbour (a goal is reachable from it and it holds none). The
scooping checks weigh the grains at the end, as ``delivered()`` and ``spilled()`` do: those in
the receiver, and those outside the receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``, each reference with its task's promise):
every grid reference kept its promise and did its task on all 1,000 episodes (0-99 of seed 0,
0-299 of seeds 1, 2 and 3), the promise's verdict equal to the check's on all. On those
episodes the tasks' branches all came up: a goal next to the start 128 times, a step along the
column 105; a choice between border and inner cells 396; a second straight step 631; the return
after comparing looks 262; the leash's exhaustion branch 10 (990 went 5 steps out); a search
with no distant goal in view before nothing was left 42; the travel budget's exhaustion branch 7
(at most 12 moves otherwise); a climb with no move 96, up to 18 moves; the square's survey up to
21 moves; the right-hand rule revisiting a cell 576; goals with different obstacle counts to
choose between 777; the search without going back stuck 468 times, walking up to 34 cells.
Faithfulness on behaviors that do not do the tasks: every grid promise was judged against 143
grid behaviors (the 12 references, 44 near misses written for this set -- other thresholds,
other directions or orders, a missing return or sense, a different goal or square -- the trivial
ones, and the grid references of the development and earlier held-out sets) on episodes 0-99
of seed 0, and the near misses and trivial behaviors again on episodes 0-299 of seed 1: on
every judged episode the promise's verdict equalled the check's. Keep rates of the trivial
behaviors: stopping at once and navigating onto the cell it stands in keep no promise on any
episode; sensing once keeps none but up_else_right_climb's (6 of 100 episodes of seed 0, 22 of
300 of seed 1: starts where neither the cell above nor the one to the right is free, where the
task asks for the one sense). The scooping references (three scoops from the default sensing
pose), run on episodes 0-19 of seed 0, kept their promises and did their tasks on all 20: the
receiver held 88.2 to 140.2 g (the bound for three scoops is 75 g), the spill was 0 to 22.6 g
(the bound is 30 g) and the grams delivered less those spilled 67.9 to 133.5 (the bound is
55); one scoop alone kept neither promise on those 20 episodes, the check agreeing.
"""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (cell, distance, exhausted, free_cell, free_neighbours,
                                        grams_in_receiver, grams_spilled, held_out_task, indices,
                                        moves, neighbours, obstacles_beside, reachable, same_steps,
                                        scoops, sensed_cells, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE, UNEXPLORED

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP, DOWN = (1, 0), (-1, 0), (0, 1), (0, -1)


def _sense(state, known, step) -> None:
    if step[0] == "sense":
        for n in [step[1], *neighbours(state, step[1])]:
            known[n] = True



# --- checks -------------------------------------------------------------------------------

def check_goal_or_row_step(state, result):
    """One sense; one move: onto a goal next to the start if there is one, else onto a free
    cell left or right of it if there is one, else onto a free cell above or below it."""
    home, steps = state.start_cell, steps_of(result)
    goals = [n for n in neighbours(state, home) if state.truth[n] == GOAL]
    row = [n for n in free_neighbours(state, home) if n[1] == home[1]]
    targets = goals or row or free_neighbours(state, home)
    if len(steps) == 2 and steps[0] == ("sense", home) and steps[1][0] == "navigate" \
            and steps[1][1] in targets:
        return None
    return f"ran {steps[:4]}; goals next to the start {goals}, free in its row {row}"


def _inner(state, c) -> bool:
    return 0 < c[0] < state.size - 1 and 0 < c[1] < state.size - 1


def check_inward_step(state, result):
    """One sense; one move onto a free cell next to the start that is off the grid's border,
    or onto any free cell next to it if none is."""
    home, steps = state.start_cell, steps_of(result)
    inner = [n for n in free_neighbours(state, home) if _inner(state, n)]
    targets = inner or free_neighbours(state, home)
    if len(steps) == 2 and steps[0] == ("sense", home) and steps[1][0] == "navigate" \
            and steps[1][1] in targets:
        return None
    return f"ran {steps[:4]}; free cells next to the start off the border: {inner}"


def check_straight_two_steps(state, result):
    """Sense; a move onto a free cell next to the start and a sense there; then, if the next
    cell the same way is inside the grid and free, a move onto it and a sense there."""
    home, steps = state.start_cell, steps_of(result)
    if len(steps) < 3 or steps[0] != ("sense", home) or steps[1][0] != "navigate" \
            or steps[1][1] not in free_neighbours(state, home) or steps[2] != ("sense", steps[1][1]):
        return f"ran {steps[:4]}: not a sense, a step onto a free neighbour and a sense there"
    a = steps[1][1]
    b = (2 * a[0] - home[0], 2 * a[1] - home[1])
    return same_steps(steps[3:], [("navigate", b), ("sense", b)] if free_cell(state, b) else [])


def check_compare_two_looks(state, result):
    """Sense; a move onto a free cell next to the start and a sense there; then a move back
    onto the start if that cell has more obstacles next to it than the start has."""
    home, steps = state.start_cell, steps_of(result)
    if len(steps) < 3 or steps[0] != ("sense", home) or steps[1][0] != "navigate" \
            or steps[1][1] not in free_neighbours(state, home) or steps[2] != ("sense", steps[1][1]):
        return f"ran {steps[:4]}: not a sense, a step onto a free neighbour and a sense there"
    a = steps[1][1]
    back = obstacles_beside(state, a) > obstacles_beside(state, home)
    return same_steps(steps[3:], [("navigate", home)] if back else [])


def check_five_out_then_home(state, result):
    """Exploring; the first move ending 5 or more steps from the start is followed by one move
    onto the start and nothing else; if the sense after which nothing more is to be found
    comes first, it is followed by one move onto the start (or by nothing, at the start)."""
    home, steps = state.start_cell, steps_of(result)
    known = state.truth != state.truth
    for index, step in enumerate(steps):
        _sense(state, known, step)
        rest = steps[index + 1:]
        if step[0] == "navigate" and distance(step[1], home) >= 5:
            return same_steps(rest, [("navigate", home)])
        if step[0] == "sense" and exhausted(state, known):
            if rest == [] and state.cell == home:
                return None
            return same_steps(rest, [("navigate", home)])
    return "never 5 steps from the start, and more could be found"


def _far_goals(state, c) -> list[tuple[int, int]]:
    """The goals a sense at ``c`` shows that are 4 or more steps from the start."""
    return [x for x in sensed_cells(state, c)
            if state.truth[x] == GOAL and distance(x, state.start_cell) >= 4]


def check_distant_goal(state, result):
    """Exploring; the first sense that shows a goal 4 or more steps from the start is followed
    by one move onto such a goal it showed and nothing else; if the sense after which nothing
    more is to be found comes first, nothing follows it."""
    steps = steps_of(result)
    known = state.truth != state.truth
    for index, step in enumerate(steps):
        _sense(state, known, step)
        if step[0] != "sense":
            continue
        rest, far = steps[index + 1:], _far_goals(state, step[1])
        if far:
            if len(rest) == 1 and rest[0][0] == "navigate" and rest[0][1] in far:
                return None
            return f"saw far goal(s) {far} at step {index + 1}, then ran {rest[:3]}"
        if exhausted(state, known):
            return same_steps(rest, [])
    return "no far goal seen, and more could be found"


def check_twelve_steps_travelled(state, result):
    """Exploring stops with the move after which the moves' lengths (steps along rows and
    columns from where each began to where it ended) add up to 12 or more, or with the sense
    after which nothing more is to be found, whichever comes first."""
    steps = steps_of(result)
    known = state.truth != state.truth
    here, travelled = state.start_cell, 0
    for index, step in enumerate(steps):
        _sense(state, known, step)
        if step[0] == "navigate":
            travelled += distance(here, step[1])
            here = step[1]
        if travelled >= 12 or (step[0] == "sense" and exhausted(state, known)):
            return same_steps(steps[index + 1:], [])
    return f"travelled {travelled} steps and more could be found"


def check_up_else_right_climb(state, result):
    """Sense; then, while the cell above or the cell to the right is inside the grid and free,
    a move onto the cell above if it is, else onto the cell to the right, each followed by a
    sense."""
    here, plan = state.start_cell, [("sense", state.start_cell)]
    while True:
        if free_cell(state, step_by(here, UP)):
            here = step_by(here, UP)
        elif free_cell(state, step_by(here, RIGHT)):
            here = step_by(here, RIGHT)
        else:
            break
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def _in_square(state, c) -> bool:
    """Whether ``c`` is at most 2 columns and 2 rows from the start."""
    home = state.start_cell
    return abs(c[0] - home[0]) <= 2 and abs(c[1] - home[1]) <= 2


def check_square_survey(state, result):
    """Every move ends in the 5x5 square centred on the start; at the end the start and every
    free cell of the square that is known have every cell next to them known."""
    out = [c for c in moves(result) if not _in_square(state, c)]
    if out:
        return f"moved out of the square to {out[:3]}"
    known = state.labels != UNEXPLORED
    size = state.size
    spots = [state.start_cell] + [(i, j) for i in range(size) for j in range(size)
                                  if known[i, j] and state.truth[i, j] != OBSTACLE
                                  and _in_square(state, (i, j))]
    loose = [c for c in spots if not (known[c] and all(known[n] for n in neighbours(state, c)))]
    return f"cells with something unknown next to them: {loose[:3]}" if loose else None


def check_right_hand_rule(state, result):
    """Sense; eight moves, each followed by a sense: heading first up, each onto the first
    free cell inside the grid to the right of the heading, straight on, to the left, or back;
    that way is the new heading."""
    here, heading, plan = state.start_cell, UP, [("sense", state.start_cell)]
    for _ in range(8):
        turns = [(heading[1], -heading[0]), heading, (-heading[1], heading[0]),
                 (-heading[0], -heading[1])]
        heading = next(d for d in turns if free_cell(state, step_by(here, d)))
        here = step_by(here, heading)
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_least_hemmed_goal(state, result):
    """Nothing more to find; ends on a reachable goal with no more obstacles next to it than
    any other reachable goal has."""
    if not exhausted(state):
        return "stopped before everything was known"
    goals = [cell(c) for c in zip(*(reachable(state) & (state.truth == GOAL)).nonzero())]
    fewest = min(obstacles_beside(state, g) for g in goals)
    if state.truth[state.cell] == GOAL and obstacles_beside(state, state.cell) == fewest:
        return None
    return f"ended in {state.cell}; the goals and their obstacles: " \
           f"{[(g, obstacles_beside(state, g)) for g in goals]}"


def check_no_backtrack_search(state, result):
    """Sense; then, while no sense has shown a goal, a move onto a free cell next to the agent
    never stood in and a sense there; after the first sense that shows a goal, one move onto
    a goal it showed; if no such cell is left before, one move onto the start."""
    home, steps = state.start_cell, steps_of(result)
    if steps[:1] != [("sense", home)]:
        return f"ran {steps[:2]}, not a sense at the start first"
    stood, index = [home], 1
    while True:
        here, rest = stood[-1], steps[index:]
        goals = [x for x in sensed_cells(state, here) if state.truth[x] == GOAL]
        if goals:
            if len(rest) == 1 and rest[0][0] == "navigate" and rest[0][1] in goals:
                return None
            return f"saw goal(s) {goals} from {here}, then ran {rest[:3]}"
        fresh = [n for n in free_neighbours(state, here) if n not in stood]
        if not fresh:
            return same_steps(rest, [("navigate", home)])
        if len(rest) < 2 or rest[0][0] != "navigate" or rest[0][1] not in fresh \
                or rest[1] != ("sense", rest[0][1]):
            return f"from {here} ran {rest[:2]}, not a step onto one of {fresh} and a sense"
        stood.append(rest[0][1])
        index += 2


def check_two_to_four_scoops_25g_each(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass = grams_in_receiver(state)
    return None if mass >= 25 * n else f"{mass:.1f} g in the receiver after {n} scoops"


NET, SPILL = 55, 30  # grams: delivered less spilled, and spilled


def check_three_scoops_net_gain(state, result):
    n = len(scoops(result))
    if len(result.steps) != 3 or n != 3:
        return f"{n} scoop(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if mass - spilled >= NET and spilled <= SPILL else \
        f"{mass:.1f} g delivered, {spilled:.1f} g spilled"



# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)




_S = "start_cell()"
_LINE = "primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and " \
        "sensed() == [start_cell()] + moves()"
_FRESH = "len(known_before_last()) < len(known_cells())"  # the last step labelled something


def _d(x: str) -> str:
    """Steps along rows and columns from the start to ``x``."""
    return f"(abs({x}[0] - start_cell()[0]) + abs({x}[1] - start_cell()[1]))"


def _crowded(x: str) -> str:
    return f"len([n for n in neighbours({x}) if is_obstacle(n)])"


def _inside(x: str) -> str:
    return f"({x}[0] > 0 and {x}[0] < 9 and {x}[1] > 0 and {x}[1] < 9)"


def _far(x: str) -> str:
    return f"(is_goal({x}) and {_d(x)} >= 4)"


def _up_free(p: str) -> str:
    return f"({p}[1] < 9 and not is_obstacle(({p}[0], {p}[1] + 1)))"


def _right_free(p: str) -> str:
    return f"({p}[0] < 9 and not is_obstacle(({p}[0] + 1, {p}[1])))"


def _square(x: str) -> str:
    return f"(abs({x}[0] - start_cell()[0]) <= 2 and abs({x}[1] - start_cell()[1]) <= 2)"


_M0 = "moves()[0]"
_ONE_STEP = "primitives() == ['sense', 'navigate'] and sensed() == [start_cell()] and " \
            f"{_M0} in neighbours(start_cell()) and not is_obstacle({_M0})"
_STEP_LOOK = "primitives()[:3] == ['sense', 'navigate', 'sense'] and sensed()[:2] == " \
             f"[start_cell(), {_M0}] and {_M0} in neighbours(start_cell()) and not " \
             f"is_obstacle({_M0})"
_LAST_SENSE_FRESH = "any(not any(c in [x] + neighbours(x) for c in sensed()[:-1]) for x in " \
                    "[sensed()[-1]] + neighbours(sensed()[-1]))"
_STOOD = "([start_cell()] + moves())"
_TRAVELLED = f"sum(abs({_STOOD}[k + 1][0] - {_STOOD}[k][0]) + abs({_STOOD}[k + 1][1] - " \
             f"{_STOOD}[k][1]) for k in {indices(100)}[:len(moves())])"
_LAST_LENGTH = f"(abs(moves()[-1][0] - {_STOOD}[-2][0]) + abs(moves()[-1][1] - {_STOOD}[-2][1]))"
_HEADED = "([(start_cell()[0], start_cell()[1] - 1)] + sensed())"  # as if it came from below
_TURNS = "[(p[0] + p[1] - q[1], p[1] - p[0] + q[0]), (2 * p[0] - q[0], 2 * p[1] - q[1]), " \
         "(p[0] - p[1] + q[1], p[1] + p[0] - q[0]), (q[0], q[1])]"  # right, on, left, back

TASKS = [
    _task("goal_or_row_step", 1, check_goal_or_row_step,
          "Sense once where you start. If a goal is on one of the cells right next to you, "
          "step onto it. If not, step sideways along your row onto a free cell to your left "
          "(i - 1) or right (i + 1); only if neither of those is free, step onto a free cell "
          "above (j + 1) or below (j - 1) you instead. Then stop.",
          f"{_ONE_STEP} and (is_goal({_M0}) if any(is_goal(n) for n in neighbours(start_cell())) "
          f"else {_M0}[1] == start_cell()[1] or not any(not is_obstacle(n) and n[1] == "
          f"start_cell()[1] for n in neighbours(start_cell())))"),
    _task("inward_step", 1, check_inward_step,
          "Sense once, then take one step away from the walls: move onto a free cell next to "
          "you that is not on the outer border of the grid (the border is every cell whose i "
          "or j is 0 or 9). If every free cell next to you is on the border, move onto any one "
          "of them. Then stop.",
          f"{_ONE_STEP} and ({_inside(_M0)} or not any(not is_obstacle(n) and {_inside('n')} "
          f"for n in neighbours(start_cell())))"),
    _task("straight_two_steps", 1, check_straight_two_steps,
          "Sense, step onto any free cell next to you and sense again. Then try to keep going "
          "the same way: if the next cell in that direction is inside the grid and not an "
          "obstacle, move onto it and sense a third time; if it is not, stop where you are.",
          "primitives()[:3] == ['sense', 'navigate', 'sense'] and all(sensed()[:2] == "
          "[start_cell(), a] and a in neighbours(start_cell()) and not is_obstacle(a) and "
          "(primitives() == ['sense', 'navigate', 'sense', 'navigate', 'sense'] and moves() == "
          "[a, b] and sensed()[2:] == [b] if b in neighbours(a) and not is_obstacle(b) else "
          "len(primitives()) == 3) for a in moves()[:1] for b in [(2 * a[0] - start_cell()[0], "
          "2 * a[1] - start_cell()[1])])"),
    _task("compare_two_looks", 2, check_compare_two_looks,
          "Sense at your starting cell, then step onto any free cell next to it and sense "
          "there too. Compare the two looks: if the cell you are now on has more obstacles on "
          "the cells right next to it than your starting cell has (the grid's edge does not "
          "count as an obstacle), go back to your starting cell and stop; if it has the same "
          "number or fewer, stay where you are and stop.",
          f"{_STEP_LOOK} and (primitives()[3:] == ['navigate'] and moves()[1:] == "
          f"[start_cell()] if {_crowded(_M0)} > {_crowded(_S)} else len(primitives()) == 3)"),
    _task("five_out_then_home", 2, check_five_out_then_home,
          "Explore the grid, moving and sensing, but stay on a short leash: the moment a move "
          "ends on a cell 5 or more steps from your starting cell (counting steps along rows "
          "and columns, ignoring obstacles), go straight back to your starting cell with one "
          "move and stop. If there is nothing more to find before that happens, go back to "
          "your starting cell right after the sense that leaves nothing more to find (if you "
          "are already there, just stop).",
          f"all({_d('m')} < 5 for m in moves()[:-2]) and ((len(moves()) >= 2 and "
          f"primitives()[-2:] == ['navigate', 'navigate'] and moves()[-1] == start_cell() and "
          f"{_d('moves()[-2]')} >= 5 and not explored_all()) or (explored_all() and "
          f"final_cell() == start_cell() and (len(moves()) < 2 or {_d('moves()[-2]')} < 5) and "
          f"(primitives()[-1:] == ['sense'] or (primitives()[-2:] == ['sense', 'navigate'] and "
          f"moves()[-1] == start_cell())) and {_LAST_SENSE_FRESH}))"),
    _task("distant_goal", 2, check_distant_goal,
          "Search for a goal that is at least 4 steps away from your starting cell (counting "
          "steps along rows and columns, ignoring obstacles); goals nearer than that do not "
          "interest you. As soon as a sense shows you such a distant goal, move onto it and "
          "stop. If there is nothing more to find before any distant goal comes into view, "
          "stop right after the sense that leaves nothing more to find.",
          f"(primitives()[-2:] == ['sense', 'navigate'] and {_far('final_cell()')} and "
          f"final_cell() in [sensed()[-1]] + neighbours(sensed()[-1]) and not "
          f"any({_far('x')} for c in sensed()[:-1] for x in [c] + neighbours(c))) or "
          f"(primitives()[-1:] == ['sense'] and explored_all() and {_FRESH} and not "
          f"any({_far('g')} for g in known_cells()))"),
    _task("twelve_steps_travelled", 2, check_twelve_steps_travelled,
          "Explore with a travel budget of 12 steps. Measure each move as the number of steps "
          "along rows and columns between the cell where it began and the cell where it ended "
          "(obstacles ignored), and add these up. Stop right after the move that brings the "
          "total to 12 or more. If there is nothing more to find before that, stop right "
          "after the sense that leaves nothing more to find.",
          f"all((primitives()[-1:] == ['navigate'] and not explored_all() and t >= 12 and "
          f"t - {_LAST_LENGTH} < 12) or (primitives()[-1:] == ['sense'] and explored_all() and "
          f"{_FRESH} and t < 12) for t in [{_TRAVELLED}])"),
    _task("up_else_right_climb", 2, check_up_else_right_climb,
          "Sense, then climb one cell at a time, sensing after every move: go up (j + 1) "
          "whenever the cell above you is inside the grid and free; when it is not, go right "
          "(i + 1) instead if that cell is inside the grid and free. Check again after every "
          "move, going up again as soon as you can. Stop when you can go neither up nor right.",
          f"{_LINE} and len(moves()) <= 18 and all(moves()[k] == ((p[0], p[1] + 1) if "
          f"{_up_free('p')} else (p[0] + 1, p[1])) and ({_up_free('p')} or {_right_free('p')}) "
          f"for k in {indices(18)}[:len(moves())] for p in [sensed()[k]]) and not "
          f"{_up_free('final_cell()')} and not {_right_free('final_cell()')}"),
    _task("square_survey", 3, check_square_survey,
          "Map the 5-by-5 square of cells centred on your starting cell: the cells at most 2 "
          "columns and at most 2 rows away from it. Move and sense as you need, but every move "
          "must end on a cell inside that square. When you stop, your starting cell and every "
          "cell inside the square that you know to be free must have all the cells next to "
          "them known (these may lie just outside the square), so that nothing more can be "
          "found inside it.",
          f"all({_square('m')} for m in moves()) and start_cell() in known_cells() and "
          f"all(n in known_cells() for c in known_cells() if {_square('c')} and not "
          f"is_obstacle(c) for n in neighbours(c))"),
    _task("right_hand_rule", 3, check_right_hand_rule,
          "Follow the right-hand rule for eight moves. You start out facing up (j + 1), so your "
          "right is i + 1. Sense, then before every move turn towards the first of these "
          "directions whose next cell is inside the grid and free: to your right, straight "
          "ahead, to your left, or back the way you came. Move one cell that way (you now "
          "face that way) and sense again. "
          "Stop after the eighth move and its sense.",
          f"{_LINE} and len(moves()) == 8 and all([c for c in {_TURNS} if c in neighbours(p) "
          f"and not is_obstacle(c)][:1] == [n] for k in {indices(8)} for q, p, n in "
          f"[({_HEADED}[k], {_HEADED}[k + 1], {_HEADED}[k + 2])])"),
    _task("least_hemmed_goal", 3, check_least_hemmed_goal,
          "Explore until there is nothing more to find. Then go to the goal you can reach that "
          "has the fewest obstacles on the cells right next to it (the grid's edge does not "
          "count; any of them if several tie), and stop on it.",
          f"explored_all() and is_goal(final_cell()) and all({_crowded('final_cell()')} <= "
          f"{_crowded('g')} for g in reachable_goals())"),
    _task("no_backtrack_search", 3, check_no_backtrack_search,
          "Search for a goal without ever going back: sense, then repeatedly step onto a free "
          "cell right next to you where you have never stood (your starting cell counts as "
          "stood in) and sense there. As soon as a sense shows you a goal, step onto it and "
          "stop. If you get stuck first, with every free cell next to you already stood in, go "
          "straight back to your starting cell with one move and stop.",
          f"len(moves()) >= 1 and len(moves()) <= 80 and primitives() == ['sense'] + "
          f"['navigate', 'sense'] * (len(moves()) - 1) + ['navigate'] and sensed() == "
          f"[start_cell()] + moves()[:-1] and all(moves()[k] in neighbours(sensed()[k]) and "
          f"moves()[k] not in sensed()[:k + 1] and not is_obstacle(moves()[k]) for k in "
          f"{indices(80)}[:len(moves()) - 1]) and ((steps_after_goal() == 1 and "
          f"is_goal(final_cell()) and final_cell() in [sensed()[-1]] + "
          f"neighbours(sensed()[-1])) or (steps_after_goal() == -1 and final_cell() == "
          f"start_cell() and all(is_obstacle(n) or n in sensed() for n in "
          f"neighbours(sensed()[-1]))))"),
    _task("two_to_four_scoops_25g_each", 2, check_two_to_four_scoops_25g_each,
          "Scoop at least twice and at most four times, then stop. On average each scoop you "
          "made must have brought at least 25 grams of grains into the receiver: after two "
          "scoops the receiver must hold at least 50 g, after three at least 75 g, after four "
          "at least 100 g.",
          "scoops() >= 2 and scoops() <= 4 and delivered() >= 25 * scoops()", SCOOP),
    _task("three_scoops_net_gain", 2, check_three_scoops_net_gain,
          f"Scoop exactly three times. What ends up in the receiver, less what you spilled "
          f"outside the containers, must come to at least {NET} grams, and the spill itself "
          f"must stay at or below {SPILL} grams.",
          f"scoops() == 3 and delivered() - spilled() >= {NET} and spilled() <= {SPILL}",
          SCOOP),
]
