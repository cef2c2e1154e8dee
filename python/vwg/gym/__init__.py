"""Learning environments on vwg's robot worlds (the optional extra ``vwg[rl]``: Gymnasium, PettingZoo).

Importing this module registers ``vwg/Navigate-v0`` with Gymnasium::

    import gymnasium, vwg.gym
    env = gymnasium.make("vwg/Navigate-v0", world="office")          # a shipped world, or a world file
    observation, info = env.reset(seed=0)
    observation, reward, terminated, truncated, info = env.step(env.action_space.sample())

    envs = vwg.gym.make_vec(8, world="office")                        # 8 environments in this process
    agents = vwg.gym.parallel_env(world="office")                    # PettingZoo: one agent per robot

The learner is the decision inside λ(ARobot, eDecide), as a planner is (paper test 1); the robot is
the case study's, on the Box2D simulator, with a laser. Spaces, step, reward and termination are
described on NavigateEnv (vwg.gym.navigate_env) and vwg.gym.navigation.
"""

from __future__ import annotations

from typing import Any

import gymnasium

from vwg.gym.navigate_env import NavigateEnv
from vwg.gym.navigation import REWARD, AgentDecider, Navigation, Reward
from vwg.gym.parallel_env import NavigateParallelEnv, parallel_env
from vwg.gym.spaces import DISCRETE_MOVES

__all__ = ["DISCRETE_MOVES", "ENV_ID", "REWARD", "AgentDecider", "NavigateEnv", "NavigateParallelEnv", "Navigation",
           "Reward", "make_vec", "parallel_env"]

ENV_ID = "vwg/Navigate-v0"
MAX_EPISODE_STEPS = 500

if ENV_ID not in gymnasium.registry:
    gymnasium.register(id=ENV_ID, entry_point="vwg.gym.navigate_env:NavigateEnv", max_episode_steps=MAX_EPISODE_STEPS)


def make_vec(num_envs: int, **kwargs: Any) -> gymnasium.vector.VectorEnv:
    """`num_envs` vwg/Navigate-v0 environments stepped together in this process (Gymnasium's
    SyncVectorEnv: no process per environment; each engine runs on one thread)."""
    if not 1 <= num_envs <= 4096:
        raise ValueError(f"num_envs: expected 1 to 4096, got {num_envs}")
    return gymnasium.make_vec(ENV_ID, num_envs=num_envs, vectorization_mode="sync", **kwargs)
