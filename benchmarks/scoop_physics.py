"""Do the scoop's speed-ups change its physics? Masses under each physics, seed by seed.

    python benchmarks/scoop_physics.py [--seeds 20] [--physics plain sleeping default]

The physics (env kwargs ``sleep_tolerance``, ``solver_iterations``, ``solver_tolerance``):
``plain`` every grain simulated at every step, CG capped at 30 iterations, tolerance 1e-6 (the
reference); ``sleeping`` island sleeping at 0.03 with that solver; ``default`` the env's defaults
(sleeping and CG capped at 20 iterations, tolerance 1e-5). For each, runs one scoop from the
default sensing pose on reset seeds ``0 .. seeds-1`` and prints the mean and standard deviation
of the scooped, delivered and spilled masses (grams), the certificates held and the median wall
seconds per scoop; then, for each physics against the first, Welch's t-test and the Mann-Whitney U
test on each mass (scipy): a p-value far from 0 says the two samples are within each other's
noise.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import statistics
import time

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


def scoops(physics: str, seeds: int) -> tuple[dict[str, np.ndarray], int, float]:
    """Per-seed masses, certificates held and the median wall seconds of one scoop."""
    env = gym.make("VLB-Scoop-v0", **PHYSICS[physics])
    masses: dict[str, list[float]] = {m: [] for m in MASSES}
    held, walls = 0, []
    for seed in range(seeds):
        env.reset(seed=seed)
        started = time.perf_counter()
        info = env.step(np.array(DEFAULT_SENSING_POSE, dtype=np.float32))[4]
        walls.append(time.perf_counter() - started)
        held += bool(info["certificate"])
        for m in MASSES:
            masses[m].append(info[m])
    env.close()
    return {m: np.array(v) for m, v in masses.items()}, held, statistics.median(walls)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--physics", nargs="+", choices=list(PHYSICS),
                        default=["plain", "sleeping", "default"])
    args = parser.parse_args()
    print(f"machine: {platform.machine()}, {os.cpu_count()} CPUs, Python "
          f"{platform.python_version()}; {args.seeds} scoops per physics (reset seeds 0..)\n")
    print("| physics | scooped g | delivered g | spilled g | certificates | s per scoop |")
    print("|---:|---:|---:|---:|---:|---:|")
    results = {}
    for physics in args.physics:
        masses, held, wall = results[physics] = scoops(physics, args.seeds)
        cells = " | ".join(f"{masses[m].mean():.1f} +- {masses[m].std(ddof=1):.1f}"
                           for m in MASSES)
        print(f"| {physics} | {cells} | {held}/{args.seeds} | {wall:.2f} |", flush=True)
    reference = args.physics[0]
    print(f"\np-values against {reference} (Welch t / Mann-Whitney U):\n")
    print("| physics | scooped | delivered | spilled |\n|---|---:|---:|---:|")
    for physics in args.physics[1:]:
        cells = []
        for m in MASSES:
            a, b = results[reference][0][m], results[physics][0][m]
            welch = stats.ttest_ind(a, b, equal_var=False).pvalue
            rank = stats.mannwhitneyu(a, b).pvalue
            cells.append(f"{welch:.2f} / {rank:.2f}")
        print(f"| {physics} | {' | '.join(cells)} |")


if __name__ == "__main__":
    main()
