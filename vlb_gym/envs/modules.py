"""Loading a user's environment module, which registers its envs with Gymnasium on import.

``vlb ... --env-module PATH_OR_MODULE`` and campaign workers use :func:`import_env_module`, so
that an env of the user's (see ``docs/new_env.md``) can be verified like the shipped ones.
Importing a module runs its code: name only modules you trust.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from pathlib import Path
from types import ModuleType

_BY_PATH: dict[Path, ModuleType] = {}


def is_path(ref: str) -> bool:
    """Whether ``ref`` names a file (``.py`` or with a ``/``) rather than a dotted module."""
    return ref.endswith(".py") or "/" in ref


def import_env_module(ref: str) -> ModuleType:
    """Import ``ref``: a Python file (as a module named after its stem, kept in ``sys.modules``
    so that its entry points resolve and its envs pickle) or a dotted module name. Each file is
    executed once per process."""
    if not is_path(ref):
        return importlib.import_module(ref)
    path = Path(ref).resolve()
    if path in _BY_PATH:
        return _BY_PATH[path]
    spec = importlib.util.spec_from_file_location(path.stem, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"{ref}: not a Python module")
    module = importlib.util.module_from_spec(spec)
    sys.modules[path.stem] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[path.stem]
        raise
    _BY_PATH[path] = module
    return module
