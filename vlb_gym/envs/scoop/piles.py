"""Settled grain piles, made once and shipped: episodes start from a snapshot, not from settling.

A pile is the grains' positions and orientations at rest in a donor centred at the origin with
yaw 0; at reset it is moved rigidly with the donor. ``python -m vlb_gym.envs.scoop.piles`` remakes
the shipped file after a change to the scene.
"""

from __future__ import annotations

from functools import lru_cache
from importlib import resources
from pathlib import Path

import mujoco
import numpy as np

from .scene import DONOR_HALF, FLOOR, GRAIN_RADIUS, PLAIN, build_scene
from .types import PILE_STYLES

GRAIN_COUNTS = (230, 260, 290)
VARIANTS = 2
PILE_FILE = "scoop_piles.npz"


def _initial(style: str, n: int, rng: np.random.Generator) -> np.ndarray:
    pitch = 2 * GRAIN_RADIUS + 0.0012
    if style == "heaped":  # a narrow column that collapses into a heap
        per, offset = 5, 2.0
    else:
        per, offset = 9, 4.0
    k = np.arange(n)
    pos = np.column_stack([(k % per - offset) * pitch, ((k // per) % per - offset) * pitch,
                           FLOOR + GRAIN_RADIUS + 0.002 + (k // (per * per)) * pitch])
    return pos + rng.normal(0, 0.001, pos.shape) * [1, 1, 0]


def settle(style: str, n: int, seed: int) -> np.ndarray:
    """A settled pile: (n, 7) positions and quaternions relative to the donor frame."""
    # no sleeping: grains asleep in the tilted donor would not feel the gravity turn back
    scene = build_scene(n).own_copy(PLAIN)
    model = scene.model
    scene.place_container(scene.donor_body, 0.0, 0.0, 0.0)
    scene.place_container(scene.receiver_body, 0.0, 0.6, 0.0)
    data = mujoco.MjData(model)
    data.qpos[scene.arm_qpos] = [0.0, -2.6, 2.4, -1.5, -1.57, 0.0]  # arm folded out of the way
    data.ctrl[:6] = data.qpos[scene.arm_qpos]
    rng = np.random.default_rng(seed)
    data.qpos[scene.grain_qpos[:, :3]] = _initial(style, n, rng)
    data.qpos[scene.grain_qpos[:, 3]] = 1.0
    gravity = model.opt.gravity.copy()
    if style == "tilted":  # settle in a donor tilted by 25 degrees, then stand it up
        angle = np.radians(25) * rng.choice([-1, 1])
        model.opt.gravity[:] = 9.81 * np.array([np.sin(angle), 0.0, -np.cos(angle)])
    try:
        for _ in range(int(1.5 / model.opt.timestep)):
            mujoco.mj_step(model, data)
        model.opt.gravity[:] = gravity
        for _ in range(int(1.0 / model.opt.timestep)):
            mujoco.mj_step(model, data)
    finally:
        model.opt.gravity[:] = gravity
    pile = data.qpos[scene.grain_qpos].copy()
    inside = np.all(np.abs(pile[:, :2]) < DONOR_HALF, axis=1)
    if not inside.all():
        raise RuntimeError(f"{style} pile of {n}: {np.sum(~inside)} grains left the donor")
    return pile


def make_piles(path: Path) -> None:
    arrays = {}
    for n in GRAIN_COUNTS:
        for style in PILE_STYLES:
            for variant in range(VARIANTS):
                arrays[f"{style}_{n}_{variant}"] = settle(style, n, seed=1000 * n + variant)
                print(f"settled {style} pile of {n} grains, variant {variant}")
    np.savez_compressed(path, **arrays)


@lru_cache(maxsize=1)
def shipped_piles() -> dict[str, np.ndarray]:
    with (resources.files("vlb_gym.assets") / PILE_FILE).open("rb") as f:
        with np.load(f) as data:
            return {k: data[k] for k in data.files}


def pile(style: str, n: int, variant: int) -> np.ndarray:
    """The shipped pile, or a freshly settled one for a grain count that ships none."""
    key = f"{style}_{n}_{variant}"
    piles = shipped_piles()
    return piles[key] if key in piles else _settled(style, n, variant)


@lru_cache(maxsize=32)
def _settled(style: str, n: int, variant: int) -> np.ndarray:
    return settle(style, n, seed=1000 * n + variant)


if __name__ == "__main__":
    target = Path(__file__).resolve().parents[2] / "assets" / PILE_FILE
    make_piles(target)
    print(f"wrote {target}")
