// The 3D maths the software renderers share (the robot camera, the depth camera and the 3D
// overview): Eigen vectors and one pinhole camera model. World: metres, z up. Image: OpenCV's
// pixels, the centre of pixel (u, v) at (u, v), v growing downwards.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vwg/sim/grid.hpp"

namespace vwg::sim {

using Vec3 = Eigen::Vector3d;

/// A camera: where it is, its image axes in the world (right, down and forward = right × down,
/// orthonormal) and its intrinsics (square pixels). Perspective, or orthographic (parallel rays
/// along `forward`, `focal` then in pixels per metre).
struct PinholeCamera {
  Vec3 eye = Vec3::Zero();
  Vec3 right = Vec3::UnitX();
  Vec3 down = -Vec3::UnitZ();
  Vec3 forward = Vec3::UnitY();
  double focal = 1.0;         ///< perspective: pixels per unit of (sideways / depth); orthographic: pixels per metre
  double cu = 0.0, cv = 0.0;  ///< the principal point: where the line of sight through the eye meets the image
  bool orthographic = false;

  /// Focal length in pixels of a horizontal field of view `hfov` (radians) across `width` pixels.
  static double focal_for(int width, double hfov) { return (width / 2.0) / std::tan(hfov / 2.0); }
  /// The principal point of an image `pixels` wide (or high), centred: OpenCV's convention.
  static double centre_of(int pixels) { return (pixels - 1) / 2.0; }

  /// A level camera `height` above the floor at a robot's pose, looking along its heading (the
  /// robot cameras): forward (cos θ, sin θ, 0), right (sin θ, -cos θ, 0), down -z.
  static PinholeCamera level(const Pose2& pose, double height, double focal, double cu, double cv) {
    PinholeCamera c;
    const double cos_h = std::cos(pose.theta), sin_h = std::sin(pose.theta);
    c.eye = Vec3(pose.x, pose.y, height);
    c.forward = Vec3(cos_h, sin_h, 0.0);
    c.right = Vec3(sin_h, -cos_h, 0.0);
    c.down = Vec3(0.0, 0.0, -1.0);
    c.focal = focal;
    c.cu = cu;
    c.cv = cv;
    return c;
  }

  /// Sideways metres per metre ahead of image column u (x/z of its rays), and downwards of row v.
  double column_x(double u) const { return (u - cu) / focal; }
  double row_y(double v) const { return (v - cv) / focal; }

  /// Pixel coordinates of a world point and its depth along the line of sight (metres from the
  /// eye). False (u, v unset) when a perspective camera does not have the point in front of it.
  bool project(const Vec3& point, double& u, double& v, double& depth) const {
    const Vec3 p = point - eye;
    depth = p.dot(forward);
    if (orthographic) {
      u = cu + focal * p.dot(right);
      v = cv + focal * p.dot(down);
      return true;
    }
    if (!(depth > 1e-9)) return false;
    u = cu + focal * p.dot(right) / depth;
    v = cv + focal * p.dot(down) / depth;
    return true;
  }

  /// The ray through image point (u, v): its origin and direction (perspective: not unit length;
  /// its component along `forward` is 1, so a distance t along it is the depth).
  void ray(double u, double v, Vec3& origin, Vec3& direction) const {
    const double a = column_x(u), b = row_y(v);
    if (orthographic) {
      origin = eye + right * a + down * b;
      direction = forward;
    } else {
      origin = eye;
      direction = forward + right * a + down * b;
    }
  }
};

}  // namespace vwg::sim
