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
    from .core.errors import UserError
    from .wrappers import BehaviorAgent, BehaviorFinished, RobustnessWrapper

__version__ = "0.1.0"

#: Every environment of the package, registered on import: (id, entry point, step bound).
ENVS = (
    ("VLB-GridExplore-v0", "vlb_gym.envs.grid_explore:GridExploreEnv", 500),
    ("VLB-Scoop-v0", "vlb_gym.envs.scoop:ScoopEnv", 20),  # needs the [scoop] extra (mujoco)
)
ENV_IDS = tuple(env_id for env_id, _, _ in ENVS)

#: The RL tasks on the grid (a reward, termination when the task is done, the observation keys
#: a memoryless policy needs), each an id of its own so that no env kwarg can change what
#: "finished" means; they live in :mod:`vlb_gym.baselines.tasks`.
RL_TASKS = (
    ("VLB-GridExplore-FindGoal-v0", "vlb_gym.baselines.tasks:find_goal", 500),
    ("VLB-GridExplore-FindGoalAndOscillate-v0",
     "vlb_gym.baselines.tasks:find_goal_and_oscillate", 500),
)

for _id, _entry_point, _steps in ENVS + RL_TASKS:
    if _id not in registry:
        register(id=_id, entry_point=_entry_point, max_episode_steps=_steps)

__getattr__, __dir__, _names = lazy_names(__name__, globals(), {
    ".core": ("BehaviorPolicy", "BehaviorSpecError", "load_behavior", "shipped_behaviors"),
    ".core.errors": ("UserError",),
    ".wrappers": ("BehaviorAgent", "BehaviorFinished", "RobustnessWrapper")})
__all__ = ["ENV_IDS", "ENVS", "RL_TASKS", "__version__", *_names]
del _names
