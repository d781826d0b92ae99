"""The search's executor runs a program exactly as the behavior file it writes runs in the
package's runtime: the same steps, and success or failure on the same episodes (Hypothesis over
programs of the statement grammar, settings of the remembered cell ``mark`` and ends where a
guard holds among them); the places it remembers sensing from are those it sensed from."""

from __future__ import annotations

import gymnasium as gym
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from vlb_gym.abstractor.programs import Act, If, Loop, Program, Set, Stop
from vlb_gym.abstractor.search import Search
from vlb_gym.core.library import BehaviorLibrary, compile_spec
from vlb_gym.core.runtime import BehaviorPolicy
from vlb_gym.core.spec import Promise, spec_from_data
from vlb_gym.verify.episode import run_episode
from vlb_gym.wrappers.robustness import RobustnessWrapper

GRID_ID = "VLB-GridExplore-v0"
SENSE = Act("sense", "current_cell()")
TARGETS = ["current_cell()", "home", "frontier_cells()[0]", "explored()[-1]", "goal_cell()",
           "beside(current_cell(), 'right')", "[c for c in adjacent() if is_free(c)][0]",
           "path[-2]", "[c for c in adjacent(home) if c not in path][0]",
           "[c for c in explored() if c not in path][-1]",  # (these two read what they update)
           "mark", "beside(mark, 'up')",
           "[c for c in explored() if promised_at(c)][0]", "believed_goals()[-1]",
           "sensed_from[-2]", "sensed_from[(len(sensed_from) - 1) // 2]"]
MARKS = ["goal_cell()", "current_cell()", "frontier_cells()[0]", "path[-2]",
         "beside(current_cell(), 'left')", "beside(mark, 'right')"]
GUARDS = ["goal_found()", "not goal_found()", "len(explored()) < 12", "True",
          "is_free(beside(current_cell(), 'up'))", "len(path) < 4", "len(sensed_from) < 3",
          "len([c for c in explored() if label(c) == 'goal']) == 0", "home != current_cell()",
          "is_free(beside(current_cell(), 'right'))", "mark != current_cell()", "is_free(mark)",
          "len([c for c in frontier_cells() if c != mark]) > 0", "len(believed_goals()) > 0",
          "any(promised_at(c) for c in adjacent())"]
FUNCTIONS = {  # functions of the behavior, as the search names a promise's readings
    "believed_goals": ((), "[k for k in explored() if label(k) == 'goal']"),
    "promised_at": (("c",), "c != home and any(label(n) == 'goal' for n in adjacent(c)) "
                            "and c not in believed_goals()")}

acts = st.one_of(st.just(SENSE), st.sampled_from(TARGETS).map(lambda t: Act("navigate", t)))
bodies = st.lists(acts, min_size=1, max_size=3).map(tuple)
statements = st.one_of(
    acts,
    st.builds(If, st.sampled_from(GUARDS), bodies.filter(lambda b: len(b) <= 2)),
    st.builds(Loop, st.sampled_from(GUARDS), bodies, st.one_of(st.none(),
                                                                st.integers(1, 3))),
    st.builds(Set, st.just("mark"), st.sampled_from(MARKS)),
    st.builds(Stop, st.sampled_from(GUARDS)))
programs = st.builds(lambda first, rest: Program((first, *rest)), acts,
                     st.lists(statements, max_size=4))
ANYTHING = Promise(expr="len(primitives()) >= 0")


def runtime_steps(document, seed):
    env = RobustnessWrapper(gym.make(GRID_ID))
    try:
        spec = spec_from_data(document, "<program>")
        compiled = compile_spec(spec, env, "<program>", None, BehaviorLibrary(shipped=False),
                                names_only=True)
        result = run_episode(env, BehaviorPolicy(compiled, env.unwrapped), seed, 0)
    finally:
        env.close()
    return result.success, [(s["primitive"], tuple(s["param"])) for s in result.steps]


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs, st.integers(0, 2**32 - 1))
@example(Program((SENSE, Set("mark", "frontier_cells()[0]"), Set("mark", "beside(mark, 'right')"),
                  Act("navigate", "mark"))), 0)  # a setting that reads the one before it
@example(Program((SENSE, Loop("not goal_found()", (Act("navigate", "frontier_cells()[0]"), SENSE)),
                  Set("mark", "current_cell()"), Stop("mark == home"),
                  Act("navigate", "home"))), 3)  # an end that reads a setting before it
@example(Program((SENSE, Loop("not goal_found()", (Act("navigate", "frontier_cells()[0]"), SENSE)),
                  Act("navigate", "[c for c in explored() if promised_at(c)][0]"))), 5)
# (a function of the behavior calling another)
@example(Program((SENSE, Loop("not goal_found()", (Act("navigate", "frontier_cells()[0]"), SENSE)),
                  Act("navigate", "[c for c in believed_goals() if c not in path][0]"))), 5)
# (a parameter chosen before two memories it is added to, path and after_goal, are updated)
def test_the_executor_and_the_runtime_agree(program, seed):
    search = Search(GRID_ID, ANYTHING, screen_seed=1)
    search.executor.max_steps = 500  # the env's own bound, as the runtime has it
    for name, (args, text) in FUNCTIONS.items():
        assert search._name(name, args, text, bool(args), [])
    try:
        run = search._run(seed, program.statements)
        held = search.executor.judge(run) is None
        document = program.document(search.space, "p", "", GRID_ID, search.functions)
        document["promise"] = ANYTHING.model_dump()
        success, steps = runtime_steps(document, seed)
    finally:
        search.close()
    if not held and run.reason.startswith("mark = "):  # a setting that cannot be evaluated
        assert list(run.trace) == steps[:len(run.trace)]  # fails the run at once, where the
        return  # runtime fails only if it acts again: the executor is the stricter
    assert held == success, (program.words(), run.reason)
    if success:
        assert [(p, tuple(c)) for p, c in run.trace] == steps
        assert run.variables["sensed_from"] == [c for p, c in run.trace if p == "sense"]
    else:  # a loop that repeats itself is failed by the executor before the step bound
        assert list(run.trace) == steps[:len(run.trace)]
