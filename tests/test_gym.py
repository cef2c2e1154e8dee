"""vwg.gym: the Gymnasium and PettingZoo checkers, determinism by seed, the action's meaning against
the simulator's poses, the observation and reward against values worked out from the world file and
an independent distance field, and the vectorised form against single environments."""

from __future__ import annotations

import math

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import parallel_api_test

import vwg.gym
from conftest import plain_dijkstra
from vwg.robot.shortest import DistanceField


@pytest.mark.parametrize("kwargs", [{}, {"flat": True}, {"discrete": True}])
def test_gymnasium_env_checker(kwargs):
    env = gymnasium.make(vwg.gym.ENV_ID, world="office", **kwargs)
    check_env(env.unwrapped)
    env.close()


def test_pettingzoo_parallel_api_test():
    env = vwg.gym.parallel_env(world="office")
    assert env.possible_agents == ["robot_1", "robot_2"]  # the office has two robots
    parallel_api_test(env, num_cycles=40)
    env.close()


def rollout(env, seed, actions):
    obs, _ = env.reset(seed=seed)
    seen = [obs]
    rewards = []
    for a in actions:
        obs, r, term, trunc, _ = env.step(a)
        seen.append(obs)
        rewards.append(r)
        if term or trunc:
            break
    return seen, rewards


def test_reset_with_a_seed_is_deterministic():
    rng = np.random.default_rng(0)
    actions = [rng.uniform([-1, 0], [1, 1]).astype(np.float32) for _ in range(15)]
    a, b = gymnasium.make(vwg.gym.ENV_ID, world="maze"), gymnasium.make(vwg.gym.ENV_ID, world="maze")
    obs_a, rew_a = rollout(a, 11, actions)
    obs_b, rew_b = rollout(b, 11, actions)
    assert rew_a == rew_b
    for x, y in zip(obs_a, obs_b, strict=True):
        np.testing.assert_array_equal(x["laser"], y["laser"])
        np.testing.assert_array_equal(x["goal"], y["goal"])
    other, _ = a.reset(seed=12)
    assert not np.array_equal(other["goal"], obs_a[0]["goal"])
    a.close()
    b.close()


def test_an_action_is_a_turn_then_a_drive():
    env = gymnasium.make(vwg.gym.ENV_ID, world="field", max_turn=math.pi / 2, step_length=0.5).unwrapped
    env.reset(seed=2)
    nav = env.nav
    rid = nav.robots[0]

    def pose():
        return nav.case.sim.robot(rid).pose

    x0, y0, yaw0 = pose()
    env.step(np.array([0.5, 0.0], np.float32))  # a quarter of a turn's half: π/4 left, no drive
    x1, y1, yaw1 = pose()
    assert math.hypot(x1 - x0, y1 - y0) < 0.02
    assert math.remainder(yaw1 - yaw0 - math.pi / 4, 2 * math.pi) == pytest.approx(0, abs=0.02)
    env.step(np.array([0.0, 1.0], np.float32))  # straight ahead by a step length
    x2, y2, _ = pose()
    assert nav.info(rid)["collisions"] == 0  # in the open (seed 2 starts clear of the field's obstacles)
    assert math.hypot(x2 - x1, y2 - y1) == pytest.approx(0.5, abs=0.02)
    assert math.atan2(y2 - y1, x2 - x1) == pytest.approx(math.remainder(yaw1, 2 * math.pi), abs=0.03)
    # A discrete move: DISCRETE_MOVES[3] turns left a quarter of a turn.
    denv = gymnasium.make(vwg.gym.ENV_ID, world="field", discrete=True).unwrapped
    denv.reset(seed=2)
    yaw_before = denv.nav.case.sim.robot(rid).pose[2]
    denv.step(3)
    assert math.remainder(denv.nav.case.sim.robot(rid).pose[2] - yaw_before - math.pi / 2, 2 * math.pi) == \
        pytest.approx(0, abs=0.02)
    env.close()
    denv.close()


def test_the_first_observation_from_the_world():
    env = gymnasium.make(vwg.gym.ENV_ID, world="office", beams=24).unwrapped
    obs, info = env.reset(seed=5)
    nav = env.nav
    robot = nav.world.robots[0]
    gx, gy = nav.world.rooms[info["room"]].goal
    x, y, yaw = robot.start
    assert obs["goal"][0] == pytest.approx(math.hypot(gx - x, gy - y), abs=1e-3)
    assert obs["goal"][1] == pytest.approx(math.remainder(math.atan2(gy - y, gx - x) - yaw, 2 * math.pi), abs=1e-3)
    assert obs["laser"].shape == (24,) and obs["laser"].dtype == np.float32
    assert (obs["laser"] > robot.radius * 0.5).all() and (obs["laser"] <= nav.laser.max_range).all()
    # The way left is the length of the shortest way round the walls (an independent distance field).
    field = DistanceField(nav.world.grid.blocked(), nav.world.grid.world_to_cell(gx, gy))
    assert info["way_left_m"] == pytest.approx(field.to(nav.world.grid.world_to_cell(x, y)) * nav.world.grid.resolution)
    env.close()


def guide(nav):
    """A robot that follows the shortest way with some clearance (a field of its own), a metre ahead."""
    rid = nav.robots[0]
    grid = nav.world.grid
    if getattr(nav, "_test_field", (None,))[0] is not nav.case:
        blocked = grid.inflate(0.3)
        blocked[grid.world_to_cell(*nav.case.sim.robot(rid).pose[:2])] = False
        nav._test_field = (nav.case, DistanceField(blocked, grid.world_to_cell(*nav.world.rooms[nav.goals[rid]].goal)))
    dist = nav._test_field[1].distance
    x, y, yaw = nav.case.sim.robot(rid).pose
    r, c = grid.world_to_cell(x, y)
    for _ in range(12):
        step = min((dist[r + dr, c + dc], r + dr, c + dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if dr or dc)
        if step[0] >= dist[r, c]:
            break
        r, c = step[1], step[2]
    tx, ty = grid.cell_to_world(r, c)
    bearing = math.remainder(math.atan2(ty - y, tx - x) - yaw, 2 * math.pi)
    return np.array([np.clip(bearing / (math.pi / 2), -1, 1), min(1.0, math.hypot(tx - x, ty - y) / 0.5)], np.float32)


def test_a_guided_robot_arrives_and_the_reward_adds_up():
    env = gymnasium.make(vwg.gym.ENV_ID, world="office")
    _, info = env.reset(seed=1)
    nav = env.unwrapped.nav
    grid = nav.world.grid
    # The way left, worked out here: a plain Dijkstra round the walls from the room's goal.
    distance = plain_dijkstra(grid.blocked(), grid.world_to_cell(*nav.world.rooms[info["room"]].goal))

    def way_left():
        return distance[grid.world_to_cell(*nav.case.sim.robot(nav.robots[0]).pose[:2])] * grid.resolution

    way0 = way_left()
    assert info["way_left_m"] == pytest.approx(way0)
    total, steps = 0.0, 0
    while True:
        _, reward, terminated, truncated, info = env.step(guide(env.unwrapped.nav))
        total += reward
        steps += 1
        if terminated or truncated:
            break
    assert terminated and not truncated and info["reached"]
    # The documented reward: metres come nearer, -0.01 a step, -1 a collision, +10 on arrival.
    expected = (way0 - way_left()) - 0.01 * steps - 1.0 * info["collisions"] + 10.0
    assert total == pytest.approx(expected, abs=1e-6)
    # The robot drove about as far as the way was long.
    assert way0 * 0.8 < info["travelled_m"] < way0 * 1.3
    env.close()


def test_the_vectorised_form_steps_environments_as_single_ones():
    n = 3
    envs = vwg.gym.make_vec(n, world="maze")
    assert envs.num_envs == n
    obs, _ = envs.reset(seed=40)
    assert obs["laser"].shape == (n, 36) and obs["goal"].shape == (n, 2)
    actions = np.tile(np.array([[0.2, 1.0]], np.float32), (n, 1))
    batched = [envs.step(actions) for _ in range(4)]
    # Environment i is seeded 40 + i (Gymnasium's rule): the same as a single one seeded so.
    for i in range(n):
        single = gymnasium.make(vwg.gym.ENV_ID, world="maze")
        first, _ = single.reset(seed=40 + i)
        np.testing.assert_array_equal(first["goal"], obs["goal"][i])
        for step in batched:
            o, r, *_ = single.step(actions[i])
            np.testing.assert_array_equal(o["laser"], step[0]["laser"][i])
            assert r == step[1][i]
        single.close()
    envs.close()
    with pytest.raises(ValueError, match="num_envs"):
        vwg.gym.make_vec(0)


def test_bad_settings_are_refused_by_name():
    from vwg.errors import SchemaError

    with pytest.raises(SchemaError, match="beams: expected 1 to 4096"):
        gymnasium.make(vwg.gym.ENV_ID, world="office", beams=0)
    with pytest.raises(ValueError, match="render_mode"):
        vwg.gym.NavigateEnv("office", render_mode="ansi")
    env = gymnasium.make(vwg.gym.ENV_ID, world="office").unwrapped
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(2, np.float32))
    env.reset(seed=0)
    with pytest.raises(ValueError, match="two finite numbers"):
        env.step(np.array([np.nan, 1.0]))
    env.close()


def test_render_gives_an_image_of_the_map():
    env = gymnasium.make(vwg.gym.ENV_ID, world="office", render_mode="rgb_array")
    env.reset(seed=0)
    image = env.render()
    assert image.ndim == 3 and image.shape[2] == 3 and image.shape[1] == 480
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 3  # walls, floor, markers and the robot
    env.close()
