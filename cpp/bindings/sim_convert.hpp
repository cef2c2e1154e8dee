// Conversions shared by the simulation bindings (private to cpp/bindings/).
#pragma once

#include <opencv2/core.hpp>

#include "common.hpp"
#include "vwg/sim/camera.hpp"
#include "vwg/sim/grid.hpp"

namespace vwg::bindings {

/// A C++ grid from a Python map: any object with `.data` (2-D int8 array, row 0 = bottom),
/// `.resolution` and `.origin` (x, y, yaw) — vwg.maps.OccupancyGrid, for one.
sim::OccupancyGrid grid_from_python(py::handle grid);
/// (x, y, theta) from a 3-sequence.
sim::Pose2 pose_from_python(py::handle pose, const std::string& field);
py::tuple pose_to_python(const sim::Pose2& p);
/// World points from an N×2 array or a list of (x, y) pairs.
std::vector<cv::Point2d> points_from_python(py::handle obj, const std::string& field);
/// Wall markers from Python: a list of dicts or objects (vwg.Room) or RobotWorld.rooms.
std::vector<sim::WallMarker> wall_markers_from_python(py::handle markers);
/// An H×W×3 uint8 numpy copy of an RGB image.
py::array_t<std::uint8_t> rgb_to_numpy(const cv::Mat& image);

}  // namespace vwg::bindings
