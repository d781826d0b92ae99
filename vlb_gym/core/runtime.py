"""Running a compiled behavior as a policy.

:class:`BehaviorPolicy` maps observations to actions with a Stable-Baselines3-like ``predict``; it
keeps its position in the graph (a stack of frames, one per active sub-behavior) and its variables,
and sets :attr:`BehaviorPolicy.finished` once it rests in a terminal node with no edge to take.

Run-time semantics: after a node's primitive (or sub-behavior) completes, its outgoing edges are
tried in file order and the first whose guard holds is taken; its ``set`` assignments run in order,
then its ``param`` is evaluated for the next primitive. If no guard holds, a terminal node finishes
its behavior (returning control to the parent's node), and a non-terminal node is an error. Every
evaluation runs under the policy's :class:`~vlb_gym.core.budget.Budget`; within one, a
behavior function of no arguments is computed once (:meth:`~vlb_gym.core.budget.Budget.once`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .compiler import CompiledBehavior
from .env import PrimitiveEnv
from .errors import UserError
from .budget import Budget, EvaluationLimitError
from .expressions import Expression, guard_namespace
from .promise import Claim


class BehaviorRuntimeError(UserError, RuntimeError):
    """A behavior failed while running (a runtime error in the graph); the episode fails."""


class _Frame:
    __slots__ = ("behavior", "ns", "node", "since")

    def __init__(self, behavior: CompiledBehavior, static: Mapping[str, Any], budget: Budget,
                 since: int):
        self.behavior = behavior
        self.since = since  # primitives chosen before this behavior began
        self.ns = guard_namespace(static, budget)
        self.node = behavior.start_node
        for name, fn in behavior.functions:
            value = fn.evaluate(self.ns)
            self.ns[name] = budget.once(value) if not fn.args else value


class BehaviorPolicy:
    """A compiled behavior acting as a policy on one environment.

    ``predict(obs)`` returns ``(action, node)``, ``node`` the id of the node that chose the
    action (``sub-behavior/node`` in a sub-behavior); once the behavior has finished it returns
    ``(None, None)`` and :attr:`finished` is True. A :class:`BehaviorRuntimeError` means the
    behavior itself failed (stuck in a non-terminal node, an expression raised, a parameter outside
    the primitive's space).

    A behavior that declares a promise and finishes leaves a :class:`~vlb_gym.core.promise.Claim`
    that :meth:`claims` hands over (innermost first): the episode's robustness wrapper judges it
    with the environment's true state, which the policy never reads.
    """

    def __init__(self, behavior: CompiledBehavior, interface: PrimitiveEnv):
        self.behavior = behavior
        self._interface = interface
        self._helpers = interface.make_helpers()
        self._budget = Budget()  # one evaluation at a time, whichever frame it runs in
        self._static = self._budget.charging(self._helpers.functions())
        self.reset()

    @property
    def name(self) -> str:
        return self.behavior.name

    @property
    def episode_work(self) -> int:
        """The work units the evaluations of this episode have used so far."""
        return self._budget.episode_spent

    def reset(self, seed: int | None = None) -> None:
        """Forget the position in the graph and the variables; the next predict starts anew
        (a graph draws no random numbers: ``seed`` is unused)."""
        self._stack: list[_Frame] = []
        self._budget.new_episode()
        self._started = False
        self.finished = False
        self.trace: list[tuple[str, str]] = []  # (behavior, node) of every primitive chosen
        self._claims: list[Claim] = []

    def claims(self) -> list[Claim]:
        """The promises of the behaviors that finished since the last call, to be judged."""
        claims, self._claims = self._claims, []
        return claims

    def predict(self, observation: Any, state: Any = None, episode_start: Any = None,
                deterministic: bool = True) -> tuple[np.ndarray | None, str | None]:
        """The next action for ``observation`` and the node that chose it, or ``(None, None)``
        once the behavior has finished."""
        if episode_start is not None and np.any(episode_start):
            self.reset()
        if self.finished:
            return None, None
        self._helpers.bind(observation)
        self._budget.new_step()
        if not self._started:
            self._started = True
            action = self._enter_behavior(self.behavior)
        else:
            action = self._advance()
        if action is None:
            return None, None
        behavior, node = self.trace[-1]
        return action, node if behavior == self.behavior.name else f"{behavior}/{node}"

    def _run(self, expr: Expression, frame: _Frame) -> Any:
        try:
            return expr.evaluate(frame.ns)
        except Exception as exc:  # any failure of the behavior's own logic fails the episode
            raise BehaviorRuntimeError(f"{expr.where}: {type(exc).__name__}: {exc}") from exc

    def _enter_behavior(self, behavior: CompiledBehavior) -> np.ndarray:
        frame = _Frame(behavior, self._static, self._budget, len(self.trace))
        self._stack.append(frame)
        for name, expr in behavior.variables:
            frame.ns[name] = self._run(expr, frame)
        return self._enter_node(frame, behavior.start_node, behavior.start_param)

    def _enter_node(self, frame: _Frame, node_id: str, param: Expression | None) -> np.ndarray:
        frame.node = node_id
        node = frame.behavior.nodes[node_id]
        if node.child is not None:
            return self._enter_behavior(node.child)
        value = self._run(param, frame)
        self.trace.append((frame.behavior.name, node_id))
        try:
            return self._interface.encode_action(node.primitive, value)
        except ValueError as exc:
            raise BehaviorRuntimeError(f"{param.where}: {exc}") from exc

    def _advance(self) -> np.ndarray | None:
        while self._stack:
            frame = self._stack[-1]
            for edge in frame.behavior.out_edges[frame.node]:
                if self._run(edge.guard, frame):
                    for name, expr in edge.assignments:
                        frame.ns[name] = self._run(expr, frame)
                    return self._enter_node(frame, edge.to, edge.param)
            if frame.node not in frame.behavior.terminals:
                raise BehaviorRuntimeError(
                    f"{frame.behavior.source}: stuck at node {frame.node!r}: no edge guard holds "
                    "and the node is not terminal")
            done = self._stack.pop().behavior
            if done.promise is not None:
                self._claims.append(Claim(done.name, done.promise,
                                          done.spec.promise.description, frame.since,
                                          done.spec.promise.as_soon_as))
        self.finished = True
        return None


def failure_cause(exc: Exception) -> str:
    """The class of an exception that ended an episode: the evaluation budget, the behavior's
    own logic, or an error of the environment or policy code."""
    if isinstance(exc, EvaluationLimitError) or isinstance(exc.__cause__, EvaluationLimitError):
        return "evaluation budget exceeded"
    if isinstance(exc, BehaviorRuntimeError):
        return "behavior runtime error"
    return f"exception ({type(exc).__name__})"
