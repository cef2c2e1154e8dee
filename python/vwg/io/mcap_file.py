"""A run's ROS 2 messages written to an MCAP file (the ``ros2`` profile: ``ros2msg`` schemas, CDR messages),
as ``ros2 bag record`` writes one: ``ros2 bag play FILE.mcap`` and Foxglove read it.

The container is written by the MCAP project's own Python writer (``mcap``: chunked, zstd, CRCs, the
summary and its index), so nothing here lays out MCAP records by hand.
"""

from __future__ import annotations

from pathlib import Path
from typing import IO

import vwg._core as _core
from vwg.errors import Error
from vwg.io.ros2_messages import Message, Schema

__all__ = ["McapFile"]

#: rmw's "infinite" duration as rosbag2 writes it.
_INFINITE = "\n    sec: 9223372036\n    nsec: 854775807"


def _qos(latched: bool) -> str:
    """The publisher's QoS that the ros2 profile requires on each channel (``offered_qos_profiles``, as rosbag2 9
    writes it): reliable; transient local (latched) for a topic sent when it changes, so that ``ros2 bag play``
    offers it to a late subscriber as a map server does."""
    durability, depth = ("transient_local", 1) if latched else ("volatile", 10)
    return (f"- history: keep_last\n  depth: {depth}\n  reliability: reliable\n  durability: {durability}\n"
            f"  deadline:{_INFINITE}\n  lifespan:{_INFINITE}\n  liveliness: automatic\n"
            f"  liveliness_lease_duration:{_INFINITE}\n  avoid_ros_namespace_conventions: false\n")


class McapFile:
    """Writes messages to `path`: ``write(topic, message, log_time_ns)``, then ``close()`` (which writes the
    summary: a file not closed is read only by a reader that recovers it). ``metadata`` goes in a
    ``vwg`` metadata record (the world, the seed, vwg's version)."""

    def __init__(self, path: str | Path, metadata: dict[str, str] | None = None) -> None:
        from mcap.writer import CompressionType, Writer

        self.path = Path(path)
        try:
            self._file: IO[bytes] | None = self.path.open("wb")
        except OSError as e:
            raise Error(f"{self.path}: {e.strerror}: the MCAP file could not be written") from None
        self._writer = Writer(self._file, compression=CompressionType.ZSTD)
        self._writer.start(profile="ros2", library=f"vwg {_core.__version__}")
        if metadata:
            self._writer.add_metadata("vwg", {k: str(v) for k, v in metadata.items()})
        self._schemas: dict[Schema, int] = {}
        self._channels: dict[str, int] = {}
        self.messages = 0

    def write(self, topic: str, message: Message, log_time: int, latched: bool = False) -> None:
        if self._file is None:
            return
        channel = self._channels.get(topic)
        if channel is None:
            schema = self._schemas.get(message.schema)
            if schema is None:
                schema = self._writer.register_schema(message.schema.name, "ros2msg", message.schema.text.encode())
                self._schemas[message.schema] = schema
            channel = self._channels[topic] = self._writer.register_channel(
                topic, "cdr", schema, {"offered_qos_profiles": _qos(latched)})
        try:
            self._writer.add_message(channel, log_time=log_time, publish_time=log_time, data=message.data)
        except OSError as e:  # a full disk: said with the file's name, not as a traceback
            raise Error(f"{self.path}: {e.strerror}: the MCAP file could not take more messages") from None
        self.messages += 1

    def frame_done(self, log_time: int) -> None:
        pass

    def close(self) -> None:
        if self._file is None:
            return
        try:
            self._writer.finish()
        finally:
            self._file.close()
            self._file = None
