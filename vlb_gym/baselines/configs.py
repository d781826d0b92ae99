"""Per-environment settings of the baselines: tasks, budgets, hyperparameters, graphs to compare."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import vlb_gym

ALGORITHMS = ("ppo", "a2c", "maskable_ppo")
OBSERVATIONS = ("flat", "image", "spatial")
"""How an agent sees the grid, and the network that reads it: ``flat``, the env's own
observation (SB3's MultiInputPolicy flattens it, labels one-hot); ``image``,
:class:`~.observations.LabelImage` through :class:`~.cnn.GridCNN` and a dense action head;
``spatial``, the same image through the fully convolutional :class:`~.cnn.SpatialPolicy`, whose
action logits are read off the feature map cell by cell (MaskablePPO only)."""
SPATIAL_ALGORITHMS = ("maskable_ppo",)
ACTING = {"greedy": "sb3", "sampled": "sb3_sampled"}
"""How a trained agent acts when verified, and the policy kind that does it: ``greedy``, the
most likely action; ``sampled``, an action drawn from its distribution (seeded per episode)."""


@dataclass(frozen=True)
class AgentSpec:
    """One RL configuration: ``ALGO[:OBSERVATION[:BONUS]]`` on the command line."""

    algorithm: str
    observation: str = "flat"
    bonus: float = 0.0

    @classmethod
    def parse(cls, text: str) -> AgentSpec:
        parts = text.split(":")
        if not 1 <= len(parts) <= 3 or parts[0] not in ALGORITHMS:
            raise ValueError(f"agent {text!r}: expected ALGO[:OBSERVATION[:BONUS]] with ALGO "
                             f"one of {', '.join(ALGORITHMS)}")
        observation = parts[1] if len(parts) > 1 else "flat"
        check_observation(parts[0], observation, f"agent {text!r}: ")
        try:
            bonus = float(parts[2]) if len(parts) > 2 else 0.0
        except ValueError:
            raise ValueError(f"agent {text!r}: the bonus is not a number") from None
        if not 0 <= bonus <= 1:
            raise ValueError(f"agent {text!r}: the bonus must lie between 0 and 1")
        return cls(parts[0], observation, bonus)

    def __str__(self) -> str:
        """The configuration as typed: ``ALGO[:OBSERVATION[:BONUS]]``, the defaults left out."""
        parts = [self.algorithm, self.observation, f"{self.bonus:g}"]
        return ":".join(parts[:3 if self.bonus else (2 if self.observation != "flat" else 1)])

    @property
    def label(self) -> str:
        """``ALGO[-OBSERVATION][-bonusB]``, the defaults left out."""
        return self.algorithm + (f"-{self.observation}" if self.observation != "flat" else "") \
            + (f"-bonus{self.bonus:g}" if self.bonus else "")


def check_observation(algorithm: str | None, observation: str, where: str = "") -> None:
    """``ValueError`` (prefixed by ``where``) unless ``observation`` is one of ours and
    ``algorithm`` (if given) can see it."""
    if observation not in OBSERVATIONS:
        raise ValueError(f"{where}observation must be one of {', '.join(OBSERVATIONS)}, not "
                         f"{observation!r}")
    if observation == "spatial" and algorithm is not None \
            and algorithm not in SPATIAL_ALGORITHMS:
        raise ValueError(f"{where}the spatial policy needs action masks: use "
                         f"{' or '.join(SPATIAL_ALGORITHMS)}, not {algorithm}")


DELTA = 0.05
"""The comparison's level: of each campaign's lower bound and of each paired test."""

DEFAULT_AGENTS = (AgentSpec("maskable_ppo", "spatial"),
                  AgentSpec("maskable_ppo", "spatial", 0.02),
                  AgentSpec("maskable_ppo", "image", 0.02), AgentSpec("maskable_ppo"))


@dataclass(frozen=True)
class Synthesis:
    """How the comparison obtains a synthesized graph: a request to vlb synthesize."""

    name: str
    env_id: str
    prompt: str  # key in vlb_gym.abstractor.paper.PROMPTS; scripted replies in <key>.replies.json
    uses: tuple[str, ...] = ()


@dataclass(frozen=True)
class TaskConfig:
    """One task of one environment, as RL trains on it and the comparison verifies it."""

    env_id: str
    task: str
    max_episode_steps: int
    graph: str  # the hand-written behavior solving it
    synthesized: str  # the name vlb synthesize gives the scripted paper replies
    budgets: tuple[int, ...] = (20_000, 40_000, 80_000)  # checkpoints: training env steps
    hyperparameters: dict[str, dict[str, Any]] = field(default_factory=dict)
    env_options: dict[str, Any] = field(default_factory=dict)  # a variant: size, obstacles
    name: str = ""  # the key in TASKS, agent names and tables; the task's own by default

    @property
    def label(self) -> str:
        return self.name or self.task

    @property
    def task_id(self) -> str:
        """The registered env id of the task, which RL trains on and the comparison verifies."""
        return TASK_IDS[self.task]

    @property
    def env_kwargs(self) -> dict[str, Any]:
        return {**self.env_options, "max_episode_steps": self.max_episode_steps}


#: The registered env id of each RL task (``vlb_gym.RL_TASKS``), by task name.
TASK_IDS = {entry.rsplit(":", 1)[1]: env_id for env_id, entry, _ in vlb_gym.RL_TASKS}

_GRID_HYPER = {
    "ppo": {"n_steps": 256, "batch_size": 256, "learning_rate": 3e-4, "ent_coef": 0.01,
            "gamma": 0.98},
    # from benchmarks/rl_sweep.py (benchmarks/results/rl/sweep.md): 1e-3 and 0.995 were the
    # two factors that helped, and together the best
    "maskable_ppo": {"n_steps": 256, "batch_size": 256, "learning_rate": 1e-3, "ent_coef": 0.01,
                     "gamma": 0.995},
    "a2c": {"n_steps": 16, "learning_rate": 7e-4, "ent_coef": 0.01, "gamma": 0.98},
}

TASKS = {
    "find_goal": TaskConfig("VLB-GridExplore-v0", "find_goal", 200, "explore_until_goal",
                            "explore_for_goal", (15_000, 30_000, 60_000), _GRID_HYPER),
    "find_goal_and_oscillate": TaskConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", 200,
                                          "find_goal_and_oscillate", "goal_and_back",
                                          (25_000, 50_000, 100_000), _GRID_HYPER),
    # the scale test: 2.25x the cells, the obstacles in proportion (30%), the step bound x1.5
    "find_goal_15x15": TaskConfig("VLB-GridExplore-v0", "find_goal", 300, "explore_until_goal",
                                  "explore_for_goal", (20_000, 40_000, 80_000), _GRID_HYPER,
                                  {"size": 15, "n_obstacles": 68}, "find_goal_15x15"),
}
DEFAULT_TASKS = ("find_goal", "find_goal_and_oscillate")  # the paper's grid

#: synthesized graphs the comparison needs, in the order they must be made (later ones use earlier)
SYNTHESES = (
    Synthesis("explore_for_goal", "VLB-GridExplore-v0", "behavior1"),
    Synthesis("goal_and_back", "VLB-GridExplore-v0", "behavior2", uses=("explore_for_goal",)),
)
