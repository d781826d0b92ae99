"""A campaign's inputs, shipped to its workers: the user's files travel with the task, so that
no worker reads them (or the user's environment) by path, and every worker checks what it
built against the driver's plan.

On the driver, :func:`capture` reads the files the policy was loaded from (a behavior file and
its sub-behaviors, library behaviors of the user's, an agent's zip and metadata) and the
``--env-module`` files into an :class:`Inputs`. In a worker, :class:`ShippedRunner` builds the
env and the policy with those bytes for files (:func:`vlb_gym.core.files.shipped`: no other
file of the user's is read, behavior names resolve in the driver's library folder), then
compares the policy's content digest, the sampling distribution and the package versions with
the plan's: a difference is :class:`InputsDiffer`, never a result.
"""

from __future__ import annotations

import copy
import os
import platform
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import gymnasium as gym
import numpy as np

import vlb_gym
from vlb_gym.core.files import input_bytes, shipped
from vlb_gym.core.library import user_dir
from vlb_gym.core.names import is_name
from vlb_gym.envs.modules import is_module_path

from .backends import BackendError
from .policies import PolicyRef

if TYPE_CHECKING:
    from .records import CampaignConfig, Plan


class InputsDiffer(BackendError):
    """A worker built something other than the driver's plan (another package version, a
    behavior that resolves differently): its results would not be the plan's."""


def versions() -> dict[str, str]:
    """The versions a plan records; workers must run the same."""
    return {"vlb_gym": vlb_gym.__version__, "gymnasium": gym.__version__,
            "numpy": np.__version__, "python": platform.python_version()}


@dataclass(frozen=True)
class Inputs:
    """The user's files of a campaign (absolute resolved path -> bytes), the library folder
    its behavior names resolve in, and what the plan says a worker must build from them."""

    files: Mapping[str, bytes]
    library: str
    content_sha256: str
    sampling_distribution: str
    versions: Mapping[str, str]


def _absolute(ref: str) -> str:
    return str(Path(ref).expanduser().resolve())


def capture(config: CampaignConfig, policy_files: list[Path], plan: Plan) -> Inputs:
    """The inputs of the campaign of ``config`` with ``plan``, read now
    from ``policy_files`` and the config's module files."""
    files = {}
    for path in [*map(str, policy_files),
                 *(m for m in config.env_modules if is_module_path(m))]:
        data = input_bytes(path)  # keyed as resolved here and as named (a worker may lack a link)
        files[_absolute(path)] = files[os.path.abspath(Path(path).expanduser())] = data
    return Inputs(files,
                  _absolute(config.policy.library or str(user_dir())), plan.content_sha256,
                  plan.sampling_distribution, dict(plan.versions))


def rebased(config: CampaignConfig, inputs: Inputs) -> CampaignConfig:
    """``config`` as a worker builds it: file references absolute as the driver resolved them,
    behavior names resolved in the driver's library folder."""
    ref = config.policy
    policy = PolicyRef(ref.kind, ref.ref if is_name(ref.ref) else _absolute(ref.ref),
                       inputs.library)
    modules = tuple(_absolute(m) if is_module_path(m) else m for m in config.env_modules)
    worker = copy.copy(config)  # validated by the driver: a worker need not know its method
    object.__setattr__(worker, "policy", policy)
    object.__setattr__(worker, "env_modules", modules)
    return worker


def check(inputs: Inputs, content_sha256: str, sampling: str) -> None:
    """InputsDiffer unless what a worker built is the plan's."""
    here = versions()
    for name, version in inputs.versions.items():
        if here.get(name) != version:
            raise InputsDiffer(f"a worker runs {name} {here.get(name)}, the campaign's plan "
                               f"{version}: install the same versions on every node")
    if content_sha256 != inputs.content_sha256:
        raise InputsDiffer(f"a worker built a policy with content digest {content_sha256[:12]}, "
                           f"not the plan's {inputs.content_sha256[:12]}: the behaviors it "
                           "resolved differ from the driver's (install the same vlb-gym on "
                           "every node)")
    if sampling != inputs.sampling_distribution:
        raise InputsDiffer("a worker's env samples from another distribution than the plan's "
                           "(another env module or package on that node)")


@dataclass(frozen=True)
class ShippedRunner:
    """A backend's ``setup``: ``runner(config, built)`` on the env and policy built from the
    shipped ``inputs`` (see the module's docstring)."""

    config: CampaignConfig
    inputs: Inputs
    runner: Callable[..., Callable[[int], Any]]

    def build(self) -> tuple[Any, Any]:
        """The env and policy, built from the shipped files and checked against the plan."""
        from .episode import build
        from .policies import policy_loader

        config = rebased(self.config, self.inputs)
        with shipped(self.inputs.files):
            env, policy = build(config)
            try:
                digest = policy_loader(config.policy.kind).content(config.policy, policy)
                check(self.inputs, digest["sha256"], env.unwrapped.sampling_distribution())
            except BaseException:
                env.close()
                raise
        return env, policy

    def __call__(self) -> Callable[[int], Any]:
        return self.runner(self.config, self.build())
