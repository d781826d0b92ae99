"""The navigate controller compiled with Numba (extra ``fast``): :mod:`.planner`'s numbers, faster.

Each function here is the compiled twin of the function of the same name in :mod:`.planner` and
does the same floating-point operations in the same order: breadth-first search, the greedy
descent, ``np.interp``'s interpolation rule, ``scipy.signal.lfilter``'s transposed direct form II
recursion and the cell lookup of the collision check. Tests hold the two equal bit for bit.
The plain versions make about twenty numpy calls per navigate; these make one pass each.
Compiled code is cached on disk (``cache=True``), so only the first process ever compiles it;
importing the module loads it (about 0.1 s), so processes forked afterwards have it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .planner import A1, A2, B0, B1, DT, SETTLE, SPEED, UNREACHABLE

_STEP = SPEED * DT  # reference distance per step
_DRIVE = B0 + B1
_EMPTY = np.empty((0, 2))
_MOVES = ((1, 0), (-1, 0), (0, 1), (0, -1))  # the planner's neighbour order: +x, -x, +y, -y


@njit(cache=True)
def _cost_to_go(passable: np.ndarray, ti: int, tj: int) -> np.ndarray:
    size = passable.shape[0]
    dist = np.full((size, size), UNREACHABLE, dtype=np.int32)
    if not passable[ti, tj]:
        return dist
    queue = np.empty(size * size, dtype=np.int64)
    dist[ti, tj] = 0
    queue[0], head, tail = ti * size + tj, 0, 1
    while head < tail:
        i, j = divmod(queue[head], size)
        head += 1
        step = dist[i, j] + 1
        for di, dj in _MOVES:
            a, b = i + di, j + dj
            if 0 <= a < size and 0 <= b < size and passable[a, b] and dist[a, b] == UNREACHABLE:
                dist[a, b] = step
                queue[tail] = a * size + b
                tail += 1
    return dist


@njit(cache=True)
def _waypoints(dist: np.ndarray, i: int, j: int) -> np.ndarray:
    size = dist.shape[0]
    offset = size / 2 - 0.5
    moves = dist[i, j]
    out = np.empty((max(moves, 1), 2))
    out[0, 0], out[0, 1] = i - offset, j - offset  # the target's centre when moves == 0
    for k in range(moves):
        best_i, best_j, best = -1, -1, UNREACHABLE + 1
        for di, dj in _MOVES:  # the first neighbour of least cost-to-go
            a, b = i + di, j + dj
            if 0 <= a < size and 0 <= b < size and dist[a, b] < best:
                best_i, best_j, best = a, b, dist[a, b]
        i, j = best_i, best_j
        out[k, 0], out[k, 1] = i - offset, j - offset
    return out


@njit(cache=True)
def _arc_lengths(start: np.ndarray, waypoints: np.ndarray) -> np.ndarray:
    n = waypoints.shape[0]
    xp = np.zeros(n + 1)
    px, py = start[0], start[1]
    for m in range(n):
        xp[m + 1] = xp[m] + math.hypot(waypoints[m, 0] - px, waypoints[m, 1] - py)
        px, py = waypoints[m, 0], waypoints[m, 1]
    return xp


@njit(cache=True)
def _steps(xp: np.ndarray) -> int:
    return int(math.ceil(xp[-1] / _STEP)) + SETTLE


@njit(cache=True)
def _interp(x: float, xp: np.ndarray, fp: np.ndarray, j: int) -> float:
    """``np.interp(x, xp, fp)`` for ``xp[0] <= x``, with ``j`` the last index where xp <= x."""
    if j == xp.shape[0] - 1 or xp[j] == x:
        return fp[j]
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    value = slope * (x - xp[j]) + fp[j]
    if math.isnan(value):
        value = slope * (x - xp[j + 1]) + fp[j + 1]
        if math.isnan(value) and fp[j] == fp[j + 1]:
            value = fp[j]
    return value


@njit(cache=True)
def _rollout(start: np.ndarray, waypoints: np.ndarray, noise: np.ndarray,
             blocked: np.ndarray) -> tuple[np.ndarray, int]:
    xp = _arc_lengths(start, waypoints)
    n_points = xp.shape[0]
    fx, fy = np.empty(n_points), np.empty(n_points)
    fx[0], fy[0] = start[0], start[1]
    fx[1:], fy[1:] = waypoints[:, 0], waypoints[:, 1]
    length, count = xp[-1], _steps(xp)
    if noise.shape[0] not in (0, count) or noise.shape[1] != 2:
        raise ValueError("noise of shape other than (steps, 2)")
    size = blocked.shape[0] - 2
    shift = size / 2 + 1
    out = np.empty((count, 2))
    zx0, zx1 = (A1 + A2) * start[0], A2 * start[0]  # lfilter's state for p_0 = p_-1 = start
    zy0, zy1 = (A1 + A2) * start[1], A2 * start[1]
    rx = ry = 0.0
    j, hit = 0, -1
    for k in range(count):
        s = min((k + 1) * _STEP, length)
        while j < n_points - 1 and xp[j + 1] <= s:
            j += 1
        prev_x, prev_y = rx, ry
        rx, ry = _interp(s, xp, fx, j), _interp(s, xp, fy, j)
        ux, uy = _DRIVE * rx, _DRIVE * ry
        if k > 0:
            ux -= B1 * (rx - prev_x)
            uy -= B1 * (ry - prev_y)
        if noise.shape[0]:
            ux += noise[k, 0]
            uy += noise[k, 1]
        px, py = zx0 + 1.0 * ux, zy0 + 1.0 * uy  # lfilter with b = (1, 0, 0), a = (1, -A1, -A2)
        zx0, zx1 = zx1 + ux * 0.0 - px * -A1, ux * 0.0 - px * -A2
        zy0, zy1 = zy1 + uy * 0.0 - py * -A1, uy * 0.0 - py * -A2
        out[k, 0], out[k, 1] = px, py
        if hit < 0:
            ci = min(max(int(px + shift), 0), size + 1)
            cj = min(max(int(py + shift), 0), size + 1)
            if blocked[ci, cj]:
                hit = k
    return out, hit


def _cell(grid: np.ndarray, cell: tuple[int, int]) -> tuple[int, int]:
    """``cell``, checked to lie in ``grid`` (compiled code does not check its indices)."""
    i, j = cell
    if not (0 <= i < grid.shape[0] and 0 <= j < grid.shape[1]):
        raise IndexError(f"cell {cell} is outside the {grid.shape[0]}x{grid.shape[1]} grid")
    return i, j


def cost_to_go(passable: np.ndarray, target: tuple[int, int]) -> np.ndarray:
    """:func:`.planner.cost_to_go`, compiled."""
    return _cost_to_go(passable, *_cell(passable, target))


def waypoints(dist: np.ndarray, start: tuple[int, int]) -> np.ndarray:
    """:func:`.planner.waypoints`, compiled."""
    i, j = _cell(dist, start)
    if dist[i, j] == UNREACHABLE:
        raise ValueError(f"cell {start} cannot reach the target")
    return _waypoints(dist, i, j)


def steps(start: np.ndarray, waypoints: np.ndarray) -> int:
    """:func:`.planner.steps`, compiled."""
    return _steps(_arc_lengths(start, waypoints))


def rollout(start: np.ndarray, waypoints: np.ndarray, noise: np.ndarray | None,
            blocked: np.ndarray) -> tuple[np.ndarray, int]:
    """:func:`.planner.rollout`, compiled."""
    return _rollout(start, waypoints, _EMPTY if noise is None else noise, blocked)


def _load() -> None:
    """Load every function's machine code now (from the cache, or compiling it), so that
    processes forked after the import (campaign workers) start with it."""
    centres = waypoints(cost_to_go(np.ones((2, 2), dtype=bool), (0, 0)), (1, 1))
    steps(np.zeros(2), centres)
    rollout(np.zeros(2), centres, None, np.zeros((4, 4), dtype=bool))


_load()
