"""ARobot's λ and θ (paper eq. 12), case by case, on a 2 m × 1 m map of 0.1 m cells (row 0 at the
bottom, cell (row, col) covers x in [0.1 col, 0.1 col + 0.1), y in [0.1 row, 0.1 row + 0.1)); every
expected cell and value is worked out by hand in the comments."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import vwg
from vwg import _core

RES = 0.1


class Fixed(vwg.robot.Decider):
    """Decides (turn, distance) = self.move, and records what it was given."""

    name = "fixed"

    def __init__(self, move=(0.5, 0.3)) -> None:
        super().__init__()
        self.move = move
        self.seen: list[tuple[tuple[float, float, float], tuple[float, float]]] = []

    def decide(self, robot):
        self.seen.append((robot.pose, robot.goal))
        return self.move


def setup(decider=None, grid_cells=None, **attributes):
    grid = SimpleNamespace(data=np.zeros((10, 20), np.int8), resolution=RES, origin=(0.0, 0.0, 0.0))
    alphabet = vwg.Alphabet(events={n: {f: spec[1] for f, spec in fields.items()}
                                    for n, fields in _core.arobot_event_types().items()} | {"tick": None},
                            visual=["eExecute"], **vwg.robot.platforms.sim.MOTION_SYMBOLS)
    # Room with marker 3: its goal at (1.55, 0.55).
    _core.add_arobot(alphabet, decider or Fixed(), grid, {3: (1.55, 0.55)}, radius=0.1, margin=0.0,
                     goal_tolerance=0.25, step_length=1.0)
    world = vwg.World(alphabet)
    cells = np.zeros((10, 20), np.int16) if grid_cells is None else grid_cells
    values = {"id": 1, "grid": vwg.Blob(cells), "row": 5, "column": 5, "angle": 0.0, "x": 0.55, "y": 0.55}
    values.update(attributes)
    return world, world.string(vwg.Sym("ARobot", **values))


def evolve(world, w, *events):
    return _core.evolve(w, [world.event(e) if isinstance(e, str) else e for e in events])


def robot(w):
    (a,) = w.actors()
    return a


def test_elaser_marks_the_cell_the_beam_stopped_in_and_clears_the_way():
    cells = np.zeros((10, 20), np.int16)
    cells[5, 7] = 101  # an obstacle seen earlier, on the beam's way
    world, w = setup(grid_cells=cells)
    # From (0.55, 0.55) heading 0, a beam at angle 0 ends 0.45 m ahead, at x = 1.0; the cell marked
    # is half a cell beyond the surface: (1.05, 0.55) -> row 5, column 10.
    grid = np.asarray(robot(evolve(world, w, "eLaser<to=1, dist=0.45, angle=0.0>"))["grid"])
    assert grid[5, 10] == 101
    assert grid[5, 7] == 0  # the beam passed through it: cleared
    assert (grid != 0).sum() == 1
    # The angle is relative to the robot's heading: facing +y (π/2), a beam at -π/2 points along +x.
    world, w = setup(angle=math.pi / 2)
    grid = np.asarray(robot(evolve(world, w, f"eLaser<to=1, dist=0.45, angle={-math.pi / 2!r}>"))["grid"])
    assert grid[5, 10] == 101 and (grid != 0).sum() == 1


def test_elaser_keeps_walls_and_markers():
    cells = np.zeros((10, 20), np.int16)
    cells[5, 10] = 100
    world, w = setup(grid_cells=cells)
    grid = np.asarray(robot(evolve(world, w, "eLaser<to=1, dist=0.45, angle=0.0>"))["grid"])
    assert grid[5, 10] == 100


def test_ecamera_marks_the_marker_where_it_was_seen():
    world, w = setup()
    # Marker 3 seen 0.45 m ahead: the cell half a cell beyond, (1.05, 0.55) -> (5, 10), holds 1000 + 3.
    grid = np.asarray(robot(evolve(world, w, "eCamera<to=1, marker=3, dist=0.45, angle=0.0>"))["grid"])
    assert grid[5, 10] == 1003 and (grid != 0).sum() == 1


def test_eobjective_sets_the_goal_and_forgets_the_old_one():
    world, w = setup(reached=True, status="arrived at marker 2", objective=2)
    a = robot(evolve(world, w, "eObjective<to=1, marker=3>"))
    assert (a["objective"], a["reached"], a["status"], len(np.asarray(a["path"]))) == (3, False, "to marker 3", 0)


def test_eodometry_sets_the_pose_its_cell_and_the_acknowledgements():
    world, w = setup()
    a = robot(evolve(world, w, "eOdometry<to=1, x=1.25, y=0.35, angle=0.5, busy=true, commands=4>"))
    assert (a["x"], a["y"], a["angle"]) == (1.25, 0.35, 0.5)
    assert (a["row"], a["column"]) == (3, 12)  # floor(0.35 / 0.1), floor(1.25 / 0.1)
    assert (a["busy"], a["acked"]) == (True, 4)


def test_ecollision_with_a_wall_marks_the_cell_ahead_but_not_with_a_robot():
    world, w = setup()
    # Bumper: radius 0.1 + half a cell ahead of (0.55, 0.55) heading 0 -> (0.70, 0.55) -> (5, 7).
    a = robot(evolve(world, w, "eCollision<to=1, other=0>"))
    grid = np.asarray(a["grid"])
    assert a["collisions"] == 1 and grid[5, 7] == 101 and (grid != 0).sum() == 1
    a = robot(evolve(world, w, "eCollision<to=1, other=2>"))
    assert a["collisions"] == 1 and (np.asarray(a["grid"]) != 0).sum() == 0


def test_edecide_asks_the_decider_and_moves_the_belief():
    decider = Fixed(move=(0.5, 0.3))
    world, w = setup(decider, objective=3)
    a = robot(evolve(world, w, "eDecide<to=1>"))
    assert decider.seen == [((0.55, 0.55, 0.0), (1.55, 0.55))]  # its pose and its room's goal
    assert (a["acting"], a["turn"], a["move"]) == (True, 0.5, 0.3)  # shown by θ as Rotate<0.5>(Move<0.3>(...))
    assert (a["sent"], a["busy"]) == (1, True)
    # Dead reckoning: turn 0.5 rad, then 0.3 m: (0.55 + 0.3 cos 0.5, 0.55 + 0.3 sin 0.5).
    assert (a["x"], a["y"], a["angle"]) == pytest.approx((0.55 + 0.3 * math.cos(0.5), 0.55 + 0.3 * math.sin(0.5), 0.5))
    # While the motors have not acknowledged the command (acked < sent) it decides nothing more.
    a2 = robot(evolve(world, evolve(world, w, "eDecide<to=1>"), "eDecide<to=1>"))
    assert len(decider.seen) == 2 and a2["sent"] == 1 and not a2["acting"]


def test_edecide_at_the_goal_says_reached_and_asks_nothing():
    decider = Fixed()
    # 0.2 m from the goal (1.55, 0.55): within the tolerance of 0.25 m.
    world, w = setup(decider, objective=3, x=1.35, y=0.55)
    a = robot(evolve(world, w, "eDecide<to=1>"))
    assert decider.seen == []
    assert (a["reached"], a["status"], a["acting"]) == (True, "arrived at marker 3", False)


def test_edecide_without_an_objective_does_nothing():
    decider = Fixed()
    world, w = setup(decider)
    assert str(evolve(world, w, "eDecide<to=1>")) == str(w)
    assert decider.seen == []


def test_eexecute_shows_the_action_or_the_robot_alone_with_its_status_and_path():
    world, w = setup(acting=True, turn=0.5, move=0.3)
    shown = _core.visualize(w, [world.event("eExecute<to=1>")])
    assert str(shown) == 'Status<1, "idle"> . Rotate<0.5>(Move<0.3>(Robot<1>))'
    world, w = setup()
    assert str(_core.visualize(w, [world.event("eExecute<to=1>")])) == 'Status<1, "idle"> . Robot<1>'
    # A planned path is shown too, as its points (the same blob the robot holds).
    points = np.array([[0.55, 0.55], [1.05, 0.55]])
    world, w = setup(path=vwg.Blob(points), status="to marker 3")
    shown = _core.visualize(w, [world.event("eExecute<to=1>")])
    text = str(shown)
    assert text.startswith("Path<1, @") and text.endswith('> . Status<1, "to marker 3"> . Robot<1>')
    np.testing.assert_array_equal(np.asarray(robot(w)["path"]), points)


def test_other_events_leave_the_robot_as_it_is():
    world, w = setup()
    assert str(evolve(world, w, "tick")) == str(w)
    # An event for another robot does not reach this one.
    assert str(evolve(world, w, "eOdometry<to=2, x=1.0, y=1.0, angle=0.0, busy=false, commands=1>")) == str(w)
