"""The engine: the system algorithm of paper §II.D over a world."""

from __future__ import annotations

import sys
from collections.abc import Iterable

import vwg._core as _core
from vwg.model.generators import AnyGenerator, resolve_generators
from vwg.model.world import World

__all__ = ["Engine"]


class Engine(_core.Engine):
    """Runs a world frame by frame::

        engine = vwg.Engine(world, "Blinker<on=true>", generators=[vwg.every_frame("tick")],
                            backend=vwg.TraceBackend(), seed=1)
        engine.run(frames=100)
        print(engine.string)

    Each frame: S = the generators' events in priority order (the order given), w_next = η(w, S),
    v = π(w, Z), φ(v) on the backend, w = w_next. ``dt`` is the simulated time of a frame and
    ``seed`` fixes every random choice (same world, seed and generators: same trace);
    ``first_frame`` is the number of the first frame (replays start where their record did);
    a frame that would grow the string past ``max_symbols`` (if not 0) fails with a FrameError;
    ``threads`` (0: the machine's cores) run the robots' lasers and λ side by side, with the same
    frames for any count."""

    def __init__(
        self,
        world: World,
        initial: _core.String | str,
        generators: Iterable[AnyGenerator] = (),
        backend: _core.Backend | None = None,
        *,
        dt: float = 0.1,
        seed: int = 0,
        first_frame: int = 0,
        max_symbols: int = 0,
        threads: int = 0,
    ) -> None:
        if isinstance(initial, str):
            initial = world.parse(initial, source="<initial string>")
        super().__init__(initial, resolve_generators(world.alphabet, generators), backend, dt, seed, first_frame,
                         max_symbols, threads)
        self.world = world

    def run(self, frames: int, progress: bool | None = False) -> str:  # type: ignore[override]
        """Run until the string is empty ('empty'), `frames` frames ran ('frames') or
        request_stop() was called ('stopped'). ``progress=True`` shows a progress bar (None: only
        on a terminal)."""
        if progress is False or frames <= 0:
            return super().run(frames)
        from tqdm import tqdm

        done = 0
        step = max(1, frames // 100)
        reason = "frames"
        with tqdm(total=frames, unit="frame", disable=None if progress is None else False, file=sys.stderr) as bar:
            while done < frames:
                start = self.frame
                reason = super().run(min(step, frames - done))
                bar.update(self.frame - start)
                done += self.frame - start
                if reason != "frames":
                    break
        return reason

    def __repr__(self) -> str:
        return f"vwg.Engine(frame={self.frame}, symbols={len(self.string)})"

