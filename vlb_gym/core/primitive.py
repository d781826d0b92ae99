"""Motion primitives (the paper's Definition 1) and their certificates (eq. certificate).

A primitive is ``P = (Xi, A, U, R)``:

* ``Xi`` -- :attr:`MotionPrimitive.param_space`, a Gymnasium space of parameters;
* ``A(x, d)`` -- :meth:`MotionPrimitive.admissible`, whether a parameter is valid in this state
  (:meth:`MotionPrimitive.inadmissible_reason` says why not);
* ``U`` -- :meth:`MotionPrimitive.run`, the controller, run to completion; it returns what it
  measured;
* ``R(xi, d)`` -- :meth:`MotionPrimitive.terminal_region`, a :class:`Region` whose
  ``violations`` say which parts of it the final state misses.

:func:`execute` is the one place where these meet: it checks the parameter, runs the controller,
and evaluates the certificate ``C = x_f in R(xi, d)``, returning everything as one
:class:`Outcome`. Environments call it from ``step()`` and build ``info`` from the outcome alone.
"""

from __future__ import annotations

import abc
import enum
import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Generic, Protocol, TypeVar

import gymnasium as gym
import numpy as np

State = TypeVar("State")
State_contra = TypeVar("State_contra", contravariant=True)


class Region(Protocol[State_contra]):
    """A set of system states: the terminal region R(xi, d) of a primitive."""

    def violations(self, state: State_contra) -> dict[str, str]:
        """What ``state`` misses of the region, by part (part name -> why); empty when the
        state lies in it."""
        ...


class ControllerFailure(RuntimeError):
    """Raised by a controller that could not complete; the certificate is then false."""


class Failure(str, enum.Enum):
    """Why a certificate is false: the parameter was inadmissible (nothing ran), the controller
    could not complete, or the final state missed the terminal region. A step's ``info`` holds
    the value under ``"failure"``."""

    INADMISSIBLE = "inadmissible"
    CONTROLLER = "controller"
    REGION = "region"


@dataclass(slots=True)
class Outcome:
    """What one primitive execution recorded: the paper's tuple (xi, P, x_f) and its certificate.

    ``failure`` says why the certificate is false (None when it holds), ``certificates`` holds
    one boolean per part of the terminal region (for primitives whose region has named parts),
    ``details`` what the controller measured. Read-only by convention
    (not frozen: one is made per step, and frozen dataclasses are slow to make).
    """

    primitive: str
    param: Any
    admissible: bool
    certificate: bool
    reason: str | None = None
    certificates: Mapping[str, bool] = field(default_factory=dict)
    details: Mapping[str, Any] = field(default_factory=dict)
    failure: Failure | None = None

    def as_info(self) -> dict[str, Any]:
        """The step's ``info``: primitive, param, admissible, certificate, the failure and its
        reason when it failed, the parts' certificates (if any) and the measurements."""
        info = {"primitive": self.primitive, "param": self.param,
                "admissible": self.admissible, "certificate": self.certificate}
        if self.failure is not None:
            info["failure"] = self.failure.value
        if self.reason is not None:
            info["reason"] = self.reason
        if self.certificates:
            info["certificates"] = dict(self.certificates)
        info.update(self.details)
        return info


class MotionPrimitive(abc.ABC, Generic[State]):
    """Base class of a motion primitive acting on an environment's state ``(x, d)``.

    Subclasses set ``name``, ``description`` and ``param_space`` and implement ``admissible``,
    ``terminal_region`` and ``run``; ``region_parts`` names the parts of a region whose
    ``violations`` report more than one (the scoop's ``pose`` and ``delivered``).
    """

    name: str
    description: str
    param_space: gym.Space
    region_parts: tuple[str, ...] = ()

    @abc.abstractmethod
    def admissible(self, state: State, param: Any) -> bool:
        """Whether ``param`` lies in A(x, d)."""

    def inadmissible_reason(self, state: State, param: Any) -> str | None:
        """None when ``param`` lies in A(x, d), else why not. Primitives that can say more than
        the default sentence override this (and define ``admissible`` from it)."""
        if self.admissible(state, param):
            return None
        return f"parameter {param!r} is not admissible for {self.name!r}"

    def admissible_mask(self, state: State) -> np.ndarray:
        """A(x, d) over a ``MultiDiscrete`` parameter space, as a boolean array of its shape
        ``nvec``. The default asks :meth:`admissible` of every parameter; primitives override it
        with a vectorised equivalent where masks are needed often (RL)."""
        nvec = tuple(int(n) for n in np.asarray(self.param_space.nvec).ravel())
        mask = np.zeros(nvec, dtype=bool)
        for index in itertools.product(*map(range, nvec)):
            mask[index] = self.admissible(state, index)
        return mask

    @abc.abstractmethod
    def terminal_region(self, state: State, param: Any) -> Region[State]:
        """R(xi, d), computed before the controller runs."""

    @abc.abstractmethod
    def run(self, state: State, param: Any, rng: np.random.Generator) -> Mapping[str, Any]:
        """Run the controller U to completion, updating ``state`` in place; return what it
        measured (reported in the step's ``info``; empty if nothing).

        Raise :class:`ControllerFailure` when it cannot complete.
        """


def execute(primitive: MotionPrimitive[State], state: State, param: Any,
            rng: np.random.Generator) -> Outcome:
    """Run one primitive and certify it.

    An inadmissible parameter is not executed; it and a failing controller give a false
    certificate with a reason, never an exception.
    """
    parts = dict.fromkeys(primitive.region_parts, False)
    reason = primitive.inadmissible_reason(state, param)
    if reason is not None:
        return Outcome(primitive.name, param, False, False, reason, parts,
                       failure=Failure.INADMISSIBLE)
    region = primitive.terminal_region(state, param)
    try:
        details = primitive.run(state, param, rng)
    except ControllerFailure as exc:
        return Outcome(primitive.name, param, True, False, f"controller failed: {exc}", parts,
                       failure=Failure.CONTROLLER)
    violations = region.violations(state)
    if not violations:
        return Outcome(primitive.name, param, True, True, None,
                       dict.fromkeys(primitive.region_parts, True), details)
    parts = {part: part not in violations for part in primitive.region_parts}
    return Outcome(primitive.name, param, True, False, "; ".join(violations.values()), parts,
                   details, Failure.REGION)
