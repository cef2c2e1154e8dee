// AprilTag detection and tag bitmaps through libapriltag 3.3 (Debian libapriltag-dev); tag pose
// through OpenCV (calib3d).
// Every C object has one owner here (unique_ptr with its destroy function); nothing leaves this file.
#include "vwg/perception/apriltag.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <vector>

#include <opencv2/calib3d.hpp>

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h10.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagCircle49h12.h>
#include <apriltag/tagCustom48h12.h>
#include <apriltag/tagStandard41h12.h>
#include <apriltag/tagStandard52h13.h>

#include "vwg/error.hpp"

namespace vwg::perception {

namespace {

// --- families -----------------------------------------------------------------------------------

struct FamilyEntry {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

constexpr FamilyEntry kFamilies[] = {
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tag36h10", tag36h10_create, tag36h10_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
    {"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
    {"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    {"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
};

const FamilyEntry& find_family(std::string_view name) {
  for (const auto& f : kFamilies) {
    if (name == f.name) return f;
  }
  std::string known;
  for (const auto& f : kFamilies) known += (known.empty() ? "" : ", ") + std::string(f.name);
  throw SchemaError("family", "unknown AprilTag family '" + std::string(name) + "'; expected one of " + known);
}

/// A family object with its own destroy function (each family has one).
class Family {
 public:
  explicit Family(const FamilyEntry& entry) : fam_(entry.create(), entry.destroy) {
    if (!fam_) throw Error(std::string("cannot create the AprilTag family ") + entry.name);
  }
  apriltag_family_t* get() const { return fam_.get(); }

 private:
  std::unique_ptr<apriltag_family_t, void (*)(apriltag_family_t*)> fam_;
};

// --- other C objects ----------------------------------------------------------------------------

struct DetectorDeleter {
  void operator()(apriltag_detector_t* td) const { apriltag_detector_destroy(td); }
};
struct DetectionsDeleter {
  void operator()(zarray_t* detections) const { apriltag_detections_destroy(detections); }
};
// Debian's libapriltag 3.3 does not export image_u8_destroy (only libapriltag-utils does, which the
// CMake target apriltag::apriltag does not link). In 3.3 an image_u8_t is the struct plus its
// buffer, both from calloc, so free() is what its destroy function does.
struct ImageU8Free {
  void operator()(image_u8_t* im) const {
    if (im) std::free(im->buf);
    std::free(im);
  }
};
bool finite(double v) { return std::isfinite(v); }

void check_settings(const AprilTagSettings& s) {
  find_family(s.family);
  // The library decimates by 1.5 or by the integer part of the factor, but rescales the corners by
  // the factor itself: anything else gives wrong corners.
  const double d = s.quad_decimate;
  if (!finite(d) || !(d == 1.5 || (d >= 1.0 && d <= 64.0 && d == std::floor(d)))) {
    throw SchemaError("quad_decimate", "expected 1, 1.5 or a whole number from 2 to 64, got " + std::to_string(d));
  }
  if (!finite(s.quad_sigma)) throw SchemaError("quad_sigma", "expected a finite number");
  if (!finite(s.decode_sharpening) || s.decode_sharpening < 0.0) {
    throw SchemaError("decode_sharpening", "expected a finite number >= 0");
  }
  if (s.threads < 1 || s.threads > 256) {
    throw SchemaError("threads", "expected 1 to 256 threads, got " + std::to_string(s.threads));
  }
  if (s.max_hamming < 0 || s.max_hamming > 2) {
    throw SchemaError("max_hamming", "expected 0, 1 or 2 (more needs prohibitive memory), got " +
                                         std::to_string(s.max_hamming));
  }
}

/// Size of the image the library looks for quads in (its image_u8_decimate).
int quad_image_size(int n, double decimate) {
  if (decimate <= 1.0) return n;
  if (decimate == 1.5) return n / 3 * 2;
  return 1 + (n - 1) / static_cast<int>(decimate);
}

/// The library blurs (or sharpens) its quad image in place, and without decimation that image is
/// the caller's: copy first then. Its kernel is int(4·|sigma|) made odd, a no-op when it is 1.
bool library_writes_input(const AprilTagSettings& s) {
  if (s.quad_decimate > 1.0 || s.quad_sigma == 0.0) return false;
  int ksz = static_cast<int>(4.0f * std::fabs(static_cast<float>(s.quad_sigma)));
  if ((ksz & 1) == 0) ++ksz;
  return ksz > 1;
}

}  // namespace

// --- families -----------------------------------------------------------------------------------

std::vector<std::string> tag_families() {
  std::vector<std::string> names;
  for (const auto& f : kFamilies) names.emplace_back(f.name);
  return names;
}

TagFamilyInfo family_info(std::string_view family) {
  const FamilyEntry& entry = find_family(family);
  Family fam(entry);
  const apriltag_family_t* f = fam.get();
  TagFamilyInfo info;
  info.name = entry.name;
  info.codes = static_cast<int>(f->ncodes);
  info.bits = static_cast<int>(f->nbits);
  info.min_hamming = static_cast<int>(f->h);
  info.width_at_border = f->width_at_border;
  info.total_width = f->total_width;
  info.reversed_border = f->reversed_border;
  return info;
}

// --- detector -----------------------------------------------------------------------------------

struct AprilTagDetector::Impl {
  AprilTagSettings settings;
  // The detector keeps a pointer to the family (and the family its decode table): declared first,
  // destroyed last.
  Family family;
  std::unique_ptr<apriltag_detector_t, DetectorDeleter> detector;
  // The library's detector keeps per-call state (worker pool, timing, counters): one call at a time.
  std::mutex mutex;

  explicit Impl(AprilTagSettings s) : settings(std::move(s)), family(find_family(settings.family)) {
    detector.reset(apriltag_detector_create());
    if (!detector) throw Error("cannot create the AprilTag detector");
    apriltag_detector_t* td = detector.get();
    td->quad_decimate = static_cast<float>(settings.quad_decimate);
    td->quad_sigma = static_cast<float>(settings.quad_sigma);
    td->refine_edges = settings.refine_edges;
    td->decode_sharpening = settings.decode_sharpening;
    td->nthreads = settings.threads;
    td->debug = false;
    errno = 0;
    apriltag_detector_add_family_bits(td, family.get(), settings.max_hamming);
    // The library reports a failed decode-table allocation only through errno.
    if (errno == ENOMEM) throw Error("out of memory for the AprilTag decode table of " + settings.family);
  }
};

AprilTagDetector::AprilTagDetector(AprilTagSettings settings) {
  check_settings(settings);
  impl_ = std::make_unique<Impl>(std::move(settings));
}
AprilTagDetector::~AprilTagDetector() = default;
AprilTagDetector::AprilTagDetector(AprilTagDetector&&) noexcept = default;
AprilTagDetector& AprilTagDetector::operator=(AprilTagDetector&&) noexcept = default;

const AprilTagSettings& AprilTagDetector::settings() const {
  if (!impl_) throw Error("AprilTagDetector: used after being moved from");
  return impl_->settings;
}

std::vector<TagDetection> AprilTagDetector::detect(const std::uint8_t* gray, int width, int height,
                                                   int stride) const {
  if (!impl_) throw Error("AprilTagDetector: used after being moved from");
  if (!gray) throw SchemaError("image", "null image pointer");
  if (width <= 0 || height <= 0) {
    throw SchemaError("image", "empty image (" + std::to_string(width) + "×" + std::to_string(height) + ")");
  }
  if (stride < width) {
    throw SchemaError("image", "row stride " + std::to_string(stride) + " is smaller than the width " +
                                   std::to_string(width));
  }
  std::vector<TagDetection> out;
  const Impl& impl = *impl_;
  // libapriltag 3.3 crashes when its quad image is 2 px or less across (seen with ASan on noise and
  // flat images); upstream later returns nothing below 6 px. Neither can hold a decodable tag.
  const double decimate = impl.settings.quad_decimate;
  if (width < 6 || height < 6 || quad_image_size(width, decimate) < 4 || quad_image_size(height, decimate) < 4) {
    return out;
  }
  std::vector<std::uint8_t> copy;
  const std::uint8_t* pixels = gray;
  int row_bytes = stride;
  if (library_writes_input(impl.settings)) {
    copy.resize(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y) {
      std::memcpy(copy.data() + static_cast<std::size_t>(y) * width, gray + static_cast<std::size_t>(y) * stride,
                  static_cast<std::size_t>(width));
    }
    pixels = copy.data();
    row_bytes = width;
  }
  // The library takes a non-const image; it only writes it in the case copied above.
  image_u8_t im{width, height, row_bytes, const_cast<std::uint8_t*>(pixels)};

  std::unique_ptr<zarray_t, DetectionsDeleter> detections;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    detections.reset(apriltag_detector_detect(impl_->detector.get(), &im));
  }
  if (!detections) throw Error("AprilTag detection failed (out of memory?)");

  const int n = zarray_size(detections.get());
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(detections.get(), i, &det);
    TagDetection d;
    d.id = det->id;
    d.hamming = det->hamming;
    d.decision_margin = det->decision_margin;
    for (int k = 0; k < 4; ++k) d.corners[k] = {det->p[k][0], det->p[k][1]};
    d.center = {det->c[0], det->c[1]};
    for (int k = 0; k < 9; ++k) d.homography[k] = MATD_EL(det->H, k / 3, k % 3);
    out.push_back(d);
  }
  return out;
}

std::vector<TagDetection> AprilTagDetector::detect(const GrayImage& image) const {
  if (image.width > 0 && image.height > 0 &&
      image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
    throw SchemaError("image", "GrayImage holds " + std::to_string(image.pixels.size()) + " pixels, not " +
                                   std::to_string(image.width) + "×" + std::to_string(image.height));
  }
  return detect(image.pixels.data(), image.width, image.height, image.width);
}

// --- pose ---------------------------------------------------------------------------------------

TagPose estimate_pose(const TagDetection& detection, double tag_size, const CameraIntrinsics& camera) {
  if (!finite(tag_size) || tag_size <= 0.0) throw SchemaError("tag_size", "expected a positive size in metres");
  if (!finite(camera.fx) || camera.fx <= 0.0) throw SchemaError("fx", "expected a positive focal length in pixels");
  if (!finite(camera.fy) || camera.fy <= 0.0) throw SchemaError("fy", "expected a positive focal length in pixels");
  if (!finite(camera.cx) || !finite(camera.cy)) throw SchemaError("cx, cy", "expected finite pixel coordinates");
  for (const auto& p : detection.corners) {
    if (!finite(p[0]) || !finite(p[1])) throw SchemaError("detection.corners", "non-finite corner");
  }
  for (double h : detection.homography) {
    if (!finite(h)) throw SchemaError("detection.homography", "non-finite entry");
  }
  // A quad without area or a singular homography has no pose: refuse it with a clear error.
  double area2 = 0.0;  // twice the signed area (shoelace)
  for (int k = 0; k < 4; ++k) {
    const auto& a = detection.corners[k];
    const auto& b = detection.corners[(k + 1) % 4];
    area2 += a[0] * b[1] - b[0] * a[1];
  }
  if (std::fabs(area2) < 2.0) throw SchemaError("detection.corners", "degenerate quad (area below 1 px²)");
  const auto& H = detection.homography;
  const double det = H[0] * (H[4] * H[8] - H[5] * H[7]) - H[1] * (H[3] * H[8] - H[5] * H[6]) +
                     H[2] * (H[3] * H[7] - H[4] * H[6]);
  if (!(std::fabs(det) > 1e-12)) throw SchemaError("detection.homography", "singular homography");

  // OpenCV's IPPE for squares gives both solutions of the planar ambiguity; the one with the smaller
  // object-space error (Lu, Hager and Mjolsness 2000, the error libapriltag's estimate_tag_pose
  // minimises) is kept. libapriltag's own estimator prints to stderr when the two are close.
  const double half = tag_size / 2;
  const std::vector<cv::Point3d> object{{-half, half, 0}, {half, half, 0}, {half, -half, 0}, {-half, -half, 0}};
  std::vector<cv::Point2d> image;
  for (const auto& p : detection.corners) image.emplace_back(p[0], p[1]);
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    cv::solvePnPGeneric(object, image, K, cv::noArray(), rvecs, tvecs, false, cv::SOLVEPNP_IPPE_SQUARE);
  } catch (const cv::Exception& e) {
    throw Error(std::string("AprilTag pose estimation failed: ") + e.what());
  }
  double err = std::numeric_limits<double>::infinity();
  cv::Matx33d R;
  cv::Vec3d t;
  for (std::size_t s = 0; s < rvecs.size(); ++s) {
    // IPPE solves the homography of the four corners in closed form; a few Levenberg-Marquardt
    // steps on the reprojection error make it the least-squares pose (as libapriltag's iteration).
    cv::solvePnPRefineLM(object, image, K, cv::noArray(), rvecs[s], tvecs[s]);
    cv::Matx33d Rs;
    cv::Rodrigues(rvecs[s], Rs);
    const cv::Vec3d ts(tvecs[s].at<double>(0), tvecs[s].at<double>(1), tvecs[s].at<double>(2));
    double e = 0.0;
    for (std::size_t i = 0; i < 4; ++i) {
      const cv::Vec3d v((image[i].x - camera.cx) / camera.fx, (image[i].y - camera.cy) / camera.fy, 1.0);
      const cv::Vec3d q = Rs * cv::Vec3d(object[i].x, object[i].y, object[i].z) + ts;
      const cv::Vec3d off = q - v * (v.dot(q) / v.dot(v));  // (I - V) q: q's distance from the ray
      e += off.dot(off);
    }
    if (e < err) {
      err = e;
      R = Rs;
      t = ts;
    }
  }
  if (!std::isfinite(err)) throw Error("AprilTag pose estimation failed (no solution for this quad)");

  TagPose pose;
  for (int k = 0; k < 9; ++k) pose.rotation[k] = R(k / 3, k % 3);
  for (int k = 0; k < 3; ++k) pose.translation[k] = t[k];
  pose.error = err;
  const auto& tr = pose.translation;
  pose.distance = std::sqrt(tr[0] * tr[0] + tr[1] * tr[1] + tr[2] * tr[2]);
  pose.bearing = std::atan2(-tr[0], tr[2]);
  bool ok = finite(pose.distance) && finite(err);
  for (double v : pose.rotation) ok = ok && finite(v);
  if (!ok) throw Error("AprilTag pose estimation failed (no finite solution for this quad)");
  return pose;
}

// --- bitmaps ------------------------------------------------------------------------------------

GrayImage render_tag(std::string_view family, int id, int border_px, int scale) {
  const FamilyEntry& entry = find_family(family);
  if (scale < 1 || scale > 4096) throw SchemaError("scale", "expected 1 to 4096 pixels per cell");
  if (border_px < 0 || border_px > 1 << 16) throw SchemaError("border_px", "expected 0 to 65536 pixels");
  Family fam(entry);
  // The library only asserts the id (a no-op in release builds): check it here.
  if (id < 0 || static_cast<std::uint32_t>(id) >= fam.get()->ncodes) {
    throw SchemaError("id", "tag id " + std::to_string(id) + " is outside " + entry.name + "'s 0.." +
                                std::to_string(fam.get()->ncodes - 1));
  }
  std::unique_ptr<image_u8_t, ImageU8Free> bitmap(apriltag_to_image(fam.get(), id));
  if (!bitmap) throw Error("apriltag_to_image failed");
  const int cells = bitmap->width;
  const long long side = static_cast<long long>(cells) * scale + 2LL * border_px;
  if (side > 1 << 16) throw SchemaError("scale", "the tag image would be " + std::to_string(side) + " pixels across");

  GrayImage out;
  out.width = out.height = static_cast<int>(side);
  out.pixels.assign(static_cast<std::size_t>(side) * static_cast<std::size_t>(side), 255);
  for (int y = 0; y < bitmap->height; ++y) {
    for (int x = 0; x < cells; ++x) {
      const std::uint8_t v = bitmap->buf[static_cast<std::size_t>(y) * bitmap->stride + x];
      for (int dy = 0; dy < scale; ++dy) {
        std::uint8_t* row = out.pixels.data() + static_cast<std::size_t>(border_px + y * scale + dy) * out.width;
        std::fill_n(row + border_px + x * scale, scale, v);
      }
    }
  }
  return out;
}

}  // namespace vwg::perception
