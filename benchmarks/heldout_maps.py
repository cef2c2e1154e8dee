"""Held-out grid maps for the planners' benchmarks: mazes and city blocks, 512 × 512, in MovingAI's
format, with scenarios whose optimal lengths come from a second method (SciPy's Dijkstra on the same
8-connected graph), not from vwg.

    python benchmarks/heldout_maps.py [OUT]   writes OUT/<name>.map and OUT/<name>.map.scen
                                              (OUT: tests/data/heldout; the files are committed)

The MovingAI benchmark's maze512-* and street maps (Berlin_0_512, ...) are not in the repository;
these stand in for them, made from a seed:
- maze-c2, maze-c8: a depth-first maze with corridors and walls 2 (8) cells wide;
- city-a, city-b: avenues cut by recursive division, streets between blocks of buildings with
  alleys, courtyards and parks, two diagonal boulevards.
Moves are the paper's: 8-connected, diagonals √2, no corner cutting (a diagonal needs both of its
orthogonal neighbours free), as the MovingAI optima are.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, dijkstra

OUT = Path(__file__).resolve().parents[1] / "tests" / "data" / "heldout"
SIZE = 512
QUERIES = 150


def maze(size: int, width: int, rng: np.random.Generator) -> np.ndarray:
    """A depth-first (recursive backtracker) maze: True = blocked. Corridors and walls `width` wide."""
    pitch = 2 * width
    n = (size - width) // pitch  # maze cells per side
    blocked = np.ones((size, size), dtype=bool)
    seen = np.zeros((n, n), dtype=bool)

    def carve(r: int, c: int) -> None:
        y, x = width + r * pitch, width + c * pitch
        blocked[y:y + width, x:x + width] = False

    stack = [(0, 0)]
    seen[0, 0] = True
    carve(0, 0)
    while stack:
        r, c = stack[-1]
        options = [(r + dr, c + dc) for dr, dc in ((0, 1), (1, 0), (0, -1), (-1, 0))
                   if 0 <= r + dr < n and 0 <= c + dc < n and not seen[r + dr, c + dc]]
        if not options:
            stack.pop()
            continue
        nr, nc = options[rng.integers(len(options))]
        seen[nr, nc] = True
        carve(nr, nc)
        y0, x0 = width + min(r, nr) * pitch, width + min(c, nc) * pitch  # the wall between them
        blocked[y0:y0 + width + (pitch if nr != r else 0), x0:x0 + width + (pitch if nc != c else 0)] = False
        stack.append((nr, nc))
    return blocked


def city(size: int, rng: np.random.Generator) -> np.ndarray:
    """City blocks: True = blocked."""
    blocked = np.zeros((size, size), dtype=bool)

    def block(y0: int, x0: int, y1: int, x1: int) -> None:
        h, w = y1 - y0, x1 - x0
        if h < 6 or w < 6:
            return
        kind = rng.random()
        if kind < 0.12:  # a park: a few trees
            for _ in range(h * w // 60):
                blocked[rng.integers(y0, y1), rng.integers(x0, x1)] = True
            return
        # Lots along the block, each a building; gaps of 0-2 cells are alleys.
        y = y0
        while y < y1:
            lot_h = int(rng.integers(6, 24))
            x = x0
            while x < x1:
                lot_w = int(rng.integers(6, 24))
                by1, bx1 = min(y + lot_h, y1), min(x + lot_w, x1)
                top, left, bottom, right = (int(v) for v in rng.integers(0, 3, 4))  # yards round the building
                blocked[y + top:by1 - bottom, x + left:bx1 - right] = True
                if rng.random() < 0.2 and by1 - y > 12 and bx1 - x > 12:  # a courtyard with a way in
                    blocked[y + top + 3:by1 - bottom - 3, x + left + 3:bx1 - right - 3] = False
                    blocked[y + top + 3:y + top + 6, x + left:x + left + 3] = False
                x = bx1 + int(rng.integers(0, 2))
            y = min(y + lot_h, y1) + int(rng.integers(0, 2))

    def divide(y0: int, x0: int, y1: int, x1: int, depth: int) -> None:
        h, w = y1 - y0, x1 - x0
        if max(h, w) < 56 or (depth > 3 and rng.random() < 0.2):
            block(y0, x0, y1, x1)
            return
        street = int(rng.integers(8, 14)) if depth < 2 else int(rng.integers(4, 8))
        if h > w:
            cut = int(rng.integers(y0 + h // 4, y1 - h // 4))
            divide(y0, x0, cut, x1, depth + 1)
            divide(cut + street, x0, y1, x1, depth + 1)
        else:
            cut = int(rng.integers(x0 + w // 4, x1 - w // 4))
            divide(y0, x0, y1, cut, depth + 1)
            divide(y0, cut + street, y1, x1, depth + 1)

    divide(0, 0, size, size, 0)
    yy, xx = np.mgrid[0:size, 0:size]
    for _ in range(2):  # boulevards at an angle, 6 cells across
        angle = rng.uniform(0.3, 1.2) * (1 if rng.random() < 0.5 else -1)
        cy, cx = rng.uniform(0.3, 0.7) * size, rng.uniform(0.3, 0.7) * size
        distance = np.abs((yy - cy) * math.cos(angle) - (xx - cx) * math.sin(angle))
        blocked[distance < 3.0] = False
    return blocked


def graph(blocked: np.ndarray) -> coo_matrix:
    """The 8-connected graph of the free cells, diagonals √2, no corner cutting."""
    h, w = blocked.shape
    free = ~blocked
    index = np.arange(h * w).reshape(h, w)
    rows, cols, costs = [], [], []
    for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
        ys = slice(0, h - dy)
        xs = slice(max(0, -dx), w - max(0, dx))
        ys2 = slice(dy, h)
        xs2 = slice(max(0, dx), w - max(0, -dx))
        ok = free[ys, xs] & free[ys2, xs2]
        if dy and dx:  # both orthogonal neighbours free
            ok &= free[ys2, xs] & free[ys, xs2]
        a, b = index[ys, xs][ok], index[ys2, xs2][ok]
        cost = math.sqrt(2.0) if (dy and dx) else 1.0
        rows += [a, b]
        cols += [b, a]
        costs += [np.full(a.size, cost), np.full(a.size, cost)]
    n = h * w
    return coo_matrix((np.concatenate(costs), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)).tocsr()


def scenarios(blocked: np.ndarray, rng: np.random.Generator, count: int) -> list[tuple[int, int, int, int, float]]:
    """`count` (start x, y, goal x, y, optimal length) between free cells of the largest region, in
    MovingAI's x (column) and y (row from the top)."""
    g = graph(blocked)
    _, labels = connected_components(g, directed=False)
    free = np.flatnonzero(~blocked.ravel())
    largest = np.bincount(labels[free]).argmax()
    cells = free[labels[free] == largest]
    starts = rng.choice(cells, count, replace=False)
    goals = rng.choice(cells, count, replace=False)
    dist = dijkstra(g, directed=False, indices=starts)
    w = blocked.shape[1]
    return [(int(s % w), int(s // w), int(t % w), int(t // w), float(dist[i, t]))
            for i, (s, t) in enumerate(zip(starts, goals, strict=True))]


def write(out: Path, name: str, blocked: np.ndarray, scens: list[tuple[int, int, int, int, float]]) -> None:
    h, w = blocked.shape
    rows_of_map = ["".join("@" if b else "." for b in row) for row in blocked]
    lines = ["type octile", f"height {h}", f"width {w}", "map", *rows_of_map]
    (out / f"{name}.map").write_text("\n".join(lines) + "\n")
    rows = ["version 1"] + [f"{int(length // 4)}\t{name}.map\t{w}\t{h}\t{sx}\t{sy}\t{gx}\t{gy}\t{length:.8f}"
                            for sx, sy, gx, gy, length in sorted(scens, key=lambda s: s[4])]
    (out / f"{name}.map.scen").write_text("\n".join(rows) + "\n")


MAPS = {
    "maze-c2": lambda rng: maze(SIZE, 2, rng),
    "maze-c8": lambda rng: maze(SIZE, 8, rng),
    "city-a": lambda rng: city(SIZE, rng),
    "city-b": lambda rng: city(SIZE, rng),
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", type=Path, default=OUT)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for seed, (name, make) in enumerate(MAPS.items()):
        rng = np.random.default_rng(1000 + seed)
        blocked = make(rng)
        scens = scenarios(blocked, rng, QUERIES)
        write(args.out, name, blocked, scens)
        print(f"{name}: {blocked.mean():.0%} blocked, {len(scens)} queries, "
              f"optimal lengths {min(s[4] for s in scens):.1f}-{max(s[4] for s in scens):.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
