"""What every ``vlb`` command shares: the parser, argument types, env and output checks, the
usage error."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import gymnasium as gym

from vlb_gym.core.errors import UserError
from vlb_gym.core.text import bounded

if TYPE_CHECKING:
    from vlb_gym.verify.records import Plan


class UsageError(UserError):
    """Bad input from the command line; printed without a traceback, exit code 2."""


class HelpFormatter(argparse.HelpFormatter):
    """Help that ends with the default of each option that takes a value and has a default
    worth stating (not None, False or an empty list), as it would be typed."""

    def _expand_help(self, action: argparse.Action) -> str:
        text = super()._expand_help(action)
        default = action.default
        if action.nargs == 0 or default is None or default is False or default == [] \
                or default is argparse.SUPPRESS:  # a flag's default is its absence
            return text
        shown = " ".join(map(str, default)) if isinstance(default, (list, tuple)) else default
        return f"{text} (default: {shown})"


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line, like every other error of ``vlb``, and
    whose help states defaults; its subcommands' parsers are Parsers too."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {bounded(message)} (see '{self.prog} --help')\n")


def probability(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 < value < 1:
        raise argparse.ArgumentTypeError(f"{text} must lie strictly between 0 and 1")
    return value


def level(text: str) -> float:
    """A probability of error (``--delta``, ``--alpha``): strictly between 0 and 1, and large
    enough that ``1 - value`` is below 1 in floating point."""
    value = probability(text)
    if 1.0 - value == 1.0:
        raise argparse.ArgumentTypeError(
            f"{text} is too small: 1 - {text} is 1 in floating point (the least usable value "
            "is about 1.2e-16)")
    return value


def comparison_level(text: str) -> float:
    """A test's level (``vlb compare --alpha``): a :func:`level` below one half."""
    value = level(text)
    if value >= 0.5:
        raise argparse.ArgumentTypeError(
            f"{text} is not below 0.5: a test wrong with probability one half or more shows "
            "nothing (and its interval would be empty)")
    return value


def fraction(text: str) -> float:
    """A number in [0, 1]."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 <= value <= 1:
        raise argparse.ArgumentTypeError(f"{text} must lie between 0 and 1")
    return value


def fraction_below_one(text: str) -> float:
    """A number in [0, 1)."""
    value = fraction(text)
    if value == 1:
        raise argparse.ArgumentTypeError(f"{text} must be below 1")
    return value


def seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 < value < math.inf:
        raise argparse.ArgumentTypeError(f"{text} must be a positive number of seconds")
    return value


def count(minimum: int) -> Callable[[str], int]:
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{text} must be at least {minimum}")
        return value
    return parse


def behavior_name(text: str) -> str:
    """A ``--name``: a behavior name, never a path (checked where it is given)."""
    from vlb_gym.core.names import is_name

    if not is_name(text):
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a behavior name: a letter, then letters, digits and _ (64 at most)")
    return text


def env_kwargs(pairs: list[str], option: str = "--env-kwarg") -> dict[str, Any]:
    kwargs = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key.isidentifier():
            raise UsageError(f"{option} {pair!r}: expected NAME=VALUE, e.g. action_noise=0.5")
        if key == "render_mode":
            raise UsageError(f"{option} render_mode: vlb chooses the render mode itself "
                             "('vlb render' films an episode)")
        try:
            kwargs[key] = json.loads(value)
        except json.JSONDecodeError:
            kwargs[key] = value
    return kwargs


def env_modules(refs: list[str]) -> tuple[str, ...]:
    """The ``--env-module`` references (modules that register the user's envs) as campaigns keep
    them: file paths absolute, as campaign workers import them again."""
    from vlb_gym.envs.modules import is_module_path

    return tuple(str(Path(ref).resolve()) if is_module_path(ref) else ref for ref in refs)


def open_env(env_id: str, kwargs: dict[str, Any], modules: tuple[str, ...] = ()) -> gym.Env:
    """The env, made and reset once (see :func:`~vlb_gym.envs.modules.make_primitive_env`);
    a bad id, module or setting is a usage error."""
    from vlb_gym.envs.modules import EnvSetupError, make_primitive_env

    try:
        return make_primitive_env(env_id, kwargs, modules)
    except EnvSetupError as exc:
        raise UsageError(str(exc)) from None


def check_env(env_id: str, kwargs: dict[str, Any], modules: tuple[str, ...] = ()) -> None:
    """Refuse env ids that are neither vlb-gym's nor a PrimitiveEnv of an ``--env-module``, and
    settings the env refuses, before any work."""
    open_env(env_id, kwargs, modules).close()


def _same_file(a: Path, b: Path) -> bool:
    if a.resolve() == b.resolve():
        return True
    try:
        return os.path.samefile(a, b)  # hard links
    except OSError:  # one of them does not exist (yet)
        return False


def check_not_input(out: Path, inputs: Iterable[str | os.PathLike[str] | None],
                    where: str) -> None:
    """Refuse an output path (a file or a folder) that is one of ``inputs`` (None entries are
    skipped; a store's inputs include the files SQLite keeps beside it)."""
    for source in inputs:
        if source is not None and _same_file(out, Path(source)):
            raise UsageError(f"{where}: is an input of this command ({source}); "
                             "choose another path")


def check_output(path: str, inputs: Iterable[str | os.PathLike[str] | None], force: bool,
                 option_name: str) -> Path:
    """``path`` if a command may write it; checked before any work, so that a bad output path
    never costs a campaign. Refused: a directory or other non-regular file, an existing file
    unless ``force``, a path that is one of ``inputs`` (None entries are skipped), and a path whose
    directory is missing and cannot be made, or cannot be written."""
    if not path:
        raise UsageError(f"{option_name}: the path is empty")
    out = Path(path)
    where = f"{option_name} {path}"
    check_not_input(out, inputs, where)
    if out.exists() and not out.is_file():
        raise UsageError(f"{where}: is a directory" if out.is_dir() else
                         f"{where}: not a regular file")
    if out.exists() and not force:
        raise UsageError(f"{where}: exists already (use --force to replace it)")
    folder = out.absolute().parent
    while not folder.exists():  # the nearest existing folder: the missing ones are made there
        folder = folder.parent
    if not folder.is_dir():
        raise UsageError(f"{where}: {folder} is not a directory")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UsageError(f"{where}: cannot write in {folder}: permission denied")
    return out


def available_cpus() -> int:
    """CPUs this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def clamp_workers(requested: int, episodes: int, command: str, option: str = "--workers",
                  items: str = "episode(s)") -> int:
    """At most one worker process per available CPU and per episode (or other ``items``); a
    note naming ``option`` when reduced."""
    cpus = available_cpus()
    workers = min(requested, cpus, episodes)
    if workers < requested:
        reason = f"{cpus} CPU(s) available" if workers == cpus else f"{episodes} {items}"
        print(f"vlb {command}: note: {option} {requested} reduced to {workers} ({reason})",
              file=sys.stderr)
    return workers


def add_run_options(p: argparse.ArgumentParser, unit: str, study: str) -> None:
    """What every command that runs a study (:class:`~vlb_gym.verify.engine.Study`) takes:
    ``--workers``, ``--store``, the backend's options, ``--keep-going``, ``--quiet`` and
    ``--env-kwarg``; ``unit`` is what it runs ("episode", "pair"), ``study`` what it is
    ("campaign", "comparison")."""
    p.add_argument("--workers", type=count(1), default=1, metavar="N",
                   help=f"worker processes, at most one per CPU and per {unit} (Ray: actors, "
                   "at most one per free CPU of the cluster)")
    p.add_argument("--store", metavar="PATH",
                   help=f"keep every {unit} in this SQLite store as it finishes; an existing "
                   f"store of the same {study} is resumed ({unit}s stored are not run again)")
    add_backend_options(p, f"{unit}s")
    p.add_argument("--keep-going", action="store_true",
                   help="run each episode to its end even after a certificate failed")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_env_kwarg(p)


def backend_name(name: str) -> str:
    """A registered backend's name (the registry is read when the option is, not before)."""
    from vlb_gym.verify.backends import BACKENDS

    if name not in BACKENDS:
        raise argparse.ArgumentTypeError(f"{name!r} is no backend (one of "
                                         f"{', '.join(BACKENDS)})")
    return name


def add_backend_options(p: argparse.ArgumentParser, items: str) -> None:
    """``--backend``, ``--ray-address`` and ``--ray-timeout``."""
    p.add_argument("--backend", type=backend_name, default="process", metavar="BACKEND",
                   help=f"where {items} run: serial (this process), process (worker processes "
                   "on this machine) or ray (Ray actors: extra 'ray', see docs/ray.md); results are identical "
                   "whatever the backend")
    p.add_argument("--ray-address", metavar="ADDRESS",
                   help="with --backend ray: an existing cluster, HOST:PORT of its head (GCS), "
                   "ray://HOST:10001, or auto (RAY_ADDRESS, else the cluster started on this "
                   "machine). Without it, a private local Ray instance is started and stopped "
                   "(RAY_ADDRESS and clusters on this machine are left alone)")
    p.add_argument("--ray-timeout", type=seconds, default=30.0, metavar="SECONDS",
                   help="with --backend ray: give up connecting to --ray-address after this "
                   "long, and on an actor that cannot start after twice this long")


def ray_options(args: argparse.Namespace, command: str):
    """The Ray options of the command line; Ray's notes go to stderr as ``vlb COMMAND: note``."""
    import logging

    from vlb_gym.verify.ray_connect import NOTES, RayOptions

    if args.ray_address and args.backend != "ray":
        raise UsageError("--ray-address needs --backend ray")
    if not NOTES.handlers:
        handler = logging.StreamHandler(sys.stderr)
        handler.setFormatter(logging.Formatter(f"vlb {command}: note: %(message)s"))
        NOTES.addHandler(handler)
        NOTES.propagate = False
    return RayOptions(args.ray_address, args.ray_timeout, 2 * args.ray_timeout)


def add_env_module(p: argparse.ArgumentParser) -> None:
    p.add_argument("--env-module", action="append", default=[], metavar="PATH_OR_MODULE",
                   help="a Python file or module that registers your own environment (see "
                   "docs/new_env.md); importing it runs its code (repeatable)")


def add_env_kwarg(p: argparse.ArgumentParser) -> None:
    p.add_argument("--env-kwarg", action="append", default=[], metavar="NAME=VALUE",
                   help="keyword argument for gym.make, e.g. action_noise=0.5 (repeatable)")
    add_env_module(p)


def add_model_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--base-url", help="OpenAI-compatible server, e.g. "
                   "https://api.openai.com/v1 or http://127.0.0.1:11434/v1 (Ollama; the ollama "
                   "dialect calls its /api/chat)")
    p.add_argument("--model", help="model name at that server")
    p.add_argument("--api-key-env", default="OPENAI_API_KEY", metavar="NAME",
                   help="environment variable holding the API key")
    p.add_argument("--structured-output", default="openai", metavar="DIALECT",
                   choices=["auto", "openai", "llamacpp", "vllm", "ollama", "json_object", "none",
                            "json_schema"],
                   help="how the schema goes with the request: openai (response_format "
                   "json_schema; alias json_schema), llamacpp (json_object + schema: llama.cpp, "
                   "llama-cpp-python), vllm (guided_json), ollama (Ollama's native /api/chat "
                   "with format), json_object (JSON, no schema), none; auto probes the server "
                   "once, in that order, and says which it uses")
    p.add_argument("--timeout", type=seconds, metavar="SECONDS",
                   help="seconds per request (default: 120 for a remote server, 900 for one on "
                   "this machine or a private network, 1800 per reply for --model-path)")
    p.add_argument("--retries", type=count(0), default=3, metavar="N", help="retries per request")
    p.add_argument("--scripted", metavar="FILE",
                   help="canned replies (a JSON list) instead of a live model")
    local = p.add_argument_group("a local model, in this process (extra llm: llama-cpp-python)")
    local.add_argument("--model-path", metavar="FILE.gguf",
                       help="a GGUF model file, decoded with the behavior grammar so every reply "
                       "is well-formed JSON; a progress line shows tokens and tokens/s")
    local.add_argument("--context", type=count(512), default=8192, metavar="TOKENS",
                       help="context window")
    local.add_argument("--threads", type=count(1), metavar="N",
                       help="CPU threads (default: all)")
    p.add_argument("--max-tokens", type=count(1), default=1500, metavar="N",
                   help="tokens per reply")
    p.add_argument("--temperature", type=float, default=0.0, metavar="T",
                   help="sampling temperature; 0 (the default) is greedy")
    p.add_argument("--sampling-seed", type=count(0), default=0, metavar="S",
                   help="seed of the sampler when --temperature > 0 (sent to a server as "
                   "'seed')")



AGENT_KINDS = {False: "sb3", True: "sb3_sampled"}  # by --sample: the policy kinds of agents


def policy_ref(args: argparse.Namespace):
    """The policy named by --policy or --behavior; files by absolute path, so that a store's plan
    means the same from any directory."""
    if args.policy:
        return named_policy(args.policy, True, args.sample)
    return named_policy(args.behavior, False, args.sample)


def named_policy(ref: str, agent: bool, sample: bool, option: str = "--sample",
                 needs: str = "--policy"):
    """A trained agent's zip (``agent``) or a behavior name or file, as a policy reference."""
    from vlb_gym.core.library import is_behavior_path
    from vlb_gym.verify.policies import PolicyRef

    if agent:
        return PolicyRef(AGENT_KINDS[sample], str(Path(ref).resolve()))
    if sample:
        raise UsageError(f"{option} draws a trained agent's actions: it needs {needs}")
    return PolicyRef("behavior", str(Path(ref).resolve()) if is_behavior_path(ref) else ref)


def read_store(path: str):
    """The store at ``path`` (a campaign's or a comparison's), opened read-only."""
    from vlb_gym.verify.store import StoreError, open_readonly

    try:
        return open_readonly(path)
    except StoreError as exc:
        raise UsageError(str(exc)) from None


def untrusted_options(store: str, plan: Plan, args: argparse.Namespace
                      ) -> list[str]:
    """What of the campaign stored in ``store`` is code that the command line does not name
    again."""
    from vlb_gym.verify.replay import untrusted_code

    try:
        return untrusted_code(plan, env_modules(args.env_module), args.policy)
    except ValueError as exc:  # a policy kind no installed package loads
        raise UsageError(f"{store}: {exc}") from None
