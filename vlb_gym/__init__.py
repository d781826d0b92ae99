"""vlb-gym: verifiable behaviors composed from motion primitives.

Importing the package registers ``VLB-GridExplore-v0`` and ``VLB-Scoop-v0``; its other names
are imported on first use, so that importing the package (and starting ``vlb``) stays quick.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from gymnasium.envs.registration import register, registry

if TYPE_CHECKING:
    from .core import BehaviorPolicy, BehaviorSpecError, load_behavior, shipped_behaviors
    from .wrappers import RobustnessWrapper

__version__ = "0.1.0"

ENV_IDS = ("VLB-GridExplore-v0", "VLB-Scoop-v0")

if "VLB-GridExplore-v0" not in registry:
    register(id="VLB-GridExplore-v0", entry_point="vlb_gym.baselines.tasks:make_grid_explore",
             max_episode_steps=500)
if "VLB-Scoop-v0" not in registry:  # needs the [scoop] extra (mujoco)
    register(id="VLB-Scoop-v0", entry_point="vlb_gym.envs.scoop:ScoopEnv", max_episode_steps=20)

_LAZY = {"BehaviorPolicy": ".core", "BehaviorSpecError": ".core", "load_behavior": ".core",
         "shipped_behaviors": ".core", "RobustnessWrapper": ".wrappers"}

__all__ = ["ENV_IDS", "BehaviorPolicy", "BehaviorSpecError", "RobustnessWrapper",
           "load_behavior", "shipped_behaviors", "__version__"]


def __getattr__(name: str) -> Any:  # PEP 562
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(_LAZY[name], __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})
