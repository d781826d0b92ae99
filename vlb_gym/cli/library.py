"""``vlb behaviors`` and ``vlb schema``: the behavior library and its file format."""

from __future__ import annotations

import argparse
import json

import gymnasium as gym

from vlb_gym.core.library import BehaviorLibrary, compile_for
from vlb_gym.core.spec import json_schema

from .common import check_env


def cmd_behaviors(args: argparse.Namespace) -> int:
    if args.name is None:
        for name in BehaviorLibrary().names():
            print(name)
        return 0
    check_env(args.env_id, {})
    compiled = compile_for(args.name, gym.make(args.env_id))
    if args.json:
        print(compiled.spec.model_dump_json(by_alias=True, indent=2, exclude_defaults=True))
        return 0
    print(graph_text(compiled))
    return 0


def graph_text(compiled) -> str:
    """The nodes and edges of a compiled behavior, one per line."""
    lines = [f"{compiled.name}: {compiled.spec.description}"]
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
    print(json.dumps(json_schema(), indent=2))
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    b = sub.add_parser("behaviors", help="list the behavior library, or show one behavior",
                       description="Without NAME, list the library (shipped behaviors and the "
                       "user's, in $VLB_BEHAVIOR_DIR); with NAME (or a file), check it against "
                       "ENV and print its graph.")
    b.add_argument("name", nargs="?", metavar="NAME_OR_FILE")
    b.add_argument("--env", dest="env_id", default="VLB-GridExplore-v0")
    b.add_argument("--json", action="store_true", help="print the behavior file")
    b.set_defaults(func=cmd_behaviors)
    s = sub.add_parser("schema", help="print the JSON Schema of behavior files")
    s.set_defaults(func=cmd_schema)
