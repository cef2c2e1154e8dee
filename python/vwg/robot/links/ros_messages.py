"""ROS messages as rosbridge v2 carries them (JSON), to and from what vwg uses: a Twist from a
velocity command, a pose from an Odometry, the ranges of a LaserScan, a time from a header
stamp. ROS 1 and ROS 2 spellings are both read: type names (``geometry_msgs/Twist`` and
``geometry_msgs/msg/Twist``) and stamps (``secs``/``nsecs`` and ``sec``/``nanosec``). Pure
functions, so a fake robot, a log replayer and the link share them.

Every reader raises ValueError naming the field it could not read; a link logs and drops such a
message (a malformed message never stops a run).
"""

from __future__ import annotations

import base64
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "CompressedImage",
    "LaserScan",
    "Odometry",
    "compressed_image",
    "compressed_image_message",
    "laser_scan",
    "odometry",
    "odometry_message",
    "pose_compose",
    "same_type",
    "scan_message",
    "stamp_message",
    "stamp_seconds",
    "twist_message",
    "twist_of",
    "yaw_of_quaternion",
]


def same_type(a: str, b: str) -> bool:
    """Whether two ROS type names are the same type (``pkg/Name`` and ``pkg/msg/Name`` are)."""
    def norm(t: str) -> str:
        parts = t.strip("/").split("/")
        return "/".join([parts[0], parts[-1]]) if len(parts) == 3 and parts[1] == "msg" else "/".join(parts)
    return norm(a) == norm(b)


def _field(msg: Any, path: str) -> Any:
    value = msg
    for key in path.split("."):
        if not isinstance(value, Mapping) or key not in value:
            raise ValueError(f"{path}: missing")
        value = value[key]
    return value


def _number(msg: Any, path: str) -> float:
    value = _field(msg, path)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{path}: expected a number, got {value!r}")
    return float(value)


def stamp_seconds(stamp: Any) -> float:
    """A header stamp in seconds: ROS 1 ``{secs, nsecs}`` or ROS 2 ``{sec, nanosec}``."""
    if isinstance(stamp, Mapping):
        seconds = None
        if "secs" in stamp:
            seconds = _number(stamp, "secs") + _number(stamp, "nsecs") * 1e-9
        elif "sec" in stamp:
            seconds = _number(stamp, "sec") + _number(stamp, "nanosec") * 1e-9
        if seconds is not None:
            if not math.isfinite(seconds):  # JSON parsers take NaN and Infinity; a reading needs a time
                raise ValueError(f"stamp: expected finite seconds, got {stamp!r}")
            return seconds
    raise ValueError(f"stamp: expected {{secs, nsecs}} or {{sec, nanosec}}, got {stamp!r}")


def stamp_message(seconds: float, ros2: bool = False) -> dict[str, int]:
    whole = math.floor(seconds)
    nanos = min(round((seconds - whole) * 1e9), 999_999_999)
    return {"sec": whole, "nanosec": nanos} if ros2 else {"secs": whole, "nsecs": nanos}


def twist_message(speed: float, turn_rate: float) -> dict[str, Any]:
    """geometry_msgs/Twist: forward speed (m/s) and turn rate (rad/s, counter-clockwise)."""
    return {"linear": {"x": float(speed), "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": float(turn_rate)}}


def twist_of(msg: Any) -> tuple[float, float]:
    """(forward speed, turn rate) of a geometry_msgs/Twist."""
    return _number(msg, "linear.x"), _number(msg, "angular.z")


def yaw_of_quaternion(q: Any) -> float:
    x, y, z, w = (_number(q, k) for k in ("x", "y", "z", "w"))
    if not all(math.isfinite(v) for v in (x, y, z, w)) or x * x + y * y + z * z + w * w < 1e-12:
        raise ValueError("orientation: expected a finite, non-zero quaternion")
    return math.atan2(2.0 * (w * z + x * y), w * w + x * x - y * y - z * z)  # right for any scale


@dataclass(frozen=True)
class Odometry:
    """A robot's own pose estimate (odometry frame, metres and radians) and velocities, at `time`."""

    time: float
    x: float
    y: float
    yaw: float
    speed: float
    turn_rate: float


def odometry(msg: Any) -> Odometry:
    """nav_msgs/Odometry: the pose and twist of ``msg``; ValueError names a missing or bad field."""
    x, y = _number(msg, "pose.pose.position.x"), _number(msg, "pose.pose.position.y")
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError("pose.pose.position: expected finite x and y")
    yaw = yaw_of_quaternion(_field(msg, "pose.pose.orientation"))
    try:
        speed, turn = twist_of(_field(msg, "twist.twist"))
    except ValueError:
        speed, turn = 0.0, 0.0  # a twist is optional for the pose
    return Odometry(stamp_seconds(_field(msg, "header.stamp")), x, y, yaw,
                    speed if math.isfinite(speed) else 0.0, turn if math.isfinite(turn) else 0.0)


def odometry_message(time: float, x: float, y: float, yaw: float, speed: float = 0.0, turn_rate: float = 0.0,
                     ros2: bool = False) -> dict[str, Any]:
    return {
        "header": {"stamp": stamp_message(time, ros2), "frame_id": "odom"},
        "child_frame_id": "base_link",
        "pose": {"pose": {"position": {"x": x, "y": y, "z": 0.0},
                          "orientation": {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}}},
        "twist": {"twist": twist_message(speed, turn_rate)},
    }


def pose_compose(start: Sequence[float], local: Sequence[float]) -> tuple[float, float, float]:
    """start ⊕ local: a pose given in the frame of `start` (odometry starts at zero where the robot
    starts), in the world's frame."""
    sx, sy, st = start
    x, y, t = local
    c, s = math.cos(st), math.sin(st)
    yaw = math.atan2(math.sin(st + t), math.cos(st + t))
    return sx + c * x - s * y, sy + s * x + c * y, yaw


def pose_relative(origin: Sequence[float], pose: Sequence[float]) -> tuple[float, float, float]:
    """origin⁻¹ ⊕ pose: `pose` (world frame) in the frame of `origin`, the inverse of pose_compose."""
    ox, oy, ot = origin
    x, y, t = pose
    c, s = math.cos(ot), math.sin(ot)
    dx, dy = x - ox, y - oy
    return c * dx + s * dy, -s * dx + c * dy, math.atan2(math.sin(t - ot), math.cos(t - ot))


@dataclass(frozen=True, eq=False)
class LaserScan:
    """A sensor_msgs/LaserScan as the message has it: beam i at angle_min + i·angle_increment
    (radians from the heading) read ``ranges[i]`` (metres, float32 as ROS carries them; NaN where the
    message had null), and the scan's limits. Which beams met an obstacle is one rule for every
    laser, simulated or real: ``vwg._core.laser_events`` (C++ platform::laser_events, REP 117)."""

    time: float
    angle_min: float
    angle_increment: float
    ranges: np.ndarray
    range_min: float
    range_max: float


_FLOAT32_MAX = float(np.finfo(np.float32).max)


def _reading(r: Any) -> float:
    """One range as float32 will hold it: null (rosbridge's JSON for NaN and ±Inf alike) and anything
    not a number are NaN (nothing known); a finite value beyond float32's range stays finite."""
    if r is None or isinstance(r, bool) or not isinstance(r, (int, float)):
        return math.nan
    if isinstance(r, int) or math.isfinite(r):
        return float(max(-_FLOAT32_MAX, min(_FLOAT32_MAX, r)))
    return float(r)


def laser_scan(msg: Any) -> LaserScan:
    """sensor_msgs/LaserScan, its fields checked (finite angles, 0 <= range_min < range_max, at
    most 100000 ranges) and its ranges kept as they are, null read as NaN. vwg._core.laser_events
    turns them into obstacles by REP 117's rules."""
    angle_min, increment = _number(msg, "angle_min"), _number(msg, "angle_increment")
    range_min, range_max = _number(msg, "range_min"), _number(msg, "range_max")
    if not all(math.isfinite(v) for v in (angle_min, increment, range_min, range_max)):
        raise ValueError("angle_min, angle_increment, range_min, range_max: expected finite numbers")
    if not 0 <= range_min < range_max:
        raise ValueError(f"range_min, range_max: expected 0 <= range_min < range_max, got {range_min}, {range_max}")
    ranges = _field(msg, "ranges")
    if not isinstance(ranges, Sequence) or isinstance(ranges, (str, bytes)):
        raise ValueError("ranges: expected a list of numbers")
    if len(ranges) > 100_000:
        raise ValueError(f"ranges: {len(ranges)} beams, more than 100000")
    readings = np.array([_reading(r) for r in ranges], dtype=np.float32)
    return LaserScan(stamp_seconds(_field(msg, "header.stamp")), angle_min, increment, readings, range_min, range_max)


@dataclass(frozen=True)
class CompressedImage:
    """A sensor_msgs/CompressedImage: its JPEG or PNG bytes, taken at `time` (its header's stamp)."""

    time: float
    data: bytes


def compressed_image(msg: Any) -> CompressedImage:
    """A sensor_msgs/CompressedImage (JPEG or PNG): rosbridge sends ``data`` (uint8[]) as base64 text;
    a list of byte values is read too."""
    time = stamp_seconds(_field(msg, "header.stamp"))
    fmt = _field(msg, "format")
    if not isinstance(fmt, str) or not any(k in fmt.lower() for k in ("jpeg", "jpg", "png")):
        raise ValueError(f"format: expected jpeg or png, got {fmt!r}")
    data = _field(msg, "data")
    if isinstance(data, str):
        try:
            return CompressedImage(time, base64.b64decode(data, validate=True))
        except ValueError:
            raise ValueError("data: not base64") from None
    if isinstance(data, list) and all(isinstance(b, int) and 0 <= b < 256 for b in data):
        return CompressedImage(time, bytes(data))
    raise ValueError("data: expected base64 text or a list of bytes")


def compressed_image_message(time: float, encoded: bytes, fmt: str = "jpeg", ros2: bool = False) -> dict[str, Any]:
    return {"header": {"stamp": stamp_message(time, ros2), "frame_id": "camera"}, "format": fmt,
            "data": base64.b64encode(encoded).decode("ascii")}


def scan_message(time: float, angle_min: float, angle_increment: float, ranges: Sequence[float], range_min: float,
                 range_max: float, ros2: bool = False) -> dict[str, Any]:
    """sensor_msgs/LaserScan; a beam with no return is +Inf, which JSON cannot hold: null, as rosbridge sends it."""
    return {
        "header": {"stamp": stamp_message(time, ros2), "frame_id": "laser"},
        "angle_min": angle_min, "angle_max": angle_min + angle_increment * max(len(ranges) - 1, 0),
        "angle_increment": angle_increment, "time_increment": 0.0, "scan_time": 0.0,
        "range_min": range_min, "range_max": range_max,
        "ranges": [float(r) if math.isfinite(r) else None for r in ranges], "intensities": [],
    }
