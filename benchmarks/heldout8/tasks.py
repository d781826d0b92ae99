"""Held-out tasks, eighth set: written before the next change of the synthesizer, run once after.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout8/tasks.py --list

Twelve grid tasks of kinds none of the earlier sets has (a step onto a neighbour of the start,
then across to the cell mirroring it on the other side of the start, else back; a step up when
the column is open both ways, else right when the row is, else anywhere free; a wander that stops
at the first sense telling nothing new; a search that stops on seeing two obstacles that touch; a
walk down that follows the bottom edge left only if it reached it; a straight walk as long as the
count of free cells around the start; after the first goal, a second goal next to it; a walk
along the row that stops on a crossroads; exploring everything without one wasted sense; after
exploring, the reachable cell farthest from its nearest obstacle; a cell four steps straight out
along the start's row or column; a search that stops on knowing ten free cells) and two scooping
tasks (two or three scoops with a bound on the spill per scoop beside a bound on the grams
delivered; two to four scoops with the grams delivered bounded above as well as below). Each has
a reference behavior (``references/``), a ground-truth ``check`` and a faithful ``promise`` over
the env's outcome helpers, so that the search can be measured apart from the model. They were
written on 2026-12-06 blind: without reading the search's code and without running the
synthesizer on them; the first run of the search on them is the evaluation, reported beside the
development figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle
(empty or a goal); *known* when the agent's label of it is not 'unexplored'; *reachable* when it
lies in the start cell's free component; *nothing more to find* when every reachable cell and
every cell next to one is known; *up* is j + 1, *down* j - 1, *right* i + 1, *left* i - 1; a
*row* is the cells of one j, a *column* those of one i; the *bottom row* is j = 0; a sense labels
its cell and the four around it (a goal is *in sight* when it is among them); a sense *tells
nothing new* when every cell it labels was labelled by an earlier sense of the behavior; two
obstacles *touch* when they are next to each other (in a row or a column, not diagonally); the
cells *next to* a cell are its four neighbours inside the grid (the grid's edge is neither free
nor an obstacle); a *crossroads* is a cell with three or more free cells next to it; the
*distance* of two cells counts steps along rows and columns (|di| + |dj|), obstacles ignored,
and a cell's distance *from its nearest obstacle* is taken over all obstacles of the grid (after
exploring everything these are as near as the known ones). The start cell always has a free
neighbour (a goal is reachable from it and it holds none). The scooping checks weigh the grains at
the end, as ``delivered()`` and ``spilled()`` do: those in the receiver, and those outside the
receiver, the donor and the spoon's tray.

Validation before the set was fixed (``evaluate``, each reference with its task's promise): every
grid reference kept its promise and did its task on all 300 episodes (0-99 of seeds 0, 1 and 2),
the promise's verdict equal to the check's on all. On those episodes the tasks' branches came up:
the mirror cell free 145 times, the way back 155; an open column 129, an open row 78, neither 93;
the wander up to 11 moves (the reference always ended on a cell stood in before; a stop on a
fresh cell that tells nothing new came up only in the behaviors judged below); a touching pair
seen in all 300 (the exhaustion branch never came up); the walk down with no move 90, reaching
the bottom row 99, then going left along it 65, up to 13 moves; 1, 2, 3 and 4 free cells around
the start 29, 104, 118 and 49 times, the walk stopped short of the count 158; a second goal next
to the first 22; the row walk going left 74, with no move 28, ending on a crossroads 192; the
efficient exploring up to 66 senses; the clearest cell 1 to 6 steps from an obstacle; no cell
four steps out reachable 35; nothing more to find before ten free cells were known 2.
Faithfulness on behaviors that do not do the tasks: every grid promise was judged against the other
11 references of this set, 49 behaviors written for it (46 near misses -- other thresholds,
directions or orders, a missing or extra sense or move, another goal or cell -- and 3 other ways of
doing the tasks) and 3 trivial behaviors (sense once, sense twice, navigate onto the cell it stands
in) on episodes 0-99 of seed 0, the written and trivial behaviors again on episodes 0-99 of seed 1,
and the 93 grid references of the development and earlier held-out sets on episodes 0-49 of seed 0:
on every judged episode the promise's verdict equalled the check's. Keep rates of the trivial
behaviors: sensing twice and navigating onto the cell it stands in keep no promise on any episode;
sensing once keeps none but down_then_edge_left's (28 of 100 episodes of seed 0, 26 of 100 of seed
1: starts above the bottom row with an obstacle below, or on it with the left blocked, where the
task asks for the one sense; 90 of the 300 reference episodes were such starts) and
row_to_junction's (10 and 9 of 100; 28 of the 300: starts with both row neighbours blocked).
The scooping references, run on episodes 0-7 of seed 0, kept their promises and did their tasks
on all 8: three scoops left 88.2 to 140.2 g in the receiver (the bound is 60 g) and spilled 4.5
to 20.4 g (the bound is 30 g); two scoops left 61.1 to 104.0 g (the bounds are 50 and 120 g). One
scoop alone (episodes 0-3) kept neither promise; four scoops left 108.6 to 171.9 g, over the cap
of 120 g in 3 of 4 episodes, the check agreeing on every judged episode.
"""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (cell, distance, exhausted, first_goal_sense, free_cell,
                                        free_neighbours, grams_in_receiver, grams_spilled,
                                        held_out_task, indices, label_sensed, neighbours, on_grid,
                                        reachable, same_steps, scoops, sensed_cells, step_by,
                                        steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP, DOWN = (1, 0), (-1, 0), (0, 1), (0, -1)




def _walk(state, result, first: int = 1):
    """The steps after the first ``first`` ones, read as (move, sense there) pairs: the list of
    cells moved to, or a reason why the steps are not such pairs."""
    steps, cells = steps_of(result)[first:], []
    for k in range(0, len(steps), 2):
        pair = steps[k:k + 2]
        if len(pair) != 2 or pair[0][0] != "navigate" or pair[1] != ("sense", pair[0][1]):
            return f"steps {pair} are not a move and a sense there"
        cells.append(pair[0][1])
    return cells



# --- checks -------------------------------------------------------------------------------

def check_mirror_step(state, result):
    """One sense; a move onto a free cell next to the start; then a move onto the cell on the
    other side of the start from it if that is inside the grid and free, else onto the start."""
    home, steps = state.start_cell, steps_of(result)
    if len(steps) != 3 or steps[0] != ("sense", home) or steps[1][0] != "navigate" \
            or steps[1][1] not in free_neighbours(state, home) or steps[2][0] != "navigate":
        return f"ran {steps[:4]}: not a sense, a step onto a free neighbour and a move"
    a = steps[1][1]
    b = (2 * home[0] - a[0], 2 * home[1] - a[1])
    want = b if free_cell(state, b) else home
    return None if steps[2][1] == want else f"went to {steps[2][1]} after {a}, not {want}"


def check_corridor_step(state, result):
    """One sense; one move: up if the cells above and below the start are both free, else
    right if the cells left and right of it are both free, else onto any free neighbour."""
    home, steps = state.start_cell, steps_of(result)
    if free_cell(state, step_by(home, UP)) and free_cell(state, step_by(home, DOWN)):
        targets = [step_by(home, UP)]
    elif free_cell(state, step_by(home, LEFT)) and free_cell(state, step_by(home, RIGHT)):
        targets = [step_by(home, RIGHT)]
    else:
        targets = free_neighbours(state, home)
    if len(steps) == 2 and steps[0] == ("sense", home) and steps[1][0] == "navigate" \
            and steps[1][1] in targets:
        return None
    return f"ran {steps[:4]}, not a sense and a move onto one of {targets}"


def check_wander_until_nothing_new(state, result):
    """Sense; then moves, each onto a free cell next to the agent and followed by a sense
    there; it stops right after the first sense that labels no cell an earlier sense had not."""
    home, steps = state.start_cell, steps_of(result)
    if steps[:1] != [("sense", home)]:
        return f"ran {steps[:2]}, not a sense at the start first"
    known = state.truth != state.truth
    label_sensed(state, known, steps[0])
    here, index = home, 1
    while True:
        rest = steps[index:]
        if len(rest) < 2 or rest[0][0] != "navigate" or rest[0][1] not in \
                free_neighbours(state, here) or rest[1] != ("sense", rest[0][1]):
            return f"from {here} ran {rest[:2]}, not a step onto a free neighbour and a sense"
        here, index = rest[0][1], index + 2
        if not label_sensed(state, known, rest[1]):
            return same_steps(steps[index:], [])


def _touching(state, known) -> bool:
    """Whether two known obstacles are next to each other."""
    size = state.size
    return any(known[i, j] and state.truth[i, j] == OBSTACLE and known[n]
               and state.truth[n] == OBSTACLE
               for i in range(size) for j in range(size) for n in neighbours(state, (i, j)))


def check_two_touching_obstacles(state, result):
    """Exploring stops with the sense after which two known obstacles are next to each other,
    or with the sense after which nothing more is to be found, whichever comes first."""
    steps = steps_of(result)
    known = state.truth != state.truth
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        if step[0] == "sense" and (_touching(state, known) or exhausted(state, known)):
            return same_steps(steps[index + 1:], [])
    return "no two touching obstacles known, and more could be found"


def check_down_then_edge_left(state, result):
    """Sense; down while the cell below is free, each move followed by a sense; then, only if
    that ended in the bottom row, left while the cell to the left is free, sensing likewise."""
    here, plan = state.start_cell, [("sense", state.start_cell)]
    while free_cell(state, step_by(here, DOWN)):
        here = step_by(here, DOWN)
        plan += [("navigate", here), ("sense", here)]
    while here[1] == 0 and free_cell(state, step_by(here, LEFT)):
        here = step_by(here, LEFT)
        plan += [("navigate", here), ("sense", here)]
    return same_steps(steps_of(result), plan)


def check_free_count_straight_walk(state, result):
    """Sense; n = the free cells next to the start; a move onto one of them, then straight on
    the same way while the next cell is free, n moves at most, each followed by a sense."""
    home, steps = state.start_cell, steps_of(result)
    if steps[:1] != [("sense", home)]:
        return f"ran {steps[:2]}, not a sense at the start first"
    cells = _walk(state, result)
    if isinstance(cells, str):
        return cells
    if not cells or cells[0] not in free_neighbours(state, home):
        return f"moved to {cells[:2]}, not first onto a free cell next to the start"
    n, step = len(free_neighbours(state, home)), (cells[0][0] - home[0], cells[0][1] - home[1])
    here, want = cells[0], [cells[0]]
    while len(want) < n and free_cell(state, step_by(here, step)):
        here = step_by(here, step)
        want.append(here)
    return None if cells == want else f"moved to {cells}, not {want} ({n} free around the start)"


def check_goal_chain(state, result):
    """After the first sense that shows a goal: a move onto a goal it showed and a sense
    there; then one move onto another goal that sense showed, if it showed one; nothing else."""
    steps, found = steps_of(result), first_goal_sense(state, result)
    if found is None:
        return "no goal was seen"
    rest = steps[found + 1:]
    shown = [x for x in sensed_cells(state, steps[found][1]) if state.truth[x] == GOAL]
    if len(rest) < 2 or rest[0][0] != "navigate" or rest[0][1] not in shown \
            or rest[1] != ("sense", rest[0][1]):
        return f"saw goal(s) {shown}, then ran {rest[:3]}"
    first = rest[0][1]
    more = [x for x in neighbours(state, first) if state.truth[x] == GOAL]
    if more:
        if len(rest) == 3 and rest[2][0] == "navigate" and rest[2][1] in more:
            return None
        return f"from the goal {first} saw goal(s) {more}, then ran {rest[2:5]}"
    return same_steps(rest[2:], [])


def check_row_to_junction(state, result):
    """Sense; right while the cell to the right is free (left, the same way, if the cell to
    the right of the start is not free), each move followed by a sense, up to and including
    the first cell moved to that has three or more free cells next to it."""
    here, plan = state.start_cell, [("sense", state.start_cell)]
    way = RIGHT if free_cell(state, step_by(here, RIGHT)) else LEFT
    while free_cell(state, step_by(here, way)):
        here = step_by(here, way)
        plan += [("navigate", here), ("sense", here)]
        if len(free_neighbours(state, here)) >= 3:
            break
    return same_steps(steps_of(result), plan)


def check_efficient_explore(state, result):
    """Every sense labels a cell no earlier sense had; the last step is the sense after which
    nothing more is to be found."""
    steps = steps_of(result)
    known = state.truth != state.truth
    for index, step in enumerate(steps):
        if step[0] == "sense" and not label_sensed(state, known, step):
            return f"the sense at step {index + 1} ({step[1]}) showed nothing new"
        if step[0] == "sense" and exhausted(state, known):
            return same_steps(steps[index + 1:], [])
    return "more could be found"


def _clearance(state, c) -> int:
    """Steps along rows and columns from ``c`` to its nearest obstacle (obstacles ignored)."""
    obstacles = list(zip(*(state.truth == OBSTACLE).nonzero()))
    return min((distance(c, o) for o in obstacles), default=0)


def check_clearest_cell(state, result):
    """Nothing more to find; ends on a reachable cell whose nearest obstacle is at least as
    far as any other reachable cell's."""
    if not exhausted(state):
        return "stopped before everything was known"
    best = max(_clearance(state, cell(c)) for c in zip(*reachable(state).nonzero()))
    got = _clearance(state, state.cell)
    return None if got == best else f"ended in {state.cell}, {got} from an obstacle; best {best}"


def _line_cells(state) -> list[tuple[int, int]]:
    """The reachable cells 4 steps from the start along its row or its column."""
    i, j = state.start_cell
    reach = reachable(state)
    return [c for c in [(i + 4, j), (i - 4, j), (i, j + 4), (i, j - 4)]
            if on_grid(state, c) and reach[c]]


def check_four_in_line(state, result):
    """Ends on a reachable cell 4 steps from the start in its row or column; where there is
    none, nothing more is to be found at the end."""
    targets = _line_cells(state)
    if targets:
        return None if state.cell in targets else f"ended in {state.cell}, not one of {targets}"
    return None if exhausted(state) else "no such cell reachable, and more could be found"


def check_ten_free_cells_known(state, result):
    """Exploring stops with the sense after which 10 or more known cells are free, or with the
    sense after which nothing more is to be found, whichever comes first."""
    steps = steps_of(result)
    known = state.truth != state.truth
    for index, step in enumerate(steps):
        label_sensed(state, known, step)
        free = int((known & (state.truth != OBSTACLE)).sum())
        if step[0] == "sense" and (free >= 10 or exhausted(state, known)):
            return same_steps(steps[index + 1:], [])
    return "fewer than 10 free cells known, and more could be found"


LOW, HIGH, PER_SCOOP = 50, 120, 10  # grams: the fill's bounds; the spill allowed per scoop
NEEDED = 60  # grams delivered with the low spill


def check_low_spill_per_scoop(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 3:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass, spilled = grams_in_receiver(state), grams_spilled(state)
    return None if mass >= NEEDED and spilled <= PER_SCOOP * n else \
        f"{mass:.1f} g delivered, {spilled:.1f} g spilled in {n} scoops"


def check_capped_fill(state, result):
    n = len(scoops(result))
    if len(result.steps) != n or not 2 <= n <= 4:
        return f"{n} scoop(s) in {len(result.steps)} step(s)"
    mass = grams_in_receiver(state)
    return None if LOW <= mass <= HIGH else f"{mass:.1f} g in the receiver after {n} scoops"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)




_S = "start_cell()"
_LINE = "primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and " \
        "sensed() == [start_cell()] + moves()"
_FRESH = "len(known_before_last()) < len(known_cells())"  # the last step labelled something
_M0 = "moves()[0]"
_ONE_STEP = "primitives() == ['sense', 'navigate'] and sensed() == [start_cell()] and " \
            f"{_M0} in neighbours(start_cell()) and not is_obstacle({_M0})"


def _at(di: int, dj: int, p: str = _S) -> str:
    return f"({p}[0] + {di}, {p}[1] + {dj})"


def _open(x: str) -> str:
    """``x`` (a cell next to the start, or off the grid) is inside the grid and free."""
    return f"({x} in neighbours(start_cell()) and not is_obstacle({x}))"


def _new(k: str) -> str:
    """The sense sensed()[k] labelled a cell no earlier sense had."""
    return f"any(not any(x in [c] + neighbours(c) for c in sensed()[:{k}]) for x in " \
           f"[sensed()[{k}]] + neighbours(sensed()[{k}]))"


# For each pair of known obstacles next to each other (either order): whether both were known
# before the last step.
_PAIRS = "[o in known_before_last() and n in known_before_last() for o in known_obstacles() " \
         "for n in neighbours(o) if n in known_obstacles()]"


def _down_free(p: str) -> str:
    return f"({p}[1] > 0 and not is_obstacle(({p}[0], {p}[1] - 1)))"


def _left_free(p: str) -> str:
    return f"({p}[0] > 0 and not is_obstacle(({p}[0] - 1, {p}[1])))"


def _right_free(p: str) -> str:
    return f"({p}[0] < 9 and not is_obstacle(({p}[0] + 1, {p}[1])))"


def _ahead_free(p: str, h: str) -> str:
    """The cell ``h`` columns right of ``p`` is inside the grid and free."""
    return f"({p}[0] + {h} >= 0 and {p}[0] + {h} <= 9 and not is_obstacle(({p}[0] + {h}, {p}[1])))"


def _descend(p: str) -> str:
    """From ``p`` the walk goes on: down is free, or ``p`` is in the bottom row and left is."""
    return f"({_down_free(p)} or ({p}[1] == 0 and {_left_free(p)}))"


def _free_count(p: str) -> str:
    """How many of the four cells next to ``p`` are inside the grid and free."""
    return f"len([n for n in neighbours({p}) if not is_obstacle(n)])"


def _clear(x: str) -> str:
    """Steps from ``x`` to the nearest known obstacle."""
    return f"min(abs({x}[0] - o[0]) + abs({x}[1] - o[1]) for o in known_obstacles())"


def _free_known(cells: str) -> str:
    return f"len([c for c in {cells} if not is_obstacle(c)])"


_UP, _DOWN, _LEFT, _RIGHT = _at(0, 1), _at(0, -1), _at(-1, 0), _at(1, 0)
_DI, _DJ = f"({_M0}[0] - start_cell()[0])", f"({_M0}[1] - start_cell()[1])"  # the first step
_AHEAD = f"(final_cell()[0] + {_DI}, final_cell()[1] + {_DJ})"
_LINE4 = f"[{_at(4, 0)}, {_at(-4, 0)}, {_at(0, 4)}, {_at(0, -4)}]"

TASKS = [
    _task("mirror_step", 1, check_mirror_step,
          "Sense once where you start, then step onto any free cell right next to you. From "
          "there, cross over to the cell on the opposite side of your starting cell (if you "
          "stepped right, the cell just left of your start; if up, the one just below it) and "
          "stop there -- but if that opposite cell is outside the grid or an obstacle, go back "
          "to your starting cell and stop instead.",
          "primitives() == ['sense', 'navigate', 'navigate'] and sensed() == [start_cell()] and "
          "all(a in neighbours(start_cell()) and not is_obstacle(a) and moves()[1] == (b if "
          f"{_open('b')} else start_cell()) for a in moves()[:1] for b in "
          "[(2 * start_cell()[0] - a[0], 2 * start_cell()[1] - a[1])])"),
    _task("corridor_step", 1, check_corridor_step,
          "Sense once. If the cell above you (j + 1) and the cell below you (j - 1) are both "
          "inside the grid and free, step up. Otherwise, if the cell to your left (i - 1) and "
          "the cell to your right (i + 1) are both inside the grid and free, step right. If "
          "neither pair is open, step onto any free cell next to you. Then stop.",
          f"{_ONE_STEP} and ({_M0} == {_UP} if {_open(_UP)} and {_open(_DOWN)} else ({_M0} == "
          f"{_RIGHT} if {_open(_LEFT)} and {_open(_RIGHT)} else True))"),
    _task("wander_until_nothing_new", 2, check_wander_until_nothing_new,
          "Wander around: sense, then step onto any free cell right next to you and sense "
          "again, and keep doing that. Stop right after the first sense that tells you "
          "nothing new, that is, when every cell it shows you (your own cell and the cells "
          "next to it) was already shown to you by an earlier sense.",
          f"{_LINE} and len(moves()) >= 1 and len(moves()) <= 90 and all(moves()[k] in "
          f"neighbours(sensed()[k]) and not is_obstacle(moves()[k]) and {_new('k')} for k in "
          f"{indices(90)}[:len(moves())]) and len(known_before_last()) == len(known_cells())"),
    _task("two_touching_obstacles", 2, check_two_touching_obstacles,
          "Explore until you have found two obstacles that touch: two obstacle cells right "
          "next to each other in a row or a column. Stop right after the sense that first "
          "shows you such a pair. If there is nothing more to find before that, stop right "
          "after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and all(not any(P) and (len(P) > 0 or (explored_all() "
          f"and {_FRESH})) for P in [{_PAIRS}])"),
    _task("down_then_edge_left", 2, check_down_then_edge_left,
          "Sense, then go down (j - 1) one cell at a time, sensing after every move, as long as "
          "the cell below you is inside the grid and free. If that brings you to the bottom "
          "row of the grid (j = 0), turn and follow the bottom edge to the left (i - 1), one "
          "cell at a time, sensing after every move, as long as the cell to your left is "
          "inside the grid and free. If an obstacle stops you before the bottom row, stop "
          "there.",
          f"{_LINE} and len(moves()) <= 18 and all(moves()[k] == ((p[0], p[1] - 1) if "
          f"{_down_free('p')} else (p[0] - 1, p[1])) and {_descend('p')} for k in "
          f"{indices(18)}[:len(moves())] for p in [sensed()[k]]) and not "
          f"{_descend('final_cell()')}"),
    _task("free_count_straight_walk", 2, check_free_count_straight_walk,
          "Sense at your starting cell and count the free cells right next to it (between 1 "
          "and 4). Then pick a direction in which the next cell is free and walk straight that "
          "way as many cells as you counted, one cell at a time, sensing after every move. "
          "Stop early if the next cell ahead is outside the grid or an obstacle.",
          f"{_LINE} and len(moves()) >= 1 and {_M0} in neighbours(start_cell()) and not "
          f"is_obstacle({_M0}) and all(moves()[k] == ({_M0}[0] + k * {_DI}, {_M0}[1] + k * "
          f"{_DJ}) for k in {indices(4)}[:len(moves())]) and all(len(moves()) <= n and (len(moves()) "
          f"== n or not (e[0] >= 0 and e[0] <= 9 and e[1] >= 0 and e[1] <= 9 and not "
          f"is_obstacle(e))) for n, e in [({_free_count(_S)}, {_AHEAD})])"),
    _task("goal_chain", 2, check_goal_chain,
          "Search for a goal. As soon as a sense shows you one, step onto it and sense there. "
          "If that sense shows you another goal right next to the one you are standing on, "
          "step onto that second goal and stop; if it shows no other goal, stop on the first "
          "one.",
          "all(len(g) >= 1 and len(g) <= 2 and steps_after_goal() == 1 + len(g) and "
          "primitives()[-1 - len(g):] == ['navigate', 'sense'] + ['navigate'] * (len(g) - 1) "
          "and sensed()[-1] == g[0] and is_goal(g[0]) and g[0] in [sensed()[-2]] + "
          "neighbours(sensed()[-2]) and (len(g) == 2 and is_goal(g[1]) and g[1] in "
          "neighbours(g[0]) if any(is_goal(x) for x in neighbours(g[0])) else len(g) == 1) "
          "for g in [moves_after_goal()])"),
    _task("row_to_junction", 2, check_row_to_junction,
          "Sense, then walk along your row one cell at a time, sensing after every move: to the "
          "right (i + 1) if the cell to the right of your start is inside the grid and free, "
          "otherwise to the left (i - 1). Keep going the same way until you stand on a "
          "crossroads: a cell with free cells on at least three of its four sides (cells "
          "outside the grid are not free); your starting cell does not count. Also stop when "
          "the next cell ahead is outside the grid or an obstacle.",
          f"{_LINE} and len(moves()) <= 9 and all((moves()[k] == (p[0] + h, p[1]) and "
          f"{_ahead_free('p', 'h')} and (k == 0 or f < 3) if k < len(moves()) else (k > 0 and "
          f"f >= 3) or not {_ahead_free('p', 'h')}) for k in {indices(10)}[:len(sensed())] for p, f, "
          f"h in [(sensed()[k], {_free_count('sensed()[k]')}, 1 if {_right_free(_S)} else -1)])"),
    _task("efficient_explore", 3, check_efficient_explore,
          "Explore until there is nothing more to find, without wasting a single look: every "
          "sense you take must show you at least one cell you did not know yet. Stop right "
          "after the sense that leaves nothing more to find.",
          f"primitives()[-1:] == ['sense'] and explored_all() and len(sensed()) <= 100 and "
          f"all({_new('k')} for k in {indices(100)}[:len(sensed())])"),
    _task("clearest_cell", 3, check_clearest_cell,
          "Explore until there is nothing more to find. Then go to the free cell you can reach "
          "that lies farthest from its nearest obstacle -- counting steps along rows and "
          "columns, ignoring obstacles in between; the grid's edge is not an obstacle -- and "
          "stop there (any of them if several tie).",
          f"explored_all() and not is_obstacle(final_cell()) and all({_clear('final_cell()')} >= "
          f"{_clear('c')} for c in reachable_cells())"),
    _task("four_in_line", 3, check_four_in_line,
          "Get to a cell exactly four cells away from your starting cell in a straight line "
          "along its row or its column: (i + 4, j), (i - 4, j), (i, j + 4) or (i, j - 4). "
          "Explore as much as you need to find one you can reach, and stop on it. If none of "
          "them can be reached, stop once there is nothing more to find.",
          f"all((final_cell() in T and not is_obstacle(final_cell())) or (not any(t in "
          f"reachable_cells() for t in T) and explored_all()) for T in [{_LINE4}])"),
    _task("ten_free_cells_known", 2, check_ten_free_cells_known,
          "Explore until you know of at least 10 free cells (empty cells or goals; obstacles do "
          "not count), and stop right after the sense that brings you to 10. If there is "
          "nothing more to find before that, stop right after the sense that leaves nothing "
          "more to find.",
          f"primitives()[-1:] == ['sense'] and {_free_known('known_before_last()')} < 10 and "
          f"({_free_known('known_cells()')} >= 10 or (explored_all() and {_FRESH}))"),
    _task("low_spill_per_scoop", 2, check_low_spill_per_scoop,
          f"Scoop two or three times. Get at least {NEEDED} grams of grains into the receiver, "
          f"while spilling on average no more than {PER_SCOOP} grams per scoop outside the "
          f"containers: at most {2 * PER_SCOOP} g in all after two scoops, {3 * PER_SCOOP} g "
          f"after three.",
          f"scoops() >= 2 and scoops() <= 3 and delivered() >= {NEEDED} and spilled() <= "
          f"{PER_SCOOP} * scoops()", SCOOP),
    _task("capped_fill", 2, check_capped_fill,
          f"Fill the receiver, but not too much: scoop at least twice and at most four times, "
          f"so that it ends up holding at least {LOW} grams and no more than {HIGH} grams of "
          f"grains.",
          f"scoops() >= 2 and scoops() <= 4 and delivered() >= {LOW} and delivered() <= {HIGH}",
          SCOOP),
]
