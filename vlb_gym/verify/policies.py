"""Policy references: what a campaign verifies, named by a kind and a reference, and loaded by the
package that owns the kind.

A loader is registered under its kind, in process with :func:`register_policy_loader` or by an
installed package through the ``vlb_gym.policies`` entry-point group (vlb-gym registers
``behavior``, behavior graphs, from its core, and ``sb3``, trained Stable-Baselines3 agents,
from its baselines).
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib.metadata import entry_points
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    import gymnasium as gym
    import numpy as np

ENTRY_POINT_GROUP = "vlb_gym.policies"


class Policy(Protocol):
    """What campaigns run: a behavior graph or a trained agent.

    ``predict`` returns ``(action, state)``; an action of None means the policy has finished. A
    behavior graph's state is the node that chose the action (a string, recorded with the step);
    an agent's is its recurrent state or None. ``reset`` gets the episode's reset seed: a policy
    that draws its actions seeds its own generator from it, so that episodes stay independent
    and each replays exactly.
    """

    def reset(self, seed: int | None = None) -> None: ...

    def predict(self, observation: Any, state: Any = None, episode_start: Any = None,
                deterministic: bool = True) -> tuple[np.ndarray | None, Any]: ...


@dataclass(frozen=True)
class PolicyRef:
    """A policy to verify: ``kind`` (``"behavior"``, ``"sb3"`` or a registered one) and ``ref``
    (a behavior name or file, an agent's zip). ``library`` is the behavior library directory that
    behavior names resolve in (default: the user's, see :mod:`vlb_gym.core.library`)."""

    kind: str
    ref: str
    library: str | None = None

    def __str__(self) -> str:
        return self.ref


class PolicyLoader(Protocol):
    """What a kind of policy supplies to campaigns. ``runs_code`` says whether loading a
    reference runs code from it (a pickled agent does): a store naming such a policy is replayed
    only when the user names it again."""

    runs_code: bool
    #: the words of ``vlb replay`` before a reference of this kind (``("--behavior",)``), or
    #: None where ``vlb replay`` cannot name one
    replay_options: tuple[str, ...] | None

    def load(self, ref: PolicyRef, env: gym.Env) -> Policy:
        """The policy, ready to run on ``env`` (checked: a bad reference raises ValueError)."""

    def files(self, ref: PolicyRef, policy: Policy) -> list[Path]:
        """The user's files the policy was read from (outputs must never overwrite them)."""

    def content(self, ref: PolicyRef, policy: Policy) -> dict[str, Any]:
        """What the campaign plan records of the policy: ``sha256`` (of everything that defines
        it) and anything a report draws from (a behavior's ``behaviors``: its specs)."""

    def trained_env(self, ref: PolicyRef) -> tuple[str, dict[str, Any]] | None:
        """The env id and kwargs the policy was made for, where it records them."""


_LOADERS: dict[str, PolicyLoader] = {}


def register_policy_loader(kind: str, loader: PolicyLoader) -> None:
    """Make ``kind`` loadable in this process (before the entry points of installed packages)."""
    _LOADERS[kind] = loader


def policy_loader(kind: str) -> PolicyLoader:
    """The loader of ``kind``; ValueError naming the known kinds if there is none."""
    if kind not in _LOADERS:
        found = entry_points(group=ENTRY_POINT_GROUP, name=kind)
        if not found:
            known = sorted({*_LOADERS, *entry_points(group=ENTRY_POINT_GROUP).names})
            raise ValueError(f"unknown policy kind {kind!r} (known: {', '.join(known)})")
        loader = next(iter(found)).load()
        _LOADERS[kind] = loader() if isinstance(loader, type) else loader
    return _LOADERS[kind]
