// AprilTag detection and tag pose for the robot's camera (the case study's markers identify rooms),
// on top of the AprilRobotics library (libapriltag 3.3). The C library stays out of this header.
//
// Conventions (those of the library, kept as they are):
// - Pixel coordinates: x to the right, y down, and the centre of pixel (column i, row j) is at
//   (i + 0.5, j + 0.5), i.e. (0, 0) is the outer corner of the top-left pixel. An OpenCV point
//   (pixel centres at integers) is this point minus 0.5.
// - Corners: the outer corners of the black border square, in the library's order, which follows
//   the tag, not the image: for a tag seen upright (as its bitmap is drawn) p0 is bottom-left, p1
//   bottom-right, p2 top-right, p3 top-left (counter-clockwise as seen on screen).
// - Homography: maps tag coordinates (-1,1), (1,1), (1,-1), (-1,-1) (the corners p0..p3; the tag's
//   y axis points down the upright tag) to pixels, row-major, as the library returns it.
// - Camera frame of a pose: x right, y down, z forward along the optical axis (as OpenCV). The tag
//   frame: origin at the tag centre, x right, y down, z into the tag (away from a camera facing it).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace vwg::perception {

/// Detector settings (the library's fields; defaults are the library's defaults).
struct AprilTagSettings {
  /// Tag family: tag36h11 (the case study), tag36h10, tag25h9, tag16h5, tagCircle21h7,
  /// tagCircle49h12, tagCustom48h12, tagStandard41h12, tagStandard52h13.
  std::string family = "tag36h11";
  /// Quads are found on the image decimated by this factor; decoding uses full resolution. 1, 1.5
  /// or a whole number (the library decimates by nothing else correctly). 2 is fast and finds tags
  /// from about 20 px across; 1 finds smaller ones, slower.
  double quad_decimate = 2.0;
  /// Gaussian blur (> 0) or sharpening (< 0) of the quad image, standard deviation in pixels.
  double quad_sigma = 0.0;
  /// Snap the quad edges to strong gradients (helps with decimation; no effect when decimate is 1).
  bool refine_edges = true;
  /// Sharpening of the decoded bits (helps small tags).
  double decode_sharpening = 0.25;
  /// Worker threads of the library (1 = in the calling thread only).
  int threads = 1;
  /// Most bit errors corrected when decoding (0, 1 or 2; the library's default is 2). Fewer means
  /// fewer false detections.
  int max_hamming = 2;

  bool operator==(const AprilTagSettings&) const = default;
};

/// One detected tag, in the library's order and pixel convention (see the top of this file).
struct TagDetection {
  int id = 0;                  ///< the code's index in the family
  int hamming = 0;             ///< bit errors corrected
  double decision_margin = 0;  ///< mean distance of the bits to the threshold (quality, small tags)
  std::array<std::array<double, 2>, 4> corners{};  ///< p0..p3, pixels (x, y)
  std::array<double, 2> center{};                  ///< the tag centre, pixels (x, y)
  std::array<double, 9> homography{};              ///< tag [-1,1]² -> pixels, row-major
};

/// Pinhole intrinsics in pixels. cx, cy use the library's convention (pixel centres at +0.5): for
/// OpenCV intrinsics pass cx + 0.5, cy + 0.5 (a half-pixel is far below what the pose resolves).
struct CameraIntrinsics {
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
};

/// The pose of a tag in the camera frame: p_camera = rotation * p_tag + translation (metres).
struct TagPose {
  std::array<double, 9> rotation{};     ///< row-major 3×3
  std::array<double, 3> translation{};  ///< the tag centre in the camera frame, metres
  double error = 0.0;     ///< object-space error of the chosen solution (sum of squared distances, m²)
  double distance = 0.0;  ///< |translation|, metres
  /// Angle of the tag centre from the optical axis in the camera's horizontal (x-z) plane, in
  /// radians, positive when the tag is to the LEFT of the axis: atan2(-t.x, t.z). For a level
  /// camera this is the bearing a robot turns by (counter-clockwise positive) to face the tag.
  double bearing = 0.0;
};

/// A tag family's geometry, in bitmap cells.
struct TagFamilyInfo {
  std::string name;
  int codes = 0;            ///< number of ids: 0 .. codes-1
  int bits = 0;             ///< data bits per code
  int min_hamming = 0;      ///< minimum Hamming distance between codes
  int width_at_border = 0;  ///< cells across the black border square (the pose's tag_size spans these)
  int total_width = 0;      ///< cells across the whole bitmap (render_tag's size at scale 1)
  bool reversed_border = false;  ///< the border is white inside black (tagCircle*, tagStandard*, tagCustom*)
};

/// An owning 8-bit grey image, row-major, no padding: pixel (x, y) is pixels[y * width + x].
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
  std::uint8_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// The names of the families this build supports.
std::vector<std::string> tag_families();

/// A family's geometry. Throws vwg::SchemaError ("family") for an unknown family.
TagFamilyInfo family_info(std::string_view family);

/// A detector: the library's detector with one family. Building one fills the family's decode
/// table (about 20 ms for tag36h11), so keep it for many images. `detect` may be called from several threads: each
/// call locks the detector (calls on one detector run one at a time; use one detector per thread
/// to run in parallel). Movable, not copyable; a moved-from detector throws vwg::Error when used.
class AprilTagDetector {
 public:
  /// Throws vwg::SchemaError naming the setting when a value is out of range or the family unknown.
  explicit AprilTagDetector(AprilTagSettings settings = {});
  ~AprilTagDetector();
  AprilTagDetector(AprilTagDetector&&) noexcept;
  AprilTagDetector& operator=(AprilTagDetector&&) noexcept;
  AprilTagDetector(const AprilTagDetector&) = delete;
  AprilTagDetector& operator=(const AprilTagDetector&) = delete;

  const AprilTagSettings& settings() const;

  /// Detect tags in an 8-bit grey image: `height` rows of `width` pixels, rows `stride` bytes apart
  /// (stride >= width, so a crop of a larger image works in place). The image is only read (copied
  /// first when the settings would make the library blur it in place). Images too small to hold a
  /// tag (under 6 pixels across, or under 4 once decimated) give no detections without calling the
  /// library, which crashes on such images. Throws vwg::SchemaError ("image") for a null pointer, a
  /// non-positive size or a stride below the width. Typical time, 640×480 photo, decimate 2: 3-6 ms.
  std::vector<TagDetection> detect(const std::uint8_t* gray, int width, int height, int stride) const;
  /// The same on an owning image.
  std::vector<TagDetection> detect(const GrayImage& image) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The pose of a detected tag: the two solutions of the planar ambiguity (OpenCV's IPPE for
/// squares), the one with the smaller object-space error kept (the criterion of libapriltag's
/// estimate_tag_pose, which is not used: it prints to stderr).
/// `tag_size` is the side of the black border square in metres (width_at_border cells).
/// Throws vwg::SchemaError for a non-positive tag size or focal length, non-finite values or a
/// degenerate quad, vwg::Error when the estimate fails.
TagPose estimate_pose(const TagDetection& detection, double tag_size, const CameraIntrinsics& camera);

/// render_tag's defaults: one pixel a cell, no quiet zone beyond the tag's own white ring.
inline constexpr int kDefaultTagScale = 1, kDefaultTagBorder = 0;

/// The tag's bitmap from the library's apriltag_to_image: total_width × total_width cells (for
/// tag36h11: 10×10, a 1-cell white ring around the 8×8 black-bordered code), white 255, black 0,
/// as in AprilRobotics/apriltag-imgs. Each cell becomes `scale`×`scale` pixels, then `border_px`
/// white pixels are added on every side (a quiet zone). Throws vwg::SchemaError for an unknown
/// family, an id outside 0..codes-1, scale < 1 or border_px < 0.
GrayImage render_tag(std::string_view family, int id, int border_px = kDefaultTagBorder, int scale = kDefaultTagScale);

}  // namespace vwg::perception
