"""Shortest path lengths on a grid, by a search that shares no code with vwg's planners: the
experiments' yardstick ("path length relative to the optimal").

The graph is the free cells of a configuration space (a boolean mask of blocked cells, such as
``OccupancyGrid.inflate(radius)``), 8-connected with diagonal steps of √2 cells that do not cut a
blocked corner, the moves vwg's A* and JPS make; it is searched by SciPy's Dijkstra
(``scipy.sparse.csgraph.dijkstra``), so the figures it gives are an independent check of theirs.

    field = DistanceField(blocked, goal=(row, col))   # every cell's distance to the goal, in cells
    DistanceField(blocked, (row, col), within=5)        # to the nearest cell within 5 cells of it
    field.to((r, c)) * grid.resolution                  # metres from (r, c); inf when cut off
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["DistanceField", "grid_graph"]

SQRT2 = math.sqrt(2.0)


def grid_graph(blocked: np.ndarray) -> object:
    """The 8-connected graph of the free cells of `blocked` (rows × columns) as a SciPy CSR matrix over
    cell indices r * columns + c: straight steps weigh 1, diagonal ones √2, and a diagonal step is
    left out when either cell beside it is blocked (no corner cutting)."""
    from scipy.sparse import coo_matrix

    blocked = np.asarray(blocked, dtype=bool)
    rows, cols = blocked.shape
    free = ~blocked
    index = np.arange(rows * cols).reshape(rows, cols)
    sources, targets, weights = [], [], []
    # Each undirected edge once (right, up, and the two diagonals up); the matrix is made symmetric below.
    for dr, dc, w in ((0, 1, 1.0), (1, 0, 1.0), (1, 1, SQRT2), (1, -1, SQRT2)):
        r0, r1 = 0, rows - dr
        c0, c1 = max(0, -dc), cols - max(0, dc)
        a = free[r0:r1, c0:c1]
        b = free[r0 + dr:r1 + dr, c0 + dc:c1 + dc]
        ok = a & b
        if dr and dc:  # the two cells beside the diagonal must be free too
            ok &= free[r0 + dr:r1 + dr, c0:c1] & free[r0:r1, c0 + dc:c1 + dc]
        sources.append(index[r0:r1, c0:c1][ok])
        targets.append(index[r0 + dr:r1 + dr, c0 + dc:c1 + dc][ok])
        weights.append(np.full(int(ok.sum()), w))
    s, t, w = np.concatenate(sources), np.concatenate(targets), np.concatenate(weights)
    n = rows * cols
    return coo_matrix((np.concatenate([w, w]), (np.concatenate([s, t]), np.concatenate([t, s]))), shape=(n, n)).tocsr()


class DistanceField:
    """Every cell's shortest distance (in cells) to `goal` over the free cells of `blocked`, or with
    `within` > 0 to the nearest free cell whose centre is at most `within` cells from the goal's (a goal
    reached within a tolerance); `graph` reuses one made by grid_graph for the same mask."""

    def __init__(self, blocked: np.ndarray, goal: tuple[int, int], graph: object | None = None,
                 within: float = 0.0) -> None:
        from scipy.sparse.csgraph import dijkstra

        blocked = np.asarray(blocked, dtype=bool)
        self.shape = blocked.shape
        rows, cols = self.shape
        r, c = goal
        if not (0 <= r < rows and 0 <= c < cols):
            raise ValueError(f"DistanceField: the goal {goal} is outside the {rows}×{cols} grid")
        k = math.floor(within)
        rr, cc = np.mgrid[max(0, r - k):min(rows, r + k + 1), max(0, c - k):min(cols, c + k + 1)]
        near = ((rr - r) ** 2 + (cc - c) ** 2 <= within * within) & ~blocked[rr, cc]
        sources = (rr[near] * cols + cc[near]).tolist()
        if not sources:
            self.distance = np.full(self.shape, math.inf)
            return
        graph = grid_graph(blocked) if graph is None else graph
        self.distance = dijkstra(graph, directed=False, indices=sources, min_only=True).reshape(self.shape)

    def to(self, cell: tuple[int, int]) -> float:
        """The distance from `cell` to the goal, in cells (inf when cut off or outside the grid)."""
        r, c = cell
        rows, cols = self.shape
        if not (0 <= r < rows and 0 <= c < cols):
            return math.inf
        return float(self.distance[r, c])
