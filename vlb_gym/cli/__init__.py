"""The ``vlb`` command line: verify behaviors and agents, plan campaigns, replay and render
episodes, synthesize behaviors from language, train and compare baselines.

Building the parser imports nothing beyond gymnasium (which registering the envs needs), so that
``vlb --help`` starts at once: each command imports scipy, networkx, pydantic, MuJoCo, torch, ...
when it runs, if it needs them."""

from __future__ import annotations

import os
import sys

import vlb_gym

from . import baselines, compare, language, library, replay, report, verify
from .common import Parser, UsageError


def parser() -> Parser:
    top = Parser(
        prog="vlb", description="Verifiable behaviors from motion primitives: run campaigns of "
        "i.i.d. episodes and turn them into probabilistic guarantees.")
    top.add_argument("--version", action="version", version=f"vlb-gym {vlb_gym.__version__}")
    sub = top.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for module in (verify, compare, report, replay, library, language, baselines):
        module.add_parsers(sub)
    return top


def main(argv: list[str] | None = None) -> int:
    """Run one command; user errors (bad arguments, unreadable or invalid files, impossible
    settings) are one line ``vlb COMMAND: error: ...`` on stderr and exit code 2, Ctrl-C is
    ``vlb COMMAND: interrupted`` and exit code 130."""
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except BrokenPipeError:  # the reader went away (``vlb ... | head``): not an error of ours
        sys.stdout = open(os.devnull, "w")
        return 0
    except KeyboardInterrupt:
        print(f"vlb {args.command}: interrupted", file=sys.stderr)
        return 130
    except (UsageError, OSError, ValueError, ImportError) as exc:
        # BehaviorSpecError (an invalid behavior) and InputFileError (an unusable input file)
        # are ValueErrors
        print(f"vlb {args.command}: error: {exc}", file=sys.stderr)
        return 2
