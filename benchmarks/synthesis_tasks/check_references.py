"""Evaluate every task's reference behavior and print a table.

    python -m benchmarks.synthesis_tasks.check_references [--episodes N] [--seed S ...]

Exit code 1 if some reference is not verified and done on every episode.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.synthesis_tasks import TASKS, evaluate  # noqa: E402
from vlb_gym.verify.bounds import floor_str  # noqa: E402

HEADER = "task | difficulty | verified | task_done | confidence | seconds"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--seed", type=int, nargs="+", default=[0])
    args = parser.parse_args(argv)
    ok = True
    for seed in args.seed:
        print(f"N = {args.episodes}, seed {seed}, confidence at eps = 0.05")
        print(HEADER.replace("task ", f"{'task':<24}"))
        for task in TASKS:
            started = time.perf_counter()
            out = evaluate(task, task.reference, args.episodes, seed)
            n = out.episodes
            print(f"{task.name:<24}| {task.difficulty:>10} | {out.verified:>4}/{n:<3} "
                  f"| {out.task_done:>5}/{n:<3} | {floor_str(out.confidence):>10} "
                  f"| {time.perf_counter() - started:7.1f}")
            for index, reason in out.failures:
                print(f"    episode {index}: {reason}")
            ok &= out.task_done == out.verified == n
        print()
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
