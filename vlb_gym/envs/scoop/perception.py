"""Locating the containers from the wrist camera's depth image (never from simulator state).

Pipeline: depth pixels -> points in the camera frame (pinhole model from the camera's field of
view) -> world frame (the robot knows its camera pose from its joint angles) -> points above the
table rasterised on a grid -> holes filled, connected regions labelled -> the two largest regions
are the containers, told apart by area -> each one's centre and yaw from the smallest rectangle
enclosing its rim (the points near its top height), over candidate angles; the donor's bed
height from the points inside it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

CELL = 0.004  # m, raster resolution
MIN_HEIGHT = 0.02  # m above the table: container walls and grains, not floors or the table
MAX_HEIGHT = 0.12  # m: anything higher is the robot itself
NEAR_CLIP = 0.12  # m: closer points are the robot's own tool
RIM = 0.008  # m below a container's top height that still counts as its rim
AREA_SPLIT = 0.015  # m^2: donor (outer 0.14 x 0.14) above, receiver (0.10 x 0.10) below


class PerceptionFailure(RuntimeError):
    """The image does not show two containers."""


@dataclass(frozen=True)
class Container:
    """A container as seen: centre (x, y), yaw in [-pi/4, pi/4), footprint area, top height."""

    center: np.ndarray
    yaw: float
    area: float
    height: float


@dataclass(frozen=True)
class Estimate:
    donor: Container
    receiver: Container
    bed_height: float  # median height of the donor's contents (m above the table)


def depth_to_points(depth: np.ndarray, fovy_deg: float, cam_pos: np.ndarray,
                    cam_mat: np.ndarray) -> np.ndarray:
    """World points of a MuJoCo depth image (distance along the view axis, in metres)."""
    height, width = depth.shape
    focal = 0.5 * height / np.tan(np.radians(fovy_deg) / 2)
    v, u = np.mgrid[:height, :width]
    keep = (depth > NEAR_CLIP) & (depth < 3.0)
    z = depth[keep]
    x = (u[keep] + 0.5 - width / 2) * z / focal
    y = -(v[keep] + 0.5 - height / 2) * z / focal
    camera = np.column_stack([x, y, -z])  # MuJoCo cameras look along their -z, y up
    return camera @ cam_mat.T + cam_pos


def _rectangle(points: np.ndarray) -> tuple[np.ndarray, float, float]:
    """Centre, yaw in [-pi/4, pi/4) and area of the smallest enclosing rectangle (1 deg steps)."""
    best = None
    for angle in np.radians(np.arange(-45, 45)):
        c, s = np.cos(angle), np.sin(angle)
        local = points @ np.array([[c, -s], [s, c]])  # rotate by -angle
        low, high = local.min(axis=0), local.max(axis=0)
        area = float(np.prod(high - low))
        if best is None or area < best[2]:
            mid = (low + high) / 2
            best = (np.array([c * mid[0] - s * mid[1], s * mid[0] + c * mid[1]]), angle, area)
    return best


def locate_containers(points: np.ndarray) -> Estimate:
    """Donor and receiver from world points of the scene."""
    above = points[(points[:, 2] > MIN_HEIGHT) & (points[:, 2] < MAX_HEIGHT)]
    if len(above) < 50:
        raise PerceptionFailure("no container in view")
    origin = above[:, :2].min(axis=0) - 4 * CELL  # a margin, so closing does not erode edges
    idx = np.floor((above[:, :2] - origin) / CELL).astype(int)
    grid = np.zeros(idx.max(axis=0) + 5, dtype=bool)
    grid[idx[:, 0], idx[:, 1]] = True
    grid = ndimage.binary_closing(grid, iterations=2)
    grid = ndimage.binary_fill_holes(grid)
    labels, count = ndimage.label(grid)
    if count < 2:
        raise PerceptionFailure(f"{count} container(s) in view, need 2")
    areas = ndimage.sum_labels(grid, labels, np.arange(1, count + 1)) * CELL**2
    order = np.argsort(areas)[::-1][:2]
    found = []
    for label in order + 1:
        member = above[labels[idx[:, 0], idx[:, 1]] == label]
        top = float(np.percentile(member[:, 2], 95))
        rim = member[member[:, 2] > top - RIM]  # the walls' top faces outline the container
        center, yaw, _ = _rectangle(rim[:, :2])
        area = float(np.sum(labels == label)) * CELL**2
        found.append(Container(center, yaw, area, top))
    big, small = sorted(found, key=lambda c: -c.area)
    if big.area < AREA_SPLIT or small.area > AREA_SPLIT:
        raise PerceptionFailure(f"container footprints {big.area:.4f} and {small.area:.4f} m^2 "
                                "do not match a donor and a receiver")
    inside = np.abs((points[:, :2] - big.center) @ _rot(big.yaw)) < 0.045
    inner = points[inside.all(axis=1)]
    bed = float(np.median(inner[:, 2])) if len(inner) else 0.0
    return Estimate(big, small, bed)


def _rot(yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s], [s, c]])
