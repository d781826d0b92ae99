"""The budget hierarchy: an evaluation, a step (every evaluation that chooses one action), an
episode and a dry run (its episodes together) each have a work budget of their own, so the worst
behavior file the schema admits (1,024 edges, each guard costing about half an evaluation's
budget) ends its episode after a bounded amount of work, whatever it does."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vlb_gym.core import budget
from vlb_gym.core.library import load_behavior
from vlb_gym.verify.episode import run_episode

from .conftest import explore_doc

#: about 4.7e5 work units per call (500 items, each a 50-item sum), half an evaluation's budget
HEAVY = {"args": ["x"], "expr": "sum([sum([x * j for j in [1] * 50]) for i in [0] * 500])"}


def charged(policy) -> tuple[int, int]:
    account = policy._budget
    return account.step, account.episode


def worst_file(edges: int = 1024) -> dict:
    """The schema's most edges, all but one from the start node, each guard a heavy call."""
    doc = explore_doc(functions={**explore_doc()["functions"], "heavy": HEAVY})
    heavy = [{"from": "sense", "to": "go", "guard": f"heavy({k}) < 0",
              "param": "most_unexplored_neighbours()"} for k in range(edges - 2)]
    doc["edges"] = heavy + doc["edges"]
    return doc


def test_one_heavy_guard_fits_an_evaluation(grid_env, write_behavior):
    doc = explore_doc(functions={**explore_doc()["functions"], "heavy": HEAVY})
    doc["edges"][0]["guard"] = "heavy(1) >= 0 and not goal_found()"
    policy = load_behavior(str(write_behavior(doc)), grid_env)
    result = run_episode(grid_env, policy, seed=0)
    assert result.rho == 1  # within every budget: the behavior works
    _, episode = charged(policy)
    assert result.primitives * budget.MAX_WORK / 8 < episode < budget.MAX_EPISODE_WORK


def test_the_worst_file_ends_its_first_step_after_a_bounded_amount_of_work(grid_env,
                                                                            write_behavior):
    doc = worst_file()
    assert len(doc["edges"]) == 1024
    policy = load_behavior(str(write_behavior(doc)), grid_env)
    result = run_episode(grid_env, policy, seed=0)
    assert result.rho == -1 and result.cause == "evaluation budget exceeded"
    assert "the evaluations of one step exceeded their budget" in result.reason
    assert result.primitives == 1  # the first step's guards, no further
    step, episode = charged(policy)
    assert step <= budget.MAX_STEP_WORK + budget.MAX_WORK  # at most one evaluation beyond


def test_an_episode_of_heavy_steps_ends_on_the_episode_budget(grid_env, write_behavior):
    """Each step costs about 5 heavy guards (half the step budget), and the behavior never
    finishes: the episode budget ends it long before the step bound."""
    doc = worst_file(8)
    doc["edges"][-1]["guard"] = "True"  # go -> sense forever; sense's last edge: always
    doc["edges"][-2]["guard"] = "True"
    doc["terminals"] = ["go"]  # whose edge back to sense always holds: it never finishes
    policy = load_behavior(str(write_behavior(doc)), grid_env)
    result = run_episode(grid_env, policy, seed=0)
    assert result.rho == -1 and "evaluations of one episode exceeded" in result.reason
    steps_per_budget = budget.MAX_EPISODE_WORK // budget.MAX_STEP_WORK
    assert steps_per_budget <= result.primitives < 8 * steps_per_budget
    _, episode = charged(policy)
    assert episode <= budget.MAX_EPISODE_WORK + budget.MAX_WORK


@pytest.mark.parametrize("shipped", ["explore_until_goal", "find_goal_and_oscillate"])
def test_the_shipped_behaviors_use_a_sliver_of_every_budget(shipped, grid_env):
    policy = load_behavior(shipped, grid_env)
    for seed in range(20):
        assert run_episode(grid_env, policy, seed=seed).rho == 1
        step, episode = charged(policy)
        assert episode < budget.MAX_EPISODE_WORK / 100


def test_a_dry_run_has_one_episode_budget_for_all_its_episodes(grid_env, write_behavior):
    """A model's reply whose episodes each stay just within the episode budget: the dry run
    stops after two of them (the layer's own budget), not after all its seeds."""
    from vlb_gym.abstractor import validate
    from vlb_gym.core.spec import BehaviorSpecError

    doc = worst_file(5)  # three heavy guards a step: about 1.4e6 units, within a step's 5e6
    doc["edges"][-1]["guard"] = doc["edges"][-2]["guard"] = "True"
    doc["terminals"] = ["go"]
    policy = load_behavior(str(write_behavior(doc)), grid_env)
    with pytest.raises(BehaviorSpecError, match="used more than 100000000 work units together"):
        validate.dry_run(policy.behavior, grid_env, seeds=(0, 1, 2, 3, 4, 5), steps=50)


def _counted(value) -> int:
    """Elements of nested lists and tuples and characters of strings, counted recursively."""
    if isinstance(value, str):
        return len(value)
    if isinstance(value, (list, tuple)):
        return len(value) + sum(_counted(v) - (not isinstance(v, (list, tuple, str)))
                                for v in value)
    return 1


_LEAVES = st.one_of(st.integers(), st.text(max_size=4), st.none(), st.booleans())
_NESTED = st.recursive(_LEAVES, lambda inner: st.one_of(
    st.lists(inner, max_size=24), st.lists(inner, max_size=24).map(tuple),
    st.lists(st.tuples(st.integers(), st.integers()), min_size=9, max_size=40)),
    max_leaves=150)


@settings(max_examples=400, deadline=None)
@given(value=_NESTED, limit=st.integers(1, 400))
def test_a_value_is_sized_by_its_elements_up_to_the_limit(value, limit):
    """What a comparison is charged: the elements counted one by one (nested lists of cells
    too); past the limit the count only says so."""
    size, counted = budget._size(value, limit), _counted(value)
    assert size == counted if counted <= limit else size > limit


def test_a_list_sharing_one_long_tuple_is_sized_past_the_limit_without_walking_it():
    """10,000 references to one 10,000-element tuple (10**8 elements, as an expression can build
    them cheaply) are sized by their lengths: past the limit at once, nothing flattened."""
    shared = tuple(range(10_000))
    assert budget._size([shared] * 10_000) > budget.MAX_WORK
    assert budget._size([shared] * 9) == 9 + 90_000
