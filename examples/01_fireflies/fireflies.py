"""Fireflies: actors that blink, eat, split in two and die — spawning and ε in one small world.

Firefly<id, x, y, energy, lit> responds to
  tick        λ: energy - 1 and toggle `lit`; ε when energy runs out; two fireflies a metre or so
              apart (a seeded random direction) when energy > 12
  food<x, y>  λ: energy + 5 if the food is within 1.5 m
  show        θ (visual): Translate<x, y>(Light<lit>)
FoodDrops is a seeded generator that reads the world: it drops food at random places, fewer as the
swarm grows (the field feeds about `capacity` fireflies), so the swarm neither dies out nor explodes.
Picture is a backend that draws each displayed frame (φ of Translate<x, y>(Light<lit>)) and writes
them as a GIF, finished by finish() at the end of the run.
"""

from __future__ import annotations

import math

import numpy as np

import vwg


def _field(v: float) -> float:
    """A coordinate kept on the 10 m field."""
    return min(max(v, 0.5), 9.5)


class Firefly(vwg.Actor):
    events = ("tick", "food", "show")
    attributes = {"id": 1, "x": 0.0, "y": 0.0, "energy": 6, "lit": False}

    def on_tick(self, e, ctx):
        energy = self.energy - 1
        if energy <= 0:
            return ""  # dies: ε
        if energy > 12:  # splits: the children take the rest of the frame's events
            half = energy // 2
            # The children fly off a metre in a random direction, staying on the 10 m field.
            a = ctx.rng().uniform(0.0, 2.0 * math.pi)
            dx, dy = math.cos(a), math.sin(a)
            return [
                self.with_(id=2 * self.id, energy=half, x=_field(self.x - dx), y=_field(self.y - dy)),
                self.with_(id=2 * self.id + 1, energy=energy - half, x=_field(self.x + dx), y=_field(self.y + dy)),
            ]
        return self.with_(energy=energy, lit=not self.lit)

    def on_food(self, e):
        if math.hypot(e.x - self.x, e.y - self.y) <= 1.5:
            return self.with_(energy=self.energy + 5)
        return self

    def show_show(self, e):
        return vwg.Sym("Translate", self.x, self.y)(vwg.Sym("Light", self.lit))


class FoodDrops(vwg.Generator):
    """Each frame, `capacity` minus the number of fireflies alive (never fewer than 0) food events,
    uniform over a `size` × `size` field (seeded by the engine)."""

    name = "food_drops"

    def __init__(self, capacity: int = 12, size: float = 10.0) -> None:
        super().__init__()
        self.capacity = capacity
        self.size = size
        self.rng = np.random.default_rng(0)

    def reset(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)

    def generate(self, frame):
        count = max(0, self.capacity - frame.world.actor_count)
        xy = self.rng.uniform(0.0, self.size, size=(count, 2))
        return [vwg.Event("food", x=float(x), y=float(y)) for x, y in xy]


class Picture(vwg.Backend):
    """Draws the fireflies displayed in each frame — a lit one as a yellow glow, a dark one as a dim
    dot — on a `size` × `size` m night field, and writes the frames to `path` (GIF or MP4)."""

    def __init__(self, path: str = "fireflies.gif", size: float = 10.0, pixels: int = 240, fps: float = 10.0) -> None:
        super().__init__()
        self.size = size
        self.pixels = pixels
        self.path, self.fps = path, fps
        self.video: vwg.VideoWriter | None = None  # opened at the first frame: loading writes nothing
        self.offsets: list[tuple[float, float]] = []
        self.lights: list[tuple[float, float, bool]] = []
        yy, xx = np.mgrid[-6:7, -6:7]
        self.glow = np.clip(1.0 - np.hypot(xx, yy) / 6.0, 0.0, 1.0)[..., None] * np.array([255.0, 230.0, 90.0])

    def begin_frame(self, frame):
        self.lights.clear()

    def open(self, t):  # β of Translate<x, y>: the scope's lights are there
        x, y = t.params
        self.offsets.append((float(x), float(y)))

    def close(self, t):  # δ
        self.offsets.pop()

    def primitive(self, p):  # α of Light<lit>
        x = sum(o[0] for o in self.offsets)
        y = sum(o[1] for o in self.offsets)
        self.lights.append((x, y, bool(p.params[0])))

    def end_frame(self, frame):
        image = np.zeros((self.pixels, self.pixels, 3), np.float64)
        image[...] = (12, 16, 40)
        scale = self.pixels / self.size
        for x, y, lit in self.lights:
            col, row = int(x * scale), int(self.pixels - 1 - y * scale)
            r0, c0 = row - 6, col - 6
            if not (r0 >= 0 and r0 + 13 <= self.pixels and c0 >= 0 and c0 + 13 <= self.pixels):
                continue
            if lit:
                image[r0:r0 + 13, c0:c0 + 13] += self.glow
            else:
                image[row - 1:row + 2, col - 1:col + 2] = (90, 90, 70)
        if self.video is None:
            self.video = vwg.VideoWriter(self.path, fps=self.fps)
        self.video.write(np.clip(image, 0, 255).astype(np.uint8))

    def finish(self) -> None:
        """Finish the file (`vwg run` calls a backend's finish() when the run ends)."""
        if self.video is not None:
            self.video.close()
