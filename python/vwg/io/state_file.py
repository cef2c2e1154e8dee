"""The state file of a saved run (``vwg run --save-state``, ``run.save_state``, ``vwg resume``).

Layout, every number little-endian::

    b"vwg-state\\n"                      10 bytes: what the file is
    u64 n, then n bytes of JSON         the manifest: format, vwg version, world, seed, frame, ... and
                                        its parts: [{"name", "bytes" (stored), "size" (raw), "sha256"}]
    the parts, one after the other     each deflated (zlib); the manifest says how long
    32 bytes                            SHA-256 of the manifest
    32 bytes                            SHA-256 of everything before it

Reading checks the end's two hashes and each part's (after inflating it no further than the size the
manifest gives), so a flipped byte anywhere is an error naming the part it is in (the manifest, a part,
or the hashes at the end); sizes are checked before anything is allocated for them. A state file holds
no code: reading one runs none.

The engine's state (vwg.EngineState) is kept as the parts ``string`` (w's text), ``blobs`` (every
blob once, by name; one of the dtype and shape of an earlier blob is stored as the elements that differ
from it, or as its XOR with it when that is smaller, so a robot's map costs what it changed of the
known map), ``generators`` and ``actors``; a robot run adds ``platform``.
"""

from __future__ import annotations

import hashlib
import io
import json
import math
import struct
import zlib
from dataclasses import dataclass
from typing import Any

import numpy as np

import vwg._core as _core
from vwg.errors import Error

__all__ = ["FORMAT", "MAX_BYTES", "SavedState", "engine_parts", "engine_state", "read_state", "write_state"]

MAGIC = b"vwg-state\n"
#: The layout above; a reader refuses another.
FORMAT = 1
#: What a state may expand to, in all: its parts inflated (a 1,000-robot run on a 1,600² map is ~1 GiB).
MAX_BYTES = 8 * 2**30
MAX_MANIFEST = 2**24
_U64 = struct.Struct("<Q")


@dataclass
class SavedState:
    """A state file read and checked: its manifest and its parts (inflated)."""

    manifest: dict[str, Any]
    parts: dict[str, bytes]


def write_state(manifest: dict[str, Any], parts: dict[str, bytes]) -> bytes:
    """The bytes of a state file holding `parts` (name -> raw bytes), described by `manifest`."""
    stored = {name: zlib.compress(raw, 6) for name, raw in parts.items()}
    described = {**manifest, "format": FORMAT,
                 "parts": [{"name": name, "bytes": len(stored[name]), "size": len(raw),
                            "sha256": hashlib.sha256(raw).hexdigest()} for name, raw in parts.items()]}
    head = json.dumps(described, sort_keys=True, allow_nan=False).encode("utf-8")
    out = io.BytesIO()
    out.write(MAGIC)
    out.write(_U64.pack(len(head)))
    out.write(head)
    for name in parts:
        out.write(stored[name])
    out.write(hashlib.sha256(head).digest())
    body = out.getvalue()
    return body + hashlib.sha256(body).digest()


def read_state(data: bytes, source: str) -> SavedState:
    """A state file's content checked (see the module's description); Error naming `source` and the
    part that is wrong."""

    def fail(what: str) -> Error:
        return Error(f"{source}: {what}")

    if not data.startswith(MAGIC):
        raise fail("not a vwg state file (it does not begin with 'vwg-state')")
    if len(data) < len(MAGIC) + 8 + 64:
        raise fail(f"cut short: {len(data)} bytes is less than the smallest state file")
    (n,) = _U64.unpack_from(data, len(MAGIC))
    start = len(MAGIC) + 8
    if n > min(MAX_MANIFEST, len(data) - start - 64):
        raise fail(f"the manifest's length ({n} bytes) is more than the file holds: the file is cut short or damaged")
    head = data[start:start + n]
    manifest_hash, file_hash = data[-64:-32], data[-32:]
    whole = hashlib.sha256(data[:-32]).digest() == file_hash
    manifest = _parse_manifest(head)
    if hashlib.sha256(head).digest() != manifest_hash:
        if hashlib.sha256(data[:-64] + hashlib.sha256(head).digest()).digest() == file_hash:
            raise fail("the hashes at its end are damaged (the manifest and parts check)")
        if isinstance(manifest, dict) and _fits(manifest, len(data) - start - n - 64) is False:
            raise fail("the file is cut short or damaged: its parts do not fill it as the manifest says")
        raise fail("the manifest is damaged (its SHA-256 differs from the one kept at the end)")
    if isinstance(manifest, str):
        raise fail(f"the manifest is not JSON: {manifest}")
    if not isinstance(manifest, dict):
        raise fail("the manifest is not a JSON object")
    if manifest.get("format") != FORMAT:
        raise fail(f"a state file of format {manifest.get('format')!r}; this vwg reads format {FORMAT}")
    entries = manifest.get("parts")
    if not (isinstance(entries, list) and all(_entry_ok(e) for e in entries)):
        raise fail("the manifest's list of parts is malformed")
    if sum(e["size"] for e in entries) > MAX_BYTES:
        raise fail(f"its parts would expand to more than {MAX_BYTES} bytes")
    at = start + n
    if at + sum(e["bytes"] for e in entries) != len(data) - 64:
        raise fail("the file is cut short or damaged: its parts do not fill it as the manifest says")
    parts: dict[str, bytes] = {}
    for e in entries:
        stored = data[at:at + e["bytes"]]
        at += e["bytes"]
        parts[e["name"]] = _inflate(stored, e, fail)
    if not whole:
        raise fail("the hashes at its end are damaged (the manifest and parts check)")
    return SavedState(manifest, parts)


def _parse_manifest(head: bytes) -> dict[str, Any] | str:
    """The manifest, or what is wrong with its text."""
    try:
        return json.loads(head.decode("utf-8"))  # type: ignore[no-any-return]
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        return str(e)
    except (RecursionError, ValueError) as e:  # nested too deep; an integer of thousands of digits
        return f"{type(e).__name__}: {str(e)[:200]}"


def _fits(manifest: dict[str, Any], room: int) -> bool | None:
    """Whether the parts a manifest lists fill `room` bytes (None: it lists none readably)."""
    entries = manifest.get("parts")
    if not (isinstance(entries, list) and all(_entry_ok(e) for e in entries)):
        return None
    return sum(e["bytes"] for e in entries) == room


def _entry_ok(e: Any) -> bool:
    return (isinstance(e, dict) and isinstance(e.get("name"), str) and isinstance(e.get("sha256"), str)
            and all(isinstance(e.get(k), int) and not isinstance(e.get(k), bool) and e[k] >= 0
                    for k in ("bytes", "size")))


def _inflate(stored: bytes, entry: dict[str, Any], fail: Any) -> bytes:
    name = entry["name"]
    try:
        d = zlib.decompressobj()
        raw = d.decompress(stored, entry["size"])
        if d.unconsumed_tail or not d.eof or d.unused_data:
            raise fail(f"the part '{name}' is damaged: it does not inflate to the {entry['size']} bytes the "
                       "manifest says")
    except zlib.error as e:
        raise fail(f"the part '{name}' is damaged ({e})") from None
    if len(raw) != entry["size"] or hashlib.sha256(raw).hexdigest() != entry["sha256"]:
        raise fail(f"the part '{name}' is damaged (its SHA-256 differs)")
    return raw


# ---- the engine's state as parts --------------------------------------------------------------------
def _pack_list(items: list[tuple[str, bytes]]) -> bytes:
    out = io.BytesIO()
    out.write(_U64.pack(len(items)))
    for name, blob in items:
        encoded = name.encode("utf-8")
        out.write(_U64.pack(len(encoded)))
        out.write(encoded)
        out.write(_U64.pack(len(blob)))
        out.write(blob)
    return out.getvalue()


class _Reader:
    def __init__(self, data: bytes, part: str) -> None:
        self.data, self.at, self.part = data, 0, part

    def u64(self) -> int:
        if self.at + 8 > len(self.data):
            raise Error(f"state part '{self.part}': cut short at byte {self.at}")
        (v,) = _U64.unpack_from(self.data, self.at)
        self.at += 8
        return int(v)

    def take(self) -> bytes:
        n = self.u64()
        if n > len(self.data) - self.at:
            raise Error(f"state part '{self.part}': a length of {n} bytes is more than is left")
        self.at += n
        return self.data[self.at - n:self.at]

    def end(self) -> None:
        if self.at != len(self.data):
            raise Error(f"state part '{self.part}': {len(self.data) - self.at} bytes after its end")


def _unpack_list(data: bytes, part: str) -> list[tuple[str, bytes]]:
    r = _Reader(data, part)
    count = r.u64()
    if count > len(data) // 16:
        raise Error(f"state part '{part}': a count of {count} is more than it can hold")
    items = []
    for _ in range(count):
        try:
            name = r.take().decode("utf-8")
        except UnicodeDecodeError:
            raise Error(f"state part '{part}': a name that is not UTF-8") from None
        items.append((name, r.take()))
    r.end()
    return items


def _pack_blobs(blobs: dict[str, _core.Blob]) -> bytes:
    """Every blob once. One of the dtype and shape of an earlier one (its base) is kept as the elements
    that differ from it (their indices, then their values) when that is smaller, else as its XOR with it:
    a robot's map costs what it changed of the known map."""
    out = io.BytesIO()
    out.write(_U64.pack(len(blobs)))
    bases: dict[tuple[str, tuple[int, ...]], tuple[int, np.ndarray]] = {}
    for k, (name, blob) in enumerate(sorted(blobs.items())):
        array = np.ascontiguousarray(np.asarray(blob)).reshape(-1)
        key = (blob.dtype, tuple(int(n) for n in np.asarray(blob).shape))
        base = bases.get(key)
        form, payload = "whole", array.view(np.uint8)
        if base is not None:
            changed = np.flatnonzero(array != base[1])
            index = np.uint32 if array.size < 2**32 else np.uint64
            if changed.size * (np.dtype(index).itemsize + array.itemsize) < array.nbytes // 2:
                form = "sparse"
                payload = np.concatenate([changed.astype(index).view(np.uint8), array[changed].view(np.uint8)])
            else:
                form, payload = "xor", array.view(np.uint8) ^ base[1].view(np.uint8)
        meta = json.dumps({"name": name, "dtype": blob.dtype, "shape": list(key[1]),
                           "base": base[0] if base else -1, "form": form}).encode("utf-8")
        out.write(_U64.pack(len(meta)))
        out.write(meta)
        out.write(_U64.pack(payload.size))
        out.write(payload.tobytes())
        if base is None:
            bases[key] = (k, array)
    return out.getvalue()


def _unpack_blobs(data: bytes) -> dict[str, _core.Blob]:
    r = _Reader(data, "blobs")
    count = r.u64()
    if count > len(data) // 16:
        raise Error(f"state part 'blobs': a count of {count} is more than it can hold")
    raws: list[np.ndarray] = []  # each blob's elements, flat: the bases of later ones
    blobs: dict[str, _core.Blob] = {}
    for k in range(count):
        try:
            meta = json.loads(r.take().decode("utf-8"))
            name, dtype, shape, base, form = (meta["name"], np.dtype(meta["dtype"]), tuple(meta["shape"]),
                                              meta["base"], meta["form"])
            if not (isinstance(name, str) and all(isinstance(n, int) and 0 <= n < 2**40 for n in shape)
                    and isinstance(base, int) and -1 <= base < k and not dtype.hasobject
                    and form in (("whole",) if base < 0 else ("xor", "sparse"))):
                raise ValueError("malformed")
        except (UnicodeDecodeError, ValueError, KeyError, TypeError, RecursionError) as e:
            raise Error(f"state part 'blobs': blob {k} is described wrongly ({str(e)[:200]})") from None
        payload = np.frombuffer(r.take(), np.uint8)
        count = math.prod(shape)
        if base >= 0 and (raws[base].dtype != dtype or raws[base].size != count):
            raise Error(f"state part 'blobs': blob {name} is not of its base's dtype and shape")
        if form == "sparse":
            index = np.uint32 if count < 2**32 else np.uint64
            per = np.dtype(index).itemsize + dtype.itemsize
            if payload.size % per:
                raise Error(f"state part 'blobs': blob {name}'s changes are cut short")
            n = payload.size // per
            at = payload[:n * np.dtype(index).itemsize].view(index)
            if n and int(at.max()) >= count:
                raise Error(f"state part 'blobs': blob {name} changes an element past its end")
            elements = raws[base].copy()
            elements[at] = payload[n * np.dtype(index).itemsize:].view(dtype)
        else:
            if payload.size != count * dtype.itemsize:
                raise Error(f"state part 'blobs': blob {name} holds {payload.size} bytes, not the "
                            f"{count * dtype.itemsize} of its shape")
            elements = payload.view(dtype) if form == "whole" else (payload ^ raws[base].view(np.uint8)).view(dtype)
        raws.append(elements)
        blobs[name] = _core.Blob(elements.reshape(shape).copy())
    r.end()
    return blobs


def engine_parts(state: _core.EngineState) -> dict[str, bytes]:
    """The parts of a file that hold an engine's state."""
    return {"string": state.string.encode("utf-8"),
            "blobs": _pack_blobs(state.blobs),
            "generators": _pack_list([(str(k), bytes(b)) for k, b in enumerate(state.generators)]),
            "actors": _pack_list([(name, bytes(b)) for name, b in state.actors])}


def engine_state(saved: SavedState, frame: int) -> _core.EngineState:
    """The engine's state kept in a file's parts (see engine_parts)."""
    missing = [p for p in ("string", "blobs", "generators", "actors") if p not in saved.parts]
    if missing:
        raise Error(f"the state file has no part {', '.join(missing)}")
    state = _core.EngineState()
    state.frame = frame
    try:
        state.string = saved.parts["string"].decode("utf-8")
    except UnicodeDecodeError:
        raise Error("state part 'string': not UTF-8 text") from None
    state.blobs = _unpack_blobs(saved.parts["blobs"])
    state.generators = [b for _, b in _unpack_list(saved.parts["generators"], "generators")]
    state.actors = _unpack_list(saved.parts["actors"], "actors")
    return state
