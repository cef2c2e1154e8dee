"""Outputs a hostile or careless command line names (issue 34's re-test): an output that is one of the
run's own inputs, or a named pipe, is refused before the run starts, naming the option and the file,
exit 2; a bad --trajectory type is found before the run, a full disk is named as the system says it."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

VWG = [sys.executable, "-m", "vwg.cli"]


def vwg(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    # The same vwg as this process from another folder (PYTHONPATH=python made absolute). A bounded
    # wait: the old code waited for ever on a named pipe nobody reads.
    paths = [os.path.abspath(p) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    return subprocess.run([*VWG, *args], cwd=cwd, capture_output=True, text=True, timeout=60,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(paths), "PYTHONWARNINGS": "ignore"})


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture
def office(tmp_path: Path) -> Path:
    """A copy of the office world (its world file, map YAML and map image) in tmp_path."""
    shutil.copy(ROOT / "maps" / "office.yaml", tmp_path / "office.yaml")
    shutil.copytree(ROOT / "maps" / "office", tmp_path / "office")
    return tmp_path


# ---- an output that is an input ---------------------------------------------------------------------------
@pytest.mark.parametrize(("flag", "target", "what"), [
    ("--record", "office.yaml", "the world file being run"),
    ("--summary-json", "office/map.yaml", "the world's map"),
    ("--trajectory", "office/map.pgm", "the map's image"),
    ("--video", "./office.yaml", "the world file being run"),  # another spelling of the same file
])
def test_an_output_onto_the_runs_own_input_is_refused(office, flag, target, what):
    before = digest(office / target)
    result = vwg("run", "office.yaml", "--frames", "2", flag, target, cwd=office)
    assert result.returncode == 2, result.stderr
    assert f"{flag} {Path(target)}: this is {what}" in result.stderr and "Traceback" not in result.stderr
    assert digest(office / target) == before


def test_an_output_through_a_symlink_to_the_world_file_is_refused(office):
    (office / "link.jsonl").symlink_to(office / "office.yaml")
    before = digest(office / "office.yaml")
    result = vwg("run", "office.yaml", "--frames", "2", "--record", "link.jsonl", cwd=office)
    assert result.returncode == 2 and "this is the world file being run" in result.stderr
    assert digest(office / "office.yaml") == before


def test_replay_from_does_not_record_over_the_record_it_reads(office):
    made = vwg("run", "office.yaml", "--frames", "3", "--record", "r.jsonl", "--allow-unreached", cwd=office)
    assert made.returncode == 0, made.stderr
    before = digest(office / "r.jsonl")
    result = vwg("replay", "r.jsonl", "--from", "1", "--record", "r.jsonl", cwd=office)
    assert result.returncode == 2, result.stderr
    assert "--record r.jsonl: this is the record being replayed" in result.stderr
    assert digest(office / "r.jsonl") == before


# ---- a named pipe as an output ----------------------------------------------------------------------------
@pytest.mark.parametrize(("flag", "name"), [
    ("--record", "out.jsonl"), ("--summary-json", "out.json"), ("--video", "out.gif"), ("--video", "out.mp4"),
    ("--trajectory", "out.png"),
])
def test_a_named_pipe_as_an_output_is_refused_before_the_run(office, flag, name):
    os.mkfifo(office / name)
    result = vwg("run", "office.yaml", "--frames", "2", flag, name, cwd=office)
    assert result.returncode == 2, result.stderr
    assert f"{flag} {name}: expected a regular file, this is a named pipe" in result.stderr


def test_a_named_pipe_beside_the_video_where_its_trajectory_goes_is_refused(office):
    os.mkfifo(office / "out.png")  # --video out.gif draws its trajectory into out.png
    result = vwg("run", "office.yaml", "--frames", "2", "--video", "out.gif", cwd=office)
    assert result.returncode == 2 and "--trajectory out.png: expected a regular file, this is a named pipe" \
        in result.stderr


def test_replay_from_refuses_a_named_pipe_as_its_record(office):
    made = vwg("run", "office.yaml", "--frames", "3", "--record", "r.jsonl", "--allow-unreached", cwd=office)
    assert made.returncode == 0, made.stderr
    os.mkfifo(office / "new.jsonl")
    result = vwg("replay", "r.jsonl", "--from", "1", "--record", "new.jsonl", cwd=office)
    assert result.returncode == 2 and "--record new.jsonl: expected a regular file, this is a named pipe" \
        in result.stderr


# ---- the trajectory picture and the video: checked before, a full disk named -------------------------------
def test_a_trajectory_of_a_type_not_written_is_refused_before_the_run(office):
    result = vwg("run", "office.yaml", "--frames", "2", "--trajectory", "t.txt", "--summary-json", "s.json",
                 cwd=office)
    assert result.returncode == 2
    assert "--trajectory t.txt: unknown picture type '.txt'; use .png, .jpg, .jpeg" in result.stderr
    assert result.stdout == "" and not (office / "s.json").exists()  # no run was made


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full (a disk that is always full)")
def test_a_trajectory_onto_a_full_disk_is_an_error_with_the_systems_reason(office):
    (office / "full.png").symlink_to("/dev/full")
    result = vwg("run", "office.yaml", "--frames", "2", "--trajectory", "full.png", "--allow-unreached", cwd=office)
    assert result.returncode == 2, result.stderr
    assert "full.png: No space left on device: the trajectory picture could not be written" in result.stderr


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full (a disk that is always full)")
def test_a_gif_onto_a_full_disk_is_an_error_with_the_systems_reason(office):
    (office / "full.gif").symlink_to("/dev/full")
    result = vwg("run", "office.yaml", "--frames", "2", "--video", "full.gif", "--trajectory", "t.png",
                 "--allow-unreached", cwd=office)
    assert result.returncode == 2, result.stderr
    assert "full.gif" in result.stderr and "No space left on device" in result.stderr
    assert "Traceback" not in result.stderr
