"""The worlds that ship with vwg, by name, and how a command-line argument names a world file.

The robot worlds of ``maps/`` in the repository are package data (``vwg/worlds/`` in the wheel), so
an installed vwg runs them from any directory:

    vwg worlds                 # lists them
    vwg run office             # the same as vwg run path/to/office.yaml

A name that is also a file in the current directory means the file.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from .errors import Error

__all__ = ["resolve_world", "shipped_world", "shipped_worlds", "worlds_dir"]


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


def shipped_world(arg: str | Path) -> Path | None:
    """The shipped world a bare name stands for (``office`` or ``office.yaml``, no folder), when no
    file of that name exists here; None otherwise."""
    path = Path(arg).expanduser()
    if path.exists() or path.parent != Path("."):
        return None
    return shipped_worlds().get(path.name.removesuffix(".yaml"))


def resolve_world(arg: str | Path) -> Path:
    """The world file an argument names: an existing file, or the name of a shipped world
    (``office`` or ``office.yaml``). Raises Error saying what was looked for otherwise."""
    path = Path(arg).expanduser()
    if path.is_file():
        return path
    if path.exists():
        raise Error(f"{path}: is not a file (expected a world file, .yaml)")
    shipped = shipped_world(path)
    if shipped is not None:
        return shipped
    if path.parent == Path("."):
        raise Error(f"{arg}: no such file, and no shipped world of that name (shipped: "
                    f"{', '.join(shipped_worlds())}; `vwg worlds` lists them)")
    raise Error(f"{arg}: file not found")
