"""The behavior robustness rho_B (paper eq. behavior_robustness)."""

from __future__ import annotations

from collections.abc import Iterable


def behavior_robustness(finished: bool, certificates: Iterable[bool]) -> int:
    """+1 iff the behavior finished and every certificate held (vacuously for none), else -1."""
    return 1 if finished and all(certificates) else -1
