"""Plugins: the parts a world names — deciders, sensors, platforms, backends and world kinds — found by
name. Each kind of part has a registry, filled from the Python entry points of its group
(``vwg.deciders``, ``vwg.sensors``, ``vwg.platforms``, ``vwg.backends``, ``vwg.world_kinds``, and
``vwg.generators`` for generic worlds) and by
in-process registration. vwg's own parts are entry points of the vwg distribution: they are found the
same way as a third party's (pyproject.toml, ``[project.entry-points."vwg.deciders"]``).

    # in a plugin's pyproject.toml
    [project.entry-points."vwg.deciders"]
    mine = "my_package.my_module:MyDecider"     # a vwg.robot.Decider subclass, or a factory returning one

    # or in-process
    vwg.plugins.deciders.register("mine", MyDecider)

A group's entry points are loaded the first time its registry is used. One that fails to import is
logged with its name, kept in ``registry.failures`` (``vwg plugins`` lists it) and left out; the
others still load.
"""

from __future__ import annotations

import importlib.metadata
import logging
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

from vwg.errors import SchemaError

__all__ = ["GROUPS", "Failure", "Plugin", "Registry", "backends", "deciders", "generators", "platforms", "sensors",
           "world_kinds"]

log = logging.getLogger("vwg.plugins")

T = TypeVar("T")


@dataclass(frozen=True)
class Plugin:
    """A registered part: its name, its group and where it came from (a distribution's entry point, or
    the module that registered it in-process)."""

    name: str
    group: str
    origin: str


@dataclass(frozen=True)
class Failure:
    """An entry point that could not be loaded: its name, group, where it came from and why."""

    name: str
    group: str
    origin: str
    error: str


def _origin_of(ep: importlib.metadata.EntryPoint) -> str:
    dist = ep.dist
    where = f"{dist.metadata['Name']} {dist.version}" if dist is not None else "an unnamed distribution"
    return f"{where} (entry point {ep.value})"


class Registry(Generic[T]):
    """Parts of one kind by name: ``registry.get(name)`` is what was registered (a class or a factory),
    ``registry.create(name, ...)`` calls it. A name is registered once; a second registration is refused."""

    def __init__(self, kind: str, group: str) -> None:
        self.kind = kind
        self.group = group
        self._factories: dict[str, Callable[..., T]] = {}
        self._origins: dict[str, str] = {}
        self._failures: dict[str, Failure] = {}
        self._loaded = False
        self._lock = threading.RLock()

    # -- filling ---------------------------------------------------------------------------------
    def register(self, name: str, factory: Callable[..., T], *, origin: str | None = None) -> Callable[..., T]:
        """Register `factory` under `name` (in-process: a test, a notebook, a program embedding vwg)."""
        with self._lock:
            self._load()
            if not isinstance(name, str) or not name or name != name.strip():
                raise SchemaError(f"{self.kind} name: expected a non-empty name without surrounding spaces, got "
                                  f"{name!r}")
            if name in self._factories:
                raise SchemaError(f"{self.kind} '{name}' is already registered (by {self._origins[name]})")
            self._factories[name] = factory
            module = getattr(factory, "__module__", None) or "?"
            self._origins[name] = origin or f"registered in-process by {module}"
            return factory

    def unregister(self, name: str) -> None:
        """Remove a registration (a plugin unloading, a test cleaning up); KeyError if none."""
        with self._lock:
            self._load()
            del self._factories[name]
            del self._origins[name]

    def _load(self) -> None:
        """The group's entry points, once; each loaded on its own, so that one broken plugin does not
        hide the others."""
        with self._lock:
            if self._loaded:
                return
            self._loaded = True  # before loading: a plugin module may use the registry while it imports
            for ep in sorted(importlib.metadata.entry_points(group=self.group), key=lambda e: e.name):
                origin = _origin_of(ep)
                if ep.name in self._factories:
                    self._fail(ep.name, origin, f"the name is already registered by {self._origins[ep.name]}")
                    continue
                try:
                    obj = ep.load()
                except Exception as e:  # any error of a plugin's import: named, and the rest still load
                    self._fail(ep.name, origin, f"{type(e).__name__}: {e}")
                    continue
                if not callable(obj):
                    self._fail(ep.name, origin, f"{ep.value} is a {type(obj).__name__}, not a class or a factory")
                    continue
                self._factories[ep.name] = obj
                self._origins[ep.name] = origin

    def _fail(self, name: str, origin: str, error: str) -> None:
        self._failures[name] = Failure(name, self.group, origin, error)
        log.warning("plugin %r of group %s (from %s) was not loaded: %s", name, self.group, origin, error)

    # -- reading ---------------------------------------------------------------------------------
    def get(self, name: str) -> Callable[..., T]:
        self._load()
        try:
            return self._factories[name]
        except KeyError:
            known = ", ".join(sorted(self._factories)) or "none"
            broken = self._failures.get(name)
            if broken is not None:
                raise SchemaError(f"{self.kind} '{name}' did not load ({broken.origin}): {broken.error}") from None
            raise SchemaError(f"unknown {self.kind} '{name}' (known: {known})") from None

    def create(self, name: str, *args: Any, **kwargs: Any) -> T:
        return self.get(name)(*args, **kwargs)

    def origin(self, name: str) -> str:
        self._load()
        return self._origins[name]

    @property
    def failures(self) -> list[Failure]:
        """The entry points of the group that could not be loaded."""
        self._load()
        return [self._failures[n] for n in sorted(self._failures)]

    def plugins(self) -> list[Plugin]:
        """Every registered part, by name."""
        self._load()
        return [Plugin(n, self.group, self._origins[n]) for n in sorted(self._factories)]

    def __contains__(self, name: object) -> bool:
        self._load()
        return name in self._factories

    def __iter__(self) -> Iterator[str]:
        self._load()
        return iter(sorted(self._factories))

    def __len__(self) -> int:
        self._load()
        return len(self._factories)


#: Deciders (paper test 1: the decision inside λ(ARobot, eDecide) is swapped, nothing else): a
#: vwg.robot.Decider subclass or a factory with no arguments returning one.
deciders: Registry[Any] = Registry("decider", "vwg.deciders")
#: Sensors (vwg.robot.sensor.Sensor subclasses): world files list them by name.
sensors: Registry[Any] = Registry("sensor", "vwg.sensors")
#: Robot platforms (vwg.robot.platform.Platform subclasses): the simulator, rosbridge, serial, ...
platforms: Registry[Any] = Registry("platform", "vwg.platforms")
#: Backends of generic worlds: a factory taking the world file's backend options, returning a vwg.Backend.
backends: Registry[Any] = Registry("backend", "vwg.backends")
#: Event generators of generic worlds by name: a factory taking ``world=`` and ``spec=`` (the world file's
#: entry), returning a vwg.Generator.
generators: Registry[Any] = Registry("generator", "vwg.generators")
#: Kinds of world file (vwg.launch.WorldKind): a class with no arguments.
world_kinds: Registry[Any] = Registry("world kind", "vwg.world_kinds")

#: The registries by entry-point group.
GROUPS: dict[str, Registry[Any]] = {r.group: r for r in (deciders, sensors, platforms, backends, generators,
                                                              world_kinds)}
