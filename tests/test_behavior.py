"""Behavior files: validation errors that name the file and the place, and run-time semantics."""

from __future__ import annotations

import json

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vlb_gym import BehaviorSpecError, load_behavior, shipped_behaviors
from vlb_gym.core.runtime import BehaviorRuntimeError
from vlb_gym.core.library import compile_for
from vlb_gym.core.spec import SCHEMA_PATH, json_schema
from vlb_gym.envs.grid_explore.helpers import GridHelpers
from vlb_gym.envs.grid_explore.types import GOAL, OBSTACLE, UNEXPLORED, cell_of
from vlb_gym.verify import run_episode

from .conftest import explore_doc


def run(env, policy, seed):
    """Run one whole episode of ``policy``; return the step infos and the wrapper's summary."""
    run_episode(env, policy, seed, stop_on_failure=False)
    return env.history, env.summary


def test_shipped_behaviors_and_schema_file():
    assert {"explore_until_goal", "find_goal_and_oscillate"} <= set(shipped_behaviors())
    assert json.loads(SCHEMA_PATH.read_text()) == json_schema()  # shipped schema is current


def test_graph_view_of_behavior_2(grid_env):
    compiled = compile_for("find_goal_and_oscillate", grid_env)
    assert isinstance(compiled.graph, nx.MultiDiGraph)
    assert set(compiled.graph.nodes) == {"explore", "to_goal", "to_start"}
    assert compiled.graph.nodes["explore"]["behavior"] == "explore_until_goal"
    assert compiled.primitives_used() == {"sense", "navigate"}
    child = compiled.nodes["explore"].child
    assert child.terminals == {"sense"} and child.start_node == "sense"


def test_behavior_1_explores_until_a_goal_is_sensed(grid_env):
    policy = load_behavior("explore_until_goal", grid_env)
    for seed in range(20):
        infos, summary = run(grid_env, policy, seed)
        assert summary["rho_B"] == 1 and policy.finished
        assert infos[-1]["primitive"] == "sense" and infos[-1]["goal_found"]
        assert not any(i["goal_found"] for i in infos[:-1])
        assert [i["primitive"] for i in infos[::2]] == ["sense"] * len(infos[::2])


def test_behavior_2_oscillates_five_round_trips(grid_env):
    policy = load_behavior("find_goal_and_oscillate", grid_env)
    for seed in range(20):
        infos, summary = run(grid_env, policy, seed)
        assert summary["rho_B"] == 1
        start = grid_env.unwrapped.state.start_cell
        goal = next(i for i in infos if i["goal_found"])
        oscillation = infos[infos.index(goal) + 1:]
        assert len(oscillation) == 10 and all(i["primitive"] == "navigate" for i in oscillation)
        assert [i["param"] for i in oscillation[1::2]] == [start] * 5
        assert len({i["param"] for i in oscillation[::2]}) == 1
        assert grid_env.unwrapped.state.truth[oscillation[0]["param"]] == GOAL
        assert grid_env.unwrapped.state.cell == start


def e4_reference(labels: np.ndarray) -> tuple[int, int]:
    """The paper's E4 written directly: first explored non-obstacle cell with most unexplored
    neighbours, cells in flat order."""
    grid = labels.reshape(10, 10)
    best, best_count = None, -1
    for i in range(10):
        for j in range(10):
            if grid[i, j] in (UNEXPLORED, 1):
                continue
            count = sum(1 for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1))
                        if 0 <= a < 10 and 0 <= b < 10 and grid[a, b] == UNEXPLORED)
            if count > best_count:
                best, best_count = (i, j), count
    return best


def test_e4_expression_matches_a_direct_implementation(grid_env):
    policy = load_behavior("explore_until_goal", grid_env)
    checked = 0
    for seed in range(15):
        obs, _ = grid_env.reset(seed=seed)
        policy.reset()
        action, _ = policy.predict(obs)
        while action is not None:
            obs, _, _, _, info = grid_env.step(action)
            action, _ = policy.predict(obs)
            if action is not None and action[0] == 1:
                assert tuple(action[1:]) == e4_reference(obs["labels"])
                checked += 1
    assert checked > 30


def test_variables_are_per_episode(grid_env):
    policy = load_behavior("find_goal_and_oscillate", grid_env)
    run(grid_env, policy, 0)
    first_home = grid_env.unwrapped.state.start_cell
    infos, _ = run(grid_env, policy, 1)
    assert infos[-1]["param"] == grid_env.unwrapped.state.start_cell != first_home


def test_predict_after_finish_returns_none(grid_env):
    policy = load_behavior("explore_until_goal", grid_env)
    run(grid_env, policy, 3)
    assert policy.predict({"labels": None, "position": None}) == (None, None)


# -- bad behavior files: each error names the file and the place -------------------------------

SENSE_GO = [{"id": "sense", "primitive": "sense"}, {"id": "go", "primitive": "navigate"}]
BACK = {"from": "go", "to": "sense", "param": "current_cell()"}


def bad(name, layer, place, message, **doc):
    return pytest.param(doc, layer, place, message, id=name)


def first_edge(**edge):
    """Edges for the two-node explore graph with a modified first edge."""
    return [{"from": "sense", "to": "go", "param": "(0, 0)", **edge}, BACK]


BAD_DOCS = [
    bad("schema: node of both kinds", "schema", "nodes[0]", "exactly one of",
        nodes=[{"id": "sense", "primitive": "sense", "behavior": "x"}, SENSE_GO[1]]),
    bad("schema: extra field", "schema", "nodes[0].colour", "Extra inputs are not permitted",
        nodes=[{"id": "sense", "primitive": "sense", "colour": "red"}, SENSE_GO[1]]),
    bad("schema: bad identifier", "schema", "nodes[0].id", "should match pattern",
        nodes=[{"id": "9lives", "primitive": "sense"}, SENSE_GO[1]]),
    bad("unknown primitive", "references", "nodes[1].primitive", "unknown primitive 'fly'",
        nodes=[SENSE_GO[0], {"id": "go", "primitive": "fly"}]),
    bad("dangling edge", "references", "edges[1].to",
        "unknown node 'nowhere' (the nodes: sense, go); an edge always leads to a node",
        edges=[first_edge()[0], {"from": "go", "to": "nowhere", "param": "(0, 0)"}]),
    bad("dangling edge source", "references", "edges[0].from", "unknown node 'ghost'",
        edges=[{"from": "ghost", "to": "go", "param": "(0, 0)"}]),
    bad("unknown terminal", "references", "terminals[0]", "unknown node 'end'",
        terminals=["end"]),
    bad("unknown start", "references", "start.node", "unknown node 'begin'",
        start={"node": "begin", "param": "current_cell()"}),
    bad("duplicate id", "references", "nodes[1].id", "duplicate node id 'sense'",
        nodes=[SENSE_GO[0], {"id": "sense", "primitive": "navigate"}]),
    bad("missing param", "references", "edges[0].param", "needs a param",
        edges=[{"from": "sense", "to": "go"}, BACK]),
    bad("unknown variable in set", "references", "edges[0].set.n", "not a declared variable",
        edges=first_edge(set={"n": "1"})),
    bad("no reachable terminal", "graph", "terminals", "no terminal node is reachable from: go",
        edges=[first_edge()[0], {"from": "go", "to": "go", "param": "(0, 0)"}]),
    bad("unreachable node", "graph", "nodes", "not reachable from the start node: go", edges=[]),
    bad("import", "expressions", "edges[0].param",
        "call to '__import__', which is not a whitelisted function",
        edges=first_edge(param="__import__('os')")),
    bad("attribute access", "expressions", "edges[0].guard", "forbidden syntax: Attribute",
        edges=first_edge(guard="current_cell().count")),
    bad("lambda call", "expressions", "edges[0].param",
        "only helpers called by plain name are allowed",
        edges=first_edge(param="(lambda: (0, 0))()")),
    bad("malformed expression", "expressions", "edges[0].param", "syntax error",
        edges=first_edge(param="current_cell(")),
    bad("unknown helper", "expressions", "functions.frontier.expr",
        "call to 'explord', which is not a whitelisted function; did you mean 'explored'? "
        "(functions here: adjacent, beside, current_cell, explored, frontier, frontier_cells, "
        "goal_cell, goal_found, is_free, label, manhattan, opposite)",
        functions={"frontier": {"args": [], "expr": "explord()"}}),
    bad("misspelled key", "schema", "edges[0].form",
        "Extra inputs are not permitted (did you mean 'from'?)",
        edges=[{"form": "sense", "to": "go", "param": "(0, 0)"}]),
    bad("misspelled key in a map", "schema", "functions.f.exp",
        "Extra inputs are not permitted (did you mean 'expr'?)",
        functions={"f": {"args": [], "exp": "0"}}),
    bad("unknown key", "schema", "nodes[0].zzz",
        "Extra inputs are not permitted (known here: id, primitive, behavior, description)",
        nodes=[{**SENSE_GO[0], "zzz": 1}, SENSE_GO[1]]),
    bad("recursive functions", "expressions", "functions", "recursive functions are not allowed",
        functions={"f": {"args": [], "expr": "g()"}, "g": {"args": [], "expr": "f()"}}),
    bad("variable shadows helper", "expressions", "variables.label",
        "'label' is already a helper, label(cell: Cell) -> str: call it in expressions",
        variables={"label": "0"}),
    bad("function shadows builtin", "expressions", "functions.len",
        "'len' is already a builtin function", functions={"len": {"args": [], "expr": "0"}}),
    bad("variable and function share a name", "expressions", "functions.k",
        "'k' is declared twice", variables={"k": "0"}, functions={"k": {"args": [], "expr": "1"}}),
    bad("wrong env", "references", "env", "written for 'VLB-Scoop-v0'", env="VLB-Scoop-v0"),
]


@pytest.mark.parametrize("changes, layer, place, message", BAD_DOCS)
def test_bad_behavior_files_are_rejected_with_file_and_place(changes, layer, place, message,
                                                             grid_env, write_behavior):
    path = write_behavior(explore_doc(**changes))
    before = path.read_bytes()
    with pytest.raises(BehaviorSpecError) as err:
        load_behavior(str(path), grid_env)
    text = str(err.value)
    assert text.startswith(str(path)), text
    assert f": {place}" in text, text
    assert message in text, text
    assert err.value.layer == layer
    assert path.read_bytes() == before  # nothing was changed


def test_invalid_json_names_line_and_column(grid_env, write_behavior):
    path = write_behavior('{"name": "x",\n  "nodes": [}', "broken.json")
    with pytest.raises(BehaviorSpecError, match=r"broken\.json: line 2 column 13: invalid JSON") \
            as err:
        load_behavior(str(path), grid_env)
    assert err.value.layer == "json"


def test_missing_file_and_unknown_name(grid_env):
    with pytest.raises(BehaviorSpecError, match="cannot read behavior file"):
        load_behavior("no/such/file.json", grid_env)
    with pytest.raises(BehaviorSpecError, match="unknown behavior .explore.: known behaviors are"):
        load_behavior("explore", grid_env)


def test_sub_behavior_cycle_is_rejected(grid_env, write_behavior):
    write_behavior({"name": "a", "nodes": [{"id": "n", "behavior": "b.json"}],
                    "start": {"node": "n"}, "terminals": ["n"]}, "a.json")
    b = write_behavior({"name": "b", "nodes": [{"id": "n", "behavior": "a.json"}],
                        "start": {"node": "n"}, "terminals": ["n"]}, "b.json")
    with pytest.raises(BehaviorSpecError, match="sub-behavior cycle"):
        load_behavior(str(b), grid_env)


def test_sub_behavior_by_relative_path(grid_env, write_behavior):
    write_behavior(explore_doc(name="mine"), "mine.json")
    parent = write_behavior({"name": "outer", "nodes": [{"id": "e", "behavior": "mine.json"}],
                             "start": {"node": "e"}, "terminals": ["e"]}, "outer.json")
    policy = load_behavior(str(parent), grid_env)
    _, summary = run(grid_env, policy, 0)
    assert summary["rho_B"] == 1 and policy.trace[0] == ("mine", "sense")


# -- run-time failures are the episode's, not exceptions out of the env ------------------------

def test_stuck_in_non_terminal_node_raises_runtime_error(grid_env, write_behavior):
    doc = explore_doc(edges=[{"from": "sense", "to": "go", "guard": "False", "param": "(0, 0)"},
                             {"from": "go", "to": "sense", "param": "current_cell()"}],
                      terminals=["go"])
    policy = load_behavior(str(write_behavior(doc)), grid_env)
    obs, _ = grid_env.reset(seed=0)
    action, _ = policy.predict(obs)
    obs, *_ = grid_env.step(action)
    with pytest.raises(BehaviorRuntimeError, match="stuck at node 'sense'"):
        policy.predict(obs)


def test_expression_error_at_run_time_names_the_place(grid_env, write_behavior):
    doc = explore_doc(edges=[{"from": "sense", "to": "go", "param": "explored()[99]"},
                             {"from": "go", "to": "sense", "param": "current_cell()"}])
    policy = load_behavior(str(write_behavior(doc)), grid_env)
    obs, _ = grid_env.reset(seed=0)
    obs, *_ = grid_env.step(policy.predict(obs)[0])
    with pytest.raises(BehaviorRuntimeError, match=r"edges\[0\]\.param: IndexError"):
        policy.predict(obs)


def test_param_outside_the_space_is_a_runtime_error(grid_env, write_behavior):
    doc = explore_doc(edges=[{"from": "sense", "to": "go", "param": "(12, 0)"},
                             {"from": "go", "to": "sense", "param": "current_cell()"}])
    policy = load_behavior(str(write_behavior(doc)), grid_env)
    obs, _ = grid_env.reset(seed=0)
    obs, *_ = grid_env.step(policy.predict(obs)[0])
    with pytest.raises(BehaviorRuntimeError, match=r"not in its parameter space"):
        policy.predict(obs)


@settings(max_examples=60, deadline=None)
@given(maps=st.lists(st.lists(st.integers(0, 3), min_size=100, max_size=100), min_size=2,
                     max_size=6))
def test_the_lists_helpers_read_follow_the_labels_bound_last(maps):
    """Explored and frontier cells, computed directly, for each label map bound in turn (the
    helpers remember maps they have seen; binding another one must never show an old list)."""
    helpers = GridHelpers(10)
    for labels in maps + maps[:1]:
        helpers.bind({"labels": np.array(labels), "position": np.array([0.5, 0.5])})
        known = [(k // 10, k % 10) for k in range(100) if labels[k] != UNEXPLORED]
        open_ = [(i, j) for i, j in known if labels[i * 10 + j] != OBSTACLE and any(
            labels[a * 10 + b] == UNEXPLORED
            for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1))
            if 0 <= a < 10 and 0 <= b < 10)]
        assert helpers.explored() == known and helpers.frontier_cells() == open_


def test_the_label_maps_helpers_remember_are_bounded_by_their_cells():
    """On the largest grid the helpers remember at most 100 maps (about as many cells as 4,096
    maps of 10x10), however many they are bound to; what they read stays right past the bound."""
    helpers = GridHelpers(64)
    rng = np.random.default_rng(0)
    for _ in range(250):
        labels = rng.integers(0, 4, 64 * 64)
        helpers.bind({"labels": labels, "position": np.array([0.5, 0.5])})
        assert len(helpers.explored()) == int(np.sum(labels != UNEXPLORED))
    assert len(helpers._views) <= 100


@settings(max_examples=300, deadline=None)
@given(size=st.integers(2, 12), here=st.tuples(st.integers(0, 11), st.integers(0, 11)),
       step=st.sampled_from([(1, 0), (-1, 0), (0, 1), (0, -1), (0, 0), (1, 1), (2, 0)]))
def test_the_opposite_cell_is_across_the_agent_from_its_neighbour(size, here, step):
    """``opposite(n)``, ``n`` beside the agent, is the cell across the agent from it (here +
    (here - n)) where that lies on the grid, else None; None too where ``n`` is not beside the
    agent; a cell off the grid is refused with the helper's name."""
    helpers = GridHelpers(size)
    here = (here[0] % size, here[1] % size)
    helpers.bind({"labels": np.full(size * size, UNEXPLORED),
                  "position": np.array([here[0] + 0.5 - size / 2, here[1] + 0.5 - size / 2])})
    assert helpers.current_cell() == here
    n = (here[0] - step[0], here[1] - step[1])
    if not all(0 <= v < size for v in n):
        with pytest.raises(ValueError, match=r"opposite\(\): .* not a cell of the"):
            helpers.opposite(n)
        return
    across = (here[0] + step[0], here[1] + step[1])
    if n not in helpers.adjacent() or not all(0 <= v < size for v in across):
        assert helpers.opposite(n) is None
        return
    assert helpers.opposite(n) == across and across in helpers.adjacent()
    assert helpers.manhattan(n, across) == 2


@pytest.mark.parametrize("cell", [None, "A1", (True, 0), (10**30, 0), (1.0, 2), (1, 2, 3),
                                  ((1, 2), 3), (-1, 0), (0, 10)])
def test_opposite_refuses_what_is_not_a_cell_in_one_line(cell):
    """A behavior's argument to ``opposite`` is untrusted: anything but a cell of the grid is
    refused with the helper's name before any arithmetic."""
    helpers = GridHelpers(10)
    with pytest.raises(ValueError, match=r"^opposite\(\): .* not a cell"):
        helpers.opposite(cell)


def test_helpers_read_only_the_observation(grid_env):
    helpers = grid_env.unwrapped.make_helpers()
    labels = np.full(100, UNEXPLORED)
    labels[[11, 12]] = [0, GOAL]
    helpers.bind({"labels": labels, "position": np.array([-3.5, -3.5])})
    assert helpers.explored() == [(1, 1), (1, 2)]
    assert helpers.goal_found() and helpers.goal_cell() == (1, 2)
    assert helpers.current_cell() == cell_of(np.array([-3.5, -3.5]), 10) == (1, 1)
    assert helpers.adjacent() == [(2, 1), (0, 1), (1, 2), (1, 0)]
    assert helpers.adjacent((0, 0)) == [(1, 0), (0, 1)]
    assert helpers.label((1, 2)) == "goal"
    with pytest.raises(ValueError, match="not a cell of the 10x10 grid"):
        helpers.label((10, 0))
    with pytest.raises(ValueError, match="not a cell"):
        helpers.adjacent("A1")
    assert helpers.frontier_cells() == [(1, 1), (1, 2)]  # known, free, an unexplored neighbour
    assert helpers.manhattan((1, 1), (4, 3)) == 5
    assert helpers.beside((1, 1), "up") == (1, 2) and helpers.beside((0, 0), "left") is None
    assert helpers.is_free((1, 2)) and not helpers.is_free((5, 5))
    assert not helpers.is_free(None)  # outside the grid: nothing can stand there
    assert not any(helpers.is_free(c) for c in [(-1, 4), (1, 10), (10**30, 0), (0, -10**30),
                                                 (np.int64(-1), np.int64(3)), [10, 0]])
    assert helpers.is_free((np.int64(1), np.int64(2))) and helpers.is_free([1, 2])
    for bad in ["A1", (1.0, 2), (True, 0), (1, 2, 3)]:
        with pytest.raises(ValueError, match=r"^is_free\(\): .* not a cell"):
            helpers.is_free(bad)
    with pytest.raises(ValueError, match="not one of"):
        helpers.beside((1, 1), "north")
    described = helpers.describe()
    assert {name.split("(")[0] for name in described} == {
        "explored", "adjacent", "goal_found", "goal_cell", "current_cell", "label",
        "frontier_cells", "manhattan", "beside", "opposite", "is_free"}
    assert all(text for text in described.values())
