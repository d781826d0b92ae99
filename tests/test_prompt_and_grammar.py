"""The compact prompt (v2) against v1, its worked examples, and the request schema compiled by
real grammar compilers: llguidance (llama.cpp's optional engine, vLLM, SGLang) and outlines-core
(outlines, vLLM, TGI) in the default suite, llama.cpp's own where llama-cpp-python is installed."""

from __future__ import annotations

import json
from importlib import resources

import gymnasium as gym
import llguidance
import pytest
from outlines_core.json_schema import build_regex_from_schema

from vlb_gym.abstractor.grammar import request_schema
from vlb_gym.abstractor.paper import PAPER, PROMPTS
from vlb_gym.abstractor.prompt import PROMPT_VERSION, PromptContext, build_messages, space_text
from vlb_gym.abstractor.synthesize import synthesize
from vlb_gym.abstractor.backends import ScriptedBackend
from vlb_gym.abstractor.validate import validate_reply
from vlb_gym.core.library import BehaviorLibrary, compile_spec
from vlb_gym.core.spec import parse_spec

ENVS = ("VLB-GridExplore-v0", "VLB-Scoop-v0")
EXAMPLES = resources.files("vlb_gym.abstractor") / "prompts" / "v2" / "examples"


@pytest.fixture
def library(user_library):
    return BehaviorLibrary(user_library)


def prompt_chars(env_id: str, library: BehaviorLibrary, version: str) -> int:
    context = PromptContext.build(gym.make(env_id), library)
    return sum(len(m["content"]) for m in build_messages("Explore.", context, version=version))


@pytest.mark.parametrize("env_id", ENVS)
def test_v2_is_the_default_and_under_half_of_v1(env_id, library):
    """Characters here; tokens (Qwen2.5's tokenizer) in benchmarks/prompt_tokens.py."""
    assert PROMPT_VERSION == "v2"
    assert prompt_chars(env_id, library, "v2") < 0.5 * prompt_chars(env_id, library, "v1")


def test_v2_keeps_what_the_model_needs(library):
    env = gym.make(ENVS[0])
    context = PromptContext.build(env, library, ("explore_until_goal",))
    system, user = (m["content"] for m in build_messages("Find a goal.", context, "Cells: 1 m."))
    for name, primitive in env.unwrapped.primitives.items():
        assert f"- {name}: {primitive.description} Space: integers in [0, 10) x [0, 10)." in user
    for signature in env.unwrapped.make_helpers().describe():
        assert f"- {signature}:" in user
    for name in ("explore_until_goal", "find_goal_and_oscillate"):
        assert f"- {name}" in user
    assert "explore_until_goal (the user asks you to build on it)" in user
    assert json.dumps(json.loads((EXAMPLES / f"{ENVS[0]}.json").read_text())) in user
    assert user.rstrip().endswith("Task: Find a goal.") and "Cells: 1 m." in user
    assert "argmax" in system and '"terminals"' in system
    with pytest.raises(ValueError, match="unknown prompt version"):
        build_messages("x", context, version="v0")


def test_the_prompt_puts_the_task_last_so_requests_share_a_prefix(library):
    context = PromptContext.build(gym.make(ENVS[0]), library)
    one, two = (build_messages(task, context)[1]["content"] for task in ("Go home.", "Patrol."))
    shared = next(i for i, (a, b) in enumerate(zip(one, two)) if a != b)
    assert one[:shared].endswith("Task: ") and one[shared:].rstrip() == "Go home."


def test_space_text():
    assert space_text(gym.spaces.MultiDiscrete([10, 7])) == "integers in [0, 10) x [0, 7)"
    assert space_text(gym.spaces.Discrete(3, start=1)) == "an integer in [1, 4)"
    assert space_text(gym.spaces.Box(-1.0, 2.5, (2,))) == "2 numbers in [-1, 2.5] x [-1, 2.5]"


def test_the_grid_example_passes_every_layer(library):
    text = (EXAMPLES / f"{ENVS[0]}.json").read_text()
    compiled = validate_reply(text, gym.make(ENVS[0]), library, source="example")
    assert compiled.name == "sense_three_cells"


def test_the_scoop_example_compiles(library):
    """Every layer but the dry run (physics: seconds per scoop; the example's pose is the
    library pose moved up 5 cm)."""
    spec = parse_spec((EXAMPLES / f"{ENVS[1]}.json").read_text(), "example")
    compile_spec(spec, gym.make(ENVS[1]), "example", None, library, names_only=True)


@pytest.mark.parametrize("replies", ["behavior1", "behavior2"])
def test_the_paper_replies_still_validate_with_the_compact_prompt(replies, library):
    uses = ("explore_for_goal",) if replies == "behavior2" else ()
    if uses:  # the paper's Behavior 2 builds on its Behavior 1, synthesized first
        first = ScriptedBackend.from_file(PAPER / "behavior1.replies.json")
        library.save(synthesize(ENVS[0], PROMPTS["behavior1"], first, library).compiled.spec)
    backend = ScriptedBackend.from_file(PAPER / f"{replies}.replies.json")
    result = synthesize(ENVS[0], PROMPTS[replies], backend, library, uses=uses)
    assert result.transcript["prompt_version"] == "v2"
    assert result.transcript["messages"][1]["content"].rstrip().endswith(PROMPTS[replies])


# -- the request schema through real grammar compilers ------------------------------------------

def _schemas():
    for env_id in ENVS:
        env = gym.make(env_id)
        yield pytest.param(request_schema(env), id=f"{env_id}-no-library")
        yield pytest.param(request_schema(env, ["explore_until_goal", "b2"]),
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
