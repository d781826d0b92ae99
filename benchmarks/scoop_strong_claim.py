"""The scoop campaign that needs a cluster: scoop_repeatedly on VLB-Scoop-v0 for the strong
claim P[success] >= 0.999 at confidence 0.95 (eps = 0.001: 2,995 episodes without a failure),
on the Ray cluster given (or a private local instance), kept in a store so that a killed run
resumes where it stopped.

``--slice K`` runs only the campaign's first K episodes (the same store: a later run without
``--slice`` goes on from there) and prints the measured episodes per core-second with what the
whole campaign would cost at that rate. The store's plan is the full campaign's either way.

Usage: python benchmarks/scoop_strong_claim.py --store scoop_strong.db [--ray-address ADDR]
       [--workers W] [--slice K] [--ray-timeout S]
"""

from __future__ import annotations

import argparse
import os
import platform
import time

from vlb_gym.verify import bounds
from vlb_gym.verify.campaign import Campaign, CampaignConfig
from vlb_gym.verify.ray_connect import RayOptions
from vlb_gym.verify.store import CampaignStore

EPSILON, CONFIDENCE = 0.001, 0.95


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--store", required=True)
    parser.add_argument("--ray-address")
    parser.add_argument("--ray-timeout", type=float, default=30.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--slice", type=int, metavar="K")
    args = parser.parse_args()
    episodes = bounds.min_episodes(EPSILON, CONFIDENCE, 0)
    config = CampaignConfig("VLB-Scoop-v0", "scoop_repeatedly", episodes, EPSILON,
                            1 - CONFIDENCE)
    ray = RayOptions(args.ray_address, args.ray_timeout, 2 * args.ray_timeout)
    print(f"machine: {platform.machine()}, {len(os.sched_getaffinity(0))} cores, Python "
          f"{platform.python_version()}; {episodes} episodes for P >= {1 - EPSILON} at "
          f"{CONFIDENCE}")
    store = CampaignStore(args.store)
    try:
        with Campaign(config) as campaign:
            store.start(campaign.plan)
            done = store.done()
            limit = episodes if args.slice is None else min(args.slice, episodes)
            todo = [i for i in range(limit) if i not in done]
            print(f"{len(done)} episodes stored; running {len(todo)} on {args.workers} Ray "
                  f"actor(s) ({args.ray_address or 'a private local instance'})")
            started = time.perf_counter()
            ran = failures = 0
            for result in campaign.episodes(todo, args.workers, "ray", ray):
                store.add(result)
                ran += 1
                failures += not result.success
            seconds = time.perf_counter() - started
    finally:
        store.close()
    rate = ran / (seconds * args.workers) if ran else 0.0
    print(f"ran {ran} episodes ({failures} failed) in {seconds:.1f} s: "
          f"{ran / seconds if ran else 0:.2f} episodes/s, {rate:.3f} episodes per core-second "
          "(start-up included)")
    if rate:
        left = episodes - len(done) - ran
        print(f"at that rate the {left} episodes left take {left / rate / 3600:.1f} core-hours "
              f"({left / rate / 3600 / 16:.2f} h on 16 cores), extrapolated from this slice")
    if ran + len(done) >= episodes:
        print(f"complete: vlb report {args.store} gives the report")


if __name__ == "__main__":
    main()
