"""What every ``vlb`` command shares: argument types, env checks, the usage error."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any, NoReturn

import gymnasium as gym

import vlb_gym


class UsageError(Exception):
    """Bad input from the command line; printed without a traceback, exit code 2."""


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line, like every other error of ``vlb``."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def probability(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 < value < 1:
        raise argparse.ArgumentTypeError(f"{text} must lie strictly between 0 and 1")
    return value


def seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 < value < math.inf:
        raise argparse.ArgumentTypeError(f"{text} must be a positive number of seconds")
    return value


def count(minimum: int):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{text} must be at least {minimum}")
        return value
    return parse


def env_kwargs(pairs: list[str]) -> dict[str, Any]:
    kwargs = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key.isidentifier():
            raise UsageError(f"--env-kwarg {pair!r}: expected NAME=VALUE, e.g. action_noise=0.5")
        if key == "render_mode":
            raise UsageError("--env-kwarg render_mode: vlb chooses the render mode itself "
                             "('vlb render' films an episode)")
        try:
            kwargs[key] = json.loads(value)
        except json.JSONDecodeError:
            kwargs[key] = value
    return kwargs


def check_env(env_id: str, kwargs: dict[str, Any]) -> None:
    """Refuse env ids that vlb-gym does not register and settings the env refuses: it is made
    and reset once here, so that impossible settings fail now, not in every episode."""
    if env_id not in vlb_gym.ENV_IDS:
        raise UsageError(f"unknown environment {env_id!r} (vlb-gym registers: "
                         f"{', '.join(vlb_gym.ENV_IDS)})")
    steps = kwargs.get("max_episode_steps", 1)
    if not isinstance(steps, int) or isinstance(steps, bool) or steps < 1:
        raise UsageError(f"{env_id}: max_episode_steps must be a positive integer (got {steps!r})")
    try:
        env = gym.make(env_id, **kwargs)
        try:
            env.reset(seed=0)
        finally:
            env.close()
    except ImportError as exc:
        raise UsageError(str(exc)) from None
    except (TypeError, ValueError) as exc:
        # gym.make appends "was raised from the environment creator ..." to a TypeError
        message = str(exc).split(" was raised from the environment creator")[0]
        raise UsageError(f"{env_id}: bad environment arguments {kwargs}: {message}") from None


def add_env_kwarg(p: argparse.ArgumentParser) -> None:
    p.add_argument("--env-kwarg", action="append", default=[], metavar="NAME=VALUE",
                   help="keyword argument for gym.make, e.g. action_noise=0.5 (repeatable)")


def add_model_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--base-url", help="OpenAI-compatible server, e.g. "
                   "https://api.openai.com/v1 or http://127.0.0.1:11434/v1 (Ollama)")
    p.add_argument("--model", help="model name at that server")
    p.add_argument("--api-key-env", default="OPENAI_API_KEY",
                   help="environment variable holding the API key (default OPENAI_API_KEY)")
    p.add_argument("--structured-output", choices=["json_schema", "json_object", "none"],
                   default="json_schema", help="what the server supports (default json_schema)")
    p.add_argument("--timeout", type=seconds, default=60.0, help="seconds per request")
    p.add_argument("--retries", type=count(0), default=3, help="retries per request")
    p.add_argument("--scripted", metavar="FILE",
                   help="canned replies (a JSON list) instead of a live model")
