"""The ``vlb`` command line, as a user runs it."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

from vlb_gym.cli import main
from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.core.spec import spec_from_data
from vlb_gym.verify.export import read_export

from .conftest import EXAMPLES


def vlb(*args, check=True):
    proc = subprocess.run([sys.executable, "-m", "vlb_gym.cli", *args], capture_output=True,
                          text=True, timeout=300)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


def test_help_explains_each_command():
    out = vlb("--help").stdout
    for command in ("verify", "plan", "replay", "behaviors", "schema"):
        assert command in out
    assert "Clopper-Pearson" in vlb("verify", "--help").stdout


def test_verify_paper_campaign_with_report(tmp_path):
    report_path = tmp_path / "out" / "report.json"
    stream = tmp_path / "episodes.jsonl"
    out = vlb("verify", "VLB-GridExplore-v0", "--behavior", "find_goal_and_oscillate",
              "--episodes", "100", "--epsilon", "0.05", "--report", str(report_path),
              "--episodes-out", str(stream)).stdout
    assert "successes 100/100" in out and "confidence 0.99407" in out  # 0.9940795, floored
    report = json.loads(report_path.read_text())
    assert report["episodes"] == 100 and report["failures"] == 0 and report["seed"] == 0
    plan, episodes, end = read_export(stream)
    assert plan.episodes == 100 and plan.policy.ref == "find_goal_and_oscillate"
    assert sorted(r.index for r in episodes) == list(range(100))
    assert all(r.rho == 1 and len(r.steps) == r.primitives > 0 for r in episodes)
    assert all(s["certificate"] and s["node"] in (
        "to_goal", "to_start", "explore_until_goal/sense", "explore_until_goal/go") for r in episodes for s in r.steps)
    assert end == {"complete": True, "episodes": 100}


def test_verify_failing_behavior_exits_zero_and_names_seeds(tmp_path, capsys):
    report_path = tmp_path / "r.json"
    code = main(["verify", "VLB-GridExplore-v0", "--behavior", str(EXAMPLES / "fixed_cell.json"),
                 "--episodes", "40", "--epsilon", "0.05", "--workers", "2", "--quiet",
                 "--report", str(report_path)])
    out = capsys.readouterr().out
    report = json.loads(report_path.read_text())
    assert code == 0 and report["failures"] > 0 and report["workers"] == 2
    assert f"failures {report['failures']}" in out and "vlb replay" in out
    seed = report["failed_episodes"][0]["seed"]
    assert main(["replay", "VLB-GridExplore-v0", "--behavior", str(EXAMPLES / "fixed_cell.json"),
                 "--seed", str(seed)]) == 0
    replay = capsys.readouterr().out
    assert "FAIL navigate" in replay and "rho_B = -1" in replay


@pytest.mark.parametrize("args, message", [
    (["verify", "VLB-Nope-v0", "--behavior", "x", "--episodes", "5", "--epsilon", "0.1"],
     "unknown environment 'VLB-Nope-v0'"),
    (["verify", "VLB-GridExplore-v0", "--behavior", "nope", "--episodes", "5",
      "--epsilon", "0.1"], "unknown behavior 'nope'"),
    (["verify", "VLB-GridExplore-v0", "--behavior", "explore_until_goal", "--episodes", "0",
      "--epsilon", "0.1"], "must be at least 1"),
    (["verify", "VLB-GridExplore-v0", "--behavior", "explore_until_goal", "--episodes", "5",
      "--epsilon", "1.5"], "strictly between 0 and 1"),
    (["verify", "VLB-GridExplore-v0", "--behavior", "explore_until_goal", "--episodes", "5",
      "--epsilon", "0.1", "--env-kwarg", "action_noise=-2"], "action_noise must be >= 0"),
    (["verify", "VLB-GridExplore-v0", "--behavior", "explore_until_goal", "--episodes", "5",
      "--epsilon", "0.1", "--env-kwarg", "oops"], "expected NAME=VALUE"),
    (["plan", "--epsilon", "0.05"], "--confidence"),
])
def test_bad_input_is_a_clear_error_and_writes_nothing(args, message, tmp_path):
    report = tmp_path / "report.json"
    proc = vlb(*args, "--report", str(report), check=False) if args[0] == "verify" \
        else vlb(*args, check=False)
    assert proc.returncode == 2
    assert message in proc.stderr
    assert not report.exists()


def test_bad_behavior_file_fails_before_any_episode(tmp_path, write_behavior):
    path = write_behavior('{"name": "x", "nodes": [', "bad.json")
    proc = vlb("verify", "VLB-GridExplore-v0", "--behavior", str(path), "--episodes", "5",
               "--epsilon", "0.1", "--report", str(tmp_path / "r.json"), check=False)
    assert proc.returncode == 2 and "bad.json: line 1" in proc.stderr
    assert not (tmp_path / "r.json").exists()


@pytest.mark.parametrize("eps, conf, k", [(0.05, 0.95, 0), (0.01, 0.99, 0), (0.05, 0.95, 2)])
def test_plan(eps, conf, k, capsys):
    assert main(["plan", "--epsilon", str(eps), "--confidence", str(conf), "--failures", str(k),
                 "--json"]) == 0
    n = json.loads(capsys.readouterr().out)["episodes"]
    if k == 0:
        assert n == math.ceil(math.log(1 - conf) / math.log(1 - eps))
    assert main(["plan", "--epsilon", str(eps), "--confidence", str(conf),
                 "--failures", str(k)]) == 0
    assert capsys.readouterr().out.startswith(f"{n} episodes")


def test_behaviors_listing_and_graph(capsys):
    assert main(["behaviors"]) == 0
    assert [line.split() for line in capsys.readouterr().out.splitlines()] == [
        ["explore_until_goal", "shipped"], ["find_goal_and_oscillate", "shipped"],
        ["scoop_repeatedly", "shipped"]]
    library = BehaviorLibrary()
    library.save(spec_from_data({**json.loads((EXAMPLES / "fixed_cell.json").read_text()),
                                 "name": "mine"}))
    assert main(["behaviors"]) == 0
    assert f"mine                     yours: {library.directory / 'mine'}.json" in \
        capsys.readouterr().out.splitlines()
    assert main(["behaviors", "find_goal_and_oscillate"]) == 0
    out = capsys.readouterr().out
    assert "node explore: behavior explore_until_goal [start]" in out
    assert "edge to_start -> to_goal: if trips < 5" in out


def test_schema_command_prints_the_schema(capsys):
    assert main(["schema"]) == 0
    schema = json.loads(capsys.readouterr().out)
    assert {"nodes", "edges", "start", "terminals"} <= schema["properties"].keys()


def test_render_writes_an_animation(tmp_path, capsys):
    from PIL import Image

    out = tmp_path / "episode.gif"
    assert main(["render", "VLB-GridExplore-v0", "--behavior", "explore_until_goal",
                 "--seed", "2", "--out", str(out), "--fps", "4"]) == 0
    assert "rho_B = +1" in capsys.readouterr().out
    with Image.open(out) as image:
        assert image.size == (320, 320) and image.n_frames > 3


def test_errors_name_the_behavior_file_as_given(tmp_path, monkeypatch, capsys):
    behavior = json.loads((EXAMPLES / "fixed_cell.json").read_text())
    behavior["edges"][0]["param"] = "label(current_cell()) == 2"
    (tmp_path / "bad.json").write_text(json.dumps(behavior))
    monkeypatch.chdir(tmp_path)
    assert main(["verify", "VLB-GridExplore-v0", "--behavior", "bad.json", "--episodes", "3",
                 "--epsilon", "0.1"]) == 2
    assert capsys.readouterr().err.startswith("vlb verify: error: bad.json: edges[0].param: ")
