"""The worlds that ship with vwg, by name, and how a command-line argument names a world file.

The robot worlds of ``maps/`` in the repository are package data (``vwg/worlds/`` in the wheel), so
an installed vwg runs them from any directory:

    vwg worlds                 # lists them
    vwg run office             # the same as vwg run path/to/office.yaml

A name that is also a file in the current directory means the file. A name that is a folder here
(``office/``, as beside the shipped ``office.yaml`` in ``maps/``) cannot be a world file: it means the
shipped world, and a warning says so (logger ``vwg.io.shipped``, which ``vwg`` prints).
"""

from __future__ import annotations

import logging
from importlib import resources
from pathlib import Path

from vwg.errors import Error

__all__ = ["expand_user", "resolve_world", "shipped_world", "shipped_worlds", "unusable_name", "worlds_dir"]


def expand_user(name: str | Path) -> Path:
    """`name` with a leading ``~`` or ``~user`` made that user's home folder; Error naming the user
    when there is no such user (Path.expanduser's RuntimeError) or no home folder is known."""
    try:
        return Path(name).expanduser()
    except RuntimeError:
        user = str(name)[1:].partition("/")[0]
        raise Error(f"{name}: no user {user}" if user else f"{name}: no home folder (HOME is not set)") from None


def unusable_name(name: str | Path, e: OSError | ValueError) -> Error:
    """The error for a name the system refused (longer than it takes, a NUL byte), clipped."""
    text = str(name) if len(str(name)) <= 80 else f"{str(name)[:60]}... ({len(str(name))} characters)"
    reason = e.strerror if isinstance(e, OSError) and e.strerror else str(e)
    return Error(f"{text}: not a file name this system takes ({reason})")


def worlds_dir() -> Path:
    """The folder of the shipped worlds: ``vwg/worlds`` when installed, ``maps/`` of the
    repository when vwg runs from its source tree."""
    installed = Path(str(resources.files("vwg"))) / "worlds"
    if installed.is_dir():
        return installed
    source = Path(__file__).resolve().parents[2] / "maps"
    if source.is_dir():
        return source
    raise Error(f"the shipped worlds are missing: neither {installed} nor {source} exists (a broken install?)")


def shipped_worlds() -> dict[str, Path]:
    """Name -> world file of every shipped world, sorted by name."""
    return {p.stem: p for p in sorted(worlds_dir().glob("*.yaml"))}


_log = logging.getLogger("vwg.io.shipped")


def shipped_world(arg: str | Path) -> Path | None:
    """The shipped world a bare name stands for (``office`` or ``office.yaml``, no folder), when no
    file of that name exists here; None otherwise. When the name is a folder (or a pipe, a device)
    here, the shipped world is the one meant, and a warning names both."""
    path = expand_user(arg)
    if path.parent != Path(".") or path.is_file():
        return None
    shipped = shipped_worlds().get(path.name.removesuffix(".yaml"))
    if shipped is not None and path.exists():
        what = "a folder" if path.is_dir() else "not a regular file"
        _log.warning("%s here is %s, not a world file: running the shipped world %s (%s)", path, what,
                     path.name.removesuffix(".yaml"), shipped)
    return shipped


def resolve_world(arg: str | Path) -> Path:
    """The world file an argument names: an existing file, or the name of a shipped world
    (``office`` or ``office.yaml``). Raises Error saying what was looked for otherwise."""
    path = expand_user(arg)
    try:
        if path.is_file():
            return path
        shipped = shipped_world(path)
        if shipped is not None:
            return shipped
        exists = path.exists()
    except (OSError, ValueError) as e:  # a name longer than the system takes, a NUL byte
        raise unusable_name(arg, e) from None
    if exists:
        raise Error(f"{path}: is not a file (expected a world file, .yaml)")
    if path.parent == Path("."):
        raise Error(f"{arg}: no such file, and no shipped world of that name (shipped: "
                    f"{', '.join(shipped_worlds())}; `vwg worlds` lists them)")
    raise Error(f"{arg}: file not found")
