"""``vwg serve``: a robot world running live, shown in the browser, with orders given by clicking.

aiohttp serves the page (plain HTML and JavaScript from the package: no build step, no CDN), a JSON
API and a WebSocket. I chose aiohttp for its HTTP server and WebSocket in one asyncio library (the
``websockets`` library that carries rosbridge serves WebSockets, not pages).

- ``GET /``: the page; ``/static/...``: its script and style.
- ``GET /api/world``: the map's size and placement, the rooms (name, marker, where), the robots.
- ``GET /api/map.png``: the map drawn from above, with the rooms' markers.
- ``GET /api/state``: frame, time, status and ``robots``: id, x, y, angle, objective (a room or null),
  reached.
- ``GET /api/camera/{id}.jpg``: the selected robot's last camera image; ``GET /api/overview.png``: the
  world in 3D with the robots where they are now.
- ``/ws``: a frame message after each frame (the latest only: a slow client skips frames, it never
  slows the run); the page sends ``order``, ``cancel``, ``select``, ``pause``, ``resume``, ``step``, ``speed``,
  ``reset`` messages (JSON). A message that cannot be done gets ``{"type": "error", "message": ...}``
  back; one over MAX_MESSAGE (4,096) bytes closes that connection (code 1009); 4,096 bytes are taken.
  A client's commands wait in a queue bounded per client (vwg.serve.live.MAX_WAITING): one over is
  answered with an error. Other clients go on.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import threading
import time
from collections.abc import Hashable
from importlib import resources
from pathlib import Path
from typing import Any

from aiohttp import WSCloseCode, WSMsgType, web

import vwg._core as _core
from vwg.errors import Error
from vwg.serve.live import LiveRun, Snapshot
from vwg.trial import replace_robot

__all__ = ["MAX_MESSAGE", "Viewer", "serve"]

MAX_MESSAGE = 4096  # bytes a message from the page may have (it sends a few dozen); one over closes
STATIC = Path(str(resources.files("vwg"))) / "serve" / "static"
MAP_WIDTH = 900  # pixels of the map image
OVERVIEW_SECONDS = 1.0  # the 3D view is drawn again at most this often


class Viewer:
    """The web application of a LiveRun: ``app`` (aiohttp), ``clients``, ``dropped`` (frames a slow
    client skipped)."""

    def __init__(self, live: LiveRun) -> None:
        self.live = live
        self.loop: asyncio.AbstractEventLoop | None = None
        self.clients: set[web.WebSocketResponse] = set()
        self.dropped = 0
        self._wake: asyncio.Event | None = None
        self._wake_pending = threading.Event()
        self._overview_lock: asyncio.Lock | None = None
        world = live.world
        self.renderer = _core.TopDownRenderer(world.grid, width=MAP_WIDTH, header=0)
        self.renderer.begin()
        for room in world.rooms.values():
            self.renderer.draw_marker(room.at[0], room.at[1], room.facing, room.name, room.marker)
        self.map_png = _core.encode_image(self.renderer.image(), "png")
        self._overview: tuple[float, bytes] | None = None
        self.app = web.Application(client_max_size=MAX_MESSAGE, middlewares=[self._same_origin])
        self.hosts: set[str] = set()  # the Host headers this server answers to (set by serve() once it listens)
        self.app.add_routes([
            web.get("/", self.index), web.get("/api/world", self.world), web.get("/api/map.png", self.map_image),
            web.get("/api/state", self.state), web.get("/api/camera/{robot}.jpg", self.camera),
            web.get("/api/overview.png", self.overview), web.get("/ws", self.websocket),
            web.static("/static", STATIC),
        ])
        self.app.on_startup.append(self._started)
        self.app.on_shutdown.append(self._closing)
        live.on_frame = self._on_frame

    # ---- the run's side: never blocks ------------------------------------------------------------------
    def _on_frame(self, snapshot: Snapshot) -> None:
        loop, wake = self.loop, self._wake
        if loop is None or wake is None or self._wake_pending.is_set():
            return  # a wake-up is on its way already (at full speed frames come faster than the loop turns)
        self._wake_pending.set()
        with contextlib.suppress(RuntimeError):  # the loop closed meanwhile
            loop.call_soon_threadsafe(self._wake_up)

    def _wake_up(self) -> None:
        self._wake_pending.clear()
        if self._wake is not None:
            self._wake.set()

    async def _started(self, app: web.Application) -> None:
        self.loop = asyncio.get_running_loop()
        self._wake = asyncio.Event()

    async def _closing(self, app: web.Application) -> None:
        async def close(ws: web.WebSocketResponse) -> None:
            with contextlib.suppress(Exception):
                await asyncio.wait_for(ws.close(code=WSCloseCode.GOING_AWAY, message=b"the server is stopping"), 2)

        await asyncio.gather(*(close(ws) for ws in list(self.clients)))
        await asyncio.to_thread(self.live.stop)

    @web.middleware
    async def _same_origin(self, request: web.Request, handler: Any) -> web.StreamResponse:
        """Only requests for this server by its own name (no DNS rebinding), and WebSockets only from
        its own page (another site open in the browser cannot drive the robots)."""
        if self.hosts and request.host not in self.hosts:
            raise web.HTTPForbidden(text=f"vwg serve answers to {', '.join(sorted(self.hosts))}, not {request.host}")
        # Every Origin header is checked: a request with two (its own, then a foreign one) is not its page's.
        origins = request.headers.getall("Origin", [])
        if len(origins) > 1:
            raise web.HTTPForbidden(text=f"vwg serve takes orders from its own page: {len(origins)} Origin headers")
        if origins and origins[0] not in {f"http://{h}" for h in self.hosts | {request.host}}:
            raise web.HTTPForbidden(text=f"vwg serve takes orders from its own page, not from {origins[0]}")
        return await handler(request)

    # ---- pages and the API -----------------------------------------------------------------------------
    async def index(self, request: web.Request) -> web.StreamResponse:
        return web.FileResponse(STATIC / "index.html")

    async def world(self, request: web.Request) -> web.Response:
        world = self.live.world
        # The map image's pixels from world metres: px = ax * x + bx, py = ay * y + by (the renderer's own
        # mapping, read at two points).
        x0, y0 = self.renderer.pixel_to_world(0, 0)
        x1, y1 = self.renderer.pixel_to_world(100, 100)
        ax, ay = 100 / (x1 - x0), 100 / (y1 - y0)
        image = self.renderer.image()
        return web.json_response({
            "name": world.name, "dt": world.dt, "planner": self.live.planner,
            "map": {"width": int(image.shape[1]), "height": int(image.shape[0]),
                    "ax": ax, "bx": -ax * x0, "ay": ay, "by": -ay * y0},
            "rooms": [{"name": name, "marker": room.marker, "x": room.at[0], "y": room.at[1],
                       "goal": list(room.goal)} for name, room in world.rooms.items()],
            "robots": [{"id": r.id, "radius": r.radius, "colour": list(self.renderer.robot_colour(r.id))}
                       for r in world.robots],
        })

    async def map_image(self, request: web.Request) -> web.Response:
        return web.Response(body=self.map_png, content_type="image/png")

    async def state(self, request: web.Request) -> web.Response:
        return web.json_response(self.live.latest.state())

    async def camera(self, request: web.Request) -> web.Response:
        snapshot = self.live.latest
        robot = request.match_info["robot"]
        if str(snapshot.selected) != robot:
            raise web.HTTPNotFound(text=f"robot {robot} is not the selected robot (select it first)")
        if snapshot.camera is None:
            raise web.HTTPNotFound(text=f"robot {robot} has no camera image (yet)")
        body = await asyncio.to_thread(_core.encode_image, snapshot.camera, "jpeg", 85)
        return web.Response(body=body, content_type="image/jpeg", headers={"Cache-Control": "no-store"})

    async def overview(self, request: web.Request) -> web.Response:
        if self._overview_lock is None:
            self._overview_lock = asyncio.Lock()
        async with self._overview_lock:  # one drawing at a time, shared by every client asking meanwhile
            now = time.monotonic()
            if self._overview is None or now - self._overview[0] > OVERVIEW_SECONDS:
                body = await asyncio.to_thread(self._render_overview, self.live.latest)
                self._overview = (time.monotonic(), body)
        return web.Response(body=self._overview[1], content_type="image/png", headers={"Cache-Control": "no-store"})

    def _render_overview(self, snapshot: Snapshot) -> bytes:

        world = self.live.world
        where = {r["id"]: (r["x"], r["y"], r["angle"]) for r in snapshot.robots}
        robots: list[Any] = [replace_robot(r, start=where.get(r.id, r.start)) for r in world.robots]
        # People as cylinders too, where they are: bodies of id -(their id), which the view draws in sand.
        robots += [{"x": p["x"], "y": p["y"], "radius": p["radius"], "id": -p["id"]} for p in snapshot.people]
        image = _core.render_overview(world.grid, markers=world.rooms, robots=robots, wall_height=world.wall_height,
                                      width=640, height=420, supersample=1)
        return bytes(_core.encode_image(image, "png"))

    # ---- the WebSocket ---------------------------------------------------------------------------------
    async def websocket(self, request: web.Request) -> web.WebSocketResponse:
        # aiohttp refuses a plain message of max_msg_size bytes or more, but a compressed one only when
        # it inflates to more: its limit is one over ours, and a compressed message of exactly that is
        # refused here (too_big).
        ws = web.WebSocketResponse(max_msg_size=MAX_MESSAGE + 1, heartbeat=20)
        await ws.prepare(request)
        self.clients.add(ws)
        sender = asyncio.create_task(self._send_frames(ws))
        try:
            async for msg in ws:
                if msg.type in (WSMsgType.TEXT, WSMsgType.BINARY) and too_big(msg.data):
                    await ws.close(code=WSCloseCode.MESSAGE_TOO_BIG,
                                   message=f"message over {MAX_MESSAGE} bytes".encode())
                    break
                if msg.type == WSMsgType.TEXT:
                    reply = self.handle(msg.data, client=ws)
                    if reply is not None:
                        await ws.send_json(reply)
                elif msg.type == WSMsgType.BINARY:
                    await ws.send_json({"type": "error", "message": "expected a JSON text message, got binary data"})
                elif msg.type == WSMsgType.ERROR:
                    break
        finally:
            sender.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await sender
            self.clients.discard(ws)
        return ws

    async def _send_frames(self, ws: web.WebSocketResponse) -> None:
        """Send the latest frame whenever there is a newer one than the last sent; frames that came
        while a send was under way are skipped (counted in ``dropped``)."""
        assert self._wake is not None
        sent = 0
        while not ws.closed:
            snapshot = self.live.latest
            if snapshot.serial != sent:
                if sent and snapshot.serial > sent + 1:
                    self.dropped += snapshot.serial - sent - 1
                sent = snapshot.serial
                text = snapshot.text if snapshot.text is not None else await asyncio.to_thread(snapshot.encode)
                try:
                    await ws.send_str(text)
                except (ConnectionError, RuntimeError):
                    return
                continue
            self._wake.clear()
            if self.live.latest.serial == sent:
                with contextlib.suppress(asyncio.TimeoutError):
                    await asyncio.wait_for(self._wake.wait(), timeout=1.0)

    def handle(self, text: str, client: Hashable = None) -> dict[str, Any] | None:
        """Do what a message from the page asks; an error message back when it cannot be done (or when
        `client` has too many commands waiting: vwg.serve.live.MAX_WAITING)."""
        try:
            message = json.loads(text)
        except json.JSONDecodeError as e:
            return {"type": "error", "message": f"malformed JSON at line {e.lineno}, column {e.colno}: {e.msg}"}
        except RecursionError:
            return {"type": "error", "message": "malformed JSON: nested too deeply"}
        if not isinstance(message, dict) or not isinstance(message.get("type"), str):
            return {"type": "error", "message": "expected a JSON object with a \"type\" (order, cancel, select, "
                                                "pause, resume, step, speed, reset)"}
        kind = message["type"]
        try:
            if kind == "order":
                robot = message.get("robot", self.live.latest.selected)
                self.live.order(robot, message.get("room"), client=client)
                room = message.get("room")
                return {"type": "ok", "what": f"robot {robot} to {room}"}
            if kind == "cancel":
                robot = message.get("robot", self.live.latest.selected)
                self.live.cancel(robot, client=client)
                return {"type": "ok", "what": f"robot {robot}: task interrupted"}
            if kind == "select":
                self.live.select(message.get("robot"), client=client)
            elif kind == "pause":
                self.live.pause(client=client)
            elif kind == "resume":
                self.live.resume(client=client)
            elif kind == "step":
                self.live.step(client=client)
            elif kind == "speed":
                self.live.set_speed(message.get("value"), client=client)
            elif kind == "reset":
                self.live.reset(client=client)
            else:
                return {"type": "error", "message": f"unknown message type {kind!r} (expected order, cancel, select, "
                                                    "pause, resume, step, speed, reset)"}
        except Error as e:
            return {"type": "error", "message": str(e)}
        except Exception as e:  # anything else a message could provoke is refused, and the connection stays
            return {"type": "error", "message": f"{kind}: {type(e).__name__}: {e}"}
        return None


def too_big(data: str | bytes) -> bool:
    """Over MAX_MESSAGE bytes (text counted in UTF-8)."""
    return len(data.encode() if isinstance(data, str) else data) > MAX_MESSAGE


def serve(live: LiveRun, host: str = "127.0.0.1", port: int = 8765,
          on_ready: Any = None) -> None:
    """Serve `live` until interrupted (Ctrl-C); `on_ready(url)` is called once it listens."""

    async def main() -> None:
        viewer = Viewer(live)
        runner = web.AppRunner(viewer.app, handle_signals=False)
        await runner.setup()
        site = web.TCPSite(runner, host, port)
        try:
            await site.start()
        except OSError as e:
            await runner.cleanup()
            raise Error(f"--port {port}: cannot listen on {host}:{port} ({e.strerror})") from None
        bound = site._server.sockets[0].getsockname()[1] if site._server else port  # type: ignore[union-attr]
        name = f"[{host}]" if ":" in host else host
        loopback = host in ("127.0.0.1", "localhost", "::1")
        viewer.hosts = ({f"127.0.0.1:{bound}", f"localhost:{bound}", f"[::1]:{bound}"} if loopback else set())
        viewer.live.start()  # the frames start once the page can be served
        if on_ready is not None:
            on_ready(f"http://{name}:{bound}/")
        try:
            await asyncio.Event().wait()
        finally:
            await runner.cleanup()

    asyncio.run(main())
