"""``vlb verify``, ``plan``, ``replay`` and ``render``: campaigns and single episodes."""

from __future__ import annotations

import argparse
import io
import json
import sys
from typing import Any

import gymnasium as gym
import numpy as np

from vlb_gym.core.files import write_atomic
from vlb_gym.wrappers import RobustnessWrapper

from .common import (UsageError, add_env_kwarg, behavior_files, check_env, check_output,
                     clamp_workers, count, env_kwargs, env_modules, probability)


def cmd_verify(args: argparse.Namespace) -> int:
    from vlb_gym.verify.campaign import (CampaignConfig, build, campaign_plan, run_campaign,
                                         run_sequential)

    if args.sequential and args.episodes is not None:
        raise UsageError("--episodes and --sequential exclude each other: a sequential campaign "
                         "stops by itself (cap it with --max-episodes)")
    if not args.sequential and args.episodes is None:
        raise UsageError("the following arguments are required: --episodes (or --sequential)")
    if args.max_episodes is not None and not args.sequential:
        raise UsageError("--max-episodes needs --sequential (a fixed-N campaign runs --episodes)")
    if args.store and args.sequential:
        raise UsageError("--store keeps fixed-N campaigns only (for now); drop --sequential")
    if args.sequential:
        from vlb_gym.verify.sequential import default_max_episodes
        max_episodes = args.max_episodes or default_max_episodes(args.epsilon, args.delta)
    kwargs = env_kwargs(args.env_kwarg)
    if args.policy:
        from vlb_gym.baselines.train import agent_files, policy_env_kwargs
        try:
            env_id, trained = policy_env_kwargs(args.policy)
        except ValueError as exc:
            raise UsageError(str(exc)) from None
        if env_id != args.env_id:
            raise UsageError(f"--policy {args.policy} was trained on {env_id}, not {args.env_id}")
        kwargs = {**trained, **kwargs}
    modules = env_modules(args.env_module)
    check_env(args.env_id, kwargs, modules)
    episodes = max_episodes if args.sequential else args.episodes
    config = CampaignConfig(args.env_id, args.policy or args.behavior, episodes,
                            args.epsilon, args.delta, args.seed, kwargs,
                            stop_on_failure=not args.keep_going, policy=bool(args.policy),
                            env_modules=modules)
    env, policy = build(config)  # compile the behavior here: a bad file fails before any episode
    env.close()
    inputs = agent_files(args.policy) if args.policy else behavior_files(policy.behavior)
    episodes_out = (check_output(args.episodes_out, inputs, args.force, "--episodes-out")
                    if args.episodes_out else None)
    # a report is replaced without --force: atomically, once the campaign is done
    report_out = (check_output(args.report, inputs, True, "--report") if args.report else None)
    if report_out and episodes_out and report_out.resolve() == episodes_out.resolve():
        raise UsageError("--report and --episodes-out name the same file")
    store = plan = None
    if args.store:  # an existing store is resumed: its plan must be this command's
        from vlb_gym.verify.store import CampaignStore, StoreError
        path = check_output(args.store, [*inputs, report_out, episodes_out], True, "--store")
        try:
            store = CampaignStore(path)
        except StoreError as exc:
            raise UsageError(f"--store {exc}") from None
        try:
            plan = campaign_plan(config)
            store.start(plan)
        except StoreError as exc:
            store.close()
            raise UsageError(f"--store {exc}") from None
        if store.done():
            print(f"vlb verify: resuming {path}: {len(store.done())} of {episodes} episodes "
                  "are stored", file=sys.stderr)
    workers = clamp_workers(args.workers, episodes, "verify")
    stream = None
    if episodes_out:
        episodes_out.parent.mkdir(parents=True, exist_ok=True)
        stream = open(episodes_out, "w" if args.force else "x")
    bar = None
    if not args.quiet and sys.stderr.isatty():
        from tqdm import tqdm
        bar = tqdm(total=config.episodes, unit="ep", file=sys.stderr, dynamic_ncols=True)

    def on_episode(result):
        if stream:
            stream.write(json.dumps(result.to_dict()) + "\n")
            stream.flush()
        if bar:
            bar.update()

    try:
        if args.sequential:
            report = run_sequential(config, max_episodes, workers, on_episode)
        else:
            report = run_campaign(config, workers, on_episode, store, plan)
    except KeyboardInterrupt:  # the pool's workers ignore Ctrl-C; leaving run_campaign ends them
        report = None
    finally:
        if bar:
            bar.close()
        if stream:
            stream.close()
        if store:
            store.close()
    if report is None:
        # counted in the file: Ctrl-C may fall between a line's write and any counter's update
        written = episodes_out.read_bytes().count(b"\n") if stream else 0
        kept = f"; {written} episode(s) written to {episodes_out}" if stream else ""
        kept += f"; the store {store.path} keeps every finished episode" if store else ""
        print(f"vlb verify: interrupted{kept}", file=sys.stderr)
        return 130
    if report_out:
        write_atomic(report_out, json.dumps(report, indent=2) + "\n")
    print(summary(report, args.report))
    return 0


def _rate(value: float) -> str:
    return f"{value:.0f}" if value >= 100 else f"{value:.3g}"


def summary(report: dict[str, Any], report_path: str | None = None) -> str:
    """The human-readable outcome of a campaign."""
    from vlb_gym.verify import bounds

    if report.get("mode") == "sequential":
        return _sequential_summary(report, report_path)
    lines = [
        f"{report['env_id']} / {report['behavior']}: {report['episodes']} episodes "
        f"(seed {report['seed']}, {report['workers']} worker(s), {report['wall_seconds']:.1f} s, "
        f"{_rate(report['episodes_per_second'])} episodes/s)",
        f"  successes {report['successes']}/{report['episodes']}, failures {report['failures']}",
        f"  P[success] >= {bounds.one_minus_str(report['epsilon'])} with confidence "
        f"{bounds.floor_str(report['confidence'])}",
        f"  P[success] >= {bounds.floor_str(report['lower_bound'])} at confidence level "
        f"{bounds.one_minus_str(report['delta'])} (one-sided Clopper-Pearson)",
        f"  holds for: {report['sampling_distribution']}",
    ]
    lines += _failures(report, report_path)
    return "\n".join(lines)


def _sequential_summary(report: dict[str, Any], report_path: str | None) -> str:
    from vlb_gym.verify import bounds
    from vlb_gym.verify.campaign import _ceil_str

    eps = bounds.one_minus_str(report["epsilon"])
    level = bounds.one_minus_str(report["delta"])
    a, b = report["prior"]
    decision = report["decision"]
    lines = [
        f"{report['env_id']} / {report['behavior']}: sequential, {report['episodes']} episodes "
        f"(at most {report['max_episodes']}; seed {report['seed']}, {report['workers']} "
        f"worker(s), {report['wall_seconds']:.1f} s, {_rate(report['episodes_per_second'])} "
        "episodes/s)",
        f"  successes {report['successes']}/{report['episodes']}, failures {report['failures']}",
    ]
    if decision == "certified":
        lines.append(f"  CERTIFIED after {report['stopped_at']} episodes: P[success] >= {eps} at "
                     f"confidence level {level}, valid however often the test looked")
    elif decision == "refuted":
        lines.append(f"  REFUTED after {report['stopped_at']} episodes: P[success] < {eps} at "
                     f"confidence level {level}, valid however often the test looked")
    else:
        lines.append(f"  UNDECIDED after {report['episodes']} episodes (the cap, --max-episodes): "
                     f"neither P[success] >= {eps} nor its negation is established; nothing is "
                     "certified")
    lines += [
        f"  anytime-valid: P[success] in [{bounds.floor_str(report['lower_bound'])}, "
        f"{_ceil_str(report['upper_bound'])}] at confidence level {level}, simultaneously for "
        "every number of episodes",
        f"  test: {report['test']}, mixing prior Beta({a:g}, {b:g}); Ville's inequality: the "
        f"true P[success] leaves the interval at some n with probability <= {report['delta']:g}",
        f"  fixed-N plan for comparison: {report['fixed_n_plan']} episodes with no failure "
        "('vlb plan')",
        f"  holds for: {report['sampling_distribution']}",
    ]
    lines += _failures(report, report_path)
    return "\n".join(lines)


def _failures(report: dict[str, Any], report_path: str | None) -> list[str]:
    lines = [f"  failures by cause: {group['count']} x {group['cause']} (e.g. seed "
             f"{group['seeds'][0]})" for group in report["failures_by_cause"]]
    failed = report["failed_episodes"]
    for item in failed[:5]:
        lines.append(f"  failed episode {item['index']} (seed {item['seed']}): {item['reason']}")
    if len(failed) > 5:
        lines.append(f"  ... {len(failed) - 5} more failed episodes in the report")
    if failed:
        kwargs = "".join(f" --env-kwarg {k}={json.dumps(v)}"
                         for k, v in report["env_kwargs"].items())
        kwargs += "".join(f" --env-module {m}" for m in report["env_modules"])
        lines.append(f"  replay one: vlb replay {report['env_id']} "
                     f"--behavior {report['behavior']} --seed {failed[0]['seed']}{kwargs}")
    if report_path:
        lines.append(f"  report: {report_path}")
    return lines


def cmd_report(args: argparse.Namespace) -> int:
    from vlb_gym.verify.campaign import report_from_store
    from vlb_gym.verify.store import CampaignStore, StoreError

    try:
        store = CampaignStore(args.store, readonly=True)
        report = report_from_store(store)
    except StoreError as exc:
        raise UsageError(str(exc)) from None
    store.close()
    stored, planned = report["episodes"], report["planned_episodes"]
    if args.json:
        print(json.dumps(report, indent=2))
        return 0
    if stored < planned:
        print(f"incomplete campaign: {stored} of {planned} episodes stored (the bounds below are "
              f"for the {stored} stored; resume with the same vlb verify command and --store)")
    print(summary(report))
    return 0


def cmd_plan(args: argparse.Namespace) -> int:
    from vlb_gym.verify import bounds

    n = bounds.min_episodes(args.epsilon, args.confidence, args.failures)
    if args.json:
        print(json.dumps({"epsilon": args.epsilon, "confidence": args.confidence,
                          "failures": args.failures, "episodes": n}))
    else:
        reached = bounds.confidence(n, args.failures, args.epsilon)
        print(f"{n} episodes: with at most {args.failures} failure(s), P[success] >= "
              f"{bounds.one_minus_str(args.epsilon)} holds with confidence >= {args.confidence} "
              f"(reached: {bounds.floor_str(reached)})")
    return 0


def cmd_replay(args: argparse.Namespace) -> int:
    from vlb_gym.verify.campaign import CampaignConfig, build, episode_seed
    from vlb_gym.verify.episode import run_episode

    kwargs = env_kwargs(args.env_kwarg)
    modules = env_modules(args.env_module)
    check_env(args.env_id, kwargs, modules)
    seed = args.seed if args.index is None else episode_seed(args.seed, args.index)
    config = CampaignConfig(args.env_id, args.behavior, 1, env_kwargs=kwargs, env_modules=modules)
    env, policy = build(config)
    result = run_episode(env, policy, seed, stop_on_failure=not args.keep_going)
    for number, info in enumerate(env.history, 1):
        mark = "ok " if info["certificate"] else "FAIL"
        extra = f"  ({info['reason']})" if "reason" in info else ""
        print(f"{number:4d} {mark} {info['primitive']:<10} {info['param']}{extra}")
    print(f"rho_B = {result.rho:+d}, finished={result.finished}, primitives={result.primitives}"
          + (f", reason: {result.reason}" if result.reason else ""))
    return 0


def cmd_render(args: argparse.Namespace) -> int:
    from PIL import Image

    from vlb_gym.core.library import load_behavior
    from vlb_gym.verify.episode import run_episode

    kwargs = env_kwargs(args.env_kwarg)
    check_env(args.env_id, {**kwargs, "render_mode": "rgb_array"}, env_modules(args.env_module))
    env = RobustnessWrapper(gym.make(args.env_id, render_mode="rgb_array", **kwargs))
    policy = load_behavior(args.behavior, env)
    out = check_output(args.out, behavior_files(policy.behavior), True, "--out")
    frames: list[np.ndarray] = []
    env.unwrapped.film(frames.append)  # after reset, after each primitive, and during motion

    def on_step(info: dict | None) -> None:
        if info is not None:
            print(f"{len(env.history):4d} {'ok  ' if info['certificate'] else 'FAIL'} "
                  f"{info['primitive']} "
                  f"{np.round(np.asarray(info['param'], dtype=float), 3).tolist()}")

    result = run_episode(env, policy, args.seed, stop_on_failure=False, on_step=on_step)
    env.unwrapped.film(None)
    stride = max(1, round(env.metadata["render_fps"] / args.fps))
    frames = frames[::stride] + frames[-1:]  # the last state too, whatever the stride
    images = [Image.fromarray(frame) for frame in frames]
    gif = io.BytesIO()
    images[0].save(gif, format="GIF", save_all=True, append_images=images[1:],
                   duration=int(1000 / args.fps), loop=0)
    write_atomic(out, gif.getvalue())
    print(f"rho_B = {result.rho:+d}; wrote {len(images)} frames to {out}")
    env.close()
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    v = sub.add_parser("verify", help="run a verification campaign and print the guarantee",
                       description="Run N i.i.d. episodes of a behavior (N fixed in advance) and "
                       "report the confidence that P[success] >= 1 - epsilon and a one-sided "
                       "Clopper-Pearson lower bound on P[success]. Exit code 0 whenever the "
                       "campaign finished, whatever its outcome. With --sequential, episodes run "
                       "until an anytime-valid test certifies or refutes the claim (or "
                       "--max-episodes ran).")
    v.add_argument("env_id", metavar="ENV_ID", help="e.g. VLB-GridExplore-v0")
    chosen = v.add_mutually_exclusive_group(required=True)
    chosen.add_argument("--behavior", metavar="NAME_OR_FILE",
                        help="a behavior name (see 'vlb behaviors') or a behavior JSON file")
    chosen.add_argument("--policy", metavar="AGENT.zip",
                        help="a trained agent ('vlb baseline train', a Stable-Baselines3 zip "
                        "with AGENT.json beside it); its training env kwargs apply, --env-kwarg "
                        "may add to them. Loading it runs code from the file (pickle): load only "
                        "agents you trust")
    v.add_argument("--episodes", type=count(1), metavar="N",
                   help="number of episodes, fixed in advance (see 'vlb plan'); required "
                   "unless --sequential")
    v.add_argument("--sequential", action="store_true",
                   help="run episodes until an anytime-valid test (Robbins' beta-binomial "
                   "mixture confidence sequence) certifies or refutes P[success] >= 1 - EPS at "
                   "level DELTA, valid however often it looks; no --episodes")
    v.add_argument("--max-episodes", type=count(1), metavar="M",
                   help="with --sequential: stop undecided after M episodes (default: 20 times "
                   "the fixed-N plan 'vlb plan --epsilon EPS --confidence 1-DELTA', e.g. 1180 "
                   "for EPS = DELTA = 0.05)")
    v.add_argument("--epsilon", required=True, type=probability, metavar="EPS",
                   help="the claim is P[success] >= 1 - EPS")
    v.add_argument("--delta", type=probability, default=0.05,
                   help="lower bound at confidence level 1 - DELTA")
    v.add_argument("--seed", type=count(0), default=0,
                   help="campaign seed: the episodes' reset seeds derive from it")
    v.add_argument("--workers", type=count(1), default=1, metavar="N",
                   help="worker processes, at most one per CPU and per episode")
    v.add_argument("--report", metavar="PATH", help="write the JSON report here when the "
                   "campaign is done (replacing the file, atomically, if it exists)")
    v.add_argument("--episodes-out", metavar="PATH",
                   help="stream one JSON line per episode here as episodes finish; kept if the "
                   "campaign is interrupted (Ctrl-C: exit code 130)")
    v.add_argument("--force", action="store_true", help="replace an existing --episodes-out")
    v.add_argument("--store", metavar="PATH",
                   help="keep every episode in this SQLite store as it finishes; an existing "
                   "store of the same campaign is resumed (episodes stored are not run again)")
    v.add_argument("--keep-going", action="store_true",
                   help="run each episode to its end even after a certificate failed")
    v.add_argument("--quiet", action="store_true", help="no progress bar")
    add_env_kwarg(v)
    v.set_defaults(func=cmd_verify)

    t = sub.add_parser("report", help="rebuild a campaign's report from its --store",
                       description="Print the summary (or, with --json, the JSON report) of the "
                       "campaign kept in a store by 'vlb verify --store', from the store alone.")
    t.add_argument("store", metavar="STORE", help="the SQLite file given to vlb verify --store")
    t.add_argument("--json", action="store_true", help="print the JSON report")
    t.set_defaults(func=cmd_report)

    p = sub.add_parser("plan", help="print the number of episodes a guarantee needs",
                       description="Least N such that N episodes with at most K failures give "
                       "confidence C that P[success] >= 1 - EPS.")
    p.add_argument("--epsilon", required=True, type=probability, metavar="EPS",
                   help="the claim is P[success] >= 1 - EPS")
    p.add_argument("--confidence", required=True, type=probability, metavar="C",
                   help="the confidence wanted in the claim")
    p.add_argument("--failures", type=count(0), default=0, metavar="K",
                   help="failures the campaign may see and still make the claim")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_plan)

    r = sub.add_parser("replay", help="re-run one episode step by step",
                       description="Re-run one episode from its reset seed (as listed in a "
                       "report's failed_episodes) and print every primitive with its certificate.")
    r.add_argument("env_id", metavar="ENV_ID", help="e.g. VLB-GridExplore-v0")
    r.add_argument("--behavior", required=True, metavar="NAME_OR_FILE",
                   help="a behavior name (see 'vlb behaviors') or a behavior JSON file")
    r.add_argument("--seed", required=True, type=count(0),
                   help="the episode's reset seed, or the campaign seed with --index")
    r.add_argument("--index", type=count(0), help="episode index within campaign --seed")
    r.add_argument("--keep-going", action="store_true",
                   help="continue after the first failed certificate")
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
