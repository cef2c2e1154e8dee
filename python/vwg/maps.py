"""Deprecated: vwg.maps is now vwg.io.maps (the Python face is organised by concept); this alias
stays for one release and warns when imported."""

from __future__ import annotations

import warnings

from vwg.io.maps import *  # noqa: F403
from vwg.io.maps import __all__  # noqa: F401

warnings.warn("vwg.maps is deprecated: import vwg.io.maps instead (the alias goes in the next release)",
              DeprecationWarning, stacklevel=2)
