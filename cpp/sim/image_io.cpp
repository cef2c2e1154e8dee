#include "vwg/sim/image_io.hpp"

#include <filesystem>
#include <string>
#include <system_error>
#include <utility>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vwg/error.hpp"

namespace vwg::sim {

cv::Mat read_image(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error(path + ": image file not found");
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw Error(path + ": cannot read the image (" + e.msg + ")");
  }
  if (image.empty()) throw Error(path + ": not an image OpenCV can read (PNG, PGM, BMP, JPEG...)");
  if (image.depth() != CV_8U && image.depth() != CV_16U) throw Error(path + ": only 8- and 16-bit images are supported");
  if (image.channels() == 3) cv::cvtColor(image, image, cv::COLOR_BGR2RGB);
  if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2RGBA);
  return image;
}

void write_image(const std::string& path, const cv::Mat& image) {
  // A new matrix for the conversion: `out = image` would share the caller's pixels and cvtColor
  // would then reorder them in place.
  cv::Mat out;
  if (image.channels() == 3) {
    cv::cvtColor(image, out, cv::COLOR_RGB2BGR);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, out, cv::COLOR_RGBA2BGRA);
  } else {
    out = image;
  }
  bool ok = false;
  try {
    ok = cv::imwrite(path, out);
  } catch (const cv::Exception& e) {
    throw Error(path + ": cannot write the image (" + e.msg + ")");
  }
  if (!ok) throw Error(path + ": cannot write the image (unknown extension or unwritable place)");
}

namespace {
std::string size_text(cv::Size s) { return std::to_string(s.width) + "×" + std::to_string(s.height); }
}  // namespace

// --- ImageSequence ---

ImageSequence::ImageSequence(std::string directory, std::string prefix, int first, int digits)
    : directory_(std::move(directory)), prefix_(std::move(prefix)), first_(first), digits_(digits) {
  if (directory_.empty()) directory_.push_back('.');  // (not = ".": GCC 12 warns falsely, bug 105651)
  if (first_ < 0) throw Error(directory_ + ": the first frame number must be >= 0");
  if (digits_ < 1 || digits_ > 12) throw Error(directory_ + ": digits must be 1..12");
  if (prefix_.find('/') != std::string::npos) throw Error(directory_ + ": the prefix must not hold a '/'");
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec || !std::filesystem::is_directory(directory_)) {
    throw Error(directory_ + ": cannot create the folder for the frames" + (ec ? ": " + ec.message() : std::string()));
  }
}

std::string ImageSequence::path_of(std::int64_t number) const {
  std::string n = std::to_string(number);
  if (n.size() < static_cast<std::size_t>(digits_)) n.insert(0, static_cast<std::size_t>(digits_) - n.size(), '0');
  return (std::filesystem::path(directory_) / (prefix_ + n + ".png")).string();
}

std::string ImageSequence::write(const cv::Mat& rgb) {
  const std::string path = path_of(first_ + count_);
  if (rgb.empty()) throw Error(path + ": the frame is empty");
  if (count_ == 0) {
    size_ = rgb.size();
    type_ = rgb.type();
  } else if (rgb.size() != size_ || rgb.type() != type_) {
    throw Error(path + ": the frame is " + size_text(rgb.size()) + " with " + std::to_string(rgb.channels()) +
                " channel(s); the sequence is " + size_text(size_) + " with " +
                std::to_string(CV_MAT_CN(type_)) + " (all frames must match the first)");
  }
  write_image(path, rgb);
  ++count_;
  return path;
}

}  // namespace vwg::sim
