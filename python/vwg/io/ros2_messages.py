"""ROS 2 messages as a bag or a Foxglove client reads them: CDR bytes of the standard types, with their
``ros2msg`` schema text.

The definitions are ROS 2 Jazzy's, from rosbags' type store (the LTS of 2024-2029; rosbags keeps the
definitions of every distribution and serializes CDR from generated code, so no message is laid out by
hand here). Each builder takes plain vwg values (metres, radians, seconds, numpy arrays) and returns a
``Message``: the type, its schema text and the bytes. Frames follow REP 105: ``map``, then per robot
``robotN/odom`` and ``robotN/base_link``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np

__all__ = [
    "Message",
    "Schema",
    "compressed_image",
    "marker_array",
    "occupancy_grid",
    "odometry",
    "path",
    "scan",
    "schema",
    "tf",
]


@dataclass(frozen=True)
class Schema:
    """A message type by its ROS 2 name (``sensor_msgs/msg/LaserScan``) and its ``ros2msg`` text (the type's
    definition followed by those of the types it uses, as ``ros2 bag`` writes it)."""

    name: str
    text: str


@dataclass(frozen=True)
class Message:
    schema: Schema
    data: bytes


@cache
def _store() -> Any:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_JAZZY)


@cache
def schema(name: str) -> Schema:
    text, _ = _store().generate_msgdef(name, ros_version=2)
    return Schema(name, text)


def _t(name: str) -> Any:
    return _store().types[name]


def _encode(msg: Any) -> Message:
    return Message(schema(msg.__msgtype__), bytes(_store().serialize_cdr(msg, msg.__msgtype__)))


def _stamp(seconds: float) -> Any:
    whole = math.floor(seconds)
    return _t("builtin_interfaces/msg/Time")(sec=whole, nanosec=min(round((seconds - whole) * 1e9), 999_999_999))


def _header(seconds: float, frame: str) -> Any:
    return _t("std_msgs/msg/Header")(stamp=_stamp(seconds), frame_id=frame)


def _quaternion(yaw: float) -> Any:
    return _t("geometry_msgs/msg/Quaternion")(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))


def _pose(x: float, y: float, yaw: float, z: float = 0.0) -> Any:
    return _t("geometry_msgs/msg/Pose")(position=_t("geometry_msgs/msg/Point")(x=float(x), y=float(y), z=float(z)),
                                        orientation=_quaternion(yaw))


def _vector(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Any:
    return _t("geometry_msgs/msg/Vector3")(x=float(x), y=float(y), z=float(z))


def odometry(seconds: float, frame: str, child: str, pose: Sequence[float], speed: float = 0.0,
             turn_rate: float = 0.0) -> Message:
    """nav_msgs/Odometry: `pose` (x, y, yaw) in `frame`, the twist (forward speed, turn rate) in `child`."""
    covariance = np.zeros(36, np.float64)
    return _encode(_t("nav_msgs/msg/Odometry")(
        header=_header(seconds, frame), child_frame_id=child,
        pose=_t("geometry_msgs/msg/PoseWithCovariance")(pose=_pose(*pose), covariance=covariance),
        twist=_t("geometry_msgs/msg/TwistWithCovariance")(
            twist=_t("geometry_msgs/msg/Twist")(linear=_vector(speed), angular=_vector(z=turn_rate)),
            covariance=covariance)))


def scan(seconds: float, frame: str, angle_min: float, angle_increment: float, ranges: np.ndarray,
         range_min: float, range_max: float, scan_time: float = 0.0) -> Message:
    """sensor_msgs/LaserScan: `ranges` (float32, +Inf where a beam met nothing, REP 117) at angle_min +
    i·angle_increment."""
    ranges = np.ascontiguousarray(ranges, np.float32)
    return _encode(_t("sensor_msgs/msg/LaserScan")(
        header=_header(seconds, frame), angle_min=float(angle_min),
        angle_max=float(angle_min + angle_increment * max(len(ranges) - 1, 0)), angle_increment=float(angle_increment),
        time_increment=0.0, scan_time=float(scan_time), range_min=float(range_min), range_max=float(range_max),
        ranges=ranges, intensities=np.zeros(0, np.float32)))


def path(seconds: float, frame: str, points: np.ndarray) -> Message:
    """nav_msgs/Path through `points` (N×2, metres), each pose facing the next point."""
    points = np.asarray(points, np.float64).reshape(-1, 2)
    poses = []
    header = _header(seconds, frame)
    for i, (x, y) in enumerate(points):
        dx, dy = (points[i + 1] - points[i]) if i + 1 < len(points) else (points[i] - points[i - 1]) if i else (0, 0)
        poses.append(_t("geometry_msgs/msg/PoseStamped")(header=header, pose=_pose(x, y, math.atan2(dy, dx))))
    return _encode(_t("nav_msgs/msg/Path")(header=header, poses=poses))


def occupancy_grid(seconds: float, frame: str, cells: np.ndarray, resolution: float,
                   origin: Sequence[float]) -> Message:
    """nav_msgs/OccupancyGrid of `cells` (rows from the bottom, as vwg's grids are: -1 unknown, 0 free, 100
    and more occupied, clipped to 100)."""
    cells = np.asarray(cells)
    height, width = cells.shape
    data = np.clip(cells, -1, 100).astype(np.int8).ravel()
    info = _t("nav_msgs/msg/MapMetaData")(map_load_time=_stamp(seconds), resolution=float(resolution),
                                          width=int(width), height=int(height),
                                          origin=_pose(origin[0], origin[1], origin[2] if len(origin) > 2 else 0.0))
    return _encode(_t("nav_msgs/msg/OccupancyGrid")(header=_header(seconds, frame), info=info, data=data))


def compressed_image(seconds: float, frame: str, encoded: bytes, fmt: str) -> Message:
    """sensor_msgs/CompressedImage: `encoded` bytes in format `fmt` ("jpeg", "png")."""
    return _encode(_t("sensor_msgs/msg/CompressedImage")(header=_header(seconds, frame), format=fmt,
                                                         data=np.frombuffer(encoded, np.uint8)))


def tf(seconds: float, transforms: Sequence[tuple[str, str, Sequence[float]]]) -> Message:
    """tf2_msgs/TFMessage: (parent, child, (x, y, yaw)) transforms, the child's pose in the parent's frame."""
    out = []
    for parent, child, (x, y, yaw) in transforms:
        out.append(_t("geometry_msgs/msg/TransformStamped")(
            header=_header(seconds, parent), child_frame_id=child,
            transform=_t("geometry_msgs/msg/Transform")(translation=_vector(x, y), rotation=_quaternion(yaw))))
    return _encode(_t("tf2_msgs/msg/TFMessage")(transforms=out))


#: visualization_msgs/Marker's types used here.
CYLINDER, TEXT = 3, 9


@dataclass(frozen=True)
class Marker:
    """A marker to draw: a cylinder of `size` (diameter, height) or a text of that height, at (x, y, z)."""

    namespace: str
    id: int
    kind: int
    x: float
    y: float
    z: float
    size: tuple[float, float]
    rgba: tuple[float, float, float, float]
    text: str = ""


def marker_array(seconds: float, frame: str, markers: Sequence[Marker]) -> Message:
    """visualization_msgs/MarkerArray of `markers`."""
    t = _t
    out = []
    header = _header(seconds, frame)
    for m in markers:
        r, g, b, a = m.rgba
        out.append(t("visualization_msgs/msg/Marker")(
            header=header, ns=m.namespace, id=m.id, type=m.kind, action=0, pose=_pose(m.x, m.y, 0.0, m.z),
            scale=_vector(m.size[0], m.size[0], m.size[1]) if m.kind != TEXT else _vector(z=m.size[1]),
            color=t("std_msgs/msg/ColorRGBA")(r=r, g=g, b=b, a=a),
            lifetime=t("builtin_interfaces/msg/Duration")(sec=0, nanosec=0), frame_locked=False, points=[],
            colors=[], texture_resource="",
            texture=t("sensor_msgs/msg/CompressedImage")(header=header, format="", data=np.zeros(0, np.uint8)),
            uv_coordinates=[], text=m.text, mesh_resource="",
            mesh_file=t("visualization_msgs/msg/MeshFile")(filename="", data=np.zeros(0, np.uint8)),
            mesh_use_embedded_materials=False))
    return _encode(t("visualization_msgs/msg/MarkerArray")(markers=out))
