"""The shortest any-angle way round blocked grid cells: the experiments' yardstick of path length
("path / optimal"), by code that shares nothing with vwg's planners.

Geometry. The blocked cells of a mask are closed unit squares; a way is any polyline through the rest of the plane.
A shortest such way bends only at convex corners of the blocked squares (Lozano-Pérez & Wesley, "An algorithm for
planning collision-free paths among polyhedral obstacles", CACM 22(10), 1979), so it is a shortest path in the
visibility graph of those corners plus the two ends. A corner is a lattice point with exactly one of its four cells
blocked; an edge is kept only where its line is tangent to the blocked cell at each corner end (a shortest way never
leaves a corner into the cell it wraps round), which shrinks the graph and not the distances. The graph's shortest
paths are SciPy's Dijkstra (``scipy.sparse.csgraph``).

Sight lines are tested at evenly spaced points at most ``step`` cells apart, a blocked square shrunk by ``EPS`` (so a
line may run along a cell's edge and leave from its corner). A line can thus graze a blocked square by less than
``step / 2`` cells unseen: the distances are lower bounds of the exact ones, by at most that much per corner of the
way. A wall thicker than ``step`` is never crossed.

    field = AnyAngle(blocked)                          # blocked: bool mask, rows × columns, row = y
    field.distance((r0, c0), (r1, c1))                 # cells; points in cell units (cell (r, c) covers [r, r+1))
    field.path((r0, c0), (r1, c1))                     # the corners between, as (row, col) points

For a disc robot on an OccupancyGrid, vwg.trial.any_angle_m builds the mask so that the figure is a lower bound of
what the robot can drive: the cells whose every point is within the robot's radius of a wall.
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np

__all__ = ["EPS", "STEP", "AnyAngle"]

STEP = 0.5  # cells between the points a sight line is tested at
EPS = 1e-6  # how far a blocked square is shrunk for the test (cells)
_CHUNK = 1 << 21  # sight lines tested at once (memory)


class AnyAngle:
    """Any-angle shortest distances among the blocked cells of `blocked` (rows × columns, True = blocked; outside
    the grid counts as blocked). The corners' visibility graph is built once; distances to a goal are kept for the
    last few goals."""

    def __init__(self, blocked: np.ndarray, step: float = STEP) -> None:
        blocked = np.asarray(blocked, dtype=bool)
        if blocked.ndim != 2 or not blocked.size:
            raise ValueError(f"AnyAngle: expected a non-empty 2-D mask, got shape {blocked.shape}")
        self.step = float(step)
        self._take_mask(np.pad(blocked, 1, constant_values=True))
        n = len(self.corners)
        per = max(1, _CHUNK // max(1, n))
        parts = []
        for first in range(0, n, per):
            i = np.repeat(np.arange(first, min(n, first + per)), n)
            j = np.tile(np.arange(n), min(n, first + per) - first)
            keep = i < j
            parts.append(self._edges(i[keep], j[keep]))
        self._graph = self._graph_of(parts)

    def _take_mask(self, pad: np.ndarray) -> None:
        """Everything that follows from the padded mask but the graph."""
        from scipy.ndimage import label

        self.shape = (pad.shape[0] - 2, pad.shape[1] - 2)
        # Padded by one blocked cell all round: point (r, c) of the map is (r + 1, c + 1) of the pad.
        self._pad = pad
        # Free regions (8-connected: two free squares meeting at a corner let a line through) to skip hopeless pairs.
        self._region, _ = label(~pad, structure=np.ones((3, 3), dtype=int))
        self.corners, self._quadrant = self._convex_corners()
        self._corner_region = self._region_at(self.corners)
        self._to_goal: OrderedDict[tuple[float, float], tuple[np.ndarray, np.ndarray, np.ndarray]] = OrderedDict()

    def with_blocked(self, more: np.ndarray) -> AnyAngle:
        """The yardstick of this mask with the cells of `more` blocked too, made from this one's graph: blocking
        cells only takes sight away, so the old edges between corners that stay are kept unless they pass the
        changed cells (those are tested again), and only the new corners' edges are searched. Much faster than a new
        AnyAngle when few cells change (a box on a building's map)."""
        more = np.asarray(more, dtype=bool)
        if more.shape != self.shape:
            raise ValueError(f"AnyAngle.with_blocked: a {more.shape} mask for a {self.shape} grid")
        out = AnyAngle.__new__(AnyAngle)
        out.step = self.step
        out._take_mask(self._pad | np.pad(more, 1, constant_values=False))
        changed = np.argwhere(out._pad & ~self._pad) - 1  # map cells newly blocked
        if not changed.size:
            out._graph = self._graph
            return out
        # Old corners still corners with the same blocked cell: their new numbers (-1: gone).
        old_key, new_key = self._corner_keys(), out._corner_keys()
        order = np.argsort(new_key)
        renumber = np.full(len(old_key), -1)
        if len(order):
            place = order[np.minimum(np.searchsorted(new_key, old_key, sorter=order), len(order) - 1)]
            stays = new_key[place] == old_key
            renumber[stays] = place[stays]
        graph = self._graph.tocoo()
        keep = graph.row < graph.col
        i, j = renumber[graph.row[keep]], renumber[graph.col[keep]]
        both = (i >= 0) & (j >= 0)
        i, j = i[both], j[both]
        same = out._corner_region[i] == out._corner_region[j]  # as a new graph would filter them
        i, j = i[same], j[same]
        # An edge whose box of cells misses the changed cells' box cannot pass them.
        (r0, c0), (r1, c1) = changed.min(axis=0), changed.max(axis=0) + 1
        a, b = out.corners[i], out.corners[j]
        near = (np.minimum(a[:, 0], b[:, 0]) <= r1) & (np.maximum(a[:, 0], b[:, 0]) >= r0) & \
            (np.minimum(a[:, 1], b[:, 1]) <= c1) & (np.maximum(a[:, 1], b[:, 1]) >= c0)
        still = np.ones(len(i), dtype=bool)
        still[near] = out.visible(a[near], b[near])
        kept = (i[still], j[still], np.hypot(*(b[still] - a[still]).T))
        # Edges of the new corners, to every corner.
        n = len(out.corners)
        fresh = np.setdiff1d(np.arange(n), renumber[renumber >= 0])
        fi = np.repeat(fresh, n)
        fj = np.tile(np.arange(n), len(fresh))
        pick = (fi != fj) & ~(np.isin(fj, fresh) & (fj < fi))  # each pair once
        out._graph = out._graph_of([kept, out._edges(fi[pick], fj[pick])])
        return out

    # ---- the corners and their graph ---------------------------------------------------------------------------
    def _corner_keys(self) -> np.ndarray:
        """A number per corner naming its lattice point and its blocked cell (the same in any mask of this size)."""
        width = self._pad.shape[1] + 1
        quadrant = (self._quadrant[:, 0] + 1) + (self._quadrant[:, 1] + 1) // 2
        return ((self.corners[:, 0] * width + self.corners[:, 1]) * 4 + quadrant).astype(np.int64)

    def _convex_corners(self) -> tuple[np.ndarray, np.ndarray]:
        """Lattice points (row, col) in map units with exactly one of the four cells round them blocked, and for
        each the (drow, dcol) sign of the blocked one."""
        p = self._pad.astype(np.int8)
        # Pad lattice point (i, j) has cells (i-1, j-1), (i-1, j), (i, j-1), (i, j) round it.
        a, b, c, d = p[:-1, :-1], p[:-1, 1:], p[1:, :-1], p[1:, 1:]
        one = (a + b + c + d) == 1
        i, j = np.nonzero(one)
        sr = np.where(a[i, j] | b[i, j], -1, 1)
        sc = np.where(a[i, j] | c[i, j], -1, 1)
        points = np.stack([i, j], axis=1).astype(float)  # between pad cells (i, j) and (i+1, j+1): map point (i, j)
        return points, np.stack([sr, sc], axis=1).astype(np.int8)

    def _region_at(self, points: np.ndarray) -> np.ndarray:
        """The free region each point touches (a corner touches three free cells of one region)."""
        out = np.zeros(len(points), dtype=np.int64)
        for dr in (-0.5, 0.5):
            for dc in (-0.5, 0.5):
                r = np.floor(points[:, 0] + dr).astype(np.int64) + 1
                c = np.floor(points[:, 1] + dc).astype(np.int64) + 1
                out = np.maximum(out, self._region[r, c])
        return out

    def _edges(self, i: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Of the corner pairs (i[k], j[k]), those joined by an edge, and its length."""
        keep = self._corner_region[i] == self._corner_region[j]
        i, j = i[keep], j[keep]
        delta = self.corners[j] - self.corners[i]
        # Tangent at both ends: the line's direction (dr, dc) with dr·dc·sr·sc <= 0 does not enter the blocked cell
        # of the corner (sr, sc).
        q_i, q_j = self._quadrant[i], self._quadrant[j]
        product = delta[:, 0] * delta[:, 1]
        keep = (product * q_i[:, 0] * q_i[:, 1] <= 0) & (product * q_j[:, 0] * q_j[:, 1] <= 0)
        i, j = i[keep], j[keep]
        seen = self.visible(self.corners[i], self.corners[j])
        return i[seen], j[seen], np.hypot(*(self.corners[j[seen]] - self.corners[i[seen]]).T)

    def _graph_of(self, parts: list[tuple[np.ndarray, np.ndarray, np.ndarray]]) -> object:
        from scipy.sparse import coo_matrix

        n = len(self.corners)
        s = np.concatenate([p[0] for p in parts] + [np.zeros(0, dtype=np.int64)])
        t = np.concatenate([p[1] for p in parts] + [np.zeros(0, dtype=np.int64)])
        w = np.concatenate([p[2] for p in parts] + [np.zeros(0)])
        return coo_matrix((np.concatenate([w, w]), (np.concatenate([s, t]), np.concatenate([t, s]))),
                          shape=(n, n)).tocsr()

    # ---- sight ---------------------------------------------------------------------------------------------------
    def blocked_at(self, points: np.ndarray) -> np.ndarray:
        """Whether each point (row, col) of the map's rectangle lies in a blocked square shrunk by EPS. Points are in
        the map's rectangle (sight lines join such points), so the padded grid holds every cell looked at."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        cols = self._pad.shape[1]
        fr, fc = np.floor(points[:, 0]), np.floor(points[:, 1])
        cell = (fr.astype(np.intp) + 1) * cols + fc.astype(np.intp) + 1
        flat = self._pad.ravel()
        out = flat[cell]
        # Within EPS of a cell's side (a line along a wall, an end at a corner): blocked only if every cell the
        # point touches is.
        near = np.nonzero(out & ((points[:, 0] - fr < EPS) | (points[:, 0] - fr > 1 - EPS)
                                 | (points[:, 1] - fc < EPS) | (points[:, 1] - fc > 1 - EPS)))[0]
        if near.size:
            q = points[near]
            every = np.ones(near.size, dtype=bool)
            for dr in (-EPS, EPS):
                for dc in (-EPS, EPS):
                    every &= flat[(np.floor(q[:, 0] + dr).astype(np.intp) + 1) * cols
                                  + np.floor(q[:, 1] + dc).astype(np.intp) + 1]
            out[near] = every
        return out

    def visible(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """For each pair of points a[k], b[k] (row, col) in the map's rectangle, whether the segment between them is
        clear: tested at evenly spaced points at most `step` apart, which depend on the two ends only, so blocking
        more cells can only take sight away (AnyAngle.with_blocked relies on it). Lines are dropped at their first
        blocked point: most end early on a wall."""
        a = np.asarray(a, dtype=float).reshape(-1, 2)
        b = np.asarray(b, dtype=float).reshape(-1, 2)
        # Each line walked from its lesser end (row, then column): the same answer whichever way it was asked.
        swap = (b[:, 0] < a[:, 0]) | ((b[:, 0] == a[:, 0]) & (b[:, 1] < a[:, 1]))
        a, b = np.where(swap[:, None], b, a), np.where(swap[:, None], a, b)
        clear = ~(self.blocked_at(a) | self.blocked_at(b))
        delta = b - a
        steps = np.maximum(1, np.ceil(np.hypot(delta[:, 0], delta[:, 1]) / self.step)).astype(np.int64)
        alive = np.nonzero(clear & (steps > 1))[0]
        k = 1
        while alive.size:
            hit = self.blocked_at(a[alive] + delta[alive] * (k / steps[alive])[:, None])
            clear[alive[hit]] = False
            alive = alive[~hit & (k + 1 < steps[alive])]
            k += 1
        return clear

    # ---- distances -----------------------------------------------------------------------------------------------
    def _goal_field(self, goal: tuple[float, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each corner's distance to `goal` and its next corner on the way (-1: straight to the goal), and the goal
        as an array."""
        from scipy.sparse.csgraph import dijkstra

        key = (float(goal[0]), float(goal[1]))
        if key in self._to_goal:
            self._to_goal.move_to_end(key)
            return self._to_goal[key]
        g = np.array(key)
        n = len(self.corners)
        seen = self.visible(np.repeat(g[None], n, axis=0), self.corners) if n else np.zeros(0, dtype=bool)
        direct = np.where(seen, np.hypot(*(self.corners - g).T) if n else np.zeros(0), np.inf)
        if n and np.isfinite(direct).any():
            # One Dijkstra from every corner the goal sees, each starting at its straight distance: a virtual source.
            from scipy.sparse import bmat, coo_matrix

            src = np.nonzero(np.isfinite(direct))[0]
            link = coo_matrix((direct[src], (np.zeros(len(src), dtype=np.int64), src)), shape=(1, n))
            graph = bmat([[None, link], [link.T, self._graph]]).tocsr()
            dist, pred = dijkstra(graph, directed=False, indices=0, return_predecessors=True)
            dist, pred = dist[1:], pred[1:] - 1  # pred -1 (the goal node 0 - 1) means straight to the goal
        else:
            dist, pred = np.full(n, np.inf), np.full(n, -1)
        field = (dist, pred, g)
        self._to_goal[key] = field
        if len(self._to_goal) > 16:
            self._to_goal.popitem(last=False)
        return field

    def distance(self, start: tuple[float, float], goal: tuple[float, float]) -> float:
        """The shortest way from `start` to `goal` (points in cell units: (row, col)), in cells; inf when none."""
        return self._way(start, goal)[0]

    def path(self, start: tuple[float, float], goal: tuple[float, float]) -> list[tuple[float, float]]:
        """The shortest way's points from `start` to `goal`, both included (empty when there is none)."""
        length, first = self._way(start, goal)
        if not math.isfinite(length):
            return []
        points = [(float(start[0]), float(start[1]))]
        _, pred, _ = self._goal_field(goal)
        k = first
        while k >= 0:
            points.append((float(self.corners[k, 0]), float(self.corners[k, 1])))
            k = int(pred[k])
        points.append((float(goal[0]), float(goal[1])))
        return points

    def _way(self, start: tuple[float, float], goal: tuple[float, float]) -> tuple[float, int]:
        dist, _, g = self._goal_field(goal)
        s = np.array([float(start[0]), float(start[1])])
        if self.visible(s, g)[0]:
            return float(np.hypot(*(g - s))), -1
        n = len(self.corners)
        if not n:
            return math.inf, -1
        finite = np.nonzero(np.isfinite(dist))[0]
        seen = self.visible(np.repeat(s[None], len(finite), axis=0), self.corners[finite])
        candidates = finite[seen]
        if not candidates.size:
            return math.inf, -1
        total = np.hypot(*(self.corners[candidates] - s).T) + dist[candidates]
        best = int(np.argmin(total))
        return float(total[best]), int(candidates[best])
