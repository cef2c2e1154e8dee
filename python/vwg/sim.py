"""Deprecated: vwg.sim is now vwg.robot.platforms.sim (the Python face is organised by concept); this alias
stays for one release and warns when imported."""

from __future__ import annotations

import warnings

from vwg.robot.platforms.sim import *  # noqa: F403
from vwg.robot.platforms.sim import __all__  # noqa: F401

warnings.warn("vwg.sim is deprecated: import vwg.robot.platforms.sim instead (the alias goes in the next release)",
              DeprecationWarning, stacklevel=2)
