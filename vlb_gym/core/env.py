"""The one contract every vlb-gym environment meets: :class:`PrimitiveEnv`.

An environment whose ``step()`` runs one whole motion primitive. The base class owns what all of
them share -- the primitives by name, the action <-> (primitive, parameter) encoding, ``step`` =
decode -> :func:`~vlb_gym.core.primitive.execute` -> ``info``, the render-mode check, the reset
guard, ``state``, the words for the sampling distribution, filming, and what behaviors need. A
subclass supplies its primitives and spaces (in ``__init__``), its state sampler, its observation,
its helpers and the words for its distribution; see ``docs/new_env.md`` for a worked example.

The action encoding: with one primitive, the action *is* its parameter (the action space is the
primitive's parameter space); with several primitives whose parameter spaces are the same
``MultiDiscrete``, the action is ``[primitive index, *parameter]``. Subclasses with other needs
override :meth:`PrimitiveEnv.encode_action` and :meth:`PrimitiveEnv.decode_action`.
"""

from __future__ import annotations

import abc
import copy
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from .helpers import Helpers, Judge, brief
from .primitive import MotionPrimitive, Outcome, execute
from .search_space import SearchSpace

State = TypeVar("State")
FrameCallback = Callable[[np.ndarray], None]


@dataclass(frozen=True)
class FrameKey:
    """How to read an env's frames: what each colour shows, and for a square grid of cells
    drawn edge to edge, its cells per side (``i`` left to right, ``j`` bottom to top), which a
    report labels along the frame's edges."""

    colours: tuple[tuple[str, tuple[int, int, int]], ...]
    cells: int | None = None


class PrimitiveEnv(gym.Env, Generic[State], abc.ABC):
    """Base class of environments whose ``step()`` runs one whole motion primitive.

    Subclasses call ``super().__init__(primitives, observation_space, render_mode)`` and
    implement :meth:`sample_state`, :meth:`observation`, :meth:`make_helpers` and
    :meth:`sampling_distribution`; they may override :meth:`make_judge` (promises),
    :meth:`search_space` (synthesis), :meth:`reset_info`, :meth:`step_info`,
    :meth:`reward`, :meth:`render` and :meth:`film`, and name slow imports in :attr:`preload`. Every step's ``info`` holds ``primitive``,
    ``param``, ``admissible``, ``certificate`` (and ``reason`` when it failed), the parts'
    certificates and the measurements of the primitive (:class:`~vlb_gym.core.primitive.Outcome`),
    plus what :meth:`step_info` adds. The env never terminates by itself: a behavior decides when
    it has finished (task termination for RL is a wrapper, in :mod:`vlb_gym.baselines`).
    """

    env_id: str = ""
    metadata: dict[str, Any] = {"render_modes": [], "render_fps": 4}
    #: Modules a campaign imports once, before it starts its worker processes (which inherit
    #: them), rather than in every worker, and before its clock starts when it runs in process:
    #: slow imports the env makes on first use.
    preload: tuple[str, ...] = ()

    def __init__(self, primitives: Sequence[MotionPrimitive[State]], observation_space: gym.Space,
                 render_mode: str | None = None):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode={render_mode!r} is not supported; "
                             f"use one of {self.metadata['render_modes']} or None")
        self.render_mode = render_mode
        self.primitives: dict[str, MotionPrimitive[State]] = {p.name: p for p in primitives}
        self.primitive_order = tuple(primitives)  # index in the action encoding
        self._index = {p.name: k for k, p in enumerate(primitives)}
        self._param_nvec = {p.name: self._nvec(p.param_space) for p in primitives}
        self.observation_space = observation_space
        self.action_space = self._action_space()
        self._action_nvec = self._nvec(self.action_space)
        self._state: State | None = None
        self._on_frame: FrameCallback | None = None
        #: what the last step's primitive recorded (None before the first step of an episode):
        #: an env's :meth:`render` may draw it, e.g. where a failed step was sent
        self.last_outcome: Outcome | None = None

    # -- what a subclass supplies ----------------------------------------------------------------
    @abc.abstractmethod
    def sample_state(self) -> State:
        """Draw ``(x, d)`` from the sampling distribution with ``self.np_random``."""

    @abc.abstractmethod
    def observation(self) -> Any:
        """The observation of the current state (an element of ``observation_space``)."""

    @abc.abstractmethod
    def make_helpers(self) -> Helpers:
        """Fresh helpers (the paper's E-functions) reading this env's observations."""

    @abc.abstractmethod
    def sampling_distribution(self) -> str:
        """The distribution ``reset()`` samples from, in words: what a guarantee holds for."""

    def make_judge(self) -> Judge | None:
        """Fresh outcome helpers for behaviors' promises (read the true state and the steps a
        behavior ran; see :mod:`vlb_gym.core.promise`); None if behaviors on this env cannot
        promise anything."""
        return None

    def search_space(self) -> SearchSpace | None:
        """What the behavior synthesizer needs to search behaviors for this env (its types,
        how primitives are parametrised, memory, least behaviors; see
        :mod:`vlb_gym.core.search_space`); None if behaviors cannot be searched for it."""
        return None

    def reset_info(self) -> dict[str, Any]:
        """``info`` returned by ``reset``."""
        return {}

    def step_info(self, outcome: Outcome) -> dict[str, Any]:
        """What the env adds to (or how it presents) a step's ``info``, after the primitive."""
        return {}

    def reward(self, outcome: Outcome) -> float:
        """The step's reward; 0 by default (rho_B, not rewards, scores behaviors)."""
        return 0.0

    # -- the action encoding ------------------------------------------------------------------
    def _action_space(self) -> gym.Space:
        first = self.primitive_order[0].param_space
        if len(self.primitive_order) == 1:
            return first
        if isinstance(first, spaces.MultiDiscrete) and all(
                p.param_space == first for p in self.primitive_order):
            return spaces.MultiDiscrete([len(self.primitive_order), *self._nvec(first)])
        raise TypeError("several primitives need MultiDiscrete parameter spaces of one shape; "
                        "override encode_action and decode_action for other layouts")

    def _layout(self) -> str:
        if len(self.primitive_order) == 1:
            return f"the parameter of {self.primitive_order[0].name!r}"
        names = ", ".join(f"{k} {p.name}" for k, p in enumerate(self.primitive_order))
        return f"an integer array [primitive ({names}), *parameter]"

    def encode_action(self, primitive: str, param: Any) -> np.ndarray:
        """The action running ``primitive`` with ``param``; ``ValueError`` if ``param`` is not in
        the primitive's parameter space."""
        if primitive not in self.primitives:
            raise ValueError(f"unknown primitive {primitive!r}")
        index, space = self._index[primitive], self.primitives[primitive].param_space
        if isinstance(space, spaces.MultiDiscrete):
            values = _discrete(param, self._param_nvec[primitive])
            if values is not None and len(self.primitive_order) > 1:
                return np.array([index, *values], dtype=self.action_space.dtype)
            value = None if values is None else np.array(values, dtype=space.dtype)
        else:
            value = _box_value(param, space)
        if value is None:
            raise ValueError(f"{primitive} parameter {brief(param)} is not in its parameter space "
                             f"{space}")
        if len(self.primitive_order) == 1:
            return value
        return np.concatenate([[index], value.ravel()]).astype(self.action_space.dtype)

    def decode_action(self, action: Any) -> tuple[MotionPrimitive[State], Any]:
        """The primitive and parameter an action names; ``ValueError`` outside the action
        space. Parameters are plain tuples of Python numbers."""
        space = self.action_space
        if not isinstance(space, spaces.MultiDiscrete):
            given = _box_value(action, space)
            values = None if given is None else np.asarray(action, np.float64).ravel().tolist()
        elif isinstance(action, np.ndarray):  # the fast path: actions are arrays
            values = action.tolist() if action.shape == space.shape and action.dtype.kind in "iu" \
                else None
            if values is not None and not _within(values, self._action_nvec):
                values = None
        else:
            values = _discrete(action, self._action_nvec)
        if values is None:
            raise ValueError(f"action {brief(action)} is not in the action space {space}: "
                             f"expected {self._layout()}")
        if len(self.primitive_order) == 1:
            cast = float if isinstance(space, spaces.Box) else int
            return self.primitive_order[0], tuple(cast(v) for v in values)
        return self.primitive_order[values[0]], tuple(values[1:])

    @staticmethod
    def _nvec(space: gym.Space) -> tuple[int, ...]:
        if not isinstance(space, spaces.MultiDiscrete):
            return ()
        return tuple(np.asarray(space.nvec).ravel().tolist())

    # -- gymnasium API -------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        self._state = self.sample_state()
        self.last_outcome = None
        self._frame()
        return self.observation(), self.reset_info()

    def step(self, action: Any):
        state = self.state
        primitive, param = self.decode_action(action)
        outcome = execute(primitive, state, param, self.np_random)
        self.last_outcome = outcome
        info = outcome.as_info()
        info.update(self.step_info(outcome))
        self._frame()
        return self.observation(), self.reward(outcome), False, False, info

    def save(self) -> Any:
        """The state and the generator, to come back to with :meth:`load` (the synthesizer
        tries many continuations of one prefix). The default deep-copies them; an env whose
        state has large parts that never change may share those."""
        return copy.deepcopy(self.state), copy.deepcopy(self.np_random.bit_generator.state)

    def load(self, saved: Any) -> None:
        """Continue from what :meth:`save` returned (which stays as it was)."""
        state, generator = saved
        self._state = copy.deepcopy(state)
        self.last_outcome = None
        self.np_random.bit_generator.state = copy.deepcopy(generator)

    @property
    def state(self) -> State:
        """The joint state (x, d); for analysis, tests and the env's own primitives, not for
        policies (they see observations)."""
        if self._state is None:
            raise RuntimeError("call reset() before using the environment")
        return self._state

    # -- what behaviors and tools use ----------------------------------------------------------
    def inadmissible_reason(self, primitive: str, param: Any) -> str | None:
        """None when ``param`` is admissible for ``primitive`` now, else why not (judged with
        the true state, as admissibility is)."""
        return self.primitives[primitive].inadmissible_reason(self.state, param)

    def frame_key(self) -> FrameKey | None:
        """What this env's frames show (None, the default: no key)."""
        return None

    def film(self, callback: FrameCallback | None) -> None:
        """Call ``callback`` with every frame the env shows (after reset and after each
        primitive, by default; envs that simulate continuous motion film it at ``render_fps``);
        None stops filming. Needs a ``render_mode``."""
        if callback is not None and self.render_mode is None:
            raise ValueError("filming needs a render_mode")
        self._on_frame = callback

    def _frame(self) -> None:
        if self._on_frame is not None:
            self._on_frame(self.render())


def _within(values: list[int], nvec: tuple[int, ...]) -> bool:
    """Whether the ints ``values`` satisfy ``0 <= values[k] < nvec[k]``, with one per bound."""
    if len(values) != len(nvec):
        return False
    for value, n in zip(values, nvec):
        if not 0 <= value < n:
            return False
    return True


def _box_value(param: Any, space: gym.Space) -> np.ndarray | None:
    """``param`` as an array of ``space``'s dtype if it is a real array (not bools) of the
    space's shape whose values, as given, lie in its bounds; else None."""
    if not isinstance(param, (tuple, list, np.ndarray)):
        return None
    try:
        given = np.asarray(param)
    except (TypeError, ValueError, OverflowError):
        return None
    if given.shape != space.shape or given.dtype.kind not in "fiu":
        return None
    given = given.astype(np.float64)
    if not (np.all(np.isfinite(given)) and np.all(given >= space.low)
            and np.all(given <= space.high)):
        return None
    return given.astype(space.dtype)


def _discrete(param: Any, nvec: tuple[int, ...]) -> list[int] | None:
    """``param`` as a list if it is a flat list, tuple or array of integers (not bools) with
    ``0 <= param[k] < nvec[k]``, else None (plain Python: this runs on every decision)."""
    if not isinstance(param, (tuple, list, np.ndarray)) or len(param) != len(nvec):
        return None
    values = param if type(param) is list else list(param)
    for value in values:
        if type(value) is not int and not isinstance(value, np.integer):
            return None
    return values if _within(values, nvec) else None
