"""Time VLB-Scoop-v0: wall seconds per episode, simulated-to-wall ratio, and the 59-episode
campaign (scoop_repeatedly, default sensing pose) with 1 and 2 workers.

Usage: python benchmarks/scoop_campaign.py [--episodes 59] [--workers 1 2] [--probe 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import gymnasium as gym
import numpy as np

import vlb_gym  # noqa: F401 - registers the envs
from vlb_gym.envs.scoop.env import DEFAULT_SENSING_POSE
from vlb_gym.verify.campaign import CampaignConfig, run_campaign
from speed_history import machine, record


def probe(episodes: int) -> tuple[float, float]:
    """Median wall seconds and simulated/wall ratio of single scoops from the default pose."""
    env = gym.make("VLB-Scoop-v0")
    walls, ratios = [], []
    for seed in range(episodes):
        env.reset(seed=seed)
        started = time.perf_counter()
        info = env.step(np.array(DEFAULT_SENSING_POSE, dtype=np.float32))[4]
        wall = time.perf_counter() - started
        walls.append(wall)
        ratios.append(info["sim_seconds"] / wall)
    env.close()
    return statistics.median(walls), statistics.median(ratios)


def campaign(episodes: int, workers: int) -> tuple[float, int]:
    """Wall seconds of the paper's campaign (scoop_repeatedly, eps 0.05), and its successes."""
    report = run_campaign(CampaignConfig("VLB-Scoop-v0", "scoop_repeatedly", episodes, 0.05),
                          workers)
    return report["wall_seconds"], report["successes"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=59)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--probe", type=int, default=5, help="episodes for the per-scoop timing")
    args = parser.parse_args()
    print(f"machine: {machine()}, MUJOCO_GL={os.environ.get('MUJOCO_GL')}")
    wall, ratio = probe(args.probe)
    print(f"one scoop: median {wall:.2f} s wall, simulated/wall {ratio:.2f} (over {args.probe} "
          "episodes)")
    for workers in args.workers:
        seconds, successes = campaign(args.episodes, workers)
        print(f"workers={workers}: {args.episodes} episodes, {successes} successes, "
              f"{seconds:.0f} s ({seconds / 60:.1f} min)")
        record("scoop_campaign", {"seconds": round(seconds, 1), "successes": successes,
                                  "one_scoop_s": round(wall, 2)}, None,
               {"workers": workers, "episodes": args.episodes})


if __name__ == "__main__":
    main()
