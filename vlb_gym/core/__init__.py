"""The formalism: primitives (Def. 1), behaviors (Def. 2) and their compilation, expressions,
runtime.

The names below are imported from their modules on first use (PEP 562): ``import vlb_gym.core``
alone costs nothing."""

from __future__ import annotations

from typing import TYPE_CHECKING

from vlb_gym._lazy import lazy_names

if TYPE_CHECKING:
    from .compiler import CompiledBehavior, compile_behavior
    from .env import FrameKey, PrimitiveEnv
    from .expressions import ExpressionError
    from .helpers import Helpers, Judge, helper
    from .library import compile_for, load_behavior, shipped_behaviors
    from .primitive import ControllerFailure, Failure, MotionPrimitive, Outcome, execute
    from .runtime import BehaviorPolicy, BehaviorRuntimeError
    from .search_space import SearchSpace
    from .spec import BehaviorSpec, BehaviorSpecError, json_schema, parse_spec

__getattr__, __dir__, __all__ = lazy_names(__name__, globals(), {
    ".compiler": ("CompiledBehavior", "compile_behavior"),
    ".env": ("FrameKey", "PrimitiveEnv"),
    ".expressions": ("ExpressionError",),
    ".helpers": ("Helpers", "Judge", "helper"),
    ".library": ("compile_for", "load_behavior", "shipped_behaviors"),
    ".primitive": ("ControllerFailure", "Failure", "MotionPrimitive", "Outcome", "execute"),
    ".runtime": ("BehaviorPolicy", "BehaviorRuntimeError"),
    ".search_space": ("SearchSpace",),
    ".spec": ("BehaviorSpec", "BehaviorSpecError", "json_schema", "parse_spec"),
})
