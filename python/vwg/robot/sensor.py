"""A kind of sensor a robot world's robots carry: one class in one file, registered by name (entry
point group ``vwg.sensors``). It gives its name, its settings (a struct with defaults and a check:
a settings struct of vwg._core, or a dataclass deriving from vwg.robot.sensor.Settings), the events
it emits, and how it is made on each platform that can carry it (``make``).

World files configure sensors by their registered names and list the ones each robot carries:

    sensors:
      laser: {beams: 180, max_range: 6.0}
      sonar: {cone: 0.5}          # a plugin's sensor, checked by its own settings
    robots:
      - {id: 1, start: [1, 1, 0], sensors: [laser, sonar]}
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Any, ClassVar

import vwg._core as _core
from vwg.errors import SchemaError

if TYPE_CHECKING:
    from vwg.robot.platform import Platform

__all__ = ["NoSettings", "Sensor", "Settings"]


class Settings:
    """The base of a sensor's settings written in Python: a dataclass whose fields all have defaults
    (``fields()``, ``replace()`` and ``check()`` as the C++ settings structs have them). ``check``
    checks each field's type against its default's; a subclass adds its own checks (calling
    ``super().check(owner)``) and raises SchemaError("OWNER.FIELD: what was expected")."""

    @classmethod
    def fields(cls) -> tuple[tuple[str, str, Any, str], ...]:
        """(name, type, default, help) of each field (the help is the field's ``metadata["help"]``)."""
        out = []
        for f in dataclasses.fields(cls):  # type: ignore[arg-type]
            default = f.default if f.default is not dataclasses.MISSING else f.default_factory()  # type: ignore[misc]
            out.append((f.name, type(default).__name__, default, f.metadata.get("help", "")))
        return tuple(out)

    def replace(self, **changes: Any) -> Any:
        return dataclasses.replace(self, **changes)  # type: ignore[type-var]

    def check(self, owner: str) -> None:
        for name, kind, default, _ in self.fields():
            value = getattr(self, name)
            if isinstance(default, float) and isinstance(value, int) and not isinstance(value, bool):
                value = float(value)
                setattr(self, name, value)
            if type(value) is not type(default):
                raise SchemaError(f"{owner}.{name}: expected {kind}, got {value!r}")
            if isinstance(value, float) and not math.isfinite(value):
                raise SchemaError(f"{owner}.{name}: expected a finite number, got {value!r}")


@dataclasses.dataclass
class NoSettings(Settings):
    """The settings of a sensor that has none."""


class Sensor:
    """A kind of sensor. A subclass sets ``name``, ``Settings`` (its settings type: the world file's
    section ``sensors.NAME`` fills one and checks it), ``events`` (the event types it emits, with their
    fields' defaults, as vwg.Alphabet takes them), ``ranging`` (ranging sensors come first in the
    frame's priority order, robot by robot: the paper's gLaser and gKinect before gCamera) and
    ``world_fields`` (settings the world sets, such as the walls' height), and implements ``make``."""

    name: ClassVar[str] = ""
    Settings: ClassVar[type] = NoSettings
    events: ClassVar[dict[str, dict[str, Any]]] = {}
    ranging: ClassVar[bool] = False
    world_fields: ClassVar[tuple[str, ...]] = ()
    #: What the sensor is, in a line (``vwg plugins``).
    summary: ClassVar[str] = ""

    def __init__(self, settings: Any = None) -> None:
        self.settings = settings if settings is not None else self.Settings()

    def make(self, platform: Platform, alphabet: _core.Alphabet, robot: int) -> _core.Generator | None:
        """This sensor's event generator for `robot` on `platform` (a vwg.robot.Platform), or None when
        that platform cannot carry it (it is then left out, with a warning)."""
        raise NotImplementedError

    def describe(self) -> str:
        """The settings in a line, for ``vwg check``."""
        return ", ".join(f"{name} {getattr(self.settings, name)!r}" for name, *_ in type(self.settings).fields())
