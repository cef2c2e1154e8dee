"""What a run may be told, in world files and on the command line alike (one range, one check): the
engine counts frames and seeds in 64 bits, and a frame time of 5e-324 s would make a second 10**323
frames."""

from __future__ import annotations

import vwg._core as _core

__all__ = ["MAX_DT", "MAX_FRAMES", "MAX_SEED", "MAX_TIME", "MIN_DT"]

#: The largest seed and number of frames (the engine's unsigned 64-bit integers).
MAX_SEED = MAX_FRAMES = 2**64 - 1
#: Seconds per frame: the C++ engine's one range (vwg::kMinDt, kMaxDt), checked by _core.check_dt.
MIN_DT: float = _core.MIN_DT
MAX_DT: float = _core.MAX_DT
#: Seconds from the start of a scripted order or event: 31 years, under 2**63 frames at MIN_DT.
MAX_TIME = 1e9
