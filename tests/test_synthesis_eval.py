"""The committed real-model results of the certified-synthesis evaluation
(benchmarks/results/synthesis): the table is the recorded samples', each certified behavior
reproduces its figures on its certificate's campaign, and (marked slow) each transcript replays
offline to the outcome the live run recorded; and the harness's options."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.synthesis_eval import read_samples, replay, tables  # noqa: E402
from benchmarks.synthesis_tasks import TASKS, evaluate  # noqa: E402
from vlb_gym.abstractor.backends import TranscriptBackend  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results" / "synthesis"
HARNESS = ROOT / "benchmarks" / "synthesis_eval.py"


def live_rows() -> dict[tuple[str, str, int], dict[str, str]]:
    with (RESULTS / "results.csv").open() as handle:
        return {(r["model"], r["task"], int(r["sample"])): r for r in csv.DictReader(handle)}


def test_the_committed_table_is_the_recorded_samples():
    samples = read_samples(RESULTS / "results.csv")
    assert {s.task for s in samples} == {t.name for t in TASKS}
    assert tables(samples) == (RESULTS / "results.md").read_text()


def test_every_certified_behavior_reproduces_its_recorded_figures(tmp_path):
    """Each committed certified behavior, run on its certificate's campaign (seed and N), is
    verified, does the task and keeps its promise faithfully as often as the table says."""
    tasks = {t.name: t for t in TASKS}
    certified = [s for s in read_samples(RESULTS / "results.csv") if s.certified]
    assert certified
    for sample in certified:
        path = RESULTS / sample.model / f"{sample.task}-{sample.sample}.json"
        certificate = json.loads(path.read_text())["certificate"]
        assert (certificate["episodes"], certificate["successes"]) == \
            (sample.episodes, sample.verified)
        outcome = evaluate(tasks[sample.task], path, certificate["episodes"],
                           certificate["seed"], library_dir=tmp_path)
        assert (outcome.episodes, outcome.verified, outcome.task_done, outcome.judged,
                outcome.faithful) == (sample.episodes, sample.verified, sample.done,
                                      sample.judged, sample.faithful), sample.task


@pytest.mark.slow
def test_every_live_sample_replays_to_its_recorded_outcome():
    """The whole pipeline again from each transcript (the model's replies as recorded, the
    searches to their recorded budgets): the same promises, behaviors and figures (about as
    long as the live run's searches: benchmarks/synthesis_eval.py --replay does the same)."""
    live = live_rows()
    replayed = replay(RESULTS, list(TASKS))
    assert len(replayed) == len(live) >= len(TASKS)
    for sample in replayed:
        row = live[(sample.model, sample.task, sample.sample)]
        assert (sample.promise, str(sample.certified), sample.candidate) == \
            (row["promise"], row["certified"], row["candidate"])
        assert (sample.episodes, sample.verified, sample.done, sample.judged,
                sample.faithful) == tuple(int(row[k]) for k in (
                    "episodes", "verified", "done", "judged", "faithful"))


def harness(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(HARNESS), *args], capture_output=True, text=True,
                          timeout=120, cwd=ROOT)


EXTERNAL = '''
from benchmarks.synthesis_tasks import REFERENCES, Task, at_start

def check(state, result):
    return at_start(state)

TASKS = [Task("stay_home", "Sense once and stay where you are.", 1, False,
              REFERENCES / "sense_once.json", check),
         Task("wander", "Walk around a bit.", 2, False, REFERENCES / "sense_once.json", check)]
'''


def test_an_external_task_file_lists_its_tasks_without_a_model(tmp_path):
    tasks = tmp_path / "tasks.py"
    tasks.write_text(EXTERNAL)
    proc = harness("--tasks", str(tasks), "--list")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines() == ["stay_home\t1", "wander\t2"]
    assert harness("--tasks", str(tasks), "--only", "wander", "--list").stdout == "wander\t2\n"


@pytest.mark.parametrize("args, words", [
    (["--only", "no_such_task", "--list"], "unknown task(s) no_such_task"),
    (["--tasks", "{missing}", "--list"], "no such file"),
    (["--tasks", "{empty}", "--list"], "defines no TASKS"),
    (["--tasks", "{tasks}", "--replay", str(RESULTS), "--out", str(ROOT / "x")],
     "go outside the repository"),
])
def test_harness_errors_are_one_line_and_write_nothing(tmp_path, args, words):
    (tmp_path / "tasks.py").write_text(EXTERNAL)
    (tmp_path / "empty.py").write_text("TASKS = 3\n")
    paths = {"missing": tmp_path / "nope.py", "empty": tmp_path / "empty.py",
             "tasks": tmp_path / "tasks.py"}
    before = (RESULTS / "results.csv").read_bytes()
    proc = harness(*[a.format(**paths) for a in args])
    assert proc.returncode != 0 and words in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert (RESULTS / "results.csv").read_bytes() == before and not (ROOT / "x").exists()


def test_the_held_out_tasks_are_satisfiable_and_their_checks_can_fail():
    from benchmarks.synthesis_eval import load_tasks
    from benchmarks.synthesis_tasks import evaluate, task_named

    held_out = {t.name: t for t in load_tasks(ROOT / "benchmarks" / "heldout" / "tasks.py")}
    assert not set(held_out) & {t.name for t in TASKS}
    for task in held_out.values():
        assert evaluate(task, task.reference, 10).task_done == 10, task.name
    for name, wrong in [("home_and_sense", "return_home"), ("goal_then_neighbour", "return_home"),
                        ("everything_then_goal", "explore_all"),
                        ("three_round_trips", "two_round_trips"),
                        ("fifteen_cells_home", "explore_all_return_home")]:
        assert evaluate(held_out[name], task_named(wrong).reference, 10).task_done == 0, name


def test_the_harness_evaluates_a_served_model(tmp_path):
    from .chat_server import ChatServer

    promise = '{"description": "one sense, no move", "expr": "primitives() == [\'sense\']"}'
    # four drafts, and the first asked again once with its witness ("sense here" keeps it)
    with ChatServer([("reply", promise)] * 5, dialect="openai") as server:
        proc = harness("--base-url", server.url, "--model", "served/m", "--structured-output",
                       "openai", "--only", "sense_once", "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    with (tmp_path / "results.csv").open() as handle:
        (row,) = list(csv.DictReader(handle))
    assert (row["model"], row["task"], row["certified"], row["done"], row["faithful"]) == \
        ("served_m", "sense_once", "True", "112", "112")
    assert len(server.requests) == 5 and server.requests[0]["max_tokens"] == 400
    assert "keeps it" in server.requests[1]["messages"][-1]["content"]
    transcript = tmp_path / "served_m" / "sense_once-0.transcript.json"
    # a replay asks in the order the live run did: the witnessed redraft after its draft
    assert len(TranscriptBackend.from_file(transcript).replies) == 5


def test_the_harness_takes_a_promise_a_least_behavior_keeps_only_where_the_task_asks_no_more(
        tmp_path):
    """As ``--yes`` does: a promise that "sense once" keeps is not certified for a task that asks
    for more, and is for one that asks for no more (``trivial_ok``, as ``--trivial-ok``)."""
    from dataclasses import replace

    from benchmarks.synthesis_eval import attempt
    from benchmarks.synthesis_tasks import task_named

    weak = replace(task_named("explore_all"), promise="primitives()[:1] == ['sense']")
    refused = attempt(weak, None, "promises", 0, tmp_path)
    assert not refused.certified
    transcript = json.loads((tmp_path / "explore_all-0.transcript.json").read_text())
    assert transcript["witnesses"] == ["sense once where it stands and stop"]
    assert transcript["finds"] == [] and transcript["certifications"] == []
    taken = attempt(replace(weak, trivial_ok=True), None, "promises", 0, tmp_path)
    assert taken.certified and taken.done == 0  # certified, and not the task


@pytest.mark.parametrize("folder", ["heldout22", "heldout21", "heldout20", "heldout19", "heldout18", "heldout17", "heldout16", "heldout15", "heldout14", "heldout13", "heldout12", "heldout11", "heldout10", "heldout9", "heldout8", "heldout7",
                                    "heldout6", "heldout5", "heldout4", "heldout3", "heldout2",
                                    "dev_general", "heldout"])
def test_task_files_are_satisfiable_faithful_and_checkable(tmp_path, folder):
    """Each grid reference keeps its task's faithful promise and does the task on every episode
    (promise and check agree), and a behavior that only senses does not do every task (the
    scooping references of the held-out sets run in benchmarks/, a few seconds an episode)."""

    from benchmarks.synthesis_eval import load_tasks
    from benchmarks.synthesis_tasks import evaluate, task_named

    tasks = load_tasks(ROOT / "benchmarks" / folder / "tasks.py")
    if folder in ("heldout2", "heldout3", "heldout4", "heldout5", "heldout6",
                  "heldout7", "heldout8", "heldout9", "heldout10", "heldout11", "heldout12",
                  "heldout13", "heldout14", "heldout15", "heldout16", "heldout17", "heldout18",
                  "heldout19", "heldout20", "heldout21", "heldout22"):
        assert len([t for t in tasks if t.env_id == "VLB-GridExplore-v0"]) >= 10
        assert 2 <= len([t for t in tasks if t.env_id == "VLB-Scoop-v0"]) <= 3
    assert all(t.promise for t in tasks)
    assert not {t.name for t in tasks} & {t.name for t in TASKS}
    sense_once = task_named("sense_once").reference
    for task in tasks:
        if task.env_id != "VLB-GridExplore-v0":
            continue
        document = json.loads(task.reference.read_text())
        document["promise"] = {"expr": task.promise}
        path = tmp_path / f"{task.name}.json"
        path.write_text(json.dumps(document))
        out = evaluate(task, path, 10)
        assert (out.verified, out.task_done, out.judged, out.faithful) == (10, 10, 10, 10), \
            (task.name, out.failures)
        assert evaluate(task, sense_once, 10).task_done < 10 or task.name == "beside_goal"


def test_the_development_promises_are_faithful(tmp_path):
    """The 13 development tasks' promises: each reference keeps its own."""

    for task in TASKS:
        document = json.loads(task.reference.read_text())
        document["promise"] = {"expr": task.promise}
        path = tmp_path / f"{task.name}.json"
        path.write_text(json.dumps(document))
        out = evaluate(task, path, 10)
        assert (out.verified, out.task_done, out.faithful) == (10, 10, 10), task.name


GOOD_TRANSCRIPT = {"task": "sense_once", "pipeline": "promise", "drafts": [], "finds": [],
                   "consensus": [], "certifications": [], "seeds": {"screen": [], "certify": []}}


@pytest.mark.parametrize("kind, words", [
    ("fifo", "not a regular file"),
    ("zero", "not a regular file"),
    ("text", "not valid JSON"),
    ("deep", "nested"),
    ("pipeline", "pipeline: Input should be 'promise' or 'intent-first'"),
    ("budget", "finds.0.built: Input should be less than or equal to 10000000"),
    ("seed", "seeds.screen.0: Input should be greater than or equal to 0"),
    ("replies", "not a vlb synthesize transcript"),
    ("name", "a number"),
])
def test_a_hostile_transcript_ends_the_replay_in_one_line(tmp_path, kind, words):
    import json
    import os

    folder = tmp_path / "runs" / "m"
    folder.mkdir(parents=True)
    path = folder / ("x-y.transcript.json" if kind == "name" else "sense_once-0.transcript.json")
    bad = dict(GOOD_TRANSCRIPT)
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "zero":
        path.symlink_to("/dev/zero")
    elif kind == "text":
        path.write_text("{not json")
    elif kind == "deep":
        path.write_text("[" * 100_000 + "]" * 100_000)
    else:
        if kind == "pipeline":
            bad["pipeline"] = "graph"
        elif kind == "budget":
            bad["finds"] = [{"built": 10 ** 30, "program": None}]
        elif kind == "seed":
            bad["seeds"] = {"screen": [-1], "certify": []}
        elif kind == "replies":
            bad["pipeline"] = "intent-first"
            bad["drafts"] = [{"promise": None, "rounds": [{"reply": 5}]}]
        path.write_text(json.dumps(bad))
    proc = harness("--replay", str(tmp_path / "runs"), "--out", str(tmp_path / "out"))
    assert proc.returncode == 1 and "Traceback" not in proc.stderr, proc.stderr
    (line,) = proc.stderr.strip().splitlines()
    assert str(path) in line and words in line, line
