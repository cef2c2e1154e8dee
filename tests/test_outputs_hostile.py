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


# ---- settings vwg check must refuse as vwg run does -----------------------------------------------------------
def with_line(office: Path, line: str) -> Path:
    """office.yaml with `line` after its wall_height (line 6 of the file)."""
    text = (office / "office.yaml").read_text()
    assert text.splitlines()[4] == "wall_height: 2.5"
    (office / "p.yaml").write_text(text.replace("wall_height: 2.5\n", f"wall_height: 2.5\n{line}\n", 1))
    return office / "p.yaml"


@pytest.mark.parametrize(("platform", "message"), [
    ("{kind: rosbridge, url: 'ws://127.0.0.1:1', watchdog: .nan}", "platform.watchdog: expected a finite number"),
    ("{kind: rosbridge, url: 'ws://127.0.0.1:1', reconnect: -5}", "platform.reconnect: expected a number >= 0"),
    ("{kind: rosbridge, url: 'ws://127.0.0.1:1', watchdog: -1}", "platform.watchdog: expected a number > 0"),
    ("{kind: rosbridge, url: 5}", "platform.url: expected text, got int 5"),
    ("{kind: rosbridge, url: 'ws://127.0.0.1:1', ros: 3}", "platform.ros: expected 1 or 2"),
    ("{kind: serial, port: /dev/zero, wheel_radius: 0}", "platform.wheel_radius: expected a number > 0"),
    ("{kind: serial, port: /dev/zero, ticks_per_rev: 0}", "platform.ticks_per_rev: expected a number > 0"),
    ("{kind: serial, port: /dev/zero, baud: 0}", "platform.baud: expected a number >= 1"),
])
def test_vwg_check_refuses_platform_settings_a_run_refuses(office, platform, message):
    with_line(office, f"platform: {platform}")
    result = vwg("check", "p.yaml", cwd=office)
    assert result.returncode == 2, result.stdout
    assert f"p.yaml:6: {message}" in result.stderr


@pytest.mark.parametrize("height", ["1.0e+12", "100.5"])
def test_a_wall_higher_than_100_m_is_refused_by_its_line(office, height):
    text = (office / "office.yaml").read_text().replace("wall_height: 2.5", f"wall_height: {height}")
    (office / "p.yaml").write_text(text)
    result = vwg("check", "p.yaml", cwd=office)
    assert result.returncode == 2
    assert f"p.yaml:5: wall_height: expected a number <= 100.0, got {float(height)!r}" in result.stderr


def test_a_wall_of_100_m_is_taken(office):
    (office / "p.yaml").write_text((office / "office.yaml").read_text().replace("wall_height: 2.5", "wall_height: 100"))
    assert vwg("check", "p.yaml", cwd=office).returncode == 0


# ---- a record replayed on another world ----------------------------------------------------------------------
def test_replay_on_a_world_whose_map_is_not_the_records_names_both_shapes(office):
    made = vwg("run", "office.yaml", "--frames", "3", "--record", "r.jsonl", "--allow-unreached", cwd=office)
    assert made.returncode == 0, made.stderr
    result = vwg("replay", "r.jsonl", "--world", "maze", cwd=office)
    assert result.returncode == 2, result.stderr
    # office's map is 500 × 360 cells (25 × 18 m at 0.05 m), maze's 302 × 302.
    assert "maze.yaml: its map is 302×302 cells; the record r.jsonl was made on a map of 500×360 cells" \
        in result.stderr
    assert vwg("replay", "r.jsonl", "--world", "office.yaml", cwd=office).returncode == 0


# ---- out of memory during a run ------------------------------------------------------------------------------
@pytest.mark.parametrize("cause", [MemoryError(), RuntimeError("std::bad_alloc")])
def test_running_out_of_memory_in_a_frame_is_exit_2_naming_the_maps_cells(monkeypatch, capsys, cause):
    import vwg.cli
    import vwg.launch
    from vwg.cli import main
    from vwg.errors import FrameError

    real_start = vwg.launch.start

    def start(world, options=None):
        run = real_start(world, options)

        def execute(progress=None):  # as the engine reports a frame whose allocation failed
            raise FrameError("frame 0, evolve of actor ARobot<id=1>: std::bad_alloc") from cause

        run.execute = execute
        return run

    monkeypatch.setattr(vwg.cli, "start", start)  # the command line's start (it imports vwg.launch's)
    assert main(["run", "office", "--frames", "1"]) == 2
    err = capsys.readouterr().err
    # office's map: 500 × 360 = 180,000 cells.
    assert "office: not enough memory for this run (its map has 180,000 cells)" in err
    assert "Traceback" not in err
