"""What a store holds, as it must be: the plan and record models a store is validated by
before anything is counted (strict types, no extra keys, records consistent with themselves)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import (AfterValidator, BaseModel, ConfigDict, Field, ValidationError,
                      field_validator, model_validator)

from .methods import FixedN, Sequential, method_named

_STRICT = ConfigDict(strict=True, extra="forbid")
Probability = Annotated[float, Field(gt=0, lt=1)]


def _representable(level: float) -> float:
    if 1.0 - level == 1.0:
        raise ValueError(f"{level!r} is too small: 1 minus it is 1 in floating point")
    return level


Level = Annotated[float, Field(gt=0, lt=1), AfterValidator(_representable)]
"""A probability of error (delta, alpha), as the command line takes it."""
Count = Annotated[int, Field(ge=0)]


class StoredPolicy(BaseModel):
    model_config = _STRICT
    kind: str
    ref: str
    library: str | None


class StoredSubject(BaseModel):
    """What a plan records of the policy under test and its env (a comparison has two)."""

    model_config = _STRICT
    env_id: str
    policy: StoredPolicy
    env_kwargs: dict[str, Any]
    stop_on_failure: bool
    env_modules: list[str]
    content_sha256: str
    policy_content: dict[str, Any]
    sampling_distribution: str
    versions: dict[str, str]

    @model_validator(mode="after")
    def _documents(self) -> StoredSubject:
        return _behaviors_valid(self)


def _behaviors_valid(subject: StoredSubject) -> StoredSubject:
    """A behavior's plan records its documents, by source: each must be a behavior file."""
    if subject.policy.kind != "behavior":
        return subject
    from vlb_gym.core.spec import spec_from_data

    behaviors = subject.policy_content.get("behaviors")
    if not isinstance(behaviors, dict) or not behaviors \
            or set(subject.policy_content) != {"behaviors"}:
        raise ValueError("policy_content: a behavior's plan records {'behaviors': {source: "
                         "document}}")
    for source, document in behaviors.items():
        try:
            spec_from_data(document, f"policy_content.behaviors[{source!r}]")
        except ValueError as exc:  # its first problem, in one line
            raise ValueError(str(exc).splitlines()[0]) from None
    return subject


class StoredPlan(StoredSubject):
    """The plan as a store holds it (what :class:`~.campaign.Campaign` makes). Stores written
    before plans named their statistical method say ``"sequential": true/false`` instead."""

    episodes: Annotated[int, Field(ge=1)]
    epsilon: Probability
    delta: Level
    seed: Count
    method: str

    @model_validator(mode="before")
    @classmethod
    def _named_method(cls, data: Any) -> Any:
        if isinstance(data, dict) and "method" not in data \
                and isinstance(data.get("sequential"), bool):
            legacy = data["sequential"]
            data = {k: v for k, v in data.items() if k != "sequential"}
            data["method"] = Sequential.name if legacy else FixedN.name
        return data

    @field_validator("method")
    @classmethod
    def _known_method(cls, name: str) -> str:
        method_named(name)  # ValueError naming the known ones
        return name


class StoredEpisode(BaseModel):
    """An episode's record as a store holds it (steps as lists of :data:`STEP_KEYS` values)."""

    model_config = _STRICT
    index: Count
    seed: Count
    rho: Literal[-1, 1]
    finished: bool
    primitives: Count
    failed_certificates: Count
    reason: str | None
    seconds: Annotated[float, Field(ge=0)]
    cause: str | None
    steps: list[tuple[str, str | None, Any, bool, str | None, str | None]]
    start: dict[str, Any]
    error: str | None

    @model_validator(mode="after")
    def _consistent(self) -> StoredEpisode:
        """A record that agrees with itself, as rho_B is defined: a success finished with no
        failed certificate and no reason; a failure says why."""
        failed_steps = sum(not step[3] for step in self.steps)
        if self.rho == 1 and (not self.finished or self.failed_certificates or failed_steps
                              or self.reason is not None or self.error is not None):
            raise ValueError("rho is +1 but the episode did not finish, or has a failed "
                             "certificate, a failure reason or an error")
        if self.rho == -1 and self.reason is None:
            raise ValueError("rho is -1 but no failure reason is recorded")
        if self.failed_certificates > self.primitives or len(self.steps) > self.primitives:
            raise ValueError("more failed certificates or steps than primitives")
        if failed_steps > self.failed_certificates:
            raise ValueError("more failed steps than failed certificates")
        return self


def first_error(exc: ValidationError) -> str:
    error = exc.errors()[0]
    where = ".".join(str(part) for part in error["loc"]) or "the record"
    return f"{where}: {error['msg']}"


class StoredComparisonPlan(BaseModel):
    """A comparison's plan as its store holds it (what :class:`~.comparison.Comparison`
    makes)."""

    model_config = _STRICT
    env_id: str
    a: StoredSubject
    b: StoredSubject
    pairs: Annotated[int, Field(ge=1)]
    margin: Annotated[float, Field(ge=0, lt=1)]
    alpha: Level
    seed: Count
    method: str

    @field_validator("method")
    @classmethod
    def _known_method(cls, name: str) -> str:
        from .paired_methods import paired_method_named

        paired_method_named(name)
        return name


class StoredPair(BaseModel):
    """A pair's record: episode ``index`` of A and of B."""

    model_config = _STRICT
    index: Count
    a: StoredEpisode
    b: StoredEpisode
