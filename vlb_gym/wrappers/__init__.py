"""Gymnasium wrappers of vlb-gym."""

from .robustness import RobustnessWrapper

__all__ = ["RobustnessWrapper"]
