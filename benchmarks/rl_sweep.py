"""The hyperparameter sweep behind the RL baselines' settings (``configs.TUNED``).

    python benchmarks/rl_sweep.py [--task find_goal_and_oscillate] [--steps 50000]
        [--agent maskable_ppo:spatial] [--episodes 50] [--out benchmarks/results/rl_sweep.md]

One factor at a time around the base settings (``configs._GRID_HYPER``): each variant changes one
hyperparameter (learning rate, entropy coefficient, rollout length, discount, epochs), then a
second round goes a step further along the best factor and combines the best two; each is
trained with one seed for ``--steps`` env steps and verified on ``--episodes`` episodes
(campaign seed 1000, away from the comparison's 0), acting greedily and by sampling. A full grid
over five factors is 32+ runs; at ~2 min a run on this 2-core machine that is an hour, the
whole comparison's budget. One factor at a time shows which knobs matter at a cost of 2 runs per
factor; the winner of each is kept. Prints and
writes a Markdown table: variant, successes (greedy, sampled), mean primitives, training
seconds. ``--threads`` sets torch's threads (1 lets two sweeps share the two cores).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import tempfile
import time
from pathlib import Path

from vlb_gym.baselines.compare import verify_agent
from vlb_gym.baselines.configs import ACTING, TASKS, AgentSpec
from vlb_gym.baselines.train import train
from vlb_gym.verify.policies import PolicyRef

VARIANTS = {
    "base": {},
    "learning_rate 1e-3": {"learning_rate": 1e-3},
    "learning_rate 1e-4": {"learning_rate": 1e-4},
    "ent_coef 0": {"ent_coef": 0.0},
    "ent_coef 0.05": {"ent_coef": 0.05},
    "n_steps 128": {"n_steps": 128},
    "n_steps 512": {"n_steps": 512},
    "gamma 0.995": {"gamma": 0.995},
    "gamma 0.95": {"gamma": 0.95},
    "n_epochs 4": {"n_epochs": 4},
    # second round: a step further along the best factor, and the best two together
    "learning_rate 3e-3": {"learning_rate": 3e-3},
    "learning_rate 1e-3, gamma 0.995": {"learning_rate": 1e-3, "gamma": 0.995},
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--task", default="find_goal_and_oscillate", choices=sorted(TASKS))
    parser.add_argument("--agent", default="maskable_ppo:spatial", type=AgentSpec.parse)
    parser.add_argument("--steps", type=int, default=50_000)
    parser.add_argument("--episodes", type=int, default=50)
    parser.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--threads", type=int, default=None)
    args = parser.parse_args()
    if args.threads:
        import torch

        torch.set_num_threads(args.threads)
    config, spec = TASKS[args.task], args.agent
    base = config.hyperparameters[spec.algorithm]
    lines = [f"Sweep: {spec.label} on {args.task}, {args.steps} env steps, seed 0, "
             f"verified on {args.episodes} episodes (campaign seed 1000). Base: {base}. "
             f"Machine: {platform.machine()}, {os.cpu_count()} CPUs, Python "
             f"{platform.python_version()}.", "",
             "| variant | greedy | sampled | mean primitives (greedy) | training s |",
             "|---|---:|---:|---:|---:|"]
    print("\n".join(lines), flush=True)
    for variant in args.variants:
        hyper = {**config.hyperparameters, spec.algorithm: {**base, **VARIANTS[variant]}}
        with tempfile.TemporaryDirectory() as tmp:
            started = time.perf_counter()
            path, = train(dataclasses.replace(config, hyperparameters=hyper), spec.algorithm,
                          Path(tmp), budgets=(args.steps,), observation=spec.observation,
                          bonus=spec.bonus)
            seconds = time.perf_counter() - started
            greedy, sampled = (verify_agent(config, PolicyRef(ACTING[how], str(path)),
                                            args.episodes, 1000) for how in ACTING)
        lines.append(f"| {variant} | {greedy['successes']}/{args.episodes} | "
                     f"{sampled['successes']}/{args.episodes} | "
                     f"{greedy['mean_primitives']:.1f} | {seconds:.0f} |")
        print(lines[-1], flush=True)
    if args.out:
        args.out.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
