"""Reading a store: a path is a path (no URI syntax), reading never writes beside the file, and
the whole store is checked (structure, each record against itself and against the plan) before
anything is counted: one line naming what was found, never a wrong count or a traceback."""

from __future__ import annotations

import json
import sqlite3

import pytest

from vlb_gym.cli import main
from vlb_gym.verify.campaign import episode_seed

GRID = "VLB-GridExplore-v0"


def verify(store, *extra) -> int:
    return main(["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "6",
                 "--epsilon", "0.1", "--backend", "serial", "--quiet", "--store", str(store),
                 *extra])


def one_line_error(capsys, *words) -> None:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error:" in err and "Traceback" not in err, err
    for word in words:
        assert word in err, err


@pytest.mark.parametrize("name", ["a#b.db", "100%41.db", "q?x.db", "run#1.db", "sp ace.db"])
def test_a_store_path_is_a_path_not_a_uri(name, tmp_path, capsys):
    store = tmp_path / name
    assert verify(store) == 0
    capsys.readouterr()
    assert main(["report", str(store), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["episodes"] == 6
    assert verify(store) == 0  # resumed: every episode stored
    assert "resuming" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


def test_reading_writes_nothing_beside_the_store(tmp_path, capsys):
    store = tmp_path / "c.db"
    assert verify(store) == 0
    before = sorted(p.name for p in tmp_path.iterdir())
    for command in (["report", str(store)], ["replay", str(store), "--episode", "1"]):
        assert main(command) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == before == ["c.db"]


def test_a_foreign_database_in_wal_mode_is_refused_untouched(tmp_path, capsys):
    foreign = tmp_path / "other.db"
    with sqlite3.connect(foreign) as db:
        db.execute("PRAGMA journal_mode=WAL")
        db.execute("CREATE TABLE t (x)")
    db.close()
    assert main(["report", str(foreign)]) == 2
    one_line_error(capsys, "not a vlb-gym campaign store")
    assert [p.name for p in tmp_path.iterdir()] == ["other.db"]


def test_a_store_in_a_new_directory_is_made(tmp_path, capsys):
    assert verify(tmp_path / "new" / "dir" / "c.db") == 0
    assert (tmp_path / "new" / "dir" / "c.db").is_file()


def rewrite(store, change) -> None:
    """Edit every record of ``store`` with ``change(index, record)``."""
    with sqlite3.connect(store) as db:
        for index, text in db.execute("SELECT idx, record FROM episodes").fetchall():
            record = json.loads(text)
            change(index, record)
            db.execute("UPDATE episodes SET record = ? WHERE idx = ?", (json.dumps(record), index))
    db.close()


@pytest.fixture
def failing_store(tmp_path):
    """A finished campaign with failed episodes (a step bound that cuts many short)."""
    store = tmp_path / "c.db"
    assert main(["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "12",
                 "--epsilon", "0.1", "--env-kwarg", "max_episode_steps=6", "--quiet",
                 "--store", str(store)]) == 0
    return store


def flip(index, record):
    if record["rho"] == -1:
        record["rho"] = 1


def renumber(index, record):
    record["index"] = index  # (already so)


CASES = {
    "a failure flipped to a success": (flip, "rho is +1 but"),
    "a success with a reason": (lambda i, r: r.update(reason="x") if r["rho"] == 1 else None,
                                "rho is +1 but"),
    "a failure without a reason": (lambda i, r: r.update(reason=None) if r["rho"] == -1 else None,
                                   "no failure reason"),
    "another reset seed": (lambda i, r: r.update(seed=r["seed"] ^ 1),
                           "was reset with seed"),
}


@pytest.mark.parametrize("case", CASES)
def test_an_edited_record_is_refused(case, failing_store, capsys):
    change, message = CASES[case]
    rewrite(failing_store, change)
    for command in (["report", str(failing_store)],
                    ["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "12",
                     "--epsilon", "0.1", "--env-kwarg", "max_episode_steps=6", "--quiet",
                     "--store", str(failing_store)]):
        assert main(command) == 2
        one_line_error(capsys, message)


def test_an_episode_beyond_the_plan_is_refused(failing_store, capsys):
    with sqlite3.connect(failing_store) as db:
        index, text = db.execute("SELECT idx, record FROM episodes WHERE idx = 3").fetchone()
        record = json.loads(text)
        plan = json.loads(db.execute("SELECT plan FROM plan").fetchone()[0])
        record.update(index=40, seed=episode_seed(plan["seed"], 40))
        db.execute("INSERT INTO episodes VALUES (40, ?)", (json.dumps(record),))
    db.close()
    assert main(["report", str(failing_store)]) == 2
    one_line_error(capsys, "stored episode 40 is beyond the campaign's 12 episodes")


def test_a_table_rebuilt_without_its_key_is_refused(failing_store, capsys):
    """Without the primary key an episode could be stored twice ('60 of 30')."""
    with sqlite3.connect(failing_store) as db:
        db.executescript("CREATE TABLE copy AS SELECT * FROM episodes; DROP TABLE episodes; "
                         "CREATE TABLE episodes (idx INTEGER, record TEXT NOT NULL); "
                         "INSERT INTO episodes SELECT * FROM copy; "
                         "INSERT INTO episodes SELECT * FROM copy; DROP TABLE copy;")
    db.close()
    assert main(["report", str(failing_store)]) == 2
    one_line_error(capsys, "not a vlb-gym campaign store")


@pytest.mark.parametrize("content", [{"behaviors": 5}, {"behaviors": {"x": {"nodes": 1}}},
                                     {}, {"behaviors": {}, "more": 1}])
def test_a_malformed_policy_content_is_refused(content, failing_store, tmp_path, capsys):
    with sqlite3.connect(failing_store) as db:
        plan = json.loads(db.execute("SELECT plan FROM plan").fetchone()[0])
        plan["policy_content"] = content
        db.execute("UPDATE plan SET plan = ?", (json.dumps(plan),))
    db.close()
    assert main(["report", str(failing_store), "--out", str(tmp_path / "out")]) == 2
    one_line_error(capsys, "the stored plan is not valid", "policy_content")


@pytest.mark.timeout(120)
def test_a_replay_is_as_long_as_the_record_whatever_step_bound_the_store_names(tmp_path,
                                                                                capsys):
    from .conftest import explore_doc

    doc = explore_doc()
    doc["edges"][0]["guard"] = "True"  # sense -> go -> sense ... never finishes
    doc["terminals"] = ["go"]
    looping = tmp_path / "loop.json"
    looping.write_text(json.dumps(doc))
    store = tmp_path / "c.db"
    assert main(["verify", GRID, "--behavior", str(looping), "--episodes", "2", "--epsilon",
                 "0.1", "--env-kwarg", "max_episode_steps=40", "--quiet", "--store",
                 str(store)]) == 0
    with sqlite3.connect(store) as db:  # the store's step bound, edited: never truncated
        plan = json.loads(db.execute("SELECT plan FROM plan").fetchone()[0])
        plan["env_kwargs"]["max_episode_steps"] = 10 ** 18
        db.execute("UPDATE plan SET plan = ?", (json.dumps(plan),))
    db.close()
    capsys.readouterr()
    main(["replay", str(store), "--episode", "0"])
    out = capsys.readouterr().out
    assert "primitives=40" in out  # the record's 40 steps, then stopped
    assert main(["report", str(store), "--out", str(tmp_path / "out")]) == 0


@pytest.mark.parametrize("option, name, size, message", [
    ("--episodes-out", "e.jsonl", 20_000, "e.jsonl: cannot write it (File too large); the lines "
                                          "written so far are kept"),
    ("--store", "c.db", 20_000, "c.db: cannot write the store (disk I/O error)"),
    ("--store", "c.db", 200_000, "c.db: cannot store episode"),
    ("--report", "r.json", 512, "r.json: cannot write it (File too large)"),
])
def test_a_full_disk_is_one_line_naming_the_file(option, name, size, message, tmp_path):
    """A file size limit (``ulimit -f``) stands for a full disk."""
    import resource
    import subprocess
    import sys

    def limited():
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))

    proc = subprocess.run(
        [sys.executable, "-m", "vlb_gym.cli", "verify", GRID, "--behavior",
         "explore_until_goal", "--episodes", "3000", "--epsilon", "0.05", "--quiet", option,
         str(tmp_path / name)], capture_output=True, text=True, preexec_fn=limited, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert message in proc.stderr
