"""Shared test worlds. The actors here are small enough that every expected string in the tests
can be worked out by hand; the pure-Python reference (vwg.testing.reference) is the second method for the
generated cases."""

from __future__ import annotations

import heapq
import math
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import vwg

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))

# A suite started in the background by a shell without job control (`make test &` in a script) inherits SIGINT
# ignored, as POSIX has it, and so would every server a test starts: none would stop on the Ctrl-C the tests send
# it. Python's own handler is taken back here; a handled signal is reset to the default in a child.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def env_with_path(folder: Path) -> dict[str, str]:
    """The environment of a child process that also imports from `folder` (first on PYTHONPATH)."""
    return {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(folder), os.environ.get("PYTHONPATH")]))}


def pip_install_apart(source: Path, target: Path) -> dict[str, str]:
    """The package at `source` installed with pip into `target`, a folder of its own (the venv is left as it was),
    and the environment of a child process that sees it (env_with_path)."""
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-build-isolation", "--target",
                    str(target), str(source)], check=True, capture_output=True)
    return env_with_path(target)


class Counter(vwg.Actor):
    """add<k>: n + k; mul<k>: n * k; show (visual): Lamp<n>."""

    events = ("add", "mul", "show")
    attributes = {"n": 0}

    def on_add(self, e):
        return self.with_(n=self.n + e.k)

    def on_mul(self, e):
        return self.with_(n=self.n * e.k)

    def show_show(self, e):
        return vwg.Sym("Lamp", self.n)


class Mortal(vwg.Actor):
    """die: ε; poke: Move<1.0>(Mortal); glow (visual): Lamp<"m">."""

    events = ("die", "poke", "glow")

    def on_die(self, e):
        return ""

    def on_poke(self, e):
        return vwg.Sym("Move", 1.0)(self)

    def show_glow(self, e):
        return 'Lamp<"m">'


class Splitter(vwg.Actor):
    """split: Splitter<gen+1> . Splitter<gen+1>."""

    events = ("split",)
    attributes = {"gen": 0}

    def on_split(self, e):
        child = self.with_(gen=self.gen + 1)
        return [child, child]


class Tagged(vwg.Actor):
    """poke: hits + 1 (targeted pokes reach only the actor with that id); show: Lamp<id, hits>."""

    events = ("poke", "show")
    attributes = {"id": int, "hits": 0, "label": "t", "on": False}

    def on_poke(self, e):
        return self.with_(hits=self.hits + 1, on=not self.on)

    def show_show(self, e):
        return vwg.Sym("Lamp", self.id, self.hits)


ACTORS = (Counter, Mortal, Splitter, Tagged)


def make_world() -> vwg.World:
    return vwg.World(
        primitives={"Lamp": None, "Robot": {"id": 0}, "Dot": {"a": 0, "b": 0.0, "s": "", "f": False}},
        transformations={"Move": {"dist": 0.0}, "Rotate": {"angle": 0.0}, "Group": None},
        events={"add": {"k": 0}, "mul": {"k": 1}, "die": None, "poke": None, "split": None,
                "show": None, "glow": None, "tick": None},
        visual=["show", "glow"],
        actors=ACTORS,
    )


@pytest.fixture
def world() -> vwg.World:
    return make_world()


def plain_dijkstra(blocked, goal):
    """A textbook Dijkstra on the 8-connected grid without corner cutting, written out here."""
    rows, cols = blocked.shape
    dist = np.full(blocked.shape, math.inf)
    if blocked[goal]:
        return dist
    dist[goal] = 0.0
    heap = [(0.0, goal)]
    while heap:
        d, (r, c) = heapq.heappop(heap)
        if d > dist[r, c]:
            continue
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if (dr or dc) and 0 <= nr < rows and 0 <= nc < cols and not blocked[nr, nc]:
                    if dr and dc and (blocked[r + dr, c] or blocked[r, c + dc]):
                        continue
                    nd = d + (math.sqrt(2) if dr and dc else 1.0)
                    if nd < dist[nr, nc]:
                        dist[nr, nc] = nd
                        heapq.heappush(heap, (nd, (nr, nc)))
    return dist


def _signal_state() -> tuple[str, str, object]:
    """The process's ignored and the main thread's blocked signals (the kernel's view, which child processes
    inherit), and SIGINT's Python handler."""
    import signal
    import threading

    status = Path("/proc/self/status").read_text() if Path("/proc/self/status").exists() else ""
    fields = dict(line.split(":\t", 1) for line in status.splitlines() if ":\t" in line)
    blocked = sorted(signal.pthread_sigmask(signal.SIG_BLOCK, [])) if threading.current_thread() is \
        threading.main_thread() else []
    return fields.get("SigIgn", "").strip(), str(blocked), signal.getsignal(signal.SIGINT)


@pytest.fixture(autouse=True)
def _signals_left_as_found():
    # A test that leaves a signal ignored or blocked leaks it to every process the worker starts later: a server
    # started by another test then never sees its Ctrl-C. The test that did it fails here, by name.
    before = _signal_state()
    yield
    after = _signal_state()
    assert after == before, f"the test changed the process's signals: {before} -> {after}"
