"""A campaign's data, one definition each: the :class:`CampaignConfig` a user writes, the
:class:`Plan` a campaign makes of it (what a store records first, and is validated by), the
:class:`EpisodeResult` of every episode, and a comparison's :class:`ComparisonPlan` and
:class:`PairResult`. Stores are untrusted data: :func:`plan_from_json`,
:func:`episode_from_json` and their comparison twins read them strictly (exact types, no extra
keys, a record consistent with itself) before anything is counted.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import field
from typing import Annotated, Any

import numpy as np
from typing_extensions import TypedDict

from pydantic import (AfterValidator, BeforeValidator, ConfigDict, Field, TypeAdapter,
                      ValidationError, model_validator, with_config)
from pydantic.dataclasses import dataclass

from .methods import FixedN, Sequential, method_named
from .policies import PolicyRef

STRICT = ConfigDict(strict=True, extra="forbid")
MAX_EPISODE_SECONDS = 365 * 24 * 3600.0  # an episode's recorded time: more is a corrupt record
Seconds = Annotated[float, Field(ge=0, le=MAX_EPISODE_SECONDS, allow_inf_nan=False)]
"""A recorded wall time: finite, and at most a year (so that any number of them sums to a
finite total)."""


def episode_seed(campaign_seed: int, index: int) -> int:
    """The reset seed of episode ``index``: the index-th spawned child of the campaign's seed."""
    child = np.random.SeedSequence(campaign_seed, spawn_key=(index,))
    return int(child.generate_state(1, dtype=np.uint64)[0])


def _representable(level: float) -> float:
    if 1.0 - level == 1.0:
        raise ValueError(f"{level!r} is too small: 1 minus it is 1 in floating point")
    return level


Probability = Annotated[float, Field(gt=0, lt=1)]
Level = Annotated[float, Field(gt=0, lt=1), AfterValidator(_representable)]
"""A probability of error (delta, alpha), as the command line takes it."""
Count = Annotated[int, Field(ge=0)]
Modules = Annotated[tuple[str, ...], Field(strict=False)]  # a JSON array as a tuple


def _known_method(name: str) -> str:
    method_named(name)  # ValueError naming the known ones
    return name


@dataclass(frozen=True, config=STRICT)
class CampaignConfig:
    """Everything that defines a campaign, fixed before it starts. ``policy`` is a
    :class:`~.policies.PolicyRef`; a string names a behavior (a name or a JSON file).
    ``method`` names the statistical method (:data:`~.methods.METHODS`: ``"fixed-N"`` runs all
    N episodes, ``"sequential"`` stops when its anytime-valid test decides); ``episodes`` is N
    (at most N for a method that stops early), by default the method's own. Values of the
    wrong type or range raise pydantic's ValidationError (a ValueError)."""

    env_id: str
    policy: PolicyRef | str
    episodes: Annotated[int, Field(ge=1)] | None = None
    epsilon: Probability = 0.05
    delta: Level = 0.05
    seed: Count = 0
    env_kwargs: dict[str, Any] = field(default_factory=dict)
    stop_on_failure: bool = True
    env_modules: Modules = ()  # modules that register the env (imported in workers too)
    method: Annotated[str, AfterValidator(_known_method)] = FixedN.name

    def __post_init__(self) -> None:
        if isinstance(self.policy, str):
            object.__setattr__(self, "policy", PolicyRef("behavior", self.policy))
        if self.episodes is None:
            default = method_named(self.method).default_episodes(self.epsilon, self.delta)
            object.__setattr__(self, "episodes", default)


@dataclass(frozen=True, config=STRICT, kw_only=True)
class Plan(CampaignConfig):
    """A campaign's plan: its config and what the campaign derived from it before any episode
    (the policy's content digest and documents, the sampling distribution in words, the
    versions), as JSON data. A store records it first; the same campaign has the same plan."""

    content_sha256: str
    policy_content: dict[str, Any]
    sampling_distribution: str
    versions: dict[str, str]

    @model_validator(mode="before")
    @classmethod
    def _as_stored(cls, data: Any) -> Any:
        """A plan read from JSON has every field (a default would change the claim) and names
        its policy's kind, reference and library. Stores written before plans named their
        method say ``"sequential": true/false``."""
        if not isinstance(data, dict):  # made in Python: the fields' own checks
            return data
        if "method" not in data and isinstance(data.get("sequential"), bool):
            data = dict(data)
            data["method"] = Sequential.name if data.pop("sequential") else FixedN.name
        _every_field(cls, data)
        if data["episodes"] is None:
            raise ValueError("episodes: no number of episodes is recorded")
        if not isinstance(data["policy"], dict) or set(data["policy"]) != _POLICY_KEYS:
            raise ValueError("policy: not a mapping of kind, ref and library")
        if isinstance(data["env_kwargs"], dict) and "render_mode" in data["env_kwargs"]:
            raise ValueError("env_kwargs: a campaign's kwargs never set render_mode")
        return data

    def __post_init__(self) -> None:
        super().__post_init__()
        _behaviors_valid(self)

    def config(self) -> CampaignConfig:
        """The config the plan was made from."""
        names = [f.name for f in dataclasses.fields(CampaignConfig)]
        return CampaignConfig(**{name: getattr(self, name) for name in names})

    def to_json(self) -> str:
        """The plan as a store records it."""
        return _PLAN.dump_json(self).decode()

    def to_dict(self) -> dict[str, Any]:
        """The plan as JSON data."""
        return _PLAN.dump_python(self, mode="json")


_POLICY_KEYS = {f.name for f in dataclasses.fields(PolicyRef)}


def _every_field(kind: type, data: dict[str, Any]) -> None:
    """ValueError unless a stored record of ``kind`` has every field: a default would stand
    for something the record does not say."""
    missing = [f.name for f in dataclasses.fields(kind) if f.name not in data]
    if missing:
        raise ValueError(f"no {missing[0]!r} is recorded")


def _behaviors_valid(plan: Plan) -> None:
    """A behavior's plan records its documents, by source: each must be a behavior file."""
    if plan.policy.kind != "behavior":
        return
    from vlb_gym.core.spec import spec_from_data

    behaviors = plan.policy_content.get("behaviors")
    if not isinstance(behaviors, dict) or not behaviors \
            or set(plan.policy_content) != {"behaviors"}:
        raise ValueError("policy_content: a behavior's plan records {'behaviors': {source: "
                         "document}}")
    for source, document in behaviors.items():
        try:
            spec_from_data(document, f"policy_content.behaviors[{source!r}]")
        except ValueError as exc:  # its first problem, in one line
            raise ValueError(str(exc).splitlines()[0]) from None


@with_config(STRICT)
class Step(TypedDict):
    """One primitive run of an episode (``reason`` and ``cause`` are None where the
    certificate held; ``seconds``, the wall time of the policy's decision and the env's step,
    is None in records written before store and export format 2)."""

    primitive: str
    node: str | None
    param: Any
    certificate: bool
    reason: str | None
    cause: str | None
    seconds: Seconds | None


STEP_KEYS = tuple(Step.__annotations__)
_UNTIMED_KEYS = STEP_KEYS[:-1]  # a step's keys in format 1, which recorded no time


def _plus_or_minus_one(rho: int) -> int:
    if rho not in (-1, 1):
        raise ValueError(f"rho_B is +1 or -1, not {rho!r}")
    return rho


def _step_dict(step: Any) -> Any:
    """One step as a dict: a store's list of its :data:`STEP_KEYS` values (half the size of the
    dict), and a format-1 step (no ``seconds``: a list one shorter, or a dict without the key)
    with ``seconds`` None; anything else is left to fail validation."""
    if isinstance(step, list):
        if len(step) == len(STEP_KEYS):
            return dict(zip(STEP_KEYS, step))
        if len(step) == len(_UNTIMED_KEYS):
            return {**dict(zip(_UNTIMED_KEYS, step)), "seconds": None}
    elif isinstance(step, dict) and "seconds" not in step and set(step) == set(_UNTIMED_KEYS):
        return {**step, "seconds": None}
    return step


def _step_dicts(steps: Any) -> Any:
    """Steps as dicts (:func:`_step_dict`)."""
    return tuple(_step_dict(step) for step in steps) if isinstance(steps, (list, tuple)) \
        else steps


@with_config(STRICT)
@dataclasses.dataclass(frozen=True)
class EpisodeResult:
    """One episode's record, the same from the runner to the store, the JSONL export and the
    report: rho_B, how it came about, and enough to replay it (``seed``).

    ``steps`` holds one :class:`Step` per primitive run; ``start`` is the env's ``reset`` info
    (a summary of the sampled start); ``error`` the traceback when the policy or the env raised.
    """

    index: Count
    seed: Count
    rho: Annotated[int, AfterValidator(_plus_or_minus_one)]
    finished: bool
    primitives: Count
    failed_certificates: Count
    reason: str | None
    seconds: Seconds  # the episode's own wall time
    cause: str | None = None  # the failure's class, for grouping (see failure_cause)
    steps: Annotated[tuple[Step, ...], BeforeValidator(_step_dicts)] = ()
    start: dict[str, Any] = field(default_factory=dict)
    error: str | None = None

    @property
    def success(self) -> bool:
        return self.rho > 0

    def to_dict(self) -> dict[str, Any]:
        """The record as JSON data (shared, not copied: steps and start are plain data)."""
        record = {name: getattr(self, name) for name in _FIELD_NAMES}
        record["steps"] = list(self.steps)
        return record

    @classmethod
    def from_dict(cls, record: dict[str, Any]) -> EpisodeResult:
        """The result a :meth:`to_dict` record (or its JSON) holds; unknown keys are ignored."""
        known = {k: v for k, v in record.items() if k in _FIELDS}
        known["steps"] = _step_dicts(tuple(known.get("steps", ())))
        return cls(**known)

    def stored(self) -> dict[str, Any]:
        """The record as a store holds it: each step a list of its :data:`STEP_KEYS` values."""
        record = self.to_dict()
        record["steps"] = [[step[key] for key in STEP_KEYS] for step in self.steps]
        return record

    def outcome(self) -> dict[str, Any]:
        """The record without what differs when the same episode runs again: its and its
        steps' wall times and the traceback (whose file paths are the machine's)."""
        record = {k: v for k, v in self.to_dict().items() if k not in ("seconds", "error")}
        record["steps"] = [{k: v for k, v in step.items() if k != "seconds"}
                           for step in self.steps]
        record["raised"] = self.error is not None
        return record

    def same_outcome(self, other: EpisodeResult) -> bool:
        """Whether ``other`` is this episode again (:meth:`outcome`)."""
        return self.outcome() == other.outcome()


_FIELD_NAMES = tuple(f.name for f in dataclasses.fields(EpisodeResult))
_FIELDS = frozenset(_FIELD_NAMES)


def _consistent(result: EpisodeResult) -> EpisodeResult:
    """A record that agrees with itself, as rho_B is defined: a success finished with no
    failed certificate and no reason; a failure says why."""
    failed_steps = sum(not step["certificate"] for step in result.steps)
    if result.rho == 1 and (not result.finished or result.failed_certificates or failed_steps
                            or result.reason is not None or result.error is not None):
        raise ValueError("rho is +1 but the episode did not finish, or has a failed "
                         "certificate, a failure reason or an error")
    if result.rho == -1 and result.reason is None:
        raise ValueError("rho is -1 but no failure reason is recorded")
    if result.failed_certificates > result.primitives or len(result.steps) > result.primitives:
        raise ValueError("more failed certificates or steps than primitives")
    if failed_steps > result.failed_certificates:
        raise ValueError("more failed steps than failed certificates")
    return result


def _stored_episode(data: Any) -> Any:
    """A stored record has every field, and its steps as lists (see :meth:`EpisodeResult.stored`)."""
    if isinstance(data, dict):
        _every_field(EpisodeResult, data)
        steps = data["steps"]
        if not isinstance(steps, list) or not all(isinstance(step, list) for step in steps):
            raise ValueError(f"steps: a list of steps, each a list of {', '.join(STEP_KEYS)}")
    return data


CheckedEpisode = Annotated[EpisodeResult, BeforeValidator(_stored_episode),
                           AfterValidator(_consistent)]


@with_config(STRICT)
@dataclasses.dataclass(frozen=True)
class PairResult:
    """Pair ``index``: episode ``index`` of A and of B (the same reset seed)."""

    index: Count
    a: CheckedEpisode
    b: CheckedEpisode

    def stored(self) -> dict[str, Any]:
        return {"index": self.index, "a": self.a.stored(), "b": self.b.stored()}


def _checked(name: str) -> Callable[[float], float]:
    """A validator running :mod:`.paired`'s check ``name`` (its words say what is allowed)."""
    def check(value: float) -> float:
        from . import paired

        getattr(paired, name)(value)
        return value
    return check


def _known_paired_method(name: str) -> str:
    from .paired_methods import paired_method_named

    paired_method_named(name)
    return name


@dataclass(frozen=True, config=STRICT)
class ComparisonConfig:
    """Everything that defines a comparison, checked as a campaign's config is. ``a`` and ``b``
    are policy references (a string names a behavior); ``env_kwargs`` apply to both,
    ``a_env_kwargs``/``b_env_kwargs`` to one (and win). ``method`` names the paired method
    (``"fixed-N"``: all ``pairs`` run; ``"sequential"``: until the anytime-valid test decides,
    ``pairs`` at most, by default :data:`~.paired.DEFAULT_MAX_PAIRS`). ``margin`` 0 tests "B is
    more reliable than A"; above 0, "B is at least as reliable as A up to the margin". Values of
    the wrong type or range raise pydantic's ValidationError (a ValueError)."""

    env_id: str
    a: PolicyRef | str
    b: PolicyRef | str
    pairs: Annotated[int, Field(ge=1)] | None = None
    margin: Annotated[float, AfterValidator(_checked("check_margin"))] = 0.0
    alpha: Annotated[float, AfterValidator(_checked("check_alpha"))] = 0.05
    seed: Count = 0
    env_kwargs: dict[str, Any] = field(default_factory=dict)
    a_env_kwargs: dict[str, Any] = field(default_factory=dict)
    b_env_kwargs: dict[str, Any] = field(default_factory=dict)
    stop_on_failure: bool = True
    env_modules: Modules = ()
    method: Annotated[str, AfterValidator(_known_paired_method)] = "fixed-N"  # FixedPairs.name

    def __post_init__(self) -> None:
        from .paired import DEFAULT_MAX_PAIRS
        from .paired_methods import paired_method_named

        for side in ("a", "b"):
            if isinstance(getattr(self, side), str):
                object.__setattr__(self, side, PolicyRef("behavior", getattr(self, side)))
        if self.pairs is None:
            if not paired_method_named(self.method).stops_early:
                raise ValueError("a fixed-N comparison needs its number of pairs")
            object.__setattr__(self, "pairs", DEFAULT_MAX_PAIRS)

    def side(self, name: str) -> CampaignConfig:
        """Side ``"a"`` or ``"b"`` as a fixed-N campaign of ``pairs`` episodes, same seed."""
        own = self.a_env_kwargs if name == "a" else self.b_env_kwargs
        return CampaignConfig(self.env_id, getattr(self, name), self.pairs, seed=self.seed,
                              env_kwargs={**self.env_kwargs, **own},
                              stop_on_failure=self.stop_on_failure,
                              env_modules=self.env_modules)


@dataclass(frozen=True, config=STRICT)
class ComparisonPlan:
    """A comparison's plan: each side's as a fixed-N campaign of ``pairs`` episodes (the same
    seed), and the test's margin, level and method."""

    env_id: str
    a: Plan
    b: Plan
    pairs: Annotated[int, Field(ge=1)]
    margin: Annotated[float, Field(ge=0, lt=1)]
    alpha: Level
    seed: Count
    method: Annotated[str, AfterValidator(_known_paired_method)]

    @model_validator(mode="before")
    @classmethod
    def _as_stored(cls, data: Any) -> Any:
        """Every field recorded; sides stored before they were whole plans (their campaign's
        env, N = pairs, seed and defaults) are made whole."""
        if not isinstance(data, dict):
            return data
        _every_field(cls, data)
        data = dict(data)
        for name in ("a", "b"):
            side = data[name]
            if isinstance(side, dict) and not {"episodes", "epsilon", "delta", "seed",
                                               "method", "env_id"} & set(side):
                data[name] = {**side, "env_id": data["env_id"], "episodes": data["pairs"],
                              "epsilon": CampaignConfig.epsilon,
                              "delta": CampaignConfig.delta, "seed": data["seed"],
                              "method": FixedN.name}
        return data

    def __post_init__(self) -> None:
        for name, side in (("a", self.a), ("b", self.b)):
            if (side.env_id, side.episodes, side.seed, side.method) != (
                    self.env_id, self.pairs, self.seed, FixedN.name):
                raise ValueError(f"{name}: not the comparison's side: a fixed-N campaign of its "
                                 f"env, {self.pairs} episodes and seed {self.seed}")

    def to_json(self) -> str:
        return _COMPARISON_PLAN.dump_json(self).decode()

    def to_dict(self) -> dict[str, Any]:
        return _COMPARISON_PLAN.dump_python(self, mode="json")


_PLAN = TypeAdapter(Plan)
_COMPARISON_PLAN = TypeAdapter(ComparisonPlan)
_EPISODE = TypeAdapter(CheckedEpisode)
_PAIR = TypeAdapter(PairResult)
plan_from_json = _PLAN.validate_json  # each: ValidationError (a ValueError) unless the text
comparison_plan_from_json = _COMPARISON_PLAN.validate_json  # is one vlb-gym writes
episode_from_json = _EPISODE.validate_json
pair_from_json = _PAIR.validate_json


def first_error(exc: ValidationError) -> str:
    """A validation error's first problem, in one line: where, and what."""
    error = exc.errors()[0]
    where = ".".join(str(part) for part in error["loc"]) or "the record"
    return f"{where}: {error['msg']}"
