"""The errors vwg raises. Each names where (file, line and column, field, or frame) and what was expected."""

from __future__ import annotations

__all__ = ["Error", "FrameError", "ParseError", "ReplayError", "SchemaError", "WorldFileError", "clip"]


class Error(Exception):
    """Base of all vwg errors."""


class ParseError(Error, ValueError):
    """Malformed text. Attributes: ``source``, ``line``, ``column`` (1-based, in characters),
    ``found`` and ``expected``."""

    source: str
    line: int
    column: int
    found: str
    expected: str


class SchemaError(Error, ValueError):
    """A value or declaration that does not fit: unknown attribute, wrong type, NaN, duplicate
    name. ``field`` names what was wrong, e.g. ``"ARobot.row"``."""

    field: str


class FrameError(Error, RuntimeError):
    """Something failed while running a frame; the engine keeps its last complete frame.

    Attributes: ``frame``; ``stage`` ("generate", "evolve" for λ, "visualize" for θ, "display" for
    φ on the backend); ``actor`` and ``event`` (text forms, or ""); ``where`` (generator or backend,
    string position). The original exception is ``__cause__``."""

    frame: int
    stage: str
    actor: str
    event: str
    where: str


class WorldFileError(SchemaError):
    """A bad world, map or record file. ``path`` is the file, ``line`` its line and ``column`` its
    column (1-based, or 0 when not known) and ``field`` the key path inside it, e.g.
    ``"alphabet.events.show.visual"``."""

    def __init__(self, path: str, field: str, message: str, line: int = 0, column: int = 0) -> None:
        where = (f"{path}:{line}:{column}" if column else f"{path}:{line}") if line else str(path)
        super().__init__(f"{where}: {field}: {message}" if field else f"{where}: {message}")
        self.path = str(path)
        self.field = field
        self.line = line
        self.column = column


class ReplayError(Error):
    """A replay did not give the recorded string at ``frame``."""

    def __init__(self, frame: int, expected: str, got: str) -> None:
        # Where the two first differ, with some text either side and a caret under the place.
        pairs = enumerate(zip(got, expected, strict=False))
        at = next((i for i, (a, b) in pairs if a != b), min(len(got), len(expected)))
        start = max(0, at - 60)

        def window(s: str) -> str:
            part = s[start:at + 60]
            return ("…" if start else "") + part + ("…" if at + 60 < len(s) else "")

        caret = " " * (at - start + (1 if start else 0)) + "^"
        super().__init__(f"frame {frame}: the replay's string differs from the record's at character {at + 1}:\n"
                         f"  replay: {window(got)}\n  record: {window(expected)}\n          {caret}")
        self.frame = frame
        self.expected = expected
        self.got = got


def clip(text: str, n: int = 200) -> str:
    """`text` cut to `n` characters with "..." (a long value quoted in a message or a summary line)."""
    return text if len(text) <= n else text[: n - 3] + "..."
