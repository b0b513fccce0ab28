"""The reverse Cuthill-McKee ordering of a small symmetric pattern, in NumPy.

The banded kernel renumbers the DOFs so that the effective stiffness fits a narrow band
(Cuthill & McKee 1969; reversed, George 1971).  The models it carries have tens to a few
hundred DOFs with dense matrices, so a breadth-first search on the boolean pattern costs
microseconds; SciPy's version would load ``scipy.sparse`` and ``scipy.sparse.csgraph``
(0.2-0.4 s and about 10 MB) into every run for it.

Each connected component starts from a pseudo-peripheral node (George & Liu 1979): from
the lowest-degree node, a breadth-first search's last level gives the next start (its
lowest-degree node) while the search's depth grows.  Neighbours join the queue in
increasing degree (ties by index), and the whole order is reversed.
"""

from __future__ import annotations

import numpy as np

__all__ = ["band_half_width", "reverse_cuthill_mckee"]


def _levels(neighbours: list[np.ndarray], start: int, allowed: np.ndarray) -> list[list[int]]:
    """Breadth-first levels from ``start`` within the nodes ``allowed``."""
    seen = {start}
    levels = [[start]]
    while True:
        following = sorted(
            {int(j) for i in levels[-1] for j in neighbours[i] if allowed[j] and j not in seen}
        )
        if not following:
            return levels
        seen.update(following)
        levels.append(following)


def _peripheral(neighbours: list[np.ndarray], degree: np.ndarray, start: int, allowed) -> int:
    depth = len(_levels(neighbours, start, allowed))
    while True:
        last = _levels(neighbours, start, allowed)[-1]
        candidate = min(last, key=lambda node: (degree[node], node))
        candidate_depth = len(_levels(neighbours, candidate, allowed))
        if candidate_depth <= depth:
            return start
        start, depth = candidate, candidate_depth


def reverse_cuthill_mckee(pattern: np.ndarray) -> np.ndarray:
    """The reverse Cuthill-McKee order of the symmetric boolean ``pattern`` (n x n).

    Returns
    -------
    numpy.ndarray
        A permutation of 0 .. n-1: row ``k`` of the reordered matrix is row
        ``order[k]`` of the original.
    """
    pattern = np.asarray(pattern, dtype=bool)
    n = pattern.shape[0]
    links = pattern | pattern.T
    np.fill_diagonal(links, False)
    neighbours = [np.flatnonzero(row) for row in links]
    degree = links.sum(axis=1)
    unvisited = np.ones(n, dtype=bool)
    order: list[int] = []
    while unvisited.any():
        candidates = np.flatnonzero(unvisited)
        first = int(candidates[np.argmin(degree[candidates])])
        start = _peripheral(neighbours, degree, first, unvisited)
        queue = [start]
        unvisited[start] = False
        head = 0
        while head < len(queue):
            node = queue[head]
            head += 1
            fresh = [int(j) for j in neighbours[node] if unvisited[j]]
            fresh.sort(key=lambda j: (degree[j], j))
            for j in fresh:
                unvisited[j] = False
            queue.extend(fresh)
        order.extend(queue)
    return np.array(order[::-1], dtype=int)


def band_half_width(pattern: np.ndarray, order: np.ndarray) -> int:
    """Largest |i - j| over the nonzeros of ``pattern`` reordered by ``order``."""
    rows, cols = np.nonzero(np.asarray(pattern, dtype=bool)[np.ix_(order, order)])
    return int(np.max(np.abs(rows - cols))) if rows.size else 0
