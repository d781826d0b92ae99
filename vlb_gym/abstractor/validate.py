"""Layered validation of a model's reply, before anything is added to the library.

Layers, in order, each failing with a :class:`BehaviorSpecError` whose ``layer`` names it and whose
message is fed back to the model: ``json`` (the reply parses), ``schema`` (it is a behavior
document), ``references`` (ids unique; primitives, sub-behaviors, nodes, variables exist;
sub-behaviors are library behaviors named, never paths; the name is free), ``graph`` (every node
reachable from the start, a terminal from every node), ``expressions`` (whitelisted syntax and
names only), ``dry-run`` (a few sampled episodes run without a run-time error, each chosen
parameter inside its primitive's space; every evaluation runs under its work budget, so a hostile
reply fails this layer instead of hanging).
"""

from __future__ import annotations

import re

import gymnasium as gym

from vlb_gym.core.budget import MAX_EPISODE_WORK
from vlb_gym.core.compiler import CompiledBehavior
from vlb_gym.core.runtime import BehaviorPolicy
from vlb_gym.core.library import BehaviorLibrary, compile_spec
from vlb_gym.core.spec import BehaviorSpec, BehaviorSpecError, parse_spec
from vlb_gym.verify.episode import run_episode
from vlb_gym.wrappers.robustness import RobustnessWrapper

_FENCE = re.compile(r"^```(?:json)?\s*\n(.*)\n```$", re.DOTALL)
DRY_RUN_SEEDS = (0, 1, 2)
DRY_RUN_STEPS = 60


def parse_reply(reply: str, source: str) -> BehaviorSpec:
    """Layers json and schema; a single Markdown code fence around the document is tolerated."""
    text = reply.strip()
    fenced = _FENCE.match(text)
    return parse_spec(fenced.group(1) if fenced else text, source)


def dry_run(compiled: CompiledBehavior, env: gym.Env, seeds=DRY_RUN_SEEDS,
            steps: int = DRY_RUN_STEPS) -> None:
    """Layer dry-run: a few episodes of at most ``steps`` primitives, run as campaigns run them
    (:func:`~vlb_gym.verify.episode.run_episode`); an episode that raised (a behavior runtime
    error, an exceeded budget) fails the layer, a failed certificate or promise does not (it is
    the behavior's outcome, which verification judges). The episodes together have one
    episode's work budget (:data:`~vlb_gym.core.budget.MAX_EPISODE_WORK`): the layer stops
    after at most two episodes' work, whatever the reply."""
    robust = env if isinstance(env, RobustnessWrapper) else RobustnessWrapper(env)
    policy = BehaviorPolicy(compiled, env.unwrapped)
    used = 0
    for seed in seeds:
        result = run_episode(robust, policy, seed, stop_on_failure=False, max_primitives=steps)
        if result.error is not None:  # the exception itself, not an earlier failed certificate
            raise BehaviorSpecError(f"dry run from reset seed {seed}, before primitive "
                                    f"{result.primitives + 1}: "
                                    f"{result.error.strip().splitlines()[-1]}", "dry-run")
        used += policy.episode_work
        if used > MAX_EPISODE_WORK:  # the dry run's budget: one episode's, all seeds together
            raise BehaviorSpecError(f"dry run: its episodes used more than {MAX_EPISODE_WORK} "
                                    "work units together (one episode's budget)", "dry-run")


def validate_reply(reply: str, env: gym.Env, library: BehaviorLibrary, name: str | None = None,
                   source: str = "reply") -> CompiledBehavior:
    """All layers; ``name`` (if given) replaces the reply's own name. Returns the compiled
    behavior; raises :class:`BehaviorSpecError` at the first failing layer."""
    spec = parse_reply(reply, source)
    if name is not None:
        spec = spec.model_copy(update={"name": name})
    elif spec.name in library:
        raise BehaviorSpecError(f"{source}: name: {spec.name!r} is already in the behavior "
                                "library; choose a new name (vlb synthesize --name NEW saves "
                                "the reply under another)", "references")
    compiled = compile_spec(spec, env, source, None, library, names_only=True)
    dry_run(compiled, env)
    return compiled

