"""A compiled behavior as a standard policy: for any Gymnasium loop, vector env and SB3 evaluator.

Two halves, because a standard loop splits the policy from the environment:

* :class:`BehaviorFinished` wraps the environment and ends the episode (``terminated=True``) when
  the behavior finishes, with rho_B in ``info`` -- what :func:`vlb_gym.verify.episode.run_episode`
  signals with a None action, which no standard loop understands;
* :class:`BehaviorAgent` is the policy: an SB3-like ``predict`` over batches of observations.

Synchronisation. Both run their own copy of the behavior (:class:`BehaviorPolicy`), so each half
works across processes (``SubprocVecEnv``, ``AsyncVectorEnv``) with no channel between them. A
behavior is deterministic: its actions are a function of the observations since the episode
began. So the wrapper's copy, fed the observations the environment returns, and the agent's copy,
fed the same observations and reset where episodes start, choose the same actions. The wrapper
checks this at every step instead of assuming it: after an action other than its copy's it no
longer ends the episode (the episode is then no run of the behavior, and "finished" would mean
nothing) and is a plain environment, as other callers need: Gymnasium's ``check_env`` steps
random actions, and SB3's ``evaluate_policy`` resets the agent's copy at every step once that
env has run its share of episodes.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, SupportsFloat

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from vlb_gym.core.compiler import CompiledBehavior
from vlb_gym.core.library import compile_for
from vlb_gym.core.runtime import BehaviorPolicy, BehaviorRuntimeError

from .loop import PolicyEpisode
from .robustness import RobustnessWrapper


def _compiled(behavior: str | CompiledBehavior, env: gym.Env) -> CompiledBehavior:
    """``behavior`` compiled against ``env`` if it is a reference (a name or a path)."""
    return compile_for(behavior, env) if isinstance(behavior, str) else behavior


def _robustness(env: gym.Env) -> RobustnessWrapper | None:
    """The outermost :class:`RobustnessWrapper` among ``env``'s wrappers, if any."""
    while isinstance(env, gym.Wrapper):
        if isinstance(env, RobustnessWrapper):
            return env
        env = env.env
    return None


class BehaviorFinished(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """Ends each episode when ``behavior`` (a library name, a path or a compiled behavior) does.

    The wrapper runs its own copy of the behavior on the observations it returns, one step ahead:
    after the reset and after every step it knows the behavior's next action. ``step(action)``
    applies ``action`` as the inner environment would, and while every action of the episode has
    been the behavior's (``info["on_behavior"]``, in every step's info) it returns

    * ``terminated=True`` when the behavior has then finished (it rests in a terminal node with no
      edge to take): the episode is scored as finished;
    * ``truncated=True`` when the behavior then fails (:class:`BehaviorRuntimeError`: no edge from
      a non-terminal node, an expression raised, a parameter outside the primitive's space): the
      episode is scored as not finished. If it fails on the reset observation, it has no action:
      the first step then ends the episode so, without applying ``action`` (and returns the
      reset observation again).

    After an action other than the behavior's the wrapper stands aside: the episode is no run of
    the behavior, and ends only as the inner environment ends it. Every episode's final ``info``
    holds the keys of :meth:`RobustnessWrapper.end` (``rho_B``, ``finished``, ``primitives``,
    ...): ``env`` is wrapped in a :class:`RobustnessWrapper` unless it contains one. So
    ``terminated`` always means finished, and for the behavior's own actions the episodes, their
    primitives and rho_B are those of :func:`~vlb_gym.verify.episode.run_episode` with
    ``stop_on_failure=False`` for the same reset seeds: a failed certificate does not end the
    episode (rho_B is -1 already). Stepping after the end raises ``RuntimeError``.
    """

    def __init__(self, env: gym.Env, behavior: str | CompiledBehavior):
        gym.utils.RecordConstructorArgs.__init__(self, behavior=behavior)
        robustness = _robustness(env)
        if robustness is None:
            env = robustness = RobustnessWrapper(env)
        super().__init__(env)
        self.robustness = robustness
        self.episode = PolicyEpisode(robustness, BehaviorPolicy(_compiled(behavior, env),
                                                                env.unwrapped),
                                     stop_on_failure=False, caught=(BehaviorRuntimeError,),
                                     env=self.env)  # every wrapper in between sees the steps
        self._obs: Any = None
        self._following = False  # every action of the episode has been the behavior's
        self._untold = False  # the episode ended at the reset and no step has said so yet

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[Any, dict[str, Any]]:
        self._obs, info = self.episode.reset(seed=seed, options=options)
        self._following, self._untold = True, self.episode.ended
        return self._obs, info

    def step(self, action: Any) -> tuple[Any, SupportsFloat, bool, bool, dict[str, Any]]:
        if self._untold:  # the behavior failed at the reset: it has no action to apply
            self._untold = False
            return self._obs, 0.0, False, True, {**self.robustness.summary, "on_behavior": False}
        if self.robustness.summary is not None:
            raise RuntimeError("the episode has ended (rho_B is recorded); call reset()")
        planned = self.episode.action
        self._following = self._following and planned is not None \
            and np.array_equal(action, planned)
        if not self._following:  # no run of the behavior: the env's episode
            obs, reward, terminated, truncated, info = self.env.step(action)
            return obs, reward, terminated, truncated, {
                **info, **self.robustness.ended_by(terminated, truncated), "on_behavior": False}
        obs, reward, terminated, truncated, info = self.episode.step()
        if self.episode.ended and not (terminated or truncated):  # the behavior ended it
            summary = self.robustness.summary
            terminated, truncated = summary["finished"], not summary["finished"]
            info = {**info, **summary}
        self._obs = obs
        return obs, reward, terminated, truncated, {**info, "on_behavior": True}


def _batch_size(space: spaces.Space, observation: Any) -> int | None:
    """None if ``observation`` is one element of ``space``, else the size of its leading batch
    axis; by shapes, leaf by leaf, as Stable-Baselines3's ``is_vectorized_observation`` does."""
    if isinstance(space, spaces.Dict):
        sizes = {_batch_size(sub, observation[key]) for key, sub in space.spaces.items()}
        if len(sizes) != 1:
            raise ValueError(f"the parts of the observation disagree on the batch size: {sizes}")
        return sizes.pop()
    shape = np.shape(observation)
    if shape == space.shape:
        return None
    if shape[1:] == space.shape:
        return shape[0]
    raise ValueError(f"observation of shape {shape} is neither one element of {space} nor a "
                     "batch of them")


def _item(batch: Any, i: int) -> Any:
    """Element ``i`` of a batch of observations (arrays, or dicts of them)."""
    return {k: _item(v, i) for k, v in batch.items()} if isinstance(batch, Mapping) else batch[i]


class BehaviorAgent:
    """``behavior`` (a library name, a path or a compiled behavior) as an SB3-like policy.

    ``env`` is one environment of the kind the behavior runs on (wrappers are looked through for
    the behavior's interface; its outer spaces are the agent's). The agent keeps one copy of the
    behavior per batch index, made when first needed; an unbatched observation uses copy 0.

    ``predict(observation, state, episode_start)`` follows ``stable_baselines3``'s
    ``PolicyPredictor``, so ``evaluate_policy`` runs it: ``observation`` is one observation or a
    batch (arrays, or a dict of arrays, with a leading batch axis) and the action is unbatched or
    batched alike. ``episode_start[i]`` True resets copy ``i`` before it acts: it must be True
    exactly where ``observation[i]`` is the first of an episode: SB3's ``episode_starts`` (its
    VecEnvs reset within the ending step); with Gymnasium's default next-step autoreset, one step
    later than ``terminated | truncated`` (the next step returns the reset observation). Once a
    copy's behavior has finished or failed it never raises: it returns zeros of the action
    space's shape and dtype, which a :class:`BehaviorFinished` env never applies (its episode
    ends first) and a next-step autoreset ignores.
    """

    def __init__(self, behavior: str | CompiledBehavior, env: gym.Env):
        self.behavior = _compiled(behavior, env)
        self.observation_space = env.observation_space
        self.action_space = env.action_space
        self._interface = env.unwrapped
        self._copies: list[BehaviorPolicy] = []
        self._done: list[bool] = []  # copy i's behavior finished or failed
        self._placeholder = np.zeros(self.action_space.shape, self.action_space.dtype)

    def predict(self, observation: Any, state: Any = None, episode_start: Any = None,
                deterministic: bool = True) -> tuple[np.ndarray, None]:
        """The behavior's actions on ``observation`` (deterministic whatever ``deterministic``);
        no recurrent state is returned: the copies keep their place in the graph themselves."""
        n = _batch_size(self.observation_space, observation)
        batch = [observation] if n is None else [_item(observation, i) for i in range(n)]
        starts = np.broadcast_to(np.asarray(False if episode_start is None else episode_start,
                                            dtype=bool).reshape(-1), (len(batch),))
        actions = [self._act(i, obs, start) for i, (obs, start) in enumerate(zip(batch, starts))]
        return (actions[0] if n is None else np.stack(actions)), None

    def _act(self, i: int, obs: Any, start: bool) -> np.ndarray:
        """Copy ``i``'s action on ``obs``, or the placeholder once its behavior has none."""
        if i == len(self._copies):  # copies are made in batch order
            self._copies.append(BehaviorPolicy(self.behavior, self._interface))
            self._done.append(False)
        if start:
            self._copies[i].reset()
            self._done[i] = False
        action = None
        if not self._done[i]:
            try:
                action, _ = self._copies[i].predict(obs)
            except BehaviorRuntimeError:  # the wrapper's copy fails alike and ends the episode
                action = None
            self._done[i] = action is None
        return self._placeholder.copy() if action is None else action
