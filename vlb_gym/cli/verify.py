"""``vlb verify``, ``plan``, ``replay`` and ``render``: campaigns and single episodes."""

from __future__ import annotations

import argparse
import dataclasses
import io
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from vlb_gym.core.files import write_atomic

from .common import (UsageError, add_env_kwarg, add_env_module, check_output, clamp_workers,
                     count, env_kwargs, env_modules, probability)


AGENT_KINDS = {False: "sb3", True: "sb3_sampled"}  # by --sample: the policy kinds of agents


def _policy_ref(args: argparse.Namespace):
    """The policy named by --policy or --behavior; files by absolute path, so that a store's plan
    means the same from any directory."""
    from vlb_gym.core.library import is_path
    from vlb_gym.verify.policies import PolicyRef

    if args.policy:
        return PolicyRef(AGENT_KINDS[args.sample], str(Path(args.policy).resolve()))
    if args.sample:
        raise UsageError("--sample draws a trained agent's actions: it needs --policy")
    ref = args.behavior
    return PolicyRef("behavior", str(Path(ref).resolve()) if is_path(ref) else ref)


def _check_verify_args(args: argparse.Namespace) -> None:
    if args.sequential and args.episodes is not None:
        raise UsageError("--episodes and --sequential exclude each other: a sequential campaign "
                         "stops by itself (cap it with --max-episodes)")
    if not args.sequential and args.episodes is None:
        raise UsageError("the following arguments are required: --episodes (or --sequential)")
    if args.max_episodes is not None and not args.sequential:
        raise UsageError("--max-episodes needs --sequential (a fixed-N campaign runs --episodes)")
    if args.ray_address and args.backend != "ray":
        raise UsageError("--ray-address needs --backend ray")


def _open_store(path: Path, campaign):
    """The store at ``path``, holding (or now recording) ``campaign``'s plan."""
    from vlb_gym.verify.store import CampaignStore, StoreError

    try:
        store = CampaignStore(path)
    except StoreError as exc:
        raise UsageError(f"--store {exc}") from None
    try:
        store.start(campaign.plan)
    except StoreError as exc:
        store.close()
        raise UsageError(f"--store {exc}") from None
    if store.done():
        most = "at most " if campaign.config.sequential else ""
        print(f"vlb verify: resuming {path}: {len(store.done())} of {most}"
              f"{campaign.config.episodes} episodes are stored", file=sys.stderr)
    return store


def cmd_verify(args: argparse.Namespace) -> int:
    _check_verify_args(args)
    if args.sequential:
        from vlb_gym.verify.sequential import default_max_episodes
        episodes = args.max_episodes or default_max_episodes(args.epsilon, args.delta)
    else:
        episodes = args.episodes
    workers = clamp_workers(args.workers, episodes, "verify") if args.backend != "ray" else \
        args.workers
    if args.backend == "process" and workers > 1:  # its imports beside ours (see there)
        from vlb_gym.verify.backends import start_forkserver
        start_forkserver(["vlb_gym.verify.campaign"])

    from vlb_gym.verify.campaign import Campaign, CampaignConfig
    from vlb_gym.verify.export import EpisodesExport

    config = CampaignConfig(args.env_id, _policy_ref(args), episodes, args.epsilon, args.delta,
                            args.seed, env_kwargs(args.env_kwarg),
                            stop_on_failure=not args.keep_going,
                            env_modules=env_modules(args.env_module), sequential=args.sequential)
    try:
        campaign = Campaign(config)  # checks the env and the policy before any episode
    except ValueError as exc:  # errors name the file as the user did, not as the plan keeps it
        given = args.policy or args.behavior
        raise UsageError(str(exc).replace(config.policy.ref, given)) from None
    inputs = [*campaign.files, *(store_files(args.store) if args.store else [])]
    export = (check_output(args.episodes_out, inputs, args.force, "--episodes-out")
              if args.episodes_out else None)
    # a report is replaced without --force: atomically, once the campaign is done
    report_out = check_output(args.report, inputs, True, "--report") if args.report else None
    if report_out and export and report_out.resolve() == export.resolve():
        raise UsageError("--report and --episodes-out name the same file")
    store = None
    if args.store:  # an existing store is resumed: its plan must be this command's
        store = _open_store(check_output(args.store, [*campaign.files, report_out, export], True,
                                         "--store"), campaign)
    stream = EpisodesExport(export, campaign.plan, args.force) if export else None
    bar = None
    if not args.quiet and sys.stderr.isatty():
        from tqdm import tqdm
        bar = tqdm(total=episodes, initial=len(store.done()) if store else 0, unit="ep",
                   file=sys.stderr, dynamic_ncols=True)

    def on_episode(result):
        if stream:
            stream.add(result)
        if bar:
            bar.update()

    report = None
    try:
        report = campaign.run(workers, on_episode, store, args.backend, args.ray_address)
    except KeyboardInterrupt:  # the workers ignore Ctrl-C; leaving the run stops them
        pass
    finally:
        if bar:
            bar.close()
        if stream:
            stream.close(complete=report is not None)
        if store:
            store.close()
        campaign.close()
    if report is None:
        kept = f"; {stream.written} episode(s) written to {export}" if stream else ""
        kept += f"; the store {store.path} keeps every finished episode" if store else ""
        print(f"vlb verify: interrupted{kept}", file=sys.stderr)
        return 130
    if report_out:
        write_atomic(report_out, report.to_json())
    print(report.summary(args.report))
    return 0


def _read_store(path: str):
    """The plan and the store at ``path``, opened read-only."""
    from vlb_gym.verify.store import CampaignStore, StoreError

    try:
        return CampaignStore(path, readonly=True)
    except StoreError as exc:
        raise UsageError(str(exc)) from None


def cmd_report(args: argparse.Namespace) -> int:
    from vlb_gym.verify.campaign import report_from_store
    from vlb_gym.verify.store import StoreError

    store = _read_store(args.store)
    try:
        report = report_from_store(store)
        plan, episodes = store.plan(), store.results()
    except StoreError as exc:
        raise UsageError(str(exc)) from None
    finally:
        store.close()
    if args.out:
        from vlb_gym.reports import write_report_dir

        out = Path(args.out)
        if out.exists() and not out.is_dir():
            raise UsageError(f"--out {args.out}: not a directory")
        check_output(str(out / "report.html"), store_files(args.store), True, "--out")
        frames = None
        untrusted = stored_code(plan, args)
        if args.frames and untrusted:
            print(f"vlb report: no frames: replaying would run code the store names (name it "
                  f"again to trust it: {' '.join(untrusted)})", file=sys.stderr)
        elif args.frames:
            frames = episode_frames(plan, episodes)
        written = write_report_dir(out, report, [e.to_dict() for e in episodes], plan, frames,
                                   args.store)
        print(f"wrote {', '.join(str(p) for p in written if p.parent == out)}")
        return 0
    print(report.to_json() if args.json else report.summary(), end="\n" * (not args.json))
    return 0


def changed_since(config, policy, digest: str) -> str | None:
    """The policy's content digest now, if it differs from ``digest`` (the campaign's)."""
    from vlb_gym.verify.policies import policy_loader

    now = policy_loader(config.policy.kind).content(config.policy, policy)["sha256"]
    return now if now != digest else None


def episode_frames(plan: dict[str, Any], episodes: list) -> dict[str, list[np.ndarray]]:
    """Frames of the first failed and the first successful episode of a stored campaign, replayed
    where the env renders and the policy is the one the campaign ran (else none)."""
    from vlb_gym.verify.campaign import CampaignConfig, build
    from vlb_gym.verify.episode import run_episode

    config = CampaignConfig.from_plan(plan)
    try:
        env, policy = build(config, "rgb_array")
    except (ValueError, ImportError) as exc:
        print(f"vlb report: no frames: {exc}", file=sys.stderr)
        return {}
    frames: dict[str, list[np.ndarray]] = {}
    try:
        if changed_since(config, policy, plan["content_sha256"]):
            print("vlb report: no frames: the policy changed since the campaign", file=sys.stderr)
            return {}
        for label, success in (("failed", False), ("successful", True)):
            record = next((e for e in episodes if e.success == success), None)
            if record is None:
                continue
            shots: list[np.ndarray] = []
            env.unwrapped.film(shots.append)
            run_episode(env, policy, record.seed, record.index, config.stop_on_failure)
            env.unwrapped.film(None)
            frames[f"{label} episode {record.index}"] = shots
    finally:
        env.close()
    return frames


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


def _print_step(number: int, step: dict[str, Any]) -> None:
    mark = "ok  " if step["certificate"] else "FAIL"
    node = f"  [node {step['node']}]" if step["node"] else ""
    extra = f"  ({step['reason']})" if step["reason"] else ""
    print(f"{number:4d} {mark} {step['primitive']:<10} {step['param']}{node}{extra}")


def store_files(path: str | Path) -> list[Path]:
    """A store and the files SQLite keeps beside it: all inputs no output may overwrite."""
    return [Path(path), Path(f"{path}-wal"), Path(f"{path}-shm")]


def stored_code(plan: dict[str, Any], args: argparse.Namespace) -> list[str]:
    """The options that would name again what of a stored campaign is code (env modules, a
    pickled agent) and that the command line does not name: a store is untrusted data, and
    replaying it must not import or unpickle what only the store names. Other policy kinds are
    loaded by installed packages, which decide what their references may do."""
    given = set(env_modules(args.env_module))
    missing = [f"--env-module {m}" for m in plan["env_modules"] if m not in given]
    policy = plan["policy"]
    if policy["kind"] in AGENT_KINDS.values() and (not args.policy
                                    or str(Path(args.policy).resolve()) != policy["ref"]):
        missing.append(f"--policy {policy['ref']}")
    return missing


def _replay_config(args: argparse.Namespace):
    """The campaign config and reset seed an episode is replayed with, and its stored record
    (None when replaying from a seed on the command line)."""
    from vlb_gym.verify.campaign import CampaignConfig, episode_seed

    if args.episode is None:
        if args.seed is None or not (args.behavior or args.policy):
            raise UsageError("replay ENV_ID needs --behavior or --policy, and --seed (or "
                             "replay STORE --episode K)")
        kwargs = env_kwargs(args.env_kwarg)
        config = CampaignConfig(args.target, _policy_ref(args), 1, env_kwargs=kwargs,
                                env_modules=env_modules(args.env_module),
                                stop_on_failure=not args.keep_going)
        seed = args.seed if args.index is None else episode_seed(args.seed, args.index)
        return config, seed, None
    if args.behavior or args.seed is not None or args.index is not None or args.env_kwarg \
            or args.sample:
        raise UsageError("replay STORE --episode K takes the campaign from the store: no "
                         "--behavior, --seed, --index, --env-kwarg or --sample")
    store = _read_store(args.target)
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
                         f"{plan['episodes']} episodes are, indices 0 to {plan['episodes'] - 1})")
    untrusted = stored_code(plan, args)
    if untrusted:
        raise UsageError(f"{args.target}: replaying would run code the store names; a store is "
                         f"data, so name it again to trust it: {' '.join(untrusted)}")
    config = CampaignConfig.from_plan(plan)
    if args.keep_going:
        config = dataclasses.replace(config, stop_on_failure=False)
    return config, stored.seed, (stored, plan["content_sha256"])


def cmd_replay(args: argparse.Namespace) -> int:
    from vlb_gym.verify.campaign import build
    from vlb_gym.verify.episode import run_episode
    from vlb_gym.verify.policies import policy_loader

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
    frames: list[np.ndarray] = []
    if args.render:
        env.unwrapped.film(frames.append)
    result = run_episode(env, policy, seed, args.episode or 0, config.stop_on_failure)
    env.unwrapped.film(None)
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
    differ = [k for k, v in result.to_dict().items()
              if k not in ("seconds", "error") and record.to_dict()[k] != v]
    print(f"vlb replay: episode {record.index} does NOT reproduce the stored record (differs "
          f"in: {', '.join(differ)}); was the env or a package upgraded? versions then: "
          f"see 'vlb report {args.target} --json'", file=sys.stderr)
    return 1


def write_gif(out: Path, frames: list[np.ndarray], render_fps: float, fps: int) -> int:
    """``frames`` (thinned to ``fps``, the last one kept) as an animated GIF at ``out``,
    written atomically; the number of frames in the file."""
    from PIL import Image

    stride = max(1, round(render_fps / fps))
    frames = frames[::stride] + frames[-1:]  # the last state too, whatever the stride
    images = [Image.fromarray(frame) for frame in frames]
    gif = io.BytesIO()
    images[0].save(gif, format="GIF", save_all=True, append_images=images[1:],
                   duration=int(1000 / fps), loop=0)
    write_atomic(out, gif.getvalue())
    with Image.open(gif) as written:  # identical consecutive frames are merged into one
        return written.n_frames


def cmd_render(args: argparse.Namespace) -> int:
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
    v.add_argument("--sample", action="store_true",
                   help="with --policy: draw the agent's actions from its distribution (the "
                   "stochastic policy it was trained as), seeded by each episode's seed, instead "
                   "of taking the most likely one")
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
    v.add_argument("--backend", choices=["serial", "process", "ray"], default="process",
                   help="where episodes run: this process, worker processes on this machine, or "
                   "Ray tasks (extra 'ray'; a local instance, or --ray-address); results are "
                   "identical whatever the backend")
    v.add_argument("--ray-address", metavar="ADDRESS",
                   help="with --backend ray: an existing cluster, e.g. ray://head:10001 or auto")
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
    t.add_argument("--out", metavar="DIR",
                   help="write report.json, report.md (with figures/) and a self-contained "
                   "report.html here: the claim in words, failures by cause with replay "
                   "commands, the behavior graph coloured by failed certificates, confidence "
                   "against eps, per-episode charts, frames of a failed and a successful episode")
    t.add_argument("--no-frames", dest="frames", action="store_false",
                   help="with --out: no frames (they replay two episodes with rendering)")
    t.add_argument("--policy", metavar="AGENT.zip",
                   help="with --out, for the frames of a campaign of a trained agent: the agent "
                   "the store names, named again to trust it (loading it runs code)")
    add_env_module(t)
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
