"""Reading the files a user names (world files, maps, images): only regular files, of a stated size at
most, with errors that name the file. A named pipe or a device (``/dev/zero``) is refused before it is
read, instead of hanging or filling the memory."""

from __future__ import annotations

import os
import stat
from pathlib import Path

from vwg.errors import Error, WorldFileError

__all__ = ["MAX_IMAGE_BYTES", "MAX_MAP_BYTES", "MAX_TEXT_BYTES", "check_output_file", "check_regular_file",
           "read_bytes", "read_text"]

MAX_TEXT_BYTES = 16 * 2**20   # a world file or a map's YAML
MAX_MAP_BYTES = 256 * 2**20   # a MovingAI map (16,000 × 16,000 cells)
MAX_IMAGE_BYTES = 512 * 2**20  # a map's image


def _kind(mode: int) -> str:
    return "a folder" if stat.S_ISDIR(mode) else "a named pipe" if stat.S_ISFIFO(mode) else \
        "a socket" if stat.S_ISSOCK(mode) else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else \
        "not a regular file"


def check_output_file(path: Path, flag: str, inputs: dict[str, Path], folder: bool = False) -> None:
    """Before a run starts: `path`, where `flag` writes, must not be one of the run's `inputs` (what it
    is -> its path; the run would overwrite what it reads) nor an existing named pipe, socket or block
    device (writing to a pipe nobody reads waits for ever). A character device (/dev/null) is taken:
    it never blocks a writer. `folder`: the output is a folder (--images), so an existing folder is fine."""
    try:
        info = os.stat(path)
    except (OSError, ValueError):
        return  # not there yet (or a name no file can have): the writer says why it cannot make it
    mode = info.st_mode
    if not (stat.S_ISREG(mode) or stat.S_ISCHR(mode) or (folder and stat.S_ISDIR(mode))):
        expected = "a folder" if folder else "a regular file"
        raise Error(f"{flag} {path}: expected {expected}, this is {_kind(mode)}")
    for what, source in inputs.items():
        try:
            same = os.path.samefile(path, source)
        except (OSError, ValueError):
            continue
        if same:
            raise Error(f"{flag} {path}: this is {what}; the run would overwrite it (write elsewhere)")


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
        raise WorldFileError(str(path), "", f"expected a regular file, this is {_kind(info.st_mode)}")
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
