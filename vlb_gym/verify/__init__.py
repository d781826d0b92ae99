"""Verification: bounds (Theorems 1-2, Corollary 1), episodes, campaigns, stores and reports.

Names are imported from their modules on first use, like the package's others: ``vlb plan``
needs the bounds alone, not the behavior compiler that campaigns bring.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from vlb_gym._lazy import lazy_names

if TYPE_CHECKING:
    from .backends import BACKENDS, register_backend
    from .bounds import confidence, lower_bound, min_episodes
    from .campaign import Campaign, report_from_store, run_campaign
    from .comparison import Comparison
    from .engine import Study
    from .episode import run_episode
    from .methods import METHODS, REGISTRY, Method, register
    from .paired_methods import PairedMethod
    from .policies import PolicyRef, register_policy_loader
    from .records import CampaignConfig, ComparisonConfig, EpisodeResult, episode_seed
    from .report import Report
    from .store import CampaignStore, ComparisonStore, StoreError

__getattr__, __dir__, __all__ = lazy_names(__name__, globals(), {
    ".backends": ("BACKENDS", "register_backend"),
    ".bounds": ("confidence", "lower_bound", "min_episodes"),
    ".campaign": ("Campaign", "report_from_store", "run_campaign"),
    ".comparison": ("Comparison",), ".engine": ("Study",), ".episode": ("run_episode",),
    ".methods": ("METHODS", "REGISTRY", "Method", "register"),
    ".paired_methods": ("PairedMethod",),
    ".policies": ("PolicyRef", "register_policy_loader"),
    ".records": ("CampaignConfig", "ComparisonConfig", "EpisodeResult", "episode_seed"),
    ".report": ("Report",), ".store": ("CampaignStore", "ComparisonStore", "StoreError")})
