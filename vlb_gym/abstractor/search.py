"""Search the behavior language for a behavior that keeps a promise.

The space is every :class:`~vlb_gym.abstractor.programs.Program` of the env's primitives whose
expressions come from its typed vocabulary (:mod:`~vlb_gym.abstractor.terms`), the promise's
readings (:mod:`~vlb_gym.abstractor.beliefs`) and the request's constants; programs are built
statement by statement, cheapest first (best-first over prefixes, each prefix's children in
order of cost).

The search is *execution-guided*: a prefix is run once on the *probe* episodes (at first the
first :data:`PROBES` screening episodes), from its parent's saved states
(:mod:`~vlb_gym.abstractor.executor`). A prefix that fails one of them (a certificate, its own
logic, the step bound) is dropped with everything that would extend it; a prefix that acts on
those episodes exactly as one already seen (the same steps and memory: *observational
equivalence* of behaviors) or as its parent does, is counted once. Every prefix is also a whole
behavior: one whose promise holds on the probe episodes is screened on the rest (``screening``
episodes of a fresh root seed, stopped at the first failure), then re-run through the package's
own runtime.

The probes are *counterexample-guided*: where a whole behavior that kept the promise on every
probe fails on another screening episode, that episode joins the probes (up to
:data:`MAX_PROBES`) and the search starts again from the empty program. Observational
equivalence on a few episodes can hide what only rarer ones need (a goal right beside the start,
no corner reachable): a statement that acts on none of the probes is dropped as acting like its
parent, and the episode that tells them apart brings it back.

The search *learns which statements are useful* (:meth:`Search._learn`): a program that keeps
the promise on a set of probes no program before it kept it on all of lends its statements to
every later prefix, at :data:`USEFUL_DISCOUNT` of their cost.

A reading of the promise and a belief that would take comprehension loops inline become
functions of the behavior (``promised_at(c)``: "would the promise hold if I ended in c?";
``promised_after(c)``: "... if one more move took me to c and I stopped?", the memory that move
updates read as updated, so a parameter that calls it is chosen before the updates;
``believed_reachable_goals()``), declared in the file it writes: the expression language allows
three loops an expression, and seeking where a promise holds filters a list by such a reading.

:func:`witnesses` tries a promise on the env's least behaviors (stop at once, ...) first: a
promise one of them keeps asks for nothing more than it does.
"""

from __future__ import annotations

import ast
import heapq
import itertools
import re
import secrets
import time
from dataclasses import dataclass, field, replace
from typing import Any

from vlb_gym.core.expressions import BUILTINS, ExpressionError
from vlb_gym.core.library import BehaviorLibrary, compile_for, compile_spec
from vlb_gym.core.runtime import BehaviorPolicy
from vlb_gym.core.search_space import SearchSpace
from vlb_gym.core.spec import BehaviorSpecError, Promise, spec_from_data
from vlb_gym.envs.modules import make_primitive_env
from vlb_gym.verify.campaign import episode_seed
from vlb_gym.verify.episode import run_episode
from vlb_gym.wrappers.robustness import RobustnessWrapper

from .beliefs import _free_names, after_moving, literals, numbers, readings
from .executor import FAILED, OPEN, Executor, Run, _frozen
from .programs import MOVED, Act, Loop, Program, Set, Statement, Stop, _loops, acts, reads
from .statements import Statements
from .terms import (BOUND, Bank, Context, Vocabulary, call_name, conforms, contexts,
                    infer_kind)

PROBES = 4
MAX_PROBES = 8  # probes, counterexamples included
PROGRESS_WEIGHT = 4.0
STEP_WEIGHT = 0.05
LOOK_FURTHER = 0.5  # of the programs built before the first find, built after it
LOOK_FURTHER_MIN = 1000
LOOK_FURTHER_MIN_SECONDS = 10.0  # (a search bounded by time: see Search.find)
MAX_STATEMENTS = 4
MAX_LEVEL = 24
MAX_FAILURES_KEPT = 5
USEFUL = 0  # the heap's level of the useful statements (see Search._learn)
USEFUL_DISCOUNT = 0.5  # of a useful statement's cost, where later prefixes try it
MAX_USEFUL = 64


def fresh_seed() -> int:
    """A root seed from the operating system's entropy (what no run has looked at)."""
    return secrets.randbits(63)


MIN_SHARED = 8  # syntax nodes of a part a reading writes more than once, to be named once
MAX_ORDERS = 4  # lists of named values, in the orders a request names them, per helper


def said(text: str, synonyms: dict[str, str]) -> list[str]:
    """The words of ``text`` in order, lower case, each synonym read as the value it names."""
    return [synonyms.get(w, w) for w in re.findall(r"[a-z]+", text.lower())]


def named_from_here(vocabulary: Vocabulary, space: SearchSpace, phrases: list[list[str]]
                    ) -> list[tuple[str, str, int]]:
    """Fragments (kind, text, depth 0) for what the request names as seen from here: a helper
    of where the agent is and one value the request or promise names (``beside(current_cell(),
    'right')`` where "right" is named), one name to the search, as the request says it; and
    where a phrase (the whole request and promise, then each sentence) names two or more,
    those the agent can move onto in the order the phrase names them: ``[c for c in
    [beside(current_cell(), 'up'), beside(current_cell(), 'right')] if is_free(c)]``, whose
    first is "up, or else right" (at most ``MAX_ORDERS`` orders)."""
    if space.here is None:
        return []
    here_kind, here = space.here
    words = {w for phrase in phrases for w in phrase}
    out = []
    for name, (kinds, result) in vocabulary.helpers.items():
        if len(kinds) == 2 and kinds[0] == here_kind and kinds[1].startswith("str:"):
            values = kinds[1][4:].split("|")
            place = {v: f"{call_name(name)}({here}, {v!r})" for v in values if v in words}
            out += [(result, text, 0) for text in place.values()]
            feasible = next((p.feasible for p in space.parameters
                             if p.kind == result and p.feasible), None)
            if feasible is None:
                continue
            orders = dict.fromkeys(tuple(dict.fromkeys(w for w in phrase if w in values))
                                   for phrase in phrases)
            var = BOUND[0]
            for order in [o for o in orders if len(o) > 1][:MAX_ORDERS]:
                places = ", ".join(place[v] for v in order)
                out.append((f"list[{result}]",
                            f"[{var} for {var} in [{places}] if {feasible.format(var)}]", 0))
    return out


@dataclass
class Found:
    """A program that kept the promise on every screening episode (not yet certified)."""

    program: Program
    cost: int


@dataclass
class Tally:
    """What a search did: programs built, those judged whole, distinct behaviors, statements
    run, and seconds."""

    built: int = 0
    judged: int = 0
    distinct: int = 0
    executed: int = 0
    seconds: float = 0.0
    failures: list[tuple[str, str]] = field(default_factory=list)

    @property
    def rate(self) -> float:
        """Programs built per second."""
        return self.built / self.seconds if self.seconds else 0.0


@dataclass
class _Node:
    program: tuple[Statement, ...]
    cost: int
    runs: list[Run]
    progress: float = 0.0  # how close it comes to the promise on the probes, in [0, 1]
    costs: tuple[int, ...] = ()  # each statement's
    tried: set[Statement] = field(default_factory=set)  # the statements it was extended by

    @property
    def steps(self) -> float:
        """The primitives it runs per probe episode, on average."""
        return sum(len(r.history) for r in self.runs) / max(len(self.runs), 1)

    def priority(self, level: int) -> float:
        """The order of this node's children of statement cost ``level``: their cost, less
        :data:`PROGRESS_WEIGHT` times how close their parent comes to the promise, plus
        :data:`STEP_WEIGHT` per primitive it runs (a behavior that does less comes first)."""
        return self.cost + level - PROGRESS_WEIGHT * self.progress + STEP_WEIGHT * self.steps


class Search:
    """The search for one promise on one env (see the module's docstring). ``screen_seed`` is
    the root seed of the screening episodes (default: a fresh one); programs may run the
    behaviors of ``library`` written for the env, but the one called ``name`` (what is being
    synthesized is never answered by its own name)."""

    def __init__(self, env_id: str, promise: Promise, request: str = "",
                 env_kwargs: dict[str, Any] | None = None, screen_seed: int | None = None,
                 cheap: frozenset[str] = frozenset(), library: BehaviorLibrary | None = None,
                 name: str | None = None):
        self.env_id = env_id
        self.promise = promise
        self.request = request
        self.env_kwargs = dict(env_kwargs or {})
        self.env = make_primitive_env(env_id, self.env_kwargs)
        self.interface = self.env.unwrapped
        space = self.interface.search_space()
        if space is None:
            raise ValueError(f"{env_id} declares no search space")
        self.space: SearchSpace = space
        self.screen_seed = fresh_seed() if screen_seed is None else screen_seed
        self.seeds = [episode_seed(self.screen_seed, i) for i in range(space.screening)]
        self.probes = self.seeds[:PROBES]  # grows by counterexamples (see the module's docstring)
        self._counterexample: int | None = None
        bounds = [self.env.spec.max_episode_steps if self.env.spec else None, space.max_steps]
        self.library = library
        self.name = name
        self.executor = Executor(self.interface, space, promise,
                                 min([b for b in bounds if b] or [10_000]), self._behaviors())
        self.tally = Tally()
        self._settable = {m.name for m in space.memory if m.settable}
        self._cheap = cheap
        self._statements: Statements | None = None
        self.functions: dict[str, tuple[tuple[str, ...], str]] = {}  # what programs may call
        self._shared: dict[str, str | None] = {}  # a part readings repeat -> its function
        self._useful: list[tuple[Statement, int]] = []  # statements (and their costs) of
        # programs that newly kept the promise on a set of probes, and those sets:
        self._covered: list[frozenset[int]] = []

    def close(self) -> None:
        self.env.close()

    def _behaviors(self) -> dict[str, Any]:
        """The library's behaviors written for this env that compile, by name (none without a
        library)."""
        if self.library is None:
            return {}
        out = {}
        specs, _ = self.library.load_all()
        for name, spec in specs.items():
            if spec.env != self.env_id or name == self.name:
                continue
            try:
                out[name] = compile_for(name, self.env, self.library)
            except (BehaviorSpecError, OSError):
                continue
        return out

    # -- the vocabulary ----------------------------------------------------------------------
    def statements(self) -> Statements:
        """The grammar's statements for this promise and request (built once)."""
        if self._statements is None:
            self._statements = self._grammar()
        return self._statements

    def _grammar(self) -> Statements:
        space, interface = self.space, self.interface
        helpers = interface.make_helpers()
        vocabulary = Vocabulary.of(helpers, space)
        found = contexts(interface, space, self.seeds[:6])
        counts = numbers(self.request, self.promise.expr, self.promise.description)
        limits = sorted({*range(1, 4), *counts, *(k - 1 for k in counts)} - {0})
        for k in counts:
            vocabulary.constants.append(("int", str(k)))
        for value in literals(self.promise.expr):
            for kind in [*space.types, *(f"list[{k}]" for k in space.types)]:
                if conforms(value, kind, space.types):
                    vocabulary.constants.append((kind, repr(value)))
        phrases = [said(self.request + " " + self.promise.expr, space.synonyms)] + [
            said(sentence, space.synonyms) for sentence in re.split(r"[.;:!?]", self.request)]
        words = set(phrases[0])
        cheap = {text for _, text in vocabulary.constants if text.strip("'") in words}
        cheap |= {call_name(n) for n in vocabulary.helpers  # named in the request's words
                  if any(len(w) >= 4 and w in words for w in call_name(n).split("_"))}
        cheap |= {call_name(n) for n, (kinds, _) in vocabulary.helpers.items()  # or one of the
                  if any(k.startswith("str:") and words & set(k[4:].split("|"))  # values it
                         for k in kinds)}  # takes ("right": the cell beside, in a direction)
        vocabulary.fragments += named_from_here(vocabulary, space, phrases)
        outcome = set(interface.make_judge().functions())
        binders = tuple(k for k in space.types)[:1] * 2
        believed = replace(space, beliefs=self._believed(found))
        decision = {call_name(n) for n in vocabulary.helpers} | set(self.functions)
        known = decision | set(BUILTINS) | {m.name for m in space.memory}
        for text, bound in readings(self.promise.expr, believed, outcome, decision,
                                    each=vocabulary.each):
            text = self._factored(text, known, found)
            kind = infer_kind(text, found, space.types, binders[0] if bound and binders else None,
                              vocabulary)
            if kind == "bool" and bound and _loops(ast.parse(text, mode="eval")):
                text = self._name_condition(text, found) or text
            if kind is not None:
                vocabulary.fragments.append((kind, text, 1 if bound else 0))
                cheap |= {call_name(n) for n in vocabulary.helpers if f"{call_name(n)}(" in text}
        for text in after_moving(self.promise.expr, believed, outcome, decision, BOUND[0]):
            named = self._name_condition(self._factored(text, known, found), found, MOVED)
            if named is not None:
                vocabulary.fragments.append(("bool", named, 1))
        vocabulary.constants = list(dict.fromkeys(vocabulary.constants))
        vocabulary.cheap = frozenset(cheap | self._cheap | set(space.common))
        space = self._narrowed(vocabulary)
        vocabulary.variables = {m.name: m.kind for m in space.memory}
        bank = Bank(vocabulary, found).build(binders)
        return Statements(bank, space, limits, list(self.executor.behaviors))

    def _narrowed(self, vocabulary: Vocabulary) -> SearchSpace:
        """The search's space narrowed to the memory the env declares ``common`` and that the
        promise's readings (and the functions they call) read, with what their updates and
        initial values read: other memory is neither a term nor kept by the behaviors run and
        written (what the promise does not speak of costs nothing)."""
        read = " ".join([*(text for _, text, _ in vocabulary.fragments),
                         *(text for _, text in self.functions.values()), *self.space.common])
        kept = self.space.memory_read(read)
        self.space = self.executor.space = replace(
            self.space, memory=tuple(m for m in self.space.memory if m.name in kept))
        return self.space

    def _name(self, name: str, args: tuple[str, ...], text: str, condition: bool,
              found: list[Context]) -> bool:
        """Make ``text`` a function of the behavior called ``name`` (on the decision contexts
        too); False where the language refuses ``text``."""
        try:
            self.executor.define(name, args, text, condition)
        except ExpressionError:
            return False
        self.functions[name] = (args, text)
        code = compile(text, name, "eval")
        for context in found:
            context.namespace[name] = _function(code, args, context.namespace)
        return True

    def _factored(self, text: str, known: set[str], found: list[Context]) -> str:
        """``text`` with each part it writes more than once (of at least :data:`MIN_SHARED`
        syntax nodes, of ``known`` names only; the largest first) a call of a function of the
        behavior of no argument, ``shared1()``, computed once an evaluation: a promise's "let"
        (``for G in [X]``), read inline, writes ``X`` wherever ``G`` was, and a reading that
        writes it often is past the language's size bound."""
        while True:
            tree = ast.parse(text, mode="eval")
            seen: dict[str, list[int]] = {}  # part -> [times written, syntax nodes]
            for node in ast.walk(tree.body):
                if isinstance(node, ast.expr) and not isinstance(node, (ast.Name, ast.Constant)) \
                        and _free_names(node) <= known:
                    part = ast.unparse(node)
                    seen.setdefault(part, [0, sum(1 for _ in ast.walk(node))])[0] += 1
            parts = sorted((p for p, (times, size) in seen.items()
                            if times > 1 and size >= MIN_SHARED), key=lambda p: -seen[p][1])
            for part in parts:
                if part not in self._shared:
                    name = f"shared{sum(v is not None for v in self._shared.values()) + 1}"
                    self._shared[part] = name if self._name(name, (), part, False, found) \
                        else None
                if self._shared[part] is not None:
                    text = ast.unparse(_Calling(part, self._shared[part]).visit(tree))
                    break
            else:
                return text

    def _believed(self, found: list[Context]) -> dict[str, str]:
        """The env's beliefs, each that is a comprehension of no argument (``reachable_goals()``
        believed to be ``[k for k in explored() if label(k) == 'goal']``) a function of the
        behavior, ``believed_reachable_goals()``: read inline, a promise's use of it takes a
        comprehension loop of the language's three."""
        beliefs = dict(self.space.beliefs)
        for outcome, belief in self.space.beliefs.items():
            if "{" not in belief and _loops(ast.parse(belief, mode="eval")) \
                    and self._name(f"believed_{outcome}", (), belief, False, found):
                beliefs[outcome] = f"believed_{outcome}()"
        return beliefs

    def _name_condition(self, text: str, found: list[Context], prefix: str = "promised_at"
                        ) -> str | None:
        """A call of a function of the behavior (named ``prefix``, numbered) that holds where
        the promise's reading ``text`` of the bound cell does (None where the language refuses
        it): the place the promise would hold at is sought by filtering a list by it, and the
        reading alone may use up the expression language's comprehension loops."""
        taken = sum(re.fullmatch(rf"{prefix}\d*", name) is not None for name in self.functions)
        name = f"{prefix}{taken + 1 if taken else ''}"
        return f"{name}({BOUND[0]})" if self._name(name, (BOUND[0],), text, True, found) else None

    def learn(self, seeds: list[int]) -> None:
        """Screen every later program on the episodes of ``seeds`` too, as probes while there
        are fewer than :data:`MAX_PROBES`: episodes a found behavior failed in a certification
        campaign (the next campaign runs on fresh seeds, so what it certifies is not tested on
        what chose it)."""
        for seed in seeds:
            if seed not in self.seeds:
                self.seeds.append(seed)
            if seed not in self.probes and len(self.probes) < MAX_PROBES:
                self.probes.append(seed)

    # -- least behaviors -----------------------------------------------------------------------
    def witnesses(self) -> list[str]:
        """The words of the env's least behaviors that keep the promise on every screening
        episode (of one done over and over, the fewest times that keep it)."""
        keeping = []
        for witness in self.space.witnesses:
            for words, steps in witness.repeated():
                if all(self._keeps(seed, steps) for seed in self.seeds):
                    keeping.append(words)
                    break
        return keeping

    def keeps(self, program: Program) -> bool:
        """Whether ``program`` keeps this search's promise on every screening episode."""
        return all(self.executor.judge(self._run(seed, program.statements)) is None
                   for seed in self.seeds)

    def grade(self, program: Program) -> tuple[bool, float]:
        """Whether ``program`` keeps this search's promise on every screening episode, and how
        close it comes on them (the mean of the promise's closeness, 1 where it holds)."""
        keeps, close = True, 0.0
        for seed in self.seeds:
            run = self._run(seed, program.statements)
            if self.executor.judge(run) is None:
                close += 1.0
            else:
                keeps = False
                close += self.executor.progress(run)
        return keeps, close / len(self.seeds)

    def overrun(self, program: Program) -> str | None:
        """The words of a least behavior (one that acts) which, run after ``program``, still
        keeps the promise on every screening episode: then the promise does not say when to
        stop. None if there is none."""
        for witness in self.space.witnesses:
            if witness.steps and self.keeps(Program(program.statements + tuple(
                    Act(p, text) for p, text in witness.steps))):
                return witness.words
        return None

    def _run(self, seed: int, statements: tuple[Statement, ...]) -> Run:
        """``statements`` run from the reset of ``seed``."""
        run = self.executor.start(seed, statements[0])
        for k, statement in enumerate(statements[1:], 1):
            if run.status == OPEN:
                run = self.executor.extend(run, statement, k)
        return run

    def _keeps(self, seed: int, steps: tuple[tuple[str, str], ...]) -> bool:
        if not steps:
            observation, info = self.interface.reset(seed=seed)
            run = Run(seed, self.interface.save(), dict(info), {})
        else:
            run = self._run(seed, tuple(Act(p, text) for p, text in steps))
        return self.executor.judge(run) is None

    # -- the search ----------------------------------------------------------------------------
    def find(self, time_limit: float = 120.0, max_programs: int | None = None,
             skip: frozenset[str] = frozenset()) -> Found | None:
        """The least program (skipping those whose words are in ``skip``) that keeps the
        promise on every screening episode, or None within ``time_limit`` seconds or
        ``max_programs`` programs built. Once one is found, the search goes on for
        :data:`LOOK_FURTHER` of the programs built so far (at least :data:`LOOK_FURTHER_MIN`)
        and, in a search bounded by time alone, for at most :data:`LOOK_FURTHER` of its seconds
        so far (at least :data:`LOOK_FURTHER_MIN_SECONDS`: where a program takes seconds to
        screen, as the scoop's do, a thousand would take the whole limit): of those found,
        the one that runs the fewest primitives on the screening episodes is kept (a promise
        seldom asks for more than it says: not "explore everything" where "explore until a
        goal is known" keeps it), the cheapest on a tie."""
        started = time.perf_counter()
        statements = self.statements()
        completions = statements.completions()
        order = itertools.count()
        def root() -> list[tuple[float, int, _Node, int, int]]:
            return [(1, next(order), _Node((), 0, []), 1, 0)]

        heap = root()
        seen: set[Any] = set()
        best: tuple[int, int, Found] | None = None
        until: int | None = None  # programs built when the search stops looking further
        deadline = started + time_limit  # (moved up once one is found, where time bounds it)
        try:
            while heap:
                if self._counterexample is not None:  # a new probe: begin again
                    self.probes.append(self._counterexample)
                    self._counterexample = None
                    heap, seen = root(), set()
                if time.perf_counter() > deadline or (
                        max_programs is not None and self.tally.built >= max_programs) or (
                        until is not None and self.tally.built >= until):
                    break
                priority, _, node, level, index = heapq.heappop(heap)
                if level == USEFUL:
                    self._push_useful(heap, order, node, index + 1)
                    statement, cost = self._useful[index]
                else:
                    items = statements.firsts(level) if not node.program else \
                        statements.at(level)
                    if index + 1 < len(items):
                        heapq.heappush(heap, (priority, next(order), node, level, index + 1))
                    if index == 0 and level < MAX_LEVEL:
                        heapq.heappush(heap, (node.priority(level + 1), next(order), node,
                                              level + 1, 0))
                    if index >= len(items):
                        continue
                    statement, cost = items[index], level
                if statement in node.tried:  # (a useful statement or a completion, tried at its
                    # own cost too)
                    continue
                node.tried.add(statement)
                child = self._child(node, statement, node.cost + cost, seen)
                if child is None:
                    continue
                grown = [child]
                if acts(child.program) < MAX_STATEMENTS and any(
                        r.status == OPEN for r in child.runs):
                    heapq.heappush(heap, (child.priority(1), next(order), child, 1, 0))
                    self._push_useful(heap, order, child, 0)
                    for act in completions if child.program else ():
                        if max_programs is not None and self.tally.built >= max_programs:
                            break
                        child.tried.add(act)
                        done = self._child(child, act, child.cost + 1, seen)
                        if done is not None:
                            grown.append(done)
                for candidate in grown:
                    steps = self._accept(candidate, skip)
                    if steps is None:
                        continue
                    if best is None or (steps, candidate.cost) < best[:2]:
                        best = (steps, candidate.cost, Found(Program(candidate.program),
                                                             candidate.cost))
                    if until is None:
                        built = self.tally.built
                        until = built + max(LOOK_FURTHER_MIN, int(built * LOOK_FURTHER))
                        if max_programs is None:
                            now = time.perf_counter()
                            deadline = min(deadline, now + max(
                                LOOK_FURTHER_MIN_SECONDS, (now - started) * LOOK_FURTHER))
        finally:
            self.tally.seconds += time.perf_counter() - started
            self.tally.executed = self.executor.executed
        return None if best is None else best[2]

    def _accept(self, node: _Node, skip: frozenset[str]) -> int | None:
        """The primitives ``node``'s program runs on the screening episodes if it keeps the
        promise on every one, else None (one that ends with a :class:`Stop` is its parent
        again)."""
        if node.progress < 1.0 or isinstance(node.program[-1], Stop) or \
                Program(node.program).words() in skip:
            return None
        return self._whole(node)

    def _child(self, node: _Node, statement: Statement, cost: int, seen: set[Any]
               ) -> _Node | None:
        """``node`` extended by ``statement``, run on the probe episodes; None if it fails
        one of them, or acts as its parent or as a program already seen, or is a setting
        anywhere but right after a loop (what held when it ended: where a program has
        something to remember that no memory holds) or a program's second, or reads a
        settable variable the program has not set (it would read its initial value)."""
        unset = self._settable.difference(s.name for s in node.program if isinstance(s, Set))
        if isinstance(statement, Set):
            if not (node.program and isinstance(node.program[-1], Loop)
                    and len(unset) == len(self._settable)):
                return None
        elif unset and reads(statement, frozenset(unset)):
            return None
        self.tally.built += 1
        index = len(node.program)
        runs = []
        for e, seed in enumerate(self.probes):
            if not node.program:
                run = self.executor.start(seed, statement)
            else:
                parent = node.runs[e]
                run = parent if parent.status != OPEN else \
                    self.executor.extend(parent, statement, index)
            if run.status == FAILED:
                return None
            runs.append(run)
        key = hash(tuple(r.key() for r in runs))  # (a hash: seen holds many)
        if node.program and key == hash(tuple(r.key() for r in node.runs)) or key in seen:
            return None
        seen.add(key)
        self.tally.distinct += 1
        closeness = [self.executor.progress(r) for r in runs]
        program, costs = (*node.program, statement), (*node.costs, cost - node.cost)
        self._learn(program, costs, frozenset(e for e, c in enumerate(closeness) if c >= 1.0))
        return _Node(program, cost, runs, sum(closeness) / len(runs), costs)

    def _push_useful(self, heap: list[Any], order: Any, node: _Node, index: int) -> None:
        """Queue ``node``'s child by useful statement ``index`` (if there is one yet), at
        :data:`USEFUL_DISCOUNT` of the statement's cost."""
        if index < len(self._useful):
            level = max(1, int(self._useful[index][1] * USEFUL_DISCOUNT))
            heapq.heappush(heap, (node.priority(level), next(order), node, USEFUL, index))

    def _learn(self, program: tuple[Statement, ...], costs: tuple[int, ...],
               kept: frozenset[int]) -> None:
        """Where ``program`` keeps the promise on the probes ``kept``, a set no program before
        it kept it on all of, its statements after the first become *useful* (at most
        :data:`MAX_USEFUL`): every later prefix tries them at :data:`USEFUL_DISCOUNT` of their
        cost, their programs keeping the whole (just-in-time learning, as Probe's bottom-up search learns from partial solutions: a
        behavior that does the task where the first look is clear, and one that stops where
        it is not, share their statements with each other's prefixes)."""
        if not kept or any(kept <= covered for covered in self._covered):
            return
        self._covered.append(kept)
        known = {statement for statement, _ in self._useful}
        for statement, cost in zip(program[1:], costs[1:]):
            if statement not in known and len(self._useful) < MAX_USEFUL:
                self._useful.append((statement, cost))

    def _whole(self, node: _Node) -> int | None:
        """The primitives ``node``'s program, ending there, runs on the screening episodes if
        it keeps the promise on every one (the probes' runs were judged; the rest run from
        their resets), else None; the first episode it fails on becomes a probe while there
        are fewer than :data:`MAX_PROBES`."""
        self.tally.judged += 1
        steps = sum(len(r.history) for r in node.runs)
        probes = set(self.probes)
        for seed in self.seeds:
            if seed in probes:
                continue
            run = self._run(seed, node.program)
            why = self.executor.judge(run)
            if why is not None:
                self._note(node, why)
                if len(self.probes) < MAX_PROBES and self._counterexample is None:
                    self._counterexample = seed
                return None
            steps += len(run.history)
        return steps

    def _note(self, node: _Node, why: str) -> None:
        if len(self.tally.failures) < MAX_FAILURES_KEPT:
            self.tally.failures.append((Program(node.program).words(), why))

    # -- through the runtime ---------------------------------------------------------------
    def document(self, found: Found, name: str, description: str) -> dict[str, Any]:
        """The behavior file of ``found`` with the promise attached."""
        document = found.program.document(self.space, name, description, self.env_id,
                                          self.functions)
        return {**document, "promise": self.promise.model_dump(exclude_defaults=True)}

    def rescreen(self, document: dict[str, Any],
                 library: BehaviorLibrary | None = None) -> str | None:
        """None if ``document`` keeps everything on every screening episode when run by the
        package's own runtime, else why not (what the search ran must be what runs)."""
        env = RobustnessWrapper(make_primitive_env(self.env_id, self.env_kwargs))
        try:
            spec = spec_from_data(document, "<found>")
            compiled = compile_spec(spec, env, "<found>", None,
                                    library or self.library or BehaviorLibrary(shipped=False),
                                    names_only=True)
            policy = BehaviorPolicy(compiled, env.unwrapped)
            for index, seed in enumerate(self.seeds):
                result = run_episode(env, policy, seed, index)
                if not result.success:
                    return result.reason or "rho_B = -1"
        except BehaviorSpecError as exc:
            return str(exc)
        finally:
            env.close()
        return None


class _Calling(ast.NodeTransformer):
    """Every expression written as ``part`` replaced by a call of ``name`` (no argument)."""

    def __init__(self, part: str, name: str):
        self.part, self.name = part, name

    def visit(self, node: ast.AST) -> ast.AST:
        if isinstance(node, ast.expr) and not isinstance(node, ast.Name) \
                and ast.unparse(node) == self.part:
            return ast.Call(ast.Name(self.name, ast.Load()), [], [])
        return self.generic_visit(node)


def _function(code: Any, args: tuple[str, ...], namespace: dict[str, Any]) -> Any:
    """The function of ``args`` whose value is ``code``'s in a decision context's
    ``namespace``, each value computed once (nothing in a context changes)."""
    values: dict[tuple[Any, ...], Any] = {}

    def value(*given: Any) -> Any:
        key = tuple(_frozen(v) for v in given)
        if key not in values:
            try:
                values[key] = eval(code, {**namespace, **dict(zip(args, given))})  # noqa: S307
            except Exception as exc:  # noqa: BLE001 - the reading's own failure, every time
                values[key] = exc
        found = values[key]
        if isinstance(found, Exception):
            raise found
        return found
    return value
