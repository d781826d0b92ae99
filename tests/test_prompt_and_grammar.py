"""The compact prompts (v2, v3) against v1, their worked examples, and the request schema compiled by
real grammar compilers: llguidance (llama.cpp's optional engine, vLLM, SGLang) and outlines-core
(outlines, vLLM, TGI) in the default suite, llama.cpp's own where llama-cpp-python is installed."""

from __future__ import annotations

import json
from importlib import resources

import gymnasium as gym
import llguidance
import pytest
from outlines_core.json_schema import build_regex_from_schema

from vlb_gym.abstractor.grammar import grammar_schema
from vlb_gym.abstractor.paper import PAPER, PROMPTS
from vlb_gym.abstractor.prompt import PROMPT_VERSION, PromptContext, build_messages, space_text
from vlb_gym.abstractor.synthesize import synthesize
from vlb_gym.abstractor.backends import ScriptedBackend
from vlb_gym.abstractor.validate import validate_reply
from vlb_gym.core.library import BehaviorLibrary, compile_spec
from vlb_gym.core.spec import parse_spec

ENVS = ("VLB-GridExplore-v0", "VLB-Scoop-v0")
PROMPTS_DIR = resources.files("vlb_gym.abstractor") / "prompts"


def examples(env_id: str, version: str = PROMPT_VERSION) -> list[dict]:
    shipped = json.loads((PROMPTS_DIR / version / "examples" / f"{env_id}.json").read_text())
    return shipped if isinstance(shipped, list) else [shipped]


@pytest.fixture
def library(user_library):
    return BehaviorLibrary(user_library)


def prompt_chars(env_id: str, library: BehaviorLibrary, version: str) -> int:
    context = PromptContext.build(gym.make(env_id), library)
    return sum(len(m["content"]) for m in build_messages("Explore.", context, version=version))


@pytest.mark.parametrize("env_id", ENVS)
def test_v3_is_the_default_and_the_compact_prompts_are_under_half_of_v1(env_id, library):
    """Characters here; tokens (Qwen2.5's tokenizer) in benchmarks/prompt_tokens.py."""
    assert PROMPT_VERSION == "v3"
    for version in ("v2", "v3"):
        assert prompt_chars(env_id, library, version) < 0.5 * prompt_chars(env_id, library, "v1")


def test_the_compact_prompt_keeps_what_the_model_needs(library):
    env = gym.make(ENVS[0])
    context = PromptContext.build(env, library, ("explore_until_goal",))
    system, *turns = build_messages("Find a goal.", context, "Cells: 1 m.")
    system, user = system["content"], "\n".join(turn["content"] for turn in turns)
    for name, primitive in env.unwrapped.primitives.items():
        assert f"- {name}: {primitive.description} Space: integers in [0, 10) x [0, 10)." in user
    for signature in env.unwrapped.make_helpers().describe():
        assert f"- {signature}:" in user
    for name in ("explore_until_goal", "find_goal_and_oscillate"):
        assert f"- {name}" in user
    assert "explore_until_goal (the user asks you to build on it)" in user
    composing, standalone = examples(ENVS[0])
    assert json.dumps(composing) in user and json.dumps(standalone) not in user
    # the example is a solved request of its own, a turn before the task
    assert [turn["role"] for turn in turns] == ["user", "assistant", "user"]
    assert turns[0]["content"].rstrip().endswith(f"Task: {composing['description']}")
    assert turns[1]["content"] == json.dumps(composing)
    assert turns[2]["content"] == "Further information: Cells: 1 m.\n\nTask: Find a goal.\n"
    assert "argmax" in system and '"terminals"' in system
    with pytest.raises(ValueError, match="unknown prompt version"):
        build_messages("x", context, version="v0")


def test_the_prompt_puts_the_task_last_so_requests_share_a_prefix(library):
    context = PromptContext.build(gym.make(ENVS[0]), library)
    one, two = ("".join(m["content"] for m in build_messages(task, context))
                for task in ("Go home.", "Patrol."))
    shared = next(i for i, (a, b) in enumerate(zip(one, two)) if a != b)
    assert one[:shared].endswith("Task: ") and one[shared:].rstrip() == "Go home."


def test_space_text():
    assert space_text(gym.spaces.MultiDiscrete([10, 7])) == "integers in [0, 10) x [0, 7)"
    assert space_text(gym.spaces.Discrete(3, start=1)) == "an integer in [1, 4)"
    assert space_text(gym.spaces.Box(-1.0, 2.5, (2,))) == "2 numbers in [-1, 2.5] x [-1, 2.5]"


def test_an_example_that_composes_a_behavior_is_shown_only_with_that_behavior(tmp_path):
    bare = BehaviorLibrary(tmp_path, shipped=False)
    system, *turns = build_messages("Go.", PromptContext.build(gym.make(ENVS[0]), bare))
    user = "\n".join(turn["content"] for turn in turns)
    composing, standalone = examples(ENVS[0])
    assert any("behavior" in node for node in composing["nodes"])
    assert json.dumps(composing) not in user and json.dumps(standalone) in user


@pytest.mark.parametrize("version", ["v2", "v3"])
def test_the_grid_examples_pass_every_layer(version, library):
    env = gym.make(ENVS[0])
    for doc in examples(ENVS[0], version):
        compiled = validate_reply(json.dumps(doc), env, library, source="example")
        assert compiled.name == doc["name"]


@pytest.mark.parametrize("version", ["v2", "v3"])
def test_the_scoop_examples_compile(version, library):
    """Every layer but the dry run (physics: seconds per scoop; the example's pose is the
    library pose moved up 5 cm)."""
    for doc in examples(ENVS[1], version):
        spec = parse_spec(json.dumps(doc), "example")
        compile_spec(spec, gym.make(ENVS[1]), "example", None, library, names_only=True)


@pytest.mark.parametrize("replies", ["behavior1", "behavior2"])
def test_the_paper_replies_still_validate_with_the_compact_prompt(replies, library):
    uses = ("explore_for_goal",) if replies == "behavior2" else ()
    if uses:  # the paper's Behavior 2 builds on its Behavior 1, synthesized first
        first = ScriptedBackend.from_file(PAPER / "behavior1.replies.json")
        library.save(synthesize(ENVS[0], PROMPTS["behavior1"], first, library).compiled.spec)
    backend = ScriptedBackend.from_file(PAPER / f"{replies}.replies.json")
    result = synthesize(ENVS[0], PROMPTS[replies], backend, library, uses=uses)
    assert result.transcript["prompt_version"] == PROMPT_VERSION
    assert result.transcript["messages"][-1]["content"].rstrip().endswith(PROMPTS[replies])


# -- the request schema through real grammar compilers ------------------------------------------

def _schemas():
    for env_id in ENVS:
        env = gym.make(env_id)
        primitives = env.unwrapped.primitives
        yield pytest.param(grammar_schema(env_id, primitives), id=f"{env_id}-no-library")
        yield pytest.param(grammar_schema(env_id, primitives, ["explore_until_goal", "b2"]),
                           id=f"{env_id}-library")


SCHEMAS = list(_schemas())


def llguidance_errors(schema: dict) -> str:
    grammar = llguidance.grammar_from("json_schema", json.dumps(schema))
    return llguidance.LLMatcher.validate_grammar(grammar)


@pytest.mark.parametrize("schema", SCHEMAS)
def test_llguidance_compiles_the_request_schema(schema):
    assert llguidance_errors(schema) == ""


@pytest.mark.parametrize("schema", SCHEMAS)
def test_outlines_core_compiles_the_request_schema(schema):
    regex = build_regex_from_schema(json.dumps(schema))
    assert '"nodes"' in regex and '"terminals"' in regex


def test_the_compilers_reject_what_they_cannot_compile():
    """The checks above can fail: the validation schema (not meant for grammars) and a
    malformed one are refused."""
    validation = json.loads((resources.files("vlb_gym") / "schema" / "behavior.schema.json")
                            .read_text())
    assert "propertyNames" in llguidance_errors(validation)
    assert "strin" in llguidance_errors({"type": "strin"})
    with pytest.raises(Exception):
        build_regex_from_schema(json.dumps({"type": "object", "properties": {"a": {"$ref": "#/x"}}}))


@pytest.mark.parametrize("schema", SCHEMAS)
def test_llama_cpp_compiles_the_request_schema(schema):
    llama_grammar = pytest.importorskip("llama_cpp.llama_grammar")
    gbnf = llama_grammar.json_schema_to_gbnf(json.dumps(schema))
    assert "root" in gbnf and len(gbnf) < 20_000
