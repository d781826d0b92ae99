"""Speed of the behavior search: programs screened per second, time to find, time to certify.

    python benchmarks/search_speed.py [--tasks FILE.py] [--repeats 3] [--out FILE.md]

For every task with a faithful promise (default: the 13 development tasks), the search of
:mod:`vlb_gym.abstractor.search` runs ``--repeats`` times (screening root seeds 0, 1, ...), in
this one process: the seconds to build its grammar (the typed terms, observational
equivalence on the decision contexts), the programs it built and ran on the probe episodes,
those left after observational equivalence, the seconds to find a behavior, and the rate of
programs per second over the whole search; then one certification campaign (112 episodes,
the engine's fixed-N campaign in process). Medians over the repeats; the machine is named.
"""

from __future__ import annotations

import argparse
import importlib.util
import platform
import statistics
import sys
import time
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPOSITORY))

from benchmarks.speed_history import record  # noqa: E402
from benchmarks.synthesis_tasks import TASKS  # noqa: E402
from vlb_gym.abstractor.certify import certify  # noqa: E402
from vlb_gym.abstractor.search import Search  # noqa: E402
from vlb_gym.core.library import BehaviorLibrary  # noqa: E402
from vlb_gym.core.spec import Promise  # noqa: E402


def load(path: Path | None) -> list:
    if path is None:
        return list(TASKS)
    spec = importlib.util.spec_from_file_location("tasks", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return list(module.TASKS)


def measure(task, seed: int, library: Path, time_limit: float) -> dict:
    search = Search(task.env_id, Promise(expr=task.promise), task.description,
                    screen_seed=seed, library=BehaviorLibrary(library) if task.library else None)
    try:
        started = time.perf_counter()
        search.statements()
        grammar = time.perf_counter() - started
        found = search.find(time_limit)
        row = {"grammar": grammar, "find": search.tally.seconds, "built": search.tally.built,
               "distinct": search.tally.distinct, "rate": search.tally.rate,
               "found": found is not None, "certify": None}
        if found is not None and seed == 0:
            document = search.document(found, task.name, task.description)
            started = time.perf_counter()
            certify(task.env_id, document, 1)
            row["certify"] = time.perf_counter() - started
        return row
    finally:
        search.close()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tasks", type=Path)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--time-limit", type=float, default=240.0)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv)
    library = Path(__import__("tempfile").mkdtemp(prefix="no-user-behaviors-"))
    lines = [f"`python benchmarks/search_speed.py{' --tasks ' + str(args.tasks) if args.tasks else ''}"
             f" --repeats {args.repeats} --time-limit {args.time_limit:g}`: {platform.machine()}, "
             f"{__import__('os').cpu_count()} CPUs, Python {platform.python_version()}; "
             f"medians of {args.repeats} searches (screening seeds 0..{args.repeats - 1}), one "
             "process, one core", "",
             "| task | grammar s | find s | programs built | distinct behaviors | programs/s "
             "| found | certify s (112 episodes) |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    rates = {}
    for task in load(args.tasks):
        if not task.promise:
            continue
        rows = [measure(task, seed, library, args.time_limit) for seed in range(args.repeats)]
        med = {k: statistics.median(r[k] for r in rows)
               for k in ("grammar", "find", "built", "distinct", "rate")}
        certified = rows[0]["certify"]
        lines.append(f"| {task.name} | {med['grammar']:.1f} | {med['find']:.1f} | "
                     f"{med['built']:.0f} | {med['distinct']:.0f} | {med['rate']:.0f} | "
                     f"{sum(r['found'] for r in rows)}/{len(rows)} | "
                     f"{'-' if certified is None else f'{certified:.1f}'} |")
        print(lines[-1], flush=True)
        rates[task.name] = round(med["rate"])
    record("search_speed", {"median_programs_per_s": statistics.median(rates.values()),
                            "programs_per_s": rates}, None,
           {"tasks": str(args.tasks or "development"), "repeats": args.repeats,
            "time_limit": args.time_limit})
    text = "\n".join(lines) + "\n"
    if args.out:
        args.out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
