"""Video files (vwg.VideoWriter, PyAV) and the frame sink a SimView records into. The files are
checked with an independent reader: Debian's ffprobe and ffmpeg programs (codec, pixel format,
frame count, colour tags, decoded pixels) and the raw bytes (the MP4 index before the data, the GIF
signature)."""

from __future__ import annotations

import gc
import json
import shutil
import subprocess
import weakref
from pathlib import Path

import numpy as np
import pytest

import vwg
from vwg.errors import Error, SchemaError

core = vwg._core


def test_ffprobe_is_installed():
    # The Makefile installs Debian's ffmpeg (ffprobe): these tests must fail, not skip, without it.
    assert shutil.which("ffprobe") and shutil.which("ffmpeg"), "install ffmpeg (make deps)"


def probe(path: Path) -> dict[str, str]:
    """ffprobe's view of the first video stream, counting its frames."""
    out = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-count_frames", "-show_entries",
                          "stream=codec_name,profile,pix_fmt,width,height,nb_read_frames,r_frame_rate,color_space,"
                          "color_primaries,color_transfer,color_range", "-of", "json", str(path)],
                         capture_output=True, text=True, check=True).stdout
    return {k: str(v) for k, v in json.loads(out)["streams"][0].items()}


def decoded(path: Path, width: int, height: int) -> np.ndarray:
    """Every frame as RGB, decoded by the ffmpeg program: N×H×W×3 uint8."""
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", str(path), "-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
                         capture_output=True, check=True).stdout
    return np.frombuffer(raw, np.uint8).reshape(-1, height, width, 3)


def solid(width: int, height: int, i: int) -> np.ndarray:
    """A frame of one colour, a different one per index."""
    frame = np.empty((height, width, 3), dtype=np.uint8)
    frame[:] = (40 + 20 * (i % 10), 200 - 15 * (i % 10), 90)
    return frame


# ------------------------------------------------------------------ MP4


def test_mp4_is_h264_yuv420p_bt709_faststart_with_every_frame(tmp_path):
    path = tmp_path / "run.mp4"
    with vwg.VideoWriter(path, 64, 48, fps=10) as video:
        for i in range(12):
            video.write(solid(64, 48, i))
        assert video.frames == 12
        assert video.size == (64, 48)
        assert video.encoder == "libx264"
    assert not video.is_open
    info = probe(path)
    assert (info["codec_name"], info["pix_fmt"], info["width"], info["height"]) == ("h264", "yuv420p", "64", "48")
    assert info["nb_read_frames"] == "12"
    assert info["r_frame_rate"] == "10/1"
    assert (info["color_space"], info["color_primaries"], info["color_transfer"], info["color_range"]) == (
        "bt709", "bt709", "bt709", "tv")
    head = path.read_bytes()[:65536]
    assert head[4:8] == b"ftyp"
    assert head.index(b"moov") < head.index(b"mdat")  # faststart: the index first
    # Colours survive: each frame decoded back is its colour, give or take the compression.
    frames = decoded(path, 64, 48)
    assert len(frames) == 12
    for i in (0, 5, 11):
        assert np.abs(frames[i, 24, 32].astype(int) - solid(1, 1, i)[0, 0]).max() <= 6, (i, frames[i, 24, 32])


def test_the_size_comes_from_the_first_frame_and_views_into_larger_images_are_written(tmp_path):
    path = tmp_path / "lazy.mp4"
    video = vwg.VideoWriter(path, fps=25)
    assert video.size == (0, 0)
    big = solid(100, 80, 2)
    view = big[10:58, 10:74]  # 64 × 48, rows not contiguous
    assert not view.flags.c_contiguous
    video.write(view)
    video.write(view)
    assert video.size == (64, 48)
    video.close()
    info = probe(path)
    assert (info["width"], info["height"], info["nb_read_frames"], info["r_frame_rate"]) == ("64", "48", "2", "25/1")


def test_renderer_frames_go_into_a_video(tmp_path):
    r = core.TopDownRenderer(np.zeros((10, 20), np.int8), 0.1, (0.0, 0.0, 0.0), pixels_per_cell=4.0)
    with vwg.VideoWriter(tmp_path / "sim.mp4", fps=20) as video:
        for i in range(6):
            r.begin(frame=i, time=i * 0.05)
            r.draw_robot((0.5 + 0.1 * i, 0.5, 0.0), 0.15, id=1)
            video.write(r.image())
    assert probe(tmp_path / "sim.mp4")["nb_read_frames"] == "6"


# ------------------------------------------------------------------ GIF


def test_gif_has_its_signature_every_frame_and_exact_flat_colours(tmp_path):
    path = tmp_path / "run.gif"
    video = vwg.VideoWriter(str(path), fps=5)
    for i in range(5):
        frame = solid(41, 31, i)  # odd sizes are fine for GIF
        frame[5:10, 5:20] = (255, 0, 0)
        video.write(frame)
    assert video.encoder == "gif"
    video.close()
    assert not video.is_open
    assert path.read_bytes()[:6] == b"GIF89a"
    info = probe(path)
    assert (info["codec_name"], info["width"], info["height"], info["nb_read_frames"]) == ("gif", "41", "31", "5")
    frames = decoded(path, 41, 31)
    assert len(frames) == 5
    for i in range(5):  # a palette per frame: few colours come back exactly
        assert tuple(frames[i, 20, 30]) == tuple(solid(1, 1, i)[0, 0]), i
        assert tuple(frames[i, 7, 10]) == (255, 0, 0)


def test_gif_faster_than_50_fps_drops_frames_to_50(tmp_path):
    # GIF delays are hundredths of a second and browsers slow delays under 2/100 s down.
    path = tmp_path / "fast.gif"
    with vwg.VideoWriter(path, fps=100) as video:
        for i in range(20):
            video.write(solid(16, 16, i))
    assert probe(path)["nb_read_frames"] == "10"


# ------------------------------------------------------------------ finishing and errors


def test_an_exception_in_the_block_passes_through_and_the_file_is_finished(tmp_path):
    path = tmp_path / "partial.mp4"
    with pytest.raises(KeyError), vwg.VideoWriter(path) as video:
        video.write(solid(64, 48, 0))
        video.write(solid(64, 48, 1))
        raise KeyError("stop")
    assert probe(path)["nb_read_frames"] == "2"


def test_a_writer_dropped_without_close_finishes_its_file(tmp_path):
    path = tmp_path / "dropped.mp4"
    video = vwg.VideoWriter(path, fps=10)
    for i in range(3):
        video.write(solid(64, 48, i))
    del video
    gc.collect()
    info = probe(path)
    assert (info["codec_name"], info["nb_read_frames"]) == ("h264", "3")


def test_wrong_frames_are_refused(tmp_path):
    path = tmp_path / "run.mp4"
    with vwg.VideoWriter(path, 64, 48, fps=10) as video:
        with pytest.raises(Error, match="32×32, the video is 64×48") as e:
            video.write(solid(32, 32, 0))
        assert str(path) in str(e.value)
        with pytest.raises(SchemaError, match="uint8"):
            video.write(solid(64, 48, 0).astype(np.float32))
        with pytest.raises(SchemaError, match="H×W×3"):
            video.write(np.zeros((48, 64), dtype=np.uint8))
        video.write(solid(64, 48, 0))  # still usable
    with pytest.raises(Error, match="closed"):
        video.write(solid(64, 48, 0))
    assert probe(path)["nb_read_frames"] == "1"


def test_bad_places_and_settings_are_named(tmp_path):
    missing = tmp_path / "no" / "such" / "run.mp4"
    with pytest.raises(Error, match="does not exist") as e:
        vwg.VideoWriter(missing)
    assert str(missing) in str(e.value)
    (tmp_path / "folder.mp4").mkdir()
    with pytest.raises(Error, match="folder"):
        vwg.VideoWriter(tmp_path / "folder.mp4")
    with pytest.raises(Error, match="even") as e:
        vwg.VideoWriter(tmp_path / "odd.mp4", 63, 48)
    assert "63×48" in str(e.value)
    odd = vwg.VideoWriter(tmp_path / "late.mp4")
    with pytest.raises(Error, match="even"):
        odd.write(solid(63, 48, 0))
    with pytest.raises(Error) as e:
        vwg.VideoWriter(tmp_path / "run.avi")
    assert str(tmp_path / "run.avi") in str(e.value) and ".mp4" in str(e.value) and ".gif" in str(e.value)
    with pytest.raises(Error, match="fps"):
        vwg.VideoWriter(tmp_path / "run.mp4", fps=0)
    with pytest.raises(Error, match="both"):
        vwg.VideoWriter(tmp_path / "run.mp4", 64)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["folder.mp4"]  # no file was made


def test_closing_without_frames_is_an_error_and_leaves_no_file(tmp_path):
    path = tmp_path / "empty.mp4"
    video = vwg.VideoWriter(path, 64, 48)
    with pytest.raises(Error, match="no frames"):
        video.close()
    assert not path.exists()
    video.close()  # closed: nothing more to do


# ------------------------------------------------------------------ the view's frame sink


class Keeper(vwg.FrameSink):
    """Keeps the frames a SimView hands it, and notes "close" in `log`."""

    def __init__(self, log: list[str] | None = None) -> None:
        super().__init__()
        self.frames: list[np.ndarray] = []
        self.log = [] if log is None else log

    def write(self, image: np.ndarray) -> None:
        self.frames.append(image)

    @property
    def closed(self) -> int:
        return self.log.count("close")

    def close(self) -> None:
        self.log.append("close")


def walking_view(sink: vwg.FrameSink | None, frames: int) -> core.SimView:
    world = vwg.robot.load_robot_world(Path(__file__).resolve().parents[1] / "maps" / "office.yaml")
    sim = vwg.robot.platforms.sim.Simulation(world)
    view = core.SimView(sim.physics, sim.world.grid, width=200)
    if sink is not None:
        view.record_video(sink)
    symbols = vwg.robot.platforms.sim
    alphabet = vwg.Alphabet(events={**symbols.SIM_EVENTS, "show": None}, visual=["show"], **symbols.MOTION_SYMBOLS)
    engine = vwg.Engine(vwg.World(alphabet), "Robot<1>", [vwg.every_frame("show")],
                        vwg.BackendGroup([sim.backend, view]))
    engine.run(frames)
    return view


def test_a_python_sink_gets_its_own_copy_of_every_frame_then_one_close():
    keeper = Keeper()
    view = walking_view(keeper, 3)
    assert len(keeper.frames) == 3 and keeper.closed == 0
    first = keeper.frames[0].copy()
    view.finish(hold_frames=4)
    assert len(keeper.frames) == 7 and keeper.closed == 1
    assert all(f.shape == view.image().shape and f.dtype == np.uint8 for f in keeper.frames)
    # Each is its own array: later frames drawn into the renderer's image do not change it.
    assert np.array_equal(keeper.frames[0], first)
    assert len({f.ctypes.data for f in keeper.frames}) == 7


def test_a_sink_is_kept_alive_by_the_view_and_closed_when_the_view_goes():
    log: list[str] = []
    keeper = Keeper(log)
    view = walking_view(keeper, 2)
    frames, alive = keeper.frames, weakref.ref(keeper)
    del keeper
    gc.collect()
    assert alive() is not None  # the view holds it: its write() is still Python
    del view
    gc.collect()
    assert alive() is None and log == ["close"] and len(frames) == 2


def test_record_video_wants_a_frame_sink():
    world = vwg.robot.load_robot_world(Path(__file__).resolve().parents[1] / "maps" / "office.yaml")
    view = core.SimView(vwg.robot.platforms.sim.Simulation(world).physics, world.grid)
    with pytest.raises(SchemaError, match="FrameSink"):
        view.record_video("run.mp4")


def test_the_view_records_into_a_video_writer(tmp_path):
    path = tmp_path / "view.gif"
    view = walking_view(vwg.VideoWriter(path, fps=10), 5)
    view.finish(hold_frames=3)
    height, width = view.image().shape[:2]
    info = probe(path)
    assert (info["codec_name"], info["nb_read_frames"]) == ("gif", "8")
    assert (int(info["width"]), int(info["height"])) == (width, height)
    last = decoded(path, width, height)[-1]
    assert np.abs(last.astype(int) - view.image().astype(int)).mean() < 2  # the final frame as drawn
