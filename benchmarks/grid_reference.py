"""The paper's exploration study hand-coded: the yardstick for the framework's grid speed.

What a researcher would write without vlb-gym, in plain Python with numpy: sample a 10x10 world
(30 obstacles, 3 goals) and a start uniformly from the allowable space, then run Behavior 2 (sense
and go to the explored free cell with the most unexplored neighbours until a goal is seen, then
goal <-> start five times), each move a breadth-first plan tracked step by step by the same PD
law on the single integrator (20 Hz, 2 cells/s, hold 24 steps), checking every step for a
collision and every move for ending in its target cell. An episode succeeds when every move did.
The same study as ``vlb verify VLB-GridExplore-v0 --behavior find_goal_and_oscillate``, not the
same random numbers.

    python benchmarks/grid_reference.py [--episodes 2100]
"""

from __future__ import annotations

import argparse
import math
import time
from collections import deque

import numpy as np

SIZE, OBSTACLES, GOALS, TRIPS = 10, 30, 3, 5
EMPTY, OBSTACLE, UNEXPLORED, GOAL = 0, 1, 2, 3
DT, SPEED, KP, KD, SETTLE = 0.05, 2.0, 8.0, 0.1, 24
HALF = SIZE / 2


def cell_of(p: np.ndarray) -> tuple[int, int]:
    return (min(max(math.floor(p[0] + HALF), 0), SIZE - 1),
            min(max(math.floor(p[1] + HALF), 0), SIZE - 1))


def neighbours(cell: tuple[int, int]) -> list[tuple[int, int]]:
    i, j = cell
    return [(a, b) for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1))
            if 0 <= a < SIZE and 0 <= b < SIZE]


def bfs(truth: np.ndarray, target: tuple[int, int]) -> dict[tuple[int, int], int]:
    """Moves from every free cell that can reach ``target``."""
    dist = {target: 0}
    queue = deque([target])
    while queue:
        cell = queue.popleft()
        for n in neighbours(cell):
            if n not in dist and truth[n] != OBSTACLE:
                dist[n] = dist[cell] + 1
                queue.append(n)
    return dist


def sample(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    while True:
        cells = rng.choice(SIZE * SIZE, OBSTACLES + GOALS, replace=False)
        truth = np.zeros(SIZE * SIZE, dtype=np.int8)
        truth[cells[:OBSTACLES]] = OBSTACLE
        truth[cells[OBSTACLES:]] = GOAL
        truth = truth.reshape(SIZE, SIZE)
        position = rng.uniform(-HALF, HALF, 2)
        start = cell_of(position)
        if truth[start] == EMPTY and any(truth[c] == GOAL for c in bfs(truth, start)):
            return truth, position


def navigate(truth: np.ndarray, position: np.ndarray, target: tuple[int, int]
             ) -> tuple[np.ndarray, bool]:
    """Plan to ``target`` and track the plan; the final position and whether it ended there."""
    dist = bfs(truth, target)
    cell = cell_of(position)
    if cell not in dist:
        return position, False
    path = [cell]
    while dist[path[-1]] > 0:
        path.append(min((n for n in neighbours(path[-1]) if n in dist), key=dist.__getitem__))
    points = [position] + [np.array([i - HALF + 0.5, j - HALF + 0.5]) for i, j in path[1:] or path]
    legs = [float(np.linalg.norm(b - a)) for a, b in zip(points, points[1:])]
    length = sum(legs)
    p = position.copy()
    previous_error = None
    for k in range(math.ceil(length / (SPEED * DT)) + SETTLE):
        s = min((k + 1) * SPEED * DT, length)
        leg = 0
        while leg < len(legs) - 1 and s > legs[leg]:  # find the reference's leg
            s -= legs[leg]
            leg += 1
        fraction = s / legs[leg] if legs[leg] else 1.0
        reference = points[leg] + fraction * (points[leg + 1] - points[leg])
        error = reference - p
        if previous_error is None:  # from rest: no derivative kick
            previous_error = error
        p = p + DT * KP * error + KD * (error - previous_error)
        previous_error = error
        if not (-HALF <= p[0] < HALF and -HALF <= p[1] < HALF) or truth[cell_of(p)] == OBSTACLE:
            return p, False
    return p, cell_of(p) == target


def episode(rng: np.random.Generator) -> tuple[bool, int]:
    """One episode of Behavior 2: whether it succeeded, and the primitives it ran."""
    truth, position = sample(rng)
    labels = np.full((SIZE, SIZE), UNEXPLORED, dtype=np.int8)
    home = cell_of(position)
    primitives = 0
    while True:  # Behavior 1: sense, then go where the most is unexplored
        here = cell_of(position)
        for c in [here] + neighbours(here):
            labels[c] = truth[c]
        primitives += 1
        if (labels == GOAL).any():
            break
        frontier = [(i, j) for i in range(SIZE) for j in range(SIZE)
                    if labels[i, j] not in (UNEXPLORED, OBSTACLE)]
        target = max(frontier, key=lambda c: sum(labels[n] == UNEXPLORED for n in neighbours(c)))
        position, ok = navigate(truth, position, target)
        primitives += 1
        if not ok:
            return False, primitives
    goal = tuple(int(v) for v in np.argwhere(labels == GOAL)[0])
    for _ in range(TRIPS):
        for target in (goal, home):
            position, ok = navigate(truth, position, target)
            primitives += 1
            if not ok:
                return False, primitives
    return True, primitives


def run(episodes: int, seed: int = 0) -> tuple[int, float]:
    """Successes of ``episodes`` episodes, and the mean primitives per episode."""
    rng = np.random.default_rng(seed)
    results = [episode(rng) for _ in range(episodes)]
    return sum(ok for ok, _ in results), sum(n for _, n in results) / episodes


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=int, default=2100)
    args = parser.parse_args()
    started = time.perf_counter()
    successes, primitives = run(args.episodes)
    seconds = time.perf_counter() - started
    print(f"hand-coded reference: {successes}/{args.episodes} successes, {primitives:.1f} "
          f"primitives per episode, {seconds:.2f} s -> {args.episodes / seconds:.0f} episodes/s")


if __name__ == "__main__":
    main()
