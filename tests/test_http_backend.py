"""The language-model backends against servers and files that misbehave: the HTTP client over real
HTTP on 127.0.0.1 (redirects, trickling, huge or endless replies, errors that must or must not be
retried), and the scripted and transcript backends against files that are not what they claim."""

from __future__ import annotations

import gzip
import json
import os
import re
from pathlib import Path

import pytest

from vlb_gym.abstractor.backends import ModelError, ScriptedBackend, TranscriptBackend
from vlb_gym.abstractor.dialects import request_rejected
from vlb_gym.abstractor.served import OpenAICompatibleBackend
from vlb_gym.core.files import MAX_FILE_BYTES

from .chat_server import LLAMA_CPP_VALIDATION_500, ChatServer

pytestmark = pytest.mark.timeout(30)

MESSAGES = [{"role": "user", "content": "hi"}]

def backend(server: ChatServer, **kwargs) -> OpenAICompatibleBackend:
    kwargs.setdefault("timeout", 5.0)
    kwargs.setdefault("backoff", 0.01)
    return OpenAICompatibleBackend(server.url, "test-model", **kwargs)


# -- redirects: the request and its key go to the configured origin only -------------------------

def test_redirect_to_another_origin_is_not_followed_and_the_key_stays_home(monkeypatch):
    monkeypatch.setenv("TEST_KEY", "sk-secret")
    with ChatServer([("reply", "stolen")]) as other:
        with ChatServer([("redirect", other.url + "/chat/completions")] * 4) as server:
            with pytest.raises(ModelError) as err:
                backend(server, api_key_env="TEST_KEY", max_retries=3).complete(MESSAGES)
    assert other.headers == []  # the other origin got no request at all, so never the key
    assert len(server.headers) == 1  # not retried
    assert server.headers[0]["Authorization"] == "Bearer sk-secret"
    message = str(err.value)
    assert f"HTTP 302 redirect to {other.origin} not followed" in message
    assert "sk-secret" not in message


@pytest.mark.parametrize("dialect", ["auto", "ollama"])
def test_probes_and_native_calls_follow_no_redirect_either(dialect, monkeypatch):
    monkeypatch.setenv("TEST_KEY", "sk-secret")
    with ChatServer([("reply", "stolen")]) as other:
        with ChatServer([("redirect", other.url + "/chat/completions")] * 4) as server:
            chat = backend(server, api_key_env="TEST_KEY", max_retries=3,
                           structured_output=dialect)
            with pytest.raises(ModelError) as err:
                chat.complete(MESSAGES)
    assert other.headers == [] and len(server.headers) == 1
    assert server.paths == ["/api/chat" if dialect == "ollama" else "/v1/chat/completions"]
    assert "not followed" in str(err.value) and "sk-secret" not in str(err.value)


def test_redirect_within_the_origin_is_not_followed_either():
    with ChatServer([("redirect", "/elsewhere"), ("reply", "never")]) as server:
        with pytest.raises(ModelError, match=f"redirect to {server.origin} not followed"):
            backend(server, max_retries=2).complete(MESSAGES)
    assert len(server.headers) == 1


# -- timeout: a total deadline per attempt -------------------------------------------------------

def test_a_server_trickling_its_body_cannot_outlast_the_timeout():
    with ChatServer([("drip", 0.1, 100)] * 2) as server:  # 10 s per reply
        with pytest.raises(ModelError,
                           match=r"after 2 attempt\(s\); last: timed out after 1 s"):
            backend(server, timeout=1.0, max_retries=1).complete(MESSAGES)
    assert len(server.headers) == 2
    assert len(server.sent) == 2 and max(server.sent) < 100  # the client hung up each time


def test_a_server_trickling_its_headers_cannot_outlast_the_timeout():
    with ChatServer([("drip_headers", 0.1, 100)]) as server:  # 10 s of headers
        with pytest.raises(ModelError, match="timed out after 1 s"):
            backend(server, timeout=1.0, max_retries=0).complete(MESSAGES)
    assert server.sent == [server.sent[0]] and server.sent[0] < 100  # hung up mid-headers


# -- size: replies are capped --------------------------------------------------------------------

def test_an_endless_body_fails_at_the_size_cap_and_is_not_retried():
    with ChatServer([("endless",)] * 3) as server:
        with pytest.raises(ModelError, match="larger than the limit of 2000000 bytes"):
            backend(server, max_retries=2).complete(MESSAGES)
    assert len(server.headers) == 1


def test_a_huge_reply_is_not_read_whole():
    size = 50_000_000
    with ChatServer([("huge", size)]) as server:
        with pytest.raises(ModelError, match="larger than the limit of 100000 bytes"):
            backend(server, max_reply_bytes=100_000).complete(MESSAGES)
    assert server.sent[0] < size // 2  # the client hung up long before the end


def test_the_reply_text_returned_is_capped():
    with ChatServer([("reply", "y" * 5000)]) as server:
        text = backend(server, max_reply_chars=1000).complete(MESSAGES)
    assert text.startswith("y" * 1000) and not text.startswith("y" * 1001)
    assert len(text) < 1100 and "the reply has 5000 characters" in text


def test_a_compressed_reply_is_refused():
    completion = {"choices": [{"message": {"role": "assistant", "content": "ok"}}]}
    body = gzip.compress(json.dumps(completion).encode())
    with ChatServer([("raw", body, {"Content-Encoding": "gzip"})]) as server:
        with pytest.raises(ModelError, match=r"compressed \(gzip\)"):
            backend(server).complete(MESSAGES)
    assert server.headers[0]["Accept-Encoding"] == "identity"


# -- what is retried and what fails at once ------------------------------------------------------

@pytest.mark.parametrize("status", [400, 401, 403, 404, 422])
def test_requests_the_server_rejects_fail_at_once_with_its_message(status):
    error = b'{"error": {"message": "no such model: test-model", "type": "invalid_request"}}'
    with ChatServer([("status", status, error), ("reply", "never")]) as server:
        with pytest.raises(ModelError, match=f"/chat/completions: HTTP {status}: "
                                               f"no such model: test-model$"):
            backend(server, max_retries=3).complete(MESSAGES)
    assert len(server.headers) == 1


def test_a_500_that_is_a_validation_error_fails_at_once_with_its_message():
    with ChatServer([("status", 500, LLAMA_CPP_VALIDATION_500), ("reply", "never")]) as server:
        with pytest.raises(ModelError) as err:
            backend(server, max_retries=3).complete(MESSAGES)
    assert len(server.headers) == 1
    assert "HTTP 500: [{'type': 'literal_error', 'loc': ('body', 'response_format', 'type')" \
        in str(err.value)
    assert "Input should be 'text' or 'json_object'" in str(err.value)


def test_server_messages_are_cut_to_one_short_line():
    with ChatServer([("status", 400, b"first line\n" + b"z" * 10_000)]) as server:
        with pytest.raises(ModelError) as err:
            backend(server).complete(MESSAGES)
    message = str(err.value)
    assert "HTTP 400: first line zzz" in message and message.endswith("z...")
    assert "\n" not in message and len(message) < len(server.url) + 350


@pytest.mark.parametrize("status, body", [(408, b""), (409, b""), (429, b"slow down"),
                                          (500, b'{"error": "CUDA out of memory"}'),
                                          (502, b"bad gateway"), (503, b""), (504, b"")])
def test_transient_errors_are_retried_with_growing_backoff(status, body, monkeypatch):
    from vlb_gym.abstractor import served

    waits: list[float] = []
    monkeypatch.setattr(served.time, "sleep", waits.append)  # the backoff, recorded
    with ChatServer([("status", status, body)] * 2 + [("reply", "ok")]) as server:
        assert backend(server, max_retries=2, backoff=0.2).complete(MESSAGES) == "ok"
    assert len(server.headers) == 3
    assert len(waits) == 2 and 0.2 <= waits[0] <= 0.25 and 0.4 <= waits[1] <= 0.5  # + jitter


@pytest.mark.parametrize("status, body, rejected", [
    (400, "", True), (404, "not found", True), (422, '{"detail": []}', True),
    (408, "", False), (409, "", False), (429, "", False),
    (500, LLAMA_CPP_VALIDATION_500.decode(), True),
    (500, '{"detail": [{"loc": ["body", "messages"], "msg": "field required"}]}', True),
    (500, "Internal Server Error", False), (502, "validation", False), (503, "", False)])
def test_request_rejected(status, body, rejected):
    assert request_rejected(status, body) is rejected


# -- the API key and the base URL ----------------------------------------------------------------

@pytest.mark.parametrize("key, echoed, shown", [
    ("sk-secret", "invalid key: Bearer sk-secret", "invalid key: Bearer [API key]"),
    ("sk-Secret", "INVALID KEY: BEARER SK-SECRET", "INVALID KEY: BEARER [API key]"),  # any case
])
def test_the_api_key_never_shows_in_errors_or_the_name(monkeypatch, key, echoed, shown):
    monkeypatch.setenv("TEST_KEY", key)
    echo = json.dumps({"error": {"message": echoed}}).encode()
    with ChatServer([("status", 401, echo)]) as server:
        chat = backend(server, api_key_env="TEST_KEY")
        with pytest.raises(ModelError) as err:
            chat.complete(MESSAGES)
    assert shown in str(err.value)
    assert key.lower() not in str(err.value).lower() and key not in chat.name


def test_a_reply_that_echoes_the_api_key_is_returned_without_it(monkeypatch):
    """A server that echoes the Authorization header into its reply: the key would be saved in
    the behavior and the transcript."""
    monkeypatch.setenv("TEST_KEY", "sk-secret")
    with ChatServer([("reply", '{"name": "x", "note": "Bearer sk-secret"}')]) as server:
        chat = backend(server, api_key_env="TEST_KEY")
        reply = chat.complete(MESSAGES)
    assert "sk-secret" not in reply and "Bearer [API key]" in reply


@pytest.mark.parametrize("url, problem", [
    ("http://user:sk-secret@127.0.0.1:8000/v1", "must not carry credentials"),
    ("ftp://127.0.0.1/v1", "must start with http:// or https://"),
    ("file:///etc/passwd", "must start with http:// or https://"),
    ("http://", "name a host"),
    ("http://[::1/v1", "not a valid URL")])
def test_bad_base_urls_are_refused(url, problem):
    with pytest.raises(ValueError, match=problem) as err:
        OpenAICompatibleBackend(url, "m")
    assert "sk-secret" not in str(err.value)


# -- scripted replies and transcripts come from files that may be anything -----------------------

def bad_file(kind: str, tmp_path: Path) -> tuple[Path, str]:
    """A file of the given kind of wrong, and what the error should say about it (a regex)."""
    path = tmp_path / f"{kind}.json"
    if kind == "missing":
        return path, "No such file or directory"
    if kind == "directory":
        return tmp_path, "not a regular file|Is a directory"
    if kind == "device":
        return Path("/dev/null"), "not a regular file"
    if kind == "fifo":
        os.mkfifo(path)  # reading it the plain way would block for ever
        return path, "not a regular file"
    if kind == "oversized":
        path.write_text(json.dumps(["x" * MAX_FILE_BYTES]))
        return path, f"the limit is {MAX_FILE_BYTES}$"
    if kind == "bad JSON":
        path.write_text('["unterminated')
        return path, "not valid JSON: Unterminated string"
    assert kind == "deep JSON"
    path.write_text("[" * 100_000 + "]" * 100_000)
    return path, "nested deeper than"


@pytest.mark.parametrize("loader", [ScriptedBackend, TranscriptBackend])
@pytest.mark.parametrize("kind", ["missing", "directory", "device", "fifo", "oversized",
                                  "bad JSON", "deep JSON"])
def test_unusable_reply_files_fail_with_one_line_naming_the_file(loader, kind, tmp_path):
    path, reason = bad_file(kind, tmp_path)
    with pytest.raises(ModelError) as err:
        loader.from_file(path)
    message = str(err.value)
    assert message.startswith(f"{path}: ") and re.search(reason, message) and "\n" not in message


@pytest.mark.parametrize("loader, text, problem", [
    (ScriptedBackend, "{}", "expected a non-empty JSON list of replies"),
    (ScriptedBackend, "[]", "expected a non-empty JSON list of replies"),
    (TranscriptBackend, "[]", "not a vlb synthesize transcript"),
    (TranscriptBackend, '{"rounds": [{"round": 1}]}', "not a vlb synthesize transcript")])
def test_reply_files_of_the_wrong_shape_fail_clearly(loader, text, problem, tmp_path):
    path = tmp_path / "replies.json"
    path.write_text(text)
    with pytest.raises(ModelError, match=f"^{path}: {problem}"):
        loader.from_file(path)
