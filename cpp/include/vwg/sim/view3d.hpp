// The 3D maths the software renderers share (the robot camera, the depth camera and the 3D
// overview): Eigen vectors, one pinhole camera model, and the colour and shading arithmetic. World:
// metres, z up. Image: OpenCV's pixels, the centre of pixel (u, v) at (u, v), v growing downwards.
// Each renderer keeps its own look (its palette, where its light is, how strong); how a colour is
// lit, fogged, mixed and stored as a pixel is computed here, once.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

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

// --- colour and shading -------------------------------------------------------------------------

/// A colour in 0..255 floats, shaded before it is stored as 8-bit pixels.
struct Colour {
  float r = 0, g = 0, b = 0;
};
inline Colour operator*(Colour c, float k) { return {c.r * k, c.g * k, c.b * k}; }
inline Colour operator+(Colour a, Colour b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
/// a at t = 0, b at t = 1.
inline Colour mix(Colour a, Colour b, float t) { return a * (1.0f - t) + b * t; }

/// A channel as a byte: clamped to 0..255 and rounded.
inline std::uint8_t to_byte(float v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0f, 255.0f) + 0.5f); }
/// Grey of a colour: ITU-R BT.601 luma, as OpenCV's RGB to grey.
inline float luma(Colour c) { return 0.299f * c.r + 0.587f * c.g + 0.114f * c.b; }

/// Lambert's diffuse light with an ambient floor: `ambient + diffuse·max(0, cos)`, where `cos` is the
/// cosine between a surface's normal and the direction towards the light. Faces turned away keep
/// `ambient` of their colour.
inline float lambert(double cos_to_light, double ambient, double diffuse) {
  return static_cast<float>(ambient + diffuse * std::max(0.0, cos_to_light));
}
/// Half-Lambert (the cosine mapped from [-1, 1] to [0, 1]): `ambient + diffuse·(0.5 + 0.5·cos)`. Never
/// fully dark and still graded on the far side: a wall turned away from the light shows its markers.
inline float half_lambert(double cos_to_light, double ambient, double diffuse) {
  return static_cast<float>(ambient + diffuse * (0.5 + 0.5 * cos_to_light));
}
/// Haze: the share of a surface's own colour left at `distance` metres when 1/e of it is left at
/// `e_distance` (the rest is the haze colour: mix(haze, surface, clarity)).
inline float clarity(double distance, double e_distance) { return static_cast<float>(std::exp(-distance / e_distance)); }

}  // namespace vwg::sim
