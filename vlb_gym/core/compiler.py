"""Behaviors (the paper's Definition 2): check a :class:`BehaviorSpec` and compile it.

:func:`compile_behavior` checks a spec against an environment's :class:`PrimitiveEnv` --
references, expressions, the graph (every node reachable from the start, a terminal reachable from
every node) -- before anything runs, and gives a :class:`CompiledBehavior`, which
:class:`vlb_gym.core.runtime.BehaviorPolicy` runs.
"""

from __future__ import annotations

import ast
import inspect
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import networkx as nx

from .env import PrimitiveEnv
from .expressions import BUILTINS, Expression, ExpressionError
from .helpers import arity
from .promise import compile_promise
from .spec import BehaviorSpec, BehaviorSpecError
from .signatures import BUILTIN_SIGNATURES, Signature, helper_signatures
from .typecheck import check as typecheck

VALUE = -1  # arity marker of names that are values, not functions
MAX_BEHAVIOR_DEPTH = 16  # sub-behaviors nested within each other
MAX_CALL_DEPTH = 16  # behavior functions calling each other


#: resolve(reference, base_dir) -> (spec, source, base_dir of that spec)
Resolver = Callable[[str, Path | None], tuple[BehaviorSpec, str, Path | None]]


@dataclass(frozen=True)
class _Node:
    id: str
    primitive: str | None
    child: CompiledBehavior | None


@dataclass(frozen=True)
class _Edge:
    source: str
    to: str
    guard: Expression
    param: Expression | None
    assignments: tuple[tuple[str, Expression], ...]


@dataclass
class CompiledBehavior:
    """A checked behavior, ready to run against one environment interface."""

    name: str
    source: str
    spec: BehaviorSpec
    nodes: dict[str, _Node]
    out_edges: dict[str, list[_Edge]]
    start_node: str
    start_param: Expression | None
    terminals: frozenset[str]
    variables: tuple[tuple[str, Expression], ...]
    functions: tuple[tuple[str, Expression], ...]
    graph: nx.MultiDiGraph = field(repr=False)
    promise: Expression | None = None

    @cached_property
    def depth(self) -> int:
        """Levels of behaviors: 1 without sub-behaviors, else 1 + the deepest sub-behavior's."""
        return 1 + max((n.child.depth for n in self.nodes.values() if n.child), default=0)

    def primitives_used(self) -> set[str]:
        """Names of all primitives this behavior and its sub-behaviors may run."""
        used = set()
        for node in self.nodes.values():
            used |= node.child.primitives_used() if node.child else {node.primitive}
        return used


def _fail(source: str, place: str, message: str, layer: str) -> BehaviorSpecError:
    return BehaviorSpecError(f"{source}: {place}: {message}", layer)


def _expr_names(text: str) -> set[str]:
    try:
        return {n.id for n in ast.walk(ast.parse(text, mode="eval")) if isinstance(n, ast.Name)}
    except (SyntaxError, RecursionError, MemoryError):  # reported by the expression checker
        return set()


def _check_references(spec: BehaviorSpec, interface: PrimitiveEnv, source: str,
                      resolve: Resolver, base_dir: Path | None, chain: tuple[str, ...],
                      compiled: dict[str, CompiledBehavior]) -> dict[str, _Node]:
    """Layer 'references': ids unique; primitives, sub-behaviors, nodes, variables exist.
    Sub-behaviors are compiled once each (``compiled`` holds them by source), never in a cycle
    and never nested deeper than MAX_BEHAVIOR_DEPTH."""
    def fail(place: str, message: str) -> BehaviorSpecError:
        return _fail(source, place, message, "references")

    nodes: dict[str, _Node] = {}
    for i, node in enumerate(spec.nodes):
        if node.id in nodes:
            raise fail(f"nodes[{i}].id", f"duplicate node id {node.id!r}")
        child = None
        if node.primitive is not None and node.primitive not in interface.primitives:
            known = ", ".join(sorted(interface.primitives))
            raise fail(f"nodes[{i}].primitive",
                       f"unknown primitive {node.primitive!r} (this environment has: {known})")
        if node.behavior is not None:
            child_spec, child_source, child_dir = resolve(node.behavior, base_dir)
            if child_source in chain:
                raise fail(f"nodes[{i}].behavior",
                           "sub-behavior cycle: " + " -> ".join((*chain, child_source)))
            too_deep = fail(f"nodes[{i}].behavior",
                            f"sub-behaviors nested more than {MAX_BEHAVIOR_DEPTH} deep")
            if len(chain) >= MAX_BEHAVIOR_DEPTH:
                raise too_deep
            child = compiled.get(child_source)
            if child is None:
                child = compile_behavior(child_spec, interface, child_source, resolve, child_dir,
                                         _chain=chain, _compiled=compiled)
            if len(chain) + child.depth > MAX_BEHAVIOR_DEPTH:  # a compiled one, met deeper here
                raise too_deep
        nodes[node.id] = _Node(node.id, node.primitive, child)

    def unknown(node_id: str) -> str:
        known = ", ".join(nodes) if len(nodes) <= 12 else f"{len(nodes)} of them"
        return f"unknown node {node_id!r} (the nodes: {known})"

    def check_target(node_id: str, param: str | None, place: str, node_field: str) -> None:
        if node_id not in nodes:
            raise fail(node_field, unknown(node_id) + (
                "; an edge always leads to a node: a behavior ends at a terminal node when "
                "none of its edges can be taken" if node_field.endswith(".to") else ""))
        if nodes[node_id].child is not None and param is not None:
            raise fail(place, f"node {node_id!r} runs the whole behavior "
                              f"{nodes[node_id].child.name!r} and takes no param (a node that "
                              "runs a primitive with a param is {\"id\": ..., \"primitive\": "
                              "NAME})")
        if nodes[node_id].child is None and param is None:
            raise fail(place, f"node {node_id!r} runs primitive {nodes[node_id].primitive!r} "
                              "and needs a param")

    for i, edge in enumerate(spec.edges):
        if edge.source not in nodes:
            raise fail(f"edges[{i}].from", unknown(edge.source))
        check_target(edge.to, edge.param, f"edges[{i}].param", f"edges[{i}].to")
        for var in edge.set:
            if var not in spec.variables:
                raise fail(f"edges[{i}].set.{var}", f"{var!r} is not a declared variable")
    check_target(spec.start.node, spec.start.param, "start.param", "start.node")
    for i, terminal in enumerate(spec.terminals):
        if terminal not in nodes:
            raise fail(f"terminals[{i}]", unknown(terminal))
    return nodes


def _check_graph(spec: BehaviorSpec, nodes: dict[str, _Node], source: str) -> nx.MultiDiGraph:
    """Layer 'graph': every node reachable from the start, a terminal reachable from every node."""
    graph = nx.MultiDiGraph(name=spec.name)
    for node in nodes.values():
        graph.add_node(node.id, primitive=node.primitive,
                       behavior=node.child.name if node.child else None)
    for i, edge in enumerate(spec.edges):
        graph.add_edge(edge.source, edge.to, guard=edge.guard, param=edge.param, order=i)
    reachable = nx.descendants(graph, spec.start.node) | {spec.start.node}
    unreachable = [n for n in nodes if n not in reachable]
    if unreachable:
        raise _fail(source, "nodes", f"not reachable from the start node: "
                                     f"{', '.join(unreachable)}", "graph")
    finishing = set(spec.terminals).union(*(nx.ancestors(graph, t) for t in spec.terminals))
    stuck = [n for n in nodes if n not in finishing]
    if stuck:
        raise _fail(source, "terminals", f"no terminal node is reachable from: "
                                         f"{', '.join(stuck)}", "graph")
    return graph


def _taken(name: str, helpers: dict[str, Any]) -> str:
    """Why a declared ``name`` is not free: a helper (with its signature, so a model knows to
    call it), a builtin, or an earlier declaration."""
    if name in helpers:
        signature = str(inspect.signature(helpers[name])).replace("'", "")
        return (f"{name!r} is already a helper, {name}{signature}: call it in expressions "
                f"instead of declaring it, or choose another name")
    if name in BUILTINS:
        return f"{name!r} is already a builtin function; choose another name"
    return f"{name!r} is declared twice (variables and functions share one namespace)"


class _Expressions:
    """Layer 'expressions': every expression checked against the whitelist and compiled."""

    def __init__(self, spec: BehaviorSpec, interface: PrimitiveEnv, source: str):
        self.source = source
        names: dict[str, int | None] = {n: None for n in BUILTINS}
        helpers = interface.make_helpers().functions()
        names.update({n: arity(f) for n, f in helpers.items()})
        self.signatures: dict[str, Signature] = {**BUILTIN_SIGNATURES,
                                                 **helper_signatures(helpers)}
        for kind, declared in (("variables", spec.variables), ("functions", spec.functions)):
            for name in declared:
                if name in names:
                    raise self.fail(f"{kind}.{name}", _taken(name, helpers))
                names[name] = VALUE if kind == "variables" else len(spec.functions[name].args)
        self.names = names
        self.own = {**{n: "an observation helper (what the agent sees, not what happened)"
                       for n in helpers},
                    **{n: "a variable of the behavior" for n in spec.variables},
                    **{n: "a function of the behavior" for n in spec.functions}}
        functions = []
        for name in self._function_order(spec):
            fn = spec.functions[name]
            clash = [a for a in fn.args if a in names]
            if clash or len(set(fn.args)) != len(fn.args):
                raise self.fail(f"functions.{name}.args",
                                f"argument names must be new and distinct ({', '.join(clash)})")
            functions.append((name, self(fn.expr, f"functions.{name}.expr", tuple(fn.args))))
            self.signatures[name] = Signature(len(fn.args), len(fn.args),
                                              returns=self.returns)
        self.functions = tuple(functions)
        self.variables = tuple((v, self(text, f"variables.{v}"))
                               for v, text in spec.variables.items())

    def fail(self, place: str, message: str) -> BehaviorSpecError:
        return _fail(self.source, place, message, "expressions")

    def __call__(self, text: str | None, place: str,
                 args: tuple[str, ...] | None = None) -> Expression | None:
        if text is None:
            return None
        try:
            expression = Expression(text, {**self.names, **{a: VALUE for a in args or ()}},
                                    f"{self.source}: {place}", args=args)
            self.returns = typecheck(text, self.signatures, f"{self.source}: {place}")
            return expression
        except ExpressionError as exc:
            raise BehaviorSpecError(str(exc), "expressions") from None

    def _function_order(self, spec: BehaviorSpec) -> list[str]:
        calls = nx.DiGraph()
        calls.add_nodes_from(spec.functions)
        for name, fn in spec.functions.items():
            calls.add_edges_from((other, name) for other in spec.functions
                                 if other in _expr_names(fn.expr))
        try:
            order = list(nx.topological_sort(calls))
        except nx.NetworkXUnfeasible:
            cycle = " -> ".join(a for a, _ in nx.find_cycle(calls))
            raise self.fail("functions", f"recursive functions are not allowed ({cycle})") from None
        if nx.dag_longest_path_length(calls) >= MAX_CALL_DEPTH:
            chain = " -> ".join(reversed(nx.dag_longest_path(calls)))
            raise self.fail("functions", f"functions call each other more than {MAX_CALL_DEPTH} "
                                         f"deep ({chain})")
        return order


def compile_behavior(spec: BehaviorSpec, interface: PrimitiveEnv, source: str,
                     resolve: Resolver, base_dir: Path | None = None, *,
                     _chain: tuple[str, ...] = (),
                     _compiled: dict[str, CompiledBehavior] | None = None) -> CompiledBehavior:
    """Check ``spec`` against ``interface`` and compile it.

    Checks run in layers -- references, then the graph, then expressions -- and the first
    problem raises :class:`BehaviorSpecError` naming the file, the place and the layer.
    """
    compiled = {} if _compiled is None else _compiled
    nodes = _check_references(spec, interface, source, resolve, base_dir, (*_chain, source),
                              compiled)
    graph = _check_graph(spec, nodes, source)
    expr = _Expressions(spec, interface, source)
    out_edges: dict[str, list[_Edge]] = {n: [] for n in nodes}
    for i, edge in enumerate(spec.edges):
        guard = expr(edge.guard, f"edges[{i}].guard")
        if expr.returns is not None and expr.returns.kind == "generator":
            raise expr.fail(f"edges[{i}].guard", f"{edge.guard!r} is a generator, not true or "
                                                 "false (write any(...) or all(...))")
        out_edges[edge.source].append(_Edge(
            edge.source, edge.to, guard,
            expr(edge.param, f"edges[{i}].param"),
            tuple((v, expr(t, f"edges[{i}].set.{v}")) for v, t in edge.set.items())))
    compiled[source] = CompiledBehavior(
        spec.name, source, spec, nodes, out_edges, spec.start.node,
        expr(spec.start.param, "start.param"), frozenset(spec.terminals), expr.variables,
        expr.functions, graph, compile_promise(spec, interface, source, expr.own))
    return compiled[source]
