"""AprilTag detection, pose and tag bitmaps from Python (vwg._core: detect_apriltags, estimate_tag_pose,
apriltag_image). Expected values come from tests/data/apriltag/ (upstream's ground truth, the
apriltag-imgs bitmaps, the family's codes and layout) or from hand geometry: tags drawn into images
with a known pinhole projection by a small numpy renderer written here."""

from __future__ import annotations

import math
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import vwg
from vwg import _core

# The lead may re-export these at the top level; the compiled module always has them.
AT = vwg if hasattr(vwg, "detect_apriltags") else _core

DATA = Path(__file__).resolve().parent / "data" / "apriltag"
GROUND_TRUTH = ["33369213973_9d9bb4cc96_c", "34085369442_304b6bafd9_c"]
PNG_IDS = [0, 1, 2, 5, 42, 100, 586]


# --- helpers ----------------------------------------------------------------------------------------


def read_ground_truth(name: str) -> list[tuple[int, np.ndarray]]:
    """Lines ``id, (x0 y0), (x1 y1), (x2 y2), (x3 y3)`` -> [(id, 4×2 corners)]."""
    tags = []
    for line in (DATA / "test_data" / f"{name}.txt").read_text().splitlines():
        if not line.strip():
            continue
        fields = line.replace(",", " ").replace("(", " ").replace(")", " ").split()
        assert len(fields) == 9, line
        tags.append((int(fields[0]), np.array([float(v) for v in fields[1:]]).reshape(4, 2)))
    return tags


def read_gray_jpeg(name: str) -> np.ndarray:
    """The test photo as grey: luma Y = 0.299 R + 0.587 G + 0.114 B of the decoded RGB, rounded (the
    JPEG's own Y channel up to rounding, which is what upstream's decoder reads)."""
    rgb = _core.read_image(str(DATA / "test_data" / f"{name}.jpg")).astype(np.float64)
    assert rgb.ndim == 3
    assert rgb.shape[2] == 3
    gray = rgb[..., 0] * 0.299 + rgb[..., 1] * 0.587 + rgb[..., 2] * 0.114
    return np.clip(np.rint(gray), 0, 255).astype(np.uint8)


def worst_corner(det, corners: np.ndarray, offset=(0.0, 0.0)) -> float:
    return float(np.max(np.hypot(*(det.corners - (corners + np.asarray(offset))).T)))


def best_match(found, tag_id: int, corners: np.ndarray, offset=(0.0, 0.0)) -> float | None:
    dists = [worst_corner(d, corners, offset) for d in found if d.id == tag_id]
    return min(dists) if dists else None


def upstream_settings() -> dict:
    """The ground truth's settings: decimate 1, no edge refinement, the rest default."""
    return {"quad_decimate": 1.0, "refine_edges": False}


# --- upstream's test images ---------------------------------------------------------------------


@pytest.mark.parametrize("name", GROUND_TRUTH)
def test_every_ground_truth_tag_is_found_within_2_px(name):
    expected = read_ground_truth(name)
    assert expected
    found = AT.detect_apriltags(read_gray_jpeg(name), **upstream_settings())
    for i, (tag_id, corners) in enumerate(expected):
        dist = best_match(found, tag_id, corners)
        assert dist is not None, f"tag {i} (id {tag_id}) not found"
        assert dist < 2.0, f"tag {i}: worst corner {dist:.2f} px away"
    assert len(found) == len(expected)


@pytest.mark.parametrize("name", GROUND_TRUTH)
def test_default_settings_find_only_true_tags(name):
    expected = read_ground_truth(name)
    found = AT.detect_apriltags(read_gray_jpeg(name))
    assert found
    for d in found:
        dists = [worst_corner(d, c) for tag_id, c in expected if tag_id == d.id]
        assert dists
        assert min(dists) < 2.0, f"detection at {d.center} matches no true tag"


@pytest.mark.parametrize("name", GROUND_TRUTH)
def test_a_crop_view_is_read_in_place_and_shifts_the_corners(name):
    expected = read_ground_truth(name)
    gray = read_gray_jpeg(name)
    x0, y0, w, h = 200, 240, 400, 200
    crop = gray[y0 : y0 + h, x0 : x0 + w]  # a view: rows gray.shape[1] bytes apart
    assert not crop.flags.c_contiguous
    found = AT.detect_apriltags(crop, **upstream_settings())
    inside = 0
    for tag_id, corners in expected:
        xs, ys = corners[:, 0], corners[:, 1]
        if xs.min() <= x0 + 4 or xs.max() >= x0 + w - 4 or ys.min() <= y0 + 4 or ys.max() >= y0 + h - 4:
            continue
        inside += 1
        dist = best_match(found, tag_id, corners, offset=(-x0, -y0))
        assert dist is not None
        assert dist < 2.0
    assert inside > 3


def test_detection_objects():
    img = AT.apriltag_image(42, scale=10, border=20)
    (d,) = AT.detect_apriltags(img)
    assert isinstance(d, _core.AprilTagDetection)
    assert d.id == 42
    assert d.hamming == 0
    assert d.decision_margin > 50
    assert d.corners.shape == (4, 2)
    assert d.corners.dtype == np.float64
    assert d.center.shape == (2,)
    assert d.homography.shape == (3, 3)
    assert "id=42" in repr(d)


# --- bitmaps --------------------------------------------------------------------------------------


def read_tag_png(tag_id: int) -> np.ndarray:
    rgba = _core.read_image(str(DATA / "tag36h11_imgs" / f"tag36_11_{tag_id:05d}.png"))
    assert rgba.shape == (10, 10, 4)
    assert (rgba[..., 3] == 255).all()
    assert (rgba[..., 0] == rgba[..., 1]).all()
    assert (rgba[..., 1] == rgba[..., 2]).all()
    return rgba[..., 0]


@pytest.mark.parametrize("tag_id", PNG_IDS)
def test_apriltag_image_equals_the_apriltag_imgs_png(tag_id):
    png = read_tag_png(tag_id)
    img = AT.apriltag_image(tag_id)
    assert img.dtype == np.uint8
    assert img.shape == (10, 10)
    np.testing.assert_array_equal(img, png)
    # scale 7 then a 3-pixel white border: each cell a 7×7 block inside a white frame
    big = np.pad(np.kron(png, np.ones((7, 7), np.uint8)), 3, constant_values=255)
    np.testing.assert_array_equal(AT.apriltag_image(tag_id, "tag36h11", scale=7, border=3), big)


def test_apriltag_image_follows_the_family_codes_and_layout():
    layout = {}
    for line in (DATA / "tag36h11_layout.txt").read_text().splitlines():
        if line.startswith(("bit_x", "bit_y")):
            key, *values = line.split()
            layout[key] = [int(v) for v in values]
    bx, by = layout["bit_x"], layout["bit_y"]
    assert len(bx) == len(by) == 36
    codes = [line.split() for line in (DATA / "tag36h11_codes.txt").read_text().splitlines() if line.strip()]
    assert len(codes) == 587
    for tag_id, code in codes:
        value = int(code, 16)
        expected = np.zeros((10, 10), np.uint8)
        expected[0, :] = expected[-1, :] = expected[:, 0] = expected[:, -1] = 255  # white outer ring
        for k in range(36):
            if (value >> (35 - k)) & 1:
                expected[by[k] + 1, bx[k] + 1] = 255
        np.testing.assert_array_equal(AT.apriltag_image(int(tag_id)), expected, err_msg=f"id {tag_id}")


def test_families():
    names = AT.apriltag_families()
    assert "tag36h11" in names
    f = AT.apriltag_family("tag36h11")
    assert (f.codes, f.bits, f.min_hamming, f.width_at_border, f.total_width) == (587, 36, 11, 8, 10)
    assert not f.reversed_border


# --- detection of rendered tags -------------------------------------------------------------------


@pytest.mark.parametrize("tag_id", PNG_IDS)
@pytest.mark.parametrize("settings", [{}, upstream_settings()], ids=["default", "decimate1"])
def test_upscaled_rendered_tag_is_found_with_hand_computed_corners(tag_id, settings):
    # Cells of 10 px in a 20 px quiet zone: the black square's edges are at 30 and 110 (pixel
    # centres at +0.5). Upright: p0 bottom-left, p1 bottom-right, p2 top-right, p3 top-left.
    img = AT.apriltag_image(tag_id, scale=10, border=20)
    assert img.shape == (140, 140)
    (d,) = AT.detect_apriltags(img, **settings)
    assert d.id == tag_id
    assert d.hamming == 0
    np.testing.assert_allclose(d.corners, [[30, 110], [110, 110], [110, 30], [30, 30]], atol=0.5)
    np.testing.assert_allclose(d.center, [70, 70], atol=0.5)
    p0 = d.homography @ [-1.0, 1.0, 1.0]
    np.testing.assert_allclose(p0[:2] / p0[2], [30, 110], atol=0.5)


def test_corner_order_follows_the_tag_when_the_image_turns():
    # Turned 90° clockwise, (x, y) goes to (140 - y, x).
    img = np.ascontiguousarray(np.rot90(AT.apriltag_image(42, scale=10, border=20), k=-1))
    (d,) = AT.detect_apriltags(img)
    assert d.id == 42
    np.testing.assert_allclose(d.corners, [[30, 30], [30, 110], [110, 110], [110, 30]], atol=0.5)


def test_the_image_is_never_modified():
    # Without decimation the library blurs its working image in place; vwg copies first.
    img = AT.apriltag_image(5, scale=10, border=20)
    before = img.copy()
    for sigma in (0.0, 0.8, -0.8, 2.0):
        for decimate in (1.0, 2.0):
            AT.detect_apriltags(img, quad_decimate=decimate, quad_sigma=sigma)
            np.testing.assert_array_equal(img, before)
    img.setflags(write=False)  # read-only arrays are fine too
    assert [d.id for d in AT.detect_apriltags(img, quad_decimate=1.0, quad_sigma=0.8)] == [5]


def test_other_families():
    for family in ("tag25h9", "tag16h5", "tagStandard41h12"):
        img = AT.apriltag_image(3, family, scale=12, border=30)
        assert [d.id for d in AT.detect_apriltags(img, family)] == [3], family


def test_tiny_and_noisy_images_give_no_crash():
    rng = np.random.default_rng(7)
    for decimate in (1.0, 1.5, 2.0, 4.0):
        for w in range(1, 25):
            for h in range(1, 25, 5):
                noise = rng.integers(0, 256, size=(h, w), dtype=np.uint8)
                found = AT.detect_apriltags(noise, quad_decimate=decimate)
                if w < 6 or h < 6:
                    assert found == []
                assert AT.detect_apriltags(np.zeros((h, w), np.uint8), quad_decimate=decimate) == []


def test_threads_detect_in_parallel_with_consistent_results():
    name = GROUND_TRUTH[1]
    expected = read_ground_truth(name)
    gray = read_gray_jpeg(name)
    barrier = threading.Barrier(4)

    def run(_):
        barrier.wait()
        return [AT.detect_apriltags(gray, **upstream_settings()) for _ in range(3)]

    with ThreadPoolExecutor(4) as pool:
        results = [r for batch in pool.map(run, range(4)) for r in batch]
    for found in results:
        assert len(found) == len(expected)
        for tag_id, corners in expected:
            dist = best_match(found, tag_id, corners)
            assert dist is not None
            assert dist < 2.0


# --- pose on synthetic images --------------------------------------------------------------------

WIDTH, HEIGHT = 640, 480
FX = FY = 600.0
CX, CY = 320.0, 240.0  # pixel centres at +0.5: the centre of a 640×480 image
TAG_SIZE = 0.2  # side of the black square, metres: 8 of tag36h11's 10 cells


def rot_y(yaw: float) -> np.ndarray:
    """Rotation about the camera's y axis (down): the tag turned about its vertical axis."""
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def tag_homography(rot: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Bitmap coordinates of the 10-cell bitmap (cell j covers [j, j+1), centre (5, 5)) to image
    pixels (centres at +0.5) for a tag with rotation R (tag to camera) and centre t (metres):
    K [c·R0, c·R1, t - 5c(R0 + R1)], c = TAG_SIZE / 8."""
    c = TAG_SIZE / 8
    m = np.column_stack([c * rot[:, 0], c * rot[:, 1], t - 5 * c * (rot[:, 0] + rot[:, 1])])
    k = np.array([[FX, 0, CX], [0, FY, CY], [0, 0, 1]])
    return k @ m


def project(hom: np.ndarray, x: float, y: float) -> np.ndarray:
    p = hom @ [x, y, 1.0]
    return p[:2] / p[2]


def render_scene(bitmap: np.ndarray, hom: np.ndarray, background: int = 170, ss: int = 4) -> np.ndarray:
    """The camera image: ss×ss samples per pixel, each the bitmap cell it falls in (or the wall),
    averaged and rounded. Only the tag's bounding box is sampled."""
    img = np.full((HEIGHT, WIDTH), float(background))
    n = bitmap.shape[0]
    box = np.array([project(hom, x, y) for x, y in ((0, 0), (n, 0), (n, n), (0, n))])
    x0, y0 = np.maximum(np.floor(box.min(axis=0)).astype(int) - 1, 0)
    x1, y1 = np.minimum(np.ceil(box.max(axis=0)).astype(int) + 1, [WIDTH, HEIGHT])
    xs = x0 + (np.arange((x1 - x0) * ss) + 0.5) / ss
    ys = y0 + (np.arange((y1 - y0) * ss) + 0.5) / ss
    gx, gy = np.meshgrid(xs, ys)
    inv = np.linalg.inv(hom)
    w = inv[2, 0] * gx + inv[2, 1] * gy + inv[2, 2]
    bx = np.floor((inv[0, 0] * gx + inv[0, 1] * gy + inv[0, 2]) / w).astype(int)
    by = np.floor((inv[1, 0] * gx + inv[1, 1] * gy + inv[1, 2]) / w).astype(int)
    inside = (bx >= 0) & (bx < n) & (by >= 0) & (by < n)
    samples = np.full(gx.shape, float(background))
    samples[inside] = bitmap[by[inside], bx[inside]]
    img[y0:y1, x0:x1] = samples.reshape(y1 - y0, ss, x1 - x0, ss).mean(axis=(1, 3))
    return np.clip(np.rint(img), 0, 255).astype(np.uint8)


# (horizontal range m, bearing ° positive left, height m (+ below the axis), tag yaw °)
POSE_CASES = [
    (0.5, 0, 0, 0), (0.5, 8, 0, 0), (0.5, -8, 0.05, 20),
    (1.0, 0, 0, 0), (1.0, 15, 0, -30), (1.0, -20, -0.1, 0),
    (2.0, 0, 0, 45), (2.0, 20, 0.2, 0), (2.0, -22, 0, 20),
    (3.5, 10, 0, -20), (3.5, -15, 0.3, 0),
    (5.0, 0, 0, 0), (5.0, 18, 0, 0), (5.0, -20, -0.3, 15),
]  # fmt: skip


@pytest.mark.parametrize(("rng", "bearing_deg", "height", "yaw_deg"), POSE_CASES)
def test_pose_distance_within_5_percent_and_bearing_within_2_degrees(rng, bearing_deg, height, yaw_deg):
    b = math.radians(bearing_deg)
    t = np.array([-rng * math.sin(b), height, rng * math.cos(b)])  # camera: x right, y down, z ahead
    rot = rot_y(math.radians(yaw_deg))
    hom = tag_homography(rot, t)
    corners = np.array([project(hom, x, y) for x, y in ((1, 9), (9, 9), (9, 1), (1, 1))])  # p0..p3
    assert (corners > 2).all()
    assert (corners[:, 0] < WIDTH - 2).all()
    assert (corners[:, 1] < HEIGHT - 2).all()
    img = render_scene(AT.apriltag_image(7), hom)
    (d,) = AT.detect_apriltags(img)
    assert d.id == 7
    assert np.max(np.hypot(*(d.corners - corners).T)) < 1.0

    pose = AT.estimate_tag_pose(d, TAG_SIZE, FX, FY, CX, CY)
    distance = float(np.linalg.norm(t))
    bearing = math.atan2(-t[0], t[2])
    assert abs(pose.distance - distance) / distance < 0.05
    assert abs(math.degrees(pose.bearing - bearing)) < 2.0
    assert pose.rotation.shape == (3, 3)
    assert pose.translation.shape == (3,)
    assert pose.distance == pytest.approx(float(np.linalg.norm(pose.translation)))
    assert pose.error >= 0
    np.testing.assert_allclose(pose.rotation @ pose.rotation.T, np.eye(3), atol=1e-6)
    if rng <= 2.0:  # farther, a tag of 30 px or less leaves the orientation ambiguous
        cos_angle = (np.trace(pose.rotation @ rot.T) - 1) / 2
        assert math.degrees(math.acos(min(1.0, max(-1.0, cos_angle)))) < 5.0


def test_bearing_is_positive_to_the_left():
    t = np.array([-0.5, 0.0, 2.0])  # 2 m ahead, 0.5 m to the left, facing the camera
    (d,) = AT.detect_apriltags(render_scene(AT.apriltag_image(1), tag_homography(np.eye(3), t)))
    pose = AT.estimate_tag_pose(d, TAG_SIZE, FX, FY, CX, CY)
    assert pose.bearing > 0
    assert pose.bearing == pytest.approx(math.atan2(0.5, 2.0), abs=math.radians(2))
    np.testing.assert_allclose(pose.translation, t, atol=0.1)
    assert "distance=" in repr(pose)


# --- errors ---------------------------------------------------------------------------------------

GOOD = np.zeros((20, 20), np.uint8)


@pytest.mark.parametrize(
    "image",
    [
        None,
        [[0, 1], [2, 3]],
        b"\x00" * 100,
        np.zeros((0, 10), np.uint8),
        np.zeros((10, 0), np.uint8),
        np.zeros((0, 0), np.uint8),
        np.zeros(100, np.uint8),
        np.zeros((10, 10, 3), np.uint8),
        np.zeros((10, 10), np.float32),
        np.zeros((10, 10), np.int8),
        np.zeros((10, 10), np.uint16),
        np.zeros((10, 10), bool),
        np.zeros((10, 10), object),
        np.zeros((20, 20), np.uint8)[:, ::2],
        np.zeros((20, 20), np.uint8)[::-1],
        np.zeros((20, 20), np.uint8).T,
    ],
    ids=lambda v: type(v).__name__ if not isinstance(v, np.ndarray) else f"{v.dtype}{v.shape}{v.strides}",
)
def test_bad_images_raise_schema_error(image):
    with pytest.raises(vwg.SchemaError, match="image"):
        AT.detect_apriltags(image)


@pytest.mark.parametrize(
    "settings",
    [
        {"family": "tag99h1"},
        {"quad_decimate": 2.5},
        {"quad_decimate": 0.5},
        {"quad_decimate": float("nan")},
        {"quad_sigma": float("inf")},
        {"decode_sharpening": -1.0},
        {"threads": 0},
        {"max_hamming": 3},
    ],
)
def test_bad_settings_raise_schema_error(settings):
    with pytest.raises(vwg.SchemaError):
        AT.detect_apriltags(GOOD, **settings)


def test_unknown_family_names_the_known_ones():
    with pytest.raises(vwg.SchemaError, match="tag36h11") as info:
        AT.detect_apriltags(GOOD, "tag36h12")
    assert info.value.field == "family"


def test_bad_tag_images_and_poses():
    for args, kwargs in (((-1,), {}), ((587,), {}), ((0, "nope"), {}), ((0,), {"scale": 0}), ((0,), {"border": -1})):
        with pytest.raises(vwg.SchemaError):
            AT.apriltag_image(*args, **kwargs)
    with pytest.raises(vwg.SchemaError):
        AT.apriltag_family("nope")
    (d,) = AT.detect_apriltags(AT.apriltag_image(0, scale=10, border=20))
    AT.estimate_tag_pose(d, 0.1, 500, 500, 70, 70)
    for args in ((0.0, 500, 500, 70, 70), (-0.1, 500, 500, 70, 70), (0.1, 0, 500, 70, 70),
                 (0.1, 500, 500, float("nan"), 70)):  # fmt: skip
        with pytest.raises(vwg.SchemaError):
            AT.estimate_tag_pose(d, *args)
    with pytest.raises(TypeError):
        AT.estimate_tag_pose("not a detection", 0.1, 500, 500, 70, 70)
