"""``vlb compare``: two behaviors or agents on the same reset seeds, one paired test."""

from __future__ import annotations

import argparse
import sys

from vlb_gym.core.files import write_atomic

from .common import (UsageError, add_run_options, check_output,
                     clamp_workers, comparison_level, count, env_kwargs, env_modules,
                     fraction_below_one, named_policy, ray_options)
from .verify import backend_failed, check_run_args, open_store, progress


def _side(ref: str, sample: bool, name: str):
    return named_policy(ref, ref.endswith(".zip"), sample, f"--{name}-sample",
                        f"{name.upper()} to be a trained agent's .zip")


def cmd_compare(args: argparse.Namespace) -> int:
    check_run_args(args, "pairs", "comparison")
    ray = ray_options(args, "compare")
    from vlb_gym.verify.backends import BackendError
    from vlb_gym.verify.comparison import Comparison, ComparisonConfig
    from vlb_gym.verify.replay import store_files
    from vlb_gym.verify.store import StoreError

    config = ComparisonConfig(
        args.env_id, _side(args.a, args.a_sample, "a"), _side(args.b, args.b_sample, "b"),
        args.max_pairs if args.sequential else args.pairs, args.margin, args.alpha, args.seed,
        env_kwargs(args.env_kwarg), env_kwargs(args.a_env_kwarg, "--a-env-kwarg"),
        env_kwargs(args.b_env_kwarg, "--b-env-kwarg"),
        stop_on_failure=not args.keep_going, env_modules=env_modules(args.env_module),
        method="sequential" if args.sequential else "fixed-N")
    workers = clamp_workers(args.workers, config.pairs, "compare", items="pair(s)") \
        if args.backend != "ray" or not args.ray_address else args.workers
    try:
        comparison = Comparison(config)
    except ValueError as exc:  # errors name the files as the user did
        message = str(exc)
        for side, given in ((config.a, args.a), (config.b, args.b)):
            message = message.replace(side.ref, given)
        raise UsageError(message) from None
    with comparison:
        given = args.store is not None
        inputs = [*comparison.files, *(store_files(args.store) if given else [])]
        report_out = check_output(args.report, inputs, True, "--report") \
            if args.report is not None else None
        store = None
        if given:
            store = open_store(check_output(args.store, [*comparison.files, report_out], True,
                                            "--store"), comparison, config.pairs, "compare",
                               "pairs")
        for caveat in comparison.method().caveats():  # after every check that can fail
            print(f"vlb compare: warning: {caveat}", file=sys.stderr)
        for difference in comparison.differences():
            print(f"vlb compare: note: A and B run on different envs (the same reset seeds): "
                  f"{difference}", file=sys.stderr)
        report = None
        try:
            with progress(args.quiet, config.pairs, len(store.done()) if store else 0,
                          "pair") as bar:
                report = comparison.run(workers, bar, store, args.backend, ray)
        except KeyboardInterrupt:
            pass
        except StoreError as exc:
            raise UsageError(f"--store {exc}") from None
        except BackendError as exc:
            raise UsageError(backend_failed(exc, store, "pair")) from None
        finally:
            if store:
                store.close()
    if report is None:
        kept = f"; the store {store.path} keeps every finished pair" if store else ""
        print(f"vlb compare: interrupted{kept}", file=sys.stderr)
        return 130
    if report_out:
        write_atomic(report_out, report.to_json())
    print(report.summary(args.report))
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    c = sub.add_parser(
        "compare", help="compare two behaviors or agents on the same seeds (paired test)",
        description="Run behavior or agent A and B on the same reset seeds, so that episodes "
        "pair up, and test whether B is more reliable than A (--margin 0) or at least as "
        "reliable up to a margin (--margin M: P_B > P_A - M), from the pairs where one "
        "succeeded and the other failed. Fixed N: McNemar's exact test (margin 0) or the exact "
        "unconditional test (margin > 0). --sequential: an anytime-valid test by betting that "
        "stops as soon as the evidence suffices. Exit code 0 whenever the comparison finished, "
        "whatever its outcome.")
    c.add_argument("env_id", metavar="ENV_ID", help="e.g. VLB-GridExplore-v0")
    for name in ("a", "b"):
        c.add_argument(name, metavar=name.upper(),
                       help="a behavior name or JSON file, or a trained agent's .zip (loading "
                       "an agent runs code from the file: load only agents you trust)")
    c.add_argument("--pairs", type=count(1), metavar="N",
                   help="number of pairs, fixed in advance; required unless --sequential")
    c.add_argument("--sequential", action="store_true",
                   help="run pairs until the anytime-valid test decides; no --pairs")
    c.add_argument("--max-pairs", type=count(1), metavar="M",
                   help="with --sequential: stop undecided after M pairs (default 5000)")
    c.add_argument("--margin", type=fraction_below_one, default=0.0, metavar="M",
                   help="0: test P_B > P_A; above 0: test P_B > P_A - M (non-inferiority)")
    c.add_argument("--alpha", type=comparison_level, default=0.05,
                   help="the probability of a wrong decision (the test's level)")
    c.add_argument("--seed", type=count(0), default=0,
                   help="the pairs' reset seeds derive from it (as vlb verify's episodes)")
    for name in ("a", "b"):
        c.add_argument(f"--{name}-env-kwarg", action="append", default=[], metavar="NAME=VALUE",
                       help=f"keyword argument for {name.upper()}'s env only (repeatable)")
        c.add_argument(f"--{name}-sample", action="store_true",
                       help=f"{name.upper()} is an agent: draw its actions from its "
                       "distribution, seeded by each episode's seed")
    c.add_argument("--report", metavar="PATH", help="write the JSON report here when the "
                   "comparison is done (replacing the file, atomically, if it exists)")
    add_run_options(c, "pair", "comparison")
    c.set_defaults(func=cmd_compare)
