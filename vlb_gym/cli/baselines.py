"""``vlb baseline train`` and ``vlb bench compare``: RL agents and the comparison."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from .common import UsageError, clamp_workers, count, fraction


def cmd_baseline_train(args: argparse.Namespace) -> int:
    from vlb_gym.baselines.configs import TASKS, check_observation
    from vlb_gym.baselines.train import train

    task = TASKS[args.task]
    if task.env_id != args.env_id:
        raise UsageError(f"task {args.task} belongs to {task.env_id}, not {args.env_id}")
    try:
        check_observation(args.algo, args.observation, "--observation: ")
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    started = time.perf_counter()
    saved = train(task, args.algo, Path(args.out), args.seed, args.n_envs,
                  tuple(args.budgets) if args.budgets else None,
                  Path(args.tensorboard) if args.tensorboard else None, verbose=args.verbose,
                  observation=args.observation, bonus=args.bonus,
                  subprocesses=args.subprocesses)
    print(f"trained {args.algo} on {args.task} in {time.perf_counter() - started:.0f} s")
    for path in saved:
        print(f"  saved {path}  (verify: vlb verify {task.task_id} --policy {path} "
              "--episodes 100 --epsilon 0.05)")
    return 0


def cmd_bench_compare(args: argparse.Namespace) -> int:
    from vlb_gym.baselines.compare import compare

    started = time.perf_counter()
    workers = clamp_workers(args.workers, args.episodes, "bench compare")
    compare(Path(args.out), tuple(args.tasks), args.episodes, args.seed, tuple(args.agents),
            args.seeds, tuple(args.budgets) if args.budgets else None, args.n_envs, workers,
            args.subprocesses, args.reuse, tuple(dict.fromkeys(args.acting)),
            clamp_workers(args.jobs, len(args.tasks) * len(args.agents) * args.seeds,
                          "bench compare", "--jobs", "training run(s)"))
    print(f"wrote {args.out}/compare.md and compare.png in {time.perf_counter() - started:.0f} s")
    print(Path(args.out, "compare.md").read_text())
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    from vlb_gym.baselines.configs import (ACTING, ALGORITHMS, DEFAULT_AGENTS, DEFAULT_TASKS,
                                           OBSERVATIONS, TASKS, AgentSpec)

    def agent_spec(text: str) -> AgentSpec:
        try:
            return AgentSpec.parse(text)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    t = sub.add_parser("baseline", help="train Stable-Baselines3 agents (extra rl)")
    tsub = t.add_subparsers(dest="baseline_command", required=True, metavar="COMMAND")
    tt = tsub.add_parser("train", help="train an agent on a task and save checkpoints",
                         description="Train PPO, A2C or MaskablePPO (invalid-action masking) on a "
                         "task, on vectorized envs, logging to the SB3 logger (and TensorBoard "
                         "with --tensorboard); saves AGENT.zip + AGENT.json at every budget.")
    tt.add_argument("env_id", metavar="ENV_ID", help="the task's environment, e.g. "
                    "VLB-GridExplore-v0")
    tt.add_argument("--task", required=True, choices=sorted(TASKS), help="what to learn")
    tt.add_argument("--algo", required=True, choices=ALGORITHMS, help="the RL algorithm")
    tt.add_argument("--budgets", type=count(1), nargs="+", metavar="STEPS",
                    help="checkpoints in environment steps (default: the task's)")
    tt.add_argument("--observation", choices=OBSERVATIONS, default="flat",
                    help="flat: the env's observation (MultiInputPolicy); image: the label map "
                    "as an image through a small CNN; spatial: the image through a fully "
                    "convolutional policy with a spatial action head (maskable_ppo only)")
    tt.add_argument("--bonus", type=fraction, default=0.0, metavar="B",
                    help="exploration bonus per newly labelled cell, for training only (never "
                    "in rho_B); default 0")
    tt.add_argument("--seed", type=count(0), default=0, help="training seed")
    tt.add_argument("--subprocesses", action="store_true",
                    help="step the --n-envs envs in worker processes (SubprocVecEnv)")
    tt.add_argument("--n-envs", type=count(1), default=4, metavar="N",
                    help="vectorized environments")
    tt.add_argument("--out", default="agents", metavar="DIR", help="where checkpoints go")
    tt.add_argument("--tensorboard", metavar="DIR", help="also log to TensorBoard here")
    tt.add_argument("--verbose", type=int, default=0, choices=[0, 1, 2],
                    help="SB3 verbosity")
    tt.set_defaults(func=cmd_baseline_train)

    c = sub.add_parser("bench", help="benchmarks")
    csub = c.add_subparsers(dest="bench_command", required=True, metavar="COMMAND")
    cc = csub.add_parser("compare", help="graphs vs RL agents on the same footing",
                         description="For each task: the hand-written graph, the synthesized "
                         "graph (scripted paper replies) and RL agents (each configuration, "
                         "--seeds training seeds, every budget), verified on the same N "
                         "episodes and seeds; writes tables (IQM across seeds with bootstrap "
                         "intervals, episodes needed to certify), CSV, JSON, learning curves "
                         "and the agents' manifest to --out.")
    cc.add_argument("--out", default="results", metavar="DIR",
                    help="where the table, the plot and the agents go")
    cc.add_argument("--tasks", nargs="+", default=list(DEFAULT_TASKS), choices=sorted(TASKS),
                    metavar="TASK", help=f"tasks to compare: {', '.join(sorted(TASKS))}")
    cc.add_argument("--agents", nargs="+", type=agent_spec, default=list(DEFAULT_AGENTS),
                    metavar="ALGO[:OBS[:BONUS]]",
                    help=f"RL configurations: algorithm ({', '.join(ALGORITHMS)}), "
                    "observation (flat, image or spatial) and exploration bonus")
    cc.add_argument("--seeds", type=count(1), default=3, metavar="N",
                    help="training seeds per configuration: --seed .. --seed + N - 1")
    cc.add_argument("--reuse", action="store_true",
                    help="verify the agents of OUT/agents/manifest.json again instead of "
                    "training them (those missing are trained); loading an agent runs code "
                    "from its file (pickle): reuse only agents you trust")
    cc.add_argument("--subprocesses", action="store_true",
                    help="step the --n-envs training envs in worker processes")
    cc.add_argument("--jobs", type=count(1), default=1, metavar="N",
                    help="training runs at once, each in a worker process, the CPUs' torch "
                    "threads shared out (at most one per CPU)")
    cc.add_argument("--acting", nargs="+", choices=ACTING, default=list(ACTING),
                    help="how agents act when verified: greedy (the most likely action), "
                    "sampled (drawn from the policy, seeded per episode)")
    cc.add_argument("--episodes", type=count(1), default=100, metavar="N",
                    help="verification episodes per graph and agent")
    cc.add_argument("--budgets", type=count(1), nargs="+", metavar="STEPS",
                    help="training checkpoints in environment steps (default: each task's)")
    cc.add_argument("--seed", type=count(0), default=0,
                    help="first training seed, and the seed of the verification campaigns")
    cc.add_argument("--n-envs", type=count(1), default=4, metavar="N",
                    help="vectorized environments in training")
    cc.add_argument("--workers", type=count(1), default=1, metavar="N",
                    help="verification worker processes")
    cc.set_defaults(func=cmd_bench_compare)
