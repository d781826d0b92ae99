"""vlb-gym: verifiable behaviors composed from motion primitives.

Importing the package registers ``VLB-GridExplore-v0`` and ``VLB-Scoop-v0``; its other names
are imported on first use, so that importing the package (and starting ``vlb``) stays quick.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gymnasium.envs.registration import register, registry

from ._lazy import lazy_names

if TYPE_CHECKING:
    from .core import BehaviorPolicy, BehaviorSpecError, load_behavior, shipped_behaviors
    from .wrappers import BehaviorAgent, BehaviorFinished, RobustnessWrapper

__version__ = "0.1.0"

#: Every environment of the package, registered on import: (id, entry point, step bound). The
#: grid's entry point applies the RL task wrapper for ``gym.make(..., task=...)``.
ENVS = (
    ("VLB-GridExplore-v0", "vlb_gym.baselines.tasks:make_grid_explore", 500),
    ("VLB-Scoop-v0", "vlb_gym.envs.scoop:ScoopEnv", 20),  # needs the [scoop] extra (mujoco)
)
ENV_IDS = tuple(env_id for env_id, _, _ in ENVS)

for _id, _entry_point, _steps in ENVS:
    if _id not in registry:
        register(id=_id, entry_point=_entry_point, max_episode_steps=_steps)

__all__ = ["ENV_IDS", "ENVS", "BehaviorAgent", "BehaviorFinished", "BehaviorPolicy",
           "BehaviorSpecError", "RobustnessWrapper", "load_behavior", "shipped_behaviors",
           "__version__"]
__getattr__, __dir__ = lazy_names(__name__, globals(), {
    ".core": ("BehaviorPolicy", "BehaviorSpecError", "load_behavior", "shipped_behaviors"),
    ".wrappers": ("BehaviorAgent", "BehaviorFinished", "RobustnessWrapper")})
