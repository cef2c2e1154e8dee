"""A run's ROS 2 messages served live over the Foxglove WebSocket protocol, by the Foxglove SDK's own server
(``foxglove-sdk``): the Foxglove app connects to ``ws://HOST:PORT`` and shows the topics as they come.

Each server has its own SDK context, so two runs in one process serve their own topics. Topics that are
sent only when they change (the maps, the rooms, the plans) are sent again to a client when it subscribes,
at the next frame: a client that connects late still sees them.

The topics a run will publish are declared before the server takes clients. foxglove-sdk 0.30 advertises a
channel made while a client is connected a moment before it takes subscriptions to it, and refuses a subscribe
sent at once ("Unknown channel ID"): the Foxglove app, which connects as soon as a server is up, then showed
no data on such a topic until it subscribed again.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping
from typing import Any

from vwg.errors import Error
from vwg.io.ros2_messages import Message, Schema

__all__ = ["FoxgloveServer"]


class FoxgloveServer:
    """``write(topic, message, log_time_ns, latched=False)`` logs a message on the topic's channel (declared
    in `topics` before the server starts, or made at its first message and advertised to the clients then);
    ``frame_done(log_time_ns)`` tells the clients the run's time; ``close()`` stops the server. Binds to `host`
    (127.0.0.1 unless said otherwise); port 0 takes a free one (``port`` says which)."""

    def __init__(self, port: int, host: str = "127.0.0.1", name: str = "vwg",
                 topics: Mapping[str, Schema] | None = None) -> None:
        import foxglove
        from foxglove.websocket import Capability

        self._foxglove = foxglove
        self._context = foxglove.Context()
        self._channels: dict[str, Any] = {}
        self._types: dict[str, str] = {}  # each channel's message type
        self._latched: dict[str, Message] = {}  # the last message of each topic sent only when it changes
        self._resend: set[str] = set()
        self._lock = threading.Lock()
        for topic, schema in sorted((topics or {}).items()):
            self._channel(topic, schema)
        try:
            self._server = foxglove.start_server(name=name, host=host, port=port, context=self._context,
                                                 capabilities=[Capability.Time], server_listener=self._Listener(self))
        except Exception as e:  # the SDK says why (the port is taken, the host is not this machine's)
            raise Error(f"--foxglove-port {port}: the Foxglove server could not start on {host}: {e}") from None
        self.port = int(self._server.port)
        self.host = host

    class _Listener:
        def __init__(self, owner: FoxgloveServer) -> None:
            self._owner = owner

        def on_subscribe(self, client: Any, channel: Any) -> None:  # the SDK's thread: noted, sent by the run's
            with self._owner._lock:
                self._owner._resend.add(channel.topic)

        def on_unsubscribe(self, client: Any, channel: Any) -> None:
            pass

    def _channel(self, topic: str, schema: Schema) -> Any:
        given = self._foxglove.Schema(name=schema.name, encoding="ros2msg", data=schema.text.encode())
        channel = self._channels[topic] = self._foxglove.Channel(topic, schema=given, message_encoding="cdr",
                                                                 context=self._context)
        self._types[topic] = schema.name
        return channel

    def write(self, topic: str, message: Message, log_time: int, latched: bool = False) -> None:
        channel = self._channels.get(topic)
        if channel is None:
            channel = self._channel(topic, message.schema)
        elif self._types[topic] != message.schema.name:  # a client would decode it as the declared type
            raise Error(f"Foxglove topic {topic}: declared as {self._types[topic]}, written as {message.schema.name}")
        channel.log(message.data, log_time=log_time)
        if latched:
            self._latched[topic] = message

    def frame_done(self, log_time: int) -> None:
        """The run's time now: the latched topics a client subscribed to since are sent again, then the time."""
        with self._lock:
            resend, self._resend = self._resend, set()
        for topic in sorted(resend & self._latched.keys()):
            self._channels[topic].log(self._latched[topic].data, log_time=log_time)
        self._server.broadcast_time(log_time)

    def close(self) -> None:
        self._server.stop()
