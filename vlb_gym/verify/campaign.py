"""Verification campaigns: N i.i.d. episodes -> a probabilistic guarantee.

One pipeline: a :class:`CampaignConfig` names the campaign; :class:`Campaign` prepares it once
(the env made and checked, the policy loaded and checked, the plan made: what a store records
first); its episodes run on a backend (:mod:`.backends`) and land, one
:class:`~.episode.EpisodeResult` each, in the caller's hands, the store and the JSONL export; a
:class:`~.report.Report` is built from the plan and the records alone.

Episode ``i`` of a campaign with seed ``s`` resets the environment with the ``i``-th child of
``numpy.random.SeedSequence(s)`` (as ``SeedSequence(s).spawn(N)[i]`` would give), so results do
not depend on the backend, the number of workers or the order in which episodes finish.
"""

from __future__ import annotations

import dataclasses
import functools
import json
from collections.abc import Callable, Iterator, Sequence
from typing import ClassVar

from .engine import EpisodeStudy, Remaining, run_where
from .episode import EpisodeResult, build, episode_runner, episode_seed
from .inputs import Inputs, ShippedRunner, capture, versions
from .methods import Method, method_named
from .policies import policy_loader
from .ray_connect import RayOptions
from .records import CampaignConfig, Plan, plan_from_json
from .report import Report
from .store import CampaignStore

__all__ = ["Campaign", "CampaignConfig", "Remaining", "build", "episode_runner", "episode_seed",
           "lightened", "report_and_records", "report_from_store", "run_campaign"]


class Campaign(EpisodeStudy[Report]):
    """A campaign prepared once: the env made and reset, the policy loaded (a bad behavior file or
    agent fails here, before any episode), the env the policy was trained on checked, and the
    :attr:`plan` made; its unit is an episode, run by the engine (:class:`~.engine.Study`).
    Close it when done (or use it as a context manager)."""

    store_kind: ClassVar[type[CampaignStore]] = CampaignStore

    def __init__(self, config: CampaignConfig):
        loader = policy_loader(config.policy.kind)
        trained = loader.trained_env(config.policy)
        if trained is not None:  # an agent runs on the env it was trained on
            env_id, kwargs = trained
            if env_id != config.env_id:
                raise ValueError(f"{config.policy.ref} was trained on {env_id}, "
                                 f"not {config.env_id}")
            config = dataclasses.replace(config, env_kwargs={**kwargs, **config.env_kwargs})
        self.config = config
        self.env, self.policy = build(config)
        self.files = loader.files(config.policy, self.policy)  # the user's inputs
        content = loader.content(config.policy, self.policy)
        self.plan: Plan = plan_from_json(json.dumps({  # as stored: tuples are lists
            **dataclasses.asdict(config), "content_sha256": content.pop("sha256"),
            "policy_content": content,
            "sampling_distribution": self.env.unwrapped.sampling_distribution(),
            "versions": versions()}))
        self.inputs: Inputs = capture(config, self.files, self.plan)  # what workers build from

    def __enter__(self) -> Campaign:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self.env.close()

    def episodes(self, indices: Sequence[int] | None = None, workers: int = 1,
                 backend: str = "process", ray: RayOptions | None = None
                 ) -> Iterator[EpisodeResult]:
        """Stream the results of ``indices`` (default: all N) as they finish, in index order on
        one worker. Closing the generator stops the workers."""
        indices = range(self.config.episodes) if indices is None else indices
        return run_where(ShippedRunner(self.config, self.inputs, episode_runner),
                         functools.partial(episode_runner, self.config, (self.env, self.policy)),
                         indices, workers, backend, ray, self.env.unwrapped.preload)

    units = episodes

    @property
    def planned(self) -> int:
        return self.config.episodes

    @property
    def preloads(self) -> Sequence[str]:
        return self.env.unwrapped.preload

    @classmethod
    def method_of(cls, plan: CampaignConfig) -> Method:
        return method_named(plan.method)(plan.epsilon, plan.delta, plan.episodes)

    @staticmethod
    def lightened(result: EpisodeResult) -> EpisodeResult:
        return lightened(result)

    report = staticmethod(Report.build)


def lightened(result: EpisodeResult) -> EpisodeResult:
    """What a campaign keeps of a finished episode for its report: a success without its steps
    and start (the store and the export have them), a failure whole."""
    if not result.success:
        return result
    return dataclasses.replace(result, steps=(), start={})


def run_campaign(config: CampaignConfig, workers: int = 1,
                 on_episode: Callable[[EpisodeResult], None] | None = None,
                 store: CampaignStore | None = None, backend: str = "process") -> Report:
    """Prepare and run a campaign (see :meth:`~.engine.Study.run`)."""
    with Campaign(config) as campaign:
        return campaign.run(workers, on_episode, store, backend)


def report_from_store(store: CampaignStore) -> Report:
    """The report of the campaign in ``store``, rebuilt from the store alone (complete or not:
    ``episodes`` is the number stored; see :meth:`~.engine.Study.from_store`)."""
    return Campaign.from_store(store)[0]


report_and_records = Campaign.from_store
"""The report of the campaign in a store, with the plan and the records it was built from."""
