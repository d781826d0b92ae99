"""Structured output in each server's dialect, and ``--structured-output auto``, against a real
HTTP server on 127.0.0.1 that answers as OpenAI, llama-cpp-python, an older vLLM, Ollama, a
JSON-mode-only and a plain server do; and the grammar-friendly request schema."""

from __future__ import annotations

import json
import socket
from pathlib import Path

import gymnasium as gym
import pytest

from vlb_gym.abstractor.backends import ModelError
from vlb_gym.abstractor.dialects import AUTO_ORDER, probe_reply_ok, shape_rejected
from vlb_gym.abstractor.served import OpenAICompatibleBackend
from vlb_gym.abstractor.grammar import MAX_GRAPH_ITEMS, MAX_STRING_LENGTH, grammar_schema
from vlb_gym.abstractor.paper import PAPER, PROMPTS
from vlb_gym.abstractor.validate import validate_reply
from vlb_gym.cli import main
from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.core.spec import BehaviorSpecError

from .chat_server import LLAMA_CPP_VALIDATION_500, ChatServer

pytestmark = pytest.mark.timeout(60)

ENV = "VLB-GridExplore-v0"
PROMPT = PROMPTS["behavior1"]


def in_full(doc: dict) -> dict:
    """A behavior document as a constrained decoder writes it: ``variables`` and ``functions``
    present (empty when unused); the validator takes either form."""
    return {"variables": {}, "functions": {}, **doc}


REPLY = json.dumps(in_full(json.loads((PAPER / "behavior1.replies.json").read_text())[0]))
BEHAVIORS = Path(__file__).resolve().parent.parent / "vlb_gym" / "behaviors"

# server mode -> the dialect auto must choose, after how many rejected or ignored probes
AUTO = {"openai": "openai", "llamacpp": "llamacpp", "vllm": "vllm", "ollama": "ollama",
        "json_mode": "json_object", "text": "none"}


def synthesize(server: ChatServer, tmp_path: Path, mode: str, *extra: str,
               base_url: str | None = None) -> int:
    return main(["synthesize", ENV, PROMPT, "--base-url", base_url or server.url, "--model", "m",
                 "--structured-output", mode, "--out", str(tmp_path / "b.json"), *extra])


@pytest.mark.parametrize("server_mode", list(AUTO))
def test_auto_finds_the_dialect_with_one_probe_per_passed_over_dialect(server_mode, tmp_path,
                                                                      capsys):
    chosen = AUTO[server_mode]
    with ChatServer([("reply", REPLY)], dialect=server_mode) as server:
        assert synthesize(server, tmp_path, "auto") == 0  # --retries 3, the default
    passed_over = list(AUTO_ORDER[:AUTO_ORDER.index(chosen)])
    assert server.shapes == passed_over + [chosen, "behavior"]  # none sent twice, no backoff
    behavior_request = server.requests[-1]
    assert "connection test" not in json.dumps(behavior_request["messages"])
    err = capsys.readouterr().err
    assert err.count("structured output:") == 1
    assert f"vlb synthesize: structured output: {chosen} (" in err
    transcript = json.loads((tmp_path / "b.transcript.json").read_text())
    assert transcript["structured_output"] == chosen
    assert [p["dialect"] for p in transcript["structured_output_probe"]] == passed_over + [chosen]
    assert json.loads((tmp_path / "b.json").read_text())["name"] == "explore_for_goal"


def test_auto_says_which_it_uses_as_documented(tmp_path, capsys):
    with ChatServer([("reply", REPLY)], dialect="llamacpp") as server:
        assert synthesize(server, tmp_path, "auto") == 0
    assert "vlb synthesize: structured output: llamacpp (json_object + schema)\n" in \
        capsys.readouterr().err
    assert server.requests[0]["response_format"]["type"] == "json_schema"
    assert server.requests[0]["max_tokens"] <= 256  # a small probe
    transcript = json.loads((tmp_path / "b.transcript.json").read_text())
    assert "Input should be 'text' or 'json_object'" in \
        transcript["structured_output_probe"][0]["outcome"]


@pytest.mark.parametrize("server_mode, dialect", [
    ("openai", "openai"), ("openai", "json_schema"), ("llamacpp", "llamacpp"),
    ("vllm", "vllm"), ("ollama", "ollama"), ("json_mode", "json_object"), ("text", "none")])
def test_each_dialect_by_name_sends_its_shape_and_no_probe(server_mode, dialect, tmp_path,
                                                          capsys):
    with ChatServer([("reply", REPLY)], dialect=server_mode) as server:
        assert synthesize(server, tmp_path, dialect) == 0
    assert server.shapes == ["behavior"] and "structured output:" not in capsys.readouterr().err
    body = server.requests[0]
    schema = {"openai": lambda: body["response_format"]["json_schema"]["schema"],
              "json_schema": lambda: body["response_format"]["json_schema"]["schema"],
              "llamacpp": lambda: body["response_format"]["schema"],
              "vllm": lambda: body["guided_json"], "ollama": lambda: body["format"],
              "json_object": lambda: None, "none": lambda: None}[dialect]()
    if schema is not None:  # the grammar-friendly request schema, enums for this request
        assert schema["$defs"]["Node"]["anyOf"][0]["properties"]["primitive"]["enum"] == \
            ["navigate", "sense"]
    assert json.loads((tmp_path / "b.transcript.json").read_text())["structured_output"] == \
        {"json_schema": "openai"}.get(dialect, dialect)


def test_ollama_is_called_natively(tmp_path):
    with ChatServer([("reply", REPLY)] * 2, dialect="ollama") as server:
        assert synthesize(server, tmp_path, "ollama", base_url=server.url + "/") == 0
        assert synthesize(server, tmp_path, "ollama", "--force", base_url=server.origin) == 0
    assert server.paths == ["/api/chat", "/api/chat"]  # a trailing /v1 (or none) either way
    body = server.requests[0]
    assert body["stream"] is False and body["model"] == "m" and "messages" in body
    assert body["options"]["temperature"] == 0 and body["options"]["num_ctx"] >= 8192
    assert "response_format" not in body


def test_a_rejected_dialect_by_name_fails_at_once(tmp_path, capsys):
    with ChatServer([("reply", REPLY)], dialect="llamacpp") as server:
        assert synthesize(server, tmp_path, "openai") == 1  # --retries 3
    assert len(server.requests) == 1
    assert "HTTP 500: [{'type': 'literal_error'" in capsys.readouterr().err


# -- what the probe does when the server fails --------------------------------------------------

def closed_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def test_a_transport_failure_while_probing_is_a_one_line_error(tmp_path, capsys):
    url = f"http://127.0.0.1:{closed_port()}/v1"
    assert main(["synthesize", ENV, PROMPT, "--base-url", url, "--model", "m",
                 "--structured-output", "auto", "--retries", "0"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("vlb synthesize: error: structured output probe (openai): ")
    assert "cannot connect" in err and err.count("\n") == 1


def test_a_probe_that_times_out_is_an_error_not_a_fallback(capsys):
    with ChatServer([("sleep", 1, "late")]) as server:
        assert main(["synthesize", ENV, PROMPT, "--base-url", server.url, "--model", "m",
                     "--structured-output", "auto", "--retries", "0",
                     "--timeout", "0.3"]) == 2
    assert len(server.requests) == 1
    assert "structured output probe (openai): " in capsys.readouterr().err


@pytest.mark.parametrize("status", [401, 403, 429])
def test_errors_that_say_nothing_of_the_shape_end_the_probe(status, capsys):
    error = b'{"error": {"message": "no"}}'
    with ChatServer([("status", status, error)] * 4) as server:
        assert main(["synthesize", ENV, PROMPT, "--base-url", server.url, "--model", "m",
                     "--structured-output", "auto", "--retries", "0"]) == 2
    assert len(server.requests) == 1
    assert f"structured output probe (openai): {server.url}/chat/completions: HTTP {status}" in \
        capsys.readouterr().err


def test_a_404_tries_the_native_api_and_then_ends_the_probe(capsys):
    error = b'{"error": {"message": "no"}}'
    with ChatServer([("status", 404, error)] * 4) as server:
        assert main(["synthesize", ENV, PROMPT, "--base-url", server.url, "--model", "m",
                     "--structured-output", "auto", "--retries", "0"]) == 2
    assert server.paths == ["/v1/chat/completions", "/api/chat"]
    assert "rejected every request shape" in capsys.readouterr().err


def test_a_server_rejecting_every_shape_is_an_error(capsys):
    with ChatServer([("status", 400, b'{"error": "no"}')] * 6) as server:
        assert main(["synthesize", ENV, PROMPT, "--base-url", server.url, "--model", "m",
                     "--structured-output", "auto"]) == 2
    assert len(server.requests) == len(AUTO_ORDER)
    assert "rejected every request shape" in capsys.readouterr().err


def test_the_probe_happens_once_per_backend():
    with ChatServer([("reply", "first"), ("reply", "second")], dialect="vllm") as server:
        chat = OpenAICompatibleBackend(server.url, "m", structured_output="auto", timeout=5)
        assert chat.dialect is None
        assert chat.complete([{"role": "user", "content": "a"}]) == "first"
        assert chat.complete([{"role": "user", "content": "b"}]) == "second"
    assert server.shapes == ["openai", "llamacpp", "vllm", "behavior", "behavior"]
    assert chat.dialect == "vllm"


@pytest.mark.parametrize("status, body, dialect, rejected", [
    (400, "", "openai", True), (422, "", "vllm", True),
    (500, LLAMA_CPP_VALIDATION_500.decode(), "openai", True),
    (500, "Internal Server Error", "openai", False), (401, "", "openai", False),
    (404, "", "openai", False), (404, "", "ollama", True), (405, "", "ollama", True),
    (429, "", "openai", False), (503, "", "openai", False)])
def test_shape_rejected(status, body, dialect, rejected):
    assert shape_rejected(status, body, dialect) is rejected


@pytest.mark.parametrize("reply, dialect, ok", [
    ('{"ok": true, "probe": "vlb"}', "openai", True), ('{"ok": true}', "openai", False),
    ('Sure! {"ok": true}', "vllm", False), ('{"ok": true}', "json_object", True),
    ("[1]", "json_object", False), ("Sure!", "none", True)])
def test_probe_reply_ok(reply, dialect, ok):
    assert probe_reply_ok(reply, dialect) is ok


def test_unknown_dialects_are_refused():
    with pytest.raises(ValueError, match="structured_output must be auto, openai"):
        OpenAICompatibleBackend("http://127.0.0.1:1/v1", "m", structured_output="grammar")
    with pytest.raises(ModelError):  # nothing listens there
        OpenAICompatibleBackend(f"http://127.0.0.1:{closed_port()}/v1", "m",
                                structured_output="auto", max_retries=0).probe()


# -- the request schema -------------------------------------------------------------------------

def walk(schema):
    yield schema
    for value in schema.values() if isinstance(schema, dict) else schema \
            if isinstance(schema, list) else ():
        yield from walk(value)


def documents():
    """(env, document, valid for the validator) of every shipped behavior and paper reply."""
    for path in sorted(BEHAVIORS.glob("*.json")):
        doc = in_full(json.loads(path.read_text()))
        yield doc["env"], doc, True
    for path in sorted(PAPER.glob("*.replies.json")):
        for doc in json.loads(path.read_text()):
            yield doc["env"], in_full(doc), None  # None: ask the validator


LIBRARY = ["explore_until_goal", "find_goal_and_oscillate", "scoop_repeatedly",
           "explore_for_goal"]  # the last one: the paper's first synthesis, used by the second


def test_the_request_schema_is_grammar_friendly():
    jsonschema = pytest.importorskip("jsonschema")
    for env_id in ("VLB-GridExplore-v0", "VLB-Scoop-v0"):
        schema = grammar_schema(env_id, gym.make(env_id).unwrapped.primitives, LIBRARY)
        jsonschema.Draft202012Validator.check_schema(schema)
        assert schema["required"] == ["name", "description", "env", "variables", "functions",
                                      "nodes", "edges", "start", "terminals"]
        assert schema["properties"]["env"] == {"const": env_id}
        for part in walk(schema):
            if not isinstance(part, dict):
                continue
            assert part.get("maxLength", 0) <= MAX_STRING_LENGTH
            assert part.get("maxItems", 0) <= MAX_GRAPH_ITEMS and "maxProperties" not in part
            assert "patternProperties" not in part and "propertyNames" not in part
            if "properties" in part:
                assert part["additionalProperties"] is False
        primitives = sorted(gym.make(env_id).unwrapped.primitives)
        assert schema["$defs"]["Node"]["anyOf"][0]["properties"]["primitive"]["enum"] == \
            primitives


def test_shipped_behaviors_and_paper_replies_meet_the_request_schema(user_library):
    jsonschema = pytest.importorskip("jsonschema")
    library = BehaviorLibrary()
    checked = 0
    for env_id, doc, valid in documents():
        env = gym.make(env_id)
        if valid is None:  # a paper reply: the repair round's first reply is wrong on purpose
            try:
                compiled = validate_reply(json.dumps(doc), env, library, doc["name"])
            except BehaviorSpecError:
                valid = False
            else:
                valid = True
                if compiled.name not in library:  # the second prompt builds on the first
                    library.save(compiled.spec)
        graph = {k: v for k, v in doc.items() if k != "promise"}  # promises are asked apart
        schema = grammar_schema(env_id, env.unwrapped.primitives, LIBRARY)
        errors = list(jsonschema.Draft202012Validator(schema).iter_errors(graph))
        assert (not errors) is bool(valid), (doc["name"], [e.message for e in errors])
        checked += 1
    assert checked >= 6


def test_the_schema_goes_with_the_request_and_the_compact_prompt_shows_an_example(tmp_path):
    with ChatServer([("reply", REPLY)], dialect="openai") as server:
        assert synthesize(server, tmp_path, "openai") == 0
    body = server.requests[0]
    prompt = "\n".join(m["content"] for m in body["messages"])
    assert body["response_format"]["json_schema"]["schema"]["properties"]["nodes"]
    assert [m["role"] for m in body["messages"]] == ["system", "user", "assistant", "user"]
    assert json.loads(body["messages"][2]["content"])["nodes"] and '"$defs"' not in prompt
    assert '"maxLength": 2000' not in prompt


# -- served models on the same footing as the local one ------------------------------------------

def test_auto_against_ollama_without_v1_finds_its_native_api(tmp_path, capsys):
    with ChatServer([("reply", REPLY)], dialect="ollama") as server:
        assert synthesize(server, tmp_path, "auto", base_url=server.origin) == 0
    assert server.paths == ["/chat/completions", "/api/chat", "/api/chat"]
    assert "vlb synthesize: structured output: ollama (" in capsys.readouterr().err
    probe = json.loads((tmp_path / "b.transcript.json").read_text())["structured_output_probe"]
    assert probe[0]["outcome"].startswith("no endpoint:") and probe[1]["outcome"] == "used"


def test_an_empty_probe_reply_is_named_not_taken_for_no_structured_output(tmp_path, capsys):
    with ChatServer([("reply", "")]) as server:
        assert synthesize(server, tmp_path, "auto") == 2
    err = capsys.readouterr().err
    assert "the model replied nothing within 256 tokens" in err and len(server.requests) == 1


def test_a_server_gets_temperature_seed_and_token_limit_and_redraws_a_repeat(tmp_path):
    with ChatServer([("reply", "A"), ("reply", "B")]) as server:
        backend = OpenAICompatibleBackend(server.url, "m", structured_output="none",
                                          temperature=0.2, seed=7, max_tokens=99)
        messages = [{"role": "user", "content": "x"}, {"role": "assistant", "content": "A"},
                    {"role": "user", "content": "again"}]
        assert backend.complete(messages) == "B"  # "A" repeats an earlier turn: drawn again
    first, second = server.requests
    assert (first["temperature"], first["seed"], first["max_tokens"]) == (0.2, 7, 99)
    assert (second["temperature"], second["seed"], second["max_tokens"]) == (0.7, 8, 99)


def test_cli_sampling_options_reach_the_server(tmp_path):
    with ChatServer([("reply", REPLY)], dialect="openai") as server:
        assert synthesize(server, tmp_path, "openai", "--temperature", "0.4",
                          "--sampling-seed", "3", "--max-tokens", "700") == 0
    body = server.requests[0]
    assert (body["temperature"], body["seed"], body["max_tokens"]) == (0.4, 3, 700)
