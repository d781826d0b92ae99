"""A durable campaign store: an embedded SQLite database that is the campaign's source of truth.

The plan (env id and kwargs, behavior or policy with a digest of its content, N, eps, delta, root
seed, versions, the sampling distribution in words) is written first; then every finished episode,
as it finishes, in a transaction of its own (WAL mode). Killing the process at any moment loses at
most the episodes in flight; the same command on the same store resumes the campaign, running only
the episodes it lacks, and a report rebuilt from the store equals an uninterrupted run's. A file
that is not a vlb-gym store is refused and left untouched.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import sqlite3
import urllib.parse
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from vlb_gym.core.errors import UserError
from vlb_gym.core.formats import CURRENT, FormatError, check_format

from .records import (ComparisonPlan, EpisodeResult, PairResult, Plan, episode_seed,
                      comparison_plan_from_json, episode_from_json, first_error,
                      pair_from_json, plan_from_json)

MAX_RECORD_CHARS = 64_000_000  # an episode's record: about 600,000 steps
APPLICATION_ID = 0x564C4231  # "VLB1", in the SQLite header: marks the file as a vlb-gym store
COMPARISON_APPLICATION_ID = 0x564C4232  # "VLB2": a comparison's store


def parting(a: Any, b: Any, width: int = 80) -> tuple[str, str]:
    """The reprs of ``a`` and ``b``, each cut to about ``width`` characters around where they
    first differ, so that two long values that share a beginning do not look the same."""
    ra, rb = repr(a), repr(b)
    at = next((i for i, (x, y) in enumerate(zip(ra, rb)) if x != y), min(len(ra), len(rb)))
    start = max(0, at - width // 4)

    def cut(text: str) -> str:
        part = text[start:start + width]
        return ("…" if start else "") + part + ("…" if start + width < len(text) else "")
    return cut(ra), cut(rb)


class StoreError(UserError, ValueError):
    """The store cannot be used: not a store, corrupt, or holding another campaign."""


class CampaignStore:
    """The store at ``path``, created if missing and locked for this process; ``readonly``
    opens an existing store to read it, also while a campaign writes it.

    A kind of store is its :attr:`application_id` (in the SQLite header: a store of one kind
    is never read as another), its :meth:`_validate_plan`, and its record's :meth:`_encode`
    and :meth:`_decode`."""

    application_id = APPLICATION_ID
    what = "campaign store"
    holds = "campaign"
    unit = "episode"

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
            self.db = _connect_readonly(self.path)
            return
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise StoreError(f"{self.path}: cannot make its directory ({exc.strerror})") from None
        self._lock = self._exclusive()
        try:
            self._create(fresh)
        except sqlite3.DatabaseError as exc:  # a full disk, a file size limit, ...
            self.close()
            raise StoreError(f"{self.path}: cannot write the store ({exc})") from None

    def _create(self, fresh: bool) -> None:
        self.db = sqlite3.connect(self.path, isolation_level=None)
        self.db.execute("PRAGMA journal_mode=WAL")
        # NORMAL: a commit is in the WAL before add() returns, safe from the process being
        # killed (only a crash of the machine itself may lose the last commits)
        self.db.execute("PRAGMA synchronous=NORMAL")
        # checkpoints (which fsync) every 32 MiB of log rather than SQLite's 4 MiB
        self.db.execute("PRAGMA wal_autocheckpoint=8192")
        self._current = fresh  # whether the store says the format its new records are in
        if fresh:
            self.db.execute(f"PRAGMA application_id={self.application_id}")
            self.db.execute(f"PRAGMA user_version={CURRENT['store']}")  # the format
            self.db.execute("CREATE TABLE IF NOT EXISTS plan "
                            "(id INTEGER PRIMARY KEY CHECK (id = 1), plan TEXT NOT NULL)")
            self.db.execute("CREATE TABLE IF NOT EXISTS episodes (idx INTEGER PRIMARY KEY, "
                            "record TEXT NOT NULL)")

    def _check_foreign(self) -> None:
        """Refuse a file that is not an intact vlb-gym store, opening it read-only."""
        try:
            with contextlib.closing(_connect_readonly(self.path)) as probe:
                (app,) = probe.execute("PRAGMA application_id").fetchone()
                (version,) = probe.execute("PRAGMA user_version").fetchone()
                columns = {table: [(row[1], row[5]) for row in probe.execute(
                    f"PRAGMA table_info({table})")] for table in ("plan", "episodes")}
                (check,) = probe.execute("PRAGMA quick_check(1)").fetchone() \
                    if app == self.application_id else ("ok",)
        except sqlite3.DatabaseError as exc:
            raise StoreError(f"{self.path}: not a vlb-gym {self.what} ({exc})") from None
        if app == self.application_id:  # a later format may have other tables: said first
            try:  # 0: a store written before formats were versioned, format 1
                check_format("store", version or None, str(self.path))
            except FormatError as exc:
                raise StoreError(str(exc)) from None
        if app != self.application_id or columns != _COLUMNS:
            other = next((kind.what for kind in _KINDS if kind.application_id == app), None)
            raise StoreError(f"{self.path}: not a vlb-gym {self.what}"
                             + (f" (it is a {other})" if other and columns == _COLUMNS else ""))
        if check != "ok":
            raise StoreError(f"{self.path}: the campaign store is damaged ({check})")

    def _exclusive(self) -> int:
        """An exclusive lock on the store for this process (released when it ends, however):
        two campaigns writing one store would interleave their episodes."""
        try:
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise StoreError(f"{self.path}: cannot write the store ({exc.strerror})") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            raise StoreError(f"{self.path}: in use by another process") from None
        return fd

    def close(self) -> None:
        if getattr(self, "db", None) is not None:
            self.db.close()
        if self._lock is not None:
            os.close(self._lock)
            self._lock = None

    def _rows(self, query: str, *args: Any) -> list[tuple[Any, ...]]:
        try:
            return self.db.execute(query, args).fetchall()
        except sqlite3.DatabaseError as exc:
            raise StoreError(f"{self.path}: the campaign store is damaged ({exc})") from None

    def plan(self) -> Plan | None:
        """The stored plan, checked (StoreError if it is not one vlb-gym writes)."""
        rows = self._rows("SELECT plan FROM plan WHERE id = 1")
        if not rows:
            return None
        try:
            return self._validate_plan(rows[0][0])
        except ValidationError as exc:
            raise StoreError(f"{self.path}: the stored plan is not valid "
                             f"({first_error(exc)})") from None

    _validate_plan = staticmethod(plan_from_json)

    def start(self, plan: Plan) -> None:
        """Record ``plan``, or check that the store holds the same one (naming what differs)."""
        stored = self.plan()
        if stored is None:
            if self._rows("SELECT idx FROM episodes LIMIT 1"):
                raise StoreError(f"{self.path}: the store holds episodes but no plan: it is "
                                 "damaged, and no campaign can continue it")
            try:
                self.db.execute("INSERT INTO plan (id, plan) VALUES (1, ?)", (plan.to_json(),))
            except sqlite3.DatabaseError as exc:
                raise StoreError(f"{self.path}: cannot write the plan ({exc})") from None
            return
        old, new = stored.to_dict(), plan.to_dict()
        differ = sorted(k for k in old.keys() | new.keys() if old.get(k) != new.get(k))
        if differ:
            details = "; ".join("{}: stored {}, now {}".format(k, *parting(old.get(k),
                                                                          new.get(k)))
                                for k in differ)
            raise StoreError(f"{self.path} holds another {self.holds} ({details})")

    def done(self) -> set[int]:
        """Indices of the episodes stored."""
        return {row[0] for row in self._rows("SELECT idx FROM episodes")}

    def add(self, result: EpisodeResult) -> None:
        """Store one finished episode (its own transaction: durable once this returns). A store
        of an earlier format says the current one from its first new record on."""
        try:
            if not self._current:
                self.db.execute(f"PRAGMA user_version={CURRENT['store']}")
                self._current = True
            self.db.execute("INSERT INTO episodes (idx, record) VALUES (?, ?)",
                            (result.index, self._encode(result)))
        except sqlite3.DatabaseError as exc:  # a full disk, a file size limit, ...
            raise StoreError(f"{self.path}: cannot store episode {result.index} ({exc}); "
                             "every episode stored before is kept: make room and run the same "
                             "command to resume") from None

    def results(self) -> list[EpisodeResult]:
        """The stored episodes, in index order, each checked against itself and the plan (its
        index below N, its reset seed the one its index gives): StoreError naming the first
        that is not."""
        rows = self._rows("SELECT idx, record FROM episodes ORDER BY idx")
        plan = self.plan() if rows else None
        if rows and plan is None:
            raise StoreError(f"{self.path}: the store holds episodes but no plan: it is damaged")
        results = [self._decode(index, record) for index, record in rows]
        for result in results:
            self._check_against(plan, result)
        return results

    def _check_against(self, plan: Plan, result: EpisodeResult) -> None:
        """StoreError unless episode ``result`` belongs to the campaign of ``plan``."""
        self._belongs(plan.episodes, plan.seed, result)

    def _belongs(self, count: int, seed: int, result: EpisodeResult) -> None:
        """StoreError unless ``result`` is one of the ``count`` episodes of root ``seed``."""
        if result.index >= count:
            raise StoreError(f"{self.path}: stored {self.unit} {result.index} is beyond the "
                             f"{self.holds}'s {count} {self.unit}s: the store was "
                             "edited or damaged")
        if result.seed != episode_seed(seed, result.index):
            raise StoreError(f"{self.path}: stored {self.unit} {result.index} was reset with "
                             f"seed {result.seed}, not the one its index gives: the store was "
                             "edited or damaged")

    def result(self, index: int) -> EpisodeResult | None:
        """Stored episode ``index``, if it is stored."""
        if not 0 <= index < 2**63:  # beyond SQLite's integers: no row can have it
            return None
        rows = self._rows("SELECT idx, record FROM episodes WHERE idx = ?", index)
        return self._decode(*rows[0]) if rows else None

    def _decode(self, index: Any, text: Any) -> EpisodeResult:
        """A stored record, checked (StoreError naming the episode if it is not one vlb-gym
        writes)."""
        return self._checked(episode_from_json, index, text)

    def _checked(self, read: Any, index: Any, text: Any) -> Any:
        """Record ``index`` read by ``read`` (StoreError naming it otherwise); one longer than
        :data:`MAX_RECORD_CHARS` is refused before it is parsed (its objects would take many
        times its size)."""
        if isinstance(text, (str, bytes)) and len(text) > MAX_RECORD_CHARS:
            raise StoreError(f"{self.path}: stored episode {index} is {len(text):,} characters "
                             f"long, more than a record holds (at most {MAX_RECORD_CHARS:,})")
        try:
            record = read(text)
        except (ValidationError, TypeError) as exc:
            message = first_error(exc) if isinstance(exc, ValidationError) else exc
            raise StoreError(f"{self.path}: stored episode {index} is not valid "
                             f"({message})") from None
        if record.index != index:
            raise StoreError(f"{self.path}: stored episode {index} says it is episode "
                             f"{record.index}")
        return record

    @staticmethod
    def _encode(result: EpisodeResult) -> str:
        return json.dumps(result.stored(), separators=(",", ":"))


_COLUMNS = {"plan": [("id", 1), ("plan", 0)], "episodes": [("idx", 1), ("record", 0)]}
"""Each table's columns, with whether each is the primary key (a table rebuilt without its key
could hold an episode twice)."""


def _connect_readonly(path: Path) -> sqlite3.Connection:
    """A read-only connection to ``path`` that never writes beside it: the path percent-encoded
    (``#``, ``?`` and ``%`` are file name characters, not URI syntax), and, when no writer's
    log is there, opened immutable (SQLite would otherwise make ``-shm``/``-wal`` files, and
    fail in a read-only directory)."""
    uri = "file:" + urllib.parse.quote(str(path.absolute()))
    live = Path(f"{path}-wal").exists()
    return sqlite3.connect(uri + ("?mode=ro" if live else "?mode=ro&immutable=1"), uri=True,
                           isolation_level=None)
class ComparisonStore(CampaignStore):
    """The store of a comparison (``vlb compare --store``): its plan, then one record per pair
    (:class:`~.comparison.PairResult`), as a campaign store keeps episodes."""

    application_id = COMPARISON_APPLICATION_ID
    what = "comparison store"
    holds = "comparison"
    unit = "pair"

    _validate_plan = staticmethod(comparison_plan_from_json)

    def _check_against(self, plan: ComparisonPlan, result: PairResult) -> None:
        for side in (result.a, result.b):
            self._belongs(plan.pairs, plan.seed, side)

    def _decode(self, index: Any, text: Any) -> PairResult:
        pair = self._checked(pair_from_json, index, text)
        for side, episode in (("A", pair.a), ("B", pair.b)):
            if episode.index != index:
                raise StoreError(f"{self.path}: stored pair {index} holds episode "
                                 f"{episode.index} of {side}")
        return pair

    @staticmethod
    def _encode(result: PairResult) -> str:
        return json.dumps(result.stored(), separators=(",", ":"))


_KINDS = (CampaignStore, ComparisonStore)


def open_readonly(path: str | Path) -> CampaignStore:
    """The store at ``path``, opened read-only as the kind its header names (a campaign's
    or a comparison's; anything else is refused as not a campaign store)."""
    kind: type[CampaignStore] = CampaignStore
    with contextlib.suppress(sqlite3.DatabaseError, OSError):
        if Path(path).is_file():
            with contextlib.closing(_connect_readonly(Path(path))) as probe:
                (app,) = probe.execute("PRAGMA application_id").fetchone()
            kind = next((k for k in _KINDS if k.application_id == app), CampaignStore)
    return kind(path, readonly=True)
