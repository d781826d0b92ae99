"""The natural-language behavior generalizer: backends over real HTTP, validation and repair,
code injection, the library, and the paper's two prompts."""

from __future__ import annotations

import json
from pathlib import Path

import gymnasium as gym
import pytest

from vlb_gym import load_behavior
from vlb_gym.abstractor.backends import ModelError, ScriptedBackend, TranscriptBackend
from vlb_gym.abstractor.served import OpenAICompatibleBackend
from vlb_gym.abstractor.prompt import PromptContext, build_messages, request_schema
from vlb_gym.abstractor.synthesize import SynthesisError, save, synthesize
from vlb_gym.cli import main
from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.core.spec import BehaviorSpecError
from vlb_gym.verify import CampaignConfig, run_campaign
from vlb_gym.wrappers import RobustnessWrapper

from .chat_server import ChatServer
from vlb_gym.abstractor.paper import PAPER, PROMPTS


ENV = "VLB-GridExplore-v0"
PAPER_PROMPT_1 = PROMPTS["behavior1"]
PAPER_PROMPT_2 = PROMPTS["behavior2"]
REPLIES_1 = PAPER / "behavior1.replies.json"
REPLIES_2 = PAPER / "behavior2.replies.json"


def reply(path: Path = REPLIES_1, index: int = 0, **changes) -> str:
    doc = json.loads(path.read_text())[index]
    doc.update(changes)
    return json.dumps(doc)


@pytest.fixture
def library(user_library):
    return BehaviorLibrary(user_library)


def http_backend(server, **kwargs):
    kwargs.setdefault("timeout", 5.0)
    kwargs.setdefault("backoff", 0.01)
    return OpenAICompatibleBackend(server.url, "test-model", **kwargs)


# -- the OpenAI-compatible backend against a real HTTP server ----------------------------------

def test_http_success_sends_schema_with_enums_and_key(library, monkeypatch):
    monkeypatch.setenv("TEST_KEY", "sk-test")
    with ChatServer([("reply", reply())]) as server:
        result = synthesize(ENV, PAPER_PROMPT_1, http_backend(server, api_key_env="TEST_KEY"),
                            library)
    assert result.rounds == 1 and result.compiled.name == "explore_for_goal"
    body = server.requests[0]
    assert body["model"] == "test-model" and body["messages"][0]["role"] == "system"
    assert PAPER_PROMPT_1 in body["messages"][-1]["content"]
    schema = body["response_format"]["json_schema"]["schema"]
    assert schema["$defs"]["Node"]["anyOf"][0]["properties"]["primitive"]["enum"] == \
        ["navigate", "sense"]
    assert server.headers[0]["Authorization"] == "Bearer sk-test"


@pytest.mark.parametrize("mode, expected", [("json_object", {"type": "json_object"}),
                                            ("none", None)])
def test_structured_output_setting(mode, expected, library):
    with ChatServer([("reply", reply())]) as server:
        synthesize(ENV, "x", http_backend(server, structured_output=mode), library)
    assert server.requests[0].get("response_format") == expected


def test_reply_that_is_not_json_is_repaired(library):
    with ChatServer([("reply", "Sure! Here is the behavior you asked for."),
                     ("reply", "```json\n" + reply() + "\n```")]) as server:
        result = synthesize(ENV, PAPER_PROMPT_1, http_backend(server), library)
    assert result.rounds == 2
    first = result.transcript["rounds"][0]
    assert first["layer"] == "json" and "invalid JSON" in first["error"]
    repair = server.requests[1]["messages"][-1]["content"]
    assert "rejected by the json check" in repair and "invalid JSON" in repair


def test_unknown_primitive_is_repaired_on_the_second_round(library):
    wrong = json.loads(reply())
    wrong["nodes"][1]["primitive"] = "teleport"
    with ChatServer([("reply", json.dumps(wrong)), ("reply", reply())]) as server:
        result = synthesize(ENV, PAPER_PROMPT_1, http_backend(server), library)
    assert result.rounds == 2 and result.compiled.primitives_used() == {"sense", "navigate"}
    messages = server.requests[1]["messages"]
    assert messages[-2] == {"role": "assistant", "content": json.dumps(wrong)}
    assert "unknown primitive 'teleport'" in messages[-1]["content"]


def test_reply_that_never_validates_fails_clearly_and_adds_nothing(library):
    replies = ["{}", '{"name": 1}', '{"nodes": 2}']  # distinct: a repeat would be drawn again
    with ChatServer([("reply", r) for r in replies]) as server:
        with pytest.raises(SynthesisError, match="no valid behavior after 3 round") as err:
            synthesize(ENV, PAPER_PROMPT_1, http_backend(server), library, max_rounds=3)
    assert len(server.requests) == 3
    assert [r["layer"] for r in err.value.transcript["rounds"]] == ["schema"] * 3
    assert library.user_behaviors() == []


def test_a_served_reply_repeating_a_rejected_one_is_drawn_again(library):
    with ChatServer([("reply", "{}"), ("reply", "{}"), ("reply", reply())]) as server:
        result = synthesize(ENV, PAPER_PROMPT_1, http_backend(server), library, max_rounds=2)
    assert result.rounds == 2 and len(server.requests) == 3
    assert server.requests[2]["temperature"] >= 0.7 and server.requests[2]["seed"] == 1


def test_server_errors_are_retried_then_fail_clearly():
    with ChatServer([("status", 500)] * 3) as server:
        backend = http_backend(server, max_retries=2)
        with pytest.raises(ModelError, match=r"no reply after 3 attempt\(s\); last: HTTP 500"):
            backend.complete([{"role": "user", "content": "hi"}])
    assert len(server.requests) == 3
    with ChatServer([("status", 503), ("status", 429), ("reply", "ok")]) as server:
        assert http_backend(server, max_retries=2).complete([]) == "ok"


def test_client_errors_are_not_retried():
    with ChatServer([("status", 401), ("reply", "never")]) as server:
        with pytest.raises(ModelError, match="HTTP 401"):
            http_backend(server, max_retries=3).complete([])
    assert len(server.requests) == 1


def test_timeouts_are_retried_then_fail_clearly():
    with ChatServer([("sleep", 1.0, "late")] * 2) as server:
        with pytest.raises(ModelError, match="timed out after 0.2 s"):
            http_backend(server, timeout=0.2, max_retries=1).complete([])
    assert len(server.requests) == 2


def test_malformed_completion_and_unreachable_server():
    with ChatServer([("raw", b'{"choices": []}')]) as server:
        with pytest.raises(ModelError, match="not a chat completion"):
            http_backend(server).complete([])
    with ChatServer([]) as server:
        url = server.url
    backend = OpenAICompatibleBackend(url, "m", timeout=1, max_retries=1, backoff=0.01)
    with pytest.raises(ModelError, match="cannot connect"):
        backend.complete([])


def test_backend_failure_during_synthesis_keeps_a_transcript(library):
    with ChatServer([("status", 500)] * 2) as server:
        with pytest.raises(SynthesisError, match="language model failed") as err:
            synthesize(ENV, "x", http_backend(server, max_retries=1), library)
    assert err.value.transcript["rounds"][0]["layer"] == "backend"


# -- code injection is rejected before anything runs -------------------------------------------

INJECTIONS = {
    "import in guard": {"guard": "__import__('os').system('touch {sentinel}') or True"},
    "import in param": {"param": "__import__('os').system('touch {sentinel}')"},
    "attribute access": {"param": "().__class__.__bases__[0].__subclasses__()"},
    "lambda called": {"param": "(lambda: open('{sentinel}', 'w'))()"},
    "open builtin": {"guard": "open('{sentinel}', 'w') is None"},
    "huge comprehension": {"param": "[c for c in explored() for a in explored() "
                                    "for b in explored() for d in explored()][0]"},
    "huge repetition": {"param": "len([0] * 100000000)"},
    "dunder name": {"param": "__builtins__"},
}


@pytest.mark.parametrize("name", INJECTIONS)
def test_code_injection_is_rejected(name, library, tmp_path):
    sentinel = tmp_path / "pwned"
    edge = {k: v.format(sentinel=sentinel) for k, v in INJECTIONS[name].items()}
    doc = json.loads(reply())
    doc["edges"][0].update(edge)
    backend = ScriptedBackend([json.dumps(doc)])
    with pytest.raises(SynthesisError) as err:
        synthesize(ENV, "x", backend, library, max_rounds=1)
    assert err.value.transcript["rounds"][0]["layer"] in ("expressions", "dry-run")
    assert not sentinel.exists() and library.user_behaviors() == []


@pytest.mark.parametrize("field, value", [
    ("variables", {"x": "__import__('os')"}),
    ("functions", {"f": {"args": [], "expr": "globals()"}}),
])
def test_injection_in_other_fields(field, value, library):
    with pytest.raises(SynthesisError, match="expressions check"):
        synthesize(ENV, "x", ScriptedBackend([reply(**{field: value})]), library, max_rounds=1)


# -- the library and Algorithm 1 ----------------------------------------------------------------

def test_library_saves_lists_and_protects_shipped(library):
    result = synthesize(ENV, PAPER_PROMPT_1, ScriptedBackend([reply()]), library)
    path = save(result, library)
    assert path == library.directory / "explore_for_goal.json"
    assert path.with_suffix(".transcript.json").exists()
    assert library.user_behaviors() == ["explore_for_goal"]
    assert "explore_for_goal" in library.names() and "explore_until_goal" in library.names()
    with pytest.raises(BehaviorSpecError, match="exists already"):
        save(result, library)
    shipped = result.compiled.spec.model_copy(update={"name": "explore_until_goal"})
    with pytest.raises(BehaviorSpecError, match="shipped behavior"):
        library.save(shipped)


def test_a_behavior_already_in_the_library_is_not_asked_for(library):
    backend = ScriptedBackend([])
    result = synthesize(ENV, "anything", backend, library, name="explore_until_goal")
    assert result.from_library and backend.requests == []


def test_reply_reusing_a_library_name_is_sent_back(library):
    taken = reply(name="explore_until_goal")
    result = synthesize(ENV, "x", ScriptedBackend([taken, reply()]), library)
    assert result.rounds == 2 and "already in the behavior library" in \
        result.transcript["rounds"][0]["error"]


def test_dry_run_catches_runtime_errors(library):
    broken = json.loads(reply())
    broken["edges"][0]["param"] = "explored()[50]"
    with pytest.raises(SynthesisError, match="dry-run") as err:
        synthesize(ENV, "x", ScriptedBackend([json.dumps(broken)]), library, max_rounds=1)
    assert "IndexError" in err.value.transcript["rounds"][0]["error"]


def test_prompt_is_generated_from_the_environment(library):
    context = PromptContext.build(gym.make(ENV), library, ("explore_until_goal",))
    system, *turns = build_messages("do things", context, info="Cells are 1 m wide.")
    user = "\n".join(turn["content"] for turn in turns)
    env = gym.make(ENV).unwrapped
    for name, primitive in env.primitives.items():
        assert f"- {name}: {primitive.description}" in user
    for helper in env.make_helpers().functions():
        assert f"- {helper}(" in user
    assert "explore_until_goal (the user asks you to build on it)" in user
    assert "Cells are 1 m wide." in turns[-1]["content"] and "argmax" in system["content"]
    assert request_schema(context)["properties"]["env"] == {"const": ENV}
    with pytest.raises(BehaviorSpecError, match="unknown behavior"):
        PromptContext.build(gym.make(ENV), library, ("nope",))


# -- the paper's two prompts --------------------------------------------------------------------

def traces(behavior: str, seeds) -> list[list[list[int]]]:
    env = RobustnessWrapper(gym.make(ENV))
    policy = load_behavior(behavior, env)
    out = []
    for seed in seeds:
        obs, _ = env.reset(seed=seed)
        policy.reset()
        actions = []
        while (action := policy.predict(obs)[0]) is not None:
            actions.append(action.tolist())
            obs, *_ = env.step(action)
        out.append(actions)
    return out


def test_paper_prompts_give_the_shipped_behaviors_and_the_paper_result(library, capsys):
    assert main(["synthesize", ENV, PAPER_PROMPT_1, "--scripted", str(REPLIES_1)]) == 0
    assert main(["synthesize", ENV, PAPER_PROMPT_2, "--uses", "explore_for_goal",
                 "--scripted", str(REPLIES_2), "--verify", "100", "--epsilon", "0.05"]) == 0
    out = capsys.readouterr().out
    assert "goal_and_back: valid after 2 round(s)" in out
    assert "successes 100/100" in out and "confidence 0.99407" in out
    seeds = range(25)
    assert traces("explore_for_goal", seeds) == traces("explore_until_goal", seeds)
    assert traces("goal_and_back", seeds) == traces("find_goal_and_oscillate", seeds)
    report = run_campaign(CampaignConfig(ENV, "goal_and_back", 200, seed=1))
    assert report["failures"] == 0


def test_transcript_replays_offline(library, tmp_path, capsys):
    out = tmp_path / "b1.json"
    assert main(["synthesize", ENV, PAPER_PROMPT_1, "--scripted", str(REPLIES_1),
                 "--out", str(out)]) == 0
    transcript = out.with_suffix(".transcript.json")
    backend = TranscriptBackend.from_file(transcript)
    again = synthesize(ENV, PAPER_PROMPT_1, backend, library, name="replayed")
    assert again.compiled.spec.nodes == load_behavior(str(out), gym.make(ENV)).behavior.spec.nodes


def test_cli_synthesize_usage_errors(capsys, tmp_path):
    assert main(["synthesize", ENV, "x"]) == 2
    assert "give exactly one language model" in capsys.readouterr().err
    assert main(["synthesize", ENV, "x", "--base-url", "ftp://x", "--model", "m"]) == 2
    assert "must start with http" in capsys.readouterr().err
    bad = tmp_path / "replies.json"
    bad.write_text('["{}"]')
    assert main(["synthesize", ENV, "x", "--scripted", str(bad), "--max-rounds", "1",
                 "--out", str(tmp_path / "o.json")]) == 1
    err = capsys.readouterr().err
    assert "no valid behavior after 1 round" in err
    assert (tmp_path / "o.failed.transcript.json").exists() and not (tmp_path / "o.json").exists()


def test_a_failed_rerun_names_the_real_cause_and_keeps_the_library_clean(library, capsys):
    """Re-running the README's example: the name is taken; that is the error shown, not only
    that the scripted replies ran out, and the failed transcript goes to failed/."""
    args = ["synthesize", ENV, PAPER_PROMPT_1, "--scripted", str(REPLIES_1)]
    assert main(args) == 0
    capsys.readouterr()
    assert main(args) == 1
    err = capsys.readouterr().err
    assert err.startswith("vlb synthesize: error: reply 1: name: 'explore_for_goal' is already "
                          "in the behavior library")
    assert "then the language model failed" in err
    assert sorted(p.name for p in library.directory.glob("*.json")) == [
        "explore_for_goal.json", "explore_for_goal.transcript.json"]
    assert len(list((library.directory / "failed").glob("*.transcript.json"))) == 1
