"""Saved runs (vwg.saved_run, ``vwg run --save-state``, ``vwg resume``): the frames after a state saved and
resumed — in another process, with another thread count — are those of the run that never stopped, byte
for byte (events, strings, blobs), as Box2D's own snapshot test checks its steps. The reference is the
uninterrupted run's record; the resumed run's record is compared with it line by line."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml

import vwg
import vwg._core as _core
from conftest import ROOT
from vwg.errors import Error, SchemaError
from vwg.io.record import read_record
from vwg.io.state_file import engine_parts, engine_state, read_state, write_state
from vwg.saved_run import resume

VWG = [sys.executable, "-m", "vwg.cli"]
FIREFLIES = ROOT / "examples" / "01_fireflies" / "world.yaml"


def cli(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*VWG, *args], cwd=cwd, capture_output=True, text=True, timeout=900,
                          env={**os.environ, "PYTHONWARNINGS": "ignore"})


def frames(record: Path) -> dict[int, tuple[list[str], str]]:
    """Frame t -> (its events, the string at its start), blobs by content hash in the texts."""
    return {f["t"]: (list(f["events"]), f["string"]) for f in read_record(record).frames}


def same_after(full: Path, resumed: Path, first: int, last: int) -> None:
    a, b = frames(full), frames(resumed)
    assert sorted(b) == list(range(first, last + 1)), (min(b), max(b))
    for t in range(first, last + 1):
        assert a[t] == b[t], f"frame {t} differs"
    # The frames compared are not still: the robots move (else any state would pass).
    assert a[first][1] != a[last][1]


def run_saving(world: str | Path, tmp: Path, frames_: int, every: int, *extra: str) -> Path:
    """The uninterrupted run, recorded, keeping its state every `every` frames beside the record."""
    record = tmp / "full.jsonl"
    robot = Path(str(world)).suffix == ""  # a shipped robot world by name
    done = cli("run", str(world), "--frames", str(frames_), "--record", str(record), "--snapshot-every", str(every),
               *(["--allow-unreached"] if robot else []), "--quiet", *extra, cwd=tmp)
    assert done.returncode == 0, done.stderr
    return record


@pytest.mark.parametrize("planner", ["astar", "dstar", "jps", "rrtconnect", "random"])
@pytest.mark.slow
def test_warehouse_frames_after_a_resume_in_another_process_are_the_uninterrupted_run_s(tmp_path, planner):
    record = run_saving("warehouse", tmp_path, 200, 100, "--planner", planner, "--threads", "1")
    state = record.with_name(record.name + ".states") / f"{100:012d}.vwgstate"
    for threads in ("1", "2"):
        resumed = tmp_path / f"rest{threads}.jsonl"
        done = cli("resume", str(state), "--frames", "100", "--threads", threads, "--record", str(resumed),
                   "--allow-unreached", "--quiet", cwd=tmp_path)
        assert done.returncode == 0, done.stderr
        same_after(record, resumed, 100, 199)


def test_a_run_saved_at_its_end_goes_on_as_if_it_had_not_stopped(tmp_path):
    # The office (two robots, A* on 2 threads): 60 frames and --save-state, then vwg resume for 40.
    record = run_saving("office", tmp_path, 100, 100, "--threads", "2")
    done = cli("run", "office", "--frames", "60", "--save-state", "s.vwgstate", "--allow-unreached", "--quiet",
               cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    done = cli("resume", "s.vwgstate", "--frames", "40", "--record", "rest.jsonl", "--allow-unreached", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "from frame 60" in done.stdout
    same_after(record, tmp_path / "rest.jsonl", 60, 99)
    # The resumed run's record replays by itself, from its frame 60.
    replayed = cli("replay", "rest.jsonl", cwd=tmp_path)
    assert replayed.returncode == 0 and "40 frames replayed" in replayed.stdout, replayed.stderr


@pytest.mark.slow
def test_fireflies_python_generator_resumes_with_its_random_stream(tmp_path):
    # A generic world: Python actors that split (ctx.rng) and die, FoodDrops a numpy Generator kept as
    # its attributes are (vwg.model.state).
    record = run_saving(FIREFLIES, tmp_path, 300, 150, "--backend", "null")
    state = record.with_name(record.name + ".states") / f"{150:012d}.vwgstate"
    done = cli("resume", str(state), "--frames", "150", "--record", "rest.jsonl", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    same_after(record, tmp_path / "rest.jsonl", 150, 299)


@pytest.mark.slow
def test_a_hundred_robots_resume_as_they_went_on(tmp_path):
    # The warehouse with a hundred robots 0.6 m apart at seeded free places, each sent to a room: a world
    # file of its own (a resumed run is made again from its world file).
    world = vwg.robot.load_robot_world(ROOT / "maps" / "warehouse.yaml")
    rng = np.random.default_rng(5)
    free = np.argwhere(~world.grid.inflate(0.5))
    picked: list[tuple[float, float]] = []
    for r, c in free[rng.permutation(len(free))]:
        x, y = world.grid.cell_to_world(int(r), int(c))
        if all((x - a) ** 2 + (y - b) ** 2 > 0.6**2 for a, b in picked):
            picked.append((x, y))
        if len(picked) == 100:
            break
    data = yaml.safe_load((ROOT / "maps" / "warehouse.yaml").read_text())
    rooms = list(data["rooms"])
    data["map"] = str(ROOT / "maps" / "warehouse" / "map.yaml")
    data["robots"] = [{"id": i + 1, "start": [float(x), float(y), 0.0], "sensors": ["laser"]}
                      for i, (x, y) in enumerate(picked)]
    data["orders"] = [{"time": 0.0, "robot": i + 1, "room": rooms[i % len(rooms)]} for i in range(100)]
    crowd = tmp_path / "crowd.yaml"
    crowd.write_text(yaml.safe_dump(data))
    record = run_saving(crowd, tmp_path, 80, 40, "--threads", "2", "--allow-unreached")
    state = record.with_name(record.name + ".states") / f"{40:012d}.vwgstate"
    done = cli("resume", str(state), "--frames", "40", "--threads", "1", "--record", "rest.jsonl",
               "--allow-unreached", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    same_after(record, tmp_path / "rest.jsonl", 40, 79)


def test_a_state_restored_into_a_second_engine_goes_on_alike_and_shares_nothing(tmp_path):
    office = vwg.load("office")
    with vwg.start(office, vwg.RunOptions(frames=30, planner="dstar", allow_unreached=True, threads=1)) as a:
        a.execute()
        data = a.save_state()
        with resume(data, vwg.RunOptions(threads=2, allow_unreached=True)) as b:
            assert b.engine.frame == a.engine.frame == 30
            assert str(b.engine.string) == str(a.engine.string)
            seen_a = []
            for _ in range(25):
                a.engine.step()
                seen_a.append((str(a.engine.string), [str(e) for e in a.engine.last_events]))
            # A ran on 25 frames; B, restored before, is still at frame 30: it shares no state with A.
            assert b.engine.frame == 30
            # A's maps, changed in place by its λ these 25 frames, did not change B's: B goes on as A went.
            for k in range(25):
                b.engine.step()
                assert (str(b.engine.string), [str(e) for e in b.engine.last_events]) == seen_a[k], f"frame {30 + k}"
            # The robots' maps are equal and distinct objects.
            ga = np.asarray(a.case.robot_actors()[1]["grid"])
            gb = np.asarray(b.case.robot_actors()[1]["grid"])
            assert np.array_equal(ga, gb) and not np.shares_memory(ga, gb)


def test_a_state_with_the_simulator_of_another_frame_goes_another_way():
    # The control: the comparisons above can fail. The simulator's state of frame 20 with the rest of
    # frame 40 (the journal is shorter, so it loads) gives other frames than the run that went on.
    office = vwg.load("office")
    with vwg.start(office, vwg.RunOptions(frames=20, allow_unreached=True, threads=1)) as run:
        run.execute()
        early = read_state(run.save_state(), "state").parts["platform"]
        run.case.frames = 20
        run.execute()
        data = run.save_state()
        run.case.frames = 40
        run.execute()
        kept = str(run.engine.string)
    saved = read_state(data, "state")
    forged = write_state({k: v for k, v in saved.manifest.items() if k not in ("parts", "format")},
                         {**saved.parts, "platform": early})
    with resume(forged, vwg.RunOptions(frames=40, threads=1, allow_unreached=True)) as run:
        run.execute()
        assert str(run.engine.string) != kept
    with resume(data, vwg.RunOptions(frames=40, threads=1, allow_unreached=True)) as run:
        run.execute()
        assert str(run.engine.string) == kept


def test_ctrl_c_saves_the_state_of_the_last_whole_frame(tmp_path):
    proc = subprocess.Popen([*VWG, "run", "warehouse", "--frames", "100000", "--save-state", "s.vwgstate",
                             "--record", "r.jsonl", "--allow-unreached", "--no-progress"], cwd=tmp_path,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONWARNINGS": "ignore"})
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not (tmp_path / "r.jsonl").exists():
        time.sleep(0.2)
    time.sleep(2.0)  # some frames
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 130, err
    state = read_state((tmp_path / "s.vwgstate").read_bytes(), "s")
    recorded = frames(tmp_path / "r.jsonl")
    frame = state.manifest["frame"]
    assert frame == max(recorded) + 1 and frame > 0
    # The state is that of the end of the last recorded frame: it goes on from there.
    done = cli("resume", "s.vwgstate", "--frames", "3", "--record", "rest.jsonl", "--allow-unreached", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert min(frames(tmp_path / "rest.jsonl")) == frame


def test_replay_from_starts_at_the_nearest_kept_state(tmp_path):
    record = run_saving("office", tmp_path, 60, 20)
    done = cli("replay", str(record), "--from", "50", "--record", "again.jsonl", "--allow-unreached", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "the state kept at frame 40, frames 40 to 49 as recorded" in done.stdout
    again = frames(tmp_path / "again.jsonl")
    full = frames(record)
    assert min(again) == 50 and all(again[t] == full[t] for t in again)
    # A state left there by another run (another seed) is refused, not used.
    other = tmp_path / "other"
    other.mkdir()
    run_saving("office", other, 40, 40, "--seed", "3")
    (record.with_name(record.name + ".states") / f"{40:012d}.vwgstate").write_bytes(
        (other / "full.jsonl.states" / f"{40:012d}.vwgstate").read_bytes())
    done = cli("replay", str(record), "--from", "50", cwd=tmp_path)
    assert done.returncode == 2 and "was not kept by the run of this record" in done.stderr


def test_replay_from_in_a_resumed_run_s_record_goes_on_to_that_run_s_end(tmp_path):
    # A record written by `vwg resume` starts at the saved frame (30) and plans 30 frames: replayed --from 55,
    # it goes live to frame 60, as the resumed run did; without kept states it cannot be started and says why.
    assert cli("run", "warehouse", "--frames", "30", "--save-state", "s.vwgstate", "-q", "--allow-unreached",
               cwd=tmp_path).returncode == 0
    done = cli("resume", "s.vwgstate", "--frames", "30", "--record", "rest.jsonl", "--snapshot-every", "10",
               "--allow-unreached", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    done = cli("replay", "rest.jsonl", "--from", "55", "--record", "again.jsonl", "--allow-unreached", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "the state kept at frame 50, frames 50 to 54 as recorded, then live to frame 60" in done.stdout
    again, rest = frames(tmp_path / "again.jsonl"), frames(tmp_path / "rest.jsonl")
    assert sorted(again) == list(range(55, 60)) and all(again[t] == rest[t] for t in again)
    assert cli("resume", "s.vwgstate", "--frames", "30", "--record", "bare.jsonl", "--allow-unreached",
               cwd=tmp_path).returncode == 0
    done = cli("replay", "bare.jsonl", "--from", "55", cwd=tmp_path)
    assert done.returncode == 2 and "bare.jsonl starts at frame 30: its run went on from a saved state" in done.stderr


def test_snapshot_every_needs_a_record_and_resume_keeps_the_saved_run_s_settings(tmp_path):
    done = cli("run", "office", "--frames", "5", "--snapshot-every", "2", cwd=tmp_path)
    assert done.returncode == 2 and "give --record too" in done.stderr
    with vwg.start(vwg.load("office"), vwg.RunOptions(frames=5, allow_unreached=True)) as run:
        run.execute()
        data = run.save_state()
    with pytest.raises(Error, match="--seed: a resumed run keeps the saved run's"):
        resume(data, vwg.RunOptions(seed=4))
    with pytest.raises(Error, match="--planner: a resumed run keeps the saved run's"):
        resume(data, vwg.RunOptions(planner="jps"))


def test_a_platform_that_cannot_be_saved_is_named():
    class Wheels(_core.RobotPlatform):
        def name(self) -> str:
            return "wheels"

    with pytest.raises(SchemaError, match="platform wheels: cannot be saved"):
        Wheels().save_state()


def test_a_python_generator_attribute_that_cannot_be_kept_is_named():
    class Logger(vwg.Generator):
        name = "logger"

        def __init__(self) -> None:
            super().__init__()
            self.out = open(os.devnull, "w")  # noqa: SIM115 (the attribute under test)

        def generate(self, frame):
            return []

    g = Logger()
    try:
        with pytest.raises(SchemaError, match=r"generator logger\.out: a _io\.TextIOWrapper cannot be kept"):
            g.save_state()
    finally:
        g.out.close()


def test_a_python_generator_s_attributes_round_trip():
    class Drops(vwg.Generator):
        def __init__(self) -> None:
            super().__init__()
            self.rng = np.random.default_rng(3)
            self.seen = {(1, 2): [1.5, float("inf")], "n": (3, None)}
            self.grid = np.arange(6, dtype=np.int16).reshape(2, 3)

        def generate(self, frame):
            return []

    a, b = Drops(), Drops()
    a.rng.random(5)
    b.load_state(a.save_state())
    assert b.rng.random() == a.rng.random()
    assert b.seen == a.seen and np.array_equal(b.grid, a.grid) and b.grid.dtype == np.int16


def test_a_real_robot_s_run_saves_its_beliefs_and_goes_on_on_the_simulator(tmp_path):
    from vwg.testing.fake_robot import FakeRosbridgeRobot

    office = vwg.load("office")
    with FakeRosbridgeRobot(office) as fake:
        options = vwg.RunOptions(platform="rosbridge", platform_options={"url": fake.url}, goals=["kitchen"],
                                 frames=20, allow_unreached=True)
        with vwg.start(office, options) as run:
            run.execute()
            with pytest.raises(SchemaError, match="platform rosbridge: cannot be saved"):
                run.save_state()
            data = run.save_state(platform=False)
            believed = {r: (float(a["x"]), float(a["y"])) for r, a in run.case.robot_actors().items()}
            grid = np.asarray(run.case.robot_actors()[1]["grid"])
    manifest = read_state(data, "s").manifest
    assert manifest["partial"] and "platform" not in [p["name"] for p in manifest["parts"]]
    with resume(data, vwg.RunOptions(frames=10, allow_unreached=True)) as run:
        assert run.case.sim.name == "sim"
        assert np.array_equal(np.asarray(run.case.robot_actors()[1]["grid"]), grid)
        for rid, (x, y) in believed.items():  # each robot on the simulator where it believed it was
            pose = run.case.sim.robot(rid).pose
            assert abs(pose[0] - x) < 1e-3 and abs(pose[1] - y) < 1e-3
        outcome = run.execute()
    assert outcome.summary["frames"] == 30


def test_gym_reset_from_a_saved_state_goes_on_as_the_episode_did():
    gym = pytest.importorskip("gymnasium")
    import vwg.gym  # noqa: F401 (registers vwg/Navigate-v0)

    env = gym.make("vwg/Navigate-v0", world="office")
    env.reset(seed=4)
    actions = [env.action_space.sample() for _ in range(6)]
    for a in actions[:3]:
        seen = env.step(a)[0]
    data = env.unwrapped.save_state()
    then = [env.step(a) for a in actions[3:]]
    env.close()
    other = gym.make("vwg/Navigate-v0", world="office")
    first, _ = other.reset(seed=99, options={"state": data})
    # The episode's observation where it was saved: the last scan too, not a laser that saw nothing yet.
    assert all(np.array_equal(first[k], seen[k]) for k in seen) and first["laser"].min() < 8.0
    again = [other.step(a) for a in actions[3:]]
    other.close()
    for (o1, r1, t1, u1, i1), (o2, r2, t2, u2, i2) in zip(then, again, strict=True):
        assert r1 == r2 and t1 == t2 and u1 == u2 and i1 == i2
        assert all(np.array_equal(o1[k], o2[k]) for k in o1)


def test_a_state_keeps_a_figure_and_reads_a_string_saved_before_figures():
    # The string is kept as its text (the part "string"), in which a figure's primitives stand side by
    # side (rule 6); a state written before figures has '.' between every two primitives and still loads.
    world = vwg.World(primitives={"Lamp": {"on": 0}})
    engine = vwg.Engine(world, "Lamp<1> Lamp<2> . Lamp<3>", [], vwg.NullBackend())
    engine.step()
    saved = read_state(write_state({"frame": 1}, engine_parts(engine.save_state())), "<figure>")
    assert saved.parts["string"] == b"Lamp<1> Lamp<2> . Lamp<3>"
    other = vwg.Engine(world, "Lamp<0>", [], vwg.NullBackend())
    other.load_state(engine_state(saved, 1))
    assert other.string == engine.string
    assert [n.joined for n in other.string.nodes()] == [False, True, False]
    saved.parts["string"] = b"Lamp<1> . Lamp<2> . Lamp<3>"
    other.load_state(engine_state(saved, 1))
    assert str(other.string) == "Lamp<1> . Lamp<2> . Lamp<3>"
    assert not any(n.joined for n in other.string.nodes())
