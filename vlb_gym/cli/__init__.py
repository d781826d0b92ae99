"""The ``vlb`` command line: verify behaviors and agents, plan campaigns, replay and render
episodes, synthesize behaviors from language, train and compare baselines.

Building the parser imports nothing beyond gymnasium (which registering the envs needs), so that
``vlb --help`` starts at once: each command imports scipy, networkx, pydantic, MuJoCo, torch, ...
when it runs, if it needs them."""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Iterator

import vlb_gym
from vlb_gym.core.errors import UserError
from vlb_gym.core.text import single_line

from . import baselines, compare, language, library, replay, report, verify
from .common import Parser
from .terminal import neutral_output


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
    settings) are one line ``vlb COMMAND: error: ...`` on stderr and exit code 2; Ctrl-C,
    SIGTERM and SIGHUP end it alike (the workers stopped, stores consistent, one
    ``interrupted`` line), with exit code 130 (128 + the signal's number for the others).
    Everything printed goes through :func:`~.terminal.neutral`."""
    args = parser().parse_args(argv)
    with neutral_output(), termination_as_interrupt() as received:
        code = _run(args)
    return 128 + received[0] if received and code == 130 else code


def _run(args) -> int:
    try:
        return args.func(args)
    except BrokenPipeError:  # the reader went away (``vlb ... | head``): not an error of ours
        sys.stdout = open(os.devnull, "w")
        return 0
    except KeyboardInterrupt:
        print(f"vlb {args.command}: interrupted", file=sys.stderr)
        return 130
    except (UserError, OSError, ValueError, ImportError) as exc:
        # UserError: every error of vlb-gym about what the user gave it (a bad argument, an
        # invalid behavior, an unusable file, a store that does not match, ...); the others:
        # what the system or a library says of the same (a missing file, a failed import)
        print(f"vlb {args.command}: error: {single_line(str(exc))}", file=sys.stderr)
        return 2
    except MemoryError:  # what was asked needs more memory than this process may have
        print(f"vlb {args.command}: error: out of memory (what this command was given needs "
              "more memory than it may use here)", file=sys.stderr)
        return 2


@contextlib.contextmanager
def termination_as_interrupt() -> Iterator[list[int]]:
    """SIGTERM and SIGHUP raise KeyboardInterrupt, as Ctrl-C does, while the block runs (in the
    main thread); the list yielded holds the signal received. A second one while the first is
    being handled is ignored (SIGKILL still ends the process)."""
    received: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield received
        return

    def interrupt(signum: int, frame: object) -> None:
        for name in ("SIGTERM", "SIGHUP"):
            signal.signal(getattr(signal, name), signal.SIG_IGN)
        received.append(signum)
        raise KeyboardInterrupt

    saved = {name: signal.signal(getattr(signal, name), interrupt)
             for name in ("SIGTERM", "SIGHUP")}
    try:
        yield received
    finally:
        for name, handler in saved.items():
            signal.signal(getattr(signal, name), handler)
