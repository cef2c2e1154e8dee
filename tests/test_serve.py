"""vwg serve: the page in a real browser (Debian's chromium, headless, driven by Playwright): the map is
drawn, a room button and a click on a marker send the robot there and it arrives; the JSON API; the
WebSocket's refusals, several clients, a client that goes away, a slow client that skips frames;
pause, step and reset; the command's bad input and Ctrl-C. Every server here listens on 127.0.0.1
and stops with its test."""

from __future__ import annotations

import asyncio
import contextlib
import http.client
import json
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import urllib.request

import pytest
import websockets

from conftest import ROOT

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
ARTIFACTS = ROOT / "build" / "test-artifacts"


class Server:
    """`vwg serve WORLD --port 0 ...` in a process of its own, its URL read from what it prints."""

    def __init__(self, *args: str) -> None:
        # A file, not a pipe: nothing waits for the test to read what the server prints on stderr.
        self.errors = tempfile.TemporaryFile("w+")  # noqa: SIM115 (closed by stop())
        self.process = subprocess.Popen([sys.executable, "-m", "vwg.cli", "serve", *args, "--port", "0"],
                                        stdout=subprocess.PIPE, stderr=self.errors, text=True)
        ready, _, _ = select.select([self.process.stdout], [], [], 120)
        line = self.process.stdout.readline() if ready else ""  # "vwg serve office: http://127.0.0.1:PORT/ ..."
        if "http://" not in line:
            self.process.kill()
            raise AssertionError(f"vwg serve did not start: {line}{self.stop()[1]}")
        self.url = line.split()[3]
        assert self.url.startswith("http://127.0.0.1:")
        self.ws = self.url.replace("http://", "ws://") + "ws"

    def get(self, path: str) -> bytes:
        with urllib.request.urlopen(self.url + path.lstrip("/"), timeout=10) as response:
            return response.read()

    def state(self) -> dict:
        return json.loads(self.get("/api/state"))

    def handle_reply(self, message: dict) -> dict:
        """Send one message over the WebSocket and return the first reply that is not a frame."""

        async def talk() -> dict:
            async with websockets.connect(self.ws) as ws:
                await ws.send(json.dumps(message))
                while True:
                    reply = json.loads(await asyncio.wait_for(ws.recv(), 10))
                    if reply.get("type") in ("ok", "error"):
                        return reply

        return asyncio.run(talk())

    def wait_for(self, test, timeout: float = 60.0) -> dict:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            state = self.state()
            if test(state):
                return state
            time.sleep(0.05)
        raise AssertionError(f"not reached in {timeout} s; last state: {state}")

    def stop(self) -> tuple[int, str]:
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)  # Ctrl-C
        try:
            self.process.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            self.process.send_signal(signal.SIGUSR1)  # where it is stuck: every thread's stack, on stderr
            time.sleep(2)
            self.process.kill()
            self.process.communicate()
        self.errors.seek(0)
        err = self.errors.read()
        self.errors.close()
        return self.process.returncode, err


@pytest.fixture
def server(request):
    args = getattr(request, "param", ("office", "--no-world-orders", "--speed", "0"))
    s = Server(*args)
    yield s
    s.stop()


def robot(state: dict, rid: int) -> dict:
    return next(r for r in state["robots"] if r["id"] == rid)


@contextlib.contextmanager
def viewer_page(server: Server):
    """The server's page in headless chromium, once it shows frames."""
    from playwright import sync_api as playwright

    with playwright.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1500, "height": 1000})
        page.goto(server.url)
        page.wait_for_function("document.getElementById('status').textContent.startsWith('frame')")
        yield page
        browser.close()


@pytest.mark.slow
def test_the_page_in_a_browser_orders_by_button_and_by_marker(server):
    world = json.loads(server.get("/api/world"))
    with viewer_page(server) as page:
        page.wait_for_function("document.getElementById('map').dataset.drawn === 'true'")
        # The map is drawn: the canvas holds the map's pixels, not a blank element.
        colours = page.evaluate("""() => {
            const c = document.getElementById('map');
            const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
            const seen = new Set();
            let dark = 0;
            for (let i = 0; i < d.length; i += 4) {
                seen.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
                if (d[i] + d[i + 1] + d[i + 2] < 200) dark++;
            }
            return [seen.size, dark / (d.length / 4)];
        }""")
        assert colours[0] > 20 and 0.02 < colours[1] < 0.6, colours  # walls (dark) on a light floor, and colour
        assert sorted(page.eval_on_selector_all("button[data-room]", "bs => bs.map(b => b.dataset.room)")) == \
            sorted(r["name"] for r in world["rooms"])
        # A room's button sends the selected robot (1) there through gObjective; it arrives.
        page.click('button[data-room="library"]')
        server.wait_for(lambda s: robot(s, 1)["objective"] == "library", timeout=20)
        server.wait_for(lambda s: robot(s, 1)["reached"], timeout=90)
        page.wait_for_function("document.getElementById('objective').textContent.includes('(reached)')")
        # The selected robot's camera and the 3D view are images the page shows.
        page.wait_for_function("document.getElementById('camera').naturalWidth > 0")
        page.wait_for_function("document.getElementById('overview').naturalWidth > 0")
        # Pause, then one step: one frame.
        page.click("#pause")
        paused = server.wait_for(lambda s: s["status"] == "paused", timeout=20)
        page.click("#step")
        server.wait_for(lambda s: s["frame"] == paused["frame"] + 1, timeout=20)
        page.click("#resume")
        server.wait_for(lambda s: s["status"] == "running", timeout=20)
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "serve_office.png"))
        # Robot 2 selected from the list, then a click on the kitchen's marker on the map sends it there.
        page.select_option("#robot", "2")
        server.wait_for(lambda s: s["selected"] == 2, timeout=20)
        kitchen = next(r for r in world["rooms"] if r["name"] == "kitchen")
        m = world["map"]
        box = page.locator("#map").bounding_box()
        u, v = m["ax"] * kitchen["x"] + m["bx"], m["ay"] * kitchen["y"] + m["by"]
        page.mouse.click(box["x"] + u * box["width"] / m["width"], box["y"] + v * box["height"] / m["height"])
        server.wait_for(lambda s: robot(s, 2)["objective"] == "kitchen", timeout=20)
        assert robot(server.state(), 1)["objective"] == "library"
        # A bad order is refused with the error shown on the page.
        page.evaluate("send({type: 'order', robot: 1, room: 'nowhere'})")
        page.wait_for_function("document.getElementById('errors').textContent.includes(\"unknown room 'nowhere'\")")
        # A message over the size limit: the server closes that connection, and the page says so.
        page.evaluate("send({type: 'order', robot: 1, room: 'x'.repeat(10000)})")
        page.wait_for_function("document.getElementById('errors').textContent.includes('code 1009')")
    assert server.state()["frame"] > 0  # the server goes on
    assert (ARTIFACTS / "serve_office.png").stat().st_size > 10_000


def test_the_api_state_and_images(server):
    state = server.state()
    assert set(state) >= {"frame", "time", "robots"} and isinstance(state["frame"], int)
    assert [r["id"] for r in state["robots"]] == [1, 2]
    for r in state["robots"]:
        assert set(r) >= {"id", "x", "y", "angle", "objective", "reached"}
        assert r["objective"] is None and r["reached"] is False  # --no-world-orders: no order yet
        assert all(isinstance(r[k], float) for k in ("x", "y", "angle"))
    assert robot(state, 1)["x"] == pytest.approx(1.5, abs=0.05) and robot(state, 1)["y"] == pytest.approx(9.0, abs=0.05)
    assert server.get("/api/map.png")[:8] == b"\x89PNG\r\n\x1a\n"
    assert server.get("/api/overview.png")[:8] == b"\x89PNG\r\n\x1a\n"
    server.wait_for(lambda s: s["frame"] > 5)
    assert server.get("/api/camera/1.jpg")[:2] == b"\xff\xd8"  # the office's robots carry a camera
    with pytest.raises(urllib.error.HTTPError, match="404"):
        server.get("/api/camera/2.jpg")  # not the selected robot


async def _exchange(url: str, *messages: str) -> list[dict]:
    replies = []
    async with websockets.connect(url, max_size=None) as ws:
        for text in messages:
            await ws.send(text)
            while True:
                reply = json.loads(await asyncio.wait_for(ws.recv(), 10))
                if reply["type"] != "frame":
                    replies.append(reply)
                    break
    return replies


def test_bad_messages_are_refused_by_name_and_the_server_goes_on(server):
    replies = asyncio.run(_exchange(
        server.ws, "{not json", json.dumps([1, 2]), json.dumps({"type": "teleport"}),
        json.dumps({"type": "order", "robot": 1, "room": "nowhere"}),
        json.dumps({"type": "order", "robot": 9, "room": "kitchen"}),
        json.dumps({"type": "speed", "value": -3}), json.dumps({"type": "select", "robot": "one"}),
        "[" * 3000, '{"type": "speed", "value": 1' + "0" * 400 + "}",
        json.dumps({"type": "order", "robot": 1, "room": "kitchen"})))
    kinds = [r["type"] for r in replies]
    assert kinds == ["error"] * 9 + ["ok"], replies
    messages = [r.get("message", "") for r in replies]
    assert "malformed JSON at line 1, column 2" in messages[0]
    assert "expected a JSON object" in messages[1]
    assert "unknown message type 'teleport'" in messages[2]
    assert "unknown room 'nowhere'" in messages[3]
    assert "no robot 9" in messages[4]
    assert "speed: expected" in messages[5]
    assert "no robot 'one'" in messages[6]
    assert "nested too deeply" in messages[7]
    assert "speed: expected" in messages[8]
    server.wait_for(lambda s: robot(s, 1)["objective"] == "kitchen", timeout=20)

    async def oversize() -> int:
        async with websockets.connect(server.ws) as ws:
            await ws.send(json.dumps({"type": "order", "room": "x" * 10_000}))
            with pytest.raises(websockets.ConnectionClosed) as info:
                while True:
                    await asyncio.wait_for(ws.recv(), 10)
            return info.value.rcvd.code

    assert asyncio.run(oversize()) == 1009  # message too big: that connection only
    assert server.state()["frame"] >= 0  # the server is still there


def _message_of(size: int) -> str:
    """An order to an unknown room, of exactly `size` bytes."""
    text = json.dumps({"type": "order", "robot": 1, "room": ""})
    message = json.dumps({"type": "order", "robot": 1, "room": "x" * (size - len(text))})
    assert len(message.encode()) == size
    return message


@pytest.mark.parametrize("compression", [None, "deflate"])
def test_a_message_of_4096_bytes_is_taken_and_one_of_4097_closes(server, compression):
    # The README: "one over 4 KB closes that connection". 4,096 bytes is the most a message may have,
    # sent plain or compressed (permessage-deflate: the limit is on the inflated message).
    async def send(text: str) -> dict | int:
        async with websockets.connect(server.ws, compression=compression) as ws:
            await ws.send(text)
            try:
                while True:
                    reply = json.loads(await asyncio.wait_for(ws.recv(), 10))
                    if reply["type"] != "frame":
                        return reply
            except websockets.ConnectionClosed as e:
                return e.rcvd.code

    reply = asyncio.run(send(_message_of(4096)))
    assert isinstance(reply, dict) and reply["type"] == "error" and "unknown room 'xxx" in reply["message"], reply
    assert asyncio.run(send(_message_of(4097))) == 1009
    assert server.state()["frame"] >= 0


def test_a_thousand_resets_from_one_client_hold_the_frames_back_under_a_second(server):
    # Each reset builds the world again (~0.1-0.3 s); 1,000 of them, 17 bytes each, were done one by
    # one and stalled the frames for 263 s. Repeated, they are one: the frames run again within 1 s.
    server.wait_for(lambda s: s["frame"] > 50)

    async def flood() -> tuple[list[int], list[int]]:
        async with websockets.connect(server.ws, max_queue=None) as ws:
            for _ in range(1000):
                await ws.send('{"type": "reset"}')
            await ws.send('{"type": "teleport"}')  # answered once every reset before it is queued
            while json.loads(await asyncio.wait_for(ws.recv(), 10))["type"] != "error":
                pass
            queued = time.monotonic()
            seen: list[int] = []  # the frames sent within a second of that
            while (left := queued + 1.0 - time.monotonic()) > 0:
                try:
                    message = json.loads(await asyncio.wait_for(ws.recv(), left))
                except asyncio.TimeoutError:
                    break
                seen.append(message["frame"])
            later = []
            for _ in range(5):  # and afterwards: no reset was left waiting, the frames go on
                later.append(server.state()["frame"])
                await asyncio.sleep(0.1)
            return seen, later

    seen, later = asyncio.run(flood())
    # After the last drop back to the first frames (the last reset done), the frames counted up again.
    last_drop = max((i for i in range(1, len(seen)) if seen[i] < seen[i - 1]), default=0)
    assert seen and seen[-1] >= seen[last_drop] + 10, seen
    assert later == sorted(later) and later[-1] > later[0], later


def test_a_client_over_its_bound_of_waiting_commands_is_told_and_others_go_on(server):
    # A reset keeps the run's thread busy; meanwhile commands that do not repeat the one before
    # (pause, resume, pause, ...) queue up to the bound, and each one over it gets an error back.
    async def flood() -> tuple[list[str], dict]:
        async with websockets.connect(server.ws, max_queue=None) as ws:
            await ws.send('{"type": "reset"}')
            for i in range(80):
                await ws.send(json.dumps({"type": ("pause", "resume")[i % 2]}))
            await ws.send('{"type": "teleport"}')
            refused = []
            while True:
                reply = json.loads(await asyncio.wait_for(ws.recv(), 10))
                if reply["type"] == "error":
                    if "teleport" in reply["message"]:
                        break
                    refused.append(reply["message"])
        async with websockets.connect(server.ws) as ws:  # another client: its order is taken, its resume done
            await ws.send(json.dumps({"type": "order", "robot": 1, "room": "kitchen"}))
            await ws.send(json.dumps({"type": "resume"}))
            while (reply := json.loads(await asyncio.wait_for(ws.recv(), 10)))["type"] == "frame":
                pass
        return refused, reply

    refused, other = asyncio.run(flood())
    assert refused, "no command was refused"
    assert len(refused) <= 80 - 31  # the bound's 32 less the reset, were it still waiting
    assert all(("pause: refused" in m or "resume: refused" in m) and "still waiting" in m for m in refused), refused
    assert other["type"] == "ok"  # another client's order is taken
    server.wait_for(lambda s: robot(s, 1)["objective"] == "kitchen", timeout=20)


def test_the_command_queue_bounds_each_client_and_merges_repeats():
    from vwg.errors import Error
    from vwg.serve.live import CommandQueue

    queue = CommandQueue(bound=4)
    for _ in range(1000):
        queue.put("reset", client="a")
    for kind, value in (("step", None), ("step", None), ("step", None), ("speed", 1.0), ("speed", 2.0),
                        ("pause", None), ("pause", None)):
        queue.put(kind, value, client="a")
    assert len(queue) == 4  # reset, step (three), speed (the last value), pause: a's bound
    with pytest.raises(Error, match="order: refused, 4 commands from this client are still waiting"):
        queue.put("order", (1, "kitchen"), client="a")
    queue.put("pause", client="a")  # a repeat of the last merges, at the bound too
    queue.put("order", (1, "kitchen"), client="b")  # another client has a bound of its own
    with pytest.raises(Error, match="speed: refused"):
        queue.put("speed", 3.0, client="a")  # repeats a's speed, but not the last command (b's order)
    taken = [(c.kind, c.value, c.count, c.client) for c in queue.take(0)]
    assert taken == [("reset", None, 1, "a"), ("step", None, 3, "a"), ("speed", 2.0, 1, "a"), ("pause", None, 1, "a"),
                     ("order", (1, "kitchen"), 1, "b")]
    queue.put("order", (1, "kitchen"), client="a")  # all taken: a may send again
    assert len(queue) == 1


def test_only_the_last_of_the_resets_taken_at_once_is_done():
    from vwg.robot.world_file import load_robot_world
    from vwg.serve.live import LiveRun

    live = LiveRun(load_robot_world("office"), world_orders=False)  # not started: its commands are done here
    built = []
    new_case = live._new_case
    live._new_case = lambda: built.append(1) or new_case()
    for _ in range(3):
        live.reset()
        live.pause()
        live.order(1, "kitchen")  # dropped by the reset after it
    live.reset()
    live.order(2, "lab")
    live.step()
    live._apply_commands(timeout=0)
    assert len(built) == 1
    assert live._paused and live._steps == 1
    live._frame()
    assert live.case.orders.last == {2: "lab"}
    live.stop()


def test_only_its_own_page_and_name(server):
    port = server.url.rsplit(":", 1)[1].rstrip("/")
    # Another web site open in the browser cannot open the WebSocket (its Origin is not this server).
    with pytest.raises(websockets.InvalidStatus) as info:
        asyncio.run(_exchange_with_origin(server.ws, "http://evil.example"))
    assert info.value.response.status_code == 403
    # A request that reaches this server under another name (DNS rebinding) is refused.
    request = urllib.request.Request(server.url + "api/state", headers={"Host": f"evil.example:{port}"})
    with pytest.raises(urllib.error.HTTPError, match="403"):
        urllib.request.urlopen(request, timeout=10)
    assert server.state()["frame"] >= 0  # by its own name it answers


def test_two_origin_headers_are_refused(server):
    # Own, then foreign (or the other way round): the page is not its own page's; one own Origin is.
    host = server.url.removeprefix("http://").rstrip("/")
    upgrade = {"Connection": "Upgrade", "Upgrade": "websocket", "Sec-WebSocket-Version": "13",
               "Sec-WebSocket-Key": "dGhlIHNhbXBsZSBub25jZQ=="}
    for origins, status in (([f"http://{host}", "http://evil.example"], 403),
                            (["http://evil.example", f"http://{host}"], 403), ([f"http://{host}"], 101)):
        for path, headers in (("/ws", upgrade), ("/api/state", {})):
            connection = http.client.HTTPConnection(host, timeout=10)
            connection.putrequest("GET", path)
            for origin in origins:
                connection.putheader("Origin", origin)
            for name, value in headers.items():
                connection.putheader(name, value)
            connection.endheaders()
            got = connection.getresponse().status
            connection.close()
            assert got == (status if path == "/ws" or status == 403 else 200), (origins, path, got)


async def _exchange_with_origin(url: str, origin: str) -> None:
    async with websockets.connect(url, origin=origin):
        pass


def test_a_live_run_on_a_robot_through_rosbridge():
    # The viewer's run on a real robot's platform (the fake ROS robot on 127.0.0.1): its frames keep
    # the robot's clock, its scans are the LaserScans' points, and stopping stops the robot.
    import dataclasses

    from vwg.robot.world_file import PlatformSpec, load_robot_world
    from vwg.serve.live import LiveRun
    from vwg.testing.fake_robot import FakeRosbridgeRobot

    office = load_robot_world("office")
    world = dataclasses.replace(office, orders=[], robots=[office.robots[0].replace(sensors=["laser"])])
    with FakeRosbridgeRobot(world) as fake:
        with pytest.raises(Exception, match="a real robot runs at real time"):
            LiveRun(world, platform=PlatformSpec("rosbridge", {"url": fake.url}), speed=5)
        live = LiveRun(world, platform=PlatformSpec("rosbridge", {"url": fake.url}))
        live.start()
        live.order(1, "office")
        end = time.monotonic() + 30
        while time.monotonic() < end and not (live.latest.frame > 10 and live.latest.robots[0]["scan"]):
            time.sleep(0.05)
        snapshot = live.latest
        assert snapshot.status == "running" and snapshot.robots[0]["objective"] == "office"
        assert len(snapshot.robots[0]["scan"]) > 20  # the LaserScan's points that met a wall
        live.stop()
        assert live.case is None  # closed by the run's own thread
        fake.read_to_close()  # every Twist the run sent before it closed the link
        commands = fake.commands[1]
        assert commands and commands[-1][1:] == (0.0, 0.0)  # the last Twist stops the robot


@pytest.mark.slow
def test_several_clients_a_client_gone_mid_stream_and_a_slow_one(server):
    async def clients() -> tuple[list[int], int, int, int]:
        frames = []
        many = [await websockets.connect(server.ws, max_queue=1) for _ in range(4)]
        for ws in many:
            frames.append(json.loads(await asyncio.wait_for(ws.recv(), 10))["frame"])
        # Two go away without a word, in the middle of the stream.
        many[0].transport.abort()
        await many[1].close()
        # A slow one: reads nothing while the run goes on, as fast as it can, for 3,000 frames (more than
        # the sockets' buffers hold of its messages).
        slow = many[2]
        start = server.state()["frame"]
        while server.state()["frame"] < start + 3000:
            await asyncio.sleep(0.2)
        end = server.state()["frame"]
        received = 0
        latest = 0
        while True:
            try:
                message = json.loads(await asyncio.wait_for(slow.recv(), 0.5))
            except asyncio.TimeoutError:
                break
            received += 1
            latest = message["frame"]
            if latest >= end:
                break
        # The one that kept reading still gets frames.
        fresh = json.loads(await asyncio.wait_for(many[3].recv(), 10))["frame"]
        for ws in many[2:]:
            await ws.close()
        return frames, end - start, received, fresh

    frames, advanced, received, fresh = asyncio.run(clients())
    assert len(frames) == 4
    # The run went on while the slow client read nothing; it got the newest frames, not every one.
    assert received < advanced / 2, (advanced, received)
    assert fresh > max(frames)
    assert server.state()["frame"] > 0


@pytest.mark.parametrize("server", [("maze", "--paused", "--speed", "1")], indirect=True)
@pytest.mark.slow
def test_pause_step_and_reset(server):
    state = server.state()
    assert state["status"] == "paused" and state["frame"] == 0

    async def send(*messages: dict) -> None:
        async with websockets.connect(server.ws) as ws:
            for m in messages:
                await ws.send(json.dumps(m))
            await asyncio.sleep(0.3)

    asyncio.run(send({"type": "step"}, {"type": "step"}, {"type": "step"}))
    server.wait_for(lambda s: s["frame"] == 3)
    time.sleep(0.5)
    assert server.state()["frame"] == 3  # paused: three steps, three frames
    asyncio.run(send({"type": "speed", "value": 0}, {"type": "resume"}))
    server.wait_for(lambda s: s["frame"] > 50 and s["status"] == "running")
    asyncio.run(send({"type": "reset"}, {"type": "pause"}))
    after = server.wait_for(lambda s: s["status"] == "paused")
    assert after["frame"] < 50  # started again from frame 0


@pytest.mark.parametrize("server", [("office", "--no-world-orders", "--speed", "1")], indirect=True)
def test_the_stop_button_interrupts_the_selected_robot_s_task(server):
    with viewer_page(server) as page:
        page.click('button[data-room="library"]')
        going = server.wait_for(lambda s: robot(s, 1)["objective"] == "library", timeout=20)
        page.click("#cancel")
        stopped = server.wait_for(lambda s: robot(s, 1)["status"] == "interrupted", timeout=20)
        assert robot(stopped, 1)["objective"] is None and not robot(stopped, 1)["reached"]
        page.wait_for_function("document.getElementById('objective').textContent === 'interrupted'")
    assert stopped["frame"] > going["frame"]
    # It came to rest and stays there (a frame at 1x is 0.1 s: a second of frames later, the same place).
    rest = server.wait_for(lambda s: s["frame"] >= stopped["frame"] + 15)
    later = server.wait_for(lambda s: s["frame"] >= rest["frame"] + 10)
    a, b = robot(rest, 1), robot(later, 1)
    assert abs(a["x"] - b["x"]) < 1e-3 and abs(a["y"] - b["y"]) < 1e-3
    # The same through the WebSocket's message, for robot 2, and an unknown robot is refused by name.
    assert server.handle_reply({"type": "order", "robot": 2, "room": "kitchen"})["type"] == "ok"
    assert server.handle_reply({"type": "cancel", "robot": 2}) == {"type": "ok", "what": "robot 2: task interrupted"}
    assert "no robot 9" in server.handle_reply({"type": "cancel", "robot": 9})["message"]


@pytest.mark.slow
def test_the_command_refuses_bad_input_and_stops_on_ctrl_c(tmp_path):
    for args, words in ((["office", "--port", "70000"], "--port"), (["office", "--planner", "teleport"], "teleport"),
                        ([str(ROOT / "examples" / "01_fireflies" / "world.yaml")], "takes a robot world")):
        done = subprocess.run([sys.executable, "-m", "vwg.cli", "serve", *args], capture_output=True, text=True,
                              timeout=60)
        assert done.returncode == 2 and words in done.stderr, done.stderr
    s = Server("office", "--speed", "1")
    s.wait_for(lambda st: st["frame"] > 2)
    code, err = s.stop()
    assert code == 130 and "interrupted" in err, (code, err)


def test_sigusr1_prints_every_threads_stack_and_the_server_goes_on():
    s = Server("office", "--speed", "1")
    s.wait_for(lambda st: st["frame"] > 1)
    s.process.send_signal(signal.SIGUSR1)
    frame = s.state()["frame"]
    s.wait_for(lambda st: st["frame"] > frame + 2)  # still running
    code, err = s.stop()
    assert code == 130, (code, err)
    # faulthandler's dump: the live run's thread (in live.py) and the main thread (the event loop).
    assert err.count("(most recent call first)") >= 2 and "live.py" in err and "asyncio" in err, err


def test_people_who_walk_are_in_the_frames_and_the_3d_view(tmp_path):
    import vwg

    office = vwg.robot.load_robot_world("office")
    text = office.path.read_text(encoding="utf-8").replace("map: office/map.yaml", f"map: {office.map_path.resolve()}")
    world = tmp_path / "office.yaml"
    world.write_text(text + "people:\n  - {start: [6.0, 9.0], waypoints: [[20.0, 9.0], [6.0, 9.0]]}\n"
                            "  - {start: [12.0, 9.5], wander: all}\n", encoding="utf-8")
    s = Server(str(world), "--no-world-orders", "--speed", "0")
    try:
        first = s.wait_for(lambda st: st["frame"] >= 5 and len(st["people"]) == 2)
        later = s.wait_for(lambda st: st["frame"] >= first["frame"] + 20)
        walker = {p["id"]: p for p in first["people"]}[1], {p["id"]: p for p in later["people"]}[1]
        assert walker[1]["x"] > walker[0]["x"] + 0.5  # walking east along the corridor
        assert all(p["radius"] == 0.25 for p in later["people"])
        assert s.get("/api/overview.png")[:8] == b"\x89PNG\r\n\x1a\n"
    finally:
        s.stop()
