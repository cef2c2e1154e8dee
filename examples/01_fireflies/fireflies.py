"""Fireflies: actors that blink, eat, split in two and die — spawning and ε in one small world.

Firefly<id, x, y, energy, lit> responds to
  tick        λ: energy - 1 and toggle `lit`; ε when energy runs out; two fireflies when energy > 12
  food<x, y>  λ: energy + 5 if the food is within 1.5 m
  show        θ (visual): Translate<x, y>(Light<lit>)
FoodDrops is a seeded generator: a few food events at random places each frame.
"""

from __future__ import annotations

import math

import numpy as np

import vwg


class Firefly(vwg.Actor):
    events = ("tick", "food", "show")
    attributes = {"id": 1, "x": 0.0, "y": 0.0, "energy": 6, "lit": False}

    def on_tick(self, e):
        energy = self.energy - 1
        if energy <= 0:
            return ""  # dies: ε
        if energy > 12:  # splits: the children take the rest of the frame's events
            half = energy // 2
            return [
                self.with_(id=2 * self.id, energy=half, x=self.x - 0.5),
                self.with_(id=2 * self.id + 1, energy=energy - half, x=self.x + 0.5),
            ]
        return self.with_(energy=energy, lit=not self.lit)

    def on_food(self, e):
        if math.hypot(e.x - self.x, e.y - self.y) <= 1.5:
            return self.with_(energy=self.energy + 5)
        return self

    def show_show(self, e):
        return vwg.Sym("Translate", self.x, self.y)(vwg.Sym("Light", self.lit))


class FoodDrops(vwg.Generator):
    """`count` food events per frame, uniform over a `size` × `size` field (seeded by the engine)."""

    name = "food_drops"

    def __init__(self, count: int = 3, size: float = 10.0) -> None:
        super().__init__()
        self.count = count
        self.size = size
        self.rng = np.random.default_rng(0)

    def reset(self, seed: int) -> None:
        self.rng = np.random.default_rng(seed)

    def generate(self, frame):
        xy = self.rng.uniform(0.0, self.size, size=(self.count, 2))
        return [vwg.Event("food", x=float(x), y=float(y)) for x, y in xy]
