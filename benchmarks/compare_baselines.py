"""Graphs vs RL baselines on VLB-GridExplore-v0 (same as ``vlb bench compare``).

Usage: python benchmarks/compare_baselines.py [--out results] [--episodes 100] [--budgets ...]
"""

import sys

from vlb_gym.cli import main

if __name__ == "__main__":
    sys.exit(main(["bench", "compare", *sys.argv[1:]]))
