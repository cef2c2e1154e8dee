// The perception side of vwg._core: AprilTag detection on numpy images, tag pose, tag bitmaps.
//
// Threads: detect_apriltags releases the GIL while the library runs. Detectors are cached (building
// one fills the family's decode table, about 20 ms for tag36h11): a call borrows an idle detector with
// its settings, or builds one, and gives it back afterwards, so calls from several threads run in
// parallel and never share a detector. At most kIdleDetectors idle detectors are kept (most
// recently used first).
#include <cstdint>
#include <cstring>
#include <limits>
#include <list>
#include <mutex>
#include <sstream>
#include <string>

#include "common.hpp"
#include "vwg/perception/apriltag.hpp"

namespace vwg::bindings {


namespace {

namespace pc = vwg::perception;

// --- detector cache -----------------------------------------------------------------------------

constexpr std::size_t kIdleDetectors = 8;

class DetectorCache {
 public:
  /// An idle detector with these settings, or a new one (built outside the lock).
  std::unique_ptr<pc::AprilTagDetector> acquire(const pc::AprilTagSettings& settings) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (auto it = idle_.begin(); it != idle_.end(); ++it) {
        if ((*it)->settings() == settings) {
          std::unique_ptr<pc::AprilTagDetector> d = std::move(*it);
          idle_.erase(it);
          return d;
        }
      }
    }
    return std::make_unique<pc::AprilTagDetector>(settings);
  }

  /// Give a detector back: it becomes the most recently used; the least recently used goes.
  void release(std::unique_ptr<pc::AprilTagDetector> d) {
    std::unique_ptr<pc::AprilTagDetector> evicted;  // destroyed after the lock is released
    std::lock_guard<std::mutex> lock(mutex_);
    idle_.push_front(std::move(d));
    if (idle_.size() > kIdleDetectors) {
      evicted = std::move(idle_.back());
      idle_.pop_back();
    }
  }

 private:
  std::mutex mutex_;
  std::list<std::unique_ptr<pc::AprilTagDetector>> idle_;
};

DetectorCache& detector_cache() {
  static DetectorCache cache;
  return cache;
}

/// A borrowed detector, given back to the cache when the call ends (also on an exception).
class Lease {
 public:
  explicit Lease(const pc::AprilTagSettings& s) : d_(detector_cache().acquire(s)) {}
  ~Lease() {
    if (d_) detector_cache().release(std::move(d_));
  }
  Lease(const Lease&) = delete;
  Lease& operator=(const Lease&) = delete;
  const pc::AprilTagDetector& operator*() const { return *d_; }

 private:
  std::unique_ptr<pc::AprilTagDetector> d_;
};

// --- numpy conversions --------------------------------------------------------------------------

/// A grey image from Python, checked: a 2-D uint8 numpy array whose rows are runs of pixels
/// (C-contiguous, or a crop of one). Keeps the array alive while its pixels are read.
struct GrayView {
  py::array array;
  const std::uint8_t* data = nullptr;
  int width = 0, height = 0, stride = 0;
};

GrayView gray_view(const py::object& image) {
  if (!py::isinstance<py::array>(image)) {
    throw SchemaError("image", "expected a 2-D uint8 numpy array (an H×W grey image), got " +
                                   std::string(py::str(py::type::handle_of(image).attr("__name__"))));
  }
  GrayView v;
  v.array = py::reinterpret_borrow<py::array>(image);
  const py::array& a = v.array;
  const py::dtype dt = a.dtype();
  if (dt.kind() != 'u' || dt.itemsize() != 1) {
    throw SchemaError("image", "expected a uint8 image, got dtype " + std::string(py::str(dt)) +
                                   " (convert with image.astype(numpy.uint8) after scaling to 0..255)");
  }
  if (a.ndim() != 2) {
    std::ostringstream shape;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape << (i ? ", " : "") << a.shape(i);
    throw SchemaError("image", "expected a 2-D (H×W) grey image, got shape (" + shape.str() + ")" +
                                   (a.ndim() == 3 ? "; convert colour images to grey first" : ""));
  }
  const py::ssize_t h = a.shape(0), w = a.shape(1);
  if (h == 0 || w == 0) {
    throw SchemaError("image", "empty image (shape " + std::to_string(h) + "×" + std::to_string(w) + ")");
  }
  constexpr py::ssize_t kMax = std::numeric_limits<std::int32_t>::max();
  if (a.strides(1) != 1 || a.strides(0) < w || h > kMax || w > kMax || a.strides(0) > kMax) {
    throw SchemaError("image", "expected rows of adjacent pixels (strides (" + std::to_string(a.strides(0)) + ", " +
                                   std::to_string(a.strides(1)) + ") for shape " + std::to_string(h) + "×" +
                                   std::to_string(w) + "); pass numpy.ascontiguousarray(image)");
  }
  v.data = static_cast<const std::uint8_t*>(a.data());
  v.width = static_cast<int>(w);
  v.height = static_cast<int>(h);
  v.stride = static_cast<int>(a.strides(0));
  return v;
}

template <std::size_t N>
py::array_t<double> vector_array(const std::array<double, N>& values) {
  py::array_t<double> out(static_cast<py::ssize_t>(N));
  auto r = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < N; ++i) r(static_cast<py::ssize_t>(i)) = values[i];
  return out;
}

py::array_t<double> matrix3(const std::array<double, 9>& values) {
  py::array_t<double> out({3, 3});
  auto r = out.mutable_unchecked<2>();
  for (int i = 0; i < 9; ++i) r(i / 3, i % 3) = values[i];
  return out;
}

py::array_t<double> corners_array(const pc::TagDetection& d) {
  py::array_t<double> out({4, 2});
  auto r = out.mutable_unchecked<2>();
  for (int k = 0; k < 4; ++k) {
    r(k, 0) = d.corners[k][0];
    r(k, 1) = d.corners[k][1];
  }
  return out;
}

std::string fmt(double v, int precision = 2) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(precision);
  s << v;
  return s.str();
}

}  // namespace

void init_perception(py::module_& m) {
  py::class_<pc::TagDetection>(m, "AprilTagDetection",
                               "One detected AprilTag. Pixel coordinates have x to the right, y down and pixel "
                               "centres at +0.5 (the library's convention: subtract 0.5 for OpenCV's). Corners "
                               "are the outer corners of the black border in the library's order: for an upright "
                               "tag p0 bottom-left, p1 bottom-right, p2 top-right, p3 top-left.")
      .def_readonly("id", &pc::TagDetection::id, "The tag's id (its code's index in the family).")
      .def_readonly("hamming", &pc::TagDetection::hamming, "Bit errors corrected when decoding.")
      .def_readonly("decision_margin", &pc::TagDetection::decision_margin,
                    "Mean distance of the bits from the threshold (a quality measure for small tags).")
      .def_property_readonly("corners", &corners_array, "4×2 float64 array of the corners p0..p3 (x, y), pixels.")
      .def_property_readonly(
          "center", [](const pc::TagDetection& d) { return vector_array(d.center); },
          "The tag centre (x, y), pixels, as a float64 array of 2.")
      .def_property_readonly(
          "homography", [](const pc::TagDetection& d) { return matrix3(d.homography); },
          "3×3 homography from tag coordinates ((-1, 1), (1, 1), (1, -1), (-1, -1) = p0..p3) to pixels.")
      .def("__repr__", [](const pc::TagDetection& d) {
        return "AprilTagDetection(id=" + std::to_string(d.id) + ", hamming=" + std::to_string(d.hamming) +
               ", center=(" + fmt(d.center[0]) + ", " + fmt(d.center[1]) + "), decision_margin=" +
               fmt(d.decision_margin, 1) + ")";
      });

  py::class_<pc::TagPose>(m, "AprilTagPose",
                          "A tag's pose in the camera frame (x right, y down, z forward): p_camera = "
                          "rotation @ p_tag + translation, metres. The tag frame has its origin at the tag "
                          "centre, x right, y down, z into the tag.")
      .def_property_readonly(
          "rotation", [](const pc::TagPose& p) { return matrix3(p.rotation); }, "3×3 rotation, tag to camera.")
      .def_property_readonly(
          "translation", [](const pc::TagPose& p) { return vector_array(p.translation); },
          "The tag centre in the camera frame, metres (array of 3).")
      .def_readonly("error", &pc::TagPose::error, "The library's object-space error of the chosen solution.")
      .def_readonly("distance", &pc::TagPose::distance, "Distance from the camera to the tag centre, metres.")
      .def_readonly("bearing", &pc::TagPose::bearing,
                    "Angle of the tag centre from the optical axis in the camera's horizontal plane, radians, "
                    "positive to the LEFT: atan2(-x, z).")
      .def("__repr__", [](const pc::TagPose& p) {
        return "AprilTagPose(distance=" + fmt(p.distance, 3) + ", bearing=" + fmt(p.bearing, 4) +
               ", translation=(" + fmt(p.translation[0], 3) + ", " + fmt(p.translation[1], 3) + ", " +
               fmt(p.translation[2], 3) + "), error=" + fmt(p.error, 6) + ")";
      });

  py::class_<pc::TagFamilyInfo>(m, "AprilTagFamily", "A tag family's geometry, in bitmap cells.")
      .def_readonly("name", &pc::TagFamilyInfo::name)
      .def_readonly("codes", &pc::TagFamilyInfo::codes, "Number of ids (0 .. codes-1).")
      .def_readonly("bits", &pc::TagFamilyInfo::bits, "Data bits per code.")
      .def_readonly("min_hamming", &pc::TagFamilyInfo::min_hamming, "Minimum Hamming distance between codes.")
      .def_readonly("width_at_border", &pc::TagFamilyInfo::width_at_border,
                    "Cells across the black border square (what a pose's tag_size measures).")
      .def_readonly("total_width", &pc::TagFamilyInfo::total_width,
                    "Cells across the whole bitmap (apriltag_image's size at scale 1).")
      .def_readonly("reversed_border", &pc::TagFamilyInfo::reversed_border)
      .def("__repr__", [](const pc::TagFamilyInfo& f) {
        return "AprilTagFamily(" + f.name + ", codes=" + std::to_string(f.codes) + ")";
      });

  m.def(
      "detect_apriltags",
      [](const py::object& image, const std::string& family, double quad_decimate, bool refine_edges,
         double quad_sigma, double decode_sharpening, int threads, int max_hamming) {
        pc::AprilTagSettings s;
        s.family = family;
        s.quad_decimate = quad_decimate;
        s.refine_edges = refine_edges;
        s.quad_sigma = quad_sigma;
        s.decode_sharpening = decode_sharpening;
        s.threads = threads;
        s.max_hamming = max_hamming;
        const GrayView view = gray_view(image);
        std::vector<pc::TagDetection> found;
        {
          py::gil_scoped_release release;
          Lease detector(s);
          found = (*detector).detect(view.data, view.width, view.height, view.stride);
        }
        py::list out;
        for (const auto& d : found) out.append(py::cast(d));
        return out;
      },
      py::arg("image"), py::arg("family") = pc::AprilTagSettings{}.family,
      py::arg("quad_decimate") = pc::AprilTagSettings{}.quad_decimate,
      py::arg("refine_edges") = pc::AprilTagSettings{}.refine_edges, py::kw_only(),
      py::arg("quad_sigma") = pc::AprilTagSettings{}.quad_sigma,
      py::arg("decode_sharpening") = pc::AprilTagSettings{}.decode_sharpening,
      py::arg("threads") = pc::AprilTagSettings{}.threads, py::arg("max_hamming") = pc::AprilTagSettings{}.max_hamming,
      "Detect AprilTags in a 2-D uint8 grey image (H×W numpy array; a crop of one is fine).\n\n"
      "Returns a list of AprilTagDetection in the library's order. quad_decimate is 1, 1.5 or a whole "
      "number (2: fast, tags from about 20 px; 1: smaller tags). The image is never modified. Raises "
      "vwg.SchemaError for anything but a non-empty 2-D uint8 array or for bad settings. Releases the GIL; "
      "safe from several threads (detectors are cached per settings and never shared by two calls).");

  m.def(
      "estimate_tag_pose",
      [](const pc::TagDetection& detection, double tag_size, double fx, double fy, double cx, double cy) {
        return pc::estimate_pose(detection, tag_size, pc::CameraIntrinsics{fx, fy, cx, cy});
      },
      py::arg("detection"), py::arg("tag_size"), py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"),
      "The pose of a detected tag (the library's estimate_tag_pose). tag_size: side of the black border "
      "square, metres. fx, fy, cx, cy: pinhole intrinsics in pixels, (cx, cy) in the detections' convention "
      "(pixel centres at +0.5: OpenCV's cx + 0.5). Raises vwg.SchemaError for bad values.");

  m.def(
      "apriltag_image",
      [](int id, const std::string& family, int scale, int border) {
        pc::GrayImage img = pc::render_tag(family, id, border, scale);
        py::array_t<std::uint8_t> out({img.height, img.width});
        std::memcpy(out.mutable_data(), img.pixels.data(), img.pixels.size());
        return out;
      },
      py::arg("id"), py::arg("family") = pc::AprilTagSettings{}.family, py::arg("scale") = pc::kDefaultTagScale,
      py::arg("border") = pc::kDefaultTagBorder,
      "The tag's bitmap (the library's apriltag_to_image) as an H×W uint8 array, white 255, black 0: "
      "total_width cells across (tag36h11: 10, a white ring around the 8×8 black-bordered code), as in "
      "AprilRobotics/apriltag-imgs. Each cell becomes scale×scale pixels, then border white pixels are "
      "added on every side. Raises vwg.SchemaError for an unknown family or an id outside the family.");

  m.def("apriltag_families", &pc::tag_families, "The AprilTag families this build supports.");
  m.def(
      "apriltag_family", [](const std::string& family) { return pc::family_info(family); }, py::arg("family"),
      "A family's geometry: codes, bits, min_hamming, width_at_border, total_width.");
}

}  // namespace vwg::bindings
