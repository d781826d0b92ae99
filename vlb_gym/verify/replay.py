"""One episode again: replayed from a seed or from a store, filmed where the env renders.

A store is untrusted data: what of a stored campaign is code (the modules that register its env,
a policy whose loading runs code, e.g. a pickled agent) is run only when the user names it again
(:func:`untrusted_code`), and a policy that changed since its campaign is not replayed as if it
were the same (:func:`changed_since`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from vlb_gym.core.env import FrameKey

from .episode import build
from .records import CampaignConfig
from .episode import EpisodeResult, run_episode
from .policies import policy_loader
from .records import Plan


def store_files(path: str | Path) -> list[Path]:
    """A store and the files SQLite keeps beside it: all inputs no output may overwrite."""
    return [Path(path), Path(f"{path}-wal"), Path(f"{path}-shm")]


def untrusted_code(plan: Plan, env_modules: Sequence[str],
                   policy: str | None) -> list[str]:
    """The options that would name again what of the stored ``plan`` is code and that the user
    has not named (``env_modules`` they gave, the ``policy`` file they gave, if any): replaying
    a store must not import or unpickle what only the store names. A policy kind whose loader
    does not run code from its references (behaviors: data) needs nothing."""
    missing = [f"--env-module {m}" for m in plan.env_modules if m not in set(env_modules)]
    stored = plan.policy
    if policy_loader(stored.kind).runs_code and \
            (policy is None or str(Path(policy).resolve()) != stored.ref):
        missing.append(f"--policy {stored.ref}")
    return missing


def changed_since(config: CampaignConfig, policy: Any, digest: str) -> str | None:
    """The policy's content digest now, if it differs from ``digest`` (the campaign's)."""
    now = policy_loader(config.policy.kind).content(config.policy, policy)["sha256"]
    return now if now != digest else None


MAX_REPLAY_PRIMITIVES = 10_000
"""A replay of a stored episode past its record (``--keep-going``) stops here: the store's step
bound is data from elsewhere."""


class FrameSample:
    """The frames of a film thinned as they come, so that at most about ``cap`` are held
    however long the film: every frame while they are few, then every 2nd, 4th, ... (evenly
    spaced), and always the last one (where an episode failed)."""

    def __init__(self, cap: int):
        self.cap, self.every, self.seen = cap, 1, 0
        self.kept: list[tuple[int, np.ndarray]] = []
        self.last: tuple[int, np.ndarray] | None = None

    def __call__(self, frame: np.ndarray) -> None:
        if self.seen % self.every == 0:
            self.kept.append((self.seen, frame))
            if len(self.kept) > self.cap:
                self.every *= 2
                self.kept = [(i, f) for i, f in self.kept if i % self.every == 0]
        self.last = (self.seen, frame)
        self.seen += 1

    def frames(self) -> list[np.ndarray]:
        kept = list(self.kept)
        if self.last is not None and (not kept or kept[-1][0] != self.last[0]):
            kept.append(self.last)
        return [frame for _, frame in kept]


def filmed(env: Any, policy: Any, config: CampaignConfig, seed: int, index: int = 0,
           film: bool = True, max_primitives: int | None = None, max_frames: int | None = None
           ) -> tuple[EpisodeResult, list[np.ndarray]]:
    """Episode ``index`` (reset seed ``seed``) of ``policy`` on ``env`` (built with
    ``render_mode="rgb_array"`` to film it) and its frames (none unless ``film``; about
    ``max_frames`` of them, evenly spaced, where given: :class:`FrameSample`), at most
    ``max_primitives`` primitives long (a stored episode's replay: as many as its record
    holds, whatever step bound the store names)."""
    every: list[np.ndarray] = []
    sample = FrameSample(max_frames) if max_frames is not None else None
    if film:
        env.unwrapped.film(sample if sample is not None else every.append)
    try:
        result = run_episode(env, policy, seed, index, config.stop_on_failure,
                             max_primitives=max_primitives)
        return result, sample.frames() if sample is not None else every
    finally:
        env.unwrapped.film(None)


REPORT_FRAMES = 48  # frames a report's replay holds per episode, however long it ran


def episode_frames(plan: Plan, episodes: Sequence[EpisodeResult]
                   ) -> tuple[dict[str, list[np.ndarray]], FrameKey | None, str | None]:
    """Frames of the first failed and the first successful episode of a stored campaign,
    replayed where the env renders and the policy is still the one the campaign ran, and how
    to read them (the env's :meth:`~vlb_gym.core.env.PrimitiveEnv.frame_key`); else no frames
    and why not."""
    config = plan.config()
    try:
        env, policy = build(config, "rgb_array")
    except (ValueError, ImportError) as exc:
        return {}, None, str(exc)
    try:
        if changed_since(config, policy, plan.content_sha256):
            return {}, None, "the policy changed since the campaign"
        frames = {}
        for label, success in (("failed", False), ("successful", True)):
            record = next((e for e in episodes if e.success == success), None)
            if record is not None:
                frames[f"{label} episode {record.index}"] = filmed(
                    env, policy, config, record.seed, record.index,
                    max_primitives=len(record.steps), max_frames=REPORT_FRAMES)[1]
        return frames, env.unwrapped.frame_key(), None
    finally:
        env.close()
