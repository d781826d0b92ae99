"""Do the scoop's speed-ups change its physics? Masses under each physics, seed by seed.

    python benchmarks/scoop_physics.py [--seeds 20] [--physics plain sleeping default] [--workers 1]

The physics (env kwargs ``sleep_tolerance``, ``solver_iterations``, ``solver_tolerance``):
``plain`` every grain simulated at every step, CG capped at 30 iterations, tolerance 1e-6 (the
reference); ``sleeping`` island sleeping at 0.03 with that solver; ``default`` the env's defaults
(sleeping and CG capped at 20 iterations, tolerance 1e-5). For each, runs one scoop from the
default sensing pose on reset seeds ``0 .. seeds-1`` and prints the mean and standard deviation
of the scooped, delivered and spilled masses (grams), the certificates held and the median wall
seconds per scoop; then, for each physics against the first, Welch's t-test, the Mann-Whitney U
test and the two-sample Kolmogorov-Smirnov test (the whole distribution) on each mass (scipy): a
p-value far from 0 says the two samples are within each other's noise. ``--workers`` splits the
seeds between processes (the masses are the same: each scoop depends on its seed alone).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import statistics
import time
from concurrent.futures import ProcessPoolExecutor

import gymnasium as gym
import numpy as np
from scipy import stats

import vlb_gym  # noqa: F401 - registers the envs
from vlb_gym.envs.scoop.env import DEFAULT_SENSING_POSE
from vlb_gym.envs.scoop.scene import DEFAULT_PHYSICS, PLAIN

MASSES = ("mass_scooped", "mass_delivered", "mass_spilled")
PHYSICS = {
    "plain": dataclasses.asdict(PLAIN),
    "sleeping": {**dataclasses.asdict(PLAIN), "sleep_tolerance": DEFAULT_PHYSICS.sleep_tolerance},
    "default": {},
}


def scoop_seeds(physics: str, seeds: list[int]) -> list[tuple[dict[str, float], bool, float]]:
    """For each seed: the masses, whether the certificate held, and the wall seconds."""
    env = gym.make("VLB-Scoop-v0", **PHYSICS[physics])
    out = []
    for seed in seeds:
        env.reset(seed=seed)
        started = time.perf_counter()
        info = env.step(np.array(DEFAULT_SENSING_POSE, dtype=np.float32))[4]
        out.append(({m: info[m] for m in MASSES}, bool(info["certificate"]),
                    time.perf_counter() - started))
    env.close()
    return out


def scoops(physics: str, seeds: int, workers: int = 1
           ) -> tuple[dict[str, np.ndarray], int, float]:
    """Per-seed masses (seed order), certificates held and the median wall seconds of one
    scoop, the seeds split between ``workers`` processes."""
    chunks = [list(range(seeds))[k::workers] for k in range(workers)]
    with ProcessPoolExecutor(workers) as pool:
        parts = list(pool.map(scoop_seeds, [physics] * workers, chunks))
    by_seed = dict(zip([s for chunk in chunks for s in chunk], [r for p in parts for r in p]))
    results = [by_seed[s] for s in range(seeds)]
    masses = {m: np.array([r[0][m] for r in results]) for m in MASSES}
    return masses, sum(r[1] for r in results), statistics.median(r[2] for r in results)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--physics", nargs="+", choices=list(PHYSICS),
                        default=["plain", "sleeping", "default"])
    parser.add_argument("--workers", type=int, default=1)
    args = parser.parse_args()
    if args.seeds < 2 or args.workers < 1:
        parser.error("--seeds takes 2 or more (a spread needs two), --workers 1 or more")
    print(f"machine: {platform.machine()}, {os.cpu_count()} CPUs, Python "
          f"{platform.python_version()}; {args.seeds} scoops per physics (reset seeds 0..)\n")
    print("| physics | scooped g | delivered g | spilled g | certificates | s per scoop |")
    print("|---:|---:|---:|---:|---:|---:|")
    results = {}
    for physics in args.physics:
        masses, held, wall = results[physics] = scoops(physics, args.seeds, args.workers)
        cells = " | ".join(f"{masses[m].mean():.1f} +- {masses[m].std(ddof=1):.1f}"
                           for m in MASSES)
        print(f"| {physics} | {cells} | {held}/{args.seeds} | {wall:.2f} |", flush=True)
    reference = args.physics[0]
    print(f"\np-values against {reference} (Welch t / Mann-Whitney U / Kolmogorov-Smirnov):\n")
    print("| physics | scooped | delivered | spilled |\n|---|---:|---:|---:|")
    for physics in args.physics[1:]:
        cells = []
        for m in MASSES:
            a, b = results[reference][0][m], results[physics][0][m]
            welch = stats.ttest_ind(a, b, equal_var=False).pvalue
            rank = stats.mannwhitneyu(a, b).pvalue
            shape = stats.ks_2samp(a, b).pvalue
            cells.append(f"{welch:.2f} / {rank:.2f} / {shape:.2f}")
        print(f"| {physics} | {' | '.join(cells)} |")


if __name__ == "__main__":
    main()
