"""One file of every speed figure the benchmarks measured: ``results/speed/history.jsonl``.

Each line is one measurement: the benchmark, what it measured (``figures``: seconds, rates,
ratios), the paired reference it was measured beside in the same run (the hand-coded loop, an
older commit), the commit measured (``+dirty`` when the working tree differed from it), the
machine and the date. A regression shows in review as a line whose figures fell; every change to
a measured path quotes the lines it added.

    python benchmarks/speed_history.py [--last 10]     # the latest lines, one per row
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
HISTORY = ROOT / "benchmarks" / "results" / "speed" / "history.jsonl"


def machine() -> str:
    """The machine in a line: processor, cores, Python, kernel."""
    return (f"{platform.processor() or platform.machine()}, {os.cpu_count()} cpus, "
            f"Python {platform.python_version()}, {platform.system()} {platform.release()}")


def commit(root: Path = ROOT) -> str:
    """The commit checked out at ``root``, with ``+dirty`` if tracked files differ from it."""
    def git(*args: str) -> str:
        return subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True,
                              check=False).stdout.strip()
    head = git("rev-parse", "--short=12", "HEAD") or "unknown"
    return head + ("+dirty" if git("status", "--porcelain", "--untracked-files=no") else "")


def record(benchmark: str, figures: dict[str, Any], reference: dict[str, Any] | None = None,
           settings: dict[str, Any] | None = None, path: Path = HISTORY) -> dict[str, Any]:
    """Append one measurement to the history (and return it)."""
    entry = {"benchmark": benchmark, "commit": commit(), "machine": machine(),
             "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
             "settings": settings or {}, "figures": figures, "reference": reference or {}}
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("a", encoding="utf-8") as out:
        out.write(json.dumps(entry, sort_keys=True) + "\n")
    return entry


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--last", type=int, default=10, help="how many lines (default 10)")
    args = parser.parse_args()
    lines = HISTORY.read_text(encoding="utf-8").splitlines() if HISTORY.exists() else []
    for line in lines[-args.last:]:
        entry = json.loads(line)
        figures = ", ".join(f"{k} {v}" for k, v in entry["figures"].items())
        reference = ", ".join(f"{k} {v}" for k, v in entry["reference"].items())
        print(f"{entry['date'][:10]} {entry['commit']} {entry['benchmark']}: {figures}"
              + (f" | beside {reference}" if reference else ""))


if __name__ == "__main__":
    main()
