"""Motion primitives (the paper's Definition 1) and their certificates (eq. certificate).

A primitive is ``P = (Xi, A, U, R)``:

* ``Xi`` -- :attr:`MotionPrimitive.param_space`, a Gymnasium space of parameters;
* ``A(x, d)`` -- :meth:`MotionPrimitive.admissible`, whether a parameter is valid in this state;
* ``U`` -- :meth:`MotionPrimitive.run`, the controller, run to completion;
* ``R(xi, d)`` -- :meth:`MotionPrimitive.terminal_region`, a :class:`Region` with ``contains``.

:func:`execute` is the one place where these meet: it checks the parameter, runs the controller,
and evaluates the certificate ``C = x_f in R(xi, d)``. Environments call it from ``step()``.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass
from typing import Any, Generic, Protocol, TypeVar

import gymnasium as gym
import numpy as np

State = TypeVar("State")


class Region(Protocol[State]):
    """A set of system states; the terminal region R(xi, d) of a primitive."""

    def contains(self, state: State) -> bool: ...


class ControllerFailure(RuntimeError):
    """Raised by a controller that could not complete; the certificate is then false."""


@dataclass(frozen=True)
class Outcome:
    """What one primitive execution recorded: the paper's tuple (xi, P, x_f) and its certificate."""

    primitive: str
    param: Any
    admissible: bool
    certificate: bool
    reason: str | None = None

    def as_info(self) -> dict[str, Any]:
        info = {"primitive": self.primitive, "param": self.param,
                "admissible": self.admissible, "certificate": self.certificate}
        if self.reason is not None:
            info["reason"] = self.reason
        return info


class MotionPrimitive(abc.ABC, Generic[State]):
    """Base class of a motion primitive acting on an environment's state ``(x, d)``."""

    name: str
    description: str
    param_space: gym.Space

    @abc.abstractmethod
    def admissible(self, state: State, param: Any) -> bool:
        """Whether ``param`` lies in A(x, d)."""

    @abc.abstractmethod
    def terminal_region(self, state: State, param: Any) -> Region[State]:
        """R(xi, d), computed before the controller runs."""

    @abc.abstractmethod
    def run(self, state: State, param: Any, rng: np.random.Generator) -> None:
        """Run the controller U to completion, updating ``state`` in place.

        Raise :class:`ControllerFailure` when it cannot complete.
        """


def execute(primitive: MotionPrimitive[State], state: State, param: Any,
            rng: np.random.Generator) -> Outcome:
    """Run one primitive and certify it.

    An inadmissible parameter is not executed; it and a failing controller give a false
    certificate with a reason, never an exception.
    """
    if not primitive.admissible(state, param):
        return Outcome(primitive.name, param, False, False,
                       f"parameter {param!r} is not admissible for {primitive.name!r}")
    region = primitive.terminal_region(state, param)
    try:
        primitive.run(state, param, rng)
    except ControllerFailure as exc:
        return Outcome(primitive.name, param, True, False, f"controller failed: {exc}")
    if region.contains(state):
        return Outcome(primitive.name, param, True, True)
    return Outcome(primitive.name, param, True, False,
                   f"final state outside the terminal region of {primitive.name!r}")
