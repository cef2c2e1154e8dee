"""Recording a run as JSON Lines and replaying it exactly.

A record (format 5) is one JSON object per line, read in order:

    {"vwg_record": 5, "version": ..., "chain": "sha256", "world_file": ..., "world": {...}, "world_kind": ...,
     "seed": 0, "dt": 0.1, "frame": 0, "frames_planned": 100, "initial": "<text>", "blobs": {...}}   the header
    {"t": 0, "time": 0.0, "events": [...], "string": "<text of w at the start of frame t>", "blobs": {...},
     "prev": "<link>"}
    ...
    {"end": true, "t": 10, "string": "<text of the last string>", "frames": 10,
     "faults": [{"time_s": 9.1, "robot": 0, "what": "link lost: ..."}], "prev": "<link>", "self": "<link>"}

Every line is written and flushed as its frame ends; the end line is written when the run ends,
however it ends, with the faults of a real robot's run (its watchdog stops, each drop and return of
its link; [] on the simulator). Every line after the header carries ``prev``, the link of the line before it: the
first 32 hex digits of the SHA-256 of its text (without the newline), or with ``"chain":
"hmac-sha256"`` of its HMAC-SHA-256 with the key of ``vwg run --record-key``. A line changed,
dropped, added or moved breaks the chain at the next line, which a reader names; a blank line is a
line like any other (the writer writes none). The end line, which no line follows, also holds
``self``, the link of its own text without ``self``, and is read whole: its fields in that order,
its text as the writer makes it, ``t`` the frame after the last line's and ``frames`` their count;
any byte after it is an error naming the line. A record without its end line was cut (the process
was killed): a reader says so and how many frames it holds (of ``frames_planned``, when the run
knew); a last line cut short in the middle is skipped with a warning.

A reader checks every line against the chain, and each line's fields (the header's seed, dt and
frame of the engine's types and the ranges a run takes, its initial string and blobs present, its
world_kind a kind this vwg knows; the end line's faults with time_s from 0 to 1e9 s, robot an id
from 0 to 2**31 - 1 and what at most MAX_FAULT_TEXT characters, which the writer cuts a longer one
to; lists and objects nested at most MAX_JSON_DEPTH deep) and each blob's dtype and shape (at most
MAX_BLOB_ELEMENTS elements) and each frame's event count (at most MAX_FRAME_EVENTS), before it
inflates anything; each blob and column is then inflated no further than its declared size holds,
so a small line that would inflate to gigabytes costs its declared size and is refused.

A record is data: replaying it runs no code it names. A generic world's record keeps the world
file's content (``world``); replay builds the world from the file the user gives, else from the
file the record names if that holds the same content (vwg.generic.world_of_record), else from the record's
copy only if that names no Python code. A robot world's record names its world file, a registered
planner and the run's --goal orders (robot_data); what it names that is not there (a missing file,
an unknown planner, a room the world lacks) is an error naming the record's line 1 and the field.

``events`` is S, the frame's events in order. An item is either one event's text, as the engine
writes it (``"eOdometry<to=1, x=3.25, y=10.5, angle=1.5, busy=false, commands=3>"``), or a *run*
of n >= MIN_RUN consecutive events of one type, with the same target presence and the same fields,
all of them int, float or bool:

    {"run": "eLaser", "n": 344, "to": "<column>", "fields": {"dist": ["f", "<column>"], "angle": ["f", "<column>"]}}

``to`` (the targets, an int column) is there when the events have targets; ``fields`` lists the
fields in the event type's order with their kind, "i" (int64), "f" (float64) or "b" (bool). The
run stands for the n texts ``eLaser<to=to[k], dist=dist[k], angle=angle[k]>``, k = 0..n-1, with
ints in decimal, floats as Python's repr (the shortest text that reads back as the same double,
which is how the engine writes reals) and bools as true/false: the engine's own texts, so replay
parses exactly what format 1 stored. The runs come from the engine's event list as columns
(FrameRecord.event_runs), without a Python object or a text per event.

A column holds the n values as little-endian 8-byte words (bools: 1 byte) and is coded in steps:

1. int and float columns: each word minus the previous one (the first as is), wrapping modulo
   2**64 (a float's word is its IEEE bits), then zigzagged (d << 1) ^ (d >> 63), so that small
   steps either way have zero high bytes;
2. shuffled: byte 0 of every word, then byte 1 of every word, and so on (as blosc does);
3. deflated (zlib format) with a preset dictionary: the step-2 bytes of the same column of the
   same run in the latest earlier frame that had that run, if any. The same run is the j-th run of
   the frame with this type, target presence and field names and kinds; the dictionary is what
   makes laser angles cost nearly nothing, as they repeat from frame to frame;
4. base85 (RFC 1924 alphabet, as Python's base64.b85encode), which JSON needs no escapes for.

So a frame's columns decode only after the frames before it, and the reader keeps that state.

``blobs`` (large attributes) maps a blob's name (its content hash, as the texts write it after
``@``) to its content, given once: in the header, or on the first line whose string or events
refer to it, before any line that uses it as a base. A blob is either whole,

    {"dtype": "int16", "shape": [360, 500], "zlib_base85": "<C-order bytes, zlib, base85>"}

or the change from an earlier blob, its base, whose dtype and shape it has:

    {"base": "<name>", "zlib_base85": "<changes, zlib, base85>"}

The changes, inflated, are k int64 gaps (the flat C-order index of the first element that differs
from the base, then the differences between successive indices) followed by the k new elements
XOR the base's (as unsigned ints of the element's size), each array shuffled as in step 2; k
follows from the length. Reading checks that every blob decodes to content whose hash is its name.
Format 4 is format 3 with those names from xxHash's XXH3 (twice as fast as format 3's own hash);
format 5 is format 4 with the end line's own link, the keyed chain, and robot worlds' --goal
orders in the header's ``world``. A reader takes one format only, and names the format a record has.

Replaying re-runs η/π/φ with the recorded events and checks every string against the record, so
a replay is a bit-for-bit determinism check as well.
"""

from __future__ import annotations

import contextlib
import hashlib
import hmac
import json
import math
import zlib
from collections import deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

import numpy as np

import vwg._core as _core
from vwg.errors import Error, SchemaError, WorldFileError, clip
from vwg.io.files import read_bytes
from vwg.io.shipped import resolve_world
from vwg.model.limits import MAX_DT, MAX_TIME, MIN_DT
from vwg.plugins import deciders, world_kinds

__all__ = ["Record", "Recorder", "decode_blob", "encode_blob", "read_record"]

FORMAT = 5
MAX_RECORD_BYTES = 2**40  # a record is read whole; it is as big as the run made it
# What a record's lines may expand to, checked before anything is inflated or allocated:
MAX_BLOB_ELEMENTS = 2**27  # 134 M elements a blob (a float64 blob is then 1 GiB; a map of 100 M cells fits)
MAX_FRAME_EVENTS = 2**24  # 16.8 M events a frame (ten thousand robots' 690-beam scans are 6.9 M)
MAX_JSON_DEPTH = 100  # lists and objects inside each other on one line (the writer's nest a few deep)
_BLOB_DTYPES = ("int8", "uint8", "int16", "int32", "int64", "float32", "float64")  # what a Blob holds
MIN_RUN = 8  # shorter runs cost less as text than their columns' framing
SMALL_DEFLATE = 64 * 1024  # bytes: up to this, columns and changes are deflated the thorough way (_deflate)
BASE_CANDIDATES = 4  # a new blob is stored against the closest of the last few of its dtype and shape

_DTYPE_OF: dict[str, np.dtype] = {"b": np.dtype(np.bool_), "i": np.dtype("<i8"), "f": np.dtype("<f8")}
_UNSIGNED: dict[int, np.dtype] = {1: np.dtype("u1"), 2: np.dtype("<u2"), 4: np.dtype("<u4"), 8: np.dtype("<u8")}

# A run's signature: (type, has target, ((field, kind), ...)).
_Signature = tuple[str, bool, tuple[tuple[str, str], ...]]


class _BadRecordError(Exception):
    """A malformed item; the reader adds the file, line and field."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(message)
        self.field = field
        self.message = message


# --- bytes ------------------------------------------------------------------------------------

def _shuffle(a: np.ndarray) -> bytes:
    # Byte-transposed, as blosc does: the sign/exponent bytes of floats and the high bytes of ints
    # end up together, which deflate compresses far better than interleaved.
    a = np.ascontiguousarray(a)
    return a.view(np.uint8).reshape(a.size, a.itemsize).T.tobytes()


def _unshuffle(raw: bytes, dtype: np.dtype, n: int) -> np.ndarray:
    if len(raw) != n * dtype.itemsize:
        raise ValueError(f"{len(raw)} bytes for {n} elements of {dtype.name}")
    return np.frombuffer(raw, np.uint8).reshape(dtype.itemsize, n).T.copy().view(dtype).reshape(n)


def _delta(a: np.ndarray) -> np.ndarray:
    """8-byte columns: each element's bits minus the previous element's (wrapping), zigzagged so
    that small steps either way have zero high bytes. Neighbouring beams differ far less than the
    ranges do, and for ints, counters and constant columns become zeros."""
    if a.itemsize != 8:
        return a
    u = np.ascontiguousarray(a).view("<u8")
    d = u.copy()
    d[1:] -= u[:-1]
    return (d << np.uint64(1)) ^ (d.view("<i8") >> np.int64(63)).view("<u8")


def _undelta(z: np.ndarray, dtype: np.dtype) -> np.ndarray:
    if dtype.itemsize != 8:
        return z.view(dtype)
    d = (z >> np.uint64(1)) ^ (np.uint64(0) - (z & np.uint64(1)))
    return np.cumsum(d, dtype="<u8").view(dtype)


# Base85 as Python's base64.b85encode (RFC 1924 alphabet: no '"' or '\\', so JSON keeps it as is):
# 5 characters per 4 bytes where base64 needs 5.33, and the columns are mostly noise that does
# not compress. Vectorised, as the standard library's is ~100 times slower than base64.
_B85 = np.frombuffer(b"0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz!#$%&()*+-;<=>?@^_`{|}~", np.uint8)
_B85_VALUE = np.full(256, 255, np.uint8)
_B85_VALUE[_B85] = np.arange(85, dtype=np.uint8)
_POW85 = np.array([85**4, 85**3, 85**2, 85, 1], np.uint64)


def _b85encode(data: bytes) -> str:
    pad = -len(data) % 4
    words = np.frombuffer(data + b"\0" * pad, ">u4").astype(np.uint64)
    digits = (words[:, None] // _POW85) % np.uint64(85)
    out = _B85[digits.astype(np.intp)].tobytes()
    return (out[: len(out) - pad] if pad else out).decode("ascii")


def _b85decode(text: str) -> bytes:
    raw = text.encode("ascii")
    pad = -len(raw) % 5
    codes = np.frombuffer(raw + b"~" * pad, np.uint8)
    values = _B85_VALUE[codes]
    if (values == 255).any():
        bad = int(np.flatnonzero(values == 255)[0])
        raise ValueError(f"bad base85 character at position {bad}")
    words = values.reshape(-1, 5).astype(np.uint64) @ _POW85
    if (words > 0xFFFFFFFF).any():
        raise ValueError("base85 overflow")
    out = words.astype(">u4").tobytes()
    return out[: len(out) - pad] if pad else out


def _deflate(data: bytes, zdict: bytes = b"", planes: int = 1) -> str:
    """zlib, then base85. Shuffled data (``planes`` bytes an element) may go in one deflate block
    per byte plane, each with its own Huffman code: noise beside near-constant bytes. Any zlib
    reader inflates either form.

    Up to SMALL_DEFLATE bytes (a few robots' scans, a blob's change) both forms are made at level
    9 and the smaller kept; above it (a crowd's scans), one form at zlib's default level, which
    on 100 robots' scans took a fifth of the time for a record 1 % larger."""
    def compressor(level: int) -> Any:
        return zlib.compressobj(level, zdict=zdict) if zdict else zlib.compressobj(level)

    if len(data) > SMALL_DEFLATE:
        c = compressor(6)
        return _b85encode(_planes_stream(c, data, planes) if _splits(data, planes) else c.compress(data) + c.flush())
    if not zdict and planes == 1:
        return _b85encode(zlib.compress(data, 9))  # starts up faster than a compressobj
    whole = compressor(9)
    best = whole.compress(data) + whole.flush()
    if _splits(data, planes):
        split = _planes_stream(compressor(9), data, planes)
        best = split if len(split) < len(best) else best
    return _b85encode(best)


def _splits(data: bytes, planes: int) -> bool:
    return planes > 1 and len(data) % planes == 0 and len(data) >= 64 * planes


def _planes_stream(c: Any, data: bytes, planes: int) -> bytes:
    n = len(data) // planes
    head = b"".join(c.compress(data[k * n:(k + 1) * n]) + c.flush(zlib.Z_BLOCK) for k in range(planes - 1))
    return head + c.compress(data[(planes - 1) * n:]) + c.flush()


def _inflate(text: str, limit: int, zdict: bytes = b"") -> bytes:
    """Base85, then zlib: at most `limit` bytes, what the entry's declared size holds. Inflated to
    one byte past it and no further, so that a small entry that inflates to gigabytes (a zlib bomb)
    costs `limit` bytes and is refused."""
    d = zlib.decompressobj(zdict=zdict) if zdict else zlib.decompressobj()
    out = d.decompress(_b85decode(text), limit + 1)  # (a max_length of 0 would mean no limit)
    if len(out) > limit or d.unconsumed_tail:
        raise ValueError(f"inflates to more than the {limit} bytes its size declares")
    if not d.eof or d.unused_data:
        raise ValueError("truncated or trailing compressed data")
    return out


# --- blobs ------------------------------------------------------------------------------------

def _change_entry(base_name: str, where: np.ndarray, values: np.ndarray) -> dict[str, Any]:
    gaps = where.astype("<i8")  # a copy
    gaps[1:] -= where[:-1]
    return {"base": base_name, "zlib_base85": _deflate(_shuffle(gaps) + _shuffle(values))}


def encode_blob(blob: _core.Blob, base: _core.Blob | None = None, base_name: str = "") -> dict[str, Any]:
    """A blob's record entry: whole, or the change from `base` (named `base_name`) when given and
    of the same dtype and shape."""
    if base is not None and base.dtype == blob.dtype and tuple(base.shape) == tuple(blob.shape):
        return _change_entry(base_name, *blob.changes_from(base))
    return {"dtype": blob.dtype, "shape": list(blob.shape), "zlib_base85": _deflate(np.asarray(blob).tobytes())}


def blob_layout(d: Any, known: dict[str, tuple[np.dtype, tuple[int, ...]]]) -> tuple[np.dtype, tuple[int, ...]]:
    """The dtype and shape of a record's blob entry, checked before anything is decoded: a whole
    blob of a dtype a Blob holds and a shape of at most MAX_BLOB_ELEMENTS elements, or a change
    from a blob in `known` (dtype and shape by name). ValueError says what is wrong."""
    if not isinstance(d, dict) or not isinstance(d.get("zlib_base85"), str):
        raise ValueError('expected {"dtype": ..., "shape": [...], "zlib_base85": ...} or {"base": NAME, '
                         '"zlib_base85": ...}')
    if "base" in d:
        if set(d) != {"base", "zlib_base85"}:
            raise ValueError(f"a change has the keys base and zlib_base85; found {', '.join(map(str, d))}")
        if not isinstance(d["base"], str) or d["base"] not in known:
            raise ValueError(f"base blob {d['base']} was not written before it")
        return known[d["base"]]
    if set(d) != {"dtype", "shape", "zlib_base85"}:
        raise ValueError(f"a whole blob has the keys dtype, shape and zlib_base85; found {', '.join(map(str, d))}")
    if d["dtype"] not in _BLOB_DTYPES:
        raise ValueError(f"dtype {d['dtype']!r}: expected one of {', '.join(_BLOB_DTYPES)}")
    shape = d["shape"]
    if (not isinstance(shape, list) or not 1 <= len(shape) <= 4
            or not all(type(s) is int and 0 <= s <= MAX_BLOB_ELEMENTS for s in shape)):
        raise ValueError(f"shape {shape!r}: expected 1 to 4 sizes, each an int >= 0")
    if math.prod(shape) > MAX_BLOB_ELEMENTS:
        raise ValueError(f"shape {shape}: {math.prod(shape):,} elements, more than the {MAX_BLOB_ELEMENTS:,} "
                         "a record's blob may have")
    return np.dtype(d["dtype"]), tuple(shape)


def decode_blob(d: dict[str, Any], blobs: dict[str, _core.Blob] | None = None) -> _core.Blob:
    """The blob of a record entry; `blobs` (by name) holds the bases of changes. Checked first
    (blob_layout), and inflated no further than its dtype and shape hold."""
    blobs = blobs or {}
    base = blobs.get(d["base"]) if isinstance(d, dict) and isinstance(d.get("base"), str) else None
    known = {d["base"]: (np.dtype(base.dtype), tuple(base.shape))} if base is not None else {}
    dtype, shape = blob_layout(d, known)
    if "base" not in d:
        raw = _inflate(d["zlib_base85"], math.prod(shape) * dtype.itemsize)
        return _core.Blob(np.frombuffer(raw, dtype=dtype).reshape(shape))
    a = np.ascontiguousarray(np.asarray(blobs[d["base"]]))
    u = _UNSIGNED[a.itemsize]
    raw = _inflate(d["zlib_base85"], a.size * (8 + a.itemsize))  # at most every element changed
    k, rest = divmod(len(raw), 8 + a.itemsize)
    if rest:
        raise ValueError(f"{len(raw)} bytes are not whole changes of {a.itemsize}-byte elements")
    where = np.cumsum(_unshuffle(raw[: 8 * k], np.dtype("<i8"), k))
    values = a.view(u).ravel().copy()
    if k and (where[0] < 0 or where[-1] >= values.size or (k > 1 and np.diff(where).min() <= 0)):
        raise ValueError("changed positions out of order or outside the blob")
    values[where] ^= _unshuffle(raw[8 * k:], u, k)
    return _core.Blob(values.view(a.dtype).reshape(a.shape))


class _BlobWriter:
    """Chooses the base of each new blob. First the blob that the same slot of the string held
    the frame before (a robot's own map a frame ago), when the change from it is under half the
    blob; otherwise, of the last BASE_CANDIDATES written blobs with its dtype and shape, the one
    with the fewest different elements (the latest on a tie)."""

    def __init__(self) -> None:
        self._recent: dict[tuple[str, tuple[int, ...]], deque[tuple[str, _core.Blob]]] = {}

    def encode(self, name: str, blob: _core.Blob, parent: tuple[str, _core.Blob] | None = None) -> dict[str, Any]:
        """The entry of a blob not written before; `parent` is what its slot held the frame before,
        by name, if that is known."""
        key = (blob.dtype, tuple(blob.shape))
        recent = self._recent.setdefault(key, deque(maxlen=BASE_CANDIDATES))
        # Changes cost 8 bytes of position and the element each (before deflate): only worth it
        # while they are under half the whole blob. Each candidate after the best so far must beat
        # it, so changes_from stops counting as soon as it cannot.
        limit = (blob.nbytes // 2 - 1) // (8 + np.dtype(blob.dtype).itemsize)
        best: tuple[str, tuple[np.ndarray, np.ndarray]] | None = None
        if limit >= 0 and parent is not None and parent[1].dtype == blob.dtype and tuple(parent[1].shape) == key[1]:
            changes = blob.changes_from(parent[1], limit)
            if changes is not None:
                best = (parent[0], changes)
        for base_name, base in reversed(recent) if best is None else ():
            if limit < 0:
                break
            changes = blob.changes_from(base, limit)
            if changes is not None:
                best = (base_name, changes)
                limit = len(changes[0]) - 1
        recent.append((name, blob))
        if best is not None:
            return _change_entry(best[0], *best[1])
        return encode_blob(blob)


# --- events -----------------------------------------------------------------------------------

def _value_text(kind: str, values: list[Any]) -> list[str]:
    # As the engine writes values: repr(float) is its real format (shortest round trip).
    if kind == "f":
        return list(map(repr, values))
    if kind == "b":
        return ["true" if v else "false" for v in values]
    return list(map(str, values))


def _run_texts(sig: _Signature, targets: list[int] | None, columns: list[list[Any]], n: int) -> list[str]:
    type_, _, fields = sig
    parts: list[list[str]] = []
    names: list[str] = []
    if targets is not None:
        parts.append(list(map(str, targets)))
        names.append("to=")
    for (name, kind), col in zip(fields, columns, strict=True):
        parts.append(_value_text(kind, col))
        names.append(name + "=")
    if not parts:
        return [type_] * n
    template = type_.replace("%", "%%") + "<" + ", ".join(s.replace("%", "%%") + "%s" for s in names) + ">"
    return [template % row for row in zip(*parts, strict=True)]


class _Columns:
    """The latest step-2 bytes of every column, by run signature, occurrence of the signature in
    its frame, and field ("to=" for the targets): the next frame's dictionaries. The writer and
    the reader go through the same states."""

    def __init__(self) -> None:
        self._prev: dict[tuple[_Signature, int, str], bytes] = {}
        self._next: dict[tuple[_Signature, int, str], bytes] = {}
        self._seen: dict[_Signature, int] = {}

    def start_frame(self) -> None:
        self._prev.update(self._next)
        self._next = {}
        self._seen = {}

    def occurrence(self, sig: _Signature) -> int:
        j = self._seen.get(sig, 0)
        self._seen[sig] = j + 1
        return j

    def encode(self, key: tuple[_Signature, int, str], a: np.ndarray) -> str:
        raw = _shuffle(_delta(a))
        self._next[key] = raw
        return _deflate(raw, self._prev.get(key, b""), a.itemsize)

    def decode(self, key: tuple[_Signature, int, str], text: str, dtype: np.dtype, n: int) -> np.ndarray:
        raw = _inflate(text, n * dtype.itemsize, self._prev.get(key, b""))
        self._next[key] = raw
        return _undelta(_unshuffle(raw, np.dtype("<u8") if dtype.itemsize == 8 else dtype, n), dtype)


# A run as FrameRecord.event_runs gives it: (type, n, targets or None, [(field, kind, column), ...]).
_Run = tuple[str, int, "np.ndarray | None", list[tuple[str, str, np.ndarray]]]


def _encode_events(columns: _Columns, items: Sequence[str | _Run]) -> list[Any]:
    """A frame's events as the record stores them, from FrameRecord.event_runs(MIN_RUN): the
    texts as they are, each run by its columns."""
    columns.start_frame()
    out: list[Any] = []
    for entry in items:
        if isinstance(entry, str):
            out.append(entry)
            continue
        type_, n, targets, fields = entry
        sig: _Signature = (type_, targets is not None, tuple((name, kind) for name, kind, _ in fields))
        k = columns.occurrence(sig)
        item: dict[str, Any] = {"run": type_, "n": n}
        if targets is not None:
            item["to"] = columns.encode((sig, k, "to="), targets)
        if fields:
            item["fields"] = {name: [kind, columns.encode((sig, k, name), col)] for name, kind, col in fields}
        out.append(item)
    return out


def _check_events(items: list[Any]) -> None:
    """A frame's ``events`` as the record stores them, checked before any column is inflated:
    texts and runs of the documented shape, at most MAX_FRAME_EVENTS events in all."""
    total = 0
    for index, item in enumerate(items):
        if isinstance(item, str):
            total += 1
            continue
        where = f"events[{index}]"
        if not isinstance(item, dict) or not isinstance(item.get("run"), str) or not item["run"]:
            raise _BadRecordError(where, "expected an event's text or a run {\"run\": TYPE, \"n\": N, ...}")
        if not set(item) <= {"run", "n", "to", "fields"}:
            raise _BadRecordError(where, f"unknown keys {', '.join(sorted(set(item) - {'run', 'n', 'to', 'fields'}))} "
                                  "(a run has run, n, to and fields)")
        n = item.get("n")
        if type(n) is not int or not 1 <= n <= MAX_FRAME_EVENTS:
            raise _BadRecordError(f"{where}.n", f"missing or not an int from 1 to {MAX_FRAME_EVENTS:,}")
        fields = item.get("fields", {})
        if not isinstance(fields, dict) or not all(
                isinstance(v, list) and len(v) == 2 and isinstance(v[0], str) and v[0] in _DTYPE_OF
                and isinstance(v[1], str) for v in fields.values()):
            raise _BadRecordError(f"{where}.fields", "expected {name: [\"i\" | \"f\" | \"b\", column], ...}")
        if "to" in item and not isinstance(item["to"], str):
            raise _BadRecordError(f"{where}.to", "expected a column")
        total += n
    if total > MAX_FRAME_EVENTS:
        raise _BadRecordError("events", f"{total:,} events, more than the {MAX_FRAME_EVENTS:,} a frame may have")


def _decode_events(columns: _Columns, items: list[Any]) -> list[str]:
    """The texts of a frame's events (checked by _check_events), runs expanded."""
    _check_events(items)
    columns.start_frame()
    texts: list[str] = []
    for index, item in enumerate(items):
        if isinstance(item, str):
            texts.append(item)
            continue
        n = item["n"]
        fields = item.get("fields", {})
        sig: _Signature = (item["run"], "to" in item, tuple((name, v[0]) for name, v in fields.items()))
        k = columns.occurrence(sig)
        try:
            targets = columns.decode((sig, k, "to="), item["to"], _DTYPE_OF["i"], n).tolist() if sig[1] else None
            cols = [columns.decode((sig, k, name), v[1], _DTYPE_OF[v[0]], n).tolist() for name, v in fields.items()]
        except (ValueError, zlib.error) as e:
            raise _BadRecordError(f"events[{index}]", f"cannot decode the run's columns: {e}") from None
        texts.extend(_run_texts(sig, targets, cols, n))
    return texts


# --- writing ----------------------------------------------------------------------------------

class Recorder:
    """Records an engine's frames to `path` from now on (flushed every frame, so a crash loses
    nothing that completed). Use as a context manager, or call close() to write the end line."""

    def __init__(self, path: str | Path, engine: _core.Engine, *, world_file: str | Path | None = None,
                 world_data: dict[str, Any] | None = None, world_kind: str | None = None,
                 frames_planned: int | None = None, key: bytes | None = None) -> None:
        self.path = Path(path)
        self._chain = Chain(key)
        self._file: IO[str] | None = None
        self._engine = engine
        self._blobs = _BlobWriter()
        self._columns = _Columns()
        initial = engine.string
        self._known = set(initial.blobs())
        self._slots = initial.blob_slots()  # the names of the blobs the string held, slot by slot
        self._slot_blobs = initial.blobs()  # and the blobs by name
        # A frame's line holds the string at its start: the previous frame's result, kept as text
        # (its blobs were written with that frame, while they had that content).
        self._before_text = str(initial)
        self._prev: str | None = None  # the hash of the last line written (the chain)
        header = {
            "vwg_record": FORMAT,
            "version": _core.__version__,
            "chain": self._chain.name,
            "world_file": str(Path(world_file).resolve()) if world_file else None,
            "world": world_data,
            "world_kind": world_kind,
            "seed": engine.seed,
            "dt": engine.dt,
            "frame": engine.frame,
            "frames_planned": frames_planned,
            "initial": str(initial),
            "blobs": {name: self._blobs.encode(name, b) for name, b in initial.blobs().items()},
        }
        try:
            _dumps(header).encode("utf-8")
        except UnicodeEncodeError:  # a name of bytes that are not UTF-8 (w\xff.yaml): JSON holds text only
            raise Error(f"{world_file}: the name is not UTF-8 text, and a record (JSON) holds its world file's name "
                        "as text: rename the file, or run without --record") from None
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file = self.path.open("w", encoding="utf-8")
        self._write(header)
        self.frames = 0
        engine.add_observer(self._on_frame)

    def _write(self, obj: dict[str, Any], *, last: bool = False) -> None:
        if self._file is None:
            return
        if self._prev is not None:
            obj["prev"] = self._prev
        text = _dumps(obj)
        if last:  # no line comes after the end line to hold its link: it holds its own
            obj["self"] = self._chain.link(text.encode("utf-8"))
            text = _dumps(obj)
        self._file.write(text + "\n")
        self._file.flush()
        self._prev = self._chain.link(text.encode("utf-8"))

    def _on_frame(self, record: _core.FrameRecord) -> None:
        if self._file is None:
            return
        events = _encode_events(self._columns, record.event_runs(MIN_RUN))
        line: dict[str, Any] = {"t": record.frame, "time": record.time, "events": events,
                                "string": self._before_text}
        blobs = record.blobs
        slots = record.after.blob_slots()
        # What each slot held the frame before: a changed blob's likely base (its own past self).
        parents = {n: (p, self._slot_blobs[p]) for n, p in zip(slots, self._slots, strict=False)
                   if n != p and p in self._slot_blobs}
        fresh = {n: b for n, b in blobs.items() if n not in self._known}
        if fresh:
            line["blobs"] = {n: self._blobs.encode(n, b, parents.get(n)) for n, b in fresh.items()}
            self._known.update(fresh)
        self._slots = slots
        self._slot_blobs = {n: blobs[n] for n in slots}
        self._before_text = record.after_text
        self._write(line)
        self.frames += 1

    def abandon(self) -> None:
        """Close the file without writing more: a write failed (a full disk), and a close would flush
        and fail the same way. The record keeps the lines before, without its end line."""
        file, self._file = self._file, None
        if file is not None:
            with contextlib.suppress(OSError):
                file.close()

    def close(self, faults: Sequence[Mapping[str, Any]] = ()) -> None:
        """Write the end line, with the run's `faults` (a real robot's, as Fault.to_json gives them:
        time_s, robot, what), and close the file."""
        if self._file is None:
            return
        # A fault's text cut to what a reader takes (an error's message can be long).
        kept = [{**f, "what": clip(str(f["what"]), MAX_FAULT_TEXT)} for f in faults]
        self._write({"end": True, "t": self._engine.frame, "string": str(self._engine.string), "frames": self.frames,
                     "faults": kept}, last=True)
        self._file.close()
        self._file = None

    def __enter__(self) -> Recorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


# --- reading ----------------------------------------------------------------------------------

def _dumps(obj: dict[str, Any]) -> str:
    """A line's text as the writer makes it (and the end line's check remakes it)."""
    return json.dumps(obj, ensure_ascii=False, allow_nan=False, separators=(",", ":"))


class Chain:
    """How a line is linked to the one before it: the first 32 hex digits of its SHA-256, or of
    its HMAC-SHA-256 with `key` (then only the key's holder can make a record that reads whole)."""

    def __init__(self, key: bytes | None = None) -> None:
        if key is not None and not key:  # an HMAC with no key is no secret: it would only look keyed
            raise Error("a record key is empty")
        self.key = key
        self.name = "hmac-sha256" if key is not None else "sha256"

    def link(self, data: bytes) -> str:
        if self.key is None:
            return hashlib.sha256(data).hexdigest()[:32]
        return hmac.new(self.key, data, hashlib.sha256).hexdigest()[:32]


MIN_KEY_BYTES = 16


def read_key(path: str | Path) -> bytes:
    """A record key file's bytes, as they are (at least MIN_KEY_BYTES; `head -c 32 /dev/urandom`)."""

    key = read_bytes(path, 64 * 1024)
    if len(key) < MIN_KEY_BYTES:
        raise WorldFileError(str(path), "", f"a record key has at least {MIN_KEY_BYTES} bytes; this file has "
                             f"{len(key)} (make one with: head -c 32 /dev/urandom > {path})")
    return key


@dataclass
class Record:
    """A record as read: the header, each frame's line with ``events`` as the events' texts (runs
    expanded, in order), the end line (None if the run was cut before it ended), every blob by
    name, and warnings (a last line cut short, skipped)."""

    header: dict[str, Any]
    frames: list[dict[str, Any]]
    end: dict[str, Any] | None
    blobs: dict[str, _core.Blob]
    warnings: list[str]

    @property
    def faults(self) -> list[dict[str, Any]]:
        """A real robot's faults in the run (time_s, robot, what), from the end line; [] without one."""
        return list(self.end["faults"]) if self.end is not None else []

    @property
    def cut(self) -> str:
        """Why the record is incomplete ("" when it ended with its end line)."""
        if self.end is not None:
            return ""
        planned = self.header.get("frames_planned")
        held = f"{len(self.frames)} frames" + (f" of the {planned} planned" if isinstance(planned, int) else "")
        return f"the record has no end line: the run was cut after {held} (killed, or the machine stopped)"


def _finite(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"the number {text} is out of range (a record's numbers are finite doubles)")
    return value


def _constant(name: str) -> Any:
    raise ValueError(f"{name} is not a number a record holds (JSON has no {name})")


def _too_deep(obj: Any, limit: int) -> bool:
    """Whether lists and objects nest more than `limit` deep in `obj` (without recursion)."""
    stack = [(obj, 1)]
    while stack:
        item, depth = stack.pop()
        if depth > limit:
            return True
        children = item.values() if isinstance(item, dict) else item
        stack.extend((c, depth + 1) for c in children if isinstance(c, (dict, list)))
    return False


def _parse(path: Path, n: int, raw: bytes) -> dict[str, Any]:
    """One line's JSON object; a WorldFileError names the line and what is wrong."""
    try:
        obj = json.loads(raw.decode("utf-8"), parse_float=_finite, parse_constant=_constant)
    except UnicodeDecodeError as e:
        raise WorldFileError(str(path), f"byte {e.start + 1}", "not UTF-8 text", line=n) from None
    except json.JSONDecodeError as e:
        raise WorldFileError(str(path), f"column {e.colno}", f"not valid JSON: {e.msg}", line=n) from None
    except RecursionError:
        raise WorldFileError(str(path), "", f"lists or objects nested deeper than the {MAX_JSON_DEPTH} levels a "
                             "record's line may have", line=n) from None
    except ValueError as e:  # a number out of range, an integer of thousands of digits
        raise WorldFileError(str(path), "", f"not valid JSON: {e}", line=n) from None
    if not isinstance(obj, dict):
        raise WorldFileError(str(path), "", "expected a JSON object on each line", line=n)
    # Counting brackets bounds the depth from above: most lines need no walk.
    if raw.count(b"[") + raw.count(b"{") > MAX_JSON_DEPTH and _too_deep(obj, MAX_JSON_DEPTH):
        raise WorldFileError(str(path), "", f"lists or objects nested deeper than the {MAX_JSON_DEPTH} levels a "
                             "record's line may have", line=n)
    return obj


def _check_format(path: Path, obj: dict[str, Any], line: int) -> None:
    found = obj.get("vwg_record")
    if found == FORMAT and type(found) is int:
        return
    if type(found) is int:
        raise WorldFileError(str(path), "vwg_record", f"this record is format {found}; this vwg reads format "
                             f"{FORMAT} only (record the run again)", line=line)
    raise WorldFileError(str(path), "vwg_record", f"not a vwg record (format {FORMAT} expected)", line=line)


def _is_int(value: Any, low: int, high: int) -> bool:
    return type(value) is int and low <= value <= high


def _check_header(path: Path, obj: dict[str, Any]) -> None:
    """The header's fields, each of the type and range the engine takes (line 1)."""

    _check_format(path, obj, 1)

    def bad(field: str, message: str) -> WorldFileError:
        return WorldFileError(str(path), field, message, line=1)

    known = ("vwg_record", "version", "chain", "world_file", "world", "world_kind", "seed", "dt", "frame",
             "frames_planned", "initial", "blobs")
    for key in obj:
        if key not in known:
            raise bad(key, f"not a field of a record's header (the header has {', '.join(known)})")
    for key in ("initial", "seed", "dt", "chain"):
        if key not in obj:
            raise bad(key, "missing from the header")
    if obj["chain"] not in ("sha256", "hmac-sha256"):
        raise bad("chain", f"expected \"sha256\" or \"hmac-sha256\", got {obj['chain']!r}")
    if not _is_int(obj["seed"], 0, 2**64 - 1):
        raise bad("seed", f"expected an integer from 0 to 2**64 - 1, got {obj['seed']!r}")
    dt = obj["dt"]  # the bounds a run takes (vwg.launch), so a record replays only what a run could make
    ok = type(dt) in (int, float)
    if ok:
        try:  # the engine's range and check (vwg::check_dt); a JSON integer may be beyond a float's range
            _core.check_dt(float(dt), "dt")
        except (SchemaError, OverflowError):
            ok = False
    if not ok:
        raise bad("dt", f"expected a number of seconds from {MIN_DT:g} to {MAX_DT:g}, got {dt!r}")
    if not _is_int(obj.get("frame", 0), 0, 2**62):
        raise bad("frame", f"expected a frame number from 0 to 2**62, got {obj['frame']!r}")
    if obj.get("frames_planned") is not None and not _is_int(obj["frames_planned"], 0, 2**62):
        raise bad("frames_planned", f"expected a number of frames >= 0, or null, got {obj['frames_planned']!r}")
    # initial and blobs are what the replay starts from: never null; the others may be (a world run
    # from Python has no file).
    for key, kind, nullable in (("initial", str, False), ("blobs", dict, False), ("version", str, True),
                                ("world_file", str, True), ("world_kind", str, True), ("world", dict, True)):
        if key in obj and not isinstance(obj[key], kind) and not (nullable and obj[key] is None):
            found = "null" if obj[key] is None else type(obj[key]).__name__
            raise bad(key, f"expected {'an object' if kind is dict else 'a string'}{' or null' if nullable else ''}, "
                      f"got {found}")
    kind_name = obj.get("world_kind")
    if kind_name is not None and kind_name not in world_kinds:
        raise bad("world_kind", f"unknown world kind {kind_name!r} (this vwg knows {', '.join(world_kinds)})")


def _check_frame(path: Path, n: int, obj: dict[str, Any], t: int) -> None:
    """A frame's line, before anything in it is inflated: its fields, and t the frame after the line before."""
    known = ("t", "time", "events", "string", "blobs", "prev")
    for key in obj:
        if key not in known:
            raise WorldFileError(str(path), key, f"not a field of a frame's line (it has {', '.join(known)})", line=n)
    for key, kind in (("t", int), ("events", list), ("string", str)):
        if not isinstance(obj.get(key), kind) or isinstance(obj.get(key), bool):
            raise WorldFileError(str(path), key, f"missing or not a {kind.__name__}", line=n)
    if obj["t"] != t:
        raise WorldFileError(str(path), "t", f"frame {obj['t']}; the line before holds frame {t - 1}, so this "
                             f"line holds frame {t}", line=n)
    if type(obj.get("time")) not in (int, float):
        raise WorldFileError(str(path), "time", "missing or not a number", line=n)
    if not isinstance(obj.get("blobs", {}), dict):
        raise WorldFileError(str(path), "blobs", "expected an object {name: blob}", line=n)
    try:
        _check_events(obj["events"])
    except _BadRecordError as e:
        raise WorldFileError(str(path), e.field, e.message, line=n) from None


_END_KEYS = ["end", "t", "string", "frames", "faults", "prev", "self"]
_FAULT_KEYS = ["time_s", "robot", "what"]
MAX_ROBOT_ID = 2**31 - 1  # the engine's robot ids are 32-bit (0: the link)
MAX_FAULT_TEXT = 4096  # characters of a fault's "what" (the writer cuts a longer one)


def _fault_error(fault: Any) -> str:
    """What is wrong with one of the end line's faults ("" if nothing): each field of the type and
    range a run writes, so printing it cannot fail."""
    if not isinstance(fault, dict) or list(fault) != _FAULT_KEYS:
        return f"expected {{\"time_s\": seconds, \"robot\": id, \"what\": text}}, got {_clip(fault)}"
    time_s, robot, what = fault["time_s"], fault["robot"], fault["what"]
    if type(time_s) not in (int, float) or not 0 <= time_s <= MAX_TIME:
        return f"time_s: expected seconds from 0 to {MAX_TIME:g}, got {_clip(time_s)}"
    if not _is_int(robot, 0, MAX_ROBOT_ID):
        return f"robot: expected a robot id from 0 (the link) to {MAX_ROBOT_ID}, got {_clip(robot)}"
    if not isinstance(what, str) or len(what) > MAX_FAULT_TEXT:
        return f"what: expected a text of at most {MAX_FAULT_TEXT} characters, got " + \
            (f"{len(what)} characters" if isinstance(what, str) else _clip(what))
    return ""


def _clip(value: Any) -> str:
    """A value from a record, for an error: its repr cut to 60 characters (a 400-digit number)."""

    return clip(repr(value), 60)


def _check_end(path: Path, n: int, obj: dict[str, Any], raw: bytes, chain: Chain, frames: int, t: int) -> None:
    """The end line, whole: nothing comes after it to hold its link, so it holds its own (``self``,
    the link of its text without ``self``), and its fields must agree with the frames before it."""
    if list(obj) != _END_KEYS:
        raise WorldFileError(str(path), "", f"the end line has the fields {', '.join(_END_KEYS)} in that order; "
                             f"this one has {', '.join(obj)}", line=n)
    if obj["end"] is not True or not isinstance(obj["string"], str):
        raise WorldFileError(str(path), "end", "expected \"end\": true and a string", line=n)
    if obj["frames"] != frames or type(obj["frames"]) is not int:
        raise WorldFileError(str(path), "frames", f"the end line counts {obj['frames']!r} frames; the record "
                             f"holds {frames}", line=n)
    faults = obj["faults"]
    if not isinstance(faults, list):
        raise WorldFileError(str(path), "faults", "expected a list of {\"time_s\": seconds, \"robot\": id, \"what\": "
                             "text}", line=n)
    for i, fault in enumerate(faults):
        if why := _fault_error(fault):
            raise WorldFileError(str(path), f"faults[{i}]", why, line=n)
    if obj["t"] != t or type(obj["t"]) is not int:
        raise WorldFileError(str(path), "t", f"the end line says the run ended at frame {obj['t']!r}; its frames "
                             f"end at frame {t}", line=n)
    body = {k: v for k, v in obj.items() if k != "self"}
    if raw != _dumps(obj).encode("utf-8") or obj["self"] != chain.link(_dumps(body).encode("utf-8")):
        raise WorldFileError(str(path), "self", "the end line does not match the link it holds of itself: it was "
                             "changed after it was written", line=n)


class _Lines:
    """Pass 1 over a record's bytes: every line parsed and checked (the chain, each line's fields,
    each blob's layout and size) before anything is inflated; a last line cut short (no newline,
    not JSON) is skipped with a warning."""

    def __init__(self, path: Path, data: bytes, key: bytes | None) -> None:
        self.path = path
        self.warnings: list[str] = []
        self.header: dict[str, Any] = {}
        self.frames: list[tuple[int, dict[str, Any]]] = []
        self.end: dict[str, Any] | None = None
        pieces = data.split(b"\n")
        torn = pieces.pop()  # what follows the last newline: b"" when the file ends with one
        if torn:
            pieces.append(torn)
        layouts: dict[str, tuple[np.dtype, tuple[int, ...]]] = {}
        chain = Chain(key)
        before: tuple[int, bytes, dict[str, Any]] | None = None  # the line before: number, bytes, object
        offset = 0  # where line n starts in the file
        for n, raw in enumerate(pieces, start=1):
            last_torn = bool(torn) and n == len(pieces)
            if self.end is not None:
                extra = len(data) - offset
                raise WorldFileError(str(path), "", f"{extra} byte{'s' if extra != 1 else ''} after the end line (line "
                                     f"{n - 1}): a record ends with its end line (it was appended to or damaged)",
                                     line=n)
            offset += len(raw) + 1
            if not raw.strip() and not last_torn:
                raise WorldFileError(str(path), "", "a blank line: every line of a record is part of its chain and "
                                     "the writer writes none (the record was edited or damaged)", line=n)
            try:
                obj = _parse(path, n, raw)
            except WorldFileError:
                if not last_torn:
                    raise
                self.warnings.append(f"{path}:{n}: the last line is cut short ({len(raw)} bytes; the run was stopped "
                                     "while writing it): skipped")
                break
            if before is None:
                _check_header(path, obj)
                chain = self._chain(obj, key)
                self.header = obj
            else:
                if obj.get("prev") != chain.link(before[1]):
                    what = "the header" if before[0] == 1 else f"frame {before[2].get('t')}'s line"
                    raise WorldFileError(str(path), "prev", f"the chain is broken here: {what} (line {before[0]}) "
                                         "does not match the link this line holds of it: a line was changed, dropped, "
                                         "added or moved" + (" (or the key is not the one it was made with)"
                                                             if key else ""), line=n)
                t = self.header.get("frame", 0) + len(self.frames)
                if "end" in obj:
                    _check_end(path, n, obj, raw, chain, len(self.frames), t)
                    self.end = obj
                else:
                    _check_frame(path, n, obj, t)
                    self.frames.append((n, obj))
            for name, d in obj.get("blobs", {}).items():
                if name in layouts:
                    raise WorldFileError(str(path), f"blobs.{name}", "given twice (a blob is written once)", line=n)
                try:
                    layouts[name] = blob_layout(d, layouts)
                except ValueError as e:
                    raise WorldFileError(str(path), f"blobs.{name}", str(e), line=n) from None
            before = (n, raw, obj)
        if before is None:
            raise WorldFileError(str(path), "", "empty record")

    def _chain(self, header: dict[str, Any], key: bytes | None) -> Chain:
        keyed = header["chain"] == "hmac-sha256"
        if keyed and key is None:
            raise WorldFileError(str(self.path), "chain", "the record's chain is keyed (hmac-sha256): give its key "
                                 "(--record-key FILE) to read it", line=1)
        if key is not None and not keyed:
            raise WorldFileError(str(self.path), "chain", "a key was given, but this record's chain is not keyed "
                                 "(sha256): it was not made with that key", line=1)
        return Chain(key)


def _read_blobs(path: Path, obj: dict[str, Any], line: int, blobs: dict[str, _core.Blob]) -> None:
    for name, d in obj.get("blobs", {}).items():
        try:
            blob = decode_blob(d, blobs)
        except Exception as e:
            raise WorldFileError(str(path), f"blobs.{name}", f"cannot decode: {e}", line=line) from None
        if blob.name != name:
            raise WorldFileError(str(path), f"blobs.{name}", f"decodes to blob {blob.name}, not {name} "
                                 "(the record is damaged)", line=line)
        blobs[name] = blob


def read_record(path: str | Path, key: bytes | None = None) -> Record:
    """Read and check a record file: first every line against the chain (keyed with `key`, if the
    record was made with one) and its layout, then its blobs and events, each inflated no further
    than its declared size."""

    path = Path(path)
    lines = _Lines(path, read_bytes(path, MAX_RECORD_BYTES), key)
    blobs: dict[str, _core.Blob] = {}
    columns = _Columns()
    _read_blobs(path, lines.header, 1, blobs)
    frames = []
    for n, obj in lines.frames:
        try:
            obj["events"] = _decode_events(columns, obj["events"])
        except _BadRecordError as e:
            raise WorldFileError(str(path), e.field, e.message, line=n) from None
        _read_blobs(path, obj, n, blobs)
        frames.append(obj)
    return Record(lines.header, frames, lines.end, blobs, lines.warnings)


def robot_data(header: dict[str, Any], path: Path) -> dict[str, Any]:
    """What a robot world's record keeps of its run (line 1's ``world``), each field checked:
    robot_world (the world file) and planner (a registered one), and optionally world_orders (default
    true), goals (the run's --goal orders, [ROBOT:]ROOM, default none; their rooms are checked
    against the world by check_goals) and avoidance (the run's --avoidance, none or orca; default the file's)."""

    def bad(field: str, message: str) -> WorldFileError:
        return WorldFileError(str(path), f"world.{field}", message, line=1)

    data = header.get("world")
    if not isinstance(data, dict):
        raise WorldFileError(str(path), "world", "a robot world's record keeps its world file and planner here",
                             line=1)
    data = {"world_orders": True, "goals": [], "avoidance": None, **data}
    for key, kind, what in (("robot_world", str, "the world file's path"), ("planner", str, "a planner's name"),
                            ("world_orders", bool, "true or false"), ("goals", list, "a list of [ROBOT:]ROOM")):
        if not isinstance(data.get(key), kind) or (key == "goals" and not all(isinstance(g, str) for g in data[key])):
            raise bad(key, f"missing or not {what}")
    if data["planner"].lower() not in deciders:
        raise bad("planner", f"unknown planner {_clip(data['planner'])} (this vwg knows {', '.join(deciders)})")
    for i, goal in enumerate(data["goals"]):
        if _goal_robot(goal) is None:
            raise bad(f"goals[{i}]", f"expected ROOM or ROBOT:ROOM, got {_clip(goal)}")
    if data["avoidance"] not in (None, "none", "orca"):
        raise bad("avoidance", f"expected none or orca (the run's --avoidance), got {_clip(data['avoidance'])}")
    return data


def _goal_robot(goal: str) -> int | None:
    """The robot a --goal order names (0: none, the first robot), read as the run read it; None if
    the order is not ROOM or ROBOT:ROOM."""
    robot, _, room = goal.rpartition(":")
    if not room:
        return None
    if not robot:
        return 0
    try:
        number = int(robot)
    except ValueError:  # not a number, or thousands of digits
        return None
    return number if 1 <= number <= MAX_ROBOT_ID else None


def robot_world_file(data: dict[str, Any], path: Path) -> Path:
    """The world file a robot world's record names (``world.robot_world``, from robot_data), found:
    a file or a shipped world's name; WorldFileError naming the record's field when it is not there."""

    named = data["robot_world"]

    def bad(why: str) -> WorldFileError:
        return WorldFileError(str(path), "world.robot_world", f"the world file the record names, {_clip(named)}: "
                              f"{why}; give the world file to replay it with (--world FILE)", line=1)

    if "\0" in named:
        raise bad("no file can have this name (it holds a NUL byte)")
    try:
        return resolve_world(named)
    except Error as e:
        raise bad(str(e).removeprefix(f"{named}: ")) from None
    except OSError as e:  # a name longer than the system takes
        raise bad(f"cannot be looked up: {e.strerror}") from None


def check_goals(data: dict[str, Any], rooms: Sequence[str], robots: Sequence[int], path: Path) -> None:
    """The --goal orders a robot world's record keeps (robot_data), against the world they are run
    in again: each a room of it, and a robot of it when one is named."""
    for i, goal in enumerate(data["goals"]):
        room, robot = goal.rpartition(":")[2], _goal_robot(goal)
        if room not in rooms:
            raise WorldFileError(str(path), f"world.goals[{i}]", f"the run's order {_clip(goal)} names no room of "
                                 f"the world (rooms: {', '.join(rooms)})", line=1)
        if robot and robot not in robots:
            raise WorldFileError(str(path), f"world.goals[{i}]", f"the run's order {_clip(goal)} names no robot of "
                                 f"the world (robots: {', '.join(map(str, robots))})", line=1)
