"""``vlb verify`` and ``vlb plan``: campaigns and the episodes a guarantee needs."""

from __future__ import annotations

import argparse
import contextlib
import json
import sys
from pathlib import Path

from vlb_gym.core.files import write_atomic

from .common import (UsageError, add_run_options, check_output,
                     clamp_workers, count, env_kwargs, env_modules, level, policy_ref,
                     probability, ray_options)

def check_run_args(args: argparse.Namespace, unit: str = "episodes",
                   what: str = "campaign") -> None:
    """The options of a run of ``unit`` (``--UNIT N`` fixed in advance, or ``--sequential``
    capped by ``--max-UNIT``) and of its backend, checked together."""
    count, cap = getattr(args, unit), getattr(args, f"max_{unit}")
    if args.sequential and count is not None:
        raise UsageError(f"--{unit} and --sequential exclude each other: a sequential {what} "
                         f"stops by itself (cap it with --max-{unit})")
    if not args.sequential and count is None:
        raise UsageError(f"the following arguments are required: --{unit} (or --sequential)")
    if cap is not None and not args.sequential:
        raise UsageError(f"--max-{unit} needs --sequential (a fixed-N {what} runs --{unit})")


def open_store(path: Path, prepared, total: int, command: str = "verify",
               unit: str = "episodes"):
    """The store at ``path`` holding (or now recording) the plan of ``prepared`` (a campaign or
    a comparison), whose method runs ``total`` at most; says how much of it is stored."""
    from vlb_gym.verify.store import StoreError

    try:
        store = prepared.open_store(path)
    except StoreError as exc:
        raise UsageError(f"--store {exc}") from None
    if store.done():
        most = "at most " if prepared.method().stops_early else ""
        print(f"vlb {command}: resuming {path}: {len(store.done())} of {most}{total} {unit} "
              "are stored", file=sys.stderr)
    return store


def backend_failed(exc: Exception, store, unit: str) -> str:
    """The one line for a backend that could not go on, saying what the store keeps."""
    if store is None:
        return str(exc)
    return (f"{exc}; the store {store.path} keeps every finished {unit} (the same command "
            "resumes)")


@contextlib.contextmanager
def progress(quiet: bool, total: int, initial: int, unit: str = "ep"):
    """A progress bar on a terminal (unless ``quiet``): yields what to call per item done, or
    None."""
    if quiet or not sys.stderr.isatty():
        yield None
        return
    from tqdm import tqdm

    with tqdm(total=total, initial=initial, unit=unit, file=sys.stderr,
              dynamic_ncols=True) as bar:
        yield lambda _item: bar.update()


def certified_campaign(args: argparse.Namespace) -> object:
    """``--certificate``: the behavior's certificate, whose campaign (N, root seed, eps, env
    kwargs) this command runs again; a usage error where there is none to run."""
    from vlb_gym.core.library import BehaviorLibrary
    from vlb_gym.core.spec import BehaviorSpecError

    if args.behavior is None:
        raise UsageError("--certificate needs --behavior: the certified behavior file")
    given = [flag for flag, value in (("--episodes", args.episodes), ("--epsilon", args.epsilon),
                                      ("--sequential", args.sequential),
                                      ("--env-kwarg", args.env_kwarg)) if value]
    if given:
        raise UsageError(f"--certificate runs the certificate's own campaign: {given[0]} "
                         "cannot change it")
    try:
        spec = BehaviorLibrary().resolve(args.behavior)[0]
    except BehaviorSpecError as exc:
        raise UsageError(str(exc)) from None
    certificate = spec.certificate
    if certificate is None:
        raise UsageError(f"--certificate: {args.behavior} carries no certificate (behaviors "
                         "certified by 'vlb synthesize --certify' do)")
    if certificate.env != args.env_id:
        raise UsageError(f"--certificate: {args.behavior} was certified on {certificate.env}, "
                         f"not {args.env_id}")
    args.episodes, args.seed, args.epsilon = certificate.episodes, certificate.seed, \
        certificate.epsilon
    args.env_kwarg = [f"{k}={json.dumps(v)}" for k, v in certificate.env_kwargs.items()]
    return certificate


def cmd_verify(args: argparse.Namespace) -> int:
    certificate = certified_campaign(args) if args.certificate else None
    if args.epsilon is None:
        raise UsageError("the following arguments are required: --epsilon")
    check_run_args(args)
    ray = ray_options(args, "verify")
    if args.backend == "process" and args.workers > 1:  # its imports beside ours (see there)
        from vlb_gym.verify.backends import start_forkserver
        start_forkserver(["vlb_gym.verify.campaign"])

    from vlb_gym.verify.campaign import Campaign, CampaignConfig
    from vlb_gym.verify.export import EpisodesExport
    from vlb_gym.verify.replay import store_files

    config = CampaignConfig(args.env_id, policy_ref(args),
                            args.max_episodes if args.sequential else args.episodes,
                            args.epsilon, args.delta, args.seed, env_kwargs(args.env_kwarg),
                            stop_on_failure=not args.keep_going,
                            env_modules=env_modules(args.env_module),
                            method="sequential" if args.sequential else "fixed-N")
    episodes = config.episodes  # the method's default where the command names none
    # a cluster's CPUs are known once connected (the backend clamps then, with a note); a
    # private local instance gets this machine's
    workers = clamp_workers(args.workers, episodes, "verify") \
        if args.backend != "ray" or not args.ray_address else args.workers
    try:
        campaign = Campaign(config)  # checks the env and the policy before any episode
    except ValueError as exc:  # errors name the file as the user did, not as the plan keeps it
        given = args.policy or args.behavior
        raise UsageError(str(exc).replace(config.policy.ref, given)) from None
    inputs = [*campaign.files, *(store_files(args.store) if args.store is not None else [])]
    export = (check_output(args.episodes_out, inputs, args.force, "--episodes-out")
              if args.episodes_out is not None else None)
    # a report is replaced without --force: atomically, once the campaign is done
    report_out = check_output(args.report, inputs, True, "--report") \
        if args.report is not None else None
    if report_out and export and report_out.resolve() == export.resolve():
        raise UsageError("--report and --episodes-out name the same file")
    store = None
    if args.store is not None:  # an existing store is resumed: its plan must be this command's
        store = open_store(check_output(args.store, [*campaign.files, report_out, export], True,
                                        "--store"), campaign, episodes)
    for caveat in campaign.method().caveats():  # after every check that can fail
        print(f"vlb verify: warning: {caveat}", file=sys.stderr)
    stream = EpisodesExport(export, campaign.plan, args.force) if export else None
    report = None
    from vlb_gym.verify.backends import BackendError
    from vlb_gym.verify.store import StoreError

    try:
        with progress(args.quiet, episodes, len(store.done()) if store else 0) as bar:
            def on_episode(result):
                if stream:
                    stream.add(result)
                if bar:
                    bar(result)

            report = campaign.run(workers, on_episode, store, args.backend, ray)
    except KeyboardInterrupt:  # the workers ignore Ctrl-C; leaving the run stops them
        pass
    except StoreError as exc:  # what the stored episodes turned out to be
        raise UsageError(f"--store {exc}") from None
    except BackendError as exc:
        raise UsageError(backend_failed(exc, store, "episode")) from None
    finally:
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
    if certificate is not None:
        return recheck(certificate, report)
    return 0


def recheck(certificate, report) -> int:
    """Whether the certificate's campaign, run again, counted what it recorded (0) or not (1)."""
    same_content = report["content_sha256"] == certificate.content_sha256
    same_count = report["successes"] == certificate.successes
    if same_content and same_count:
        print(f"  certificate reproduced: {certificate.successes}/{certificate.episodes} as "
              f"certified (root seed {certificate.seed}, same behavior content)")
        return 0
    if not same_content:
        print("  certificate NOT reproduced: the behavior's content differs from what was "
              f"certified (digest {report['content_sha256'][:12]}, certified "
              f"{certificate.content_sha256[:12]})")
    if not same_count:
        print(f"  certificate NOT reproduced: {report['successes']}/{report['episodes']} now, "
              f"{certificate.successes}/{certificate.episodes} certified")
    return 1


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
    v.add_argument("--epsilon", type=probability, metavar="EPS",
                   help="the claim is P[success] >= 1 - EPS (required unless --certificate)")
    v.add_argument("--certificate", action="store_true",
                   help="with --behavior FILE: run the campaign of the file's certificate again "
                   "(its N, root seed, eps and env kwargs) and say whether it counts what the "
                   "certificate records (exit 1 if not)")
    v.add_argument("--delta", type=level, default=0.05,
                   help="lower bound at confidence level 1 - DELTA")
    v.add_argument("--seed", type=count(0), default=0,
                   help="campaign seed: the episodes' reset seeds derive from it")
    v.add_argument("--report", metavar="PATH", help="write the JSON report here when the "
                   "campaign is done (replacing the file, atomically, if it exists)")
    v.add_argument("--episodes-out", metavar="PATH",
                   help="stream one JSON line per episode here as episodes finish; kept if the "
                   "campaign is interrupted (Ctrl-C: exit code 130)")
    v.add_argument("--force", action="store_true", help="replace an existing --episodes-out")
    add_run_options(v, "episode", "campaign")
    v.set_defaults(func=cmd_verify)

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
