"""A behavior's promise: what it guarantees holds when it finishes (the paper's composition).

A behavior file may declare ``"promise": {"expr": ..., "description": ...}``: an expression over
the environment's *outcome helpers* (:meth:`PrimitiveEnv.make_judge`), which read the true state
when the behavior finished and the steps it ran -- never the behavior's own variables, which
would let a behavior certify itself. rho_B is +1 only if, besides every certificate holding and
the behavior finishing, every promise held: the top behavior's when it finishes, and a
sub-behavior's when its node completes (a behavior used as a node is a primitive whose terminal
region is its promise, so a parent may rely on it).

:func:`compile_promise` checks a promise when the behavior compiles; the runtime hands a
:class:`Claim` to the episode's :class:`~vlb_gym.wrappers.robustness.RobustnessWrapper` when a
behavior finishes, and :func:`judge` decides it.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .budget import Budget
from .expressions import BUILTINS, Expression, ExpressionError, guard_namespace
from .helpers import arity
from .spec import BehaviorSpec, BehaviorSpecError
from .signatures import BUILTIN_SIGNATURES, helper_signatures
from .typecheck import check as typecheck

if TYPE_CHECKING:
    from .env import PrimitiveEnv


@dataclass(frozen=True)
class Episode:
    """What a judge reads: the env's ``state`` when the behavior finished, the ``steps`` (each
    step's ``info``) the behavior ran, and ``entry``, the ``info`` just before its first step
    (the reset's info, or the previous step's)."""

    state: Any
    steps: Sequence[Mapping[str, Any]]
    entry: Mapping[str, Any]


@dataclass(frozen=True)
class Claim:
    """A behavior that has just finished, and what it promised: judged over the steps from
    index ``since`` of the episode on."""

    behavior: str
    expression: Expression
    description: str
    since: int

    @property
    def words(self) -> str:
        """The promise in words: its description, else its expression."""
        return self.description or self.expression.source


def compile_promise(spec: BehaviorSpec, interface: PrimitiveEnv, source: str,
                    own: Mapping[str, str]) -> Expression | None:
    """The promise of ``spec`` checked by :func:`check_promise` (None if it declares none)."""
    if spec.promise is None:
        return None
    return check_promise(spec.promise.expr, interface, f"{source}: promise.expr", own)


def check_promise(text: str, interface: PrimitiveEnv, where: str = "promise",
                  own: Mapping[str, str] | None = None) -> Expression:
    """``text`` compiled as a promise over ``interface``'s outcome helpers (``own`` maps the
    behavior's own names -- variables, functions, observation helpers -- to what they are, for
    a precise refusal). BehaviorSpecError (layer ``expressions``) if it is malformed, names
    anything but outcome helpers and builtins, or depends on nothing the episode did."""
    judge = interface.make_judge()
    if judge is None:
        raise BehaviorSpecError(f"{where}: {interface.env_id or type(interface).__name__} "
                                "offers no outcome helpers, so a behavior on it cannot promise "
                                "anything", "expressions")
    helpers = judge.functions()
    names: dict[str, int | None] = {n: None for n in BUILTINS}
    names.update({n: arity(f) for n, f in helpers.items()})
    try:
        expression = Expression(text, names, where)
    except ExpressionError as exc:
        unknown = sorted(n for n in own or {} if _mentions(text, n) and n not in names)
        if unknown:
            raise BehaviorSpecError(
                f"{where}: {unknown[0]!r} is {own[unknown[0]]}; a promise is judged by the "
                "environment from the episode, so it may use only the outcome helpers ("
                f"{', '.join(sorted(helpers))}) and builtins", "expressions") from None
        raise BehaviorSpecError(str(exc), "expressions") from None
    try:
        kind = typecheck(text, {**BUILTIN_SIGNATURES, **helper_signatures(helpers)}, where)
    except ExpressionError as exc:
        raise BehaviorSpecError(str(exc), "expressions") from None
    if kind is not None and kind.kind != "bool":
        raise BehaviorSpecError(f"{where}: {text!r} is a {kind.describe()}, not true or false; "
                                "a promise is a condition (e.g. a comparison)", "expressions")
    if not expression.names & set(helpers):
        raise BehaviorSpecError(f"{where}: {text!r} calls no outcome helper, so it holds or "
                                "fails whatever the behavior does and proves nothing; use "
                                f"{', '.join(sorted(helpers))}", "expressions")
    return expression


def _mentions(text: str, name: str) -> bool:
    return re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", text) is not None


class Judging:
    """Judges promises on one env: its outcome helpers made once, and every judgement of an
    episode under one budget (:meth:`new_episode` at each reset), so that however many
    promises an episode judges, their work together stays bounded."""

    def __init__(self, interface: PrimitiveEnv):
        self.interface = interface
        helpers = interface.make_judge()
        assert helpers is not None  # compile_promise refused a promise without outcome helpers
        self.helpers = helpers
        self.budget = Budget()
        self.namespace = guard_namespace(self.budget.charging(helpers.functions()), self.budget)

    def new_episode(self) -> None:
        self.budget.new_episode()

    def __call__(self, claim: Claim, history: Sequence[Mapping[str, Any]],
                 reset_info: Mapping[str, Any]) -> str | None:
        """None if ``claim``'s promise holds on the episode so far (``history``: every step's
        info since the reset), else why not: the promise, and what the judge saw. An
        evaluation that raises or exceeds its budget is a failed promise, never an
        exception."""
        helpers, since = self.helpers, claim.since
        helpers.bind(Episode(self.interface.state, history[since:],
                             history[since - 1] if since > 0 else reset_info))
        try:
            held = bool(claim.expression.evaluate(self.namespace))
            problem = None if held else "it does not hold"
        except Exception as exc:  # the promise's own failure: the episode's, not the process's
            problem = f"{type(exc).__name__}: {exc}"
        if problem is None:
            return None
        return (f"promise of {claim.behavior} failed ({claim.words}: {problem}): "
                f"{helpers.summary()}")


def judge(interface: PrimitiveEnv, claim: Claim, history: Sequence[Mapping[str, Any]],
          reset_info: Mapping[str, Any]) -> str | None:
    """One judgement (see :class:`Judging`) with a budget of its own."""
    return Judging(interface)(claim, history, reset_info)
