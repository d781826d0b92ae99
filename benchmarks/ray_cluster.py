"""Throughput of grid campaigns on a local two-node Ray cluster against the process backend.

A cluster is started here (``ray.cluster_utils.Cluster`` on this machine: a head node without
CPUs and two worker nodes of one CPU each, so that both actors live on worker nodes), and the
driver connects to it as ``vlb verify --ray-address`` does. Each backend runs a small and a
large campaign (find_goal_and_oscillate on VLB-GridExplore-v0, 2 workers), interleaved,
``--repeats`` times; the fixed cost is the small campaign's wall time, the rate is the large
campaign's extra episodes over its extra time. Figures are medians; the results are written as
JSON (``--out``).

Usage: python benchmarks/ray_cluster.py [--repeats 3] [--small 20] [--large 4000]
       [--out benchmarks/results/speed/ray_cluster.json]
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import platform
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import ray
from ray.cluster_utils import Cluster

from vlb_gym.verify.campaign import Campaign, CampaignConfig
from vlb_gym.verify.ray_connect import RayOptions


def timed(episodes: int, backend: str, ray_options: RayOptions | None) -> float:
    config = CampaignConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", episodes)
    started = time.perf_counter()
    with Campaign(config) as campaign:
        report = campaign.run(2, backend=backend, ray=ray_options)
    assert report["episodes"] == episodes
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--small", type=int, default=20)
    parser.add_argument("--large", type=int, default=4000)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    folder = tempfile.mkdtemp(prefix="vb", dir="/tmp")  # AF_UNIX paths are short
    cluster = Cluster(initialize_head=True, head_node_args={
        "num_cpus": 0, "temp_dir": folder, "include_dashboard": False})
    try:
        for _ in range(2):
            cluster.add_node(num_cpus=1)
        cluster.wait_for_nodes()
        ray.init(address=cluster.address, log_to_driver=False, logging_level=logging.ERROR)
        on_cluster = RayOptions(cluster.address)
        runs: dict[str, dict[str, list[float]]] = {
            b: {"small": [], "large": []} for b in ("process", "ray")}
        for _ in range(args.repeats):
            for backend in runs:
                options = on_cluster if backend == "ray" else None
                runs[backend]["small"].append(timed(args.small, backend, options))
                runs[backend]["large"].append(timed(args.large, backend, options))
        ray.shutdown()
    finally:
        cluster.shutdown()
        shutil.rmtree(folder, ignore_errors=True)
    result = {"machine": f"{platform.machine()}, {len(os.sched_getaffinity(0))} cores, "
                         f"Python {platform.python_version()}, Ray {ray.__version__}",
              "cluster": "local: a head without CPUs, two worker nodes of 1 CPU", "workers": 2,
              "small": args.small, "large": args.large, "repeats": args.repeats}
    for backend, times in runs.items():
        small, large = (statistics.median(times[k]) for k in ("small", "large"))
        result[backend] = {"fixed_seconds": round(small, 2),
                           "episodes_per_second": round((args.large - args.small)
                                                        / (large - small), 1),
                           "small_seconds": [round(t, 2) for t in times["small"]],
                           "large_seconds": [round(t, 2) for t in times["large"]]}
        rate = result[backend]["episodes_per_second"]
        print(f"{backend:8s} fixed cost {small:5.2f} s, {rate:7.1f} episodes/s "
              f"(medians of {args.repeats})")
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
