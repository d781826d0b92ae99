"""Names of a package imported from their modules on first use (PEP 562), so that importing the
package, and starting ``vlb``, stays quick."""

from __future__ import annotations

import importlib
import importlib.util
from collections.abc import Callable, Mapping
from typing import Any


def lazy_names(package: str, namespace: dict[str, Any], modules: Mapping[str, tuple[str, ...]]
               ) -> tuple[Callable[[str], Any], Callable[[], list[str]], list[str]]:
    """A module's ``__getattr__``, ``__dir__`` and ``__all__`` (the names of ``modules``, where
    they are written once) serving each name of ``modules`` (relative module -> names) from its
    module, imported on first use and then kept in ``namespace``; a submodule's name imports it,
    as an eager ``__init__`` would have (``package.store``)."""
    lazy = {name: module for module, names in modules.items() for name in names}

    def getattr_(name: str) -> Any:
        if name not in lazy:
            if not name.startswith("_") and importlib.util.find_spec(f"{package}.{name}"):
                return importlib.import_module(f"{package}.{name}")
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(lazy[name], package), name)
        namespace[name] = value
        return value

    def dir_() -> list[str]:
        return sorted({*namespace, *lazy})

    return getattr_, dir_, sorted(lazy)
