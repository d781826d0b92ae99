"""``vlb behaviors`` and ``vlb schema``: the behavior library and its file format."""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING

import gymnasium as gym

import vlb_gym

from .common import UsageError, add_env_module, check_env, env_modules

if TYPE_CHECKING:
    from vlb_gym.core.compiler import CompiledBehavior


def cmd_behaviors(args: argparse.Namespace) -> int:
    from vlb_gym.core.library import BehaviorLibrary, compile_spec, shipped_behaviors, spec_json

    library = BehaviorLibrary()
    if args.name is None:
        names, shipped = library.names(), set(shipped_behaviors())
        width = max(map(len, names), default=0)
        for name in names:  # a user's behavior never shadows a shipped one (save refuses it)
            where = "shipped" if name in shipped else f"yours: {library.directory / name}.json"
            print(f"{name:<{width}}  {where}")
        return 0
    spec, source, base_dir = library.resolve(args.name)
    env_id = args.env_id or spec.env
    if env_id is None:
        raise UsageError(f"{args.name}: the behavior names no env; give one with --env "
                         f"({', '.join(vlb_gym.ENV_IDS)})")
    check_env(env_id, {}, env_modules(args.env_module))
    env = gym.make(env_id)
    try:
        compiled = compile_spec(spec, env, source, base_dir, library)
    finally:
        env.close()
    if args.json:
        print(spec_json(compiled.spec), end="")  # as a behavior file is written
        return 0
    print(graph_text(compiled))
    return 0


def graph_text(compiled: CompiledBehavior) -> str:
    """The nodes and edges of a compiled behavior, one per line."""
    from vlb_gym.core.promise import words

    lines = [f"{compiled.name}: {compiled.spec.description}"]
    promise = compiled.spec.promise
    if promise is not None:
        said = words(promise.description or promise.expr, promise.as_soon_as)
        lines.append(f"  promise: {said}"
                     + (f"\n    judged as: {promise.expr}" if promise.description else ""))
    certificate = compiled.spec.certificate
    if certificate is not None:
        from vlb_gym.verify.bounds import floor_str, one_minus_str

        lines.append(f"  certified: P >= {one_minus_str(certificate.epsilon)} at confidence "
                     f"{floor_str(certificate.confidence)}, {certificate.successes}/"
                     f"{certificate.episodes} episodes of {certificate.env} (root seed "
                     f"{certificate.seed}, vlb-gym {certificate.vlb_gym}); check it again: "
                     f"vlb verify {certificate.env} --behavior FILE --certificate")
    for node in compiled.spec.nodes:
        kind = f"primitive {node.primitive}" if node.primitive else f"behavior {node.behavior}"
        tags = (" [start]" if node.id == compiled.start_node else "") + \
               (" [terminal]" if node.id in compiled.terminals else "")
        lines.append(f"  node {node.id}: {kind}{tags}")
    for edge in compiled.spec.edges:
        lines.append(f"  edge {edge.source} -> {edge.to}: if {edge.guard}"
                     + (f", param {edge.param}" if edge.param else "")
                     + "".join(f", {k} := {v}" for k, v in edge.set.items()))
    return "\n".join(lines)


def cmd_schema(args: argparse.Namespace) -> int:
    from vlb_gym.core.spec import json_schema

    print(json.dumps(json_schema(), indent=2))
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    b = sub.add_parser("behaviors", help="list the behavior library, or show one behavior",
                       description="Without NAME, list the library (shipped behaviors and the "
                       "user's, in $VLB_BEHAVIOR_DIR); with NAME (or a file), check it against "
                       "its environment and print its graph.")
    b.add_argument("name", nargs="?", metavar="NAME_OR_FILE",
                   help="a behavior name or a behavior JSON file")
    b.add_argument("--env", dest="env_id", metavar="ENV_ID",
                   help="check against this environment (default: the behavior's 'env')")
    b.add_argument("--json", action="store_true", help="print the behavior file")
    add_env_module(b)
    b.set_defaults(func=cmd_behaviors)
    s = sub.add_parser("schema", help="print the JSON Schema of behavior files")
    s.set_defaults(func=cmd_schema)
