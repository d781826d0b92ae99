"""The JSONL export of a campaign (``vlb verify --episodes-out``).

Line 1 is the plan (``{"record": "plan", "format": 1, "plan": {...}}``; the format is
:data:`~vlb_gym.core.formats.CURRENT`'s, absent from files written before versions), then one
``{"record": "episode", ...}`` line per episode as it finishes (the fields of
:class:`~.episode.EpisodeResult`), then a closing ``{"record": "end", "complete": ...,
"episodes": ...}`` line. A file without the closing line is a campaign that was killed;
``complete: false`` one that was interrupted.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path
from typing import Any

from vlb_gym.core.files import OutputFileError
from vlb_gym.core.formats import CURRENT, check_format

from .records import EpisodeResult, Plan, plan_from_json


class EpisodesExport:
    """Writes the export at ``path`` (an existing file only with ``overwrite``)."""

    def __init__(self, path: Path, plan: Plan, overwrite: bool = False):
        path.parent.mkdir(parents=True, exist_ok=True)
        self.path = path
        self.written = 0
        self._file = open(path, "w" if overwrite else "x")
        self._line({"record": "plan", "format": CURRENT["export"], "plan": plan.to_dict()})

    def _line(self, data: dict[str, Any]) -> None:
        try:
            self._file.write(json.dumps(data, separators=(",", ":")) + "\n")
            self._file.flush()
        except OSError as exc:
            raise OutputFileError(f"{self.path}: cannot write it ({exc.strerror or exc}); the "
                                  "lines written so far are kept") from None

    def add(self, result: EpisodeResult) -> None:
        self._line({"record": "episode", **result.to_dict()})
        self.written += 1

    def close(self, complete: bool) -> None:
        """Write the closing line (if the file can still be written) and close the file."""
        with contextlib.suppress(OSError):  # a write that fails has said so already
            try:
                if not complete:  # counted in the file: Ctrl-C may fall between a write and
                    self._file.flush()  # the count
                    self.written = self.path.read_bytes().count(b'\n{"record":"episode"')
                self._line({"record": "end", "complete": complete, "episodes": self.written})
            finally:
                with contextlib.suppress(OSError):
                    self._file.close()


def read_export(path: Path) -> tuple[Plan, list[EpisodeResult], dict[str, Any] | None]:
    """The plan, the episodes and the closing line (None if the campaign was killed) of an
    export."""
    plan, episodes, end = None, [], None
    for line in path.read_text().splitlines():
        data = json.loads(line)
        kind = data.pop("record")
        if kind == "plan":
            check_format("export", data.get("format"), f"{path}: line 1")
            plan = plan_from_json(json.dumps(data["plan"]))
        elif kind == "episode":
            episodes.append(EpisodeResult.from_dict(data))
        else:
            end = data
    if plan is None:
        raise ValueError(f"{path}: no plan line: not a vlb verify --episodes-out file")
    return plan, episodes, end
