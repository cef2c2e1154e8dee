"""Defaults once (issue 35): every default lives in one C++ struct or constant, and what the Python side says
(the bindings' signatures, module constants, the world-file docs, a loaded world) is read from it. The C++ side
is reported by the settings classes (fields(), from default-constructed structs) and by
_core.struct_defaults() (the structs that are not settings classes); the C++ test test_defaults.cpp holds them
to their documented values."""

from __future__ import annotations

import ast
import inspect
import re
from pathlib import Path
from typing import Any

import pytest

import vwg._core as _core
from vwg.errors import SchemaError

ROOT = Path(__file__).resolve().parents[1]
CPP = _core.struct_defaults()


def signature_defaults(fn: Any) -> dict[str, Any]:
    """{argument: default} from a pybind11 function's signature line (its __doc__): the defaults Python sees."""
    first = fn.__doc__.splitlines()[0]
    params = first[first.index("(") + 1:first.rindex(") ->")]
    tree = ast.parse(f"def f({params}): pass")
    args = tree.body[0].args  # type: ignore[attr-defined]
    out: dict[str, Any] = {}
    positional = args.args[len(args.args) - len(args.defaults):]
    pairs = [*zip(positional, args.defaults, strict=True), *zip(args.kwonlyargs, args.kw_defaults, strict=True)]
    for arg, node in pairs:
        if node is not None:
            try:
                out[arg.arg] = ast.literal_eval(node)
            except ValueError:
                out[arg.arg] = ast.unparse(node)
    return out


def test_one_robot_radius() -> None:
    radius = CPP["constants"]["kDefaultRobotRadius"]
    assert radius == _core.RobotSettings().radius == _core.ARobotConfig().radius
    assert CPP["DecisionInput"]["radius"] == CPP["RobotShape"]["radius"] == radius
    assert signature_defaults(_core.add_arobot)["radius"] == radius
    assert signature_defaults(_core.Engine.keep_robots_in_step)["radius"] == radius
    assert signature_defaults(_core.RobotState.__init__)["radius"] == radius
    from vwg.robot import case_study

    assert radius == case_study._DEFAULT_RADIUS


def test_the_bindings_keywords_default_to_the_structs() -> None:
    arobot = signature_defaults(_core.add_arobot)
    config = _core.ARobotConfig()
    assert (arobot["margin"], arobot["goal_tolerance"], arobot["step_length"], arobot["carve"]) == (
        config.margin, config.goal_tolerance, config.step_length, config.carve_free_space)
    engine = signature_defaults(_core.Engine.__init__)
    options = _core.EngineOptions().to_dict()
    assert {k: engine[k] for k in options} == options
    view = _core.OverviewView().to_dict()
    overview = signature_defaults(_core.render_overview)
    assert {k: overview[k] for k in view} == view
    assert overview["wall_height"] == CPP["constants"]["kDefaultWallHeight"] == _core.CameraSpec().wall_height
    assert overview["threshold"] == CPP["constants"]["kObstacleThreshold"]
    assert signature_defaults(_core.create_sensor)["seed"] == CPP["SensorSetup"]["seed"]
    assert "camera_period" not in signature_defaults(_core.create_sensor)


def test_python_constants_are_the_cpp_ones() -> None:
    from vwg.io.maps import OBSTACLE_THRESHOLD
    from vwg.model.limits import MAX_DT, MIN_DT
    from vwg.robot.overview import render_world_overview, robots_seen
    from vwg.robot.sensors.camera import PERIOD
    from vwg.robot.world_file import RobotWorld

    assert (MIN_DT, MAX_DT) == (CPP["constants"]["kMinDt"], CPP["constants"]["kMaxDt"]) == (1e-6, 3600.0)
    assert CPP["constants"]["kObstacleThreshold"] == OBSTACLE_THRESHOLD
    assert PERIOD == _core.CameraSpec().period == 3
    assert RobotWorld.__dataclass_fields__["goal_tolerance"].default == _core.ARobotConfig().goal_tolerance
    view = _core.OverviewView()
    assert inspect.signature(robots_seen).parameters["robot_height"].default == view.robot_height
    overview = inspect.signature(render_world_overview).parameters
    assert (overview["width"].default, overview["height"].default) == (view.width, view.height)


def test_the_world_file_docs_and_a_world_without_the_keys_say_the_cpp_defaults(tmp_path: Path) -> None:
    from vwg.robot import world_file

    documented = dict(re.findall(r"^\s+(\w+): [^#\n]*# \[([-0-9.]+)\]", world_file.__doc__ or "", re.M))
    assert float(documented["radius"]) == _core.RobotSettings().radius
    assert float(documented["wall_height"]) == _core.CameraSpec().wall_height
    assert float(documented["dt"]) == _core.EngineOptions().dt
    assert int(documented["seed"]) == _core.EngineOptions().seed
    assert float(documented["goal_tolerance"]) == _core.ARobotConfig().goal_tolerance
    path = tmp_path / "w.yaml"
    path.write_text(f"map: {ROOT / 'maps' / 'office' / 'map.yaml'}\nrobots:\n  - {{id: 1, start: [1.5, 9.0, 0.0]}}\n")
    world = world_file.load_robot_world(path)
    assert (world.dt, world.seed, world.goal_tolerance, world.wall_height, world.robots[0].radius) == (
        _core.EngineOptions().dt, _core.EngineOptions().seed, _core.ARobotConfig().goal_tolerance,
        _core.CameraSpec().wall_height, _core.RobotSettings().radius)
    assert world.sensor_settings("camera").period == 3


@pytest.mark.parametrize("dt", [1e-6, 0.1, 20.0, 3600.0])
def test_one_range_of_seconds_per_frame_taken(dt: float) -> None:
    from vwg.launch import RunOptions

    _core.check_dt(dt)
    RunOptions(dt=dt).check()
    _core.EngineOptions(dt=dt).check("engine")


@pytest.mark.parametrize("dt", [0.0, 9e-7, 3600.5, float("nan"), float("inf")])
def test_one_range_of_seconds_per_frame_refused_with_one_message(dt: float) -> None:
    from vwg.errors import Error
    from vwg.launch import RunOptions

    with pytest.raises(SchemaError) as core:
        _core.check_dt(dt, "--dt")
    assert str(core.value).startswith("--dt: expected a number of seconds from 1e-06 to 3600, got ")
    with pytest.raises(Error) as run:
        RunOptions(dt=dt).check()
    assert str(run.value) == str(core.value)
    with pytest.raises(SchemaError) as engine:
        _core.EngineOptions(dt=dt).check("engine")
    assert str(engine.value) == str(core.value).replace("--dt", "engine.dt")


def test_vwg_serve_takes_the_range_of_vwg_run(capsys: pytest.CaptureFixture[str]) -> None:
    # vwg serve took (0, 10] seconds per frame and vwg run [1e-06, 3600]: one check now.
    pytest.importorskip("aiohttp")
    from vwg.cli import main

    assert main(["serve", "office", "--dt", "3600.5"]) == 2
    assert "--dt: expected a number of seconds from 1e-06 to 3600, got 3600.5" in capsys.readouterr().err


# ---- the bindings spell no default a C++ struct holds ---------------------------------------------------------------
_DEFAULT = re.compile(r'py::arg\("(\w+)"\)\s*=\s*(-?[0-9][0-9.eE+-]*f?|true|false|"[^"]*")')
#: Literal defaults that are no setting: where a point is when none is said (the floor).
_ALLOWED = {"z": "0.0"}


def _settings_fields() -> set[str]:
    names: set[str] = set()
    for cls in vars(_core).values():
        if isinstance(cls, type) and hasattr(cls, "fields") and hasattr(cls, "to_dict"):
            names |= {name for name, *_ in cls.fields()}
    return names


def test_the_bindings_spell_no_default_value() -> None:
    """A number in a binding's default restates a C++ default (or makes a second one): it is read from a
    default-constructed struct or a named constant instead. A bool or text default is refused when its name is a
    settings field (it would restate the struct's)."""
    fields = _settings_fields()
    assert {"radius", "dt", "period", "goal_tolerance", "azimuth"} <= fields
    found = []
    for path in sorted((ROOT / "cpp" / "bindings").glob("*.cpp")):
        text = path.read_text()
        for m in _DEFAULT.finditer(text):
            name, value = m.groups()
            numeric = value[0].isdigit() or value[0] == "-"
            if (numeric and _ALLOWED.get(name) != value) or (not numeric and name in fields):
                found.append(f"{path.name}:{text[:m.start()].count(chr(10)) + 1}: py::arg(\"{name}\") = {value}")
    assert not found, "defaults spelt in the bindings:\n" + "\n".join(found)
