"""A rosbridge v2 client (JSON over WebSocket, the ``websockets`` library) on a thread of its own:
vwg advertises and publishes topics and subscribes to others on a robot's rosbridge server, and
the run goes on while the link waits for the network.

The link keeps what it advertised and subscribed, and says so again after a reconnection. A
message that is not JSON, not a mapping, larger than ``max_message`` or that a handler cannot
read is logged and dropped: it never stops the link. A lost connection is retried with backoff for
``reconnect`` seconds; after that the link has ``failed`` (with the reason), and a platform on it
ends the run. Every connection made and lost is told to ``on_state``; ``connection`` numbers them
(1 for the first), and ``publish(..., connection=n)`` sends only over connection ``n``.

A service call is answered over the connection it went out on, or not at all: when that connection drops
first, the call raises CallLostError at once (``sent``: it had gone out, so the service may have run), and
it is the caller's to say whether calling again is safe (a lockstep step is, when the service knows its
step id).

    link = RosbridgeLink("ws://127.0.0.1:9090", on_message=lambda topic, msg: ...)
    link.connect()
    link.advertise("/cmd_vel", "geometry_msgs/Twist")
    link.subscribe("/odom", "nav_msgs/Odometry")
    link.publish("/cmd_vel", twist_message(0.2, 0.0))
    link.call_service("/step", {"seconds": 0.01}, timeout=0.5)
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import json
import logging
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future
from concurrent.futures import TimeoutError as FutureTimeout
from typing import Any

from vwg.errors import Error

__all__ = ["CallLostError", "LinkError", "RosbridgeLink"]

log = logging.getLogger("vwg.robot.links.rosbridge_client")


class LinkError(Error):
    """A robot's link failed: it could not connect, or it was lost and did not come back in time."""


class CallLostError(LinkError):
    """A service call got no answer because its connection was not up (``sent`` False: it never went out)
    or dropped before the answer came (``sent`` True: the service may have run)."""

    def __init__(self, message: str, *, sent: bool) -> None:
        super().__init__(message)
        self.sent = sent


class RosbridgeLink:
    """One WebSocket connection to a rosbridge server. ``on_message(topic, msg)`` runs on the link's
    thread for every message published to a subscribed topic; ``on_state(connected, detail)`` on
    the same thread when a connection comes (before any of its messages) or goes (``detail``: why).

    Keepalive: a ping every second or so (at most half the ``reconnect`` time, at least 0.5 s); a pong that
    has not come within ``ping_timeout`` seconds (default: the ping's period) drops the connection, which
    notices a peer gone without closing (power, Wi-Fi) within the reconnect time. A peer that closes or
    crashes is seen at once, whatever the pings."""

    def __init__(self, url: str, *, on_message: Callable[[str, Any], None],
                 on_state: Callable[[bool, str], None] | None = None, reconnect: float = 5.0,
                 connect_timeout: float = 5.0, max_message: int = 8 * 1024 * 1024,
                 ping_timeout: float | None = None) -> None:
        if not url.startswith(("ws://", "wss://")):
            raise LinkError(f"rosbridge url: expected ws://HOST:PORT or wss://HOST:PORT, got {url!r}")
        self.url = url
        self.reconnect = reconnect
        self.ping_interval = max(0.5, min(1.0, reconnect / 2))
        self.ping_timeout = self.ping_interval if ping_timeout is None else max(self.ping_interval, ping_timeout)
        self.connect_timeout = connect_timeout
        self.max_message = max_message
        self._on_message = on_message
        self._on_state = on_state or (lambda connected, detail: None)
        self._topics: dict[str, tuple[str, str]] = {}  # topic -> (op, type): what to say again on reconnection
        self._topics_lock = threading.Lock()
        self._loop = asyncio.new_event_loop()
        self._ws: Any = None
        self._connected = threading.Event()
        self._closing = False
        self.failed: str | None = None  # why the link gave up, once it has
        self.connection = 0             # connections made so far: the current one's number while up
        self._last_error = "closed"     # why the last connection attempt ended
        self.dropped = 0                # malformed or oversized messages logged and ignored
        self._calls: dict[str, tuple[str, Future[Any]]] = {}  # call_service ids waiting: (service, answer)
        self._call_ids = itertools.count(1)
        self._thread = threading.Thread(target=self._loop.run_forever, name="vwg-rosbridge", daemon=True)
        self._thread.start()
        self._task: Any = None

    # ---- connection ------------------------------------------------------------------------------------------
    def connect(self) -> None:
        """Connect (within connect_timeout seconds) and keep the connection up from then on."""
        self._task = asyncio.run_coroutine_threadsafe(self._run(), self._loop)
        if not self._connected.wait(self.connect_timeout + 1.0):
            reason = self.failed or f"no answer within {self.connect_timeout:g} s"
            self.close()
            raise LinkError(f"rosbridge {self.url}: cannot connect: {reason}")

    @property
    def connected(self) -> bool:
        return self._connected.is_set()

    async def _run(self) -> None:
        # The link ends failed or closed, never silently: a platform waiting for it to come back polls
        # ``failed``, so an error escaping the connection loop (a callback's, say) must end up there.
        try:
            await self._keep_connected()
        except asyncio.CancelledError:
            raise
        except BaseException as e:
            self.failed = self.failed or f"the link to {self.url} stopped: {type(e).__name__}: {e}"
            log.exception("rosbridge %s: the link stopped", self.url)
            raise
        finally:
            self._connected.clear()

    async def _keep_connected(self) -> None:
        import websockets

        lost_at: float | None = None
        delay = 0.1
        opened = False  # a connection was made on this pass (its loss is told to on_state)
        while not self._closing:
            try:
                async with websockets.connect(self.url, open_timeout=self.connect_timeout, max_size=None,
                                              ping_interval=self.ping_interval, ping_timeout=self.ping_timeout,
                                              close_timeout=1.0) as ws:
                    # Up from the handshake on: a server that closes while vwg declares its topics
                    # has dropped a connection too (and counts towards a platform's flap limit).
                    self._ws = ws
                    self.connection += 1
                    opened = True
                    if lost_at is not None:  # a platform on the link reports it (a fault)
                        log.info("rosbridge %s: connected again after %.2f s", self.url, time.monotonic() - lost_at)
                    self._on_state(True, "")
                    with self._topics_lock:
                        declared = list(self._topics.items())
                    for topic, (op, kind) in declared:
                        await ws.send(json.dumps(self._op(op, topic, kind)))
                    self._connected.set()
                    lost_at, delay = None, 0.1
                    async for text in ws:
                        self._receive(text)
                    self._last_error = "closed by the server"
            except asyncio.CancelledError:
                raise
            except Exception as e:  # refused, reset, closed, timed out: all mean "not connected"
                reason = f"{type(e).__name__}: {e}" if str(e) else type(e).__name__
                if opened or lost_at is None:
                    log.info("rosbridge %s: link lost or refused (%s)", self.url, reason)
                self._last_error = reason
            self._ws = None
            self._connected.clear()
            if opened:
                opened = False
                self._lose_calls(self._last_error)
                self._on_state(False, self._last_error)
            if self._closing:
                break
            now = time.monotonic()
            lost_at = now if lost_at is None else lost_at
            if now - lost_at >= self.reconnect:
                self.failed = (f"the link to {self.url} was lost and did not come back within "
                               f"{self.reconnect:g} s ({self._last_error})")
                log.error("rosbridge: %s", self.failed)
                return
            await asyncio.sleep(delay)
            delay = min(delay * 2, 1.0)

    def _lose_calls(self, reason: str) -> None:
        """The connection dropped: no call still waiting will be answered (an answer comes over the connection
        its call went out on), so each raises CallLostError now rather than at its timeout."""
        for call_id, (service, answer) in list(self._calls.items()):
            self._calls.pop(call_id, None)
            with contextlib.suppress(Exception):  # answered or given up on meanwhile
                answer.set_exception(CallLostError(
                    f"rosbridge {self.url}: the connection dropped before {service} answered ({reason})", sent=True))

    def _receive(self, text: str | bytes) -> None:
        if len(text) > self.max_message:
            self.dropped += 1
            log.warning("rosbridge %s: dropped a message of %d bytes (more than %d)", self.url, len(text),
                        self.max_message)
            return
        try:
            message = json.loads(text)
        except (ValueError, UnicodeDecodeError) as e:
            self.dropped += 1
            log.warning("rosbridge %s: dropped a message that is not JSON (%s)", self.url, e)
            return
        if not isinstance(message, dict):
            self.dropped += 1
            log.warning("rosbridge %s: dropped a message that is not a JSON object", self.url)
            return
        op = message.get("op")
        if op == "publish" and isinstance(message.get("topic"), str):
            try:
                self._on_message(message["topic"], message.get("msg"))
            except Exception as e:  # a message a handler cannot read is dropped, not the run
                self.dropped += 1
                log.warning("rosbridge %s: dropped a message on %s (%s)", self.url, message["topic"], e)
        elif op == "service_response" and isinstance(message.get("id"), str) and message["id"] in self._calls:
            _, call = self._calls.pop(message["id"])
            if message.get("result", True) is False:
                call.set_exception(LinkError(f"rosbridge {self.url}: service {message.get('service')} failed: "
                                             f"{message.get('values')}"))
            else:
                call.set_result(message.get("values"))
        elif op == "status":
            log.info("rosbridge %s: %s: %s", self.url, message.get("level"), message.get("msg"))
        else:
            self.dropped += 1
            log.debug("rosbridge %s: ignored op %r", self.url, op)

    # ---- topics -------------------------------------------------------------------------------------------------
    @staticmethod
    def _op(op: str, topic: str, kind: str) -> dict[str, Any]:
        if op == "subscribe":
            return {"op": "subscribe", "topic": topic, "type": kind, "queue_length": 1, "throttle_rate": 0}
        return {"op": "advertise", "topic": topic, "type": kind}

    def advertise(self, topic: str, kind: str) -> None:
        with self._topics_lock:
            self._topics[topic] = ("advertise", kind)
        self._send(self._op("advertise", topic, kind))

    def subscribe(self, topic: str, kind: str) -> None:
        with self._topics_lock:
            self._topics[topic] = ("subscribe", kind)
        self._send(self._op("subscribe", topic, kind))

    def publish(self, topic: str, msg: dict[str, Any], connection: int | None = None) -> bool:
        """Send `msg` on `topic` (advertised first); False when not connected (the message is lost),
        or when `connection` is given and is no longer the one that is up."""
        return self._send({"op": "publish", "topic": topic, "msg": msg}, connection=connection)

    def wait_connected(self, timeout: float) -> bool:
        """Wait up to `timeout` seconds for a connection to be up; whether one is."""
        return self._connected.wait(timeout)

    def call_service(self, service: str, args: dict[str, Any], timeout: float, connection: int | None = None) -> Any:
        """Call `service` and wait for its response's values; messages published before the response
        have been handled when it returns (one connection keeps the order). With `connection`, only over
        that connection. CallLostError when not connected (or `connection` is no longer the one up) or when
        the connection drops before the answer; LinkError when the service fails, or after `timeout`
        seconds without an answer."""
        call_id = f"vwg_call_{next(self._call_ids)}"
        answer: Future[Any] = Future()
        self._calls[call_id] = (service, answer)
        try:
            if not self._send({"op": "call_service", "id": call_id, "service": service, "args": args},
                              connection=connection):
                raise CallLostError(f"rosbridge {self.url}: cannot call {service}: not connected", sent=False)
            return answer.result(timeout)
        except FutureTimeout:
            raise LinkError(f"rosbridge {self.url}: service {service} did not answer within {timeout:g} s") from None
        finally:
            self._calls.pop(call_id, None)

    def _send(self, message: dict[str, Any], timeout: float = 1.0, connection: int | None = None) -> bool:
        ws = self._ws
        if ws is None or not self._connected.is_set():
            return False
        text = json.dumps(message, allow_nan=False)

        async def send() -> bool:
            # Checked on the link's thread, which alone changes connections: no new one can come
            # between this check and the send, and a connection that has dropped sends nothing more.
            if self._ws is not ws or (connection is not None and connection != self.connection):
                return False
            await ws.send(text)
            return True

        try:
            return asyncio.run_coroutine_threadsafe(send(), self._loop).result(timeout)
        except Exception as e:  # closed under us: the reconnection loop takes it from here
            log.debug("rosbridge %s: send failed (%s)", self.url, e)
            return False

    def close(self) -> None:
        """Close the connection and stop the thread (idempotent)."""
        if self._closing:
            return
        self._closing = True
        ws = self._ws

        async def shut() -> None:
            if self._task is not None:
                self._task.cancel()  # first: the loop ends even if the peer never answers the close
            if ws is not None:
                await ws.close()

        with contextlib.suppress(Exception):  # already closed or the loop is gone: nothing left to close
            asyncio.run_coroutine_threadsafe(shut(), self._loop).result(2.0)
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join(2.0)
        if not self._thread.is_alive():
            self._loop.close()
        self._connected.clear()
