"""The formalism: primitives (Def. 1), behaviors (Def. 2) and their compilation, expressions, runtime."""

from .compiler import CompiledBehavior, compile_behavior
from .expressions import ExpressionError
from .library import compile_for, load_behavior, shipped_behaviors
from .primitive import ControllerFailure, MotionPrimitive, Outcome, execute
from .runtime import BehaviorPolicy, BehaviorRuntimeError
from .spec import BehaviorSpec, BehaviorSpecError, json_schema, parse_spec

__all__ = ["BehaviorPolicy", "BehaviorRuntimeError", "BehaviorSpec", "BehaviorSpecError",
           "CompiledBehavior", "ControllerFailure", "ExpressionError", "MotionPrimitive", "Outcome",
           "compile_behavior", "compile_for", "execute", "json_schema",
           "load_behavior", "parse_spec", "shipped_behaviors"]
