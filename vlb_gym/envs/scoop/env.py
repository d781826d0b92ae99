"""``VLB-Scoop-v0``: a UR5e-like arm scoops granular media in MuJoCo (the paper's Sec. V-B)."""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np
from gymnasium import spaces

from vlb_gym.core.env import FrameCallback, PrimitiveEnv
from vlb_gym.core.primitive import Outcome
from vlb_gym.core.search_space import Parameter, SearchSpace
from vlb_gym.envs import arguments

from . import gl, piles
from .generator import place, sample_environment
from .helpers import Pose, ScoopHelpers, ScoopJudge
from .kinematics import Kinematics, matrix_rpy, rpy_matrix
from .primitives import Scoop
from .scene import DEFAULT_PHYSICS, GRAIN_MASS, Physics, Scene, build_scene
from .types import ScoopState

MAX_PLACEMENT_NOISE = 0.04  # m: the containers, shifted by up to 2.5 sigma, never overlap
MAX_YAW_NOISE_DEG = 72.0  # 2.5 sigma reaches a half turn
MAX_GRAINS = 350  # the donor holds a settled pile of this many grains in every style
MAX_SLEEP_TOLERANCE = 0.1  # m/s: three times the default, far past the jitter of grains at rest
MAX_SOLVER_ITERATIONS = 200  # CG iterations per step: far past convergence (30 was the cap)
SOLVER_TOLERANCES = (1e-10, 1e-2)  # relative improvement at which CG stops
DEFAULT_SENSING_POSE = (0.5, 0.075, 0.55, np.pi, -0.35, np.pi / 2)
#: The default sensing pose as behavior files write it (five decimals).
SENSING_POSE_EXPRESSION = "(" + ", ".join(f"{round(v, 5):g}" for v in DEFAULT_SENSING_POSE) + ")"
FOLDED = np.array([0.0, -1.9, 1.9, -1.57, -1.57, 0.0])


@lru_cache(maxsize=1)
def home_configuration() -> np.ndarray:
    """Joint angles of the default sensing pose: where every episode starts."""
    kin = Kinematics(build_scene(piles.GRAIN_COUNTS[0]), "flange")
    pose = np.array(DEFAULT_SENSING_POSE)
    return kin.solve(pose[:3], rpy_matrix(*pose[3:]), FOLDED)


class ScoopEnv(PrimitiveEnv[ScoopState]):
    """A 6-DOF arm with a wrist depth camera scoops sand from a donor into a receiver.

    ## Description
    MuJoCo scene (``vlb_gym/assets/ur5e_scoop.xml``): a table, an arm with the UR5e's DH
    kinematics and link masses, position-controlled joints (150 N m limits on the three large
    joints, 28 N m on the wrists) with gravity compensation, a scoop on the flange, a wrist depth
    camera, a donor container (inner 12 x 12 cm) holding 230-290 spherical grains of 6 mm radius
    (2.26 g each) and an empty receiver (inner 8 x 8 cm). Physics: 4 ms steps, CG solver capped at
    20 iterations (tolerance 1e-5), elliptic friction cones, island sleeping: grains in contact
    with each other whose speeds all stay under ``sleep_tolerance`` for 10 steps are frozen (not
    simulated) until something awake touches them, so the pile costs nothing while the scoop is
    elsewhere. ``sleep_tolerance=0, solver_iterations=30, solver_tolerance=1e-6`` is the plain
    physics these settings were checked against (same masses within noise; about 3x slower).

    One primitive, ``scoop`` (P^r): move to the sensing pose, render a depth image from the wrist
    camera, locate both containers in it (no simulator ground truth), then scoop, lift, transfer,
    dump and return to the sensing pose, all executed by the simulated arm.

    ## Action Space
    ``Box(6,)`` float32: the sensing pose (x, y, z, roll, pitch, yaw) of the flange in the robot
    base frame, metres and radians (extrinsic x-y-z angles). Outside the box: ``ValueError``.

    ## Observation Space
    ``Box(6,)`` float64: the flange pose in the same coordinates.

    ## Rewards
    The delivered mass in kilograms (a task-aligned default; rho_B does not use it).

    ## Starting State
    The arm rests at the default sensing pose; d is drawn from pi: container positions around
    set-points (donor (0.5, -0.2), receiver (0.5, 0.2)) with independent truncated Gaussian noise
    (``placement_noise`` m, ``yaw_noise_deg``), a sand level (230, 260 or 290 grains) and a pile
    style (flat, tilted, heaped), each uniform; the pile starts from a shipped settled snapshot.

    ## Episode End
    Never terminates by itself (the behavior decides); truncated after 20 primitives.

    ## Info
    ``primitive``, ``param``, ``admissible``, ``certificate`` (and ``failure`` and ``reason``),
    ``certificates``
    (``pose``: the flange ended within 1 cm and 3 deg of the sensing pose; ``delivered``: at least
    ``delivered_threshold_g`` grams reached the receiver), ``mass_scooped``, ``mass_delivered``,
    ``mass_spilled`` (grams), ``perceived`` (container estimates from the depth image) and
    ``sim_seconds``.

    ## Arguments
    ``render_mode`` (``"rgb_array"``: the overview camera; ``"depth_array"``: the wrist camera),
    ``placement_noise=0.02`` (0 to 0.04 m), ``yaw_noise_deg=8`` (0 to 72),
    ``grain_counts=(230, 260, 290)`` (each 1 to 350; a count that ships no settled pile is settled
    at its first reset, a few seconds), ``delivered_threshold_g=10`` (finite, >= 0),
    ``width=480``, ``height=480`` (rgb frames, at most 640 x 480), ``sleep_tolerance=0.03`` (0 to
    0.1 m/s, and rad/s times the grain radius; 0 simulates every grain at every step),
    ``solver_iterations=20`` (1 to 200), ``solver_tolerance=1e-5`` (1e-10 to 1e-2). Arguments of
    the wrong type raise ``TypeError``, out of range ``ValueError``.
    """

    metadata = {"render_modes": ["rgb_array", "depth_array"], "render_fps": 25}
    env_id = "VLB-Scoop-v0"
    preload = ("vlb_gym.envs.scoop",)  # MuJoCo, the headless GL backend and the env

    def __init__(self, render_mode: str | None = None, placement_noise: float = 0.02,
                 yaw_noise_deg: float = 8.0, grain_counts: tuple[int, ...] = piles.GRAIN_COUNTS,
                 delivered_threshold_g: float = 10.0, width: int = 480, height: int = 480,
                 sleep_tolerance: float = DEFAULT_PHYSICS.sleep_tolerance,
                 solver_iterations: int = DEFAULT_PHYSICS.solver_iterations,
                 solver_tolerance: float = DEFAULT_PHYSICS.solver_tolerance):
        self.placement_noise = arguments.real("placement_noise", placement_noise, 0.0,
                                              MAX_PLACEMENT_NOISE)
        self.yaw_noise_deg = arguments.real("yaw_noise_deg", yaw_noise_deg, 0.0, MAX_YAW_NOISE_DEG)
        if not isinstance(grain_counts, (list, tuple)) or not grain_counts:
            raise TypeError(f"grain_counts must be a non-empty list of integers "
                            f"(got {grain_counts!r})")
        self.grain_counts = tuple(arguments.integer("grain_counts", n, 1, MAX_GRAINS)
                                  for n in grain_counts)
        # the offscreen buffer of the scene (<global offwidth="640" offheight="480"/>)
        self.width = arguments.integer("width", width, 1, 640)
        self.height = arguments.integer("height", height, 1, 480)
        self.scoop = Scoop(arguments.real("delivered_threshold_g", delivered_threshold_g, 0.0))
        observations = spaces.Box(np.array([-2, -2, -1, -np.pi, -np.pi, -np.pi]),
                                  np.array([2, 2, 2, np.pi, np.pi, np.pi]), dtype=np.float64)
        self.physics = Physics(
            arguments.real("sleep_tolerance", sleep_tolerance, 0.0, MAX_SLEEP_TOLERANCE),
            arguments.integer("solver_iterations", solver_iterations, 1, MAX_SOLVER_ITERATIONS),
            arguments.real("solver_tolerance", solver_tolerance, *SOLVER_TOLERANCES))
        super().__init__([self.scoop], observations, render_mode)
        self._simulations: dict[int, tuple[Scene, mujoco.MjData]] = {}
        self._renderers: dict[tuple[int, str], mujoco.Renderer] = {}

    def make_helpers(self) -> ScoopHelpers:
        return ScoopHelpers()

    def make_judge(self) -> ScoopJudge:
        """Fresh outcome helpers for promises (what the behavior's scoops measured)."""
        return ScoopJudge()

    def search_space(self) -> SearchSpace:
        """Scoops from poses, the default sensing pose first; a scoop costs seconds of
        simulation, so candidates are screened on a few episodes and the decision contexts
        come from one scoop after the first reset (the other rollouts give their resets)."""
        return SearchSpace(types={"pose": Pose}, parameters=(Parameter("scoop", "pose"),),
                           constants=(("pose", SENSING_POSE_EXPRESSION),), screening=3,
                           context_steps=1)

    def sample_state(self) -> ScoopState:
        env = sample_environment(self.np_random, self.grain_counts, self.placement_noise,
                                 self.yaw_noise_deg)
        scene, data = self._simulation(env.n_grains)
        place(scene, data, env, home_configuration())
        state = ScoopState(scene, data, env)
        self._film_motion(state)
        return state

    def _simulation(self, n_grains: int) -> tuple[Scene, mujoco.MjData]:
        """This env's scene of ``n_grains`` (its own model: containers are placed in it, with
        this env's physics) and its data, made at the first use."""
        if n_grains not in self._simulations:
            scene = build_scene(n_grains).own_copy(self.physics)
            self._simulations[n_grains] = scene, mujoco.MjData(scene.model)
        return self._simulations[n_grains]

    def observation(self) -> np.ndarray:
        pos, rot = self.state.flange_pose
        return np.concatenate([pos, matrix_rpy(rot)])

    def reset_info(self) -> dict[str, Any]:
        env = self.state.env
        return {"environment": {
            "donor": env.donor.round(4).tolist(), "receiver": env.receiver.round(4).tolist(),
            "grains": env.n_grains, "pile": env.pile_style}}

    def step_info(self, outcome: Outcome) -> dict[str, Any]:
        return {"param": tuple(round(v, 4) for v in outcome.param)}  # float32 digits are noise

    def reward(self, outcome: Outcome) -> float:
        """The delivered mass in kilograms (a task-aligned default; rho_B does not use it)."""
        return outcome.details.get("mass_delivered", 0.0) / 1000.0

    def film(self, callback: FrameCallback | None) -> None:
        """Also films the arm's motion during a scoop, at ``render_fps``."""
        super().film(callback)
        if self._state is not None:
            self._film_motion(self._state)

    def _film_motion(self, state: ScoopState) -> None:
        filming = self._on_frame is not None
        state.on_frame = (lambda: self._on_frame(self.render())) if filming else None
        state.frame_every = max(1, round(1 / (self.metadata["render_fps"]
                                             * state.scene.model.opt.timestep)))

    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode")
            return None
        state = self.state
        if self.render_mode == "depth_array":
            return self.scoop.camera(state).depth(state.data)
        key = (id(state.scene), "rgb")
        if key not in self._renderers:
            self._renderers[key] = gl.renderer(state.scene.model, self.height, self.width)
        renderer = self._renderers[key]
        renderer.update_scene(state.data, camera="overview")
        return renderer.render().copy()

    def close(self) -> None:
        for renderer in self._renderers.values():
            renderer.close()
        self._renderers.clear()
        self.scoop.close()

    # -- interactive set-up (vlb scoop-setup) ----------------------------------------------------
    def move_to(self, pose: np.ndarray, seconds: float = 1.0) -> str | None:
        """Drive the flange to ``pose`` through the simulated arm; the reason if unreachable."""
        from .kinematics import IKFailure
        from .motion import ArmDriver

        state = self.state
        driver = ArmDriver(state.scene, state.data)
        try:
            q = driver.flange.solve(np.asarray(pose[:3], float), rpy_matrix(*pose[3:]), driver.q)
        except IKFailure as exc:
            return str(exc)
        driver.move_joints(q, seconds)
        driver.settle(0.2)
        return None

    def wrist_image(self) -> np.ndarray:
        """What the wrist camera sees now, as RGB."""
        key = (id(self.state.scene), "wrist")
        if key not in self._renderers:
            self._renderers[key] = gl.renderer(self.state.scene.model, 240, 320)
        renderer = self._renderers[key]
        renderer.update_scene(self.state.data, camera="wrist")
        return renderer.render().copy()

    def sampling_distribution(self) -> str:
        return (f"pi: donor and receiver placed around (0.5, -0.2) and (0.5, 0.2) m with "
                f"independent Gaussian noise (sigma {self.placement_noise:g} m in x and y, "
                f"{self.yaw_noise_deg:g} deg in yaw, truncated at 2.5 sigma), sand level uniform "
                f"over {list(self.grain_counts)} grains of {GRAIN_MASS * 1000:.2f} g, pile flat, "
                "tilted or heaped (uniform); arm starting at the default sensing pose; "
                f"{self._physics_words()}")

    def _physics_words(self) -> str:
        """The simulation the guarantee holds in (a store made under other settings is refused
        on resume, since its plan says this)."""
        physics = self.physics
        step_ms = build_scene(self.grain_counts[0]).model.opt.timestep * 1000  # the asset's
        sleeping = (f"island sleeping under {physics.sleep_tolerance:g} m/s"
                    if physics.sleep_tolerance else "no sleeping")
        return (f"simulated with {step_ms:g} ms steps, CG capped at {physics.solver_iterations} "
                f"iterations (tolerance {physics.solver_tolerance:g}), {sleeping}")
