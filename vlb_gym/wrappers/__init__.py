"""Gymnasium wrappers of vlb-gym (imported on first use, like the package's other names)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from vlb_gym._lazy import lazy_names

if TYPE_CHECKING:
    from .behavior import BehaviorAgent, BehaviorFinished
    from .robustness import RobustnessWrapper

__getattr__, __dir__, __all__ = lazy_names(__name__, globals(), {
    ".behavior": ("BehaviorAgent", "BehaviorFinished"), ".robustness": ("RobustnessWrapper",)})
