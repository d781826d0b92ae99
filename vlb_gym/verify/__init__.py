"""Verification: bounds (Theorems 1-2, Corollary 1), episodes and campaigns."""

from .bounds import confidence, lower_bound, min_episodes
from .campaign import (CampaignConfig, build_report, episode_seed, iter_episodes,
                       report_from_store, run_campaign, run_sequential)
from .episode import EpisodeResult, run_episode
from .store import CampaignStore, StoreError

__all__ = ["CampaignConfig", "CampaignStore", "EpisodeResult", "StoreError", "build_report",
           "confidence", "episode_seed", "iter_episodes", "lower_bound", "min_episodes",
           "report_from_store", "run_campaign", "run_episode", "run_sequential"]
