"""Every headline figure in one table, with the machine: what an issue's note quotes.

    python benchmarks/headline.py [--repeats 3] [--scoop-episodes 59] [--skip scoop ...]

- grid: the paper's Behavior-2 campaign (2,100 episodes) with 1 and 2 workers, and the same
  study hand-coded (``grid_reference.py``) on as many processes, interleaved: episodes/s and
  their ratio (``grid_campaign.py``);
- scoop: median seconds of one scoop (5 seeds), and the 59-episode campaign on 2 workers
  (``scoop_campaign.py``);
- rl: env steps/s of the RL training env with random admissible actions, flat and image
  observations (``rl_throughput.py``);
- cli: seconds from start to exit of ``vlb --help`` and of ``vlb plan`` in a fresh interpreter.

Figures are medians of ``--repeats`` runs; the scoop campaign (about 45 s a run) runs
``--scoop-repeats`` times, once by default.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

PARTS = ("grid", "scoop", "rl", "cli")
CLI = (["--help"], ["plan", "--epsilon", "0.05", "--confidence", "0.95"])


# Each part imports its benchmark when it runs: every campaign worker imports this script again
# (multiprocessing's workers import the main module), and with MuJoCo and the RL stack imported
# at its top the 2-worker grid campaign took 10-15% longer.


def grid(repeats: int) -> list[tuple[str, str]]:
    import grid_campaign

    rows = []
    for workers in (1, 2):
        r = grid_campaign.compare(workers, repeats)
        rows.append((f"grid campaign, {workers} worker(s)",
                     f"{grid_campaign.EPISODES / r['seconds']:,.0f} episodes/s "
                     f"({r['successes']}/{grid_campaign.EPISODES}); hand-coded "
                     f"{grid_campaign.EPISODES / r['reference']:,.0f} episodes/s; "
                     f"**{r['ratio']:.2f}x**"))
    return rows


def scoop(repeats: int, episodes: int) -> list[tuple[str, str]]:
    import scoop_campaign

    wall, ratio = scoop_campaign.probe(5)
    runs = [scoop_campaign.campaign(episodes, 2) for _ in range(repeats)]
    seconds = statistics.median(s for s, _ in runs)
    return [("scoop, one episode", f"{wall:.2f} s (simulated/wall {ratio:.2f})"),
            (f"scoop campaign, {episodes} episodes, 2 workers",
             f"{seconds:.0f} s ({runs[0][1]}/{episodes}; runs: "
             f"{', '.join(f'{s:.0f}' for s, _ in runs)} s)")]


def rl(repeats: int) -> list[tuple[str, str]]:
    import rl_throughput

    rows = []
    for observation in ("flat", "image"):
        rates = [rl_throughput.steps_per_second("find_goal", observation, 0.0, 3000, seed)
                 for seed in range(repeats)]
        rows.append((f"RL env, find_goal, {observation}",
                     f"{statistics.median(rates):,.0f} env steps/s"))
    return rows


def cli(repeats: int) -> list[tuple[str, str]]:
    rows = []
    for argv in CLI:
        times = []
        for _ in range(max(repeats, 5)):
            started = time.perf_counter()
            subprocess.run([sys.executable, "-m", "vlb_gym.cli", *argv], check=True,
                           capture_output=True)
            times.append(time.perf_counter() - started)
        rows.append((f"CLI start-up, vlb {' '.join(argv)}", f"{statistics.median(times):.2f} s"))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--scoop-repeats", type=int, default=1)
    parser.add_argument("--scoop-episodes", type=int, default=59)
    parser.add_argument("--skip", nargs="+", choices=PARTS, default=[])
    args = parser.parse_args()
    from speed_history import machine

    print(f"machine: {machine()}; medians of {args.repeats} runs\n")
    print("| figure | value |\n|---|---|", flush=True)
    parts = {"grid": lambda: grid(args.repeats),
             "scoop": lambda: scoop(args.scoop_repeats, args.scoop_episodes),
             "rl": lambda: rl(args.repeats), "cli": lambda: cli(args.repeats)}
    for name in PARTS:
        if name not in args.skip:
            for figure, value in parts[name]():
                print(f"| {figure} | {value} |", flush=True)


if __name__ == "__main__":
    main()
