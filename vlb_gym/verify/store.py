"""A durable campaign store: an embedded SQLite database that is the campaign's source of truth.

The plan (env id and kwargs, behavior or policy with a digest of its content, N, eps, delta, root
seed, versions, the sampling distribution in words) is written first; then every finished episode,
as it finishes, in a transaction of its own (WAL mode). Killing the process at any moment loses at
most the episodes in flight; the same command on the same store resumes the campaign, running only
the episodes it lacks, and a report rebuilt from the store equals an uninterrupted run's. A file
that is not a vlb-gym store is refused and left untouched.
"""

from __future__ import annotations

import fcntl
import json
import os
import sqlite3
from pathlib import Path
from typing import Any

from .episode import STEP_KEYS, EpisodeResult

APPLICATION_ID = 0x564C4231  # "VLB1", in the SQLite header: marks the file as a vlb-gym store


class StoreError(ValueError):
    """The store cannot be used: not a store, corrupt, or holding another campaign."""


class CampaignStore:
    """The store at ``path``, created if missing and locked for this process; ``readonly``
    opens an existing store to read it, also while a campaign writes it."""

    def __init__(self, path: str | Path, readonly: bool = False):
        self.path = Path(path)
        if self.path.exists() and not self.path.is_file():
            raise StoreError(f"{self.path}: not a regular file")
        if readonly and not self.path.exists():
            raise StoreError(f"{self.path}: no such campaign store")
        fresh = not self.path.exists() or self.path.stat().st_size == 0
        if not fresh or readonly:
            self._check_foreign()
        self._lock: int | None = None
        if readonly:
            self.db = sqlite3.connect(f"file:{self.path}?mode=ro", uri=True, isolation_level=None)
            return
        self._lock = self._exclusive()
        self.db = sqlite3.connect(self.path, isolation_level=None)
        self.db.execute("PRAGMA journal_mode=WAL")
        # NORMAL: a commit is in the WAL before add() returns, safe from the process being
        # killed (only a crash of the machine itself may lose the last commits)
        self.db.execute("PRAGMA synchronous=NORMAL")
        # checkpoints (which fsync) every 32 MiB of log rather than SQLite's 4 MiB
        self.db.execute("PRAGMA wal_autocheckpoint=8192")
        if fresh:
            self.db.execute(f"PRAGMA application_id={APPLICATION_ID}")
            self.db.execute("CREATE TABLE IF NOT EXISTS plan "
                            "(id INTEGER PRIMARY KEY CHECK (id = 1), plan TEXT NOT NULL)")
            self.db.execute("CREATE TABLE IF NOT EXISTS episodes (idx INTEGER PRIMARY KEY, "
                            "record TEXT NOT NULL)")

    def _check_foreign(self) -> None:
        """Refuse a file that is not a readable vlb-gym store, opening it read-only."""
        try:
            with sqlite3.connect(f"file:{self.path}?mode=ro", uri=True) as probe:
                (app,) = probe.execute("PRAGMA application_id").fetchone()
                tables = {row[0] for row in probe.execute(
                    "SELECT name FROM sqlite_master WHERE type = 'table'")}
        except sqlite3.DatabaseError as exc:
            raise StoreError(f"{self.path}: not a vlb-gym campaign store ({exc})") from None
        if app != APPLICATION_ID or not {"plan", "episodes"} <= tables:
            raise StoreError(f"{self.path}: not a vlb-gym campaign store")

    def _exclusive(self) -> int:
        """An exclusive lock on the store for this process (released when it ends, however):
        two campaigns writing one store would interleave their episodes."""
        fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            raise StoreError(f"{self.path}: in use by another process") from None
        return fd

    def close(self) -> None:
        self.db.close()
        if self._lock is not None:
            os.close(self._lock)

    def plan(self) -> dict[str, Any] | None:
        row = self.db.execute("SELECT plan FROM plan WHERE id = 1").fetchone()
        return None if row is None else json.loads(row[0])

    def start(self, plan: dict[str, Any]) -> None:
        """Record ``plan``, or check that the store holds the same one (naming what differs)."""
        stored = self.plan()
        if stored is None:
            self.db.execute("INSERT INTO plan (id, plan) VALUES (1, ?)", (json.dumps(plan),))
            return
        differ = sorted(k for k in stored.keys() | plan.keys() if stored.get(k) != plan.get(k))
        if differ:
            details = "; ".join(f"{k}: stored {stored.get(k)!r:.80}, now {plan.get(k)!r:.80}"
                                for k in differ)
            raise StoreError(f"{self.path} holds another campaign ({details})")

    def done(self) -> set[int]:
        """Indices of the episodes stored."""
        return {row[0] for row in self.db.execute("SELECT idx FROM episodes")}

    def add(self, result: EpisodeResult) -> None:
        """Store one finished episode (its own transaction: durable once this returns)."""
        self.db.execute("INSERT INTO episodes (idx, record) VALUES (?, ?)",
                        (result.index, _encode(result)))

    def results(self) -> list[EpisodeResult]:
        """The stored episodes, in index order."""
        rows = self.db.execute("SELECT record FROM episodes ORDER BY idx")
        return [_decode(row[0]) for row in rows]

    def result(self, index: int) -> EpisodeResult | None:
        """Stored episode ``index``, if it is stored."""
        row = self.db.execute("SELECT record FROM episodes WHERE idx = ?", (index,)).fetchone()
        return None if row is None else _decode(row[0])


def _encode(result: EpisodeResult) -> str:
    """An episode's record as stored: compact JSON, each step a list of its :data:`STEP_KEYS`
    values (half the size of the dicts)."""
    record = result.to_dict()
    record["steps"] = [[step[key] for key in STEP_KEYS] for step in result.steps]
    return json.dumps(record, separators=(",", ":"))


def _decode(text: str) -> EpisodeResult:
    record = json.loads(text)
    record["steps"] = [dict(zip(STEP_KEYS, step)) for step in record.get("steps", ())]
    return EpisodeResult.from_dict(record)
