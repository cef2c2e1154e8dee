"""``vwg export RECORD FILE.mcap``: a robot run's record as the MCAP file ``vwg run --mcap`` writes.

The record is read with its own checks (a cut or edited record is refused, naming the line), then its world
is started again as ``vwg replay --from`` starts it: each frame's string is checked against the record and
the frame runs on the recorded events, while the generators run beside it as they did. The messages come
from those frames (vwg.robot.topics), so they are the run's. The simulator beside them gives the ground truth
and the cameras' pictures only while it gives the record's own events: a run on a real robot has none from
the frame where its recorded sensors part from the simulator's.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tqdm import tqdm

from vwg.errors import Error, ReplayError
from vwg.io.mcap_file import McapFile
from vwg.io.record import read_record, robot_data, robot_world_file
from vwg.launch import check_outputs, load, record_options, record_world_path, start, step_as_recorded
from vwg.robot.topics import case_topics, require_ros

__all__ = ["Export", "export_record"]


@dataclass
class Export:
    frames: int
    messages: int
    truth_frames: int  # frames with ground truth (all of them for a run on the simulator)


def export_record(record_path: str | Path, out: str | Path, *, world_file: str | Path | None = None,
                  key: bytes | None = None, progress: bool | None = False, allow_cut: bool = False) -> Export:
    """Write `record_path`'s run to `out` (MCAP). `world_file` replaces the one the record names. A record with no
    end line (its run was killed) is refused unless `allow_cut`, which exports the frames it holds."""
    record_path, out = Path(record_path), Path(out)
    require_ros("mcap", "rosbags")
    record = read_record(record_path, key)
    header = record.header
    if record.cut and not allow_cut:
        where = record.warnings[0] if record.warnings else f"{record_path}:{len(record.frames) + 2}: no end line"
        raise Error(f"{where}; {record.cut}. vwg export --allow-cut writes the {len(record.frames)} whole frames it "
                    "holds")
    kind = header.get("world_kind") or "generic"
    if kind != "robot":
        raise Error(f"{record_path}: the record is of a {kind} world; only a robot world's run has ROS topics to "
                    "export")
    if int(header.get("frame") or 0):
        raise Error(f"{record_path}: the record starts at frame {header['frame']} (its run went on from a saved "
                    "state): export the record of the run that was saved, or run the saved state again with "
                    "vwg resume --mcap")
    path = record_world_path(world_file or robot_world_file(robot_data(header, record_path), record_path), "robot")
    world = load(path)
    options = record_options(header, world, record_path)
    check_outputs(world, dataclasses.replace(options, mcap=out), {"the record": record_path})
    truth_frames = 0
    with start(world, options) as run:
        sink = McapFile(out, {"world": world.name, "planner": run.case.planner, "seed": str(run.case.seed),
                              "record": str(record_path)})
        topics = case_topics(run.case, [sink])
        try:
            def compare(generated: list[Any]) -> None:
                # The simulator no longer senses what the robot sensed: its truth and pictures are not the run's.
                if topics.truth is not None and [str(e) for e in generated] != frame["events"]:
                    topics.truth = None
                    topics.cameras = {}

            for frame in tqdm(record.frames, unit="frame", disable=None if progress is None else not progress):
                try:
                    step_as_recorded(run.engine, frame, record_path, compare)
                except ReplayError as e:
                    raise Error(f"{record_path}: the world {path} does not give the record's frames: {e}") from None
                truth_frames += topics.truth is not None
            if record.end is not None and str(run.engine.string) != record.end["string"]:
                raise Error(f"{record_path}: the world {path} does not give the record's last string")
            topics.end()
        finally:
            topics.close()
    return Export(frames=len(record.frames), messages=sink.messages, truth_frames=truth_frames)

