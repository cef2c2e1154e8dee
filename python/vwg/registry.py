"""Deprecated: vwg.registry is now vwg.plugins (the Python face is organised by concept); this alias
stays for one release and warns when imported."""

from __future__ import annotations

import warnings

from vwg.plugins import *  # noqa: F403
from vwg.plugins import __all__  # noqa: F401

warnings.warn("vwg.registry is deprecated: import vwg.plugins instead (the alias goes in the next release)",
              DeprecationWarning, stacklevel=2)
