"""Held-out tasks, third set: written before the next change of the synthesizer, run once after.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout3/tasks.py --list

Twelve grid tasks of kinds composed the way requests are (two loops in a row, a loop then a
return, a conditional with an else-if, an alternating pattern, a count carried from one loop to
the next, memory of the cells moved to or of the first goal found, an argmax after one look, the
smallest neighbour, a spatial condition met while exploring, a second goal or else home) and two
scooping tasks. Each has a reference behavior (``references/``), a ground-truth ``check`` and a
faithful ``promise`` over the env's outcome helpers, so that the search can be measured apart
from the model. They were written on 2026-12-05 without running the synthesizer on them; the
first run of the search on them is the evaluation, reported beside the development figures.

Words as the checks read them (as in the other sets): a cell is *free* when it holds no obstacle;
*known* when the agent's label of it is not 'unexplored'; *up* is j + 1, *down* j - 1, *right*
i + 1, *left* i - 1; a sense labels its cell and the four around it.
"""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (cell, exhausted, free_cell, grams_in_receiver,
                                        held_out_task, known_after, moves, neighbours, reachable,
                                        same_steps, scoops, step_by, steps_of)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"
SCOOP = "VLB-Scoop-v0"
RIGHT, LEFT, UP, DOWN = (1, 0), (-1, 0), (0, 1), (0, -1)


def _walk(state, start, directions, stop=lambda here: False):
    """Sense at ``start``, then one move per direction drawn from ``directions`` (an iterator)
    while the next cell is free and ``stop(here)`` is false, sensing after every move."""
    here, plan = start, [("sense", start)]
    for step in directions:
        nxt = step_by(here, step)
        if stop(here) or not free_cell(state, nxt):
            break
        plan += [("navigate", nxt), ("sense", nxt)]
        here = nxt
    return plan, here


def _forever(*steps):
    while True:
        yield from steps


# --- checks -------------------------------------------------------------------------------

def check_right_then_home(state, result):
    """Sense; step right while free, sensing after each step; then back to the start in one
    move if it moved at all."""
    home = state.start_cell
    plan, end = _walk(state, home, _forever(RIGHT))
    return same_steps(steps_of(result), plan + ([("navigate", home)] if end != home else []))


def check_up_then_right(state, result):
    """Sense; step up while free, then right while free, sensing after every step."""
    plan, corner = _walk(state, state.start_cell, _forever(UP))
    more, _ = _walk(state, corner, _forever(RIGHT))
    return same_steps(steps_of(result), plan + more[1:])


def check_left_or_right(state, result):
    """One sense; onto the left cell if free, else onto the right cell if free, else no move."""
    home = state.start_cell
    want = [("sense", home)]
    for step in (LEFT, RIGHT):
        if free_cell(state, step_by(home, step)):
            want.append(("navigate", step_by(home, step)))
            break
    return same_steps(steps_of(result), want)


def check_retrace_to_start(state, result):
    """A move onto a goal; after it, only moves: the earlier moves in reverse, then the start."""
    steps, targets = steps_of(result), moves(result)
    onto = [k for k, c in enumerate(targets) if state.truth[c] == GOAL]
    if not onto:
        return "never moved onto a goal"
    g = onto[0]
    after = targets[g + 1:]
    if after != targets[:g][::-1] + [state.start_cell]:
        return f"after the goal it moved {after[:6]}, not back the way it came"
    tail = steps[len(steps) - len(after):] if after else []
    if any(kind != "navigate" for kind, _ in tail) or len(steps) - len(after) - 1 < 0 \
            or steps[len(steps) - len(after) - 1] != ("navigate", targets[g]):
        return "did more than move back after the goal"
    return None


def _touches(state, c) -> bool:
    return free_cell(state, c) and any(state.truth[n] == OBSTACLE for n in neighbours(state, c))


def check_touching_obstacle(state, result):
    """Ends on a free cell with an obstacle beside it, or none is reachable and everything
    that can be found is known."""
    if _touches(state, state.cell):
        return None
    if exhausted(state) and not any(_touches(state, cell(c))
                                    for c in zip(*reachable(state).nonzero())):
        return None
    return f"ended in {state.cell}, which touches no obstacle"


def check_zigzag_right_up(state, result):
    """Sense; right, up, right, up, ... while the next cell of the pattern is free, sensing
    after every move."""
    plan, _ = _walk(state, state.start_cell, _forever(RIGHT, UP))
    return same_steps(steps_of(result), plan)


def check_down_until_goal_or_blocked(state, result):
    """Sense; step down while not on a goal and the cell below is free, sensing after each."""
    plan, _ = _walk(state, state.start_cell, _forever(DOWN),
                    stop=lambda here: state.truth[here] == GOAL)
    return same_steps(steps_of(result), plan)


def check_most_unknown_neighbour(state, result):
    """Sense; onto a free neighbour with the most cells around it still unknown after that
    sense (any of the tied), sense there; no move if no neighbour is free."""
    home, steps = state.start_cell, steps_of(result)
    known = known_after(state, result.steps[:1])
    free = [n for n in neighbours(state, home) if free_cell(state, n)]
    if not free:
        return same_steps(steps, [("sense", home)])
    score = {n: sum(not known[m] for m in neighbours(state, n)) for n in free}
    best = max(score.values())
    if len(steps) == 3 and steps[0] == ("sense", home) and steps[1][0] == "navigate" \
            and score.get(steps[1][1]) == best and steps[2] == ("sense", steps[1][1]):
        return None
    return f"ran {steps[:4]}; the free neighbours score {score}"


def _revealed(state, c) -> list[tuple[int, int]]:
    return [x for x in [c, *neighbours(state, c)] if state.truth[x] == GOAL]


def check_first_goal_after_all(state, result):
    """Everything that can be found is known; ends on a goal that the first sense showing a goal
    showed."""
    if not exhausted(state):
        return "stopped before everything was known"
    senses = [c for kind, c in steps_of(result) if kind == "sense"]
    first = next((_revealed(state, c) for c in senses if _revealed(state, c)), [])
    return None if state.cell in first else f"ended in {state.cell}; the first goals: {first}"


def check_right_then_same_up(state, result):
    """Sense; right while free (k moves), then up while free, at most k moves, sensing after
    every move."""
    plan, corner = _walk(state, state.start_cell, _forever(RIGHT))
    k = len(plan) // 2
    more, _ = _walk(state, corner, iter([UP] * k))
    return same_steps(steps_of(result), plan + more[1:])


def check_second_goal_or_home(state, result):
    """The sense after which two goals are known is the last; one move follows it, onto a goal
    that sense showed first. If two goals are never known, everything is known and it ends at
    the start."""
    steps = steps_of(result)
    senses = [k for k, (kind, _) in enumerate(steps) if kind == "sense"]
    seen: list[tuple[int, int]] = []
    for number, k in enumerate(senses):
        new = [g for g in _revealed(state, steps[k][1]) if g not in seen]
        seen += new
        if len(seen) >= 2:
            if number != len(senses) - 1 or len(steps) != k + 2:
                return "did more than one move after two goals were known"
            return None if state.cell in new else f"ended in {state.cell}, not on {new}"
    if exhausted(state) and state.cell == state.start_cell:
        return None
    return f"one goal known; ended in {state.cell}, everything known: {exhausted(state)}"


def check_smallest_neighbour_and_back(state, result):
    """Sense; onto the free neighbour with the smallest (i, j), sense, back to the start, sense;
    only the first sense if no neighbour is free."""
    home = state.start_cell
    free = sorted(n for n in neighbours(state, home) if free_cell(state, n))
    want = [("sense", home)]
    if free:
        want += [("navigate", free[0]), ("sense", free[0]), ("navigate", home), ("sense", home)]
    return same_steps(steps_of(result), want)


def check_four_scoops(state, result):
    n = len(scoops(result))
    return None if n == 4 and len(result.steps) == 4 else f"{n} scoop(s)"


def check_two_scoops_40g(state, result):
    n = len(scoops(result))
    if len(result.steps) != 2 or n != 2:
        return f"{n} scoop(s)"
    mass = grams_in_receiver(state)
    return None if mass >= 40 else f"{mass:.1f} g in the receiver"


# --- the set ------------------------------------------------------------------------------

_task = held_out_task(REFERENCES)


_LINE = "primitives() == ['sense'] + ['navigate', 'sense'] * len(moves()) and " \
        "sensed() == [start_cell()] + moves()"
_N = "[1, 2, 3, 4, 5, 6, 7, 8, 9]"  # the promises' language has no range()
_S0, _S1 = "start_cell()[0]", "start_cell()[1]"
_U = "(len(moves()) - final_cell()[0] + start_cell()[0])"  # up moves, before the right ones
_K = "(final_cell()[0] - start_cell()[0])"  # right moves, before the up ones

TASKS = [
    _task("right_then_home", 2, check_right_then_home,
          "Sense where you stand, then keep stepping right (increasing i) one cell at a time, "
          "sensing after each step, for as long as the next cell to the right is inside the "
          "grid and free. If you moved at all, go straight back to your starting cell and stop "
          "there; if you could not move, just stop.",
          f"(primitives() == ['sense'] and sensed() == [start_cell()] and ({_S0} == 9 or "
          f"is_obstacle(({_S0} + 1, {_S1})))) if not moves() else (len(moves()) > 1 and "
          f"primitives() == ['sense', 'navigate'] * len(moves()) and moves() == [({_S0} + n, "
          f"{_S1}) for n in {_N}][:len(moves()) - 1] + [start_cell()] and sensed() == "
          f"[({_S0} + n, {_S1}) for n in [0] + {_N}][:len(moves())] and ({_S0} + len(moves()) "
          f"- 1 == 9 or is_obstacle(({_S0} + len(moves()), {_S1}))))"),
    _task("up_then_right", 2, check_up_then_right,
          "Sense where you are. Walk up (increasing j) one cell at a time while the cell above "
          "you is inside the grid and free, then from there walk right (increasing i) the same "
          "way while the cell to your right is inside the grid and free. Sense after every "
          "move, and stop when you cannot go right any more.",
          f"{_LINE} and moves() == [({_S0}, {_S1} + n) for n in {_N}][:{_U}] + [({_S0} + n, "
          f"{_S1} + {_U}) for n in {_N}][:len(moves()) - {_U}] and ({_S1} + {_U} == 9 or "
          f"is_obstacle(({_S0}, {_S1} + {_U} + 1))) and (final_cell()[0] == 9 or "
          "is_obstacle((final_cell()[0] + 1, final_cell()[1])))"),
    _task("left_or_right", 1, check_left_or_right,
          "Sense once. If the cell to your left (i - 1) is inside the grid and not an obstacle, "
          "move onto it. If it is not, but the cell to your right (i + 1) is inside the grid and "
          "not an obstacle, move onto that one instead. Otherwise stay where you are. Then stop.",
          "all(primitives()[0] == 'sense' and sensed() == [s] and moves() == ([l] if s[0] > 0 "
          "and not is_obstacle(l) else [r] if s[0] < 9 and not is_obstacle(r) else []) "
          "for s in [start_cell()] for l in [(s[0] - 1, s[1])] for r in [(s[0] + 1, s[1])])"),
    _task("retrace_to_start", 3, check_retrace_to_start,
          "Explore until you find a goal and move onto it. Then return to where you started "
          "by retracing your path: revisit the cells you moved to before reaching the goal in "
          "reverse order, one move each, and finish with a move onto your starting cell.",
          "len(moves()) >= 2 and len(moves()) % 2 == 0 and is_goal(moves()[len(moves()) // 2 - "
          "1]) and not any(is_goal(c) for c in moves()[:len(moves()) // 2 - 1]) and "
          "moves()[len(moves()) // 2:] == moves()[:len(moves()) // 2 - 1][::-1] + "
          "[start_cell()] and primitives()[len(primitives()) - len(moves()) // 2 - 1:] == "
          "['navigate'] * (len(moves()) // 2 + 1)"),
    _task("touching_obstacle", 2, check_touching_obstacle,
          "Find a free cell that has an obstacle directly next to it (the edge of the grid "
          "does not count), exploring as much as needed, go there and stop; your starting "
          "cell counts if it qualifies. If no such cell can be reached, stop once there is "
          "nothing more to find.",
          "(not is_obstacle(final_cell()) and any(is_obstacle(n) for n in "
          "neighbours(final_cell()))) or (explored_all() and not any(any(is_obstacle(n) for n "
          "in neighbours(c)) for c in reachable_cells()))"),
    _task("zigzag_right_up", 3, check_zigzag_right_up,
          "Sense, then move in a staircase: one cell right (i + 1), one cell up (j + 1), one "
          "right, one up, and so on, sensing after every move. Stop as soon as the next move of "
          "the staircase would leave the grid or hit an obstacle.",
          f"{_LINE} and moves() == [({_S0} + (n + 1) // 2, {_S1} + n // 2) for n in {_N[:-1]}, "
          "10, 11, 12, 13, 14, 15, 16, 17, 18]][:len(moves())] and ((final_cell()[0] == 9 or "
          "is_obstacle((final_cell()[0] + 1, final_cell()[1]))) if len(moves()) % 2 == 0 else "
          "(final_cell()[1] == 9 or is_obstacle((final_cell()[0], final_cell()[1] + 1))))"),
    _task("down_until_goal_or_blocked", 2, check_down_until_goal_or_blocked,
          "Sense, then go down (decreasing j) one cell at a time, sensing after every move. "
          "Stop as soon as you are standing on a goal, or the cell below you is outside the "
          "grid or an obstacle.",
          f"{_LINE} and moves() == [({_S0}, {_S1} - n) for n in {_N}][:len(moves())] and not "
          "any(is_goal(c) for c in moves()[:-1]) and (is_goal(final_cell()) or "
          "final_cell()[1] == 0 or is_obstacle((final_cell()[0], final_cell()[1] - 1)))"),
    _task("most_unknown_neighbour", 3, check_most_unknown_neighbour,
          "Sense where you stand. Among the free cells right next to you, move to the one with "
          "the most still-unexplored cells around it (any of them if several tie), sense there, "
          "and stop. If none of the cells next to you is free, stop after the first sense.",
          "(primitives() == ['sense'] and sensed() == [start_cell()] and reachable_cells() == "
          "[start_cell()]) if not moves() else (primitives() == ['sense', 'navigate', 'sense'] "
          "and sensed() == [start_cell(), moves()[0]] and moves()[0] in "
          "neighbours(start_cell()) and not is_obstacle(moves()[0]) and all(len([m for m in "
          "neighbours(moves()[0]) if m not in [start_cell()] + neighbours(start_cell())]) >= "
          "len([m for m in neighbours(n) if m not in [start_cell()] + neighbours(start_cell())]) "
          "for n in neighbours(start_cell()) if not is_obstacle(n)))"),
    _task("first_goal_after_all", 3, check_first_goal_after_all,
          "Explore the whole area you can reach, until there is nothing more to find. Remember "
          "the first goal you came across, and when the exploring is done, go to that goal and "
          "stop on it.",
          "explored_all() and is_goal(final_cell()) and [c for c in sensed() if "
          "any(is_goal(x) for x in [c] + neighbours(c))][:1] == [c for c in sensed() if "
          "final_cell() in [c] + neighbours(c)][:1]"),
    _task("right_then_same_up", 3, check_right_then_same_up,
          "Sense, then walk right (increasing i) while the next cell is inside the grid and "
          "free, counting your steps. Then walk up (increasing j) as many steps as you walked "
          "right, stopping early if the cell above is outside the grid or an obstacle. Sense "
          "after every move.",
          f"{_LINE} and moves() == [({_S0} + n, {_S1}) for n in {_N}][:{_K}] + [({_S0} + {_K}, "
          f"{_S1} + n) for n in {_N}][:len(moves()) - {_K}] and len(moves()) - {_K} <= {_K} and "
          f"({_S0} + {_K} == 9 or is_obstacle(({_S0} + {_K} + 1, {_S1}))) and (len(moves()) - "
          f"{_K} == {_K} or final_cell()[1] == 9 or is_obstacle((final_cell()[0], "
          "final_cell()[1] + 1)))"),
    _task("second_goal_or_home", 3, check_second_goal_or_home,
          "Explore until you know of two goals, then go to the one you found second and stop "
          "on it (if one look showed you both at once, either will do). If you never find a "
          "second goal, go back to your starting cell once there is nothing more to find.",
          "(is_goal(final_cell()) and primitives()[-2:] == ['sense', 'navigate'] and "
          "final_cell() in [sensed()[-1]] + neighbours(sensed()[-1]) and [2 if g == "
          "final_cell() else 1 for g in reachable_goals() if any(g in [c] + neighbours(c) for c "
          "in sensed()[:-1])] in [[], [1]] and len([g for g in known_cells() if is_goal(g)]) >= "
          "2) if len(reachable_goals()) >= 2 else (final_cell() == start_cell() and "
          "explored_all())"),
    _task("smallest_neighbour_and_back", 2, check_smallest_neighbour_and_back,
          "Sense at your starting cell. Of the free cells next to it, pick the one with the "
          "smallest i (and, between two with the same i, the smaller j): go there, sense, come "
          "back to the start and sense again, then stop. If no cell next to the start is free, "
          "stop after the first sense.",
          "all(((primitives() == ['sense', 'navigate', 'sense', 'navigate', 'sense'] and "
          "moves() == [free[0], s] and sensed() == [s, free[0], s]) if free else "
          "(primitives() == ['sense'] and sensed() == [s])) for s in [start_cell()] for free "
          "in [sorted([n for n in neighbours(s) if not is_obstacle(n)])])"),
    _task("four_scoops", 1, check_four_scoops, "Scoop four times, one after the other, and then "
          "stop.", "scoops() == 4", SCOOP),
    _task("two_scoops_40g", 2, check_two_scoops_40g,
          "Scoop exactly twice; together the two scoops must get at least 40 grams of grains "
          "into the receiver.", "scoops() == 2 and delivered() >= 40", SCOOP),
]
