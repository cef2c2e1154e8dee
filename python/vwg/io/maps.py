"""Occupancy-grid maps: ROS map_server YAML + image pairs, MovingAI ``.map`` files, and the grid they load into.

    grid = vwg.io.maps.load_map("maps/office/map.yaml")            # ROS map_server / Nav2 YAML + PGM/PNG/BMP
    grid = vwg.io.maps.load_map("arena.map", resolution=0.1)        # MovingAI benchmark map
    grid = vwg.io.maps.load_map({"movingai": "arena.map", "resolution": 0.1, "origin": [0, 0, 0]})
    row, col = grid.world_to_cell(2.0, 3.5)
    grid.save("out/map.yaml")                               # map.yaml + map.pgm, trinary

Conventions are those of nav_msgs/OccupancyGrid and of the C++ ``vwg::sim::OccupancyGrid``: ``data[row, col]``
with row 0 the BOTTOM row of the map (smallest y); ``origin`` (x, y, yaw) is the pose of the lower-left corner of
cell (0, 0); cell (row, col) covers [col, col+1) × [row, row+1) cells of the map frame. Values: -1 unknown,
0 free, 100 occupied; maps loaded in ``scale`` mode hold 1..99 in between.

Loading a map_server image follows ROS 1 map_server (``image_loader.cpp``), which Nav2 matches in trinary mode:

- the colour channels are averaged (in trinary mode an alpha channel is averaged in too, as map_server does);
- ``negate: 1`` replaces the average v by 255 − v; then p = (255 − v) / 255;
- trinary: 100 if p > occupied_thresh, 0 if p < free_thresh, else -1;
- scale: the same ends, and in between -1 where the pixel is fully transparent (alpha 0), else
  ``int(1 + 98 (p − free_thresh) / (occupied_thresh − free_thresh))`` (truncated, as map_server's unsigned char);
- raw: the (negated) average itself, truncated to 0..255 and stored as map_server stores it in the int8
  message, so values above 127 read negative: ``grid.data.view(numpy.uint8)`` gives 0..255 back;
- image rows are flipped so that row 0 is the bottom.

Required keys are map_server's: image (relative to the YAML), resolution, origin, negate, occupied_thresh,
free_thresh; ``mode`` defaults to trinary; other keys are ignored, as map_server and Nav2 do. The image is a
PNG, PGM/PPM/PBM/PAM, BMP or JPEG of at most ``MAX_IMAGE_PIXELS`` (100,000,000) pixels, sized from its header
before it is decoded (vwg.io.image_size); the origin's x and y are within ±1e6 m, its yaw within ±1e3 rad, and so
is the map's far corner (the simulator's bounds).

Where vwg differs: ROS 1 map_server takes the last byte of a 3-channel pixel (blue) as its "alpha" in scale mode
(an artefact of SDL surfaces); vwg takes alpha only from a real alpha channel. 16-bit images are scaled to 0..255
(v / 257) before the rule. Nav2's scale mode (``rint(100·ratio)``) and raw mode (values over 100 unknown) differ
from ROS 1; vwg follows ROS 1, whose upstream tests (map_server/test) are in tests/data/rosmaps.

MovingAI maps (``type octile`` / ``height H`` / ``width W`` / ``map`` then H rows of W characters, LF or CRLF)
count their rows from the TOP: MovingAI (x, y) is column x of row y from the top, so it is cell
``(row, col) = (H − 1 − y, x)`` here (``movingai_cell``), whose centre is at
``origin + ((x + 0.5)·res, (H − 1 − y + 0.5)·res)`` for yaw 0. Passable: ``. G S``; blocked: ``@ O T W``; any
other character is refused, naming its line and column (a map holding one is damaged, and neither guess is safe).
They are read by the C++ reader (``vwg::plan::parse_movingai_map``), the one the C++ planner tests use; scenario
files (``.map.scen``) too (``load_movingai_scenarios``). The grid is the C++ ``vwg::geometry::OccupancyGrid``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

import vwg._core as _core
from vwg.errors import Error, WorldFileError
from vwg.io.files import MAX_IMAGE_BYTES, MAX_MAP_BYTES, check_regular_file, read_bytes
from vwg.io.image_size import ImageHeaderError, image_size
from vwg.io.shipped import expand_user
from vwg.io.yamldoc import YamlDoc

__all__ = ["FREE", "MAX_IMAGE_PIXELS", "MAX_ORIGIN", "OBSTACLE_THRESHOLD", "OCCUPIED", "UNKNOWN", "OccupancyGrid",
           "load_map", "load_map_server", "load_movingai", "load_movingai_scenarios", "movingai_cell"]

UNKNOWN = -1
FREE = 0
OCCUPIED = 100
#: Cells of at least this value are obstacles unless a caller says otherwise (vwg::geometry::kObstacleThreshold).
OBSTACLE_THRESHOLD: int = _core.OBSTACLE_THRESHOLD

MODES = ("trinary", "scale", "raw")
#: Pixels of a map image, read from its header and refused before it is decoded (10,000 × 10,000):
#: the limit is on what the file expands to, not on its bytes (a 409 KB PNG can hold 400 M pixels).
MAX_IMAGE_PIXELS = 100_000_000
#: Metres from (0, 0) of a map's corners, and radians of its yaw: the simulator's bounds
#: (platform::kMaxCoordinate and kMaxAngle: Box2D keeps coordinates as float).
MAX_ORIGIN, MAX_YAW = 1e6, 1e3
_PIXEL_ROWS = 2**20  # pixels turned into cells at a time: the float64 arithmetic needs 8 bytes a value
# map_saver's grey levels: free, occupied, unknown (205/255 sits just above free_thresh 0.196).
_PGM_FREE, _PGM_OCCUPIED, _PGM_UNKNOWN = 254, 0, 205


class OccupancyGrid(_core.OccupancyGrid):
    """A 2-D occupancy grid in nav_msgs/OccupancyGrid order (row 0 = bottom row): the C++
    ``vwg::geometry::OccupancyGrid`` (``vwg._core.OccupancyGrid``, whose transforms and masks it uses)
    with how a file was read added.

    ``data`` is an int8 array (rows × columns) of -1 unknown / 0 free / 100 occupied (1..99 for scale
    maps): a view of the C++ grid, which it keeps alive, so writing to it changes the grid. The cells
    given are copied in (bools as 100 / 0). ``resolution`` is metres per cell; ``origin`` the (x, y, yaw)
    pose of the lower-left corner of cell (0, 0), as map_server's ``origin``; ``mode`` how the image was
    read; ``source`` the file it came from ("" when built in memory).
    """

    mode: str
    source: str

    def __init__(self, data: Any, resolution: float, origin: Sequence[float] = (0.0, 0.0, 0.0),
                 mode: str = "trinary", source: str = "") -> None:
        if mode not in MODES:
            raise ValueError(f"OccupancyGrid.mode: expected one of {', '.join(MODES)}, got {mode!r}")
        super().__init__(data, resolution, origin)
        self.mode = mode
        self.source = source

    @classmethod
    def _of(cls, grid: _core.OccupancyGrid, mode: str = "trinary", source: str = "") -> OccupancyGrid:
        """A copy of a C++ grid (a reader's) with how it was read."""
        out = cls.__new__(cls)
        _core.OccupancyGrid.__init__(out, grid)
        out.mode, out.source = mode, source
        return out

    # -- masks (blocked, free_mask) and coordinates (world_to_cell, cell_to_world, inside, contains, ...) are the
    # C++ grid's: vwg._core.OccupancyGrid.
    def inflate(self, radius: float, threshold: int = OBSTACLE_THRESHOLD, unknown: bool = True) -> np.ndarray:
        """Cells a disc robot of ``radius`` metres cannot be centred on: those whose centre is at most
        ``radius`` from a blocked cell (as a square). Cells outside the grid count as blocked when ``unknown``.
        The free cells of the result are the configuration space of the robot, for 8-connected search: the
        same cells the C++ planners avoid (one implementation, ``vwg::geometry::inflate``)."""
        return _core.grid_inflate(self, radius, threshold, unknown)

    def clearance(self, x: float, y: float, limit: float = 1.0, threshold: int = OBSTACLE_THRESHOLD,
                  unknown: bool = True) -> float:
        """Distance (m) from the world point (x, y) to the nearest blocked cell, capped at ``limit``;
        0 inside a blocked cell. Cells outside the grid count as blocked when ``unknown``
        (``vwg::geometry::clearance``)."""
        return _core.grid_clearance(self, x, y, limit, threshold, unknown)

    # -- files --------------------------------------------------------------------------------------------
    def to_image(self, threshold: int = OBSTACLE_THRESHOLD) -> np.ndarray:
        """The map as a map_saver greyscale image (top row first): 254 free, 0 occupied, 205 unknown.
        Values >= threshold are occupied, 0 <= value < threshold free, -1 unknown, so ``blocked(threshold)``
        and ``free_mask(threshold)`` survive ``save`` and ``load_map`` (map_saver uses 65 and 25 instead)."""
        img = np.full(self.data.shape, _PGM_UNKNOWN, dtype=np.uint8)
        img[self.free_mask(threshold)] = _PGM_FREE
        img[self.blocked(threshold)] = _PGM_OCCUPIED
        return np.ascontiguousarray(img[::-1])

    def save(self, path: str | Path, threshold: int = OBSTACLE_THRESHOLD) -> Path:
        """Write a map_server pair: ``path`` (the YAML) and the PGM beside it with the same stem (trinary,
        see ``to_image``). Returns the YAML path."""
        path = Path(path)
        image = path.with_suffix(".pgm")
        path.parent.mkdir(parents=True, exist_ok=True)
        _core.write_image(str(image), self.to_image(threshold))
        ox, oy, yaw = self.origin
        path.write_text(
            f"image: {image.name}\n"
            "mode: trinary\n"
            f"resolution: {self.resolution!r}\n"
            f"origin: [{ox!r}, {oy!r}, {yaw!r}]\n"
            "negate: 0\n"
            "occupied_thresh: 0.65\n"
            "free_thresh: 0.196\n",
            encoding="utf-8")
        return path

    # -- misc ---------------------------------------------------------------------------------------------
    def copy(self) -> OccupancyGrid:
        """A deep copy."""
        return OccupancyGrid(self.data.copy(), self.resolution, self.origin, self.mode, self.source)

    def __reduce__(self) -> tuple[Any, ...]:
        return type(self), (self.data.copy(), self.resolution, self.origin, self.mode, self.source)

    def __repr__(self) -> str:
        ox, oy, yaw = self.origin
        src = f", source={self.source!r}" if self.source else ""
        return (f"OccupancyGrid({self.width}×{self.height} cells, {self.resolution!r} m/cell, "
                f"{self.width_m:g}×{self.height_m:g} m, origin=({ox:g}, {oy:g}, {yaw:g}), mode={self.mode!r}{src})")


def movingai_cell(x: int, y: int, height: int) -> tuple[int, int]:
    """(row, col) in an OccupancyGrid of the MovingAI cell (x, y) of a map ``height`` rows high
    (MovingAI x is the column, y the row from the top)."""
    return height - 1 - y, x


# ---- map_server -------------------------------------------------------------------------------------------
def _pixels_to_grid(img: np.ndarray, mode: str, negate: bool, occupied: float, free: float) -> np.ndarray:
    """Apply map_server's loading rule to an image (top row first); returns int8 data, bottom row first.
    A block of rows at a time: the rule's float64 values of a whole 100 M-pixel RGBA image would take 3.2 GB."""
    out = np.empty(img.shape[:2], dtype=np.int8)
    rows = max(1, _PIXEL_ROWS // max(1, img.shape[1]))
    for top in range(0, img.shape[0], rows):
        out[top:top + rows] = _pixels_to_cells(img[top:top + rows], mode, negate, occupied, free)
    return np.ascontiguousarray(out[::-1])


def _pixels_to_cells(img: np.ndarray, mode: str, negate: bool, occupied: float, free: float) -> np.ndarray:
    """map_server's rule on a block of pixels: int8 cells in the same order."""
    values = img.astype(np.float64)
    if img.dtype == np.uint16:
        values /= 257.0  # 16-bit to the 0..255 scale the thresholds are written for
    if values.ndim == 2:
        average = values
        alpha = None
    else:
        channels = values.shape[2]
        has_alpha = channels in (2, 4)
        # trinary averages the alpha channel in with the colours (map_server keeps this for compatibility)
        n_avg = channels if (mode == "trinary" or not has_alpha) else channels - 1
        average = values[:, :, :n_avg].sum(axis=2) / n_avg
        alpha = values[:, :, -1] if has_alpha else None
    if negate:
        average = 255.0 - average
    if mode == "raw":
        out = np.floor(average).astype(np.uint8).view(np.int8)
    else:
        p = (255.0 - average) / 255.0
        out = np.full(p.shape, UNKNOWN, dtype=np.int8)
        if mode == "scale":
            ratio = (p - free) / (occupied - free)
            middle = (1.0 + 98.0 * ratio).astype(np.int64).clip(0, 100).astype(np.int8)
            opaque = np.ones(p.shape, dtype=bool) if alpha is None else alpha >= 1.0
            out = np.where(opaque, middle, out).astype(np.int8)
        out[p < free] = FREE
        out[p > occupied] = OCCUPIED
    return out


def _origin(doc: YamlDoc, path: tuple[Any, ...]) -> tuple[float, float, float]:
    value = doc.get(path, list)
    if len(value) != 3:
        raise doc.error(path, f"expected [x, y, yaw], got {len(value)} values")
    x, y = (float(doc.number((*path, i), minimum=-MAX_ORIGIN, maximum=MAX_ORIGIN)) for i in range(2))
    yaw = float(doc.number((*path, 2), minimum=-MAX_YAW, maximum=MAX_YAW))
    return x, y, yaw


def _check_extent(doc: YamlDoc, path: tuple[Any, ...], grid: OccupancyGrid) -> OccupancyGrid:
    """The map's far corners within the simulator's ±MAX_ORIGIN metres too, named by the origin's line."""
    extent = max(grid.width_m, grid.height_m)
    if max(abs(grid.origin[0]), abs(grid.origin[1])) + extent > MAX_ORIGIN:
        raise doc.error(path, f"a map of {grid.width_m:g} × {grid.height_m:g} m placed at ({grid.origin[0]:g}, "
                              f"{grid.origin[1]:g}) reaches beyond ±{MAX_ORIGIN:g} m, the simulator's bounds")
    return grid


def _regular_file(doc: YamlDoc, path: tuple[Any, ...], file: Path, limit: int, what: str) -> Path:
    """`file` if it is a regular file of at most `limit` bytes; an error at `path` saying what it is otherwise
    (a folder, a named pipe, a device such as /dev/zero, missing)."""
    try:
        return check_regular_file(file, limit)
    except WorldFileError as e:
        reason = str(e).removeprefix(f"{file}: ")
        raise doc.error(path, f"{what} {str(file)!r}: {reason}") from None


def _checked_image_size(doc: YamlDoc, file: Path) -> tuple[int, int]:
    """(width, height) of a map image from its header; an error at ``image`` when it is not a format read
    here or holds more than MAX_IMAGE_PIXELS pixels (nothing decoded yet)."""
    try:
        with file.open("rb") as f:
            kind, width, height = image_size(f)
    except ImageHeaderError as e:
        raise doc.error(("image",), f"cannot read image {str(file)!r}: {e}") from None
    except OSError as e:
        raise doc.error(("image",), f"cannot read image {str(file)!r}: {e.strerror}") from None
    if width * height > MAX_IMAGE_PIXELS:
        raise doc.error(("image",), f"image {str(file)!r} is a {kind} of {width} × {height} = {width * height:,} "
                                    f"pixels, over the limit of {MAX_IMAGE_PIXELS:,} pixels of a map image "
                                    "(read from its header; it was not decoded)")
    return width, height


def _map_server(doc: YamlDoc, base: Path) -> OccupancyGrid:
    """A map_server YAML (already parsed) to a grid; ``base`` is the directory image paths are relative to."""
    if not isinstance(doc.data, dict):
        raise doc.error((), "expected a mapping with image, resolution, origin, negate, occupied_thresh, free_thresh")
    image_ref = doc.get(("image",), str)
    if not image_ref.strip():
        raise doc.error(("image",), "empty image path")
    resolution = float(doc.number(("resolution",), minimum=1e-4, maximum=100.0))  # metres per cell
    origin = _origin(doc, ("origin",))
    negate_raw = doc.get(("negate",), (int, bool))
    if negate_raw not in (0, 1):
        raise doc.error(("negate",), f"expected 0 or 1, got {negate_raw!r}")
    occupied = float(doc.number(("occupied_thresh",), minimum=0.0, maximum=1.0))
    free = float(doc.number(("free_thresh",), minimum=0.0, maximum=1.0))
    if occupied <= free:
        raise doc.error(("occupied_thresh",), f"must be greater than free_thresh ({free!r}), got {occupied!r}")
    mode = doc.get(("mode",), str, default="trinary")
    if mode not in MODES:
        raise doc.error(("mode",), f"expected one of {', '.join(MODES)}, got {mode!r}")
    image_path = _expand_user(doc, ("image",), image_ref)
    if not image_path.is_absolute():
        image_path = base / image_path
    _regular_file(doc, ("image",), image_path, MAX_IMAGE_BYTES, "image file")
    _checked_image_size(doc, image_path)
    try:
        img = _core.read_image(str(image_path))
    except Error as e:
        raise doc.error(("image",), f"cannot read image {str(image_path)!r}: {e}") from None
    data = _pixels_to_grid(img, mode, bool(negate_raw), occupied, free)
    return _check_extent(doc, ("origin",), OccupancyGrid(data, resolution, origin, mode, str(doc.path)))


def load_map_server(path: str | Path) -> OccupancyGrid:
    """Load a ROS map_server / Nav2 map YAML and its image (see the module docs for the rule)."""
    doc = YamlDoc(path)
    return _map_server(doc, doc.path.parent)


# ---- MovingAI ---------------------------------------------------------------------------------------------
def load_movingai(path: str | Path, resolution: float = 1.0,
                  origin: Sequence[float] = (0.0, 0.0, 0.0)) -> OccupancyGrid:
    """Load a MovingAI ``.map`` (rows from the top, flipped so row 0 is the bottom); ``resolution`` and
    ``origin`` place it in the world, as the format has neither."""
    p = str(path)
    if isinstance(resolution, bool) or not isinstance(resolution, (int, float)) or not math.isfinite(resolution) \
            or resolution <= 0:
        raise WorldFileError(p, "resolution", f"expected a finite number > 0, got {resolution!r}")
    if len(origin) != 3 or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in origin):
        raise WorldFileError(p, "origin", f"expected three finite numbers [x, y, yaw], got {list(origin)!r}")
    if max(abs(origin[0]), abs(origin[1])) > MAX_ORIGIN or abs(origin[2]) > MAX_YAW:
        raise WorldFileError(p, "origin", f"expected x and y within ±{MAX_ORIGIN:g} m and yaw within ±{MAX_YAW:g} "
                                          f"rad (the simulator's bounds), got {list(origin)!r}")

    # The one MovingAI reader is the C++ one (vwg::plan::parse_movingai_map): a character the format does not
    # have is refused with its line and column, here as in C++ benchmarks and tests.
    x, y, yaw = (float(v) for v in origin)
    result = OccupancyGrid._of(_core.movingai_grid(read_bytes(path, MAX_MAP_BYTES), p, float(resolution), (x, y, yaw)),
                               "trinary", p)
    if max(abs(x), abs(y)) + max(result.width_m, result.height_m) > MAX_ORIGIN:
        raise WorldFileError(p, "origin", f"a map of {result.width_m:g} × {result.height_m:g} m placed at ({x:g}, "
                                          f"{y:g}) reaches beyond ±{MAX_ORIGIN:g} m, the simulator's bounds")
    return result


def load_movingai_scenarios(path: str | Path) -> list[_core.MovingAiScenario]:
    """The scenarios of a MovingAI ``.map.scen`` file, read by the same C++ reader as the maps: each has
    bucket, map, map_width, map_height, start_x, start_y, goal_x, goal_y (MovingAI x, y: ``movingai_cell`` gives
    the grid cell) and optimal_length. A bad line is a WorldFileError naming the file and the line."""
    return _core.movingai_scenarios(read_bytes(path, MAX_MAP_BYTES), str(path))


def _expand_user(doc: YamlDoc, path: tuple[Any, ...], name: str) -> Path:
    """A file name of a YAML file with ``~user`` expanded; no such user is an error at its line."""

    try:
        return expand_user(name)
    except Error as e:
        raise doc.error(path, str(e)) from None


def _movingai_spec(doc: YamlDoc, path: tuple[Any, ...], base: Path) -> OccupancyGrid:
    """``{movingai: file.map, resolution: r, origin: [x, y, yaw]}`` at ``path`` in a YAML document."""
    spec = doc.get(path, dict)
    for key in spec:
        if key not in ("movingai", "resolution", "origin"):
            raise doc.error((*path, key), "unknown key (expected movingai, resolution, origin)")
    ref = doc.get((*path, "movingai"), str)
    resolution = float(doc.number((*path, "resolution"), 1.0, minimum=1e-4, maximum=100.0))  # as map_server's
    origin = _origin(doc, (*path, "origin")) if doc.get((*path, "origin"), default=None) is not None else (0., 0., 0.)
    file = _expand_user(doc, (*path, "movingai"), ref)
    if not file.is_absolute():
        file = base / file
    _regular_file(doc, (*path, "movingai"), file, MAX_MAP_BYTES, "map file")
    return load_movingai(file, resolution, origin)


def _plain(value: Any) -> Any:
    """Mappings to dicts and tuples to lists, as YAML would have given them."""
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    return value


def load_map(source: str | Path | Mapping[str, Any], *, resolution: float | None = None,
             origin: Sequence[float] | None = None, base_dir: str | Path | None = None) -> OccupancyGrid:
    """Load a map: a map_server YAML (``.yaml``/``.yml``), a MovingAI ``.map`` (``resolution`` and ``origin``
    default to 1.0 and (0, 0, 0)), or a mapping ``{movingai: path, resolution:, origin:}``. Relative paths in a
    mapping are taken from ``base_dir`` (default: the current directory). Bad files raise WorldFileError naming
    the file, the field and (for YAML) the line."""
    if isinstance(source, Mapping):
        # a YamlDoc without text: errors name the field, with no file line to point at
        doc = object.__new__(YamlDoc)
        doc.path, doc.data, doc.lines = Path("<map>"), _plain(source), {}
        return _movingai_spec(doc, (), Path(base_dir) if base_dir is not None else Path.cwd())
    path = Path(source)
    if base_dir is not None and not path.is_absolute():
        path = Path(base_dir) / path
    if path.suffix.lower() == ".map":
        return load_movingai(path, 1.0 if resolution is None else resolution,
                             (0.0, 0.0, 0.0) if origin is None else origin)
    if resolution is not None or origin is not None:
        raise TypeError("load_map: resolution and origin are for MovingAI maps; a map_server YAML gives its own")
    return load_map_server(path)
