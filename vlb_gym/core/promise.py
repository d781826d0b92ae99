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
    as_soon_as: bool = False

    @property
    def words(self) -> str:
        """The promise in words: its description, else its expression."""
        return words(self.description or self.expression.source, self.as_soon_as)


def words(text: str, as_soon_as: bool) -> str:
    """A promise's words, saying so when it is kept as soon as it holds."""
    return f"{text}, stopping as soon as that holds" if as_soon_as else text


def compile_promise(spec: BehaviorSpec, interface: PrimitiveEnv, source: str,
                    own: Mapping[str, str]) -> Expression | None:
    """The promise of ``spec`` checked by :func:`check_promise` (None if it declares none)."""
    if spec.promise is None:
        return None
    expression = check_promise(spec.promise.expr, interface, f"{source}: promise.expr", own)
    if spec.promise.as_soon_as:
        check_rewinds(interface, f"{source}: promise.as_soon_as")
    return expression


def check_rewinds(interface: PrimitiveEnv, where: str) -> None:
    """BehaviorSpecError unless ``interface``'s judge can tell whether a promise held before a
    behavior's last step (what "as soon as" is judged with)."""
    judge = interface.make_judge()
    if judge is None or not judge.rewinds:
        raise BehaviorSpecError(f"{where}: {interface.env_id or type(interface).__name__} cannot "
                                "judge what held before a behavior's last step, so a promise "
                                "on it cannot be kept 'as soon as' it holds", "expressions")


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
        episode = Episode(self.interface.state, history[since:],
                          history[since - 1] if since > 0 else reset_info)
        try:
            problem = self._problem(claim, episode)
        except Exception as exc:  # the promise's own failure: the episode's, not the process's
            problem = f"{type(exc).__name__}: {exc}"
        if problem is None:
            return None
        helpers.bind(episode)  # the summary tells the finished episode
        return (f"promise of {claim.behavior} failed ({claim.words}: {problem}): "
                f"{helpers.summary()}")

    def _problem(self, claim: Claim, episode: Episode) -> str | None:
        self.helpers.bind(episode)
        if not claim.expression.evaluate(self.namespace):
            return "it does not hold"
        if not claim.as_soon_as:
            return None
        earlier: Episode | None = episode
        while earlier.steps:  # it held after no earlier step, nor before the first
            earlier = self.helpers.rewind(earlier)
            if earlier is None:
                return "what held before the last step cannot be told"
            self.helpers.bind(earlier)
            if claim.expression.evaluate(self.namespace):
                return (f"it already held after step {len(earlier.steps)}" if earlier.steps
                        else "it already held before the first step")
        return None


def judge(interface: PrimitiveEnv, claim: Claim, history: Sequence[Mapping[str, Any]],
          reset_info: Mapping[str, Any]) -> str | None:
    """One judgement (see :class:`Judging`) with a budget of its own."""
    return Judging(interface)(claim, history, reset_info)
