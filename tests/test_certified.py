"""Certified synthesis, intent first: promise drafts, the search, certification on fresh seeds."""

from __future__ import annotations

import json
import subprocess
import sys

from pathlib import Path

import gymnasium as gym
import pytest

from vlb_gym import BehaviorSpecError
from vlb_gym.abstractor.backends import ScriptedBackend, TranscriptBackend
from vlb_gym.abstractor.certified import synthesize_certified
from vlb_gym.abstractor.intent import bank, draft_promise, nearest, parse_promise
from vlb_gym.abstractor.search import (CERTIFY_SEED, SCREEN_SEED, Screen, certification_episodes,
                                       find, procedure_confidence, search)
from vlb_gym.abstractor.sketches import GRID, candidates, numbers
from vlb_gym.core.spec import Promise, spec_from_data
from vlb_gym.verify.campaign import episode_seed

ROOT = Path(__file__).resolve().parent.parent
GRID_ID = "VLB-GridExplore-v0"
HOME = Promise(expr="goal_found() and len(moves()) > 0 and final_cell() == start_cell()",
               description="a goal is known and the agent moved, then ended where it began")
REQUEST = "Search the grid until you know where a goal is, then come back to where you began."


def reply(promise: Promise) -> str:
    return json.dumps({"description": promise.description, "expr": promise.expr})


@pytest.fixture(scope="module")
def interface():
    env = gym.make(GRID_ID)
    yield env.unwrapped
    env.close()


@pytest.mark.parametrize("epsilon, delta, attempts", [(0.05, 0.01, 3), (0.05, 0.01, 1),
                                                      (0.1, 0.05, 2), (0.01, 0.001, 5)])
def test_certification_size_is_the_least_that_bounds_the_union(epsilon, delta, attempts):
    n = certification_episodes(epsilon, delta, attempts)
    assert attempts * (1 - epsilon) ** n <= delta < attempts * (1 - epsilon) ** (n - 1)
    assert procedure_confidence(epsilon, delta, attempts) == pytest.approx(
        1 - attempts * (1 - epsilon) ** n) and procedure_confidence(epsilon, delta,
                                                                    attempts) >= 1 - delta
    assert certification_episodes() == 112  # the README's figure


def test_numbers_read_digits_and_words():
    assert numbers("make 3 round trips", "twice, then five times", "0 or 1000") == [2, 3, 5]


def test_the_space_is_smallest_first_and_structurally_distinct():
    space = list(candidates(GRID, GRID_ID, "x", "y", [2]))
    sizes = [c.phases for c in space]
    assert sizes == sorted(sizes) and sizes[0] == 1 and max(sizes) == 3
    assert len({c.key for c in space}) == len(space)
    for candidate in space[:40]:  # every document is a valid behavior file
        spec_from_data(candidate.document, candidate.label)


def test_search_finds_the_smallest_behavior_and_certifies_it_on_fresh_seeds():
    result = search(GRID_ID, REQUEST, HOME, time_limit=120)
    assert result.candidate.label == "explore until a goal is found -> go to the start"
    certification = result.certification
    assert certification.seed == CERTIFY_SEED and certification.passed
    assert len(certification.episodes) == certification_episodes()
    screening = {episode_seed(SCREEN_SEED, i) for i in range(30)}
    assert not screening & {e.seed for e in certification.episodes}
    assert result.confidence == pytest.approx(1 - 3 * 0.95 ** 112)
    assert result.failures and result.failures[0][0] == "sense here"
    assert "promise of synthesized failed" in result.failures[0][1]


def test_a_promise_no_candidate_keeps_is_not_certified():
    screen = Screen(GRID_ID)
    impossible = Promise(expr="len(primitives()) == 0", description="")  # every node runs one
    result = find(GRID_ID, "do nothing", impossible, screen, max_candidates=60)
    screen.close()
    assert result.candidate is None and result.tried == 60


def test_the_bank_holds_no_evaluation_task():
    sys.path.insert(0, str(ROOT))
    from benchmarks.synthesis_tasks import TASKS

    examples = bank(GRID_ID)
    assert len(examples) >= 10
    requests = {e.request.lower() for e in examples}
    for task in TASKS:
        assert task.description.lower() not in requests
        words = set(task.description.lower().split())
        for request in requests:  # no rewording: most of the words differ
            overlap = len(words & set(request.split())) / len(words | set(request.split()))
            assert overlap < 0.6, (task.name, request)


def test_nearest_examples_come_nearest_last_and_skip_moves_on():
    examples = bank(GRID_ID)
    shown = nearest("go back to the start after finding a goal", examples, k=3)
    assert len(shown) == 3 and len({e.request for e in shown}) == 3
    assert nearest("x", examples, k=3, skip=1) != nearest("x", examples, k=3, skip=0) or \
        len(examples) <= 3
    assert nearest("anything", [], k=3) == []


@pytest.mark.parametrize("text, layer", [("not json", "json"), ('{"expr": 3}', "schema"),
                                         ('{"description": "d", "expr": "seen > 1"}',
                                          "expressions"),
                                         ('{"description": "d", "expr": "True"}',
                                          "expressions")])
def test_a_bad_promise_reply_is_refused_with_its_layer(interface, text, layer):
    with pytest.raises(BehaviorSpecError) as err:
        parse_promise(text, interface)
    assert err.value.layer == layer


def test_a_reply_that_would_write_to_the_terminal_is_refused_in_one_line(interface):
    with pytest.raises(BehaviorSpecError) as err:
        parse_promise('{"description": "\\u001b]0;owned\\u0007ok", "expr": "goal_found()"}',
                      interface)
    assert str(err.value) == ("the reply: promise.description: Value error, character U+001B at "
                              "position 1 is not printable; text here is one line of printable "
                              "characters")


def test_a_rejected_draft_is_asked_again_out_of_the_conversation(interface):
    backend = ScriptedBackend(['{"description": "d", "expr": "home == 1"}', reply(HOME)])
    draft = draft_promise(REQUEST, interface, backend, max_rounds=2)
    assert draft.promise == HOME and [r["layer"] for r in draft.rounds] == ["expressions", None]
    first, second = backend.requests
    assert "home == 1" not in json.dumps(first)
    assert [m["role"] for m in second] == [m["role"] for m in first]  # no rejected turn added
    assert "home == 1" in second[-1]["content"] and "was rejected" in second[-1]["content"]
    assert draft.rounds[0]["examples"] != draft.rounds[1]["examples"]


def test_the_pipeline_certifies_a_confirmed_promise_and_replays(tmp_path):
    backend = ScriptedBackend([reply(HOME)] * 4)
    shown = []
    got = synthesize_certified(GRID_ID, REQUEST, backend, lambda p: shown.append(p) or True,
                               name="home_again", drafts=4)
    assert got.certified and got.promise == HOME and shown == [HOME]
    assert got.document["promise"] == HOME.model_dump()
    assert spec_from_data(got.document, "<got>").name == "home_again"
    t = got.transcript
    assert len(t["drafts"]) == 4 and len(t["finds"]) == 1  # equal promises searched once
    assert t["certifications"] == [{"candidate": got.search.candidate.label, "promise": HOME.expr,
                                    "seed": CERTIFY_SEED, "successes": 112, "episodes": 112}]
    path = tmp_path / "t.json"
    path.write_text(json.dumps(t))
    again = synthesize_certified(GRID_ID, REQUEST, TranscriptBackend.from_file(path),
                                 name="home_again")
    assert again.document == got.document


def test_a_declined_promise_searches_nothing():
    got = synthesize_certified(GRID_ID, REQUEST, ScriptedBackend([reply(HOME)] * 4),
                               lambda promise: False)
    assert got.declined and not got.certified and got.transcript["certifications"] == []


def test_a_backend_failure_ends_the_drafts_honestly():
    got = synthesize_certified(GRID_ID, REQUEST, ScriptedBackend([None]))
    assert not got.certified and got.promise is None
    assert got.transcript["drafts"][0]["rounds"][0]["layer"] == "backend"


def vlb(*args, stdin=""):
    return subprocess.run([sys.executable, "-m", "vlb_gym.cli", *args], capture_output=True,
                          text=True, timeout=300, input=stdin, cwd=ROOT)


def test_cli_certify_shows_the_promise_and_saves_a_certified_behavior(tmp_path):
    replies = tmp_path / "replies.json"
    replies.write_text(json.dumps([reply(HOME)] * 4))
    out = tmp_path / "home.json"
    proc = vlb("synthesize", GRID_ID, REQUEST, "--certify", "--yes", "--scripted", str(replies),
               "--name", "home_again", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    assert f"promise: {HOME.description}\n  judged as: {HOME.expr}\n  accepted (--yes)" \
        in proc.stdout
    assert "certified on 112/112 fresh episodes" in proc.stdout
    saved = json.loads(out.read_text())
    assert saved["promise"]["expr"] == HOME.expr
    shown = vlb("behaviors", str(out))
    assert shown.returncode == 0 and f"promise: {HOME.description}" in shown.stdout
    verified = vlb("verify", GRID_ID, "--behavior", str(out), "--episodes", "20", "--epsilon", "0.05")
    assert verified.returncode == 0 and "successes 20/20" in verified.stdout


def test_cli_certify_without_yes_asks_and_a_no_saves_nothing(tmp_path):
    replies = tmp_path / "replies.json"
    replies.write_text(json.dumps([reply(HOME)] * 4))
    out = tmp_path / "home.json"
    proc = vlb("synthesize", GRID_ID, REQUEST, "--certify", "--scripted", str(replies),
               "--out", str(out), stdin="n\n")
    assert proc.returncode == 1 and "[y/N]" in proc.stdout and "not confirmed" in proc.stdout
    assert not out.exists() and not list(tmp_path.glob("home*transcript*"))


def test_cli_certify_on_an_env_without_a_space_is_one_error_line(tmp_path):
    replies = tmp_path / "replies.json"
    replies.write_text(json.dumps([reply(HOME)]))
    proc = vlb("synthesize", "VLB-Integrator-v0", "reach the origin", "--certify", "--yes",
               "--env-module", "examples/integrator_env.py", "--scripted", str(replies),
               "--out", str(tmp_path / "x.json"))
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1
    assert "no search space" in proc.stderr


def test_consensus_weighs_the_first_draft_most():
    """Two later drafts agreeing on a weaker promise do not outvote the first draft's (the
    nearest examples'): the behavior that keeps the first one is certified."""
    weaker = [Promise(expr="goal_found() and primitives()[-1] == 'sense'", description="a"),
              Promise(expr="goal_found() and primitives()[-1] == 'sense' and len(sensed()) > 0",
                      description="b")]
    backend = ScriptedBackend([reply(HOME), reply(weaker[0]), reply(weaker[1]),
                               reply(weaker[0])])
    got = synthesize_certified(GRID_ID, REQUEST, backend)
    consensus = {c["candidate"]: c["keeps"] for c in got.transcript["consensus"]}
    assert consensus == {"explore until a goal is found -> go to the start": [0],
                         "explore until a goal is found": [1, 2]}
    assert got.certified and got.promise == HOME
    assert got.search.candidate.label == "explore until a goal is found -> go to the start"


def test_cli_certify_refuses_the_graph_first_options(tmp_path):
    replies = tmp_path / "replies.json"
    replies.write_text(json.dumps([reply(HOME)]))
    proc = vlb("synthesize", GRID_ID, REQUEST, "--certify", "--yes", "--scripted", str(replies),
               "--verify", "10", "--out", str(tmp_path / "x.json"))
    assert proc.returncode == 2 and "--certify: --verify" in proc.stderr
    assert not (tmp_path / "x.json").exists()
