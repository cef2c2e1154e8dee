"""The 2D top-down renderer and image sequences from Python (vwg._core.TopDownRenderer, ImageSequence;
videos are tested in test_video.py). Expected pixels are worked out by hand from each test's geometry:
pixel (i, j) covers [i, i+1) × [j, j+1), the map's bottom row is at the image bottom, and numpy indexes
image[row, column]."""

from __future__ import annotations

import math
import types

import numpy as np
import pytest

import vwg
from vwg.errors import Error, SchemaError

core = vwg._core


def free_grid() -> np.ndarray:
    """10 rows × 20 columns of free cells; at 0.1 m a cell, 2 m × 1 m."""
    return np.zeros((10, 20), dtype=np.int8)


def plain_style() -> core.RenderStyle:
    """Plain colours, so expected pixels are simple numbers; 4 px per cell, 8 px margins."""
    s = core.RenderStyle()
    s.pixels_per_cell = 4.0
    s.margin = 8
    s.background = (0, 0, 255)
    s.free = (255, 255, 255)
    s.occupied = (0, 0, 0)
    s.unknown = (128, 0, 128)
    s.palette = [(10, 20, 30), (40, 50, 60), (200, 100, 0)]
    s.hit = (255, 0, 0)
    s.ray = (0, 255, 0)
    s.ray_miss = (0, 200, 200)
    s.belief_occupied = (0, 0, 255)
    s.belief_occupied_alpha = 0.5
    s.text_box = (0, 0, 0)
    s.text_box_alpha = 0.5
    return s


def renderer(grid: np.ndarray | None = None, **kw) -> core.TopDownRenderer:
    return core.TopDownRenderer(free_grid() if grid is None else grid, 0.1, (0.0, 0.0, 0.0), style=plain_style(), **kw)


def solid(width: int, height: int, i: int) -> np.ndarray:
    """A frame of one colour, a different one per index."""
    frame = np.empty((height, width, 3), dtype=np.uint8)
    frame[:] = (40 + 20 * (i % 10), 200 - 15 * (i % 10), 90)
    return frame


# ------------------------------------------------------------------ geometry


def test_image_size_and_map_corners():
    r = renderer()
    image = r.image()
    # 20 cells × 4 px + 2 × 8 px margin wide, 10 × 4 + 16 high.
    assert image.shape == (56, 96, 3)
    assert image.dtype == np.uint8
    assert (r.width, r.height) == (96, 56)
    assert r.map_rect == (8, 8, 80, 40)
    assert r.world_to_pixel(0.0, 0.0) == (8.0, 48.0)  # the map's lower-left corner: image bottom-left
    assert r.world_to_pixel(2.0, 1.0) == (88.0, 8.0)  # upper-right corner
    assert r.pixel_to_world(10.0, 46.0) == pytest.approx((0.05, 0.05))
    assert r.pixels_per_metre == pytest.approx(40.0)


def test_origin_offset_moves_the_world():
    r = core.TopDownRenderer(free_grid(), 0.1, (-1.0, 2.0, 0.0), pixels_per_cell=4.0, margin=8)
    assert r.world_to_pixel(-1.0, 2.0) == pytest.approx((8.0, 48.0))
    assert r.world_to_pixel(0.0, 2.5) == pytest.approx((48.0, 28.0))  # 10 cells right, 5 up


def test_width_sets_the_scale():
    r = core.TopDownRenderer(free_grid(), 0.1, width=216, margin=8)
    # 200 px of map for 20 cells: 10 px a cell; 10 rows: 100 px + 16.
    assert r.pixels_per_cell == pytest.approx(10.0)
    assert r.image().shape == (116, 216, 3)


def test_header_adds_room_above_the_map():
    r = renderer(header=30)
    assert r.image().shape == (86, 96, 3)
    assert r.world_to_pixel(0.0, 0.0) == (8.0, 78.0)


def test_an_object_with_data_resolution_and_origin_is_a_grid():
    grid = types.SimpleNamespace(data=free_grid(), resolution=0.1, origin=(-1.0, 2.0, 0.0))
    r = core.TopDownRenderer(grid, pixels_per_cell=4.0, margin=8)
    assert r.world_to_pixel(-1.0, 2.0) == pytest.approx((8.0, 48.0))


def test_bad_grids_are_refused():
    with pytest.raises(SchemaError, match="int8"):
        core.TopDownRenderer(np.zeros((10, 20), dtype=np.float64), 0.1)
    with pytest.raises(SchemaError, match="resolution"):
        core.TopDownRenderer(free_grid())
    with pytest.raises(SchemaError, match="2-D"):
        core.TopDownRenderer(np.zeros(20, dtype=np.int8), 0.1)
    with pytest.raises(Error):
        core.TopDownRenderer(free_grid(), 0.1, pixels_per_cell=0.0)


# ------------------------------------------------------------------ pixels


def test_map_cells_have_their_colours():
    grid = free_grid()
    grid[0, 0] = 100   # row 0 = bottom row: pixels x 8..11, y 44..47
    grid[9, 19] = -1   # top-right cell: x 84..87, y 8..11
    grid[5, 5] = 50    # half way: x 28..31, y 24..27
    image = renderer(grid).image()
    assert tuple(image[46, 10]) == (0, 0, 0)
    assert tuple(image[10, 86]) == (128, 0, 128)
    assert tuple(image[26, 30]) == (128, 128, 128)  # 255 / 2 rounded
    assert tuple(image[46, 14]) == (255, 255, 255)
    assert tuple(image[2, 2]) == (0, 0, 255)


def test_update_map_redraws():
    r = renderer()
    grid = free_grid()
    grid[0, 0] = 100
    r.update_map(grid)
    r.begin()
    assert tuple(r.image()[46, 10]) == (0, 0, 0)
    with pytest.raises(SchemaError, match="shape"):
        r.update_map(np.zeros((5, 5), dtype=np.int8))


def test_robot_colours_the_pixel_at_its_centre():
    r = renderer()
    r.begin()
    r.draw_robot((1.0, 0.5, math.pi / 2), 0.2, id=2)  # centre at pixel corner (48, 28); radius 8 px
    image = r.image()
    assert tuple(image[28, 48]) == (200, 100, 0)  # palette[2]
    assert tuple(image[38, 48]) == (255, 255, 255)  # 10 px below: outside the disc
    assert r.robot_colour(5) == (200, 100, 0)  # 5 mod 3
    r.begin()
    r.draw_robot([1.0, 0.5, 0.0], 0.2, id=0, label="", colour=(1, 2, 3))
    assert tuple(r.image()[28, 47]) == (1, 2, 3)
    with pytest.raises(SchemaError, match=r"0\.\.255"):
        r.draw_robot((1.0, 0.5, 0.0), 0.2, colour=(0, 0, 300))


def test_scan_hit_points_land_where_the_ranges_say():
    r = renderer()
    r.begin()
    # The sensor at the centre of pixel (48, 28), facing +x; a hit at 0.25 m = 10 px right, a miss upwards.
    pose = (1.0125, 0.4875, 0.0)
    r.draw_scan(pose, np.array([0.0, math.pi / 2], dtype=np.float32), np.array([0.25, np.inf]), max_range=0.3)
    image = r.image()
    assert tuple(image[28, 58]) == (255, 0, 0)
    assert np.abs(image[20, 48].astype(int) - (0, 200, 200)).max() <= 30  # the faint miss ray, 8 px up
    assert tuple(image[12, 48]) == (255, 255, 255)  # beyond max_range (12 px up)
    with pytest.raises(Error, match="2 angles but 1 ranges"):
        r.draw_scan(pose, [0.0, 1.0], [1.0])


def test_belief_is_blended_over_the_map():
    r = renderer()
    belief = np.full((10, 20), -1, dtype=np.int8)
    belief[0, 0] = 100
    r.draw_belief(belief)
    image = r.image()
    # Opacity 0.5 = 128/256 of (0, 0, 255) over white: 255·128 >> 8 = 127; blue stays 255.
    assert tuple(image[46, 10]) == (127, 127, 255)
    assert tuple(image[46, 14]) == (255, 255, 255)  # unknown belief: the map shows
    with pytest.raises(SchemaError):
        r.draw_belief(np.zeros((10, 19), dtype=np.int8))


def test_paths_markers_and_trajectories_take_lists_and_arrays():
    r = renderer()
    r.draw_path([(0.5, 0.5), (1.5, 0.5)])  # along pixel row boundary 28, 2 px thick
    assert tuple(r.image()[28, 40]) != (255, 255, 255)
    r.draw_path(np.empty((0, 2)))
    r.draw_trajectory(np.array([[0.2, 0.2], [0.4, 0.2], [0.6, 0.3]]), id=1)
    r.draw_marker(1.0, 0.25, math.pi / 2, "kitchen", 3)
    with pytest.raises(SchemaError, match="N×2"):
        r.draw_path(np.zeros((3, 3)))


def test_corner_text_sits_on_a_translucent_box():
    r = renderer()
    assert tuple(r.image()[3, 3]) == (0, 0, 255)  # no text, no box
    r.begin(frame=3, time=0.3, status="exploring")
    first = r.image()
    assert np.abs(first[3, 3].astype(int) - (0, 0, 128)).max() <= 1  # half the background's blue
    assert np.array_equal(r.image(), first)  # asking again does not draw it twice
    r.begin()
    assert tuple(r.image()[3, 3]) == (0, 0, 255)


def test_image_is_a_copy_and_save_writes_it(tmp_path):
    r = renderer()
    image = r.image()
    image[:] = 0
    assert tuple(r.image()[30, 30]) == (255, 255, 255)
    r.save(tmp_path / "frame.png")
    assert np.array_equal(vwg._core.read_image(str(tmp_path / "frame.png")), r.image())


def test_style_reads_back():
    s = plain_style()
    assert s.free == (255, 255, 255)
    assert s.palette == [(10, 20, 30), (40, 50, 60), (200, 100, 0)]
    r = renderer()
    assert r.style.unknown == (128, 0, 128)


def test_image_sequence_writes_numbered_pngs(tmp_path):
    seq = core.ImageSequence(tmp_path / "frames")
    paths = [seq.write(solid(20, 10, i)) for i in range(3)]
    assert paths[0].endswith("frame_00001.png")
    assert seq.frames == 3
    assert sorted(p.name for p in (tmp_path / "frames").iterdir()) == [
        "frame_00001.png", "frame_00002.png", "frame_00003.png"]
    back = vwg._core.read_image(paths[1])
    assert tuple(back[5, 5]) == (60, 185, 90)  # frame 1's colour, RGB kept
    with pytest.raises(Error, match=r"frame_00004\.png"):
        seq.write(solid(21, 10, 0))


def test_write_image_leaves_the_image_untouched(tmp_path):
    image = np.zeros((4, 5, 3), np.uint8)
    image[..., 0] = 200  # red
    before = image.copy()
    core.write_image(str(tmp_path / "red.png"), image)
    np.testing.assert_array_equal(image, before)
    np.testing.assert_array_equal(core.read_image(str(tmp_path / "red.png")), before)
