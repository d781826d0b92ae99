"""Headless OpenGL for MuJoCo's renderers: the backend, chosen before MuJoCo loads, and renderers
that say what to do when no OpenGL context can be made."""

from __future__ import annotations

import ctypes.util
import os
import sys

#: Whether MuJoCo was imported before this package without ``MUJOCO_GL``: it has then chosen its
#: default backend (GLFW, which needs a display) and the choice below comes too late.
CHOSEN_BEFORE_US = "mujoco" in sys.modules and "MUJOCO_GL" not in os.environ


def _headless_backend() -> str | None:
    """EGL where libEGL loads, else OSMesa where it is installed (``MUJOCO_GL`` wins if set)."""
    for backend, library in (("egl", "EGL"), ("osmesa", "OSMesa")):
        if ctypes.util.find_library(library):
            return backend
    return None


# must happen before the first ``import mujoco``
if "MUJOCO_GL" not in os.environ and (_backend := _headless_backend()) is not None:
    os.environ["MUJOCO_GL"] = _backend

import mujoco  # noqa: E402


def renderer(model: mujoco.MjModel, height: int, width: int) -> mujoco.Renderer:
    """A :class:`mujoco.Renderer`; a RuntimeError that names the fix if none can be made."""
    try:
        return mujoco.Renderer(model, height, width)
    except (mujoco.FatalError, RuntimeError) as exc:
        if CHOSEN_BEFORE_US:
            raise RuntimeError(
                "MuJoCo was imported before vlb_gym without MUJOCO_GL, so it chose a backend that "
                "needs a display; set MUJOCO_GL=egl (or osmesa) or import vlb_gym first "
                f"({exc})") from exc
        raise RuntimeError(f"MuJoCo cannot render here (MUJOCO_GL="
                           f"{os.environ.get('MUJOCO_GL', 'unset')}): {exc}; VLB-Scoop-v0 needs "
                           "EGL (libegl1) or OSMesa (libosmesa6) without a display") from exc
