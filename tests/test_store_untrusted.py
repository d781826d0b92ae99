"""A store is untrusted data: what an adversarial review of the campaign pipeline found, one test
per finding (code named by a store, outputs over inputs, damaged or edited stores, interrupted
sequential stores)."""

from __future__ import annotations

import hashlib
import json
import shutil
import sqlite3

import pytest

from vlb_gym.cli import main

GRID = "VLB-GridExplore-v0"


def digest(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture
def store(tmp_path):
    """A small finished fixed-N campaign store (serial backend)."""
    path = tmp_path / "campaign.db"
    assert main(["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "6",
                 "--epsilon", "0.1", "--env-kwarg", "action_noise=0.3", "--backend", "serial",
                 "--quiet", "--store", str(path)]) == 0
    return path


def edit_plan(path, change) -> None:
    db = sqlite3.connect(path)
    plan = json.loads(db.execute("SELECT plan FROM plan").fetchone()[0])
    change(plan)
    db.execute("UPDATE plan SET plan = ?", (json.dumps(plan),))
    db.commit()
    db.close()


# -- 1. a store is untrusted data, yet report --out and replay import modules it names --------

@pytest.fixture
def booby_trapped(store, tmp_path):
    marker = tmp_path / "PWNED"
    module = tmp_path / "evil.py"
    module.write_text(f"open({str(marker)!r}, 'w').write('code from the store ran')\n")
    edit_plan(store, lambda plan: plan.update(env_modules=[str(module)]))
    return store, marker


def test_report_out_does_not_execute_code_named_by_the_store(booby_trapped, tmp_path):
    store, marker = booby_trapped
    main(["report", str(store), "--out", str(tmp_path / "out")])
    assert not marker.exists(), "vlb report --out imported an --env-module named in the store"


def test_replay_from_a_store_does_not_execute_code_named_by_the_store(booby_trapped):
    store, marker = booby_trapped
    main(["replay", str(store), "--episode", "0"])
    assert not marker.exists(), "vlb replay STORE imported an --env-module named in the store"


# -- 2. replay --render overwrites its inputs ---------------------------------------------------

def test_replay_render_refuses_to_overwrite_the_store(store, capsys):
    before = digest(store)
    assert main(["replay", str(store), "--episode", "0", "--render", str(store)]) == 2
    assert digest(store) == before, "the campaign store was replaced by a GIF"


def test_replay_render_refuses_to_overwrite_the_behavior_file(tmp_path, capsys):
    from pathlib import Path

    import vlb_gym

    behavior = tmp_path / "b.json"
    shutil.copy(Path(vlb_gym.__file__).parent / "behaviors" / "explore_until_goal.json",
                behavior)
    before = digest(behavior)
    assert main(["replay", GRID, "--behavior", str(behavior), "--seed", "3",
                 "--render", str(behavior)]) == 2
    assert digest(behavior) == before, "the behavior file was replaced by a GIF"


# -- 3. a store with episodes but no plan adopts any campaign -----------------------------------

def test_a_store_with_episodes_but_no_plan_is_not_adopted_by_another_campaign(tmp_path, capsys):
    path = tmp_path / "c.db"
    assert main(["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "8",
                 "--epsilon", "0.1", "--env-kwarg", "action_noise=0.3", "--backend", "serial",
                 "--quiet", "--store", str(path)]) == 0
    db = sqlite3.connect(path)
    db.execute("DELETE FROM plan")
    db.commit()
    db.close()
    capsys.readouterr()
    # a different campaign (3 episodes, no noise) must not count the 8 foreign episodes
    code = main(["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "3",
                 "--epsilon", "0.1", "--backend", "serial", "--quiet", "--store", str(path)])
    out = capsys.readouterr()
    assert "8 of 3" not in out.err + out.out
    assert code == 2


# -- 4. an interrupted sequential campaign is reported as complete and undecided at the cap ------

def test_report_of_an_interrupted_sequential_store_is_not_complete(tmp_path, capsys):
    path = tmp_path / "seq.db"
    assert main(["verify", GRID, "--behavior", "explore_until_goal", "--sequential",
                 "--max-episodes", "60", "--epsilon", "0.02", "--delta", "0.01", "--env-kwarg",
                 "action_noise=0.3", "--backend", "serial", "--quiet", "--store", str(path)]) == 0
    db = sqlite3.connect(path)
    db.execute("DELETE FROM episodes WHERE idx >= 10")  # as if killed after 10 episodes
    db.commit()
    db.close()
    capsys.readouterr()
    assert main(["report", str(path), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["episodes"] == 10
    assert report["complete"] is False, "10 of at most 60 episodes: the campaign was cut short"
    assert main(["report", str(path)]) == 0
    assert "the cap" not in capsys.readouterr().out


# -- 5. an edited or malformed store: a traceback, not one line and exit code 2 -----------------

MISSING_KEY = ("missing-key", lambda plan: plan.pop("epsilon"))
WRONG_TYPE = ("wrong-type", lambda plan: plan.update(delta=None))
POLICY_STR = ("policy-not-a-mapping", lambda plan: plan.update(policy="behavior"))
POLICY_FIELD = ("policy-unknown-field",
                lambda plan: plan.update(policy={"kind": "behavior", "ref": "x", "extra": 1}))
REPORT, REPLAY = ["report"], ["replay", "--episode", "0"]


@pytest.mark.parametrize("command,case", [
    (REPORT, MISSING_KEY), (REPORT, WRONG_TYPE), (REPORT, POLICY_STR),
    (REPLAY, WRONG_TYPE), (REPLAY, POLICY_STR), (REPLAY, POLICY_FIELD),
], ids=lambda value: value[0])
def test_an_edited_plan_is_a_usage_error(store, command, case, capsys):
    edit_plan(store, case[1])
    assert main([command[0], str(store), *command[1:]]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_a_store_with_the_right_id_and_wrong_tables_is_a_usage_error(tmp_path, capsys):
    path = tmp_path / "spoof.db"
    db = sqlite3.connect(path)
    db.execute("PRAGMA application_id = 1447838257")
    db.execute("CREATE TABLE plan (a)")
    db.execute("CREATE TABLE episodes (b)")
    db.commit()
    db.close()
    assert main(["report", str(path)]) == 2  # sqlite3.OperationalError escapes


# -- 6. the store's WAL is an input too ----------------------------------------------------------

def test_episodes_out_may_not_name_the_stores_wal(store, tmp_path, capsys):
    wal = f"{store}-wal"
    assert main(["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "6",
                 "--epsilon", "0.1", "--env-kwarg", "action_noise=0.3", "--backend", "serial",
                 "--quiet", "--store", str(store), "--episodes-out", wal, "--force"]) == 2


def test_modules_named_again_on_the_command_line_are_trusted(tmp_path, capsys):
    from .conftest import EXAMPLES

    module = str(EXAMPLES / "integrator_env.py")
    store = tmp_path / "integrator.db"
    assert main(["verify", "VLB-Integrator-v0", "--env-module", module, "--behavior",
                 str(EXAMPLES / "integrator_reach.json"), "--episodes", "5", "--epsilon", "0.1",
                 "--quiet", "--store", str(store)]) == 0
    capsys.readouterr()
    assert main(["replay", str(store), "--episode", "1"]) == 2
    assert f"--env-module {module}" in capsys.readouterr().err
    assert main(["replay", str(store), "--episode", "1", "--env-module", module]) == 0
    assert "reproduces the stored record" in capsys.readouterr().out
    assert main(["report", str(store), "--out", str(tmp_path / "r")]) == 0
    assert "no frames: replaying would run code the store names" in capsys.readouterr().err


# -- 7. a second review, of the typed records: nothing a store leaves out is filled in ----------

def edit_episode(path, index, change) -> None:
    db = sqlite3.connect(path)
    record = json.loads(db.execute("SELECT record FROM episodes WHERE idx = ?",
                                   (index,)).fetchone()[0])
    change(record)
    db.execute("UPDATE episodes SET record = ? WHERE idx = ?", (json.dumps(record), index))
    db.commit()
    db.close()


PLAN_EDITS = {
    "episodes-null": lambda plan: plan.update(episodes=None),
    "policy-without-library": lambda plan: plan["policy"].pop("library"),
    "render-mode-kwarg": lambda plan: plan["env_kwargs"].update(render_mode=5),
}
EPISODE_EDITS = {
    "no-steps": lambda record: record.pop("steps"),
    "no-start": lambda record: record.pop("start"),
    "no-cause": lambda record: record.pop("cause"),
    "no-error": lambda record: record.pop("error"),
    "step-as-dict": lambda record: record.update(steps=[dict(zip(
        ("primitive", "node", "param", "certificate", "reason", "cause"), record["steps"][0]))]),
    "rho-true": lambda record: record.update(rho=True),
    "rho-float": lambda record: record.update(rho=float(record["rho"])),
    "seconds-infinite": lambda record: record.update(seconds=float("inf")),
    # finite, but two such records sum to infinity (report --json would print Infinity)
    "seconds-past-a-year": lambda record: record.update(seconds=1e308),
    # a step's own time (format 2): a number of seconds, finite, at most a year, or null
    "step-seconds-negative": lambda record: record["steps"][0].__setitem__(6, -1.0),
    "step-seconds-infinite": lambda record: record["steps"][0].__setitem__(6, float("inf")),
    "step-seconds-past-a-year": lambda record: record["steps"][0].__setitem__(6, 1e308),
    "step-seconds-text": lambda record: record["steps"][0].__setitem__(6, "0.1"),
    "step-seconds-true": lambda record: record["steps"][0].__setitem__(6, True),
    "step-seconds-list": lambda record: record["steps"][0].__setitem__(6, [0.1]),
    "step-seconds-huge-int": lambda record: record["steps"][0].__setitem__(6, 10**400),
    "step-of-five-fields": lambda record: record["steps"][0].__delitem__(slice(5, None)),
    "step-of-eight-fields": lambda record: record["steps"][0].append(0.1),
}


@pytest.mark.parametrize("edit", PLAN_EDITS, ids=str)
@pytest.mark.parametrize("command", [["report"], ["replay", "--episode", "0"]],
                         ids=lambda c: c[0])
def test_a_plan_missing_what_a_default_would_fill_is_refused(store, edit, command, capsys):
    edit_plan(store, PLAN_EDITS[edit])
    capsys.readouterr()
    assert main([command[0], str(store), *command[1:]]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "the stored plan is not valid" in err


@pytest.mark.parametrize("edit", EPISODE_EDITS, ids=str)
def test_a_record_missing_a_field_or_of_another_shape_is_refused(store, edit, capsys):
    edit_episode(store, 0, EPISODE_EDITS[edit])
    for command in (["report", str(store)], ["replay", str(store), "--episode", "0"]):
        capsys.readouterr()
        assert main(command) == 2, command
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "stored episode 0 is not valid" in err, err


def test_a_record_longer_than_any_episode_writes_is_refused_before_it_is_parsed(store, capsys,
                                                                                 monkeypatch):
    """A record of millions of steps would take gigabytes as objects: its length is checked
    first (the limit lowered here, so that the test writes kilobytes, not 64 MB)."""
    from vlb_gym.verify import store as store_module

    monkeypatch.setattr(store_module, "MAX_RECORD_CHARS", 5_000)
    edit_episode(store, 0, lambda record: record.update(steps=record["steps"] * 200))
    capsys.readouterr()
    assert main(["report", str(store)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "stored episode 0 is" in err and "at most 5,000" in err
