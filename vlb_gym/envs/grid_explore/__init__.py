"""``VLB-GridExplore-v0``: env, generator, planner, primitives, helpers, viewer."""

from .env import GridExploreEnv

__all__ = ["GridExploreEnv"]
