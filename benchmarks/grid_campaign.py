"""Time the paper's full exploration campaign: 100 episodes (seed 0) + 2000 episodes (seed 1),
side by side with the same study hand-coded (``grid_reference.py``).

For each worker count, ``--repeats`` rounds, each timing the campaign of ``vlb verify`` and then
the hand-coded loop on as many processes (the 2100 episodes split between them); prints the
medians, episodes per second, and the ratio of the two measured in the same rounds, with the
machine.

Usage: python benchmarks/grid_campaign.py [--repeats 3] [--workers 1 2]
"""

from __future__ import annotations

import argparse
import statistics
import time
from multiprocessing import get_context

import grid_reference
from speed_history import machine, record

from vlb_gym.verify.campaign import CampaignConfig, run_campaign

BEHAVIOR = "find_goal_and_oscillate"
CAMPAIGNS = ((100, 0), (2000, 1))  # (episodes, campaign seed): the paper's two
EPISODES = sum(n for n, _ in CAMPAIGNS)


def campaign_seconds(workers: int) -> tuple[float, int]:
    """Wall seconds of the paper's two campaigns on ``workers`` workers, and the successes."""
    started = time.perf_counter()
    successes = 0
    for n, seed in CAMPAIGNS:
        report = run_campaign(CampaignConfig("VLB-GridExplore-v0", BEHAVIOR, n, seed=seed),
                              workers)
        successes += report["successes"]
    return time.perf_counter() - started, successes


def reference_seconds(processes: int) -> tuple[float, int]:
    """Wall seconds of the hand-coded loop over as many episodes on ``processes`` processes."""
    shares = [(EPISODES // processes + (i < EPISODES % processes), i) for i in range(processes)]
    started = time.perf_counter()
    if processes == 1:
        successes = grid_reference.run(*shares[0])[0]
    else:
        with get_context("forkserver").Pool(processes) as pool:
            successes = sum(s for s, _ in pool.starmap(grid_reference.run, shares))
    return time.perf_counter() - started, successes


def compare(workers: int, repeats: int) -> dict[str, float]:
    """Medians over interleaved rounds: framework and reference seconds, episodes/s, ratio."""
    ours, theirs, ratios = [], [], []
    successes = reference_successes = 0
    for _ in range(repeats):
        seconds, successes = campaign_seconds(workers)
        reference, reference_successes = reference_seconds(workers)
        ours.append(seconds)
        theirs.append(reference)
        ratios.append(reference / seconds)
    return {"seconds": statistics.median(ours), "reference": statistics.median(theirs),
            "ratio": statistics.median(ratios), "successes": successes,
            "reference_successes": reference_successes, "runs": ours}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args()
    print(f"machine: {machine()}")
    for workers in args.workers:
        r = compare(workers, args.repeats)
        print(f"workers={workers}: {EPISODES} episodes ({r['successes']} successes) in median "
              f"{r['seconds']:.2f} s -> {EPISODES / r['seconds']:.0f} episodes/s (runs: "
              f"{', '.join(f'{s:.2f}' for s in r['runs'])} s); hand-coded "
              f"{r['reference']:.2f} s ({r['reference_successes']} successes) -> "
              f"{EPISODES / r['reference']:.0f} episodes/s; {r['ratio']:.2f}x the hand-coded loop")
        record("grid_campaign", {"seconds": round(r["seconds"], 3),
                                 "episodes_per_s": round(EPISODES / r["seconds"]),
                                 "ratio": round(r["ratio"], 2)},
               {"hand_coded_seconds": round(r["reference"], 3)},
               {"workers": workers, "episodes": EPISODES, "repeats": args.repeats})


if __name__ == "__main__":
    main()
