"""Reading the files a user names (world files, maps, images): only regular files, of a stated size at
most, with errors that name the file. A named pipe or a device (``/dev/zero``) is refused before it is
read, instead of hanging or filling the memory."""

from __future__ import annotations

import os
import stat
from pathlib import Path

from .errors import WorldFileError

__all__ = ["MAX_IMAGE_BYTES", "MAX_MAP_BYTES", "MAX_TEXT_BYTES", "check_regular_file", "read_bytes", "read_text"]

MAX_TEXT_BYTES = 16 * 2**20   # a world file or a map's YAML
MAX_MAP_BYTES = 256 * 2**20   # a MovingAI map (16,000 × 16,000 cells)
MAX_IMAGE_BYTES = 512 * 2**20  # a map's image


def check_regular_file(path: str | Path, limit: int) -> Path:
    """`path` if it is a regular file of at most `limit` bytes; WorldFileError naming it otherwise."""
    path = Path(path)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise WorldFileError(str(path), "", "file not found") from None
    except OSError as e:
        raise WorldFileError(str(path), "", f"cannot read the file: {e.strerror}") from None
    except ValueError:  # a NUL byte in the name (from a record or a world file): no file has that name
        raise WorldFileError(repr(str(path)), "", "no file can have this name (it holds a NUL byte)") from None
    if not stat.S_ISREG(info.st_mode):
        kind = "a folder" if stat.S_ISDIR(info.st_mode) else "a named pipe" if stat.S_ISFIFO(info.st_mode) else \
            "a device" if stat.S_ISCHR(info.st_mode) or stat.S_ISBLK(info.st_mode) else "not a regular file"
        raise WorldFileError(str(path), "", f"expected a regular file, this is {kind}")
    if info.st_size > limit:
        raise WorldFileError(str(path), "", f"{info.st_size} bytes: more than the {limit // 2**20} MB such a file "
                                            "may have")
    return path


def read_bytes(path: str | Path, limit: int) -> bytes:
    path = check_regular_file(path, limit)
    chunks: list[bytes] = []
    size = 0
    try:
        with path.open("rb") as f:
            # In pieces, to the limit: the file may have grown since it was looked at.
            while chunk := f.read(min(2**24, limit + 1 - size)):
                chunks.append(chunk)
                size += len(chunk)
                if size > limit:
                    raise WorldFileError(str(path), "", f"more than the {limit // 2**20} MB such a file may have")
    except OSError as e:
        raise WorldFileError(str(path), "", f"cannot read the file: {e.strerror}") from None
    return b"".join(chunks)


def read_text(path: str | Path, limit: int = MAX_TEXT_BYTES) -> str:
    """A UTF-8 text file; an error names the line of a byte that is not UTF-8."""
    data = read_bytes(path, limit)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data[:e.start].count(b"\n") + 1
        raise WorldFileError(str(path), "", f"not UTF-8 text (byte 0x{data[e.start]:02X})", line=line) from None
