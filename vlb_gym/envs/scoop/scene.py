"""The MuJoCo scene: the MJCF asset plus a bed of spherical grains, compiled with MjSpec."""

from __future__ import annotations

import copy
from dataclasses import dataclass, replace
from functools import lru_cache
from importlib import resources

import mujoco
import numpy as np

ASSET = "ur5e_scoop.xml"
GRAIN_RADIUS = 0.006  # m
GRAIN_DENSITY = 2500.0  # kg/m^3, quartz sand
GRAIN_MASS = GRAIN_DENSITY * 4 / 3 * np.pi * GRAIN_RADIUS**3  # ~2.26 g
ARM_JOINTS = ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3")

# container interiors (half sizes) and wall heights, as in the asset
DONOR_HALF, DONOR_WALL = 0.06, 0.065  # inner half width, wall top height (m)
RECEIVER_HALF, RECEIVER_WALL = 0.04, 0.06
DONOR_OUTER, RECEIVER_OUTER = 0.07, 0.05  # outer half widths
FLOOR = 0.01


@dataclass(frozen=True)
class Physics:
    """The simulation settings an env chooses over the asset's: island sleeping (grains whose
    speeds stay under ``sleep_tolerance`` for 10 steps are frozen until something awake touches
    them; 0: every grain simulated at every step) and the CG solver's iteration cap and
    tolerance. :data:`PLAIN` is the asset's own: the physics before any speed-up (shipped piles
    settle in it)."""

    sleep_tolerance: float = 0.03  # m/s, and rad/s times the grain radius
    solver_iterations: int = 20
    solver_tolerance: float = 1e-5


DEFAULT_PHYSICS = Physics()
PLAIN = Physics(sleep_tolerance=0.0, solver_iterations=30, solver_tolerance=1e-6)


@dataclass(frozen=True)
class Scene:
    """A compiled model with ``n_grains`` grains and the indices the env needs."""

    model: mujoco.MjModel
    n_grains: int
    arm_qpos: np.ndarray  # qpos addresses of the six arm joints
    arm_dof: np.ndarray  # dof addresses of the six arm joints
    grain_qpos: np.ndarray  # (n_grains, 7) qpos addresses of the grains' free joints
    grain_dof: np.ndarray  # (n_grains, 6) dof addresses
    donor_body: int  # the containers: static bodies, placed by writing their poses
    receiver_body: int

    def own_copy(self, physics: Physics) -> Scene:
        """This scene with a model of its own, to place containers in (:meth:`place_container`)
        without touching the shared compiled model, simulated with ``physics``."""
        model = copy.copy(self.model)
        model.opt.sleep_tolerance = physics.sleep_tolerance
        sleep = int(mujoco.mjtEnableBit.mjENBL_SLEEP)
        model.opt.enableflags = (model.opt.enableflags | sleep if physics.sleep_tolerance
                                 else model.opt.enableflags & ~sleep)
        model.opt.iterations = physics.solver_iterations
        model.opt.tolerance = physics.solver_tolerance
        return replace(self, model=model)

    def place_container(self, body: int, x: float, y: float, yaw: float) -> None:
        """Move a container (``donor_body`` or ``receiver_body``) to ``(x, y)`` on the table with
        ``yaw``; takes effect at the next ``mj_resetData`` or ``mj_forward``."""
        self.model.body_pos[body] = [x, y, 0.0]
        self.model.body_quat[body] = yaw_quat(yaw)


def yaw_quat(yaw: float) -> np.ndarray:
    """The quaternion of a turn by ``yaw`` about the vertical."""
    return np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])


@lru_cache(maxsize=4)
def build_scene(n_grains: int) -> Scene:
    """Compile the asset with ``n_grains`` free spheres (placed later, from a settled snapshot).
    Shared and cached: whoever places containers works on :meth:`Scene.own_copy`."""
    xml = (resources.files("vlb_gym.assets") / ASSET).read_text()
    spec = mujoco.MjSpec.from_string(xml)
    for k in range(n_grains):
        body = spec.worldbody.add_body(name=f"grain{k}", pos=[2.0 + 0.02 * k, 2.0, 0.1])
        body.add_freejoint()
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[GRAIN_RADIUS, 0, 0],
                      mass=GRAIN_MASS, rgba=[0.86, 0.74, 0.5, 1], contype=1, conaffinity=1,
                      condim=3, friction=[0.9, 0.005, 0.0001])
    model = spec.compile()
    arm_qpos = np.array([model.joint(j).qposadr[0] for j in ARM_JOINTS])
    arm_dof = np.array([model.joint(j).dofadr[0] for j in ARM_JOINTS])
    grain_qpos = np.array([model.joint(model.body(f"grain{k}").jntadr[0]).qposadr[0]
                           for k in range(n_grains)]).reshape(-1, 1) + np.arange(7)
    grain_dof = np.array([model.joint(model.body(f"grain{k}").jntadr[0]).dofadr[0]
                          for k in range(n_grains)]).reshape(-1, 1) + np.arange(6)
    return Scene(model, n_grains, arm_qpos, arm_dof, grain_qpos, grain_dof,
                 model.body("donor").id, model.body("receiver").id)
