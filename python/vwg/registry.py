"""Named registries of generators and backends, so world files can name them. A name is
registered once; a second registration is refused."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

from .errors import SchemaError

__all__ = ["Registry", "Sensor", "backends", "deciders", "generators", "platforms", "sensors", "world_kinds"]

T = TypeVar("T")


class Registry(Generic[T]):
    """Factories by name: ``registry.register("sim", make_sim)`` then ``registry.create("sim", **args)``."""

    def __init__(self, kind: str) -> None:
        self.kind = kind
        self._factories: dict[str, Callable[..., T]] = {}

    def register(self, name: str, factory: Callable[..., T]) -> Callable[..., T]:
        if name in self._factories:
            raise SchemaError(f"{self.kind} '{name}' is already registered")
        self._factories[name] = factory
        return factory

    def unregister(self, name: str) -> None:
        """Remove a registration (a plugin unloading, a test cleaning up); KeyError if none."""
        del self._factories[name]

    def create(self, name: str, *args: Any, **kwargs: Any) -> T:
        return self.get(name)(*args, **kwargs)

    def get(self, name: str) -> Callable[..., T]:
        try:
            return self._factories[name]
        except KeyError:
            known = ", ".join(sorted(self._factories)) or "none"
            raise SchemaError(f"unknown {self.kind} '{name}' (known: {known})") from None

    def __contains__(self, name: object) -> bool:
        return name in self._factories

    def __iter__(self) -> Iterator[str]:
        return iter(sorted(self._factories))

    def in_order(self) -> list[str]:
        """The names in the order they were registered."""
        return list(self._factories)


@dataclass(frozen=True)
class Sensor:
    """A kind of sensor a world file's robot may list: ``make(platform, alphabet, robot_id)`` gives
    its event generator on that platform (a vwg.Simulation, say). ``ranging`` sensors come first in
    the priority order, robot by robot, then the others (the paper's gLaser/gKinect, then gCamera)."""

    make: Callable[..., Any]
    ranging: bool = True


backends: Registry[Any] = Registry("backend")
generators: Registry[Any] = Registry("generator")
#: Deciders by name (paper test 1: the decision is swapped, nothing else): a factory with no
#: arguments -> a vwg.Decider. ``deciders.register("mine", MyDecider)`` makes ``--planner mine`` work.
deciders: Registry[Any] = Registry("decider")
#: Robot platforms by name: a factory (robot world, seed, options) -> an object with ``platform`` (a
#: vwg.RobotPlatform), ``backend`` (φ on it), ``feedback(alphabet)``, ``sensors(alphabet, kinds)``,
#: ``view(...)`` and ``robot(id)``, as vwg.Simulation has them.
platforms: Registry[Any] = Registry("platform")
#: Sensors by name, as world files list them (``robots[i].sensors``): a factory with no arguments ->
#: a Sensor. ``sensors.register("sonar", lambda: Sensor(make_sonar))`` lets a world list ``sonar``.
sensors: Registry[Sensor] = Registry("sensor")
#: Kinds of world file (vwg.launch.WorldKind), tried in registration order: a factory with no arguments.
world_kinds: Registry[Any] = Registry("world kind")


def _register_builtins() -> None:
    from . import _core

    def robot_kind() -> Any:
        from .casestudy import RobotKind

        return RobotKind()

    def generic_kind() -> Any:
        from .worldfile import GenericKind

        return GenericKind()

    world_kinds.register("robot", robot_kind)
    world_kinds.register("generic", generic_kind)
    backends.register("trace", lambda **_: _core.TraceBackend())
    backends.register("null", lambda **_: _core.NullBackend())

    def simulator(world: Any, seed: int, options: dict[str, Any]) -> Any:
        from .sim import Simulation

        if options:
            raise SchemaError(f"platform sim: unknown option(s) {', '.join(sorted(options))} (it takes none)")
        return Simulation(world, seed=seed)

    platforms.register("sim", simulator)

    sensors.register("laser", lambda: Sensor(lambda platform, alphabet, robot: platform.laser(alphabet, robot)))
    sensors.register("kinect", lambda: Sensor(lambda platform, alphabet, robot: platform.kinect(alphabet, robot)))
    sensors.register("camera", lambda: Sensor(lambda platform, alphabet, robot: platform.camera(alphabet, robot),
                                              ranging=False))

    deciders.register("random", lambda: _core.RandomDecider())
    deciders.register("astar", lambda: _core.GridDecider("astar"))
    deciders.register("dstar", lambda: _core.GridDecider("dstar"))
    # OMPL planners bounded by iterations, not time, so a run is the same on any machine: RRT-Connect
    # stops at its first solution; RRT* improves its path for all its iterations; "prm" is OMPL's
    # LazyPRM (PRM proper builds its roadmap on a second thread and is not reproducible).
    deciders.register("rrtconnect", lambda: _core.OmplDecider("RRTConnect", 20000))
    deciders.register("rrtstar", lambda: _core.OmplDecider("RRTstar", 5000))
    deciders.register("prm", lambda: _core.OmplDecider("LazyPRM", 5000))


_register_builtins()
