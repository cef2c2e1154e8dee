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
    its event generator on that platform (a vwg.sim.WorldRobots), or None when the platform does not
    carry it. ``ranging`` sensors come first in
    the priority order, robot by robot, then the others (the paper's gLaser/gKinect, then gCamera)."""

    make: Callable[..., Any]
    ranging: bool = True


backends: Registry[Any] = Registry("backend")
generators: Registry[Any] = Registry("generator")
#: Deciders by name (paper test 1: the decision is swapped, nothing else): a factory with no
#: arguments -> a vwg.robot.Decider. ``deciders.register("mine", MyDecider)`` makes ``--planner mine`` work.
deciders: Registry[Any] = Registry("decider")
#: Robot platforms by name (a factory's ``options`` attribute, when it has one, lists the keys a
#: world file's ``platform:`` may give it, checked with the file's line): a factory (robot world,
#: seed, options) -> a vwg.sim.WorldRobots (``platform``, ``backend`` on it, the feedback and sensor
#: generators, a view), as vwg.sim.Simulation and vwg.real_robots.RealRobots are.
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
    # The built-in backends, sensors and deciders are the C++ registries' (vwg/registry.hpp,
    # vwg/robot/registries.hpp): one list of names, one set of settings (the OMPL planners' budgets).
    for name in _core.backend_names():
        backends.register(name, lambda n=name, **_: _core.create_backend(n))

    def simulator(world: Any, seed: int, options: dict[str, Any]) -> Any:
        from .sim import Simulation

        if options:
            raise SchemaError(f"platform sim: unknown option(s) {', '.join(sorted(options))} (it takes none)")
        return Simulation(world, seed=seed)

    simulator.options = ()  # type: ignore[attr-defined]  # what a world file's platform: may hold
    platforms.register("sim", simulator)

    def rosbridge(world: Any, seed: int, options: dict[str, Any]) -> Any:
        from .real_robots import RealRobots
        from .rosbridge_platform import OPTIONS, RosbridgePlatform

        unknown = sorted(set(options) - set(OPTIONS))
        if unknown:
            raise SchemaError(f"platform rosbridge: unknown option(s) {', '.join(unknown)} "
                              f"(known: {', '.join(OPTIONS)})")
        if not isinstance(options.get("url"), str):
            raise SchemaError("platform rosbridge: url: missing (ws://HOST:PORT, or --url)")
        numbers = {k: float(options[k]) for k in ("watchdog", "reconnect", "control_rate") if k in options}
        platform = RosbridgePlatform(list(world.robots), options["url"], topics=options.get("topics"),
                                     ros=options.get("ros", 1), lockstep=options.get("lockstep"),
                                     flap_limit=options.get("flap_limit"), **numbers)
        return RealRobots(world, platform)

    from .rosbridge_platform import OPTIONS as ROSBRIDGE_OPTIONS
    from .serial_platform import OPTIONS as SERIAL_OPTIONS

    rosbridge.options = ROSBRIDGE_OPTIONS  # type: ignore[attr-defined]
    platforms.register("rosbridge", rosbridge)

    def serial_base(world: Any, seed: int, options: dict[str, Any]) -> Any:
        from .real_robots import RealRobots
        from .serial_platform import OPTIONS, SerialPlatform

        unknown = sorted(set(options) - set(OPTIONS))
        if unknown:
            raise SchemaError(f"platform serial: unknown option(s) {', '.join(unknown)} (known: {', '.join(OPTIONS)})")
        if not isinstance(options.get("port"), str):
            raise SchemaError("platform serial: port: missing (/dev/ttyUSB0, socket://HOST:PORT, or --port)")
        if len(world.robots) != 1:
            raise SchemaError(f"platform serial: one base per serial line, and the world has {len(world.robots)} "
                              "robots")
        numbers = {k: options[k] for k in OPTIONS if k in options and k != "port"}
        return RealRobots(world, SerialPlatform(world.robots[0], options["port"], **numbers))

    serial_base.options = SERIAL_OPTIONS  # type: ignore[attr-defined]
    platforms.register("serial", serial_base)

    ranging = set(_core.ranging_sensors())
    for name in _core.sensor_names():
        def make(platform: Any, alphabet: Any, robot: int, name: str = name) -> Any:
            return platform.sensor(name, alphabet, robot)

        sensors.register(name, lambda make=make, name=name: Sensor(make, ranging=name in ranging))
    for name in _core.decider_names():
        deciders.register(name, lambda n=name: _core.create_decider(n))

    def wavefront() -> Any:
        from .wavefront import WavefrontDecider

        return WavefrontDecider()

    deciders.register("wavefront", wavefront)  # a decider written in Python (paper test 1)


_register_builtins()
