// A 3D overview of a map (the paper's Fig. 5): the walls extruded to their height and lit, the
// floor with the walls' shadows, the AprilTag markers on their walls and the robots as cylinders,
// seen from above at an angle. A small software renderer (z-buffer, supersampled), so it needs no
// GPU or display.
#pragma once

#include <concepts>
#include <span>
#include <string>
#include <type_traits>

#include <opencv2/core.hpp>

#include "vwg/sim/camera.hpp"
#include "vwg/sim/grid.hpp"
#include "vwg/sim/view3d.hpp"

namespace vwg::sim {

/// Where the overview is seen from, and what it shows.
struct OverviewView {
  int width = 1000;   ///< image size, pixels
  int height = 700;
  /// Direction from the scene's centre towards the eye, radians counter-clockwise from +x.
  /// -π/2 looks from the south (x to the right, as in the 2D view); the default turns a little
  /// further so that walls running both ways show a side.
  double azimuth = -1.9;
  double elevation = 1.1;  ///< angle of the line of sight below the horizon, radians (π/2: straight down)
  double fov = 0.6;         ///< horizontal field of view, radians; 0 = orthographic
  double robot_height = 0.4;  ///< robots are cylinders this tall, metres
  bool labels = true;         ///< write each marker's label (or "#id") above it
  int supersample = 3;        ///< rays per pixel side (anti-aliasing), 1..4
  /// true: frame the map's free cells, a metre around them and the walls' height to fill the
  /// image (a map whose unexplored outside is stored as walls is framed on its building). false: aim
  /// at (target_x, target_y, target_z) with `scale` pixels per metre (orthographic) or the eye
  /// `distance` metres from the target (perspective), target at the image centre.
  bool fit = true;
  double target_x = 0.0, target_y = 0.0, target_z = 0.0;
  double scale = 0.0;
  double distance = 0.0;
};

/// The view's settings (vwg._core.OverviewView through the settings binder); where it aims when
/// not fitted (fit, target, scale, distance) is given per call.
template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, OverviewView>
void visit_settings(S& s, F&& field) {
  field("width", s.width, "image width, pixels");
  field("height", s.height, "image height, pixels");
  field("azimuth", s.azimuth, "direction from the scene's centre towards the eye, radians counter-clockwise from +x");
  field("elevation", s.elevation, "angle of the line of sight below the horizon, radians");
  field("fov", s.fov, "horizontal field of view, radians; 0 = orthographic");
  field("robot_height", s.robot_height, "robots are cylinders this tall, metres");
  field("labels", s.labels, "write each marker's label above it");
  field("supersample", s.supersample, "rays per pixel side (anti-aliasing), 1..4");
}

/// The projection of an overview: world points (metres, z up) to pixels (OpenCV convention: the
/// centre of pixel (u, v) is at (u, v)). The camera model is the renderers' shared PinholeCamera;
/// an orthographic overview's eye is a point far behind the scene.
struct OverviewCamera : PinholeCamera {
  int width = 0, height = 0;

  using PinholeCamera::project;
  /// Pixel coordinates of a world point, and its depth along the line of sight (metres from the
  /// eye). False (u, v unset) when the point is not in front of the eye.
  bool project(double x, double y, double z, double& u, double& v, double& depth) const {
    return project(Vec3(x, y, z), u, v, depth);
  }
  bool project(double x, double y, double z, double& u, double& v) const {
    double depth;
    return project(Vec3(x, y, z), u, v, depth);
  }
};

/// Throws vwg::SchemaError naming the field for a size outside 16..8192, non-finite angles, an
/// elevation outside (0, π/2], a field of view outside [0, π), supersample outside 1..4, or (fit
/// off) a non-finite target or a scale / distance that is not > 0.
void check_overview_view(const OverviewView& view);
/// check_overview_view, for the settings binder (its fields are named view.FIELD whatever the owner).
inline void check_settings(const OverviewView& view, const std::string& /*owner*/) { check_overview_view(view); }

/// The projection render_overview uses for this map and view.
OverviewCamera overview_camera(const OccupancyGrid& grid, double wall_height, const OverviewView& view, int threshold = kObstacleThreshold);

/// The overview image, RGB (CV_8UC3). Cells >= threshold are walls, `wall_height` metres tall;
/// markers are drawn as their tag with a coloured frame, robots in the 2D view's colours (by id).
/// Throws vwg::SchemaError for a bad grid, view, wall height or markers.
cv::Mat render_overview(const OccupancyGrid& grid, double wall_height, std::span<const WallMarker> markers,
                        std::span<const RobotShape> robots, const OverviewView& view = {}, int threshold = kObstacleThreshold);

}  // namespace vwg::sim
