"""Robot world files (the case study's worlds): the shipped worlds load and every room is reachable; each kind of
mistake is reported with the file, the line and the field."""

from __future__ import annotations

import math
from collections import deque
from pathlib import Path

import numpy as np
import pytest

from vwg.errors import WorldFileError
from vwg.io.maps import OccupancyGrid
from vwg.robot.platforms.sim import CameraSpec, DepthCameraSpec, LaserSpec, NoiseModel
from vwg.robot.world_file import RobotWorld, load_robot_world

ROOT = Path(__file__).resolve().parents[1]
MAPS = ROOT / "maps"
SHIPPED = sorted(p.stem for p in MAPS.glob("*.yaml"))


# ---- the shipped worlds ---------------------------------------------------------------------------------------
def test_at_least_five_worlds_ship() -> None:
    assert {"office", "maze", "warehouse", "field", "willow"} <= set(SHIPPED)
    assert (MAPS / "README.md").is_file()
    assert "BSD" in (MAPS / "willow" / "SOURCE.md").read_text()


def free_space(grid: OccupancyGrid, radius: float) -> np.ndarray:
    """Cells a disc of `radius` can be centred on: farther than `radius` from every blocked or unknown cell
    (and from the map's edge). Written here apart from OccupancyGrid.inflate, by distance to cell squares."""
    blocked = np.pad(grid.data >= 50, 1, constant_values=True) | np.pad(grid.data < 0, 1, constant_values=True)
    k = math.ceil(radius / grid.resolution) + 1
    out = np.ones(grid.data.shape, dtype=bool)
    h, w = grid.data.shape
    for dr in range(-k, k + 1):
        for dc in range(-k, k + 1):
            gap = math.hypot(max(abs(dr) - 0.5, 0), max(abs(dc) - 0.5, 0)) * grid.resolution
            if gap < radius:
                shifted = np.pad(blocked, k, constant_values=True)[k + 1 + dr:k + 1 + dr + h, k + 1 + dc:k + 1 + dc + w]
                out &= ~shifted
    return out


def reach(free: np.ndarray, start: tuple[int, int]) -> np.ndarray:
    """8-connected breadth-first search; a diagonal step needs both side cells free."""
    seen = np.zeros_like(free)
    seen[start] = free[start]
    queue = deque([start] if free[start] else [])
    while queue:
        r, c = queue.popleft()
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if (0 <= nr < free.shape[0] and 0 <= nc < free.shape[1] and free[nr, nc] and not seen[nr, nc]
                        and free[r + dr, c] and free[r, c + dc]):
                    seen[nr, nc] = True
                    queue.append((nr, nc))
    return seen


@pytest.mark.parametrize("name", SHIPPED)
@pytest.mark.slow
def test_shipped_world_loads_and_every_room_is_reachable(name: str) -> None:
    world = load_robot_world(MAPS / f"{name}.yaml")
    assert isinstance(world, RobotWorld) and world.name == name
    assert world.map_path == MAPS / name / "map.yaml"
    assert world.grid.resolution == 0.05
    assert 1 <= len(world.robots) <= 3 and len(world.rooms) >= 4 and world.orders
    assert len(world.markers) == len(world.rooms)
    for robot in world.robots:
        area = reach(free_space(world.grid, robot.radius), world.grid.world_to_cell(*robot.start[:2]))
        for room in world.rooms.values():
            assert area[world.grid.world_to_cell(*room.goal)], f"robot {robot.id} cannot reach {room.name}"


def test_office() -> None:
    world = load_robot_world(MAPS / "office.yaml")
    assert {"kitchen", "lab", "meeting", "office"} <= set(world.rooms)
    assert len(world.robots) == 2
    assert 24 <= world.grid.width_m <= 26 and 17 <= world.grid.height_m <= 19
    assert world.rooms["kitchen"].goal == pytest.approx((5.5, 16.8))  # 1 m in front of the marker
    assert world.room_of_marker(world.rooms["lab"].marker) is world.rooms["lab"]
    assert {o.robot for o in world.orders} == {1, 2}


def test_shipped_sizes() -> None:
    grids = {name: load_robot_world(MAPS / f"{name}.yaml").grid for name in ("maze", "warehouse", "field")}
    sizes = {name: (g.width_m, g.height_m) for name, g in grids.items()}
    assert sizes["maze"] == pytest.approx((15.1, 15.1))
    assert sizes["warehouse"] == pytest.approx((30.0, 20.0))
    assert sizes["field"] == pytest.approx((20.0, 20.0))


# ---- a small world for the error cases ------------------------------------------------------------------------
# 6 × 4 m at 0.05 m: 0.2 m walls all round and a wall stub x 2.8..3.2, y 0..2.0
def room_map(directory: Path) -> Path:
    data = np.zeros((80, 120), np.int8)
    data[:4, :] = data[-4:, :] = 100
    data[:, :4] = data[:, -4:] = 100
    data[:40, 56:64] = 100
    return OccupancyGrid(data, 0.05).save(directory / "room" / "map.yaml")


BASE = """\
name: test
map: room/map.yaml
wall_height: 2.5
rooms:
  east:
    marker: 3
    at: [5.8, 2.0]
    facing: 3.141592653589793
  stub:
    marker: 4
    at: [3.2, 1.0]
    facing: 0.0
    size: 0.2
    height: 0.5
    goal: [3.9, 1.0]
robots:
  - id: 1
    start: [1.0, 1.0, 0.0]
  - id: 2
    start: [1.0, 3.0, 0.0]
    radius: 0.25
    sensors: [kinect, camera]
laser: {beams: 180, noise: 0.02}
camera: {width: 320, height: 240, mount_height: 0.4}
frames: 100
orders:
  - {time: 5.0, robot: 2, room: stub}
  - {time: 0.0, robot: 1, room: east}
"""


@pytest.fixture
def world_dir(tmp_path: Path) -> Path:
    room_map(tmp_path)
    return tmp_path


def write(directory: Path, text: str) -> Path:
    path = directory / "world.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def line_of(text: str, needle: str) -> int:
    for i, line in enumerate(text.splitlines(), 1):
        if needle in line:
            return i
    raise AssertionError(needle)


def test_small_world_loads_with_defaults(world_dir: Path) -> None:
    world = load_robot_world(write(world_dir, BASE))
    assert world.name == "test" and world.description == ""
    assert (world.grid.width, world.grid.height) == (120, 80)
    east = world.rooms["east"]
    assert (east.marker, east.at, east.size, east.height) == (3, (5.8, 2.0), 0.3, 0.6)
    assert east.goal == pytest.approx((4.8, 2.0))
    assert world.rooms["stub"].goal == (3.9, 1.0)
    r1, r2 = world.robots
    assert (r1.radius, r1.max_speed, r1.max_turn_rate, r1.max_accel, r1.max_turn_accel) == (0.18, 0.5, 1.5, 1.0, 4.0)
    assert r1.sensors == ("laser", "camera") and r2.sensors == ("kinect", "camera") and r2.radius == 0.25
    assert world.sensors["laser"] == LaserSpec(beams=180, fov=2 * math.pi, max_range=8.0, noise=0.02)
    assert world.noise == NoiseModel() and (world.noise.odometry, world.noise.motors) == (0.0, 0.0)
    assert world.sensors["kinect"] == DepthCameraSpec(wall_height=2.5)
    assert world.sensors["kinect"].hfov == pytest.approx(math.radians(58))
    assert world.sensors["camera"] == CameraSpec(width=320, height=240, mount_height=0.4)
    assert LaserSpec().noise == 0.01 and world.sensors["laser"].min_range == 0.05  # the C++ struct's defaults
    assert (world.frames, world.dt, world.seed, world.wall_height) == (100, 0.1, 0, 2.5)
    assert [(o.time, o.robot, o.room) for o in world.orders] == [(0.0, 1, "east"), (5.0, 2, "stub")]  # by time
    assert world.robot(2) is r2 and world.markers == {3: "east", 4: "stub"}
    assert world.data["frames"] == 100


def test_name_defaults_to_stem_and_movingai_map(tmp_path: Path) -> None:
    rows = ["@@@@@@@@@@"] + ["@........@"] * 8 + ["@@@@@@@@@@"]
    (tmp_path / "box.map").write_text("type octile\nheight 10\nwidth 10\nmap\n" + "\n".join(rows) + "\n")
    text = ("map: {movingai: box.map, resolution: 0.5, origin: [0.0, 0.0, 0.0]}\n"
            "rooms:\n  west: {marker: 0, at: [0.5, 2.5], facing: 0.0}\n"
            "robots:\n  - {id: 7, start: [3.0, 2.5, 0.0]}\n")
    path = tmp_path / "boxworld.yaml"
    path.write_text(text)
    world = load_robot_world(path)
    assert world.name == "boxworld" and world.grid.resolution == 0.5 and world.map_path == tmp_path / "box.map"
    assert world.rooms["west"].goal == pytest.approx((1.5, 2.5))
    assert world.orders == [] and world.frames == 3000 and world.dt == 0.1


# ---- error cases: (replace this, with that) -> field, the line to point at, message ---------------------------
CASES = [
    # unknown keys
    ("frames: 100", "frames: 100\nspeed: 2", "speed", "speed: 2", "unknown key"),
    ("    marker: 3", "    marker: 3\n    colour: red", "rooms.east.colour", "colour: red", "unknown key"),
    ("    radius: 0.25", "    radius: 0.25\n    max_sped: 1.0", "robots[1].max_sped", "max_sped",
     "did you mean 'max_speed'"),
    ("laser: {beams: 180, noise: 0.02}", "laser: {beams: 180, nois: 0.02}", "laser.nois", "laser:", "unknown key"),
    # wrong types
    ("wall_height: 2.5", "wall_height: high", "wall_height", "wall_height", "expected an integer or a number"),
    ("    marker: 3", "    marker: 3.5", "rooms.east.marker", "marker: 3.5", "expected an integer"),
    ("    sensors: [kinect, camera]", "    sensors: kinect", "robots[1].sensors", "sensors: kinect",
     "expected a list"),
    ("    start: [1.0, 3.0, 0.0]", "    start: [1.0, 3.0]", "robots[1].start", "start: [1.0, 3.0]",
     "expected [x, y, yaw]"),
    ("    at: [5.8, 2.0]", "    at: [5.8, yes]", "rooms.east.at[1]", "at: [5.8, yes]", "got bool"),
    ("name: test", "name: [test]", "name", "name: [test]", "expected text"),
    ("map: room/map.yaml", "map: 3", "map", "map: 3", "expected text or a mapping"),
    # NaN and out-of-range numbers
    ("frames: 100", "frames: 100\ndt: .nan", "dt", "dt: .nan", "finite"),
    ("    radius: 0.25", "    radius: -0.1", "robots[1].radius", "radius: -0.1", "> 0"),
    ("frames: 100", "frames: -1", "frames", "frames: -1", ">= 0"),
    ("frames: 100", "frames: 100\nseed: 1.5", "seed", "seed: 1.5", "expected an integer"),
    ("wall_height: 2.5", "wall_height: 0", "wall_height", "wall_height: 0", "> 0"),
    ("laser: {beams: 180, noise: 0.02}", "laser: {beams: 0}", "laser.beams", "laser:",
     "expected 1 to 100000 beams, got 0"),
    ("laser: {beams: 180, noise: 0.02}", "laser: {fov: 7.0}", "laser.fov", "laser:", "(0, 2π] radians, got 7.0"),
    ("laser: {beams: 180, noise: 0.02}", "laser: {noise: -0.01}", "laser.noise", "laser:", ">= 0"),
    ("    radius: 0.25", "    radius: 0.25\n    max_speed: .inf", "robots[1].max_speed", "max_speed", "finite"),
    ("frames: 100", "frames: 100\nkinect: {min_range: 5.0}", "kinect.min_range", "kinect:", "less than max_range"),
    ("    height: 0.5", "    height: 0.05", "rooms.stub.height", "height: 0.05", "does not fit"),
    ("    height: 0.5", "    height: 2.45", "rooms.stub.height", "height: 2.45", "does not fit"),
    ("frames: 100", "frames: 100\nnoise: {laser: 0.05}", "noise.laser", "noise: {", "conflicts with laser.noise"),
    ("frames: 100", "frames: 100\nnoise: {odometry: -0.1}", "noise.odometry", "noise: {", ">= 0"),
    # sensors
    ("    sensors: [kinect, camera]", "    sensors: [kinect, sonar]", "robots[1].sensors[1]", "sonar",
     "unknown sensor 'sonar'"),
    ("    sensors: [kinect, camera]", "    sensors: [camera, camera]", "robots[1].sensors[1]", "camera, camera",
     "listed twice"),
    # duplicate ids
    ("    marker: 4", "    marker: 3", "rooms.stub.marker", "    marker: 3\n    at: [3.2", "already names room 'east'"),
    ("  - id: 2", "  - id: 1", "robots[1].id", "  - id: 1\n    start: [1.0, 3.0", "already used by robots[0]"),
    ("  - id: 2", "  - id: 0", "robots[1].id", "id: 0", ">= 1"),
    # marker ids out of range
    ("    marker: 3", "    marker: 587", "rooms.east.marker", "marker: 587", "<= 586"),
    ("    marker: 3", "    marker: -1", "rooms.east.marker", "marker: -1", ">= 0"),
    # markers not on a wall
    ("    at: [5.8, 2.0]", "    at: [5.0, 2.0]", "rooms.east.at", "at: [5.0, 2.0]", "not on a wall face"),
    ("    facing: 3.141592653589793", "    facing: 0.0", "rooms.east.at", "at: [5.8, 2.0]", "not on a wall face"),
    ("    at: [3.2, 1.0]", "    at: [3.2, 2.5]", "rooms.stub.at", "at: [3.2, 2.5]", "not on a wall face"),
    ("    at: [5.8, 2.0]", "    at: [7.0, 2.0]", "rooms.east.at", "at: [7.0, 2.0]", "outside the map"),
    # goals
    ("    goal: [3.9, 1.0]", "    goal: [3.0, 1.0]", "rooms.stub.goal", "goal: [3.0, 1.0]", "is inside a wall"),
    ("    goal: [3.9, 1.0]", "    goal: [3.4, 1.0]", "rooms.stub.goal", "goal: [3.4, 1.0]",
     "closer than the radius 0.25 m of the largest robot"),
    ("    goal: [3.9, 1.0]", "    goal: [9.0, 1.0]", "rooms.stub.goal", "goal: [9.0, 1.0]", "outside the map"),
    ("    at: [5.8, 2.0]", "    at: [5.8, 3.7]", "rooms.east.goal", "  east:", "closer than the radius"),
    # robot starts
    ("    start: [1.0, 3.0, 0.0]", "    start: [3.0, 1.0, 0.0]", "robots[1].start", "start: [3.0, 1.0",
     "robot 2 at (3.0, 1.0) is inside a wall"),
    ("    start: [1.0, 3.0, 0.0]", "    start: [-1.0, 3.0, 0.0]", "robots[1].start", "start: [-1.0",
     "robot 2 at (-1.0, 3.0) is outside the map"),
    ("    start: [1.0, 3.0, 0.0]", "    start: [0.4, 3.0, 0.0]", "robots[1].start", "start: [0.4",
     "robot 2 at (0.4, 3.0) is 0.200 m from a wall, closer than the radius 0.25 m"),
    ("    start: [1.0, 3.0, 0.0]", "    start: [1.2, 1.3, 0.0]", "robots[1].start", "start: [1.2",
     "robot 2 overlaps robot 1"),
    # orders
    ("  - {time: 5.0, robot: 2, room: stub}", "  - {time: 5.0, robot: 2, room: kitchen}", "orders[0].room",
     "room: kitchen", "no room named 'kitchen'"),
    ("  - {time: 5.0, robot: 2, room: stub}", "  - {time: 5.0, robot: 2, room: stb}", "orders[0].room",
     "room: stb", "did you mean 'stub'"),
    ("  - {time: 5.0, robot: 2, room: stub}", "  - {time: 5.0, robot: 9, room: stub}", "orders[0].robot",
     "robot: 9", "no robot with id 9"),
    ("  - {time: 5.0, robot: 2, room: stub}", "  - {time: -1.0, robot: 2, room: stub}", "orders[0].time",
     "time: -1.0", ">= 0"),
    ("  - {time: 5.0, robot: 2, room: stub}", "  - {time: 5.0, robot: 2, room: stub, who: me}", "orders[0].who",
     "who: me", "unknown key"),
    # the map
    ("map: room/map.yaml", "map: room/nothere.yaml", "map", "map: room/nothere.yaml", "not found"),
    ("map: room/map.yaml", "map: {movingai: x.map, scale: 2}", "map.scale", "map: {", "unknown key"),
    # settings read through the C++ structs: their types and ranges
    ("laser: {beams: 180, noise: 0.02}", "laser: {beams: 1.0e+9}", "laser.beams", "laser:",
     "expected an integer, got float 1000000000.0"),
    ("laser: {beams: 180, noise: 0.02}", "laser: {beams: 1180591620717411303424}", "laser.beams", "laser:",
     "expected an integer from -2147483648 to 2147483647"),
    ("laser: {beams: 180, noise: 0.02}", "laser: {min_range: 9.0}", "laser.max_range", "laser:",
     "expected a finite range > min_range (9.0)"),
    ("frames: 100", "frames: 100\nkinect: {wall_height: 3.0}", "kinect.wall_height", "kinect:", "unknown key"),
    ("frames: 100", "frames: 100\nkinect: {noise: 1}", "kinect.noise", "kinect:",
     "expected true or false, got int 1"),
    ("frames: 100", "frames: 100\nkinect: {scan_rows: 500}", "kinect.scan_rows", "kinect:",
     "expected 1 to height rows"),
    ("camera: {width: 320, height: 240, mount_height: 0.4}", "camera: {mount_height: 2.6}", "camera.wall_height",
     "camera:", "expected a finite height above the camera's mount_height"),
    ("    radius: 0.25", "    radius: 0.25\n    max_speed: fast", "robots[1].max_speed", "max_speed",
     "expected a number, got str 'fast'"),
    ("    start: [1.0, 3.0, 0.0]", "    start: [1.0, 3.0, .nan]", "robots[1].start", "start: [1.0, 3.0, .nan]",
     "expected finite x, y, yaw"),
    # a platform's options, checked by the platform's own list
    ("frames: 100", "frames: 100\nplatform: {kind: rosbridge, url: 'ws://127.0.0.1:9', watchdg: 0.3}",
     "platform.watchdg", "platform:", "did you mean 'watchdog'"),
    ("frames: 100", "frames: 100\nplatform: {kind: sim, url: 'ws://127.0.0.1:9'}", "platform.url", "platform:",
     "unknown key"),
    # sensors' two heights
    ("camera: {width: 320, height: 240, mount_height: 0.4}", "camera: {width: 320, height: 240, height: 0.4}",
     "camera.height", "camera:", "duplicate key; the image size is width/height and the mounting height is"),
]


@pytest.mark.parametrize(("old", "new", "field", "needle", "message"), CASES,
                         ids=[f"{c[2]}:{c[4][:24]}" for c in CASES])
def test_error_names_file_line_and_field(world_dir: Path, old: str, new: str, field: str, needle: str,
                                         message: str) -> None:
    assert old in BASE
    text = BASE.replace(old, new, 1)
    path = write(world_dir, text)
    with pytest.raises(WorldFileError) as e:
        load_robot_world(path)
    err = e.value
    assert message in str(err)
    assert err.path == str(path)
    assert err.field == field
    want = text[:text.index(needle)].count("\n") + 1 if "\n" in needle else line_of(text, needle)
    assert err.line == want
    assert str(err).startswith(f"{path}:{err.line}: {field}: ")


def test_missing_and_malformed(world_dir: Path) -> None:
    for text, field, message in (("map: room/map.yaml\n", "robots", "missing"),
                                 ("robots:\n  - {id: 1, start: [1.0, 1.0, 0.0]}\n", "map", "missing"),
                                 ("map: room/map.yaml\nrobots: []\n", "robots", "at least one robot"),
                                 ("- 1\n- 2\n", "", "expected a mapping")):
        with pytest.raises(WorldFileError, match=message) as e:
            load_robot_world(write(world_dir, text))
        assert e.value.field == field
    with pytest.raises(WorldFileError, match="not valid YAML") as e:
        load_robot_world(write(world_dir, BASE.replace("frames: 100", "frames: [100")))
    assert e.value.line > 0
    with pytest.raises(WorldFileError, match="file not found"):
        load_robot_world(world_dir / "nothere.yaml")


def test_error_in_the_map_file_names_the_map(world_dir: Path) -> None:
    (world_dir / "room" / "map.yaml").write_text("image: map.pgm\nresolution: 0\norigin: [0, 0, 0]\nnegate: 0\n"
                                                 "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    with pytest.raises(WorldFileError, match=r">= 0\.0001") as e:
        load_robot_world(write(world_dir, BASE))
    assert (e.value.path, e.value.field, e.value.line) == (str(world_dir / "room" / "map.yaml"), "resolution", 2)


def test_unknown_space_start(tmp_path: Path) -> None:
    data = np.full((40, 40), -1, np.int8)
    data[10:30, 10:30] = 0
    OccupancyGrid(data, 0.1).save(tmp_path / "m.yaml")
    text = "map: m.yaml\nrobots:\n  - {id: 1, start: [0.5, 0.5, 0.0]}\n"
    with pytest.raises(WorldFileError, match=r"robot 1 at \(0.5, 0.5\) is in unknown space") as e:
        load_robot_world(write(tmp_path, text))
    assert (e.value.field, e.value.line) == ("robots[0].start", 3)
    text = "map: m.yaml\nrobots:\n  - {id: 1, start: [1.1, 2.0, 0.0]}\n"
    with pytest.raises(WorldFileError, match=r"is 0\.100 m from a wall"):  # unknown space counts as a wall
        load_robot_world(write(tmp_path, text))
    assert load_robot_world(write(tmp_path, text.replace("1.1", "2.0"))).robots[0].start == (2.0, 2.0, 0.0)


def test_every_setting_of_the_structs_is_a_world_file_key(world_dir: Path) -> None:
    # The sections take the C++ structs' fields (LaserSpec.fields() lists them), each set as written.
    text = BASE.replace("laser: {beams: 180, noise: 0.02}",
                        "laser: {beams: 90, fov: 3.0, min_range: 0.1, max_range: 5.0, noise: 0.0}\n"
                        "kinect: {width: 320, height: 240, hfov: 1.0, min_range: 0.4, max_range: 3.0,"
                        " mount_height: 0.2, robot_height: 0.5, noise: true, noise_a: 0.002, noise_b: 0.003,"
                        " scan_rows: 3}")
    world = load_robot_world(write(world_dir, text))
    assert world.sensors["laser"] == LaserSpec(beams=90, fov=3.0, min_range=0.1, max_range=5.0, noise=0.0)
    assert world.sensors["kinect"] == DepthCameraSpec(width=320, height=240, hfov=1.0, min_range=0.4, max_range=3.0,
                                           mount_height=0.2, wall_height=2.5, robot_height=0.5, noise=True,
                                           noise_a=0.002, noise_b=0.003, scan_rows=3)
    assert [name for name, *_ in LaserSpec.fields()] == ["beams", "fov", "min_range", "max_range", "noise"]
    assert [name for name, *_ in CameraSpec.fields()] == ["width", "height", "hfov", "mount_height", "wall_height",
                                                          "robot_height", "noise", "blur", "period"]


def test_the_structs_defaults_are_the_documented_ones() -> None:
    # The module docs and the README give these; the structs are the only place that holds them.
    assert LaserSpec() == LaserSpec(beams=360, fov=2 * math.pi, min_range=0.05, max_range=8.0, noise=0.01)
    assert (CameraSpec().width, CameraSpec().height, CameraSpec().hfov) == (640, 480, pytest.approx(math.pi / 3))
    assert DepthCameraSpec().hfov == pytest.approx(math.radians(58)) and DepthCameraSpec().min_range == 0.5
    assert NoiseModel() == NoiseModel(motors=0.0, odometry=0.0)


def test_settings_copy_pickle_and_refuse_unknown_fields() -> None:
    import copy
    import pickle

    from vwg import SchemaError
    from vwg.robot import RobotSettings
    from vwg.robot.platforms.sim import PhysicsSettings

    robot = RobotSettings(id=3, start=(1.0, 2.0, 0.5), sensors=["laser"])
    assert robot.sensors == ("laser",) and robot.max_speed == 0.5
    assert pickle.loads(pickle.dumps(robot)) == robot and copy.copy(robot) == robot
    faster = robot.replace(max_speed=1.2)
    assert faster.max_speed == 1.2 and robot.max_speed == 0.5 and faster != robot
    physics = PhysicsSettings(noise={"motors": 0.1})
    assert physics.noise == NoiseModel(motors=0.1) and physics.step == 0.01
    with pytest.raises(SchemaError, match=r"LaserSpec\.beamz: unknown setting \(expected one of beams, fov"):
        LaserSpec(beamz=3)
    with pytest.raises(SchemaError, match=r"RobotSettings\.start: expected \[x, y, yaw\]"):
        RobotSettings(start=(1.0, 2.0))
    with pytest.raises(SchemaError, match=r"robot\.radius: expected a finite number > 0 and <= 100\.0, got -1"):
        RobotSettings(radius=-1.0).check("robot")
