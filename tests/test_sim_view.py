"""The simulation view: a backend that draws the robots where the physics put them, and records video."""

from __future__ import annotations

import json
import subprocess

import vwg
from conftest import ROOT
from vwg import _core


class Walker(vwg.Actor):
    """Shows Move<0.5>(Robot<id>) when told to go, else Robot<id> (so it is drawn every frame)."""

    events = ("go", "show")
    attributes = {"id": 1}

    def show_go(self, e):
        return f"Move<0.5>(Robot<{self.id}>)"

    def show_show(self, e):
        return f"Robot<{self.id}>"


def test_view_draws_the_robots_and_writes_a_video(tmp_path):
    world = vwg.robot.load_robot_world(ROOT / "maps" / "office.yaml")
    sim = vwg.robot.platforms.sim.Simulation(world)
    sim_events = vwg.robot.platforms.sim.SIM_EVENTS
    alphabet = vwg.Alphabet(events={**sim_events, "go": None, "show": None}, visual=["go", "show"],
                            actors=[Walker], **vwg.robot.platforms.sim.MOTION_SYMBOLS)
    gens = [*sim.make_sensors(alphabet), vwg.Schedule({0: ["go"], 20: ["go"]}), vwg.every_frame("show")]
    video = tmp_path / "run.mp4"
    view = sim.view(video=str(video), images=str(tmp_path / "frames"))
    engine = vwg.Engine(vwg.World(alphabet), "Walker<id=1> . Walker<id=2>", gens, vwg.BackendGroup([sim.backend, view]))
    engine.run(40)
    view.close()
    # Each walker moved 0.5 m twice along its heading (a move takes 1.5 s: 0.5 s speeding up,
    # 0.5 s at 0.5 m/s, 0.5 s braking): robot 1 from (1.5, 9) facing +x, robot 2 from (23.5, 9)
    # facing -x.
    assert abs(sim.robot(1).pose[0] - 2.5) < 1e-5
    assert abs(sim.robot(2).pose[0] - 22.5) < 1e-5
    # The last frame shows robot 1 in its colour at its pose.
    renderer = _core.TopDownRenderer(world.grid, width=800, header=40)
    px, py = renderer.world_to_pixel(*sim.robot(1).pose[:2])
    image = view.image()
    assert tuple(image[int(py), int(px)]) == renderer.robot_colour(1)
    assert view.frames_written == 40
    assert len(list((tmp_path / "frames").glob("frame_*.png"))) == 40
    assert view.trajectories[1].shape == (40, 2)
    probe = json.loads(subprocess.run(
        ["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
         "stream=codec_name,pix_fmt,nb_read_frames,width,height", "-of", "json", str(video)],
        capture_output=True, text=True, check=True).stdout)["streams"][0]
    assert (probe["codec_name"], probe["pix_fmt"], int(probe["nb_read_frames"])) == ("h264", "yuv420p", 40)
    assert (probe["width"], probe["height"]) == image.shape[1::-1]
