"""Time the paper's full exploration campaign: 100 episodes (seed 0) + 2000 episodes (seed 1).

Prints episodes per second for 1 and 2 workers (median over --repeats) and the machine.
Usage: python benchmarks/grid_campaign.py [--repeats 3] [--workers 1 2]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

from vlb_gym.verify.campaign import CampaignConfig, run_campaign

BEHAVIOR = "find_goal_and_oscillate"


def campaign_seconds(workers: int) -> tuple[float, int, int]:
    started = time.perf_counter()
    episodes = successes = 0
    for n, seed in ((100, 0), (2000, 1)):
        report = run_campaign(CampaignConfig("VLB-GridExplore-v0", BEHAVIOR, n, seed=seed), workers)
        episodes += report["episodes"]
        successes += report["successes"]
    return time.perf_counter() - started, episodes, successes


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cpus, "
          f"Python {platform.python_version()}, {platform.system()} {platform.release()}")
    for workers in args.workers:
        runs = [campaign_seconds(workers) for _ in range(args.repeats)]
        seconds = statistics.median(r[0] for r in runs)
        episodes, successes = runs[0][1], runs[0][2]
        print(f"workers={workers}: {episodes} episodes ({successes} successes) in median "
              f"{seconds:.2f} s -> {episodes / seconds:.0f} episodes/s "
              f"(runs: {', '.join(f'{r[0]:.2f}' for r in runs)} s)")


if __name__ == "__main__":
    main()
