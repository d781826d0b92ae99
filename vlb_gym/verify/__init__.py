"""Verification: bounds (Theorems 1-2, Corollary 1), episodes and campaigns."""

from .bounds import confidence, lower_bound, min_episodes
from .campaign import (CampaignConfig, build_report, episode_seed, iter_episodes, run_campaign,
                       run_sequential)
from .episode import EpisodeResult, run_episode

__all__ = ["CampaignConfig", "EpisodeResult", "build_report", "confidence", "episode_seed",
           "iter_episodes", "lower_bound", "min_episodes", "run_campaign", "run_episode",
           "run_sequential"]
