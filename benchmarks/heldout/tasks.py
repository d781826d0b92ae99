"""Held-out grid tasks: written after the certified-synthesis pipeline was frozen, run once.

    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout/tasks.py --list
    python benchmarks/synthesis_eval.py --tasks benchmarks/heldout/tasks.py \
        --model-path qwen2.5-coder-1.5b-instruct-q4_k_m.gguf --out /tmp/heldout

None of these requests, nor a rewording of one, is in the pipeline's worked examples or the
development set (``benchmarks.synthesis_tasks``), and nothing of the pipeline was changed after
seeing how it fared on them; the README quotes that run. Like any external task file it uses
only the public ground-truth helpers of ``benchmarks.synthesis_tasks``, and its results go
outside the repository.
"""

from __future__ import annotations

from pathlib import Path

from benchmarks.synthesis_tasks import (Task, at_start, cell, exhausted, first_goal_sense,
                                        first_reaching, neighbours, round_trips)
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE

REFERENCES = Path(__file__).resolve().parent / "references"


def _steps(result) -> list[tuple[str, tuple[int, int]]]:
    return [(s["primitive"], cell(s["param"])) for s in result.steps]


def _after(index, result) -> list[tuple[str, tuple[int, int]]] | None:
    return None if index is None else _steps(result)[index + 1:]


def check_home_and_sense(state, result):
    """Once a goal is revealed: back to the start (no move if already there), sense, stop."""
    home = state.start_cell
    rest = _after(first_goal_sense(state, result), result)
    if rest is None:
        return "no goal was found"
    if rest in ([("navigate", home), ("sense", home)], [("sense", home)]):
        return at_start(state)
    return f"after finding a goal it ran {rest[:6]}"


def check_look_step_sense(state, result):
    """Sense at the start, one move onto a free neighbour of the start, sense there, stop."""
    home, steps = state.start_cell, _steps(result)
    if len(steps) != 3 or steps[0] != ("sense", home) or steps[1][0] != "navigate":
        return f"ran {steps[:6]}"
    spot = steps[1][1]
    if spot not in neighbours(state, home) or state.truth[spot] == OBSTACLE:
        return f"moved to {spot}, not a free cell next to the start {home}"
    return None if steps[2] == ("sense", spot) else f"then ran {steps[2]}, not a sense at {spot}"


def check_fifteen_cells_home(state, result):
    """Exploring stops once 15 cells are known (or nothing more can be found), then straight
    back to the start."""
    home = state.start_cell
    index = first_reaching(state, result,
                           lambda known: int(known.sum()) >= 15 or exhausted(state, known))
    rest = _after(index, result)
    if rest is None:
        return "never knew 15 cells"
    ok = rest == [("navigate", home)] or (rest == [] and state.cell == home)
    return None if ok else f"after knowing 15 cells it ran {rest[:6]}"


def check_everything_then_goal(state, result):
    """Exploring stops when nothing more can be found, then one move onto a goal."""
    rest = _after(first_reaching(state, result, lambda known: exhausted(state, known)), result)
    if rest is None:
        return "never explored everything"
    if len(rest) == 1 and rest[0][0] == "navigate" and state.truth[rest[0][1]] == GOAL:
        return None
    return f"after exploring everything it ran {rest[:6]}"


def check_goal_then_neighbour(state, result):
    """Once a goal is revealed: one move, onto a free cell next to the start, and stop."""
    home = state.start_cell
    rest = _after(first_goal_sense(state, result), result)
    if rest is None:
        return "no goal was found"
    if len(rest) == 1 and rest[0][0] == "navigate" and rest[0][1] in neighbours(state, home) \
            and state.truth[rest[0][1]] != OBSTACLE:
        return None
    return f"after finding a goal it ran {rest[:6]}"


def _task(name: str, difficulty: int, check, description: str) -> Task:
    return Task(name, description, difficulty, False, REFERENCES / f"{name}.json", check,
                PROMISES[name])


#: Faithful promises, added later (for the search's own figure; the model never saw them).
PROMISES = {
    "home_and_sense": "goal_found() and final_cell() == start_cell() and primitives()[-1] == "
                      "'sense' and steps_after_goal() in [1, 2] and (steps_after_goal() == 1 or "
                      "primitives()[-2] == 'navigate')",
    "look_step_sense": "primitives() == ['sense', 'navigate', 'sense'] and moves()[0] in "
                       "neighbours(start_cell())",
    "fifteen_cells_home": "(len(known_cells()) >= 15 or explored_all()) and final_cell() == "
                          "start_cell()",
    "everything_then_goal": "explored_all() and is_goal(final_cell()) and primitives()[-1] == "
                            "'navigate'",
    "goal_then_neighbour": "steps_after_goal() == 1 and primitives()[-1] == 'navigate' and "
                           "final_cell() in neighbours(start_cell())",
    "three_round_trips": "len(moves_after_goal()) == 6 and is_goal(moves_after_goal()[0]) and "
                         "moves_after_goal() == [moves_after_goal()[0], start_cell()] * 3",
}


TASKS = [
    _task("home_and_sense", 2, check_home_and_sense,
          "Look for a goal until you find one. Then walk back to the cell where you began, "
          "take one sensing there, and finish."),
    _task("look_step_sense", 1, check_look_step_sense,
          "Sense where you are first. Then step onto one neighbouring cell of your start that "
          "is not an obstacle, sense once more from there, and end."),
    _task("fifteen_cells_home", 3, check_fifteen_cells_home,
          "Keep exploring until the contents of at least 15 cells are known, or until there "
          "is nothing left to discover; after that, return to your starting cell and end "
          "there."),
    _task("everything_then_goal", 3, check_everything_then_goal,
          "Discover everything that can be discovered from your start, and only then walk "
          "onto one of the goals you found and end on it."),
    _task("goal_then_neighbour", 2, check_goal_then_neighbour,
          "Once you have spotted a goal, do not go to it: instead walk to a free cell right "
          "beside your starting cell and end there."),
    _task("three_round_trips", 2, round_trips(3),
          "Locate a goal. Afterwards travel between that goal and your start three times "
          "(goal, start, goal, start, goal, start), ending at your start, with no other "
          "moves once you first step onto the goal."),
]
