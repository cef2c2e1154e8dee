"""What a generator or decider written in Python keeps, for a saved run (``vwg.resume``).

A Python generator or decider is saved by its own ``save_state(self) -> bytes`` and restored by its
``load_state(self, data)`` when its class defines them. Otherwise its attributes are kept, as JSON:
numbers (NaN and infinities too), text, booleans, None, lists, tuples, dicts, numpy arrays, and the
random generators of numpy (``numpy.random.Generator``, any of numpy's bit generators) and of the
standard library (``random.Random``). An attribute of another kind (a file, a robot's link, a
compiled object) is refused by name: define save_state and load_state for such a class.

Reading a state makes only these kinds of objects: no class the state names is imported, no code runs.
"""

from __future__ import annotations

import base64
import binascii
import json
import math
import random
from typing import Any

import numpy as np

from vwg.errors import SchemaError

__all__ = ["capture", "restore"]

#: numpy's bit generators a state may name (their states are plain numbers).
_BIT_GENERATORS = ("PCG64", "PCG64DXSM", "MT19937", "Philox", "SFC64")
#: How deep lists and dicts may nest in a kept attribute (a limit on what a state expands to).
MAX_DEPTH = 64


def _encode(value: Any, where: str, depth: int = 0) -> Any:
    if depth > MAX_DEPTH:
        raise SchemaError(f"{where}: nested more than {MAX_DEPTH} deep; define save_state and load_state")
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else {"float": repr(v)}
    if isinstance(value, list):
        return [_encode(v, f"{where}[{i}]", depth + 1) for i, v in enumerate(value)]
    if isinstance(value, tuple):
        return {"tuple": [_encode(v, f"{where}[{i}]", depth + 1) for i, v in enumerate(value)]}
    if isinstance(value, dict):
        return {"dict": [[_encode(k, f"{where} key", depth + 1), _encode(v, f"{where}[{k!r}]", depth + 1)]
                         for k, v in value.items()]}
    if isinstance(value, np.ndarray):
        if value.dtype.hasobject:
            raise SchemaError(f"{where}: a numpy array of Python objects cannot be kept; define save_state and "
                              "load_state")
        data = np.ascontiguousarray(value)
        return {"ndarray": {"dtype": data.dtype.str, "shape": list(data.shape),
                            "base64": base64.b64encode(data.tobytes()).decode("ascii")}}
    if isinstance(value, np.random.Generator):  # its bit generator's state: numbers and arrays
        return {"numpy_rng": _encode(value.bit_generator.state, where, depth + 1)}
    if isinstance(value, random.Random):
        version, internal, gauss = value.getstate()
        return {"random": [version, list(internal), gauss]}
    raise SchemaError(f"{where}: a {type(value).__module__}.{type(value).__qualname__} cannot be kept in a saved "
                      "run; define save_state(self) -> bytes and load_state(self, data) on its class")


def _decode(value: Any, where: str, depth: int = 0) -> Any:
    if depth > MAX_DEPTH:  # capture() nests no deeper
        raise SchemaError(f"{where}: a saved value nested more than {MAX_DEPTH} deep")
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, list):
        return [_decode(v, where, depth + 1) for v in value]
    if not (isinstance(value, dict) and len(value) == 1):
        raise SchemaError(f"{where}: a saved value of unknown form")
    (kind, body), = value.items()
    if kind == "float" and body in ("nan", "inf", "-inf"):
        return float(body)
    if kind == "tuple" and isinstance(body, list):
        return tuple(_decode(v, where, depth + 1) for v in body)
    if kind == "dict" and isinstance(body, list) and all(isinstance(p, list) and len(p) == 2 for p in body):
        return {_freeze(_decode(k, where, depth + 1)): _decode(v, where, depth + 1) for k, v in body}
    if kind == "ndarray" and isinstance(body, dict):
        dtype = np.dtype(str(body.get("dtype")))
        if dtype.hasobject:
            raise SchemaError(f"{where}: a saved array of Python objects")
        shape = tuple(int(n) for n in body.get("shape", ()))
        data = base64.b64decode(str(body.get("base64", "")), validate=True)
        if math.prod(shape) * dtype.itemsize != len(data):
            raise SchemaError(f"{where}: a saved array whose bytes are not its shape")
        return np.frombuffer(data, dtype=dtype).reshape(shape).copy()
    if kind == "numpy_rng":
        state = _decode(body, where, depth + 1)
        name = state.get("bit_generator") if isinstance(state, dict) else None
        if not isinstance(name, str) or name not in _BIT_GENERATORS:
            raise SchemaError(f"{where}: a random generator of unknown kind {str(name)[:40]!r}")
        bits = getattr(np.random, name)()
        bits.state = state
        return np.random.Generator(bits)
    if kind == "random" and isinstance(body, list) and len(body) == 3:
        rng = random.Random()
        rng.setstate((body[0], tuple(body[1]), body[2]))
        return rng
    raise SchemaError(f"{where}: a saved value of unknown kind {kind!r}")


def _freeze(key: Any) -> Any:
    return tuple(_freeze(k) for k in key) if isinstance(key, (list, tuple)) else key


def capture(obj: Any, what: str) -> bytes:
    """The attributes of `obj` (a Python generator or decider) as bytes; SchemaError naming `what`
    and the attribute that cannot be kept."""
    attributes = {name: _encode(value, f"{what}.{name}") for name, value in sorted(vars(obj).items())}
    return json.dumps({"attributes": attributes}, sort_keys=True).encode("utf-8")


def restore(obj: Any, data: bytes, what: str) -> None:
    """Set the attributes capture() kept back on `obj` (of the same class, made the same way)."""
    try:
        saved = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as e:  # JSONDecodeError is a ValueError
        raise SchemaError(f"{what}: its saved state is not what capture() writes: {str(e)[:200]}") from None
    attributes = saved.get("attributes") if isinstance(saved, dict) else None
    if not isinstance(attributes, dict):
        raise SchemaError(f"{what}: its saved state has no attributes")
    missing = sorted(set(vars(obj)) - set(attributes))
    extra = sorted(set(attributes) - set(vars(obj)))
    if missing or extra:
        raise SchemaError(f"{what}: the saved state is of another kind of object (attributes "
                          f"{'missing: ' + ', '.join(missing) if missing else ''}"
                          f"{'; ' if missing and extra else ''}{'unknown: ' + ', '.join(extra) if extra else ''})")
    values = {}
    for name, value in attributes.items():
        try:
            values[name] = _decode(value, f"{what}.{name}")
        except SchemaError:
            raise
        except (TypeError, KeyError, IndexError, ValueError, OverflowError, RecursionError, binascii.Error) as e:
            # numpy and random check what they are given: their refusal, said as a vwg error
            raise SchemaError(f"{what}.{name}: a saved value that cannot be restored "
                              f"({type(e).__name__}: {str(e)[:200]})") from None
    for name, value in values.items():
        setattr(obj, name, value)
