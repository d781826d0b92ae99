"""``vlb report``: a campaign's report rebuilt from its store, in words, JSON or a folder."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .common import (UsageError, add_env_module, check_not_input, check_output, count,
                     read_store, seconds, untrusted_options)

def cmd_report(args: argparse.Namespace) -> int:
    from vlb_gym.verify import comparison
    from vlb_gym.verify.campaign import report_from_store
    from vlb_gym.verify.store import ComparisonStore, StoreError

    store = read_store(args.store)
    if isinstance(store, ComparisonStore):
        try:
            report = comparison.report_from_store(store)
        except StoreError as exc:
            raise UsageError(str(exc)) from None
        finally:
            store.close()
        if args.out:
            raise UsageError(f"--out: {args.store} holds a comparison, whose report is printed "
                             "(in words, or with --json)")
        print(report.to_json() if args.json else report.summary(), end="\n" * (not args.json))
        return 0
    try:
        report = report_from_store(store)
        plan, episodes = store.plan(), store.results()
    except StoreError as exc:
        raise UsageError(str(exc)) from None
    finally:
        store.close()
    if args.out:
        from vlb_gym.reports import write_report_dir
        from vlb_gym.verify.replay import episode_frames, store_files

        out = Path(args.out)
        check_not_input(out, store_files(args.store), f"--out {args.out}")
        if out.exists() and not out.is_dir():
            raise UsageError(f"--out {args.out}: not a directory")
        check_output(str(out / "report.html"), store_files(args.store), True, "--out")
        frames = key = None
        untrusted = untrusted_options(args.store, plan, args)
        if args.frames and untrusted:
            print(f"vlb report: no frames: replaying would run code the store names (name it "
                  f"again to trust it: {' '.join(untrusted)})", file=sys.stderr)
        elif args.frames:
            replayed = any(not e.success for e in episodes) + any(e.success for e in episodes)
            print(f"vlb report: replaying {replayed} episode(s) for their frames ...",
                  file=sys.stderr, flush=True)
            frames, key, why_not = episode_frames(plan, episodes)
            if why_not:
                print(f"vlb report: no frames: {why_not}", file=sys.stderr)
        print(f"vlb report: drawing the report of {len(episodes)} episode(s) ...",
              file=sys.stderr, flush=True)
        written = write_report_dir(out, report, [e.to_dict() for e in episodes], plan, frames,
                                   args.store, key)
        print(f"wrote {', '.join(str(p) for p in written if p.parent == out)}")
        return 0
    if args.json:
        import json

        from vlb_gym.reports import report_data

        data = report_data(report, [e.to_dict() for e in episodes], plan)
        print(json.dumps(data, indent=2, allow_nan=False))
    else:
        print(report.summary())
    return 0


def cmd_monitor(args: argparse.Namespace) -> int:
    from vlb_gym.reports.monitor import Monitor

    if args.port > 65535:
        raise UsageError(f"--port {args.port}: a port is at most 65535")
    try:
        server = Monitor(args.store, args.port, args.interval)
    except OSError as exc:
        raise UsageError(f"--port {args.port}: cannot listen on 127.0.0.1 ({exc.strerror})"
                         ) from None
    waiting = "" if Path(args.store).exists() else f" ({args.store} does not exist yet: the " \
        "page waits for it)"
    print(f"vlb monitor: {server.url} shows {args.store}{waiting}; Ctrl-C stops it", flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        print("vlb monitor: stopped", file=sys.stderr)
    finally:
        server.server_close()
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    t = sub.add_parser("report", help="rebuild a campaign's report from its --store",
                       description="Print the summary (or, with --json, the JSON report) of the "
                       "campaign kept in a store by 'vlb verify --store' (or the comparison "
                       "of 'vlb compare --store'), from the store alone.")
    t.add_argument("store", metavar="STORE",
                   help="the SQLite file given to vlb verify (or vlb compare) --store")
    t.add_argument("--json", action="store_true",
                   help="print the JSON report (a campaign's with each node's steps, failures by "
                   "kind and mean step time, under \"nodes\")")
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

    m = sub.add_parser("monitor", help="a live view of a running campaign's --store",
                       description="Serve a page on 127.0.0.1 that shows a campaign (or "
                       "comparison) while it runs, read-only from its store: episodes done and "
                       "per second, the current guarantee or the sequential test's state, "
                       "failures by cause with replay commands, each node's steps and failed "
                       "certificates. It refreshes every --interval seconds; Ctrl-C stops it.")
    m.add_argument("store", metavar="STORE",
                   help="the SQLite file given to vlb verify (or vlb compare) --store")
    m.add_argument("--port", type=count(0), default=8765, metavar="PORT",
                   help="the port on 127.0.0.1 (0: any free port)")
    m.add_argument("--interval", type=seconds, default=2.0, metavar="SECONDS",
                   help="how often the page refreshes")
    m.set_defaults(func=cmd_monitor)
