"""Training SB3 agents on a task, with checkpoints at each budget, and loading them as policies.

A saved agent is ``NAME.zip`` (Stable-Baselines3's own format) plus ``NAME.json`` (what it was
trained on: algorithm, env id and kwargs, steps, seed, wall time), so that ``vlb verify --policy``
rebuilds exactly the environment it was trained for.
"""

from __future__ import annotations

import hashlib
import io
import json
import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import vlb_gym  # noqa: F401 - registers the envs
from vlb_gym.core.files import input_bytes, is_input_file, read_json_file

from .configs import ALGORITHMS, TASK_IDS, AgentSpec, TaskConfig, check_observation
from .observations import LabelImage, LabelImager
from .tasks import ExplorationBonus
from .wrappers import ActionMasks, FlatActions, admissible_actions


def _algorithm(name: str):
    try:
        import stable_baselines3  # noqa: F401
        import sb3_contrib  # noqa: F401
    except ImportError as exc:
        raise ImportError("the RL baselines need Stable-Baselines3: pip install torch==2.13.0 "
                          "&& pip install 'vlb-gym[rl]'") from exc
    if name == "ppo":
        from stable_baselines3 import PPO
        return PPO
    if name == "a2c":
        from stable_baselines3 import A2C
        return A2C
    if name == "maskable_ppo":
        from sb3_contrib import MaskablePPO
        return MaskablePPO
    raise ValueError(f"unknown algorithm {name!r}; choose one of {ALGORITHMS}")


def make_env(env_id: str, env_kwargs: dict[str, Any], observation: str = "flat",
             bonus: float = 0.0) -> gym.Env:
    """The training env: the exploration bonus (``bonus`` > 0, training only), the
    ``observation``, then flattened actions and their masks where the space is
    MultiDiscrete."""
    check_observation(None, observation)
    env = gym.make(env_id, **env_kwargs)
    if bonus:
        env = ExplorationBonus(env, bonus)
    if observation in IMAGES:
        env = LabelImage(env)
    if isinstance(env.action_space, gym.spaces.MultiDiscrete):
        return ActionMasks(FlatActions(env))
    return env


def agent_name(config: TaskConfig, algorithm: str, observation: str = "flat",
               bonus: float = 0.0, seed: int = 0) -> str:
    """``TASK_`` + the configuration's :attr:`~.configs.AgentSpec.label` (``p`` for a decimal
    point: a dot would start a file suffix) + ``-sSEED`` for a seed other than 0."""
    label = AgentSpec(algorithm, observation, bonus).label.replace(".", "p")
    return f"{config.label}_{label}" + (f"-s{seed}" if seed else "")


IMAGES = ("image", "spatial")  # the observations seen through LabelImage


def _policy(vec, observation: str) -> tuple[Any, dict[str, Any]]:
    if observation == "spatial":
        from .cnn import SpatialPolicy
        return SpatialPolicy, {}
    if observation == "image":
        from .cnn import GridCNN
        return "CnnPolicy", {"features_extractor_class": GridCNN}
    if isinstance(vec.observation_space, gym.spaces.Dict):
        return "MultiInputPolicy", {}
    return "MlpPolicy", {}


def train(config: TaskConfig, algorithm: str, out_dir: Path, seed: int = 0, n_envs: int = 4,
          budgets: tuple[int, ...] | None = None, tensorboard: Path | None = None,
          verbose: int = 0, observation: str = "flat", bonus: float = 0.0,
          subprocesses: bool = False) -> list[Path]:
    """Train ``algorithm`` on ``config``'s task, seeing ``observation`` and rewarded with the
    exploration ``bonus`` on top of the task's reward, on ``n_envs`` envs (in as many worker
    processes with ``subprocesses``, else stepped in turn here); save a checkpoint at every
    budget (:func:`agent_name` ``_BUDGET``) with its metadata, training throughput included;
    return them."""
    cls = _algorithm(algorithm)  # first: it says which extra is missing
    check_observation(algorithm, observation)
    from stable_baselines3.common.env_util import make_vec_env

    budgets = tuple(sorted(budgets or config.budgets))
    vec_cls = None
    if subprocesses and n_envs > 1:
        from stable_baselines3.common.vec_env import SubprocVecEnv
        vec_cls = SubprocVecEnv
    vec = make_vec_env(make_env, n_envs=n_envs, seed=seed, vec_env_cls=vec_cls,
                       env_kwargs={"env_id": config.task_id, "env_kwargs": config.env_kwargs,
                                   "observation": observation, "bonus": bonus})
    network, policy_kwargs = _policy(vec, observation)
    hyper = dict(config.hyperparameters.get(algorithm, {}))
    policy_kwargs.update(hyper.pop("policy_kwargs", {}))
    model = cls(network, vec, seed=seed, verbose=verbose, device="cpu",
                tensorboard_log=str(tensorboard) if tensorboard else None,
                policy_kwargs=policy_kwargs or None, **hyper)
    out_dir.mkdir(parents=True, exist_ok=True)
    name = agent_name(config, algorithm, observation, bonus, seed)
    saved, started, done = [], time.perf_counter(), 0
    for budget in budgets:
        model.learn(total_timesteps=budget - done, reset_num_timesteps=done == 0,
                    tb_log_name=name)
        done = budget
        path = out_dir / f"{name}_{budget}"
        model.save(path)
        meta = {"algorithm": algorithm, "env_id": config.task_id, "env_kwargs": config.env_kwargs,
                "task": config.label, "observation": observation, "bonus": bonus,
                "steps": int(model.num_timesteps), "seed": seed, "n_envs": n_envs,
                "subprocesses": vec_cls is not None,
                "wall_seconds": time.perf_counter() - started,
                "vlb_gym_version": vlb_gym.__version__}
        meta["steps_per_second"] = meta["steps"] / meta["wall_seconds"]
        path.with_suffix(".json").write_text(json.dumps(meta, indent=2) + "\n")
        saved.append(path.with_suffix(".zip"))
    vec.close()
    return saved


SAMPLING_STREAM = 0x5A4D  # spawn key of a sampled agent's draws, apart from the env's


class SB3Policy:
    """A trained agent behind the :class:`~vlb_gym.verify.policies.Policy` interface.

    It never "finishes" by itself: episodes end when the task terminates them (finished) or at
    the step bound (not finished), exactly as rho_B is defined for any policy. It takes the most
    likely admissible action, or with ``sample`` draws one from its distribution (the
    stochastic policy PPO trains), with a generator seeded from the episode's seed at each
    :meth:`reset`: episodes stay independent, and each replays exactly.
    """

    def __init__(self, path: str | Path, env: gym.Env, sample: bool = False):
        zip_path, _ = agent_files(path)
        self.meta = load_metadata(path)
        if not is_input_file(zip_path):
            raise ValueError(f"{zip_path}: no such saved agent")
        try:  # from the bytes: a campaign's workers have them shipped, not on their disk
            self.model = _algorithm(self.meta["algorithm"]).load(
                io.BytesIO(input_bytes(zip_path)), device="cpu")
        except Exception as exc:  # any malformed file: SB3 raises what its readers raise
            raise ValueError(f"{zip_path}: not a saved {self.meta['algorithm']} agent "
                             f"({type(exc).__name__}: {str(exc)[:200]})") from None
        if sample and not isinstance(self.model.action_space, gym.spaces.Discrete):
            raise ValueError(f"{zip_path}: sampling needs a discrete action space, not "
                             f"{self.model.action_space}")
        self.env = env
        self.imager = LabelImager(env.observation_space) \
            if self.meta["observation"] in IMAGES else None
        self.masked = self.meta["algorithm"] == "maskable_ppo"
        self.sample = sample
        self.rng = np.random.default_rng(0)
        space = env.action_space
        self.nvec = tuple(int(n) for n in space.nvec) if isinstance(
            space, gym.spaces.MultiDiscrete) else None
        self.name = zip_path.stem

    def reset(self, seed: int | None = None) -> None:
        """The agents are feed-forward (no recurrent state); an image agent's pictures start
        again from the next observation (the episode's first); a sampling agent's draws from
        ``seed``."""
        if self.imager is not None:
            self.imager.start = None
        self.rng = np.random.default_rng([SAMPLING_STREAM, 0 if seed is None else seed])

    def predict(self, observation: Any, state: Any = None, episode_start: Any = None,
                deterministic: bool = True) -> tuple[np.ndarray, None]:
        if self.imager is not None:
            if self.imager.start is None:
                self.imager.reset(observation)
            observation = self.imager(observation)
        masks = admissible_actions(self.env.unwrapped) if self.masked else None
        if self.sample:
            action = self._draw(observation, masks)
        else:
            kwargs = {"action_masks": masks} if self.masked else {}
            action, _ = self.model.predict(observation, deterministic=True, **kwargs)
        if self.nvec is not None:  # trained on flattened actions
            action = np.array(np.unravel_index(int(action), self.nvec), dtype=np.int64)
        return action, None

    def _draw(self, observation: Any, masks: np.ndarray | None) -> Any:
        """An action drawn from the agent's (masked) distribution with this episode's
        generator."""
        import torch

        policy = self.model.policy
        tensor, _ = policy.obs_to_tensor(observation)
        with torch.no_grad():
            kwargs = {"action_masks": masks} if self.masked else {}
            probs = policy.get_distribution(tensor, **kwargs).distribution.probs
        probs = probs[0].double().numpy()
        return self.rng.choice(probs.size, p=probs / probs.sum())


def agent_files(path: str | Path) -> tuple[Path, Path]:
    """The saved agent ``NAME.zip`` and its metadata ``NAME.json``, given either (or ``NAME``)."""
    path = Path(path)
    zip_path = path if path.suffix == ".zip" else path.with_suffix(".zip")
    return zip_path, zip_path.with_suffix(".json")


def load_metadata(path: str | Path) -> dict[str, Any]:
    """An agent's metadata, checked: ``algorithm`` one of ours, ``env_id`` a string and
    ``env_kwargs`` an object; ``ValueError`` naming the file otherwise."""
    meta_path = agent_files(path)[1]
    meta = read_json_file(meta_path, "the agent's metadata")
    for key, kind in (("algorithm", str), ("env_id", str), ("env_kwargs", dict)):
        if not isinstance(meta.get(key), kind):
            raise ValueError(f"{meta_path}: the agent's metadata needs {key!r} "
                             f"({'an object' if kind is dict else 'a string'})")
    if meta["algorithm"] not in ALGORITHMS:
        raise ValueError(f"{meta_path}: unknown algorithm {meta['algorithm']!r}; "
                         f"expected one of {ALGORITHMS}")
    meta.setdefault("observation", "flat")  # agents saved before images were offered
    if "task" in meta["env_kwargs"]:  # agents saved when a task was a kwarg of the grid env
        task = meta["env_kwargs"].pop("task")
        if task not in TASK_IDS:
            raise ValueError(f"{meta_path}: env_kwargs.task: unknown task {task!r}; expected one "
                             f"of {', '.join(TASK_IDS)}")
        meta["env_id"] = TASK_IDS[task]
    check_observation(meta["algorithm"], meta["observation"], f"{meta_path}: ")
    return meta


def policy_env_kwargs(path: str | Path) -> tuple[str, dict[str, Any]]:
    """The env id and kwargs an agent was trained on (from its metadata)."""
    meta = load_metadata(path)
    return meta["env_id"], dict(meta["env_kwargs"])


class SB3Loader:
    """Trained agents as the policies of campaigns: ``NAME.zip`` with its metadata ``NAME.json``
    beside it; policy kind ``sb3`` takes the most likely action, ``sb3_sampled``
    (:class:`SampledSB3Loader`) draws it (see :class:`SB3Policy`)."""

    sample = False
    runs_code = True  # loading unpickles the zip
    replay_options: tuple[str, ...] = ("--policy",)

    def load(self, ref, env: gym.Env) -> SB3Policy:
        return SB3Policy(ref.ref, env, self.sample)

    def files(self, ref, policy: SB3Policy) -> list[Path]:
        return list(agent_files(ref.ref))

    def content(self, ref, policy: SB3Policy) -> dict[str, Any]:
        """A digest of the saved agent and its metadata."""
        digest = hashlib.sha256()
        for path in agent_files(ref.ref):
            digest.update(input_bytes(path))
        return {"sha256": digest.hexdigest(), "algorithm": policy.meta["algorithm"],
                "sample": self.sample}

    def trained_env(self, ref) -> tuple[str, dict[str, Any]]:
        return policy_env_kwargs(ref.ref)


class SampledSB3Loader(SB3Loader):
    """Policy kind ``sb3_sampled``: trained agents that draw their actions."""

    sample = True
    replay_options = ("--sample", "--policy")
