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
"""

from __future__ import annotations

from collections import deque
from functools import lru_cache

import numpy as np
from scipy.signal import lfilter, lfiltic

DT = 0.05  # s per integration step
SPEED = 2.0  # cells per second along the plan
KP = 8.0  # 1/s
KD = 0.1  # dimensionless (derivative gain times 1/dt folded into the discrete law)
SETTLE = 24  # steps holding the target at the end
UNREACHABLE = np.iinfo(np.int32).max

# closed loop: p_{k+1} = A1 p_k + A2 p_{k-1} + B0 r_k + B1 r_{k-1} + dt sigma w_k
A1, A2 = 1.0 - DT * KP - KD, KD
B0, B1 = DT * KP + KD, -KD
_DEN = np.array([1.0, -A1, -A2])


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


def reference(start: np.ndarray, waypoints: np.ndarray) -> np.ndarray:
    """Reference positions, one per step: along ``start -> waypoints`` at SPEED, then hold."""
    points = np.vstack([start, waypoints])
    cumulative = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    steps = int(np.ceil(cumulative[-1] / (SPEED * DT))) + SETTLE
    s = np.minimum(np.arange(1, steps + 1) * (SPEED * DT), cumulative[-1])
    return np.column_stack([np.interp(s, cumulative, points[:, 0]),
                            np.interp(s, cumulative, points[:, 1])])


def track(start: np.ndarray, ref: np.ndarray, noise: np.ndarray | None) -> np.ndarray:
    """Closed-loop positions p_1..p_K tracking ``ref`` (r_0..r_{K-1}) from rest at ``start``.

    ``noise`` is the per-step displacement ``dt sigma w_k`` (shape like ``ref``) or None.
    """
    previous = np.vstack([ref[:1], ref[:-1]])  # r_{k-1}, with r_{-1} = r_0 (no derivative kick)
    drive = B0 * ref + B1 * previous
    if noise is not None:
        drive = drive + noise
    out = np.empty_like(ref)
    for axis in range(2):
        zi = lfiltic([1.0], _DEN, [start[axis], start[axis]])
        out[:, axis] = lfilter([1.0], _DEN, drive[:, axis], zi=zi)[0]
    return out
