"""The extension points a world file and the command line reach: sensors by registered name with their
own settings, platform options checked by the platform's declarations (world file and --platform-opt
alike), the planner a world names, and the events a plugin's sensor declares."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

import vwg
from vwg.cli import main
from vwg.errors import SchemaError, WorldFileError
from vwg.plugins import sensors
from vwg.robot import load_robot_world
from vwg.robot.case_study import case_study_world, make_decider
from vwg.robot.sensor import Sensor, Settings

OFFICE = Path(vwg.robot.load_robot_world("office").path)


def _office(tmp_path: Path, extra: str, drop: tuple[str, ...] = ()) -> Path:
    text = OFFICE.read_text().replace("map: office/map.yaml", f"map: {OFFICE.parent / 'office' / 'map.yaml'}")
    lines = [line for line in text.splitlines() if not line.startswith(drop)] if drop else text.splitlines()
    path = tmp_path / "w.yaml"
    path.write_text("\n".join(lines) + "\n" + extra)
    return path


def test_sensor_settings_by_registered_name_and_the_older_sections(tmp_path: Path) -> None:
    world = load_robot_world(_office(tmp_path, "sensors:\n  laser: {beams: 90, max_range: 5.0}\n"
                                               "  kinect: {width: 320}\n", drop=("laser:", "kinect:")))
    assert (world.sensors["laser"].beams, world.sensors["laser"].max_range) == (90, 5.0)
    assert world.sensors["laser"].min_range == vwg.robot.LaserSpec().min_range  # the struct's default
    assert world.sensors["kinect"].width == 320 and world.sensors["kinect"].wall_height == world.wall_height
    old = load_robot_world(_office(tmp_path, "laser: {beams: 45}\n", drop=("laser:",)))
    assert old.sensors["laser"].beams == 45
    # A sensor given twice, an unknown sensor, and a wrong setting are named by line and field.
    path = _office(tmp_path, "laser: {beams: 45}\nsensors:\n  laser: {beams: 90}\n", drop=("laser:",))
    with pytest.raises(WorldFileError, match=r"laser: sensor laser is given twice"):
        load_robot_world(path)
    path = _office(tmp_path, "sensors:\n  radar: {}\n")
    with pytest.raises(WorldFileError, match=r"sensors\.radar: unknown sensor 'radar' \(registered: camera, "):
        load_robot_world(path)
    path = _office(tmp_path, "sensors:\n  laser: {beams: 0}\n", drop=("laser:",))
    lines = path.read_text().splitlines()
    with pytest.raises(WorldFileError) as e:
        load_robot_world(path)
    assert (e.value.field, e.value.line) == ("sensors.laser.beams", len(lines))


def test_noise_of_a_sensor_given_with_the_others(tmp_path: Path) -> None:
    world = load_robot_world(_office(tmp_path, "noise: {odometry: 0.02, laser: 0.03}\n", drop=("noise:", "laser:")))
    assert world.sensors["laser"].noise == 0.03 and world.noise.odometry == 0.02
    with pytest.raises(WorldFileError, match=r"noise\.laser: 0\.03 conflicts with laser\.noise"):
        load_robot_world(_office(tmp_path, "laser: {noise: 0.01}\nnoise: {laser: 0.03}\n",
                                 drop=("noise:", "laser:")))
    with_sensor = world.with_sensor("laser", noise=0.0)
    assert with_sensor.sensors["laser"].noise == 0.0 and world.sensors["laser"].noise == 0.03


@dataclasses.dataclass
class PingSettings(Settings):
    pings: int = 2
    gain: float = 1.0

    def check(self, owner: str) -> None:
        super().check(owner)
        if self.pings < 1:
            raise SchemaError(f"{owner}.pings: expected at least 1 ping, got {self.pings}")


class Ping(Sensor):
    name = "ping-test"
    Settings = PingSettings
    events = {"ePing": {"strength": 0.0}}
    ranging = False

    def make(self, platform, alphabet, robot):
        return None


def test_a_python_sensor_s_settings_are_checked_by_its_own_check_and_its_events_declared(tmp_path: Path) -> None:
    sensors.register("ping-test", Ping)
    try:
        world = load_robot_world(_office(tmp_path, "sensors:\n  ping-test: {gain: 2}\n"))
        assert world.sensors["ping-test"] == PingSettings(pings=2, gain=2.0)  # an int taken as the float it is
        for bad, field, message in (("{pings: 0}", "sensors.ping-test.pings", "expected at least 1 ping, got 0"),
                                    ("{gain: fast}", "sensors.ping-test.gain", "expected float, got 'fast'"),
                                    ("{loud: 1}", "sensors.ping-test.loud", "unknown key")):
            with pytest.raises(WorldFileError) as e:
                load_robot_world(_office(tmp_path, f"sensors:\n  ping-test: {bad}\n"))
            assert e.value.field == field and message in str(e.value)
    finally:
        sensors.unregister("ping-test")


def test_the_case_study_alphabet_declares_the_events_of_the_sensors_carried(tmp_path: Path) -> None:
    sensors.register("ping-test", Ping)
    try:
        text = _office(tmp_path, "").read_text().replace("sensors: [laser, camera]", "sensors: [laser, ping-test]")
        path = tmp_path / "p.yaml"
        path.write_text(text)
        world = load_robot_world(path)
        alphabet = case_study_world(world, make_decider("astar")).alphabet
        assert "ePing" in alphabet.event_types
        assert "ePing" not in case_study_world(load_robot_world("office"), make_decider("astar")).alphabet.event_types
    finally:
        sensors.unregister("ping-test")


def test_platform_options_from_the_command_line_are_checked_as_the_world_file_s(capsys, tmp_path: Path) -> None:
    assert main(["run", "office", "--platform", "rosbridge", "--url", "ws://127.0.0.1:9",
                 "--platform-opt", "watchdog=-1", "--frames", "1"]) == 2
    assert "platform.watchdog: expected a number > 0.0, got -1" in capsys.readouterr().err
    assert main(["run", "office", "--platform", "rosbridge", "--platform-opt", "url=ws://127.0.0.1:9",
                 "--platform-opt", "flap_limit={drops: 0}", "--frames", "1"]) == 2
    assert "platform.flap_limit.drops: expected a number >= 1, got 0" in capsys.readouterr().err
    assert main(["run", "office", "--platform", "sim", "--platform-opt", "speed=2", "--frames", "1"]) == 2
    assert "platform sim: unknown option(s) speed (known: none: it takes no options)" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["run", "office", "--platform-opt", "novalue"])
    assert "expected KEY=VALUE, got 'novalue'" in capsys.readouterr().err
    assert main(["run", "office", "--platform", "serial", "--serial-port", "loop://", "--platform-opt",
                 "port=loop://", "--frames", "1"]) == 2
    assert "--platform-opt port= and its shorthand are both given" in capsys.readouterr().err
    path = _office(tmp_path, "platform: {kind: rosbridge, url: 'ws://127.0.0.1:9', watchdog: -1}\n")
    line = len(path.read_text().splitlines())
    assert main(["check", str(path)]) == 2
    assert f"{path}:{line}: platform.watchdog: expected a number > 0.0, got -1" in capsys.readouterr().err


def test_a_world_names_its_planner(tmp_path: Path) -> None:
    world = load_robot_world(_office(tmp_path, "planner: jps\n"))
    assert world.planner == "jps"
    with vwg.robot.CaseStudy(world, world.planner, goals={1: "kitchen"}) as run:
        assert run.planner == "jps"
    with pytest.raises(WorldFileError, match=r"planner: unknown planner 'dijkstra' \(registered: astar, "):
        load_robot_world(_office(tmp_path, "planner: dijkstra\n"))
    assert load_robot_world("office").planner == "astar"


def test_a_run_with_a_decider_written_in_python_replays(tmp_path: Path, capsys) -> None:
    # The world a record is replayed in holds the decider its ARobot calls: a decider written in Python
    # (wavefront) was collected with the call that made it, and the replay failed at frame 0.
    record = tmp_path / "w.jsonl"
    assert main(["run", "office", "--planner", "wavefront", "--goal", "kitchen", "--frames", "40",
                 "--allow-unreached", "--record", str(record), "-q"]) == 0
    import gc

    gc.collect()
    assert main(["replay", str(record)]) == 0, capsys.readouterr().err


def test_experiments_take_the_deciders_test_1_compares_by_registered_name(tmp_path: Path, capsys) -> None:
    assert main(["experiments", str(tmp_path / "out"), "--quick", "--planner", "astar", "--planner", "dijkstra"]) == 2
    err = capsys.readouterr().err
    assert "--planner: unknown planner 'dijkstra' (known: astar, " in err and "wavefront" in err
    assert not (tmp_path / "out").exists()  # refused before anything ran
