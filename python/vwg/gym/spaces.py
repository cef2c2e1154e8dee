"""The observation and action spaces of vwg.gym's environments, and how an action becomes a move."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from gymnasium import spaces

__all__ = ["DISCRETE_MOVES", "action_space", "check_move", "flatten", "move_of", "observation_space"]

#: The discrete moves (turn in radians, then drive in step lengths): ahead, left and ahead, right and
#: ahead, turn left, turn right.
DISCRETE_MOVES: tuple[tuple[float, float], ...] = (
    (0.0, 1.0), (math.pi / 4, 1.0), (-math.pi / 4, 1.0), (math.pi / 2, 0.0), (-math.pi / 2, 0.0))


def observation_space(beams: int, max_range: float, max_distance: float, flat: bool) -> spaces.Space[Any]:
    """``laser``: the ranges (metres, 0..max_range); ``goal``: the room's distance (metres, 0..the map's
    diagonal) and bearing (radians, -π..π, from the heading). ``flat``: the two side by side in one Box."""
    laser = spaces.Box(0.0, np.float32(max_range), shape=(beams,), dtype=np.float32)
    goal = spaces.Box(np.array([0.0, -math.pi], np.float32), np.array([max_distance, math.pi], np.float32),
                      dtype=np.float32)
    if flat:
        low = np.concatenate([laser.low, goal.low]).astype(np.float32)
        high = np.concatenate([laser.high, goal.high]).astype(np.float32)
        return spaces.Box(low, high, dtype=np.float32)
    return spaces.Dict({"laser": laser, "goal": goal})


def flatten(observation: dict[str, np.ndarray]) -> np.ndarray:
    return np.concatenate([observation["laser"], observation["goal"]]).astype(np.float32)


def action_space(discrete: bool) -> spaces.Space[Any]:
    """Continuous: Box([-1, 0], [1, 1]) = (turn as a share of max_turn, drive as a share of the step
    length); discrete: one of DISCRETE_MOVES."""
    if discrete:
        return spaces.Discrete(len(DISCRETE_MOVES))
    return spaces.Box(np.array([-1.0, 0.0], np.float32), np.array([1.0, 1.0], np.float32), dtype=np.float32)


def check_move(max_turn: float, step_length: float) -> None:
    """The largest turn (0..π rad) and drive (0..10 m) of a move."""
    if not (math.isfinite(max_turn) and 0 < max_turn <= math.pi):
        raise ValueError(f"max_turn: expected 0 < max_turn <= π radians, got {max_turn!r}")
    if not (math.isfinite(step_length) and 0 < step_length <= 10):
        raise ValueError(f"step_length: expected 0 < step_length <= 10 m, got {step_length!r}")


def move_of(action: Any, discrete: bool, max_turn: float, step_length: float) -> tuple[float, float]:
    """(turn radians, distance metres) of an action; values outside the space are clipped."""
    if discrete:
        turn, drive = DISCRETE_MOVES[int(action)]
        return turn, drive * step_length
    a = np.asarray(action, dtype=np.float64).reshape(-1)
    if a.shape != (2,) or not np.all(np.isfinite(a)):
        raise ValueError(f"action: expected two finite numbers (turn, drive), got {action!r}")
    return float(np.clip(a[0], -1, 1)) * max_turn, float(np.clip(a[1], 0, 1)) * step_length
