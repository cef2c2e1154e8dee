// The simulated robot camera (gCamera's eyes): first-person images of the world made from the 2D
// map, in which the AprilTag markers that name the rooms (paper §III) can be detected.
//
// The scene follows the depth camera's conventions (depth_camera.hpp): walls are the blocked cells
// extruded from the floor to wall_height, a flat ceiling at wall_height, other robots upright
// cylinders of robot_height, the camera level with the floor at mount_height, looking along the
// robot's heading. Pixels are OpenCV's: the centre of pixel (u, v) is at (u, v), and the image is
// an exact pinhole projection with fx = fy = (width / 2) / tan(hfov / 2), cx = (width - 1) / 2,
// cy = (height - 1) / 2.
//
// Markers are tag36h11 bitmaps drawn as planar squares on their wall. A marker's `size` is the edge
// of the tag's outer BLACK square (what the pose estimate's tag_size measures); the square drawn on
// the wall is the library's whole bitmap (apriltag_to_image: a ring of white cells around the black
// square, 10 cells across for 8 cells of black), so it is 10/8 × size wide and the detector sees
// the white quiet zone it needs even on a dark wall.
#pragma once

#include <concepts>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <opencv2/core.hpp>

#include "vwg/perception/apriltag.hpp"
#include "vwg/platform/platform.hpp"
#include "vwg/random.hpp"
#include "vwg/sim/grid.hpp"
#include "vwg/sim/view3d.hpp"

namespace vwg::sim {

/// The camera: image size, field of view, where it sits, how tall the world is, its defects, and how
/// often gCamera looks.
struct CameraSpec {
  int width = 640;
  int height = 480;
  double hfov = 1.0471975511965976;  ///< horizontal field of view, radians (60°)
  double mount_height = 0.5;         ///< optical centre above the floor, metres
  double wall_height = kDefaultWallHeight;  ///< walls and ceiling, metres
  double robot_height = 0.4;         ///< other robots are cylinders this tall, metres
  double noise = 0.0;                ///< standard deviation of the added pixel noise, grey levels (0..255)
  double blur = 0.0;                 ///< Gaussian blur sigma, pixels (applied before the noise, as optics are)
  int period = 3;                    ///< gCamera looks every this many frames (AprilTag detection costs milliseconds)

  /// Focal lengths in pixels (square pixels: fy = fx).
  double fx() const;
  double fy() const { return fx(); }
  /// Principal point, OpenCV convention (pixel centres at whole numbers).
  double cx() const { return PinholeCamera::centre_of(width); }
  double cy() const { return PinholeCamera::centre_of(height); }
};

template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, CameraSpec>
void visit_settings(S& s, F&& field) {
  field("width", s.width, "image width, pixels");
  field("height", s.height, "image height, pixels");
  field("hfov", s.hfov, "horizontal field of view, radians");
  field("mount_height", s.mount_height, "optical centre above the floor, metres");
  field("wall_height", s.wall_height, "walls and ceiling, metres");
  field("robot_height", s.robot_height, "other robots are cylinders this tall, metres");
  field("noise", s.noise, "standard deviation of the added pixel noise, grey levels (0..255)");
  field("blur", s.blur, "Gaussian blur sigma, pixels");
  field("period", s.period, "gCamera looks every this many frames (detection costs milliseconds)");
}

/// Throws vwg::SchemaError naming `owner`.field for a size outside 1..8192, a field of view outside
/// (0, π), heights that are not 0 < mount_height < wall_height and 0 < robot_height, negative or
/// non-finite noise or blur, or a period outside 1..1000000 frames.
void check_settings(const CameraSpec& spec, const std::string& owner = "camera");

/// The intrinsics to give vwg::perception::estimate_pose for images of this camera: the library
/// puts pixel centres at +0.5, so its principal point is OpenCV's + 0.5.
perception::CameraIntrinsics apriltag_intrinsics(const CameraSpec& spec);

/// A tag36h11 marker on a wall (a room of the world file, vwg.robotworld.Room).
struct WallMarker {
  int id = 0;            ///< tag id, 0..586
  double x = 0.0;        ///< centre of the marker on the wall face, metres (world frame)
  double y = 0.0;
  double facing = 0.0;   ///< direction the marker faces (the wall's outward normal), radians
  double size = 0.3;     ///< edge of the tag's outer black square, metres
  double height = 0.6;   ///< height of the marker's centre above the floor, metres (the world files' default)
  std::string label;     ///< shown by the overview (e.g. the room name); "" shows "#id"
};

/// Another robot as the cameras see it: an upright cylinder on the floor.
struct RobotShape {
  Pose2 pose{};
  double radius = platform::kDefaultRobotRadius;  ///< metres
  int id = 0;            ///< picks the colour: RenderStyle::body(id), a robot's palette colour; below zero a person, sand
};

/// Checks markers against a wall height; throws vwg::SchemaError naming "markers[i].field" for an
/// id outside tag36h11's codes, non-finite values, size <= 0, or a centre height outside
/// (0, wall_height).
void check_markers(std::span<const WallMarker> markers, double wall_height);

enum class PixelFormat : std::uint8_t {
  Rgb,   ///< CV_8UC3, R G B order (vwg's images are RGB, not OpenCV's BGR)
  Grey,  ///< CV_8UC1, the luma (0.299 R + 0.587 G + 0.114 B) of the same scene
};

/// Renders first-person camera images of one map. The projection is exact, column by column: each
/// image column is one horizontal ray (azimuth heading + atan((cx - u) / fx)) cast through the
/// grid, and since walls are vertical planes the column's wall span and the point along the wall
/// are exact; markers are sampled from their bitmaps by intersecting each pixel's rays with the
/// marker's plane, 8×8 rays per pixel where the pixel straddles a cell edge (anti-aliased edges,
/// so the detector's corners land where the pinhole model puts them), one elsewhere.
///
/// A marker is drawn as a flat square on its own plane (through `x, y`, normal `facing`), in the
/// columns whose wall hit lies within two cells of that plane: a marker slightly off the face, or
/// on a slanted wall that the grid turns into a staircase of cells, stays planar, so its pose is
/// measured as exactly as on a straight wall.
///
/// Shading: a fixed light from the east-north-east (30° from +x); walls lit by their direction
/// (normals smoothed over a few cells, so a staircase of cells along a slanted wall shades as one
/// wall) and faded into a haze with distance; floor and ceiling graded by distance.
///
/// The camera is level: with the defaults (60°, 4:3, 0.5 m up) a marker centred 1.2 m up would be
/// wholly in the image only from about 2.3 m away.
///
/// Not thread-safe (it keeps buffers and the noise generator): one renderer per thread.
///
///     CameraRenderer camera(grid, {{.id = 3, .x = 12.0, .y = 4.3, .facing = std::numbers::pi / 2}});
///     cv::Mat grey = camera.render(pose, {}, PixelFormat::Grey);
class CameraRenderer {
 public:
  /// Cells >= threshold are walls. Throws vwg::SchemaError for a bad spec, markers or grid.
  CameraRenderer(const OccupancyGrid& grid, std::vector<WallMarker> markers, CameraSpec spec = {},
                 int threshold = kObstacleThreshold, std::uint64_t seed = kDefaultSeed);
  static constexpr std::uint64_t kDefaultSeed = 0;  ///< of the pixel noise
  ~CameraRenderer();
  CameraRenderer(CameraRenderer&&) noexcept;
  CameraRenderer& operator=(CameraRenderer&&) noexcept;
  CameraRenderer(const CameraRenderer&) = delete;
  CameraRenderer& operator=(const CameraRenderer&) = delete;

  /// The image seen from `pose` (the camera's robot; do not list it in `robots`, though a robot
  /// whose cylinder holds the camera is skipped anyway). `out` is (re)allocated as needed, so
  /// passing the same Mat every frame reuses its memory. Throws vwg::SchemaError for a non-finite
  /// pose or a robot with a non-finite pose or a radius <= 0.
  void render(const Pose2& pose, std::span<const RobotShape> robots, cv::Mat& out, PixelFormat format = PixelFormat::Rgb);
  cv::Mat render(const Pose2& pose, std::span<const RobotShape> robots = {}, PixelFormat format = PixelFormat::Rgb);

  /// Restart the noise sequence: the same seed and poses give the same images.
  void reseed(std::uint64_t seed) { rng_.reseed(seed); }

  const CameraSpec& spec() const { return spec_; }
  std::span<const WallMarker> markers() const { return markers_; }
  perception::CameraIntrinsics apriltag_intrinsics() const { return sim::apriltag_intrinsics(spec_); }

 private:
  struct Scene;
  template <int Channels>
  void render_columns(const Pose2& pose, std::span<const RobotShape> robots, cv::Mat& columns);

  CameraSpec spec_;
  std::vector<WallMarker> markers_;
  std::unique_ptr<Scene> scene_;
  Rng rng_;
  cv::Mat columns_;  // the image transposed: one row per image column, so a column is contiguous
};

}  // namespace vwg::sim
