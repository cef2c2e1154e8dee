"""The simulated robot camera and the 3D overview from Python (vwg._core.CameraRenderer, render_overview,
overview_camera). Expected values come from the scene definition and the pinhole model written out here
(fx = (w/2)/tan(hfov/2), cx = (w-1)/2: the camera's documented intrinsics) or from the shipped maps' cells,
never from the renderer; the AprilTag detector and pose estimate (tested in test_apriltag.py) measure the
rendered markers."""

from __future__ import annotations

import math
import re
import threading
from pathlib import Path

import numpy as np
import pytest

import vwg
from vwg import _core

ROOT = Path(__file__).resolve().parents[1]
MAPS = ["office", "maze", "warehouse", "field", "willow"]
RES = 0.05


# --- scenes and the pinhole model -------------------------------------------------------------------


def east_wall_room() -> vwg.io.maps.OccupancyGrid:
    """20 m × 20 m at 0.05 m per cell; everything east of x = 10 m is wall, so its face is the plane x = 10,
    facing west (-x)."""
    data = np.zeros((400, 400), np.int8)
    data[:, 200:] = 100
    return vwg.io.maps.OccupancyGrid(data, RES)


class Pinhole:
    """The camera's documented projection: level, at mount_height, looking along the heading."""

    def __init__(self, width=640, height=480, hfov=math.pi / 3, mount=0.5):
        self.fx = width / 2 / math.tan(hfov / 2)
        self.cx = (width - 1) / 2
        self.cy = (height - 1) / 2
        self.mount = mount
        self.width = width
        self.height = height

    def project(self, pose, x, y, z):
        px, py, th = pose
        dx, dy = x - px, y - py
        depth = dx * math.cos(th) + dy * math.sin(th)
        right = dx * math.sin(th) - dy * math.cos(th)
        assert depth > 0
        return self.cx + self.fx * right / depth, self.cy + self.fx * (self.mount - z) / depth


def black_corners(marker):
    """World corners of the marker's black square in the detector's order for an upright tag: p0 bottom-left,
    p1 bottom-right, p2 top-right, p3 top-left."""
    x, y = marker["at"]
    rx, ry = -math.sin(marker["facing"]), math.cos(marker["facing"])  # right of a viewer facing the marker
    h = marker["size"] / 2
    z = marker["height"]
    return [(x - rx * h, y - ry * h, z - h), (x + rx * h, y + ry * h, z - h),
            (x + rx * h, y + ry * h, z + h), (x - rx * h, y - ry * h, z + h)]


def fully_in_view(pin: Pinhole, pose, marker, margin=2.0) -> bool:
    """Whether the drawn square (the tag with its white ring: 10/8 of the black square) is inside the image."""
    drawn = dict(marker, size=marker["size"] * 10 / 8)
    for x, y, z in black_corners(drawn):
        px, py, th = pose
        if (x - px) * math.cos(th) + (y - py) * math.sin(th) <= 0:
            return False
        u, v = pin.project(pose, x, y, z)
        if not (margin <= u <= pin.width - 1 - margin and margin <= v <= pin.height - 1 - margin):
            return False
    return True


def re_field(field: str) -> str:
    """A pattern for an error message that starts by naming `field` (vwg.SchemaError's "field: message")."""
    return "^" + re.escape(field) + ":"


def marker(tag_id=7, height=0.5, size=0.3):
    return {"id": tag_id, "at": (10.0, 10.0), "facing": math.pi, "size": size, "height": height}


# --- intrinsics and images ----------------------------------------------------------------------------


def test_intrinsics_follow_the_field_of_view():
    cam = _core.CameraRenderer(east_wall_room(), [])
    assert cam.width == 640 and cam.height == 480
    assert cam.fx == pytest.approx(320 / math.tan(math.pi / 6), abs=1e-9)
    assert cam.fy == cam.fx
    assert (cam.cx, cam.cy) == (319.5, 239.5)
    fx, fy, cx, cy = cam.apriltag_intrinsics()
    assert (fx, fy, cx, cy) == (cam.fx, cam.fy, 320.0, 240.0)
    other = _core.CameraRenderer(east_wall_room(), [], vwg.robot.CameraSpec(width=320, height=200, hfov=1.2))
    assert other.fx == pytest.approx(160 / math.tan(0.6), abs=1e-9)
    assert (other.cx, other.cy) == (159.5, 99.5)


def test_images_are_uint8_rgb_or_grey():
    cam = _core.CameraRenderer(east_wall_room(), [marker()], vwg.robot.CameraSpec(width=200, height=150))
    rgb = cam.render((6.0, 10.0, 0.0))
    grey = cam.render((6.0, 10.0, 0.0), grey=True)
    assert rgb.shape == (150, 200, 3) and rgb.dtype == np.uint8
    assert grey.shape == (150, 200) and grey.dtype == np.uint8
    luma = rgb[..., 0] * 0.299 + rgb[..., 1] * 0.587 + rgb[..., 2] * 0.114
    assert np.max(np.abs(luma - grey)) <= 2.0  # the same scene; rounding and per-channel blending aside


@pytest.mark.parametrize("d", [1.5, 2.5, 4.0, 7.0])
def test_wall_top_and_foot_where_the_pinhole_puts_them(d):
    # Walls 1 m tall, so the top (0.5 m above the camera) is in view from 1.2 m on.
    cam = _core.CameraRenderer(east_wall_room(), [], vwg.robot.CameraSpec(wall_height=1.0))
    pin = Pinhole()
    grey = cam.render((10.0 - d, 10.0, 0.0), grey=True).astype(int)  # square on: every column's depth is d
    top = pin.cy - pin.fx * (1.0 - 0.5) / d
    foot = pin.cy + pin.fx * 0.5 / d
    for col in (0, 200, 320, 639):
        column = grey[:, col]
        ceiling, wall, floor = column[0], column[240], column[-1]
        assert abs(ceiling - wall) > 10 and abs(floor - wall) > 10
        first = int(np.argmax(np.abs(column - wall) < np.abs(column - ceiling)))
        last = int(np.nonzero(np.abs(column - wall) < np.abs(column - floor))[0][-1])
        assert abs(first - top) <= 1.0, (col, first, top)
        assert abs(last - foot) <= 1.0, (col, last, foot)


POSES = [(9.0, 10.0, 0.0), (7.5, 10.0, 0.0), (8.0, 10.3, -0.25), (8.4, 8.5, math.pi / 4 - 0.1), (6.0, 11.0, -0.3)]


@pytest.mark.parametrize("pose", POSES)
def test_marker_corners_where_the_pinhole_puts_them(pose):
    m = marker(42)
    cam = _core.CameraRenderer(east_wall_room(), [m])
    pin = Pinhole()
    found = _core.detect_apriltags(cam.render(pose, grey=True), quad_decimate=1.0)
    assert [d.id for d in found] == [42]
    expected = np.array([pin.project(pose, *p) for p in black_corners(m)])
    # The detector's pixel centres are at +0.5.
    assert np.max(np.abs(found[0].corners - 0.5 - expected)) <= 1.0


# --- detection ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("d", [0.5, 1.0, 2.0, 3.0, 4.0, 5.0])
def test_marker_distance_and_bearing(d):
    m = marker(7)
    cam = _core.CameraRenderer(east_wall_room(), [m])
    pin = Pinhole()
    seen = 0
    for oblique in (0.0, 30.0, 45.0, -45.0):
        for bearing in (0.0, 20.0, -20.0, 10.0):
            a, b = math.radians(oblique), math.radians(bearing)
            x, y = 10.0 - d * math.cos(a), 10.0 + d * math.sin(a)
            pose = (x, y, math.atan2(10.0 - y, 10.0 - x) - b)  # the marker `bearing` to the left of the axis
            if not fully_in_view(pin, pose, m):
                continue
            found = _core.detect_apriltags(cam.render(pose, grey=True))
            assert [f.id for f in found] == [7], (oblique, bearing)
            tag = _core.estimate_tag_pose(found[0], m["size"], *cam.apriltag_intrinsics())
            assert abs(tag.distance - d) / d < 0.05, (oblique, bearing, tag.distance)
            assert abs(math.degrees(tag.bearing) - bearing) < 2.0, (oblique, bearing, tag.bearing)
            seen += 1
    # Square on always; from 1 m on, turned and oblique views too (nearer, they do not hold the whole tag).
    assert seen >= (1 if d < 1.0 else 4)


def clear_line(grid: vwg.io.maps.OccupancyGrid, a, b) -> bool:
    """No wall cell on the segment a-b (sampled every 1/4 cell)."""
    n = int(math.hypot(b[0] - a[0], b[1] - a[1]) / (grid.resolution / 4)) + 1
    for t in np.linspace(0.0, 1.0, n):
        col = int((a[0] + t * (b[0] - a[0]) - grid.origin[0]) // grid.resolution)
        row = int((a[1] + t * (b[1] - a[1]) - grid.origin[1]) // grid.resolution)
        if 0 <= row < grid.data.shape[0] and 0 <= col < grid.data.shape[1] and grid.data[row, col] >= 50:
            return False
    return True


def test_world_file_rooms_are_markers_and_detected():
    world = vwg.robot.load_robot_world(ROOT / "maps" / "office.yaml")
    for markers in (world.rooms, list(world.rooms.values())):
        cam = _core.CameraRenderer(world.grid, markers, vwg.robot.CameraSpec(wall_height=world.wall_height))
        assert sorted(m["id"] for m in cam.markers) == sorted(r.marker for r in world.rooms.values())
        assert {m["label"] for m in cam.markers} == set(world.rooms)
    pin = Pinhole()
    tested = 0
    for room in world.rooms.values():
        # The markers are 1.2 m up: a level camera at 0.5 m holds the whole tag from about 2.3 m. Stand
        # in front of it, facing it, where the lines of sight to the tag's middle and edges are clear
        # (furniture stands in front of some markers).
        nx, ny = room.normal
        rx, ry = -ny, nx
        m = {"at": room.at, "facing": room.facing, "size": room.size, "height": room.height}
        for d in (3.0, 2.8, 2.6, 2.4, 3.3, 3.6):
            pose = (room.at[0] + d * nx, room.at[1] + d * ny, room.facing + math.pi)
            edges = [(room.at[0] + nx * 0.01 + k * rx * 0.2, room.at[1] + ny * 0.01 + k * ry * 0.2) for k in (-1, 0, 1)]
            if fully_in_view(pin, pose, m) and all(clear_line(world.grid, pose[:2], e) for e in edges):
                break
        else:
            continue
        found = _core.detect_apriltags(cam.render(pose, grey=True))
        assert [f.id for f in found] == [room.marker], room.name
        tag = _core.estimate_tag_pose(found[0], room.size, *cam.apriltag_intrinsics())
        expected = math.hypot(d, room.height - 0.5)
        assert abs(tag.distance - expected) / expected < 0.05, room.name
        assert abs(tag.bearing) < math.radians(2.0), room.name
        tested += 1
    assert tested >= 5


def test_noise_and_blur_still_detect_at_two_metres():
    m = marker(3, height=0.9)
    cam = _core.CameraRenderer(east_wall_room(), [m], vwg.robot.CameraSpec(noise=6.0, blur=1.2), seed=5)
    for turn in (0.0, 0.25, -0.25):
        pose = (8.0, 10.0, turn)
        assert fully_in_view(Pinhole(), pose, m)
        found = _core.detect_apriltags(cam.render(pose, grey=True))
        assert [f.id for f in found] == [3]
        tag = _core.estimate_tag_pose(found[0], 0.3, *cam.apriltag_intrinsics())
        expected = math.hypot(2.0, 0.4)
        assert abs(tag.distance - expected) / expected < 0.05
        assert abs(tag.bearing + turn) < math.radians(2.0)


def test_noise_is_seeded():
    pose = (6.0, 10.0, 0.1)
    a = _core.CameraRenderer(east_wall_room(), [], vwg.robot.CameraSpec(noise=5.0), seed=1)
    b = _core.CameraRenderer(east_wall_room(), [], vwg.robot.CameraSpec(noise=5.0), seed=1)
    c = _core.CameraRenderer(east_wall_room(), [], vwg.robot.CameraSpec(noise=5.0), seed=2)
    clean = _core.CameraRenderer(east_wall_room(), []).render(pose, grey=True).astype(float)
    ia = a.render(pose, grey=True)
    assert np.array_equal(ia, b.render(pose, grey=True))
    assert not np.array_equal(ia, c.render(pose, grey=True))
    diff = ia.astype(float) - clean
    assert abs(diff.mean()) < 0.1
    assert diff.std() == pytest.approx(5.0, abs=0.25)
    a.reseed(1)
    assert np.array_equal(a.render(pose, grey=True), ia)


# --- robots -------------------------------------------------------------------------------------------


def test_other_robots_are_cylinders():
    cam = _core.CameraRenderer(east_wall_room(), [])
    pin = Pinhole()
    pose = (5.0, 10.0, 0.0)
    empty = cam.render(pose)
    # Straight ahead, 3 m to its centre, radius 0.25: its front is 2.75 m away.
    for robot in ({"pose": (8.0, 10.0, 0.0), "radius": 0.25, "id": 1}, {"x": 8.0, "y": 10.0, "radius": 0.25}):
        image = cam.render(pose, robots=[robot])
        changed = np.any(image != empty, axis=2)
        rows = np.nonzero(changed[:, 320])[0]
        assert abs(rows[-1] - (pin.cy + pin.fx * 0.5 / 2.75)) <= 1.0  # its foot
        assert abs(rows[0] - (pin.cy + pin.fx * (0.5 - 0.4) / 3.25)) <= 1.0  # the far edge of its lid
        cols = np.nonzero(changed[300])[0]
        half = pin.fx * math.tan(math.asin(0.25 / 3.0))
        assert abs(cols[0] - (pin.cx - half)) <= 1.0 and abs(cols[-1] - (pin.cx + half)) <= 1.0
    # A robot behind the wall, the camera's own body and one behind the camera are not seen.
    hidden = [{"pose": (12.0, 10.0, 0.0), "radius": 0.3}, {"pose": (5.02, 10.0, 0.0), "radius": 0.18},
              {"pose": (3.0, 10.0, 0.0), "radius": 0.3}]
    assert np.array_equal(cam.render(pose, robots=hidden), empty)


def test_robots_from_the_world_file_and_the_physics():
    world = vwg.robot.load_robot_world(ROOT / "maps" / "office.yaml")
    cam = _core.CameraRenderer(world.grid, world.rooms, vwg.robot.CameraSpec(wall_height=world.wall_height))
    one, two = world.robots[0], world.robots[1]
    # RobotSettings (start); robot 1's own cylinder holds the camera and is skipped.
    with_specs = cam.render(one.start, robots=world.robots)
    only_two = cam.render(one.start, robots=[two])
    assert np.array_equal(with_specs, only_two)


# --- errors -------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("bad", "field"), [
    ({"at": (1.0, 2.0), "facing": 0.0}, "markers[0].id"),
    ({"id": 1, "facing": 0.0}, "markers[0].at"),
    ({"id": 1, "at": (1.0, 2.0)}, "markers[0].facing"),
    ({"id": 600, "at": (1.0, 2.0), "facing": 0.0}, "markers[0].id"),
    ({"id": 1, "at": (1.0, 2.0), "facing": 0.0, "size": -0.3}, "markers[0].size"),
    ({"id": 1, "at": (1.0, 2.0), "facing": 0.0, "height": 3.0}, "markers[0].height"),
    ({"id": 1, "at": (1.0, float("nan")), "facing": 0.0}, "markers[0].at"),
])
def test_bad_markers_name_the_field(bad, field):
    with pytest.raises(vwg.SchemaError, match=re_field(field)):
        _core.CameraRenderer(east_wall_room(), [bad])


@pytest.mark.parametrize(("kwargs", "field"), [
    ({"width": 0}, "camera.width"),
    ({"hfov": 4.0}, "camera.hfov"),
    ({"mount_height": 3.0}, "camera.wall_height"),
    ({"noise": -1.0}, "camera.noise"),
    ({"blur": -1.0}, "camera.blur"),
])
def test_bad_camera_settings_name_the_field(kwargs, field):
    with pytest.raises(vwg.SchemaError, match=re_field(field)):
        _core.CameraRenderer(east_wall_room(), [], vwg.robot.CameraSpec(**kwargs))


def test_bad_poses_and_robots_raise():
    cam = _core.CameraRenderer(east_wall_room(), [], vwg.robot.CameraSpec(width=64, height=48))
    with pytest.raises(vwg.SchemaError, match="pose"):
        cam.render((1.0, 2.0))
    with pytest.raises(vwg.SchemaError, match=re_field("robots[0].radius")):
        cam.render((1.0, 2.0, 0.0), robots=[{"pose": (3.0, 3.0, 0.0), "radius": 0.0}])
    with pytest.raises(vwg.SchemaError, match=re_field("robots[0].pose")):
        cam.render((1.0, 2.0, 0.0), robots=[{"radius": 0.2}])


# --- threads ------------------------------------------------------------------------------------------


def test_renders_in_threads_match_serial_renders():
    cams = [_core.CameraRenderer(east_wall_room(), [marker(i)]) for i in range(4)]
    poses = [(6.0 + 0.3 * i, 10.0, 0.05 * i) for i in range(4)]
    serial = [c.render(p, grey=True) for c, p in zip(cams, poses, strict=False)]
    results = [None] * 4

    def work(i):
        for _ in range(5):
            results[i] = cams[i].render(poses[i], grey=True)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for got, want in zip(results, serial, strict=False):
        assert np.array_equal(got, want)


# --- the overview -------------------------------------------------------------------------------------


def deep_cells(mask: np.ndarray, radius: int) -> np.ndarray:
    """(row, col) of the cells whose whole (2·radius+1)² neighbourhood is in mask."""
    k = 2 * radius + 1
    padded = np.pad(mask.astype(np.int32), radius)
    integral = np.zeros((padded.shape[0] + 1, padded.shape[1] + 1), np.int64)
    integral[1:, 1:] = padded.cumsum(0).cumsum(1)
    count = integral[k:, k:] - integral[:-k, k:] - integral[k:, :-k] + integral[:-k, :-k]
    return np.argwhere(count == k * k)


@pytest.mark.parametrize("name", MAPS)
def test_overview_of_each_shipped_map(name):
    world = vwg.robot.load_robot_world(ROOT / "maps" / f"{name}.yaml")
    grid = world.grid
    image = _core.render_overview(grid, world.rooms, world.robots, wall_height=world.wall_height)
    assert image.shape == (700, 1000, 3) and image.dtype == np.uint8
    assert image.std() > 20  # not a blank picture

    # Straight down, orthographic, aimed by hand at a point of open floor, 60 pixels per metre (3 per cell,
    # so even the maze's 2-cell walls are 6 pixels wide): pixel = image centre + 60 · (x - tx, -(y - ty)).
    free = deep_cells(grid.data == 0, 12)  # at least 0.6 m from anything else: lit or shadowed floor
    row, col = free[len(free) // 2]
    scale = 60.0
    tx = grid.origin[0] + (col + 0.5) * grid.resolution
    ty = grid.origin[1] + (row + 0.5) * grid.resolution
    top = _core.render_overview(grid, wall_height=world.wall_height, width=1000, height=700, azimuth=-math.pi / 2,
                                elevation=math.pi / 2, fov=0.0, labels=False, target=(tx, ty), scale=scale)
    brightness = top.astype(float).mean(axis=2)

    def in_view(cells):
        x = grid.origin[0] + (cells[:, 1] + 0.5) * grid.resolution
        y = grid.origin[1] + (cells[:, 0] + 0.5) * grid.resolution
        u = np.rint(499.5 + scale * (x - tx)).astype(int)
        v = np.rint(349.5 - scale * (y - ty)).astype(int)
        keep = (u >= 5) & (u <= 994) & (v >= 5) & (v <= 694)
        return u[keep], v[keep]

    rng = np.random.default_rng(3)
    for cells, what in ((np.argwhere(grid.data >= 50), "wall"), (free, "floor")):
        u, v = in_view(cells)
        assert len(u) >= 25, what
        pick = rng.choice(len(u), size=25, replace=False)
        values = brightness[v[pick], u[pick]]
        if what == "wall":
            assert np.all(values < 130), values  # the wall tops' dark slate
        else:
            assert np.all(values > 150), values  # the floor, lit or in a wall's shadow


def test_overview_perspective_follows_the_documented_view():
    data = np.zeros((160, 200), np.int8)
    data[:4], data[-4:], data[:, :4], data[:, -4:] = 100, 100, 100, 100
    data[60:80, 80:120] = 100  # a block: x 4..6 m, y 3..4 m
    grid = vwg.io.maps.OccupancyGrid(data, RES)
    az, el, fov, dist = -2.0, 1.0, 0.7, 14.0
    eye = np.array([5.0 + dist * math.cos(el) * math.cos(az), 4.0 + dist * math.cos(el) * math.sin(az),
                    dist * math.sin(el)])
    fwd = np.array([-math.cos(el) * math.cos(az), -math.cos(el) * math.sin(az), -math.sin(el)])
    right = np.array([-math.sin(az), math.cos(az), 0.0])
    down = np.cross(fwd, right)
    focal = 450 / math.tan(fov / 2)

    def hand(x, y, z):
        p = np.array([x, y, z]) - eye
        return 449.5 + focal * (p @ right) / (p @ fwd), 299.5 + focal * (p @ down) / (p @ fwd)

    kwargs = dict(wall_height=2.5, width=900, height=600, azimuth=az, elevation=el, fov=fov, target=(5.0, 4.0),
                  distance=dist)
    cam = _core.overview_camera(grid, **kwargs)
    for point in [(5.0, 3.5, 2.5), (0.0, 0.0, 0.0), (10.0, 8.0, 2.5)]:
        assert cam.project(*point) == pytest.approx(hand(*point), abs=1e-6)
    image = _core.render_overview(grid, labels=False, **kwargs).astype(float).mean(axis=2)
    u, v = hand(5.0, 3.5, 2.5)
    assert image[round(v), round(u)] < 130  # the block's top
    u, v = hand(2.0, 6.0, 0.0)
    assert image[round(v), round(u)] > 150  # open floor


def test_overview_fitted_view_holds_the_whole_map():
    world = vwg.robot.load_robot_world(ROOT / "maps" / "maze.yaml")
    for fov in (0.6, 0.0):
        cam = _core.overview_camera(world.grid, world.wall_height, fov=fov)
        w_m = world.grid.data.shape[1] * world.grid.resolution
        h_m = world.grid.data.shape[0] * world.grid.resolution
        for x, y in [(0, 0), (w_m, 0), (w_m, h_m), (0, h_m)]:
            for z in (0.0, world.wall_height):
                u, v = cam.project(x, y, z)
                assert 0 <= u <= 999 and 0 <= v <= 699


def test_overview_bad_arguments():
    grid = east_wall_room()
    with pytest.raises(vwg.SchemaError, match=re_field("view.elevation")):
        _core.render_overview(grid, elevation=0.0)
    with pytest.raises(vwg.SchemaError, match=re_field("view.supersample")):
        _core.render_overview(grid, supersample=9)
    with pytest.raises(vwg.SchemaError, match=re_field("scale")):
        _core.render_overview(grid, scale=10.0)  # a scale needs a target
    with pytest.raises(vwg.SchemaError, match=re_field("view.scale")):
        _core.render_overview(grid, fov=0.0, target=(1.0, 1.0))
