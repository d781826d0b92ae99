"""The type check of behavior expressions: meaning errors refused before running, never a valid
behavior (shipped, example or paper reply) refused."""

from __future__ import annotations

import json
import re
import shlex
from pathlib import Path

import gymnasium as gym
import pytest

from vlb_gym import BehaviorSpecError
from vlb_gym.core import compiler
from vlb_gym.core.library import (
    BehaviorLibrary,
    compile_for,
    compile_spec,
    shipped_behaviors,
)
from vlb_gym.core.spec import spec_from_data
from vlb_gym.core.signatures import BUILTIN_SIGNATURES, helper_signatures
from vlb_gym.core.typecheck import TypeCheckError, check
from vlb_gym.envs.grid_explore.helpers import GridHelpers
from vlb_gym.envs.modules import import_env_module

from .conftest import explore_doc

ROOT = Path(__file__).resolve().parent.parent
PAPER = ROOT / "vlb_gym" / "abstractor" / "paper"
LABELS = "'empty', 'obstacle', 'unexplored', 'goal'"
GRID = {**BUILTIN_SIGNATURES, **helper_signatures(GridHelpers(10).functions())}


def guard(text: str) -> dict:
    """The shipped explore_until_goal with its first edge's guard replaced."""
    doc = explore_doc()
    doc["edges"][0]["guard"] = text
    return doc


def compile_doc(doc: dict, env: gym.Env):
    return compile_spec(spec_from_data(doc, "b.json"), env, "b.json")


@pytest.mark.parametrize("text, message", [
    ("label(current_cell()) == 2",
     f"label() returns one of {LABELS}; compared with int 2 (column 1)"),
    ("2 != label(current_cell())",
     f"label() returns one of {LABELS}; compared with int 2 (column 6)"),
    ("label(current_cell()) == 'wall'",
     f"label() returns one of {LABELS}; compared with 'wall', which it never is"),
    ("label(current_cell()) == None",
     f"label() returns one of {LABELS}; compared with None (column 1)"),
    ("label(current_cell()) < 1.5",
     f"label() returns one of {LABELS}; compared with float 1.5"),
    ("label(current_cell()) in ('goal', 'wall')",
     f"label() returns one of {LABELS}; tested against 'wall', which it never is"),
    ("any(label(c) == 3 for c in explored())",
     f"label() returns one of {LABELS}; compared with int 3"),
    ("label(current_cell()) == len(explored())",
     f"label() returns one of {LABELS}; compared with int len(explored())"),
    ("(label(current_cell()) if goal_found() else 'none') == 'wall'",
     ("label(current_cell()) if goal_found() else 'none' is one of 'empty', 'obstacle', "
      "'unexplored', 'goal', 'none'; compared with 'wall', which it never is")),
    ("label(2) == 'goal'", "label() argument 1 is a tuple; given int 2"),
    ("label('a', 'b') == 'goal'", "label() takes 1 argument(s), 2 given"),
    ("len(adjacent(current_cell(), 1)) > 0", "adjacent() takes 0 to 1 argument(s), 2 given"),
    ("len() > 0", "len() takes 1 argument(s), 0 given"),
    ("explored() > 3", "explored() (list) and 3 (int) have no order (column 1)"),
    ("current_cell() <= len(explored())",
     "current_cell() (tuple) and len(explored()) (int) have no order"),
    ("goal_cell() > None", "None is None, which has no order"),
    ("sum(explored()) > 0", "sum() adds numbers; explored() is a list of tuple (column 1)"),
    ("current_cell() + 1 == (1, 1)",
     "'current_cell() + 1' applies '+' to a tuple and an int, which fails whenever it runs"),
    ("len(explored() + current_cell()) > 2", "applies '+' to a list and a tuple"),
    ("label(current_cell()) - 1 > 0", "applies '-' to a str and an int"),
    ("len(explored() * explored()) > 0", "applies '*' to a list and a list"),
    ("len(explored() * 1.5) > 0", "applies '*' to a list and a float"),
    ("manhattan(current_cell(), current_cell()) + None > 0", "applies '+' to an int and None"),
    ("len(label(current_cell()) % 2) > 0", "applies '%' to a str and an int"),
])
def test_refusals_name_the_place_and_say_why(grid_env, text, message):
    with pytest.raises(BehaviorSpecError) as info:
        compile_doc(guard(text), grid_env)
    assert str(info.value).startswith("b.json: edges[0].guard: ")
    assert message in str(info.value)
    assert info.value.layer == "expressions"


def test_arithmetic_on_a_function_result_of_the_wrong_kind_is_caught_at_load(grid_env):
    doc = explore_doc()
    doc["functions"]["best_step"] = {"args": [], "expr": "current_cell()"}
    doc["edges"][0]["param"] = "(best_step() + 1, 0)"
    with pytest.raises(BehaviorSpecError, match=r"b.json: edges\[0\].param: 'best_step\(\) \+ 1' "
                                                 r"applies '\+' to a tuple and an int"):
        compile_doc(doc, grid_env)


def test_behavior_functions_carry_their_result_type(grid_env):
    doc = explore_doc()
    doc["functions"]["kind"] = {"args": ["c"], "expr": "label(c)"}
    doc["edges"][0]["guard"] = "kind(current_cell()) == 1"
    with pytest.raises(BehaviorSpecError, match=r"kind\(\) returns one of .*compared with int 1"):
        compile_doc(doc, grid_env)
    doc["functions"]["bad"] = {"args": ["c"], "expr": "label(c) == 'wal'"}
    with pytest.raises(BehaviorSpecError, match=r"b.json: functions.bad.expr: .*'wal'"):
        compile_doc(doc, grid_env)


@pytest.mark.parametrize("text", [
    "label(current_cell()) == 'goal'", "label(current_cell()) != 'obstacle'",
    "label(current_cell()) in ['empty', 'goal']", "label(current_cell()) < 'z'",
    "label(goal_cell()) == 'goal'", "label([0, 1]) == 'empty'",
    "label(current_cell()) == label(goal_cell())", "not goal_found()",
    "label(current_cell())[0] == 'g'", "sorted([label(c) for c in explored()])[0] == 'goal'",
    "current_cell() < (3, 4)", "len(explored()) >= 2.5 > True", "sum(current_cell()) > 3",
    "sum([len(adjacent(c)) for c in explored()]) > 3", "explored() < adjacent()",
    "len(explored() + adjacent()) > 2", "len(current_cell() + (1,)) == 3",
    "len(explored() * 2) > 0", "len(3 * label(current_cell())) > 0", "len(True * explored()) >= 0",
    "len(explored()) * 2.5 + goal_found() - 1 > 0", "len(explored()) % 3 == 1",
])
def test_what_can_be_right_is_accepted(text):
    check(text, GRID, "here")


def test_unknowns_are_accepted():
    for text in ("v == 2", "f(1, 2) == 3", "label(v) == 'goal'", "[a for a, b in v][0] == 2"):
        check(text, GRID, "here")
    with pytest.raises(TypeCheckError,
                       match=r"^here: \[label\(c\) for c in explored\(\)\]\[0\] is one of "):
        check("[label(c) for c in explored()][0] == 0", GRID, "here")


def test_shipped_behaviors_still_load(grid_env):
    envs = {}
    try:
        for name in shipped_behaviors():
            spec_env = json.loads((ROOT / "vlb_gym" / "behaviors" / f"{name}.json")
                                  .read_text())["env"]
            env = envs.setdefault(spec_env, gym.make(spec_env))
            compile_for(name, env)
    finally:
        for env in envs.values():
            env.close()


def test_examples_still_load():
    import_env_module(str(ROOT / "examples" / "integrator_env.py"))
    for path in sorted((ROOT / "examples").glob("*.json")):
        if path.name.startswith("bad"):  # the documented refusals: see the next test
            continue
        env = gym.make(json.loads(path.read_text())["env"])
        try:
            compile_for(str(path), env)
        finally:
            env.close()


def test_valid_paper_replies_still_load(grid_env, monkeypatch):
    """Every paper reply loads (after the ones before it, as the scripted synthesis saves them),
    or fails for a reason of its own: the type check never refuses one."""
    refused = []

    def spy(*args, **kwargs):
        try:
            return real(*args, **kwargs)
        except TypeCheckError as exc:
            refused.append(str(exc))
            raise

    real = compiler.typecheck
    monkeypatch.setattr(compiler, "typecheck", spy)
    library = BehaviorLibrary()
    loaded = 0
    for path in sorted(PAPER.glob("*.replies.json")):
        for i, doc in enumerate(json.loads(path.read_text())):
            spec = spec_from_data(doc, f"{path.name}[{i}]")
            try:
                compile_spec(spec, grid_env, f"{path.name}[{i}]", library=library)
            except BehaviorSpecError:
                continue  # wrong on purpose (e.g. an unknown primitive): the repair loop's job
            library.save(spec, overwrite=True)
            loaded += 1
    assert refused == []
    assert loaded == 2  # behavior 1's reply and behavior 2's repaired reply


@pytest.mark.parametrize("example", ["bad.json", "bad_label.json"])
def test_the_documented_refused_examples_print_what_the_page_shows(example, capsys, monkeypatch):
    from vlb_gym.cli import main

    readme = (ROOT / "docs" / "behaviors.md").read_text()
    command, shown = re.search(rf"^\$ vlb (verify .*examples/{example}.*)\n(.*)$", readme,
                               re.M).groups()
    monkeypatch.chdir(ROOT)
    assert main(shlex.split(command)) == 2
    assert capsys.readouterr().err.strip() == shown
