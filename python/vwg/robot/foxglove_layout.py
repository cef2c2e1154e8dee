"""A Foxglove layout for a robot world's topics (vwg.robot.topics): the 3D panel seen from above with the known
map, each robot's own map, scans, plans, believed and true poses, the rooms and the people; beside it each
robot's camera. Built with the Foxglove SDK's layout types (``foxglove.layouts``), so the JSON is the one the
app imports (Layouts, Import from file). ``vwg foxglove-layout WORLD FILE.json`` writes one; the office's is
shipped as ``vwg/data/foxglove_layout.json``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from vwg.errors import Error
from vwg.robot.topics import CAMERA, GROUND_TRUTH, MAP, ODOM, PEOPLE, PLAN, ROBOT_MAP, ROOMS, SCAN, require_ros
from vwg.robot.world_file import RobotWorld

__all__ = ["layout_json", "shipped_layout", "write_layout"]

#: One colour a robot, as the videos draw them (robot 1 first).
_COLOURS = ["#e4572e", "#2e86ab", "#76b041", "#a23b72", "#f3a712", "#6c757d"]


def layout_json(world: RobotWorld) -> str:
    """The layout for `world`'s robots, as the JSON the Foxglove app imports."""
    require_ros("foxglove")
    import foxglove.layouts as fl

    topics: dict[str, Any] = {
        MAP.name: fl.BaseRendererRosOccupancyGridTopicSettings(visible=True, color_mode="map", draw_behind=True),
        ROOMS.name: fl.BaseRendererRosMarkerTopicSettings(visible=True),
        PEOPLE.name: fl.BaseRendererRosMarkerTopicSettings(visible=True),
    }
    cameras = []
    for n, robot in enumerate(world.robots):
        colour = _COLOURS[n % len(_COLOURS)]
        topics[ROBOT_MAP.of(robot.id)] = fl.BaseRendererRosOccupancyGridTopicSettings(visible=n == 0,
                                                                                    color_mode="costmap", alpha=0.35)
        topics[SCAN.of(robot.id)] = fl.BaseRendererLaserScanTopicSettings(visible=True, point_size=4, color_mode="flat",
                                                                         flat_color=colour)
        topics[PLAN.of(robot.id)] = fl.BaseRendererPosesTopicSettings(visible=True, type="line", line_width=0.05,
                                                                     gradient=(colour, colour))
        topics[ODOM.of(robot.id)] = fl.BaseRendererPoseTopicSettings(visible=True, type="arrow", color=colour)
        topics[GROUND_TRUTH.of(robot.id)] = fl.BaseRendererPoseTopicSettings(visible=True, type="axis", axis_scale=0.5)
        if "camera" in robot.sensors:
            cameras.append(fl.StackItem(size=1, panel=fl.ImagePanel(
                title=f"robot {robot.id}'s camera",
                config=fl.ImageConfig(image_mode=fl.ImageModeConfig(
                    image_topic=CAMERA.of(robot.id))))))
    g = world.grid
    centre = (g.origin[0] + g.width_m / 2, g.origin[1] + g.height_m / 2, 0.0)
    scene = fl.ThreeDeePanel(title=f"{world.name}: maps, scans, plans", config=fl.ThreeDeeConfig(
        follow_tf="map", fixed_frame="map", follow_mode="follow-none", topics=topics,
        camera_state=fl.ThreeDeeCameraState(perspective=False, distance=max(g.width_m, g.height_m) * 1.3, phi=0.0,
                                            target=centre),
        layers={"grid": fl.BaseRendererGridLayerSettings(visible=False)}))
    content: Any = scene
    if cameras:
        content = fl.SplitContainer(direction="row", items=[
            fl.SplitItem(proportion=3, content=scene),
            fl.SplitItem(proportion=1, content=fl.StackContainer(panels=cameras)),
        ])
    return fl.Layout(content=content).to_json()


def write_layout(world: RobotWorld, path: str | Path) -> None:
    path = Path(path)
    try:
        path.write_text(layout_json(world) + "\n", encoding="utf-8")
    except OSError as e:
        raise Error(f"{path}: {e.strerror}: the layout could not be written") from None


def shipped_layout() -> Path:
    """The layout shipped with vwg (the office's two robots)."""
    return Path(__file__).resolve().parent.parent / "data" / "foxglove_layout.json"
