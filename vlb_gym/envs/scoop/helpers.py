"""Decision helpers of the scooping env: read the end-effector pose from the observation."""

from __future__ import annotations

from typing import Any

import numpy as np

from vlb_gym.core.helpers import Helpers, Judge, brief, helper
from vlb_gym.core.promise import Episode

Pose = tuple[float, float, float, float, float, float]


def _number(fn: str, value: Any) -> float:
    """``value`` as a float if it is a real number (checked before anything else)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{fn}(): {brief(value)} is not a number")
    return float(value)


class ScoopHelpers(Helpers):
    """Helpers for ``VLB-Scoop-v0`` observations.

    A Pose is a tuple (x, y, z, roll, pitch, yaw) of the flange in the robot base frame: metres and
    radians (extrinsic x-y-z angles). The scoop primitive's parameter is a sensing Pose.
    """

    def __init__(self) -> None:
        self._pose: Pose = (0.0,) * 6

    def bind(self, observation: Any) -> None:
        self._pose = tuple(float(v) for v in observation)

    @helper
    def current_pose(self) -> Pose:
        """The flange pose now."""
        return self._pose

    @helper
    def offset(self, pose: Pose, dx: float, dy: float, dz: float) -> Pose:
        """``pose`` moved by (dx, dy, dz) metres in the base frame, orientation unchanged."""
        if not (isinstance(pose, (tuple, list)) and len(pose) == 6):
            raise ValueError(f"offset(): {brief(pose)} is not a pose (x, y, z, roll, pitch, yaw)")
        values = [_number("offset", v) for v in (*pose, dx, dy, dz)]
        x, y, z, roll, pitch, yaw, dx, dy, dz = values
        return (x + dx, y + dy, z + dz, roll, pitch, yaw)


class ScoopJudge(Judge):
    """Outcome helpers for ``VLB-Scoop-v0`` promises: what the behavior's scoops measured.

    Masses are in grams, as the scoop primitive measures them (grains in the receiver, on the
    table, in the spoon).
    """

    def __init__(self) -> None:
        self._steps: list[dict[str, Any]] = []

    def bind(self, episode: Episode) -> None:
        self._steps = [dict(s) for s in episode.steps]

    def _now(self, key: str) -> float:
        """``key`` as the last scoop measured it: the scoop primitive weighs what lies in the
        receiver (or on the table) after it, everything so far, not what it alone added."""
        measured = [s[key] for s in self._steps if s["primitive"] == "scoop" and key in s]
        return float(measured[-1]) if measured else 0.0

    @helper
    def scoops(self) -> int:
        """How many scoops the behavior ran."""
        return sum(1 for s in self._steps if s["primitive"] == "scoop")

    @helper
    def delivered(self) -> float:
        """Grams the behavior's scoops delivered into the receiver, in all (the receiver's
        contents after the last scoop)."""
        return self._now("mass_delivered")

    @helper
    def spilled(self) -> float:
        """Grams the behavior's scoops spilled outside both containers, in all (what lies
        outside them after the last scoop)."""
        return self._now("mass_spilled")

    def summary(self) -> str:
        return (f"{self.scoops()} scoop(s), {self.delivered():.1f} g delivered, "
                f"{self.spilled():.1f} g spilled")
