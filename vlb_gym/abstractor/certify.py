"""Certifying a found behavior: a fixed-N campaign of the verifier on fresh seeds.

A behavior the search found kept its promise on the screening episodes, which chose it; it is
certified by the campaign engine itself (:class:`~vlb_gym.verify.campaign.Campaign`): N
episodes of a root seed drawn afresh from the operating system's entropy, every one of which
must keep every certificate and the promise. The search certifies at most ``attempts``
behaviors; a behavior below 1 - eps passes one such campaign with probability at most
``(1 - eps)**N``, so N is the least with ``attempts * (1 - eps)**N <= delta`` (a union bound) and
the confidence of the whole procedure is ``1 - attempts * (1 - eps)**N``.

The behavior file carries its :class:`~vlb_gym.core.spec.Certificate` (the promise, the env and
its kwargs, the campaign's root seed, N, successes, eps, the confidence, the behavior's content
digest and the package version): ``vlb verify ENV --behavior FILE --episodes N --seed S``
runs the same episodes again and counts the same successes.
"""

from __future__ import annotations

import json
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from vlb_gym.core.spec import Certificate
from vlb_gym.verify.bounds import min_episodes
from vlb_gym.verify.campaign import Campaign
from vlb_gym.verify.policies import PolicyRef
from vlb_gym.verify.records import CampaignConfig
from vlb_gym.verify.report import Report

EPSILON = 0.05
DELTA = 0.01
ATTEMPTS = 3


def certification_episodes(epsilon: float = EPSILON, delta: float = DELTA,
                           attempts: int = ATTEMPTS) -> int:
    """The least N with ``attempts * (1 - epsilon)**N <= delta``."""
    return min_episodes(epsilon, 1 - delta / attempts)


def procedure_confidence(epsilon: float = EPSILON, delta: float = DELTA,
                         attempts: int = ATTEMPTS) -> float:
    """The confidence of a behavior that passed one of up to ``attempts`` certifications."""
    return 1 - attempts * (1 - epsilon) ** certification_episodes(epsilon, delta, attempts)


@dataclass
class Certification:
    """One certification campaign: its report, and the certificate if it passed."""

    report: Report
    certificate: Certificate | None

    @property
    def passed(self) -> bool:
        return self.certificate is not None

    @property
    def seed(self) -> int:
        return self.report["seed"]

    @property
    def successes(self) -> int:
        return self.report["successes"]

    @property
    def episodes(self) -> int:
        return self.report["episodes"]

    @property
    def failed_seeds(self) -> list[int]:
        """Reset seeds of a few failed episodes (up to three per cause)."""
        return [seed for group in self.report.get("failures_by_cause", [])
                for seed in group["seeds"]]


def certify(env_id: str, document: dict[str, Any], seed: int,
            env_kwargs: dict[str, Any] | None = None, epsilon: float = EPSILON,
            delta: float = DELTA, attempts: int = ATTEMPTS, workers: int = 1) -> Certification:
    """Run the certification campaign of ``document`` (a behavior with its promise) from root
    seed ``seed`` (see the module's docstring)."""
    episodes = certification_episodes(epsilon, delta, attempts)
    with tempfile.TemporaryDirectory(prefix="vlb-certify-") as scratch:
        path = Path(scratch) / f"{document['name']}.json"
        path.write_text(json.dumps(document))
        config = CampaignConfig(env_id, PolicyRef("behavior", str(path)), episodes, epsilon,
                                seed=seed, env_kwargs=dict(env_kwargs or {}))
        with Campaign(config) as campaign:
            report = campaign.run(workers)
            plan = campaign.plan
    if report["successes"] != episodes:
        return Certification(report, None)
    certificate = Certificate(
        promise=document["promise"]["expr"],
        as_soon_as=document["promise"].get("as_soon_as", False), env=env_id,
        env_kwargs=dict(env_kwargs or {}),
        seed=seed, episodes=episodes, successes=report["successes"], epsilon=epsilon,
        confidence=procedure_confidence(epsilon, delta, attempts), attempts=attempts,
        content_sha256=plan.content_sha256, vlb_gym=plan.versions["vlb_gym"])
    return Certification(report, certificate)
