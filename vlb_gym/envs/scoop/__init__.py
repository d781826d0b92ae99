"""``VLB-Scoop-v0``: scene, piles, generator, kinematics, motion, perception, controller,
primitives, helpers, env."""

import ctypes.util
import os


def _headless_backend() -> str | None:
    """EGL where libEGL loads, else OSMesa where it is installed (``MUJOCO_GL`` wins if set)."""
    for backend, library in (("egl", "EGL"), ("osmesa", "OSMesa")):
        if ctypes.util.find_library(library):
            return backend
    return None


# must happen before the first ``import mujoco``
if "MUJOCO_GL" not in os.environ and (_backend := _headless_backend()) is not None:
    os.environ["MUJOCO_GL"] = _backend

try:
    import mujoco  # noqa: E402, F401
except ImportError as exc:  # pragma: no cover - depends on the installation
    raise ImportError("VLB-Scoop-v0 needs MuJoCo: pip install 'vlb-gym[scoop]'") from exc

from .env import ScoopEnv  # noqa: E402

__all__ = ["ScoopEnv"]
