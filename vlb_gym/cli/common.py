"""What every ``vlb`` command shares: argument types, env checks, the usage error."""

from __future__ import annotations

import argparse
import json
from typing import Any

import gymnasium as gym

import vlb_gym


class UsageError(Exception):
    """Bad input from the command line; printed without a traceback, exit code 2."""


def probability(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 < value < 1:
        raise argparse.ArgumentTypeError(f"{text} must lie strictly between 0 and 1")
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
        try:
            kwargs[key] = json.loads(value)
        except json.JSONDecodeError:
            kwargs[key] = value
    return kwargs


def check_env(env_id: str, kwargs: dict[str, Any]) -> None:
    if env_id not in gym.registry:
        known = ", ".join(vlb_gym.ENV_IDS)
        raise UsageError(f"unknown environment {env_id!r} (vlb-gym registers: {known})")
    try:
        gym.make(env_id, **kwargs).close()
    except ImportError as exc:
        raise UsageError(str(exc)) from None
    except (TypeError, ValueError) as exc:
        raise UsageError(f"{env_id}: bad environment arguments {kwargs}: {exc}") from None


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
    p.add_argument("--timeout", type=float, default=60.0, help="seconds per request")
    p.add_argument("--retries", type=count(0), default=3, help="retries per request")
    p.add_argument("--scripted", metavar="FILE",
                   help="canned replies (a JSON list) instead of a live model")
