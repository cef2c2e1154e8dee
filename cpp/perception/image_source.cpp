#include "vwg/perception/image_source.hpp"

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

}  // namespace vwg::perception
