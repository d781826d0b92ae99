"""Whole ``vlb verify`` processes of this working tree against an older commit, interleaved.

The older commit is checked out in a temporary git worktree (removed afterwards) and run by this
interpreter with that worktree first on ``PYTHONPATH``; each round runs both sides once, this
tree first, so that the machine's load falls on both alike. Prints the median wall and CPU
seconds of each side and their ratio, and appends them to the speed history.

    python benchmarks/against_commit.py 077b528 [--rounds 5] [--episodes 3000]
        [--behavior find_goal_and_oscillate] [--env VLB-GridExplore-v0]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import speed_history

ROOT = speed_history.ROOT
CLI = "from vlb_gym.cli import main; main()"


def run_once(source: Path, arguments: list[str], scratch: Path) -> tuple[float, float, str]:
    """Wall and CPU seconds of one ``vlb`` process importing vlb_gym from ``source``, and its
    report's first line."""
    env = {**os.environ, "PYTHONPATH": str(source), "HOME": str(scratch)}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", CLI, *arguments], cwd=scratch, env=env,
                          capture_output=True, text=True, check=False)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.exit(f"{source}: vlb {' '.join(arguments)} failed:\n{done.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.stdout.splitlines()[0] if done.stdout else ""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("commit", help="the older commit (e.g. 077b528)")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--episodes", type=int, default=3000)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--env", default="VLB-GridExplore-v0")
    parser.add_argument("--behavior", default="find_goal_and_oscillate")
    args = parser.parse_args()
    arguments = ["verify", args.env, "--behavior", args.behavior, "--episodes",
                 str(args.episodes), "--workers", str(args.workers), "--epsilon", "0.01"]
    with tempfile.TemporaryDirectory(prefix="vlb-against-") as tmp:
        old = Path(tmp) / "old"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(old),
                        args.commit], check=True)
        try:
            scratch = Path(tmp) / "scratch"
            scratch.mkdir()
            sides: dict[str, list[tuple[float, float]]] = {"this tree": [], args.commit: []}
            for _ in range(args.rounds):
                for name, source in (("this tree", ROOT), (args.commit, old)):
                    wall, cpu, first = run_once(source, arguments, scratch)
                    sides[name].append((wall, cpu))
                    print(f"{name}: wall {wall:.2f} s, cpu {cpu:.2f} s  ({first})", flush=True)
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(old)],
                           check=False)
    medians = {name: (statistics.median(w for w, _ in runs), statistics.median(c for _, c in runs))
               for name, runs in sides.items()}
    (wall, cpu), (old_wall, old_cpu) = medians["this tree"], medians[args.commit]
    print(f"machine: {speed_history.machine()}")
    print(f"vlb {' '.join(arguments)}, medians of {args.rounds} interleaved rounds: this tree "
          f"wall {wall:.2f} s, cpu {cpu:.2f} s; {args.commit} wall {old_wall:.2f} s, cpu "
          f"{old_cpu:.2f} s; this tree takes {wall / old_wall:.2f}x the wall time "
          f"({cpu / old_cpu:.2f}x the CPU)")
    speed_history.record("against_commit", {"wall_s": round(wall, 3), "cpu_s": round(cpu, 3),
                                            "wall_ratio": round(wall / old_wall, 3)},
                         {"commit": args.commit, "wall_s": round(old_wall, 3),
                          "cpu_s": round(old_cpu, 3)},
                         {"command": "vlb " + " ".join(arguments), "rounds": args.rounds})


if __name__ == "__main__":
    main()
