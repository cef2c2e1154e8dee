"""``vwg/Navigate-v0``: one robot of a robot world, sent to a room, moved by a learner (Gymnasium)."""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np

import vwg._core as _core
from vwg.gym.navigation import REWARD, Navigation, Reward
from vwg.gym.spaces import action_space, check_move, flatten, move_of, observation_space

__all__ = ["NavigateEnv"]


class NavigateEnv(gym.Env[Any, Any]):
    """A robot at a free place drawn from the seed, sent to a room drawn from the seed (one it can reach).

    - observation: ``{"laser": ranges (beams,), "goal": [distance m, bearing rad]}`` (``flat=True``:
      one Box, the ranges then the goal);
    - action: ``Box([-1, 0], [1, 1])`` = turn (share of ``max_turn``) then drive (share of
      ``step_length``), or with ``discrete=True`` one of five moves (vwg.gym.DISCRETE_MOVES);
    - a step is one move, carried out by the simulated motors (see vwg.gym.navigation);
    - reward: metres come nearer the room along the shortest way round the walls, -0.01 a step, -1 a
      collision, +10 on arrival (vwg.gym.Reward);
    - terminated when the robot reaches its room (within the world's goal tolerance); truncated after
      ``max_episode_steps`` (500 as registered).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, world: str | Any = "office", *, beams: int = 36, discrete: bool = False, flat: bool = False,
                 max_turn: float = math.pi / 2, step_length: float = 0.5, frames_per_step: int = 50,
                 reward: Reward = REWARD, render_mode: str | None = None) -> None:
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode: expected None or 'rgb_array', got {render_mode!r}")
        check_move(max_turn, step_length)
        self.nav = Navigation(world, robots=1, beams=beams, frames_per_step=frames_per_step, reward=reward)
        self.discrete, self.flat = discrete, flat
        self.max_turn, self.step_length = max_turn, step_length
        self.render_mode = render_mode
        self.observation_space = observation_space(beams, self.nav.laser.max_range, self.nav.max_distance, flat)
        self.action_space = action_space(discrete)
        self._seeds: np.random.Generator | None = None

    def _observation(self) -> Any:
        obs = self.nav.observe(self.nav.robots[0])
        return flatten(obs) if self.flat else obs

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        super().reset(seed=seed)
        # Each episode's world from the env's generator: reset(seed=s) then resets give one sequence.
        episode_seed = int(self.np_random.integers(2**63 - 1))
        state = (options or {}).get("state")
        if state is not None:  # an episode saved by save_state(), as it stood (a path or its bytes)
            self.nav.restore(state)
        else:
            self.nav.reset(episode_seed)
        return self._observation(), self.nav.info(self.nav.robots[0])

    def save_state(self) -> bytes:
        """The episode as it stands, for ``reset(options={"state": data})`` (here or in another process)."""
        return self.nav.save_state()

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        if self.nav.case is None:
            raise RuntimeError("NavigateEnv.step: call reset() first")
        rid = self.nav.robots[0]
        reward = self.nav.step({rid: move_of(action, self.discrete, self.max_turn, self.step_length)})[rid]
        return self._observation(), reward, self.nav.reached(rid), False, self.nav.info(rid)

    def render(self) -> np.ndarray | None:
        if self.render_mode != "rgb_array" or self.nav.case is None:
            return None

        nav = self.nav
        renderer = _core.TopDownRenderer(nav.world.grid, width=480)
        renderer.begin(frame=nav.case.engine.frame, time=nav.case.engine.time, status=f"to {nav.goals[nav.robots[0]]}")
        for room in nav.world.rooms.values():
            renderer.draw_marker(room.at[0], room.at[1], room.facing, room.name, room.marker)
        for rid in nav.robots:
            renderer.draw_robot(nav.case.sim.robot(rid).pose, nav.world.robot(rid).radius, rid)
        return np.asarray(renderer.image())

    def close(self) -> None:
        self.nav.close()
