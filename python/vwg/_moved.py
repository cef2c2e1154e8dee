"""The module names before the Python face was organised by concept (vwg.casestudy, vwg.sim, ...):
for one release each still imports, as the module it became, with a DeprecationWarning naming the
new one. One finder on sys.meta_path stands for all of them; nothing else of vwg uses the old names."""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import sys
import types
import warnings

__all__ = ["MOVED", "install"]

#: Old module (below vwg) -> the module it became.
MOVED = {
    "actor": "vwg.model.actor", "world": "vwg.model.world", "engine": "vwg.model.engine",
    "generators": "vwg.model.generators", "files": "vwg.io.files", "yamldoc": "vwg.io.yamldoc",
    "image_size": "vwg.io.image_size", "maps": "vwg.io.maps", "video": "vwg.io.video", "worlds": "vwg.io.shipped",
    "record": "vwg.io.record", "worldfile": "vwg.generic", "robotworld": "vwg.robot.world_file",
    "casestudy": "vwg.robot.case_study", "sim": "vwg.robot.platforms.sim",
    "real_robot": "vwg.robot.platforms.real_robot", "real_robots": "vwg.robot.platforms.real_robots",
    "rosbridge_platform": "vwg.robot.platforms.rosbridge", "serial_platform": "vwg.robot.platforms.serial_base",
    "rosbridge": "vwg.robot.links.rosbridge_client", "ros_messages": "vwg.robot.links.ros_messages",
    "overview": "vwg.robot.overview", "map_quality": "vwg.robot.map_quality", "shortest": "vwg.robot.shortest",
    "wavefront": "vwg.robot.deciders.wavefront", "fake_robot": "vwg.testing.fake_robot",
    "fake_base": "vwg.testing.fake_base", "reference": "vwg.testing.reference", "registry": "vwg.plugins",
}


class _Moved(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds vwg.OLD and loads it as the module it became (the same module object, not a copy)."""

    def find_spec(self, fullname: str, path: object = None,
                  target: object = None) -> importlib.machinery.ModuleSpec | None:
        old = fullname.removeprefix("vwg.")
        if fullname.startswith("vwg.") and old in MOVED:
            return importlib.util.spec_from_loader(fullname, self)
        return None

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        new = MOVED[spec.name.removeprefix("vwg.")]
        warnings.warn(f"{spec.name} is deprecated: import {new} (the old name goes in the next release)",
                      DeprecationWarning, stacklevel=2)
        return importlib.import_module(new)  # its __name__ and __spec__ stay the new module's

    def exec_module(self, module: types.ModuleType) -> None:
        """Nothing to run: the module was imported under its new name."""


def install() -> None:
    if not any(isinstance(f, _Moved) for f in sys.meta_path):
        sys.meta_path.append(_Moved())
