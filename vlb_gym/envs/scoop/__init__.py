"""``VLB-Scoop-v0``: scene, piles, generator, kinematics, motion, perception, controller,
primitives, helpers, env."""

import os

# headless rendering by default; must happen before the first ``import mujoco``
os.environ.setdefault("MUJOCO_GL", "egl")

from .env import ScoopEnv  # noqa: E402

__all__ = ["ScoopEnv"]
