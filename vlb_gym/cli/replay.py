"""``vlb replay`` and ``vlb render``: one episode again, step by step or filmed."""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path
from typing import Any

import numpy as np

from .common import (UsageError, add_env_kwarg, check_output, count,
                     env_kwargs, env_modules, policy_ref, read_store, untrusted_options)

def _print_step(number: int, step: dict[str, Any]) -> None:
    mark = "ok  " if step["certificate"] else "FAIL"
    node = f"  [node {step['node']}]" if step["node"] else ""
    extra = f"  ({step['reason']})" if step["reason"] else ""
    print(f"{number:4d} {mark} {step['primitive']:<10} {step['param']}{node}{extra}")


def _replay_config(args: argparse.Namespace):
    """The campaign config and reset seed an episode is replayed with, and its stored record
    (None when replaying from a seed on the command line)."""
    from vlb_gym.verify.campaign import CampaignConfig, episode_seed

    if args.episode is None:
        if args.seed is None or not (args.behavior or args.policy):
            raise UsageError("replay ENV_ID needs --behavior or --policy, and --seed (or "
                             "replay STORE --episode K)")
        kwargs = env_kwargs(args.env_kwarg)
        config = CampaignConfig(args.target, policy_ref(args), 1, env_kwargs=kwargs,
                                env_modules=env_modules(args.env_module),
                                stop_on_failure=not args.keep_going)
        seed = args.seed if args.index is None else episode_seed(args.seed, args.index)
        return config, seed, None
    if args.behavior or args.seed is not None or args.index is not None or args.env_kwarg \
            or args.sample:
        raise UsageError("replay STORE --episode K takes the campaign from the store: no "
                         "--behavior, --seed, --index, --env-kwarg or --sample")
    store = read_store(args.target)
    if store.holds != "campaign":
        store.close()
        raise UsageError(f"{args.target}: holds a {store.holds}: replay one side's episode with "
                         "the command its report prints ('vlb report STORE')")
    try:
        plan = store.plan()
        stored = store.result(args.episode)
        count = len(store.done())
    finally:
        store.close()
    if plan is None:
        raise UsageError(f"{args.target}: the store holds no campaign yet")
    if stored is None:
        raise UsageError(f"{args.target}: episode {args.episode} is not stored ({count} of "
                         f"{plan.episodes} episodes are, indices 0 to {plan.episodes - 1})")
    untrusted = untrusted_options(args.target, plan, args)
    if untrusted:
        raise UsageError(f"{args.target}: replaying would run code the store names; a store is "
                         f"data, so name it again to trust it: {' '.join(untrusted)}")
    config = plan.config()
    if args.keep_going:
        config = dataclasses.replace(config, stop_on_failure=False)
    return config, stored.seed, (stored, plan.content_sha256)


def cmd_replay(args: argparse.Namespace) -> int:
    from vlb_gym.reports.gif import write_gif
    from vlb_gym.verify.campaign import build
    from vlb_gym.verify.policies import policy_loader
    from vlb_gym.verify.replay import MAX_REPLAY_PRIMITIVES, changed_since, filmed, store_files

    config, seed, stored = _replay_config(args)
    if args.render:
        try:
            import PIL  # noqa: F401 - checked before the episode runs
        except ImportError:
            raise UsageError("--render needs Pillow: pip install pillow (or the extra "
                             "'scoop')") from None
    try:
        env, policy = build(config, "rgb_array" if args.render else None)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if args.render:
        inputs = policy_loader(config.policy.kind).files(config.policy, policy)
        if stored is not None:
            inputs += store_files(args.target)
        check_output(args.render, inputs, True, "--render")
    if stored is not None:
        record, digest = stored
        now = changed_since(config, policy, digest)
        if now:
            raise UsageError(f"{config.policy.ref} changed since the campaign (content sha256 "
                             f"{now[:12]}..., the store's {digest[:12]}...): the episode cannot "
                             "be replayed")
    limit = None
    if stored is not None:  # as long as the record, whatever step bound the store names
        limit = MAX_REPLAY_PRIMITIVES if args.keep_going else len(stored[0].steps)
    result, frames = filmed(env, policy, config, seed, args.episode or 0, bool(args.render),
                            limit)
    for number, step in enumerate(result.steps, 1):
        _print_step(number, step)
    print(f"rho_B = {result.rho:+d}, finished={result.finished}, primitives={result.primitives}"
          + (f", reason: {result.reason}" if result.reason else ""))
    if args.render:
        written = write_gif(Path(args.render), frames, env.metadata["render_fps"], args.fps)
        print(f"wrote {written} frames to {args.render}")
    env.close()
    if stored is None:
        return 0
    record = stored[0]
    if args.keep_going or result.same_outcome(record):
        print(f"episode {record.index} (seed {seed}) reproduces the stored record"
              if not args.keep_going else "--keep-going: not compared with the stored record")
        return 0
    stored_outcome = record.outcome()
    differ = [k for k, v in result.outcome().items() if stored_outcome[k] != v]
    print(f"vlb replay: episode {record.index} does NOT reproduce the stored record (differs "
          f"in: {', '.join(differ)}); was the env or a package upgraded? versions then: "
          f"see 'vlb report {args.target} --json'", file=sys.stderr)
    return 1


def cmd_render(args: argparse.Namespace) -> int:
    from vlb_gym.reports.gif import write_gif
    from vlb_gym.verify.campaign import CampaignConfig, build
    from vlb_gym.verify.episode import run_episode
    from vlb_gym.verify.policies import policy_loader

    config = CampaignConfig(args.env_id, args.behavior, 1, env_kwargs=env_kwargs(args.env_kwarg),
                            env_modules=env_modules(args.env_module))
    try:
        env, policy = build(config, "rgb_array")
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    loader = policy_loader(config.policy.kind)
    out = check_output(args.out, loader.files(config.policy, policy), True, "--out")
    frames: list[np.ndarray] = []
    env.unwrapped.film(frames.append)  # after reset, after each primitive, and during motion

    def on_step(info: dict | None) -> None:
        if info is not None:
            print(f"{len(env.history):4d} {'ok  ' if info['certificate'] else 'FAIL'} "
                  f"{info['primitive']} "
                  f"{np.round(np.asarray(info['param'], dtype=float), 3).tolist()}")

    result = run_episode(env, policy, args.seed, stop_on_failure=False, on_step=on_step)
    env.unwrapped.film(None)
    written = write_gif(out, frames, env.metadata["render_fps"], args.fps)
    print(f"rho_B = {result.rho:+d}; wrote {written} frames to {out}")
    env.close()
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    r = sub.add_parser("replay", help="re-run one episode step by step",
                       description="Re-run one episode and print every primitive with its "
                       "certificate. 'vlb replay STORE --episode K' takes episode K of a campaign "
                       "kept with --store (policy, env, seed, all from the store) and checks that "
                       "it reproduces the stored record (exit code 1 if not); 'vlb replay ENV_ID "
                       "--behavior B --seed S' replays from a reset seed (as listed in a "
                       "report's failed_episodes).")
    r.add_argument("target", metavar="STORE_OR_ENV_ID",
                   help="a campaign store (with --episode) or an env id, e.g. VLB-GridExplore-v0")
    r.add_argument("--episode", type=count(0), metavar="K",
                   help="the episode of the campaign in STORE to replay")
    chosen = r.add_mutually_exclusive_group()
    chosen.add_argument("--behavior", metavar="NAME_OR_FILE",
                        help="a behavior name (see 'vlb behaviors') or a behavior JSON file")
    chosen.add_argument("--policy", metavar="AGENT.zip",
                        help="a trained agent (a Stable-Baselines3 zip with AGENT.json beside "
                        "it); loading it runs code from the file: load only agents you trust")
    r.add_argument("--sample", action="store_true",
                   help="with --policy: the agent draws its actions (as 'vlb verify --sample')")
    r.add_argument("--seed", type=count(0),
                   help="the episode's reset seed, or the campaign seed with --index")
    r.add_argument("--index", type=count(0), help="episode index within campaign --seed")
    r.add_argument("--keep-going", action="store_true",
                   help="continue after the first failed certificate")
    r.add_argument("--render", metavar="FILE.gif",
                   help="also film the episode into this animated GIF (replaced if it exists)")
    r.add_argument("--fps", type=count(1), default=10,
                   help="frames per second of the --render animation")
    add_env_kwarg(r)
    r.set_defaults(func=cmd_replay)

    w = sub.add_parser("render", help="write one episode of a behavior as an animated GIF",
                       description="Run one episode (reset seed --seed) and write what the "
                       "environment's rgb_array rendering shows as a GIF; environments that film "
                       "their primitives (VLB-Scoop-v0) give the whole motion.")
    w.add_argument("env_id", metavar="ENV_ID", help="e.g. VLB-Scoop-v0")
    w.add_argument("--behavior", required=True, metavar="NAME_OR_FILE",
                   help="a behavior name (see 'vlb behaviors') or a behavior JSON file")
    w.add_argument("--seed", type=count(0), default=0, help="the episode's reset seed")
    w.add_argument("--out", required=True, metavar="FILE.gif",
                   help="the animation (replaced, atomically, if it exists)")
    w.add_argument("--fps", type=count(1), default=10, help="frames per second of the animation")
    add_env_kwarg(w)
    w.set_defaults(func=cmd_render)
