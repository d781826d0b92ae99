"""The navigate controller: an MDP planner on the grid tracked by a PD controller.

Planning. The grid MDP has one state per free cell, the four moves as actions, cost 1 per move and
the target absorbing. Its optimal cost-to-go is the fixed point of value iteration
``V(s) = 1 + min_{s'} V(s')``, ``V(target) = 0``; for this deterministic unit-cost MDP that fixed
point is the breadth-first distance to the target, which :func:`cost_to_go` computes in one sweep
(tests check it against plain value iteration). The greedy policy descends ``V``.

Tracking. The agent is a single integrator ``p_{k+1} = p_k + dt (u_k + sigma w_k)`` with
``w_k ~ N(0, I)`` (``sigma`` = ``action_noise``, a velocity disturbance in cells/s). A reference
moves along the planned cell centres at ``SPEED`` and then holds at the target for ``SETTLE``
steps; the PD law ``u_k = KP e_k + KD (e_k - e_{k-1}) / dt`` with ``e = r - p`` tracks it. The
closed loop is linear, so the whole trajectory is one IIR filter (:func:`scipy.signal.lfilter`).

Navigate calls :func:`waypoints`, :func:`steps` and :func:`rollout` (and :func:`cost_to_go`);
:mod:`.compiled` has the same four functions compiled with Numba, giving the same numbers.
"""

from __future__ import annotations

from collections import deque
from functools import lru_cache

import numpy as np

DT = 0.05  # s per integration step
SPEED = 2.0  # cells per second along the plan
KP = 8.0  # 1/s
KD = 0.1  # dimensionless (derivative gain times 1/dt folded into the discrete law)
SETTLE = 24  # steps holding the target at the end
UNREACHABLE = np.iinfo(np.int32).max

# closed loop: p_{k+1} = A1 p_k + A2 p_{k-1} + B0 r_k + B1 r_{k-1} + dt sigma w_k
A1, A2 = 1.0 - DT * KP - KD, KD
B0, B1 = DT * KP + KD, -KD
_NUM, _DEN = np.array([1.0]), np.array([1.0, -A1, -A2])


@lru_cache(maxsize=8)
def _neighbours(size: int) -> tuple[tuple[int, ...], ...]:
    """Flat-index 4-neighbours of every cell, in the fixed order +x, -x, +y, -y."""
    out = []
    for k in range(size * size):
        i, j = divmod(k, size)
        cand = ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1))
        out.append(tuple(a * size + b for a, b in cand if 0 <= a < size and 0 <= b < size))
    return tuple(out)


def cost_to_go(passable: np.ndarray, target: tuple[int, int]) -> np.ndarray:
    """Optimal number of moves from every cell to ``target`` (UNREACHABLE where none)."""
    size = passable.shape[0]
    free = passable.ravel().tolist()
    dist = [UNREACHABLE] * (size * size)
    goal = target[0] * size + target[1]
    if not free[goal]:
        return np.full((size, size), UNREACHABLE, dtype=np.int32)
    neighbours = _neighbours(size)
    dist[goal] = 0
    queue = deque([goal])
    while queue:
        k = queue.popleft()
        step = dist[k] + 1
        for m in neighbours[k]:
            if free[m] and dist[m] == UNREACHABLE:
                dist[m] = step
                queue.append(m)
    return np.array(dist, dtype=np.int32).reshape(size, size)


def greedy_path(dist: np.ndarray, start: tuple[int, int]) -> list[tuple[int, int]]:
    """Cells from ``start`` to the target, descending the cost-to-go (first best neighbour)."""
    size = dist.shape[0]
    flat = dist.ravel().tolist()
    k = start[0] * size + start[1]
    if flat[k] == UNREACHABLE:
        raise ValueError(f"cell {start} cannot reach the target")
    neighbours = _neighbours(size)
    path = [k]
    while flat[k] > 0:
        k = min(neighbours[k], key=flat.__getitem__)
        path.append(k)
    return [divmod(k, size) for k in path]


def waypoints(dist: np.ndarray, start: tuple[int, int]) -> np.ndarray:
    """Centres of the cells after ``start`` on the greedy path (the target's alone when
    ``start`` is the target), shape (n, 2)."""
    path = greedy_path(dist, start)
    centres = np.array(path[1:] or path, dtype=float)
    centres -= dist.shape[0] / 2 - 0.5
    return centres


def _arc_lengths(start: np.ndarray, waypoints: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The points ``start, *waypoints`` and the path length up to each."""
    points = np.concatenate([start[None], waypoints])
    step = np.diff(points, axis=0)
    cumulative = np.zeros(len(points))
    np.cumsum(np.hypot(step[:, 0], step[:, 1]), out=cumulative[1:])
    return points, cumulative


def _count(length: float) -> int:
    """Steps of a reference of ``length``: moving at SPEED, then SETTLE steps holding."""
    return int(np.ceil(length / (SPEED * DT))) + SETTLE


def steps(start: np.ndarray, waypoints: np.ndarray) -> int:
    """Number of steps of the reference from ``start`` through ``waypoints``."""
    return _count(_arc_lengths(start, waypoints)[1][-1])


def rollout(start: np.ndarray, waypoints: np.ndarray, noise: np.ndarray | None,
            blocked: np.ndarray) -> tuple[np.ndarray, int]:
    """The closed-loop trajectory from rest at ``start`` through ``waypoints`` (``noise`` of
    shape ``(steps(start, waypoints), 2)`` or None), and its first collision (-1: none)."""
    trajectory = track(start, reference(start, waypoints), noise)
    return trajectory, first_collision(trajectory, blocked)


def reference(start: np.ndarray, waypoints: np.ndarray) -> np.ndarray:
    """Reference positions, one per step: along ``start -> waypoints`` at SPEED, then hold."""
    points, cumulative = _arc_lengths(start, waypoints)
    length = cumulative[-1]
    s = np.arange(1, _count(length) + 1) * (SPEED * DT)
    np.minimum(s, length, out=s)
    return np.column_stack([np.interp(s, cumulative, points[:, 0]),
                            np.interp(s, cumulative, points[:, 1])])


def first_collision(trajectory: np.ndarray, blocked: np.ndarray) -> int:
    """Index of the first point in a blocked cell or off the grid, or -1.

    ``blocked`` is the obstacle mask padded with a blocked border (see :func:`padded_blocked`).
    """
    size = blocked.shape[0] - 2
    # +1 shifts into the padded frame; anything off the grid truncates or clips onto the border
    cells = np.clip((trajectory + (size / 2 + 1)).astype(np.intp), 0, size + 1)
    hits = blocked[cells[:, 0], cells[:, 1]]
    return int(hits.argmax()) if hits.any() else -1


def padded_blocked(passable: np.ndarray) -> np.ndarray:
    """The obstacle mask with a one-cell blocked border (the grid's edge)."""
    rows, cols = passable.shape
    blocked = np.ones((rows + 2, cols + 2), dtype=bool)  # np.pad: 5x the time, once per reset
    np.logical_not(passable, out=blocked[1:-1, 1:-1])
    return blocked


def track(start: np.ndarray, ref: np.ndarray, noise: np.ndarray | None) -> np.ndarray:
    """Closed-loop positions p_1..p_K tracking ``ref`` (r_0..r_{K-1}) from rest at ``start``.

    ``noise`` is the per-step displacement ``dt sigma w_k`` (shape like ``ref``) or None.
    """
    drive = (B0 + B1) * ref  # B1 r_{k-1}, with r_{-1} = r_0 (no derivative kick) ...
    drive[1:] -= B1 * np.diff(ref, axis=0)  # ... and B1 (r_{k-1} - r_k) for k >= 1
    if noise is not None:
        drive += noise
    # transposed direct form II state for p_0 = p_{-1} = start (at rest)
    zi = np.array([(A1 + A2) * start, A2 * start])
    from scipy.signal import lfilter  # here: scipy.signal takes 0.4 s to import (it brings
    # scipy.stats), and with the extra `fast` the compiled rollout replaces this function
    return lfilter(_NUM, _DEN, drive, axis=0, zi=zi)[0]
