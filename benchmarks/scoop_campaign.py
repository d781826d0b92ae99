"""Time VLB-Scoop-v0: wall seconds per episode, simulated-to-wall ratio, and the 59-episode
campaign (scoop_repeatedly, default sensing pose) with 1 and 2 workers.

Usage: python benchmarks/scoop_campaign.py [--episodes 59] [--workers 1 2] [--probe 5]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

import gymnasium as gym
import numpy as np

import vlb_gym  # noqa: F401 - registers the envs
from vlb_gym.envs.scoop.env import DEFAULT_SENSING_POSE
from vlb_gym.verify.campaign import CampaignConfig, run_campaign


def probe(episodes: int) -> None:
    """Per-episode wall time and simulated/wall ratio of single scoops."""
    env = gym.make("VLB-Scoop-v0")
    walls, ratios = [], []
    for seed in range(episodes):
        env.reset(seed=seed)
        started = time.perf_counter()
        info = env.step(np.array(DEFAULT_SENSING_POSE, dtype=np.float32))[4]
        wall = time.perf_counter() - started
        walls.append(wall)
        ratios.append(info["sim_seconds"] / wall)
    print(f"one scoop: median {statistics.median(walls):.2f} s wall, simulated/wall "
          f"{statistics.median(ratios):.2f} (over {episodes} episodes)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=59)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--probe", type=int, default=5, help="episodes for the per-scoop timing")
    args = parser.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cpus, "
          f"Python {platform.python_version()}, MUJOCO_GL={os.environ.get('MUJOCO_GL')}")
    probe(args.probe)
    for workers in args.workers:
        config = CampaignConfig("VLB-Scoop-v0", "scoop_repeatedly", args.episodes, 0.05)
        report = run_campaign(config, workers)
        print(f"workers={workers}: {report['episodes']} episodes, {report['successes']} "
              f"successes, {report['wall_seconds']:.0f} s ({report['wall_seconds'] / 60:.1f} min)")


if __name__ == "__main__":
    main()
