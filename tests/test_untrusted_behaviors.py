"""Hostile behavior files and LLM replies: every finding of the hardening review, kept as a test.

Each case used to hang, exhaust memory, end in a traceback or leak a file; now it is refused at
load or fails its episode with a clear reason, within seconds.
"""

from __future__ import annotations

import json
import os

import pytest

from vlb_gym.abstractor.backends import ScriptedBackend
from vlb_gym.abstractor.synthesize import SynthesisError, synthesize
from vlb_gym.abstractor.validate import validate_reply
from vlb_gym.core.compiler import MAX_BEHAVIOR_DEPTH, MAX_CALL_DEPTH
from vlb_gym.core.budget import MAX_CALLS, EvaluationLimitError
from vlb_gym.core.expressions import BUILTINS, Expression, ExpressionError, guard_namespace
from vlb_gym.core.library import BehaviorLibrary, compile_for, load_behavior
from vlb_gym.core.spec import MAX_FUNCTIONS, BehaviorSpecError
from vlb_gym.verify.episode import run_episode

from .conftest import explore_doc

pytestmark = pytest.mark.timeout(120)

ENV = "VLB-GridExplore-v0"

#: The reviewer's payloads, each within the whitelist of the old checker.
ROUND_DIGITS = "round(5, -1000000000)"
NESTED_IN = "[[0]*10000 in [[0]*9999+[1]]*10000 for a in [0]*10000 for b in [0]*19]"
FORMAT_WIDTH = "'%99999999d' % 1"
FORMAT_REPR = "'%s' % explored"


def evaluate(source: str, **values):
    names = {name: (0 if callable(value) else -1) for name, value in values.items()}
    return Expression(source, {**names, **{n: None for n in BUILTINS}},
                      "test").evaluate(guard_namespace(values))


def timed(call):
    """Run a hostile case: the budgets decide it (its exception or result is what the test
    asserts); the module's timeout, far above any budget, catches one that would hang. No
    assertion on wall time: a loaded machine must not fail the suite."""
    call()


# -- expressions ---------------------------------------------------------------------------------

def test_round_with_a_huge_digits_argument_is_refused_at_once():
    with pytest.raises(EvaluationLimitError, match="round"):
        timed(lambda: evaluate(ROUND_DIGITS))
    assert evaluate("round(2.675, 2)") == 2.67 or evaluate("round(2.675, 2)") == 2.68


def test_work_counts_what_each_item_does_not_only_items():
    with pytest.raises(EvaluationLimitError):
        timed(lambda: evaluate(NESTED_IN))


def test_string_formatting_is_refused_at_load():
    for source in (FORMAT_WIDTH, FORMAT_REPR):
        with pytest.raises(ExpressionError, match="numeric modulo only"):
            Expression(source, {"explored": -1}, "test")


def test_string_formatting_is_refused_at_run_time_for_variables():
    with pytest.raises(EvaluationLimitError, match="numeric modulo only"):
        evaluate("s % 1", s="%99999999d")
    assert evaluate("n % 4", n=7) == 3


def test_integers_cannot_grow_without_bound():
    with pytest.raises(EvaluationLimitError, match="integer"):
        evaluate("n * n * n * n", n=10**9)
    with pytest.raises(EvaluationLimitError, match="integer"):
        evaluate("int(x)", x=1e300)


def doubling_functions(count: int, args: tuple[str, ...] = ("x",)) -> dict:
    """The shipped explore functions plus f0 ... f(count-1), each calling the previous twice
    (with ``args``; a function without arguments is computed once per evaluation)."""
    call = ", ".join(args)
    functions = {**explore_doc()["functions"], "f0": {"args": list(args), "expr": "1"}}
    for k in range(1, count):
        functions[f"f{k}"] = {"args": list(args),
                              "expr": f"f{k - 1}({call}) + f{k - 1}({call})"}
    return functions


def test_too_many_functions_are_refused_at_load(grid_env, write_behavior):
    doc = explore_doc(functions=doubling_functions(41))
    with pytest.raises(BehaviorSpecError, match=f"at most {MAX_FUNCTIONS} items"):
        compile_for(str(write_behavior(doc)), grid_env)


def test_functions_nested_too_deep_are_refused_at_load(grid_env, write_behavior):
    doc = explore_doc(functions=doubling_functions(MAX_CALL_DEPTH + 2))
    with pytest.raises(BehaviorSpecError, match=f"more than {MAX_CALL_DEPTH} deep"):
        compile_for(str(write_behavior(doc)), grid_env)


def test_exponentially_many_calls_fail_the_episode_quickly(grid_env, write_behavior):
    """2**16 calls from 16 doubling functions: the call budget ends the episode, not the process."""
    doc = explore_doc(functions=doubling_functions(MAX_CALL_DEPTH))
    doc["edges"][0]["guard"] = f"f{MAX_CALL_DEPTH - 1}(1) > 0"
    policy = load_behavior(str(write_behavior(doc)), grid_env)
    result = run_episode(grid_env, policy, seed=0)
    assert result.rho == -1 and f"more than {MAX_CALLS} function calls" in result.reason


def test_functions_without_arguments_are_computed_once_per_evaluation(grid_env, write_behavior):
    """The same doubling chain without arguments: each f_k runs once, so the guard is 2**15
    after 16 calls, well inside the call budget."""
    doc = explore_doc(functions=doubling_functions(MAX_CALL_DEPTH, args=()))
    doc["edges"][0]["guard"] = f"f{MAX_CALL_DEPTH - 1}() == {2 ** (MAX_CALL_DEPTH - 1)}"
    doc["edges"][0]["guard"] += " and not goal_found()"
    policy = load_behavior(str(write_behavior(doc)), grid_env)
    result = run_episode(grid_env, policy, seed=0)
    assert result.rho == 1 and result.primitives > 2


def test_a_string_doubled_in_every_step_fails_the_episode(grid_env, write_behavior):
    doc = explore_doc(variables={"s": "'ab'"})
    doc["edges"][1]["set"] = {"s": "s + s"}
    result = run_episode(grid_env, load_behavior(str(write_behavior(doc)), grid_env), seed=0,
                         stop_on_failure=False)
    assert result.rho == -1 and "more than 10000 elements" in result.reason


# -- files ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("path", ["/dev/zero", "/dev/null"])
def test_special_files_are_refused_without_reading(grid_env, path):
    with pytest.raises(BehaviorSpecError, match="not a regular file"):
        timed(lambda: load_behavior(path, grid_env))


def test_a_fifo_is_refused_without_blocking(grid_env, tmp_path):
    fifo = tmp_path / "behavior.json"
    os.mkfifo(fifo)
    with pytest.raises(BehaviorSpecError, match="not a regular file"):
        timed(lambda: load_behavior(str(fifo), grid_env))


def test_an_oversized_file_is_refused(grid_env, write_behavior):
    path = write_behavior(json.dumps(explore_doc(description="x" * 2_000_000)))
    with pytest.raises(BehaviorSpecError, match="the limit is 1000000"):
        load_behavior(str(path), grid_env)


def test_deeply_nested_json_is_refused(grid_env, write_behavior):
    path = write_behavior("[" * 100_000 + "]" * 100_000)
    with pytest.raises(BehaviorSpecError, match="nested deeper than 64 levels"):
        load_behavior(str(path), grid_env)


def chain_doc(name: str, child: str | None, fan: int = 1) -> dict:
    """A behavior whose ``fan`` nodes in a row each run ``child`` (or sense, at the end)."""
    if child is None:
        nodes = [{"id": f"n{k}", "primitive": "sense"} for k in range(fan)]
        edges = [{"from": f"n{k}", "to": f"n{k + 1}", "param": "current_cell()"}
                 for k in range(fan - 1)]
        return {"name": name, "nodes": nodes, "edges": edges,
                "start": {"node": "n0", "param": "current_cell()"}, "terminals": [f"n{fan - 1}"]}
    nodes = [{"id": f"n{k}", "behavior": child} for k in range(fan)]
    edges = [{"from": f"n{k}", "to": f"n{k + 1}"} for k in range(fan - 1)]
    return {"name": name, "nodes": nodes, "edges": edges, "start": {"node": "n0"},
            "terminals": [f"n{fan - 1}"]}


def test_a_3000_deep_chain_of_sub_behaviors_is_refused(grid_env, tmp_path):
    depth = 3000
    for k in range(depth):
        child = f"b{k + 1}.json" if k + 1 < depth else None
        (tmp_path / f"b{k}.json").write_text(json.dumps(chain_doc(f"b{k}", child)))
    with pytest.raises(BehaviorSpecError, match=f"nested more than {MAX_BEHAVIOR_DEPTH} deep"):
        timed(lambda: compile_for(str(tmp_path / "b0.json"), grid_env))


def test_sub_behaviors_are_compiled_once_per_file(grid_env, tmp_path, monkeypatch):
    """Three files of 256 nodes, each node running the next file: 256**3 compilations before;
    counted, not timed (a loaded machine once failed a 10 s limit here)."""
    from vlb_gym.core import compiler

    for name, child in (("a", "b.json"), ("b", "c.json"), ("c", None)):
        (tmp_path / f"{name}.json").write_text(json.dumps(chain_doc(name, child, fan=256)))
    assert (tmp_path / "a.json").stat().st_size > 15_000
    compiled_files: list[str] = []
    original = compiler.compile_behavior

    def counting(spec, interface, source, *args, **kwargs):
        compiled_files.append(source)
        return original(spec, interface, source, *args, **kwargs)

    monkeypatch.setattr(compiler, "compile_behavior", counting)
    monkeypatch.setattr("vlb_gym.core.library.compile_behavior", counting)
    compiled = compile_for(str(tmp_path / "a.json"), grid_env)
    assert len(compiled_files) == 3  # a, b and c, once each
    children = {id(node.child) for node in compiled.nodes.values()}
    assert len(children) == 1  # one compiled b, shared by all 256 nodes
    result = run_episode(grid_env, load_behavior(str(tmp_path / "c.json"), grid_env), seed=0)
    assert result.rho == 1 and result.primitives == 256


# -- LLM replies ---------------------------------------------------------------------------------

def test_a_reply_may_not_reference_a_path(grid_env, tmp_path, user_library):
    secret = tmp_path / "secret.json"
    secret.write_text("TOP-SECRET-CONTENT")
    for ref in (str(secret), "/etc/hostname", "../secret.json", "explore_until_goal.json"):
        reply = json.dumps({"name": "sneaky", "nodes": [{"id": "x", "behavior": ref}],
                            "start": {"node": "x"}, "terminals": ["x"]})
        with pytest.raises(BehaviorSpecError, match="is not a behavior name") as info:
            validate_reply(reply, grid_env, BehaviorLibrary(user_library))
        assert "TOP-SECRET" not in str(info.value) and info.value.layer == "references"


def test_a_reply_may_reference_library_behaviors_by_name(grid_env, user_library):
    reply = json.dumps({"name": "again", "nodes": [{"id": "x", "behavior": "explore_until_goal"}],
                        "start": {"node": "x"}, "terminals": ["x"]})
    compiled = validate_reply(reply, grid_env, BehaviorLibrary(user_library))
    assert compiled.nodes["x"].child.name == "explore_until_goal"


@pytest.mark.parametrize("payload", [ROUND_DIGITS, NESTED_IN, "len('ab' * 6000 * 6000)"])
def test_hostile_expressions_in_a_reply_fail_the_dry_run_quickly(payload, user_library):
    hostile = explore_doc(name="hostile")
    hostile["edges"][0]["guard"] = f"not goal_found() and bool({payload})"
    backend = ScriptedBackend([json.dumps(hostile)])
    with pytest.raises(SynthesisError) as info:
        timed(lambda: synthesize(ENV, "explore", backend, BehaviorLibrary(user_library),
                                 max_rounds=1))
    rounds = info.value.transcript["rounds"]
    assert rounds[0]["layer"] == "dry-run" and "EvaluationLimitError" in rounds[0]["error"]


def test_one_broken_library_file_does_not_stop_synthesis(user_library):
    (user_library / "broken.json").write_text("{ not json")
    good = explore_doc(name="mine")
    (user_library / "mine.json").write_text(json.dumps(good))
    replies = [json.dumps(explore_doc(name="fresh"))]
    result = synthesize(ENV, "explore", ScriptedBackend(replies), BehaviorLibrary(user_library))
    assert result.compiled.name == "fresh"
    assert "broken" in result.transcript["skipped_library_behaviors"]
    prompt = result.transcript["messages"][1]["content"]
    assert "- mine:" in prompt and "broken" not in prompt


def test_a_directory_is_refused_and_no_descriptor_leaks(grid_env, tmp_path):
    before = len(os.listdir("/proc/self/fd"))
    for _ in range(20):
        with pytest.raises(BehaviorSpecError, match="not a regular file"):
            load_behavior(str(tmp_path) + "/", grid_env)
    assert len(os.listdir("/proc/self/fd")) <= before


def test_a_failed_atomic_write_leaves_the_old_file_and_nothing_else(tmp_path):
    from vlb_gym.core.files import write_atomic

    (tmp_path / "taken").mkdir()  # os.replace cannot put a file over a directory
    with pytest.raises(OSError):
        write_atomic(tmp_path / "taken", "new")
    write_atomic(tmp_path / "report.json", "old")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report.json", "taken"]
    assert (tmp_path / "report.json").read_text() == "old"


def test_a_compiled_sub_behavior_met_deeper_still_counts_its_depth(grid_env, tmp_path):
    """c0 -> ... -> c14 (15 levels) is compiled once, via a shallow reference; met again under a
    10-deep chain it would nest 25 deep: refused, though it comes from the compile cache."""
    def write(name, children):
        nodes = [{"id": f"n{k}", "behavior": child} for k, child in enumerate(children)]
        edges = [{"from": f"n{k}", "to": f"n{k + 1}"} for k in range(len(children) - 1)]
        (tmp_path / f"{name}.json").write_text(json.dumps(
            {"name": name, "nodes": nodes, "edges": edges, "start": {"node": "n0"},
             "terminals": [f"n{len(children) - 1}"]}))

    (tmp_path / "c14.json").write_text(json.dumps(chain_doc("c14", None)))
    for k in range(13, -1, -1):
        write(f"c{k}", [f"c{k + 1}.json"])
    for k in range(9, -1, -1):
        write(f"d{k}", [f"d{k + 1}.json" if k < 9 else "c0.json"])
    write("top", ["c0.json", "d0.json"])
    assert compile_for(str(tmp_path / "c0.json"), grid_env).depth == 15
    with pytest.raises(BehaviorSpecError, match=f"nested more than {MAX_BEHAVIOR_DEPTH} deep"):
        compile_for(str(tmp_path / "top.json"), grid_env)


def test_hostile_helper_arguments_are_refused_without_hashing_or_printing_them(grid_env):
    """A tuple nested 40 deep whose halves are shared hashes for hours, and a huge list prints
    for ever: grid helpers check types first and print arguments briefly."""
    helpers = grid_env.unwrapped.make_helpers()
    obs, _ = grid_env.reset(seed=0)
    helpers.bind(obs)
    nested = (0, 0)
    for _ in range(40):
        nested = (nested, nested)
    huge = [["a" * 10_000] * 10_000] * 10_000
    for bad in (nested, huge, (nested, 1), (True, 1)):
        with pytest.raises(ValueError, match="label"):
            timed(lambda: helpers.label(bad))
    assert helpers.label((0, 0)) in ("unexplored", "empty", "obstacle", "goal")


def test_hostile_values_in_error_messages_are_printed_briefly(grid_env, write_behavior):
    doc = explore_doc()
    doc["start"]["param"] = "[['a' * 10000] * 10000] * 10000"
    result = run_episode(grid_env, load_behavior(str(write_behavior(doc)), grid_env), seed=0)
    assert result.rho == -1 and len(result.reason) < 500 and "parameter space" in result.reason


def test_json_with_an_unclosed_string_of_escapes_is_refused_in_linear_time(grid_env,
                                                                           write_behavior):
    path = write_behavior('"' + '\\"' * 400_000)
    with pytest.raises(BehaviorSpecError, match="invalid JSON"):
        timed(lambda: load_behavior(str(path), grid_env))


def test_a_number_of_5000_digits_is_a_json_error_naming_the_file(grid_env, write_behavior):
    path = write_behavior('{"name": ' + "1" * 5000 + "}")
    with pytest.raises(BehaviorSpecError, match="behavior.json: Exceeds the limit") as info:
        load_behavior(str(path), grid_env)
    assert info.value.layer == "json"


def test_scoop_offset_refuses_what_is_not_a_pose():
    from vlb_gym.envs.scoop.helpers import ScoopHelpers

    with pytest.raises(ValueError, match="not a number"):
        timed(lambda: ScoopHelpers().offset(([0] * 10_000, 0, 0, 0, 0, 0), 1, 0, 0))


@pytest.mark.parametrize("param", [{1: 2, 3: 4}, [True, 1], (1.0, 2), "12", (1, 2, 3), (-1, 0)])
def test_encode_and_decode_refuse_what_is_not_a_cell(grid_env, param):
    env = grid_env.unwrapped
    with pytest.raises(ValueError, match="not in its parameter space"):
        env.encode_action("navigate", param)
    with pytest.raises(ValueError, match="not in the action space"):
        env.decode_action([1, *param] if isinstance(param, (list, tuple)) else param)


def test_box_actions_are_checked_as_given_not_after_rounding():
    import gymnasium as gym
    import numpy as np

    env = gym.make("VLB-Scoop-v0").unwrapped
    high = np.array([1.00000001, 0, 1.2, 3.14, 0, 0])  # x above 1.0 by less than float32 sees
    with pytest.raises(ValueError, match="not in the action space"):
        env.decode_action(high)
    with pytest.raises(ValueError, match="not in its parameter space"):
        env.encode_action("scoop", [True] * 6)
    assert env.decode_action(np.array([0.5, 0, 0.5, 3.1, 0, 0]))[1][0] == 0.5
    env.close()
