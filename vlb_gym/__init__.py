"""vlb-gym: verifiable behaviors composed from motion primitives.

Importing the package registers ``VLB-GridExplore-v0`` and ``VLB-Scoop-v0``.
"""

from gymnasium.envs.registration import register, registry

from .core import BehaviorPolicy, BehaviorSpecError, load_behavior, shipped_behaviors
from .wrappers import RobustnessWrapper

__version__ = "0.1.0"

ENV_IDS = ("VLB-GridExplore-v0", "VLB-Scoop-v0")

if "VLB-GridExplore-v0" not in registry:
    register(id="VLB-GridExplore-v0", entry_point="vlb_gym.baselines.tasks:make_grid_explore",
             max_episode_steps=500)
if "VLB-Scoop-v0" not in registry:  # needs the [scoop] extra (mujoco)
    register(id="VLB-Scoop-v0", entry_point="vlb_gym.envs.scoop:ScoopEnv", max_episode_steps=20)

__all__ = ["ENV_IDS", "BehaviorPolicy", "BehaviorSpecError", "RobustnessWrapper",
           "load_behavior", "shipped_behaviors", "__version__"]
