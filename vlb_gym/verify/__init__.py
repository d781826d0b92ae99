"""Verification: bounds (Theorems 1-2, Corollary 1), episodes, campaigns, stores and reports.

Names are imported from their modules on first use, like the package's others: ``vlb plan``
needs the bounds alone, not the behavior compiler that campaigns bring.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from vlb_gym._lazy import lazy_names

if TYPE_CHECKING:
    from .bounds import confidence, lower_bound, min_episodes
    from .campaign import Campaign, CampaignConfig, episode_seed, report_from_store, run_campaign
    from .episode import EpisodeResult, run_episode
    from .methods import METHODS, Method
    from .policies import PolicyRef, register_policy_loader
    from .report import Report
    from .store import CampaignStore, StoreError

__all__ = ["METHODS", "Campaign", "CampaignConfig", "CampaignStore", "EpisodeResult", "Method",
           "PolicyRef", "Report", "StoreError", "confidence", "episode_seed", "lower_bound",
           "min_episodes", "register_policy_loader", "report_from_store", "run_campaign",
           "run_episode"]
__getattr__, __dir__ = lazy_names(__name__, globals(), {
    ".bounds": ("confidence", "lower_bound", "min_episodes"),
    ".campaign": ("Campaign", "CampaignConfig", "episode_seed", "report_from_store",
                  "run_campaign"),
    ".episode": ("EpisodeResult", "run_episode"), ".methods": ("METHODS", "Method"),
    ".policies": ("PolicyRef", "register_policy_loader"),
    ".report": ("Report",), ".store": ("CampaignStore", "StoreError")})
