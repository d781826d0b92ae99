"""Per-episode overhead of the campaign store on the grid campaign: the same 2000 episodes of
find_goal_and_oscillate (seed 1) with and without ``--store``, interleaved, for 1 and 2 workers.

Usage: python benchmarks/store_overhead.py [--repeats 3] [--episodes 2000]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import tempfile
import time
from pathlib import Path

from vlb_gym.verify import CampaignConfig, CampaignStore, run_campaign


def seconds(config: CampaignConfig, workers: int, stored: bool) -> float:
    with tempfile.TemporaryDirectory() as folder:
        store = CampaignStore(Path(folder) / "campaign.db") if stored else None
        started = time.perf_counter()
        run_campaign(config, workers, store=store)
        elapsed = time.perf_counter() - started
        if store is not None:
            store.close()
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--episodes", type=int, default=2000)
    args = parser.parse_args()
    print(f"machine: {platform.machine()}, {os.cpu_count()} cpus, Python "
          f"{platform.python_version()}")
    config = CampaignConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", args.episodes, seed=1)
    for workers in (1, 2):
        bare, stored = [], []
        for _ in range(args.repeats):
            bare.append(seconds(config, workers, False))
            stored.append(seconds(config, workers, True))
        b, s = statistics.median(bare), statistics.median(stored)
        print(f"workers={workers}: bare {b:.2f} s, with store {s:.2f} s (median of "
              f"{args.repeats}): {100 * (s / b - 1):+.1f}%, {1e6 * (s - b) / args.episodes:+.0f} "
              "us per episode")


if __name__ == "__main__":
    main()
