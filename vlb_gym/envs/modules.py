"""Loading a user's environment module, which registers its envs with Gymnasium on import.

``vlb ... --env-module PATH_OR_MODULE`` and campaign workers use :func:`import_env_module`, so
that an env of the user's (see ``docs/new_env.md``) can be verified like the shipped ones.
Importing a module runs its code: name only modules you trust.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import gymnasium as gym

from vlb_gym.core.errors import UserError
from vlb_gym.core.files import input_bytes

_BY_PATH: dict[Path, ModuleType] = {}


def is_module_path(ref: str) -> bool:
    """Whether ``ref`` names a file (``.py`` or with a ``/``) rather than a dotted module."""
    return ref.endswith(".py") or "/" in ref


def import_env_module(ref: str) -> ModuleType:
    """Import ``ref``: a Python file (as a module named after its stem, kept in ``sys.modules``
    so that its entry points resolve and its envs pickle) or a dotted module name. Each file is
    executed once per process."""
    if not is_module_path(ref):
        return importlib.import_module(ref)
    path = Path(ref).resolve()
    if path in _BY_PATH:
        return _BY_PATH[path]
    spec = importlib.util.spec_from_file_location(path.stem, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"{ref}: not a Python module")
    module = importlib.util.module_from_spec(spec)
    sys.modules[path.stem] = module
    try:  # from the bytes: a campaign's workers have them shipped, not on their disk
        exec(compile(input_bytes(path), str(path), "exec"), module.__dict__)
    except BaseException:
        del sys.modules[path.stem]
        raise
    _BY_PATH[path] = module
    return module


class EnvSetupError(UserError, ValueError):
    """The environment cannot be made as asked: unknown id, a module that fails to import,
    settings the env refuses."""


def make_primitive_env(env_id: str, kwargs: dict[str, Any], modules: Sequence[str] = ()
                       ) -> gym.Env:
    """``gym.make(env_id, **kwargs)`` after importing ``modules``, checked: a vlb-gym env or a
    :class:`~vlb_gym.core.env.PrimitiveEnv` registered by one of ``modules``, reset once so that
    impossible settings fail here, not in every episode. :class:`EnvSetupError` otherwise."""
    import vlb_gym
    from vlb_gym.core.env import PrimitiveEnv

    for ref in modules:
        try:
            import_env_module(ref)
        except Exception as exc:  # a module of the user's: any failure is their input's
            raise EnvSetupError(f"--env-module {ref}: {type(exc).__name__}: {exc}") from None
    unknown = EnvSetupError(f"unknown environment {env_id!r} (vlb-gym registers: "
                            f"{', '.join(vlb_gym.ENV_IDS)}; an env of your own needs "
                            "--env-module)")
    if env_id not in gym.registry:
        raise unknown
    steps = kwargs.get("max_episode_steps", 1)
    if not isinstance(steps, int) or isinstance(steps, bool) or steps < 1:
        raise EnvSetupError(f"{env_id}: max_episode_steps must be a positive integer "
                            f"(got {steps!r})")
    try:
        env = gym.make(env_id, **kwargs)
    except ImportError as exc:
        raise EnvSetupError(str(exc)) from None
    except (TypeError, ValueError) as exc:
        raise _bad_kwargs(env_id, kwargs, exc) from None
    try:
        if not isinstance(env.unwrapped, PrimitiveEnv):
            raise unknown
        env.reset(seed=0)
    except (TypeError, ValueError) as exc:
        env.close()
        raise (exc if isinstance(exc, EnvSetupError) else _bad_kwargs(env_id, kwargs, exc)
               ) from None
    return env


def _bad_kwargs(env_id: str, kwargs: dict[str, Any], exc: Exception) -> EnvSetupError:
    # gym.make appends "was raised from the environment creator ..." to a TypeError
    message = str(exc).split(" was raised from the environment creator")[0]
    return EnvSetupError(f"{env_id}: bad environment arguments {kwargs}: {message}")
