"""Finding and loading behavior files: shipped ones by name, the user's by path."""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import Any

import gymnasium as gym

from .behavior import BehaviorPolicy, compile_behavior, CompiledBehavior
from .spec import BehaviorSpec, BehaviorSpecError, parse_spec

SHIPPED = "vlb_gym.behaviors"


def shipped_behaviors() -> list[str]:
    """Names of the behaviors that ship with the package."""
    return sorted(p.name[:-5] for p in resources.files(SHIPPED).iterdir()
                  if p.name.endswith(".json"))


def _is_path(ref: str) -> bool:
    return ref.endswith(".json") or "/" in ref or "\\" in ref


def resolve(ref: str, base_dir: Path | None = None) -> tuple[BehaviorSpec, str, Path | None]:
    """Load ``ref`` (a shipped name or a path, relative to ``base_dir`` if given) as a spec."""
    if _is_path(ref):
        path = Path(ref).expanduser()
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
        try:
            text = path.read_bytes()
        except OSError as exc:
            raise BehaviorSpecError(f"{path}: cannot read behavior file: {exc.strerror}") from None
        return parse_spec(text, str(path)), str(path.resolve()), path.resolve().parent
    if ref not in shipped_behaviors():
        raise BehaviorSpecError(f"unknown behavior {ref!r}: shipped behaviors are "
                                f"{', '.join(shipped_behaviors())}; or give a path to a .json file")
    text = resources.files(SHIPPED).joinpath(f"{ref}.json").read_bytes()
    return parse_spec(text, f"{ref}.json"), f"{ref}.json", None


def compile_for(ref: str, env: gym.Env) -> CompiledBehavior:
    """Resolve ``ref`` and compile it against ``env`` (wrappers are looked through)."""
    interface: Any = env.unwrapped
    spec, source, base_dir = resolve(ref)
    env_id = getattr(interface, "env_id", None)
    if spec.env is not None and env_id is not None and spec.env != env_id:
        raise BehaviorSpecError(f"{source}: env: behavior is written for {spec.env!r}, "
                                f"not {env_id!r}")
    return compile_behavior(spec, interface, source, resolve, base_dir)


def load_behavior(ref: str, env: gym.Env) -> BehaviorPolicy:
    """A ready-to-run policy for behavior ``ref`` (shipped name or path) on ``env``."""
    return BehaviorPolicy(compile_for(ref, env), env.unwrapped)
