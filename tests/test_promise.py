"""Promises: a behavior's outcome, judged by the env from the episode, counts in rho_B."""

from __future__ import annotations

import json
import re
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import vlb_gym
from vlb_gym import BehaviorSpecError
from vlb_gym.cli import main
from vlb_gym.core.library import BehaviorLibrary, compile_spec, load_behavior
from vlb_gym.core.promise import Episode
from vlb_gym.core.runtime import BehaviorPolicy
from vlb_gym.core.spec import spec_from_data
from vlb_gym.envs.grid_explore.judge import GridJudge
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE, UNEXPLORED
from vlb_gym.envs.scoop.helpers import ScoopJudge
from vlb_gym.verify import run_episode
from vlb_gym.wrappers import RobustnessWrapper
from vlb_gym.wrappers.behavior import BehaviorFinished

BEHAVIORS = Path(vlb_gym.__file__).parent / "behaviors"
SENSE_ONCE = {"name": "sense_once", "description": "sense where it stands",
              "env": "VLB-GridExplore-v0", "nodes": [{"id": "look", "primitive": "sense"}],
              "start": {"node": "look", "param": "current_cell()"}, "terminals": ["look"]}


def behavior(env, promise: str | None, doc: dict = SENSE_ONCE, library=None) -> BehaviorPolicy:
    data = {**doc, **({"promise": {"expr": promise, "description": "as written"}}
                      if promise else {})}
    spec = spec_from_data(data, "<test>")
    return BehaviorPolicy(compile_spec(spec, env, "<test>", None, library), env.unwrapped)


def test_a_promise_that_holds_keeps_rho_and_one_that_fails_names_itself(grid_env):
    held = behavior(grid_env, "sensed() == [start_cell()] and final_cell() == start_cell()")
    broken = behavior(grid_env, "len(moves()) > 0")
    for seed in range(5):
        assert run_episode(grid_env, held, seed).success
        result = run_episode(grid_env, broken, seed)
        assert not result.success and result.cause == "sense_once: promise"
        assert result.reason.startswith("after step 1: promise of sense_once failed (as written:"
                                        " it does not hold): began in")
        assert result.failed_certificates == 0  # every certificate held: the promise failed


def test_a_promise_that_raises_fails_the_episode_not_the_process(grid_env):
    policy = behavior(grid_env, "moves()[0] == start_cell()")  # sense only: no move at all
    result = run_episode(grid_env, policy, 0)
    assert not result.success and "IndexError" in result.reason
    assert result.error is None


@pytest.mark.parametrize("promise, words", [
    ("len(explored()) > 3", "'explored' is an observation helper"),
    ("seen > 0 and goal_found()", "'seen' is a variable"),
    ("True", "calls no outcome helper"),
    ("1 + 1 == 2", "calls no outcome helper"),
    ("goal_found(3)", "goal_found"),
    ("is_goal(start_cell(), 1)", "is_goal"),
])
def test_promises_over_the_behaviors_own_state_or_nothing_are_refused(grid_env, promise, words):
    doc = {**SENSE_ONCE, "variables": {"seen": "0"}}
    with pytest.raises(BehaviorSpecError, match="promise") as err:
        behavior(grid_env, promise, doc)
    assert words in str(err.value)
    assert err.value.layer == "expressions"


@pytest.mark.parametrize("promise, words", [
    ("start_cell()", "'start_cell()' is a tuple, not true or false"),
    ("len(moves())", "is a int, not true or false"),
    ("known_cells() > 3", "known_cells() (list) and 3 (int) have no order"),
    ("sum(moves()) > 0", "sum() adds numbers; moves() is a list of tuple"),
    ("final_cell() >= None", "None is None, which has no order"),
    ("len([a for a in moves() for b in moves() for c in moves() for d in moves()]) > 0",
     "more than 3 comprehension loops"),
    ("(" * 300 + "goal_found()" + ")" * 300, "too many nested parentheses"),
    ("moves()[10**9] == start_cell()", "forbidden syntax: Pow"),
    ("str(moves()) == ''", "'str', which is not a whitelisted function"),
    ("goal_found().__class__ == 1", "forbidden"),
])
def test_promises_that_cannot_be_right_are_refused_before_running(grid_env, promise, words):
    with pytest.raises(BehaviorSpecError, match="promise.expr") as err:
        behavior(grid_env, promise)
    assert words in str(err.value)


def test_an_expensive_promise_fails_its_budget_not_the_machine(grid_env):
    policy = behavior(grid_env, "len([a for a in reachable_cells() for b in reachable_cells() "
                                "for c in reachable_cells() if a != b]) > 0")
    result = run_episode(grid_env, policy, 0)
    assert not result.success and "EvaluationLimitError" in result.reason
    assert result.cause == "sense_once: promise"


@pytest.mark.parametrize("field, value, words", [
    ("description", "\x1b[2J\x1b]0;owned\x07 fine", "character U+001B at position 1"),
    ("description", "two\nlines", "character U+000A at position 4"),
    ("description", "right\u202eto left", "character U+202E at position 6"),
    ("description", "x" * 501, "at most 500 characters"),
    ("expr", "", "at least 1 character"),
    ("expr", 5, "valid string"),
    ("extra", 1, "Extra inputs are not permitted"),
])
def test_a_promise_field_that_is_not_printable_bounded_text_is_refused(field, value, words):
    promise = {"expr": "goal_found()", "description": "fine", field: value}
    with pytest.raises(BehaviorSpecError) as err:
        spec_from_data({**SENSE_ONCE, "promise": promise}, "b.json")
    assert str(err.value).startswith(f"b.json: promise.{field}: ") and words in str(err.value)
    assert err.value.layer == "schema" and "\n" not in str(err.value)


@pytest.mark.parametrize("place", ["description", "env", "nodes[0].description"])
def test_every_text_a_terminal_shows_is_one_printable_line(place):
    doc = json.loads(json.dumps(SENSE_ONCE))
    if place.startswith("nodes"):
        doc["nodes"][0]["description"] = "ok\x1b[31m"
    else:
        doc[place] = "ok\x1b[31m"
    with pytest.raises(BehaviorSpecError, match=rf"^b.json: {re.escape(place)}: .*U\+001B"):
        spec_from_data(doc, "b.json")


def test_a_sub_behaviors_promise_is_its_nodes_certificate(grid_env, user_library):
    library = BehaviorLibrary()
    library.save(spec_from_data({**SENSE_ONCE, "promise": {
        "expr": "len(known_obstacles()) > 0", "description": "an obstacle is known"}},
        "<child>"))
    parent = {"name": "parent", "description": "the child, then go to the start",
              "env": "VLB-GridExplore-v0", "variables": {"home": "current_cell()"},
              "nodes": [{"id": "child", "behavior": "sense_once"},
                        {"id": "go", "primitive": "navigate"}],
              "edges": [{"from": "child", "to": "go", "param": "home"}],
              "start": {"node": "child"}, "terminals": ["go"]}
    policy = behavior(grid_env, None, parent, library)
    outcomes = []
    for seed in range(20):  # the child promised an obstacle: the parent stops where it broke
        result = run_episode(grid_env, policy, seed)
        outcomes.append(result.success)
        obstacles = int((grid_env.unwrapped.state.labels == OBSTACLE).sum())
        if result.success:
            assert result.primitives == 2 and obstacles > 0
        else:
            assert result.cause == "sense_once: promise" and result.primitives == 1
            assert obstacles == 0 and "0 obstacle(s) known" in result.reason
    assert 0 < sum(outcomes) < 20


def test_behavior_finished_wrapper_scores_the_promise(grid_env):
    compiled = behavior(grid_env, "len(moves()) > 0").behavior
    wrapped = BehaviorFinished(grid_env, compiled)
    _, start = wrapped.reset(seed=0)
    sense_here = wrapped.unwrapped.encode_action("sense", tuple(start["start_cell"]))
    *_, terminated, truncated, info = wrapped.step(sense_here)
    assert (terminated, truncated) == (True, False)  # the behavior finished: the env is done
    assert info["rho_B"] == -1 and info["failure_cause"] == "sense_once: promise"


def test_shipped_behaviors_keep_their_promises(grid_env):
    for name in ("explore_until_goal", "find_goal_and_oscillate"):
        policy = load_behavior(name, grid_env)
        assert policy.behavior.promise is not None
        for seed in range(10):
            assert run_episode(grid_env, policy, seed).success, (name, seed)


# --- the judges, against an independent reading of the state ----------------------------------

def independent_reachable(truth: np.ndarray, start: tuple[int, int]) -> set[tuple[int, int]]:
    size = truth.shape[0]
    seen, todo = {start}, [start]
    while todo:
        i, j = todo.pop()
        for n in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
            if 0 <= n[0] < size and 0 <= n[1] < size and n not in seen \
                    and truth[n] != OBSTACLE:
                seen.add(n)
                todo.append(n)
    return seen


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10_000), moves=st.integers(0, 12))
def test_grid_judge_agrees_with_an_independent_reading(seed, moves):
    env = RobustnessWrapper(gym.make("VLB-GridExplore-v0"))
    _, reset_info = env.reset(seed=seed)
    state = env.unwrapped.state
    rng = np.random.default_rng(seed)
    for _ in range(moves):
        cell = tuple(int(v) for v in state.cell)
        options = [n for n in ((cell[0] + 1, cell[1]), (cell[0] - 1, cell[1]),
                               (cell[0], cell[1] + 1), (cell[0], cell[1] - 1))
                   if 0 <= min(n) and max(n) < state.truth.shape[0]]
        target = options[rng.integers(len(options))]
        primitive = ["sense", "navigate"][int(rng.integers(2))]
        env.step(env.unwrapped.encode_action(primitive, target if primitive == "navigate" else cell))
        if env.summary is not None:
            break
    judge = GridJudge(state.truth.shape[0])
    judge.bind(Episode(state, env.history, reset_info))
    start = tuple(reset_info["start_cell"])
    navigate = [tuple(int(v) for v in s["param"]) for s in env.history
                if s["primitive"] == "navigate"]
    reach = independent_reachable(state.truth, start)
    labels = state.labels
    assert judge.start_cell() == start and judge.final_cell() == tuple(state.cell)
    assert judge.moves() == navigate
    assert set(judge.reachable_cells()) == reach
    assert set(judge.reachable_goals()) == {c for c in reach if state.truth[c] == GOAL}
    assert set(judge.known_cells()) == {tuple(c) for c in np.argwhere(labels != UNEXPLORED)}
    assert judge.goal_found() == bool((labels == GOAL).any())
    known = [False] + [bool(s["goal_found"]) for s in env.history]
    after = -1 if not known[-1] else len(known) - 1 - known.index(True)
    assert judge.steps_after_goal() == after
    later = env.history[len(env.history) - after:] if after > 0 else []
    assert judge.moves_after_goal() == [tuple(int(v) for v in s["param"]) for s in later
                                        if s["primitive"] == "navigate"]
    near = reach | {n for c in reach for n in judge.neighbours(c)}
    assert judge.explored_all() == all(labels[c] != UNEXPLORED for c in near)
    env.close()


def test_scoop_judge_reads_what_the_last_scoop_weighed():
    """Each scoop weighs the receiver's (and the table's) contents after it, everything so far:
    the behavior's delivery is the last weighing, not their sum (which counted the first scoop's
    grains once per later scoop)."""
    judge = ScoopJudge()
    steps = [{"primitive": "scoop", "mass_delivered": 2.5, "mass_spilled": 0.25},
             {"primitive": "scoop", "mass_delivered": 3.5, "mass_spilled": 0.25}]
    judge.bind(Episode(None, steps, {}))
    assert (judge.scoops(), judge.delivered(), judge.spilled()) == (2, 3.5, 0.25)
    assert judge.summary() == "2 scoop(s), 3.5 g delivered, 0.2 g spilled"
    judge.bind(Episode(None, [], {}))
    assert (judge.scoops(), judge.delivered(), judge.spilled()) == (0, 0.0, 0.0)


@pytest.mark.parametrize("promise, words", [
    ({"expr": "goal_found()", "description": "\x1b]0;owned\x07a goal is known"},
     "promise.description: Value error, character U+001B at position 1"),
    ({"expr": "known_cells() > 3"}, "promise.expr: known_cells() (list) and 3 (int)"),
])
def test_vlb_verify_refuses_a_hostile_promise_in_one_line(tmp_path, capsys, promise, words):
    path = tmp_path / "hostile.json"
    path.write_text(json.dumps({**SENSE_ONCE, "promise": promise}))
    assert main(["verify", "VLB-GridExplore-v0", "--behavior", str(path), "--episodes", "3",
                 "--epsilon", "0.1", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "\x1b" not in err and "Traceback" not in err
    assert f"{path}: {words}" in err


def test_every_promise_judged_in_an_episode_shares_its_budget(grid_env, user_library,
                                                             monkeypatch):
    """A parent that runs a child again and again, the child's promise each time costly: the
    judgements together stay within one episode's budget (a fresh budget per judgement let
    one episode run for minutes), and the episode fails on it, naming the budget."""
    import vlb_gym.core.budget as budget

    monkeypatch.setattr(budget, "MAX_EPISODE_WORK", 3 * budget.MAX_WORK)  # a short test
    library = BehaviorLibrary()
    library.save(spec_from_data({**SENSE_ONCE, "promise": {
        "expr": "len([a for a in reachable_cells() for b in reachable_cells() if a != b]) > 0",
        "description": "costly"}}, "<child>"))
    parent = {"name": "parent", "description": "the child, a thousand times",
              "env": "VLB-GridExplore-v0", "variables": {"n": "0"},
              "nodes": [{"id": "child", "behavior": "sense_once"}],
              "edges": [{"from": "child", "to": "child", "guard": "n < 1000",
                         "set": {"n": "n + 1"}}],
              "start": {"node": "child"}, "terminals": ["child"]}
    policy = behavior(grid_env, None, parent, library)
    result = run_episode(grid_env, policy, 0)
    assert not result.success and "EvaluationLimitError" in result.reason, result.reason
    assert result.cause == "sense_once: promise" and 2 <= result.primitives < 60


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10_000), steps=st.integers(1, 14))
def test_grid_judge_rewinds_each_step_to_the_state_the_env_was_in(seed, steps):
    env = RobustnessWrapper(gym.make("VLB-GridExplore-v0"))
    _, reset_info = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    snapshots = [env.unwrapped.save()]
    for _ in range(steps):
        state = env.unwrapped.state
        cell = tuple(int(v) for v in state.cell)
        free = [n for n in ((cell[0] + 1, cell[1]), (cell[0] - 1, cell[1]),
                            (cell[0], cell[1] + 1), (cell[0], cell[1] - 1))
                if 0 <= min(n) and max(n) < state.truth.shape[0] and state.truth[n] != OBSTACLE]
        navigate = free and rng.random() < 0.5
        target = free[rng.integers(len(free))] if navigate else cell
        env.step(env.unwrapped.encode_action("navigate" if navigate else "sense", target))
        snapshots.append(env.unwrapped.save())
    judge = GridJudge(env.unwrapped.state.truth.shape[0])
    episode = Episode(env.unwrapped.state, env.history, reset_info)
    for k in range(len(env.history) - 1, -1, -1):  # rewound step by step, down to the reset
        episode = judge.rewind(episode)
        env.unwrapped.load(snapshots[k])
        real = env.unwrapped.state
        assert len(episode.steps) == k and episode.state.cell == real.cell
        assert (episode.state.labels == real.labels).all()
        assert episode.state.goal_found == real.goal_found
    env.close()


TWO_SENSES = {**SENSE_ONCE, "name": "two_senses", "description": "sense twice where it stands",
              "nodes": [{"id": "look", "primitive": "sense"},
                        {"id": "again", "primitive": "sense"}],
              "edges": [{"from": "look", "to": "again", "param": "current_cell()"}],
              "terminals": ["again"]}


@pytest.mark.parametrize("doc, expr, why", [
    (TWO_SENSES, "len(sensed()) == 2", None),
    (TWO_SENSES, "len(sensed()) >= 1", "it already held after step 1"),
    (SENSE_ONCE, "len(moves()) == 0", "it already held before the first step"),
    (SENSE_ONCE, "len(sensed()) == 1", None),
])
def test_a_promise_kept_as_soon_as_it_holds_fails_where_it_held_earlier(grid_env, doc, expr,
                                                                         why):
    spec = spec_from_data({**doc, "promise": {"expr": expr, "as_soon_as": True}}, "<t>")
    policy = BehaviorPolicy(compile_spec(spec, grid_env, "<t>", None, None), grid_env.unwrapped)
    result = run_episode(grid_env, policy, 3)
    assert result.success == (why is None)
    if why is not None:
        assert f"stopping as soon as that holds: {why})" in result.reason


def test_the_shipped_explore_until_goal_stops_as_soon_as_a_goal_is_found(grid_env):
    data = json.loads((BEHAVIORS / "explore_until_goal.json").read_text())
    spec = spec_from_data({**data, "promise": {"expr": "goal_found() or explored_all()",
                                               "as_soon_as": True}}, "<t>")
    policy = BehaviorPolicy(compile_spec(spec, grid_env, "<t>", None, None), grid_env.unwrapped)
    for seed in range(5):
        assert run_episode(grid_env, policy, seed).success


def test_as_soon_as_is_refused_where_the_judge_cannot_rewind():
    env = gym.make("VLB-Scoop-v0")
    data = json.loads((BEHAVIORS / "scoop_repeatedly.json").read_text())
    spec = spec_from_data({**data, "promise": {"expr": "delivered() > 0", "as_soon_as": True}},
                          "<t>")
    with pytest.raises(BehaviorSpecError, match="promise.as_soon_as: .*cannot judge what held "
                                                "before a behavior's last step"):
        compile_spec(spec, env, "<t>", None, None)
    env.close()
