"""VLB-Scoop-v0 at small scale: kinematics against the DH table, piles at rest (and asleep),
perception from a rendered depth image, admissibility, a real scoop moving mass, and the default
(sleeping, shorter CG) physics within the plain physics' band."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import vlb_gym  # noqa: F401 - registers the envs
from vlb_gym import RobustnessWrapper, load_behavior
from vlb_gym.envs.scoop import ScoopEnv  # first: it picks MuJoCo's headless GL before mujoco loads
from vlb_gym.envs.scoop.controller import DepthCamera, grains_in_box, grains_in_scoop
from vlb_gym.envs.scoop.env import DEFAULT_SENSING_POSE
from vlb_gym.envs.scoop.kinematics import Kinematics, matrix_rpy, rpy_matrix
from vlb_gym.envs.scoop.perception import locate_containers
from vlb_gym.envs.scoop.scene import (DONOR_HALF, DONOR_WALL, GRAIN_MASS, RECEIVER_HALF,
                                      PLAIN, RECEIVER_WALL, build_scene)
from vlb_gym.verify import run_episode

import mujoco  # noqa: E402, I001 - after vlb_gym.envs.scoop (see above)

POSE = np.array(DEFAULT_SENSING_POSE, dtype=np.float32)
DH_A = [0, -0.425, -0.3922, 0, 0, 0]
DH_D = [0.1625, 0, 0, 0.1333, 0.0997, 0.0996]
DH_ALPHA = [np.pi / 2, 0, 0, np.pi / 2, -np.pi / 2, 0]


def dh_flange(q: np.ndarray) -> np.ndarray:
    """Independent forward kinematics from the published UR5e DH table (base frame)."""
    transform = np.eye(4)
    for theta, a, d, alpha in zip(q, DH_A, DH_D, DH_ALPHA):
        ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
        transform = transform @ np.array([[ct, -st * ca, st * sa, a * ct],
                                          [st, ct * ca, -ct * sa, a * st],
                                          [0, sa, ca, d], [0, 0, 0, 1]])
    return transform


@pytest.fixture(scope="module")
def env():
    env = ScoopEnv()
    yield env
    env.close()


def test_arm_matches_the_ur5e_dh_table_and_masses():
    scene = build_scene(10)
    kin = Kinematics(scene, "flange")
    base = np.diag([-1.0, -1.0, 1.0])  # the base is mounted turned by 180 degrees about z
    rng = np.random.default_rng(0)
    for q in [np.zeros(6), *rng.uniform(-np.pi, np.pi, (10, 6))]:
        pos, rot = kin.forward(q)
        expected = dh_flange(q)
        assert np.allclose(pos, base @ expected[:3, 3], atol=1e-6)
        assert np.allclose(rot, base @ expected[:3, :3], atol=1e-6)
    masses = [scene.model.body(b).mass[0] for b in ("shoulder_link", "upper_arm_link",
              "forearm_link", "wrist_1_link", "wrist_2_link", "wrist_3_link")]
    assert np.allclose(masses, [3.761, 8.058, 2.846, 1.37, 1.3, 0.365])
    limits = scene.model.actuator_forcerange[:, 1]
    assert np.allclose(limits, [150, 150, 150, 28, 28, 28])


def test_inverse_kinematics_round_trip():
    kin = Kinematics(build_scene(10), "flange")
    target = rpy_matrix(*POSE[3:])
    q = kin.solve(POSE[:3].astype(float), target, np.array([0, -1.9, 1.9, -1.57, -1.57, 0]))
    pos, rot = kin.forward(q)
    assert np.linalg.norm(pos - POSE[:3]) < 1e-3
    assert np.allclose(matrix_rpy(rot), POSE[3:], atol=1e-2)


def test_grains_stay_in_the_donor_at_rest(env):
    for seed in range(3):
        env.reset(seed=seed)
        state = env.state
        for _ in range(250):  # one second with the arm holding still
            mujoco.mj_step(state.scene.model, state.data)
        grains = state.data.qpos[state.scene.grain_qpos[:, :3]]
        assert grains_in_box(grains, state.env.donor, DONOR_HALF, DONOR_WALL).all()
        assert np.abs(state.data.qvel[state.scene.grain_dof[:, :3]]).max() < 0.05


def test_a_pile_at_rest_falls_asleep_where_it_lies_and_the_containers_are_where_d_says(env):
    for seed in range(3):
        env.reset(seed=seed)
        state = env.state
        model, data = state.scene.model, state.data
        for body, pose in ((state.scene.donor_body, state.env.donor),
                           (state.scene.receiver_body, state.env.receiver)):
            assert np.allclose(data.xpos[body][:2], pose[:2])
            assert np.isclose(np.arctan2(data.xmat[body][3], data.xmat[body][0]), pose[2])
        before = data.qpos[state.scene.grain_qpos[:, :3]].copy()
        for _ in range(100):
            mujoco.mj_step(model, data)
        assert data.ntree_awake == 1  # the arm, which never sleeps; every grain is asleep
        assert np.abs(data.qpos[state.scene.grain_qpos[:, :3]] - before).max() < 0.002


def test_envs_place_containers_in_their_own_models():
    a, b = ScoopEnv(grain_counts=(260,)), ScoopEnv(grain_counts=(260,))
    a.reset(seed=1)
    b.reset(seed=2)
    assert a.state.scene.model is not b.state.scene.model
    assert not np.allclose(a.state.env.donor, b.state.env.donor)
    for env in (a, b):
        assert np.allclose(env.state.data.xpos[env.state.scene.donor_body][:2],
                           env.state.env.donor[:2])
        assert np.allclose(env.state.scene.model.body_pos[env.state.scene.donor_body][:2],
                           env.state.env.donor[:2])
    a.close()
    b.close()


SEEDS_IN_BAND = range(6)
PLAIN_PHYSICS = dataclasses.asdict(PLAIN)  # the env's kwargs of the same names


def test_default_physics_keeps_the_masses_within_the_plain_physics_band():
    """Sleeping grains and the shorter CG solve change trajectories, not the physics: over the
    same reset seeds, the mean masses with the defaults and with the plain physics (every grain
    simulated at every step, 30 CG iterations, tolerance 1e-6) agree within a band of about one
    standard deviation of a single scoop (7 g delivered, 3 g spilled; see
    ``benchmarks/scoop_physics.py``), and every certificate holds in both."""
    masses = {}
    for name, physics in (("plain", PLAIN_PHYSICS), ("default", {})):
        env = ScoopEnv(**physics)
        rows = []
        for seed in SEEDS_IN_BAND:
            env.reset(seed=seed)
            info = env.step(POSE)[4]
            assert info["certificate"], (name, seed, info)
            rows.append([info["mass_scooped"], info["mass_delivered"], info["mass_spilled"]])
        env.close()
        masses[name] = np.array(rows)
    difference = masses["default"].mean(axis=0) - masses["plain"].mean(axis=0)
    assert np.all(np.abs(difference) <= [8.0, 7.0, 3.0]), difference
    assert masses["default"][:, 1].min() >= 10  # nothing frozen in the scoop: every scoop delivers


def test_the_guarantee_names_the_physics_so_a_store_of_other_physics_is_refused(tmp_path):
    from vlb_gym.verify.campaign import Campaign, CampaignConfig
    from vlb_gym.verify.store import CampaignStore, StoreError

    def plan(physics):
        config = CampaignConfig("VLB-Scoop-v0", "scoop_repeatedly", 2, epsilon=0.05,
                                env_kwargs=physics)
        with Campaign(config) as campaign:
            return campaign.plan

    default, plain = plan({}), plan(PLAIN_PHYSICS)
    assert default.sampling_distribution.endswith(
        "simulated with 4 ms steps, CG capped at 20 iterations (tolerance 1e-05), island "
        "sleeping under 0.03 m/s")
    assert "CG capped at 30 iterations (tolerance 1e-06), no sleeping" in \
        plain.sampling_distribution
    store = CampaignStore(tmp_path / "s.db")
    try:
        store.start(dataclasses.replace(plain, env_kwargs={}))  # before the defaults changed
        with pytest.raises(StoreError, match="sampling_distribution"):
            store.start(default)
    finally:
        store.close()


def test_physics_arguments_reach_the_model():
    env = ScoopEnv(sleep_tolerance=0.0, solver_iterations=7, solver_tolerance=1e-4)
    env.reset(seed=0)
    opt = env.state.scene.model.opt
    assert (opt.iterations, opt.tolerance, opt.sleep_tolerance) == (7, 1e-4, 0.0)
    assert not opt.enableflags & int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    env.close()
    env = ScoopEnv()
    env.reset(seed=0)
    opt = env.state.scene.model.opt
    assert (opt.iterations, opt.tolerance, opt.sleep_tolerance) == (20, 1e-5, 0.03)
    assert opt.enableflags & int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    env.close()


def test_perception_locates_containers_from_a_depth_image(env):
    for seed in range(6):
        env.reset(seed=seed)
        state = env.state
        kin = Kinematics(state.scene, "flange")
        q = kin.solve(POSE[:3].astype(float), rpy_matrix(*POSE[3:]),
                      state.data.qpos[state.scene.arm_qpos])
        state.data.qpos[state.scene.arm_qpos] = q
        import mujoco
        mujoco.mj_forward(state.scene.model, state.data)
        camera = DepthCamera(state.scene)
        estimate = locate_containers(camera.points(state.data))
        camera.close()
        for seen, truth in ((estimate.donor, state.env.donor),
                            (estimate.receiver, state.env.receiver)):
            assert np.linalg.norm(seen.center - truth[:2]) < 0.005  # stated error: 5 mm
            yaw_error = (seen.yaw - truth[2] + np.pi / 4) % (np.pi / 2) - np.pi / 4
            assert abs(yaw_error) < np.radians(2)  # and 2 degrees (squares: modulo 90)


def test_a_scoop_moves_mass_from_donor_to_receiver(env):
    obs, info = env.reset(seed=3)
    state = env.state
    total = state.env.n_grains
    obs, reward, terminated, truncated, info = env.step(POSE)
    assert info["admissible"] and info["certificate"], info
    assert info["certificates"] == {"pose": True, "delivered": True}
    assert info["mass_delivered"] >= 10 and reward == pytest.approx(info["mass_delivered"] / 1000)
    grains = state.data.qpos[state.scene.grain_qpos[:, :3]]
    delivered = grains_in_box(grains, state.env.receiver, RECEIVER_HALF, RECEIVER_WALL)
    kept = grains_in_box(grains, state.env.donor, DONOR_HALF, DONOR_WALL)
    scoop = grains_in_scoop(grains, state.data, state.scene.model.site("scoop").id)
    assert delivered.sum() * GRAIN_MASS * 1000 == pytest.approx(info["mass_delivered"])
    assert delivered.sum() + kept.sum() + scoop.sum() + round(
        info["mass_spilled"] / (GRAIN_MASS * 1000)) == total
    assert np.allclose(obs[:3], POSE[:3], atol=0.01)
    assert info["sim_seconds"] > 5  # the motion was simulated, not teleported


def test_scoop_is_deterministic_for_a_seed():
    a, b = ScoopEnv(), ScoopEnv()
    a.reset(seed=11)
    b.reset(seed=11)
    out_a, out_b = a.step(POSE), b.step(POSE)
    assert np.array_equal(out_a[0], out_b[0])
    assert out_a[4]["mass_delivered"] == out_b[4]["mass_delivered"]
    a.close()
    b.close()


@pytest.mark.parametrize("pose, reason", [
    ((0.5, 0.075, 0.55, np.pi, -0.35, 0.0), "not fully in the camera's view"),
    ((0.95, 0.9, 1.1, np.pi, 0.0, 0.0), "not reachable"),
])
def test_bad_sensing_poses_fail_admissibility_not_the_env(pose, reason, env):
    env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(np.array(pose, dtype=np.float32))
    assert not info["admissible"] and not info["certificate"]
    assert reason in info["reason"]


def test_out_of_view_behavior_is_reported_with_failures(write_behavior):
    doc = {"name": "looks_away", "env": "VLB-Scoop-v0",
           "nodes": [{"id": "scoop", "primitive": "scoop"}],
           "start": {"node": "scoop", "param": "(0.5, 0.075, 0.55, 3.14159, -0.35, 0.0)"},
           "terminals": ["scoop"]}
    env = RobustnessWrapper(gym.make("VLB-Scoop-v0"))
    policy = load_behavior(str(write_behavior(doc)), env)
    result = run_episode(env, policy, seed=0)
    assert result.rho == -1 and "camera's view" in result.reason
    env.close()


def test_depth_rendering():
    env = gym.make("VLB-Scoop-v0", render_mode="depth_array")
    env.reset(seed=0)
    depth = env.render()
    assert depth.dtype == np.float32 and depth.ndim == 2
    assert 0.3 < np.median(depth) < 0.7  # the table, about half a metre below the camera
    env.close()


def test_mujoco_imported_first_without_a_display_says_what_to_do():
    """MuJoCo imported before vlb_gym picks GLFW; rendering then fails with the fix named."""
    code = ("import mujoco, gymnasium as gym, vlb_gym\n"
            "env = gym.make('VLB-Scoop-v0', render_mode='rgb_array')\n"
            "env.reset(seed=0)\n"
            "try:\n    env.render()\nexcept RuntimeError as exc:\n    print(exc)\n")
    environ = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "DISPLAY",
                                                                "PYOPENGL_PLATFORM")}
    out = subprocess.run([sys.executable, "-c", code], env=environ, capture_output=True,
                         text=True, timeout=120)
    assert "set MUJOCO_GL=egl (or osmesa) or import vlb_gym first" in out.stdout, out.stderr


def test_the_shipped_behavior_senses_from_the_envs_pose():
    """The sensing pose is the env's knowledge: the shipped behavior's variable and the search
    space's constant are the env's one value, written out."""
    import json

    from vlb_gym.envs.scoop.env import SENSING_POSE_EXPRESSION

    shipped = json.loads((Path(vlb_gym.__file__).parent / "behaviors" /
                          "scoop_repeatedly.json").read_text())
    assert shipped["variables"]["sensing_pose"] == SENSING_POSE_EXPRESSION


@pytest.mark.parametrize("arguments", [["--workers", "0"], ["--seeds", "1"], ["--seeds", "-5"]])
def test_the_physics_benchmark_refuses_counts_it_cannot_run_in_one_line(arguments):
    """``benchmarks/scoop_physics.py`` refuses a worker count below 1 and fewer than 2 seeds
    (no spread) before any scoop runs: exit 2, argparse's error line, no traceback."""
    script = Path(__file__).resolve().parents[1] / "benchmarks" / "scoop_physics.py"
    out = subprocess.run([sys.executable, str(script), *arguments], capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 2
    assert out.stderr.strip().splitlines()[-1] == (
        "scoop_physics.py: error: --seeds takes 2 or more (a spread needs two), --workers 1 or "
        "more")
    assert "Traceback" not in out.stderr and out.stdout == ""
