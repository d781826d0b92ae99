"""Running program prefixes for the search: one statement at a time, from saved states.

A :class:`Run` is one screening episode of a program prefix: where it stands (the env's saved
state, the memory, the steps so far) and whether it is still *open* (it has reached the end of
the prefix and would go on with whatever statement comes next), *finished* (the behavior ended
inside the prefix: no edge could be taken) or *failed* (a certificate, the behavior's own
logic or the step bound). :meth:`Executor.extend` runs one more statement from an open run;
:meth:`Executor.judge` decides the promise of a run whose behavior ends there.

The semantics are those of the behavior graph :meth:`~vlb_gym.abstractor.programs.Program.
document` writes (edges in order, a list-picking act entered only when its list is not empty,
every node terminal), evaluated with the package's checked expressions under the runtime's
budget; the search re-runs what it found through the real runtime before certifying it.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

from vlb_gym.core.budget import Budget, EvaluationLimitError
from vlb_gym.core.expressions import BUILTINS, Expression, guard_namespace
from vlb_gym.core.helpers import arity
from vlb_gym.core.promise import Claim, Episode, Judging
from vlb_gym.core.search_space import SearchSpace
from vlb_gym.core.signatures import BOOL, BUILTIN_SIGNATURES, Signature, helper_signatures
from vlb_gym.core.typecheck import check as typecheck
from vlb_gym.core.spec import Promise

from .closeness import Closeness
from .programs import (CHOSEN, Act, If, Loop, Set, Statement, Stop, Use, _list_of,
                       _substitute, chosen_first, memory_updates)

OPEN, FINISHED, FAILED = "open", "finished", "failed"
MAX_REPEATS = 4  # iterations in a row that repeat their steps, the guard's memory growing


@dataclass
class Run:
    """One episode of a prefix (see the module's docstring)."""

    seed: int
    saved: Any
    reset_info: dict[str, Any]
    variables: dict[str, Any]
    history: list[dict[str, Any]] = field(default_factory=list)
    status: str = OPEN
    reason: str | None = None
    work: int = 0  # the evaluation budget's work spent in the episode so far

    @property
    def trace(self) -> tuple[tuple[str, tuple], ...]:
        return tuple((s["primitive"], tuple(s["param"])) for s in self.history)

    def key(self) -> Any:
        """What later statements can depend on: the status, the steps and the memory."""
        return (self.status, self.trace,
                tuple((k, _frozen(v)) for k, v in sorted(self.variables.items())))


def _frozen(value: Any) -> Any:
    if isinstance(value, (list, tuple)):
        return tuple(_frozen(v) for v in value)
    return value


class _Failed(Exception):
    pass


def _observed(observation: Any) -> Any:
    """An observation as a comparable value (arrays as bytes)."""
    if isinstance(observation, dict):
        return tuple((k, _observed(v)) for k, v in sorted(observation.items()))
    tobytes = getattr(observation, "tobytes", None)
    return tobytes() if tobytes is not None else observation


class Executor:
    """Runs statements of programs on one env (unwrapped, made by the caller) with a
    promise."""

    def __init__(self, interface: Any, space: SearchSpace, promise: Promise,
                 max_steps: int, behaviors: dict[str, Any] | None = None):
        self.interface = interface
        self.behaviors = behaviors or {}  # library behaviors programs may use, compiled
        self.space = space
        self.max_steps = max_steps
        self.helpers = interface.make_helpers()
        self.budget = Budget()
        functions = self.helpers.functions()
        self._static = self.budget.charging(functions)
        self._names = {**{n: None for n in BUILTINS}, **{n: arity(f) for n, f in functions.items()},
                       **{m.name: -1 for m in space.memory}, **{f"n{k}": -1 for k in range(16)},
                       CHOSEN: -1}
        self._signatures = {**BUILTIN_SIGNATURES, **helper_signatures(functions)}
        self._expressions: dict[str, Expression] = {}
        self._functions: dict[str, Expression] = {}  # the behavior's own, by name
        self._reads: dict[Loop, tuple[str, ...]] = {}  # the memory each loop reads
        self._judging = Judging(interface)
        judge_names = {**{n: None for n in BUILTINS},
                       **{n: arity(f) for n, f in self._judging.helpers.functions().items()}}
        self.promise = Expression(promise.expr, judge_names, "promise")
        self.claim = Claim("candidate", self.promise, promise.description, 0, promise.as_soon_as)
        self._closeness = Closeness(promise.expr, judge_names)
        self.executed = 0  # statements run

    # -- expressions -----------------------------------------------------------------------
    def expression(self, text: str) -> Expression:
        """``text`` checked (the expression language's whitelist and limits, then the type
        check) and compiled once; ExpressionError if it is not well formed."""
        found = self._expressions.get(text)
        if found is None:
            found = Expression(text, self._names, text)
            typecheck(text, self._signatures, text)
            self._expressions[text] = found
        return found

    def define(self, name: str, args: tuple[str, ...], text: str, condition: bool) -> None:
        """Let programs call ``name(*args)``, whose value is ``text``'s (a function of the
        behavior file :meth:`~vlb_gym.abstractor.programs.Program.document` writes; a
        ``condition`` is a bool); ExpressionError if the language refuses ``text``."""
        self._functions[name] = Expression(text, {**self._names, **{a: -1 for a in args}}, name,
                                           args=args)
        self._reads.clear()
        self._names[name] = len(args)
        self._signatures[name] = Signature(len(args), len(args),
                                           **({"returns": BOOL} if condition else {}))

    def _value(self, text: str, namespace: dict[str, Any]) -> Any:
        try:
            return self.expression(text).evaluate(namespace)
        except Exception as exc:  # the candidate's own failure: its episode fails
            raise _Failed(f"{text}: {type(exc).__name__}: {exc}") from None

    # -- episodes ----------------------------------------------------------------------------
    def start(self, seed: int, first: Act) -> Run:
        """Reset to ``seed`` and run the program's first act."""
        observation, info = self.interface.reset(seed=seed)
        self.budget.new_episode()
        run = Run(seed, None, dict(info), {})
        try:
            namespace = self._namespace(observation, run)
            for memory in self.space.memory:
                run.variables[memory.name] = self._value(memory.initial, namespace)
                namespace[memory.name] = run.variables[memory.name]
            self._act(run, first, namespace)
        except _Failed as exc:
            run.status, run.reason = FAILED, str(exc)
        run.saved = self.interface.save()
        run.work = self.budget.episode_spent
        return run

    def extend(self, run: Run, statement: Statement, index: int) -> Run:
        """``run`` (open) with statement number ``index`` run after it; ``run`` is unchanged."""
        self.executed += 1
        self.interface.load(run.saved)
        self.budget.new_episode()
        self.budget.episode = run.work
        out = Run(run.seed, None, run.reset_info, dict(run.variables), list(run.history))
        try:
            self._statement(out, statement, index)
        except _Failed as exc:
            out.status, out.reason = FAILED, str(exc)
        out.saved = self.interface.save()
        out.work = self.budget.episode_spent
        return out

    def judge(self, run: Run) -> str | None:
        """None if the promise holds where ``run``'s behavior ends, else why not (the
        runtime's own judgement)."""
        if run.status == FAILED:
            return run.reason
        self.interface.load(run.saved)
        self._judging.new_episode()
        return self._judging(self.claim, run.history, run.reset_info)

    def progress(self, run: Run) -> float:
        """How close ``run``'s behavior, ending there, comes to keeping the promise (1.0: it
        keeps it; 0 for a failed run; :mod:`~vlb_gym.abstractor.closeness`)."""
        if run.status == FAILED:
            return 0.0
        self.interface.load(run.saved)
        judging = self._judging
        judging.helpers.bind(Episode(self.interface.state, run.history, run.reset_info))
        judging.new_episode()
        return self._closeness(judging.namespace)

    def _namespace(self, observation: Any, run: Run) -> dict[str, Any]:
        self.helpers.bind(observation)
        try:
            self.budget.new_step()
        except EvaluationLimitError as exc:
            raise _Failed(str(exc)) from None
        namespace = guard_namespace(self._static, self.budget)
        namespace.update(run.variables)
        for name, function in self._functions.items():  # as the runtime does
            value = function.evaluate(namespace)
            namespace[name] = value if function.args else self.budget.once(value)
        return namespace

    def _holds(self, conditions: list[str], namespace: dict[str, Any]) -> bool:
        return all(c == "True" or self._value(c, namespace) for c in conditions)

    def _statement(self, run: Run, statement: Statement, index: int) -> None:
        observation = self.interface.observation()
        namespace = self._namespace(observation, run)
        if isinstance(statement, Set):  # (one that cannot be evaluated fails the run, where
            try:  # the behavior file would fail only if it acted again: stricter, never laxer)
                run.variables[statement.name] = self._value(statement.value, namespace)
            except _Failed as exc:
                raise _Failed(f"{statement.words()}: {exc}") from None
            return
        if isinstance(statement, Stop):
            if self._holds([statement.guard], namespace):
                run.status = FINISHED
            return
        if isinstance(statement, Use):
            self._act(run, statement, namespace)
            return
        if isinstance(statement, Act):
            if self._enters(statement, [], namespace):
                self._act(run, statement, namespace)
            return
        if isinstance(statement, If):
            if self._enters(statement.body[0], [statement.guard], namespace):
                self._body(run, statement.body, namespace)
            return
        count = repeats = 0
        while run.status == OPEN:
            conditions = [statement.guard]
            if statement.limit is not None:
                conditions.insert(0, "True" if count < statement.limit else "False")
            if "False" in conditions or not self._enters(statement.body[0], conditions,
                                                         namespace):
                return
            count += 1
            before = (len(run.history), _observed(self.interface.observation()),
                      self._memory_read(run, statement))
            namespace = self._body(run, statement.body, namespace)
            if statement.limit is None:
                repeated = self._repeated(run, before, statement)
                repeats = repeats + 1 if repeated is not None else 0
                if repeated or repeats > MAX_REPEATS:
                    raise _Failed("the loop repeats itself and never ends")

    def _use(self, run: Run, name: str) -> None:
        """Run the library behavior ``name`` to its end, its promise judged as the runtime
        judges a sub-behavior's."""
        from vlb_gym.core.runtime import BehaviorPolicy, BehaviorRuntimeError

        policy = BehaviorPolicy(self.behaviors[name], self.interface)
        start = len(run.history)
        try:
            while True:
                action, _ = policy.predict(self.interface.observation())
                if action is None:
                    break
                _, _, _, _, info = self.interface.step(action)
                run.history.append(info)
                if not info["certificate"]:
                    raise _Failed(f"step {len(run.history)}: {info['primitive']} "
                                  f"{info['param']}: {info.get('reason', 'certificate failed')}")
                if len(run.history) >= self.max_steps:
                    raise _Failed(f"truncated: step bound of {self.max_steps} primitives")
                self._claims(policy, run, start)
        except BehaviorRuntimeError as exc:
            raise _Failed(str(exc)) from None
        self._claims(policy, run, start)

    def _claims(self, policy: Any, run: Run, start: int) -> None:
        for claim in policy.claims():
            moved = replace(claim, since=claim.since + start)
            problem = self._judging(moved, run.history, run.reset_info)
            if problem is not None:
                raise _Failed(problem)

    def _repeated(self, run: Run, before: tuple[int, Any, Any], loop: Loop) -> bool | None:
        """Whether a loop's iteration ran the previous iteration's steps again and left what
        the agent observes, and the memory its guard reads, as they were (so it would go on
        forever); None where it did not repeat the steps or changed what the agent observes.
        (Where the guard reads a memory that grew, as "while fewer than three senses", the loop
        may end: False, and after :data:`MAX_REPEATS` of them in a row it is taken to repeat
        itself, the runtime's step bound being far.)"""
        steps, seen, memory = before
        acts = len(loop.body)
        if steps < acts or run.status != OPEN:
            return None
        trace = run.trace
        if trace[-acts:] != trace[steps - acts:steps] or \
                _observed(self.interface.observation()) != seen:
            return None
        return self._memory_read(run, loop) == memory

    def _memory_read(self, run: Run, loop: Loop) -> tuple[Any, ...]:
        """The values of the memory variables ``loop``'s guard reads, itself or through the
        behavior's functions it calls."""
        names = self._reads.get(loop)
        if names is None:
            memory = {m.name for m in self.space.memory}
            pending, called, read = [self.expression(loop.guard)], set(), set()
            while pending:
                used = pending.pop().names
                read |= used & memory
                for name in (used & self._functions.keys()) - called:
                    called.add(name)
                    pending.append(self._functions[name])
            names = self._reads[loop] = tuple(sorted(read))
        return tuple(_frozen(run.variables.get(name)) for name in names)

    def _enters(self, act: Act, conditions: list[str], namespace: dict[str, Any]) -> bool:
        picked = _list_of(act.param)
        extra = [f"len({picked}) > 0"] if picked is not None else []
        return self._holds([*conditions, *extra], namespace)

    def _body(self, run: Run, body: tuple[Act, ...], namespace: dict[str, Any]
              ) -> dict[str, Any]:
        self._act(run, body[0], namespace)
        for act in body[1:]:
            if run.status != OPEN:
                break
            namespace = self._namespace(self.interface.observation(), run)
            if not self._enters(act, [], namespace):
                run.status = FINISHED
                break
            self._act(run, act, namespace)
        if run.status == OPEN:
            namespace = self._namespace(self.interface.observation(), run)
        return namespace

    def _act(self, run: Run, act: Act | Use, namespace: dict[str, Any]) -> None:
        if isinstance(act, Use):
            self._use(run, act.behavior)
            return
        first = chosen_first(self.space, act)
        if first:  # from the memory as it was, as the behavior's graph chooses it
            param = namespace[CHOSEN] = self._value(act.param, namespace)
        for name, update in memory_updates(self.space, act.primitive):
            value = self._value(_substitute(update, "PARAM", CHOSEN if first else act.param),
                                namespace)
            run.variables[name] = namespace[name] = value
        if not first:
            param = self._value(act.param, namespace)
        try:
            action = self.interface.encode_action(act.primitive, param)
        except ValueError as exc:
            raise _Failed(f"{act.param}: {exc}") from None
        _, _, _, _, info = self.interface.step(action)
        run.history.append(info)
        if not info["certificate"]:
            raise _Failed(f"step {len(run.history)}: {act.primitive} {info['param']}: "
                          f"{info.get('reason', 'certificate failed')}")
        if len(run.history) >= self.max_steps:
            raise _Failed(f"truncated: step bound of {self.max_steps} primitives")
