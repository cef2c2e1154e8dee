#include "vwg/perception/image_source.hpp"

#include <algorithm>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "vwg/error.hpp"

namespace vwg::perception {

namespace {
void to_grey(const cv::Mat& image, cv::Mat& grey, const std::string& what) {
  if (image.empty()) throw Error(what + ": empty image");
  cv::Mat eight = image;
  if (image.depth() != CV_8U) image.convertTo(eight, CV_8U, image.depth() == CV_16U ? 1.0 / 256 : 1.0);
  if (eight.channels() == 1) {
    eight.copyTo(grey);
  } else if (eight.channels() == 3) {
    cv::cvtColor(eight, grey, cv::COLOR_BGR2GRAY);
  } else if (eight.channels() == 4) {
    cv::cvtColor(eight, grey, cv::COLOR_BGRA2GRAY);
  } else {
    throw Error(what + ": images of " + std::to_string(eight.channels()) + " channels are not supported");
  }
}
}  // namespace

ImageFiles::ImageFiles(std::vector<std::string> paths) : paths_(std::move(paths)) {
  for (const auto& p : paths_) {
    if (!std::filesystem::is_regular_file(p)) throw Error(p + ": image file not found");
  }
}

bool ImageFiles::grab(const FrameInfo&, cv::Mat& grey) {
  if (next_ >= paths_.size()) return false;
  const std::string& path = paths_[next_++];
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw Error(path + ": cannot read the image (" + e.msg + ")");
  }
  if (image.empty()) throw Error(path + ": not an image OpenCV can read (corrupt or of an unknown format)");
  to_grey(image, grey, path);
  return true;
}

struct VideoSource::Capture {
  cv::VideoCapture capture;
  cv::Mat frame;
};

VideoSource::VideoSource(const std::string& path) : capture_(std::make_unique<Capture>()), name_("video " + path) {
  if (!std::filesystem::is_regular_file(path)) throw Error(path + ": video file not found");
  if (!capture_->capture.open(path)) throw Error(path + ": OpenCV cannot open this video");
}

VideoSource::VideoSource(int device) : capture_(std::make_unique<Capture>()), name_("camera " + std::to_string(device)) {
  if (!capture_->capture.open(device)) throw Error("camera device " + std::to_string(device) + " cannot be opened");
}

VideoSource::~VideoSource() = default;

bool VideoSource::grab(const FrameInfo&, cv::Mat& grey) {
  if (!capture_->capture.read(capture_->frame) || capture_->frame.empty()) return false;
  to_grey(capture_->frame, grey, name_);
  return true;
}

void ReceivedImages::push(std::vector<std::uint8_t> encoded, double stamp) {
  std::lock_guard lock(mutex_);
  latest_ = std::move(encoded);
  latest_stamp_ = stamp;
  fresh_ = true;
  ++received_;
}

bool ReceivedImages::grab(const FrameInfo&, cv::Mat& grey) {
  std::vector<std::uint8_t> encoded;
  {
    std::lock_guard lock(mutex_);
    if (!fresh_) return false;
    encoded.swap(latest_);
    grabbed_stamp_ = latest_stamp_;
    fresh_ = false;
  }
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(encoded, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    decoded.release();
  }
  if (decoded.empty()) {
    std::lock_guard lock(mutex_);
    ++dropped_;
    return false;
  }
  grey = decoded;
  return true;
}

std::optional<geometry::Pose2> ReceivedImages::taken_from() {
  if (!viewpoint_) return geometry::Pose2{};
  double stamp;
  {
    std::lock_guard lock(mutex_);
    stamp = grabbed_stamp_;
  }
  auto from = viewpoint_(stamp);  // outside the lock: the viewpoint takes the platform's
  if (!from) {
    std::lock_guard lock(mutex_);
    ++stale_;
  }
  return from;
}

std::uint64_t ReceivedImages::stale() const {
  std::lock_guard lock(mutex_);
  return stale_;
}

std::uint64_t ReceivedImages::received() const {
  std::lock_guard lock(mutex_);
  return received_;
}

std::uint64_t ReceivedImages::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

std::vector<std::uint8_t> encode_image(const cv::Mat& image, const std::string& format, int quality) {
  if (format != "jpeg" && format != "png") throw SchemaError("format", "expected jpeg or png, got '" + format + "'");
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw SchemaError("image", "expected an 8-bit grey or RGB image");
  }
  cv::Mat bgr = image;
  if (image.channels() == 3) cv::cvtColor(image, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> out;
  const std::vector<int> params = format == "jpeg" ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, std::clamp(quality, 0, 100)}
                                                   : std::vector<int>{};
  cv::imencode(format == "jpeg" ? ".jpg" : ".png", bgr, out, params);
  return out;
}

}  // namespace vwg::perception
