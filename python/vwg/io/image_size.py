"""The size of a map image read from its header, before anything is decoded.

A compressed image is small on disk and large in memory: a 409 KB PNG can hold 20,000 × 20,000
pixels (3.2 GB once they are numbers). ``vwg.io.maps`` asks for the size here first and refuses an
image over its pixel limit without decoding it. Only the formats a map image may be in are read,
told apart by their first bytes as OpenCV (the decoder) tells them apart: PNG, the Netpbm family
(PBM, PGM, PPM: ``P1`` to ``P6``; PAM: ``P7``), BMP and JPEG. Anything else is refused, so no
image reaches the decoder without its size being known.
"""

from __future__ import annotations

import struct
from typing import BinaryIO

__all__ = ["FORMATS", "ImageHeaderError", "image_size"]

FORMATS = "PNG, PGM/PPM/PBM/PAM, BMP or JPEG"
_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_JPEG_MAX_SEGMENTS = 10_000  # markers before the frame header: real files have tens (EXIF, ICC, tables)
_PNM_MAX_HEADER = 4096       # bytes of a Netpbm header, comments included


class ImageHeaderError(ValueError):
    """The header is not one of the formats read here, or is cut short or malformed."""


def image_size(f: BinaryIO) -> tuple[str, int, int]:
    """(format, width, height) from the header of the image open in `f` (binary, at its start)."""
    head = f.read(32)
    if head.startswith(_PNG_SIGNATURE):
        return "PNG", *_png(head)
    if len(head) >= 3 and head[0:1] == b"P" and head[1:2] in b"123456" and head[2:3].isspace():
        return "PNM", *_pnm(head + f.read(_PNM_MAX_HEADER))
    if len(head) >= 3 and head[0:2] == b"P7" and head[2:3].isspace():
        return "PAM", *_pam(head + f.read(_PNM_MAX_HEADER))
    if head.startswith(b"BM"):
        return "BMP", *_bmp(head)
    if head.startswith(b"\xff\xd8\xff"):
        return "JPEG", *_jpeg(f)
    raise ImageHeaderError(f"not a {FORMATS} image (the formats a map image may be in)")


def _png(head: bytes) -> tuple[int, int]:
    # The first chunk is IHDR: length 13, then width and height as big-endian 32-bit numbers.
    if len(head) < 24 or head[12:16] != b"IHDR":
        raise ImageHeaderError("a PNG whose first chunk is not its header (IHDR)")
    width, height = struct.unpack(">II", head[16:24])
    return width, height


def _pnm_tokens(data: bytes, count: int) -> list[int]:
    """The first `count` numbers after the magic number, skipping whitespace and # comments."""
    numbers: list[int] = []
    i = 2
    while len(numbers) < count:
        while i < len(data) and (data[i:i + 1].isspace() or data[i:i + 1] == b"#"):
            if data[i:i + 1] == b"#":
                end = data.find(b"\n", i)
                i = len(data) if end < 0 else end
            i += 1
        start = i
        while i < len(data) and data[i:i + 1].isdigit():
            i += 1
        if i == start or i - start > 10 or i >= len(data):
            raise ImageHeaderError("a Netpbm image whose header does not give its width and height")
        numbers.append(int(data[start:i]))
    return numbers


def _pnm(data: bytes) -> tuple[int, int]:
    width, height = _pnm_tokens(data, 2)
    return width, height


def _pam(data: bytes) -> tuple[int, int]:
    size: dict[bytes, int] = {}
    for line in data.split(b"\n")[1:]:
        words = line.split()
        if words[:1] == [b"ENDHDR"]:
            break
        if len(words) == 2 and words[0] in (b"WIDTH", b"HEIGHT") and words[1].isdigit() and len(words[1]) <= 10:
            size[words[0]] = int(words[1])
    if len(size) != 2:
        raise ImageHeaderError("a PAM image whose header does not give WIDTH and HEIGHT")
    return size[b"WIDTH"], size[b"HEIGHT"]


def _bmp(head: bytes) -> tuple[int, int]:
    if len(head) < 26:
        raise ImageHeaderError("a BMP cut short in its header")
    (info_size,) = struct.unpack("<I", head[14:18])
    if info_size == 12:  # OS/2 1.x: 16-bit sizes
        width, height = struct.unpack("<HH", head[18:22])
    else:  # Windows and OS/2 2.x: 32-bit signed sizes, a negative height for rows top first
        width, height = struct.unpack("<ii", head[18:26])
    return abs(width), abs(height)


def _jpeg(f: BinaryIO) -> tuple[int, int]:
    # Markers and their segments up to the frame header (SOF0..SOF15 but DHT, JPG and DAC).
    f.seek(2)
    for _ in range(_JPEG_MAX_SEGMENTS):
        byte = f.read(1)
        if byte != b"\xff":
            raise ImageHeaderError("a JPEG whose markers are broken before its frame header")
        marker = f.read(1)
        while marker == b"\xff":  # fill bytes
            marker = f.read(1)
        if not marker:
            break
        code = marker[0]
        if code == 0x01 or 0xD0 <= code <= 0xD7:  # markers without a segment
            continue
        if code in (0xD9, 0xDA):  # the end, or the scan, before any frame header
            break
        length_bytes = f.read(2)
        if len(length_bytes) < 2:
            break
        (length,) = struct.unpack(">H", length_bytes)
        if 0xC0 <= code <= 0xCF and code not in (0xC4, 0xC8, 0xCC):
            frame = f.read(5)
            if len(frame) < 5:
                break
            height, width = struct.unpack(">HH", frame[1:5])
            return width, height
        if length < 2:
            raise ImageHeaderError("a JPEG with a segment shorter than its own length field")
        f.seek(length - 2, 1)
    raise ImageHeaderError("a JPEG without a frame header (SOF) giving its size")
