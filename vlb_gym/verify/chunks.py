"""The tasks of a run on workers: indices cut into chunks as the workers take them."""

from __future__ import annotations

import collections
import itertools
from collections.abc import Iterable, Sequence, Sized


def count(indices: Sized) -> int:
    """How many indices there are, as a Python integer: ``len()`` past 2**63 - 1
    (``--episodes 10**20``) overflows, so a range's is computed from its ends and a collection
    with a ``size`` gives that."""
    size = getattr(indices, "size", None)
    if isinstance(size, int):
        return size
    if isinstance(indices, range):
        if indices.step > 0:
            return max(0, -(-(indices.stop - indices.start) // indices.step))
        return max(0, -(-(indices.start - indices.stop) // -indices.step))
    return len(indices)


def chunk_size(count: int, workers: int) -> int:
    """Indices per task: as :class:`multiprocessing.pool.Pool` campaigns always had it."""
    return max(1, min(64, count // (workers * 16)))


class ChunkQueue:
    """The tasks of a run: ``count`` indices from ``indices`` cut into chunks of
    :func:`chunk_size` as they are taken, shrinking towards the end (at most an eighth of what
    is left per worker, down to one index) so that workers finish together; chunks given back
    (a dead worker's) come first. Cut lazily, so memory does not grow with the count."""

    def __init__(self, indices: Iterable[int], count: int, workers: int):
        self._source = iter(indices)
        self._left, self._workers = count, workers
        self._size = chunk_size(count, workers)
        self._back: collections.deque[list[int]] = collections.deque()

    def __bool__(self) -> bool:
        return bool(self._back) or self._left > 0

    def __getitem__(self, position: int) -> list[int]:
        """The next chunk (``position`` 0), left in the queue."""
        if position != 0:
            raise IndexError("only the next chunk can be seen")
        if not self._back:
            self._back.append(self._cut())
        return self._back[0]

    def popleft(self) -> list[int]:
        return self._back.popleft() if self._back else self._cut()

    def appendleft(self, chunk: list[int]) -> None:
        self._back.appendleft(chunk)

    def extendleft(self, chunks: Iterable[list[int]]) -> None:
        self._back.extendleft(chunks)

    def _cut(self) -> list[int]:
        if self._left <= 0:
            raise IndexError("no chunk left")
        step = max(1, min(self._size, -(-self._left // (4 * self._workers))))
        chunk = list(itertools.islice(self._source, step))
        self._left = self._left - len(chunk) if len(chunk) == step else 0
        return chunk


def chunks(indices: Sequence[int], workers: int) -> list[list[int]]:
    """Every chunk :class:`ChunkQueue` cuts ``indices`` into, in order."""
    queue = ChunkQueue(indices, count(indices), workers)
    out = []
    while queue:
        out.append(queue.popleft())
    return out
