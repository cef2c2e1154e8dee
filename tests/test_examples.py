"""Every example runs (02_python_decider through the README test, cpp through `make cpp-package`);
the fireflies world keeps a living swarm and draws it."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from conftest import ROOT
from vwg.cli import main
from vwg.io.record import read_record

FIREFLIES = ROOT / "examples" / "01_fireflies" / "world.yaml"


def test_fireflies_live_through_the_whole_run_and_are_drawn(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    record = tmp_path / "run.jsonl"
    assert main(["run", str(FIREFLIES), "--record", str(record), "-q"]) == 0
    frames = read_record(record).frames
    assert len(frames) == 400
    # The string at the start of every frame holds fireflies: the swarm neither dies out nor grows
    # without bound (the food generator feeds about 12).
    alive = [f["string"].count("Firefly<") for f in frames]
    assert min(alive) >= 1 and max(alive) <= 30, (min(alive), max(alive))
    assert len(set(alive)) > 3  # it changes: births and deaths
    gif = tmp_path / "fireflies.gif"
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                            "stream=nb_read_frames,width,height", "-of", "csv=p=0", str(gif)],
                           capture_output=True, text=True, check=True)
    width, height, count = (int(v) for v in probe.stdout.strip().split(","))
    assert (width, height) == (240, 240) and count == 400
    # Lit fireflies are drawn as yellow glows on the dark field (a firefly blinks: it is lit in one
    # of two consecutive frames).
    two = subprocess.run(["ffmpeg", "-v", "error", "-i", str(gif), "-vf", r"select=between(n\,200\,201)",
                          "-vsync", "0", "-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
                         capture_output=True, check=True).stdout
    images = np.frombuffer(two, np.uint8).reshape(2, 240, 240, 3)
    yellow = (images[..., 0] > 150) & (images[..., 1] > 130) & (images[..., 2] < 120)
    assert yellow.sum() > 20


def test_python_decider_example_reaches_the_kitchen():
    done = subprocess.run([sys.executable, str(ROOT / "examples" / "02_python_decider" / "run.py")],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert "robot 1 to kitchen: reached" in done.stdout
