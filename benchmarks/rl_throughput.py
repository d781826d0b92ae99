"""RL environment throughput: env steps/s of the training stack with random admissible actions.

    python benchmarks/rl_throughput.py [--steps 5000] [--repeats 3] [--train-steps 20000]

For each task and observation (flat, image; the image with the exploration bonus too), the
training env of ``vlb baseline train`` (:func:`vlb_gym.baselines.train.make_env`) is stepped
with uniformly random admissible actions (its own masks), resetting when an episode ends; prints
the median steps/s of ``--repeats`` runs, with the machine. This is the ceiling of training
throughput: PPO's updates come on top.

With ``--train-steps N``, then MaskablePPO with the spatial policy trains for N steps on
``find_goal`` (4 envs) stepped in this process (DummyVecEnv) and in worker processes
(SubprocVecEnv), alternately, ``--repeats`` times each: the median env steps/s of training.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

import vlb_gym  # noqa: F401  (registers the environments)
from vlb_gym.baselines.configs import TASKS
from vlb_gym.baselines.train import make_env

SETUPS = (("flat", 0.0), ("image", 0.0), ("image", 0.02))


def steps_per_second(task: str, observation: str, bonus: float, steps: int, seed: int) -> float:
    config = TASKS[task]
    env = make_env(config.task_id, config.env_kwargs, observation, bonus)
    rng = np.random.default_rng(seed)
    env.reset(seed=seed)
    started = time.perf_counter()
    for _ in range(steps):
        action = rng.choice(np.flatnonzero(env.action_masks()))
        _, _, terminated, truncated, _ = env.step(int(action))
        if terminated or truncated:
            env.reset()
    elapsed = time.perf_counter() - started
    env.close()
    return steps / elapsed


def training_steps_per_second(steps: int, subprocesses: bool, seed: int) -> float:
    from vlb_gym.baselines.train import train

    with tempfile.TemporaryDirectory() as tmp:
        path, = train(TASKS["find_goal"], "maskable_ppo", Path(tmp), seed=seed, budgets=(steps,),
                      observation="spatial", subprocesses=subprocesses)
        return json.loads(path.with_suffix(".json").read_text())["steps_per_second"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=5000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--train-steps", type=int, default=0)
    args = parser.parse_args()
    print(f"machine: {platform.machine()}, {os.cpu_count()} CPUs, Python "
          f"{platform.python_version()}; {args.steps} steps, median of {args.repeats}\n")
    print("| task | observation | bonus | env steps/s |")
    print("|---|---|---:|---:|")
    for task in TASKS:
        for observation, bonus in SETUPS:
            rates = [steps_per_second(task, observation, bonus, args.steps, seed)
                     for seed in range(args.repeats)]
            print(f"| {task} | {observation} | {bonus:g} | {statistics.median(rates):,.0f} |",
                  flush=True)

    if args.train_steps:
        print("\n| training (maskable_ppo, spatial, 4 envs) | env steps/s |\n|---|---:|")
        rates: dict[bool, list[float]] = {False: [], True: []}
        for seed in range(args.repeats):
            for subprocesses in rates:
                rates[subprocesses].append(
                    training_steps_per_second(args.train_steps, subprocesses, seed))
        for subprocesses, found in rates.items():
            print(f"| {'SubprocVecEnv' if subprocesses else 'DummyVecEnv'} | "
                  f"{statistics.median(found):,.0f} |")


if __name__ == "__main__":
    main()
