"""The ``vlb`` command line: verify behaviors, plan campaigns, replay episodes, list behaviors."""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import vlb_gym
from vlb_gym.abstractor.backends import BackendError
from vlb_gym.core.library import BehaviorLibrary, compile_for, load_behavior, write_atomic
from vlb_gym.wrappers import RobustnessWrapper
from vlb_gym.core.spec import BehaviorSpecError, json_schema
from vlb_gym.verify import bounds
from vlb_gym.verify.campaign import CampaignConfig, build, episode_seed, run_campaign
from vlb_gym.verify.episode import run_episode


class UsageError(Exception):
    """Bad input from the command line; printed without a traceback, exit code 2."""


def _probability(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 < value < 1:
        raise argparse.ArgumentTypeError(f"{text} must lie strictly between 0 and 1")
    return value


def _count(minimum: int):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{text} must be at least {minimum}")
        return value
    return parse


def _env_kwargs(pairs: list[str]) -> dict[str, Any]:
    kwargs = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key.isidentifier():
            raise UsageError(f"--env-kwarg {pair!r}: expected NAME=VALUE, e.g. action_noise=0.5")
        try:
            kwargs[key] = json.loads(value)
        except json.JSONDecodeError:
            kwargs[key] = value
    return kwargs


def _check_env(env_id: str, kwargs: dict[str, Any]) -> None:
    if env_id not in gym.registry:
        known = ", ".join(vlb_gym.ENV_IDS)
        raise UsageError(f"unknown environment {env_id!r} (vlb-gym registers: {known})")
    try:
        gym.make(env_id, **kwargs).close()
    except ImportError as exc:
        raise UsageError(str(exc)) from None
    except (TypeError, ValueError) as exc:
        raise UsageError(f"{env_id}: bad environment arguments {kwargs}: {exc}") from None


def cmd_verify(args: argparse.Namespace) -> int:
    kwargs = _env_kwargs(args.env_kwarg)
    if args.policy:
        from vlb_gym.baselines.train import policy_env_kwargs
        try:
            env_id, trained = policy_env_kwargs(args.policy)
        except ValueError as exc:
            raise UsageError(str(exc)) from None
        if env_id != args.env_id:
            raise UsageError(f"--policy {args.policy} was trained on {env_id}, not {args.env_id}")
        kwargs = {**trained, **kwargs}
    _check_env(args.env_id, kwargs)
    config = CampaignConfig(args.env_id, args.policy or args.behavior, args.episodes,
                            args.epsilon, args.delta, args.seed, kwargs,
                            stop_on_failure=not args.keep_going, policy=bool(args.policy))
    build(config)[0].close()  # compile the behavior here, so a bad file fails before any episode
    stream = open(args.episodes_out, "w") if args.episodes_out else None
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
        report = run_campaign(config, args.workers, on_episode)
    finally:
        if bar:
            bar.close()
        if stream:
            stream.close()
    if args.report:
        write_atomic(Path(args.report), json.dumps(report, indent=2) + "\n")
    print(summary(report, args.report))
    return 0


def _rate(value: float) -> str:
    return f"{value:.0f}" if value >= 100 else f"{value:.3g}"


def summary(report: dict[str, Any], report_path: str | None = None) -> str:
    """The human-readable outcome of a campaign."""
    lines = [
        f"{report['env_id']} / {report['behavior']}: {report['episodes']} episodes "
        f"(seed {report['seed']}, {report['workers']} worker(s), {report['wall_seconds']:.1f} s, "
        f"{_rate(report['episodes_per_second'])} episodes/s)",
        f"  successes {report['successes']}/{report['episodes']}, failures {report['failures']}",
        f"  P[success] >= {1 - report['epsilon']:g} with confidence {report['confidence']:.5f}",
        f"  P[success] >= {report['lower_bound']:.5f} at confidence level "
        f"{1 - report['delta']:g} (one-sided Clopper-Pearson)",
        f"  holds for: {report['sampling_distribution']}",
    ]
    failed = report["failed_episodes"]
    for item in failed[:5]:
        lines.append(f"  failed episode {item['index']} (seed {item['seed']}): {item['reason']}")
    if len(failed) > 5:
        lines.append(f"  ... {len(failed) - 5} more failed episodes in the report")
    if failed:
        kwargs = "".join(f" --env-kwarg {k}={json.dumps(v)}"
                         for k, v in report["env_kwargs"].items())
        lines.append(f"  replay one: vlb replay {report['env_id']} --behavior {report['behavior']} "
                     f"--seed {failed[0]['seed']}{kwargs}")
    if report_path:
        lines.append(f"  report: {report_path}")
    return "\n".join(lines)


def cmd_plan(args: argparse.Namespace) -> int:
    n = bounds.min_episodes(args.epsilon, args.confidence, args.failures)
    if args.json:
        print(json.dumps({"epsilon": args.epsilon, "confidence": args.confidence,
                          "failures": args.failures, "episodes": n}))
    else:
        print(f"{n} episodes: with at most {args.failures} failure(s), P[success] >= "
              f"{1 - args.epsilon:g} holds with confidence >= {args.confidence:g} "
              f"(reached: {bounds.confidence(n, args.failures, args.epsilon):.5f})")
    return 0


def cmd_replay(args: argparse.Namespace) -> int:
    kwargs = _env_kwargs(args.env_kwarg)
    _check_env(args.env_id, kwargs)
    seed = args.seed if args.index is None else episode_seed(args.seed, args.index)
    config = CampaignConfig(args.env_id, args.behavior, 1, env_kwargs=kwargs)
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

    kwargs = _env_kwargs(args.env_kwarg)
    _check_env(args.env_id, {**kwargs, "render_mode": "rgb_array"})
    env = RobustnessWrapper(gym.make(args.env_id, render_mode="rgb_array", **kwargs))
    policy = load_behavior(args.behavior, env)
    recorder = env.unwrapped
    continuous = hasattr(recorder, "frames")  # envs that film their primitives as they run
    frames: list[np.ndarray] = []
    if continuous:
        recorder.frames = frames

    def on_step(info: dict | None) -> None:
        if not continuous:
            frames.append(env.render())
        if info is not None:
            print(f"{len(env.history):4d} {'ok  ' if info['certificate'] else 'FAIL'} "
                  f"{info['primitive']} "
                  f"{np.round(np.asarray(info['param'], dtype=float), 3).tolist()}")

    result = run_episode(env, policy, args.seed, stop_on_failure=False, on_step=on_step)
    if continuous:
        recorder.frames = None
        stride = max(1, round(env.metadata["render_fps"] / args.fps))
        frames = frames[::stride]
    frames.append(env.render())
    images = [Image.fromarray(frame) for frame in frames]
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    images[0].save(out, save_all=True, append_images=images[1:], duration=int(1000 / args.fps),
                   loop=0)
    print(f"rho_B = {result.rho:+d}; wrote {len(images)} frames to {out}")
    env.close()
    return 0


def cmd_behaviors(args: argparse.Namespace) -> int:
    if args.name is None:
        for name in BehaviorLibrary().names():
            print(name)
        return 0
    _check_env(args.env_id, {})
    compiled = compile_for(args.name, gym.make(args.env_id))
    if args.json:
        print(compiled.spec.model_dump_json(by_alias=True, indent=2, exclude_defaults=True))
        return 0
    print(graph_text(compiled))
    return 0


def _backend(args: argparse.Namespace):
    from vlb_gym.abstractor.backends import (OpenAICompatibleBackend, ScriptedBackend,
                                             TranscriptBackend)
    chosen = [flag for flag, value in (("--scripted", args.scripted),
                                       ("--replay-transcript", args.replay_transcript),
                                       ("--base-url", args.base_url)) if value]
    if len(chosen) != 1:
        raise UsageError("give exactly one language model: --base-url URL (with --model), "
                         "--scripted FILE or --replay-transcript FILE"
                         + (f" (got {', '.join(chosen)})" if chosen else ""))
    if args.scripted:
        return ScriptedBackend.from_file(args.scripted)
    if args.replay_transcript:
        return TranscriptBackend.from_file(args.replay_transcript)
    if not args.model:
        raise UsageError("--base-url needs --model NAME")
    try:
        return OpenAICompatibleBackend(args.base_url, args.model, args.api_key_env, args.timeout,
                                       args.retries, structured_output=args.structured_output)
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def cmd_synthesize(args: argparse.Namespace) -> int:
    from vlb_gym.abstractor.synthesize import SynthesisError, save, save_transcript, synthesize

    _check_env(args.env_id, {})
    backend = _backend(args)
    library = BehaviorLibrary()
    info = ""
    if args.info:
        try:
            info = Path(args.info).read_text()
        except OSError as exc:
            raise UsageError(f"--info {args.info}: {exc.strerror}") from None
    try:
        result = synthesize(args.env_id, args.description, backend, library, info,
                            tuple(args.uses), args.name, args.max_rounds)
    except (SynthesisError, BackendError) as exc:
        transcript = getattr(exc, "transcript", None)
        if transcript is not None:
            where = Path(args.out).with_suffix(".failed.transcript.json") if args.out else \
                library.directory / f"failed-{int(time.time())}.transcript.json"
            save_transcript(transcript, where)
            print(f"vlb synthesize: error: {exc}\n  transcript: {where}", file=sys.stderr)
        else:
            print(f"vlb synthesize: error: {exc}", file=sys.stderr)
        return 1
    compiled = result.compiled
    if result.from_library:
        print(f"{compiled.name} is already in the behavior library ({compiled.source}); "
              "nothing asked")
        path = Path(compiled.source)
    else:
        path = save(result, library, Path(args.out) if args.out else None, args.force)
        print(f"{compiled.name}: valid after {result.rounds} round(s) with {backend.name}")
        print(f"  saved: {path}\n  transcript: {path.with_suffix('.transcript.json')}")
    print(graph_text(compiled))
    if args.verify:
        config = CampaignConfig(args.env_id, str(path) if args.out else compiled.name,
                                args.verify, args.epsilon, seed=args.seed)
        print(summary(run_campaign(config)))
    return 0


def cmd_scoop_setup(args: argparse.Namespace) -> int:
    from vlb_gym.abstractor.scoop_setup import ScoopSetup, SetupError, transcript_json

    backend = _backend(args) if (args.base_url or args.scripted) else None
    env = gym.make("VLB-Scoop-v0").unwrapped
    env.reset(seed=args.seed)
    session = ScoopSetup(env, Path(args.images), backend)
    library = BehaviorLibrary()
    if backend is None:
        print("No language model configured: type commands -- translate DX DY DZ (m, base "
              "frame: x forward, y left, z up), rotate DROLL DPITCH DYAW (degrees), save, quit.")
    else:
        print(f"Say how to move the end-effector ({backend.name}); 'quit' to stop.")
    print(session.view())
    while True:
        if sys.stdin.isatty():
            print("> ", end="", flush=True)
        line = sys.stdin.readline()
        if not line or line.strip().lower() in ("quit", "exit", "q"):
            break
        if not line.strip():
            continue
        try:
            for message in session.request(line.strip()):
                print(message)
        except (SetupError, BackendError) as exc:
            print(f"error: {exc}")
    env.close()
    if backend is not None:
        write_atomic(Path(args.images) / "transcript.json", transcript_json(session) + "\n")
    if session.saved is None:
        print("no pose saved; nothing written")
        return 1
    try:
        path = session.save_behavior(library, args.name, args.force)
    except SetupError as exc:
        print(f"vlb scoop-setup: error: {exc}", file=sys.stderr)
        return 2
    print(f"wrote {path}\nverify it: vlb verify VLB-Scoop-v0 --behavior {args.name} "
          "--episodes 59 --epsilon 0.05 --workers 2")
    return 0


def cmd_baseline_train(args: argparse.Namespace) -> int:
    from vlb_gym.baselines.configs import TASKS
    from vlb_gym.baselines.train import train

    task = TASKS[args.task]
    if task.env_id != args.env_id:
        raise UsageError(f"task {args.task} belongs to {task.env_id}, not {args.env_id}")
    started = time.perf_counter()
    saved = train(task, args.algo, Path(args.out), args.seed, args.n_envs,
                  tuple(args.budgets) if args.budgets else None,
                  Path(args.tensorboard) if args.tensorboard else None, verbose=args.verbose)
    print(f"trained {args.algo} on {args.task} in {time.perf_counter() - started:.0f} s")
    for path in saved:
        print(f"  saved {path}  (verify: vlb verify {args.env_id} --policy {path} "
              "--episodes 100 --epsilon 0.05)")
    return 0


def cmd_bench_compare(args: argparse.Namespace) -> int:
    from vlb_gym.baselines.compare import compare

    started = time.perf_counter()
    compare(Path(args.out), tuple(args.tasks), args.episodes, args.seed, tuple(args.algos),
            tuple(args.budgets) if args.budgets else None, args.n_envs, args.workers)
    print(f"wrote {args.out}/compare.md and compare.png in {time.perf_counter() - started:.0f} s")
    print(Path(args.out, "compare.md").read_text())
    return 0


def graph_text(compiled) -> str:
    """The nodes and edges of a compiled behavior, one per line."""
    lines = [f"{compiled.name}: {compiled.spec.description}"]
    for node in compiled.spec.nodes:
        kind = f"primitive {node.primitive}" if node.primitive else f"behavior {node.behavior}"
        tags = (" [start]" if node.id == compiled.start_node else "") + \
               (" [terminal]" if node.id in compiled.terminals else "")
        lines.append(f"  node {node.id}: {kind}{tags}")
    for edge in compiled.spec.edges:
        lines.append(f"  edge {edge.source} -> {edge.to}: if {edge.guard}"
                     + (f", param {edge.param}" if edge.param else "")
                     + "".join(f", {k} := {v}" for k, v in edge.set.items()))
    return "\n".join(lines)


def cmd_schema(args: argparse.Namespace) -> int:
    print(json.dumps(json_schema(), indent=2))
    return 0


def parser() -> argparse.ArgumentParser:
    top = argparse.ArgumentParser(
        prog="vlb", description="Verifiable behaviors from motion primitives: run campaigns of "
        "i.i.d. episodes and turn them into probabilistic guarantees.")
    top.add_argument("--version", action="version", version=f"vlb-gym {vlb_gym.__version__}")
    sub = top.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def env_kwarg(p: argparse.ArgumentParser) -> None:
        p.add_argument("--env-kwarg", action="append", default=[], metavar="NAME=VALUE",
                       help="keyword argument for gym.make, e.g. action_noise=0.5 (repeatable)")

    def model_options(p: argparse.ArgumentParser) -> None:
        p.add_argument("--base-url", help="OpenAI-compatible server, e.g. "
                       "https://api.openai.com/v1 or http://127.0.0.1:11434/v1 (Ollama)")
        p.add_argument("--model", help="model name at that server")
        p.add_argument("--api-key-env", default="OPENAI_API_KEY",
                       help="environment variable holding the API key (default OPENAI_API_KEY)")
        p.add_argument("--structured-output", choices=["json_schema", "json_object", "none"],
                       default="json_schema", help="what the server supports (default "
                       "json_schema)")
        p.add_argument("--timeout", type=float, default=60.0, help="seconds per request")
        p.add_argument("--retries", type=_count(0), default=3, help="retries per request")
        p.add_argument("--scripted", metavar="FILE",
                       help="canned replies (a JSON list) instead of a live model")

    v = sub.add_parser("verify", help="run a verification campaign and print the guarantee",
                       description="Run N i.i.d. episodes of a behavior (N fixed in advance) and "
                       "report the confidence that P[success] >= 1 - epsilon and a one-sided "
                       "Clopper-Pearson lower bound on P[success]. Exit code 0 whenever the "
                       "campaign finished, whatever its outcome.")
    v.add_argument("env_id", metavar="ENV_ID", help="e.g. VLB-GridExplore-v0")
    chosen = v.add_mutually_exclusive_group(required=True)
    chosen.add_argument("--behavior", metavar="NAME_OR_FILE",
                        help="a behavior name (see 'vlb behaviors') or a behavior JSON file")
    chosen.add_argument("--policy", metavar="AGENT.zip",
                        help="a trained agent ('vlb baseline train'); its training env kwargs "
                        "apply, --env-kwarg may add to them")
    v.add_argument("--episodes", required=True, type=_count(1), metavar="N")
    v.add_argument("--epsilon", required=True, type=_probability, metavar="EPS",
                   help="the claim is P[success] >= 1 - EPS")
    v.add_argument("--delta", type=_probability, default=0.05,
                   help="lower bound at confidence level 1 - DELTA (default 0.05)")
    v.add_argument("--seed", type=_count(0), default=0, help="campaign seed (default 0)")
    v.add_argument("--workers", type=_count(1), default=1, help="processes (default 1)")
    v.add_argument("--report", metavar="PATH", help="write the JSON report here")
    v.add_argument("--episodes-out", metavar="PATH",
                   help="stream one JSON line per episode here as episodes finish")
    v.add_argument("--keep-going", action="store_true",
                   help="run each episode to its end even after a certificate failed")
    v.add_argument("--quiet", action="store_true", help="no progress bar")
    env_kwarg(v)
    v.set_defaults(func=cmd_verify)

    p = sub.add_parser("plan", help="print the number of episodes a guarantee needs",
                       description="Least N such that N episodes with at most K failures give "
                       "confidence C that P[success] >= 1 - EPS.")
    p.add_argument("--epsilon", required=True, type=_probability, metavar="EPS")
    p.add_argument("--confidence", required=True, type=_probability, metavar="C")
    p.add_argument("--failures", type=_count(0), default=0, metavar="K")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_plan)

    r = sub.add_parser("replay", help="re-run one episode step by step",
                       description="Re-run one episode from its reset seed (as listed in a "
                       "report's failed_episodes) and print every primitive with its certificate.")
    r.add_argument("env_id", metavar="ENV_ID")
    r.add_argument("--behavior", required=True, metavar="NAME_OR_FILE")
    r.add_argument("--seed", required=True, type=_count(0),
                   help="the episode's reset seed, or the campaign seed with --index")
    r.add_argument("--index", type=_count(0), help="episode index within campaign --seed")
    r.add_argument("--keep-going", action="store_true",
                   help="continue after the first failed certificate")
    env_kwarg(r)
    r.set_defaults(func=cmd_replay)

    w = sub.add_parser("render", help="write one episode of a behavior as an animated GIF",
                       description="Run one episode (reset seed --seed) and write what the "
                       "environment's rgb_array rendering shows as a GIF; environments that film "
                       "their primitives (VLB-Scoop-v0) give the whole motion.")
    w.add_argument("env_id", metavar="ENV_ID")
    w.add_argument("--behavior", required=True, metavar="NAME_OR_FILE")
    w.add_argument("--seed", type=_count(0), default=0)
    w.add_argument("--out", required=True, metavar="FILE.gif")
    w.add_argument("--fps", type=_count(1), default=10)
    env_kwarg(w)
    w.set_defaults(func=cmd_render)

    b = sub.add_parser("behaviors", help="list the behavior library, or show one behavior",
                       description="Without NAME, list the library (shipped behaviors and the "
                       "user's, in $VLB_BEHAVIOR_DIR); with NAME (or a file), check it against "
                       "ENV and print its graph.")
    b.add_argument("name", nargs="?", metavar="NAME_OR_FILE")
    b.add_argument("--env", dest="env_id", default="VLB-GridExplore-v0")
    b.add_argument("--json", action="store_true", help="print the behavior file")
    b.set_defaults(func=cmd_behaviors)

    y = sub.add_parser("synthesize", help="compose a behavior from a description with an LLM",
                       description="Algorithm 1 of the paper: ask a language model for a behavior "
                       "graph over the environment's primitives, validate it (JSON, schema, "
                       "references, graph, expressions, dry run), feed errors back for repair, and "
                       "add the valid behavior to the library (or --out). A transcript of prompts, "
                       "replies and errors is saved beside the result.")
    y.add_argument("env_id", metavar="ENV_ID")
    y.add_argument("description", metavar="DESCRIPTION", help="the desired behavior, in words")
    y.add_argument("--info", metavar="FILE", help="extra information for the model (the "
                   "paper's string I)")
    y.add_argument("--uses", nargs="+", default=[], metavar="BEHAVIOR",
                   help="existing behaviors the new one should build on")
    y.add_argument("--name", help="name of the new behavior; if the library has it already, it "
                   "is used and the model is not asked")
    y.add_argument("--out", metavar="FILE", help="write here instead of the user library")
    y.add_argument("--force", action="store_true", help="replace an existing file")
    y.add_argument("--max-rounds", type=_count(1), default=3,
                   help="replies to try, repairs included (default 3)")
    model_options(y)
    y.add_argument("--replay-transcript", metavar="FILE",
                   help="replay the replies of an earlier synthesize transcript")
    y.add_argument("--verify", type=_count(1), metavar="N",
                   help="then verify the result with N episodes")
    y.add_argument("--epsilon", type=_probability, default=0.05, help="for --verify")
    y.add_argument("--seed", type=_count(0), default=0, help="for --verify")
    y.set_defaults(func=cmd_synthesize)

    z = sub.add_parser("scoop-setup", help="choose the scooping sensing pose in words",
                       description="Move the scoop arm's end-effector by saying how (an LLM turns "
                       "each request into translate / rotate / save helper calls) or, without a "
                       "model, by typing those commands; each move writes the wrist camera's "
                       "view to an image. The saved pose becomes the sensing pose of a copy of "
                       "scoop_repeatedly in the behavior library. Reads requests from stdin.")
    z.add_argument("--name", default="my_scoop", help="name of the behavior to write")
    z.add_argument("--images", default="scoop_setup", metavar="DIR",
                   help="where the camera views go (default ./scoop_setup)")
    z.add_argument("--seed", type=_count(0), default=0, help="which container placement to show")
    z.add_argument("--force", action="store_true", help="replace a behavior of that name")
    model_options(z)
    z.set_defaults(func=cmd_scoop_setup, replay_transcript=None)

    from vlb_gym.baselines.configs import ALGORITHMS, TASKS

    t = sub.add_parser("baseline", help="train Stable-Baselines3 agents (extra rl)")
    tsub = t.add_subparsers(dest="baseline_command", required=True, metavar="COMMAND")
    tt = tsub.add_parser("train", help="train an agent on a task and save checkpoints",
                         description="Train PPO, A2C or MaskablePPO (invalid-action masking) on a "
                         "task, on vectorized envs, logging to the SB3 logger (and TensorBoard "
                         "with --tensorboard); saves AGENT.zip + AGENT.json at every budget.")
    tt.add_argument("env_id", metavar="ENV_ID")
    tt.add_argument("--task", required=True, choices=sorted(TASKS))
    tt.add_argument("--algo", required=True, choices=ALGORITHMS)
    tt.add_argument("--budgets", type=_count(1), nargs="+", metavar="STEPS",
                    help="checkpoints in environment steps (default: the task's)")
    tt.add_argument("--seed", type=_count(0), default=0)
    tt.add_argument("--n-envs", type=_count(1), default=4)
    tt.add_argument("--out", default="agents", metavar="DIR")
    tt.add_argument("--tensorboard", metavar="DIR")
    tt.add_argument("--verbose", type=int, default=0, choices=[0, 1, 2])
    tt.set_defaults(func=cmd_baseline_train)

    c = sub.add_parser("bench", help="benchmarks")
    csub = c.add_subparsers(dest="bench_command", required=True, metavar="COMMAND")
    cc = csub.add_parser("compare", help="graphs vs RL agents on the same footing",
                         description="For each task: the hand-written graph, the synthesized "
                         "graph (scripted paper replies) and RL agents at each training budget, "
                         "verified on the same N episodes and seeds; writes a Markdown table "
                         "and a plot to --out.")
    cc.add_argument("--out", default="results", metavar="DIR")
    cc.add_argument("--tasks", nargs="+", default=sorted(TASKS), choices=sorted(TASKS))
    cc.add_argument("--algos", nargs="+", default=list(ALGORITHMS), choices=ALGORITHMS)
    cc.add_argument("--episodes", type=_count(1), default=100)
    cc.add_argument("--budgets", type=_count(1), nargs="+", metavar="STEPS")
    cc.add_argument("--seed", type=_count(0), default=0)
    cc.add_argument("--n-envs", type=_count(1), default=4)
    cc.add_argument("--workers", type=_count(1), default=1)
    cc.set_defaults(func=cmd_bench_compare)

    s = sub.add_parser("schema", help="print the JSON Schema of behavior files")
    s.set_defaults(func=cmd_schema)
    return top


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except BrokenPipeError:  # the reader went away (``vlb ... | head``): not an error of ours
        sys.stdout = open(os.devnull, "w")
        return 0
    except (UsageError, BehaviorSpecError, OSError, ValueError, ImportError) as exc:
        print(f"vlb {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
