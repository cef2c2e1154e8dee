"""A PettingZoo ParallelEnv: every robot of a robot world an agent, all moving at once."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from pettingzoo import ParallelEnv

from vwg.gym.navigation import REWARD, Navigation, Reward
from vwg.gym.spaces import action_space, check_move, flatten, move_of, observation_space
from vwg.robot.world_file import RobotWorld
from vwg.trial import cached_world

__all__ = ["NavigateParallelEnv", "parallel_env"]


class NavigateParallelEnv(ParallelEnv):  # type: ignore[misc]
    """`robots` robots (default: as many as the world file has) at free places drawn from the seed, each
    sent to a room drawn from the seed; agents ``robot_1`` … ``robot_N``. The spaces, the step and the
    reward are vwg/Navigate-v0's, per agent; a robot meets the others (collisions count against it).
    An agent that reaches its room is terminated and leaves; all are truncated after ``max_steps``."""

    metadata = {"name": "vwg_navigate_v0", "render_modes": [], "is_parallelizable": True}

    def __init__(self, world: str | Any = "office", *, robots: int | None = None, beams: int = 36,
                 discrete: bool = False, flat: bool = False, max_turn: float = math.pi / 2, step_length: float = 0.5,
                 frames_per_step: int = 50, max_steps: int = 500, reward: Reward = REWARD) -> None:

        check_move(max_turn, step_length)
        loaded = world if isinstance(world, RobotWorld) else cached_world(str(world))
        count = robots if robots is not None else len(loaded.robots)
        self.nav = Navigation(world, robots=count, beams=beams, frames_per_step=frames_per_step, reward=reward)
        self.discrete, self.flat = discrete, flat
        self.max_turn, self.step_length, self.max_steps = max_turn, step_length, max_steps
        self.possible_agents = [f"robot_{i}" for i in range(1, count + 1)]
        self.agents: list[str] = []
        self._steps = 0
        self._observation_space = observation_space(beams, self.nav.laser.max_range, self.nav.max_distance, flat)
        self._action_space = action_space(discrete)

    def observation_space(self, agent: str) -> Any:
        return self._observation_space  # the same object each time, as PettingZoo asks

    def action_space(self, agent: str) -> Any:
        return self._action_space

    @staticmethod
    def _robot(agent: str) -> int:
        return int(agent.removeprefix("robot_"))

    def _observe(self, agent: str) -> Any:
        obs = self.nav.observe(self._robot(agent))
        return flatten(obs) if self.flat else obs

    def reset(self, seed: int | None = None,
              options: dict[str, Any] | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        elif not hasattr(self, "_rng"):
            self._rng = np.random.default_rng()
        state = (options or {}).get("state")
        episode_seed = int(self._rng.integers(2**63 - 1))
        if state is not None:  # an episode saved by save_state() (a path or its bytes)
            self.nav.restore(state)
        else:
            self.nav.reset(episode_seed)
        # A restored episode's robots that had reached their rooms had left (terminated).
        self.agents = [a for a in self.possible_agents if state is None or not self.nav.reached(self._robot(a))]
        self._steps = 0
        return ({a: self._observe(a) for a in self.agents}, {a: self.nav.info(self._robot(a)) for a in self.agents})

    def step(self, actions: dict[str, Any]) -> tuple[dict[str, Any], ...]:
        if not self.agents:
            raise RuntimeError("NavigateParallelEnv.step: no agents left; call reset()")
        moves = {self._robot(a): move_of(actions[a], self.discrete, self.max_turn, self.step_length)
                 for a in self.agents if a in actions}
        rewards_by_robot = self.nav.step(moves)
        self._steps += 1
        agents = self.agents
        observations = {a: self._observe(a) for a in agents}
        rewards = {a: rewards_by_robot.get(self._robot(a), 0.0) for a in agents}
        terminations = {a: self.nav.reached(self._robot(a)) for a in agents}
        truncations = {a: self._steps >= self.max_steps for a in agents}
        infos = {a: self.nav.info(self._robot(a)) for a in agents}
        self.agents = [a for a in agents if not (terminations[a] or truncations[a])]
        return observations, rewards, terminations, truncations, infos

    def save_state(self) -> bytes:
        """The episode as it stands, for ``reset(options={"state": data})`` (its step count starts again)."""
        return self.nav.save_state()

    def close(self) -> None:
        self.nav.close()


def parallel_env(**kwargs: Any) -> NavigateParallelEnv:
    """PettingZoo's constructor convention: ``vwg.gym.parallel_env(world="office")``."""
    return NavigateParallelEnv(**kwargs)
