"""Video files from RGB frames: MP4 (H.264, yuv420p, faststart: what browsers play) and GIF.

Encoded with PyAV (the ``av`` package): its wheels bundle FFmpeg's libraries, so frames are encoded
in this process by libx264 and FFmpeg's GIF encoder, with no ffmpeg program to find and no
process, pipe or signal handling of our own (what the C++ simulator library used to carry).

A ``VideoWriter`` is also a ``vwg.FrameSink``: a ``SimView`` hands it each frame it draws.

    with VideoWriter("run.mp4", fps=20) as video:
        for image in images:          # H×W×3 uint8 RGB arrays, all one size
            video.write(image)
"""

from __future__ import annotations

import contextlib
import math
import os
import weakref
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

import vwg._core as _core
from vwg.errors import Error, SchemaError

__all__ = ["VIDEO_EXTENSIONS", "VideoWriter"]

#: File extensions a VideoWriter writes, and the container each means.
VIDEO_EXTENSIONS: dict[str, str] = {".mp4": "mp4", ".m4v": "mp4", ".gif": "gif"}

# Browsers play GIF delays under 2/100 s slowly: faster videos drop frames to this rate instead.
_GIF_MAX_FPS = 50


class _Encoder:
    """The open file: container, stream and (GIF) the palette filters. Kept apart from the writer so
    that a finalizer can finish the file when the writer is dropped unclosed."""

    def __init__(self, path: Path, kind: str, width: int, height: int, fps: float, crf: int, preset: str,
                 gif_dither: bool) -> None:
        import av  # imported here: `import vwg` does not load FFmpeg's libraries

        self.av = av
        self.path = path
        self.rate = Fraction(fps).limit_denominator(1_000_000)
        self.time_base = 1 / self.rate
        self.graph: Any = None
        # "file:" so that a name with a colon is not taken for a protocol.
        if kind == "mp4":
            self.container = av.open(f"file:{path}", "w", format="mp4", options={"movflags": "+faststart"})
            stream = self.container.add_stream("libx264", rate=self.rate)
            stream.width, stream.height, stream.pix_fmt = width, height, "yuv420p"
            # The frames are converted to BT.709 (write()) and tagged so: players assume BT.709 for
            # untagged video, and an untagged BT.601 conversion would shift colours.
            stream.options = {"crf": str(crf), "preset": preset, "color_primaries": "bt709", "color_trc": "bt709",
                              "colorspace": "bt709", "color_range": "tv"}
        else:
            self.container = av.open(f"file:{path}", "w", format="gif", options={"loop": "0"})
            out_rate = min(self.rate, Fraction(_GIF_MAX_FPS))
            stream = self.container.add_stream("gif", rate=out_rate)
            stream.width, stream.height, stream.pix_fmt = width, height, "pal8"
            # A palette per frame, made from that frame: streams in bounded memory and keeps flat
            # colours exact (palettegen + paletteuse, as `ffmpeg -vf` would run them).
            graph = av.filter.Graph()
            node = graph.add_buffer(width=width, height=height, format="rgb24", time_base=self.time_base)
            if self.rate > _GIF_MAX_FPS:
                fps_node = graph.add("fps", f"fps={_GIF_MAX_FPS}")
                node.link_to(fps_node)
                node = fps_node
            split = graph.add("split")
            palette = graph.add("palettegen", "stats_mode=single")
            use = graph.add("paletteuse", "new=1:dither=" + ("bayer:bayer_scale=4" if gif_dither else "none"))
            sink = graph.add("buffersink")
            node.link_to(split)
            split.link_to(palette, 0, 0)
            split.link_to(use, 1, 0)
            palette.link_to(use, 0, 1)
            use.link_to(sink)
            graph.configure()
            self.graph = graph
        self.stream = stream
        self.frames = 0

    def write(self, image: np.ndarray) -> None:
        av = self.av
        frame = av.VideoFrame.from_ndarray(image, format="rgb24")
        frame.pts = self.frames
        frame.time_base = self.time_base
        if self.graph is None:
            frame = frame.reformat(format="yuv420p", dst_colorspace="ITU709", dst_color_range="MPEG")
            frame.pts = self.frames
            frame.time_base = self.time_base
            self._encode(frame)
        else:
            self.graph.push(frame)
            self._drain()
        self.frames += 1

    def _drain(self) -> None:
        av = self.av
        while True:
            try:
                frame = self.graph.pull()
            except (av.error.BlockingIOError, av.error.EOFError):
                return
            self._encode(frame)

    def _encode(self, frame: Any) -> None:
        for packet in self.stream.encode(frame):
            self.container.mux(packet)

    def finish(self) -> None:
        """Flush the encoder and write the container's index; the file is closed even on failure."""
        try:
            if self.graph is not None:
                self.graph.push(None)
                self._drain()
            for packet in self.stream.encode(None):
                self.container.mux(packet)
        finally:
            self.container.close()


def _finish_quietly(writer_state: dict[str, Any]) -> None:
    """Finish a writer's file when the writer is dropped unclosed (or Python exits)."""
    encoder: _Encoder | None = writer_state.pop("encoder", None)
    if encoder is not None:
        try:
            encoder.finish()
        except Exception as e:  # a finalizer must not raise; say what happened
            import sys

            print(f"vwg: {encoder.path}: {e}", file=sys.stderr)


class VideoWriter(_core.FrameSink):
    """A video file, by extension: ``.mp4`` (H.264 High, yuv420p, BT.709, the index first so
    browsers start playing before the download ends) or ``.gif`` (looping, a palette per frame).

    ``width`` and ``height`` fix the frame size (MP4 needs both even); without them the first frame
    gives it. ``crf`` (0 lossless .. 51 worst; 18-23 look clean) and ``preset`` (x264's speed
    against size, ultrafast .. veryslow) tune H.264; ``gif_dither`` dithers GIF colours (smoother
    fades, larger files). Use it as a context manager or call close(); a writer dropped unclosed
    still finishes its file. Not thread-safe: one thread writes a given video.

    Raises vwg.Error naming the file: unknown extension, folder missing, a folder in the file's
    place, odd MP4 size, fps not positive.
    """

    def __init__(self, path: str | os.PathLike[str], width: int | None = None, height: int | None = None,
                 fps: float = 10.0, *, crf: int = 20, preset: str = "fast", gif_dither: bool = False) -> None:
        super().__init__()
        self._path = Path(path)
        where = str(path)
        suffix = self._path.suffix.lower()
        if suffix not in VIDEO_EXTENSIONS:
            raise Error(f"{where}: unknown video type '{suffix}'; use "
                        + " or ".join(f"{e} ({VIDEO_EXTENSIONS[e].upper()})" for e in (".mp4", ".gif"))
                        + " (also .m4v for MP4)")
        self._kind = VIDEO_EXTENSIONS[suffix]
        if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not math.isfinite(fps) or fps <= 0:
            raise Error(f"{where}: fps must be a positive number, got {fps!r}")
        if (width is None) != (height is None):
            raise Error(f"{where}: give both width and height, or neither (the first frame's size)")
        if width is not None and height is not None:
            if not (isinstance(width, int) and isinstance(height, int) and width > 0 and height > 0):
                raise Error(f"{where}: bad frame size {width}×{height}")
            self._check_even(width, height)
        if not 0 <= crf <= 51:
            raise SchemaError(f"crf: expected 0 (lossless) to 51, got {crf}")
        if self._path.is_dir():
            raise Error(f"{where}: is a folder, not a file")
        folder = self._path.absolute().parent
        if not folder.is_dir():
            raise Error(f"{where}: cannot create the file: the folder {folder} does not exist")
        if not os.access(folder, os.W_OK):
            raise Error(f"{where}: cannot create the file: the folder {folder} is not writable")
        self._size = (width, height) if width is not None and height is not None else (0, 0)
        self._fps = float(fps)
        self._settings = (int(crf), str(preset), bool(gif_dither))
        self._frames = 0
        self._closed = False
        self._state: dict[str, Any] = {}
        self._finalizer = weakref.finalize(self, _finish_quietly, self._state)

    def _check_even(self, width: int, height: int) -> None:
        if self._kind == "mp4" and (width % 2 or height % 2):
            raise Error(f"{self._path}: H.264 in yuv420p (what browsers play) needs an even width and height, got "
                        f"{width}×{height} (RenderStyle.even_size gives even images)")

    def write(self, image: np.ndarray) -> None:
        """Append one frame: an H×W×3 uint8 RGB array of the video's size."""
        if self._closed:
            raise Error(f"{self._path}: the video is closed")
        if not isinstance(image, np.ndarray) or image.ndim != 3 or image.shape[2] != 3:
            shape = getattr(image, "shape", type(image).__name__)
            raise SchemaError(f"image: expected an H×W×3 array (RGB), got {shape}")
        if image.dtype != np.uint8:
            raise SchemaError(f"image: expected uint8 pixels, got {image.dtype}")
        height, width = image.shape[:2]
        which = f"{self._path}: frame {self._frames}"
        if self._size == (0, 0):
            self._check_even(width, height)
            self._size = (width, height)
        if (width, height) != self._size:
            raise Error(f"{which} is {width}×{height}, the video is {self._size[0]}×{self._size[1]}")
        encoder: _Encoder | None = self._state.get("encoder")
        try:
            if encoder is None:
                encoder = _Encoder(self._path, self._kind, *self._size, self._fps, *self._settings)
                self._state["encoder"] = encoder
            encoder.write(np.ascontiguousarray(image))
        except Exception as e:
            # The encoder or the disk failed (full disk, ...): the file cannot be finished.
            self._state.pop("encoder", None)
            self._closed = True
            if encoder is not None:
                with contextlib.suppress(Exception):  # the original error is the one to report
                    encoder.container.close()
            raise Error(f"{which}: the encoder failed: {e}") from e
        self._frames += 1

    def close(self) -> None:
        """Finish the file. Raises vwg.Error if no frame was written (no file is then made) or the
        encoder failed. Does nothing when already closed."""
        if self._closed:
            return
        self._closed = True
        self._finalizer.detach()
        encoder: _Encoder | None = self._state.pop("encoder", None)
        if encoder is None:
            raise Error(f"{self._path}: no frames were written; no video was made")
        try:
            encoder.finish()
        except Exception as e:
            raise Error(f"{self._path}: the encoder failed after {self._frames} frames: {e}") from e
        if not self._path.is_file() or self._path.stat().st_size == 0:
            raise Error(f"{self._path}: the encoder ({self.encoder}) left no video behind")

    def __enter__(self) -> VideoWriter:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, *exc: object) -> None:
        if exc_type is None:
            self.close()
            return
        # An exception is already on its way out: finishing must not replace it with our own.
        with contextlib.suppress(Error):
            self.close()

    @property
    def path(self) -> str:
        """The file."""
        return str(self._path)

    @property
    def is_open(self) -> bool:
        """Until close() (or a failed write)."""
        return not self._closed

    @property
    def frames(self) -> int:
        """Frames written so far."""
        return self._frames

    @property
    def fps(self) -> float:
        return self._fps

    @property
    def size(self) -> tuple[int, int]:
        """(width, height); (0, 0) before the first frame when not given."""
        return self._size

    @property
    def encoder(self) -> str:
        """The FFmpeg encoder: 'libx264' or 'gif'."""
        return "libx264" if self._kind == "mp4" else "gif"

    def __repr__(self) -> str:
        state = "open" if self.is_open else "closed"
        width, height = self._size
        return f"VideoWriter({self.path!r}, {width}×{height}, {self._fps:g} fps, {self._frames} frames, {state})"
