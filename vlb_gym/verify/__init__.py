"""Verification: bounds (Theorems 1-2, Corollary 1), episodes, campaigns, stores and reports."""

from .bounds import confidence, lower_bound, min_episodes
from .campaign import (Campaign, CampaignConfig, episode_seed, report_from_store, run_campaign,
                       run_sequential)
from .episode import EpisodeResult, run_episode
from .policies import PolicyRef, register_policy_loader
from .report import Report
from .store import CampaignStore, StoreError

__all__ = ["Campaign", "CampaignConfig", "CampaignStore", "EpisodeResult", "PolicyRef", "Report",
           "StoreError", "confidence", "episode_seed", "lower_bound", "min_episodes",
           "register_policy_loader", "report_from_store", "run_campaign", "run_episode",
           "run_sequential"]
