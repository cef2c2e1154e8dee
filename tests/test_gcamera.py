"""gCamera: AprilTags seen by the robot's camera become eCamera<marker, dist, angle> events, whatever
the image source (simulated camera, image files, video file) — and ARobot marks them (eq. 12)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import vwg
from conftest import ROOT
from vwg import _core
from vwg.robot import RobotSettings
from vwg.robot.case_study import CaseStudy
from vwg.robot.platforms.sim import CameraSpec

DATA = ROOT / "tests" / "data" / "apriltag" / "test_data"


def alphabet():
    return vwg.Alphabet(events=vwg.robot.platforms.sim.SIM_EVENTS, **vwg.robot.platforms.sim.MOTION_SYMBOLS)


def test_a_robot_at_a_rooms_goal_sees_its_marker():
    world = vwg.robot.load_robot_world(ROOT / "maps" / "office.yaml")
    room = world.rooms["kitchen"]
    gx, gy = room.goal
    facing_marker = room.facing + math.pi
    robots = [RobotSettings(id=1, start=(gx, gy, facing_marker))]
    physics = _core.PhysicsWorld(world.grid, robots)
    source = _core.SimulatedCamera(physics, 1, world.grid, world.rooms, CameraSpec(wall_height=world.wall_height))
    a = alphabet()
    camera = _core.CameraGenerator(source, 1, a, *source.apriltag_intrinsics(), tag_size=room.size)
    engine = vwg.Engine(vwg.World(a), "Robot<1>", [camera])
    engine.step()
    events = engine.last_events
    assert [(e.type, e.target, e.marker) for e in events] == [("eCamera", 1, room.marker)]
    # The goal stands 1 m in front of the marker, on its normal: straight ahead, 1 m away.
    expected = math.dist(room.goal, room.at)
    assert events[0].dist == pytest.approx(expected, rel=0.05)
    assert abs(events[0].angle) < math.radians(2)
    assert camera.image.shape == (480, 640)


def test_arobot_marks_the_markers_it_sees():
    world = vwg.robot.load_robot_world(ROOT / "maps" / "office.yaml")
    run = CaseStudy(world, "astar", goals={1: "kitchen"}, sensors=("laser", "camera"), world_orders=False)
    assert run.run(frames=600).robots[0].reached
    grid = np.asarray(run.robot_actors()[1]["grid"])
    rows, cols = np.nonzero(grid == 1000 + world.rooms["kitchen"].marker)
    assert len(rows) > 0, "the kitchen's marker was never marked"
    # Marked within two cells of where the marker is.
    row, col = world.grid.world_to_cell(*world.rooms["kitchen"].at)
    assert np.min(np.hypot(rows - row, cols - col)) <= 2.0


def expected_ids(txt):
    return sorted(int(line.split(",")[0]) for line in txt.read_text().splitlines() if line.strip())


def test_gcamera_on_real_photos_and_on_a_video(tmp_path):
    a = alphabet()
    photos = sorted(DATA.glob("*.jpg"))
    files = _core.ImageFiles([str(p) for p in photos])
    # The ground truth was made with quad_decimate 1 and refine_edges off (tests/data/apriltag/README.md).
    camera = _core.CameraGenerator(files, 1, a, 600.0, 600.0, 200.0, 150.0, quad_decimate=1.0, refine_edges=False)
    engine = vwg.Engine(vwg.World(a), "Robot<1>", [camera])
    for photo in photos:
        engine.step()
        assert sorted(e.marker for e in engine.last_events) == expected_ids(photo.with_suffix(".txt"))
    engine.step()
    assert engine.last_events == []  # no more images
    # The same photos as a video (lossless enough for the tags): the same tags.
    first = vwg._core.read_image(str(photos[0]))
    video = tmp_path / "tags.mp4"
    with vwg.VideoWriter(video, fps=5) as writer:
        rgb = first if first.ndim == 3 else np.stack([first] * 3, axis=-1)
        h, w = (rgb.shape[0] // 2) * 2, (rgb.shape[1] // 2) * 2
        for _ in range(3):
            writer.write(np.ascontiguousarray(rgb[:h, :w]))
    camera = _core.CameraGenerator(_core.VideoSource(str(video)), 1, a, 600.0, 600.0, 200.0, 150.0, quad_decimate=1.0,
                                   refine_edges=False)
    engine = vwg.Engine(vwg.World(a), "Robot<1>", [camera])
    engine.step()
    found = sorted(e.marker for e in engine.last_events)
    wanted = expected_ids(photos[0].with_suffix(".txt"))
    # The photos hold many tags, all id 0: the video must give (nearly) as many, all of the right id.
    assert set(found) <= set(wanted)
    assert len(found) >= len(wanted) - 1  # video compression may cost one small tag


def test_bad_images_are_clear_errors(tmp_path):
    a = alphabet()
    with pytest.raises(vwg.Error, match=r"nope\.png: image file not found"):
        _core.ImageFiles([str(tmp_path / "nope.png")])
    corrupt = tmp_path / "corrupt.png"
    corrupt.write_bytes(b"\x89PNG\r\n\x1a\n not really")
    camera = _core.CameraGenerator(_core.ImageFiles([str(corrupt)]), 1, a, 600.0, 600.0, 200.0, 150.0)
    engine = vwg.Engine(vwg.World(a), "Robot<1>", [camera])
    with pytest.raises(vwg.FrameError, match=r"corrupt\.png") as info:
        engine.step()
    assert info.value.stage == "generate"
    with pytest.raises(vwg.Error, match="video file not found"):
        _core.VideoSource(str(tmp_path / "none.mp4"))
    with pytest.raises(vwg.SchemaError, match=r"camera\.period"):
        _core.CameraGenerator(_core.ImageFiles([]), 1, a, 600.0, 600.0, 200.0, 150.0, period=0)
