"""``VLB-Scoop-v0``: scene, piles, generator, kinematics, motion, perception, controller,
primitives, helpers, env."""

try:
    from . import gl  # first: it picks MuJoCo's headless backend before MuJoCo loads
except ImportError as exc:  # pragma: no cover - depends on the installation
    raise ImportError("VLB-Scoop-v0 needs MuJoCo: pip install 'vlb-gym[scoop]'") from exc

from .env import ScoopEnv  # noqa: E402

__all__ = ["ScoopEnv"]
