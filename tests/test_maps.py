"""Occupancy-grid maps against real files: ROS map_server's own test maps and expected cells, the TurtleBot3 and
Willow Garage maps, the MovingAI benchmarks. Expected values come from the data files (tests/data/rosmaps/README.md)
or are worked out by hand from the map_server rule written in the tests."""

from __future__ import annotations

import math
from collections import deque
from pathlib import Path

import numpy as np
import pytest

from vwg import _core
from vwg.errors import WorldFileError
from vwg.io.maps import OccupancyGrid, load_map, load_map_server, load_movingai, movingai_cell

DATA = Path(__file__).resolve().parent / "data"
ROS = DATA / "rosmaps"
MST = ROS / "map_server_test"
ROOT = Path(__file__).resolve().parents[1]


def _movingai_dir() -> Path:
    return DATA / "movingai"  # copied from the shared test data, with its README


def expected(name: str) -> np.ndarray:
    """An expected_*.txt grid: rows as printed, lower-left pixel first, i.e. already in OccupancyGrid order."""
    return np.loadtxt(MST / name, comments="#", dtype=np.int64)


def write_yaml(path: Path, image_file: str | Path, **fields: object) -> Path:
    values = {"image": str(image_file), "resolution": 0.1, "origin": "[0.0, 0.0, 0.0]", "negate": 0,
              "occupied_thresh": 0.65, "free_thresh": 0.196}
    values.update(fields)
    path.write_text("".join(f"{k}: {v}\n" for k, v in values.items() if v is not None), encoding="utf-8")
    return path


# ---- map_server: upstream test maps ---------------------------------------------------------------------------
def test_testmap_png_matches_upstream_cells() -> None:
    grid = load_map(MST / "testmap.yaml")
    assert grid.data.dtype == np.int8
    assert (grid.width, grid.height) == (10, 10)
    assert grid.resolution == 0.1
    assert grid.origin == (2.0, 3.0, 1.0)
    assert grid.mode == "trinary"
    np.testing.assert_array_equal(grid.data, expected("expected_testmap.txt"))


@pytest.mark.parametrize("image", ["testmap.png", "testmap.bmp", "testmap.pgm"])
@pytest.mark.parametrize("free_thresh", [0.1, 0.196])  # ROS 1 utest uses 0.1, the YAML and Nav2 0.196
def test_testmap_every_format(tmp_path: Path, image: str, free_thresh: float) -> None:
    yaml_path = write_yaml(tmp_path / "m.yaml", MST / image, origin="[2.0, 3.0, 1.0]", free_thresh=free_thresh)
    grid = load_map(yaml_path)
    np.testing.assert_array_equal(grid.data, expected("expected_testmap.txt"))
    assert grid.source == str(yaml_path)


def test_testmap_nav2_yaml() -> None:
    grid = load_map(MST / "testmap.nav2.yaml")
    assert grid.resolution == 0.1 and grid.origin == (2.0, 3.0, 1.0)
    np.testing.assert_array_equal(grid.data, expected("expected_testmap.txt"))


def test_testmap2_negate() -> None:
    grid = load_map(MST / "testmap2.yaml")
    assert (grid.width, grid.height) == (12, 12)
    assert grid.origin == (-2.0, -3.0, -1.0)
    np.testing.assert_array_equal(grid.data, expected("expected_testmap2.txt"))


def test_rows_are_flipped_bottom_first() -> None:
    # the PNG's top row is image row 0; the grid's row 0 is the image's bottom row
    img = _core.read_image(str(MST / "testmap.png"))
    grid = load_map(MST / "testmap.yaml")
    top_row_black = img[0, :, 0] == 0
    np.testing.assert_array_equal(grid.data[-1] == 100, top_row_black)


# ---- map_server: modes on spectrum.png (each grey 0..255 once) ------------------------------------------------
def spectrum(tmp_path: Path, mode: str, negate: int = 0) -> tuple[np.ndarray, OccupancyGrid]:
    grey = _core.read_image(str(MST / "spectrum.png"))
    yaml_path = write_yaml(tmp_path / f"s_{mode}_{negate}.yaml", MST / "spectrum.png", mode=mode, negate=negate,
                           free_thresh=0.1)
    return grey, load_map(yaml_path)


def test_spectrum_image_has_each_grey_once() -> None:
    grey = _core.read_image(str(MST / "spectrum.png"))
    assert grey.shape == (16, 16) and grey.dtype == np.uint8
    assert sorted(grey.ravel().tolist()) == list(range(256))


def test_spectrum_trinary(tmp_path: Path) -> None:
    grey, grid = spectrum(tmp_path, "trinary")
    # the rule, by hand: p = (255 - g) / 255; 100 if p > 0.65 (g <= 89), 0 if p < 0.1 (g >= 230), else -1
    g = grey[::-1].astype(int)
    want = np.where(g <= 89, 100, np.where(g >= 230, 0, -1))
    np.testing.assert_array_equal(grid.data, want)
    counts = {v: int((grid.data == v).sum()) for v in (100, 0, -1)}
    assert counts == {100: 90, 0: 26, -1: 140}  # expected_spectrum.txt


def test_spectrum_scale(tmp_path: Path) -> None:
    grey, grid = spectrum(tmp_path, "scale")
    g = grey[::-1].astype(int)
    data = grid.data.astype(int)
    np.testing.assert_array_equal(data[g <= 89], 100)
    np.testing.assert_array_equal(data[g >= 230], 0)
    middle = (g > 89) & (g < 230)
    assert middle.sum() == 140 and data[middle].min() >= 1 and data[middle].max() <= 99  # expected_spectrum.txt
    # by hand: g=90: p=165/255=0.647059, ratio=(0.647059-0.1)/0.55=0.994652, 1+98*ratio=98.476 -> 98
    #          g=128: p=127/255=0.498039, ratio=0.723708, 1+70.923=71.923 -> 71
    #          g=229: p=26/255=0.101961, ratio=0.003565, 1.349 -> 1
    for grey_value, value in ((90, 98), (128, 71), (229, 1), (89, 100), (230, 0)):
        assert data[g == grey_value].tolist() == [value]
    # and the whole middle band by the formula
    p = (255 - g[middle]) / 255
    np.testing.assert_array_equal(data[middle], (1 + 98 * (p - 0.1) / 0.55).astype(int))


def test_spectrum_raw(tmp_path: Path) -> None:
    grey, grid = spectrum(tmp_path, "raw")
    assert grid.mode == "raw"
    # raw keeps each grey as is; stored in the int8 message as map_server does (>127 reads negative)
    np.testing.assert_array_equal(grid.data.view(np.uint8), grey[::-1])
    assert sorted(grid.data.view(np.uint8).ravel().tolist()) == list(range(256))
    assert int(grid.data[grey[::-1] == 200][0]) == 200 - 256


def test_spectrum_raw_negated(tmp_path: Path) -> None:
    grey, grid = spectrum(tmp_path, "raw", negate=1)
    np.testing.assert_array_equal(grid.data.view(np.uint8), 255 - grey[::-1])


def test_spectrum_trinary_negated(tmp_path: Path) -> None:
    grey, grid = spectrum(tmp_path, "trinary", negate=1)
    # negate: v = 255 - g, p = g / 255; 100 if g/255 > 0.65 (g >= 166), 0 if g/255 < 0.1 (g <= 25)
    g = grey[::-1].astype(int)
    np.testing.assert_array_equal(grid.data, np.where(g >= 166, 100, np.where(g <= 25, 0, -1)))


def test_colour_and_alpha(tmp_path: Path) -> None:
    # one row of RGBA pixels; values worked out by hand below
    px = np.array([[[0, 0, 0, 255], [128, 128, 128, 255], [128, 128, 128, 0], [255, 255, 255, 0],
                    [255, 255, 255, 255], [30, 60, 90, 255]]], dtype=np.uint8)
    _core.write_image(str(tmp_path / "rgba.png"), px)
    tri = load_map(write_yaml(tmp_path / "t.yaml", "rgba.png"))
    scale = load_map(write_yaml(tmp_path / "s.yaml", "rgba.png", mode="scale"))
    # trinary averages alpha in (map_server): (0+0+0+255)/4=63.75 -> p=0.75 -> 100; (3*128+255)/4=159.75 ->
    # p=0.3735 -> -1; (3*128+0)/4=96 -> p=0.6235 -> -1; (3*255+0)/4=191.25 -> p=0.25 -> -1; white opaque -> 0;
    # (30+60+90+255)/4=108.75 -> p=0.5735 -> -1
    assert tri.data[0].tolist() == [100, -1, -1, -1, 0, -1]
    # scale averages the colours only: black -> 100; 128 -> p=0.498039, ratio=(0.498039-0.196)/0.454=0.665285,
    # 1+65.198 -> 66; the same grey fully transparent -> -1; white transparent -> p=0 < free -> 0 (free first);
    # white -> 0; (30+60+90)/3=60 -> p=0.764706 > 0.65 -> 100
    assert scale.data[0].tolist() == [100, 66, -1, 0, 0, 100]


def test_rgb_average(tmp_path: Path) -> None:
    px = np.array([[[0, 0, 255], [200, 100, 0], [255, 255, 150]]], dtype=np.uint8)
    _core.write_image(str(tmp_path / "rgb.png"), px)
    grid = load_map(write_yaml(tmp_path / "m.yaml", "rgb.png"))
    # averages 85 (p=0.667 > 0.65: 100), 100 (p=0.608: -1), 220 (p=0.137 < 0.196: 0)
    assert grid.data[0].tolist() == [100, -1, 0]


def test_sixteen_bit_image(tmp_path: Path) -> None:
    _core.write_image(str(tmp_path / "w.png"), np.array([[0, 65535, 32896]], dtype=np.uint16))
    grid = load_map(write_yaml(tmp_path / "m.yaml", "w.png"))
    assert grid.data[0].tolist() == [100, 0, -1]  # 32896/257 = 128 -> p = 0.498


def test_image_path_relative_to_yaml(tmp_path: Path) -> None:
    sub = tmp_path / "a" / "b"
    sub.mkdir(parents=True)
    (sub / "img.pgm").write_bytes((MST / "testmap.pgm").read_bytes())
    write_yaml(sub / "m.yaml", "img.pgm")
    assert load_map(sub / "m.yaml").width == 10


# ---- TurtleBot3 world -------------------------------------------------------------------------------------------
def test_turtlebot3_world() -> None:
    grid = load_map(ROS / "turtlebot3_world" / "map.yaml")
    assert (grid.width, grid.height) == (384, 384)
    assert grid.resolution == 0.05
    assert grid.origin == (-10.0, -10.0, 0.0)
    assert grid.width_m == pytest.approx(19.2) and grid.height_m == pytest.approx(19.2)
    img = _core.read_image(str(ROS / "turtlebot3_world" / "map.pgm"))
    # the PGM holds 0 (occupied), 205 (unknown: p = 50/255 = 0.19608, just above free_thresh 0.196), 254 (free)
    for value, grey in ((100, 0), (-1, 205), (0, 254)):
        assert int((grid.data == value).sum()) == int((img == grey).sum())
    assert int((grid.data == 100).sum()) == 795 and int((grid.data == 0).sum()) == 7939
    # world (0, 0) is cell (200, 200): inside the centre pillar, which the map leaves unknown
    assert grid.world_to_cell(0.0, 0.0) == (200, 200)
    assert grid.data[200, 200] == -1
    # a few cells against their pixels (image row = 383 - grid row)
    for row, col in ((200, 150), (200, 175), (0, 0), (383, 383), (150, 200)):
        grey = int(img[383 - row, col])
        assert grid.data[row, col] == {0: 100, 205: -1, 254: 0}[grey]
    assert grid.data[200, 150] == 0 and grid.data[200, 175] == 100


# ---- coordinates --------------------------------------------------------------------------------------------------
def test_cell_world_conversions_with_yaw() -> None:
    grid = load_map(MST / "testmap.yaml")  # origin (2, 3, yaw 1 rad), 0.1 m
    x, y = grid.cell_to_world(0, 0)
    c, s = math.cos(1.0), math.sin(1.0)
    assert (x, y) == pytest.approx((2 + 0.05 * c - 0.05 * s, 3 + 0.05 * s + 0.05 * c))
    x, y = grid.cell_to_world(3, 7)  # centre of column 7, row 3: (0.75, 0.35) in the map frame
    assert (x, y) == pytest.approx((2 + 0.75 * c - 0.35 * s, 3 + 0.75 * s + 0.35 * c))
    for row in range(10):
        for col in range(10):
            assert grid.world_to_cell(*grid.cell_to_world(row, col)) == (row, col)
    assert not grid.contains(2.0 - 0.01, 3.0 - 0.01) and grid.contains(*grid.cell_to_world(9, 9))


def test_cell_world_conversions_axis_aligned() -> None:
    grid = OccupancyGrid(np.zeros((4, 6), np.int8), 0.5, (-1.0, 2.0, 0.0))
    assert (grid.width, grid.height, grid.width_m, grid.height_m) == (6, 4, 3.0, 2.0)
    assert grid.cell_to_world(0, 0) == (-0.75, 2.25)
    assert grid.cell_to_world(3, 5) == (1.75, 3.75)
    assert grid.world_to_cell(-1.0, 2.0) == (0, 0)
    assert grid.world_to_cell(-0.51, 2.49) == (0, 0)
    assert grid.world_to_cell(-0.5, 2.5) == (1, 1)
    assert grid.world_to_cell(-1.01, 1.99) == (-1, -1) and not grid.inside(-1, -1)


def test_masks_inflate_clearance() -> None:
    data = np.zeros((7, 7), np.int8)
    data[3, 3] = 100
    data[0, 0] = -1
    data[6, 6] = 40
    grid = OccupancyGrid(data, 1.0)
    assert grid.blocked().sum() == 1 and grid.blocked(unknown=True).sum() == 2
    assert grid.blocked(threshold=40).sum() == 2
    assert grid.free_mask().sum() == 47 and not grid.free_mask()[0, 0] and grid.free_mask()[6, 6]
    # clearance from the centre of (3, 5): 1.5 m to the square of (3, 3)
    assert grid.clearance(*grid.cell_to_world(3, 5), limit=10, unknown=False) == pytest.approx(1.5)
    assert grid.clearance(3.5, 3.5) == 0.0
    assert grid.clearance(*grid.cell_to_world(3, 5), limit=1.0) == 1.0
    # diagonal: centre (5.5, 5.5) of cell (5, 5) to the corner (4, 4) of cell (3, 3)
    assert grid.clearance(5.5, 5.5, limit=10, unknown=False) == pytest.approx(math.hypot(1.5, 1.5))
    # outside cells count as blocked when unknown=True
    assert grid.clearance(3.5, 0.5, limit=10) == pytest.approx(0.5)
    inflated = grid.inflate(1.2, unknown=False)
    want = np.zeros((7, 7), bool)
    want[2:5, 2:5] = True  # the 8 neighbours: distance 0.5 or 0.707 < 1.2; two away: 1.5 >= 1.2
    np.testing.assert_array_equal(inflated, want)


def test_inflate_matches_brute_force() -> None:
    rng = np.random.default_rng(3)
    data = np.where(rng.random((30, 25)) < 0.05, 100, 0).astype(np.int8)
    data[rng.random((30, 25)) < 0.02] = -1
    grid = OccupancyGrid(data, 0.05, (1.0, -2.0, 0.3))
    for radius in (0.03, 0.08, 0.18):
        for unknown in (False, True):
            fast = grid.inflate(radius, unknown=unknown)
            slow = np.zeros_like(fast)
            for r in range(30):
                for c in range(25):
                    slow[r, c] = grid.clearance(*grid.cell_to_world(r, c), limit=1.0, unknown=unknown) <= radius
            np.testing.assert_array_equal(fast, slow)


def test_grid_validation() -> None:
    with pytest.raises(ValueError, match="resolution"):
        OccupancyGrid(np.zeros((2, 2), np.int8), 0.0)
    with pytest.raises(ValueError, match="resolution"):
        OccupancyGrid(np.zeros((2, 2), np.int8), float("nan"))
    with pytest.raises(ValueError, match="2-D"):
        OccupancyGrid(np.zeros(4, np.int8), 1.0)
    with pytest.raises(ValueError, match="values"):
        OccupancyGrid(np.full((2, 2), 101), 1.0)
    with pytest.raises(ValueError, match="origin"):
        OccupancyGrid(np.zeros((2, 2), np.int8), 1.0, (0.0, 0.0))  # type: ignore[arg-type]
    grid = OccupancyGrid(np.array([[True, False]]), 1.0)
    assert grid.data.tolist() == [[100, 0]]
    assert "2×1 cells" in repr(grid)


# ---- save --------------------------------------------------------------------------------------------------------
def test_save_round_trip(tmp_path: Path) -> None:
    grid = load_map(MST / "testmap2.yaml")
    out = grid.save(tmp_path / "out" / "copy.yaml")
    assert out == tmp_path / "out" / "copy.yaml" and (tmp_path / "out" / "copy.pgm").is_file()
    again = load_map(out)
    assert again == grid
    assert again.origin == (-2.0, -3.0, -1.0)
    img = _core.read_image(str(tmp_path / "out" / "copy.pgm"))
    assert sorted(np.unique(img).tolist()) == [0, 254]


def test_save_keeps_blocked_and_free(tmp_path: Path) -> None:
    data = np.array([[-1, 0, 10, 49], [50, 70, 99, 100]], np.int8)
    grid = OccupancyGrid(data, 0.25, (1.5, -0.5, 0.0), mode="scale")
    again = load_map(grid.save(tmp_path / "m.yaml"))
    np.testing.assert_array_equal(again.blocked(), grid.blocked())
    np.testing.assert_array_equal(again.free_mask(), grid.free_mask())
    assert again.data.tolist() == [[-1, 0, 0, 0], [100, 100, 100, 100]]
    assert (again.resolution, again.origin) == (0.25, (1.5, -0.5, 0.0))


# ---- MovingAI ----------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("name", "width", "height"),
                         [("arena", 49, 49), ("den312d", 65, 81), ("8room_000", 512, 512),
                          ("random512-10-0", 512, 512)])
def test_movingai_maps(name: str, width: int, height: int) -> None:
    d = _movingai_dir()
    grid = load_map(d / f"{name}.map")
    assert (grid.width, grid.height) == (width, height)
    assert grid.resolution == 1.0 and grid.origin == (0.0, 0.0, 0.0)
    # the rows, from the top, against the grid, from the bottom
    rows = (d / f"{name}.map").read_text().splitlines()[4:4 + height]
    for y in (0, height // 2, height - 1):
        want = [0 if ch in ".GS" else 100 for ch in rows[y]]
        assert grid.data[height - 1 - y].tolist() == want
    # every scenario's start and goal is a passable cell
    for line in filter(None, (d / f"{name}.map.scen").read_text().splitlines()[1:]):
        _, _, w, h, sx, sy, gx, gy, _ = line.split("\t")
        assert (int(w), int(h)) == (width, height)
        assert grid.data[movingai_cell(int(sx), int(sy), height)] == 0
        assert grid.data[movingai_cell(int(gx), int(gy), height)] == 0


def test_movingai_arena_cells() -> None:
    grid = load_movingai(_movingai_dir() / "arena.map")
    # line 6 of arena.map (MovingAI y = 1) starts "TTT............TTTT."
    row = movingai_cell(0, 1, 49)[0]
    assert row == 47
    assert grid.data[row, :20].tolist() == [100] * 3 + [0] * 12 + [100] * 4 + [0]
    assert (grid.data[48] == 100).all()  # the top line is all trees


def test_movingai_dict_crlf_and_placement(tmp_path: Path) -> None:
    text = (_movingai_dir() / "arena.map").read_text()
    (tmp_path / "crlf.map").write_bytes(text.replace("\n", "\r\n").encode())
    lf = load_map(_movingai_dir() / "arena.map")
    crlf = load_map({"movingai": "crlf.map", "resolution": 0.1, "origin": (1.0, 2.0, 0.0)}, base_dir=tmp_path)
    np.testing.assert_array_equal(crlf.data, lf.data)
    assert crlf.resolution == 0.1 and crlf.origin == (1.0, 2.0, 0.0)
    # MovingAI (x, y) = (3, 1): column 3, row 47 from the bottom; centre 1 + 3.5*0.1, 2 + 47.5*0.1
    assert crlf.cell_to_world(*movingai_cell(3, 1, 49)) == pytest.approx((1.35, 6.75))
    assert load_map(tmp_path / "crlf.map", resolution=0.5).width_m == pytest.approx(24.5)


def test_movingai_small_file(tmp_path: Path) -> None:
    (tmp_path / "m.map").write_text("type octile\nheight 2\nwidth 3\nmap\n.@G\nSTW\n")
    grid = load_map(tmp_path / "m.map")
    assert grid.data.tolist() == [[0, 100, 100], [0, 100, 0]]  # bottom row first


# ---- Willow Garage cost map ------------------------------------------------------------------------------------
def test_willow_costmap_file() -> None:
    cost = _core.read_image(str(ROS / "willow_costmap" / "willow_costmap.pgm"))
    assert cost.shape == (1217, 1132)
    assert sorted(np.unique(cost).tolist()) == [50, 253, 254]


def _connected(free: np.ndarray, a: tuple[int, int], b: tuple[int, int]) -> bool:
    """Plain 8-connected breadth-first search."""
    seen = np.zeros_like(free)
    seen[a] = True
    queue = deque([a])
    while queue:
        r, c = queue.popleft()
        if (r, c) == b:
            return True
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if 0 <= nr < free.shape[0] and 0 <= nc < free.shape[1] and free[nr, nc] and not seen[nr, nc]:
                    seen[nr, nc] = True
                    queue.append((nr, nc))
    return False


@pytest.mark.slow
def test_shipped_willow_map_is_the_costmap() -> None:
    cost = _core.read_image(str(ROS / "willow_costmap" / "willow_costmap.pgm"))
    grid = load_map(ROOT / "maps" / "willow" / "map.yaml")
    assert (grid.width, grid.height, grid.resolution) == (1132, 1217, 0.05)
    np.testing.assert_array_equal(grid.data == 100, cost[::-1] == 254)
    np.testing.assert_array_equal(grid.data == 0, cost[::-1] != 254)
    # upstream's navfn test pairs (x, y from the top) are free and connected once 253 cells count as free
    pairs = [line.split("#")[0].split() for line in
             (ROS / "willow_costmap" / "expected_navfn.txt").read_text().splitlines() if not line.startswith("#")]
    for sx, sy, gx, gy in ((int(v) for v in p) for p in pairs if p):
        start, goal = (1216 - sy, sx), (1216 - gy, gx)
        assert grid.data[start] == 0 and grid.data[goal] == 0
        assert _connected(grid.data == 0, start, goal)


# ---- bad files ----------------------------------------------------------------------------------------------------
GOOD = {"image": str(MST / "testmap.png"), "resolution": 0.1, "origin": "[2.0, 3.0, 1.0]", "negate": 0,
        "occupied_thresh": 0.65, "free_thresh": 0.196}


@pytest.mark.parametrize("key", list(GOOD))
def test_missing_key(tmp_path: Path, key: str) -> None:
    path = write_yaml(tmp_path / "m.yaml", str(GOOD["image"]), **{key: None})
    with pytest.raises(WorldFileError, match="missing") as e:
        load_map(path)
    assert e.value.path == str(path) and e.value.field == key


@pytest.mark.parametrize(("key", "value", "message", "field"), [
    ("resolution", '"fine"', "expected an integer or a number", "resolution"),
    ("resolution", "0", ">= 0.0001", "resolution"),
    ("resolution", "-0.05", ">= 0.0001", "resolution"),
    ("resolution", ".nan", "finite", "resolution"),
    ("origin", "[1.0, 2.0]", "x, y, yaw", "origin"),
    ("origin", "[1.0, .nan, 0.0]", "finite", "origin[1]"),
    ("origin", "3.0", "expected a list", "origin"),
    ("negate", "2", "0 or 1", "negate"),
    ("negate", '"yes"', "expected", "negate"),
    ("occupied_thresh", "1.5", "<= 1", "occupied_thresh"),
    ("free_thresh", "-0.1", ">= 0", "free_thresh"),
    ("free_thresh", "0.7", "greater than free_thresh", "occupied_thresh"),
    ("occupied_thresh", "0.196", "greater than free_thresh", "occupied_thresh"),
    ("mode", "fancy", "trinary, scale, raw", "mode"),
    ("mode", "Trinary", "trinary, scale, raw", "mode"),
    ("image", "nothere.png", "not found", "image"),
    ("image", "[a, b]", "expected text", "image"),
])
def test_bad_field(tmp_path: Path, key: str, value: str, message: str, field: str) -> None:
    path = write_yaml(tmp_path / "m.yaml", str(GOOD["image"]), **{key: value})
    with pytest.raises(WorldFileError, match=message) as e:
        load_map(path)
    err = e.value
    assert err.path == str(path) and err.field == field
    lines = path.read_text().splitlines()
    assert lines[err.line - 1].startswith(field.split("[")[0] + ":")
    assert f"{path}:{err.line}: {field}:" in str(err)


def test_not_an_image(tmp_path: Path) -> None:
    (tmp_path / "x.png").write_text("not a png")
    path = write_yaml(tmp_path / "m.yaml", "x.png")
    with pytest.raises(WorldFileError, match="cannot read image") as e:
        load_map(path)
    assert e.value.field == "image" and e.value.line == 1


def test_not_yaml(tmp_path: Path) -> None:
    (tmp_path / "m.yaml").write_text("image: [unclosed\n")
    with pytest.raises(WorldFileError, match="not valid YAML"):
        load_map(tmp_path / "m.yaml")
    with pytest.raises(WorldFileError, match="file not found"):
        load_map(tmp_path / "none.yaml")


@pytest.mark.parametrize(("text", "field", "line", "message"), [
    ("height 2\nwidth 3\nmap\n...\n...\n", "type", 1, "expected 'type <value>'"),
    ("type octile\nheight two\nwidth 3\nmap\n...\n...\n", "height", 2, "whole number"),
    ("type octile\nheight 2\nwidth 0\nmap\n...\n...\n", "width", 3, "whole number"),
    ("type octile\nheight 2\nwidth 3\n...\n...\n", "map", 4, "expected 'map'"),
    ("type octile\nheight 2\nwidth 3\nmap\n...\n....\n", "map[1]", 6, "4 characters, expected 3"),
    ("type octile\r\nheight 2\r\nwidth 3\r\nmap\r\n..\r\n...\r\n", "map[0]", 5, "2 characters"),
    ("type octile\nheight 2\nwidth 3\nmap\n...\n", "map", 6, "expected 2 rows"),
    ("type octile\nheight 2\nwidth 3\nmap\n...\n...\n...\n", "map", 7, "more than 2 rows"),
    ("type octile\nheight 2\nwidth 3\nmap\n...\n.x.\n", "map[1]", 6, "unknown terrain 'x' at column 2"),
])
def test_bad_movingai(tmp_path: Path, text: str, field: str, line: int, message: str) -> None:
    path = tmp_path / "bad.map"
    path.write_bytes(text.encode())
    with pytest.raises(WorldFileError, match=message) as e:
        load_map(path)
    assert (e.value.path, e.value.field, e.value.line) == (str(path), field, line)


def test_bad_movingai_placement(tmp_path: Path) -> None:
    (tmp_path / "m.map").write_text("type octile\nheight 1\nwidth 1\nmap\n.\n")
    with pytest.raises(WorldFileError, match="resolution"):
        load_movingai(tmp_path / "m.map", resolution=0.0)
    with pytest.raises(WorldFileError, match="origin"):
        load_movingai(tmp_path / "m.map", origin=(0.0, float("nan"), 0.0))
    with pytest.raises(WorldFileError, match="not found"):
        load_map(tmp_path / "none.map")
    with pytest.raises(WorldFileError, match="unknown key") as e:
        load_map({"movingai": "m.map", "res": 1.0}, base_dir=tmp_path)
    assert e.value.field == "res"
    with pytest.raises(WorldFileError, match="not found") as e:
        load_map({"movingai": "none.map"}, base_dir=tmp_path)
    assert e.value.field == "movingai"
    with pytest.raises(TypeError):
        load_map(MST / "testmap.yaml", resolution=0.1)


def test_load_map_server_alias() -> None:
    assert load_map_server(MST / "testmap.yaml") == load_map(MST / "testmap.yaml")


def test_inflate_counts_a_centre_exactly_radius_away() -> None:
    # One wall square [3, 4] × [3, 4]; the centre of cell (3, 5) is 1.5 m from it. The planners' rule
    # (vwg::geometry::inflate, the configuration space robots plan in) blocks it; vwg.io.maps used to free it.
    data = np.zeros((7, 7), np.int8)
    data[3, 3] = 100
    inflated = OccupancyGrid(data, 1.0).inflate(1.5, unknown=False)
    assert inflated[3, 5] and inflated[5, 3] and not inflated[4, 5]
    assert inflated.sum() == 13  # the 3 × 3 block and the four cells two away in a line


# ---- one grid: vwg.io.maps.OccupancyGrid is the C++ one -------------------------------------------------------
def test_the_python_grid_is_the_cpp_grid_and_data_is_a_view_of_it() -> None:
    grid = OccupancyGrid(np.zeros((7, 9), np.int8), 1.0)
    assert isinstance(grid, _core.OccupancyGrid)
    # The transforms and masks are the C++ class's: none is defined again in Python.
    for name in ("world_to_grid", "grid_to_world", "world_to_cell", "cell_to_world", "inside", "contains", "blocked",
                 "free_mask", "width", "height", "width_m", "height_m", "data", "resolution", "origin"):
        assert name not in vars(OccupancyGrid), name
    # A write through the view is seen by C++: from the centre of cell (3, 4), 3.5 m from the grid's nearest edge,
    # to a new wall in cell (3, 7) is the 2.5 m gap between them.
    data = grid.data
    assert grid.clearance(4.5, 3.5, limit=10) == pytest.approx(3.5)
    data[3, 7] = 100
    assert grid.clearance(4.5, 3.5, limit=10) == pytest.approx(2.5)
    # The view keeps the grid alive after the last name of it is gone.
    del grid
    import gc

    gc.collect()
    assert data.sum() == 100 and data.flags.writeable


def test_the_grid_copies_what_it_is_given_and_pickles_with_its_file_fields() -> None:
    import copy
    import pickle

    given = np.zeros((2, 3), np.int8)
    grid = OccupancyGrid(given, 0.5, (1.0, 2.0, 0.5), mode="scale", source="m.yaml")
    given[0, 0] = 100
    assert grid.data[0, 0] == 0  # copied in: the caller's array is not the grid
    for again in (pickle.loads(pickle.dumps(grid)), copy.deepcopy(grid), grid.copy()):
        assert type(again) is OccupancyGrid and again == grid and again is not grid
        assert (again.mode, again.source, again.origin) == ("scale", "m.yaml", (1.0, 2.0, 0.5))
        again.data[1, 1] = 100
        assert grid.data[1, 1] == 0 and again != grid
    assert OccupancyGrid(np.zeros((2, 3), np.uint16), 0.5) == OccupancyGrid(np.zeros((2, 3), np.int8), 0.5)
    assert grid != "a grid" and grid != 3


def test_far_points_and_huge_indices_are_outside() -> None:
    grid = OccupancyGrid(np.zeros((4, 4), np.int8), 0.05)
    assert grid.world_to_cell(float("inf"), float("-inf")) == (-(2**62), 2**62)
    assert grid.world_to_cell(float("nan"), 0.0) == (0, -(2**62))  # (row, col): x is the column
    assert not grid.inside(2**70, 0) and not grid.inside(0, -(2**70)) and grid.inside(np.int64(3), np.int32(0))


def test_movingai_scenarios_read_by_the_cpp_reader(tmp_path: Path) -> None:
    from vwg.io.maps import load_movingai_scenarios

    d = _movingai_dir()
    scenarios = load_movingai_scenarios(d / "arena.map.scen")
    lines = [line.split("\t") for line in (d / "arena.map.scen").read_text().splitlines()[1:] if line]
    assert len(scenarios) == len(lines) == 160
    for s, f in zip(scenarios, lines, strict=True):
        assert (s.bucket, s.map, s.map_width, s.map_height) == (int(f[0]), f[1], int(f[2]), int(f[3]))
        assert (s.start_x, s.start_y, s.goal_x, s.goal_y) == tuple(int(v) for v in f[4:8])
        assert s.optimal_length == float(f[8])
    bad = tmp_path / "bad.scen"
    bad.write_text("version 1\n0\tarena.map\t49\t49\t1\t2\n")
    with pytest.raises(WorldFileError) as e:
        load_movingai_scenarios(bad)
    assert (e.value.path, e.value.line, e.value.field) == (str(bad), 2, "scenario")
