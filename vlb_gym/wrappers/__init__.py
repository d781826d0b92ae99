"""Gymnasium wrappers of vlb-gym."""

from .behavior import BehaviorAgent, BehaviorFinished
from .robustness import RobustnessWrapper

__all__ = ["BehaviorAgent", "BehaviorFinished", "RobustnessWrapper"]
